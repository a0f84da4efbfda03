//! Register FIFO, `DEPTH` entries of `W` bits, show-ahead (the head entry is on
//! `head` whenever `empty` is low). The per-axis period FIFO ([`PeriodFifo`]) and the
//! per-axis segment queues are instances.
//!
//! Period entry layout ([`pack_entry`]): bits 31..0 ticks, bit 32 step (1: the entry
//! ends in a STEP edge; 0: a dwell), bit 33 reverse (direction of that step), bit 34
//! last (the entry ends its segment; the step generator counts segments done on it).
//! `push` is ignored when full and `pop` when empty; both in one cycle is allowed.
//! `reset` (synchronous) empties it. `level` is the number of entries held.

use rust_hdl::prelude::*;

/// Width of a period entry.
pub const ENTRY_BITS: usize = 35;

/// Packs an entry as the FIFO stores it.
pub fn pack_entry(ticks: u32, step: bool, reverse: bool, last: bool) -> u64 {
    ticks as u64 | (step as u64) << 32 | (reverse as u64) << 33 | (last as u64) << 34
}

/// The per-axis period FIFO.
pub type PeriodFifo<const DEPTH: usize> = RegFifo<ENTRY_BITS, DEPTH>;

#[derive(LogicBlock)]
pub struct RegFifo<const W: usize, const DEPTH: usize> {
    pub clock: Signal<In, Clock>,
    pub reset: Signal<In, Bit>,
    pub push: Signal<In, Bit>,
    pub entry_in: Signal<In, Bits<W>>,
    pub pop: Signal<In, Bit>,
    pub head: Signal<Out, Bits<W>>,
    pub empty: Signal<Out, Bit>,
    pub full: Signal<Out, Bit>,
    pub level: Signal<Out, Bits<8>>,
    mem: [DFF<Bits<W>>; DEPTH],
    wr: DFF<Bits<8>>,
    rd: DFF<Bits<8>>,
    count: DFF<Bits<8>>,
    do_push: Signal<Local, Bit>,
    do_pop: Signal<Local, Bit>,
    last: Constant<Bits<8>>,
    depth: Constant<Bits<8>>,
}

impl<const W: usize, const DEPTH: usize> Default for RegFifo<W, DEPTH> {
    fn default() -> Self {
        assert!((2..=64).contains(&DEPTH), "RegFifo<{W}, {DEPTH}>: depth outside 2..=64");
        RegFifo {
            clock: Default::default(),
            reset: Default::default(),
            push: Default::default(),
            entry_in: Default::default(),
            pop: Default::default(),
            head: Default::default(),
            empty: Default::default(),
            full: Default::default(),
            level: Default::default(),
            mem: std::array::from_fn(|_| Default::default()),
            wr: Default::default(),
            rd: Default::default(),
            count: Default::default(),
            do_push: Default::default(),
            do_pop: Default::default(),
            last: Constant::new(((DEPTH - 1) as u64).into()),
            depth: Constant::new((DEPTH as u64).into()),
        }
    }
}

impl<const W: usize, const DEPTH: usize> Logic for RegFifo<W, DEPTH> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, wr, rd, count);
        for i in 0..DEPTH {
            self.mem[i].clock.next = self.clock.val();
            self.mem[i].d.next = self.mem[i].q.val();
        }
        self.empty.next = self.count.q.val() == 0;
        self.full.next = self.count.q.val() == self.depth.val();
        self.level.next = self.count.q.val();
        self.do_push.next = self.push.val() & (self.count.q.val() != self.depth.val());
        self.do_pop.next = self.pop.val() & (self.count.q.val() != 0);
        self.head.next = 0.into();
        for i in 0..DEPTH {
            if self.rd.q.val().index() == i {
                self.head.next = self.mem[i].q.val();
            }
            if self.do_push.val() & (self.wr.q.val().index() == i) {
                self.mem[i].d.next = self.entry_in.val();
            }
        }
        if self.do_push.val() {
            if self.wr.q.val() == self.last.val() {
                self.wr.d.next = 0.into();
            } else {
                self.wr.d.next = self.wr.q.val() + 1;
            }
        }
        if self.do_pop.val() {
            if self.rd.q.val() == self.last.val() {
                self.rd.d.next = 0.into();
            } else {
                self.rd.d.next = self.rd.q.val() + 1;
            }
        }
        if self.do_push.val() & !self.do_pop.val() {
            self.count.d.next = self.count.q.val() + 1;
        }
        if self.do_pop.val() & !self.do_push.val() {
            self.count.d.next = self.count.q.val() - 1;
        }
        if self.reset.val() {
            self.wr.d.next = 0.into();
            self.rd.d.next = 0.into();
            self.count.d.next = 0.into();
        }
    }
}
