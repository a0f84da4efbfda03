//! The accuracy report: our integer algorithm against the exact kinematics and
//! against the alternatives ([`crate::model::alternatives`]), on the same moves.
//!
//! Edge error: the algorithm's STEP edge tick minus the exact time of that step,
//! both from the axis release (cumulative: it includes any drift). Period error:
//! (emitted period − exact period) / exact period, in %. `tdm-stepper accuracy`
//! prints the table and writes `accuracy.json`, `accuracy.md` and one SVG per axis
//! (like Fig. 11 of the paper) into the output folder.

use crate::model::alternatives::Algorithm;
use crate::model::{planner, scurve, AxisRun, Limits, Motion, Segment};
use crate::vectors::{paper_experiment_segments, PAPER_CLOCK_HZ};
use plotters::prelude::*;
use serde::Serialize;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Periods at least this long (exact, in ticks) count for the paper's ±0.2% claim.
pub const PERIOD_FLOOR_TICKS: f64 = 500.0;

/// A move to measure.
pub struct Move {
    pub name: &'static str,
    pub description: &'static str,
    pub clock_hz: u32,
    pub axes: Vec<Vec<Segment>>,
}

/// The moves of the report.
pub fn moves() -> Vec<Move> {
    let lim = Limits::default();
    let by_limits = |steps, v, a, f| planner::trapezoid_by_limits(steps, v, a, f, &lim).expect("plans");
    vec![
        Move {
            name: "paper_experiment",
            description: "50 MHz, 20/10/20 ms from rest, 2,400 and 1,800 steps",
            clock_hz: PAPER_CLOCK_HZ,
            axes: paper_experiment_segments(),
        },
        Move {
            name: "long_slow",
            description: "100 MHz, 20,000 steps, v_max 5,000 steps/s, a_max 2,000 steps/s^2",
            clock_hz: 100_000_000,
            axes: vec![by_limits(20_000, 5_000.0, 2_000.0, 100_000_000)],
        },
        Move {
            name: "fast_short",
            description: "100 MHz, 2,000 steps, v_max 200,000 steps/s, a_max 2e7 steps/s^2",
            clock_hz: 100_000_000,
            axes: vec![by_limits(2_000, 200_000.0, 2e7, 100_000_000)],
        },
    ]
}

/// One algorithm on one axis.
#[derive(Clone, Debug, Serialize)]
pub struct Metrics {
    pub algorithm: Algorithm,
    pub label: &'static str,
    pub steps: usize,
    pub max_abs_edge_error_ticks: f64,
    pub rms_edge_error_ticks: f64,
    /// Over steps whose exact period is ≥ [`PERIOD_FLOOR_TICKS`].
    pub max_abs_period_error_pct_ge_floor: f64,
    pub max_abs_period_error_pct_all: f64,
    /// Last edge minus the exact end of the move, ticks.
    pub end_error_ticks: f64,
    #[serde(skip)]
    pub period_error_pct: Vec<f64>,
    #[serde(skip)]
    pub edge_error_ticks: Vec<f64>,
}

/// All algorithms on one axis of one move.
#[derive(Clone, Debug, Serialize)]
pub struct AxisReport {
    pub move_name: &'static str,
    pub description: &'static str,
    pub axis: usize,
    pub clock_hz: u32,
    pub min_exact_period_ticks: f64,
    pub metrics: Vec<Metrics>,
    #[serde(skip)]
    pub exact_speed: Vec<f64>,
}

fn measure(alg: Algorithm, run: &AxisRun) -> Metrics {
    let edges = alg.edges(&run.accepted);
    let exact = &run.exact_ticks;
    assert_eq!(edges.len(), exact.len(), "{alg:?} emitted a different step count");
    let mut period_error_pct = Vec::with_capacity(edges.len());
    let mut edge_error_ticks = Vec::with_capacity(edges.len());
    let (mut max_ge, mut max_all, mut max_edge, mut sq) = (0f64, 0f64, 0f64, 0f64);
    for k in 0..edges.len() {
        let prev_e = if k == 0 { 0 } else { edges[k - 1] };
        let prev_x = if k == 0 { 0.0 } else { exact[k - 1] };
        let p_exact = exact[k] - prev_x;
        let p_err = ((edges[k] - prev_e) as f64 - p_exact) / p_exact * 100.0;
        let e_err = edges[k] as f64 - exact[k];
        period_error_pct.push(p_err);
        edge_error_ticks.push(e_err);
        max_all = max_all.max(p_err.abs());
        if p_exact >= PERIOD_FLOOR_TICKS {
            max_ge = max_ge.max(p_err.abs());
        }
        max_edge = max_edge.max(e_err.abs());
        sq += e_err * e_err;
    }
    Metrics {
        algorithm: alg,
        label: alg.label(),
        steps: edges.len(),
        max_abs_edge_error_ticks: max_edge,
        rms_edge_error_ticks: (sq / edges.len().max(1) as f64).sqrt(),
        max_abs_period_error_pct_ge_floor: max_ge,
        max_abs_period_error_pct_all: max_all,
        end_error_ticks: edges.last().map_or(0.0, |&e| e as f64 - exact.last().copied().unwrap_or(0.0)),
        period_error_pct,
        edge_error_ticks,
    }
}

/// Measures every algorithm on every axis of every move.
pub fn report() -> Vec<AxisReport> {
    let limits = Limits::default();
    let mut out = Vec::new();
    for mv in moves() {
        for (axis, segs) in mv.axes.iter().enumerate() {
            let run = AxisRun::run(segs, &limits);
            assert!(run.rejected.is_empty(), "{}: planned segment rejected", mv.name);
            let x = &run.exact_ticks;
            let periods: Vec<f64> = (0..x.len()).map(|k| x[k] - if k == 0 { 0.0 } else { x[k - 1] }).collect();
            out.push(AxisReport {
                move_name: mv.name,
                description: mv.description,
                axis,
                clock_hz: mv.clock_hz,
                min_exact_period_ticks: periods.iter().copied().fold(f64::INFINITY, f64::min),
                exact_speed: periods.iter().map(|p| mv.clock_hz as f64 / p).collect(),
                metrics: Algorithm::ALL.iter().map(|&a| measure(a, &run)).collect(),
            });
        }
    }
    out
}

/// The report as a markdown table (also what the CLI prints).
pub fn table(reports: &[AxisReport]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "| move | axis | algorithm | steps | max abs edge error (ticks) | rms edge error (ticks) | \
         max abs period error, periods >= {PERIOD_FLOOR_TICKS} ticks (%) | max abs period error, all (%) | end error (ticks) |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|");
    for r in reports {
        for m in &r.metrics {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {:.3} | {:.3} | {:.4} | {:.4} | {:.2} |",
                r.move_name,
                r.axis,
                m.label,
                m.steps,
                m.max_abs_edge_error_ticks,
                m.rms_edge_error_ticks,
                m.max_abs_period_error_pct_ge_floor,
                m.max_abs_period_error_pct_all,
                m.end_error_ticks
            );
        }
    }
    s
}

/// One profile of the S-curve comparison: the same move and limits planned as a
/// trapezoid, a jerk-limited and a fourth-order profile, run through the model.
#[derive(Clone, Debug, Serialize)]
pub struct ProfileRow {
    pub profile: &'static str,
    pub segments: usize,
    pub steps: usize,
    pub duration_ms: f64,
    /// Largest |acceleration| anywhere in the segments, steps/s².
    pub peak_accel: f64,
    /// Largest |jerk| inside a segment, steps/s³ (0 inside a trapezoid's segments).
    pub peak_jerk_inside: f64,
    /// Largest jump of the acceleration where two segments join, steps/s² (a jerk
    /// without bound there).
    pub largest_accel_jump: f64,
    /// Largest |edge − exact time| against the segments' exact kinematics, ticks.
    pub max_edge_error_ticks: f64,
}

/// The comparison's move: 50 MHz, 20,000 steps, v_max 50,000 steps/s, a_max 500,000
/// steps/s², j_max 2·10⁷ steps/s³, s_max 2·10⁹ steps/s⁴.
pub const COMPARISON: (u32, i64, f64, f64, f64, f64) = (50_000_000, 20_000, 50_000.0, 500_000.0, 2e7, 2e9);

/// Runs the comparison (see [`ProfileRow`]).
pub fn profile_comparison() -> Vec<ProfileRow> {
    let (f, steps, v, a, j, s) = COMPARISON;
    let lim = Limits::default();
    let trapezoid: Vec<Motion> =
        planner::trapezoid_by_limits(steps, v, a, f, &lim).expect("plans").into_iter().map(Motion::from).collect();
    let jerk = scurve::jerk_limited(steps, 0.0, 0.0, v, a, j, a, j, f, &lim).expect("plans");
    let fourth = scurve::fourth_order(steps, v, a, j, s, f, &lim).expect("plans");
    let ff = f as f64;
    [("trapezoid", trapezoid), ("jerk-limited", jerk), ("fourth-order", fourth)]
        .into_iter()
        .map(|(profile, moves)| {
            let run = AxisRun::run_motions(&moves, &lim);
            assert!(run.rejected.is_empty(), "{profile}: a planned segment was rejected");
            // (acceleration at start, at end, largest |jerk| inside), per tick units.
            let ends: Vec<(f64, f64, f64)> = moves
                .iter()
                .map(|m| match m {
                    Motion::Trapezoid(seg) => {
                        let t = seg.t_ticks as f64;
                        let alpha = 2.0 * (seg.d_q32() as f64 / 2f64.powi(32)) / (t * t);
                        (alpha, alpha, 0.0)
                    }
                    Motion::Poly(p) => {
                        let (_, a0, j0) = p.derivatives_at(0.0);
                        let (_, a1, j1) = p.derivatives_at(p.t_ticks as f64);
                        (a0, a1, j0.abs().max(j1.abs()))
                    }
                })
                .collect();
            let peak_accel = ends.iter().map(|e| e.0.abs().max(e.1.abs())).fold(0.0, f64::max) * ff * ff;
            let peak_jerk_inside = ends.iter().map(|e| e.2).fold(0.0, f64::max) * ff * ff * ff;
            let mut jumps = vec![ends.first().map_or(0.0, |e| e.0.abs()), ends.last().map_or(0.0, |e| e.1.abs())];
            jumps.extend(ends.windows(2).map(|w| (w[1].0 - w[0].1).abs()));
            ProfileRow {
                profile,
                segments: moves.len(),
                steps: run.edge_ticks.len(),
                duration_ms: run.end_tick as f64 / ff * 1e3,
                peak_accel,
                peak_jerk_inside,
                largest_accel_jump: jumps.into_iter().fold(0.0, f64::max) * ff * ff,
                max_edge_error_ticks: run.max_edge_error_ticks(),
            }
        })
        .collect()
}

/// The comparison as a markdown table.
pub fn profile_table(rows: &[ProfileRow]) -> String {
    let mut s = String::from(
        "| profile | segments | steps | duration (ms) | peak acceleration (steps/s²) | peak jerk inside segments (steps/s³) | largest acceleration jump at a join (steps/s²) | max abs edge error (ticks) |\n|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {:.3} | {:.0} | {:.4e} | {:.1} | {:.3} |",
            r.profile,
            r.segments,
            r.steps,
            r.duration_ms,
            r.peak_accel,
            r.peak_jerk_inside,
            r.largest_accel_jump,
            r.max_edge_error_ticks
        );
    }
    s
}

/// The committed accuracy.md text for these reports.
pub fn markdown(reports: &[AxisReport]) -> String {
    let mut s = String::from(
        "# Accuracy report\n\nGenerated by `cargo run --release -p tdm-stepper -- accuracy` \
         (do not edit). Edge error: emitted STEP edge minus exact step time, from the axis \
         release, so it includes drift. Period error: emitted minus exact period, over exact \
         period. Alternatives are described in `ip/src/model/alternatives.rs`.\n\n",
    );
    for r in reports.iter().filter(|r| r.axis == 0) {
        let _ = writeln!(s, "- `{}`: {}", r.move_name, r.description);
    }
    s.push('\n');
    s.push_str(&table(reports));
    s.push('\n');
    for r in reports {
        let _ = writeln!(s, "![{} axis {}]({})", r.move_name, r.axis, svg_name(r));
    }
    let (f, steps, v, a, j, snap) = COMPARISON;
    let _ = write!(
        s,
        "\n## S-curve profiles\n\nOne move, {steps} steps at {} MHz with v_max {v} steps/s and a_max {a} \
         steps/s² (both sides), planned three ways: a trapezoid (`trapezoid_by_limits`), a \
         jerk-limited profile (j_max {j:e} steps/s³, `scurve::jerk_limited`) and the fourth-order \
         profile (also s_max {snap:e} steps/s⁴, `scurve::fourth_order`), each run through the \
         model. The edge error is against the exact kinematics of the segments; an S-curve's \
         acceleration jumps at a join only by the rounding of its boundaries.\n\n",
        f / 1_000_000
    );
    s.push_str(&profile_table(&profile_comparison()));
    s
}

fn svg_name(r: &AxisReport) -> String {
    format!("{}-axis{}.svg", r.move_name, r.axis)
}

fn range(v: &[f64]) -> std::ops::Range<f64> {
    let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if !lo.is_finite() || !hi.is_finite() || hi - lo < 1e-9 {
        return (lo.min(0.0) - 1.0)..(hi.max(0.0) + 1.0);
    }
    let pad = (hi - lo) * 0.05;
    (lo - pad)..(hi + pad)
}

type PlotResult<T> = Result<T, Box<dyn std::error::Error>>;

fn panel(
    area: &DrawingArea<SVGBackend, plotters::coord::Shift>,
    caption: &str,
    y_desc: &str,
    series: &[(&[f64], RGBColor)],
) -> PlotResult<()> {
    let n = series.iter().map(|s| s.0.len()).max().unwrap_or(1).max(2);
    let all: Vec<f64> = series.iter().flat_map(|s| s.0.iter().copied()).collect();
    let mut chart = ChartBuilder::on(area)
        .caption(caption, ("sans-serif", 15))
        .margin(8)
        .x_label_area_size(28)
        .y_label_area_size(64)
        .build_cartesian_2d(1f64..n as f64, range(&all))?;
    chart.configure_mesh().x_desc("step").y_desc(y_desc).light_line_style(WHITE).draw()?;
    for &(data, color) in series {
        chart.draw_series(LineSeries::new(data.iter().enumerate().map(|(k, &y)| (k as f64 + 1.0, y)), color))?;
    }
    Ok(())
}

/// Writes one SVG for an axis: the exact speed, then per algorithm its period
/// error (%) and its cumulative edge error (ticks).
pub fn write_svg(r: &AxisReport, path: &Path) -> PlotResult<()> {
    let rows = 1 + r.metrics.len();
    let root = SVGBackend::new(path, (1200, 260 * rows as u32)).into_drawing_area();
    root.fill(&WHITE)?;
    let root = root.titled(
        &format!("{} axis {}: {}", r.move_name, r.axis, r.description),
        ("sans-serif", 18),
    )?;
    let (top, rest) = root.split_vertically(260);
    panel(&top, "exact speed (steps/s)", "steps/s", &[(&r.exact_speed, BLACK)])?;
    let cells = rest.split_evenly((r.metrics.len(), 2));
    let colors = [BLUE, RED, MAGENTA, GREEN];
    for (k, m) in r.metrics.iter().enumerate() {
        let c = colors[k % colors.len()];
        panel(&cells[2 * k], &format!("{}: period error (%)", m.label), "%", &[(&m.period_error_pct, c)])?;
        panel(
            &cells[2 * k + 1],
            &format!("{}: edge error (ticks, cumulative)", m.label),
            "ticks",
            &[(&m.edge_error_ticks, c)],
        )?;
    }
    root.present()?;
    Ok(())
}

/// Runs the report and writes accuracy.json, accuracy.md and the SVGs into `dir`.
pub fn write_report(dir: &Path) -> PlotResult<(Vec<AxisReport>, Vec<PathBuf>)> {
    std::fs::create_dir_all(dir)?;
    let reports = report();
    let mut paths = Vec::new();
    let json = dir.join("accuracy.json");
    std::fs::write(&json, serde_json::to_string_pretty(&reports)? + "\n")?;
    paths.push(json);
    let md = dir.join("accuracy.md");
    std::fs::write(&md, markdown(&reports))?;
    paths.push(md);
    for r in &reports {
        let p = dir.join(svg_name(r));
        write_svg(r, &p)?;
        paths.push(p);
    }
    Ok((reports, paths))
}
