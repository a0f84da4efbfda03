//! Property tests of the reference model over the documented range.
//!
//! Each property runs 10,000 cases, the heavier ones a fixed fraction of that (each
//! says how many); `PROPTEST_CASES` scales them all (`PROPTEST_CASES=100000` runs ten
//! times as many everywhere: the deep run, outside the timed test command). Segments are drawn
//! log-uniformly over T ∈ [1, 2^30] and n ∈ [0, 2^24], with start speeds at the
//! interval ends, uniform, and nearly uniform (tiny |D|, which reaches the widest
//! accumulators and the uniform fallback). Every edge is checked twice: in f64
//! against the documented bound, and exactly, in integers, against 1 tick.

use proptest::prelude::*;
use tdm_stepper::model::exact::{edge_within, step_time};
use tdm_stepper::model::poly::*;
use tdm_stepper::model::scurve;
use tdm_stepper::model::*;

const CASES: u32 = 10_000;
/// Segments up to this many steps are checked at every step; longer ones at samples.
const FULL_CHECK_STEPS: u32 = 4096;

/// `n` cases at the default [`CASES`], scaled as `PROPTEST_CASES` scales it.
fn scaled(n: u32) -> u32 {
    (n as u64 * config().cases as u64 / CASES as u64).max(1) as u32
}

fn config() -> ProptestConfig {
    let cases = std::env::var("PROPTEST_CASES").ok().and_then(|s| s.parse().ok()).unwrap_or(CASES);
    ProptestConfig {
        cases,
        max_shrink_iters: 2000,
        // Most near-uniform draws fall outside the range; allow for it.
        max_local_rejects: 1 << 22,
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

/// Log-uniform integer in [lo, hi].
fn log_uniform(lo: u64, hi: u64) -> impl Strategy<Value = u64> {
    let (l, h) = ((lo.max(1) as f64).ln(), (hi as f64).ln());
    (0.0f64..=1.0).prop_map(move |x| ((l + x * (h - l)).exp().round() as u64).clamp(lo, hi))
}

fn min_period() -> impl Strategy<Value = u32> {
    prop_oneof![Just(2u32), Just(3), 2u32..20, 20u32..2000]
}

/// The valid v0_rate interval for (T, n, M): no reversal and both ends at most RMAX.
fn rate_interval(t: u64, n: u64, m: u32) -> Option<(u64, u64)> {
    let one = 1u128 << 32;
    let rmax = Limits::new(m).unwrap().max_rate() as u128;
    let hi = ((2 * n as u128 * one) / t as u128).min(rmax).min(MAX_V0_RATE as u128);
    // v_end·T·2^32 = 2n·2^32 − v0·T ≤ T·RMAX  ⟺  v0 ≥ (2n·2^32 − T·RMAX)/T
    let need = (2 * n as u128 * one).saturating_sub(t as u128 * rmax);
    let lo = need.div_ceil(t as u128);
    (lo <= hi).then_some((lo as u64, hi as u64))
}

/// A valid segment anywhere in the range.
fn valid_segment() -> impl Strategy<Value = (Segment, Limits)> {
    (min_period(), log_uniform(1, MAX_T_TICKS as u64), 0.0f64..=1.0, 0u8..6, any::<u64>(), any::<bool>())
        .prop_filter_map("no valid rate", |(m, t, nx, pick, r, neg)| {
            // Average rate n/T at most RMAX/2^32 (both ends can then be within it).
            let rmax = Limits::new(m).unwrap().max_rate() as u64;
            let n_max = ((t as u128 * rmax as u128) >> 32).min(MAX_STEPS as u128) as u64;
            let n = if nx < 0.05 { 0 } else { ((n_max as f64 + 1.0).powf(nx) - 1.0).round() as u64 };
            let n = n.min(n_max);
            let (lo, hi) = if n == 0 { (0, 0) } else { rate_interval(t, n, m)? };
            let uniform = ((n as u128) << 32) / t as u128;
            let v0 = match pick {
                0 => lo,
                1 => hi,
                2 => (uniform as u64).clamp(lo, hi),
                3 => (uniform as u64 + r % 3).saturating_sub(1).clamp(lo, hi),
                _ => lo + r % (hi - lo + 1),
            };
            let steps = if neg { -(n as i64) } else { n as i64 } as i32;
            Some((Segment::new(v0 as u32, t as u32, steps), Limits::new(m).unwrap()))
        })
}

/// A nearly uniform segment: |D·2^32| small, so P is huge (up to the sqrt path's width
/// and past it, into the uniform fallback). Built by solving v0_rate·T ≡ −d (mod 2^32).
fn nearly_uniform_segment() -> impl Strategy<Value = (Segment, Limits)> {
    (0u32..(1 << 28), -4000i64..4000, any::<bool>()).prop_filter_map("no segment in range", |(half_rate, d, neg)| {
        let seg = Segment::with_tiny_d(2 * half_rate + 1, d, neg)?;
        let limits = Limits::default();
        seg.validate(&limits).ok().map(|_| (seg, limits))
    })
}

/// Checks one segment's edges; returns the largest f64 error seen.
fn check_segment(seg: &Segment, limits: &Limits, rng_seed: u64) -> Result<f64, TestCaseError> {
    prop_assert_eq!(seg.validate(limits), Ok(()));
    let plan = SegmentPlan::new(*seg);
    let n = seg.n_steps();
    let mut worst = 0.0f64;
    let mut check_edge = |i: u32, e: u64| -> Result<(), TestCaseError> {
        let err = (e as f64 - step_time(seg, i)).abs();
        worst = worst.max(err);
        prop_assert!(err <= EDGE_ERROR_BOUND_TICKS + 1e-6, "step {i}: edge {e}, error {err} ticks, {plan:?}");
        prop_assert!(edge_within(seg, i, e as i64, 1), "step {i}: edge {e} not within 1 tick (exact check)");
        Ok(())
    };
    if n <= FULL_CHECK_STEPS {
        let mut edge = 0u64;
        let mut count = 0;
        for (k, p) in plan.periods().enumerate() {
            let i = k as u32 + 1;
            prop_assert!(p >= limits.min_period_ticks, "step {i}: period {p} < {}", limits.min_period_ticks);
            edge += p as u64;
            prop_assert_eq!(edge, plan.edge(i), "incremental and direct edge differ at step {}", i);
            check_edge(i, edge)?;
            count += 1;
        }
        prop_assert_eq!(count, n);
        prop_assert_eq!(edge, if n == 0 { 0 } else { seg.t_ticks as u64 }, "segment does not sum to T");
    } else {
        // Ends of the segment plus pseudo-random steps in between (direct form).
        let mut x = rng_seed | 1;
        let mut samples: Vec<u32> = (1..=64).chain(n - 64..=n).collect();
        for _ in 0..192 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            samples.push(1 + (x % n as u64) as u32);
        }
        for i in samples {
            let e = plan.edge(i);
            check_edge(i, e)?;
            let p = e - plan.edge(i - 1);
            prop_assert!(p >= limits.min_period_ticks as u64, "step {i}: period {p}");
        }
        prop_assert_eq!(plan.edge(n), seg.t_ticks as u64);
    }
    Ok(worst)
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn every_edge_within_bound_over_the_range((seg, limits) in valid_segment(), seed in any::<u64>()) {
        check_segment(&seg, &limits, seed)?;
    }

    #[test]
    fn nearly_uniform_segments_within_bound((seg, limits) in nearly_uniform_segment(), seed in any::<u64>()) {
        check_segment(&seg, &limits, seed)?;
    }

    #[test]
    fn offset_root_equals_isqrt_over_its_range(
        p in prop_oneof![any::<u64>(), Just(0u64), Just(u64::MAX - (1 << 37)), 0u64..1000],
        x in prop_oneof![0u64..(1 << 36), Just(0u64), Just((1u64 << 34) + 1), ((1u64 << 36) - 4)..(1u64 << 36)],
        pick in 0u8..3,
        frac in any::<u64>(),
    ) {
        // Keep the whole interval of c inside the accumulator: (x+1)(2p + x + 1) ≤ 2^100
        // holds when x + 1 ≤ 2^100 / (2p + 2^36). Roots above that cap are folded onto
        // the cap's top few values, so the largest admissible roots are still drawn.
        let cap = ((1u128 << ACC_BITS) / (2 * p as u128 + (1u128 << 36))).min(1 << 36) as u64;
        let x = if x < cap { x } else { cap - 1 - (x % 4).min(cap - 1) };
        let (p128, x128) = (p as u128, x as u128);
        prop_assume!(p128 + x128 < 1 << 64);
        // The interval of c whose root is x: [x² + 2px, (x+1)² + 2p(x+1) − 1].
        let lo = x128 * x128 + 2 * p128 * x128;
        let width = 2 * (p128 + x128) + 1;
        let c = match pick { 0 => lo, 1 => lo + width - 1, _ => lo + (frac as u128 % width) };
        prop_assert!(c < 1u128 << ACC_BITS);
        prop_assert_eq!((p128 * p128 + c).isqrt() - p128, x128);
        prop_assert_eq!(offset_root(p, c), x);
    }

    /// Multi-segment moves: edges measured from the move start, cumulatively.
    #[test]
    fn multi_segment_moves_do_not_drift(
        parts in prop::collection::vec(valid_segment(), 1..6),
    ) {
        let limits = Limits::default();
        let segs: Vec<Segment> = parts.iter()
            .map(|(s, _)| *s)
            .filter(|s| s.n_steps() <= FULL_CHECK_STEPS && s.validate(&limits).is_ok())
            .collect();
        let run = AxisRun::run(&segs, &limits);
        prop_assert!(run.rejected.is_empty());
        prop_assert_eq!(run.end_tick, segs.iter().map(|s| s.t_ticks as u64).sum::<u64>());
        prop_assert_eq!(run.position, segs.iter().map(|s| s.steps as i64).sum::<i64>());
        prop_assert_eq!(run.fifo.iter().map(|f| f.ticks as u64).sum::<u64>(), run.end_tick);
        prop_assert_eq!(run.edge_ticks.len(), segs.iter().map(|s| s.n_steps() as usize).sum::<usize>());
        prop_assert!(run.max_edge_error_ticks() <= EDGE_ERROR_BOUND_TICKS + 1e-6,
            "cumulative error {} ticks", run.max_edge_error_ticks());
        // The same, exactly in integers, segment by segment against each segment's start.
        let mut start = 0u64;
        let mut k = 0usize;
        for s in &segs {
            for i in 1..=s.n_steps() {
                prop_assert!(edge_within(s, i, (run.edge_ticks[k] - start) as i64, 1));
                k += 1;
            }
            start += s.t_ticks as u64;
        }
    }

    /// Any 32-bit register image: validation never panics, and its verdict is
    /// right by an independent, semantic check.
    #[test]
    fn invalid_segments_rejected_with_the_right_code(
        v0 in prop_oneof![any::<u32>(), 0u32..(1 << 24), Just(0u32)],
        t in prop_oneof![any::<u32>(), 0u32..2000, Just(0u32), (MAX_T_TICKS - 2)..=(MAX_T_TICKS + 2)],
        steps in prop_oneof![any::<i32>(), -3000i32..3000, Just(0i32),
                             (MAX_STEPS as i32 - 1)..=(MAX_STEPS as i32 + 1)],
        m in min_period(),
    ) {
        let seg = Segment::new(v0, t, steps);
        let limits = Limits::new(m).unwrap();
        let verdict = seg.validate(&limits);
        let n = steps.unsigned_abs();
        let v0f = v0 as f64 / 2f64.powi(32);
        match verdict {
            Err(SegmentError::TicksZero) => prop_assert_eq!(t, 0),
            Err(SegmentError::TicksRange) => prop_assert!(t > MAX_T_TICKS),
            Err(SegmentError::StepsRange) => prop_assert!(n > MAX_STEPS && t >= 1 && t <= MAX_T_TICKS),
            Err(SegmentError::RateRange) => prop_assert!(v0 > MAX_V0_RATE && n <= MAX_STEPS),
            Err(SegmentError::Reverses) => {
                // The exact final speed 2n/T − v0 is negative (checked in i128, not f64).
                prop_assert!((2 * n as i128) << 32 < v0 as i128 * t as i128);
            }
            Err(SegmentError::PeriodTooShort) => {
                // Faster than RMAX/2^32 ≈ 1/(M+1) steps/tick at one end.
                let rmax = limits.max_rate() as f64 / 2f64.powi(32);
                let v_end = 2.0 * n as f64 / t as f64 - v0f;
                prop_assert!(v0f.max(v_end) > rmax - 1e-12);
            }
            Ok(()) => {
                prop_assert!(t >= 1 && t <= MAX_T_TICKS && n <= MAX_STEPS && v0 <= MAX_V0_RATE);
                // Valid means the model runs and every period honours the minimum.
                if n <= FULL_CHECK_STEPS {
                    check_segment(&seg, &limits, 1)?;
                }
            }
        }
        if verdict.is_err() {
            // A rejected segment between valid ones disturbs nothing.
            // Peak 2e-4 steps/tick: valid for every minimum period drawn here.
            let good = Segment::new(0, 1_000_000, 100);
            let alone = AxisRun::run(&[good, good], &limits);
            prop_assert!(alone.rejected.is_empty());
            let mixed = AxisRun::run(&[good, seg, good], &limits);
            prop_assert_eq!(&mixed.rejected, &vec![Rejected { index: 1, error: verdict.unwrap_err() }]);
            prop_assert_eq!(&mixed.edge_ticks, &alone.edge_ticks);
            prop_assert_eq!(mixed.position, alone.position);
        }
    }
}

proptest! {
    // 2,000 cases: each checks up to 4,096 edges twice.
    #![proptest_config(ProptestConfig { cases: scaled(2_000), ..config() })]

    /// A deceleration to rest whose v0 = ⌈2n·2^32/T⌉ was rounded up (its end speed is
    /// below zero by less than one rate unit) is accepted and runs as its effective
    /// form (v0 − 1): exactly n steps in T ticks, every edge within the bound of that
    /// form's exact kinematics, every period at least the minimum. One unit more and
    /// it is rejected as reversing.
    #[test]
    fn deceleration_to_rest_with_v0_rounded_up_is_accepted(
        m in min_period(),
        n in log_uniform(1, 1 << 22),
        stretch in 0.0f64..=1.0,
        neg in any::<bool>(),
        seed in any::<u64>(),
    ) {
        let limits = Limits::new(m).unwrap();
        let rmax = limits.max_rate() as u128;
        // The shortest T whose rest-to-rest v0 ≤ RMAX + 1, stretched up to 2^10 times
        // (fewer steps when that T is out of range); then the next T whose 2n·2^32/T
        // is not whole (a whole one needs no rounding).
        let t_min = |n: u64| ((2 * n as u128) << 32).div_ceil(rmax + 1);
        let mut n = n;
        while t_min(n) > MAX_T_TICKS as u128 / 2 {
            n /= 2;
        }
        let mut t = ((t_min(n) as f64 * stretch.mul_add(10.0, 0.0).exp2()) as u128).clamp(t_min(n), MAX_T_TICKS as u128 - 8);
        while ((2 * n as u128) << 32) % t == 0 {
            t += 1;
        }
        let (n, t) = (n.max(1), t as u64);
        let v0 = ((2 * n as u128) << 32).div_ceil(t as u128) as u64;
        let steps = if neg { -(n as i64) } else { n as i64 } as i32;
        let seg = Segment::new(v0 as u32, t as u32, steps);
        prop_assert!(seg.rounds_past_rest(), "{:?}", seg);
        prop_assert_eq!(seg.validate(&limits), Ok(()));
        let eff = seg.effective();
        prop_assert_eq!(eff.v0_rate as u64, v0 - 1);
        prop_assert!(!eff.rounds_past_rest() && eff.v_end_t_q32() >= 0 && eff.v_end_t_q32() < t as i128);
        if n <= FULL_CHECK_STEPS as u64 {
            prop_assert_eq!(SegmentPlan::new(seg).periods().collect::<Vec<_>>(), SegmentPlan::new(eff).periods().collect::<Vec<_>>());
            let run = AxisRun::run(&[seg], &limits);
            prop_assert_eq!(run.edge_ticks.len() as u64, n);
            prop_assert_eq!(run.end_tick, t);
        }
        check_segment(&eff, &limits, seed)?;
        // One rate unit more: reversing by at least T/2^32 steps/tick, rejected.
        let past = Segment::new(v0 as u32 + 1, t as u32, steps);
        prop_assert_eq!(past.validate(&limits), Err(SegmentError::Reverses));
    }
}

/// The user's case: decelerate from 120,000 steps/s to rest over 1,200 steps at
/// 50 MHz (20 ms). v0 rounds to nearest, up, to rate 10,307,922; the segment is
/// accepted (it was rejected with code 2) and emits 1,200 steps in 1,000,000 ticks.
#[test]
fn the_documented_decelerate_to_rest_example_is_accepted() {
    let f = 50_000_000;
    let v0 = units::steps_per_s_to_rate(120_000.0, f).unwrap();
    assert_eq!(v0, 10_307_922);
    let t = units::seconds_to_ticks(0.02, f).unwrap();
    let stop = Segment::new(v0, t, 1200);
    assert!(stop.rounds_past_rest());
    let limits = Limits::new(44).unwrap();
    assert_eq!(stop.validate(&limits), Ok(()));
    let run = AxisRun::run(&[stop], &limits);
    assert!(run.rejected.is_empty());
    assert_eq!((run.edge_ticks.len(), *run.edge_ticks.last().unwrap()), (1200, 1_000_000));
    assert!(run.max_edge_error_ticks() <= EDGE_ERROR_BOUND_TICKS);
}

/// Output timing registers with max(H, D) + max(L, S) ≤ M, each value at least 1.
fn pulse_timing(m: u32) -> impl Strategy<Value = PulseTiming> {
    (1u32..=m - 1, 0.0f64..=1.0, 0.0f64..=1.0, 0.0f64..=1.0).prop_map(move |(hm, xh, xs, xd)| {
        let lm = m - hm;
        // One of each pair is the minimum itself, the other anything up to it.
        let other = |x: f64, top: u32| 1 + (x * (top - 1) as f64) as u32;
        let (step_high, dir_hold) = if xd < 0.5 { (hm, other(xh, hm)) } else { (other(xh, hm), hm) };
        let (step_low, dir_setup) = if xs < 0.5 { (lm, other(xd, lm)) } else { (other(xd, lm), lm) };
        PulseTiming {
            step_high: step_high.min(65_535) as u16,
            step_low: step_low.min(65_535) as u16,
            dir_setup: dir_setup.min(65_535) as u16,
            dir_hold: dir_hold.min(65_535) as u16,
        }
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: scaled(2_000), ..config() })]

    /// Multi-segment moves with reversals and dwells, under any accepted output timing:
    /// every pulse on the pins is at least max(H, D) high and max(L, S) low, DIR changes
    /// at least S before and D after a rising edge, and the rising edges are the model's.
    /// With the default registers the pulse is the half period, max(1, ⌊Δ/2⌋).
    #[test]
    fn pulse_timing_holds_on_the_pins(
        parts in prop::collection::vec(valid_segment(), 1..6),
        (timing, m) in min_period().prop_filter("room for H and L", |&m| m >= 2)
            .prop_flat_map(|m| (pulse_timing(m), Just(m))),
    ) {
        let limits = Limits::new(m).unwrap();
        prop_assert_eq!(timing.check(&limits), Ok(()));
        let segs: Vec<Segment> = parts.iter()
            .map(|(s, _)| *s)
            .filter(|s| s.n_steps() <= FULL_CHECK_STEPS && s.validate(&limits).is_ok())
            .collect();
        let run = AxisRun::run(&segs, &limits);
        let pins = pulse::pins(&run.fifo, &timing);
        prop_assert_eq!(&pins.rises, &run.edge_ticks);
        let (high, low, setup, hold) = pulse::measure(&pins);
        prop_assert!(high >= timing.step_high as u64 && high >= timing.dir_hold as u64, "high {high}, {timing:?}");
        prop_assert!(low >= timing.step_low as u64 && low >= timing.dir_setup as u64, "low {low}, {timing:?}");
        prop_assert!(setup >= timing.dir_setup as u64, "DIR setup {setup}, {timing:?}");
        prop_assert!(hold >= timing.dir_hold as u64, "DIR hold {hold}, {timing:?}");
        // Every reversal is on the pins, in order.
        let mut dir = false;
        let mut changes = Vec::new();
        for (k, e) in run.fifo.iter().filter(|e| e.step).enumerate() {
            if e.reverse != dir {
                changes.push((k, e.reverse));
                dir = e.reverse;
            }
        }
        prop_assert_eq!(changes.len(), pins.dir_changes.len());
        for ((k, rev), (t, level)) in changes.iter().zip(&pins.dir_changes) {
            prop_assert_eq!(rev, level);
            prop_assert!(*t < pins.rises[*k] && (*k == 0 || *t > pins.rises[*k - 1]), "DIR change at {t} not before step {k}");
        }
        // The default registers: half the following period (of the last one at the end).
        let half = pulse::pins(&run.fifo, &PulseTiming::default());
        let steps: Vec<usize> = (0..run.fifo.len()).filter(|&k| run.fifo[k].step).collect();
        for (i, &k) in steps.iter().enumerate() {
            let next = run.fifo.get(k + 1).map_or(run.fifo[k].ticks, |e| e.ticks);
            prop_assert_eq!(half.falls[i] - half.rises[i], ((next / 2).max(1)).min(MAX_PULSE_TICKS) as u64);
        }
    }
}

/// The check the core applies before CTRL.ENABLE: values of 0 and a sum over M refused.
#[test]
fn pulse_timing_check_refuses_zero_and_a_sum_over_the_minimum_period() {
    let limits = Limits::new(44).unwrap();
    let t = |h, l, s, d| PulseTiming { step_high: h, step_low: l, dir_setup: s, dir_hold: d };
    assert_eq!(t(1, 1, 1, 1).check(&limits), Ok(()));
    assert_eq!(t(22, 22, 1, 1).check(&limits), Ok(()));
    assert_eq!(t(10, 10, 22, 22).check(&limits), Ok(()));
    assert!(t(23, 22, 1, 1).check(&limits).is_err());
    assert!(t(10, 10, 22, 23).check(&limits).is_err());
    assert!(t(0, 1, 1, 1).check(&limits).is_err());
    assert!(t(1, 1, 0, 1).check(&limits).is_err());
    // h(Δ) at the boundaries: the low minimum wins over the half, the high minimum over both.
    let h = t(5, 30, 1, 1);
    assert_eq!(h.high_ticks(44), 14);
    assert_eq!(h.high_ticks(100), 50);
    assert_eq!(h.high_ticks(20), 5);
    assert_eq!(PulseTiming::default().high_ticks(1), 1);
    assert_eq!(PulseTiming::default().high_ticks(u32::MAX), 65_535);
}

proptest! {
    #![proptest_config(ProptestConfig { cases: scaled(2_000), ..config() })]

    /// The distance/speed/acceleration planner: the steps sum to the request, every
    /// segment is one the core accepts, the phases are the documented roundings of
    /// the exact profile (within one tick, and a triangle exactly when the distance
    /// is too short to reach the speed), the speed never exceeds the request by
    /// more than the tick and step rounding, and the axis ends at rest within the
    /// step rounding.
    #[test]
    fn moves_by_speed_and_acceleration_plan_exactly(
        steps in log_uniform(1, 200_000),
        neg in any::<bool>(),
        speed in log_uniform(10, 2_000_000),
        accel in log_uniform(100, 1_000_000_000),
        decel in log_uniform(100, 1_000_000_000),
        m in min_period(),
    ) {
        use tdm_stepper::model::planner::trapezoid_by_rates;
        let f = 50_000_000u32;
        let limits = Limits::new(m).unwrap();
        let signed = if neg { -(steps as i64) } else { steps as i64 };
        let Ok(segs) = trapezoid_by_rates(signed, speed as u32, accel as u32, decel as u32, f, &limits) else {
            return Ok(());
        };
        prop_assert_eq!(segs.iter().map(|s| s.steps as i64).sum::<i64>(), signed);
        for s in &segs {
            prop_assert!(s.validate(&limits).is_ok(), "{:?}", s);
        }
        if steps == 1 {
            prop_assert_eq!(segs.len(), 1, "one step is one segment");
            return Ok(());
        }
        // The phases are the exact profile's, rounded, for the requested rates or
        // (when a phase would get no step) both at the smaller one.
        let (v, n) = (speed as f64, steps as f64);
        let phases = |a: f64, d: f64| -> (bool, f64, f64) {
            let reaches = v * v * (a + d) <= 2.0 * n * a * d;
            let vp = if reaches { v } else { (2.0 * n * a * d / (a + d)).sqrt() };
            (reaches, vp / a * f as f64, vp / d * f as f64)
        };
        let first = segs[0].t_ticks as f64;
        let last = segs.last().unwrap().t_ticks as f64;
        let lo = accel.min(decel) as f64;
        let fits = |(_, ta, td): (bool, f64, f64)| (first - ta).abs() <= 1.0 && (last - td).abs() <= 1.0;
        let asked = phases(accel as f64, decel as f64);
        prop_assert!(fits(asked) || fits(phases(lo, lo)), "T_acc {} and T_dec {} against {:?}", first, last, asked);
        prop_assert!(asked.0 || segs.len() <= 2, "a triangle has no cruise: {:?}", segs);
        // Peak speed: the largest segment start rate, against the request: with at
        // least 100 steps in every phase, within 5 % (the step split's rounding).
        let big = segs.iter().all(|s| s.n_steps() >= 100);
        let peak = segs.iter().map(|s| s.v0_rate as f64 * f as f64 / 2f64.powi(32)).fold(0.0, f64::max);
        prop_assert!(!big || peak <= 1.05 * v + 1.0, "peak {} steps/s for a speed of {}", peak, v);
        let end = segs.last().unwrap();
        // At rest at the end, to the step split's rounding: each phase's steps are its
        // exact share ± 1, so with at least 100 steps in every phase the end speed is
        // under 5 % of the speed asked for (the README's planner paragraph).
        if big {
            let end_sps = end.v_end_t_q32() as f64 / end.t_ticks as f64 / 2f64.powi(32) * f as f64;
            prop_assert!(end_sps <= 0.05 * v, "ends at {} steps/s for a speed of {}: {:?}", end_sps, v, segs);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: scaled(2_000), ..config() })]

    /// The controlled stop's segment (model::stop), from any last period Δ the core can
    /// emit (the minimum period up to the rest threshold) and any accepted deceleration:
    /// it passes validation as it is (no v0 − 1 adjustment), fits one segment's range,
    /// starts no faster than 1/(Δ + 1), ends at rest within one rate unit without
    /// reversing, decelerates at most a·(1 + 2^-8) and covers at least v²/(2a) with it,
    /// and its edges keep the 0.625-tick bound.
    #[test]
    fn the_stop_segment_is_valid_and_ends_at_rest(
        m in min_period(),
        dx in 0.0f64..=1.0,
        ax in 0.0f64..=1.0,
        rev in any::<bool>(),
        seed in any::<u64>(),
    ) {
        use tdm_stepper::model::stop::*;
        let limits = Limits::new(m).unwrap();
        let lg = |lo: u64, hi: u64, x: f64| (((lo as f64).ln() + x * ((hi as f64).ln() - (lo as f64).ln())).exp().round() as u64).clamp(lo, hi);
        let delta = lg(m as u64, STOP_REST_PERIOD as u64 - 1, dx) as u32;
        let a_min = stop_decel_min(&limits);
        let decel = lg(a_min as u64, u32::MAX as u64, ax) as u32;
        let seg = stop_segment(delta, decel, rev).unwrap();
        prop_assert_eq!(seg.validate(&limits), Ok(()), "{:?} from {} at {}", seg, delta, decel);
        prop_assert_eq!(seg.effective(), seg);
        prop_assert!(seg.n_steps() >= 1 && seg.n_steps() <= MAX_STEPS && seg.t_ticks <= MAX_T_TICKS);
        prop_assert_eq!(seg.reverse(), rev);
        prop_assert!((seg.v0_rate as u64) * (delta as u64 + 1) <= 1 << 32);
        let v_end_t = seg.v_end_t_q32();
        prop_assert!(v_end_t >= 0 && v_end_t < seg.t_ticks as i128);
        // |α| = (v0 − v_end)/T in steps/tick², against a = DECEL/2^57.
        let (v0, t) = (seg.v0_rate as f64 / 2f64.powi(32), seg.t_ticks as f64);
        let v_end = v_end_t as f64 / 2f64.powi(32) / t;
        let a = decel as f64 / 2f64.powi(57);
        prop_assert!((v0 - v_end) / t <= a * (1.0 + 2f64.powi(-8)));
        prop_assert!(seg.n_steps() as f64 >= v0 * v0 / (2.0 * a) * (1.0 - 1e-12));
        check_segment(&seg, &limits, seed)?;
        // At rest: a dwell's 0 or a period at the threshold forms nothing.
        prop_assert_eq!(stop_segment(0, decel, rev), None);
        prop_assert_eq!(stop_segment(STOP_REST_PERIOD, decel, rev), None);
    }
}

/// The deceleration register's unit: 1 step/s² at 50 MHz is 2^57 / 2.5·10^15 ≈ 57.6;
/// its minimum for a 2-tick minimum period is the n bound, for 50 ticks the T bound.
#[test]
fn the_stop_deceleration_unit_and_minimum() {
    use tdm_stepper::model::stop::*;
    assert_eq!(decel_from_steps_per_s2(1.0, 50e6), Some(58));
    assert_eq!(decel_from_steps_per_s2(0.001, 50e6), None);
    let l2 = Limits::new(2).unwrap();
    let r2 = l2.max_rate() as u128;
    assert_eq!(stop_decel_min(&l2) as u128, (r2 * r2).div_ceil(256 * ((1 << 24) - 1)));
    let l50 = Limits::new(50).unwrap();
    assert_eq!(stop_decel_min(&l50), l50.max_rate().div_ceil(31));
    // At the minimum, the stop from the top rate fits: from a 2-tick period ...
    let s = stop_segment(2, stop_decel_min(&l2), false).unwrap();
    assert_eq!(s.validate(&l2), Ok(()));
    assert!(s.n_steps() > MAX_STEPS / 2, "{s:?}");
    // ... and from a 50-tick one, the T bound nearly reached.
    let s = stop_segment(50, stop_decel_min(&l50), true).unwrap();
    assert_eq!(s.validate(&l50), Ok(()));
    assert!(s.t_ticks > MAX_T_TICKS / 2 && s.steps < 0, "{s:?}");
}

// ---------------------------------------------------------------------------------
// Polynomial (S-curve) segments: model::poly.

/// A polynomial segment in the range: its speed's Bernstein control points (Q0.32
/// rates) each at 0, at RMAX, tiny, just under RMAX or anywhere between; n and A'
/// rounded from them. Shapes: a cubic through the ends (a jerk-limited phase), a
/// quartic starting with zero acceleration (from rest when b0 = 0), a near-uniform
/// cubic (tiny jerk), a general quartic. Filtered to the valid ones.
fn poly_segment(valid: bool) -> impl Strategy<Value = (PolySegment, Limits)> {
    let point = (0u8..5, 0.0f64..=1.0);
    (
        min_period(),
        log_uniform(1, POLY_MAX_T_TICKS as u64),
        [point.clone(), point.clone(), point.clone(), point],
        0u8..4,
        -2i64..=2,
        any::<bool>(),
    )
        .prop_filter_map("outside the range", move |(m, t, cps, shape, nudge, neg)| {
            let limits = Limits::new(m).unwrap();
            let rmax = limits.max_rate() as f64;
            let b: Vec<f64> = cps
                .iter()
                .map(|&(k, x)| match k {
                    0 => 0.0,
                    1 => rmax,
                    2 => (x * 1000.0).round(),
                    3 => (rmax * (1.0 - x * 1e-3)).floor(),
                    _ => (x * rmax).round(),
                })
                .collect();
            let tf = t as f64;
            let n = (tf * b.iter().sum::<f64>() / 4.0 / 2f64.powi(32)).round() as i64;
            let (v0, v1) = (b[0] as u32, b[3] as u32);
            let sign = |n: i64| if neg { -n } else { n } as i32;
            let seg = match shape {
                0 => PolySegment::cubic(v0, v1, t as u32, sign(n))?,
                1 => PolySegment::new(v0, v1, 0, t as u32, sign(n)),
                2 => {
                    let n = (v0 as i64 * t as i64 + (1 << 31)) >> 32;
                    PolySegment::cubic(v0, v0, t as u32, sign((n + nudge).max(0)))?
                }
                _ => PolySegment::new(v0, v1, (1.5 * (b[1] - b[0]) * tf).round() as i64, t as u32, sign(n)),
            };
            (seg.validate(&limits).is_ok() == valid).then_some((seg, limits))
        })
}

/// Checks a valid polynomial segment: every edge (or windows of 48 beyond
/// FULL_CHECK_STEPS) equal to its definition, within ½ tick of exact time exactly in
/// integers and in f64, every period at least the minimum, the edges summing to T,
/// and the search's words within POLY_WORD_BITS.
fn check_poly(seg: &PolySegment, limits: &Limits, seed: u64) -> Result<u32, TestCaseError> {
    prop_assert_eq!(seg.validate(limits), Ok(()));
    let plan = PolyPlan::new(*seg);
    let n = seg.n_steps();
    let check = |i: u32, e: u32, prev: u32, by_definition: bool| -> Result<(), TestCaseError> {
        prop_assert!(seg.edge_within(i, e as i64, 4), "step {i}: edge {e} not within ½ tick, {seg:?}");
        let err = (e as f64 - seg.step_time_near(i, e)).abs();
        prop_assert!(err <= POLY_EDGE_ERROR_BOUND_TICKS + 1e-5, "step {i}: error {err}");
        prop_assert!(
            e - prev >= limits.min_period_ticks,
            "step {i}: period {} < {}",
            e - prev,
            limits.min_period_ticks
        );
        if by_definition {
            prop_assert_eq!(e, seg.edge_by_definition(i), "step {}", i);
        }
        Ok(())
    };
    let mut widest = 0;
    if n <= FULL_CHECK_STEPS {
        let mut s = plan.search();
        // The core's galloping search, from its setup's state at base 1 and the
        // last period's digit (every ninth step from a digit off by up to 3 either
        // way): the same edges, and the same state after each.
        let mut g = if n >= 2 { plan.setup_state() } else { plan.search() };
        let (mut prev, mut delta, mut x) = (0, 0, seed | 1);
        for i in 1..=n {
            let e = s.next_edge().unwrap();
            check(i, e, prev, n <= 256 || i % 61 == 0)?;
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let b = gallop_start(delta) as i64 + if i % 9 == 0 { (x % 7) as i64 - 3 } else { 0 };
            let (ge, _) = g.next_edge_galloping(b.clamp(0, POLY_TOP_DIGIT as i64) as u32).unwrap();
            prop_assert_eq!(ge, e, "galloping search, step {}", i);
            prop_assert_eq!((g.rem, g.taylor), (s.rem, s.taylor), "galloping search's state, step {}", i);
            delta = e - prev;
            prev = e;
        }
        prop_assert_eq!(s.next_edge(), None);
        prop_assert_eq!(g.next_edge_galloping(0), None);
        prop_assert_eq!(prev, if n == 0 { 0 } else { seg.t_ticks });
        widest = s.widest_bits.max(g.widest_bits);
    } else {
        let mut x = seed | 1;
        let mut starts = vec![0, n - 48];
        for _ in 0..3 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            starts.push((x % (n as u64 - 48)) as u32);
        }
        for start in starts {
            let mut prev = if start == 0 { 0 } else { seg.edge_by_definition(start) };
            let mut s = plan.search_after(start, prev);
            let mut g = plan.search_after(start, prev);
            let before = if start <= 1 { 0 } else { seg.edge_by_definition(start - 1) };
            let mut delta = if start == 0 { 0 } else { prev - before };
            for i in start + 1..=start + 48 {
                let e = s.next_edge().unwrap();
                check(i, e, prev, true)?;
                let (ge, _) = g.next_edge_galloping(gallop_start(delta)).unwrap();
                prop_assert_eq!(ge, e, "galloping search, step {}", i);
                delta = e - prev;
                prev = e;
            }
            widest = widest.max(s.widest_bits).max(g.widest_bits);
        }
    }
    prop_assert!(widest <= POLY_WORD_BITS, "search word of {widest} bits");
    for (k, (c, bits)) in seg.n_coefficients().into_iter().zip(POLY_COEFF_BITS).enumerate() {
        prop_assert!(signed_bits(c) <= bits, "c{} = {} wider than {} bits, {:?}", k + 1, c, bits, seg);
    }
    Ok(widest)
}

/// The extreme speeds of a polynomial segment in f64 (steps/tick): the ends and the
/// interior zeros of the acceleration (a quadratic in t).
fn poly_speed_range(seg: &PolySegment) -> (f64, f64) {
    let t = seg.t_ticks as f64;
    let mut ts = vec![0.0, t];
    // a(t) = a0 + a1·t + a2·t²: from three samples.
    let (a0, a_mid, a1) = (seg.derivatives_at(0.0).1, seg.derivatives_at(t / 2.0).1, seg.derivatives_at(t).1);
    let c2 = 2.0 * (a0 - 2.0 * a_mid + a1) / (t * t);
    let c1 = (a1 - a0) / t - c2 * t;
    // Roots of c2·t² + c1·t + a0 in the cancellation-free form.
    let disc = c1 * c1 - 4.0 * c2 * a0;
    if disc >= 0.0 {
        let q = -0.5 * (c1 + c1.signum() * disc.sqrt());
        if q != 0.0 {
            ts.push(a0 / q);
        }
        if c2 != 0.0 {
            ts.push(q / c2);
        }
    }
    ts.iter()
        .filter(|&&x| (0.0..=t).contains(&x))
        .map(|&x| seg.derivatives_at(x).0)
        .fold((f64::MAX, f64::MIN), |(lo, hi), v| (lo.min(v), hi.max(v)))
}

proptest! {
    #![proptest_config(config())]

    /// Every edge of a valid polynomial segment is the nearest tick to exact time.
    #[test]
    fn poly_edges_are_the_nearest_tick_over_the_range((seg, limits) in poly_segment(true), seed in any::<u64>()) {
        check_poly(&seg, &limits, seed)?;
    }

    /// Validation is sound (an accepted segment's speed stays within [0, RMAX]
    /// everywhere) and gives away at most T²·|jerk|max/18 (a rejected one comes that
    /// close to a limit), and any register image gets a verdict without a panic.
    #[test]
    fn poly_validation_is_sound_and_gives_away_at_most_the_bound(
        (seg, limits) in prop_oneof![poly_segment(true), poly_segment(false)],
        raw in (any::<u32>(), any::<u32>(), any::<i64>(), prop_oneof![any::<u32>(), 0u32..=POLY_MAX_T_TICKS + 2], any::<i32>()),
    ) {
        let rmax = limits.max_rate() as f64 / 2f64.powi(32);
        let _ = PolySegment::new(raw.0, raw.1, raw.2, raw.3, raw.4).validate(&limits);
        let (lo, hi) = poly_speed_range(&seg);
        let t = seg.t_ticks as f64;
        let jerk = seg.derivatives_at(0.0).2.abs().max(seg.derivatives_at(t).2.abs());
        let give = t * t * jerk / 18.0 + 1e-12 + 4.0 * f64::EPSILON * rmax;
        match seg.validate(&limits) {
            Ok(()) => prop_assert!(lo >= -give * 1e-6 - 1e-12 && hi <= rmax + 1e-12, "{seg:?}: speed in [{lo}, {hi}], RMAX {rmax}"),
            Err(SegmentError::Reverses) => prop_assert!(lo < give, "{seg:?}: min speed {lo}, bound {give}"),
            Err(SegmentError::PeriodTooShort) => prop_assert!(hi > rmax - give, "{seg:?}: max speed {hi}, bound {give}"),
            Err(e) => prop_assert!(false, "unexpected {e:?} for {seg:?}"),
        }
    }

}

proptest! {
    // 100 cases: each runs up to seven segments of up to 4,096 steps twice and takes
    // the exact error of every edge (about 1 s a case; 1,000 took 15 minutes).
    #![proptest_config(ProptestConfig { cases: scaled(100), ..config() })]

    /// Trapezoid and polynomial segments mixed on one axis: edges measured from the
    /// move start, cumulatively, never drift; a rejected segment between them changes
    /// nothing.
    #[test]
    fn mixed_trapezoid_and_poly_moves_do_not_drift(
        parts in prop::collection::vec(prop_oneof![
            valid_segment().prop_map(|(s, _)| Motion::Trapezoid(s)),
            poly_segment(true).prop_map(|(p, _)| Motion::Poly(p)),
        ], 1..7),
        bad in poly_segment(false),
        at in any::<prop::sample::Index>(),
    ) {
        let limits = Limits::default();
        let moves: Vec<Motion> = parts.into_iter()
            .filter(|m| m.n_steps() <= FULL_CHECK_STEPS && m.validate(&limits).is_ok())
            .collect();
        let run = AxisRun::run_motions(&moves, &limits);
        prop_assert!(run.rejected.is_empty());
        prop_assert_eq!(&run.motions, &moves.iter().map(|m| match m {
            Motion::Trapezoid(s) => Motion::Trapezoid(s.effective()),
            p => *p,
        }).collect::<Vec<_>>());
        prop_assert_eq!(run.end_tick, moves.iter().map(|m| m.t_ticks() as u64).sum::<u64>());
        prop_assert_eq!(run.position, moves.iter().map(|m| m.steps() as i64).sum::<i64>());
        prop_assert_eq!(run.fifo.iter().map(|f| f.ticks as u64).sum::<u64>(), run.end_tick);
        prop_assert!(run.max_edge_error_ticks() <= EDGE_ERROR_BOUND_TICKS + 1e-6,
            "cumulative error {} ticks", run.max_edge_error_ticks());
        let mut with_bad = moves.clone();
        with_bad.insert(at.index(moves.len() + 1), Motion::Poly(bad.0));
        let mixed = AxisRun::run_motions(&with_bad, &limits);
        if bad.0.validate(&limits).is_err() {
            prop_assert_eq!(mixed.rejected.len(), 1);
            prop_assert_eq!(&mixed.edge_ticks, &run.edge_ticks);
            prop_assert_eq!(mixed.position, run.position);
        }
    }
}

// ---------------------------------------------------------------------------------
// S-curve planner: model::scurve.

/// Random S-curve limits at a clock: (clock, min period, steps, v_start, v_end, v_max,
/// a, j, d, jd, snap), each in a range a machine uses.
fn scurve_inputs() -> impl Strategy<Value = (u32, u32, i64, f64, f64, f64, f64, f64, f64, f64, f64)> {
    (
        prop_oneof![Just(10_000_000u32), Just(50_000_000), Just(100_000_000)],
        min_period(),
        log_uniform(1, 40_000),
        any::<bool>(),
        (0.0f64..=1.0, 0.0f64..=1.0, 0.0f64..=1.0),
        (0.0f64..=1.0, 0.0f64..=1.0, 0.0f64..=1.0, 0.0f64..=1.0, 0.0f64..=1.0, 0.0f64..=1.0),
        0u8..4,
    )
        .prop_map(|(f, m, n, neg, (xv, xs, xe), (xa, xj, xd, xjd, xsn, _), ends)| {
            let rmax = Limits::new(m).unwrap().max_rate() as f64 / 2f64.powi(32) * f as f64;
            // The planner's documented domain: v_max ≤ 0.95·RMAX, and every speed
            // change spanning at least 4 steps (a, d ≤ v_max²/8).
            let v_max = (100f64.ln() + xv * (0.95 * rmax / 100.0).ln()).exp();
            let lu = |x: f64, lo: f64, hi: f64| (lo.ln() + x * (hi / lo).ln()).exp();
            // Reach the top speed in 0.1 ms .. 1 s; the jerk phases 2% .. 100% of that.
            let a_top = (v_max / 1e-4).min(v_max * v_max / 8.0).max(v_max);
            let a = lu(xa, v_max / 1.0, a_top);
            let d = lu(xd, v_max / 1.0, a_top);
            let j = lu(xj, a / (v_max / a), a / (0.02 * v_max / a));
            let jd = lu(xjd, d / (v_max / d), d / (0.02 * v_max / d));
            let snap = lu(xsn, j / (a / j), j / (0.02 * a / j));
            let (vs, ve) = match ends {
                0 => (0.0, 0.0),
                1 => (xs * v_max, 0.0),
                2 => (0.0, xe * v_max),
                _ => (xs * v_max, xe * v_max),
            };
            let steps = if neg { -(n as i64) } else { n as i64 };
            (f, m, steps, vs, ve, v_max, a, j, d, jd, snap)
        })
}

/// Checks a planned S-curve move: every segment valid, steps and ticks summing to the
/// move, each boundary on the exact profile (position within ½ step, speed within a
/// few rate units; the rest-end correction may lower a speed further, never raise
/// it), the end speed exact, and the edges within the bounds when run.
fn check_scurve(
    moves: &[Motion],
    prof: &scurve::Profile,
    steps: i64,
    v_end: f64,
    f: u32,
    limits: &Limits,
) -> Result<(), TestCaseError> {
    let n = steps.unsigned_abs() as i64;
    prop_assert_eq!(moves.iter().map(|m| m.steps() as i64).sum::<i64>(), steps);
    let total: u64 = moves.iter().map(|m| m.t_ticks() as u64).sum();
    prop_assert!((total as f64 - prof.duration() * f as f64).abs() <= 0.5 + 1e-6 * total as f64);
    let one = 2f64.powi(32);
    let (mut tick, mut pos) = (0u64, 0i64);
    let mut worst_rate = 0.0f64;
    for (k, m) in moves.iter().enumerate() {
        prop_assert_eq!(m.validate(limits), Ok(()), "segment {}", k);
        // The boundary is where the profile reaches a whole step, rounded to a tick.
        let ff = f as f64;
        let [x, v, a, _] = prof.state_at(tick as f64 / ff);
        prop_assert!((pos as f64 - x).abs() <= 0.5 + 1e-6 * n as f64, "boundary {k}: position {pos}, exact {x}");
        let v0 = m.v0_rate();
        let exact = v / ff * one;
        let slack = 0.5 * a.abs() / ff / ff * one + 1.0 + 1e-9 * exact;
        // Pieces of a few steps follow the profile only as closely as whole steps allow.
        let few = m.n_steps() < 20 || (k > 0 && moves[k - 1].n_steps() < 20);
        if !few {
            worst_rate = worst_rate.max(((v0 as f64 - exact).abs() - slack).max(0.0));
        }
        tick += m.t_ticks() as u64;
        pos += m.n_steps() as i64;
    }
    prop_assert_eq!(pos, n);
    // A repaired boundary's speed may move (never past RMAX): within 5% of v_max
    // between pieces of 20 steps or more.
    let v_max_rate = prof.starts.iter().map(|s| s[2]).fold(0.0, f64::max) / f as f64 * one;
    prop_assert!(
        worst_rate <= 0.05 * v_max_rate + 2.0,
        "a boundary speed {worst_rate} rate units off the profile (v_max {v_max_rate})"
    );
    if let Some(Motion::Poly(p)) = moves.last() {
        prop_assert_eq!(p.v1_rate, (v_end / f as f64 * one).round() as u32);
    }
    let run = AxisRun::run_motions(moves, limits);
    prop_assert!(run.rejected.is_empty());
    prop_assert_eq!(run.edge_ticks.len() as i64, n);
    prop_assert!(
        run.max_edge_error_ticks() <= EDGE_ERROR_BOUND_TICKS + 1e-6,
        "edge error {}",
        run.max_edge_error_ticks()
    );
    Ok(())
}

/// A move needs more than 128 segments only when its phases, split into parts of at
/// most 2^23 ticks, are more than 128 (each part at most one segment).
fn too_long_for_128(prof: &scurve::Profile, f: u32) -> bool {
    let parts: f64 = prof.phases.iter().map(|p| (p.dur * f as f64 / (1u64 << 23) as f64).ceil().max(1.0)).sum();
    parts > scurve::MAX_SCURVE_SEGMENTS as f64
}

/// The longest time between two consecutive whole steps of the exact profile (from
/// its start, to its end), ticks.
fn longest_gap_ticks(prof: &scurve::Profile, n: u64, f: u32) -> f64 {
    let total = prof.duration();
    let time_of = |x: f64| {
        let (mut lo, mut hi) = (0.0, total);
        for _ in 0..100 {
            let mid = (lo + hi) / 2.0;
            if prof.state_at(mid)[0] < x {
                lo = mid
            } else {
                hi = mid
            }
        }
        hi
    };
    let mut prev = 0.0;
    let mut gap = 0.0f64;
    for i in 1..=n {
        let t = if i == n { total } else { time_of(i as f64) };
        gap = gap.max(t - prev);
        prev = t;
    }
    gap * f as f64
}

proptest! {
    // 300 cases: each runs a whole move through the models.
    #![proptest_config(ProptestConfig { cases: scaled(300), ..config() })]

    /// Jerk-limited moves over the range: planned, or refused only when the move is
    /// shorter than its speed change needs.
    #[test]
    fn jerk_limited_moves_plan_exactly((f, m, steps, vs, ve, v_max, a, j, d, jd, _snap) in scurve_inputs()) {
        let limits = Limits::new(m).unwrap();
        let up = scurve::SideLimits { accel: a, jerk: j, snap: None };
        let down = scurve::SideLimits { accel: d, jerk: jd, snap: None };
        let n = steps.unsigned_abs() as f64;
        match scurve::jerk_limited(steps, vs, ve, v_max, a, j, d, jd, f, &limits) {
            Ok(moves) => {
                let prof = scurve::profile(n, vs, ve, v_max, up, down).unwrap();
                check_scurve(&moves, &prof, steps, ve, f, &limits)?;
            }
            Err(scurve::ScurveError::TooShort(need)) => prop_assert!(need > n),
            Err(scurve::ScurveError::TooSlow) => {
                let prof = scurve::profile(n, vs, ve, v_max, up, down).unwrap();
                let gap = longest_gap_ticks(&prof, steps.unsigned_abs(), f);
                prop_assert!(gap > (1u64 << 22) as f64, "TooSlow, but the longest stretch without a step is {gap} ticks");
            }
            Err(scurve::ScurveError::TooManySegments) => {
                let prof = scurve::profile(n, vs, ve, v_max, up, down).unwrap();
                prop_assert!(too_long_for_128(&prof, f), "TooManySegments for a move of {} s", prof.duration());
            }
            Err(e) => prop_assert!(false, "{e}"),
        }
    }

    /// Fourth-order moves (rest to rest) over the range.
    #[test]
    fn fourth_order_moves_plan_exactly((f, m, steps, _vs, _ve, v_max, a, j, _d, _jd, snap) in scurve_inputs()) {
        let limits = Limits::new(m).unwrap();
        let side = scurve::SideLimits { accel: a, jerk: j, snap: Some(snap) };
        let n = steps.unsigned_abs() as f64;
        let prof = scurve::profile(n, 0.0, 0.0, v_max, side, side).unwrap();
        match scurve::fourth_order(steps, v_max, a, j, snap, f, &limits) {
            Ok(moves) => check_scurve(&moves, &prof, steps, 0.0, f, &limits)?,
            Err(scurve::ScurveError::TooSlow) => {
                let gap = longest_gap_ticks(&prof, steps.unsigned_abs(), f);
                prop_assert!(gap > (1u64 << 22) as f64, "TooSlow, but the longest stretch without a step is {gap} ticks");
            }
            Err(scurve::ScurveError::TooManySegments) => {
                prop_assert!(too_long_for_128(&prof, f), "TooManySegments for a move of {} s", prof.duration());
            }
            Err(e) => prop_assert!(false, "{e}"),
        }
    }
}

// The model's example tests (one module per model file): they live here rather than
// in the library, so that the test build compiles the library once (a `#[cfg(test)]`
// library is a second whole build of it, about as long as the first).

mod scurve_examples {
    use tdm_stepper::model::scurve::*;
    use tdm_stepper::model::axis::Motion;
    use tdm_stepper::model::segment::Limits;
    use tdm_stepper::model::AxisRun;

    #[test]
    fn a_jerk_limited_move_has_seven_phases_and_sums_exactly() {
        let l = Limits::new(44).unwrap();
        let f = 50_000_000;
        let segs =
            jerk_limited(20_000, 0.0, 0.0, 60_000.0, 400_000.0, 8_000_000.0, 400_000.0, 8_000_000.0, f, &l).unwrap();
        assert_eq!(segs.iter().map(|m| m.steps() as i64).sum::<i64>(), 20_000);
        let run = AxisRun::run_motions(&segs, &l);
        assert!(run.rejected.is_empty(), "{:?}", run.rejected);
        assert_eq!(run.edge_ticks.len(), 20_000);
        assert!(run.max_edge_error_ticks() <= 0.5 + 1e-6, "{}", run.max_edge_error_ticks());
        // Seven phases: jerk, hold, jerk, cruise, jerk, hold, jerk.
        assert_eq!(segs.len(), 7);
        assert!(segs.iter().all(|m| matches!(m, Motion::Poly(p) if p.degree() <= 3)));
    }

    #[test]
    fn a_fourth_order_move_sums_exactly() {
        let l = Limits::new(44).unwrap();
        let segs = fourth_order(-12_345, 50_000.0, 500_000.0, 2.0e7, 2.0e9, 50_000_000, &l).unwrap();
        assert_eq!(segs.iter().map(|m| m.steps() as i64).sum::<i64>(), -12_345);
        assert!(segs.iter().any(|m| matches!(m, Motion::Poly(p) if p.degree() == 4)));
        let run = AxisRun::run_motions(&segs, &l);
        assert!(run.rejected.is_empty());
        assert_eq!(run.position, -12_345);
    }
}

mod encoder_examples {
    use tdm_stepper::model::encoder::*;

    fn run(cfg: &EncConfig, pins: &[EncPins]) -> EncoderModel {
        let mut m = EncoderModel::new();
        for _ in 0..3 {
            m.clock(cfg, pins[0], false, false, true, true);
        }
        for &p in pins {
            m.clock(cfg, p, false, false, true, false);
        }
        m
    }

    #[test]
    fn counts_a_quadrature_walk_both_ways_and_its_period() {
        for spacing in [1u64, 2, 5] {
            let mut g = QuadratureGen::new(4000, spacing);
            let mut pins = vec![QuadratureGen::lines(0, 4000)];
            for t in 0..3000 {
                pins.push(g.tick(if t < 1500 { 250 } else { -37 }));
            }
            pins.extend(std::iter::repeat(pins[pins.len() - 1]).take(5));
            let m = run(&EncConfig::default(), &pins);
            assert_eq!(m.outputs().count as i32, -37, "spacing {spacing}");
            assert_eq!(m.outputs().illegal, 0);
            assert_eq!(m.outputs().period as u64, spacing, "the last period is the spacing");
            assert!(!m.outputs().last_dir);
            let inv = run(&EncConfig { invert: true, ..Default::default() }, &pins);
            assert_eq!(inv.outputs().count as i32, 37);
        }
    }

    #[test]
    fn both_lines_at_once_is_illegal_and_not_counted() {
        let p = |a, b| EncPins { a, b, z: false };
        let pins = [p(false, false), p(false, false), p(true, true), p(true, true), p(true, true), p(false, true), p(false, true), p(false, true)];
        let m = run(&EncConfig::default(), &pins);
        assert_eq!(m.outputs().illegal, 1);
        // 11 → 01 is one count up.
        assert_eq!(m.outputs().count, 1);
    }

    #[test]
    fn the_filter_ignores_bounce_shorter_than_it() {
        let cfg = EncConfig { filter: 3, ..Default::default() };
        let p = |a| EncPins { a, b: false, z: false };
        let mut pins = vec![p(false); 4];
        pins.extend([p(true), p(true), p(true), p(false), p(true), p(false)]);
        pins.extend(vec![p(false); 6]);
        assert_eq!(run(&cfg, &pins).outputs().count, 0, "3-tick bounce under a 3-tick filter");
        pins.extend(vec![p(true); 4]);
        pins.extend(vec![p(true); 3]);
        assert_eq!(run(&cfg, &pins).outputs().count, 1, "held 4 ticks");
    }

    #[test]
    fn the_index_latches_and_the_armed_clear_counts_from_it() {
        let cfg = EncConfig { gate: true, gate_ab: 0, ..Default::default() };
        let mut g = QuadratureGen::new(16, 2);
        let mut m = EncoderModel::new();
        for _ in 0..3 {
            m.clock(&cfg, g.tick(0), false, false, true, true);
        }
        m.clock(&cfg, g.tick(0), true, false, true, false);
        assert!(m.outputs().armed);
        let mut tog = m.outputs().index_tog;
        let mut seen = vec![];
        for _ in 0..200 {
            m.clock(&cfg, g.tick(40), false, false, true, false);
            if m.outputs().index_tog != tog {
                tog = m.outputs().index_tog;
                seen.push((m.outputs().index_count, m.outputs().count, m.outputs().armed));
            }
        }
        // Z was high from reset at 0 (no edge); the indexes at 16 (armed: the count
        // restarts there, a tick later) and 32 (16 counts later).
        assert_eq!(seen, vec![(16, 16, false), (16, 16, false)]);
        assert_eq!(m.outputs().count, 40 - 16);
    }

    /// The narrow decoders and the shared extension give, at every visit, the full
    /// model's 32-bit count and latches: random walks at up to a count per tick, far
    /// from 0 (every narrow field wraps), with indexes, armed clears (two indexes
    /// within a visit too), probes next to clears and resets, for K = 1..16.
    #[test]
    fn the_extension_gives_the_full_count_and_latches_at_every_visit() {
        let mut seed = 0x9E37_79B9_7F4A_7C15u64;
        let mut rng = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        };
        let mut checked = [0u64; 6];
        for k in 1..=16usize {
            let mut bank = EncoderBankModel::new(k);
            let mut pos = vec![0i64; k];
            // The step positions (0 at reset, a step a tick at most) and each axis's
            // position at its last index.
            let mut steps = vec![0u32; k];
            let mut at_index = vec![0u32; k];
            let mut target = vec![0i64; k];
            // Some runs hold every axis still for longer than the velocity saturates.
            let long = [1, 5, 16].contains(&k);
            let stall = |t: u64| long && (6_000..74_000).contains(&t);
            let mut visit = (0, EncOutputs::default(), false, 0u32);
            for t in 0..if long { 80_000 } else { 6_000 } {
                let reset = t < 3 || (!stall(t) && rng() % 3_000 == 0);
                let vel_prescale = if long || k % 3 == 0 { 0 } else { 3 };
                let mut i = BankInputs { mode: 0x20, vel_prescale, ..Default::default() };
                for a in 0..k {
                    if stall(t) {
                        target[a] = pos[a];
                    } else if rng() % 200 == 0 {
                        // Far away, or near (then the axis rests until the next).
                        target[a] = if rng() % 2 == 0 {
                            (rng() % 4_000) as i64 - 2_000 + if a % 2 == 0 { 100_000 } else { -70_000 }
                        } else {
                            pos[a] + (rng() % 40) as i64 - 20
                        };
                    }
                    // At most a count per tick (every other tick for some axes).
                    if pos[a] != target[a] && (a % 3 != 0 || t % 2 == 0) {
                        pos[a] += (target[a] - pos[a]).signum();
                    }
                    // An index every 6 counts, so two can fall between two visits.
                    let p = QuadratureGen::lines(pos[a], 6);
                    i.a |= (p.a as u32) << a;
                    i.b |= (p.b as u32) << a;
                    i.z |= (p.z as u32) << a;
                    // Frequent armed clears on some axes, rare on the others.
                    if !stall(t) && rng() % if a % 4 == 0 { 40 } else { 3_000 } == 0 {
                        i.arm |= 1 << a;
                    }
                }
                i.probe = rng() % 25 == 0;
                if reset {
                    steps.iter_mut().for_each(|s| *s = 0);
                    at_index.iter_mut().for_each(|s| *s = 0);
                } else if !stall(t) {
                    for (a, s) in steps.iter_mut().enumerate() {
                        // Runs one way and the other; some axes step every tick.
                        let r = rng() % 8;
                        if a % 5 == 1 || r < 3 {
                            *s = if (t / 1_500 + a as u64) % 2 == 0 { s.wrapping_add(1) } else { s.wrapping_sub(1) };
                        }
                    }
                }
                i.position = steps[bank.pos_axis()];
                i.pos_low = steps.iter().enumerate().fold(0u128, |w, (a, &s)| w | ((s & 0xFF) as u128) << (8 * a));
                // The visit's sample, written by the next edge.
                let (ax, full, ok, at_idx) = visit;
                visit = (bank.fe.ax(), bank.dec[bank.fe.ax()].outputs(), !reset, at_index[bank.fe.ax()]);
                let togs: Vec<bool> = bank.dec.iter().map(|d| d.outputs().index_tog).collect();
                bank.clock(&i, reset);
                for a in 0..k {
                    if bank.dec[a].outputs().index_tog != togs[a] && !reset {
                        at_index[a] = steps[a];
                    }
                }
                if ok && !reset {
                    let e = &bank.ext;
                    assert_eq!(e.cnt[ax], full.count, "K {k}, tick {t}, axis {ax}: the count");
                    assert_eq!(e.idx[ax], full.index_count, "K {k}, tick {t}, axis {ax}: the index latch");
                    assert_eq!(e.prb[ax], full.probe_count, "K {k}, tick {t}, axis {ax}: the probe latch");
                    // The step position at the last index: written at a visit with a new
                    // index, held at the others.
                    assert_eq!(e.ipos[ax], at_idx, "K {k}, tick {t}, axis {ax}: the index's step position (new: {})", full.inew);
                    checked[5] += (full.inew && (at_idx as i32).unsigned_abs() > 300) as u64;
                    assert_eq!(e.live[ax], live_word(&full));
                    assert_eq!((e.per[ax], e.age[ax]), (full.period, full.age), "K {k}, tick {t}, axis {ax}: the velocity");
                    checked[3] += (full.age == VEL_MAX) as u64;
                    checked[4] += (full.period > 255 && full.enew && !full.e2) as u64;
                    checked[0] += ((full.count as i32).unsigned_abs() > 1 << 9 && !full.cnew) as u64;
                    checked[1] += (full.inew && full.iafter) as u64;
                    checked[2] += (full.pnew && full.pafter) as u64;
                }
            }
        }
        assert!(checked.iter().all(|&c| c > 20), "every case was met: {checked:?}");
    }

    #[test]
    fn the_rate_bound_keeps_two_ticks_and_grows_with_the_filter() {
        assert_eq!(max_count_rate_ticks(0), 2);
        assert_eq!(max_count_rate_ticks(1), 2);
        assert_eq!(max_count_rate_ticks(3), 3);
        assert_eq!(max_count_rate_ticks(15), 9);
    }
}

mod guard_examples {
    use tdm_stepper::model::guard::*;

    fn free() -> GuardFlags {
        GuardFlags::default()
    }

    #[test]
    fn the_checks_in_their_order() {
        let mut g = PushGuardModel::new(2);
        assert_eq!(g.check(0, 10, free()), Err(GuardError::Halted), "stale after reset");
        g.resync(0, 100);
        assert_eq!(g.check(0, 10, free()), Ok(110));
        assert_eq!(g.check(0, 10, GuardFlags { held: true, ..free() }), Err(GuardError::Halted));
        assert_eq!(g.check(0, 10, GuardFlags { limit_pos: true, ..free() }), Err(GuardError::Limit));
        assert_eq!(g.check(0, -10, GuardFlags { limit_pos: true, ..free() }), Ok(90), "away from the limit runs");
        assert_eq!(g.check(0, -10, GuardFlags { limit_neg: true, ..free() }), Err(GuardError::Limit));
        assert_eq!(g.check(0, 0, GuardFlags { limit_neg: true, limit_pos: true, held: false }), Ok(100), "a dwell");
        assert_eq!(g.set_soft(0, Some(SoftLimits { min: 0, max: -1 })), Err(()));
        assert_eq!(g.soft[0], None, "a refused pair changes nothing");
        g.set_soft(0, Some(SoftLimits { min: 50, max: 150 })).unwrap();
        assert_eq!(g.check(0, 50, free()), Ok(150), "max is inclusive");
        assert_eq!(g.check(0, 51, free()), Err(GuardError::SoftLimit));
        assert_eq!(g.check(0, -50, free()), Ok(50), "min is inclusive");
        assert_eq!(g.check(0, -51, free()), Err(GuardError::SoftLimit));
        g.accept(0, 150);
        assert_eq!(g.check(0, 1, free()), Err(GuardError::SoftLimit), "after everything queued before it");
        assert_eq!(g.check(0, 0, free()), Ok(150));
        g.mark_stale(0);
        assert_eq!(g.check(0, -1, free()), Err(GuardError::Halted));
        g.resync(0, 120);
        assert_eq!(g.check(0, 30, free()), Ok(150));
        // The end is exact at the 32-bit edges (no wrap into range).
        g.set_soft(1, Some(SoftLimits { min: i32::MIN, max: i32::MAX })).unwrap();
        g.resync(1, i32::MAX - 5);
        assert_eq!(g.check(1, 5, free()), Ok(i32::MAX as i64));
        assert_eq!(g.check(1, 6, free()), Err(GuardError::SoftLimit));
        g.set_soft(1, None).unwrap();
        assert_eq!(g.check(1, 6, free()), Ok(i32::MAX as i64 + 1));
        g.accept(1, i32::MAX as i64 + 1);
        assert_eq!(g.plan[1], i32::MIN, "the plan wraps like the position");
    }
}

mod poly_examples {
    use tdm_stepper::model::poly::*;
    use tdm_stepper::model::segment::{Limits, SegmentError, MAX_V0_RATE};

    fn limits() -> Limits {
        Limits::default()
    }

    fn check(seg: PolySegment) -> Vec<u32> {
        seg.validate(&limits()).unwrap();
        let plan = PolyPlan::new(seg);
        let edges = plan.edges();
        assert_eq!(edges.len() as u32, seg.n_steps());
        for (k, &e) in edges.iter().enumerate() {
            let i = k as u32 + 1;
            assert_eq!(e, seg.edge_by_definition(i), "step {i} of {seg:?}");
            assert!(seg.edge_within(i, e as i64, 4), "step {i} of {seg:?} not within ½ tick");
        }
        edges
    }

    #[test]
    fn the_setup_state_is_the_search_at_base_one() {
        let segs = [
            PolySegment::cubic(0, 3000 << 16, 1 << 16, 1000).unwrap(),
            PolySegment::new(1 << 20, 1 << 21, -(1 << 30), 1 << 12, 3),
            PolySegment::cubic(MAX_V0_RATE / 3, 0, 1 << 24, -(1 << 20)).unwrap(),
        ];
        for seg in segs {
            let plan = PolyPlan::new(seg);
            let (a, b) = (plan.setup_state(), plan.search_after(0, 1));
            assert_eq!((a.i, a.base, a.rem, a.taylor), (b.i, b.base, b.rem, b.taylor), "{seg:?}");
        }
    }

    #[test]
    fn a_cubic_from_rest_has_its_edges_at_the_cube_root() {
        // x = n·u³ (v0 = 0, A = 0): v1 = 3n/T. T = 2^16, n = 1000: v1·2^32 = 3000·2^16.
        let t = 1u32 << 16;
        let seg = PolySegment::cubic(0, 3000 << 16, t, 1000).unwrap();
        assert_eq!(seg.a_q32, 0);
        assert_eq!(seg.degree(), 3);
        let edges = check(seg);
        for (k, &e) in edges.iter().enumerate() {
            let exact = t as f64 * ((k + 1) as f64 / 1000.0).cbrt();
            assert!((e as f64 - exact).abs() <= 0.5 + 1e-9, "step {}: {e} vs {exact}", k + 1);
        }
    }

    #[test]
    fn a_quartic_from_rest_matches_the_fourth_root() {
        // x = n·u⁴: v0 = 0, A = 0, C = 0, Q = n → Rn = n, Rv = v1·T = 4n.
        let t = 1u32 << 18;
        let n = 4096;
        let seg = PolySegment::new(0, ((4 * n as u64) << 32 >> 18) as u32, 0, t, n);
        assert_eq!(seg.hermite_q32(), (0, (n as i128) << 32));
        let edges = check(seg);
        for (k, &e) in edges.iter().enumerate() {
            let exact = t as f64 * ((k + 1) as f64 / n as f64).powf(0.25);
            assert!((e as f64 - exact).abs() <= 0.5 + 1e-9);
        }
    }

    #[test]
    fn a_uniform_segment_is_bresenham() {
        let seg = PolySegment::cubic(1 << 28, 1 << 28, 1 << 20, 1 << 16).unwrap();
        assert_eq!(seg.degree(), 1);
        let edges = check(seg);
        for (k, &e) in edges.iter().enumerate() {
            assert_eq!(e, 16 * (k as u32 + 1));
        }
    }

    #[test]
    fn rest_to_rest_in_one_cubic_and_one_step() {
        // x = n(3u² − 2u³): v0 = v1 = 0, A = 3n.
        let seg = PolySegment::cubic(0, 0, POLY_MAX_T_TICKS, 1).unwrap();
        assert_eq!(seg.a_q32, 3 << 32);
        assert_eq!(check(seg), vec![POLY_MAX_T_TICKS]);
        let seg = PolySegment::cubic(0, 0, POLY_MAX_T_TICKS, 2).unwrap();
        assert_eq!(check(seg), vec![POLY_MAX_T_TICKS / 2, POLY_MAX_T_TICKS]);
    }

    #[test]
    fn the_search_resumes_from_any_step() {
        let mut seg = PolySegment::cubic(1 << 27, 3 << 26, 1 << 19, 20000).unwrap();
        seg.a_q32 += 1 << 44; // a quartic
        assert_eq!(seg.degree(), 4);
        seg.validate(&limits()).unwrap();
        let plan = PolyPlan::new(seg);
        let edges = plan.edges();
        for i in [0u32, 1, 77, 6000, 19998] {
            let base = if i == 0 { 0 } else { edges[i as usize - 1] };
            let mut s = plan.search_after(i, base);
            let again: Vec<u32> = std::iter::from_fn(|| s.next_edge()).collect();
            assert_eq!(&again[..], &edges[i as usize..]);
        }
    }

    /// The widest search word over the corners of the range: every speed control point
    /// at 0 or RMAX (minimum period 2), T = 2^24, 2^24 − 1 and 2^12, in windows at the start,
    /// the middle and the end of each segment.
    #[test]
    fn the_search_words_fit_at_the_corners() {
        let l = limits();
        let mut widest = 0;
        let mut coeff = [0u32; 4];
        for seg in corner_segments(&l, &[POLY_MAX_T_TICKS, POLY_MAX_T_TICKS - 1, 1 << 12]) {
            let plan = PolyPlan::new(seg);
            for (k, c) in seg.n_coefficients().into_iter().enumerate() {
                coeff[k] = coeff[k].max(signed_bits(c));
            }
            let n = seg.n_steps();
            for start in [0, n / 2, n.saturating_sub(40)] {
                let base = if start == 0 { 0 } else { seg.edge_by_definition(start) };
                let mut s = plan.search_after(start, base);
                for _ in 0..40 {
                    if s.next_edge().is_none() {
                        break;
                    }
                }
                widest = widest.max(s.widest_bits);
            }
        }
        eprintln!("widest poly search word: {widest} bits");
        assert!(widest <= POLY_WORD_BITS && widest + 8 > POLY_WORD_BITS, "widest {widest}");
        // The setup's products: within their widths, and the bounds not loose by
        // more than the control points' slack (a few bits).
        eprintln!("widest setup coefficients: {coeff:?} bits");
        for k in 0..4 {
            assert!(coeff[k] <= POLY_COEFF_BITS[k] && coeff[k] + 4 > POLY_COEFF_BITS[k], "c{}: {coeff:?}", k + 1);
        }
    }

    #[test]
    fn validation_catches_interior_reversal_and_peak() {
        let l = limits();
        let rmax = l.max_rate();
        // n = 0 with an acceleration term reverses inside.
        assert_eq!(PolySegment::new(0, 0, 1 << 40, 1000, 0).validate(&l), Err(SegmentError::Reverses));
        assert!(PolySegment::new(0, 0, 0, 1000, 0).validate(&l).is_ok());
        // Rest to rest over T with n steps peaks at 1.5·n/T: too fast when that exceeds RMAX
        // although both ends are at rest.
        let t = 3000u32;
        let n = ((rmax as u64 * t as u64) >> 32) as i32; // average speed ≈ RMAX
        assert_eq!(PolySegment::cubic(0, 0, t, n).unwrap().validate(&l), Err(SegmentError::PeriodTooShort));
        assert_eq!(PolySegment::cubic(0, 0, t, 2 * n / 5).unwrap().validate(&l), Ok(()));
        assert_eq!(
            PolySegment::cubic(0, 0, POLY_MAX_T_TICKS + 1, 1).unwrap().validate(&l),
            Err(SegmentError::TicksRange)
        );
        assert_eq!(PolySegment::new(MAX_V0_RATE + 1, 0, 0, 10, 1).validate(&l), Err(SegmentError::RateRange));
    }
}
