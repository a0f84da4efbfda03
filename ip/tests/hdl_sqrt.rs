//! Sqrt<R> three ways: u128::isqrt (the reference model's square root) with a
//! cycle-level protocol model, rust-hdl simulation, and the exported Verilog in
//! Verilator and Icarus, on the same stimulus, for R = 1, 2 and 4 digits per cycle.

use rust_hdl::prelude::*;
use std::path::PathBuf;
use tdm_stepper::hdl::sqrt::{sqrt_latency, Sqrt, SQRT_RADICAND_BITS, SQRT_ROOT_BITS};
use tdm_stepper::verify::{run, run_rust_hdl, Port, Simulator, TbSpec};

/// Radicands: the extremes, squares and their neighbours, then pseudo-random ones.
fn radicands(count: usize) -> Vec<u128> {
    let top = (1u128 << 64) - 1;
    let mut v = vec![0, 1, 2, 3, 4, u128::MAX, top * top, top * top - 1, 1u128 << 127, (1u128 << 64) + 1];
    let mut x = 0x2545_f491_4f6c_dd1du64;
    let mut next = move || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        x
    };
    while v.len() < count {
        let r = ((next() as u128) << 64) | next() as u128;
        let shift = next() % 128;
        let k = (r >> shift) as u64 as u128;
        v.push(match v.len() % 3 {
            0 => r >> shift,
            1 => k * k,
            _ => (k * k).saturating_sub(1),
        });
    }
    v
}

/// Rows of (start, radicand): each operation starts, then idles until its result,
/// with a start pulse (and junk radicand) while busy that must be ignored.
fn stimulus(r: usize, ops: &[u128]) -> Vec<Vec<u128>> {
    let mut rows = vec![vec![0, 0]];
    for &x in ops {
        rows.push(vec![1, x]);
        for k in 0..sqrt_latency(r) {
            rows.push(if k == 1 { vec![1, !x] } else { vec![0, x ^ 0x5555] });
        }
    }
    rows
}

/// Expected (root, valid, busy) per row; None where the Verilog may be undefined.
fn model(r: usize, rows: &[Vec<u128>]) -> Vec<[Option<u128>; 3]> {
    let (mut left, mut done, mut root, mut pending, mut started) = (0usize, false, 0u128, 0u128, false);
    let mut out = Vec::new();
    for row in rows {
        let defined = started;
        out.push([
            (defined && done).then_some(root),
            defined.then_some(done as u128),
            defined.then_some((left > 0) as u128),
        ]);
        if left > 0 {
            left -= 1;
            if left == 0 {
                done = true;
                root = pending;
            }
        } else if row[0] == 1 {
            left = SQRT_ROOT_BITS / r;
            done = false;
            pending = row[1].isqrt();
            started = true;
        }
    }
    out
}

fn check(r: usize, rows: &[Vec<u128>], got: &[Vec<Option<u128>>], what: &str) {
    let want = model(r, rows);
    assert_eq!(got.len(), want.len(), "{what}");
    let mut results = 0;
    for (k, (g, w)) in got.iter().zip(&want).enumerate() {
        for p in 0..3 {
            if let Some(w) = w[p] {
                assert_eq!(g[p], Some(w), "{what}: row {k}, output {p} (root, valid, busy)");
                results += (p == 0) as usize;
            }
        }
    }
    assert!(results > 0, "{what}: no result was checked");
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

fn three_ways<const R: usize>(ops: usize) {
    let rows = stimulus(R, &radicands(ops));
    let mut u = uut::<R>();
    let got = run_rust_hdl(
        &mut u,
        &rows,
        |u, c| u.clock.next = Clock::from(c),
        |u, row| {
            u.start.next = row[0] == 1;
            u.radicand.next = Bits::<SQRT_RADICAND_BITS>::from(num_bigint::BigUint::from(row[1]));
        },
        |u| vec![u.root.val().to_u64() as u128, u.valid.val() as u128, u.busy.val() as u128],
    );
    let got: Vec<Vec<Option<u128>>> = got.into_iter().map(|r| r.into_iter().map(Some).collect()).collect();
    check(R, &rows, &got, &format!("rust-hdl R={R}"));
    let verilog = generate_verilog(&uut::<R>());
    for sim in [Simulator::Verilator, Simulator::Icarus] {
        let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("sqrt_r{R}_{sim:?}"));
        let got = run(sim, &dir, &verilog, &spec(), &rows).unwrap();
        check(R, &rows, &got, &format!("{sim:?} R={R}"));
    }
}

#[test]
fn sqrt_radix_2() {
    three_ways::<1>(40);
}

#[test]
fn sqrt_radix_4() {
    three_ways::<2>(80);
}

#[test]
fn sqrt_radix_16() {
    three_ways::<4>(80);
}
