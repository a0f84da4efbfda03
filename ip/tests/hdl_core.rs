//! The TDM core against the reference model, through its command port: every STEP
//! edge of every axis at release + 1 + E_i with one release tick for all axes (0 skew),
//! no underrun when K·t_calc is below the shortest period, final positions and
//! segment counts. The core is fed what the push check passes (valid segments, in
//! their effective form; hdl_push_check.rs checks the verdicts), so an invalid segment
//! in a move list is dropped before the core, as in the exported IP. rust-hdl simulation and the exported Verilog (Verilator) must produce the
//! same trace. Also: the FSM's state constants in the Verilog are a Gray sequence.

#[macro_use]
mod common;

use common::*;
use rust_hdl::prelude::*;
use tdm_stepper::hdl::baseline::Baseline;
use tdm_stepper::hdl::core::{gray, t_calc_sqrt, t_poly_step, TdmCore, STATES, STATE_BITS, T_POLY_LAST, T_POLY_SETUP};
use tdm_stepper::model::poly::PolySegment;
use tdm_stepper::model::{planner, AxisRun, Limits, Motion, Segment, SegmentPlan};
use tdm_stepper::verify::{run_rust_hdl_sparse, run_sparse, Change, Port, Simulator, TbSpec};

/// The rust-hdl trace of any core with these ports (TdmCore and Baseline).
macro_rules! rust_hdl_trace {
    ($uut:expr, $ev:expr, $cycles:expr) => {
        run_rust_hdl_sparse(
            &mut $uut,
            $ev,
            $cycles,
            |u, c| u.clock.next = Clock::from(c),
            |u, r| {
                u.reset.next = r[0] == 1;
                u.cmd_valid.next = r[1] == 1;
                u.cmd_axis.next = (r[2] as u64).into();
                u.cmd_v0.next = (r[3] as u64).into();
                u.cmd_t.next = (r[4] as u64).into();
                u.cmd_steps.next = (r[5] as u64).into();
                u.start.next = r[6] == 1;
                u.start_mask.next = (r[7] as u64).into();
                u.sel_axis.next = (r[8] as u64).into();
                u.ext_go.next = (r[9] as u64).into();
                u.abort.next = r[10] == 1;
                u.stop_axes.next = (r[11] as u64).into();
                // The controlled-stop columns, where the stimulus has them (spec_cs).
                if r.len() > 12 {
                    u.cstop_axes.next = (r[12] as u64).into();
                    u.decel.next = (r[13] as u64).into();
                }
                // The polynomial fields, where the stimulus has them (spec_poly).
                if r.len() > 14 {
                    u.cmd_extra.next = r[14].to_bits();
                }
            },
            |u| {
                vec![
                    u.step.val().to_u64() as u128,
                    u.dir.val().to_u64() as u128,
                    u.underrun.val().to_u64() as u128,
                    u.busy.val().to_u64() as u128,
                    u.sel_position.val().to_u64() as u128,
                    u.cmd_ready.val() as u128,
                    u.fsm_state.val().to_u64() as u128,
                    u.sel_taken.val().to_u64() as u128,
                    u.sel_done.val().to_u64() as u128,
                ]
            },
        )
    };
}

const R: usize = 4;
const DEPTH: usize = 4;
const QDEPTH: usize = 16;

fn plan(steps: i64, ticks: [u32; 3]) -> Vec<Segment> {
    planner::trapezoid_by_ticks(steps, ticks, &Limits::default()).unwrap()
}

/// Per axis: rest-to-rest moves (accelerate, cruise, decelerate), an exactly uniform
/// segment, a dwell, both directions, and rejected segments between them.
/// Shortest period about 100 ticks.
fn moves() -> Vec<Vec<Segment>> {
    vec![
        [
            plan(100, [8000, 4000, 8000]),
            // Exactly uniform, at 128 and at 1365⅓ ticks per step (the remainder path).
            vec![Segment::new(0, 0, 10), Segment::dwell(3000), Segment::new(1 << 25, 5120, -40)],
            vec![Segment::new(3 << 20, 8192, 6)],
            plan(-50, [5000, 0, 5000]),
        ]
        .concat(),
        [
            plan(80, [6000, 2000, 6000]),
            vec![Segment::new(858_993, 100_000, 5), Segment::new(0, 100, 50)],
            plan(30, [3000, 1000, 3000]),
        ]
        .concat(),
    ]
}

fn spec<const K: usize>() -> TbSpec {
    TbSpec {
        clock: "clock".into(),
        inputs: vec![
            Port::new("reset", 1),
            Port::new("cmd_valid", 1),
            Port::new("cmd_axis", 8),
            Port::new("cmd_v0", 32),
            Port::new("cmd_t", 32),
            Port::new("cmd_steps", 32),
            Port::new("start", 1),
            Port::new("start_mask", K),
            Port::new("sel_axis", 8),
            Port::new("ext_go", K),
            Port::new("abort", 1),
            Port::new("stop_axes", K),
        ],
        outputs: vec![
            Port::new("step", K),
            Port::new("dir", K),
            Port::new("underrun", K),
            Port::new("busy", K),
            Port::new("sel_position", 32),
            Port::new("cmd_ready", 1),
            Port::new("fsm_state", STATE_BITS),
            Port::new("sel_taken", 8),
            Port::new("sel_done", 8),
        ],
    }
}

/// What the push check hands the core for these segments: the valid ones, each in
/// its effective form.
fn core_feed(segs: &[Segment]) -> Vec<Segment> {
    let limits = Limits::default();
    segs.iter().filter(|s| s.validate(&limits).is_ok()).map(|s| s.effective()).collect()
}

/// What the push check hands the core for these motions: the valid ones, the
/// trapezoids in their effective form.
fn motion_feed(ms: &[Motion]) -> Vec<Motion> {
    let limits = Limits::default();
    ms.iter()
        .filter(|m| m.validate(&limits).is_ok())
        .map(|m| match m {
            Motion::Trapezoid(s) => Motion::Trapezoid(s.effective()),
            p => *p,
        })
        .collect()
}

/// A motion's command columns: v0, T, steps and the polynomial fields (v1, A', the
/// flag; 0 for a trapezoid).
fn command_of(m: &Motion) -> [u128; 4] {
    match m {
        Motion::Trapezoid(s) => [s.v0_rate as u128, s.t_ticks as u128, s.steps as u32 as u128, 0],
        Motion::Poly(p) => [
            p.v0_rate as u128,
            p.t_ticks as u128,
            p.steps as u32 as u128,
            tdm_stepper::hdl::poly_lane::poly_extra(p),
        ],
    }
}

/// [`events`] for motions, on [`spec_poly`]'s ports (no controlled stop).
fn events_poly<const K: usize>(axes: &[Vec<Motion>], cycles: u64) -> Vec<(u64, Vec<u128>)> {
    let idle = |sel: u128| vec![0, 0, 0, 0, 0, 0, 0, 0, sel, 0, 0, 0, 0, 0, 0];
    let mut ev = vec![(0u64, [vec![1], idle(0)[1..].to_vec()].concat())];
    let mut c = 3u64;
    ev.push((c, idle(0)));
    for (a, ms) in axes.iter().enumerate() {
        for m in motion_feed(ms) {
            let [v0, t, steps, extra] = command_of(&m);
            c += 1;
            ev.push((c, vec![0, 1, a as u128, v0, t, steps, 0, 0, 0, 0, 0, 0, 0, 0, extra]));
        }
    }
    c += 1;
    let mut go = idle(0);
    go[6] = 1;
    go[7] = (1u128 << K) - 1;
    ev.push((c, go));
    c += 1;
    ev.push((c, idle(0)));
    for a in 0..K {
        ev.push((cycles - 2 * (K - a) as u64, idle(a as u128)));
    }
    ev
}

fn cycles_for_motions(axes: &[Vec<Motion>]) -> u64 {
    let limits = Limits::default();
    axes.iter().map(|s| AxisRun::run_motions(s, &limits).end_tick).max().unwrap() + 6000
}

/// Reset, one command per cycle (the segments the push check passes), a synchronised
/// start of all axes, and at the end a status read of each axis.
fn events<const K: usize>(axes: &[Vec<Segment>], cycles: u64) -> Vec<(u64, Vec<u128>)> {
    let idle = |sel: u128| vec![0, 0, 0, 0, 0, 0, 0, 0, sel, 0];
    let mut ev = vec![(0u64, [vec![1], idle(0)[1..].to_vec()].concat())];
    let mut c = 3u64;
    ev.push((c, idle(0)));
    for (a, segs) in axes.iter().enumerate() {
        for s in core_feed(segs) {
            c += 1;
            ev.push((c, vec![0, 1, a as u128, s.v0_rate as u128, s.t_ticks as u128, s.steps as u32 as u128, 0, 0, 0, 0]));
        }
    }
    c += 1;
    ev.push((c, vec![0, 0, 0, 0, 0, 0, 1, (1u128 << K) - 1, 0, 0]));
    c += 1;
    ev.push((c, idle(0)));
    for a in 0..K {
        ev.push((cycles - 2 * (K - a) as u64, idle(a as u128)));
    }
    // No abort, no stop.
    for e in &mut ev {
        e.1.push(0);
        e.1.push(0);
    }
    ev
}

fn uut<const K: usize>() -> TdmCore<K, R, DEPTH, QDEPTH> {
    uut_q::<K, QDEPTH>()
}

fn uut_q<const K: usize, const Q: usize>() -> TdmCore<K, R, DEPTH, Q> {
    uut_rq::<K, R, Q>()
}

fn uut_rq<const K: usize, const RR: usize, const Q: usize>() -> TdmCore<K, RR, DEPTH, Q> {
    connect_core!(TdmCore::<K, RR, DEPTH, Q>::new())
}

fn baseline<const K: usize>() -> Baseline<K, R, DEPTH, QDEPTH> {
    connect_core!(Baseline::<K, R, DEPTH, QDEPTH>::new())
}

/// Runs `axes` in Verilator on the given Verilog and checks them against the model.
fn verilator_run<const K: usize>(name: &str, verilog: &str, axes: &[Vec<Segment>]) -> Vec<Change> {
    let cycles = cycles_for(axes);
    let ev = events::<K>(axes, cycles);
    let got = run_sparse(Simulator::Verilator, &sim_dir(name, Simulator::Verilator), verilog, &spec::<K>(), &ev, cycles).unwrap();
    check_against_model::<K>(axes, &got, cycles, name);
    got
}

/// rust-hdl and Verilator traces are the same, change for change (after reset).
fn same_traces(a: &[Change], b: &[Change], what: &str) {
    let strip = |t: &[Change]| -> Vec<(u64, Vec<u128>)> { t.iter().skip(2).map(|(c, v)| (*c, v.iter().map(|x| x.unwrap_or(u128::MAX)).collect())).collect() };
    assert_eq!(strip(a), strip(b), "{what}: Verilator and rust-hdl traces differ");
}

/// Value of output `port` at every cycle where it changes, from cycle `from`.
fn expand(trace: &[Change], port: usize, cycles: u64) -> Vec<u128> {
    let mut out = Vec::with_capacity(cycles as usize);
    let mut cur = 0;
    let mut k = 0;
    for c in 0..cycles {
        while k < trace.len() && trace[k].0 == c {
            cur = trace[k].1[port].unwrap_or(0);
            k += 1;
        }
        out.push(cur);
    }
    out
}

/// The cycles in which axis `a`'s STEP rises, from the expanded STEP bus.
fn rises_of(step: &[u128], a: usize) -> Vec<u64> {
    (1..step.len()).filter(|&c| (step[c] >> a) & 1 == 1 && (step[c - 1] >> a) & 1 == 0).map(|c| c as u64).collect()
}

/// Every rise seen is the model's edge at the same offset, release + 1 + E_i (as many
/// edges as were seen); returns that release cycle, or None without an edge.
fn release_of(rises: &[u64], edge_ticks: &[u64], what: &str) -> Option<i64> {
    let l0 = *rises.first()? as i64 - 1 - *edge_ticks.first()? as i64;
    for (i, (&r, &e)) in rises.iter().zip(edge_ticks).enumerate() {
        assert_eq!(r as i64, l0 + 1 + e as i64, "{what} edge {i}");
    }
    Some(l0)
}

/// The columns of a controlled-stop trace one window's check reads (per cycle, bit a
/// = axis a): BUSY, sel_position and UNDERRUN.
struct StopTrace<'a> {
    busy: &'a [u128],
    pos: &'a [u128],
    under: &'a [u128],
}

/// One window of a controlled-stop test: axis `ax` ran `run` from cycle `from`, a stop
/// came at `stop`, and by `end` it rests. Its rising edges (from `r1`) are the run's
/// until the stop, then the model's cut and ramp (`stop_cut_matching` over the entries
/// the FIFO could hold); at `end` it is at rest, `position` (the sum over the windows so
/// far, updated here) is its position, and it never underran. Returns the edges seen,
/// those emitted by the stop, the entries they took, the cut and the cut run.
#[allow(clippy::too_many_arguments)]
fn check_stop_window(
    what: &str,
    run: &AxisRun,
    r1: &[u64],
    (from, stop, end): (u64, u64, u64),
    ax: usize,
    decel: u32,
    t: &StopTrace,
    position: &mut i64,
) -> (Vec<u64>, usize, usize, usize, AxisRun) {
    let limits = Limits::default();
    let rises: Vec<u64> = r1.iter().copied().filter(|&x| x > from && x < end).collect();
    release_of(&rises[..2], &run.edge_ticks[..2], what).unwrap();
    let emitted = rises.iter().filter(|&&x| x <= stop).count();
    let e0 = entries_for_edges(run, emitted);
    let (cut, m) = stop_cut_matching(run, &rises, e0..=(e0 + DEPTH + 3).min(run.fifo.len()), decel, &limits)
        .unwrap_or_else(|| panic!("{what}: no cut after {e0}..{} FIFO entries gives the {} edges seen (the move has {})", e0 + DEPTH + 3, rises.len(), run.edge_ticks.len()));
    eprintln!("{what}: stop after {emitted} edges, cut after {cut} entries (+{}), ramp {:?}, {} edges", cut - e0, m.accepted.first(), rises.len());
    *position += m.position;
    assert_eq!(t.busy[end as usize - 1] >> ax & 1, 0, "{what}: the axis at rest");
    assert_eq!(t.pos[end as usize - 1] as u32 as i32 as i64, *position, "{what}: position = edges emitted");
    assert!((from..end).all(|x| t.under[x as usize] >> ax & 1 == 0), "{what}: an underrun");
    (rises, emitted, e0, cut, m)
}

fn check_against_model<const K: usize>(axes: &[Vec<Segment>], trace: &[Change], cycles: u64, what: &str) {
    let axes: Vec<Vec<Motion>> = axes.iter().map(|a| a.iter().map(|&s| s.into()).collect()).collect();
    check_motions::<K>(&axes, trace, cycles, what)
}

/// As [`check_against_model`], for trapezoid and polynomial segments mixed.
fn check_motions<const K: usize>(axes: &[Vec<Motion>], trace: &[Change], cycles: u64, what: &str) {
    check_motion_columns::<K>(axes, trace, cycles, what, [0, 2, 4, 5, 7, 8]);
}

/// [`check_motions`] on a trace whose step, underrun, sel_position, cmd_ready,
/// sel_taken and sel_done outputs are the columns `cols`.
fn check_motion_columns<const K: usize>(axes: &[Vec<Motion>], trace: &[Change], cycles: u64, what: &str, cols: [usize; 6]) {
    let limits = Limits::default();
    let step = expand(trace, cols[0], cycles);
    let under = expand(trace, cols[1], cycles);
    let pos = expand(trace, cols[2], cycles);
    let ready = expand(trace, cols[3], cycles);
    assert!(ready.iter().skip(4).all(|&r| r == 1), "{what}: a command was refused");
    let mut release: Option<i64> = None;
    for (a, segs) in axes.iter().enumerate() {
        let run = AxisRun::run_motions(segs, &limits);
        let rises = rises_of(&step, a);
        assert_eq!(rises.len(), run.edge_ticks.len(), "{what}: axis {a} step count");
        if let Some(l0) = release_of(&rises, &run.edge_ticks, &format!("{what}: axis {a}")) {
            assert_eq!(*release.get_or_insert(l0), l0, "{what}: axis {a} released on another tick (skew)");
        }
        // Status reads at the end: position and the segment counts.
        let sel_cycle = (cycles - 2 * (K - a) as u64 + 1) as usize;
        assert_eq!(pos[sel_cycle] as u32 as i32 as i64, run.position, "{what}: axis {a} position");
        let fed = motion_feed(segs).len() as u128;
        assert_eq!(fed, (segs.len() - run.rejected.len()) as u128, "{what}: axis {a}: the model rejects what the check drops");
        let taken = expand(trace, cols[4], cycles)[sel_cycle];
        let done = expand(trace, cols[5], cycles)[sel_cycle];
        assert_eq!(taken, fed % 256, "{what}: axis {a} segments taken");
        assert_eq!(done, fed % 256, "{what}: axis {a} segments done");
    }
    assert!(under.iter().all(|&u| u == 0), "{what}: underrun");
}

fn cycles_for(axes: &[Vec<Segment>]) -> u64 {
    let limits = Limits::default();
    axes.iter().map(|s| AxisRun::run(s, &limits).end_tick).max().unwrap() + 6000
}

#[test]
fn two_axes_match_the_model_in_rust_hdl_and_verilator() {
    const K: usize = 2;
    let axes = moves();
    let cycles = cycles_for(&axes);
    let reference = rust_hdl_trace!(uut::<K>(), &events::<K>(&axes, cycles), cycles);
    check_against_model::<K>(&axes, &reference, cycles, "rust-hdl");
    let got = verilator_run::<K>("core_k2", &generate_verilog(&uut::<K>()), &axes);
    same_traces(&got, &reference, "TDM core");
}

/// The non-TDM baseline does the same thing with K schedulers and K math units.
#[test]
fn baseline_matches_the_model_in_rust_hdl_and_verilator() {
    const K: usize = 2;
    let axes = moves();
    let cycles = cycles_for(&axes);
    let reference = rust_hdl_trace!(baseline::<K>(), &events::<K>(&axes, cycles), cycles);
    check_against_model::<K>(&axes, &reference, cycles, "baseline, rust-hdl");
    let got = verilator_run::<K>("baseline_k2", &generate_verilog(&baseline::<K>()), &axes);
    same_traces(&got, &reference, "baseline");
}

/// The committed vectors whose periods leave the scheduler time (K·t_calc below every
/// period): every error code between valid segments, and decelerations in both
/// directions (5 M cycles). The others have 2-tick periods (the step generator's tests
/// run them) or 2^30-tick segments (hdl_core_setup.rs checks their arithmetic).
#[test]
fn committed_vectors_run_on_a_two_axis_core() {
    let root = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../vectors");
    for name in ["invalid", "pure_deceleration"] {
        let v: tdm_stepper::vectors::VectorFile =
            serde_json::from_str(&std::fs::read_to_string(root.join(format!("{name}.json"))).unwrap()).unwrap();
        assert_eq!(v.min_period_ticks, 2, "the core is built for the default minimum period");
        let mut axes: Vec<Vec<Segment>> = v.axes.iter().map(|a| a.segments.iter().map(|s| s.segment()).collect()).collect();
        axes.resize(2, vec![Segment::dwell(10)]);
        verilator_run::<2>(&format!("core_vec_{name}"), &generate_verilog(&uut::<2>()), &axes);
    }
}

/// K = 1, 4 and 8 on the paper's experiment (its two axes' moves repeated over K).
#[test]
fn one_four_and_eight_axes_run_the_paper_experiment() {
    let paper = tdm_stepper::vectors::paper_experiment_segments();
    let cycled = |k: usize| (0..k).map(|a| paper[a % 2].clone()).collect::<Vec<_>>();
    verilator_run::<1>("core_k1_paper", &generate_verilog(&uut::<1>()), &cycled(1));
    verilator_run::<4>("core_k4_paper", &generate_verilog(&uut::<4>()), &cycled(4));
    verilator_run::<8>("core_k8_paper", &generate_verilog(&uut::<8>()), &cycled(8));
}

/// Four axes reaching segment boundaries together, with 100-tick periods there: no FIFO
/// runs dry at the boundaries. (Their 4-entry FIFOs would cover the four setups even if
/// these waited for the boundary; the next test is the one that needs them ahead.)
#[test]
fn simultaneous_segment_boundaries_do_not_underrun() {
    const K: usize = 4;
    let axes = vec![moves()[0].clone(); K];
    verilator_run::<K>("core_k4_boundaries", &generate_verilog(&uut::<K>()), &axes);
}

/// Setup ahead of time, where it is what keeps the edges on time: four identical
/// axes, each six accelerating segments from 1/121 to about 1/119 step per tick
/// (periods near 120 ticks at every boundary; load 4·22/120 = 0.73), on a core with a
/// 2-entry period FIFO. At a boundary an axis holds about three periods (its current
/// entry and the FIFO's two), some 360 cycles, less than four setups one after the
/// other (about 470 cycles here). The core sets each axis's next segment up while every
/// FIFO is full, at the start of the segment before, so every edge is the model's;
/// setting it up only when the axis runs out of periods (mutant 13 in
/// scripts/mutants.sh) makes axis 0's first edge after the first boundary late.
/// (`simultaneous_segment_boundaries_do_not_underrun`'s 4-entry FIFOs cover the four
/// setups either way.)
#[test]
fn setups_ahead_of_time_cover_boundaries_near_the_maximum_rate() {
    const K: usize = 4;
    let seg = Segment::new(((1u64 << 32) / 121) as u32, 12_000, 100);
    assert!(seg.validate(&Limits::default()).is_ok());
    let axes = vec![vec![seg; 6]; K];
    let u = connect_core!(TdmCore::<K, R, 2, QDEPTH>::new());
    verilator_run::<K>("core_k4_near_max_boundaries", &generate_verilog(&u), &axes);
}

/// Identical commands on sync-started axes: identical STEP and DIR on every cycle.
/// (The paper's moves: four simultaneous setups fit in the FIFO's slack at their
/// segment boundaries; see docs/architecture.md, "Setup at segment boundaries".)
#[test]
fn identical_commands_give_zero_skew() {
    const K: usize = 4;
    let axes = vec![tdm_stepper::vectors::paper_experiment_segments()[0].clone(); K];
    let got = verilator_run::<K>("core_k4_same", &generate_verilog(&uut::<K>()), &axes);
    let cycles = cycles_for(&axes);
    for port in [0, 1] {
        let bus = expand(&got, port, cycles);
        assert!(bus.iter().all(|&b| b == 0 || b == (1 << K) - 1), "port {port}: axes differ on some cycle");
        assert!(bus.iter().any(|&b| b != 0) || port == 1, "no steps at all");
    }
}

/// Random valid segments (any kind, both directions, dwells, rejected ones), chained
/// per axis, with periods of at least `min_period` ticks.
fn random_moves(axes: usize, per_axis: usize, seed: u64) -> Vec<Vec<Segment>> {
    let limits = Limits::default();
    let mut rng = Rng(seed);
    (0..axes)
        .map(|_| {
            let mut segs = Vec::new();
            while segs.len() < per_axis {
                let t = 200 + rng.next() % 6000;
                let n = rng.next() % (t / 120 + 1);
                let one = 1u64 << 32;
                // Both end rates at most 1/100 step/tick, no reversal.
                let hi = ((2 * n * one) / t).min(one / 100);
                let lo = (2 * n * one).saturating_sub(t * (one / 100)).div_ceil(t);
                let v0 = match rng.next() % 4 {
                    _ if n == 0 => 0,
                    0 => lo,
                    1 => hi,
                    2 => ((n << 32) / t).clamp(lo, hi),
                    _ => lo + rng.next() % (hi - lo + 1).max(1),
                };
                let steps = if rng.next() % 2 == 0 { n as i32 } else { -(n as i32) };
                let seg = Segment::new(v0 as u32, t as u32, steps);
                if lo <= hi && seg.validate(&limits).is_ok() {
                    segs.push(seg);
                } else if rng.next() % 8 == 0 {
                    segs.push(seg); // an invalid one now and then, as a host would send
                }
            }
            segs
        })
        .collect()
}

/// Hundreds of random segments in Verilator: every edge against the model, so
/// that differences in the last bits of the setup (rounding of P' and B') show up.
#[test]
fn random_segments_match_the_model_in_verilator() {
    const K: usize = 2;
    const Q: usize = 32; // the deepest queue a RamFifo holds
    let axes = random_moves(K, Q - 4, 0x5eed_0f_c0de);
    verilator_run::<K>("core_random", &generate_verilog(&uut_q::<K, Q>()), &axes);
}

/// The uniform step's carry when its running remainder is exactly 2n. That needs n
/// even and T ≡ n/2 (mod n) (remainder n, plus 2T mod 2n = n, at the first step), which
/// an exactly uniform segment cannot have (v0 would be 2^33 / odd), so the segment is
/// nearly uniform: v0 = (2^33 − 1)/161 and T = 161n/2 give D·2^32 = n/2, so small that
/// the setup falls back to the uniform step (P' + 2T' ≥ 2^64), and n ≥ 2^29/161 makes it
/// so. The segment is 2^28 ticks long: every edge in the time of its first 13, in
/// rust-hdl and Verilator, against the model's. A carry missed at the first step puts edge 1 a tick early and
/// takes it at step 2 (so E_2 and the context are right again).
#[test]
fn uniform_step_carries_a_remainder_equal_to_2n() {
    let n: u32 = 3_400_000;
    let t = 161 * n / 2;
    let seg = Segment::new((((1u64 << 33) - 1) / 161) as u32, t, n as i32);
    assert_eq!(seg.validate(&Limits::default()), Ok(()));
    let plan = tdm_stepper::model::SegmentPlan::new(seg);
    assert_eq!(plan.kind, tdm_stepper::model::PlanKind::Uniform { nearly: true }, "{seg:?}");
    let (n64, t64) = (n as u64, t as u64);
    assert_eq!(n64 + (2 * t64) % (2 * n64), 2 * n64, "the remainder at the first step");
    let axes = vec![vec![seg]];
    let run = AxisRun::run(&axes[0], &Limits::default());
    let edges = 12;
    let cycles = 1_000 + run.edge_ticks[edges];
    let ev = events::<1>(&axes, cycles);
    let verilator =
        run_sparse(Simulator::Verilator, &sim_dir("core_uniform_carry", Simulator::Verilator), &generate_verilog(&uut::<1>()), &spec::<1>(), &ev, cycles)
            .unwrap();
    let rust = rust_hdl_trace!(uut::<1>(), &ev, cycles);
    same_traces(&verilator, &rust, "uniform carry");
    let rises = rises_of(&expand(&verilator, 0, cycles), 0);
    assert!(rises.len() > edges, "only {} edges in {cycles} cycles", rises.len());
    release_of(&rises, &run.edge_ticks, "uniform carry");
}

/// t_calc measured: with no start, a one-axis core computes periods back to back
/// until its FIFO is full; the square root is started once per period.
fn measured_t_calc<const RR: usize>() -> u64 {
    let mut u = one_segment_core::<RR, DEPTH, 4>(Segment::new(0, 1_000_000, 800));
    let p_start = tdm_stepper::hdl::core::gray(STATES.iter().position(|s| *s == "P_START").unwrap());
    let mut starts = Vec::new();
    for c in 0..2000u64 {
        if u.fsm_state.val().to_u64() == p_start {
            starts.push(c);
        }
        tick_core(&mut u);
    }
    assert!(starts.len() >= DEPTH, "only {} periods computed", starts.len());
    let gaps: Vec<u64> = starts.windows(2).map(|w| w[1] - w[0]).collect();
    assert!(gaps.iter().all(|&g| g == gaps[0]), "uneven: {gaps:?}");
    gaps[0]
}

/// Cycles from S_CHECK to the commit of a segment's setup (one-axis core, no start).
fn measured_t_setup<const RR: usize>(seg: Segment) -> u64 {
    let mut u = one_segment_core::<RR, DEPTH, 4>(seg);
    let code = |name: &str| tdm_stepper::hdl::core::gray(STATES.iter().position(|s| *s == name).unwrap());
    let (check, commit) = (code("S_CHECK"), code("S_COMMIT_SETUP"));
    let mut first = None;
    for c in 0..2000u64 {
        let st = u.fsm_state.val().to_u64();
        if st == check && first.is_none() {
            first = Some(c);
        }
        if st == commit {
            return c - first.unwrap() + 1;
        }
        tick_core(&mut u);
    }
    panic!("no setup commit");
}

#[test]
fn t_setup_is_what_the_constant_says() {
    use tdm_stepper::hdl::core::t_setup;
    let accel = Segment::new(0, 1_000_000, 800);
    let decel = Segment::new(6_871_947, 1_000_000, 800);
    for (seg, decelerating) in [(accel, false), (decel, true)] {
        assert_eq!(measured_t_setup::<4>(seg), t_setup(4, decelerating) as u64, "{seg:?} at R = 4");
        assert_eq!(measured_t_setup::<2>(seg), t_setup(2, decelerating) as u64, "{seg:?} at R = 2");
    }
}

/// The exported period FIFO depth absorbs a setup begun while an axis's FIFO was full
/// plus the scheduler's round trip at the shortest period the export enforces
/// (docs/architecture.md, "FIFO depth"): DEPTH × Δ_min ≥ t_setup + K·t_calc for every
/// TDM axis count and the baseline (one axis per shared unit). At 4 it fails for K = 1
/// and 2, where the output timing test's top-rate reversal then underruns.
#[test]
fn fifo_depth_covers_a_setup_at_the_minimum_period() {
    use tdm_stepper::export::{Arch, ExportOptions, BASELINE_AXES, FIFO_DEPTH, RADIX_BITS};
    use tdm_stepper::hdl::core::t_setup;
    let worst_setup = t_setup(RADIX_BITS, true).max(t_setup(RADIX_BITS, false)) as u64;
    for arch in [Arch::Tdm, Arch::Baseline] {
        for axes in 1..=16 {
            if arch == Arch::Baseline && !BASELINE_AXES.contains(&axes) {
                continue;
            }
            let o = ExportOptions { axes, arch, ..Default::default() };
            let served = if arch == Arch::Tdm { axes as u64 } else { 1 };
            let round_trip = served * t_calc_sqrt(RADIX_BITS) as u64;
            let slack = FIFO_DEPTH as u64 * o.min_period_ticks();
            assert!(
                slack >= worst_setup + round_trip,
                "{arch:?} K = {axes}: {FIFO_DEPTH} periods of {} ticks < t_setup {worst_setup} + round trip {round_trip}",
                o.min_period_ticks()
            );
        }
    }
}

#[test]
fn t_calc_is_what_the_constant_says() {
    assert_eq!(measured_t_calc::<4>(), t_calc_sqrt(4) as u64);
    assert_eq!(measured_t_calc::<2>(), t_calc_sqrt(2) as u64);
    assert!(t_calc_sqrt(4) <= 16, "the <= 16-cycle target at R = 4");
}

/// K axes, each running segments with constant periods Δ on the square-root path
/// (v0 = round(2^32/Δ), T = n·Δ: nearly uniform, so P' is large but fits the root).
fn constant_period_moves(k: usize, delta: u32, n: u32) -> Vec<Vec<Segment>> {
    let v0 = ((1u64 << 32) as f64 / delta as f64).round() as u32;
    let seg = Segment::new(v0, n * delta, n as i32);
    let plan = tdm_stepper::model::SegmentPlan::new(seg);
    assert!(matches!(plan.kind, tdm_stepper::model::PlanKind::Accelerate | tdm_stepper::model::PlanKind::Decelerate));
    assert!(plan.periods().all(|p| p == delta), "periods not all {delta}");
    vec![vec![seg]; k]
}

fn underruns<const K: usize, const RR: usize>(delta: u32) -> bool {
    let axes = constant_period_moves(K, delta, 400);
    let cycles = cycles_for(&axes);
    let ev = events::<K>(&axes, cycles);
    let verilog = generate_verilog(&uut_rq::<K, RR, QDEPTH>());
    let dir = sim_dir(&format!("underrun_k{K}_r{RR}_d{delta}"), Simulator::Verilator);
    let got = run_sparse(Simulator::Verilator, &dir, &verilog, &spec::<K>(), &ev, cycles).unwrap();
    let under = expand(&got, 2, cycles);
    let step = expand(&got, 0, cycles);
    // No step is lost either way.
    for a in 0..K {
        assert_eq!(rises_of(&step, a).len(), 400, "axis {a}, delta {delta}: steps");
    }
    under.iter().any(|&u| u != 0)
}

/// Underrun is flagged exactly when K·t_calc exceeds the (constant) period.
#[test]
fn underrun_exactly_when_k_t_calc_exceeds_the_period() {
    let edge2 = (2 * t_calc_sqrt(R)) as u32;
    assert!(!underruns::<2, R>(edge2), "K = 2, period = K·t_calc: no underrun expected");
    assert!(underruns::<2, R>(edge2 - 1), "K = 2, period = K·t_calc − 1: underrun expected");
    let edge4 = (4 * t_calc_sqrt(R)) as u32;
    assert!(!underruns::<4, R>(edge4), "K = 4, period = K·t_calc: no underrun expected");
    assert!(underruns::<4, R>(edge4 - 1), "K = 4, period = K·t_calc − 1: underrun expected");
}

/// The axis capacity the sweep and the export manifest report (the shortest period
/// an axis sustains, so its highest step rate) is the exported configuration's
/// simulated underrun boundary: none at that period, an underrun one tick below.
#[test]
fn axis_capacity_is_the_exported_cores_underrun_boundary() {
    use tdm_stepper::export::{ExportOptions, RADIX_BITS};
    for (k, min) in [(2usize, ExportOptions { axes: 2, ..Default::default() }.min_period_ticks()), (4, ExportOptions { axes: 4, ..Default::default() }.min_period_ticks())] {
        let rate = tdm_stepper::sweep::max_step_rate_hz(k, 50e6, false);
        assert!((rate - 50e6 / min as f64).abs() < 1e-6, "K = {k}: capacity {rate} steps/s for a {min}-tick period");
        let (ok, under) = match k {
            2 => (underruns::<2, RADIX_BITS>(min as u32), underruns::<2, RADIX_BITS>(min as u32 - 1)),
            _ => (underruns::<4, RADIX_BITS>(min as u32), underruns::<4, RADIX_BITS>(min as u32 - 1)),
        };
        assert!(!ok, "K = {k}: underrun at the reported minimum period {min}");
        assert!(under, "K = {k}: no underrun one tick below the reported minimum period {min}");
    }
}

#[test]
fn fsm_state_constants_are_a_gray_sequence() {
    let verilog = generate_verilog(&uut::<2>());
    // `localparam  k_pick = 5'b0;` ... in declaration order (the order of STATES), in
    // the core's own module (`top`; the blocks that decode the state hold copies).
    let core = verilog.split("\nmodule top(").nth(1).expect("module top").split("\nendmodule").next().unwrap();
    let codes: Vec<u64> = core
        .lines()
        .filter_map(|l| l.trim().strip_prefix("localparam")?.trim().strip_prefix("k_"))
        .map(|l| {
            let v = l.split('=').nth(1).unwrap().trim().trim_end_matches(';');
            let (w, rest) = v.split_once('\'').unwrap();
            assert_eq!(w.trim(), STATE_BITS.to_string(), "state width");
            let radix = match &rest[..1] {
                "b" => 2,
                "h" => 16,
                "d" => 10,
                other => panic!("base {other}"),
            };
            u64::from_str_radix(&rest[1..], radix).unwrap()
        })
        .collect();
    assert_eq!(codes.len(), STATES.len(), "one constant per state");
    for w in codes.windows(2) {
        assert_eq!((w[0] ^ w[1]).count_ones(), 1, "{:05b} -> {:05b} is not a Gray step", w[0], w[1]);
    }
    let mut sorted = codes.clone();
    sorted.sort();
    sorted.dedup();
    assert_eq!(sorted.len(), codes.len(), "state codes are distinct");
}

/// One axis's stream of 1 ms segments for a host that plans ahead: a random walk of
/// speeds between rest and `v_max` (accelerating, decelerating and cruising segments),
/// dwells at rest, and a direction change now and then at rest; it ends at rest. Each
/// segment starts at the end speed of the one before (rounded down to Q0.32; one that
/// aimed at rest ends below 2^33/T and the next starts from 0).
fn streaming_segments(t: u32, v_max: u64, count: usize, seed: u64) -> Vec<Segment> {
    let mut rng = Rng(seed);
    let two32 = 1u64 << 32;
    let (mut v, mut reverse) = (0u64, false);
    let mut segs = Vec::with_capacity(count);
    // The end speed lands up to one step's worth (2^33/T) above the aim: aim below v_max.
    let top = v_max - (2 * two32).div_ceil(t as u64);
    for j in 0..count {
        let aim = match rng.next() % 6 {
            _ if j + 1 == count => 0,
            0 => 0,
            1 => v.min(top),
            2 => top,
            _ => rng.next() % (top + 1),
        };
        if v == 0 && (aim == 0 || rng.next() % 2 == 0) {
            if rng.next() % 2 == 0 {
                reverse = !reverse;
            }
            segs.push(Segment::dwell(t));
            continue;
        }
        // θ = ⌈(v + aim)·T / 2^33⌉, so the end speed 2θ/T − v is at least `aim` (never
        // below rest) and below v_max.
        let n = ((v + aim) as u128 * t as u128).div_ceil(2 * two32 as u128) as u64;
        segs.push(Segment::new(v as u32, t, if reverse { -(n as i32) } else { n as i32 }));
        v = ((2 * n as u128 * two32 as u128 - v as u128 * t as u128) / t as u128) as u64;
        if aim == 0 {
            // Below one step per T/2: the host counts the axis at rest.
            v = 0;
        }
        assert!(v <= v_max, "end speed {v} above {v_max}");
    }
    segs
}

/// Streaming, the way a LinuxCNC- or Klipper-style host drives a step generator: 16
/// axes, each fed 100 segments of 1 ms at the export's default 50 MHz clock (100 ms)
/// at up to half the documented maximum step rate (twice `min_period_ticks`), pushed
/// as the move goes on, about eight segments ahead, so that no queue ever holds all of
/// them. Every segment is accepted, no axis underruns, every edge equals the model.
#[test]
fn sixteen_axes_stream_one_ms_segments_for_100_ms() {
    use tdm_stepper::export::{ExportOptions, QUEUE_DEPTH, RADIX_BITS};
    const K: usize = 16;
    const COUNT: usize = 100;
    const AHEAD: usize = 8;
    let opts = ExportOptions { axes: K, ..Default::default() };
    let t = opts.clock_hz / 1000;
    let v_max = (1u64 << 32) / (2 * opts.min_period_ticks());
    let limits = Limits::default();
    let axes: Vec<Vec<Segment>> = (0..K).map(|a| streaming_segments(t, v_max, COUNT, 0x5713_ea11 + a as u64)).collect();
    for (a, segs) in axes.iter().enumerate() {
        assert!(segs.iter().all(|s| s.validate(&limits).is_ok()), "axis {a}: the stream holds an invalid segment");
        let run = AxisRun::run(segs, &limits);
        assert!(run.end_tick >= 100 * t as u64, "axis {a}: the stream is shorter than 100 ms");
        let shortest = run.edge_ticks.windows(2).map(|w| w[1] - w[0]).min().unwrap();
        assert!(shortest >= 2 * opts.min_period_ticks() - 1, "axis {a}: a {shortest}-tick period is above half the maximum rate");
    }
    // The stream covers what the issue asks for on every axis.
    let kinds = |segs: &[Segment]| {
        let acc = segs.iter().any(|s| s.steps != 0 && (2 * (s.steps.unsigned_abs() as u64) << 32) > 2 * s.v0_rate as u64 * s.t_ticks as u64);
        let dec = segs.iter().any(|s| s.steps != 0 && (2 * (s.steps.unsigned_abs() as u64) << 32) < 2 * s.v0_rate as u64 * s.t_ticks as u64);
        let dwell = segs.iter().any(|s| s.steps == 0);
        let both = segs.iter().any(|s| s.steps > 0) && segs.iter().any(|s| s.steps < 0);
        acc && dec && dwell && both
    };
    for (a, segs) in axes.iter().enumerate() {
        assert!(kinds(segs), "axis {a} lacks acceleration, deceleration, dwells or both directions");
    }

    // Reset, the first AHEAD segments of every axis, a synchronised start, then each
    // later segment j pushed (j − AHEAD) ms after the start: its queue holds about AHEAD.
    let cycles = cycles_for(&axes);
    let mut ev = events::<K>(&axes.iter().map(|s| s[..AHEAD].to_vec()).collect::<Vec<_>>(), cycles);
    let start = ev.iter().find(|e| e.1[6] == 1).unwrap().0;
    for j in AHEAD..COUNT {
        for (a, segs) in axes.iter().enumerate() {
            let s = segs[j].effective();
            let c = start + (j - AHEAD) as u64 * t as u64 + 2 + 2 * a as u64;
            ev.push((c, vec![0, 1, a as u128, s.v0_rate as u128, s.t_ticks as u128, s.steps as u32 as u128, 0, 0, 0, 0, 0, 0]));
            ev.push((c + 1, vec![0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]));
        }
    }
    ev.sort_by_key(|e| e.0);
    assert!(ev.windows(2).all(|w| w[0].0 < w[1].0), "two stimulus events on one cycle");
    let verilog = generate_verilog(&uut_rq::<K, RADIX_BITS, QUEUE_DEPTH>());
    let dir = sim_dir("core_k16_streaming", Simulator::Verilator);
    let got = run_sparse(Simulator::Verilator, &dir, &verilog, &spec::<K>(), &ev, cycles).unwrap();
    check_against_model::<K>(&axes, &got, cycles, "16-axis streaming");
}

/// The per-axis stop: axis 1 is stopped in the middle of its moves (`stop_axes` high
/// for three cycles) while axis 0 runs on. Axis 0's edges are all the model's; axis 1's
/// are the model's up to the stop and none rises after it; its queue is emptied
/// (every segment counted taken), BUSY drops, the position read is its edge count;
/// then a new segment pushed and started on axis 1 alone runs exactly as the model's
/// from its own release. rust-hdl and Verilator give the same trace.
#[test]
fn one_axis_stops_and_the_other_runs_on() {
    const K: usize = 2;
    let limits = Limits::default();
    let axes = moves();
    let run1 = AxisRun::run(&axes[1], &limits);
    let after = plan(-60, [3000, 1000, 3000]);
    let run_after = AxisRun::run(&after, &limits);
    let cycles = cycles_for(&axes) + run_after.end_tick + 6000;
    let mut ev = events::<K>(&axes, cycles);
    let start_cycle = ev.iter().find(|e| e.1[6] == 1).unwrap().0;
    // Mid-move on axis 1 (its release comes a few hundred cycles after the START).
    let stop = start_cycle + 300 + run1.edge_ticks[run1.edge_ticks.len() / 2];
    let idle = |stop_bits: u128| vec![0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, stop_bits];
    let restart = stop + 2000;
    let mut extra = vec![(stop, idle(0b10)), (stop + 3, idle(0))];
    let feed = core_feed(&after);
    for (j, sgm) in feed.iter().enumerate() {
        extra.push((restart + j as u64, vec![0, 1, 1, sgm.v0_rate as u128, sgm.t_ticks as u128, sgm.steps as u32 as u128, 0, 0, 0, 0, 0, 0]));
    }
    let go = restart + feed.len() as u64;
    extra.push((go, vec![0, 0, 0, 0, 0, 0, 1, 0b10, 0, 0, 0, 0]));
    extra.push((go + 1, idle(0)));
    ev.extend(extra);
    ev.sort_by_key(|e| e.0);

    let with_stops = || connect_core!(TdmCore::<K, R, DEPTH, QDEPTH>::new().with_axis_stops());
    let reference = rust_hdl_trace!(with_stops(), &ev, cycles);
    let got = run_sparse(Simulator::Verilator, &sim_dir("core_axis_stop", Simulator::Verilator), &generate_verilog(&with_stops()), &spec::<K>(), &ev, cycles).unwrap();
    same_traces(&got, &reference, "per-axis stop");

    let step = expand(&reference, 0, cycles);
    let busy = expand(&reference, 3, cycles);
    let pos = expand(&reference, 4, cycles);
    let run0 = AxisRun::run(&axes[0], &limits);
    let r0 = rises_of(&step, 0);
    assert_eq!(r0.len(), run0.edge_ticks.len(), "axis 0 ran all its steps");
    let l0 = release_of(&r0, &run0.edge_ticks, "axis 0").unwrap();
    let r1 = rises_of(&step, 1);
    let before: Vec<u64> = r1.iter().copied().filter(|&c| c < restart).collect();
    assert!(before.len() > 5 && before.len() < run1.edge_ticks.len() - 5, "axis 1 stopped mid-move after {} edges", before.len());
    assert_eq!(release_of(&before, &run1.edge_ticks, "axis 1 before the stop"), Some(l0), "axis 1's edges before the stop (and no skew)");
    assert!(*before.last().unwrap() <= stop, "axis 1: an edge at cycle {} after the stop at {stop}", before.last().unwrap());
    // BUSY drops once the pulse the stop caught (if any) has had its high time.
    let low_from = (stop..restart).find(|&c| (step[c as usize] >> 1) & 1 == 0).unwrap();
    let idle_from = (stop..restart).find(|&c| (busy[c as usize] >> 1) & 1 == 0).expect("axis 1 stays busy after the stop");
    assert!(idle_from <= low_from.max(stop) + 3, "axis 1 busy until {idle_from}, STEP low from {low_from}, stop at {stop}");
    assert!((idle_from..restart).all(|c| (busy[c as usize] >> 1) & 1 == 0 && (step[c as usize] >> 1) & 1 == 0), "axis 1 busy or stepping again before the restart");
    let later: Vec<u64> = r1.iter().copied().filter(|&c| c >= restart).collect();
    assert_eq!(later.len(), run_after.edge_ticks.len(), "axis 1's move after the stop");
    release_of(&later, &run_after.edge_ticks, "axis 1 after the stop").unwrap();
    // Status at the end (sel_axis reads each axis): positions and counts.
    let sel1 = (cycles - 2 + 1) as usize;
    let dir_sign = |segs: &[Segment]| if segs.iter().find(|s| s.steps != 0).unwrap().steps < 0 { -1 } else { 1 };
    assert_eq!(dir_sign(&axes[1][..1]), 1);
    // Axis 1's moves before the stop: the edges emitted, each with its segment's sign.
    let signed_before: i64 = {
        let mut k = 0usize;
        let mut p = 0i64;
        for sgm in &core_feed(&axes[1]) {
            for _ in 0..sgm.steps.unsigned_abs() {
                if k < before.len() {
                    p += sgm.steps.signum() as i64;
                    k += 1;
                }
            }
        }
        p
    };
    assert_eq!(pos[sel1] as u32 as i32 as i64, signed_before + run_after.position, "axis 1's position: the edges before the stop, then the new move");
    let taken = expand(&reference, 7, cycles)[sel1];
    assert_eq!(taken, (core_feed(&axes[1]).len() + feed.len()) as u128, "axis 1: every segment taken (the stopped ones flushed)");
}

/// The S-curve core's ports: the controlled stop's, and `cmd_extra`.
fn spec_poly<const K: usize>() -> TbSpec {
    let mut s = spec_cs::<K>();
    s.inputs.push(Port::new("cmd_extra", 97));
    s
}

fn uut_poly<const K: usize>() -> TdmCore<K, R, DEPTH, QDEPTH, 1> {
    connect_core!(TdmCore::<K, R, DEPTH, QDEPTH, 1>::new())
}

/// Motions of both kinds for a two-axis core, shortest period about 250 ticks: axis 0
/// a trapezoid move, a cubic from rest to speed and back, a dwell, a cubic in reverse
/// and a trapezoid again; axis 1 a jerk-limited move (seven phases) each way, with
/// a rejected polynomial segment (its speed reverses inside it) between them.
fn mixed_moves() -> Vec<Vec<Motion>> {
    mixed_moves_slower(1)
}

/// [`mixed_moves`] `s` times slower (every duration × s, every speed / s).
fn mixed_moves_slower(s: u32) -> Vec<Vec<Motion>> {
    let limits = Limits::default();
    let tr = |v: Vec<Segment>| v.into_iter().map(Motion::from).collect::<Vec<_>>();
    let v1 = ((1u64 << 32) / (250 * s as u64)) as u32;
    let cubic = |v0, v1, t: u32, n| Motion::from(PolySegment::cubic(v0, v1, t * s, n).unwrap());
    let f = s as f64;
    let jl = |steps| {
        tdm_stepper::model::scurve::jerk_limited(steps, 0.0, 0.0, 4000.0 / f, 4.0e5 / (f * f), 8.0e7 / (f * f * f), 3.0e5 / (f * f), 6.0e7 / (f * f * f), 1_000_000, &limits)
            .unwrap()
    };
    let sc = |t: [u32; 3]| t.map(|x| x * s);
    vec![
        [
            tr(plan(20, sc([3000, 1000, 3000]))),
            vec![cubic(0, v1, 3000, 6), cubic(v1, 0, 3000, 6), Segment::dwell(2000 * s).into(), cubic(0, 0, 4000, -5)],
            tr(plan(-12, sc([2000, 500, 2000]))),
        ]
        .concat(),
        [jl(60), vec![Motion::from(PolySegment::new(0, 0, -(40i64 << 32), 3000 * s, 5))], jl(-45)].concat(),
    ]
}

/// The S-curve core (S = 1) runs trapezoid and polynomial segments mixed on two axes,
/// every edge the model's, in rust-hdl and in Verilator (the same trace).
#[test]
fn mixed_trapezoid_and_polynomial_segments_match_the_model() {
    const K: usize = 2;
    let axes = mixed_moves();
    let limits = Limits::default();
    let rejected: usize = axes.iter().map(|a| AxisRun::run_motions(a, &limits).rejected.len()).sum();
    assert_eq!(rejected, 1, "the move list has its one rejected segment");
    let poly: usize = axes.iter().flatten().filter(|m| matches!(m, Motion::Poly(_))).count();
    assert!(poly >= 10, "{poly} polynomial segments");
    let cycles = cycles_for_motions(&axes);
    let ev = events_poly::<K>(&axes, cycles);
    let reference = rust_hdl_trace!(uut_poly::<K>(), &ev, cycles);
    check_motions::<K>(&axes, &reference, cycles, "S-curve core, rust-hdl");
    // The scheduler's time per polynomial setup and period, from the state trace:
    // S_CHECK to S_COMMIT_SETUP for a setup, PICK to S_COMMIT_STEP for a period.
    let code = |n: &str| gray(STATES.iter().position(|s| *s == n).unwrap()) as u128;
    let st = expand(&reference, 6, cycles);
    let run_to = |c: usize, end: &str| (c..st.len()).find(|&e| st[e] == code(end)).unwrap() - c + 1;
    // (S_ISSUE_VT branches to Y_SETUP on the lane's registered flag, the cycle after
    // S_CHECK.)
    let setups: Vec<usize> = (2..st.len())
        .filter(|&c| st[c] == code("Y_SETUP") && st[c - 1] != code("Y_SETUP"))
        .map(|c| {
            assert!(st[c - 1] == code("S_ISSUE_VT") && st[c - 2] == code("S_CHECK"), "Y_SETUP at {c} follows S_CHECK, S_ISSUE_VT");
            run_to(c - 2, "S_COMMIT_SETUP")
        })
        .collect();
    let periods: Vec<usize> = (1..st.len()).filter(|&c| st[c] == code("Y_WAIT") && st[c - 1] == code("PICK")).map(|c| run_to(c - 1, "S_COMMIT_STEP")).collect();
    let fed = |f: &dyn Fn(&PolySegment) -> bool| axes.iter().flat_map(|a| motion_feed(a)).filter(|m| matches!(m, Motion::Poly(p) if f(p))).count();
    assert_eq!(setups.len(), fed(&|p| p.steps != 0), "one lane setup per polynomial segment with steps");
    assert!(setups.iter().all(|&l| l == T_POLY_SETUP), "setups {setups:?} take T_POLY_SETUP = {T_POLY_SETUP}");
    let n_poly: u32 = axes.iter().flat_map(|a| motion_feed(a)).map(|m| if let Motion::Poly(p) = m { p.n_steps() } else { 0 }).sum();
    assert_eq!(periods.len() as u32, n_poly, "one lane request per polynomial step");
    let lasts = periods.iter().filter(|&&l| l == T_POLY_LAST).count();
    assert_eq!(lasts, fed(&|p| p.steps != 0), "one last step (no search) per segment");
    assert!(periods.iter().all(|&l| l == T_POLY_LAST || l >= t_poly_step(1)), "a searched period takes t_poly_step(search)");
    let verilog = generate_verilog(&uut_poly::<K>());
    let got = run_sparse(Simulator::Verilator, &sim_dir("core_poly_k2", Simulator::Verilator), &verilog, &spec_poly::<K>(), &ev, cycles).unwrap();
    check_motions::<K>(&axes, &got, cycles, "S-curve core, Verilator");
    same_traces(&got, &reference, "S-curve core");
}

/// The same on K = 1, 4 and 8 axes (Verilator), the two axes' moves cycled over the
/// axes and slowed down K times (K = 1: as for K = 2), every edge the model's (K = 16:
/// the streaming test below).
#[test]
fn mixed_segments_on_one_four_eight_and_sixteen_axes() {
    fn run<const K: usize>() {
        let two = mixed_moves_slower(K.max(2) as u32 / 2);
        let axes: Vec<Vec<Motion>> = (0..K).map(|a| two[a % 2].clone()).collect();
        let cycles = cycles_for_motions(&axes);
        let ev = events_poly::<K>(&axes, cycles);
        let name = format!("core_poly_k{K}");
        let got = run_sparse(Simulator::Verilator, &sim_dir(&name, Simulator::Verilator), &generate_verilog(&uut_poly::<K>()), &spec_poly::<K>(), &ev, cycles).unwrap();
        check_motions::<K>(&axes, &got, cycles, &name);
    }
    run::<1>();
    run::<4>();
    run::<8>();
}

/// The streaming test of the S-curve option: K = 16 axes, each fed (as its queue
/// drains, never more than QDEPTH − 3 segments waiting) a mix of jerk-limited,
/// fourth-order, trapezoid and cubic segments and dwells for 5.2 M ticks (over 100 ms
/// at 50 MHz), at half the documented S-curve maximum rate (a period of at least
/// 2·K·POLY_T_CALC = 3,200 ticks; every axis reaches 93 % of that rate). No underrun,
/// no refused command, every edge the model's from one release tick on every axis,
/// and each axis's position and segment counts at the end (Verilator, the core with
/// DEPTH = 4 period FIFO entries).
#[test]
fn sixteen_axes_stream_mixed_segments_at_half_the_scurve_rate() {
    use tdm_stepper::export::POLY_T_CALC;
    use tdm_stepper::model::scurve::{fourth_order, jerk_limited};
    const K: usize = 16;
    const HZ: u32 = 50_000_000;
    let min_period = 2 * K as u32 * POLY_T_CALC as u32;
    let half = Limits::new(min_period).unwrap(); // RMAX = 2^32 / (3,200 + 1)
    let vh = HZ as f64 / min_period as f64; // 15,625 steps/s
    let rate = |v: f64| (v / HZ as f64 * 2f64.powi(32)) as u32;
    let span = |ms: &[Motion]| ms.iter().map(|m| m.t_ticks() as u64).sum::<u64>();
    let mut axes: Vec<Vec<Motion>> = Vec::new();
    for a in 0..K {
        let f = 1.0 - a as f64 / 400.0;
        let sign = if a % 2 == 0 { 1 } else { -1 };
        let v1 = rate(0.95 * vh * f);
        let t = 150_000 + 10_000 * a as u32;
        let n = (v1 as u64 * t as u64 >> 33) as i32;
        let cubic = |v0, v1, n| Motion::from(PolySegment::cubic(v0, v1, t, n).unwrap());
        let s32 = sign as i32;
        let moves: Vec<Vec<Motion>> = vec![
            jerk_limited(sign * 700, 0.0, 0.0, 0.99 * vh * f, 2.0e6 * f, 4.0e8 * f, 1.5e6, 3.0e8, HZ, &half).unwrap(),
            planner::trapezoid_by_rates(-sign * 400, (0.97 * vh * f) as u32, (1.5e6 * f) as u32, 2_000_000, HZ, &half).unwrap().into_iter().map(Motion::from).collect(),
            vec![cubic(0, v1, s32 * n), cubic(v1, v1, s32 * 2 * n), cubic(v1, 0, s32 * n), Segment::dwell(40_000 + 1_000 * a as u32).into()],
            fourth_order(-sign * 500, 0.97 * vh, 2.5e6, 6.0e8, 2.0e11, HZ, &half).unwrap(),
            planner::trapezoid_by_rates(sign * 250, (0.9 * vh) as u32, 3_000_000, (1.0e6 * f) as u32, HZ, &half).unwrap().into_iter().map(Motion::from).collect(),
            // From rest to half speed, then on from there to rest.
            [
                jerk_limited(sign * 300, 0.0, 0.5 * vh, 0.97 * vh, 1.0e6, 2.0e8, 1.0e6, 2.0e8, HZ, &half).unwrap(),
                jerk_limited(sign * 300, 0.5 * vh, 0.0, 0.98 * vh * f, 1.0e6, 2.0e8, 2.0e6, 5.0e8, HZ, &half).unwrap(),
            ]
            .concat(),
        ];
        // Each axis opens with one of the trapezoid moves, then cycles through the list.
        let mut ms: Vec<Motion> = moves[if a % 2 == 0 { 1 } else { 4 }].clone();
        let mut k = a;
        while span(&ms) < 5_200_000 {
            ms.extend(moves[k % moves.len()].iter().copied());
            k += 1;
        }
        assert!(ms.iter().all(|m| m.validate(&half).is_ok()), "axis {a}: every segment within half the S-curve rate");
        let moving_traps = ms.iter().filter(|m| matches!(m, Motion::Trapezoid(s) if s.steps != 0)).count();
        let polys = ms.iter().filter(|m| matches!(m, Motion::Poly(_))).count();
        assert!(moving_traps >= 2 && polys >= 5, "axis {a}: a mix ({moving_traps} trapezoid, {polys} polynomial segments)");
        axes.push(ms);
    }
    // Every axis reaches 93 % of the half rate: its shortest period is at most 3,440 ticks.
    let limits = Limits::default();
    let runs: Vec<AxisRun> = axes.iter().map(|ms| AxisRun::run_motions(ms, &limits)).collect();
    for (a, run) in runs.iter().enumerate() {
        let shortest = run.edge_ticks.windows(2).map(|w| w[1] - w[0]).min().unwrap();
        assert!(shortest >= min_period as u64 && shortest as f64 <= min_period as f64 / 0.93, "axis {a}: shortest period {shortest}");
    }
    let polys: usize = axes.iter().flatten().filter(|m| matches!(m, Motion::Poly(_))).count();
    let traps: usize = axes.iter().flatten().filter(|m| matches!(m, Motion::Trapezoid(_))).count();
    // The pushes: the first P of each axis before START, then segment j once segment
    // j − P + 1 has started (model time + 20,000 cycles for the release): at most
    // P − 1 = QDEPTH − 3 waiting.
    const P: usize = QDEPTH - 2;
    let idle = |sel: u128| vec![0, 0, 0, 0, 0, 0, 0, 0, sel, 0, 0, 0, 0, 0, 0];
    let push = |a: usize, m: &Motion| {
        let [v0, t, steps, extra] = command_of(m);
        vec![0, 1, a as u128, v0, t, steps, 0, 0, 0, 0, 0, 0, 0, 0, extra]
    };
    let feed: Vec<Vec<Motion>> = axes.iter().map(|ms| motion_feed(ms)).collect();
    assert!(feed.iter().zip(&axes).all(|(f, ms)| f.len() == ms.len()));
    let mut rows: std::collections::BTreeMap<u64, Vec<u128>> = std::collections::BTreeMap::new();
    rows.insert(0, [vec![1], idle(0)[1..].to_vec()].concat());
    let mut c = 3u64;
    for (a, ms) in feed.iter().enumerate() {
        for m in &ms[..P.min(ms.len())] {
            c += 1;
            rows.insert(c, push(a, m));
        }
    }
    let mut go = idle(0);
    go[6] = 1;
    go[7] = (1u128 << K) - 1;
    c += 1;
    rows.insert(c, go);
    let go_cycle = c;
    let mut later: Vec<(u64, usize, usize)> = Vec::new();
    for (a, ms) in axes.iter().enumerate() {
        let starts: Vec<u64> = ms.iter().scan(0u64, |t, m| { let s = *t; *t += m.t_ticks() as u64; Some(s) }).collect();
        for j in P..ms.len() {
            later.push((go_cycle + 20_000 + starts[j + 1 - P], a, j));
        }
    }
    later.sort();
    let mut last = go_cycle;
    for (want, a, j) in later {
        let at = want.max(last + 2);
        rows.insert(at, push(a, &feed[a][j]));
        last = at;
    }
    let cycles = runs.iter().map(|r| r.end_tick).max().unwrap() + 40_000;
    assert!(last + 10_000 < cycles - 2 * K as u64);
    let pushes: Vec<u64> = rows.iter().filter(|(_, r)| r[1] == 1).map(|(&c, _)| c).collect();
    for p in pushes {
        rows.entry(p + 1).or_insert_with(|| idle(0));
    }
    rows.entry(go_cycle + 1).or_insert_with(|| idle(0));
    for a in 0..K {
        rows.insert(cycles - 2 * (K - a) as u64, idle(a as u128));
    }
    let ev: Vec<(u64, Vec<u128>)> = rows.into_iter().collect();
    // The spec without the state trace (it would change every few cycles for 5 M cycles).
    let mut sp = spec_poly::<K>();
    sp.outputs.retain(|p| p.name != "fsm_state");
    let name = "core_poly_stream_k16";
    let got = run_sparse(Simulator::Verilator, &sim_dir(name, Simulator::Verilator), &generate_verilog(&uut_poly::<K>()), &sp, &ev, cycles).unwrap();
    check_motion_columns::<K>(&axes, &got, cycles, name, [0, 2, 4, 5, 6, 7]);
    let steps: usize = runs.iter().map(|r| r.edge_ticks.len()).sum();
    println!("{name}: {cycles} cycles, {polys} polynomial and {traps} trapezoid segments, {steps} steps over {K} axes, no underrun");
    assert!(polys > 10 * K && traps > 2 * K, "a mix: {polys} polynomial, {traps} trapezoid segments");
}

/// The controlled-stop core's ports: the core's, and `cstop_axes` and `decel`.
fn spec_cs<const K: usize>() -> TbSpec {
    let mut s = spec::<K>();
    s.inputs.push(Port::new("cstop_axes", K));
    s.inputs.push(Port::new("decel", 32));
    s
}

/// The controlled stop (model::stop), three ways: axis 1 runs a move of each kind and
/// is stopped in it (accelerating, cruising, decelerating, an exactly uniform segment,
/// a dwell between two moves, within a few steps of a segment's end, and near the top
/// rate the test's two-axis core sustains) while axis 0 runs its moves untouched. For
/// each stop, the edges of axis 1 are exactly the model's cut of the move after c
/// FIFO entries followed by the model's stop segment from the last of them
/// (model::stop::cut_run), with c at most DEPTH + 3 entries past the edges emitted
/// when the stop was requested (in the dwell, the axis at rest: it stops as the hard
/// stop does, after the dwell's entry); the axis ends at rest (BUSY low) with its position the
/// edges emitted, and no underrun. The scheduler's state trace shows the ramp's
/// formation taking `t_stop_form(R)` cycles from the PICK that took the request.
/// In the first (accelerating) the request is held as a level past the ramp's end, as
/// a limit in controlled mode holds it, and a segment is pushed while the ramp runs:
/// the ramp is not cut again and the segment is dropped (StopRamp's `stopping`).
/// rust-hdl and Verilator give the same trace up to the end of that first stop.
#[test]
fn controlled_stop_ramps_down_from_every_kind_of_segment() {
    controlled_stop_scenarios::<2>(true);
}

/// The same scenarios on a one-axis core (Verilator; the model's edges as above): with
/// K = 1 the scheduler reads an axis's last period in the cycle after its write, which
/// `StopRamp` serves from the write's register (a bypass only K = 1 builds).
#[test]
fn controlled_stop_ramps_down_on_a_one_axis_core() {
    controlled_stop_scenarios::<1>(false);
}

/// The controlled stop on the S-curve core (S = 1 with the stop, as an export with
/// both options builds it; Verilator): axis 1 runs a jerk-limited move (polynomial
/// segments, the next ones queued behind the running one) and is stopped in its
/// acceleration, at cruise and in its deceleration, while axis 0 runs its mixed moves
/// untouched. Each time the edges are exactly the model's cut of the move followed by
/// the trapezoid ramp from the last period (model::stop::cut_run), the queued
/// polynomial segments are dropped (the ramp's setup, which enters S_ISSUE_VT from C_T
/// with axis 1's stale queue head under the read port, never goes to the lane), the
/// axis ends at rest with its position the edges emitted, and nothing underruns.
#[test]
fn controlled_stop_ramps_down_from_polynomial_segments() {
    use tdm_stepper::model::stop::stop_segment;
    const K: usize = 2;
    let (ax, bit) = (1usize, 2u128);
    let limits = Limits::default();
    let decel: u32 = u32::MAX;
    let mv = tdm_stepper::model::scurve::jerk_limited(300, 0.0, 0.0, 4000.0, 4.0e5, 8.0e7, 3.0e5, 6.0e7, 1_000_000, &limits).unwrap();
    assert!(mv.iter().filter(|m| matches!(m, Motion::Poly(_))).count() >= 5, "the move is polynomial segments: {mv:?}");
    let run = AxisRun::run_motions(&mv, &limits);
    let n = run.edge_ticks.len();
    let scenarios = [("accelerating", run.edge_ticks[4]), ("cruising", run.edge_ticks[n / 2]), ("decelerating", run.edge_ticks[n - 25])];
    let axis0 = mixed_moves()[0].clone();
    let row = |cmd: Option<(usize, &Motion)>, start: u128, cstop: u128| -> Vec<u128> {
        let (v, a, c) = match cmd {
            Some((a, m)) => (1, a as u128, command_of(m)),
            None => (0, 0, [0; 4]),
        };
        vec![0, v, a, c[0], c[1], c[2], (start != 0) as u128, start, ax as u128, 0, 0, 0, cstop, decel as u128, c[3]]
    };
    let mut ev: Vec<(u64, Vec<u128>)> = vec![(0, [vec![1], row(None, 0, 0)[1..].to_vec()].concat()), (3, row(None, 0, 0))];
    let mut c = 3u64;
    for m in motion_feed(&axis0) {
        c += 1;
        ev.push((c, row(Some((0, &m)), 0, 0)));
    }
    let slowest = run.fifo.iter().map(|e| e.ticks as u64).max().unwrap();
    let ramp = run.fifo.iter().filter(|e| e.step).filter_map(|e| stop_segment(e.ticks, decel, e.reverse)).map(|s| s.t_ticks as u64).max().unwrap_or(0);
    let mut windows = Vec::new();
    for (k, (what, at)) in scenarios.iter().enumerate() {
        for m in motion_feed(&mv) {
            c += 1;
            ev.push((c, row(Some((ax, &m)), 0, 0)));
        }
        c += 1;
        ev.push((c, row(None, if k == 0 { 3 } else { bit }, 0)));
        ev.push((c + 1, row(None, 0, 0)));
        let stop = c + 1000 + at;
        ev.push((stop, row(None, 0, bit)));
        ev.push((stop + 1, row(None, 0, 0)));
        let end = stop + (DEPTH as u64 + 3) * slowest + ramp + 4000;
        windows.push((*what, c, stop, end));
        c = end;
    }
    let cycles = c + 10;
    let uut = connect_core!(TdmCore::<K, R, DEPTH, QDEPTH, 1>::new().with_controlled_stop());
    let got = run_sparse(Simulator::Verilator, &sim_dir("core_poly_cstop", Simulator::Verilator), &generate_verilog(&uut), &spec_poly::<K>(), &ev, cycles).unwrap();
    let step = expand(&got, 0, cycles);
    let under = expand(&got, 2, cycles);
    let busy = expand(&got, 3, cycles);
    let pos = expand(&got, 4, cycles);
    let fsm = expand(&got, 6, cycles);
    let r0 = rises_of(&step, 0);
    let run0 = AxisRun::run_motions(&axis0, &limits);
    assert_eq!(r0.len(), run0.edge_ticks.len(), "axis 0 ran all its steps");
    release_of(&r0, &run0.edge_ticks, "axis 0").unwrap();
    let code = |name: &str| gray(STATES.iter().position(|s| *s == name).unwrap()) as u128;
    let r1 = rises_of(&step, ax);
    let t = StopTrace { busy: &busy, pos: &pos, under: &under };
    let mut position = 0i64;
    let mut quiet = 0;
    for (what, from, stop, end) in &windows {
        let (rises, _, _, _, m) = check_stop_window(what, &run, &r1, (*from, *stop, *end), ax, decel, &t, &mut position);
        assert_eq!(m.accepted.len(), 1, "{what}: a stop ramp was formed");
        assert!(rises.len() != n || m.position != run.position, "{what}: the stop changed nothing");
        // With axis 0 at rest, the lane set up no segment after the stop (axis 1's
        // queue was dropped).
        if (*stop..*end).all(|x| busy[x as usize] & 1 == 0) {
            quiet += 1;
            assert!((*stop..*end).all(|x| fsm[x as usize] != code("Y_SETUP")), "{what}: a polynomial setup after the stop");
        }
    }
    assert!(quiet >= 2, "{quiet} windows with axis 0 at rest");
}

/// Axis K − 1 runs the scenarios (axis 0 of a two-axis core runs its moves alongside);
/// `rust_hdl`: compare the first scenarios' trace with rust-hdl's too.
fn controlled_stop_scenarios<const K: usize>(rust_hdl: bool) {
    use tdm_stepper::hdl::core::{gray, t_stop_form};
    use tdm_stepper::model::stop::stop_segment;
    let ax = K - 1;
    let bit = 1u128 << ax;
    let limits = Limits::default();
    let decel: u32 = u32::MAX;
    let axes = moves();
    let accel = plan(30, [16_000, 12_000, 16_000]);
    let acc_run = AxisRun::run(&accel, &limits);
    let cruise_end = SegmentPlan::new(accel[0]).n_steps() as usize + SegmentPlan::new(accel[1]).n_steps() as usize;
    let dwell = [plan(12, [8_000, 0, 8_000]), vec![Segment::dwell(30_000)], plan(12, [8_000, 0, 8_000])].concat();
    let fast = plan(-700, [40_000, 20_000, 40_000]);
    // (what, segments, stop at this many ticks after the release)
    let uniform = vec![Segment::new(1 << 22, 51_200, -50)];
    let at_edge = |segs: &[Segment], i: usize| AxisRun::run(segs, &limits).edge_ticks[i];
    // The first three (the held request and the dropped push among them) run in
    // rust-hdl too: it simulates a few thousand cycles a second, and the three took
    // 90 s alone, 6 minutes beside other tests (the rest run in Verilator only).
    let mut scenarios: Vec<(&str, Vec<Segment>, u64)> = vec![
        ("accelerating", accel.clone(), acc_run.edge_ticks[3]),
        ("in a dwell", dwell.clone(), AxisRun::run(&dwell[..dwell.len() - 3], &limits).end_tick + 15_000),
        ("a few steps before a segment's end", accel.clone(), acc_run.edge_ticks[cruise_end - 6]),
        ("cruising", accel.clone(), acc_run.edge_ticks[cruise_end - 8]),
        ("decelerating", accel.clone(), acc_run.edge_ticks[cruise_end - 1]),
        ("uniform", uniform.clone(), at_edge(&uniform, 25)),
        ("near the top rate", fast.clone(), at_edge(&fast, 350)),
    ];
    if K == 1 {
        // The scheduler takes a stop in the PICK right after a commit when the request
        // came while it computed: with K = 1 that PICK reads the axis it has just
        // written. Stops every 5 ticks over an accelerating period put some there.
        for d in (0..150).step_by(5) {
            scenarios.push(("accelerating, stopped at every phase of a period", fast.clone(), at_edge(&fast, 100) + d));
        }
    }
    const RUST_HDL_SCENARIOS: usize = 3;
    let row = |cmd: Option<(u128, &Segment)>, start: bool, cstop: u128| -> Vec<u128> {
        let (v, a, s) = match cmd {
            Some((a, s)) => (1, a, (s.v0_rate as u128, s.t_ticks as u128, s.steps as u32 as u128)),
            None => (0, 0, (0, 0, 0)),
        };
        vec![0, v, a, s.0, s.1, s.2, start as u128, if start { bit } else { 0 }, ax as u128, 0, 0, 0, cstop, decel as u128]
    };
    let mut ev: Vec<(u64, Vec<u128>)> = vec![(0, [vec![1], row(None, false, 0)[1..].to_vec()].concat()), (3, row(None, false, 0))];
    // Axis 0's moves first, released with axis 1's first move.
    let mut c = 3u64;
    if K > 1 {
        for s in core_feed(&axes[0]) {
            c += 1;
            ev.push((c, row(Some((0, &s)), false, 0)));
        }
    }
    let mut windows = Vec::new();
    for (k, (what, segs, at)) in scenarios.iter().enumerate() {
        let run = AxisRun::run(segs, &limits);
        for s in core_feed(segs) {
            c += 1;
            ev.push((c, row(Some((ax as u128, &s)), false, 0)));
        }
        c += 1;
        let mut r = row(None, true, 0);
        if k == 0 {
            r[7] = (1 << K) - 1;
        }
        ev.push((c, r));
        let stop = c + 400 + at;
        ev.push((c + 1, row(None, false, 0)));
        ev.push((stop, row(None, false, bit)));
        let slowest = run.fifo.iter().map(|e| e.ticks as u64).max().unwrap();
        let ramp = run.fifo.iter().filter(|e| e.step).filter_map(|e| stop_segment(e.ticks, decel, e.reverse)).map(|s| s.t_ticks as u64).max().unwrap_or(0);
        let end = stop + (DEPTH as u64 + 3) * slowest + ramp + 4000;
        if k == 0 {
            // The request held as a level (a limit's, in controlled mode) past the
            // ramp's end, and a segment pushed while the ramp runs: the ramp is not cut
            // again and the segment is dropped (the edges are one cut_run's).
            let late = core_feed(&uniform)[0];
            ev.push((stop + 2000, row(Some((ax as u128, &late)), false, bit)));
            ev.push((stop + 2001, row(None, false, bit)));
            ev.push((end - 3000, row(None, false, 0)));
        } else {
            ev.push((stop + 1, row(None, false, 0)));
        }
        windows.push((*what, run, c, stop, end));
        c = end;
    }
    let cycles = c + 10;
    let uut = || connect_core!(TdmCore::<K, R, DEPTH, QDEPTH>::new().with_controlled_stop());
    ev.sort_by_key(|e| e.0);
    let got = run_sparse(Simulator::Verilator, &sim_dir(&format!("core_cstop_k{K}"), Simulator::Verilator), &generate_verilog(&uut()), &spec_cs::<K>(), &ev, cycles).unwrap();
    if rust_hdl {
        let cut_off = windows[RUST_HDL_SCENARIOS - 1].4;
        let ev_short: Vec<_> = ev.iter().filter(|e| e.0 < cut_off).cloned().collect();
        let reference = rust_hdl_trace!(uut(), &ev_short, cut_off);
        let short: Vec<Change> = got.iter().filter(|c| c.0 < cut_off).cloned().collect();
        same_traces(&short, &reference, "controlled stop");
    }

    let step = expand(&got, 0, cycles);
    let under = expand(&got, 2, cycles);
    let busy = expand(&got, 3, cycles);
    let pos = expand(&got, 4, cycles);
    let fsm = expand(&got, 6, cycles);
    if K > 1 {
        // Axis 0 untouched.
        let run0 = AxisRun::run(&axes[0], &limits);
        let r0 = rises_of(&step, 0);
        assert_eq!(r0.len(), run0.edge_ticks.len(), "axis 0 ran all its steps");
        release_of(&r0, &run0.edge_ticks, "axis 0").unwrap();
    }
    let r1 = rises_of(&step, ax);
    let st = |name: &str| gray(STATES.iter().position(|s| *s == name).unwrap()) as u128;
    let t = StopTrace { busy: &busy, pos: &pos, under: &under };
    let mut position = 0i64;
    for (what, run, from, stop, end) in &windows {
        let (rises, emitted, e0, cut, m) = check_stop_window(what, run, &r1, (*from, *stop, *end), ax, decel, &t, &mut position);
        if *what == "in a dwell" {
            // At rest in the dwell: stopped as the hard stop does, with no edge after it.
            assert_eq!((m.accepted.len(), rises.len(), cut), (0, emitted, e0 + 1), "{what}: the axis stays at rest");
        } else {
            assert_eq!(m.accepted.len(), 1, "{what}: a stop ramp was formed");
            assert!(rises.len() < run.edge_ticks.len() || m.position != run.position, "{what}: the stop changed nothing");
        }
        // The ramp's formation: the first C_V0 after the stop, to the commit that follows.
        if let Some(v0) = (*stop..*end).find(|&x| fsm[x as usize] == st("C_V0")) {
            let commit = (v0..*end).find(|&x| fsm[x as usize] == st("S_COMMIT_SETUP")).unwrap();
            assert_eq!(commit - v0 + 2, t_stop_form(R) as u64, "{what}: PICK to the ramp's commit");
        }
    }
}
