//! One axis running a list of segments back to back: what the core emits.
//!
//! Rejected segments are dropped (their error is reported) and never disturb
//! the segments queued around them, exactly as the hardware queue behaves.
//! The axis starts at tick 0 (its release on the start mask). Step i of the
//! whole move has its rising STEP edge at `edge_ticks[i]`; a segment starts at
//! the end of the previous one, so a dwell simply shifts what follows.

use super::exact;
use super::integer::SegmentPlan;
use super::segment::{Limits, Segment, SegmentError};
use serde::{Deserialize, Serialize};

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
    /// The accepted segments, in order, as the core runs them ([`Segment::effective`]).
    pub accepted: Vec<Segment>,
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
        let mut run = AxisRun::default();
        for (index, seg) in segments.iter().enumerate() {
            match seg.validate(limits) {
                Err(error) => run.rejected.push(Rejected { index, error }),
                Ok(()) => run.push(*seg),
            }
        }
        run
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
    }

    /// Largest |edge − exact| over the move, in ticks.
    pub fn max_edge_error_ticks(&self) -> f64 {
        self.edge_ticks
            .iter()
            .zip(&self.exact_ticks)
            .map(|(&e, &x)| (e as f64 - x).abs())
            .fold(0.0, f64::max)
    }
}
