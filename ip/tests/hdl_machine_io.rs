//! InputFilter and MachineIo three ways: rust-hdl, the exported Verilog in Verilator and
//! Icarus, and the model (`model::io`). Random pins with bounce, random configurations
//! (changed between phases, as the registers do between moves), commands and resets:
//! every output equals the model's in every cycle. Then the behaviour the docs promise,
//! on the rust-hdl block: the filter's latency and what it ignores, the e-stop latch
//! and its re-arm rules, the watchdog's exact timeout, the latch strobes' edge choice.

mod common;

use common::*;
use rust_hdl::prelude::*;
use tdm_stepper::hdl::input_filter::InputFilter;
use tdm_stepper::hdl::machine_io::MachineIo;
use tdm_stepper::model::io::{
    pin_to_level_ticks, InputModel, IoCommands, IoConfig, IoPins, MachineIoModel, FILTER_MAX_SAMPLES, WATCHDOG_UNIT_TICKS,
};
use tdm_stepper::verify::{run_rust_hdl, Port, TbSpec};

/// A pin that holds a level for a while, then changes, sometimes with bounce (a burst of
/// short toggles) around the change.
struct PinGen {
    level: bool,
    left: u64,
    bounce: u64,
}

impl PinGen {
    fn new(level: bool) -> Self {
        PinGen { level, left: 5, bounce: 0 }
    }
    fn next(&mut self, rng: &mut Rng, hold: u64) -> bool {
        if self.bounce > 0 {
            self.bounce -= 1;
            return if rng.next() % 2 == 0 { !self.level } else { self.level };
        }
        if self.left == 0 {
            self.level = !self.level;
            self.left = 1 + rng.next() % hold;
            if rng.next() % 3 == 0 {
                self.bounce = 1 + rng.next() % 12;
            }
        } else {
            self.left -= 1;
        }
        self.level
    }
}

fn filter_uut(reset_active: bool) -> InputFilter {
    let mut u = InputFilter::new(reset_active);
    u.clock.connect();
    u.reset.connect();
    u.pin.connect();
    u.invert.connect();
    u.sample.connect();
    u.samples.connect();
    u.connect_all();
    u
}

#[test]
fn input_filter_equals_the_model_three_ways() {
    for reset_active in [false, true] {
        input_filter_three_ways(reset_active);
    }
}

fn input_filter_three_ways(reset_active: bool) {
    let mut rng = Rng(0x5eed_f1a7_0001 + reset_active as u64);
    let mut pin = PinGen::new(false);
    let mut rows = Vec::new();
    for phase in 0..40u64 {
        let n = match phase % 5 {
            0 => 0,
            1 => FILTER_MAX_SAMPLES as u64,
            _ => rng.next() % 16,
        };
        let invert = rng.next() % 2;
        let every = 1 + rng.next() % 4; // a sample every `every` cycles, at a random phase
        let reset_rows = if phase == 0 { 3 } else { (rng.next() % 8 == 0) as u64 };
        for k in 0..300u64 {
            let sample = (k % every == 0) as u128;
            rows.push(vec![(k < reset_rows) as u128, pin.next(&mut rng, 40) as u128, invert as u128, sample, n as u128]);
        }
    }
    let mut m = InputModel::new(reset_active);
    let mut want = Vec::new();
    for (r, row) in rows.iter().enumerate() {
        let (reset, p, inv, s, n) = (row[0] == 1, row[1] == 1, row[2] == 1, row[3] == 1, row[4] as u8);
        let ch = m.changes(inv, s, n);
        let out = vec![m.level as u128, (ch && !m.level) as u128, (ch && m.level) as u128];
        // Before the synchroniser has clocked twice its flip-flops are undefined in Verilog.
        want.push(out.into_iter().map(|v| (r >= 3).then_some(v)).collect());
        m.clock(p, inv, s, n, reset);
    }
    let changes = want.iter().filter(|w: &&Vec<Option<u128>>| w[1] == Some(1) || w[2] == Some(1)).count();
    assert!(changes > 100, "stimulus too thin: {changes} level changes");
    let spec = TbSpec {
        clock: "clock".into(),
        inputs: vec![Port::new("reset", 1), Port::new("pin", 1), Port::new("invert", 1), Port::new("sample", 1), Port::new("samples", 4)],
        outputs: vec![Port::new("active", 1), Port::new("rise", 1), Port::new("fall", 1)],
    };
    three_ways(
        &format!("input_filter_{reset_active}"),
        || filter_uut(reset_active),
        |u, c| u.clock.next = Clock::from(c),
        |u, r| {
            u.reset.next = r[0] == 1;
            u.pin.next = r[1] == 1;
            u.invert.next = r[2] == 1;
            u.sample.next = r[3] == 1;
            u.samples.next = Bits::<4>::from(r[4] as u64);
        },
        |u| vec![u.active.val() as u128, u.rise.val() as u128, u.fall.val() as u128],
        &spec,
        &rows,
        &want,
    );
}

const K: usize = 3;

fn io_uut() -> MachineIo<K> {
    let mut u = MachineIo::<K>::default();
    u.connect_ports();
    u
}

/// One row: reset, run, estop_n, probe, limit_neg, limit_pos, home, alarm, polarity,
/// filter, prescale, edges, wd_timeout, estop_rearm, wd_feed, wd_rearm.
fn io_row(reset: bool, run: bool, pins: &IoPins, cfg: &IoConfig, cmd: &IoCommands) -> Vec<u128> {
    vec![
        reset as u128,
        run as u128,
        pins.estop_n as u128,
        pins.probe as u128,
        pins.limit_neg as u128,
        pins.limit_pos as u128,
        pins.home as u128,
        pins.alarm as u128,
        cfg.polarity as u128,
        cfg.filter_word() as u128,
        cfg.prescale as u128,
        cfg.edges as u128,
        cfg.wd_timeout as u128,
        cmd.estop_rearm as u128,
        cmd.wd_feed as u128,
        cmd.wd_rearm as u128,
        pins.dir as u128,
        pins.active as u128,
    ]
}

fn unrow(r: &[u128]) -> (bool, bool, IoPins, IoConfig, IoCommands) {
    let fw = r[9] as u32;
    let cfg = IoConfig {
        polarity: r[8] as u8,
        filter: std::array::from_fn(|g| (fw >> (4 * g) & 0xF) as u8),
        prescale: r[10] as u16,
        edges: r[11] as u8,
        wd_timeout: r[12] as u16,
    };
    let pins = IoPins {
        estop_n: r[2] == 1,
        probe: r[3] == 1,
        limit_neg: r[4] as u32,
        limit_pos: r[5] as u32,
        home: r[6] as u32,
        alarm: r[7] as u32,
        dir: r[16] as u32,
        active: r[17] as u32,
    };
    let cmd = IoCommands { estop_rearm: r[13] == 1, wd_feed: r[14] == 1, wd_rearm: r[15] == 1 };
    (r[0] == 1, r[1] == 1, pins, cfg, cmd)
}

fn set_io(u: &mut MachineIo<K>, r: &[u128]) {
    u.reset.next = r[0] == 1;
    u.run.next = r[1] == 1;
    u.estop_n.next = r[2] == 1;
    u.probe.next = r[3] == 1;
    u.limit_neg.next = Bits::<K>::from(r[4] as u64);
    u.limit_pos.next = Bits::<K>::from(r[5] as u64);
    u.home.next = Bits::<K>::from(r[6] as u64);
    u.alarm.next = Bits::<K>::from(r[7] as u64);
    u.polarity.next = Bits::<6>::from(r[8] as u64);
    u.filter.next = Bits::<24>::from(r[9] as u64);
    u.prescale.next = Bits::<16>::from(r[10] as u64);
    u.edges.next = Bits::<2>::from(r[11] as u64);
    u.wd_timeout.next = Bits::<16>::from(r[12] as u64);
    u.estop_rearm.next = r[13] == 1;
    u.wd_feed.next = r[14] == 1;
    u.wd_rearm.next = r[15] == 1;
    u.dir.next = Bits::<K>::from(r[16] as u64);
    u.active.next = Bits::<K>::from(r[17] as u64);
}

fn get_io(u: &MachineIo<K>) -> Vec<u128> {
    vec![
        u.hard_stop.val() as u128,
        u.estop_latched.val() as u128,
        u.estop_active.val() as u128,
        u.probe_active.val() as u128,
        u.wd_tripped.val() as u128,
        u.drv_enable.val().to_u64() as u128,
        u.limit_neg_active.val().to_u64() as u128,
        u.limit_pos_active.val().to_u64() as u128,
        u.home_active.val().to_u64() as u128,
        u.alarm_active.val().to_u64() as u128,
        u.home_latch.val().to_u64() as u128,
        u.probe_latch.val() as u128,
        u.axis_stop.val().to_u64() as u128,
        u.stop_tog.val().to_u64() as u128,
    ]
}

fn model_out(o: &tdm_stepper::model::io::IoOutputs) -> Vec<u128> {
    vec![
        o.hard_stop as u128,
        o.estop_latched as u128,
        o.estop_active as u128,
        o.probe_active as u128,
        o.wd_tripped as u128,
        o.drv_enable as u128,
        o.limit_neg as u128,
        o.limit_pos as u128,
        o.home as u128,
        o.alarm as u128,
        o.home_latch as u128,
        o.probe_latch as u128,
        o.axis_stop as u128,
        o.stop_tog as u128,
    ]
}

/// The model's outputs for `rows`, None before the synchronisers have clocked twice.
fn io_model(rows: &[Vec<u128>]) -> Vec<Vec<Option<u128>>> {
    let mut m = MachineIoModel::new(K);
    rows.iter()
        .enumerate()
        .map(|(r, row)| {
            let (reset, run, pins, cfg, cmd) = unrow(row);
            let out = model_out(&m.outputs(&cfg));
            m.clock(&cfg, &pins, &cmd, run, reset);
            out.into_iter().map(|v| (r >= 3).then_some(v)).collect()
        })
        .collect()
}

fn io_spec() -> TbSpec {
    TbSpec {
        clock: "clock".into(),
        inputs: vec![
            Port::new("reset", 1),
            Port::new("run", 1),
            Port::new("estop_n", 1),
            Port::new("probe", 1),
            Port::new("limit_neg", K),
            Port::new("limit_pos", K),
            Port::new("home", K),
            Port::new("alarm", K),
            Port::new("polarity", 6),
            Port::new("filter", 24),
            Port::new("prescale", 16),
            Port::new("edges", 2),
            Port::new("wd_timeout", 16),
            Port::new("estop_rearm", 1),
            Port::new("wd_feed", 1),
            Port::new("wd_rearm", 1),
            Port::new("dir", K),
            Port::new("active", K),
        ],
        outputs: vec![
            Port::new("hard_stop", 1),
            Port::new("estop_latched", 1),
            Port::new("estop_active", 1),
            Port::new("probe_active", 1),
            Port::new("wd_tripped", 1),
            Port::new("drv_enable", K),
            Port::new("limit_neg_active", K),
            Port::new("limit_pos_active", K),
            Port::new("home_active", K),
            Port::new("alarm_active", K),
            Port::new("home_latch", K),
            Port::new("probe_latch", 1),
            Port::new("axis_stop", K),
            Port::new("stop_tog", K),
        ],
    }
}

#[test]
fn machine_io_equals_the_model_three_ways() {
    let mut rng = Rng(0x10_5afe_7e57);
    let mut gens: Vec<PinGen> = (0..2 + 6 * K).map(|_| PinGen::new(false)).collect();
    let mut rows = Vec::new();
    for phase in 0..12u64 {
        let cfg = IoConfig {
            polarity: (rng.next() % 64) as u8,
            filter: std::array::from_fn(|_| if phase % 3 == 0 { 0 } else { (rng.next() % 16) as u8 }),
            prescale: if phase % 2 == 0 { 0 } else { (rng.next() % 4) as u16 },
            edges: (rng.next() % 4) as u8,
            wd_timeout: if phase % 4 == 3 { 0 } else { 1 + (rng.next() % 2) as u16 },
        };
        for k in 0..2500u64 {
            let estop_n = gens[0].next(&mut rng, 900);
            let probe = gens[1].next(&mut rng, 200);
            let mut word = |base: usize| (0..K).map(|a| (gens[base + a].next(&mut rng, 300) as u32) << a).sum::<u32>();
            let pins = IoPins {
                estop_n,
                probe,
                limit_neg: word(2),
                limit_pos: word(2 + K),
                home: word(2 + 2 * K),
                alarm: word(2 + 3 * K),
                // The core's DIR and moving flags: long stretches, short ones too.
                dir: word(2 + 4 * K),
                active: word(2 + 5 * K),
            };
            // Feeds mostly every few hundred cycles, with gaps long enough to trip.
            let feed_every = if phase % 3 == 1 { 3000 } else { 500 };
            let cmd = IoCommands {
                estop_rearm: rng.next() % 200 == 0,
                wd_feed: k % feed_every == feed_every - 1 && rng.next() % 4 != 0,
                wd_rearm: rng.next() % 700 == 0,
            };
            let reset = (phase == 0 && k < 3) || (k < 2 && rng.next() % 4 == 0);
            rows.push(io_row(reset, k % 1000 != 999, &pins, &cfg, &cmd));
        }
    }
    let want = io_model(&rows);
    let count = |p: usize| want.iter().filter(|w| w[p].map_or(false, |v| v != 0)).count();
    // The stimulus reaches every output both ways.
    assert!(count(4) > 100 && count(4) < rows.len() - 100, "watchdog trips: {}", count(4));
    assert!(count(1) > 100 && count(1) < rows.len() - 100, "e-stop latched: {}", count(1));
    assert!(count(10) > 20 && count(11) > 5, "latch strobes: {} home, {} probe", count(10), count(11));
    assert!(count(5) > 1000, "drivers enabled: {}", count(5));
    let tog_changes = want.windows(2).filter(|w| w[0][13].is_some() && w[0][13] != w[1][13]).count();
    assert!(count(12) > 1000 && count(12) < rows.len() - 1000 && tog_changes > 50, "axis stops: {} cycles, {tog_changes} events", count(12));
    three_ways("machine_io", io_uut, |u, c| u.clock.next = Clock::from(c), set_io, get_io, &io_spec(), &rows, &want);
}

/// The rust-hdl block over `rows`.
fn run_io(rows: &[Vec<u128>]) -> Vec<Vec<u128>> {
    run_rust_hdl(&mut io_uut(), rows, |u, c| u.clock.next = Clock::from(c), set_io, get_io)
}

const OUT_HARD: usize = 0;
const OUT_LATCHED: usize = 1;
const OUT_ESTOP: usize = 2;
const OUT_TRIPPED: usize = 4;
const OUT_DRV: usize = 5;
const OUT_HOME: usize = 8;
const OUT_HOME_LATCH: usize = 10;
const OUT_PROBE_LATCH: usize = 11;

/// A scripted run: `f(cycle)` gives the pins and commands; reset for the first 3 rows.
fn scripted(cfg: IoConfig, cycles: usize, f: impl Fn(usize) -> (IoPins, IoCommands)) -> Vec<Vec<u128>> {
    let rows: Vec<Vec<u128>> = (0..cycles)
        .map(|c| {
            let (pins, cmd) = f(c);
            io_row(c < 3, true, &pins, &cfg, &cmd)
        })
        .collect();
    let out = run_io(&rows);
    // Whatever the script, the block is the model's.
    check(&io_model(&rows), &defined(out.clone()), "scripted run");
    out
}

/// Every input inactive, with the e-stop active low (polarity bit 0 set, as in these scripts).
fn released() -> IoPins {
    IoPins { estop_n: true, ..Default::default() }
}

#[test]
fn filter_latency_is_two_plus_n_and_shorter_pulses_are_ignored() {
    for n in [0u8, 1, 5, FILTER_MAX_SAMPLES] {
        let cfg = IoConfig { polarity: 1, filter: [n; 6], ..Default::default() };
        // home of axis 1: a pulse of n cycles (ignored), then a level change at cycle 200.
        let out = scripted(cfg, 300, |c| {
            let on = (100..100 + n as usize).contains(&c) || c >= 200;
            (IoPins { home: (on as u32) << 1, ..released() }, IoCommands::default())
        });
        let first = out.iter().position(|o| o[OUT_HOME] >> 1 & 1 == 1).expect("home never active");
        // The pin is first sampled at the edge ending cycle 200; the level shows after
        // edge 200 + 2 + n, i.e. in cycle 200 + 2 + n + 1 - 1 of the rows (outputs are read
        // before each row's edge).
        assert_eq!(first as u64, 200 + pin_to_level_ticks(n) + 1, "n = {n}: pin to level");
        // The latch strobe is in the cycle before, so the latch and the level change together.
        assert_eq!(out[first - 1][OUT_HOME_LATCH], 0b10, "n = {n}: latch strobe");
        assert_eq!(out.iter().filter(|o| o[OUT_HOME_LATCH] != 0).count(), 1, "n = {n}: one strobe");
    }
    // A pulse of exactly n + 1 cycles is taken.
    let n = 4u8;
    let cfg = IoConfig { polarity: 1, filter: [n; 6], ..Default::default() };
    let out = scripted(cfg, 200, |c| {
        (IoPins { home: (100..100 + n as usize + 1).contains(&c) as u32, ..released() }, IoCommands::default())
    });
    assert!(out.iter().any(|o| o[OUT_HOME] & 1 == 1), "a pulse of n + 1 samples is taken");
}

#[test]
fn estop_starts_latched_and_a_release_alone_never_clears_it() {
    let n = 2u8;
    let cfg = IoConfig { polarity: 1, filter: [n; 6], ..Default::default() }; // estop_n active low
    let rearm_at = [50usize, 400, 700];
    let out = scripted(cfg, 1000, |c| {
        // Released, then pressed from 300 to 600, released again.
        let pressed = (300..600).contains(&c);
        (IoPins { estop_n: !pressed, ..Default::default() }, IoCommands { estop_rearm: rearm_at.contains(&c), ..Default::default() })
    });
    // Latched after reset, until the re-arm at 50 (the input is released then).
    assert!(out[3..=50].iter().all(|o| o[OUT_LATCHED] == 1 && o[OUT_HARD] == 1), "starts latched");
    assert!(out[51..300].iter().all(|o| o[OUT_LATCHED] == 0 && o[OUT_HARD] == 0), "re-armed while released");
    assert_eq!(out[51][OUT_DRV], 0, "the enables are a cycle behind");
    assert!(out[52..300].iter().all(|o| o[OUT_DRV] == 0b111), "drivers enabled once re-armed");
    // Pressed at 300: the hard stop rises after 2 + n edges, as the filtered level does.
    let hard = 300 + out[300..].iter().position(|o| o[OUT_HARD] == 1).unwrap();
    assert_eq!(hard as u64, 300 + pin_to_level_ticks(n) + 1, "pin to hard stop");
    assert_eq!(out[hard][OUT_ESTOP], 1);
    assert_eq!(out[hard + 1][OUT_DRV], 0, "drivers disabled a cycle later");
    // The re-arm at 400 (still pressed) does nothing; the release at 600 does not clear it.
    assert!(out[hard..=700].iter().all(|o| o[OUT_LATCHED] == 1 || o[OUT_ESTOP] == 1));
    assert!(out[610..=700].iter().all(|o| o[OUT_LATCHED] == 1 && o[OUT_HARD] == 1 && o[OUT_ESTOP] == 0), "released, still latched");
    // Only the re-arm at 700, while released, clears it.
    assert_eq!(out[701][OUT_LATCHED], 0);
    assert_eq!(out[701][OUT_HARD], 0);
}

#[test]
fn the_watchdog_trips_after_exactly_its_timeout_and_never_while_fed() {
    let t = 2u16;
    let ticks = t as usize * WATCHDOG_UNIT_TICKS as usize;
    let cfg = IoConfig { polarity: 1, wd_timeout: t, ..Default::default() };
    // Re-armed (and e-stop re-armed) at 10; fed every `ticks` edges until 10 + 5·ticks, then starved.
    let last_feed = 10 + 5 * ticks;
    let out = scripted(cfg, last_feed + ticks + 50, |c| {
        let feed = c > 10 && c <= last_feed && (c - 10) % ticks == 0;
        (released(), IoCommands { estop_rearm: c == 10, wd_rearm: c == 10, wd_feed: feed })
    });
    assert!(out[11..=last_feed + ticks].iter().all(|o| o[OUT_TRIPPED] == 0), "tripped while fed");
    // The feed's edge ends row last_feed; the trip shows `ticks` edges later.
    assert_eq!(out[last_feed + ticks + 1][OUT_TRIPPED], 1, "trip after exactly the timeout");
    assert_eq!(out[last_feed + ticks + 1][OUT_HARD], 1);
    assert_eq!(out[last_feed + ticks + 2][OUT_DRV], 0);
    assert!(out[last_feed + ticks + 1..].iter().all(|o| o[OUT_TRIPPED] == 1), "sticky");
}

#[test]
fn latch_strobes_follow_the_chosen_edge() {
    for edges in 0..4u8 {
        let cfg = IoConfig { polarity: 1, edges, ..Default::default() };
        let out = scripted(cfg, 200, |c| {
            let on = (50..120).contains(&c);
            (IoPins { home: on as u32 * 0b100, probe: on, ..released() }, IoCommands::default())
        });
        let home_at: Vec<usize> = (0..out.len()).filter(|&r| out[r][OUT_HOME_LATCH] != 0).collect();
        let probe_at: Vec<usize> = (0..out.len()).filter(|&r| out[r][OUT_PROBE_LATCH] != 0).collect();
        let expect = |bit: u8| if edges >> bit & 1 == 0 { 50 + 2 } else { 120 + 2 };
        assert_eq!(home_at, vec![expect(0)], "edges {edges}: home");
        assert_eq!(out[home_at[0]][OUT_HOME_LATCH], 0b100);
        assert_eq!(probe_at, vec![expect(1)], "edges {edges}: probe");
    }
}
