//! Pulse stage: between the scheduler and the per-axis period FIFOs, one for the whole
//! core. It writes into every period entry the STEP high time of a pulse that rises at
//! the entry's start, from the output timing (docs/architecture.md, "Step timing"):
//!
//! `h(Δ) = max(Hm, min(⌊Δ/2⌋, Δ − Lm, 65,535))` for an entry of Δ ticks, with
//! `Hm = max(STEP_HIGH, DIR_HOLD)` and `Lm = max(STEP_LOW, DIR_SETUP)` (`high_min`,
//! `low_min`, quasi-static; a `high_min` of 0 acts as 1: the register file changes them only while the core is held
//! in reset). It is [`crate::model::PulseTiming::high_ticks`], bit for bit.
//!
//! Computing it once here, not in each step generator, keeps the per-axis logic to a
//! 16-bit down-counter: one more axis costs no arithmetic.
//!
//! Pipeline (latency 2 cycles, one entry per cycle):
//! * stage 0 registers the scheduler's entry and its axis (`push_in`, `axis_in`,
//!   `entry_in`, whose bits 51..35 are ignored);
//! * stage 1 registers ⌊Δ/2⌋ and Δ − Lm (clamped to 0), both capped for Δ ≥ 2^17,
//!   and whether Δ = 1 (the entry's bit 51, which the step generator reads at a load);
//! * the output (`push_out`, `axis_out`, `entry_out`) takes the minimum and the maximum
//!   with Hm from three parallel compares of stage 1's registers.
//!
//! So the entry offered at edge c is written into its FIFO at edge c + 2. `p0_*` and
//! `p1_*` say which axes have an entry in flight, so the core counts them as coming
//! (`more`, BUSY) and keeps FIFO room for them. `flush` (synchronous, with `reset` or an
//! abort) drops what is in flight.

use super::ram_fifo::ENTRY_BITS;
use rust_hdl::prelude::*;

#[derive(LogicBlock, Default)]
pub struct PulseStage {
    pub clock: Signal<In, Clock>,
    pub flush: Signal<In, Bit>,
    pub high_min: Signal<In, Bits<16>>,
    pub low_min: Signal<In, Bits<16>>,
    pub push_in: Signal<In, Bit>,
    pub axis_in: Signal<In, Bits<8>>,
    pub entry_in: Signal<In, Bits<ENTRY_BITS>>,
    pub push_out: Signal<Out, Bit>,
    pub axis_out: Signal<Out, Bits<8>>,
    pub entry_out: Signal<Out, Bits<ENTRY_BITS>>,
    pub p0_valid: Signal<Out, Bit>,
    pub p0_axis: Signal<Out, Bits<8>>,
    pub p1_valid: Signal<Out, Bit>,
    pub p1_axis: Signal<Out, Bits<8>>,
    v0: DFF<Bit>,
    a0: DFF<Bits<8>>,
    e0: DFF<Bits<ENTRY_BITS>>,
    v1: DFF<Bit>,
    a1: DFF<Bits<8>>,
    e1: DFF<Bits<ENTRY_BITS>>,
    /// Stage 1: Δ = 1.
    one1: DFF<Bit>,
    half1: DFF<Bits<16>>,
    lo1: DFF<Bits<17>>,
    d17: Signal<Local, Bits<17>>,
    big: Signal<Local, Bit>,
    low17: Signal<Local, Bits<17>>,
    lo_lt_half: Signal<Local, Bit>,
    hm_gt_half: Signal<Local, Bit>,
    hm_gt_lo: Signal<Local, Bit>,
    high: Signal<Local, Bits<16>>,
    hm: Signal<Local, Bits<16>>,
}

impl Logic for PulseStage {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, v0, a0, e0, v1, a1, e1, one1, half1, lo1);
        // Stage 0.
        self.v0.d.next = self.push_in.val();
        self.a0.d.next = self.axis_in.val();
        self.e0.d.next = self.entry_in.val();
        // Stage 1: ⌊Δ/2⌋ and Δ − Lm on 17 bits; from 2^17 on both exceed the cap.
        self.d17.next = self.e0.q.val().get_bits::<17>(0);
        self.big.next = self.e0.q.val().get_bits::<15>(17) != 0;
        self.low17.next = bit_cast::<17, 16>(self.low_min.val());
        self.v1.d.next = self.v0.q.val();
        self.a1.d.next = self.a0.q.val();
        self.e1.d.next = self.e0.q.val();
        self.one1.d.next = self.e0.q.val().get_bits::<32>(0) == 1;
        self.half1.d.next = self.d17.val().get_bits::<16>(1);
        if self.d17.val() < self.low17.val() {
            self.lo1.d.next = 0.into();
        } else {
            self.lo1.d.next = self.d17.val() - self.low17.val();
        }
        if self.big.val() {
            self.half1.d.next = 0xFFFF.into();
            self.lo1.d.next = 0x1FFFF.into();
        }
        // Output: max(Hm, min(half, lo)), three compares side by side. Hm = 0 (inputs
        // left at 0, as in the core's own tests) acts as 1: no pulse is ever 0 ticks.
        self.hm.next = self.high_min.val();
        if self.high_min.val() == 0 {
            self.hm.next = 1.into();
        }
        self.lo_lt_half.next = self.lo1.q.val() < bit_cast::<17, 16>(self.half1.q.val());
        self.hm_gt_half.next = self.hm.val() > self.half1.q.val();
        self.hm_gt_lo.next = bit_cast::<17, 16>(self.hm.val()) > self.lo1.q.val();
        if self.lo_lt_half.val() {
            if self.hm_gt_lo.val() {
                self.high.next = self.hm.val();
            } else {
                self.high.next = self.lo1.q.val().get_bits::<16>(0);
            }
        } else if self.hm_gt_half.val() {
            self.high.next = self.hm.val();
        } else {
            self.high.next = self.half1.q.val();
        }
        self.push_out.next = self.v1.q.val();
        self.axis_out.next = self.a1.q.val();
        self.entry_out.next = bit_cast::<ENTRY_BITS, 35>(self.e1.q.val().get_bits::<35>(0))
            | (bit_cast::<ENTRY_BITS, 16>(self.high.val()) << 35)
            | (bit_cast::<ENTRY_BITS, 1>(self.one1.q.val().into()) << 51);
        self.p0_valid.next = self.v0.q.val();
        self.p0_axis.next = self.a0.q.val();
        self.p1_valid.next = self.v1.q.val();
        self.p1_axis.next = self.a1.q.val();
        if self.flush.val() {
            self.v0.d.next = false;
            self.v1.d.next = false;
        }
    }
}
