//! The HDL blocks of the core, one block per file (DESIGN.md §9).
//!
//! | block | file | latency |
//! |---|---|---|
//! | wide multiplier (custom Verilog leaf) and its registered form | `mul_wide.rs` | 0 / 1 cycle |

pub mod mul_wide;
