//! FIFO in LUT RAM, `DEPTH` entries of `W` bits (DEPTH ≤ 32), show-ahead (the head
//! entry is on `head` whenever `empty` is low). The per-axis period FIFO
//! ([`PeriodFifo`]) is its instance (the segment queues share one RAM, in
//! [`super::seg_queue::SegQueue`]).
//!
//! The entries live in a 32-word [`LutRam`] (asynchronous read at the read pointer),
//! so a deeper FIFO costs memory bits, not flip-flops and a DEPTH:1 multiplexer; only
//! the pointers and the count are registers.
//!
//! Period entry layout ([`pack_entry`]): bits 31..0 ticks, bit 32 step (1: the entry
//! ends in a STEP edge; 0: a dwell), bit 33 reverse (direction of that step), bit 34
//! last (the entry ends its segment; the step generator counts segments done on it),
//! bits 50..35 the STEP high time of a pulse that rises at the entry's start (or at
//! its end, for the last entry of a move), as [`crate::model::PulseTiming::high_ticks`]
//! computes it, bit 51 one (the entry is one tick long, ticks = 1: the step generator
//! then ends it at the edge after its load without a compare of its count).
//! `push` is ignored when full and `pop` when empty; both in one cycle is allowed.
//! `reset` (synchronous) empties it. `level` is the number of entries held. Latency:
//! an entry pushed at an edge is on `head` from that edge when the FIFO was empty.
//!
//! Structure (area, one per axis): the count moves by one adder (+1 on a push alone,
//! −1 on a pop alone, selected ahead of the carry chain), and the pointers run modulo
//! the RAM's 32 words whatever DEPTH is (the count keeps at most DEPTH ≤ 32 entries
//! between them), so they wrap by themselves, with no compare.

use super::lut_ram::LutRam;
use rust_hdl::prelude::*;

/// Width of a period entry.
pub const ENTRY_BITS: usize = 52;
/// Address bits of the RAM behind every FIFO: 32 words.
const ADDR_BITS: usize = 5;

/// Packs an entry as the FIFO stores it.
pub fn pack_entry(ticks: u32, step: bool, reverse: bool, last: bool, high: u16) -> u64 {
    ticks as u64 | (step as u64) << 32 | (reverse as u64) << 33 | (last as u64) << 34 | (high as u64) << 35 | ((ticks == 1) as u64) << 51
}

/// The per-axis period FIFO.
pub type PeriodFifo<const DEPTH: usize> = RamFifo<ENTRY_BITS, DEPTH>;

#[derive(LogicBlock)]
pub struct RamFifo<const W: usize, const DEPTH: usize> {
    pub clock: Signal<In, Clock>,
    pub reset: Signal<In, Bit>,
    pub push: Signal<In, Bit>,
    pub entry_in: Signal<In, Bits<W>>,
    pub pop: Signal<In, Bit>,
    pub head: Signal<Out, Bits<W>>,
    pub empty: Signal<Out, Bit>,
    pub full: Signal<Out, Bit>,
    pub level: Signal<Out, Bits<8>>,
    ram: LutRam<W, ADDR_BITS>,
    wr: DFF<Bits<ADDR_BITS>>,
    rd: DFF<Bits<ADDR_BITS>>,
    count: DFF<Bits<8>>,
    do_push: Signal<Local, Bit>,
    do_pop: Signal<Local, Bit>,
    count_delta: Signal<Local, Bits<8>>,
    minus_one: Constant<Bits<8>>,
    depth: Constant<Bits<8>>,
}

impl<const W: usize, const DEPTH: usize> Default for RamFifo<W, DEPTH> {
    fn default() -> Self {
        assert!((2..=1 << ADDR_BITS).contains(&DEPTH), "RamFifo<{W}, {DEPTH}>: depth outside 2..=32");
        RamFifo {
            clock: Default::default(),
            reset: Default::default(),
            push: Default::default(),
            entry_in: Default::default(),
            pop: Default::default(),
            head: Default::default(),
            empty: Default::default(),
            full: Default::default(),
            level: Default::default(),
            ram: Default::default(),
            wr: Default::default(),
            rd: Default::default(),
            count: Default::default(),
            do_push: Default::default(),
            do_pop: Default::default(),
            count_delta: Default::default(),
            minus_one: Constant::new(0xFFu64.into()),
            depth: Constant::new((DEPTH as u64).into()),
        }
    }
}

impl<const W: usize, const DEPTH: usize> Logic for RamFifo<W, DEPTH> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, wr, rd, count);
        self.empty.next = self.count.q.val() == 0;
        self.full.next = self.count.q.val() == self.depth.val();
        self.level.next = self.count.q.val();
        self.do_push.next = self.push.val() & (self.count.q.val() != self.depth.val());
        self.do_pop.next = self.pop.val() & (self.count.q.val() != 0);
        self.ram.clock.next = self.clock.val();
        self.ram.we.next = self.do_push.val();
        self.ram.waddr.next = self.wr.q.val();
        self.ram.wdata.next = self.entry_in.val();
        self.ram.raddr.next = self.rd.q.val();
        self.head.next = self.ram.rdata.val();
        // The pointers wrap at the RAM's 32 words (5 bits), not at DEPTH.
        if self.do_push.val() {
            self.wr.d.next = self.wr.q.val() + 1;
        }
        if self.do_pop.val() {
            self.rd.d.next = self.rd.q.val() + 1;
        }
        // One adder for both directions: +1 on a push alone, -1 on a pop alone.
        if self.do_push.val() {
            self.count_delta.next = 1.into();
        } else {
            self.count_delta.next = self.minus_one.val();
        }
        if self.do_push.val() != self.do_pop.val() {
            self.count.d.next = self.count.q.val() + self.count_delta.val();
        }
        if self.reset.val() {
            self.wr.d.next = 0.into();
            self.rd.d.next = 0.into();
            self.count.d.next = 0.into();
        }
    }
}
