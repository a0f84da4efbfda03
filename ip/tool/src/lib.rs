//! tdm-stepper: a time-division multiplexed multi-axis stepper motor controller IP
//! core. See README.md and docs/ for the architecture. This crate is the tool: the
//! export of the Verilog and its integration package, the synthesis sweep, the
//! system simulation and the board design, and the CLI. The IP itself (the reference
//! model, the register table, the HDL blocks and their verification) is the
//! tdm-stepper-ip crate (ip/), whose modules are re-exported here, so that every
//! module is named `tdm_stepper::…`.

pub use tdm_stepper_ip::{accuracy, hdl, latency, model, regs, vectors, verify};

pub mod board;
pub mod export;
pub mod package;
pub mod sim;
pub mod sweep;
