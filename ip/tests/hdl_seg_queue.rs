//! SegQueue three ways: a model of K bounded queues (a VecDeque per axis, a taken
//! counter per axis), rust-hdl simulation, and the exported Verilog in Verilator and
//! Icarus. Random pushes (to every axis and to axes ≥ K, many to full queues), pops
//! (many of empty queues, many with a push to the same axis in the same cycle),
//! aborts (some with a push in the same cycle) and resets: every cycle `push_ready`,
//! `nonempty`, the selected axis's level and taken counter, and the head of the axis
//! read in the cycle before equal the model's. Flushes of one queue (`flush`, the
//! per-axis stop), some with a push to that queue in the same cycle (written and
//! counted taken) and some with a push to another, empty it alone. A second RAM on the
//! queue's RAM ports reads, beside every head, the field it stored for that segment.

mod common;

use common::*;
use rust_hdl::prelude::*;
use std::collections::VecDeque;
use tdm_stepper::hdl::block_ram::BlockRam;
use tdm_stepper::hdl::seg_queue::{SegQueue, SEGMENT_BITS, SEG_ADDR_BITS};
use tdm_stepper::verify::{Port, TbSpec};

const K: usize = 3;
const QDEPTH: usize = 4;
const CYCLES: usize = 6000;

/// The queue with a second RAM on its RAM ports (`ram_we`, `ram_waddr`, `ram_raddr`)
/// that stores each pushed word's step field (bits 95..64): `side` must read, one
/// cycle after `head`'s address, the step field of the head, as a RAM holding more of
/// each segment beside the queue does (the S-curve option's fields).
#[derive(LogicBlock)]
struct QueueWithSide {
    clock: Signal<In, Clock>,
    reset: Signal<In, Bit>,
    abort: Signal<In, Bit>,
    flush: Signal<In, Bit>,
    push_valid: Signal<In, Bit>,
    push_axis: Signal<In, Bits<8>>,
    push_word: Signal<In, Bits<SEGMENT_BITS>>,
    axis: Signal<In, Bits<8>>,
    pop: Signal<In, Bit>,
    sel_axis: Signal<In, Bits<8>>,
    push_ready: Signal<Out, Bit>,
    nonempty: Signal<Out, Bits<K>>,
    sel_level: Signal<Out, Bits<8>>,
    sel_taken: Signal<Out, Bits<8>>,
    head: Signal<Out, Bits<SEGMENT_BITS>>,
    side: Signal<Out, Bits<32>>,
    q: SegQueue<K, QDEPTH>,
    ram: BlockRam<32, SEG_ADDR_BITS>,
}

impl Logic for QueueWithSide {
    #[hdl_gen]
    fn update(&mut self) {
        self.q.clock.next = self.clock.val();
        self.q.reset.next = self.reset.val();
        self.q.abort.next = self.abort.val();
        self.q.flush.next = self.flush.val();
        self.q.push_valid.next = self.push_valid.val();
        self.q.push_axis.next = self.push_axis.val();
        self.q.push_word.next = self.push_word.val();
        self.q.axis.next = self.axis.val();
        self.q.pop.next = self.pop.val();
        self.q.sel_axis.next = self.sel_axis.val();
        self.push_ready.next = self.q.push_ready.val();
        self.nonempty.next = self.q.nonempty.val();
        self.sel_level.next = self.q.sel_level.val();
        self.sel_taken.next = self.q.sel_taken.val();
        self.head.next = self.q.head.val();
        self.ram.clock.next = self.clock.val();
        self.ram.we.next = self.q.ram_we.val();
        self.ram.waddr.next = self.q.ram_waddr.val();
        self.ram.raddr.next = self.q.ram_raddr.val();
        self.ram.wdata.next = self.push_word.val().get_bits::<32>(64);
        self.side.next = self.ram.rdata.val();
    }
}

fn uut() -> QueueWithSide {
    let mut u = QueueWithSide {
        clock: Default::default(),
        reset: Default::default(),
        abort: Default::default(),
        flush: Default::default(),
        push_valid: Default::default(),
        push_axis: Default::default(),
        push_word: Default::default(),
        axis: Default::default(),
        pop: Default::default(),
        sel_axis: Default::default(),
        push_ready: Default::default(),
        nonempty: Default::default(),
        sel_level: Default::default(),
        sel_taken: Default::default(),
        head: Default::default(),
        side: Default::default(),
        q: SegQueue::<K, QDEPTH>::new(),
        ram: BlockRam::new(1 << SEG_ADDR_BITS),
    };
    u.clock.connect();
    u.reset.connect();
    u.abort.connect();
    u.flush.connect();
    u.push_valid.connect();
    u.push_axis.connect();
    u.push_word.connect();
    u.axis.connect();
    u.pop.connect();
    u.sel_axis.connect();
    u.connect_all();
    u
}

/// Rows: reset, abort, push_valid, push_axis, push_word, axis, pop, sel_axis, flush. Pushes
/// outnumber pops in some stretches and pops outnumber pushes in others, so that the
/// queues run full and empty again and again; the taken counters wrap (more than 256
/// segments per axis).
fn stimulus() -> Vec<Vec<u128>> {
    let mut rng = Rng(0x5e90_0e5e_1234_abcd);
    let mut rows = vec![vec![1, 0, 0, 0, 0, 0, 0, 0, 0]];
    for c in 0..CYCLES {
        let push_bias = if (c / 300) % 2 == 0 { 3 } else { 1 };
        let push = (rng.next() % 4 < push_bias) as u128;
        // Axis K (not present) now and then.
        let push_axis = (rng.next() % (K as u64 + 1)).min(K as u64) as u128;
        let axis = (rng.next() % K as u64) as u128;
        let pop = (rng.next() % 4 < 4 - push_bias) as u128;
        let abort = (rng.next() % 400 == 0) as u128;
        let reset = (rng.next() % 3000 == 0) as u128;
        let sel = (rng.next() % K as u64) as u128;
        let flush = (rng.next() % 150 == 0) as u128;
        // Half the flushes come with a push to the flushed queue.
        let (push, push_axis) = if flush == 1 && rng.next() % 2 == 0 { (1, axis) } else { (push, push_axis) };
        rows.push(vec![reset, abort, push, push_axis, rng.next_u128() >> 32, axis, pop, sel, flush]);
    }
    rows
}

/// Outputs per row: push_ready, nonempty, sel_level, sel_taken, head (the head of the
/// previous row's `axis` as it was before that row's edge; None while that queue was
/// empty, where the RAM word is not defined), the side RAM's word (the head's step
/// field); and how many segments were popped.
fn model(rows: &[Vec<u128>]) -> (Vec<Vec<Option<u128>>>, usize) {
    let mut q: Vec<VecDeque<u128>> = vec![VecDeque::new(); K];
    let mut pops = 0;
    let mut taken = [0u8; K];
    let mut head: Option<u128> = None;
    let mut out = Vec::new();
    for r in rows {
        let (reset, abort, push, pa, word, axis, pop, sel) =
            (r[0] == 1, r[1] == 1, r[2] == 1, r[3] as usize, r[4], r[5] as usize, r[6] == 1, r[7] as usize);
        let flush = r[8] == 1;
        let ready = pa >= K || q[pa].len() < QDEPTH;
        let nonempty = (0..K).filter(|&i| !q[i].is_empty()).map(|i| 1u128 << i).sum::<u128>();
        let side = head.map(|h| (h >> 64) & 0xffff_ffff);
        out.push(vec![Some(ready as u128), Some(nonempty), Some(q[sel].len() as u128), Some(taken[sel] as u128), head, side]);
        head = q[axis].front().copied();
        if reset {
            q.iter_mut().for_each(|x| x.clear());
            taken = [0; K];
        } else if abort {
            for i in 0..K {
                taken[i] = taken[i].wrapping_add(q[i].len() as u8);
                q[i].clear();
            }
        } else if flush {
            // Queue `axis` empties, a push to it in this cycle with it; pushes to
            // other queues go on.
            let with_push = push && pa == axis && ready;
            taken[axis] = taken[axis].wrapping_add((q[axis].len() + with_push as usize) as u8);
            q[axis].clear();
            if push && pa < K && pa != axis && ready {
                q[pa].push_back(word);
            }
        } else {
            if pop && !q[axis].is_empty() {
                q[axis].pop_front();
                taken[axis] = taken[axis].wrapping_add(1);
                pops += 1;
            }
            if push && pa < K && ready {
                q[pa].push_back(word);
            }
        }
    }
    (out, pops)
}

#[test]
fn seg_queue_three_ways() {
    let rows = stimulus();
    let (want, pops) = model(&rows);
    // The stimulus reaches what it is meant to: full queues refusing, heads read, the
    // taken counters past 255.
    assert!(want.iter().filter(|w| w[0] == Some(0)).count() > 500, "full queues");
    assert!(want.iter().filter(|w| w[4].is_some()).count() > CYCLES / 2, "heads read");
    assert!(rows.iter().filter(|r| r[1] == 1).count() >= 5, "aborts");
    assert!(rows.iter().filter(|r| r[8] == 1 && r[0] == 0 && r[1] == 0).count() >= 20, "flushes");
    assert!(rows.iter().filter(|r| r[8] == 1 && r[2] == 1 && r[3] == r[5]).count() >= 3, "flushes with a push to the same queue");
    assert!(pops > 256 * K, "the taken counters wrap ({pops} pops)");
    let spec = TbSpec {
        clock: "clock".into(),
        inputs: vec![
            Port::new("reset", 1),
            Port::new("abort", 1),
            Port::new("push_valid", 1),
            Port::new("push_axis", 8),
            Port::new("push_word", SEGMENT_BITS),
            Port::new("axis", 8),
            Port::new("pop", 1),
            Port::new("sel_axis", 8),
            Port::new("flush", 1),
        ],
        outputs: vec![
            Port::new("push_ready", 1),
            Port::new("nonempty", K),
            Port::new("sel_level", 8),
            Port::new("sel_taken", 8),
            Port::new("head", SEGMENT_BITS),
            Port::new("side", 32),
        ],
    };
    three_ways(
        "seg_queue",
        uut,
        |u, c| u.clock.next = Clock::from(c),
        |u, r| {
            u.reset.next = r[0] == 1;
            u.abort.next = r[1] == 1;
            u.push_valid.next = r[2] == 1;
            u.push_axis.next = Bits::<8>::from(r[3] as u64);
            u.push_word.next = Bits::<SEGMENT_BITS>::from(num_bigint::BigUint::from(r[4]));
            u.axis.next = Bits::<8>::from(r[5] as u64);
            u.pop.next = r[6] == 1;
            u.sel_axis.next = Bits::<8>::from(r[7] as u64);
            u.flush.next = r[8] == 1;
        },
        |u| {
            vec![
                u.push_ready.val() as u128,
                u.nonempty.val().to_u64() as u128,
                u.sel_level.val().to_u64() as u128,
                u.sel_taken.val().to_u64() as u128,
                bits_to_u128(u.head.val()),
                u.side.val().to_u64() as u128,
            ]
        },
        &spec,
        &rows,
        &want,
    );
}

#[test]
#[should_panic(expected = "power of two")]
fn seg_queue_rejects_a_depth_that_is_not_a_power_of_two() {
    let _ = SegQueue::<2, 12>::new();
}

#[test]
#[should_panic(expected = "outside 1..=16")]
fn seg_queue_rejects_more_axes_than_its_ram_reaches() {
    let _ = SegQueue::<17, 2>::new();
}
