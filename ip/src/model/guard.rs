//! The push guard of the machine I/O (`hdl::push_guard`): the checks a push passes, in
//! the bus clock, on top of the segment's own ([`super::Segment::validate`]), and the
//! planned position they need. Plain Rust, no HDL.
//!
//! **The planned position** of an axis (`plan`) is where its queued segments end: the
//! position once everything pushed and accepted has run. An accepted push moves it by
//! the push's steps (wrapping at 32 bits, as the position does). A stop takes the
//! queued segments away, so after an abort, an e-stop or watchdog trip, a limit or
//! alarm stop, or a core reset, the plan is **stale** until it is taken again from the
//! position: whenever a status word shows the axis at rest with nothing pushed that
//! the core has not taken (taken count = pushed count, BUSY = 0), `plan` becomes that
//! word's position and the axis is no longer stale ([`PushGuardModel::resync`]). In
//! normal running that changes nothing (the plan equals the position at rest).
//!
//! **The checks**, in this order, after the segment's own codes (which win):
//! 1. [`GuardError::Halted`] (9): the axis is held stopped (the e-stop latch or a
//!    watchdog trip, or its alarm is active) or its plan is stale: the push would be
//!    flushed, or checked against a plan that no longer holds. Every push, dwells too.
//! 2. [`GuardError::Limit`] (7): steps > 0 while `limit_pos` is active, or steps < 0
//!    while `limit_neg` is active (a push toward an active limit; motion away runs).
//! 3. [`GuardError::SoftLimit`] (8): soft limits enabled on the axis, steps ≠ 0, and
//!    the end position `plan + steps` (exact, 33 bits) below `min` or above `max`. A
//!    segment is monotonic, so its end bounds it; a dwell never fails this check.
//!
//! Soft limits are set per axis as a pair (`min ≤ max`, both inclusive) with an
//! enable; a pair with `min > max` is refused and changes nothing.

use std::fmt;

/// Why the push guard rejects a push (codes follow [`super::SegmentError`]'s).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(u8)]
pub enum GuardError {
    /// The push moves toward an active limit switch.
    Limit = 7,
    /// The push's end position lies outside the axis's soft limits.
    SoftLimit = 8,
    /// The axis is held stopped, or its planned position is stale after a stop.
    Halted = 9,
}

impl GuardError {
    pub const ALL: [GuardError; 3] = [GuardError::Limit, GuardError::SoftLimit, GuardError::Halted];

    pub fn code(self) -> u8 {
        self as u8
    }

    pub fn from_code(code: u8) -> Option<GuardError> {
        Self::ALL.into_iter().find(|e| e.code() == code)
    }

    /// Short upper-case name, as in the C header.
    pub fn name(self) -> &'static str {
        match self {
            GuardError::Limit => "LIMIT",
            GuardError::SoftLimit => "SOFT_LIMIT",
            GuardError::Halted => "HALTED",
        }
    }
}

impl fmt::Display for GuardError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let what = match self {
            GuardError::Limit => "the push moves toward an active limit switch",
            GuardError::SoftLimit => "the push's end position lies outside the axis's soft limits",
            GuardError::Halted => "the axis is held stopped, or its planned position is stale after a stop",
        };
        write!(f, "error {} ({}): {what}", self.code(), self.name())
    }
}

/// The machine's state as the guard sees it for one axis, in the cycle of the check.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct GuardFlags {
    pub limit_neg: bool,
    pub limit_pos: bool,
    /// The e-stop latch or a watchdog trip holds, or the axis's alarm is active.
    pub held: bool,
}

/// One axis's soft limits (inclusive).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SoftLimits {
    pub min: i32,
    pub max: i32,
}

/// The guard of `axes` axes.
#[derive(Clone, Debug)]
pub struct PushGuardModel {
    pub plan: Vec<i32>,
    pub stale: Vec<bool>,
    pub soft: Vec<Option<SoftLimits>>,
}

impl PushGuardModel {
    /// After reset: every plan stale, no soft limits.
    pub fn new(axes: usize) -> Self {
        PushGuardModel { plan: vec![0; axes], stale: vec![true; axes], soft: vec![None; axes] }
    }

    /// The verdict on a push of `steps` to `axis`: its end position, or the code.
    pub fn check(&self, axis: usize, steps: i32, flags: GuardFlags) -> Result<i64, GuardError> {
        if flags.held || self.stale[axis] {
            return Err(GuardError::Halted);
        }
        if (steps > 0 && flags.limit_pos) || (steps < 0 && flags.limit_neg) {
            return Err(GuardError::Limit);
        }
        let end = self.plan[axis] as i64 + steps as i64;
        if let Some(s) = self.soft[axis] {
            if steps != 0 && (end < s.min as i64 || end > s.max as i64) {
                return Err(GuardError::SoftLimit);
            }
        }
        Ok(end)
    }

    /// A push the whole check accepted (its end from [`Self::check`]).
    pub fn accept(&mut self, axis: usize, end: i64) {
        self.plan[axis] = end as i32;
    }

    /// A status word shows `axis` at rest with nothing pushed that the core has not
    /// taken: its position is the plan.
    pub fn resync(&mut self, axis: usize, pos: i32) {
        self.plan[axis] = pos;
        self.stale[axis] = false;
    }

    /// A stop took `axis`'s queued segments away (or the core was reset).
    pub fn mark_stale(&mut self, axis: usize) {
        self.stale[axis] = true;
    }

    /// Sets (`Some`) or clears `axis`'s soft limits; a pair with min > max is refused
    /// and changes nothing (`Err`).
    pub fn set_soft(&mut self, axis: usize, soft: Option<SoftLimits>) -> Result<(), ()> {
        if let Some(s) = soft {
            if s.min > s.max {
                return Err(());
            }
        }
        self.soft[axis] = soft;
        Ok(())
    }
}
