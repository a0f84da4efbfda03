//! BlockRam three ways: a Vec model (registered read, read-first on a same-address
//! write), rust-hdl simulation, and the exported Verilog in Verilator and Icarus.

mod common;

use common::*;
use rust_hdl::prelude::*;
use tdm_stepper::hdl::block_ram::BlockRam;
use tdm_stepper::verify::{Port, TbSpec};

const W: usize = 96;
const N: usize = 9;
/// Not a power of two: the core's RAM has K·QDEPTH words.
const WORDS: usize = 96;
const CYCLES: usize = 3000;

/// Rows (we, waddr, wdata, raddr): writes and reads over the whole RAM, many to the
/// address being read in the same cycle.
fn stimulus() -> Vec<Vec<u128>> {
    let mut rng = Rng(0x0123_4567_89ab_cdef);
    let mut rows = Vec::new();
    // Fill every word first, so that no read sees an unwritten (undefined) word.
    for a in 0..WORDS {
        rows.push(vec![1, a as u128, rng.next_u128() >> 32, 0]);
    }
    while rows.len() < CYCLES {
        let waddr = (rng.next() % WORDS as u64) as u128;
        let raddr = if rng.next() % 4 == 0 { waddr } else { (rng.next() % WORDS as u64) as u128 };
        rows.push(vec![(rng.next() % 2) as u128, waddr, rng.next_u128() >> 32, raddr]);
    }
    rows
}

/// Cycle k shows the word at row k − 1's raddr as it was before row k − 1's write.
fn model(rows: &[Vec<u128>]) -> Vec<Vec<Option<u128>>> {
    let mut mem: Vec<Option<u128>> = vec![None; WORDS];
    let mut out = vec![vec![None]];
    for r in rows {
        out.push(vec![mem[r[3] as usize]]);
        if r[0] == 1 {
            mem[r[1] as usize] = Some(r[2]);
        }
    }
    out.pop();
    out
}

fn uut() -> BlockRam<W, N> {
    let mut u = BlockRam::<W, N>::new(WORDS);
    u.clock.connect();
    u.we.connect();
    u.waddr.connect();
    u.wdata.connect();
    u.raddr.connect();
    u.connect_all();
    u
}

#[test]
fn block_ram_three_ways() {
    let rows = stimulus();
    let want = model(&rows);
    assert!(want.iter().filter(|w| w[0].is_some()).count() > CYCLES / 2, "the reads must check something");
    let spec = TbSpec {
        clock: "clock".into(),
        inputs: vec![Port::new("we", 1), Port::new("waddr", N), Port::new("wdata", W), Port::new("raddr", N)],
        outputs: vec![Port::new("rdata", W)],
    };
    three_ways(
        "block_ram",
        uut,
        |u, c| u.clock.next = Clock::from(c),
        |u, r| {
            u.we.next = r[0] == 1;
            u.waddr.next = Bits::<N>::from(r[1] as u64);
            u.wdata.next = Bits::<W>::from(num_bigint::BigUint::from(r[2]));
            u.raddr.next = Bits::<N>::from(r[3] as u64);
        },
        |u| vec![bits_to_u128(u.rdata.val())],
        &spec,
        &rows,
        &want,
    );
}

#[test]
#[should_panic(expected = "words")]
fn block_ram_rejects_more_words_than_its_address_reaches() {
    let _ = BlockRam::<8, 4>::new(17);
}
