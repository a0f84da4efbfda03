//! Conversions between physical units and register units.
//!
//! Rates are Q0.32 steps per tick: `v0_rate = round(steps_per_s · 2^32 / f_clk)`.
//! Times are whole clock ticks: `ticks = round(seconds · f_clk)`. Each conversion
//! refuses values it cannot represent instead of clipping them.

use super::segment::{MAX_T_TICKS, MAX_V0_RATE, RATE_FRAC_BITS};
use std::fmt;

/// Lowest supported core clock.
pub const MIN_CLOCK_HZ: u32 = 1_000_000;
/// Highest supported core clock.
pub const MAX_CLOCK_HZ: u32 = 100_000_000;

/// A value that has no register representation.
#[derive(Clone, Debug, PartialEq)]
pub enum UnitError {
    ClockRange(u64),
    NotFinite(&'static str),
    Negative(&'static str, f64),
    RateRange(f64),
    TicksRange(f64),
}

impl fmt::Display for UnitError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            UnitError::ClockRange(hz) => {
                write!(f, "clock {hz} Hz is outside {MIN_CLOCK_HZ}..={MAX_CLOCK_HZ} Hz")
            }
            UnitError::NotFinite(what) => write!(f, "{what} is not a finite number"),
            UnitError::Negative(what, v) => write!(f, "{what} = {v} is negative"),
            UnitError::RateRange(v) => write!(
                f,
                "{v} steps/s is above the largest start rate ({MAX_V0_RATE} in Q0.32, just under half the clock)"
            ),
            UnitError::TicksRange(s) => {
                write!(f, "{s} s is more than {MAX_T_TICKS} ticks at this clock")
            }
        }
    }
}

impl std::error::Error for UnitError {}

/// Checks a core clock frequency.
pub fn check_clock(clock_hz: u64) -> Result<u32, UnitError> {
    if (MIN_CLOCK_HZ as u64..=MAX_CLOCK_HZ as u64).contains(&clock_hz) {
        Ok(clock_hz as u32)
    } else {
        Err(UnitError::ClockRange(clock_hz))
    }
}

/// steps/s → Q0.32 steps/tick, rounded to nearest.
pub fn steps_per_s_to_rate(steps_per_s: f64, clock_hz: u32) -> Result<u32, UnitError> {
    if !steps_per_s.is_finite() {
        return Err(UnitError::NotFinite("speed"));
    }
    if steps_per_s < 0.0 {
        return Err(UnitError::Negative("speed", steps_per_s));
    }
    let rate = (steps_per_s * (1u64 << RATE_FRAC_BITS) as f64 / clock_hz as f64).round();
    if rate > MAX_V0_RATE as f64 {
        return Err(UnitError::RateRange(steps_per_s));
    }
    Ok(rate as u32)
}

/// Q0.32 steps/tick → steps/s.
pub fn rate_to_steps_per_s(rate: u32, clock_hz: u32) -> f64 {
    rate as f64 * clock_hz as f64 / (1u64 << RATE_FRAC_BITS) as f64
}

/// seconds → ticks, rounded to nearest. 0 s gives 0 ticks (validation rejects T = 0).
pub fn seconds_to_ticks(seconds: f64, clock_hz: u32) -> Result<u32, UnitError> {
    if !seconds.is_finite() {
        return Err(UnitError::NotFinite("time"));
    }
    if seconds < 0.0 {
        return Err(UnitError::Negative("time", seconds));
    }
    let ticks = (seconds * clock_hz as f64).round();
    if ticks > MAX_T_TICKS as f64 {
        return Err(UnitError::TicksRange(seconds));
    }
    Ok(ticks as u32)
}

/// ticks → seconds.
pub fn ticks_to_seconds(ticks: u64, clock_hz: u32) -> f64 {
    ticks as f64 / clock_hz as f64
}
