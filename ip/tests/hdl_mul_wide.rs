//! MulReg three ways: the model (a·b one cycle later), rust-hdl simulation, and the
//! exported Verilog in Verilator and Icarus, on the same random stimulus.

mod common;

use common::*;
use rust_hdl::prelude::*;
use tdm_stepper::hdl::mul_wide::{MulReg, MUL_REG_LATENCY};
use tdm_stepper::verify::{Port, TbSpec};

const A: usize = 32;
const B: usize = 31;
const P: usize = 63;
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

/// Cycle k shows the product of row k − 1; before the first edge, nothing defined.
fn model(rows: &[Vec<u128>]) -> Vec<Vec<Option<u128>>> {
    (0..rows.len()).map(|k| vec![(k >= MUL_REG_LATENCY).then(|| rows[k - 1][0] * rows[k - 1][1])]).collect()
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
