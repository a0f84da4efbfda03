//! OffsetRoot<R> three ways: the reference model's `offset_root` (checked here to
//! equal `isqrt(p² + c) − p`) with a cycle-level protocol model, rust-hdl
//! simulation, and the exported Verilog in Verilator and Icarus, on the same
//! stimulus, for R = 2, 4 and 6 digits per cycle.

mod common;

use common::*;
use rust_hdl::prelude::*;
use tdm_stepper::hdl::root::{root_latency, OffsetRoot, ROOT_C_BITS, ROOT_P_BITS, ROOT_X_BITS};
use tdm_stepper::model::offset_root;
use tdm_stepper::verify::{Port, TbSpec};

/// (p, c): each root x at both ends of its interval of c, at the extremes of p and
/// x (the widest trial and remainder), then pseudo-random ones.
fn operands(count: usize) -> Vec<Vec<u128>> {
    let x_max = (1u128 << ROOT_X_BITS) - 1;
    let p_max = (1u128 << 64) - 1 - x_max;
    let interval = |p: u128, x: u128| (x * x + 2 * p * x, x * x + 2 * p * x + 2 * (p + x));
    let mut v = Vec::new();
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let mut n = 0usize;
    while v.len() < count {
        let (p, x) = match n {
            0 => (0, 0),
            1 => (0, x_max),
            2 => (p_max, 0),
            3 => (p_max, x_max),
            4 => ((1u128 << 56) + 12345, (1 << 34) + 1),
            _ => {
                let x = (rng.next() as u128 & x_max) >> (rng.next() % 36);
                ((rng.next() as u128 >> (rng.next() % 64) as u32).min(p_max), x)
            }
        };
        n += 1;
        let (lo, hi) = interval(p, x);
        for c in [lo, hi] {
            if c < 1u128 << ROOT_C_BITS {
                v.push(vec![p, c]);
            }
        }
    }
    v.truncate(count);
    v
}

fn uut<const R: usize>() -> OffsetRoot<R> {
    let mut u = OffsetRoot::<R>::default();
    u.clock.connect();
    u.start.connect();
    u.p.connect();
    u.c.connect();
    u.connect_all();
    u
}

fn spec() -> TbSpec {
    TbSpec {
        clock: "clock".into(),
        inputs: vec![Port::new("start", 1), Port::new("p", ROOT_P_BITS), Port::new("c", ROOT_C_BITS)],
        outputs: vec![Port::new("x", ROOT_X_BITS), Port::new("valid", 1), Port::new("busy", 1)],
    }
}

fn three_ways_r<const R: usize>(ops: usize) {
    let operands = operands(ops);
    for op in &operands {
        let (p, c) = (op[0], op[1]);
        assert_eq!(offset_root(p as u64, c) as u128, (p * p + c).isqrt() - p, "model at p = {p}, c = {c}");
    }
    let rows = iterative_stimulus(root_latency(R), &operands, |op| vec![!op[0] & u64::MAX as u128, !op[1] >> 28]);
    let want = iterative_model(ROOT_X_BITS / R, &rows, 1, |op| vec![offset_root(op[0] as u64, op[1]) as u128]);
    three_ways(
        &format!("root_r{R}"),
        uut::<R>,
        |u, c| u.clock.next = Clock::from(c),
        |u, row| {
            u.start.next = row[0] == 1;
            u.p.next = Bits::<ROOT_P_BITS>::from(row[1] as u64);
            u.c.next = Bits::<ROOT_C_BITS>::from(num_bigint::BigUint::from(row[2]));
        },
        |u| vec![u.x.val().to_u64() as u128, u.valid.val() as u128, u.busy.val() as u128],
        &spec(),
        &rows,
        &want,
    );
}

#[test]
fn root_two_digits_per_cycle() {
    three_ways_r::<2>(120);
}

#[test]
fn root_four_digits_per_cycle() {
    three_ways_r::<4>(80);
}

#[test]
fn root_six_digits_per_cycle() {
    three_ways_r::<6>(40);
}
