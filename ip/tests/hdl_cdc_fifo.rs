//! AsyncFifo and MaskCross three ways: a model of their pointers, toggles and
//! synchronisers, rust-hdl, and the exported Verilog in Verilator and Icarus. Both
//! sides run on one clock here (a wrapper ties the two clocks together), so each
//! synchroniser is exactly two
//! edges: the writer sees the reader's pointer two cycles late and the reader the
//! writer's. Random writes (also while full) and reads (also while empty): every entry
//! comes out once, in order; `full` and `empty` are the model's every cycle, and
//! `almost_full` is DEPTH − 1 entries or more as the writer saw them a cycle before.

mod common;

use common::*;
use rust_hdl::prelude::*;
use std::collections::VecDeque;
use tdm_stepper::hdl::cdc::{AsyncFifo, MaskCross, ASYNC_FIFO_DEPTH};
use tdm_stepper::verify::{run_rust_hdl, Port, TbSpec};

/// The FIFO with both clocks on one input, so the common testbench can drive it.
#[derive(LogicBlock, Default)]
struct OneClockFifo {
    pub clock: Signal<In, Clock>,
    pub reset: Signal<In, Bit>,
    pub write: Signal<In, Bit>,
    pub data_in: Signal<In, Bits<8>>,
    pub read: Signal<In, Bit>,
    pub full: Signal<Out, Bit>,
    pub almost_full: Signal<Out, Bit>,
    pub empty: Signal<Out, Bit>,
    pub data_out: Signal<Out, Bits<8>>,
    fifo: AsyncFifo<8>,
}

impl Logic for OneClockFifo {
    #[hdl_gen]
    fn update(&mut self) {
        self.fifo.wclock.next = self.clock.val();
        self.fifo.rclock.next = self.clock.val();
        self.fifo.wreset.next = self.reset.val();
        self.fifo.rreset.next = self.reset.val();
        self.fifo.write.next = self.write.val();
        self.fifo.data_in.next = self.data_in.val();
        self.fifo.read.next = self.read.val();
        self.full.next = self.fifo.full.val();
        self.almost_full.next = self.fifo.almost_full.val();
        self.empty.next = self.fifo.empty.val();
        // The head only while there is one (an unwritten RAM word is x in the Verilog).
        self.data_out.next = 0.into();
        if !self.fifo.empty.val() {
            self.data_out.next = self.fifo.data_out.val();
        }
    }
}

fn uut() -> OneClockFifo {
    let mut u = OneClockFifo::default();
    u.clock.connect();
    u.reset.connect();
    u.write.connect();
    u.data_in.connect();
    u.read.connect();
    u.connect_all();
    u
}

fn spec() -> TbSpec {
    TbSpec {
        clock: "clock".into(),
        inputs: vec![Port::new("reset", 1), Port::new("write", 1), Port::new("data_in", 8), Port::new("read", 1)],
        outputs: vec![Port::new("full", 1), Port::new("almost_full", 1), Port::new("empty", 1), Port::new("data_out", 8)],
    }
}

#[test]
fn async_fifo_flags_and_order_three_ways() {
    let mut rng = Rng(0xf1f0_5eed);
    let mut rows: Vec<Vec<u128>> = vec![vec![1, 0, 0, 0]; 3];
    for phase in 0..6 {
        // Phases that fill the FIFO (writes often, reads rare), drain it, and mix.
        let (pw, pr) = [(90, 10), (20, 90), (60, 60), (95, 30), (30, 30), (100, 0)][phase];
        for _ in 0..200 {
            rows.push(vec![0, (rng.next() % 100 < pw) as u128, (rng.next() & 0xff) as u128, (rng.next() % 100 < pr) as u128]);
        }
    }
    rows.extend(vec![vec![0, 0, 0, 1]; 8]);

    let out = run_rust_hdl(
        &mut uut(),
        &rows,
        |u, c| u.clock.next = Clock::from(c),
        |u, r| {
            u.reset.next = r[0] == 1;
            u.write.next = r[1] == 1;
            u.data_in.next = (r[2] as u64).into();
            u.read.next = r[3] == 1;
        },
        |u| vec![u.full.val() as u128, u.almost_full.val() as u128, u.empty.val() as u128, u.data_out.val().to_u64() as u128],
    );

    // The model: pointers as counts; w[t] and r[t] are their values in cycle t.
    let depth = ASYNC_FIFO_DEPTH as i64;
    let (mut w, mut r) = (vec![0i64; rows.len() + 1], vec![0i64; rows.len() + 1]);
    let mut q = VecDeque::new();
    let (mut out_vals, mut in_vals) = (vec![], vec![]);
    let back = |v: &[i64], t: usize, n: usize| if t >= n { v[t - n] } else { 0 };
    let (mut saw_full, mut saw_almost_not_full) = (0, 0);
    for (t, row) in rows.iter().enumerate() {
        if row[0] == 1 {
            w[t + 1] = 0;
            r[t + 1] = 0;
            q.clear();
            continue;
        }
        let full = w[t] - back(&r, t, 2) == depth;
        let empty = r[t] == back(&w, t, 2);
        let almost = t >= 1 && rows[t - 1][0] == 0 && w[t - 1] - back(&r, t - 1, 2) >= depth - 1;
        assert_eq!(out[t][0], full as u128, "full at row {t}");
        assert_eq!(out[t][2], empty as u128, "empty at row {t}");
        assert_eq!(out[t][1], almost as u128, "almost_full at row {t}");
        saw_full += full as usize;
        saw_almost_not_full += (almost && !full) as usize;
        w[t + 1] = w[t];
        r[t + 1] = r[t];
        if !empty {
            assert_eq!(out[t][3], *q.front().unwrap() as u128, "data_out at row {t}");
            if row[3] == 1 {
                out_vals.push(q.pop_front().unwrap());
                r[t + 1] += 1;
            }
        }
        if row[1] == 1 && !full {
            q.push_back(row[2] as u8);
            in_vals.push(row[2] as u8);
            w[t + 1] += 1;
        }
    }
    assert!(saw_full > 50 && saw_almost_not_full > 20, "the test reaches full ({saw_full}) and almost full ({saw_almost_not_full})");
    assert_eq!(out_vals, in_vals[..out_vals.len()], "entries out in order");
    assert!(out_vals.len() + 4 >= in_vals.len(), "drained at the end");

    verilog_matches_rust_hdl("cdc_fifo", &generate_verilog(&uut()), &spec(), &rows, &out, 3);
}

/// The mask crossing with both clocks on one input.
#[derive(LogicBlock, Default)]
struct OneClockMask {
    pub clock: Signal<In, Clock>,
    pub reset: Signal<In, Bit>,
    pub req: Signal<In, Bits<8>>,
    pub out: Signal<Out, Bits<8>>,
    x: MaskCross<8>,
}

impl Logic for OneClockMask {
    #[hdl_gen]
    fn update(&mut self) {
        self.x.bus_clock.next = self.clock.val();
        self.x.clock.next = self.clock.val();
        self.x.bus_reset.next = self.reset.val();
        self.x.req.next = self.req.val();
        self.out.next = self.x.out.val();
    }
}

fn mask_uut() -> OneClockMask {
    let mut u = OneClockMask::default();
    u.clock.connect();
    u.reset.connect();
    u.req.connect();
    u.connect_all();
    u
}

/// MaskCross: requests in bursts and alone, a reset dropping a pending one (and not the
/// mask already crossing). Every cycle equals a model of its toggle and synchronisers;
/// after the reset every
/// requested bit leaves within 11 cycles, in a one-cycle mask of bits requested and not
/// yet sent, and a request with nothing crossing leaves exactly 4 cycles later (the
/// write's edge, one to take the mask, two synchroniser stages).
#[test]
fn mask_crossing_loses_nothing_three_ways() {
    let mut rng = Rng(0x3a5c_c055);
    let mut rows: Vec<Vec<u128>> = vec![vec![1, 0]; 3];
    for phase in 0..8 {
        let p = [40, 3, 0, 90, 10, 5, 60, 2][phase];
        for _ in 0..250 {
            let req = if rng.next() % 100 < p { 1u128 << (rng.next() % 8) } else { 0 };
            rows.push(vec![0, req]);
        }
        if phase == 0 {
            // With nothing crossing, a request (taken at once), a second (collecting
            // while the first crosses), and the reset, which drops the second only.
            rows.extend(vec![vec![0, 0]; 12]);
            rows.push(vec![0, 0x81]);
            rows.push(vec![0, 0x42]);
            rows.push(vec![1, 0]);
            rows.extend(vec![vec![0, 0]; 12]);
        }
    }
    rows.extend(vec![vec![0, 0]; 16]);
    let out = run_rust_hdl(
        &mut mask_uut(),
        &rows,
        |u, c| u.clock.next = Clock::from(c),
        |u, r| {
            u.reset.next = r[0] == 1;
            u.req.next = (r[1] as u64).into();
        },
        |u| vec![u.out.val().to_u64() as u128],
    );

    // The model, one clock: (nxt, mask, tog) in the bus clock, the toggle's two stages
    // and its copy `tprev` in clk, the copy's two stages back.
    let (mut nxt, mut mask, mut tog) = (0u128, 0u128, false);
    let (mut s1, mut s2, mut tprev, mut a1, mut a2) = (false, false, false, false, false);
    for (t, row) in rows.iter().enumerate() {
        let o = if s2 ^ tprev { mask } else { 0 };
        assert_eq!(out[t][0], o, "out at row {t}");
        let busy = tog ^ a2;
        let (mut n_nxt, mut n_mask, mut n_tog) = (nxt | row[1], mask, tog);
        if !busy && nxt != 0 {
            (n_mask, n_tog, n_nxt) = (nxt, !tog, row[1]);
        }
        if row[0] == 1 {
            n_nxt = 0;
        }
        (a2, a1, tprev, s2, s1) = (a1, tprev, s2, s1, tog);
        (nxt, mask, tog) = (n_nxt, n_mask, n_tog);
    }

    // The contract, from the rows alone, after the last reset.
    let last_reset = rows.iter().rposition(|r| r[0] == 1).unwrap();
    let around = (last_reset + 1..last_reset + 13).fold(0, |a, t| a | out[t][0]);
    assert_eq!((around & 0x40, around & 0x01), (0, 0x01), "the reset drops the request still collecting, not the mask already taken");
    let mut pending: Vec<(usize, u128)> = vec![];
    let (mut sent, mut idle_4) = (0, 0);
    for t in last_reset + 13..rows.len() {
        let o = out[t][0];
        if o != 0 {
            assert_eq!(out.get(t + 1).map_or(0, |r| r[0]), 0, "row {t}: a mask lasts one cycle");
            // A mask sent now was taken three cycles ago, from requests of rows before.
            let asked = pending.iter().filter(|p| p.0 + 4 <= t).fold(0, |a, p| a | p.1);
            assert_eq!(o & !asked, 0, "row {t}: {o:#x} sends bits not requested");
            if pending.len() == 1 && t == pending[0].0 + 4 {
                idle_4 += 1;
            }
            pending.retain(|p| p.0 + 4 > t || p.1 & !o != 0);
            sent += 1;
        }
        if let Some(p) = pending.first() {
            assert!(t <= p.0 + 11, "row {t}: the request of row {} ({:#x}) not sent", p.0, p.1);
        }
        if rows[t][1] != 0 {
            pending.push((t, rows[t][1]));
        }
    }
    assert!(pending.is_empty(), "requests left: {pending:?}");
    assert!(sent > 100 && idle_4 > 15, "masks sent {sent}, of them alone and 4 cycles after their request {idle_4}");

    verilog_matches_rust_hdl("cdc_mask", &generate_verilog(&mask_uut()), &TbSpec {
        clock: "clock".into(),
        inputs: vec![Port::new("reset", 1), Port::new("req", 8)],
        outputs: vec![Port::new("out", 8)],
    }, &rows, &out, 0);
}
