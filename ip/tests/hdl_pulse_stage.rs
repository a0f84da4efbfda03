//! PulseStage three ways: rust-hdl, the exported Verilog in Verilator and Icarus, and
//! the model (`PulseTiming::high_ticks`). Random entries (periods from 1 tick to 2^32 − 1,
//! dwells, both directions) under random output timing, back to back and with gaps: every
//! entry comes out two cycles later, for its axis, with its fields unchanged and the
//! model's high time in bits 50..35; a flush drops what is in flight; the in-flight
//! flags say which axes have an entry in each stage.

mod common;

use common::*;
use rust_hdl::prelude::*;
use tdm_stepper::hdl::pulse_stage::PulseStage;
use tdm_stepper::hdl::ram_fifo::{pack_entry, ENTRY_BITS};
use tdm_stepper::model::PulseTiming;
use tdm_stepper::verify::{run_rust_hdl, Port, TbSpec};

fn uut() -> PulseStage {
    let mut u = PulseStage::default();
    u.clock.connect();
    u.flush.connect();
    u.high_min.connect();
    u.low_min.connect();
    u.push_in.connect();
    u.axis_in.connect();
    u.entry_in.connect();
    u.connect_all();
    u
}

/// One row of inputs: flush, high_min, low_min, push_in, axis_in, entry_in.
fn drive(u: &mut PulseStage, r: &[u128]) {
    u.flush.next = r[0] == 1;
    u.high_min.next = Bits::<16>::from(r[1] as u64);
    u.low_min.next = Bits::<16>::from(r[2] as u64);
    u.push_in.next = r[3] == 1;
    u.axis_in.next = Bits::<8>::from(r[4] as u64);
    u.entry_in.next = Bits::<ENTRY_BITS>::from(r[5] as u64);
}

fn spec() -> TbSpec {
    TbSpec {
        clock: "clock".into(),
        inputs: vec![
            Port::new("flush", 1),
            Port::new("high_min", 16),
            Port::new("low_min", 16),
            Port::new("push_in", 1),
            Port::new("axis_in", 8),
            Port::new("entry_in", ENTRY_BITS),
        ],
        outputs: vec![
            Port::new("push_out", 1),
            Port::new("axis_out", 8),
            Port::new("entry_out", ENTRY_BITS),
            Port::new("p0_valid", 1),
            Port::new("p0_axis", 8),
            Port::new("p1_valid", 1),
            Port::new("p1_axis", 8),
        ],
    }
}

/// A period: mostly near the clamps (around 2·Hm, Hm + Lm, 2^17), else anywhere.
fn period(rng: &mut Rng, hm: u32, lm: u32) -> u32 {
    let around = |c: u64, r: &mut Rng| (c + r.next() % 9).saturating_sub(4).clamp(1, u32::MAX as u64) as u32;
    match rng.next() % 6 {
        0 => around(2 * hm as u64, rng),
        1 => around((hm + lm) as u64, rng),
        2 => around(1 << 17, rng),
        3 => 1 + (rng.next() % 64) as u32,
        4 => (rng.next() >> 32) as u32,
        _ => 1 + (rng.next() % 200_000) as u32,
    }
}

#[test]
fn high_time_equals_the_model_three_ways() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let mut rows: Vec<Vec<u128>> = Vec::new();
    // (row, axis, entry, timing) of every push.
    let mut pushed = Vec::new();
    let mut flushes = Vec::new();
    for phase in 0..24 {
        // Output timing changes only while nothing is in flight (as with the core in reset).
        let hm = match phase % 4 {
            0 => 1,
            1 => 1 + (rng.next() % 40) as u32,
            2 => 1 + (rng.next() % 65_535) as u32,
            _ => 65_535,
        };
        let lm = (1 + rng.next() % 65_535) as u32;
        let lm = if phase % 3 == 0 { 1 } else { lm };
        let timing = PulseTiming { step_high: hm as u16, dir_hold: 1, step_low: 1, dir_setup: lm as u16 };
        for _ in 0..3 {
            rows.push(vec![0, hm as u128, lm as u128, 0, 0, 0]);
        }
        for _ in 0..40 {
            let push = rng.next() % 4 != 0;
            let axis = (rng.next() % 16) as u8;
            let ticks = period(&mut rng, hm, lm);
            let step = rng.next() % 5 != 0;
            let entry = pack_entry(ticks, step, rng.next() % 2 == 0, rng.next() % 3 == 0, rng.next() as u16);
            let flush = rng.next() % 50 == 0;
            if flush {
                flushes.push(rows.len());
            }
            if push {
                pushed.push((rows.len(), axis, entry, timing));
            }
            rows.push(vec![flush as u128, hm as u128, lm as u128, push as u128, axis as u128, if push { entry as u128 } else { rng.next() as u128 & ((1 << ENTRY_BITS) - 1) }]);
        }
        // Let the stage drain before the timing changes.
        for _ in 0..2 {
            rows.push(vec![0, hm as u128, lm as u128, 0, 0, 0]);
        }
    }
    for _ in 0..3 {
        rows.push(vec![0, 1, 1, 0, 0, 0]);
    }

    let reference = run_rust_hdl(
        &mut uut(),
        &rows,
        |u, c| u.clock.next = Clock::from(c),
        drive,
        |u| {
            vec![
                u.push_out.val() as u128,
                u.axis_out.val().to_u64() as u128,
                u.entry_out.val().to_u64() as u128,
                u.p0_valid.val() as u128,
                u.p0_axis.val().to_u64() as u128,
                u.p1_valid.val() as u128,
                u.p1_axis.val().to_u64() as u128,
            ]
        },
    );
    // The model: each push out two rows later unless a flush in its row or the next
    // dropped it; every entry_out has the model's high time.
    let dropped = |r: usize| flushes.contains(&r) || flushes.contains(&(r + 1));
    let mut expected_pushes = 0;
    for &(r, axis, entry, timing) in &pushed {
        let out = &reference[r + 2];
        if dropped(r) {
            assert_eq!(out[0], 0, "row {r}: an entry survived a flush");
            continue;
        }
        expected_pushes += 1;
        assert_eq!(out[0], 1, "row {r}: entry not out two cycles later");
        assert_eq!(out[1], axis as u128, "row {r}: axis");
        let ticks = entry as u32;
        let high = timing.high_ticks(ticks) as u128;
        assert_eq!(out[2] & ((1 << 35) - 1), entry as u128 & ((1 << 35) - 1), "row {r}: entry fields changed");
        assert_eq!((out[2] >> 35) & 0xFFFF, high, "row {r}: high time for Δ = {ticks}, {timing:?}");
        assert_eq!(out[2] >> 51, (ticks == 1) as u128, "row {r}: the one-tick flag for Δ = {ticks}");
        assert_eq!((reference[r + 1][3], reference[r + 1][4]), (1, axis as u128), "row {r}: stage 0 flags");
        if !flushes.contains(&r) {
            assert_eq!((out[5], out[6]), (1, axis as u128), "row {r}: stage 1 flags");
        }
    }
    assert_eq!(reference.iter().filter(|o| o[0] == 1).count(), expected_pushes, "pushes out of nothing");
    assert!(expected_pushes > 500 && flushes.len() > 5, "stimulus too thin");

    verilog_matches_rust_hdl("pulse_stage", &generate_verilog(&uut()), &spec(), &rows, &reference, 3);
}

/// A high minimum of 0 (the core's inputs left unconnected) acts as 1: no pulse of 0.
#[test]
fn a_zero_high_minimum_acts_as_one() {
    let rows: Vec<Vec<u128>> = [1u32, 2, 3]
        .iter()
        .map(|&t| vec![0, 0, 0, 1, 0, pack_entry(t, true, false, false, 0) as u128])
        .chain((0..3).map(|_| vec![0, 0, 0, 0, 0, 0]))
        .collect();
    let out = run_rust_hdl(
        &mut uut(),
        &rows,
        |u, c| u.clock.next = Clock::from(c),
        drive,
        |u| vec![u.push_out.val() as u128, (u.entry_out.val().to_u64() as u128 >> 35) & 0xFFFF],
    );
    let highs: Vec<u128> = out.iter().filter(|o| o[0] == 1).map(|o| o[1]).collect();
    assert_eq!(highs, vec![1, 1, 1], "Δ = 1, 2, 3 with Hm = Lm = 0");
}
