//! The HDL blocks of the core, one block per file (DESIGN.md §9).
//!
//! | block | file | latency |
//! |---|---|---|
//! | wide multiplier (custom Verilog leaf) and its registered form | `mul_wide.rs` | 0 / 1 cycle |
//! | integer square root, 128-bit radicand, R digits per cycle | `sqrt.rs` | `1 + 64/R` cycles |

pub mod mul_wide;
pub mod sqrt;
