//! Other ways to turn segments into step periods, for the accuracy report.
//!
//! Each takes the same accepted segments as the core and returns the absolute
//! tick of every step edge, so that all algorithms are measured against the same
//! exact times ([`super::exact`]). None of these runs in the hardware.
//!
//! * [`Algorithm::Integer`]: ours ([`super::integer`]): periods from ⌊τ_i + ½⌋
//!   differences, each segment summing to exactly T.
//! * [`Algorithm::PerPeriodRounding`]: the paper's method, each period computed on its
//!   own, Δ_i = round(f·(t_i − t_{i−1})), and the periods played back to back. We
//!   round to nearest from the exact f64 period, the kindest version of it (the
//!   paper does not say how its hardware rounds), so its drift here is a floor.
//! * [`Algorithm::Avr446`]: the Atmel AVR446 recurrence in its integer form:
//!   c_k = c_{k−1} − (2c_{k−1} + rest)/(4k + 1), rest = (2c_{k−1} + rest) mod (4k + 1),
//!   with c_0 = 0.676·sqrt(2/α) from rest, or c = 1/v0 and k = round(v0²/2α) when
//!   entering a segment moving (k negative when decelerating); constant 1/v0 when α = 0.
//! * [`Algorithm::SpeedLut`]: a speed lookup table as in FPGA table-lookup designs
//!   (seeds/fpga-trapezoid-lookup-table.txt): per segment, 256 entries of 16-bit
//!   speed over equal numbers of steps, scaled to the move's peak speed; each step
//!   waits round(1/speed) ticks of its entry.

use super::segment::{Segment, RATE_FRAC_BITS};
use super::{exact, integer::SegmentPlan};
use serde::Serialize;

/// A period-generation algorithm.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
pub enum Algorithm {
    Integer,
    PerPeriodRounding,
    Avr446,
    SpeedLut,
}

impl Algorithm {
    pub const ALL: [Algorithm; 4] =
        [Algorithm::Integer, Algorithm::PerPeriodRounding, Algorithm::Avr446, Algorithm::SpeedLut];

    pub fn label(self) -> &'static str {
        match self {
            Algorithm::Integer => "tdm-stepper integer",
            Algorithm::PerPeriodRounding => "per-period rounding (paper)",
            Algorithm::Avr446 => "AVR446 recurrence",
            Algorithm::SpeedLut => "256x16 speed LUT",
        }
    }

    /// Absolute step-edge ticks for `segments` (all valid), from tick 0.
    pub fn edges(self, segments: &[Segment]) -> Vec<u64> {
        let peak = peak_speed(segments);
        let mut edges = Vec::new();
        // Each algorithm starts a segment where its previous one ended (ours: exactly
        // at the sum of the T, as its periods sum to T; the others wherever they drifted).
        let mut start = 0u64;
        for seg in segments {
            let mut edge = start;
            for p in self.periods(seg, peak) {
                edge += p.max(1);
                edges.push(edge);
            }
            if seg.n_steps() == 0 {
                edge += seg.t_ticks as u64;
            }
            start = edge;
        }
        edges
    }

    fn periods(self, seg: &Segment, peak: f64) -> Vec<u64> {
        let n = seg.n_steps();
        match self {
            Algorithm::Integer => SegmentPlan::new(*seg).periods().map(u64::from).collect(),
            Algorithm::PerPeriodRounding => {
                (1..=n).map(|i| exact::step_period(seg, i).round() as u64).collect()
            }
            Algorithm::Avr446 => avr446_periods(seg),
            Algorithm::SpeedLut => lut_periods(seg, peak),
        }
    }
}

fn v0_of(seg: &Segment) -> f64 {
    seg.v0_rate as f64 / (1u64 << RATE_FRAC_BITS) as f64
}

fn alpha_of(seg: &Segment) -> f64 {
    let t = seg.t_ticks as f64;
    2.0 * (seg.d_q32() as f64 / (1u64 << RATE_FRAC_BITS) as f64) / (t * t)
}

/// Largest speed reached over the segments, steps/tick.
fn peak_speed(segments: &[Segment]) -> f64 {
    segments
        .iter()
        .map(|s| v0_of(s).max(exact::speed_at(s, s.t_ticks as f64)))
        .fold(0.0, f64::max)
}

fn avr446_periods(seg: &Segment) -> Vec<u64> {
    let n = seg.n_steps() as usize;
    let v0 = v0_of(seg);
    let alpha = alpha_of(seg);
    if n == 0 {
        return Vec::new();
    }
    // Uniform, or so nearly uniform that the virtual index would overflow.
    let k0 = if alpha == 0.0 { f64::INFINITY } else { v0 * v0 / (2.0 * alpha) };
    if !k0.is_finite() || k0.abs() > 1e15 {
        return vec![(1.0 / v0).round() as u64; n];
    }
    let (mut c, mut k): (i64, i64) = if v0 == 0.0 {
        ((0.676 * (2.0 / alpha).sqrt()).round() as i64, 0)
    } else {
        ((1.0 / v0).round() as i64, k0.round() as i64)
    };
    let mut rest: i64 = 0;
    let mut out = Vec::with_capacity(n);
    out.push(c.max(1) as u64);
    for _ in 1..n {
        // Decelerating, k counts up towards 0 (the virtual stop); hold it at -1.
        k = if k < 0 { (k + 1).min(-1) } else { k + 1 };
        let den = 4 * k + 1;
        let num = 2 * c + rest;
        c -= num / den;
        rest = num % den;
        out.push(c.max(1) as u64);
    }
    out
}

/// Entries in the speed table of one segment.
pub const LUT_ENTRIES: u32 = 256;
/// Bits of one table entry.
pub const LUT_BITS: u32 = 16;

fn lut_periods(seg: &Segment, peak: f64) -> Vec<u64> {
    let n = seg.n_steps();
    let v0 = v0_of(seg);
    let alpha_q = seg.d_q32() as f64 / (1u64 << RATE_FRAC_BITS) as f64; // D, steps
    let t = seg.t_ticks as f64;
    let full = ((1u32 << LUT_BITS) - 1) as f64;
    (0..n)
        .map(|j| {
            let entry = (j as u64 * LUT_ENTRIES as u64 / n as u64) as f64;
            // Speed at the middle of the entry's steps: w² = v0² + 2α·x, α = 2D/T².
            let x = (entry + 0.5) * n as f64 / LUT_ENTRIES as f64;
            let w = (v0 * v0 + 4.0 * alpha_q * x / (t * t)).max(0.0).sqrt();
            let q = (w / peak * full).round().max(1.0);
            (full / (q * peak)).round() as u64
        })
        .collect()
}
