//! The core's arithmetic state against the reference model over the full range.
//!
//! One segment at a time into a one-axis core without a start: the scheduler sets the
//! segment up and computes periods until the period FIFO is full, then waits. The
//! context it committed must then equal the model's, bit for bit: the plan kind, P',
//! B', and after i computed steps the accumulator A_i and the edge E_i. Segments are
//! drawn over T ∈ [1, 2^30], n ∈ [0, 2^24], including nearly uniform ones that take the
//! fallback; no step has to be played out, so long segments cost nothing.
//! (rust-hdl simulation; its equality with the Verilog is hdl_core.rs's subject.)

mod common;

use common::*;
use tdm_stepper::hdl::core::TdmCore;
use tdm_stepper::model::{Limits, PlanKind, Segment, SegmentPlan, MAX_STEPS, MAX_T_TICKS};

const DEPTH: usize = 2;

fn run_setup<const R: usize>(seg: Segment) -> TdmCore<1, R, DEPTH, 2> {
    let mut u = one_segment_core::<R, DEPTH, 2>(seg);
    // Setup (~200 cycles at R = 2) plus DEPTH steps (~22 each), with margin.
    for _ in 0..800 {
        tick_core(&mut u);
    }
    u
}

fn check(seg: Segment) {
    check_r::<4>(seg);
    check_r::<2>(seg);
}

/// At R digits per cycle (the configurations the docs name: 2, exported, and 4).
fn check_r<const R: usize>(seg: Segment) {
    // The core takes only what the push check passes (hdl_push_check.rs): valid
    // segments, in their effective form.
    if seg.validate(&Limits::default()).is_err() {
        return;
    }
    let u = run_setup::<R>(seg.effective());
    let (kind, word) = u.context(0);
    let kind = kind as u64;
    let plan = SegmentPlan::new(seg);
    let i = word.i;
    let n = seg.n_steps();
    // The scheduler stops once the FIFO holds DEPTH periods; up to two more may be in
    // the pulse stage by then, so DEPTH to DEPTH + 2 are computed. A segment of at most
    // DEPTH steps (or a dwell) is done: the context is idle again.
    if n as usize <= DEPTH {
        assert_eq!(kind, 0, "{seg:?}: context should be idle after {n} steps");
        return;
    }
    if kind == 0 {
        assert!(n as usize <= DEPTH + 2, "{seg:?}: idle with steps left");
        return;
    }
    assert!((DEPTH..=DEPTH + 2).contains(&(i as usize)), "{seg:?}: {i} steps computed before the FIFO filled");
    let want_kind = match plan.kind {
        PlanKind::Uniform { .. } => 1,
        PlanKind::Accelerate => 2,
        PlanKind::Decelerate => 3,
        PlanKind::Dwell => unreachable!(),
    };
    assert_eq!(kind, want_kind, "{seg:?}: plan kind ({:?})", plan.kind);
    assert_eq!(word.e as u64, plan.edge(i), "{seg:?}: E_{i}");
    if want_kind != 1 {
        assert_eq!(word.p as u128, plan.p_scaled, "{seg:?}: P'");
        assert_eq!(word.b, plan.b_scaled, "{seg:?}: B'");
        assert_eq!(word.a, plan.accumulator(i), "{seg:?}: C_{i}");
    }
}

/// Random segments over the whole range, valid and not, plus nearly uniform ones.
#[test]
fn setup_state_equals_the_model_over_the_range() {
    let limits = Limits::default();
    let mut rng = Rng(0xa076_1d64_78bd_642f);
    let mut kinds = std::collections::HashMap::new();
    let mut checked = 0;
    while checked < 60 {
        let t = (((rng.next() % 31) as f64).exp2() as u64 + rng.next() % 1024).clamp(1, MAX_T_TICKS as u64);
        let n_max = ((t as u128 * limits.max_rate() as u128) >> 32).min(MAX_STEPS as u128) as u64;
        let n = if n_max == 0 { 0 } else { ((rng.next() % 25) as f64).exp2() as u64 % (n_max + 1) };
        let uniform = ((n as u128) << 32) / t as u128;
        let v0 = match rng.next() % 4 {
            0 => 0u64,
            1 => uniform as u64,
            2 => (uniform as u64).saturating_add(rng.next() % 3).saturating_sub(1),
            _ => rng.next() % (2 * uniform as u64 + 1),
        };
        let seg = Segment::new(v0.min(u32::MAX as u64) as u32, t as u32, if rng.next() % 2 == 0 { n as i32 } else { -(n as i32) });
        let key = match seg.validate(&limits) {
            Ok(()) => format!("{:?}", SegmentPlan::new(seg).kind),
            Err(e) => format!("{e:?}"),
        };
        *kinds.entry(key).or_insert(0) += 1;
        check(seg);
        checked += 1;
    }
    // And the widest path: nearly uniform segments that fall back.
    for d in [1, -1, 7] {
        let seg = tdm_stepper::vectors::nearly_uniform_fallback(4000, d);
        *kinds.entry(format!("{:?}", SegmentPlan::new(seg).kind)).or_insert(0) += 1;
        check(seg);
    }
    // The fallback's boundary: the largest P' + 2T' that still takes the sqrt path
    // and the smallest that falls back, from a deterministic search.
    let (below, above) = fallback_boundary();
    assert!(matches!(SegmentPlan::new(below).kind, PlanKind::Accelerate | PlanKind::Decelerate));
    assert!(matches!(SegmentPlan::new(above).kind, PlanKind::Uniform { nearly: true }));
    check(below);
    check(above);
    eprintln!("kinds checked: {kinds:?}");
    for k in ["Accelerate", "Decelerate", "Uniform { nearly: true }"] {
        assert!(kinds.contains_key(k), "no {k} segment was drawn: {kinds:?}");
    }
}

/// Valid nearly-uniform segments closest to the sqrt path's width limit on each side.
fn fallback_boundary() -> (Segment, Segment) {
    let limits = Limits::default();
    let limit = 1u128 << tdm_stepper::model::ROOT_BITS;
    let (mut below, mut above): (Option<(u128, Segment)>, Option<(u128, Segment)>) = (None, None);
    for half in (1u32 << 12)..(1u32 << 12) + 4000 {
        for d in [1i64, -1, 2, -2, 3, -3, 5, -5, 9, -9, 17, -17, 33, -33] {
            let Some(seg) = Segment::with_tiny_d(2 * half + 1, d, false) else { continue };
            if seg.validate(&limits).is_err() {
                continue;
            }
            let x = SegmentPlan::p_unbounded(&seg) + 2 * ((seg.t_ticks as u128) << tdm_stepper::model::TAU_FRAC_BITS);
            if x < limit && below.is_none_or(|(b, _)| x > b) {
                below = Some((x, seg));
            }
            if x >= limit && above.is_none_or(|(a, _)| x < a) {
                above = Some((x, seg));
            }
        }
    }
    let (b, a) = (below.expect("a segment below the limit"), above.expect("a segment above the limit"));
    eprintln!("boundary: below 2^64 by {}, above by {}", limit - b.0, a.0 - limit);
    (b.1, a.1)
}

/// Decelerations to rest whose v0 = ⌈2n·2^32/T⌉ was rounded up: the push check hands
/// the core their effective segment (v0 − 1), which it runs as the model does, bit for
/// bit, at both R. In the model, one rate unit more is rejected as reversing (code 2),
/// v0 − 1 above RMAX is code 3, and the effective v0 = RMAX exactly is accepted (the
/// push check's verdicts on the same cases: hdl_push_check.rs).
#[test]
fn decelerations_to_rest_with_v0_rounded_up_run_as_the_model_says() {
    let limits = Limits::default();
    let rmax = limits.max_rate() as u64;
    let mut cases = vec![
        // The documented example: 120,000 steps/s to rest over 1,200 steps at 50 MHz.
        Segment::new(10_307_922, 1_000_000, 1200),
        Segment::new(10_307_923, 1_000_000, 1200),
        Segment::new(10_307_922, 1_000_000, -1200),
        // v0 − 1 = RMAX exactly (accepted), and v0 − 1 above RMAX (code 3).
        Segment::new((rmax + 1) as u32, 6000, 1000),
        Segment::new(1_431_894_415, 5999, 1000),
    ];
    let mut rng = Rng(0x2545_f491_4f6c_dd1d);
    while cases.len() < 16 {
        let t = (((rng.next() % 31) as f64).exp2() as u64 + rng.next() % 1024).clamp(2, MAX_T_TICKS as u64);
        let n_max = ((t as u128 * rmax as u128) >> 33).min(MAX_STEPS as u128) as u64;
        if n_max == 0 {
            continue;
        }
        let n = 1 + ((rng.next() % 25) as f64).exp2() as u64 % n_max;
        let exact = (2 * n as u128) << 32;
        if exact % t as u128 == 0 {
            continue;
        }
        cases.push(Segment::new(exact.div_ceil(t as u128) as u32, t as u32, n as i32));
    }
    let codes: Vec<_> = cases.iter().map(|s| s.validate(&limits).err().map(|e| e.code())).collect();
    assert_eq!(&codes[..5], &[None, Some(2), None, None, Some(3)], "the fixed cases");
    assert!(cases[5..].iter().all(|s| s.rounds_past_rest() && s.validate(&limits).is_ok()));
    for seg in cases {
        check(seg);
    }
}
