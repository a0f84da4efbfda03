//! The HDL blocks of the core, one block per file (DESIGN.md §9).
//!
//! | block | file | latency |
//! |---|---|---|
//! | wide multiplier (custom Verilog leaf) and its registered form | `mul_wide.rs` | 0 / 1 cycle |
//! | control of an iterative unit (start, fixed cycles, valid) | `iterate.rs` | `1 + cycles` |
//! | integer square root, 128-bit radicand, R digits per cycle | `sqrt.rs` | `1 + 64/R` cycles |
//! | sequential multiplier, 128 × 64 → 128 bits, R bits per cycle | `mul_seq.rs` | `1 + 64/R` cycles |
//! | divider, 128-bit numerator by 64-bit denominator, R digits per cycle | `divider.rs` | `1 + 128/R` cycles |

pub mod baseline;
pub mod bit_insert;
pub mod context;
pub mod core;
pub mod divider;
pub mod iterate;
pub mod mul_seq;
pub mod mul_wide;
pub mod reg_fifo;
pub mod sqrt;
pub mod step_gen;
pub mod sync_start;
