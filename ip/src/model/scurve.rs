//! S-curve moves: a jerk-limited (third-order, seven-phase) and a snap-limited
//! (fourth-order) profile, planned in continuous time and rounded to segments.
//!
//! * [`jerk_limited`]: distance, start and end speed, top speed, acceleration and
//!   its jerk, deceleration and its jerk. Up to seven phases: jerk +J, 0, −J
//!   (accelerate), cruise, jerk −Jd, 0, +Jd (decelerate). Degenerate cases fall out
//!   of the same construction: no cruise (the peak speed is found by bisection so
//!   that the distance is met), the acceleration limit not reached (no constant
//!   acceleration phase), a very short move, a move from and to a non-zero speed.
//! * [`fourth_order`]: the profile of the source design (snap piecewise constant,
//!   jerk continuous), by distance, speed, acceleration, jerk and snap, rest to rest.
//!   Each speed change raises the acceleration with a jerk-limited S of its own
//!   (snap +S, 0, −S), holds it, and lowers it the same way: up to 15 phases.
//!
//! # Rounding (docs/model.md, "S-curve planner")
//! The exact profile is built in f64 with only +, −, ×, ÷ and √ (each correctly
//! rounded, so the C planner computes the same numbers) and a fixed number of
//! bisection steps where a peak has no closed form. Its phase ends (phases longer
//! than 2^23 ticks split in equal parts) become the segment boundaries, each moved to
//! the time at which the profile reaches the nearest whole step (bisection), and that
//! time rounded to the nearest tick; a boundary that would leave a piece without a
//! step, or closer than [`MIN_PIECE_TICKS`] to the one before or to the end, is
//! dropped (its piece merges into the next). So every boundary is on the exact
//! profile (whole steps at times within ½ tick), and the steps sum exactly. The
//! speed at a boundary is the profile's there, rounded to the nearest Q0.32 rate (the
//! move's first and last are the requested start and end speeds). A piece that
//! overlaps a phase with snap is a quartic [`PolySegment`] with the profile's
//! acceleration at its start (A = a0·T²/2, rounded); any other piece, or one whose
//! quartic is invalid where its cubic is not, the cubic through its ends. Where the
//! rounding leaves a piece invalid (a rest end whose step count rounded the wrong
//! way, a short piece near RMAX), the rate at its far end, else its near end (never
//! the move's own end speeds), moves by the fewest rate units that make it and its
//! neighbour valid. Every segment is then validated; an invalid one is an error.
//!
//! Tested domain (`model_props`): v_max ≤ 0.95·RMAX and speed changes spanning at
//! least 4 steps (a, d ≤ v_max²/8); there every move plans, every boundary position
//! is within ½ step of the profile at its tick and every boundary speed between
//! pieces of 20 steps or more within 5% of v_max of the profile's (most within a
//! rate unit: the 5% is what a repair next to a merged short phase can take).

use super::axis::Motion;
use super::poly::{PolySegment, POLY_MAX_T_TICKS};
use super::segment::{Limits, SegmentError, RATE_FRAC_BITS};
use std::fmt;

/// Phases longer than this many ticks are split in equal parts.
pub const SPLIT_TICKS: u64 = 1 << 23;
/// A boundary closer than this many ticks to the one before (or to the move's end) is
/// dropped, so that the ½-tick rounding of a boundary moves a piece's mean speed by at
/// most 1/64 (0.8% at each end).
pub const MIN_PIECE_TICKS: u64 = 64;
/// The most segments one move plans into (the C planner's arrays).
pub const MAX_SCURVE_SEGMENTS: usize = 128;
/// Bisection steps for a peak speed or acceleration (enough to reach f64's resolution).
pub const BISECTION_STEPS: u32 = 100;

/// Why an S-curve move cannot be planned.
#[derive(Clone, Debug, PartialEq)]
pub enum ScurveError {
    /// A limit or speed that is not a finite number in range: (name, value).
    BadLimit(&'static str, f64),
    /// The move is shorter than the speed change it asks for (from v_start to v_end
    /// within the limits): the distance it needs, in steps.
    TooShort(f64),
    /// A stretch of the move without a step is longer than a segment can be (2^24
    /// ticks, or 2^30 for a cruise): the speed is too low for too long (a start from
    /// rest whose first step comes more than 2^24 ticks in, a jerk too small).
    TooSlow,
    /// The move needs more than [`MAX_SCURVE_SEGMENTS`] segments (more than about
    /// 128·2^23 ticks long): plan it as several moves.
    TooManySegments,
    /// Segment `index` is not valid.
    Segment { index: usize, error: SegmentError },
}

impl fmt::Display for ScurveError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ScurveError::BadLimit(what, v) => {
                write!(f, "{what} = {v} is not a valid limit (a positive finite number; speeds at most v_max)")
            }
            ScurveError::TooShort(need) => {
                write!(f, "the move is too short for its speed change: it needs at least {need:.1} steps")
            }
            ScurveError::TooSlow => {
                write!(f, "the move goes more than 2^24 ticks without a step (raise the jerk or the speed)")
            }
            ScurveError::TooManySegments => write!(f, "the move needs more than {MAX_SCURVE_SEGMENTS} segments: plan it as several moves"),
            ScurveError::Segment { index, error } => write!(f, "segment {index}: {error}"),
        }
    }
}

impl std::error::Error for ScurveError {}

impl ScurveError {
    /// The number the C planner returns for this error (as [`super::planner::PlanError::c_code`]).
    pub fn c_code(&self) -> i32 {
        match self {
            ScurveError::Segment { error, .. } => error.code() as i32,
            ScurveError::BadLimit(..) => -21,
            ScurveError::TooShort(_) => -24,
            ScurveError::TooSlow => -25,
            ScurveError::TooManySegments => -26,
        }
    }
}

/// One phase of the exact profile: `dur` seconds with jerk `jerk` at its start and
/// constant snap `snap` (steps/s³, steps/s⁴).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Phase {
    pub dur: f64,
    pub jerk: f64,
    pub snap: f64,
}

/// The exact profile: phases, with the state at each phase start.
#[derive(Clone, Debug, PartialEq)]
pub struct Profile {
    pub phases: Vec<Phase>,
    /// (t, x, v, a) at each phase start (s, steps, steps/s, steps/s²), and at the end.
    pub starts: Vec<[f64; 4]>,
}

impl Profile {
    fn new(v_start: f64, phases: Vec<Phase>) -> Profile {
        let phases: Vec<Phase> = phases.into_iter().filter(|p| p.dur > 0.0).collect();
        let mut starts = Vec::with_capacity(phases.len() + 1);
        let mut s = [0.0, 0.0, v_start, 0.0];
        for p in &phases {
            starts.push(s);
            s = Self::advance(s, p, p.dur);
        }
        starts.push(s);
        Profile { phases, starts }
    }

    fn advance(s: [f64; 4], p: &Phase, tau: f64) -> [f64; 4] {
        let [t, x, v, a] = s;
        let (j, q) = (p.jerk, p.snap);
        let t2 = tau * tau;
        let t3 = t2 * tau;
        [
            t + tau,
            x + v * tau + a * t2 / 2.0 + j * t3 / 6.0 + q * t3 * tau / 24.0,
            v + a * tau + j * t2 / 2.0 + q * t3 / 6.0,
            a + j * tau + q * t2 / 2.0,
        ]
    }

    /// Total duration, seconds.
    pub fn duration(&self) -> f64 {
        self.starts.last().unwrap()[0]
    }

    /// (x, v, a, jerk) at time t (clamped to the profile).
    pub fn state_at(&self, t: f64) -> [f64; 4] {
        let k = self.starts[..self.phases.len()].iter().rposition(|s| s[0] <= t).unwrap_or(0);
        if self.phases.is_empty() {
            let [_, x, v, a] = self.starts[0];
            return [x, v, a, 0.0];
        }
        let p = &self.phases[k];
        let tau = (t - self.starts[k][0]).clamp(0.0, p.dur);
        let [_, x, v, a] = Self::advance(self.starts[k], p, tau);
        [x, v, a, p.jerk + p.snap * tau]
    }
}

/// `BISECTION_STEPS` halvings of [lo, hi] keeping `below(lo)` and `!below(hi)`: the
/// final (lo, hi).
fn bisect(mut lo: f64, mut hi: f64, below: impl Fn(f64) -> bool) -> (f64, f64) {
    for _ in 0..BISECTION_STEPS {
        let mid = (lo + hi) / 2.0;
        if below(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    (lo, hi)
}

/// A change of `x` whose own rate is limited to `limit` and whose rate's rate is `r`
/// (a speed change: x = dv, limit = a, r = j; an acceleration ramp: x = ap, limit = j,
/// r = s): the ramp time and the hold at the limit, (√(x/r), 0) when the limit is not
/// reached, else (limit/r, x/limit − limit/r).
fn ramp(x: f64, limit: f64, r: f64) -> (f64, f64) {
    if x * r <= limit * limit {
        ((x / r).sqrt(), 0.0)
    } else {
        (limit / r, x / limit - limit / r)
    }
}

/// A speed change of `dv` ≥ 0 with acceleration limit `a`, jerk `j` and (fourth
/// order) snap `s`: its phases with the sign `sign` (+1 speeding up, −1 slowing).
fn speed_change(dv: f64, a: f64, j: f64, snap: Option<f64>, sign: f64) -> Vec<Phase> {
    if dv <= 0.0 {
        return Vec::new();
    }
    match snap {
        None => {
            // Jerk ±j for tj, a hold of the peak acceleration for th.
            let (tj, th) = ramp(dv, a, j);
            vec![
                Phase { dur: tj, jerk: sign * j, snap: 0.0 },
                Phase { dur: th, jerk: 0.0, snap: 0.0 },
                Phase { dur: tj, jerk: -sign * j, snap: 0.0 },
            ]
        }
        Some(s) => {
            // The acceleration rises to ap by an S of its own: snap ±s for ts, jerk ±j
            // held for tjh; rise time r(ap); the speed gained by rise and fall is ap·r(ap).
            let rise = |ap: f64| {
                if ap * s <= j * j {
                    2.0 * (ap / s).sqrt()
                } else {
                    ap / j + j / s
                }
            };
            let (ap, th) = if a * rise(a) <= dv {
                (a, (dv - a * rise(a)) / a)
            } else {
                (bisect(0.0, a, |ap| ap * rise(ap) <= dv).0, 0.0)
            };
            let (ts, tjh) = ramp(ap, j, s);
            let js = sign * s * ts; // the jerk reached
            let q = sign * s;
            vec![
                Phase { dur: ts, jerk: 0.0, snap: q },
                Phase { dur: tjh, jerk: js, snap: 0.0 },
                Phase { dur: ts, jerk: js, snap: -q },
                Phase { dur: th, jerk: 0.0, snap: 0.0 },
                Phase { dur: ts, jerk: 0.0, snap: -q },
                Phase { dur: tjh, jerk: -js, snap: 0.0 },
                Phase { dur: ts, jerk: -js, snap: q },
            ]
        }
    }
}

fn phases_duration(p: &[Phase]) -> f64 {
    p.iter().map(|p| p.dur).sum()
}

/// The limits of one side of the move (speeding up or slowing down).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SideLimits {
    /// Acceleration (steps/s²), jerk (steps/s³) and, for the fourth order, snap (steps/s⁴).
    pub accel: f64,
    pub jerk: f64,
    pub snap: Option<f64>,
}

/// The exact profile of a move of `dist` > 0 steps from `v0` to `v1` (steps/s) with
/// top speed `vmax`: the peak speed vp ∈ [max(v0, v1), vmax] is vmax with a cruise
/// when the two speed changes fit, else the one whose two speed changes cover
/// exactly `dist` (bisection; the distance of a speed change from va to vb is
/// (va + vb)/2 times its duration, its speed curve being point-symmetric).
pub fn profile(
    dist: f64,
    v0: f64,
    v1: f64,
    vmax: f64,
    up: SideLimits,
    down: SideLimits,
) -> Result<Profile, ScurveError> {
    let acc = |vp: f64| speed_change(vp - v0, up.accel, up.jerk, up.snap, 1.0);
    let dec = |vp: f64| speed_change(vp - v1, down.accel, down.jerk, down.snap, -1.0);
    let need = |vp: f64| (v0 + vp) / 2.0 * phases_duration(&acc(vp)) + (vp + v1) / 2.0 * phases_duration(&dec(vp));
    let floor = if v0 > v1 { v0 } else { v1 };
    if need(floor) > dist {
        return Err(ScurveError::TooShort(need(floor)));
    }
    let (vp, cruise) = if need(vmax) <= dist {
        (vmax, (dist - need(vmax)) / vmax)
    } else {
        (bisect(floor, vmax, |vp| need(vp) <= dist).0, 0.0)
    };
    let mut phases = acc(vp);
    phases.push(Phase { dur: cruise, jerk: 0.0, snap: 0.0 });
    phases.extend(dec(vp));
    Ok(Profile::new(v0, phases))
}

fn check_limit(what: &'static str, v: f64, zero_ok: bool) -> Result<f64, ScurveError> {
    if v.is_finite() && (v > 0.0 || (zero_ok && v == 0.0)) {
        Ok(v)
    } else {
        Err(ScurveError::BadLimit(what, v))
    }
}

/// Plans a jerk-limited move: `steps` (signed) from `v_start` to `v_end` (steps/s, ≥ 0,
/// ≤ `v_max`), acceleration `a_max` with jerk `j_max`, deceleration `d_max` with jerk
/// `jd_max`, at `clock_hz`. Returns its segments, each valid for `limits`.
#[allow(clippy::too_many_arguments)]
pub fn jerk_limited(
    steps: i64,
    v_start: f64,
    v_end: f64,
    v_max: f64,
    a_max: f64,
    j_max: f64,
    d_max: f64,
    jd_max: f64,
    clock_hz: u32,
    limits: &Limits,
) -> Result<Vec<Motion>, ScurveError> {
    let up = SideLimits {
        accel: check_limit("a_max", a_max, false)?,
        jerk: check_limit("j_max", j_max, false)?,
        snap: None,
    };
    let down = SideLimits {
        accel: check_limit("d_max", d_max, false)?,
        jerk: check_limit("jd_max", jd_max, false)?,
        snap: None,
    };
    plan(steps, v_start, v_end, v_max, up, down, clock_hz, limits)
}

/// Plans the fourth-order (snap-limited) profile of the source design, rest to rest:
/// `steps` (signed), top speed `v_max`, acceleration `a_max`, jerk `j_max`, snap
/// `s_max` (the same for speeding up and slowing down), at `clock_hz`.
pub fn fourth_order(
    steps: i64,
    v_max: f64,
    a_max: f64,
    j_max: f64,
    s_max: f64,
    clock_hz: u32,
    limits: &Limits,
) -> Result<Vec<Motion>, ScurveError> {
    let side = SideLimits {
        accel: check_limit("a_max", a_max, false)?,
        jerk: check_limit("j_max", j_max, false)?,
        snap: Some(check_limit("s_max", s_max, false)?),
    };
    plan(steps, 0.0, 0.0, v_max, side, side, clock_hz, limits)
}

/// A boundary between segments: its tick, position (steps), rate (Q0.32) and the
/// exact acceleration there (steps/tick²).
#[derive(Clone, Copy, Debug)]
struct Boundary {
    tick: u64,
    pos: i64,
    rate: u32,
    acc: f64,
}

#[allow(clippy::too_many_arguments)]
fn plan(
    steps: i64,
    v_start: f64,
    v_end: f64,
    v_max: f64,
    up: SideLimits,
    down: SideLimits,
    clock_hz: u32,
    limits: &Limits,
) -> Result<Vec<Motion>, ScurveError> {
    if clock_hz == 0 {
        return Err(ScurveError::BadLimit("clock_hz", 0.0));
    }
    let v_max = check_limit("v_max", v_max, false)?;
    let v_start = check_limit("v_start", v_start, true)?;
    let v_end = check_limit("v_end", v_end, true)?;
    if v_start > v_max {
        return Err(ScurveError::BadLimit("v_start", v_start));
    }
    if v_end > v_max {
        return Err(ScurveError::BadLimit("v_end", v_end));
    }
    let f = clock_hz as f64;
    let one = (1u64 << RATE_FRAC_BITS) as f64;
    let rate = |v: f64| -> u32 { (v / f * one).round().min(u32::MAX as f64) as u32 };
    if rate(v_max) > limits.max_rate() {
        return Err(ScurveError::Segment { index: 0, error: SegmentError::PeriodTooShort });
    }
    let n = steps.unsigned_abs() as i64;
    if n == 0 {
        return Ok(Vec::new());
    }
    let prof = profile(n as f64, v_start, v_end, v_max, up, down)?;
    let total_s = prof.duration();
    let total = (total_s * f).round() as u64;
    // Candidate boundaries: each phase end, long phases split into parts of at most
    // 2^23 ticks.
    let count = prof.phases.len();
    let mut cand: Vec<f64> = Vec::new();
    for k in 0..count {
        let (t0, t1) = (prof.starts[k][0], prof.starts[k + 1][0]);
        let parts = ((t1 - t0) * f / SPLIT_TICKS as f64).ceil().max(1.0) as u64;
        for i in 1..=parts {
            cand.push(t0 + (t1 - t0) * i as f64 / parts as f64);
        }
    }
    cand.pop(); // the move's end
    // The time at which the exact profile reaches position x (it never moves back).
    let time_of = |x: f64| -> f64 { bisect(0.0, total_s, |t| prof.state_at(t)[0] < x).1 };
    // Each boundary moves to where the profile reaches the nearest whole step, and
    // that time is rounded to a tick: (tick, position, exact time). A boundary that
    // would leave a piece without a step or without a tick is dropped (merged).
    let mut marks: Vec<(u64, i64, f64)> = vec![(0, 0, 0.0)];
    for t in cand {
        let xs = prof.state_at(t)[0].round() as i64;
        let last = *marks.last().unwrap();
        if xs <= last.1 || xs >= n {
            continue;
        }
        let ts = time_of(xs as f64);
        let tick = (ts * f).round() as u64;
        if tick < last.0 + MIN_PIECE_TICKS || tick + MIN_PIECE_TICKS > total {
            continue;
        }
        marks.push((tick, xs, ts));
    }
    marks.push((total, n, total_s));
    if marks.len() - 1 > MAX_SCURVE_SEGMENTS {
        return Err(ScurveError::TooManySegments);
    }
    // Each piece: may it be a quartic (it overlaps a phase with snap)?
    let mut ticks: Vec<(u64, bool)> = vec![(0, false)]; // (tick, overlaps snap)
    for k in 1..marks.len() {
        let (t0, t1) = (marks[k - 1].2, marks[k].2);
        let snap =
            (0..count).any(|p| prof.phases[p].snap != 0.0 && prof.starts[p][0] < t1 && prof.starts[p + 1][0] > t0);
        if marks[k].0 - marks[k - 1].0 > POLY_MAX_T_TICKS as u64 {
            return Err(ScurveError::TooSlow);
        }
        ticks.push((marks[k].0, snap));
    }
    let sign = steps.signum();
    let f2 = f * f;
    let mut bounds: Vec<Boundary> = marks
        .iter()
        .map(|&(tick, pos, ts)| {
            let [_, v, a, _] = prof.state_at(ts);
            Boundary { tick, pos, rate: rate(v), acc: a / f2 }
        })
        .collect();
    bounds.first_mut().unwrap().rate = rate(v_start);
    bounds.last_mut().unwrap().rate = rate(v_end);
    // Segment k (1-based) from its boundaries; `snap` as a quartic, else a cubic.
    let make = |k: usize, b: &[Boundary], snap: bool| -> Motion {
        let (s, e) = (b[k - 1], b[k]);
        let t = (e.tick - s.tick) as u32;
        let theta = (sign * (e.pos - s.pos)) as i32;
        if snap {
            let a_q32 = (s.acc * (t as f64) * (t as f64) / 2.0 * one).round() as i64;
            Motion::Poly(PolySegment::new(s.rate, e.rate, a_q32, t, theta))
        } else {
            Motion::Poly(PolySegment::cubic(s.rate, e.rate, t, theta).expect("A fits"))
        }
    };
    let last = bounds.len() - 1;
    let rmax = limits.max_rate() as i64;
    let mut snaps: Vec<bool> = ticks.iter().map(|t| t.1).collect();
    let mut out: Vec<Motion> = Vec::with_capacity(bounds.len());
    for k in 1..bounds.len() {
        // A piece that overlaps a phase with snap is a quartic with the exact start
        // acceleration, else (or when the quartic is invalid and the cubic is not) the
        // cubic through its ends. Rounding can leave both outside the range (a rest end
        // whose step count rounded the wrong way, a short piece at a speed near RMAX):
        // then the rate at the piece's far end, else at its near end (never the move's
        // own end speeds), moves by the fewest rate units that make the piece and its
        // neighbour valid, in the form that needs the fewest.
        let forms: &[bool] = if snaps[k] { &[true, false] } else { &[false] };
        let mut chosen = None;
        for &snap in forms {
            if make(k, &bounds, snap).validate(limits).is_ok() {
                chosen = Some(snap);
                break;
            }
        }
        if chosen.is_none() {
            let mut best: Option<(i64, bool, usize, Vec<Boundary>)> = None;
            for &snap in forms {
                for which in [k, k - 1] {
                    if which == 0 || which == last {
                        continue;
                    }
                    let valid = |b: &[Boundary]| {
                        make(k, b, snap).validate(limits).is_ok()
                            && (which == k || make(k - 1, b, snaps[k - 1]).validate(limits).is_ok())
                    };
                    let at = |delta: i64| -> Option<Vec<Boundary>> {
                        let r = bounds[which].rate as i64 + delta;
                        if !(0..=rmax).contains(&r) {
                            return None;
                        }
                        let mut b = bounds.clone();
                        b[which].rate = r as u32;
                        valid(&b).then_some(b)
                    };
                    // Nearest first: ±1, ±2, ±4, …; then bisect down to the smallest step.
                    let found =
                        (0..32).find_map(|e| [-1i64, 1].into_iter().find_map(|sg| at(sg << e).map(|_| (sg, e))));
                    if let Some((sg, e)) = found {
                        let (mut lo, mut hi) = (if e == 0 { 0 } else { 1i64 << (e - 1) }, 1i64 << e); // invalid, valid
                        while hi - lo > 1 {
                            let mid = lo + (hi - lo) / 2;
                            if at(sg * mid).is_some() {
                                hi = mid;
                            } else {
                                lo = mid;
                            }
                        }
                        if best.as_ref().is_none_or(|b| hi < b.0) {
                            best = Some((hi, snap, which, at(sg * hi).unwrap()));
                        }
                        break;
                    }
                }
            }
            if let Some((_, snap, which, b)) = best {
                bounds = b;
                if which == k - 1 {
                    out[k - 2] = make(k - 1, &bounds, snaps[k - 1]);
                }
                chosen = Some(snap);
            }
        }
        snaps[k] = chosen.unwrap_or(false);
        out.push(make(k, &bounds, snaps[k]));
    }
    for (index, m) in out.iter().enumerate() {
        m.validate(limits).map_err(|error| ScurveError::Segment { index, error })?;
    }
    Ok(out)
}
