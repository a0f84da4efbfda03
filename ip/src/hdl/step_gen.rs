//! Per-axis step generator: turns period-FIFO entries into STEP and DIR.
//!
//! Timing (docs/architecture.md, "Step timing"; the pins' model is
//! [`crate::model::pulse`]):
//! * `go` (the release: one cycle, while idle and the FIFO is not empty) loads the first
//!   entry at that clock edge, tick L₀. An entry of `ticks` loaded at edge L ends at
//!   edge L + ticks, where the next entry loads. So step i of a move rises exactly
//!   at L₀ + E_i, E_i being the reference model's edge tick.
//! * STEP rises at the end of an entry whose `step` bit is set (a dwell has none),
//!   and the position moves by ±1 on that edge.
//! * STEP stays high for the high time `h` carried by the entry that follows (bits
//!   50..35, computed by the core from the output timing registers: at least
//!   max(STEP_HIGH, DIR_HOLD), leaving at least max(STEP_LOW, DIR_SETUP) low). At the end
//!   of a move (FIFO empty, `more` low) it is the `h` of the entry that just ended.
//! * DIR takes the direction of the next step while STEP is low: on the edge where STEP
//!   falls, or one tick after a step's entry loads if STEP is already low. A dwell entry
//!   leaves DIR alone. So DIR holds for at least the high time after a rising edge and
//!   is set up for at least the low time (or the entry less one tick) before the next.
//! * Underrun: an entry ends, the FIFO is empty and `more` says steps are still to
//!   come. The generator waits with STEP held (the pulse stretches), sets the sticky
//!   `underrun`, and continues when the entry arrives, the pulse then lasting that
//!   entry's `h`. No step is lost; the next edge is late by the wait.
//! * `abort` (one cycle) is a hard stop: no further edge rises, the FIFO's entries are
//!   left for the owner to flush, and a pulse already high keeps its high time, so
//!   the position counts exactly the edges emitted.
//! * Counters (8 bits, wrapping): `done_count` counts entries flagged last that
//!   ended (segments done), `under_count` counts underruns begun.
//! * `reset` (synchronous) stops the axis and clears position, `underrun` and the
//!   counters, but a pulse already high finishes its high time first (with DIR held):
//!   disabling the core or resetting it never cuts a pulse short.
//!
//! Latency: a `go` or a loaded entry acts at the clock edge it is seen; STEP and DIR are
//! registers (no combinational path from any input to them).
//!
//! Structure (area, since there is one per axis): the three loads of the head entry
//! (an entry's end, an underrun's end, the release) are one `load`, and the position
//! moves by one adder (+1 or −1 selected ahead of the carry chain), not two. An entry
//! ends on a flip-flop, `one` (the count is 1), set a cycle ahead from a running count
//! of 2 or, at a load, from the entry's one-tick flag (bit 51, written by the pulse
//! stage), so no compare of the 32-bit count lies in front of `load` and the pop.

use super::ram_fifo::ENTRY_BITS;
use rust_hdl::prelude::*;

#[derive(LogicBlock)]
pub struct StepGen {
    pub clock: Signal<In, Clock>,
    pub reset: Signal<In, Bit>,
    pub go: Signal<In, Bit>,
    pub abort: Signal<In, Bit>,
    /// More entries are coming for this axis (the scheduler still has steps).
    pub more: Signal<In, Bit>,
    /// The FIFO's head entry and whether it is there.
    pub head: Signal<In, Bits<ENTRY_BITS>>,
    pub head_valid: Signal<In, Bit>,
    pub pop: Signal<Out, Bit>,
    pub step: Signal<Out, Bit>,
    pub dir: Signal<Out, Bit>,
    pub position: Signal<Out, Bits<32>>,
    pub underrun: Signal<Out, Bit>,
    pub active: Signal<Out, Bit>,
    /// Running an entry that ends with a step (not a dwell's): the axis is moving.
    pub moving: Signal<Out, Bit>,
    pub done_count: Signal<Out, Bits<8>>,
    pub under_count: Signal<Out, Bits<8>>,
    running: DFF<Bit>,
    waiting: DFF<Bit>,
    count: DFF<Bits<32>>,
    cur_high: DFF<Bits<16>>,
    cur_step: DFF<Bit>,
    cur_rev: DFF<Bit>,
    high: DFF<Bits<16>>,
    step_q: DFF<Bit>,
    dir_q: DFF<Bit>,
    pos: DFF<Bits<32>>,
    under: DFF<Bit>,
    cur_last: DFF<Bit>,
    /// The count is 1 (the current entry ends at this edge), registered: set from the
    /// head's one-tick flag (bit 51) at a load, else when a running count is at 2.
    one: DFF<Bit>,
    done_cnt: DFF<Bits<8>>,
    under_cnt: DFF<Bits<8>>,
    head_ticks: Signal<Local, Bits<32>>,
    head_high: Signal<Local, Bits<16>>,
    ends: Signal<Local, Bit>,
    load: Signal<Local, Bit>,
    stepping: Signal<Local, Bit>,
    pos_delta: Signal<Local, Bits<32>>,
    pulse_alive: Signal<Local, Bit>,
    /// −1 in 32 bits: the position's step backwards.
    c_minus_one: Constant<Bits<32>>,
}

impl Default for StepGen {
    fn default() -> Self {
        StepGen {
            clock: Default::default(),
            reset: Default::default(),
            go: Default::default(),
            abort: Default::default(),
            more: Default::default(),
            head: Default::default(),
            head_valid: Default::default(),
            pop: Default::default(),
            step: Default::default(),
            dir: Default::default(),
            position: Default::default(),
            underrun: Default::default(),
            active: Default::default(),
            moving: Default::default(),
            done_count: Default::default(),
            under_count: Default::default(),
            running: Default::default(),
            waiting: Default::default(),
            count: Default::default(),
            cur_high: Default::default(),
            cur_step: Default::default(),
            cur_rev: Default::default(),
            high: Default::default(),
            step_q: Default::default(),
            dir_q: Default::default(),
            pos: Default::default(),
            under: Default::default(),
            cur_last: Default::default(),
            one: Default::default(),
            done_cnt: Default::default(),
            under_cnt: Default::default(),
            head_ticks: Default::default(),
            head_high: Default::default(),
            ends: Default::default(),
            load: Default::default(),
            stepping: Default::default(),
            pos_delta: Default::default(),
            pulse_alive: Default::default(),
            c_minus_one: Constant::new((u32::MAX as u64).into()),
        }
    }
}

impl Logic for StepGen {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clock, running, waiting, count, cur_high, cur_step, cur_rev, high, step_q, dir_q, pos, under, cur_last,
            one, done_cnt, under_cnt
        );
        self.head_ticks.next = self.head.val().get_bits::<32>(0);
        self.head_high.next = self.head.val().get_bits::<16>(35);
        // The entry ends at this edge: its count is 1, a flag registered a cycle ahead
        // (no compare of the count in front of the load and the pop).
        self.ends.next = self.running.q.val() & !self.waiting.q.val() & self.one.q.val();
        // The head entry becomes the current one: at the end of an entry, at the end of
        // an underrun's wait, or at the release. One load for every case, so each
        // register has one data path from the head.
        self.load.next = self.head_valid.val()
            & (self.ends.val()
                | (self.running.q.val() & self.waiting.q.val())
                | (!self.running.q.val() & self.go.val()));
        // A step at the end of this entry: the position moves by ±1, as one adder.
        self.stepping.next = self.ends.val() & self.cur_step.q.val();
        if self.cur_rev.q.val() {
            self.pos_delta.next = self.c_minus_one.val();
        } else {
            self.pos_delta.next = 1.into();
        }
        self.step.next = self.step_q.q.val();
        self.dir.next = self.dir_q.q.val();
        self.position.next = self.pos.q.val();
        self.underrun.next = self.under.q.val();
        self.active.next = self.running.q.val();
        self.moving.next = self.running.q.val() & self.cur_step.q.val();
        self.done_count.next = self.done_cnt.q.val();
        self.under_count.next = self.under_cnt.q.val();
        self.pop.next = self.load.val();

        // DIR follows the current step's direction while STEP is low.
        if !self.step_q.q.val() {
            self.dir_q.d.next = self.cur_rev.q.val();
        }
        // The pulse: count its high time down, except while an underrun stretches it.
        if (self.high.q.val() != 0) & !self.waiting.q.val() {
            self.high.d.next = self.high.q.val() - 1;
            if self.high.q.val() == 1 {
                self.step_q.d.next = false;
                self.dir_q.d.next = self.cur_rev.q.val();
            }
        }
        // The entry's ticks: loaded from the head, else counted down while running.
        if self.load.val() {
            self.count.d.next = self.head_ticks.val();
        } else if self.running.q.val() & !self.waiting.q.val() {
            self.count.d.next = self.count.q.val() - 1;
        }
        // `one` follows the count: 1 after this edge when the head loads with ticks = 1,
        // or a running count moves from 2 (no load can come with a count of 2).
        if self.load.val() {
            self.one.d.next = self.head.val().get_bit(51);
        } else {
            self.one.d.next = self.running.q.val() & !self.waiting.q.val() & (self.count.q.val() == 2);
        }
        if self.load.val() {
            self.cur_high.d.next = self.head_high.val();
            self.cur_step.d.next = self.head.val().get_bit(32);
            self.cur_last.d.next = self.head.val().get_bit(34);
            if self.head.val().get_bit(32) {
                self.cur_rev.d.next = self.head.val().get_bit(33);
            }
        }
        if self.stepping.val() {
            self.step_q.d.next = true;
            self.pos.d.next = self.pos.q.val() + self.pos_delta.val();
        }
        // A pulse that rises at this entry's end takes the high time of the entry that
        // follows, or, at an underrun or the end of the move, the current entry's.
        if self.stepping.val() {
            if self.head_valid.val() {
                self.high.d.next = self.head_high.val();
            } else {
                self.high.d.next = self.cur_high.q.val();
            }
        }
        // Underrun over: a stretched pulse restarts its high time from the late entry.
        if self.running.q.val() & self.waiting.q.val() & self.head_valid.val() & self.step_q.q.val() {
            self.high.d.next = self.head_high.val();
        }
        if self.ends.val() & self.cur_last.q.val() {
            self.done_cnt.d.next = self.done_cnt.q.val() + 1;
        }
        if self.ends.val() & !self.head_valid.val() {
            if self.more.val() {
                self.waiting.d.next = true;
                self.under.d.next = true;
                self.under_cnt.d.next = self.under_cnt.q.val() + 1;
            } else {
                self.running.d.next = false;
            }
        }
        if self.load.val() {
            self.running.d.next = true;
            self.waiting.d.next = false;
        }
        if self.abort.val() {
            self.running.d.next = false;
            self.waiting.d.next = false;
            self.count.d.next = 0.into();
            self.one.d.next = false;
        }
        // A pulse still to run its high time (or held by an underrun) survives a reset;
        // written as if/else so that an unknown (X) state at power-up takes the clearing
        // branch in a four-state simulator.
        self.pulse_alive.next = self.step_q.q.val() & (self.high.q.val() > 1);
        if self.reset.val() {
            self.done_cnt.d.next = 0.into();
            self.under_cnt.d.next = 0.into();
            self.running.d.next = false;
            self.waiting.d.next = false;
            self.pos.d.next = 0.into();
            self.under.d.next = false;
            self.count.d.next = 0.into();
            self.one.d.next = false;
            if self.pulse_alive.val() {
                self.high.d.next = self.high.q.val() - 1;
            } else {
                self.high.d.next = 0.into();
                self.step_q.d.next = false;
                self.dir_q.d.next = false;
                self.cur_rev.d.next = false;
            }
        }
    }
}

/// The per-axis back end: a period FIFO feeding a [`StepGen`]. `full` says the FIFO
/// holds `DEPTH` entries, the most the scheduler computes ahead. The scheduler reads
/// `full` from a register of its own, a cycle later, while an entry may still be in the
/// pulse stage, so a FIFO can reach DEPTH + 1 entries (docs/architecture.md, "PICK
/// decides from flip-flops"); the FIFO itself has room for 32, so they always fit.
#[derive(LogicBlock)]
pub struct StepAxis<const DEPTH: usize> {
    pub clock: Signal<In, Clock>,
    pub reset: Signal<In, Bit>,
    pub push: Signal<In, Bit>,
    pub entry_in: Signal<In, Bits<ENTRY_BITS>>,
    pub go: Signal<In, Bit>,
    pub abort: Signal<In, Bit>,
    pub more: Signal<In, Bit>,
    pub step: Signal<Out, Bit>,
    pub dir: Signal<Out, Bit>,
    pub position: Signal<Out, Bits<32>>,
    pub underrun: Signal<Out, Bit>,
    pub active: Signal<Out, Bit>,
    /// See [`StepGen::moving`].
    pub moving: Signal<Out, Bit>,
    /// Entries still coming (`more`) or waiting in the FIFO (a move not yet released),
    /// moving, or STEP still high: the axis's BUSY.
    pub busy: Signal<Out, Bit>,
    pub done_count: Signal<Out, Bits<8>>,
    pub under_count: Signal<Out, Bits<8>>,
    pub full: Signal<Out, Bit>,
    pub level: Signal<Out, Bits<8>>,
    fifo: super::ram_fifo::PeriodFifo<32>,
    gen: StepGen,
    depth: Constant<Bits<8>>,
    depth_less: Constant<Bits<8>>,
    /// `full`, registered: set at the edge after which the FIFO holds DEPTH entries or
    /// more, from the level and this cycle's push and pop, so it always equals
    /// `level >= DEPTH` and the scheduler reads a flip-flop, not a compare.
    full_q: DFF<Bit>,
}

impl<const DEPTH: usize> Default for StepAxis<DEPTH> {
    fn default() -> Self {
        assert!((2..=30).contains(&DEPTH), "StepAxis<{DEPTH}>: depth outside 2..=30");
        StepAxis {
            clock: Default::default(),
            reset: Default::default(),
            push: Default::default(),
            entry_in: Default::default(),
            go: Default::default(),
            abort: Default::default(),
            more: Default::default(),
            step: Default::default(),
            dir: Default::default(),
            position: Default::default(),
            underrun: Default::default(),
            active: Default::default(),
            moving: Default::default(),
            busy: Default::default(),
            done_count: Default::default(),
            under_count: Default::default(),
            full: Default::default(),
            level: Default::default(),
            fifo: Default::default(),
            gen: Default::default(),
            depth: Constant::new((DEPTH as u64).into()),
            depth_less: Constant::new(((DEPTH - 1) as u64).into()),
            full_q: Default::default(),
        }
    }
}

impl<const DEPTH: usize> Logic for StepAxis<DEPTH> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, full_q);
        self.fifo.clock.next = self.clock.val();
        self.gen.clock.next = self.clock.val();
        self.fifo.reset.next = self.reset.val() | self.abort.val();
        self.gen.abort.next = self.abort.val();
        self.gen.reset.next = self.reset.val();
        self.fifo.push.next = self.push.val();
        self.fifo.entry_in.next = self.entry_in.val();
        self.fifo.pop.next = self.gen.pop.val();
        self.gen.head.next = self.fifo.head.val();
        self.gen.head_valid.next = !self.fifo.empty.val();
        self.gen.go.next = self.go.val();
        self.gen.more.next = self.more.val();
        self.step.next = self.gen.step.val();
        self.busy.next = self.more.val() | !self.fifo.empty.val() | self.gen.active.val() | self.gen.step.val();
        self.dir.next = self.gen.dir.val();
        self.position.next = self.gen.position.val();
        self.underrun.next = self.gen.underrun.val();
        self.active.next = self.gen.active.val();
        self.moving.next = self.gen.moving.val();
        self.done_count.next = self.gen.done_count.val();
        self.under_count.next = self.gen.under_count.val();
        // The level after this edge is at least DEPTH: above DEPTH already (one pop
        // leaves DEPTH), at DEPTH unless a pop without a push, or at DEPTH − 1 with a
        // push and no pop. At these levels (DEPTH ≤ 30 of 32) neither a push nor a pop
        // is ignored.
        self.full_q.d.next = (self.fifo.level.val() > self.depth.val())
            | ((self.fifo.level.val() == self.depth.val()) & (self.push.val() | !self.gen.pop.val()))
            | ((self.fifo.level.val() == self.depth_less.val()) & self.push.val() & !self.gen.pop.val());
        if self.reset.val() | self.abort.val() {
            self.full_q.d.next = false;
        }
        self.full.next = self.full_q.q.val();
        self.level.next = self.fifo.level.val();
    }
}
