//! Turns a point-to-point move into segments.
//!
//! Two shorthands, both from rest to rest:
//! * [`trapezoid_by_times`]: (steps, t_acc, t_cruise, t_dec), as in the paper's
//!   experiment (20 ms / 10 ms / 20 ms);
//! * [`trapezoid_by_limits`]: (steps, v_max, a_max); a triangle when the move is
//!   too short to reach v_max.
//!
//! Times are rounded to whole ticks, steps are split over the phases in proportion
//! to their area under the speed curve (largest remainder, so they sum exactly to
//! the request), and each segment's v0 is the previous segment's exact end speed
//! rounded to the Q0.32 rate unit, lowered by at most one unit where needed so that
//! no segment would have to reverse. The achieved peak speed and acceleration can
//! therefore differ from the request by the tick and step rounding (relative error
//! about 1/T_acc + 1/n_acc). Every segment is validated; an invalid one is an error.

use super::segment::{Limits, Segment, SegmentError, MAX_STEPS, RATE_FRAC_BITS};
use super::units::{seconds_to_ticks, UnitError};
use std::fmt;

/// Why a move cannot be planned.
#[derive(Clone, Debug, PartialEq)]
pub enum PlanError {
    Unit(UnitError),
    /// All phase durations round to 0 ticks.
    NoDuration,
    /// A limit (v_max, a_max) that is not a positive finite number.
    BadLimit(&'static str, f64),
    /// More steps than one segment can carry in a phase.
    TooManySteps(i64),
    /// Phase `index` (0 accelerate, 1 cruise, 2 decelerate) is not a valid segment.
    Segment { index: usize, error: SegmentError },
}

impl fmt::Display for PlanError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PlanError::Unit(e) => write!(f, "{e}"),
            PlanError::NoDuration => write!(f, "the move has no duration (all phases round to 0 ticks)"),
            PlanError::BadLimit(what, v) => write!(f, "{what} = {v} must be a positive finite number"),
            PlanError::TooManySteps(s) => {
                write!(f, "{s} steps do not fit: each phase carries at most {MAX_STEPS} steps")
            }
            PlanError::Segment { index, error } => {
                let phase = ["accelerate", "cruise", "decelerate"].get(*index).unwrap_or(&"?");
                write!(f, "{phase} phase: {error}")
            }
        }
    }
}

impl std::error::Error for PlanError {}

impl From<UnitError> for PlanError {
    fn from(e: UnitError) -> Self {
        PlanError::Unit(e)
    }
}

/// Splits `total` into parts proportional to `weights` (largest remainder).
fn apportion(total: u64, weights: [u64; 3]) -> [u64; 3] {
    let sum: u128 = weights.iter().map(|&w| w as u128).sum();
    let mut parts = [0u64; 3];
    let mut rems = [(0u128, 0usize); 3];
    for k in 0..3 {
        let exact = total as u128 * weights[k] as u128;
        parts[k] = (exact / sum) as u64;
        rems[k] = (exact % sum, k);
    }
    let short = total - parts.iter().sum::<u64>();
    rems.sort_by(|a, b| b.0.cmp(&a.0).then(a.1.cmp(&b.1)));
    for &(_, k) in rems.iter().take(short as usize) {
        parts[k] += 1;
    }
    parts
}

/// Plans a rest-to-rest trapezoid from phase durations in ticks.
pub fn trapezoid_by_ticks(
    steps: i64,
    phase_ticks: [u32; 3],
    limits: &Limits,
) -> Result<Vec<Segment>, PlanError> {
    let total_ticks: u64 = phase_ticks.iter().map(|&t| t as u64).sum();
    if total_ticks == 0 {
        return Err(PlanError::NoDuration);
    }
    let n_total = steps.unsigned_abs();
    if steps == 0 {
        // No motion: wait for the whole duration, one dwell per non-empty phase.
        return Ok(phase_ticks.iter().filter(|&&t| t > 0).map(|&t| Segment::dwell(t)).collect());
    }
    // Area weights in half-ticks: accelerate T/2, cruise T, decelerate T/2.
    let weights = [phase_ticks[0] as u64, 2 * phase_ticks[1] as u64, phase_ticks[2] as u64];
    let parts = apportion(n_total, weights);
    if parts.iter().any(|&p| p > MAX_STEPS as u64) {
        return Err(PlanError::TooManySteps(steps));
    }
    let sign = steps.signum() as i32;
    let mut segments = Vec::new();
    let mut v_end_rate: u128 = 0; // the speed the axis has reached, Q0.32
    for (index, (&t, &n)) in phase_ticks.iter().zip(parts.iter()).enumerate() {
        if t == 0 {
            continue;
        }
        // Highest start rate that does not reverse: v0·T ≤ 2n.
        let no_reverse = ((2 * n as u128) << RATE_FRAC_BITS) / t as u128;
        let v0_rate = v_end_rate.min(no_reverse).min(u32::MAX as u128) as u32;
        let seg = Segment::new(v0_rate, t, sign * n as i32);
        seg.validate(limits).map_err(|error| PlanError::Segment { index, error })?;
        let v_end_t = seg.v_end_t_q32() as u128;
        v_end_rate = (v_end_t + t as u128 / 2) / t as u128;
        segments.push(seg);
    }
    Ok(segments)
}

/// Plans a rest-to-rest trapezoid from phase durations in seconds.
pub fn trapezoid_by_times(
    steps: i64,
    t_acc_s: f64,
    t_cruise_s: f64,
    t_dec_s: f64,
    clock_hz: u32,
    limits: &Limits,
) -> Result<Vec<Segment>, PlanError> {
    let ticks = [
        seconds_to_ticks(t_acc_s, clock_hz)?,
        seconds_to_ticks(t_cruise_s, clock_hz)?,
        seconds_to_ticks(t_dec_s, clock_hz)?,
    ];
    trapezoid_by_ticks(steps, ticks, limits)
}

/// Plans a rest-to-rest move limited by speed (steps/s) and acceleration (steps/s²).
pub fn trapezoid_by_limits(
    steps: i64,
    v_max: f64,
    a_max: f64,
    clock_hz: u32,
    limits: &Limits,
) -> Result<Vec<Segment>, PlanError> {
    for (what, v) in [("v_max", v_max), ("a_max", a_max)] {
        if !(v.is_finite() && v > 0.0) {
            return Err(PlanError::BadLimit(what, v));
        }
    }
    let n = steps.unsigned_abs() as f64;
    let d_acc = v_max * v_max / (2.0 * a_max);
    let (t_acc, t_cruise) = if 2.0 * d_acc >= n {
        ((n / a_max).sqrt(), 0.0)
    } else {
        (v_max / a_max, (n - 2.0 * d_acc) / v_max)
    };
    trapezoid_by_times(steps, t_acc, t_cruise, t_acc, clock_hz, limits)
}
