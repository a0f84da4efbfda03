//! Encoder feedback: the decoder three ways (rust-hdl, the exported Verilog in
//! Verilator and Icarus, and `model::encoder`) on random traffic, then what the docs
//! promise, on the model the three-way test holds the block to: an encoder following
//! STEP/DIR at 4,000 counts against 3,200 steps per revolution through reversals,
//! bounce and a stall and a slip; the index latch and its clear; the maximum count
//! rate with asynchronous pins.

mod common;

use common::*;
use rust_hdl::prelude::*;
use tdm_stepper::hdl::enc_bank::EncoderBank;
use tdm_stepper::hdl::enc_decoder::EncDecoder;
use tdm_stepper::hdl::follow_err::{FollowErr, FOLLOW_ERR_LATENCY};
use tdm_stepper::model::encoder::{
    deviation, follow_refresh_ticks, BankInputs, EncoderBankModel, max_count_rate_ticks, EncConfig, EncPins, EncoderModel, FollowErrModel, QuadratureGen, FILTER_MAX,
    VEL_MAX,
};
use tdm_stepper::verify::{Port, TbSpec};

fn decoder_uut() -> EncDecoder {
    let mut u = EncDecoder::default();
    u.connect_ports();
    u
}

/// Input columns: reset, a, b, z, mode, arm, probe, vel_tick, invert, ack, position.
const IN_COLS: [(&str, usize); 11] =
    [("reset", 1), ("a", 1), ("b", 1), ("z", 1), ("mode", 8), ("arm", 1), ("probe", 1), ("vel_tick", 1), ("invert", 1), ("ack", 1), ("position", 8)];
const OUT_COLS: [(&str, usize); 20] = [
    ("count", 8),
    ("index_count", 8),
    ("probe_count", 8),
    ("illegal", 8),
    ("cnew", 1),
    ("inew", 1),
    ("iafter", 1),
    ("pnew", 1),
    ("pafter", 1),
    ("armed", 1),
    ("clearing", 1),
    ("enew", 1),
    ("e2", 1),
    ("period", 8),
    ("age", 8),
    ("last_dir", 1),
    ("lev_a", 1),
    ("lev_b", 1),
    ("lev_z", 1),
    ("index_pos", 8),
];

/// The narrow view the HDL decoder shows.
fn model_outputs(m: &EncoderModel) -> Vec<u128> {
    let o = m.outputs().narrow();
    vec![
        o.count as u128,
        o.index_count as u128,
        o.probe_count as u128,
        o.illegal as u128,
        o.cnew as u128,
        o.inew as u128,
        o.iafter as u128,
        o.pnew as u128,
        o.pafter as u128,
        o.armed as u128,
        o.clearing as u128,
        o.enew as u128,
        o.e2 as u128,
        o.period as u128,
        o.age as u128,
        o.last_dir as u128,
        (o.levels & 1) as u128,
        (o.levels >> 1 & 1) as u128,
        (o.levels >> 2 & 1) as u128,
        o.index_pos as u128,
    ]
}

fn config_of(word: u128, invert: u128) -> EncConfig {
    let w = word as u8;
    EncConfig { filter: w & 0xF, invert: invert == 1, z_low: w >> 4 & 1 == 1, gate: w >> 5 & 1 == 1, gate_ab: w >> 6 & 3 }
}

/// Random traffic: an encoder walking toward random targets (reversals), slips of two
/// counts (both lines at once), bounce on A, random configurations changed under
/// reset, arms, probes, a prescaled velocity tick and visits every few ticks.
fn random_rows(seed: u64, phases: u64) -> Vec<Vec<u128>> {
    let mut rng = Rng(seed);
    let mut rows = Vec::new();
    let mut g = QuadratureGen::new(12 + (rng.next() % 20) as i64, 1);
    let mut target = 0i64;
    for phase in 0..phases {
        let cfg = EncConfig {
            filter: match phase % 4 {
                0 => 0,
                1 => FILTER_MAX,
                _ => (rng.next() % 6) as u8,
            },
            invert: rng.next() % 2 == 0,
            z_low: rng.next() % 2 == 0,
            gate: rng.next() % 2 == 0,
            gate_ab: (rng.next() % 4) as u8,
        };
        g.spacing = 1 + rng.next() % (2 * cfg.filter as u64 + 4);
        let every = 1 + rng.next() % 3;
        let visit = 1 + rng.next() % 40;
        let reset_rows = if phase == 0 { 4 } else { 1 + rng.next() % 2 };
        for k in 0..400u64 {
            if rng.next() % 60 == 0 {
                target = g.pos + (rng.next() % 80) as i64 - 40;
            }
            if rng.next() % 150 == 0 {
                g.pos -= 2; // a slip: both lines at once
            }
            let mut p = g.tick(target);
            if rng.next() % 25 == 0 {
                p.a = !p.a; // a one-tick glitch
            }
            rows.push(vec![
                (k < reset_rows) as u128,
                p.a as u128,
                p.b as u128,
                p.z as u128,
                cfg.word() as u128,
                (rng.next() % 90 == 0) as u128,
                (rng.next() % 70 == 0) as u128,
                (k % every == 0) as u128,
                cfg.invert as u128,
                (k % visit == 0) as u128,
                (rng.next() % 256) as u128,
            ]);
        }
    }
    rows
}

#[test]
fn decoder_equals_the_model_three_ways() {
    let rows = random_rows(0xe4c0_de01, 24);
    let mut m = EncoderModel::new();
    let mut want = Vec::new();
    let (mut counted, mut illegal, mut indexes, mut probes, mut after_clear) = (0, 0u64, 0, 0, 0);
    for (r, row) in rows.iter().enumerate() {
        let before = m.outputs();
        // The synchroniser's flip-flops are undefined in Verilog until reset loads the levels.
        want.push(model_outputs(&m).into_iter().map(|v| (r >= 3).then_some(v)).collect::<Vec<_>>());
        let pins = EncPins { a: row[1] == 1, b: row[2] == 1, z: row[3] == 1 };
        m.clock_visit(&config_of(row[4], row[8]), pins, row[5] == 1, row[6] == 1, row[7] == 1, row[9] == 1, row[10] as u32, row[0] == 1);
        let after = m.outputs();
        if row[0] == 0 {
            counted += (after.count != before.count) as u64;
            illegal += (after.illegal != before.illegal) as u64;
            indexes += (after.index_tog != before.index_tog) as u64;
            probes += (after.probe_tog != before.probe_tog) as u64;
            after_clear += ((after.iafter && !before.iafter) || (after.pafter && !before.pafter)) as u64;
        }
    }
    assert!(
        counted > 1200 && illegal > 20 && indexes > 40 && probes > 40 && after_clear > 5,
        "stimulus too thin: {counted} counts, {illegal} illegal, {indexes} indexes, {probes} probes, {after_clear} latches after a clear"
    );
    let spec = TbSpec {
        clock: "clock".into(),
        inputs: IN_COLS.iter().map(|(n, w)| Port::new(n, *w)).collect(),
        outputs: OUT_COLS.iter().map(|(n, w)| Port::new(n, *w)).collect(),
    };
    three_ways(
        "enc_decoder",
        decoder_uut,
        |u, c| u.clock.next = Clock::from(c),
        |u, r| {
            u.reset.next = r[0] == 1;
            u.a.next = r[1] == 1;
            u.b.next = r[2] == 1;
            u.z.next = r[3] == 1;
            u.mode.next = (r[4] as u64).into();
            u.arm.next = r[5] == 1;
            u.probe.next = r[6] == 1;
            u.vel_tick.next = r[7] == 1;
            u.invert.next = r[8] == 1;
            u.ack.next = r[9] == 1;
            u.position.next = (r[10] as u64).into();
        },
        |u| {
            vec![
                u.count.val().to_u64() as u128,
                u.index_count.val().to_u64() as u128,
                u.probe_count.val().to_u64() as u128,
                u.illegal.val().to_u64() as u128,
                u.cnew.val() as u128,
                u.inew.val() as u128,
                u.iafter.val() as u128,
                u.pnew.val() as u128,
                u.pafter.val() as u128,
                u.armed.val() as u128,
                u.clearing.val() as u128,
                u.enew.val() as u128,
                u.e2.val() as u128,
                u.period.val().to_u64() as u128,
                u.age.val().to_u64() as u128,
                u.last_dir.val() as u128,
                u.lev_a.val() as u128,
                u.lev_b.val() as u128,
                u.lev_z.val() as u128,
                u.index_pos.val().to_u64() as u128,
            ]
        },
        &spec,
        &rows,
        &want,
    );
}

/// A line as an asynchronous pin: each change is seen by the synchroniser at its tick
/// or one tick later, at random.
struct Jitter {
    seen: bool,
    pending: Option<bool>,
}

impl Jitter {
    fn new(level: bool) -> Self {
        Jitter { seen: level, pending: None }
    }
    fn next(&mut self, ideal: bool, rng: &mut Rng) -> bool {
        if let Some(v) = self.pending.take() {
            self.seen = v;
        }
        if ideal != self.seen && self.pending.is_none() {
            if rng.next() % 2 == 0 {
                self.seen = ideal;
            } else {
                self.pending = Some(ideal);
            }
        }
        self.seen
    }
}

/// Runs the model decoder from reset on `pins`, returning it and its outputs per tick.
fn decode(cfg: &EncConfig, pins: impl Iterator<Item = EncPins>) -> (EncoderModel, Vec<tdm_stepper::model::encoder::EncOutputs>) {
    let mut m = EncoderModel::new();
    for _ in 0..3 {
        m.clock(cfg, QuadratureGen::lines(0, 1 << 20), false, false, true, true);
    }
    let mut outs = vec![];
    for p in pins {
        m.clock(cfg, p, false, false, true, false);
        outs.push(m.outputs());
    }
    (m, outs)
}

#[test]
fn no_count_is_lost_at_the_documented_rate_with_asynchronous_pins() {
    let mut rng = Rng(0xe4c0_de02);
    for filter in [0u8, 1, 3, 7, FILTER_MAX] {
        let spacing = max_count_rate_ticks(filter);
        let mut g = QuadratureGen::new(1 << 20, spacing);
        let (mut ja, mut jb) = (Jitter::new(false), Jitter::new(false));
        let mut pins = vec![];
        for t in 0..60_000u64 {
            let target = if t < 30_000 { 2_000 } else { -1_234 };
            let p = g.tick(target);
            pins.push(EncPins { a: ja.next(p.a, &mut rng), b: jb.next(p.b, &mut rng), z: false });
        }
        assert_eq!(g.pos, -1_234, "the walk reached its end (filter {filter})");
        pins.extend(std::iter::repeat(*pins.last().unwrap()).take(40));
        let (m, _) = decode(&EncConfig { filter, ..Default::default() }, pins.into_iter());
        assert_eq!(m.outputs().count as i32, -1_234, "filter {filter}, an edge every {spacing} ticks: a count lost");
        assert_eq!(m.outputs().illegal, 0, "filter {filter}: an illegal transition at the documented rate");
    }
    // The filter off counts at clk/2 (the target is clk/4).
    assert_eq!(max_count_rate_ticks(0), 2);
    // One tick faster than the bound, the filter loses edges (the bound is not loose).
    let spacing = max_count_rate_ticks(7) - 1;
    let mut g = QuadratureGen::new(1 << 20, spacing);
    let (mut ja, mut jb) = (Jitter::new(false), Jitter::new(false));
    let mut pins = vec![];
    for _ in 0..20_000u64 {
        let p = g.tick(3_000);
        pins.push(EncPins { a: ja.next(p.a, &mut rng), b: jb.next(p.b, &mut rng), z: false });
    }
    let (m, _) = decode(&EncConfig { filter: 7, ..Default::default() }, pins.into_iter());
    assert!(m.outputs().count != 3_000 || m.outputs().illegal != 0, "faster than the bound went unharmed");
}

const STEPS_REV: i64 = 3_200;
const COUNTS_REV: i64 = 4_000;

/// The pins of an encoder on a motor following STEP/DIR at 3,200 steps and 4,000
/// counts per revolution (floor(steps · 5 / 4) counts, one edge at a time): moves with
/// reversals, a step every 7 to 12 ticks, lines seen with a tick of jitter (`jitter`)
/// and contact bounce on B shorter than `filter` (`bounce`) where B has held its
/// level longer than the filter. Returns the pins, the
/// final count, the passes through an index and the bounces.
fn follow(filter: u8, jitter: bool, bounce: bool) -> (Vec<EncPins>, i64, usize, usize) {
    let mut b_held = 0;
    let mut rng = Rng(0xe4c0_de03);
    let mut steps = 0i64;
    let mut g = QuadratureGen::new(COUNTS_REV, max_count_rate_ticks(filter));
    let (mut ja, mut jb) = (Jitter::new(false), Jitter::new(false));
    let mut pins = vec![];
    let (mut bounces, mut indexes) = (0, 0);
    for &(delta, period) in &[(9_000i64, 7u64), (-2_500, 9), (6_400, 12), (-640, 8)] {
        let goal = steps + delta;
        while steps != goal {
            steps += delta.signum();
            for _ in 0..period {
                let before = g.pos;
                let p = g.tick((steps * COUNTS_REV).div_euclid(STEPS_REV));
                if g.pos != before && g.pos.rem_euclid(COUNTS_REV) == 0 {
                    indexes += 1;
                }
                let (a, b) = if jitter { (ja.next(p.a, &mut rng), jb.next(p.b, &mut rng)) } else { (p.a, p.b) };
                if bounce && b_held > filter && rng.next() % 20 == 0 {
                    // B bounces once the filter has taken its level (a bounce on an
                    // edge would only delay the edge).
                    bounces += 1;
                    for _ in 0..filter {
                        pins.push(EncPins { a, b: !b, z: p.z });
                    }
                }
                b_held = if pins.last().is_some_and(|l: &EncPins| l.b == b) { b_held + 1 } else { 0 };
                pins.push(EncPins { a, b, z: p.z });
            }
        }
    }
    let end = (steps * COUNTS_REV).div_euclid(STEPS_REV);
    for _ in 0..40 {
        pins.push(g.tick(end));
    }
    (pins, end, indexes, bounces)
}

#[test]
fn an_encoder_following_step_dir_is_counted_exactly_through_bounce_stall_and_slip() {
    let filter = 3u8;
    let cfg = EncConfig { filter, gate: true, gate_ab: 0, ..Default::default() };
    for (jitter, bounce) in [(false, false), (true, false), (false, true), (true, true)] {
        let (pins, end, expected_indexes, bounces) = follow(filter, jitter, bounce);
        assert!(!bounce || bounces > 50, "too little bounce: {bounces}");
        let what = format!("jitter {jitter}, bounce {bounce}");
        let (m, outs) = decode(&cfg, pins.clone().into_iter());
        let o = m.outputs();
        assert_eq!(o.count as i32 as i64, end, "{what}: the count equals the encoder's position");
        assert_eq!(o.illegal, 0, "{what}: bounce shorter than the filter is no fault");
        // Every index strobe latched a multiple of a revolution (the count is exact there).
        let mut latched = vec![];
        for w in outs.windows(2) {
            if w[1].index_tog != w[0].index_tog {
                latched.push(w[1].index_count as i32 as i64);
            }
        }
        assert_eq!(latched.len(), expected_indexes, "{what}: one index per pass through a revolution's position 0");
        assert!(latched.len() >= 4);
        assert!(latched.iter().all(|c| c.rem_euclid(COUNTS_REV) == 0), "{what}: index latches {latched:?}");
        if !(jitter && bounce) {
            continue;
        }
        // A stall: steps go on, the counts stop; then a slip of two counts back (both
        // lines at once): the count stays, the slip is counted illegal.
        let mut stalled = pins.clone();
        let hold = *stalled.last().unwrap();
        stalled.extend(std::iter::repeat(hold).take(5_000));
        let (m2, _) = decode(&cfg, stalled.clone().into_iter());
        assert_eq!(m2.outputs().count as i32 as i64, end, "a stall leaves the count where the motor stopped");
        assert_eq!(m2.outputs().age, o.age + 5_000, "age counts the ticks since the last edge");
        stalled.extend(std::iter::repeat(QuadratureGen::lines(end - 2, COUNTS_REV)).take(20));
        let (m3, _) = decode(&cfg, stalled.into_iter());
        assert_eq!(m3.outputs().illegal, 1, "the slip is one illegal transition");
        assert_eq!(m3.outputs().count as i32 as i64, end, "an illegal transition does not count");
    }
    // A stall longer than the velocity registers hold: age saturates.
    let (pins, ..) = follow(filter, false, false);
    let mut long = pins.clone();
    long.extend(std::iter::repeat(*pins.last().unwrap()).take(VEL_MAX as usize + 100));
    assert_eq!(decode(&cfg, long.into_iter()).0.outputs().age, VEL_MAX, "age saturates");
}

const FK: usize = 3;

/// One edge of the following-error model as the bank drives it: axis `ax`'s position
/// now, and the count of the axis taken two edges ago (`ax2`) as it was then (`taken`
/// holds the last two); `count` is axis `ax`'s count now, kept for later.
#[allow(clippy::too_many_arguments)]
fn fe_clock(m: &mut FollowErrModel, taken: &mut [u32; 2], position: u32, count: u32, ratio: u32, tol: u16, align: u32, clear: u32, reset: bool) -> u32 {
    let c2 = taken[0];
    *taken = [taken[1], count];
    m.clock(position, c2, ratio, tol, align, clear, reset);
    c2
}

/// Per axis of the following-error stimulus: the step position, the encoder count, the
/// ratio and the tolerance.
#[derive(Clone, Copy)]
struct FeAxis {
    pos: i32,
    count: i32,
    ratio: u32,
    tol: u16,
}

/// Random traffic for [`FollowErr`]: axes moving both ways through 0 with encoders
/// that follow with small errors and sometimes jump, random ratios and tolerances
/// (changed under reset), aligns and clears; rows as the block's inputs, each cycle's
/// inputs those of the axis the model says the block takes (the `ax` it shows).
fn follow_rows(seed: u64, cycles: usize) -> (Vec<Vec<u128>>, Vec<Vec<Option<u128>>>) {
    let mut rng = Rng(seed);
    let mut m = FollowErrModel::new(FK);
    let mut axes = [FeAxis { pos: 0, count: 0, ratio: 0x1_4000, tol: 4 }; FK];
    let (mut rows, mut want) = (vec![], vec![]);
    let (mut fails, mut aligns) = (0, 0);
    let mut taken = [0u32; 2];
    for cyc in 0..cycles {
        let reset = cyc < 2 || rng.next() % 1500 == 0;
        if reset {
            for ax in axes.iter_mut() {
                ax.ratio = match rng.next() % 4 {
                    0 => 0x1_4000,
                    1 => 1 + (rng.next() % 0xFFFF_FFFF) as u32,
                    _ => (rng.next() % 0x8_0000) as u32 + 1,
                };
                ax.tol = match rng.next() % 3 {
                    0 => 0,
                    1 => (rng.next() % 8) as u16 + 1,
                    _ => rng.next() as u16,
                };
            }
        }
        for ax in axes.iter_mut() {
            if rng.next() % 3 == 0 {
                ax.pos = ax.pos.wrapping_add((rng.next() % 3) as i32 - 1);
            }
            let exact = deviation(ax.pos, 0, ax.ratio, 0);
            let r = rng.next() % 400;
            ax.count = if r == 0 { ax.count.wrapping_add((rng.next() % 200) as i32 - 100) } else if r < 300 { exact.wrapping_add((rng.next() % 5) as i32 - 2) } else { ax.count };
            if rng.next() % 5000 == 0 {
                ax.pos = rng.next() as i32; // a jump across the range
            }
        }
        let align = if rng.next() % 200 == 0 { 1u32 << (rng.next() % FK as u64) } else { 0 };
        let clear = if rng.next() % 100 == 0 { (rng.next() % 8) as u32 } else { 0 };
        let dev_axis = (rng.next() % FK as u64) as usize;
        let a = axes[m.ax()];
        want.push(vec![
            (cyc >= 1).then_some(m.ax() as u128),
            (cyc >= 2).then_some(m.ax2() as u128),
            m.dev(dev_axis).map(|d| d as u128),
            (cyc >= 1).then_some(m.fail() as u128),
        ]);
        let before = m.fail();
        let c1 = fe_clock(&mut m, &mut taken, a.pos as u32, a.count as u32, a.ratio, a.tol, align, clear, reset);
        rows.push(vec![reset as u128, a.pos as u32 as u128, c1 as u128, a.ratio as u128, a.tol as u128, align as u128, clear as u128, dev_axis as u128]);
        fails += (m.fail() & !before).count_ones();
        aligns += align.count_ones();
    }
    assert!(fails > 30 && aligns > 30, "stimulus too thin: {fails} fails, {aligns} aligns");
    (rows, want)
}

#[test]
fn following_error_equals_the_model_three_ways() {
    let (rows, want) = follow_rows(0xe4c0_de10, 40_000);
    let spec = TbSpec {
        clock: "clock".into(),
        inputs: vec![
            Port::new("reset", 1),
            Port::new("position", 32),
            Port::new("count", 32),
            Port::new("ratio", 32),
            Port::new("tol", 16),
            Port::new("align", FK),
            Port::new("clear", FK),
            Port::new("dev_axis", 4),
        ],
        outputs: vec![Port::new("ax", 4), Port::new("ax2", 4), Port::new("dev", 32), Port::new("fail", FK)],
    };
    three_ways(
        "follow_err",
        || {
            let mut u = FollowErr::<FK>::default();
            u.connect_ports();
            u
        },
        |u, c| u.clock.next = Clock::from(c),
        |u, r| {
            u.reset.next = r[0] == 1;
            u.position.next = (r[1] as u64).into();
            u.count.next = (r[2] as u64).into();
            u.ratio.next = (r[3] as u64).into();
            u.tol.next = (r[4] as u64).into();
            u.align.next = (r[5] as u64).into();
            u.clear.next = (r[6] as u64).into();
            u.dev_axis.next = (r[7] as u64).into();
        },
        |u| vec![u.ax.val().to_u64() as u128, u.ax2.val().to_u64() as u128, u.dev.val().to_u64() as u128, u.fail.val().to_u64() as u128],
        &spec,
        &rows,
        &want,
    );
}

/// The documented refresh and latency: a count that crosses the tolerance at edge X
/// sets ENC_FAIL by edge X + K + 4 and not before X; the deviation is the formula;
/// an align makes it 0.
#[test]
fn enc_fail_comes_within_one_refresh_and_four_ticks_and_align_zeroes_the_deviation() {
    let mut rng = Rng(0xe4c0_de11);
    for k in [1usize, 3, 16] {
        let refresh = follow_refresh_ticks(k);
        assert_eq!(refresh, k as u64);
        let mut worst = 0;
        for trial in 0..40 {
            let mut m = FollowErrModel::new(k);
            let ratio = 0x1_4000u32; // 1.25 counts per step
            let tol = 10u16;
            let pos: Vec<i32> = (0..k).map(|_| (rng.next() % 20_000) as i32 - 10_000).collect();
            let mut count: Vec<i32> = pos.iter().map(|&p| deviation(p, 0, ratio, 0) - 3).collect();
            let victim = (rng.next() % k as u64) as usize;
            let x = 40 + rng.next() % 50;
            let mut rose = None;
            let mut taken = [0u32; 2];
            for edge in 0..(x + 2 * k as u64 + 20) {
                if edge == x {
                    // The count steps past the tolerance (a slip).
                    count[victim] -= tol as i32 + 1 - 3 + (trial % 3);
                }
                let a = m.ax();
                fe_clock(&mut m, &mut taken, pos[a] as u32, count[a] as u32, ratio, tol, 0, 0, edge < 2);
                if rose.is_none() && m.fail() != 0 {
                    assert_eq!(m.fail(), 1 << victim, "K = {k}: only the slipped axis fails");
                    rose = Some(edge);
                }
                if edge > x + 10 + k as u64 {
                    // Every axis's deviation reads the formula.
                    for b in 0..k {
                        assert_eq!(m.dev(b).map(|d| d as i32), Some(deviation(pos[b], count[b], ratio, 0)));
                    }
                }
            }
            let rose = rose.expect("ENC_FAIL never came");
            // The count register took its new value at edge x − 1 (the value the loop
            // presents before edge x): that is the crossing.
            let crossing = x - 1;
            assert!(rose > crossing, "K = {k}: ENC_FAIL before the crossing");
            let latency = rose - crossing;
            assert!(latency <= refresh + FOLLOW_ERR_LATENCY, "K = {k}: ENC_FAIL {latency} ticks after the crossing");
            worst = worst.max(latency);
            // An align makes the deviation 0, and the flag stays until cleared.
            let all = (1u32 << k) - 1;
            for edge in 0..(3 * k as u64 + 10) {
                let a = m.ax();
                fe_clock(&mut m, &mut taken, pos[a] as u32, count[a] as u32, ratio, tol, if edge == 0 { all } else { 0 }, 0, false);
            }
            assert!((0..k).all(|b| m.dev(b) == Some(0)), "K = {k}: aligned");
            assert_eq!(m.fail(), 1 << victim, "the flag is sticky");
            let a = m.ax();
            fe_clock(&mut m, &mut taken, pos[a] as u32, count[a] as u32, ratio, tol, 0, all, false);
            assert_eq!(m.fail(), 0, "cleared");
        }
        assert_eq!(worst, refresh + FOLLOW_ERR_LATENCY, "K = {k}: the bound is reached, not loose");
    }
}

/// A clear right after an align sticks, whatever the delay between them: no visit
/// that took the old offset (in flight when the align came) sets the flag after the
/// clear. The C driver's correction writes ENC_ALIGN, then ENC_CLEAR a few ticks later;
/// without the rule the flag came back at delays of 1 to 4 ticks.
#[test]
fn a_clear_right_after_an_align_sticks() {
    let mut failed_before = 0;
    for k in [1usize, 2, 3, 16] {
        for delay in 0..12u64 {
            let mut m = FollowErrModel::new(k);
            let mut taken = [0u32; 2];
            let (ratio, tol) = (0x1_4000u32, 6u16);
            // Every axis 50 counts behind its steps: the flags set.
            let (pos, count) = (2_000u32, 2_450u32);
            let all = (1u32 << k) - 1;
            for edge in 0..(3 * k as u64 + 10) {
                fe_clock(&mut m, &mut taken, pos, count, ratio, tol, 0, 0, edge < 2);
            }
            assert_eq!(m.fail(), all, "K = {k}: the flags before the align");
            for edge in 0..(3 * k as u64 + 20) {
                let al = if edge == 0 { all } else { 0 };
                let cl = if edge == delay { all } else { 0 };
                fe_clock(&mut m, &mut taken, pos, count, ratio, tol, al, cl, false);
                if edge == delay + 1 && m.fail() != 0 {
                    failed_before += 1;
                }
            }
            assert_eq!(m.fail(), 0, "K = {k}: a clear {delay} ticks after the align did not stick");
            assert!((0..k).all(|b| m.dev(b) == Some(0)), "K = {k}: aligned");
        }
    }
    assert_eq!(failed_before, 0, "a flag came back right after its clear");
}

/// The bank three ways: two axes whose steps move both ways and whose encoders follow
/// at 1.25 counts per step, stall now and then (ENC_FAIL) and slip; random modes,
/// inverts, prescales, ratios and tolerances (under reset), commands and the probe;
/// the word of a random axis each cycle. Then one axis (K = 1: every visit is the
/// same axis, so the extension's words read ahead are the ones it writes).
#[test]
fn encoder_bank_equals_the_model_three_ways() {
    bank_three_ways::<2>(92_000, 20_000..88_000, "enc_bank");
    bank_three_ways::<1>(30_000, 0..0, "enc_bank_k1");
}

fn bank_three_ways<const BK: usize>(cycles: usize, rest_cycles: std::ops::Range<usize>, name: &str) {
    let mask = (1u64 << BK) - 1;
    let mut rng = Rng(0xe4c0_de20);
    let mut m = EncoderBankModel::new(BK);
    let mut gens: Vec<QuadratureGen> = (0..BK).map(|_| QuadratureGen::new(64, 2)).collect();
    let mut pos = [0i32; BK];
    let mut stalled = [false; BK];
    let mut inp = BankInputs { ratio: 0x1_4000, tol: 6, ..Default::default() };
    let mut ratios = [0x1_4000u32; BK];
    let mut tols = [6u16; BK];
    let (mut rows, mut want) = (vec![], vec![]);
    let (mut fails, mut counts, mut saturated) = (0, 0, 0);
    // A rest longer than the velocity's 16 bits in the middle: its saturation.
    let rest = |cyc: usize| rest_cycles.contains(&cyc);
    for cyc in 0..cycles {
        let reset = cyc < 4 || cyc + 10 == rest_cycles.start || (!rest(cyc) && rng.next() % 3000 == 0);
        if reset {
            inp.mode = (rng.next() % 4) as u8 | ((rng.next() % 8) as u8) << 4 | (rng.next() as u8 & 0xC0);
            inp.invert = if rng.next() % 4 == 0 { (rng.next() & mask) as u32 } else { 0 };
            inp.vel_prescale = if cyc + 10 == rest_cycles.start { 0 } else { (rng.next() % 3) as u16 };
            for a in 0..BK {
                ratios[a] = if rng.next() % 3 == 0 { (rng.next() % 0x4_0000) as u32 + 1 } else { 0x1_4000 };
                tols[a] = [0, 3, 6, 200][(rng.next() % 4) as usize];
                pos[a] = 0;
                gens[a].pos = 0;
            }
        }
        for a in 0..BK {
            if rest(cyc) {
                continue;
            }
            if rng.next() % 7 == 0 {
                pos[a] += if (cyc / 2000) % 2 == a % 2 { 1 } else { -1 };
            }
            if rng.next() % 2500 == 0 {
                stalled[a] = !stalled[a];
            }
            if rng.next() % 4000 == 0 {
                gens[a].pos -= 2; // a slip
            }
        }
        let mut a_bits = 0;
        let mut b_bits = 0;
        let mut z_bits = 0;
        for a in 0..BK {
            let target = if stalled[a] { gens[a].pos } else { (pos[a] as i64 * 5).div_euclid(4) };
            gens[a].spacing = 2 + (inp.mode & 0xF) as u64;
            let p = gens[a].tick(target);
            a_bits |= (p.a as u32) << a;
            b_bits |= (p.b as u32) << a;
            z_bits |= (p.z as u32) << a;
        }
        inp.a = a_bits;
        inp.b = b_bits;
        inp.z = z_bits;
        inp.arm = if rng.next() % 300 == 0 { (rng.next() & mask) as u32 } else { 0 };
        inp.align = if rng.next() % 500 == 0 { (rng.next() & mask) as u32 } else { 0 };
        inp.clear = if rng.next() % 200 == 0 { (rng.next() & mask) as u32 } else { 0 };
        inp.probe = rng.next() % 400 == 0;
        let pa = m.pos_axis();
        inp.position = pos[pa] as u32;
        inp.pos_low = (0..BK).fold(0u128, |w, a| w | ((pos[a] as u32 & 0xFF) as u128) << (8 * a));
        inp.ratio = ratios[pa];
        inp.tol = tols[pa];
        let sel = (rng.next() % BK as u64) as usize;
        let (lo, hi) = m.word(sel);
        let ok = cyc >= 4;
        want.push(vec![ok.then_some(pa as u128), lo.filter(|_| ok), hi.filter(|_| ok), ok.then_some(m.fe.fail() as u128)]);
        rows.push(vec![
            reset as u128,
            inp.a as u128,
            inp.b as u128,
            inp.z as u128,
            inp.mode as u128,
            inp.invert as u128,
            inp.vel_prescale as u128,
            inp.arm as u128,
            inp.align as u128,
            inp.clear as u128,
            inp.probe as u128,
            inp.position as u128,
            inp.ratio as u128,
            inp.tol as u128,
            sel as u128,
            inp.pos_low,
        ]);
        let before = (m.fe.fail(), m.dec[0].outputs().count);
        m.clock(&inp, reset);
        fails += (m.fe.fail() & !before.0).count_ones();
        counts += (m.dec[0].outputs().count != before.1) as u32;
        saturated += hi.is_some_and(|h| h >> 16 & 0xFFFF == 0xFFFF) as u32;
    }
    let want_saturated = if rest_cycles.is_empty() { 0 } else { 100 };
    assert!(fails > 10 * cycles as u32 / 92_000 && counts > 2000 * cycles as u32 / 92_000 && saturated >= want_saturated, "K = {BK}: stimulus too thin: {fails} fails, {counts} counts, {saturated} saturated ages");
    let cols: [(&str, usize); 16] = [
        ("reset", 1),
        ("enc_a", BK),
        ("enc_b", BK),
        ("enc_z", BK),
        ("mode", 8),
        ("invert", BK),
        ("vel_prescale", 16),
        ("arm", BK),
        ("align", BK),
        ("clear", BK),
        ("probe", 1),
        ("position", 32),
        ("ratio", 32),
        ("tol", 16),
        ("sel", 8),
        ("pos_low", 128),
    ];
    let spec = TbSpec {
        clock: "clock".into(),
        inputs: cols.iter().map(|(n, w)| Port::new(n, *w)).collect(),
        outputs: vec![Port::new("pos_axis", 4), Port::new("word_lo", 128), Port::new("word_hi", 81), Port::new("fail", BK)],
    };
    three_ways(
        name,
        || {
            let mut u = EncoderBank::<BK>::default();
            u.connect_ports();
            u
        },
        |u, c| u.clock.next = Clock::from(c),
        |u, r| {
            u.reset.next = r[0] == 1;
            u.enc_a.next = (r[1] as u64).into();
            u.enc_b.next = (r[2] as u64).into();
            u.enc_z.next = (r[3] as u64).into();
            u.mode.next = (r[4] as u64).into();
            u.invert.next = (r[5] as u64).into();
            u.vel_prescale.next = (r[6] as u64).into();
            u.arm.next = (r[7] as u64).into();
            u.align.next = (r[8] as u64).into();
            u.clear.next = (r[9] as u64).into();
            u.probe.next = r[10] == 1;
            u.position.next = (r[11] as u64).into();
            u.ratio.next = (r[12] as u64).into();
            u.tol.next = (r[13] as u64).into();
            u.sel.next = (r[14] as u64).into();
            u.pos_low.next = tdm_stepper::hdl::u128_to_bits(r[15]);
        },
        |u| {
            vec![
                u.pos_axis.val().to_u64() as u128,
                bits_to_u128(u.word_lo.val()),
                bits_to_u128(u.word_hi.val()),
                u.fail.val().to_u64() as u128,
            ]
        },
        &spec,
        &rows,
        &want,
    );
}
/// The bank's Verilog at K = 1, 2, 8 and 16 and the decoder's for
/// scripts/enc-bank-cost.sh (in the test's temporary folder); each generates and
/// names its top module.
#[test]
fn encoder_bank_verilog_for_the_cost_script() {
    fn dump<const K: usize>() {
        let mut u = EncoderBank::<K>::default();
        u.connect_ports();
        let v = generate_verilog(&u);
        assert!(v.contains("module top(") && v.contains("enc_a"), "K = {K}: no bank in the Verilog");
        let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"));
        std::fs::write(dir.join(format!("enc_bank_k{K}.v")), v).unwrap();
    }
    let v = generate_verilog(&decoder_uut());
    assert!(v.contains("module top(") && v.contains("index_count"), "no decoder in the Verilog");
    std::fs::write(std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("enc_decoder.v"), v).unwrap();
    dump::<1>();
    dump::<2>();
    dump::<8>();
    dump::<16>();
}

/// The extension's sign extension alone (a wrapper gives the testbench its clock).
#[derive(LogicBlock, Default)]
struct SextTb {
    pub clock: Signal<In, Clock>,
    pub value: Signal<In, Bits<8>>,
    pub wide: Signal<Out, Bits<32>>,
    x: tdm_stepper::hdl::bit_insert::SignExtend<8, 32>,
}

impl Logic for SextTb {
    #[hdl_gen]
    fn update(&mut self) {
        self.x.value.next = self.value.val();
        self.wide.next = self.x.wide.val();
    }
}

/// `SignExtend<8, 32>` three ways: every 8-bit value, rust-hdl and the exported Verilog
/// equal to Rust's own `i8 as i32`.
#[test]
fn sign_extend_equals_i8_as_i32_three_ways() {
    let mk = || {
        let mut u = SextTb::default();
        u.clock.connect();
        u.value.connect();
        u.connect_all();
        u
    };
    let rows: Vec<Vec<u128>> = (0..256u128).map(|v| vec![v]).collect();
    let out = tdm_stepper::verify::run_rust_hdl(
        &mut mk(),
        &rows,
        |u, c| u.clock.next = Clock::from(c),
        |u, r| u.value.next = (r[0] as u64).into(),
        |u| vec![u.wide.val().to_u64() as u128],
    );
    for (v, o) in out.iter().enumerate() {
        assert_eq!(o[0], (v as u8 as i8 as i32 as u32) as u128, "value {v:#x}");
    }
    let spec = TbSpec { clock: "clock".into(), inputs: vec![Port::new("value", 8)], outputs: vec![Port::new("wide", 32)] };
    verilog_matches_rust_hdl("sign_extend", &generate_verilog(&mk()), &spec, &rows, &out, 0);
}
