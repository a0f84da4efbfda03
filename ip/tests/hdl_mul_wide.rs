//! MulReg three ways: the model (a·b MUL_REG_LATENCY cycles later), rust-hdl simulation, and the
//! exported Verilog in Verilator and Icarus, on the same random stimulus.

mod common;

use common::*;
use rust_hdl::prelude::*;
use tdm_stepper::hdl::mul_wide::{MulReg, MUL_REG_LATENCY};
use tdm_stepper::verify::{Port, TbSpec};

const A: usize = 32;
const B: usize = 31;
const P: usize = 63;
// and the core's own shape, 32 × 32 → 64, in `mul_reg_core_shape`.
const CYCLES: usize = 2000;

fn stimulus() -> Vec<Vec<u128>> {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let mut rows: Vec<Vec<u128>> = vec![
        vec![(1u128 << A) - 1, (1u128 << B) - 1], // the largest product
        vec![0, (1u128 << B) - 1],
        vec![1, 1],
    ];
    while rows.len() < CYCLES {
        rows.push(vec![(rng.next() >> (64 - A)) as u128, (rng.next() >> (64 - B)) as u128]);
    }
    rows
}

/// Cycle k shows the product of row k − MUL_REG_LATENCY; before that, nothing defined.
fn model(rows: &[Vec<u128>]) -> Vec<Vec<Option<u128>>> {
    (0..rows.len()).map(|k| vec![(k >= MUL_REG_LATENCY).then(|| rows[k - MUL_REG_LATENCY][0] * rows[k - MUL_REG_LATENCY][1])]).collect()
}

fn uut() -> MulReg<A, B, P> {
    let mut u = MulReg::<A, B, P>::default();
    u.clock.connect();
    u.a.connect();
    u.b.connect();
    u.connect_all();
    u
}

#[test]
fn mul_reg_three_ways() {
    let rows = stimulus();
    let spec = TbSpec { clock: "clock".into(), inputs: vec![Port::new("a", A), Port::new("b", B)], outputs: vec![Port::new("p", P)] };
    three_ways(
        "mul_wide",
        uut,
        |u, c| u.clock.next = Clock::from(c),
        |u, r| {
            u.a.next = Bits::<A>::from(r[0] as u64);
            u.b.next = Bits::<B>::from(r[1] as u64);
        },
        |u| vec![u.p.val().to_u64() as u128],
        &spec,
        &rows,
        &model(&rows),
    );
}

#[test]
fn mul_reg_core_shape() {
    let rows: Vec<Vec<u128>> = {
        let mut rng = Rng(0x2545_f491_4f6c_dd1d);
        let mut v = vec![vec![u32::MAX as u128, u32::MAX as u128], vec![1 << 31, 1 << 31], vec![0xffff, 0x1_0000]];
        while v.len() < 500 {
            v.push(vec![(rng.next() >> 32) as u128, (rng.next() >> (32 + rng.next() % 32)) as u128]);
        }
        v
    };
    let want: Vec<Vec<Option<u128>>> = (0..rows.len())
        .map(|k| vec![(k >= MUL_REG_LATENCY).then(|| rows[k - MUL_REG_LATENCY][0] * rows[k - MUL_REG_LATENCY][1])])
        .collect();
    let spec = TbSpec { clock: "clock".into(), inputs: vec![Port::new("a", 32), Port::new("b", 32)], outputs: vec![Port::new("p", 64)] };
    let uut = || {
        let mut u = MulReg::<32, 32, 64>::default();
        u.clock.connect();
        u.a.connect();
        u.b.connect();
        u.connect_all();
        u
    };
    three_ways(
        "mul_wide_core",
        uut,
        |u, c| u.clock.next = Clock::from(c),
        |u, r| {
            u.a.next = Bits::<32>::from(r[0] as u64);
            u.b.next = Bits::<32>::from(r[1] as u64);
        },
        |u| vec![u.p.val().to_u64() as u128],
        &spec,
        &rows,
        &want,
    );
}
