//! tdm-stepper-ip: the IP core of tdm-stepper, a time-division multiplexed
//! multi-axis stepper motor controller. See README.md and docs/ for the
//! architecture. This crate holds the reference model, the register table, the HDL
//! blocks, their verification harnesses, the test vectors and the accuracy report;
//! the tool crate (ip/tool: export, package, sweep, sim, board and the CLI) builds on
//! it and re-exports its modules as `tdm_stepper::…`.

pub mod accuracy;
pub mod hdl;
pub mod latency;
pub mod model;
pub mod regs;
pub mod vectors;
pub mod verify;
