//! MulReg three ways: the model (a·b one cycle later), rust-hdl simulation, and the
//! exported Verilog in Verilator and Icarus, on the same random stimulus.

use rust_hdl::prelude::*;
use std::path::PathBuf;
use tdm_stepper::hdl::mul_wide::{MulReg, MUL_REG_LATENCY};
use tdm_stepper::verify::{run, run_rust_hdl, Port, Simulator, TbSpec};

const A: usize = 32;
const B: usize = 31;
const P: usize = 63;

fn stimulus(cycles: usize) -> Vec<Vec<u128>> {
    let mut x = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = move || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        x
    };
    let mut rows: Vec<Vec<u128>> = vec![
        vec![(1u128 << A) - 1, (1u128 << B) - 1], // the largest product
        vec![0, (1u128 << B) - 1],
        vec![1, 1],
    ];
    while rows.len() < cycles {
        rows.push(vec![(next() >> (64 - A)) as u128, (next() >> (64 - B)) as u128]);
    }
    rows
}

fn model(rows: &[Vec<u128>]) -> Vec<Option<u128>> {
    // Cycle k shows the product of row k − 1; before the first edge, nothing defined.
    (0..rows.len()).map(|k| (k >= MUL_REG_LATENCY).then(|| rows[k - 1][0] * rows[k - 1][1])).collect()
}

fn uut() -> MulReg<A, B, P> {
    let mut u = MulReg::<A, B, P>::default();
    u.clock.connect();
    u.a.connect();
    u.b.connect();
    u.connect_all();
    u
}

fn spec() -> TbSpec {
    TbSpec { clock: "clock".into(), inputs: vec![Port::new("a", A), Port::new("b", B)], outputs: vec![Port::new("p", P)] }
}

/// Every cycle equals the model; an undefined (x/z) output is accepted only where the
/// model has no value yet (before the register's first load).
fn check(got: &[Vec<Option<u128>>], what: &str) {
    let want = model(&stimulus(got.len()));
    assert_eq!(got.len(), want.len());
    for (k, (g, w)) in got.iter().zip(&want).enumerate() {
        match (g[0], w) {
            (Some(g), Some(w)) => assert_eq!(g, *w, "{what}: cycle {k}"),
            (None, Some(_)) => panic!("{what}: cycle {k}: undefined output where the model has a value"),
            (_, None) => {}
        }
    }
}

const CYCLES: usize = 2000;

#[test]
fn rust_hdl_matches_model() {
    let mut u = uut();
    let got = run_rust_hdl(
        &mut u,
        &stimulus(CYCLES),
        |u, c| u.clock.next = Clock::from(c),
        |u, r| {
            u.a.next = Bits::<A>::from(r[0] as u64);
            u.b.next = Bits::<B>::from(r[1] as u64);
        },
        |u| vec![u.p.val().to_u64() as u128],
    );
    let got: Vec<Vec<Option<u128>>> = got.into_iter().map(|r| r.into_iter().map(Some).collect()).collect();
    check(&got, "rust-hdl");
}

fn exported(sim: Simulator) {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("mul_wide_{sim:?}"));
    let got = run(sim, &dir, &generate_verilog(&uut()), &spec(), &stimulus(CYCLES)).unwrap();
    check(&got, &format!("{sim:?}"));
}

#[test]
fn verilator_matches_model() {
    exported(Simulator::Verilator);
}

#[test]
fn icarus_matches_model() {
    exported(Simulator::Icarus);
}
