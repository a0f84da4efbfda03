//! The controlled stop's per-axis state, beside the scheduler ([`super::core::TdmCore`]
//! forms the ramp on the shared unit; docs/architecture.md, "Controlled stop").
//!
//! * **Requests** (`pend`, bit i): set by `request` bit i (a one-cycle pulse or a
//!   level), kept until the scheduler takes axis i's request (`clear` with
//!   `clear_axis`); a request in the same cycle as its clear survives. `reset` empties
//!   them.
//! * **Last period** per axis: every period entry the scheduler pushes (`last_we`, with
//!   `last_axis`, `last_delta` Δ, `last_step` and `last_rev`) is registered, then written
//!   to a K-word LUT RAM as (Δ, direction), Δ taken as 0 (at rest) for a dwell's entry or
//!   Δ ≥ [`crate::model::stop::STOP_REST_PERIOD`] (the register keeps the subtraction that
//!   forms Δ and this comparison in two cycles: it was the K = 2 core's critical path).
//!   The scheduler reads axis `raxis`'s word combinationally: `d1` = Δ + 1, `rest` (Δ = 0)
//!   and `rev`. A word is read only for an axis that is running, whose move has pushed at
//!   least one entry. The scheduler reads an axis no sooner than the cycle after its
//!   write, when the word is still in the register: with K ≥ 2 the axis read then is
//!   another one (round robin), and with K = 1 the read takes the registered word
//!   (a bypass that only K = 1 builds), so a read sees every earlier write.
//!
//! * **Ramping** (`stopping`, bit i): a stop ramp of axis i is in its next slot
//!   (`set_next`, at the ramp's commit, axis `clear_axis`) or is its current segment
//!   (moved there by `promote` of axis `clear_axis`; the next promote of the axis ends
//!   it). Both bits clear while the axis is not `active`, and on `reset`. The scheduler
//!   does not cut a ramp: a request on a stopping axis drops what is queued behind the
//!   ramp instead.
//!
//! Ports: the above; latency 1 from `request`/`clear` to `pend`; a write is seen by
//! every read from the next cycle on.

use super::lut_ram::LutRam;
use rust_hdl::prelude::*;

/// Bits of a stored last period (Δ < 2^24 − 1) and of Δ + 1.
pub const LAST_BITS: usize = 24;
const _: () = assert!(LAST_BITS + 1 == 25);

#[derive(LogicBlock)]
pub struct StopRamp<const K: usize> {
    pub clock: Signal<In, Clock>,
    pub reset: Signal<In, Bit>,
    pub request: Signal<In, Bits<K>>,
    pub clear: Signal<In, Bit>,
    pub clear_axis: Signal<In, Bits<8>>,
    pub pend: Signal<Out, Bits<K>>,
    pub set_next: Signal<In, Bit>,
    pub promote: Signal<In, Bit>,
    pub active: Signal<In, Bits<K>>,
    pub stopping: Signal<Out, Bits<K>>,
    r_next: DFF<Bits<K>>,
    r_cur: DFF<Bits<K>>,
    pub last_we: Signal<In, Bit>,
    pub last_axis: Signal<In, Bits<4>>,
    pub last_delta: Signal<In, Bits<32>>,
    pub last_step: Signal<In, Bit>,
    pub last_rev: Signal<In, Bit>,
    pub raxis: Signal<In, Bits<4>>,
    pub d1: Signal<Out, Bits<LAST_BITS>>,
    pub rest: Signal<Out, Bit>,
    pub rev: Signal<Out, Bit>,
    r_pend: DFF<Bits<K>>,
    ram: LutRam<25, 4>,
    clr_bit: Signal<Local, Bits<K>>,
    m_bit: Signal<Local, Bits<K>>,
    c_one: Constant<Bits<K>>,
    c_rest: Constant<Bits<32>>,
    w_delta: Signal<Local, Bits<LAST_BITS>>,
    r_delta: Signal<Local, Bits<LAST_BITS>>,
    r_word: Signal<Local, Bits<25>>,
    p_we: DFF<Bit>,
    p_axis: DFF<Bits<4>>,
    p_delta: DFF<Bits<32>>,
    p_step: DFF<Bit>,
    p_rev: DFF<Bit>,
    c_bypass: Constant<Bit>,
}

impl<const K: usize> Default for StopRamp<K> {
    fn default() -> Self {
        assert!((1..=16).contains(&K), "StopRamp: K = {K} outside 1..=16");
        StopRamp {
            clock: Default::default(),
            reset: Default::default(),
            request: Default::default(),
            clear: Default::default(),
            clear_axis: Default::default(),
            pend: Default::default(),
            set_next: Default::default(),
            promote: Default::default(),
            active: Default::default(),
            stopping: Default::default(),
            r_next: Default::default(),
            r_cur: Default::default(),
            last_we: Default::default(),
            last_axis: Default::default(),
            last_delta: Default::default(),
            last_step: Default::default(),
            last_rev: Default::default(),
            raxis: Default::default(),
            d1: Default::default(),
            rest: Default::default(),
            rev: Default::default(),
            r_pend: Default::default(),
            ram: Default::default(),
            clr_bit: Default::default(),
            m_bit: Default::default(),
            c_one: Constant::new(1.into()),
            c_rest: Constant::new((crate::model::stop::STOP_REST_PERIOD as u64).into()),
            w_delta: Default::default(),
            r_delta: Default::default(),
            r_word: Default::default(),
            p_we: Default::default(),
            p_axis: Default::default(),
            p_delta: Default::default(),
            p_step: Default::default(),
            p_rev: Default::default(),
            c_bypass: Constant::new(K == 1),
        }
    }
}

impl<const K: usize> Logic for StopRamp<K> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, r_pend, r_next, r_cur, p_we, p_axis, p_delta, p_step, p_rev);
        self.m_bit.next = self.c_one.val() << self.clear_axis.val();
        self.clr_bit.next = 0.into();
        if self.clear.val() {
            self.clr_bit.next = self.m_bit.val();
        }
        self.r_pend.d.next = (self.r_pend.q.val() & !self.clr_bit.val()) | self.request.val();
        self.r_next.d.next = self.r_next.q.val() & self.active.val();
        self.r_cur.d.next = self.r_cur.q.val() & self.active.val();
        if self.promote.val() {
            self.r_next.d.next = self.r_next.q.val() & self.active.val() & !self.m_bit.val();
            self.r_cur.d.next = (self.r_cur.q.val() & self.active.val() & !self.m_bit.val())
                | (self.r_next.q.val() & self.m_bit.val());
        }
        if self.set_next.val() {
            self.r_next.d.next = (self.r_next.q.val() & self.active.val()) | self.m_bit.val();
        }
        if self.reset.val() {
            self.r_pend.d.next = 0.into();
            self.r_next.d.next = 0.into();
            self.r_cur.d.next = 0.into();
        }
        self.pend.next = self.r_pend.q.val();
        self.stopping.next = self.r_next.q.val() | self.r_cur.q.val();
        self.ram.clock.next = self.clock.val();
        self.p_we.d.next = self.last_we.val();
        self.p_axis.d.next = self.last_axis.val();
        self.p_delta.d.next = self.last_delta.val();
        self.p_step.d.next = self.last_step.val();
        self.p_rev.d.next = self.last_rev.val();
        self.ram.we.next = self.p_we.q.val();
        self.ram.waddr.next = self.p_axis.q.val();
        self.w_delta.next = 0.into();
        if self.p_step.q.val() & (self.p_delta.q.val() < self.c_rest.val()) {
            self.w_delta.next = self.p_delta.q.val().get_bits::<LAST_BITS>(0);
        }
        self.ram.wdata.next = bit_cast::<25, LAST_BITS>(self.w_delta.val())
            | (bit_cast::<25, 1>(self.p_rev.q.val().into()) << 24u64);
        self.ram.raddr.next = self.raxis.val();
        self.r_word.next = self.ram.rdata.val();
        if self.c_bypass.val() & self.p_we.q.val() {
            self.r_word.next = self.ram.wdata.val();
        }
        self.r_delta.next = self.r_word.val().get_bits::<LAST_BITS>(0);
        self.d1.next = self.r_delta.val() + 1;
        self.rest.next = self.r_delta.val() == 0;
        self.rev.next = self.r_word.val().get_bit(24);
    }
}
