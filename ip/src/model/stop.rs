//! The controlled stop (category 1): the segment the core forms itself to bring an
//! axis from its current speed to rest at a configured deceleration.
//!
//! When a stop reaches an axis, the core cuts the axis's motion after the last period
//! it has computed (the periods already in the period FIFO still run), drops
//! everything queued, and sets up one decelerating segment from that last period Δ
//! (ticks, the speed the axis has when the ramp begins):
//!
//! ```text
//! v0 = ⌊2^32 / (Δ + 1)⌋            (Q0.32 steps/tick, at most 1/(Δ + 1))
//! n  = ⌊v0² / (256 · DECEL)⌋ + 1    (steps; the distance v²/2a, rounded up, one more
//!                                    when it is whole: no adder before the divide)
//! T  = 2 · n · (Δ + 1)              (ticks)
//! ```
//!
//! with the steps signed in the direction of that last step. Its end speed is
//! 2n/T − v0/2^32 = 1/(Δ + 1) − v0/2^32, in [0, 2^-32): it ends at rest (to within one
//! rate unit) and never reverses. Its first rate is at most 1/(Δ + 1), so no period of
//! the ramp is shorter than the one before it (Δ ≥ the export's minimum period, so v0
//! is at most RMAX and the segment passes [`Segment::validate`]). It is an ordinary
//! segment: the core runs it on the shared unit like any other, with the same
//! 0.625-tick edge bound.
//!
//! `DECEL` is the deceleration a in steps/tick² as an unsigned Q-57 number,
//! a = DECEL / 2^57 ([`decel_from_steps_per_s2`]); the distance v²/(2a) in steps is
//! (v0/2^32)² / (2 · DECEL / 2^57) = v0² / (256 · DECEL). The ramp's deceleration is at
//! most a · 2^32 / (2^32 − Δ − 1) (the rounding of v0; under a · (1 + 2^-8)) and is
//! lower by the rounding up of n.
//!
//! Range: a `DECEL` below [`stop_decel_min`] of the export's limits is refused (below
//! it a stop from the top rate may not fit one segment, 2^30 ticks and 2^24 steps). An axis whose last period is 0 (a dwell) or at least
//! [`STOP_REST_PERIOD`] ticks is taken as at rest: it only loses its queue, and no
//! ramp is formed.

use super::axis::{AxisRun, FifoEntry};
use super::segment::{Limits, Segment};

/// A last period of at least this many ticks (0.34 s at 50 MHz) counts as rest.
pub const STOP_REST_PERIOD: u32 = (1 << 24) - 1;
/// Fractional bits of the deceleration register (a = DECEL / 2^57 steps/tick²).
pub const DECEL_FRAC_BITS: u32 = 57;

/// The smallest `DECEL` the export accepts: max(⌈RMAX/31⌉, ⌈RMAX² / (256·(2^24 − 1))⌉),
/// so that a stop from any rate up to RMAX fits one segment (T ≤ 2^30, n ≤ 2^24: n is at
/// most v0²/(256·DECEL) + 1).
pub fn stop_decel_min(limits: &Limits) -> u32 {
    let rmax = limits.max_rate() as u128;
    let by_t = rmax.div_ceil(31);
    let by_n = (rmax * rmax).div_ceil(256 * ((1u128 << 24) - 1));
    by_t.max(by_n).max(1) as u32
}

/// The `DECEL` register value for a deceleration in steps/s² at `clock_hz`, rounded to
/// nearest; None when it falls outside 1 ..= 2^32 − 1.
pub fn decel_from_steps_per_s2(steps_per_s2: f64, clock_hz: f64) -> Option<u32> {
    let v = (steps_per_s2 / (clock_hz * clock_hz) * (1u64 << DECEL_FRAC_BITS) as f64).round();
    (v >= 1.0 && v <= u32::MAX as f64).then_some(v as u32)
}

/// The stop segment from last period `delta` (ticks) and `decel`, stepping in the
/// negative direction when `reverse`; None when the axis counts as at rest (`delta` 0
/// or ≥ [`STOP_REST_PERIOD`]). `decel` must be at least [`stop_decel_min`] (checked
/// when it is written).
pub fn stop_segment(delta: u32, decel: u32, reverse: bool) -> Option<Segment> {
    if delta == 0 || delta >= STOP_REST_PERIOD || decel == 0 {
        return None;
    }
    let d1 = delta as u64 + 1;
    let v0 = (1u64 << 32) / d1;
    let n = ((v0 as u128 * v0 as u128) / (256 * decel as u128)) as u64 + 1;
    let t = 2 * n * d1;
    let steps = if reverse { -(n as i64) } else { n as i64 };
    Some(Segment::new(v0 as u32, t.min(u32::MAX as u64) as u32, steps.clamp(i32::MIN as i64, i32::MAX as i64) as i32))
}

/// The stop the model forms after the first `cut` entries of an axis's FIFO stream: the
/// ramp from the last of them, if that is a step at speed (None at rest or `cut` = 0).
pub fn stop_after(fifo: &[FifoEntry], cut: usize, decel: u32) -> Option<Segment> {
    let last = fifo[..cut].last()?;
    if !last.step {
        return None;
    }
    stop_segment(last.ticks, decel, last.reverse)
}

/// What an axis does when a controlled stop cuts `run` after its first `cut` FIFO
/// entries: those entries, then the stop ramp (if any). Edges and position follow. A
/// cut after the last entry (the whole move already computed) leaves the move as it
/// is: it ends as planned, and no ramp is added after it.
pub fn cut_run(run: &AxisRun, cut: usize, decel: u32, limits: &Limits) -> AxisRun {
    let mut out = AxisRun::default();
    let mut edge = 0u64;
    for e in &run.fifo[..cut] {
        edge += e.ticks as u64;
        out.fifo.push(*e);
        if e.step {
            out.edge_ticks.push(edge);
            out.exact_ticks.push(f64::NAN);
            out.position += if e.reverse { -1 } else { 1 };
        }
    }
    out.end_tick = edge;
    let ramp = if cut < run.fifo.len() { stop_after(&run.fifo, cut, decel) } else { None };
    if let Some(seg) = ramp {
        let ramp = AxisRun::run(&[seg], limits);
        assert!(ramp.rejected.is_empty(), "stop segment {seg:?} rejected: {:?}", ramp.rejected);
        for (e, x) in ramp.edge_ticks.iter().zip(&ramp.exact_ticks) {
            out.edge_ticks.push(edge + e);
            out.exact_ticks.push(edge as f64 + x);
        }
        out.fifo.extend(&ramp.fifo);
        out.position += ramp.position;
        out.end_tick = edge + ramp.end_tick;
        out.accepted.push(seg);
        out.motions.push(seg.into());
    }
    out
}
