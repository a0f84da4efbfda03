//! The S-curve option's lane beside the scheduler: the polynomial unit
//! ([`PolyUnit`]), the queued segments' polynomial fields, and which axes run a
//! polynomial segment. The scheduler ([`super::core::TdmCore`] with S = 1) sends it
//! requests and takes its periods; a core without the option has no lane (no Verilog,
//! no cost). Checked three ways inside the core (tests/hdl_core.rs: mixed segments
//! against the model, rust-hdl and Verilator), where its ports are driven as the
//! scheduler drives them.
//!
//! **Queued fields.** The core keeps them in a RAM beside the segment queue, at the
//! queue's own addresses, and gives the head's as `head_extra`: the polynomial flag
//! (bit 96), A' (95..32) and v1 (31..0). (The RAM is the core's, not the lane's: its
//! read register then reaches the scheduler straight, with no process of the lane in
//! between, which Verilator would see as a loop through the lane's inputs.)
//!
//! **Requests** (one at a time, while `busy` is low; latency: [`PolyUnit`]'s):
//! * `setup` sets up the queue head (`head`: v0, T, signed steps, and `head_extra`,
//!   as they were in the cycle before, the steps two cycles before: the lane registers
//!   them; the head must hold for those cycles) into axis `axis`'s next slot (`slot` is the axis's current slot; the unit
//!   takes the other one);
//! * `step` asks for the next period of axis `axis`'s current slot (`slot`).
//!
//! `head_go`: the head as it was in the cycle before is a polynomial segment with
//! steps (one with steps 0 is a dwell, which the scheduler sets up as a trapezoid's).
//! The scheduler branches on it in S_ISSUE_VT, the cycle after S_CHECK, so no state
//! decision waits for the queue RAMs' read ports (on ECP5 that path closed the K = 16
//! core's `clk` at 62.7 MHz).
//!
//! `done` pulses when the request is served; for a step `period` (ticks) and `last`
//! (the segment's last step) hold until the next request, and `was_setup` says which
//! request it was. Every output is a register (the scheduler's process reads them:
//! an output that followed an input combinationally would close a loop between the
//! two blocks' processes).
//!
//! **Per-axis flags** (latency 1): `cur_poly` bit i (axis i's current segment is a
//! polynomial one) and `next_poly` (its next slot's). `nwe` (the scheduler's commit
//! into axis `axis`'s next slot) sets its `next_poly` to `from_queue` and the head's flag (a
//! stop ramp, formed by the scheduler, is a trapezoid); `promote` moves it into
//! `cur_poly`; `cut` (a controlled stop drops the next slot) clears `next_poly`;
//! `axis_reset` clears both, `abort` and `reset` every axis's. `pk_poly`: axis
//! `next_m`'s `cur_poly` registered for the next PICK (K ≥ 2), or axis 0's directly at
//! K = 1, as [`super::axis_view::AxisView`] gives PICK its flags.

use super::poly_unit::PolyUnit;
use super::seg_queue::SEGMENT_BITS;
use crate::model::poly::PolySegment;
use rust_hdl::prelude::*;

/// The polynomial fields of a queued segment: v1 (31..0), A' (95..32), the flag (96).
pub const POLY_EXTRA_BITS: usize = 97;

/// A polynomial segment's fields beside v0, T and the steps, as the push path carries
/// them (`cmd_extra` less the flag): v1 in 31..0, A' (two's complement) in 95..32.
pub fn poly_fields(p: &PolySegment) -> u128 {
    p.v1_rate as u128 | (p.a_q32 as u64 as u128) << 32
}

/// The queued word of a polynomial segment ([`POLY_EXTRA_BITS`]): its fields and the
/// flag.
pub fn poly_extra(p: &PolySegment) -> u128 {
    poly_fields(p) | 1 << 96
}

#[derive(LogicBlock)]
pub struct PolyLane<const K: usize> {
    pub clock: Signal<In, Clock>,
    pub reset: Signal<In, Bit>,
    pub abort: Signal<In, Bit>,
    pub head: Signal<In, Bits<SEGMENT_BITS>>,
    pub head_extra: Signal<In, Bits<POLY_EXTRA_BITS>>,
    pub setup: Signal<In, Bit>,
    pub step: Signal<In, Bit>,
    pub axis: Signal<In, Bits<8>>,
    pub slot: Signal<In, Bit>,
    pub next_m: Signal<In, Bits<8>>,
    pub nwe: Signal<In, Bit>,
    pub from_queue: Signal<In, Bit>,
    pub promote: Signal<In, Bit>,
    pub cut: Signal<In, Bit>,
    pub axis_reset: Signal<In, Bit>,
    pub pk_poly: Signal<Out, Bit>,
    pub head_go: Signal<Out, Bit>,
    pub busy: Signal<Out, Bit>,
    pub done: Signal<Out, Bit>,
    pub was_setup: Signal<Out, Bit>,
    pub period: Signal<Out, Bits<32>>,
    pub last: Signal<Out, Bit>,
    unit: PolyUnit,
    cur_poly: DFF<Bits<K>>,
    next_poly: DFF<Bits<K>>,
    req_setup: DFF<Bit>,
    pf_poly: DFF<Bit>,
    /// The head's fields, registered every cycle: the unit's setup inputs start at
    /// flip-flops, not at the queue RAM's unregistered read port (on ECP5 its 5.8 ns
    /// clock-to-out then an adder chain into the setup made the K = 16 core's
    /// critical path). The scheduler asks for a setup only in Y_SETUP, two cycles
    /// after S_CHECK read the same head (S_ISSUE_VT lies between), which every field
    /// needs: |steps| takes two stages (`r_s`, the signed count, then `r_n`), as the
    /// negation's carry chain after the RAM's read port was the K = 8 core's path.
    r_v0: DFF<Bits<32>>,
    r_s: DFF<Bits<32>>,
    r_t: DFF<Bits<32>>,
    r_n: DFF<Bits<32>>,
    r_v1: DFF<Bits<32>>,
    r_a: DFF<Bits<64>>,
    r_go: DFF<Bit>,
    /// Axis `axis`'s bit, and `next_m`'s flag shifted down to bit 0.
    m_bit: Signal<Local, Bits<K>>,
    nx_sh: Signal<Local, Bits<K>>,
    nx_poly: Signal<Local, Bit>,
    u_slot: Signal<Local, Bits<1>>,
    h_steps: Signal<Local, Bits<32>>,
    h_neg: Signal<Local, Bits<32>>,
    c_one_k: Constant<Bits<K>>,
    c_single: Constant<Bit>,
}

impl<const K: usize> Default for PolyLane<K> {
    fn default() -> Self {
        PolyLane {
            clock: Default::default(),
            reset: Default::default(),
            abort: Default::default(),
            head: Default::default(),
            head_extra: Default::default(),
            setup: Default::default(),
            step: Default::default(),
            axis: Default::default(),
            slot: Default::default(),
            next_m: Default::default(),
            nwe: Default::default(),
            from_queue: Default::default(),
            promote: Default::default(),
            cut: Default::default(),
            axis_reset: Default::default(),
            pk_poly: Default::default(),
            head_go: Default::default(),
            busy: Default::default(),
            done: Default::default(),
            was_setup: Default::default(),
            period: Default::default(),
            last: Default::default(),
            unit: PolyUnit::new(K),
            cur_poly: Default::default(),
            next_poly: Default::default(),
            req_setup: Default::default(),
            pf_poly: Default::default(),
            r_v0: Default::default(),
            r_s: Default::default(),
            r_t: Default::default(),
            r_n: Default::default(),
            r_v1: Default::default(),
            r_a: Default::default(),
            r_go: Default::default(),
            m_bit: Default::default(),
            nx_sh: Default::default(),
            nx_poly: Default::default(),
            u_slot: Default::default(),
            h_steps: Default::default(),
            h_neg: Default::default(),
            c_one_k: Constant::new(1.into()),
            c_single: Constant::new(K == 1),
        }
    }
}

impl<const K: usize> Logic for PolyLane<K> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, cur_poly, next_poly, req_setup, pf_poly, r_v0, r_s, r_t, r_n, r_v1, r_a, r_go);
        // ---- the unit ---------------------------------------------------------
        // n = |steps| (a polynomial segment has n ≥ 1).
        self.h_steps.next = self.head.val().get_bits::<32>(64);
        self.h_neg.next = (!self.r_s.q.val()) + 1;
        self.unit.clock.next = self.clock.val();
        self.unit.setup.next = self.setup.val();
        self.unit.step.next = self.step.val();
        self.unit.axis.next = self.axis.val().get_bits::<4>(0);
        // A setup goes into the next slot, a step reads the current one.
        if self.slot.val() ^ self.setup.val() {
            self.u_slot.next = 1.into();
        } else {
            self.u_slot.next = 0.into();
        }
        self.unit.slot.next = self.u_slot.val();
        self.r_v0.d.next = self.head.val().get_bits::<32>(0);
        self.r_t.d.next = self.head.val().get_bits::<32>(32);
        self.r_s.d.next = self.h_steps.val();
        if self.r_s.q.val().get_bit(31) {
            self.r_n.d.next = self.h_neg.val();
        } else {
            self.r_n.d.next = self.r_s.q.val();
        }
        self.r_v1.d.next = self.head_extra.val().get_bits::<32>(0);
        self.r_a.d.next = self.head_extra.val().get_bits::<64>(32);
        self.r_go.d.next = self.head_extra.val().get_bit(96) & (self.h_steps.val() != 0);
        self.head_go.next = self.r_go.q.val();
        self.unit.in_v0.next = self.r_v0.q.val();
        self.unit.in_t.next = self.r_t.q.val();
        self.unit.in_n.next = self.r_n.q.val();
        self.unit.in_v1.next = self.r_v1.q.val();
        self.unit.in_a.next = self.r_a.q.val();
        if self.setup.val() | self.step.val() {
            self.req_setup.d.next = self.setup.val();
        }
        self.busy.next = self.unit.busy.val();
        self.done.next = self.unit.done.val();
        self.period.next = self.unit.period.val();
        self.last.next = self.unit.last.val();
        self.was_setup.next = self.req_setup.q.val();

        // ---- per-axis flags ---------------------------------------------------
        self.m_bit.next = self.c_one_k.val() << self.axis.val();
        if self.nwe.val() {
            if self.from_queue.val() & self.head_extra.val().get_bit(96) {
                self.next_poly.d.next = self.next_poly.q.val() | self.m_bit.val();
            } else {
                self.next_poly.d.next = self.next_poly.q.val() & !self.m_bit.val();
            }
        }
        if self.promote.val() {
            if (self.next_poly.q.val() & self.m_bit.val()).any() {
                self.cur_poly.d.next = self.cur_poly.q.val() | self.m_bit.val();
            } else {
                self.cur_poly.d.next = self.cur_poly.q.val() & !self.m_bit.val();
            }
            self.next_poly.d.next = self.next_poly.q.val() & !self.m_bit.val();
        }
        if self.cut.val() {
            self.next_poly.d.next = self.next_poly.q.val() & !self.m_bit.val();
        }
        if self.axis_reset.val() {
            self.cur_poly.d.next = self.cur_poly.q.val() & !self.m_bit.val();
            self.next_poly.d.next = self.next_poly.q.val() & !self.m_bit.val();
        }
        if self.reset.val() | self.abort.val() {
            self.cur_poly.d.next = 0.into();
            self.next_poly.d.next = 0.into();
        }
        // PICK's flag: axis m + 1's, registered (K = 1: axis 0's register itself).
        self.nx_sh.next = self.cur_poly.q.val() >> self.next_m.val();
        self.nx_poly.next = (self.nx_sh.val() & self.c_one_k.val()).any();
        self.pf_poly.d.next = self.nx_poly.val() & !self.reset.val();
        if self.c_single.val() {
            self.pk_poly.next = self.cur_poly.q.val().any();
        } else {
            self.pk_poly.next = self.pf_poly.q.val();
        }
    }
}
