//! The HDL blocks of the core, one block per file (DESIGN.md §9).
//!
//! | block | file | latency |
//! |---|---|---|
//! | wide multiplier (custom Verilog leaf) and its registered form | `mul_wide.rs` | 0 / 1 cycle |
//! | sequential multiplier, 128 × 64 → 128 bits, R bits per cycle | `mul_seq.rs` | `1 + 64/R` cycles |
//! | divider, 128-bit numerator by 64-bit denominator, R digits per cycle | `divider.rs` | `1 + 128/R` cycles |
//! | integer square root, 128-bit radicand, R digits per cycle | `sqrt.rs` | `1 + 64/R` cycles |
//! | control of an iterative unit (start, fixed cycles, valid) | `iterate.rs` | `1 + cycles` |
//! | register FIFO (period FIFOs, segment queues), show-ahead | `reg_fifo.rs` | 0 (head) |
//! | step generator, and the FIFO plus generator (`StepAxis`) | `step_gen.rs` | edges at release + E_i |
//! | per-axis scheduler context, in registers | `context.rs` | 1 cycle (write) |
//! | synchronised start of masked axes | `sync_start.rs` | 1 cycle |
//! | K-bit bus assembly and bit selection | `bit_insert.rs` | 0 |
//! | the TDM core: queues, contexts, step axes, shared units, scheduler | `core.rs` | `t_calc_sqrt(R)`, `t_setup(R, _)` |
//! | the non-TDM baseline: K one-axis cores | `baseline.rs` | as the core |
//!
//! Timing conventions, latencies, sizes and what each test proves: docs/architecture.md.

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
