//! Exact kinematics of a segment, the reference every other model is judged by.
//!
//! The segment is taken at its register values: v0 = v0_rate/2^32 steps/tick,
//! T ticks, n steps, α = 2(n − v0·T)/T². Step i happens at
//!
//! ```text
//! t_i = 2i / (v0 + sqrt(v0² + 2αi))      (stable form of paper eq. 7; t_n = T)
//! ```
//!
//! The f64 form here avoids both cancellations a naive evaluation has: D = n − v0·T
//! and the radicand `v0² + 2αi` are formed exactly in i128 before any rounding, so
//! t_i carries only a few ulps of relative error (about 1e-6 ticks at T = 2^30).
//!
//! [`edge_within`] is an independent, exact check in integers: it decides whether
//! an integer tick lies within a whole number of ticks of t_i without any floating
//! point, using the monotonic position function pos(t) = v0·t + D·t²/T².

use super::segment::{Segment, RATE_FRAC_BITS};

/// w_k·T·2^32, the speed after k steps scaled by T·2^32: the square root of
/// (v0² + 2αk)·T²·2^64 = (v0·T·2^32)² + 4·k·D·2^32·2^32, whose radicand is exact.
fn speed_scaled(seg: &Segment, k: u32) -> f64 {
    let v0t = seg.v0_rate as i128 * seg.t_ticks as i128;
    let radicand = v0t * v0t + 4 * (k as i128) * seg.d_q32() * (1i128 << RATE_FRAC_BITS);
    (radicand.max(0) as f64).sqrt()
}

/// T·2^32, the scale of [`speed_scaled`].
fn speed_scale(seg: &Segment) -> f64 {
    seg.t_ticks as f64 * (1u64 << RATE_FRAC_BITS) as f64
}

/// Exact time of step i (1 ≤ i ≤ n) after the segment start, in ticks:
/// t_i = 2i / (v0 + w_i), both speeds scaled by T·2^32.
pub fn step_time(seg: &Segment, i: u32) -> f64 {
    debug_assert!(i >= 1 && i <= seg.n_steps());
    2.0 * i as f64 * speed_scale(seg) / (speed_scaled(seg, 0) + speed_scaled(seg, i))
}

/// Exact times of all steps of a segment, t_1..t_n, relative to its start.
pub fn step_times(seg: &Segment) -> Vec<f64> {
    (1..=seg.n_steps()).map(|i| step_time(seg, i)).collect()
}

/// Exact period of step i (t_i − t_{i−1}, t_0 = 0) in ticks, without cancellation:
/// t_i − t_{i−1} = 2/(w_{i−1} + w_i) in steps/tick.
pub fn step_period(seg: &Segment, i: u32) -> f64 {
    debug_assert!(i >= 1 && i <= seg.n_steps());
    2.0 * speed_scale(seg) / (speed_scaled(seg, i - 1) + speed_scaled(seg, i))
}

/// pos(t)·T²·2^32 for an integer tick t: v0_rate·T²·t + D·2^32·t².
fn pos_scaled(seg: &Segment, t: i128) -> i128 {
    let tt = seg.t_ticks as i128;
    seg.v0_rate as i128 * tt * tt * t + seg.d_q32() * t * t
}

/// Exactly decides |tick − t_i| ≤ tol_ticks for step i of a valid segment.
///
/// pos(t) is increasing on [0, T] for a valid segment (its speed never goes
/// negative), so t_i ∈ [tick − tol, tick + tol] ⟺ pos(tick − tol) ≤ i ≤ pos(tick + tol),
/// with the ends clamped to [0, T] where t_i always lies. All in i128 (< 2^123).
pub fn edge_within(seg: &Segment, i: u32, tick: i64, tol_ticks: i64) -> bool {
    let t = seg.t_ticks as i128;
    let lo = (tick as i128 - tol_ticks as i128).max(0);
    let hi = (tick as i128 + tol_ticks as i128).min(t);
    if lo > hi {
        return false;
    }
    let target = (i as i128) * t * t * (1i128 << RATE_FRAC_BITS);
    pos_scaled(seg, lo) <= target && target <= pos_scaled(seg, hi)
}

/// Speed at a time t (ticks) into the segment, in steps/tick: v0 + α·t.
pub fn speed_at(seg: &Segment, t_ticks: f64) -> f64 {
    let v0 = seg.v0_rate as f64 / (1u64 << RATE_FRAC_BITS) as f64;
    let tt = seg.t_ticks as f64;
    let alpha = 2.0 * (seg.d_q32() as f64 / (1u64 << RATE_FRAC_BITS) as f64) / (tt * tt);
    v0 + alpha * t_ticks
}
