//! The arithmetic's latencies and the shared unit's radix: the numbers the register
//! table ([`crate::regs`]), the export and the HDL blocks all quote. This module sits
//! at the bottom beside the model and imports nothing from `hdl`, `export` or
//! `package`; each HDL block re-exports the constants it implements, and its tests
//! measure them (tests/hdl_divider.rs, hdl_mul_seq.rs, hdl_mul_wide.rs,
//! hdl_push_check.rs, hdl_core_setup.rs).

/// Bits per cycle of the shared multiplier, divider and square root.
pub const RADIX_BITS: usize = 2;

/// Segments per axis queue of an export.
pub const QUEUE_DEPTH: usize = 16;

/// The period FIFO depth of an export. Each supported configuration is compiled
/// into the tool (the design is generic at compile time), so one depth is offered.
/// 8 entries at the shortest period (K·t_calc) outlast a segment setup started while
/// the FIFO was full plus the scheduler's round trip, at every K from 1 to 16
/// (docs/architecture.md, "FIFO depth"; `fifo_depth_covers_a_setup_at_the_minimum_period`).
/// The FIFO's LUT RAM has 32 entries whatever the depth, so the depth costs no area.
pub const FIFO_DEPTH: usize = 8;

/// Numerator bits of the shared divider ([`crate::hdl::divider`]).
pub const DIV_NUM_BITS: usize = 104;

/// Divider cycles from the `start` edge to `valid` for `r` digits per cycle: the load,
/// one cycle that forms 3d from the loaded d, and 104/r digit cycles.
pub const fn div_latency(r: usize) -> usize {
    2 + DIV_NUM_BITS / r
}

/// Multiplier bits of the sequential multiplier ([`crate::hdl::mul_seq`]).
pub const MUL_B_BITS: usize = 32;
/// Radix-4 Booth digits of an unsigned 32-bit multiplier (one more than 32/2: the
/// top digit carries bit 31).
pub const MUL_DIGITS: usize = MUL_B_BITS / 2 + 1;

/// Sequential multiplier step cycles for `r` multiplier bits (`r / 2` Booth digits)
/// per cycle.
pub const fn mul_seq_steps(r: usize) -> usize {
    MUL_DIGITS.div_ceil(r / 2)
}

/// Sequential multiplier cycles from the `start` edge to `valid` for `r` bits per
/// cycle: the load and [`mul_seq_steps`] digit cycles.
pub const fn mul_seq_latency(r: usize) -> usize {
    1 + mul_seq_steps(r)
}

/// Pipelined 32×32 multiplier ([`crate::hdl::mul_wide::MulReg`]): cycles from `a`,
/// `b` to `p`.
pub const MUL_REG_LATENCY: usize = 2;

/// Trapezoid push check ([`crate::hdl::push_check`]): cycles from `in_valid` to
/// `out_valid` / `rej_valid`.
pub const PUSH_CHECK_LATENCY: usize = 4;
/// Polynomial control-point check ([`crate::hdl::poly_check`]): cycles from
/// `in_valid` to `out_valid`.
pub const POLY_CHECK_LATENCY: usize = 6;
/// Push check cycles for a polynomial push (S = 1).
pub const POLY_PUSH_LATENCY: usize = POLY_CHECK_LATENCY;

/// Cycles the shared unit spends setting up an accelerating or decelerating
/// segment, from S_CHECK to its commit: the head into registers, two 32×32
/// products issued back to back into the pipelined multiplier from registered
/// operands (v0·T, T²; the last arrives 1 + MUL_REG_LATENCY cycles after the first is
/// issued), one on the sequential multiplier (v·T²; two with n·B' when decelerating)
/// and two divides (P', B'), P' issued in the cycle its operand arrives and B' one
/// cycle after P' (the fallback test on P' is registered). Measured by
/// tests/hdl_core.rs.
pub const fn t_setup(r: usize, decelerating: bool) -> usize {
    let wide = if decelerating { 2 } else { 1 };
    4 + (1 + MUL_REG_LATENCY) + wide * mul_seq_latency(r) + 2 * div_latency(r)
}

/// EXMC master of the SPI, Wishbone and AXI4-Lite front ends
/// ([`crate::hdl::exmc_master`]), in bus clocks: NE and NWE low for a write, NE and
/// NOE low for a read (the data taken at the last), the strobes high after an access.
pub const EXMC_MASTER_WRITE_LOW: u64 = 3;
pub const EXMC_MASTER_READ_LOW: u64 = 5;
pub const EXMC_MASTER_GAP: u64 = 2;

/// Wishbone front end ([`crate::hdl::wb_front`]): bus clocks from the cycle STB rises
/// to ACK, for a write and a read (ERR: 1).
pub const WB_WRITE_ACK: u64 = 1 + EXMC_MASTER_WRITE_LOW + 1;
pub const WB_READ_ACK: u64 = 1 + EXMC_MASTER_READ_LOW + 1;

/// AXI4-Lite front end ([`crate::hdl::axil_front`]): bus clocks from the handshake
/// (the later of AW and W; AR) to BVALID and RVALID, the ready signals high (a refused
/// access: 2).
pub const AXIL_WRITE_RESP: u64 = 2 + EXMC_MASTER_WRITE_LOW + 1;
pub const AXIL_READ_RESP: u64 = 2 + EXMC_MASTER_READ_LOW + 1;
