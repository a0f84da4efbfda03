//! STEP and DIR on the pins: the pulse high time of every step and when DIR changes,
//! from an axis's period FIFO stream and the core's output timing registers.
//!
//! The rising edges are the integer model's ([`super::AxisRun::edge_ticks`]); this
//! module adds what happens between them. With the registers STEP_HIGH (H), STEP_LOW
//! (L), DIR_SETUP (S) and DIR_HOLD (D), all in clk ticks and at least 1:
//!
//! * high minimum `Hm = max(H, D)`, low minimum `Lm = max(L, S)`, and the core accepts
//!   them only when `Hm + Lm ≤ M`, the export's minimum period ([`PulseTiming::check`]);
//! * every FIFO entry carries the high time of a pulse that rises at its start (or, for
//!   the last entry of a move, at its end): `h(Δ) = max(Hm, min(⌊Δ/2⌋, Δ − Lm, 65,535))`
//!   for an entry of Δ ticks ([`PulseTiming::high_ticks`]); the default registers (all 1)
//!   give today's half period, `max(1, ⌊Δ/2⌋)`, up to the 65,535-tick cap;
//! * a step's pulse rises at the end of its entry and stays high for the `h` of the entry
//!   that follows, or of its own entry at the end of a move;
//! * DIR takes the direction of the next step once STEP is low: on the edge where STEP
//!   falls, or one tick after the step's entry is loaded if STEP is already low then
//!   (after a dwell, and at the release). A dwell entry does not touch DIR.
//!
//! Every interval between rising edges is at least M (docs/model.md), so these rules
//! give every pulse at least Hm high and Lm low, DIR at least Hm ≥ D after a rising edge
//! and at least Lm ≥ S (or Δ − 1 ≥ M − 1 ≥ S after a load) before the next one. The
//! property test `model_props::pulse_timing_holds_on_the_pins` checks it over the
//! parameter range; the HDL tests compare every pin edge with [`pins`].

use super::axis::FifoEntry;
use super::segment::Limits;
use serde::{Deserialize, Serialize};

/// Longest STEP high time the core emits, in ticks (the step generator's pulse counter
/// is 16 bits). At 50 MHz, 1.31 ms: the half period of any step rate above 381 steps/s.
pub const MAX_PULSE_TICKS: u32 = 65_535;

/// The core's output timing registers, in clk ticks.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct PulseTiming {
    /// Minimum STEP high time (STEP_HIGH).
    pub step_high: u16,
    /// Minimum STEP low time (STEP_LOW).
    pub step_low: u16,
    /// Minimum DIR setup before a rising STEP edge (DIR_SETUP).
    pub dir_setup: u16,
    /// Minimum DIR hold after a rising STEP edge (DIR_HOLD).
    pub dir_hold: u16,
}

impl Default for PulseTiming {
    /// The reset values: 1 tick each, so the pulse is the half period.
    fn default() -> Self {
        PulseTiming { step_high: 1, step_low: 1, dir_setup: 1, dir_hold: 1 }
    }
}

impl PulseTiming {
    /// Minimum high time the generator applies: max(STEP_HIGH, DIR_HOLD).
    pub fn high_min(&self) -> u32 {
        self.step_high.max(self.dir_hold) as u32
    }

    /// Minimum low time the generator applies: max(STEP_LOW, DIR_SETUP).
    pub fn low_min(&self) -> u32 {
        self.step_low.max(self.dir_setup) as u32
    }

    /// Whether the core accepts these values with minimum period `limits`: every value at
    /// least 1 and high_min + low_min ≤ M. CTRL.ENABLE = 1 is refused otherwise.
    pub fn check(&self, limits: &Limits) -> Result<(), String> {
        if self.step_high == 0 || self.step_low == 0 || self.dir_setup == 0 || self.dir_hold == 0 {
            return Err(format!("{self:?}: every output timing value must be at least 1 tick"));
        }
        let sum = self.high_min() + self.low_min();
        if sum > limits.min_period_ticks {
            return Err(format!(
                "max(STEP_HIGH, DIR_HOLD) + max(STEP_LOW, DIR_SETUP) = {sum} ticks exceeds the minimum period of {} ticks",
                limits.min_period_ticks
            ));
        }
        Ok(())
    }

    /// High time of a pulse whose next rising edge is at least `delta` ticks after its own:
    /// max(high_min, min(⌊Δ/2⌋, Δ − low_min, 65,535)).
    pub fn high_ticks(&self, delta: u32) -> u32 {
        (delta / 2).min(delta.saturating_sub(self.low_min())).min(MAX_PULSE_TICKS).max(self.high_min())
    }
}

/// What the STEP and DIR pins do, in ticks from the release (tick 0).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Pins {
    /// Rising STEP edges.
    pub rises: Vec<u64>,
    /// Falling STEP edges, one per rise.
    pub falls: Vec<u64>,
    /// DIR changes: (tick, new level; true is reverse). DIR is 0 before the release.
    pub dir_changes: Vec<(u64, bool)>,
}

/// The pins for a FIFO stream that never runs dry (no underrun, no abort).
pub fn pins(fifo: &[FifoEntry], timing: &PulseTiming) -> Pins {
    let mut out = Pins::default();
    let mut dir = false;
    let mut load = 0u64; // tick at which the current entry loads
    let mut high_until = 0u64; // the current pulse falls at this tick (0: none yet)
    for (k, e) in fifo.iter().enumerate() {
        if e.step && e.reverse != dir {
            // The next step's direction, once STEP is low.
            let at = (load + 1).max(high_until);
            out.dir_changes.push((at, e.reverse));
            dir = e.reverse;
        }
        let end = load + e.ticks as u64;
        if e.step {
            let h = timing.high_ticks(fifo.get(k + 1).map_or(e.ticks, |n| n.ticks)) as u64;
            out.rises.push(end);
            out.falls.push(end + h);
            high_until = end + h;
        }
        load = end;
    }
    out
}

/// The narrowest timing the pins show: (shortest high, shortest low between a fall and
/// the next rise, shortest DIR setup before a rise, shortest DIR hold after a rise), in
/// ticks; `u64::MAX` where there is nothing to measure.
pub fn measure(p: &Pins) -> (u64, u64, u64, u64) {
    let high = p.rises.iter().zip(&p.falls).map(|(r, f)| f - r).min().unwrap_or(u64::MAX);
    let low = p.falls.iter().zip(p.rises.iter().skip(1)).map(|(f, r)| r - f).min().unwrap_or(u64::MAX);
    let (mut setup, mut hold) = (u64::MAX, u64::MAX);
    for &(t, _) in &p.dir_changes {
        // The rise at or after the change, and the one before it.
        let next = p.rises.partition_point(|&r| r < t);
        if let Some(&r) = p.rises.get(next) {
            setup = setup.min(r - t);
        }
        if next > 0 {
            hold = hold.min(t - p.rises[next - 1]);
        }
    }
    (high, low, setup, hold)
}
