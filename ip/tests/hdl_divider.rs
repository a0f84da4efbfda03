//! Divider<R> three ways: u128 `/` and `%` on 104-bit numerators (the reference
//! model's setup divides)
//! with a cycle-level protocol model, rust-hdl simulation, and the exported Verilog
//! in Verilator and Icarus, for R = 1, 2 and 4 digits per cycle.

mod common;

use common::*;
use num_bigint::BigUint;
use rust_hdl::prelude::*;
use tdm_stepper::hdl::divider::{div_latency, Divider, DIV_DEN_BITS, DIV_NUM_BITS};
use tdm_stepper::verify::{Port, TbSpec};

/// (numerator, denominator): extremes, the setup's own shapes, then random ones.
fn operands(count: usize) -> Vec<Vec<u128>> {
    let d_max = u64::MAX as u128;
    let mut v: Vec<Vec<u128>> = vec![
        vec![0, 1],
        vec![NUM_MAX, 1],
        vec![NUM_MAX, d_max],
        vec![d_max, d_max],
        vec![d_max - 1, d_max],
        vec![(1u128 << 100) | 12345, 3],            // B' = T²·2^41 / |D| shapes
        vec![((1u128 << 30) * (1u128 << 30)) << 41, 1],
        vec![7, 0],                                   // by zero: all ones, numerator low bits
    ];
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    while v.len() < count {
        let num = rng.next_u128() >> (128 - DIV_NUM_BITS as u32 + rng.next() as u32 % DIV_NUM_BITS as u32);
        let den = (rng.next() >> (rng.next() % 64)).max(1) as u128;
        v.push(vec![num, den]);
    }
    v
}

const NUM_MAX: u128 = (1u128 << DIV_NUM_BITS) - 1;

fn divide(op: &[u128]) -> Vec<u128> {
    if op[1] == 0 {
        vec![NUM_MAX, op[0] & u64::MAX as u128]
    } else {
        vec![op[0] / op[1], op[0] % op[1]]
    }
}

fn uut<const R: usize>() -> Divider<R> {
    let mut u = Divider::<R>::default();
    u.clock.connect();
    u.start.connect();
    u.numerator.connect();
    u.denominator.connect();
    u.connect_all();
    u
}

fn spec() -> TbSpec {
    TbSpec {
        clock: "clock".into(),
        inputs: vec![Port::new("start", 1), Port::new("numerator", DIV_NUM_BITS), Port::new("denominator", DIV_DEN_BITS)],
        outputs: vec![
            Port::new("quotient", DIV_NUM_BITS),
            Port::new("remainder", DIV_DEN_BITS),
            Port::new("valid", 1),
            Port::new("busy", 1),
        ],
    }
}

fn three_ways_r<const R: usize>(ops: usize) {
    let rows = iterative_stimulus(div_latency(R), &operands(ops), |op| vec![!op[0] & NUM_MAX, op[1] ^ 0xff]);
    let want = iterative_model(div_latency(R) - 1, &rows, 2, divide);
    three_ways(
        &format!("div_r{R}"),
        uut::<R>,
        |u, c| u.clock.next = Clock::from(c),
        |u, row| {
            u.start.next = row[0] == 1;
            u.numerator.next = Bits::<DIV_NUM_BITS>::from(BigUint::from(row[1]));
            u.denominator.next = Bits::<DIV_DEN_BITS>::from(row[2] as u64);
        },
        |u| vec![bits_to_u128(u.quotient.val()), u.remainder.val().to_u64() as u128, u.valid.val() as u128, u.busy.val() as u128],
        &spec(),
        &rows,
        &want,
    );
}

#[test]
fn divider_radix_256() {
    three_ways_r::<8>(30);
}

#[test]
fn divider_radix_4() {
    three_ways_r::<2>(60);
}

#[test]
fn divider_radix_16() {
    three_ways_r::<4>(60);
}
