//! Turns a point-to-point move into segments.
//!
//! Three shorthands, all from rest to rest:
//! * [`trapezoid_by_times`]: (steps, t_acc, t_cruise, t_dec), as in the paper's
//!   experiment (20 ms / 10 ms / 20 ms);
//! * [`trapezoid_by_rates`]: (steps, speed, acceleration, deceleration) in integer
//!   steps/s and steps/s², integer-exact (the C planner `tdm_plan_rates` gives the
//!   same segments); a triangle when the move is too short to reach the speed;
//! * [`trapezoid_by_limits`]: (steps, v_max, a_max) in floating point, symmetric.
//!
//! Times are rounded to whole ticks, steps are split over the phases in proportion
//! to their area under the speed curve (largest remainder, so they sum exactly to
//! the request), and each segment's v0 is the previous segment's exact end speed
//! rounded to the Q0.32 rate unit, lowered by at most one unit where needed so that
//! no segment would have to reverse. The achieved peak speed and acceleration can
//! therefore differ from the request by the tick and step rounding (relative error
//! about 1/T_acc + 1/n_acc). Every segment is validated; an invalid one is an error.

use super::segment::{Limits, Segment, SegmentError, MAX_STEPS, MAX_T_TICKS, RATE_FRAC_BITS};
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
    /// An integer limit (speed, acceleration, deceleration, clock) of
    /// [`trapezoid_by_rates`] outside 1..=max: (name, value, max).
    LimitRange(&'static str, u64, u64),
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
            PlanError::LimitRange(what, v, max) => write!(f, "{what} = {v} is out of range: it must be 1 to {max}"),
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
        let mut dwells = Vec::new();
        for (index, &t) in phase_ticks.iter().enumerate().filter(|(_, &t)| t > 0) {
            let seg = Segment::dwell(t);
            seg.validate(limits).map_err(|error| PlanError::Segment { index, error })?;
            dwells.push(seg);
        }
        return Ok(dwells);
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

/// Largest acceleration or deceleration [`trapezoid_by_rates`] takes, steps/s².
pub const MAX_ACCEL: u32 = (1 << 31) - 1;
/// Largest clock [`trapezoid_by_rates`] takes, Hz (2^29, above the export's 400 MHz).
pub const MAX_PLAN_CLOCK_HZ: u32 = 1 << 29;

/// Round half up of `num / den`.
fn div_round(num: u128, den: u128) -> u128 {
    (2 * num + den) / (2 * den)
}

/// The triangle's phase of rate `x` (the other `y`): round(f·√(2n·y / (x·(x + y))))
/// ticks, the largest T with (2T − 1)²·x·(x + y) ≤ 8·n·y·f² (found by bisection, so
/// the C planner computes it the same way with 64×64-bit products).
fn triangle_phase_ticks(n: u64, x: u64, y: u64, f: u64) -> u64 {
    let rhs = (8 * n * y) as u128 * (f * f) as u128;
    let xx = x * (x + y);
    let fits = |t: u64| -> bool {
        let w = 2 * t - 1;
        (w * w) as u128 * xx as u128 <= rhs
    };
    let (mut lo, mut hi) = (0u64, (1u64 << 31) - 1); // fits(lo) or lo = 0; T ≤ hi
    if fits(hi) {
        return hi;
    }
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        if fits(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// Plans a rest-to-rest move given as a distance (`steps`, signed), a top speed
/// (steps/s), an acceleration and a deceleration (steps/s²), all integers, so that
/// the C planner (`tdm_plan_rates`) gives exactly the same segments.
///
/// With v the speed, a and d the rates and f the clock: when the move reaches v
/// (v²·(a + d) ≤ 2n·a·d) the phases are round(v·f/a), round(n·f/v − (T_a + T_d)/2)
/// (rounded half up, never below 0) and round(v·f/d) ticks; otherwise a triangle
/// with peak √(2n·a·d/(a + d)): T_a = round(f·√(2n·d/(a(a + d)))) and T_d likewise.
/// A phase the step split would leave without a step is not left as a dwell (the
/// next phase would start from rest and the move end at speed): a cruise shorter
/// than half a step is dropped, and when an accelerate or decelerate phase gets no
/// step (a short move with very unequal rates) the phases are planned again with
/// both rates at the smaller one. A move of one step is one segment from rest.
/// [`trapezoid_by_ticks`] then splits the steps over the phases. A move of 0 steps
/// gives no segment. Errors: a zero or out-of-range limit (speed above f, a or d
/// above [`MAX_ACCEL`], f above [`MAX_PLAN_CLOCK_HZ`]), more than 3·2^24 steps, a
/// phase longer than 2^30 ticks (error 4 on that phase), or a segment the core
/// would reject (a speed whose period is under the minimum: error 3).
pub fn trapezoid_by_rates(
    steps: i64,
    speed: u32,
    accel: u32,
    decel: u32,
    clock_hz: u32,
    limits: &Limits,
) -> Result<Vec<Segment>, PlanError> {
    for (what, v, max) in [
        ("clock_hz", clock_hz, MAX_PLAN_CLOCK_HZ),
        ("speed", speed, clock_hz),
        ("accel", accel, MAX_ACCEL),
        ("decel", decel, MAX_ACCEL),
    ] {
        if v == 0 || v > max {
            return Err(PlanError::LimitRange(what, v as u64, max as u64));
        }
    }
    let n = steps.unsigned_abs();
    if n == 0 {
        return Ok(Vec::new());
    }
    if n > 3 * MAX_STEPS as u64 {
        return Err(PlanError::TooManySteps(steps));
    }
    let (v, f) = (speed as u64, clock_hz as u64);
    // A phase the step split leaves without a step would start the next one from
    // rest (the move would end at speed): a cruise shorter than half a step is
    // dropped (in rate_phases); an accelerate or decelerate phase left empty by
    // very unequal rates is planned again with both rates at the smaller one.
    let mut ticks = rate_phases(n, v, accel as u64, decel as u64, f)?;
    let e = empty_phases(n, &ticks);
    if (e[0] || e[2]) && accel != decel {
        let r = accel.min(decel) as u64;
        ticks = rate_phases(n, v, r, r, f)?;
    }
    if n == 1 {
        // One step: one segment from rest over the whole time.
        ticks = [ticks[0] + ticks[1] + ticks[2], 0, 0];
        if ticks[0] > MAX_T_TICKS as u64 {
            return Err(PlanError::Segment { index: 0, error: SegmentError::TicksRange });
        }
    }
    trapezoid_by_ticks(steps, [ticks[0] as u32, ticks[1] as u32, ticks[2] as u32], limits)
}

/// The phases that have ticks but get no step from the step split.
fn empty_phases(n: u64, t: &[u64; 3]) -> [bool; 3] {
    let parts = apportion(n, [t[0], 2 * t[1], t[2]]);
    [t[0] > 0 && parts[0] == 0, t[1] > 0 && parts[1] == 0, t[2] > 0 && parts[2] == 0]
}

/// The phase durations of [`trapezoid_by_rates`], ticks (each checked ≤ 2^30), a
/// cruise that would get no step dropped.
fn rate_phases(n: u64, v: u64, a: u64, d: u64, f: u64) -> Result<[u64; 3], PlanError> {
    let reaches = (v * v) as u128 * (a + d) as u128 <= (2 * n * a) as u128 * d as u128;
    let mut ticks = if reaches {
        [div_round((v * f) as u128, a as u128) as u64, 0, div_round((v * f) as u128, d as u128) as u64]
    } else {
        [triangle_phase_ticks(n, a, d, f), 0, triangle_phase_ticks(n, d, a, f)]
    };
    for index in [0, 2] {
        if ticks[index] > MAX_T_TICKS as u64 {
            return Err(PlanError::Segment { index, error: SegmentError::TicksRange });
        }
    }
    if reaches {
        // 2·T_c = 2n·f/v − (T_a + T_d), rounded half up: ⌊(2n·f − v(T_a + T_d) + v) / 2v⌋.
        let num = (2 * n * f) as i128 - (v * (ticks[0] + ticks[2])) as i128 + v as i128;
        ticks[1] = if num <= 0 { 0 } else { (num / (2 * v) as i128) as u64 };
        if ticks[1] > MAX_T_TICKS as u64 {
            return Err(PlanError::Segment { index: 1, error: SegmentError::TicksRange });
        }
        if empty_phases(n, &ticks)[1] {
            ticks[1] = 0;
        }
    }
    Ok(ticks)
}

impl PlanError {
    /// The number the C planner returns for this error: the segment's error code
    /// (1..6) for [`PlanError::Segment`], negative for the others (units errors,
    /// which the C planner has no inputs for, are -23).
    pub fn c_code(&self) -> i32 {
        match self {
            PlanError::Segment { error, .. } => error.code() as i32,
            PlanError::NoDuration => -20,
            PlanError::BadLimit(..) | PlanError::LimitRange(..) => -21,
            PlanError::TooManySteps(_) => -22,
            PlanError::Unit(_) => -23,
        }
    }
}
