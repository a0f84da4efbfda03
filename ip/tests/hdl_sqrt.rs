//! Sqrt<R> three ways: u128::isqrt (the reference model's square root) with a
//! cycle-level protocol model, rust-hdl simulation, and the exported Verilog in
//! Verilator and Icarus, on the same stimulus, for R = 1, 2 and 4 digits per cycle.

mod common;

use common::*;
use rust_hdl::prelude::*;
use tdm_stepper::hdl::sqrt::{sqrt_latency, Sqrt, SQRT_RADICAND_BITS, SQRT_ROOT_BITS};
use tdm_stepper::verify::{Port, TbSpec};

/// Radicands: the extremes, squares and their neighbours, then pseudo-random ones.
fn radicands(count: usize) -> Vec<Vec<u128>> {
    let top = (1u128 << 64) - 1;
    let mut v = vec![0, 1, 2, 3, 4, u128::MAX, top * top, top * top - 1, 1u128 << 127, (1u128 << 64) + 1];
    let mut rng = Rng(0x2545_f491_4f6c_dd1d);
    while v.len() < count {
        let r = rng.next_u128() >> (rng.next() % 128);
        let k = r as u64 as u128;
        v.push(match v.len() % 3 {
            0 => r,
            1 => k * k,
            _ => (k * k).saturating_sub(1),
        });
    }
    v.into_iter().map(|x| vec![x]).collect()
}

fn uut<const R: usize>() -> Sqrt<R> {
    let mut u = Sqrt::<R>::default();
    u.clock.connect();
    u.start.connect();
    u.radicand.connect();
    u.connect_all();
    u
}

fn spec() -> TbSpec {
    TbSpec {
        clock: "clock".into(),
        inputs: vec![Port::new("start", 1), Port::new("radicand", SQRT_RADICAND_BITS)],
        outputs: vec![Port::new("root", SQRT_ROOT_BITS), Port::new("valid", 1), Port::new("busy", 1)],
    }
}

fn three_ways_r<const R: usize>(ops: usize) {
    let rows = iterative_stimulus(sqrt_latency(R), &radicands(ops), |op| vec![!op[0]]);
    let want = iterative_model(SQRT_ROOT_BITS / R, &rows, 1, |op| vec![op[0].isqrt()]);
    three_ways(
        &format!("sqrt_r{R}"),
        uut::<R>,
        |u, c| u.clock.next = Clock::from(c),
        |u, row| {
            u.start.next = row[0] == 1;
            u.radicand.next = Bits::<SQRT_RADICAND_BITS>::from(num_bigint::BigUint::from(row[1]));
        },
        |u| vec![u.root.val().to_u64() as u128, u.valid.val() as u128, u.busy.val() as u128],
        &spec(),
        &rows,
        &want,
    );
}

#[test]
fn sqrt_radix_2() {
    three_ways_r::<1>(40);
}

#[test]
fn sqrt_radix_4() {
    three_ways_r::<2>(80);
}

#[test]
fn sqrt_radix_16() {
    three_ways_r::<4>(80);
}
