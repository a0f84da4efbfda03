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
        cfg.stop_mode as u128,
        cfg.home_stop as u128,
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
        stop_mode: r[18] as u8,
        home_stop: r[19] as u32,
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
    u.stop_mode.next = Bits::<4>::from(r[18] as u64);
    u.home_stop.next = Bits::<K>::from(r[19] as u64);
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
        u.axis_cstop.val().to_u64() as u128,
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
        o.axis_cstop as u128,
    ]
}

/// The model's outputs for `rows`, None before the synchronisers have clocked twice.
fn io_model(rows: &[Vec<u128>]) -> Vec<Vec<Option<u128>>> {
    io_model_of(rows, tdm_stepper::regs::IO_ALL)
}

/// [`io_model`] for a block with the groups `groups` only.
fn io_model_of(rows: &[Vec<u128>], groups: u8) -> Vec<Vec<Option<u128>>> {
    let mut m = MachineIoModel::new(K).with_groups(groups);
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
            Port::new("stop_mode", 4),
            Port::new("home_stop", K),
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
            Port::new("axis_cstop", K),
        ],
    }
}

/// Random pins, configuration and commands over 12 phases (every stop mode after the
/// first), with resets.
fn random_io_rows(seed: u64) -> Vec<Vec<u128>> {
    let mut rng = Rng(seed);
    let mut gens: Vec<PinGen> = (0..2 + 6 * K).map(|_| PinGen::new(false)).collect();
    let mut rows = Vec::new();
    for phase in 0..12u64 {
        let cfg = IoConfig {
            polarity: (rng.next() % 64) as u8,
            filter: std::array::from_fn(|_| if phase % 3 == 0 { 0 } else { (rng.next() % 16) as u8 }),
            prescale: if phase % 2 == 0 { 0 } else { (rng.next() % 4) as u16 },
            edges: (rng.next() % 4) as u8,
            wd_timeout: if phase % 4 == 3 { 0 } else { 1 + (rng.next() % 2) as u16 },
            // Every stop mode (hard in phase 0), stop on home on some axes.
            stop_mode: if phase == 0 { 0 } else { (rng.next() % 16) as u8 },
            home_stop: (rng.next() % (1 << K)) as u32,
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
                wd_rearm: rng.next() % 2000 == 0,
            };
            let reset = (phase == 0 && k < 3) || (k < 2 && rng.next() % 4 == 0);
            rows.push(io_row(reset, k % 1000 != 999, &pins, &cfg, &cmd));
        }
    }
    rows
}

#[test]
fn machine_io_equals_the_model_three_ways() {
    let rows = random_io_rows(0x10_5afe_7e57);
    let want = io_model(&rows);
    let count = |p: usize| want.iter().filter(|w| w[p].map_or(false, |v| v != 0)).count();
    // The stimulus reaches every output both ways.
    assert!(count(4) > 100 && count(4) < rows.len() - 100, "watchdog trips: {}", count(4));
    assert!(count(1) > 100 && count(1) < rows.len() - 100, "e-stop latched: {}", count(1));
    assert!(count(10) > 20 && count(11) > 5, "latch strobes: {} home, {} probe", count(10), count(11));
    assert!(count(5) > 1000, "drivers enabled: {}", count(5));
    let tog_changes = want.windows(2).filter(|w| w[0][13].is_some() && w[0][13] != w[1][13]).count();
    assert!(count(12) > 1000 && count(12) < rows.len() - 1000 && tog_changes > 50, "axis stops: {} cycles, {tog_changes} events", count(12));
    let cs_cycles = count(14);
    assert!(cs_cycles > 1000 && cs_cycles < rows.len() - 1000, "controlled stop requests: {cs_cycles} cycles");
    three_ways("machine_io", io_uut, |u, c| u.clock.next = Clock::from(c), set_io, get_io, &io_spec(), &rows, &want);
}

/// The block of an export with some groups only (`--io limits,home,watchdog`), three
/// ways over the same kind of stimulus: the other groups' inputs read inactive and
/// drive nothing, the e-stop latch never sets (no e-stop group: no re-arm needed), and
/// the kept groups behave as in the whole block.
#[test]
fn machine_io_with_some_groups_equals_the_model_three_ways() {
    use tdm_stepper::regs::{IO_HOME, IO_LIMITS, IO_WATCHDOG};
    let groups = IO_LIMITS | IO_HOME | IO_WATCHDOG;
    let rows: Vec<Vec<u128>> = random_io_rows(0x6a09_e667).into_iter().take(12_000).collect();
    let want = io_model_of(&rows, groups);
    let count = |p: usize| want.iter().filter(|w| w[p].map_or(false, |v| v != 0)).count();
    assert_eq!((count(1), count(2), count(3), count(9), count(11)), (0, 0, 0, 0, 0), "no e-stop, probe or alarm");
    assert!(count(4) > 100 && count(6) + count(7) > 1000 && count(8) > 1000 && count(12) > 100, "trips, limits, home, stops");
    let make = || {
        let mut u = MachineIo::<K>::default().with_groups(groups);
        u.connect_ports();
        u
    };
    three_ways("machine_io_groups", make, |u, c| u.clock.next = Clock::from(c), set_io, get_io, &io_spec(), &rows, &want);
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
    // Re-armed while released: the latch at once, the hard stop and the enables (both
    // registered) a cycle later.
    assert!(out[51..300].iter().all(|o| o[OUT_LATCHED] == 0), "re-armed while released");
    assert_eq!((out[51][OUT_HARD], out[51][OUT_DRV]), (1, 0), "the hard stop and the enables are a cycle behind");
    assert!(out[52..300].iter().all(|o| o[OUT_HARD] == 0), "the hard stop released");
    assert!(out[52..300].iter().all(|o| o[OUT_DRV] == 0b111), "drivers enabled once re-armed");
    // Pressed at 300: the filtered level rises after 2 + n edges, the (registered) hard
    // stop one edge later, and the drivers' enables fall with it.
    let hard = 300 + out[300..].iter().position(|o| o[OUT_HARD] == 1).unwrap();
    assert_eq!(hard as u64, 300 + pin_to_level_ticks(n) + 2, "pin to hard stop");
    assert_eq!((out[hard - 1][OUT_ESTOP], out[hard - 2][OUT_ESTOP]), (1, 0), "the level a tick before the hard stop");
    assert_eq!((out[hard - 1][OUT_DRV], out[hard][OUT_DRV]), (0b111, 0), "drivers disabled with the hard stop");
    // The re-arm at 400 (still pressed) does nothing; the release at 600 does not clear it.
    assert!(out[hard..=700].iter().all(|o| o[OUT_LATCHED] == 1 || o[OUT_ESTOP] == 1));
    assert!(out[610..=700].iter().all(|o| o[OUT_LATCHED] == 1 && o[OUT_HARD] == 1 && o[OUT_ESTOP] == 0), "released, still latched");
    // Only the re-arm at 700, while released, clears it.
    assert_eq!(out[701][OUT_LATCHED], 0);
    assert_eq!((out[701][OUT_HARD], out[702][OUT_HARD]), (1, 0));
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
    // The hard stop (registered) and the enables a tick later.
    assert_eq!((out[last_feed + ticks + 1][OUT_HARD], out[last_feed + ticks + 2][OUT_HARD]), (0, 1));
    assert_eq!((out[last_feed + ticks + 1][OUT_DRV], out[last_feed + ticks + 2][OUT_DRV]), (0b111, 0));
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

// ---- The push guard --------------------------------------------------------------

use tdm_stepper::hdl::push_guard::{PushGuard, GUARD_CODE_CYCLE};
use tdm_stepper::model::guard::{GuardFlags, PushGuardModel, SoftLimits};
use tdm_stepper::regs;

fn guard_uut() -> PushGuard<K> {
    let mut u = PushGuard::<K>::default();
    u.connect_ports();
    u
}

/// Columns of a guard row as simulated (the offered command's kind, axis and steps in
/// three; the generator and the model keep them packed in one, as a command).
const G_COLS: [(&str, usize); 23] = [
    ("reset", 1),
    ("enable", 1),
    ("wr", 1),
    ("wr_addr", 9),
    ("wr_data", 16),
    ("rd", 1),
    ("rd_addr", 9),
    ("offer", 1),
    ("offer_kind", 2),
    ("offer_axis", 4),
    ("offer_steps", 32),
    ("accept", 1),
    ("st_valid", 1),
    ("st_axis", 4),
    ("st_pos", 32),
    ("st_taken", 8),
    ("st_busy", 1),
    ("st_pushed", 8),
    ("lim_neg", K),
    ("lim_pos", K),
    ("alarm", K),
    ("held_all", 1),
    ("stop_ev", K),
];

fn set_guard(u: &mut PushGuard<K>, r: &[u128]) {
    u.reset.next = r[0] == 1;
    u.enable.next = r[1] == 1;
    u.wr.next = r[2] == 1;
    u.wr_addr.next = Bits::<9>::from(r[3] as u64);
    u.wr_data.next = Bits::<16>::from(r[4] as u64);
    u.rd.next = r[5] == 1;
    u.rd_addr.next = Bits::<9>::from(r[6] as u64);
    u.offer.next = r[7] == 1;
    u.offer_kind.next = Bits::<2>::from(r[8] as u64);
    u.offer_axis.next = Bits::<4>::from(r[9] as u64);
    u.offer_steps.next = Bits::<32>::from(r[10] as u64);
    u.accept.next = r[11] == 1;
    u.st_valid.next = r[12] == 1;
    u.st_axis.next = Bits::<4>::from(r[13] as u64);
    u.st_pos.next = Bits::<32>::from(r[14] as u64);
    u.st_taken.next = Bits::<8>::from(r[15] as u64);
    u.st_busy.next = r[16] == 1;
    u.st_pushed.next = Bits::<8>::from(r[17] as u64);
    u.lim_neg.next = Bits::<K>::from(r[18] as u64);
    u.lim_pos.next = Bits::<K>::from(r[19] as u64);
    u.alarm.next = Bits::<K>::from(r[20] as u64);
    u.held_all.next = r[21] == 1;
    u.stop_ev.next = Bits::<K>::from(r[22] as u64);
}

/// A generated row (the command packed in column 8, the status word in 12) as simulated.
fn unpack_offer(r: &[u128]) -> Vec<u128> {
    let mut v = r[..8].to_vec();
    v.extend([r[8] >> 104 & 3, r[8] >> 96 & 0xF, r[8] >> 64 & 0xFFFF_FFFF]);
    v.extend_from_slice(&r[9..12]);
    v.extend([r[12] & 0xFFFF_FFFF, r[12] >> 32 & 0xFF, r[12] >> 56 & 1]);
    v.extend_from_slice(&r[13..]);
    v
}

/// The guard in a register-level model: [`PushGuardModel`] for the checks and the
/// plan, the pipeline's timing and the registers as the block comment gives them.
struct GuardTb {
    m: PushGuardModel,
    plan_known: [bool; K],
    sl_axis: u8,
    sl_min: u32,
    sl_max: u32,
    refused: bool,
    hi: Option<u16>,
    /// A push in the pipeline: (axis, steps, cycle it is in, verdict).
    push: Option<(usize, i32, u8, Option<Result<i64, u8>>)>,
}

impl GuardTb {
    fn new() -> Self {
        GuardTb {
            m: PushGuardModel::new(K),
            plan_known: [false; K],
            sl_axis: 0,
            sl_min: 0,
            sl_max: 0,
            refused: false,
            hi: Some(0),
            push: None,
        }
    }

    /// The outputs before the edge, then the edge.
    fn clock(&mut self, r: &[u128]) -> Vec<Option<u128>> {
        let a = |n: &str| regs::addr(n) as u128;
        let (reset, enable, wr, waddr, wdata, rd, raddr) = (r[0] == 1, r[1] == 1, r[2] == 1, r[3], r[4] as u16, r[5] == 1, r[6]);
        let bit = |col: usize, ax: usize| (r[col] >> ax) & 1 == 1;
        // Cycle 1 of a push: the verdict from this cycle's state.
        if let Some((ax, steps, 1, None)) = self.push {
            let flags = GuardFlags { limit_neg: bit(14, ax), limit_pos: bit(15, ax), held: r[17] == 1 || bit(16, ax) };
            self.push = Some((ax, steps, 1, Some(self.m.check(ax, steps, flags).map_err(|e| e.code()))));
        }
        let code = match self.push {
            Some((_, _, c, Some(v))) if c as usize == GUARD_CODE_CYCLE => v.err().unwrap_or(0) as u128,
            _ => 0,
        };
        let sa = self.sl_axis as usize;
        // The plan memory's read port is the check's in a push's cycle 1.
        let pa = match self.push {
            Some((ax, _, 1, _)) => ax,
            _ => sa,
        };
        let rdv: Option<u128> = if raddr == a("SL_AXIS") {
            Some(self.sl_axis as u128)
        } else if raddr == a("SL_MIN_LO") {
            Some((self.sl_min & 0xFFFF) as u128)
        } else if raddr == a("SL_MIN_HI") {
            Some((self.sl_min >> 16) as u128)
        } else if raddr == a("SL_MAX_LO") {
            Some((self.sl_max & 0xFFFF) as u128)
        } else if raddr == a("SL_MAX_HI") {
            Some((self.sl_max >> 16) as u128)
        } else if raddr == a("SL_STATUS") {
            let stale = sa < K && self.m.stale[sa];
            let on = sa < K && self.m.soft[sa].is_some();
            Some(on as u128 | (stale as u128) << 1 | (self.refused as u128) << 2)
        } else if raddr == a("PLAN_LO") {
            (pa < K && self.plan_known[pa]).then(|| (self.m.plan[pa] as u32 & 0xFFFF) as u128)
        } else if raddr == a("PLAN_HI") {
            self.hi.map(|h| h as u128)
        } else {
            Some(0)
        };
        let out = vec![Some(code), rdv];

        // The edge.
        if rd && raddr == a("PLAN_LO") {
            self.hi = (pa < K && self.plan_known[pa]).then(|| (self.m.plan[pa] as u32 >> 16) as u16);
        }
        let mut w_write = false;
        if let Some((ax, _, 4, Some(Ok(end)))) = self.push {
            if r[9] == 1 {
                self.m.accept(ax, end);
                self.plan_known[ax] = true;
                w_write = true;
            }
        }
        let word = r[12];
        let (st_ax, pos, taken, busy) = (r[11] as usize, word as u32 as i32, (word >> 32) as u8, (word >> 56) & 1 == 1);
        let resync = r[10] == 1 && !busy && taken == r[13] as u8;
        if resync && !w_write {
            self.m.resync(st_ax, pos);
            self.plan_known[st_ax] = true;
        }
        let kind = (r[8] >> 104) & 3;
        let all = r[17] == 1 || !enable || (r[7] == 1 && kind == 2);
        for ax in 0..K {
            if all || bit(18, ax) || bit(16, ax) {
                self.m.mark_stale(ax);
            }
        }
        if wr {
            if waddr == a("SL_AXIS") {
                self.sl_axis = (wdata & 0xF) as u8;
            }
            if waddr == a("SL_MIN_LO") {
                self.sl_min = (self.sl_min & 0xFFFF_0000) | wdata as u32;
            }
            if waddr == a("SL_MIN_HI") {
                self.sl_min = (self.sl_min & 0xFFFF) | (wdata as u32) << 16;
            }
            if waddr == a("SL_MAX_LO") {
                self.sl_max = (self.sl_max & 0xFFFF_0000) | wdata as u32;
            }
            if waddr == a("SL_MAX_HI") {
                self.sl_max = (self.sl_max & 0xFFFF) | (wdata as u32) << 16;
            }
            if waddr == a("SL_APPLY") {
                let en = wdata & 1 == 1;
                let lim = SoftLimits { min: self.sl_min as i32, max: self.sl_max as i32 };
                if sa >= K {
                    self.refused = true;
                } else if en {
                    if self.m.set_soft(sa, Some(lim)).is_err() {
                        self.refused = true;
                    }
                } else {
                    self.m.set_soft(sa, None).unwrap();
                }
            }
            if waddr == a("SL_STATUS") && wdata & 4 != 0 {
                self.refused = false;
            }
        }
        // The pipeline moves on; a new push enters it.
        self.push = match self.push {
            Some((ax, s, c, v)) if c < 4 => Some((ax, s, c + 1, v)),
            _ => None,
        };
        if r[7] == 1 && kind == 0 {
            self.push = Some((((r[8] >> 96) & 0xF) as usize, (r[8] >> 64) as u32 as i32, 1, None));
        }
        if reset || !enable {
            self.push = None;
        }
        if reset {
            let plan = self.m.plan.clone();
            self.m = PushGuardModel::new(K);
            self.m.plan = plan; // the plan memory keeps its words; stale covers them
            self.sl_axis = 0;
            self.sl_min = 0;
            self.sl_max = 0;
            self.refused = false;
            self.hi = Some(0);
        }
        out
    }
}

#[test]
fn push_guard_equals_the_model_three_ways() {
    let mut rng = Rng(0x6a4d_0001);
    let a = |n: &str| regs::addr(n) as u128;
    let guard_regs = ["SL_AXIS", "SL_MIN_LO", "SL_MIN_HI", "SL_MAX_LO", "SL_MAX_HI", "SL_STATUS", "PLAN_LO", "PLAN_HI"];
    let mut rows: Vec<Vec<u128>> = Vec::new();
    let (mut lneg, mut lpos, mut alarm, mut held, mut enable) = (0u128, 0u128, 0u128, false, true);
    let mut pos = [0i32; K];
    let mut since_offer = 10;
    let mut tb = GuardTb::new();
    let mut want: Vec<Vec<Option<u128>>> = Vec::new();
    for cyc in 0..12_000usize {
        let mut r = vec![0u128; G_COLS.len() - 4];
        r[0] = (cyc < 3 || rng.next() % 3000 == 0) as u128;
        if rng.next() % 400 == 0 {
            enable = !enable || rng.next() % 2 == 0;
        }
        r[1] = enable as u128;
        // Register writes: mostly the soft limits around the positions in use.
        if rng.next() % 9 == 0 {
            r[2] = 1;
            let which = rng.next() % 9;
            let v = (rng.next() % 400) as i32 - 200;
            let (addr, data) = match which {
                0 => (a("SL_AXIS"), rng.next() % (K as u64 + 1)),
                1 | 2 => (a("SL_MIN_LO"), (v - 50) as u32 as u64 & 0xFFFF),
                3 => (a("SL_MIN_HI"), if v < 60 { 0xFFFF } else { 0 }),
                4 | 5 => (a("SL_MAX_LO"), (v + 50) as u32 as u64 & 0xFFFF),
                6 => (a("SL_MAX_HI"), if v < -60 { 0xFFFF } else { 0 }),
                7 => (a("SL_APPLY"), rng.next() % 4),
                _ => (a("SL_STATUS"), rng.next() % 8),
            };
            r[3] = addr;
            r[4] = data as u128;
        }
        r[5] = (rng.next() % 4 == 0) as u128;
        r[6] = if rng.next() % 8 == 0 { a("IO_STATUS") } else { a(guard_regs[(rng.next() % 8) as usize]) };
        // A command into the check at most every 4 cycles.
        since_offer += 1;
        if since_offer >= 4 && rng.next() % 3 == 0 {
            since_offer = 0;
            r[7] = 1;
            let kind = match rng.next() % 40 {
                0 => 2u128,
                1 => 1,
                _ => 0,
            };
            let ax = (rng.next() % K as u64) as usize;
            let steps: i32 = match rng.next() % 6 {
                0 => 0,
                1 => i32::MAX - (rng.next() % 3) as i32,
                2 => i32::MIN + (rng.next() % 3) as i32,
                _ => (rng.next() % 160) as i32 - 80,
            };
            r[8] = (kind << 104) | ((ax as u128) << 96) | ((steps as u32 as u128) << 64) | rng.next_u128() & ((1 << 64) - 1);
        }
        // The check's verdict in cycle 4: a random accept (the segment's own checks
        // pass or not); noise elsewhere.
        r[9] = (rng.next() % 3 != 0) as u128;
        // Status words: half of them show their axis at rest with nothing untaken.
        if rng.next() % 3 == 0 {
            r[10] = 1;
            let ax = (rng.next() % K as u64) as usize;
            if rng.next() % 5 == 0 {
                pos[ax] = (rng.next() % 300) as i32 - 150;
            }
            let pushed = rng.next() % 256;
            let idle = rng.next() % 2 == 0;
            let taken = if idle { pushed } else { (pushed + 1 + rng.next() % 3) % 256 };
            let busy = !idle && rng.next() % 2 == 0 || idle && rng.next() % 6 == 0;
            r[11] = ax as u128;
            r[12] = (pos[ax] as u32 as u128) | (taken as u128) << 32 | (rng.next() as u128 & 0xFFFF) << 40 | (busy as u128) << 56 | 1 << 57;
            r[13] = pushed as u128;
        }
        if rng.next() % 150 == 0 {
            lneg ^= 1 << (rng.next() % K as u64);
        }
        if rng.next() % 150 == 0 {
            lpos ^= 1 << (rng.next() % K as u64);
        }
        if rng.next() % 300 == 0 {
            alarm ^= 1 << (rng.next() % K as u64);
        }
        if rng.next() % 500 == 0 {
            held = !held && rng.next() % 3 == 0;
        }
        r[14] = lneg;
        r[15] = lpos;
        r[16] = alarm;
        r[17] = held as u128;
        r[18] = if rng.next() % 200 == 0 { 1 << (rng.next() % K as u64) } else { 0 };
        // The check never passes a push the guard rejects.
        if let Some((_, _, 4, Some(Err(_)))) = tb.push {
            r[9] = 0;
        }
        let o = tb.clock(&r);
        // Before the first reset's edge nothing is defined in Verilog.
        want.push(if cyc < 1 { vec![None, None] } else { o });
        rows.push(r);
    }
    for code in [7u128, 8, 9] {
        let n = want.iter().filter(|w| w[0] == Some(code)).count();
        assert!(n >= 20, "stimulus too thin: code {code} {n} times");
    }
    let passed = want.iter().zip(&rows).filter(|(_, r)| r[7] == 1).count();
    assert!(passed > 1500, "{passed} commands");
    let spec = TbSpec {
        clock: "clock".into(),
        inputs: G_COLS.iter().map(|(n, w)| Port::new(n, *w)).collect(),
        outputs: vec![Port::new("code", 4), Port::new("rd_data", 16)],
    };
    three_ways(
        "push_guard",
        guard_uut,
        |u, c| u.clock.next = Clock::from(c),
        set_guard,
        |u| vec![u.code.val().to_u64() as u128, u.rd_data.val().to_u64() as u128],
        &spec,
        &rows.iter().map(|r| unpack_offer(r)).collect::<Vec<_>>(),
        &want,
    );
}

const OUT_AXIS_STOP: usize = 12;
const OUT_AXIS_CSTOP: usize = 14;

/// STOP_MODE routes each source to the hard or the controlled stop: a limit toward
/// which axis 0 moves, axis 1's alarm, axis 2's home latch (armed), the watchdog.
#[test]
fn stop_modes_route_each_source_to_the_hard_or_the_controlled_stop() {
    use tdm_stepper::model::io::{MODE_ALARM, MODE_HOME, MODE_LIMITS, MODE_WATCHDOG};
    for mode in [0u8, MODE_LIMITS | MODE_HOME, MODE_ALARM | MODE_WATCHDOG, 0xF] {
        let cfg = IoConfig { polarity: 1, stop_mode: mode, home_stop: 0b100, wd_timeout: 1, ..Default::default() };
        let wd = WATCHDOG_UNIT_TICKS as usize;
        // Every axis active until 2000 (the ramps), then at rest; fed until 600.
        let out = scripted(cfg, 2100, |c| {
            let pins = IoPins {
                limit_pos: ((100..150).contains(&c) as u32) << 0,
                alarm: ((300..350).contains(&c) as u32) << 1,
                home: ((500..900).contains(&c) as u32) << 2,
                active: if c < 2000 { 0b111 } else { 0 },
                ..released()
            };
            let cmd = IoCommands { estop_rearm: c == 10, wd_rearm: c == 10, wd_feed: c > 10 && c <= 600 && c % 500 == 0 };
            (pins, cmd)
        });
        let rows = |mask: u128, col: usize, r: std::ops::Range<usize>| r.filter(|&i| out[i][col] & mask != 0).collect::<Vec<_>>();
        let cols = |m: u8| if mode & m == 0 { (OUT_AXIS_STOP, OUT_AXIS_CSTOP) } else { (OUT_AXIS_CSTOP, OUT_AXIS_STOP) };
        // The limit: pin at 100, level from row 103, toward it two cycles, registered (the
        // limits read active from the reset until filtered: skip those rows).
        // (on: the stop this source's mode picks; off: the other.)
        let (on, off) = cols(MODE_LIMITS);
        assert_eq!(rows(1, on, 20..400), (105..154).collect::<Vec<_>>(), "mode {mode:#x}: the limit");
        assert!(rows(1, off, 20..400).is_empty(), "mode {mode:#x}: the limit, other stop");
        let (on, off) = cols(MODE_ALARM);
        assert_eq!(rows(2, on, 20..450), (304..354).collect::<Vec<_>>(), "mode {mode:#x}: the alarm");
        assert!(rows(2, off, 20..450).is_empty(), "mode {mode:#x}: the alarm, other stop");
        // A controlled alarm keeps the axis's enable while it moves.
        let drv1 = out[340][OUT_DRV] >> 1 & 1;
        assert_eq!(drv1, (mode & MODE_ALARM != 0) as u128, "mode {mode:#x}: drv_enable during the alarm");
        // Home: the strobe in the cycle before the level (502 → 503), the stop one cycle later.
        let (on, off) = cols(MODE_HOME);
        assert_eq!(rows(4, on, 450..700), vec![503], "mode {mode:#x}: the stop on home");
        assert!(rows(4, off, 450..700).is_empty(), "mode {mode:#x}: home, other stop");
        // The watchdog: fed at 500, trips at 500 + wd + 1.
        let trip = 500 + wd + 1;
        assert_eq!(out[trip][OUT_TRIPPED], 1);
        assert_eq!(out[trip - 1][OUT_TRIPPED], 0);
        if mode & MODE_WATCHDOG == 0 {
            assert_eq!((out[trip][OUT_HARD], out[trip + 1][OUT_HARD]), (0, 1), "mode {mode:#x}: a hard trip stops a tick later");
            assert!(rows(7, OUT_AXIS_CSTOP, trip..2100).is_empty());
        } else {
            // Every axis asked to ramp down (registered), the hard stop only at rest.
            assert!(out[trip + 1..2000].iter().all(|o| o[OUT_AXIS_CSTOP] == 0b111 && o[OUT_HARD] == 0), "mode {mode:#x}: ramps");
            assert!(out[trip + 2..2000].iter().all(|o| o[OUT_DRV] == 0b111), "mode {mode:#x}: enabled while ramping");
            assert_eq!(out[2001][OUT_HARD], 0);
            assert_eq!(out[2002][OUT_HARD], 1, "mode {mode:#x}: hard once no axis is active (two ticks: registered twice)");
            assert_eq!((out[2001][OUT_DRV], out[2002][OUT_DRV]), (0b111, 0));
        }
    }
}
