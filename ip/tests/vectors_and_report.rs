//! The committed vectors and accuracy report are current and say what they must;
//! the planner, the unit helpers and the error codes behave as documented.

use std::path::PathBuf;
use tdm_stepper::accuracy;
use tdm_stepper::model::alternatives::Algorithm;
use tdm_stepper::model::exact::edge_within;
use tdm_stepper::model::units::*;
use tdm_stepper::model::*;
use tdm_stepper::model::{exact, planner};
use tdm_stepper::vectors::{self, VectorFile};

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

#[test]
fn committed_vectors_match_the_generator() {
    let all = vectors::all();
    let mut names: Vec<String> = all.iter().map(|v| format!("{}.json", v.name)).collect();
    for v in &all {
        let path = repo().join("vectors").join(format!("{}.json", v.name));
        let committed = std::fs::read_to_string(&path)
            .unwrap_or_else(|e| panic!("{}: {e}; run `tdm-stepper vectors`", path.display()));
        assert!(committed == vectors::to_json(v), "{} is stale: run `tdm-stepper vectors`", path.display());
    }
    // No stray file that the generator no longer makes.
    let mut on_disk: Vec<String> = std::fs::read_dir(repo().join("vectors"))
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|n| n.ends_with(".json"))
        .collect();
    names.sort();
    on_disk.sort();
    assert_eq!(names, on_disk);
}

/// Re-checks every committed vector from its JSON alone, the way an HDL test will
/// read it: periods sum to the edges, edges within 1 tick of exact (in integers),
/// errors where expected, positions and end ticks consistent.
#[test]
fn committed_vectors_are_self_consistent() {
    for entry in std::fs::read_dir(repo().join("vectors")).unwrap() {
        let path = entry.unwrap().path();
        let v: VectorFile = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        let limits = Limits::new(v.min_period_ticks).unwrap();
        for (a, axis) in v.axes.iter().enumerate() {
            let mut start = 0u64;
            let mut k = 0usize;
            let mut position = 0i64;
            for sv in &axis.segments {
                let seg = sv.segment();
                assert_eq!(seg.validate(&limits).err().map(|e| e.code()), sv.error, "{path:?} axis {a}");
                if sv.error.is_some() {
                    assert!(sv.periods.is_empty());
                    continue;
                }
                assert_eq!(sv.periods.len(), seg.n_steps() as usize);
                let mut edge = start;
                for (i, &p) in sv.periods.iter().enumerate() {
                    assert!(p >= v.min_period_ticks, "{path:?}: period {p}");
                    edge += p as u64;
                    assert_eq!(axis.edge_ticks[k], edge, "{path:?} axis {a} edge {k}");
                    assert!(edge_within(&seg, i as u32 + 1, (edge - start) as i64, 1), "{path:?} edge {k}");
                    k += 1;
                }
                start += seg.t_ticks as u64;
                position += seg.steps as i64;
            }
            assert_eq!(k, axis.edge_ticks.len());
            assert_eq!(start, axis.end_tick);
            assert_eq!(position, axis.final_position);
            assert!(axis.max_edge_error_ticks <= EDGE_ERROR_BOUND_TICKS);
        }
    }
}

#[test]
fn vectors_cover_what_the_issue_asks() {
    let all = vectors::all();
    let kinds: std::collections::HashSet<String> = all
        .iter()
        .flat_map(|v| v.axes.iter().flat_map(|a| a.segments.iter().filter_map(|s| s.kind.clone())))
        .collect();
    for k in ["dwell", "uniform", "nearly_uniform", "accelerate", "decelerate"] {
        assert!(kinds.contains(k), "no {k} segment in the vectors");
    }
    let codes: std::collections::HashSet<u8> =
        all.iter().flat_map(|v| v.axes.iter().flat_map(|a| a.segments.iter().filter_map(|s| s.error))).collect();
    for e in SegmentError::ALL {
        assert!(codes.contains(&e.code()), "no vector for {e}");
    }
    let paper = all.iter().find(|v| v.name == "paper_experiment").unwrap();
    assert_eq!(paper.clock_hz, 50_000_000);
    assert_eq!(paper.axes[0].final_position, 2400);
    assert_eq!(paper.axes[1].final_position, 1800);
    assert_eq!(paper.axes[0].end_tick, 2_500_000); // 50 ms
    // Near the limit: some period equals the 2-tick minimum.
    let near = all.iter().find(|v| v.name == "near_limit").unwrap();
    let min_p = near.axes[0].segments.iter().flat_map(|s| s.periods.iter()).min().unwrap();
    assert!(*min_p <= 3, "near_limit reaches only {min_p}-tick periods");
}

/// The issue's acceptance figures for the paper's experiment, measured.
#[test]
fn accuracy_report_meets_the_targets_on_the_paper_experiment() {
    let reports = accuracy::report();
    let paper: Vec<_> = reports.iter().filter(|r| r.move_name == "paper_experiment").collect();
    assert_eq!(paper.len(), 2);
    for r in &paper {
        let ours = r.metrics.iter().find(|m| m.algorithm == Algorithm::Integer).unwrap();
        assert!(ours.max_abs_edge_error_ticks <= 1.0, "axis {}: {}", r.axis, ours.max_abs_edge_error_ticks);
        assert!(ours.max_abs_period_error_pct_ge_floor <= 0.2, "axis {}", r.axis);
        assert_eq!(ours.end_error_ticks, 0.0);
        // The alternatives are measured, not assumed: every one emitted every step,
        // and per-period rounding drifts by more than a tick over the move.
        for m in &r.metrics {
            assert_eq!(m.steps, if r.axis == 0 { 2400 } else { 1800 });
            assert!(m.max_abs_edge_error_ticks.is_finite());
        }
        let rounding = r.metrics.iter().find(|m| m.algorithm == Algorithm::PerPeriodRounding).unwrap();
        assert!(rounding.max_abs_edge_error_ticks > 1.0);
    }
    for r in &reports {
        let ours = r.metrics.iter().find(|m| m.algorithm == Algorithm::Integer).unwrap();
        assert!(ours.max_abs_edge_error_ticks <= EDGE_ERROR_BOUND_TICKS, "{}", r.move_name);
    }
}

/// The S-curve comparison: the same move as a trapezoid, jerk-limited and fourth-order
/// profile. The S-curves keep the jerk inside their segments near j_max and their
/// acceleration continuous up to the rounding of the boundaries (where the
/// trapezoid's jumps by a_max), take longer, and put every edge within ½ tick.
#[test]
fn the_s_curve_comparison_says_what_the_profiles_do() {
    let (_, steps, _, a, j, _) = accuracy::COMPARISON;
    let rows = accuracy::profile_comparison();
    assert_eq!(rows.iter().map(|r| r.profile).collect::<Vec<_>>(), ["trapezoid", "jerk-limited", "fourth-order"]);
    for r in &rows {
        assert_eq!(r.steps as i64, steps);
        assert!((r.peak_accel - a).abs() <= 0.01 * a, "{}: peak acceleration {}", r.profile, r.peak_accel);
    }
    let (t, jl, fo) = (&rows[0], &rows[1], &rows[2]);
    assert!((t.largest_accel_jump - a).abs() <= 0.01 * a && t.peak_jerk_inside == 0.0);
    for s in [jl, fo] {
        assert!(s.largest_accel_jump <= 0.002 * a, "{}: a jump of {}", s.profile, s.largest_accel_jump);
        assert!(s.peak_jerk_inside <= 1.1 * j && s.peak_jerk_inside >= 0.9 * j, "{}: jerk {}", s.profile, s.peak_jerk_inside);
        assert!(s.max_edge_error_ticks <= tdm_stepper::model::poly::POLY_EDGE_ERROR_BOUND_TICKS + 1e-6);
    }
    assert!(t.duration_ms < jl.duration_ms && jl.duration_ms < fo.duration_ms);
}

#[test]
fn committed_accuracy_report_is_current() {
    let path = repo().join("docs/accuracy/accuracy.md");
    let committed = std::fs::read_to_string(&path).expect("docs/accuracy/accuracy.md");
    assert!(
        committed == accuracy::markdown(&accuracy::report()),
        "docs/accuracy is stale: run `cargo run --release -- accuracy`"
    );
}

#[test]
fn paper_experiment_plans_as_the_paper_says() {
    let segs = vectors::paper_experiment_segments();
    let ax0: Vec<(u32, i32)> = segs[0].iter().map(|s| (s.t_ticks, s.steps)).collect();
    assert_eq!(ax0, vec![(1_000_000, 800), (500_000, 800), (1_000_000, 800)]);
    // Cruise at 80,000 steps/s: 0.0016 steps/tick.
    assert!((rate_to_steps_per_s(segs[0][1].v0_rate, 50_000_000) - 80_000.0).abs() < 0.02);
    assert!((rate_to_steps_per_s(segs[1][1].v0_rate, 50_000_000) - 60_000.0).abs() < 0.02);
}

#[test]
fn planner_by_limits_keeps_steps_and_rests() {
    let lim = Limits::default();
    for (steps, v, a) in [(10_000i64, 20_000.0, 1e5), (-3, 1e5, 1e6), (123_457, 50_000.0, 3e5), (1, 10.0, 10.0)] {
        let segs = planner::trapezoid_by_limits(steps, v, a, 50_000_000, &lim).unwrap();
        assert_eq!(segs.iter().map(|s| s.steps as i64).sum::<i64>(), steps);
        assert_eq!(segs[0].v0_rate, 0, "starts from rest");
        let last = segs.last().unwrap();
        let v_end = exact::speed_at(last, last.t_ticks as f64) * 50e6;
        assert!(v_end.abs() < 1.0, "ends at rest, not {v_end} steps/s");
        let peak = segs.iter().map(|s| rate_to_steps_per_s(s.v0_rate, 50_000_000)).fold(0.0, f64::max);
        assert!(peak <= v * 1.01, "peak {peak} above v_max {v}");
        assert!(AxisRun::run(&segs, &lim).rejected.is_empty());
    }
    assert!(matches!(
        planner::trapezoid_by_limits(10, -1.0, 1.0, 50_000_000, &lim),
        Err(planner::PlanError::BadLimit("v_max", _))
    ));
    assert!(matches!(planner::trapezoid_by_ticks(5, [0, 0, 0], &lim), Err(planner::PlanError::NoDuration)));
    // Too fast for the period limit: refused with the segment's code, not clipped.
    assert!(matches!(
        planner::trapezoid_by_ticks(1000, [100, 100, 100], &lim),
        Err(planner::PlanError::Segment { error: SegmentError::PeriodTooShort, .. })
    ));
}

#[test]
fn unit_helpers_round_and_refuse() {
    assert_eq!(steps_per_s_to_rate(80_000.0, 50_000_000), Ok(6_871_948));
    assert_eq!(seconds_to_ticks(0.020, 50_000_000), Ok(1_000_000));
    assert_eq!(ticks_to_seconds(1_000_000, 50_000_000), 0.020);
    assert!(matches!(steps_per_s_to_rate(30e6, 50_000_000), Err(UnitError::RateRange(_))));
    assert!(matches!(steps_per_s_to_rate(-1.0, 50_000_000), Err(UnitError::Negative(..))));
    assert!(matches!(steps_per_s_to_rate(f64::NAN, 50_000_000), Err(UnitError::NotFinite(_))));
    assert!(matches!(seconds_to_ticks(30.0, 50_000_000), Err(UnitError::TicksRange(_))));
    assert!(matches!(check_clock(200_000_000), Err(UnitError::ClockRange(_))));
    assert_eq!(check_clock(100_000_000), Ok(100_000_000));
    let r = steps_per_s_to_rate(12_345.0, 100_000_000).unwrap();
    assert!((rate_to_steps_per_s(r, 100_000_000) - 12_345.0).abs() < 0.03);
}

#[test]
fn error_codes_are_stable() {
    let codes: Vec<(u8, &str)> = SegmentError::ALL.iter().map(|e| (e.code(), e.name())).collect();
    assert_eq!(
        codes,
        vec![(1, "TICKS_ZERO"), (2, "REVERSES"), (3, "PERIOD_TOO_SHORT"), (4, "TICKS_RANGE"), (5, "STEPS_RANGE"), (6, "RATE_RANGE")]
    );
    for e in SegmentError::ALL {
        assert_eq!(SegmentError::from_code(e.code()), Some(e));
    }
    assert_eq!(SegmentError::from_code(0), None);
}

#[test]
fn widths_hold_at_the_corners_of_the_range() {
    // Overflow panics in this profile, so planning and stepping the extremes proves the widths.
    let lim = Limits::default();
    let t = MAX_T_TICKS;
    let n = MAX_STEPS;
    for seg in [
        Segment::new(0, t, n as i32),                                           // from rest, longest, most steps
        Segment::new(((2 * n as u64) << 32).div_euclid(t as u64) as u32, t, -(n as i32)), // to rest
        Segment::new(((n as u64) << 32).div_euclid(t as u64) as u32 + 1, t, n as i32),     // nearly uniform
        Segment::new(1, t, 1),
        Segment::new(0, t, 1),
        vectors::nearly_uniform_fallback(4000, 1),
    ] {
        assert_eq!(seg.validate(&lim), Ok(()), "{seg:?}");
        let plan = SegmentPlan::new(seg);
        assert!(plan.p_scaled < 1u128 << ROOT_BITS);
        let n = seg.n_steps();
        for i in [1, 2, n / 2, n - 1, n].into_iter().filter(|&i| i >= 1 && i <= n) {
            let e = plan.edge(i);
            assert!(edge_within(&seg, i, e as i64, 1), "{seg:?} step {i}");
        }
    }
    assert!(matches!(SegmentPlan::new(vectors::nearly_uniform_fallback(4000, 1)).kind, PlanKind::Uniform { nearly: true }));
}
