//! MulSeq<R> three ways: multiplication mod 2^100 with a cycle-level protocol
//! model, rust-hdl simulation, and the exported Verilog in Verilator and Icarus.

mod common;

use common::*;
use num_bigint::BigUint;
use rust_hdl::prelude::*;
use tdm_stepper::hdl::mul_seq::{mul_seq_latency, mul_seq_steps, MulSeq, MUL_A_BITS, MUL_B_BITS};
use tdm_stepper::verify::{Port, TbSpec};

/// (a, b): the setup's products at their widest, extremes, then random ones.
fn operands(count: usize) -> Vec<Vec<u128>> {
    let t = (1u128 << 30) - 1;
    let mut v: Vec<Vec<u128>> = vec![
        vec![0, 0],
        vec![(1u128 << 100) - 1, u32::MAX as u128], // wraps: only the low 100 bits
        vec![t * t, (1u128 << 31) - 1],             // v0·T²
        vec![u64::MAX as u128, 1u128 << 30],        // (v_end·T·2^32)·T
        vec![(1u128 << 100) - 1, 1u128 << 24],      // B'·n
    ];
    let mut rng = Rng(0xd1b5_4a32_d192_ed03);
    while v.len() < count {
        v.push(vec![rng.next_u128() >> (28 + rng.next() % 100), ((rng.next() as u32) >> (rng.next() % 32)) as u128]);
    }
    v
}

const A_MASK: u128 = (1u128 << MUL_A_BITS) - 1;

fn uut<const R: usize>() -> MulSeq<R> {
    let mut u = MulSeq::<R>::default();
    u.clock.connect();
    u.start.connect();
    u.a.connect();
    u.b.connect();
    u.connect_all();
    u
}

fn three_ways_r<const R: usize>(ops: usize) {
    let rows = iterative_stimulus(mul_seq_latency(R), &operands(ops), |op| vec![!op[0] & A_MASK, op[1] ^ 0xff]);
    let want = iterative_model(mul_seq_steps(R), &rows, 1, |op| vec![op[0].wrapping_mul(op[1]) & A_MASK]);
    let spec = TbSpec {
        clock: "clock".into(),
        inputs: vec![Port::new("start", 1), Port::new("a", MUL_A_BITS), Port::new("b", MUL_B_BITS)],
        outputs: vec![Port::new("product", MUL_A_BITS), Port::new("valid", 1), Port::new("busy", 1)],
    };
    three_ways(
        &format!("mul_seq_r{R}"),
        uut::<R>,
        |u, c| u.clock.next = Clock::from(c),
        |u, row| {
            u.start.next = row[0] == 1;
            u.a.next = Bits::<MUL_A_BITS>::from(BigUint::from(row[1] & A_MASK));
            u.b.next = Bits::<MUL_B_BITS>::from(row[2] as u64);
        },
        |u| vec![bits_to_u128(u.product.val()), u.valid.val() as u128, u.busy.val() as u128],
        &spec,
        &rows,
        &want,
    );
}

#[test]
fn mul_seq_radix_4() {
    three_ways_r::<2>(40);
}

#[test]
fn mul_seq_radix_16() {
    three_ways_r::<4>(60);
}
