//! Running exported Verilog: one generated testbench for Verilator and Icarus.
//!
//! A block is checked three ways: against the reference model, in
//! rust-hdl simulation, and as exported Verilog. [`run`] does the third: it writes a
//! testbench that reads one row of input values per clock cycle (`$readmemh`) and
//! prints the outputs of every cycle (`$fwrite`), runs it in the chosen simulator and
//! parses what it printed. The cycle convention is the one of a hand-written rust-hdl
//! loop: in cycle k the inputs take row k, the outputs are sampled before the rising
//! edge, and the rising edge then clocks row k in. [`run_sparse`] takes input events
//! and reports output changes only, for runs of millions of cycles.

pub(crate) mod tb;

pub use tb::{run, run_rust_hdl, run_rust_hdl_sparse, run_sparse, Change, Port, Simulator, TbSpec};
pub mod system;
pub mod bus;
pub mod encoder;
pub mod spi;
pub mod mmio;
