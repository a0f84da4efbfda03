//! A motion segment in register units, its documented range, and validation.
//!
//! A segment is what the host writes for one axis: start speed `v0_rate`,
//! duration `t_ticks` and signed step count `steps` (θ). The core runs the
//! segment with constant acceleration α = 2(n − v0·T)/T² (paper eq. 2), so that
//! exactly n = |θ| steps are emitted in exactly T ticks.
//!
//! Units (shared with the registers, see docs/model.md):
//! - `v0_rate`: steps per clock tick as an unsigned Q0.32 fraction
//!   (`v0 = v0_rate / 2^32` steps/tick). [`crate::model::units`] converts from steps/s.
//! - `t_ticks`: clock ticks, 1 ..= 2^30.
//! - `steps`: signed step count θ, |θ| ≤ 2^24; the sign is the direction.

use serde::{Deserialize, Serialize};
use std::fmt;

/// Fractional bits of `v0_rate` (Q0.32 steps per tick).
pub const RATE_FRAC_BITS: u32 = 32;
/// Longest segment, in ticks (about 10.7 s at 100 MHz, 21.5 s at 50 MHz).
pub const MAX_T_TICKS: u32 = 1 << 30;
/// Largest |θ| of one segment.
pub const MAX_STEPS: u32 = 1 << 24;
/// Largest start rate: just under 0.5 steps/tick (a 2-tick period).
pub const MAX_V0_RATE: u32 = (1 << 31) - 1;
/// The smallest minimum period the core accepts: one tick high, one tick low.
pub const MIN_PERIOD_FLOOR_TICKS: u32 = 2;
/// The largest configurable minimum period.
pub const MIN_PERIOD_CEIL_TICKS: u32 = 1 << 20;

/// One motion segment of one axis, in register units.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Segment {
    /// Start speed, Q0.32 steps per tick.
    pub v0_rate: u32,
    /// Duration in clock ticks.
    pub t_ticks: u32,
    /// Signed step count θ; the sign gives the direction.
    pub steps: i32,
}

/// Why a segment is rejected. The numeric codes are the ones the axis status
/// register reports; they never change meaning.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[repr(u8)]
pub enum SegmentError {
    /// T = 0.
    TicksZero = 1,
    /// The final speed 2n/T − v0 would be below zero: the axis would have to reverse.
    Reverses = 2,
    /// The peak step rate needs a period under the configured minimum.
    PeriodTooShort = 3,
    /// T above [`MAX_T_TICKS`].
    TicksRange = 4,
    /// |θ| above [`MAX_STEPS`].
    StepsRange = 5,
    /// `v0_rate` above [`MAX_V0_RATE`].
    RateRange = 6,
}

impl SegmentError {
    /// Every error, in code order.
    pub const ALL: [SegmentError; 6] = [
        SegmentError::TicksZero,
        SegmentError::Reverses,
        SegmentError::PeriodTooShort,
        SegmentError::TicksRange,
        SegmentError::StepsRange,
        SegmentError::RateRange,
    ];

    /// The status-register code (never 0; 0 means no error).
    pub fn code(self) -> u8 {
        self as u8
    }

    /// The error with this status code, if any.
    pub fn from_code(code: u8) -> Option<SegmentError> {
        Self::ALL.into_iter().find(|e| e.code() == code)
    }

    /// Short upper-case name, as in the C header.
    pub fn name(self) -> &'static str {
        match self {
            SegmentError::TicksZero => "TICKS_ZERO",
            SegmentError::Reverses => "REVERSES",
            SegmentError::PeriodTooShort => "PERIOD_TOO_SHORT",
            SegmentError::TicksRange => "TICKS_RANGE",
            SegmentError::StepsRange => "STEPS_RANGE",
            SegmentError::RateRange => "RATE_RANGE",
        }
    }
}

impl fmt::Display for SegmentError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let what = match self {
            SegmentError::TicksZero => "segment duration T is 0 ticks".to_string(),
            SegmentError::Reverses => {
                "final speed 2n/T - v0 would be negative (the deceleration would reverse)".to_string()
            }
            SegmentError::PeriodTooShort => {
                "peak step rate needs a period under the configured minimum".to_string()
            }
            SegmentError::TicksRange => format!("T above the maximum of {MAX_T_TICKS} ticks"),
            SegmentError::StepsRange => format!("|steps| above the maximum of {MAX_STEPS}"),
            SegmentError::RateRange => format!("v0_rate above the maximum of {MAX_V0_RATE}"),
        };
        write!(f, "error {} ({}): {}", self.code(), self.name(), what)
    }
}

impl std::error::Error for SegmentError {}

/// The range checks every kind of segment makes first, in this order: T = 0, T above
/// `max_t_ticks`, n above [`MAX_STEPS`], a rate (the largest of the segment's) above
/// [`MAX_V0_RATE`].
pub(crate) fn check_range(t_ticks: u32, max_t_ticks: u32, n_steps: u32, rate: u32) -> Result<(), SegmentError> {
    if t_ticks == 0 {
        return Err(SegmentError::TicksZero);
    }
    if t_ticks > max_t_ticks {
        return Err(SegmentError::TicksRange);
    }
    if n_steps > MAX_STEPS {
        return Err(SegmentError::StepsRange);
    }
    if rate > MAX_V0_RATE {
        return Err(SegmentError::RateRange);
    }
    Ok(())
}

/// Per-core limits that validation depends on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Limits {
    /// Every emitted step period is at least this many ticks.
    pub min_period_ticks: u32,
}

impl Default for Limits {
    fn default() -> Self {
        Limits { min_period_ticks: MIN_PERIOD_FLOOR_TICKS }
    }
}

impl Limits {
    /// Limits with the given minimum period, checked against the supported range.
    pub fn new(min_period_ticks: u32) -> Result<Limits, String> {
        if !(MIN_PERIOD_FLOOR_TICKS..=MIN_PERIOD_CEIL_TICKS).contains(&min_period_ticks) {
            return Err(format!(
                "minimum period {min_period_ticks} ticks is outside {MIN_PERIOD_FLOOR_TICKS}..={MIN_PERIOD_CEIL_TICKS}"
            ));
        }
        Ok(Limits { min_period_ticks })
    }

    /// RMAX = ⌊2^32 / (min_period + 1)⌋: the largest rate (Q0.32 steps/tick) at either
    /// end of a segment.
    pub fn max_rate(&self) -> u32 {
        ((1u64 << RATE_FRAC_BITS) / (self.min_period_ticks as u64 + 1)) as u32
    }
}

impl Segment {
    /// A segment from its three register values.
    pub const fn new(v0_rate: u32, t_ticks: u32, steps: i32) -> Segment {
        Segment { v0_rate, t_ticks, steps }
    }

    /// A dwell: no steps, the axis waits `t_ticks`.
    pub const fn dwell(t_ticks: u32) -> Segment {
        Segment { v0_rate: 0, t_ticks, steps: 0 }
    }

    /// n = |θ|.
    pub fn n_steps(&self) -> u32 {
        self.steps.unsigned_abs()
    }

    /// True when the segment steps in the negative direction.
    pub fn reverse(&self) -> bool {
        self.steps < 0
    }

    /// D·2^32 = (n − v0·T)·2^32, exact. Positive: accelerate; negative: decelerate.
    pub fn d_q32(&self) -> i128 {
        ((self.n_steps() as i128) << RATE_FRAC_BITS) - (self.v0_rate as i128) * (self.t_ticks as i128)
    }

    /// The final speed times T, in Q32: (2n − v0·T)·2^32 = v_end·T·2^32. Exact.
    pub fn v_end_t_q32(&self) -> i128 {
        ((2 * self.n_steps() as i128) << RATE_FRAC_BITS) - (self.v0_rate as i128) * (self.t_ticks as i128)
    }

    /// The segment with an odd `v0_rate` whose D·2^32 = n·2^32 − v0_rate·T equals
    /// `d_q32` exactly: T solves v0_rate·T ≡ −d (mod 2^32). With |d| small it is nearly
    /// uniform and P is huge. None when T or n falls outside the range (not validated).
    pub fn with_tiny_d(v0_rate_odd: u32, d_q32: i64, reverse: bool) -> Option<Segment> {
        let v0 = v0_rate_odd as u64;
        if v0 % 2 == 0 {
            return None;
        }
        // Inverse of v0 mod 2^64 by Newton's iteration (each step doubles the bits).
        let inv = (0..6).fold(v0, |x, _| x.wrapping_mul(2u64.wrapping_sub(v0.wrapping_mul(x))));
        let t = (d_q32.wrapping_neg() as u64).wrapping_mul(inv) & 0xffff_ffff;
        if t == 0 || t > MAX_T_TICKS as u64 {
            return None;
        }
        let n = (d_q32 as i128 + v0 as i128 * t as i128) >> RATE_FRAC_BITS;
        if n <= 0 || n > MAX_STEPS as i128 {
            return None;
        }
        let steps = if reverse { -(n as i32) } else { n as i32 };
        Some(Segment::new(v0_rate_odd, t as u32, steps))
    }

    /// True when the segment would reverse only by the rounding of v0 to Q0.32: its
    /// end speed is below zero by less than one rate unit, −T < v_end·T·2^32 < 0.
    /// Such a segment is a deceleration to rest whose v0 was rounded up (v0 =
    /// round(2n·2^32/T) when 2n·2^32/T is not whole).
    pub fn rounds_past_rest(&self) -> bool {
        let v_end_t = self.v_end_t_q32();
        v_end_t < 0 && v_end_t + self.t_ticks as i128 > 0
    }

    /// The segment the core runs: itself, or with `v0_rate − 1` when it
    /// [`rounds_past_rest`](Self::rounds_past_rest) (then 0 ≤ v_end·T·2^32 < T: it
    /// ends at rest or within one rate unit of it). Both emit exactly n steps in T
    /// ticks; the exact kinematics of this one are the reference for its edges.
    pub fn effective(&self) -> Segment {
        if self.rounds_past_rest() {
            Segment { v0_rate: self.v0_rate - 1, ..*self }
        } else {
            *self
        }
    }

    /// Checks the segment against the documented range and the limits.
    ///
    /// Checks run in this order and the first failure is reported: T = 0, T range,
    /// steps range, rate range, reversal, minimum period. A dwell (n = 0, v0 = 0,
    /// T > 0) is valid. n = 0 with v0 > 0 would have to reverse and is rejected.
    /// The reversal and period checks apply to the [`effective`](Self::effective)
    /// segment: a deceleration to rest whose v0 was rounded up is accepted.
    ///
    /// The period rule: with `RMAX = ⌊2^32/(min_period + 1)⌋` ([`Limits::max_rate`]),
    /// `v0_rate ≤ RMAX` and `v_end·T·2^32 ≤ T·RMAX`: both ends at most RMAX/2^32 ≤
    /// 1/(min_period + 1) steps/tick. The exact periods are then at least min_period + 1
    /// ticks, and as every emitted edge is within
    /// [`crate::model::integer::EDGE_ERROR_BOUND_TICKS`] of exact time, every emitted
    /// (integer) period is at least min_period. (The hardware checks exactly this,
    /// with one 31×32-bit multiply.)
    pub fn validate(&self, limits: &Limits) -> Result<(), SegmentError> {
        check_range(self.t_ticks, MAX_T_TICKS, self.n_steps(), self.v0_rate)?;
        let seg = self.effective();
        let v_end_t = seg.v_end_t_q32();
        if v_end_t < 0 {
            return Err(SegmentError::Reverses);
        }
        let rmax = limits.max_rate() as i128;
        let v0_too_fast = seg.v0_rate as i128 > rmax;
        let v_end_too_fast = v_end_t > seg.t_ticks as i128 * rmax;
        if v0_too_fast || v_end_too_fast {
            return Err(SegmentError::PeriodTooShort);
        }
        Ok(())
    }
}
