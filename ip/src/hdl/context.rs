//! Per-axis context of the scheduler: the state of the axis's current segment.
//!
//! Held in registers, one set per axis. The scheduler reads the set of the axis it
//! serves through a multiplexer and writes it back whole (`we`), from its working
//! copy. A second, *next* slot holds the following segment, set up ahead of time
//! (`nwe` writes it from the same inputs; `new_dwell` marks a dwell); `promote` moves
//! it into the current slot with i = 0, E = 0 and the uniform counters reset, or, for a
//! dwell, only clears it (the scheduler pushes the dwell's FIFO entry). `err` is
//! written separately (`err_we`). `reset` empties both slots and clears the error.
//!
//! | field | bits | meaning |
//! |---|---|---|
//! | kind | 2 | 0 idle, 1 uniform, 2 accelerate, 3 decelerate |
//! | rev | 1 | direction of the segment's steps |
//! | n, i | 32 each | steps in the segment, steps computed so far |
//! | t | 32 | T, ticks |
//! | e | 32 | edge tick of the last computed step (E_i), from the segment start |
//! | p | 64 | P' |
//! | b, a | 128 each | B' and the accumulator A |
//! | uq, ur, uqs, urs | 32 each | uniform path: quotient, remainder and their steps |

use rust_hdl::prelude::*;

#[derive(LogicBlock, Default)]
pub struct AxisContext {
    pub clock: Signal<In, Clock>,
    pub reset: Signal<In, Bit>,
    pub we: Signal<In, Bit>,
    pub err_we: Signal<In, Bit>,
    pub nwe: Signal<In, Bit>,
    pub promote: Signal<In, Bit>,
    pub new_dwell: Signal<In, Bit>,
    pub new_kind: Signal<In, Bits<2>>,
    pub new_rev: Signal<In, Bit>,
    pub new_n: Signal<In, Bits<32>>,
    pub new_i: Signal<In, Bits<32>>,
    pub new_t: Signal<In, Bits<32>>,
    pub new_e: Signal<In, Bits<32>>,
    pub new_p: Signal<In, Bits<64>>,
    pub new_b: Signal<In, Bits<128>>,
    pub new_a: Signal<In, Bits<128>>,
    pub new_uq: Signal<In, Bits<32>>,
    pub new_ur: Signal<In, Bits<32>>,
    pub new_uqs: Signal<In, Bits<32>>,
    pub new_urs: Signal<In, Bits<32>>,
    pub new_err: Signal<In, Bits<8>>,
    pub kind: Signal<Out, Bits<2>>,
    pub rev: Signal<Out, Bit>,
    pub n: Signal<Out, Bits<32>>,
    pub i: Signal<Out, Bits<32>>,
    pub t: Signal<Out, Bits<32>>,
    pub e: Signal<Out, Bits<32>>,
    pub p: Signal<Out, Bits<64>>,
    pub b: Signal<Out, Bits<128>>,
    pub a: Signal<Out, Bits<128>>,
    pub uq: Signal<Out, Bits<32>>,
    pub ur: Signal<Out, Bits<32>>,
    pub uqs: Signal<Out, Bits<32>>,
    pub urs: Signal<Out, Bits<32>>,
    pub err: Signal<Out, Bits<8>>,
    /// The next slot holds a segment (a set-up segment or a dwell).
    pub next_valid: Signal<Out, Bit>,
    pub next_dwell: Signal<Out, Bit>,
    pub next_t: Signal<Out, Bits<32>>,
    r_kind: DFF<Bits<2>>,
    r_rev: DFF<Bit>,
    r_n: DFF<Bits<32>>,
    r_i: DFF<Bits<32>>,
    r_t: DFF<Bits<32>>,
    r_e: DFF<Bits<32>>,
    r_p: DFF<Bits<64>>,
    r_b: DFF<Bits<128>>,
    r_a: DFF<Bits<128>>,
    r_uq: DFF<Bits<32>>,
    r_ur: DFF<Bits<32>>,
    r_uqs: DFF<Bits<32>>,
    r_urs: DFF<Bits<32>>,
    r_err: DFF<Bits<8>>,
    x_kind: DFF<Bits<2>>,
    x_dwell: DFF<Bit>,
    x_rev: DFF<Bit>,
    x_n: DFF<Bits<32>>,
    x_t: DFF<Bits<32>>,
    x_p: DFF<Bits<64>>,
    x_b: DFF<Bits<128>>,
    x_a: DFF<Bits<128>>,
    x_uqs: DFF<Bits<32>>,
    x_urs: DFF<Bits<32>>,
}

impl Logic for AxisContext {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clock, r_kind, r_rev, r_n, r_i, r_t, r_e, r_p, r_b, r_a, r_uq, r_ur, r_uqs, r_urs, r_err, x_kind,
            x_dwell, x_rev, x_n, x_t, x_p, x_b, x_a, x_uqs, x_urs
        );
        self.kind.next = self.r_kind.q.val();
        self.rev.next = self.r_rev.q.val();
        self.n.next = self.r_n.q.val();
        self.i.next = self.r_i.q.val();
        self.t.next = self.r_t.q.val();
        self.e.next = self.r_e.q.val();
        self.p.next = self.r_p.q.val();
        self.b.next = self.r_b.q.val();
        self.a.next = self.r_a.q.val();
        self.uq.next = self.r_uq.q.val();
        self.ur.next = self.r_ur.q.val();
        self.uqs.next = self.r_uqs.q.val();
        self.urs.next = self.r_urs.q.val();
        self.err.next = self.r_err.q.val();
        self.next_valid.next = (self.x_kind.q.val() != 0) | self.x_dwell.q.val();
        self.next_dwell.next = self.x_dwell.q.val();
        self.next_t.next = self.x_t.q.val();
        if self.we.val() {
            self.r_kind.d.next = self.new_kind.val();
            self.r_rev.d.next = self.new_rev.val();
            self.r_n.d.next = self.new_n.val();
            self.r_i.d.next = self.new_i.val();
            self.r_t.d.next = self.new_t.val();
            self.r_e.d.next = self.new_e.val();
            self.r_p.d.next = self.new_p.val();
            self.r_b.d.next = self.new_b.val();
            self.r_a.d.next = self.new_a.val();
            self.r_uq.d.next = self.new_uq.val();
            self.r_ur.d.next = self.new_ur.val();
            self.r_uqs.d.next = self.new_uqs.val();
            self.r_urs.d.next = self.new_urs.val();
        }
        if self.err_we.val() {
            self.r_err.d.next = self.new_err.val();
        }
        if self.nwe.val() {
            self.x_kind.d.next = self.new_kind.val();
            self.x_dwell.d.next = self.new_dwell.val();
            self.x_rev.d.next = self.new_rev.val();
            self.x_n.d.next = self.new_n.val();
            self.x_t.d.next = self.new_t.val();
            self.x_p.d.next = self.new_p.val();
            self.x_b.d.next = self.new_b.val();
            self.x_a.d.next = self.new_a.val();
            self.x_uqs.d.next = self.new_uqs.val();
            self.x_urs.d.next = self.new_urs.val();
        }
        if self.promote.val() {
            if !self.x_dwell.q.val() {
                self.r_kind.d.next = self.x_kind.q.val();
                self.r_rev.d.next = self.x_rev.q.val();
                self.r_n.d.next = self.x_n.q.val();
                self.r_i.d.next = 0.into();
                self.r_t.d.next = self.x_t.q.val();
                self.r_e.d.next = 0.into();
                self.r_p.d.next = self.x_p.q.val();
                self.r_b.d.next = self.x_b.q.val();
                self.r_a.d.next = self.x_a.q.val();
                self.r_uq.d.next = 0.into();
                self.r_ur.d.next = self.x_n.q.val();
                self.r_uqs.d.next = self.x_uqs.q.val();
                self.r_urs.d.next = self.x_urs.q.val();
            }
            self.x_kind.d.next = 0.into();
            self.x_dwell.d.next = false;
        }
        if self.reset.val() {
            self.r_kind.d.next = 0.into();
            self.r_err.d.next = 0.into();
            self.x_kind.d.next = 0.into();
            self.x_dwell.d.next = false;
        }
    }
}
