//! One axis running a list of segments back to back: what the core emits.
//!
//! Rejected segments are dropped (their error is reported) and never disturb
//! the segments queued around them, exactly as the hardware queue behaves.
//! The axis starts at tick 0 (its release on the start mask). Step i of the
//! whole move has its rising STEP edge at `edge_ticks[i]`; a segment starts at
//! the end of the previous one, so a dwell simply shifts what follows.

use super::exact;
use super::integer::SegmentPlan;
use super::poly::{PolyPlan, PolySegment};
use super::segment::{Limits, Segment, SegmentError};
use serde::{Deserialize, Serialize};

/// One queued motion command of an axis: a trapezoid segment (constant acceleration)
/// or a polynomial segment (an S-curve phase). Both go through the same queue.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Motion {
    Trapezoid(Segment),
    Poly(PolySegment),
}

impl Motion {
    /// Validation by the segment's own rules.
    pub fn validate(&self, limits: &Limits) -> Result<(), SegmentError> {
        match self {
            Motion::Trapezoid(s) => s.validate(limits),
            Motion::Poly(p) => p.validate(limits),
        }
    }

    /// Duration T in ticks.
    pub fn t_ticks(&self) -> u32 {
        match self {
            Motion::Trapezoid(s) => s.t_ticks,
            Motion::Poly(p) => p.t_ticks,
        }
    }

    /// Signed steps θ.
    pub fn steps(&self) -> i32 {
        match self {
            Motion::Trapezoid(s) => s.steps,
            Motion::Poly(p) => p.steps,
        }
    }

    /// n = |θ|.
    pub fn n_steps(&self) -> u32 {
        self.steps().unsigned_abs()
    }

    /// Start speed, Q0.32 steps/tick.
    pub fn v0_rate(&self) -> u32 {
        match self {
            Motion::Trapezoid(s) => s.v0_rate,
            Motion::Poly(p) => p.v0_rate,
        }
    }
}

impl From<Segment> for Motion {
    fn from(s: Segment) -> Motion {
        Motion::Trapezoid(s)
    }
}

impl From<PolySegment> for Motion {
    fn from(p: PolySegment) -> Motion {
        Motion::Poly(p)
    }
}

/// One entry of an axis's period FIFO: wait `ticks`, then emit a step (or, for a
/// dwell, nothing).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct FifoEntry {
    pub ticks: u32,
    pub step: bool,
    /// Direction of the step: true for negative θ.
    pub reverse: bool,
}

/// A segment the axis refused, with its index in the command list.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Rejected {
    pub index: usize,
    pub error: SegmentError,
}

/// Everything one axis does for a list of segments.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AxisRun {
    /// The accepted trapezoid segments, in order, as the core runs them ([`Segment::effective`]).
    pub accepted: Vec<Segment>,
    /// Every accepted motion of either kind, in order (trapezoids in their effective form).
    pub motions: Vec<Motion>,
    /// Refused segments.
    pub rejected: Vec<Rejected>,
    /// The period FIFO stream.
    pub fifo: Vec<FifoEntry>,
    /// Absolute tick of every step edge, from the axis release.
    pub edge_ticks: Vec<u64>,
    /// Exact time of every step edge, in ticks from the axis release.
    pub exact_ticks: Vec<f64>,
    /// Final signed position in steps.
    pub position: i64,
    /// Tick at which the last segment ends (sum of the accepted T).
    pub end_tick: u64,
}

impl AxisRun {
    /// Runs `segments` through validation and the integer model.
    pub fn run(segments: &[Segment], limits: &Limits) -> AxisRun {
        let motions: Vec<Motion> = segments.iter().map(|&s| s.into()).collect();
        AxisRun::run_motions(&motions, limits)
    }

    /// Runs trapezoid and polynomial segments, mixed, through validation and the
    /// integer models, back to back.
    pub fn run_motions(motions: &[Motion], limits: &Limits) -> AxisRun {
        let mut run = AxisRun::default();
        for (index, m) in motions.iter().enumerate() {
            match m.validate(limits) {
                Err(error) => run.rejected.push(Rejected { index, error }),
                Ok(()) => match m {
                    Motion::Trapezoid(seg) => run.push(*seg),
                    Motion::Poly(p) => run.push_poly(*p),
                },
            }
        }
        run
    }

    fn push_poly(&mut self, seg: PolySegment) {
        let start = self.end_tick;
        if seg.n_steps() == 0 {
            self.fifo.push(FifoEntry { ticks: seg.t_ticks, step: false, reverse: false });
        }
        let mut prev = 0u32;
        for (k, e) in PolyPlan::new(seg).edges().into_iter().enumerate() {
            self.fifo.push(FifoEntry { ticks: e - prev, step: true, reverse: seg.reverse() });
            self.edge_ticks.push(start + e as u64);
            self.exact_ticks.push(start as f64 + seg.step_time_near(k as u32 + 1, e));
            prev = e;
        }
        self.position += seg.steps as i64;
        self.end_tick = start + seg.t_ticks as u64;
        self.motions.push(Motion::Poly(seg));
    }

    fn push(&mut self, seg: Segment) {
        // The segment the core runs (v0 − 1 for a deceleration that rounds past rest).
        let seg = seg.effective();
        let start = self.end_tick;
        let plan = SegmentPlan::new(seg);
        if seg.n_steps() == 0 {
            self.fifo.push(FifoEntry { ticks: seg.t_ticks, step: false, reverse: false });
        }
        let mut edge = start;
        for (k, period) in plan.periods().enumerate() {
            edge += period as u64;
            self.fifo.push(FifoEntry { ticks: period, step: true, reverse: seg.reverse() });
            self.edge_ticks.push(edge);
            self.exact_ticks.push(start as f64 + exact::step_time(&seg, k as u32 + 1));
        }
        self.position += seg.steps as i64;
        self.end_tick = start + seg.t_ticks as u64;
        self.accepted.push(seg);
        self.motions.push(Motion::Trapezoid(seg));
    }

    /// Largest |edge − exact| over the move, in ticks.
    pub fn max_edge_error_ticks(&self) -> f64 {
        self.edge_ticks.iter().zip(&self.exact_ticks).map(|(&e, &x)| (e as f64 - x).abs()).fold(0.0, f64::max)
    }
}
