//! Test vectors: segments in, expected periods, edges and rejections out.
//!
//! `tdm-stepper vectors` writes one JSON file per [`VectorFile`] into `vectors/`.
//! The files are made by the reference model and are the shared stimulus of every
//! later check (rust-hdl simulation, Verilator, Icarus). A test regenerates them and
//! fails if a committed file differs.
//!
//! Format (see docs/vectors.md): per axis, the segment list as written to the
//! core, each with its expected status (`error`: null or the error code), its plan
//! kind and its periods; then the absolute tick of every STEP rising edge from the
//! axis release, the final position and the tick at which the last segment ends.

use crate::model::{planner, AxisRun, Limits, PlanKind, Segment, SegmentPlan};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// One vector file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct VectorFile {
    pub name: String,
    pub description: String,
    pub clock_hz: u32,
    pub min_period_ticks: u32,
    pub axes: Vec<AxisVector>,
}

/// One axis of a vector.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AxisVector {
    pub segments: Vec<SegmentVector>,
    /// Absolute tick of every step edge, from the axis release.
    pub edge_ticks: Vec<u64>,
    pub final_position: i64,
    pub end_tick: u64,
    /// Largest |edge − exact time| over the axis, in ticks (for information).
    pub max_edge_error_ticks: f64,
}

/// One segment as written, with what the core must do with it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SegmentVector {
    pub v0_rate: u32,
    pub t_ticks: u32,
    pub steps: i32,
    /// Expected error code, or None if the segment is accepted.
    pub error: Option<u8>,
    /// "dwell", "uniform", "nearly_uniform", "accelerate" or "decelerate"; None if rejected.
    pub kind: Option<String>,
    /// Expected periods (ticks), one per step; empty for a dwell or a rejected segment.
    pub periods: Vec<u32>,
}

impl SegmentVector {
    pub fn segment(&self) -> Segment {
        Segment::new(self.v0_rate, self.t_ticks, self.steps)
    }
}

fn kind_name(kind: PlanKind) -> &'static str {
    match kind {
        PlanKind::Dwell => "dwell",
        PlanKind::Uniform { nearly: false } => "uniform",
        PlanKind::Uniform { nearly: true } => "nearly_uniform",
        PlanKind::Accelerate => "accelerate",
        PlanKind::Decelerate => "decelerate",
    }
}

/// Builds the expected outputs of one axis from its segment list.
pub fn axis_vector(segments: &[Segment], limits: &Limits) -> AxisVector {
    let run = AxisRun::run(segments, limits);
    let segs = segments
        .iter()
        .map(|s| match s.validate(limits) {
            Err(e) => SegmentVector {
                v0_rate: s.v0_rate,
                t_ticks: s.t_ticks,
                steps: s.steps,
                error: Some(e.code()),
                kind: None,
                periods: vec![],
            },
            Ok(()) => {
                let plan = SegmentPlan::new(*s);
                SegmentVector {
                    v0_rate: s.v0_rate,
                    t_ticks: s.t_ticks,
                    steps: s.steps,
                    error: None,
                    kind: Some(kind_name(plan.kind).to_string()),
                    periods: plan.periods().collect(),
                }
            }
        })
        .collect();
    AxisVector {
        segments: segs,
        max_edge_error_ticks: run.max_edge_error_ticks(),
        edge_ticks: run.edge_ticks,
        final_position: run.position,
        end_tick: run.end_tick,
    }
}

fn file(name: &str, description: &str, clock_hz: u32, min_period: u32, axes: &[Vec<Segment>]) -> VectorFile {
    let limits = Limits::new(min_period).expect("vector limits in range");
    VectorFile {
        name: name.to_string(),
        description: description.to_string(),
        clock_hz,
        min_period_ticks: min_period,
        axes: axes.iter().map(|a| axis_vector(a, &limits)).collect(),
    }
}

/// The paper's experiment: 50 MHz, 20 ms / 10 ms / 20 ms from rest to rest,
/// 2,400 steps on axis 0 and 1,800 on axis 1 (v_max 80,000 and 60,000 steps/s).
pub fn paper_experiment_segments() -> Vec<Vec<Segment>> {
    let limits = Limits::default();
    [2400, 1800]
        .iter()
        .map(|&steps| {
            planner::trapezoid_by_times(steps, 0.020, 0.010, 0.020, PAPER_CLOCK_HZ, &limits)
                .expect("the paper's experiment plans")
        })
        .collect()
}

/// The paper's clock.
pub const PAPER_CLOCK_HZ: u32 = 50_000_000;

/// A nearly uniform segment of about `approx_steps` steps whose P overflows the
/// root width, so the core takes the uniform fallback: v0_rate·T ≡ −d (mod 2^32)
/// with |d| small. Deterministic search.
pub fn nearly_uniform_fallback(approx_steps: u64, d: i64) -> Segment {
    for half in (1u32 << 14)..(1u32 << 20) {
        let Some(seg) = Segment::with_tiny_d(2 * half + 1, d, false) else { continue };
        let n = seg.n_steps() as u64;
        if n >= approx_steps / 2
            && n <= approx_steps
            && matches!(SegmentPlan::new(seg).kind, PlanKind::Uniform { nearly: true })
            && seg.validate(&Limits::default()).is_ok()
        {
            return seg;
        }
    }
    panic!("no nearly uniform fallback segment near {approx_steps} steps");
}

/// Every vector file, in a fixed order.
pub fn all() -> Vec<VectorFile> {
    let lim = Limits::default();
    let plan = |steps: i64, ticks: [u32; 3]| planner::trapezoid_by_ticks(steps, ticks, &lim).expect("plans");
    let rate = |v: f64, f: u32| crate::model::units::steps_per_s_to_rate(v, f).expect("rate in range");
    // The largest v0 that stops exactly at the end: v0·T = 2n.
    let to_rest = |n: u64, t: u32| ((2 * n << 32) / t as u64) as u32;
    let mut out = Vec::new();

    out.push(file(
        "paper_experiment",
        "Wu et al. experiment: 50 MHz, 20 ms accelerate / 10 ms cruise / 20 ms decelerate from rest, \
         2,400 steps on axis 0 and 1,800 on axis 1 (v_max 80,000 and 60,000 steps/s)",
        PAPER_CLOCK_HZ,
        2,
        &paper_experiment_segments(),
    ));

    out.push(file(
        "short_segments",
        "Very short segments and moves: 1 to 5 steps in a few ticks, chained back to back",
        100_000_000,
        2,
        &[
            vec![Segment::new(0, 7, 1), Segment::new(0, 13, 2), Segment::new(rate(10e6, 100_000_000), 9, 1)],
            [plan(3, [13, 0, 13]), plan(-5, [30, 30, 30]), plan(1, [7, 0, 7])].concat(),
        ],
    ));

    out.push(file(
        "long_segments",
        "Segments of 2^30 ticks (10.7 s at 100 MHz): a slow acceleration from rest, a long \
         deceleration to rest, and a nearly uniform segment that takes the uniform fallback",
        100_000_000,
        2,
        &[
            vec![Segment::new(0, 1 << 30, 3000), Segment::new(to_rest(3000, 1 << 30), 1 << 30, 3000)],
            vec![nearly_uniform_fallback(4000, 1)],
        ],
    ));

    out.push(file(
        "pure_deceleration",
        "Decelerations only: 100,000 steps/s to rest forwards, and 40,000 to 10,000 steps/s backwards",
        50_000_000,
        2,
        &[
            vec![Segment::new(to_rest(5000, 5_000_000), 5_000_000, 5000)],
            vec![Segment::new(rate(40_000.0, 50_000_000), 2_500_000, -1250)],
        ],
    ));

    out.push(file(
        "dwells",
        "Dwells (n = 0, T > 0) between rest-to-rest moves, at the start, and back to back",
        50_000_000,
        2,
        &[
            [
                vec![Segment::dwell(12_345)],
                plan(200, [100_000, 50_000, 100_000]),
                vec![Segment::dwell(1 << 30), Segment::dwell(1)],
                plan(-200, [100_000, 0, 100_000]),
            ]
            .concat(),
            vec![Segment::dwell(500_000)],
        ],
    ));

    out.push(file(
        "near_limit",
        "Near the step-rate limit: accelerating to just under 1/3 step/tick, then starting at \
         RMAX, with a 2-tick minimum period; exactly uniform at 256 and 4 ticks per step, and 200 kHz (250 ticks) at 50 MHz",
        50_000_000,
        2,
        &[
            vec![Segment::new(0, 6001, 1000), Segment::new(Limits::default().max_rate(), 3000, 999)],
            // Exactly uniform (v0·T = n): 256-tick periods, 4-tick periods; then 200 kHz.
            vec![
                Segment::new(1 << 24, 256_000, 1000),
                Segment::new(1 << 30, 4000, -1000),
                Segment::new(rate(200_000.0, 50_000_000), 250_000, 1000),
            ],
        ],
    ));

    let valid = Segment::new(0, 100_000, 50);
    out.push(file(
        "invalid",
        "Each error code, between valid segments that must still run exactly: T = 0, a \
         reversing deceleration, too short a period, and T, steps and v0 out of range",
        50_000_000,
        2,
        &[vec![
            valid,
            Segment::new(0, 0, 10),
            Segment::new(rate(10_000.0, 50_000_000), 100_000, 5),
            Segment::new(0, 100, 50),
            Segment::new(0, (1 << 30) + 1, 10),
            Segment::new(0, 1 << 30, (1 << 24) + 1),
            Segment::new(u32::MAX, 1000, 10),
            Segment::new(1000, 100_000, 0),
            valid,
        ]],
    ));
    out
}

/// The JSON text of a vector file, exactly as committed.
pub fn to_json(v: &VectorFile) -> String {
    let mut s = serde_json::to_string_pretty(v).expect("vectors serialise");
    s.push('\n');
    s
}

/// Writes every vector file into `dir`; returns the paths written.
pub fn write_all(dir: &Path) -> std::io::Result<Vec<std::path::PathBuf>> {
    std::fs::create_dir_all(dir)?;
    let mut paths = Vec::new();
    for v in all() {
        let path = dir.join(format!("{}.json", v.name));
        std::fs::write(&path, to_json(&v))?;
        paths.push(path);
    }
    Ok(paths)
}
