//! Shared by the HDL block tests: stimulus and a cycle-level protocol model for the
//! iterative units (pulse `start` while idle, results `valid` after a fixed latency,
//! `busy` in between, `start` while busy ignored), and pseudo-random numbers.
#![allow(dead_code)]

/// Connects every input of a core (TdmCore or Baseline: the same ports) and wires it up.
macro_rules! connect_core {
    ($u:expr) => {{
        let mut u = $u;
        u.connect_ports();
        u
    }};
}

use tdm_stepper::verify::Simulator;

/// xorshift64: deterministic pseudo-random numbers for stimulus.
pub struct Rng(pub u64);

impl Rng {
    pub fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    pub fn next_u128(&mut self) -> u128 {
        ((self.next() as u128) << 64) | self.next() as u128
    }
}

/// Rows of (start, operands...): each operation starts, then idles for `latency`
/// cycles, with a start pulse and junk operands while busy that must be ignored.
pub fn iterative_stimulus(latency: usize, ops: &[Vec<u128>], junk: impl Fn(&[u128]) -> Vec<u128>) -> Vec<Vec<u128>> {
    let width = ops[0].len();
    let mut rows = vec![vec![0; width + 1]];
    for op in ops {
        rows.push([vec![1], op.clone()].concat());
        for k in 0..latency {
            rows.push([vec![(k == 1) as u128], junk(op)].concat());
        }
    }
    rows
}

/// Expected (results..., valid, busy) per row of an iterative unit that runs
/// `iterations` cycles after its start edge. None where the Verilog may be
/// undefined: everything before the first start, results before the first valid.
pub fn iterative_model(
    iterations: usize,
    rows: &[Vec<u128>],
    results: usize,
    compute: impl Fn(&[u128]) -> Vec<u128>,
) -> Vec<Vec<Option<u128>>> {
    let (mut left, mut done, mut started) = (0usize, false, false);
    let mut shown = vec![0u128; results];
    let mut pending = shown.clone();
    let mut out = Vec::new();
    for row in rows {
        let mut r: Vec<Option<u128>> = shown.iter().map(|&v| (started && done).then_some(v)).collect();
        r.push(started.then_some(done as u128));
        r.push(started.then_some((left > 0) as u128));
        out.push(r);
        if left > 0 {
            left -= 1;
            if left == 0 {
                done = true;
                shown = pending.clone();
            }
        } else if row[0] == 1 {
            left = iterations;
            done = false;
            pending = compute(&row[1..]);
            started = true;
        }
    }
    out
}

/// Compares simulator output with the model row by row. Undefined output is
/// accepted only where the model has no value; at least one result must be checked.
pub fn check(want: &[Vec<Option<u128>>], got: &[Vec<Option<u128>>], what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: cycle count");
    let mut checked = 0;
    for (k, (g, w)) in got.iter().zip(want).enumerate() {
        for (p, w) in w.iter().enumerate() {
            if let Some(w) = w {
                assert_eq!(g[p], Some(*w), "{what}: row {k}, output {p}");
                checked += 1;
            }
        }
    }
    assert!(checked > 0, "{what}: nothing was checked");
}

/// rust-hdl outputs are always defined.
pub fn defined(rows: Vec<Vec<u128>>) -> Vec<Vec<Option<u128>>> {
    rows.into_iter().map(|r| r.into_iter().map(Some).collect()).collect()
}

pub const SIMULATORS: [Simulator; 2] = [Simulator::Verilator, Simulator::Icarus];

/// A scratch folder for one simulator run. CARGO_TARGET_TMPDIR is shared by the debug
/// and release builds of a test, so the folder names the profile too: a release run
/// of a test beside the test command's debug run of it must not read the other's files.
pub fn sim_dir(name: &str, sim: Simulator) -> std::path::PathBuf {
    let profile = if cfg!(debug_assertions) { "debug" } else { "release" };
    std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("{name}_{sim:?}_{profile}"))
}

/// The Verilator simulators the test binaries share, by build stamp
/// (`RunOptions::build_cache`): a core that several tests run is built once.
#[allow(dead_code)]
pub fn verilator_cache() -> std::path::PathBuf {
    std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("verilator_cache")
}

/// Runs a block three ways on `rows`: `want` (the model's outputs per row), the
/// block in a rust-hdl clock loop, and its exported Verilog in every simulator.
pub fn three_ways<B: rust_hdl::prelude::Block>(
    name: &str,
    make: impl Fn() -> B,
    clock: impl FnMut(&mut B, bool),
    set: impl FnMut(&mut B, &[u128]),
    get: impl FnMut(&B) -> Vec<u128>,
    spec: &tdm_stepper::verify::TbSpec,
    rows: &[Vec<u128>],
    want: &[Vec<Option<u128>>],
) {
    let got = tdm_stepper::verify::run_rust_hdl(&mut make(), rows, clock, set, get);
    check(want, &defined(got), &format!("{name}: rust-hdl"));
    let verilog = rust_hdl::prelude::generate_verilog(&make());
    for sim in SIMULATORS {
        let got = tdm_stepper::verify::run(sim, &sim_dir(name, sim), &verilog, spec, rows).unwrap();
        check(want, &got, &format!("{name}: {sim:?}"));
    }
}

/// Runs `verilog` in every simulator on `rows` and holds each trace to the rust-hdl
/// `reference`, row for row from row `skip` on (the reset rows before it may show x),
/// with no undefined output after it.
#[allow(dead_code)] // not every test binary compares traces
pub fn verilog_matches_rust_hdl(
    name: &str,
    verilog: &str,
    spec: &tdm_stepper::verify::TbSpec,
    rows: &[Vec<u128>],
    reference: &[Vec<u128>],
    skip: usize,
) {
    for sim in SIMULATORS {
        let got = tdm_stepper::verify::run(sim, &sim_dir(name, sim), verilog, spec, rows).unwrap();
        for (k, (g, r)) in got.iter().zip(reference).enumerate().skip(skip) {
            let g: Vec<u128> = g.iter().map(|v| v.unwrap_or_else(|| panic!("{name} {sim:?}: x at row {k}"))).collect();
            assert_eq!(&g, r, "{name}: {sim:?} differs from rust-hdl at row {k}");
        }
    }
}

#[allow(unused_imports)] // not every test binary inspects wide values
pub use tdm_stepper::hdl::bits_to_u128;

/// One clock cycle of a rust-hdl block with a `clock` input, by a hand-written loop.
pub fn tick_core<const R: usize, const D: usize, const Q: usize>(u: &mut tdm_stepper::hdl::core::TdmCore<1, R, D, Q>) {
    use rust_hdl::prelude::*;
    u.clock.next = false.into();
    assert!(simulate(u, 100), "rust-hdl simulation did not settle");
    u.clock.next = true.into();
    assert!(simulate(u, 100), "rust-hdl simulation did not settle");
}

/// A one-axis core, reset, with `seg` pushed into its queue and no start: the
/// scheduler sets it up and fills the period FIFO, then waits.
pub fn one_segment_core<const R: usize, const D: usize, const Q: usize>(
    seg: tdm_stepper::model::Segment,
) -> tdm_stepper::hdl::core::TdmCore<1, R, D, Q> {
    let mut u = connect_core!(tdm_stepper::hdl::core::TdmCore::<1, R, D, Q>::new());
    u.reset.next = true;
    tick_core(&mut u);
    tick_core(&mut u);
    u.reset.next = false;
    u.cmd_valid.next = true;
    u.cmd_v0.next = (seg.v0_rate as u64).into();
    u.cmd_t.next = (seg.t_ticks as u64).into();
    u.cmd_steps.next = (seg.steps as u32 as u64).into();
    tick_core(&mut u);
    u.cmd_valid.next = false;
    u
}

/// The FIFO entries of `run` that hold its first `edges` steps (the dwells among them
/// included).
pub fn entries_for_edges(run: &tdm_stepper::model::AxisRun, edges: usize) -> usize {
    (0..=run.fifo.len())
        .find(|&e| run.fifo[..e].iter().filter(|x| x.step).count() == edges)
        .expect("the run has that many edges")
}

/// The controlled stop that gives exactly the STEP rising edges `rises` (clk cycles, the
/// first one the axis's first edge): `model::stop::cut_run` of `run` after c FIFO
/// entries, for the first c in `cuts` whose edges, aligned on the first one, are these.
/// Returns c and the cut run.
pub fn stop_cut_matching(
    run: &tdm_stepper::model::AxisRun,
    rises: &[u64],
    cuts: std::ops::RangeInclusive<usize>,
    decel: u32,
    limits: &tdm_stepper::model::Limits,
) -> Option<(usize, tdm_stepper::model::AxisRun)> {
    let l0 = rises[0] as i64 - 1 - run.edge_ticks[0] as i64;
    cuts.map(|c| (c, tdm_stepper::model::stop::cut_run(run, c, decel, limits))).find(|(_, m)| {
        m.edge_ticks.len() == rises.len() && m.edge_ticks.iter().zip(rises).all(|(&e, &g)| g as i64 == l0 + 1 + e as i64)
    })
}
