//! Per-axis step generator: turns period-FIFO entries into STEP and DIR.
//!
//! Timing (docs/architecture.md, "Step timing"):
//! * `go` (the release: one cycle, while idle and the FIFO is not empty) loads the first
//!   entry at that clock edge, tick L₀. An entry of `ticks` loaded at edge L ends at
//!   edge L + ticks, where the next entry loads. So step i of a move rises exactly
//!   at L₀ + E_i, E_i being the reference model's edge tick.
//! * STEP rises at the end of an entry whose `step` bit is set (a dwell has none),
//!   and the position moves by ±1 on that edge.
//! * STEP stays high for max(1, ⌊ticks/2⌋) of the entry that follows: the pulse is the
//!   first half of the next period, the paper's 50% duty. At the end of a move
//!   (FIFO empty, `more` low) it is the half of the period that just ended.
//! * DIR follows the direction of the current entry's step while STEP is low, and
//!   changes only as STEP falls: setup before a rising edge ⌈Δ/2⌉ ticks, hold after it
//!   ⌊Δ/2⌋ ticks, both ≥ 1 for Δ ≥ 2.
//! * Underrun: an entry ends, the FIFO is empty and `more` says steps are still to
//!   come. The generator waits with STEP held (the pulse stretches), sets the sticky
//!   `underrun`, and continues when the entry arrives. No step is lost; the next edge
//!   is late by the wait.
//! * `abort` (one cycle) is a hard stop: no further edge rises, the FIFO's entries are
//!   left for the owner to flush, and a pulse already high keeps its high time, so
//!   the position counts exactly the edges emitted.
//! * Counters (8 bits, wrapping): `done_count` counts entries flagged last that
//!   ended (segments done), `under_count` counts underruns begun.
//! * `reset` (synchronous) stops the axis and clears position, `underrun` and the
//!   counters.

use super::ram_fifo::ENTRY_BITS;
use rust_hdl::prelude::*;

#[derive(LogicBlock, Default)]
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
    pub done_count: Signal<Out, Bits<8>>,
    pub under_count: Signal<Out, Bits<8>>,
    running: DFF<Bit>,
    waiting: DFF<Bit>,
    count: DFF<Bits<32>>,
    cur_ticks: DFF<Bits<32>>,
    cur_step: DFF<Bit>,
    cur_rev: DFF<Bit>,
    high: DFF<Bits<32>>,
    step_q: DFF<Bit>,
    dir_q: DFF<Bit>,
    pos: DFF<Bits<32>>,
    under: DFF<Bit>,
    cur_last: DFF<Bit>,
    done_cnt: DFF<Bits<8>>,
    under_cnt: DFF<Bits<8>>,
    head_ticks: Signal<Local, Bits<32>>,
    head_half: Signal<Local, Bits<32>>,
    last_half: Signal<Local, Bits<32>>,
    ends: Signal<Local, Bit>,
}

impl Logic for StepGen {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clock, running, waiting, count, cur_ticks, cur_step, cur_rev, high, step_q, dir_q, pos, under, cur_last,
            done_cnt, under_cnt
        );
        self.head_ticks.next = self.head.val().get_bits::<32>(0);
        self.head_half.next = self.head_ticks.val() >> 1;
        if self.head_ticks.val() < 2 {
            self.head_half.next = 1.into();
        }
        self.last_half.next = self.cur_ticks.q.val() >> 1;
        if self.cur_ticks.q.val() < 2 {
            self.last_half.next = 1.into();
        }
        self.ends.next = self.running.q.val() & !self.waiting.q.val() & (self.count.q.val() == 1);
        self.step.next = self.step_q.q.val();
        self.dir.next = self.dir_q.q.val();
        self.position.next = self.pos.q.val();
        self.underrun.next = self.under.q.val();
        self.active.next = self.running.q.val();
        self.done_count.next = self.done_cnt.q.val();
        self.under_count.next = self.under_cnt.q.val();
        self.pop.next = false;

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
        if self.running.q.val() & !self.waiting.q.val() {
            self.count.d.next = self.count.q.val() - 1;
        }
        if self.ends.val() {
            if self.cur_last.q.val() {
                self.done_cnt.d.next = self.done_cnt.q.val() + 1;
            }
            if self.cur_step.q.val() {
                self.step_q.d.next = true;
                if self.cur_rev.q.val() {
                    self.pos.d.next = self.pos.q.val() - 1;
                } else {
                    self.pos.d.next = self.pos.q.val() + 1;
                }
            }
            if self.head_valid.val() {
                self.pop.next = true;
                self.count.d.next = self.head_ticks.val();
                self.cur_ticks.d.next = self.head_ticks.val();
                self.cur_step.d.next = self.head.val().get_bit(32);
                self.cur_rev.d.next = self.head.val().get_bit(33);
            self.cur_last.d.next = self.head.val().get_bit(34);
                if self.cur_step.q.val() {
                    self.high.d.next = self.head_half.val();
                }
            } else if self.more.val() {
                self.waiting.d.next = true;
                self.under.d.next = true;
                self.under_cnt.d.next = self.under_cnt.q.val() + 1;
                if self.cur_step.q.val() {
                    self.high.d.next = self.last_half.val();
                }
            } else {
                self.running.d.next = false;
                if self.cur_step.q.val() {
                    self.high.d.next = self.last_half.val();
                }
            }
        }
        // Underrun over: load the late entry; a stretched pulse restarts its half period.
        if self.running.q.val() & self.waiting.q.val() & self.head_valid.val() {
            self.pop.next = true;
            self.waiting.d.next = false;
            self.count.d.next = self.head_ticks.val();
            self.cur_ticks.d.next = self.head_ticks.val();
            self.cur_step.d.next = self.head.val().get_bit(32);
            self.cur_rev.d.next = self.head.val().get_bit(33);
            self.cur_last.d.next = self.head.val().get_bit(34);
            if self.step_q.q.val() {
                self.high.d.next = self.head_half.val();
            }
        }
        if !self.running.q.val() & self.go.val() & self.head_valid.val() {
            self.pop.next = true;
            self.running.d.next = true;
            self.waiting.d.next = false;
            self.count.d.next = self.head_ticks.val();
            self.cur_ticks.d.next = self.head_ticks.val();
            self.cur_step.d.next = self.head.val().get_bit(32);
            self.cur_rev.d.next = self.head.val().get_bit(33);
            self.cur_last.d.next = self.head.val().get_bit(34);
        }
        if self.abort.val() {
            self.running.d.next = false;
            self.waiting.d.next = false;
            self.count.d.next = 0.into();
        }
        if self.reset.val() {
            self.done_cnt.d.next = 0.into();
            self.under_cnt.d.next = 0.into();
            self.running.d.next = false;
            self.waiting.d.next = false;
            self.high.d.next = 0.into();
            self.step_q.d.next = false;
            self.dir_q.d.next = false;
            self.cur_rev.d.next = false;
            self.pos.d.next = 0.into();
            self.under.d.next = false;
            self.count.d.next = 0.into();
        }
    }
}

/// The per-axis back end: a period FIFO of `DEPTH` entries feeding a [`StepGen`].
#[derive(LogicBlock, Default)]
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
    pub done_count: Signal<Out, Bits<8>>,
    pub under_count: Signal<Out, Bits<8>>,
    pub full: Signal<Out, Bit>,
    pub level: Signal<Out, Bits<8>>,
    fifo: super::ram_fifo::PeriodFifo<DEPTH>,
    gen: StepGen,
}

impl<const DEPTH: usize> Logic for StepAxis<DEPTH> {
    #[hdl_gen]
    fn update(&mut self) {
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
        self.dir.next = self.gen.dir.val();
        self.position.next = self.gen.position.val();
        self.underrun.next = self.gen.underrun.val();
        self.active.next = self.gen.active.val();
        self.done_count.next = self.gen.done_count.val();
        self.under_count.next = self.gen.under_count.val();
        self.full.next = self.fifo.full.val();
        self.level.next = self.fifo.level.val();
    }
}
