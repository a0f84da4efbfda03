//! tdm-stepper: a time-division multiplexed multi-axis stepper motor controller IP
//! core. See README.md and docs/ for the architecture; this crate holds the
//! reference model, the test vectors, the accuracy report and the CLI.

pub mod accuracy;
pub mod board;
pub mod export;
pub mod hdl;
pub mod latency;
pub mod model;
pub mod package;
pub mod regs;
pub mod sim;
pub mod sweep;
pub mod vectors;
pub mod verify;
