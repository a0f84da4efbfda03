//! AxisBank three ways: rust-hdl, the exported Verilog in Verilator and Icarus (equal
//! to rust-hdl row for row on every output), and the model: three axes fed period
//! entries through the bank's pulse stage, released together by a synchronised start.
//! * Axes 0 and 1 get all their entries before the start: every STEP rise, fall and DIR
//!   change equals the pins model (`model::pulse::pins`, with output timing other than
//!   the reset values), from one release row shared by all three axes (zero skew).
//! * Axis 2 is starved: its last entries arrive late while `pending` says they are
//!   coming. It flags an underrun and loses no step; its edges up to the starvation
//!   equal the model's.
//! * `full`, `ready`, `busy` and `all_sat` follow their definitions every row; the
//!   selected axis's position, FIFO level, segments done and underruns equal the
//!   model's at the end; a start whose mask holds an axis with nothing to run pulses
//!   `failed` once and releases nothing; `ext_go` releases one axis at once, and an
//!   entry that reaches the FIFO a cycle after its predecessor ended, announced only by
//!   the pulse stage's last register, costs a one-cycle underrun and no step.
//! * The position latches: with home strobes of single axes and probe strobes of
//!   every axis scattered over the run, `lsel_word` (the selected axis's latches and
//!   toggles) equals, every row, a latch taken from the positions the STEP and DIR
//!   outputs imply at the strobe's row.

mod common;

use common::*;
use rust_hdl::prelude::*;
use tdm_stepper::hdl::axis_bank::AxisBank;
use tdm_stepper::hdl::ram_fifo::{pack_entry, ENTRY_BITS};
use tdm_stepper::model::{pulse, FifoEntry, PulseTiming};
use tdm_stepper::verify::{run_rust_hdl, Port, TbSpec};

const K: usize = 3;
const DEPTH: usize = 4;
const RESET_ROWS: usize = 3;
/// Rows after the `ext_go` at which axis 1's third entry is pushed: its second entry
/// ends 20 + 30 rows after the release, and the pulse stage takes 2.
const JUST_LATE: usize = 20 + 30 - 2;
const TIMING: PulseTiming = PulseTiming { step_high: 3, step_low: 2, dir_setup: 4, dir_hold: 2 };

// Input columns.
const I_RESET: usize = 0;
const I_PUSH: usize = 2;
const I_AXIS: usize = 3;
const I_ENTRY: usize = 4;
const I_PENDING: usize = 5;
const I_START: usize = 6;
const I_MASK: usize = 7;
const I_EXT_GO: usize = 8;
const I_SEL: usize = 9;
// Output columns.
const O_STEP: usize = 0;
const O_DIR: usize = 1;
const O_UNDER: usize = 2;
const O_ACTIVE: usize = 3;
const O_BUSY: usize = 4;
const O_READY: usize = 5;
const O_FULL: usize = 6;
const O_SAT: usize = 7;
const O_FAILED: usize = 8;
const O_POS: usize = 9;
const O_FIFO: usize = 10;
const O_DONE: usize = 11;
const O_UNDERS: usize = 12;
const O_SBUSY: usize = 13;
const O_LATCH: usize = 14;
// Latch input columns (after the two timing columns).
const I_HOME_LATCH: usize = 12;
const I_PROBE_LATCH: usize = 13;
const I_LSEL: usize = 14;

#[derive(Clone, Copy, Debug)]
struct Entry {
    ticks: u32,
    step: bool,
    reverse: bool,
    last: bool,
}

/// Segments of random entries for one axis: a dwell now and then, both directions.
fn entries(rng: &mut Rng, segments: usize) -> Vec<Entry> {
    let mut v = Vec::new();
    for _ in 0..segments {
        if rng.next() % 5 == 0 {
            v.push(Entry { ticks: 14 + (rng.next() % 40) as u32, step: false, reverse: false, last: true });
            continue;
        }
        let reverse = rng.next() % 2 == 1;
        let n = 2 + (rng.next() % 4) as usize;
        for k in 0..n {
            v.push(Entry { ticks: 14 + (rng.next() % 40) as u32, step: true, reverse, last: k + 1 == n });
        }
    }
    v
}

struct Plan {
    rows: Vec<Vec<u128>>,
    axes: Vec<Vec<Entry>>,
    /// Axis 2's entries pushed before the start (the rest come late).
    early2: usize,
    start_row: usize,
    fail_row: usize,
    ext_row: usize,
    /// Axis 1's entries for the `ext_go` release.
    ext: Vec<Entry>,
}

fn plan() -> Plan {
    let mut rng = Rng(0xba9c_0ffe_e123_4567);
    let axes: Vec<Vec<Entry>> = (0..K).map(|_| entries(&mut rng, 4)).collect();
    assert!(axes.iter().all(|a| a.len() <= 30), "every entry fits the 32-word FIFO before the start");
    let early2 = axes[2].len() - 3;
    let mut rows: Vec<Vec<u128>> = Vec::new();
    let row = |rows: &mut Vec<Vec<u128>>, pending: u128| {
        let sel = (rows.len() % K) as u128;
        rows.push(vec![0, 0, 0, 0, 0, pending, 0, 0, 0, sel]);
    };
    for _ in 0..RESET_ROWS {
        row(&mut rows, 0);
        rows.last_mut().unwrap()[I_RESET] = 1;
    }
    let pack = |e: &Entry| pack_entry(e.ticks, e.step, e.reverse, e.last, 0) as u128;
    // Axis 2 still has work coming until its late entries are pushed.
    let pend = 0b100;
    let longest = axes.iter().map(|a| a.len()).max().unwrap();
    for k in 0..longest {
        for (a, es) in axes.iter().enumerate() {
            if k < es.len() && !(a == 2 && k >= early2) {
                row(&mut rows, pend);
                let r = rows.last_mut().unwrap();
                r[I_PUSH] = 1;
                r[I_AXIS] = a as u128;
                r[I_ENTRY] = pack(&es[k]);
            }
        }
    }
    for _ in 0..3 {
        row(&mut rows, pend);
    }
    let start_row = rows.len();
    row(&mut rows, pend);
    rows[start_row][I_START] = 1;
    rows[start_row][I_MASK] = 0b111;
    // Axis 2 runs dry after its early entries (about 33 ticks each): push the rest
    // 200 rows after it would have needed them.
    let early_ticks: usize = axes[2][..early2].iter().map(|e| e.ticks as usize).sum();
    let late_row = start_row + early_ticks + 200;
    while rows.len() < late_row {
        row(&mut rows, pend);
    }
    // Three rows apart, so that the first late entry is, for a cycle, the only work
    // of the waiting axis 2 still coming (in the pulse stage's last register).
    for e in &axes[2][early2..] {
        row(&mut rows, 0);
        let r = rows.last_mut().unwrap();
        r[I_PUSH] = 1;
        r[I_AXIS] = 2;
        r[I_ENTRY] = pack(e);
        for _ in 0..3 {
            row(&mut rows, 0);
        }
    }
    let all_ticks: usize = axes.iter().map(|a| a.iter().map(|e| e.ticks as usize).sum::<usize>()).max().unwrap();
    let end = late_row + all_ticks + 100;
    while rows.len() < end {
        row(&mut rows, 0);
    }
    // A start whose mask holds axis 0, which has nothing to run.
    let fail_row = rows.len();
    row(&mut rows, 0);
    rows[fail_row][I_START] = 1;
    rows[fail_row][I_MASK] = 0b001;
    for _ in 0..10 {
        row(&mut rows, 0);
    }
    // Three entries for axis 1, released by ext_go: two pushed ahead, the third just
    // too late (see `JUST_LATE`).
    let ext = vec![
        Entry { ticks: 20, step: true, reverse: true, last: false },
        Entry { ticks: 30, step: true, reverse: false, last: false },
        Entry { ticks: 25, step: true, reverse: false, last: true },
    ];
    for e in &ext[..2] {
        row(&mut rows, 0);
        let r = rows.last_mut().unwrap();
        r[I_PUSH] = 1;
        r[I_AXIS] = 1;
        r[I_ENTRY] = pack(e);
    }
    for _ in 0..3 {
        row(&mut rows, 0);
    }
    let ext_row = rows.len();
    row(&mut rows, 0);
    rows[ext_row][I_EXT_GO] = 0b010;
    for _ in 0..120 {
        row(&mut rows, 0);
    }
    // The second entry ends at row ext_row + 50 with the FIFO empty and nothing
    // pending: the third, pushed two rows earlier, is then in the pulse stage's last
    // register, and only it says that more is coming. The axis waits one cycle (an
    // underrun) and loses no step.
    let r = &mut rows[ext_row + JUST_LATE];
    r[I_PUSH] = 1;
    r[I_AXIS] = 1;
    r[I_ENTRY] = pack(&ext[2]);
    // The last K rows select each axis once, for the end-of-run status.
    Plan { rows, axes, early2, start_row, fail_row, ext_row, ext }
}

fn uut() -> AxisBank<K, DEPTH> {
    let mut u = AxisBank::<K, DEPTH>::default();
    u.clock.connect();
    u.reset.connect();
    u.abort.connect();
    u.high_min.connect();
    u.low_min.connect();
    u.push.connect();
    u.push_axis.connect();
    u.entry.connect();
    u.pending.connect();
    u.start.connect();
    u.start_mask.connect();
    u.ext_go.connect();
    u.sel_axis.connect();
    u.home_latch.connect();
    u.probe_latch.connect();
    u.lsel_axis.connect();
    u.epos_axis.connect();
    u.stop.connect();
    u.connect_all();
    u
}

fn spec() -> TbSpec {
    TbSpec {
        clock: "clock".into(),
        inputs: vec![
            Port::new("reset", 1),
            Port::new("abort", 1),
            Port::new("push", 1),
            Port::new("push_axis", 8),
            Port::new("entry", ENTRY_BITS),
            Port::new("pending", K),
            Port::new("start", 1),
            Port::new("start_mask", K),
            Port::new("ext_go", K),
            Port::new("sel_axis", 8),
            Port::new("high_min", 16),
            Port::new("low_min", 16),
            Port::new("home_latch", K),
            Port::new("probe_latch", 1),
            Port::new("lsel_axis", 8),
            Port::new("stop", K),
        ],
        outputs: vec![
            Port::new("step", K),
            Port::new("dir", K),
            Port::new("underrun", K),
            Port::new("active", K),
            Port::new("busy", K),
            Port::new("ready", K),
            Port::new("full", K),
            Port::new("all_sat", 1),
            Port::new("failed", 1),
            Port::new("sel_position", 32),
            Port::new("sel_fifo", 8),
            Port::new("sel_done", 8),
            Port::new("sel_underruns", 8),
            Port::new("sel_busy", 1),
            Port::new("lsel_word", 66),
        ],
    }
}

/// The timing columns, and latch strobes scattered over the rows: a home strobe of
/// one axis every 37 rows, a probe strobe every 53, the latch selector round robin.
fn with_timing(rows: &[Vec<u128>]) -> Vec<Vec<u128>> {
    rows.iter()
        .enumerate()
        .map(|(n, r)| {
            let home = if n % 37 == 5 { 1u128 << ((n / 37) % K) } else { 0 };
            let probe = (n % 53 == 7) as u128;
            // (The per-axis stop is held at 0 here: tests/hdl_core.rs stops an axis.)
            [r.clone(), vec![TIMING.high_min() as u128, TIMING.low_min() as u128, home, probe, (n % K) as u128, 0]].concat()
        })
        .collect()
}

/// The latch words the model expects, row by row: each axis's position from its STEP
/// rises and DIR, taken by the latches at a strobe's row and seen from the next.
fn expected_latches(rows: &[Vec<u128>], trace: &[Vec<u128>]) -> Vec<u128> {
    let mut pos = [0i32; K];
    let (mut home, mut probe, mut htog, mut ptog) = ([0i32; K], [0i32; K], [0u128; K], [0u128; K]);
    let mut out = Vec::new();
    for (r, row) in rows.iter().enumerate() {
        for a in 0..K {
            if r > 0 && bit(trace[r][O_STEP], a) && !bit(trace[r - 1][O_STEP], a) {
                pos[a] += if bit(trace[r][O_DIR], a) { -1 } else { 1 };
            }
        }
        let s = row[I_LSEL] as usize;
        out.push(home[s] as u32 as u128 | (probe[s] as u32 as u128) << 32 | htog[s] << 64 | ptog[s] << 65);
        // The strobes of this row take this row's positions, seen from the next.
        for a in 0..K {
            if row[I_RESET] == 1 {
                (pos[a], home[a], probe[a], htog[a], ptog[a]) = (0, 0, 0, 0, 0);
                continue;
            }
            if bit(row[I_HOME_LATCH], a) {
                (home[a], htog[a]) = (pos[a], htog[a] ^ 1);
            }
            if row[I_PROBE_LATCH] == 1 {
                (probe[a], ptog[a]) = (pos[a], ptog[a] ^ 1);
            }
        }
    }
    out
}

fn simulate_all(rows: &[Vec<u128>]) -> Vec<Vec<u128>> {
    let reference = run_rust_hdl(
        &mut uut(),
        rows,
        |u, c| u.clock.next = Clock::from(c),
        |u, r| {
            u.reset.next = r[0] == 1;
            u.abort.next = r[1] == 1;
            u.push.next = r[2] == 1;
            u.push_axis.next = Bits::<8>::from(r[3] as u64);
            u.entry.next = Bits::<ENTRY_BITS>::from(r[4] as u64);
            u.pending.next = Bits::<K>::from(r[5] as u64);
            u.start.next = r[6] == 1;
            u.start_mask.next = Bits::<K>::from(r[7] as u64);
            u.ext_go.next = Bits::<K>::from(r[8] as u64);
            u.sel_axis.next = Bits::<8>::from(r[9] as u64);
            u.high_min.next = Bits::<16>::from(r[10] as u64);
            u.low_min.next = Bits::<16>::from(r[11] as u64);
            u.home_latch.next = Bits::<K>::from(r[12] as u64);
            u.probe_latch.next = r[13] == 1;
            u.lsel_axis.next = Bits::<8>::from(r[14] as u64);
            u.stop.next = Bits::<K>::from(r[15] as u64);
        },
        |u| {
            vec![
                u.step.val().to_u64() as u128,
                u.dir.val().to_u64() as u128,
                u.underrun.val().to_u64() as u128,
                u.active.val().to_u64() as u128,
                u.busy.val().to_u64() as u128,
                u.ready.val().to_u64() as u128,
                u.full.val().to_u64() as u128,
                u.all_sat.val() as u128,
                u.failed.val() as u128,
                u.sel_position.val().to_u64() as u128,
                u.sel_fifo.val().to_u64() as u128,
                u.sel_done.val().to_u64() as u128,
                u.sel_underruns.val().to_u64() as u128,
                u.sel_busy.val() as u128,
                tdm_stepper::hdl::bits_to_u128(u.lsel_word.val()),
            ]
        },
    );
    verilog_matches_rust_hdl("axis_bank", &generate_verilog(&uut()), &spec(), rows, &reference, RESET_ROWS);
    reference
}

fn bit(v: u128, a: usize) -> bool {
    (v >> a) & 1 == 1
}

fn rises_of(trace: &[Vec<u128>], a: usize, from: usize, to: usize) -> Vec<usize> {
    (from.max(1)..to).filter(|&r| bit(trace[r][O_STEP], a) && !bit(trace[r - 1][O_STEP], a)).collect()
}

fn fifo(es: &[Entry]) -> Vec<FifoEntry> {
    es.iter().map(|e| FifoEntry { ticks: e.ticks, step: e.step, reverse: e.reverse }).collect()
}

#[test]
fn axes_released_together_match_the_pins_model() {
    let p = plan();
    let rows = with_timing(&p.rows);
    let trace = simulate_all(&rows);
    let n = trace.len();
    let latches = expected_latches(&rows, &trace);
    let strobes = rows.iter().filter(|r| r[I_HOME_LATCH] != 0 || r[I_PROBE_LATCH] != 0).count();
    assert!(strobes > 20 && latches.iter().filter(|&&w| w as u32 as i32 != 0 && (w >> 32) as u32 != 0).count() > 20, "the latches saw too little motion");
    for r in RESET_ROWS..n {
        assert_eq!(trace[r][O_LATCH], latches[r], "row {r}: lsel_word (axis {})", rows[r][I_LSEL]);
    }

    // One release for all three axes: each becomes active on the same row.
    let first_active: Vec<usize> =
        (0..K).map(|a| (p.start_row..n).find(|&r| bit(trace[r][O_ACTIVE], a)).expect("axis released")).collect();
    assert!(first_active.iter().all(|&r| r == first_active[0]), "skew: first active rows {first_active:?}");
    // The entry loads at the release row's edge; tick t of the model is row release + 1 + t.
    let release = first_active[0] - 1;
    let at = |t: u64| release + 1 + t as usize;

    for a in 0..2 {
        let pins = pulse::pins(&fifo(&p.axes[a]), &TIMING);
        let rises = rises_of(&trace, a, p.start_row, p.fail_row);
        assert_eq!(rises, pins.rises.iter().map(|&t| at(t)).collect::<Vec<_>>(), "axis {a}: rising edges");
        let falls: Vec<usize> =
            (p.start_row..p.fail_row).filter(|&r| !bit(trace[r][O_STEP], a) && bit(trace[r - 1][O_STEP], a)).collect();
        assert_eq!(falls, pins.falls.iter().map(|&t| at(t)).collect::<Vec<_>>(), "axis {a}: falling edges");
        let dirs: Vec<(usize, bool)> = (p.start_row..p.fail_row)
            .filter(|&r| bit(trace[r][O_DIR], a) != bit(trace[r - 1][O_DIR], a))
            .map(|r| (r, bit(trace[r][O_DIR], a)))
            .collect();
        assert_eq!(dirs, pins.dir_changes.iter().map(|&(t, d)| (at(t), d)).collect::<Vec<_>>(), "axis {a}: DIR changes");
        assert!(pins.rises.len() >= 8, "axis {a}: the run checks something");
        assert!(!trace[..p.fail_row].iter().any(|t| bit(t[O_UNDER], a)), "axis {a}: underrun while fed");
    }

    // Axis 2: starved, no step lost, the edges before the starvation exact.
    let pins2 = pulse::pins(&fifo(&p.axes[2][..p.early2]), &TIMING);
    let rises2 = rises_of(&trace, 2, p.start_row, p.fail_row);
    let steps2 = p.axes[2].iter().filter(|e| e.step).count();
    assert_eq!(rises2.len(), steps2, "axis 2: every step emitted");
    let exact = pins2.rises.len();
    assert!(exact >= 3, "axis 2 runs before it starves");
    assert_eq!(&rises2[..exact], &pins2.rises.iter().map(|&t| at(t)).collect::<Vec<_>>()[..], "axis 2: edges before the starvation");
    assert!(bit(trace[p.fail_row - 1][O_UNDER], 2), "axis 2: underrun flagged");

    // Flags by their definitions, every row after reset.
    for r in RESET_ROWS..n {
        let t = &trace[r];
        for a in 0..K {
            let pending = bit(rows[r][I_PENDING], a);
            let sat = bit(t[O_FULL], a) || !pending;
            if !sat {
                assert_eq!(t[O_SAT], 0, "row {r}: all_sat with axis {a} unsatisfied");
            }
            if bit(t[O_ACTIVE], a) {
                assert!(!bit(t[O_READY], a), "row {r}: axis {a} ready while moving");
                assert!(bit(t[O_BUSY], a), "row {r}: axis {a} moving but not busy");
            }
            if pending {
                assert!(bit(t[O_BUSY], a), "row {r}: axis {a} has work coming but is not busy");
            }
            if bit(t[O_READY], a) {
                assert!(bit(t[O_BUSY], a), "row {r}: axis {a} has periods waiting for its release but is not busy");
            }
        }
        let all = (0..K).all(|a| bit(t[O_FULL], a) || !bit(rows[r][I_PENDING], a));
        assert_eq!(t[O_SAT] == 1, all, "row {r}: all_sat");
        let sel = rows[r][I_SEL] as usize;
        assert_eq!(bit(t[O_FULL], sel), t[O_FIFO] >= DEPTH as u128, "row {r}: full of axis {sel}, level {}", t[O_FIFO]);
        assert_eq!(t[O_SBUSY] == 1, bit(t[O_BUSY], sel), "row {r}: sel_busy");
        if t[O_FIFO] > 0 {
            assert!(bit(t[O_BUSY], sel), "row {r}: axis {sel} has {} periods in its FIFO but is not busy", t[O_FIFO]);
        }
    }
    // Before the start every axis is ready, and full when it holds DEPTH entries.
    for a in 0..K {
        let held = if a == 2 { p.early2 } else { p.axes[a].len() };
        assert_eq!(bit(trace[p.start_row][O_FULL], a), held >= DEPTH, "axis {a} ({held} entries): full before the start");
        assert!(bit(trace[p.start_row][O_READY], a), "axis {a} ready before the start");
    }

    // The failed start: one pulse, no release.
    let fails: Vec<usize> = (0..n).filter(|&r| trace[r][O_FAILED] == 1).collect();
    assert_eq!(fails.len(), 1, "failed pulses once: rows {fails:?}");
    assert!(fails[0] > p.fail_row && fails[0] <= p.fail_row + 2, "failed at row {}, start at {}", fails[0], p.fail_row);
    assert!(!(p.fail_row..p.ext_row).any(|r| trace[r][O_ACTIVE] != 0), "nothing released by the failed start");

    // ext_go: axis 1 loads at that row's edge, alone; its third edge one cycle late
    // (the entry arrived a cycle after the second ended), none lost.
    let pins_ext = pulse::pins(&fifo(&p.ext), &TIMING);
    let mut want: Vec<usize> = pins_ext.rises.iter().map(|&t| p.ext_row + 1 + t as usize).collect();
    want[2] += 1;
    let ext_rises = rises_of(&trace, 1, p.ext_row, n);
    assert_eq!(ext_rises, want, "ext_go release, the just-late entry");
    assert!(rises_of(&trace, 0, p.ext_row, n).is_empty() && rises_of(&trace, 2, p.ext_row, n).is_empty());

    // Status of each axis at the end (the last K rows select every axis once).
    let all: Vec<Vec<Entry>> = vec![p.axes[0].clone(), [p.axes[1].clone(), p.ext.clone()].concat(), p.axes[2].clone()];
    for r in n - K..n {
        let a = rows[r][I_SEL] as usize;
        let t = &trace[r];
        let pos: i64 = all[a].iter().filter(|e| e.step).map(|e| if e.reverse { -1 } else { 1 }).sum();
        assert_eq!(t[O_POS] as u32 as i32 as i64, pos, "axis {a}: position");
        assert_eq!(t[O_DONE], all[a].iter().filter(|e| e.last).count() as u128, "axis {a}: segments done");
        assert_eq!(t[O_UNDERS], (a != 0) as u128, "axis {a}: underruns begun");
        assert_eq!(t[O_FIFO], 0, "axis {a}: FIFO empty at the end");
    }
}
