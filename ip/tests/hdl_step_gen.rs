//! StepAxis (period FIFO + step generator) against the reference model's vectors:
//! every STEP rising edge at release + 1 + E_i, pulse widths, DIR setup and hold,
//! the final position, and underrun exactly when the FIFO is starved. Every falling
//! STEP edge and DIR change equals the pins model (`model::pulse`), with the default
//! output timing and with one at the minimum period. The rust-hdl
//! simulation and the exported Verilog (Verilator, Icarus) must also produce the
//! same trace, bit for bit. Segment-done and underrun counters, and an abort in
//! the middle of a move (no edge after it, the pulse in flight keeps its high time),
//! and a reset in the middle of a pulse (the pulse finishes, then nothing).

mod common;

use common::*;
use rust_hdl::prelude::*;
use std::path::PathBuf;
use tdm_stepper::hdl::ram_fifo::{pack_entry, ENTRY_BITS};
use tdm_stepper::hdl::step_gen::StepAxis;
use tdm_stepper::model::{pulse, FifoEntry, PulseTiming};
use tdm_stepper::verify::{run_rust_hdl, Port, TbSpec};
use tdm_stepper::vectors::VectorFile;

const DEPTH: usize = 4;
const RESET_ROWS: usize = 3;

#[derive(Clone, Copy, Debug)]
struct Entry {
    ticks: u32,
    step: bool,
    reverse: bool,
    last: bool,
    /// The STEP high time the pulse stage writes into the entry.
    high: u16,
}

/// The FIFO stream of one vector axis, and its expected edges (ticks from release).
fn axis_entries(file: &str, axis: usize) -> (Vec<Entry>, Vec<u64>, i64) {
    axis_entries_with(file, axis, &PulseTiming::default())
}

fn axis_entries_with(file: &str, axis: usize, timing: &PulseTiming) -> (Vec<Entry>, Vec<u64>, i64) {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../vectors").join(file);
    let v: VectorFile = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let a = &v.axes[axis];
    let mut entries = Vec::new();
    for s in a.segments.iter().filter(|s| s.error.is_none()) {
        if s.steps == 0 {
            entries.push(Entry { ticks: s.t_ticks, step: false, reverse: false, last: true, high: 0 });
        }
        for (k, &p) in s.periods.iter().enumerate() {
            entries.push(Entry { ticks: p, step: true, reverse: s.steps < 0, last: k + 1 == s.periods.len(), high: 0 });
        }
    }
    for e in entries.iter_mut() {
        e.high = timing.high_ticks(e.ticks) as u16;
    }
    (entries, a.edge_ticks.clone(), a.final_position)
}

struct Scenario {
    rows: Vec<Vec<u128>>,
    release_row: usize,
}

/// Pushes each entry as early as the FIFO allows (or `starve` cycles later for entry
/// `starve_at`), releases once the first entry is in, and says `more` while entries
/// are still to be pushed. Pops are predicted from the reference edges, which the
/// generator must meet for the prediction (and the test) to hold.
fn scenario(entries: &[Entry], starve_at: Option<(usize, usize)>, abort_row: Option<usize>) -> Scenario {
    let n = entries.len();
    // pop_rows[k]: the row in which entry k is loaded (its pop takes effect at that
    // row's edge). Entry 0 loads on release; entry k + 1 when entry k ends, or the
    // row after its push if that is later (the generator waits for it).
    let mut pushes: Vec<usize> = Vec::with_capacity(n);
    let mut pop_rows: Vec<usize> = Vec::with_capacity(n);
    for k in 0..n {
        let after_previous = pushes.last().map_or(RESET_ROWS, |&r| r + 1);
        // Room: entry k − DEPTH must have been popped in an earlier row.
        let room = if k >= DEPTH { pop_rows[k - DEPTH] + 1 } else { 0 };
        let mut r = after_previous.max(room);
        if let Some((at, extra)) = starve_at {
            if k == at {
                r = r.max(pop_rows[k - 1] + entries[k - 1].ticks as usize + extra);
            }
        }
        pushes.push(r);
        let due = if k == 0 { r + 1 } else { pop_rows[k - 1] + entries[k - 1].ticks as usize };
        pop_rows.push(due.max(r + 1));
    }
    let release_row = pop_rows[0];
    let last = pop_rows[n - 1] + 2 * entries[n - 1].ticks as usize + 4;
    let mut rows = Vec::with_capacity(last);
    let mut next_push = 0;
    for r in 0..last {
        let push = next_push < n && pushes[next_push] == r;
        let entry = if push {
            let e = entries[next_push];
            pack_entry(e.ticks, e.step, e.reverse, e.last, e.high) as u128
        } else {
            0
        };
        let more = (next_push < n) as u128;
        let abort = abort_row == Some(r);
        rows.push(vec![(r < RESET_ROWS) as u128, push as u128, entry, (r == release_row) as u128, more, abort as u128]);
        next_push += push as usize;
    }
    Scenario { rows, release_row }
}

fn uut() -> StepAxis<DEPTH> {
    let mut u = StepAxis::<DEPTH>::default();
    u.clock.connect();
    u.reset.connect();
    u.push.connect();
    u.entry_in.connect();
    u.go.connect();
    u.more.connect();
    u.abort.connect();
    u.connect_all();
    u
}

fn spec() -> TbSpec {
    TbSpec {
        clock: "clock".into(),
        inputs: ["reset", "push"].iter().map(|n| Port::new(n, 1))
            .chain([Port::new("entry_in", ENTRY_BITS)])
            .chain(["go", "more", "abort"].iter().map(|n| Port::new(n, 1)))
            .collect(),
        outputs: vec![
            Port::new("step", 1),
            Port::new("dir", 1),
            Port::new("position", 32),
            Port::new("underrun", 1),
            Port::new("active", 1),
            Port::new("level", 8),
            Port::new("done_count", 8),
            Port::new("under_count", 8),
            Port::new("full", 1),
        ],
    }
}

fn simulate_all(name: &str, rows: &[Vec<u128>]) -> Vec<Vec<u128>> {
    let reference = run_rust_hdl(
        &mut uut(),
        rows,
        |u, c| u.clock.next = Clock::from(c),
        |u, r| {
            u.reset.next = r[0] == 1;
            u.push.next = r[1] == 1;
            u.entry_in.next = Bits::<ENTRY_BITS>::from(r[2] as u64);
            u.go.next = r[3] == 1;
            u.more.next = r[4] == 1;
            u.abort.next = r[5] == 1;
        },
        |u| {
            vec![
                u.step.val() as u128,
                u.dir.val() as u128,
                u.position.val().to_u64() as u128,
                u.underrun.val() as u128,
                u.active.val() as u128,
                u.level.val().to_u64() as u128,
                u.done_count.val().to_u64() as u128,
                u.under_count.val().to_u64() as u128,
                u.full.val() as u128,
            ]
        },
    );
    // `full` is a register kept equal to level >= DEPTH (the scheduler reads it).
    for (k, r) in reference.iter().enumerate().skip(RESET_ROWS) {
        assert_eq!(r[8], (r[5] >= DEPTH as u128) as u128, "{name}: full at row {k}, level {}", r[5]);
    }
    // Outputs: step, dir, position, underrun, active, level, done, underruns, full.
    verilog_matches_rust_hdl(name, &generate_verilog(&uut()), &spec(), rows, &reference, RESET_ROWS);
    reference
}

/// Checks a trace against the reference edges and the timing rules.
#[allow(clippy::too_many_arguments)]
/// The entries as the pins model takes them (`pulse::pins`).
fn model_entries(entries: &[Entry]) -> Vec<FifoEntry> {
    entries.iter().map(|e| FifoEntry { ticks: e.ticks, step: e.step, reverse: e.reverse }).collect()
}

fn check_trace(
    name: &str,
    entries: &[Entry],
    edges: &[u64],
    position: i64,
    sc: &Scenario,
    trace: &[Vec<u128>],
    starved: bool,
    timing: &PulseTiming,
) {
    let rises: Vec<usize> = (1..trace.len()).filter(|&r| trace[r][0] == 1 && trace[r - 1][0] == 0).collect();
    assert_eq!(rises.len(), edges.len(), "{name}: step count");
    let steps: Vec<&Entry> = entries.iter().filter(|e| e.step).collect();
    if !starved {
        for (i, (&r, &e)) in rises.iter().zip(edges).enumerate() {
            assert_eq!(r as u64, sc.release_row as u64 + 1 + e, "{name}: edge {i}");
        }
        assert!(trace.iter().all(|t| t[3] == 0), "{name}: underrun without starvation");
    } else {
        assert_eq!(trace.last().unwrap()[3], 1, "{name}: starved but no underrun flag");
        for (i, w) in rises.windows(2).enumerate() {
            assert!(w[1] - w[0] >= steps[i + 1].ticks as usize, "{name}: edge {} early", i + 1);
        }
    }
    assert_eq!(trace.last().unwrap()[2] as u32 as i32 as i64, position, "{name}: final position");
    let segments = entries.iter().filter(|e| e.last).count() as u128;
    assert_eq!(trace.last().unwrap()[6], segments % 256, "{name}: segments done");
    let underruns = (1..trace.len()).filter(|&r| trace[r][3] == 1 && trace[r - 1][3] == 0).count() as u128;
    assert_eq!(trace.last().unwrap()[7], underruns, "{name}: underrun count");
    // Falling edges and DIR changes: the pins model, row = release + 1 + tick.
    if !starved {
        let pins = pulse::pins(&model_entries(entries), timing);
        let row = |t: u64| sc.release_row + 1 + t as usize;
        let falls: Vec<usize> = (1..trace.len()).filter(|&r| trace[r][0] == 0 && trace[r - 1][0] == 1).collect();
        assert_eq!(falls, pins.falls.iter().map(|&t| row(t)).collect::<Vec<_>>(), "{name}: falling edges");
        let dir_changes: Vec<(usize, bool)> =
            (sc.release_row + 1..trace.len()).filter(|&r| trace[r][1] != trace[r - 1][1]).map(|r| (r, trace[r][1] == 1)).collect();
        assert_eq!(dir_changes, pins.dir_changes.iter().map(|&(t, d)| (row(t), d)).collect::<Vec<_>>(), "{name}: DIR changes");
        let (high, low, setup, hold) = pulse::measure(&pins);
        assert!(high >= timing.high_min() as u64 && low >= timing.low_min() as u64, "{name}: high {high}, low {low}");
        assert!(setup >= timing.dir_setup as u64 && hold >= timing.dir_hold as u64, "{name}: setup {setup}, hold {hold}");
    }
    for (i, &r) in rises.iter().enumerate() {
        // DIR at the edge is the step's direction, and was already one row before.
        assert_eq!(trace[r][1] == 1, steps[i].reverse, "{name}: DIR at edge {i}");
        assert_eq!(trace[r - 1][1], trace[r][1], "{name}: DIR setup at edge {i}");
    }
    // DIR never changes while STEP is high.
    for r in 1..trace.len() {
        if trace[r][1] != trace[r - 1][1] {
            assert_eq!(trace[r][0], 0, "{name}: DIR changed at row {r} with STEP high");
        }
    }
}

fn run_vector(file: &str, axis: usize) {
    let name = format!("step_{}_{axis}", file.trim_end_matches(".json"));
    let (entries, edges, position) = axis_entries(file, axis);
    let sc = scenario(&entries, None, None);
    let trace = simulate_all(&name, &sc.rows);
    check_trace(&name, &entries, &edges, position, &sc, &trace, false, &PulseTiming::default());
}

#[test]
fn short_segments_both_axes() {
    run_vector("short_segments.json", 0);
    run_vector("short_segments.json", 1);
}

#[test]
fn near_limit_two_tick_periods() {
    run_vector("near_limit.json", 0);
}

#[test]
fn starved_fifo_flags_underrun_and_loses_no_step() {
    let (entries, edges, position) = axis_entries("short_segments.json", 1);
    let sc = scenario(&entries, Some((5, 7)), None);
    let trace = simulate_all("step_starved", &sc.rows);
    check_trace("step_starved", &entries, &edges, position, &sc, &trace, true, &PulseTiming::default());
}

/// One-tick entries (a dwell of T = 1, a first step one tick after its segment starts)
/// next to two- and three-tick ones: the generator ends a one-tick entry at the edge
/// after its load (the entry's one-tick flag, bit 51), also right after the release,
/// after another one-tick entry and after an underrun's wait. Every edge, fall and DIR
/// change equals the model.
#[test]
fn one_tick_entries_end_after_one_tick() {
    // (ticks, step, reverse, last): steps at least two ticks apart, as the period rule
    // guarantees; a direction change after a dwell (its step's entry two ticks, so DIR
    // is set up a tick before the edge: a one-tick entry leaves it none).
    let plan: [(u32, bool, bool, bool); 12] = [
        (1, true, false, false),
        (1, false, false, false),
        (1, true, false, true),
        (1, false, false, true),
        (1, false, false, true),
        (2, true, false, false),
        (1, false, false, true),
        (2, true, true, false),
        (3, true, true, false),
        (2, true, true, true),
        (1, false, false, true),
        (1, false, false, true),
    ];
    let timing = PulseTiming::default();
    let entries: Vec<Entry> = plan
        .iter()
        .map(|&(ticks, step, reverse, last)| Entry { ticks, step, reverse, last, high: timing.high_ticks(ticks) as u16 })
        .collect();
    // The edges from the pins model, the position from the steps' directions.
    let edges = pulse::pins(&model_entries(&entries), &timing).rises;
    let position: i64 = entries.iter().filter(|e| e.step).map(|e| if e.reverse { -1 } else { 1 }).sum();
    let sc = scenario(&entries, None, None);
    let trace = simulate_all("step_one_tick", &sc.rows);
    check_trace("step_one_tick", &entries, &edges, position, &sc, &trace, false, &timing);
    // Starved after the fourth entry (a one-tick dwell loads after the wait).
    let sc = scenario(&entries, Some((4, 5)), None);
    let trace = simulate_all("step_one_tick_starved", &sc.rows);
    check_trace("step_one_tick_starved", &entries, &edges, position, &sc, &trace, true, &timing);
}

/// Abort mid-move, once with STEP low and once just after an edge: no edge rises
/// after the abort, a pulse already high keeps its full high time, the position is
/// exactly the edges emitted, and the FIFO is empty.
#[test]
fn abort_stops_at_once_with_an_exact_position() {
    let (entries, edges, _) = axis_entries("short_segments.json", 0);
    let plain = scenario(&entries, None, None);
    let edge_rows: Vec<usize> = edges.iter().map(|&e| plain.release_row + 1 + e as usize).collect();
    let k = edges.len() / 2;
    for (label, abort_row) in [("low", edge_rows[k] - 2), ("high", edge_rows[k])] {
        let name = format!("step_abort_{label}");
        let sc = scenario(&entries, None, Some(abort_row));
        let trace = simulate_all(&name, &sc.rows);
        let rises: Vec<usize> = (1..trace.len()).filter(|&r| trace[r][0] == 1 && trace[r - 1][0] == 0).collect();
        // An edge that rises at the abort's own clock edge (row abort_row + 1) is emitted.
        assert!(rises.iter().all(|&r| r <= abort_row + 1), "{name}: edge after the abort: {rises:?}");
        assert_eq!(&rises[..], &edge_rows[..rises.len()], "{name}: edges before the abort moved");
        let expected = if label == "low" { k } else { k + 1 };
        assert_eq!(rises.len(), expected, "{name}: edges emitted");
        let last = trace.last().unwrap();
        assert_eq!(last[2] as u32 as i32 as i64, rises.len() as i64, "{name}: position");
        assert_eq!(last[4], 0, "{name}: still active");
        assert_eq!(last[5], 0, "{name}: FIFO not flushed");
        let r = *rises.last().unwrap();
        let high = (r..trace.len()).take_while(|&q| trace[q][0] == 1).count();
        let step_entries: Vec<&Entry> = entries.iter().filter(|e| e.step).collect();
        let next = step_entries.get(rises.len()).map_or(0, |e| e.high);
        assert_eq!(high as u16, next, "{name}: pulse in flight cut short");
    }
}

/// Output timing at the vector's shortest period M: max(H, D) + max(L, S) = M, so the
/// pulse is clamped on both sides at the fastest steps and DIR changes as late and as
/// early as allowed. Every rise, fall and DIR change equals the pins model.
#[test]
fn output_timing_at_the_minimum_period_is_met_on_the_pins() {
    let (plain, _, _) = axis_entries("short_segments.json", 0);
    let m = plain.iter().filter(|e| e.step).map(|e| e.ticks).min().unwrap();
    assert!(m >= 4, "vector too fast for this test: {m}");
    let timing = PulseTiming {
        step_high: (m / 3) as u16,
        dir_hold: (m / 2) as u16,
        step_low: (m / 4) as u16,
        dir_setup: (m - m / 2) as u16,
    };
    assert_eq!(timing.high_min() + timing.low_min(), m);
    let (entries, edges, position) = axis_entries_with("short_segments.json", 0, &timing);
    let sc = scenario(&entries, None, None);
    let trace = simulate_all("step_timing", &sc.rows);
    check_trace("step_timing", &entries, &edges, position, &sc, &trace, false, &timing);
}

/// A reset (CTRL.ENABLE = 0, or the reset pin) one tick into a pulse: the pulse keeps
/// its whole high time, DIR does not change while it is high, and nothing rises after.
#[test]
fn reset_mid_pulse_leaves_no_runt() {
    let (entries, edges, _) = axis_entries("short_segments.json", 0);
    let mut sc = scenario(&entries, None, None);
    let k = edges.len() / 2;
    let edge_row = sc.release_row + 1 + edges[k] as usize;
    for r in edge_row..edge_row + 3 {
        sc.rows[r][0] = 1;
    }
    let trace = simulate_all("step_reset_pulse", &sc.rows);
    let rises: Vec<usize> = (1..trace.len()).filter(|&r| trace[r][0] == 1 && trace[r - 1][0] == 0).collect();
    assert_eq!(rises.len(), k + 1, "step_reset_pulse: edges emitted");
    let high = (edge_row..trace.len()).take_while(|&q| trace[q][0] == 1).count();
    let step_k = entries.iter().enumerate().filter(|(_, e)| e.step).nth(k).unwrap().0;
    let expected = entries.get(step_k + 1).map_or(entries[step_k].high, |e| e.high);
    assert!(expected > 3, "the pulse must outlast the reset for this test");
    assert_eq!(high as u16, expected, "step_reset_pulse: pulse cut by the reset");
    for r in edge_row..edge_row + high {
        assert_eq!(trace[r][1], trace[edge_row][1], "step_reset_pulse: DIR changed during the pulse");
    }
    let last = trace.last().unwrap();
    assert_eq!(last[2], 0, "step_reset_pulse: position not cleared");
    assert_eq!(last[4], 0, "step_reset_pulse: still active");
}

/// The registered `full` against the level it stands for, with pushes at random rows
/// (into a full FIFO too: it has room for 32) and short periods, so that a push and a
/// pop meet at DEPTH − 1, DEPTH and above; an abort empties it midway. The check on
/// every row is in `simulate_all`; this asserts that the cases were reached.
#[test]
fn full_flag_follows_the_level_under_random_pushes() {
    let mut rng = Rng(0x5eed_f011);
    let rows_n = 700;
    let mut rows = Vec::with_capacity(rows_n);
    for r in 0..rows_n {
        let push = r >= RESET_ROWS && r < rows_n - 150 && rng.next() % 16 < 3;
        let entry = if push { pack_entry(2 + (rng.next() % 6) as u32, true, rng.next() % 2 == 1, false, 1) as u128 } else { 0 };
        rows.push(vec![(r < RESET_ROWS) as u128, push as u128, entry, (r == RESET_ROWS + 6) as u128, 1, (r == 400) as u128]);
    }
    let trace = simulate_all("step_full_flag", &rows);
    let levels: Vec<u128> = trace.iter().map(|t| t[5]).collect();
    let met = |lv: u128| (1..rows_n).any(|r| levels[r - 1] == lv && rows[r - 1][1] == 1 && trace[r][5] == lv);
    assert!(levels.iter().any(|&l| l > DEPTH as u128 + 1), "the level never went above DEPTH + 1");
    assert!(met(DEPTH as u128), "no push and pop together at DEPTH");
    assert!((1..rows_n).any(|r| levels[r - 1] == DEPTH as u128 - 1 && levels[r] == DEPTH as u128), "never filled to DEPTH");
    assert!((1..rows_n).any(|r| levels[r - 1] == DEPTH as u128 && levels[r] == DEPTH as u128 - 1), "never drained below DEPTH");
}
