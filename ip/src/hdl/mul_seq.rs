//! Sequential multiplier: `product = a × b mod 2^100`, a 100-bit multiplicand by a
//! 32-bit multiplier, `R` multiplier bits per clock (shift and add, no DSP blocks).
//!
//! The setup's wide products have a multiplier of at most 32 bits: v0·T² (v0),
//! (v_end·T·2^32)·T (T) and n·B' (n), each < 2^100 (docs/model.md, "Widths"), so
//! 100 bits hold every product exactly and each bit is one 100-bit adder. Ports and
//! timing as [`super::divider::Divider`]: pulse `start` while idle; `product` and
//! `valid` follow [`mul_seq_latency`]`(R)` cycles later.

use super::iterate::Iterate;
use rust_hdl::prelude::*;

pub const MUL_A_BITS: usize = 100;
const _: () = assert!(MUL_A_BITS == crate::model::ACC_BITS as usize);
pub const MUL_B_BITS: usize = 32;

/// Cycles from the `start` edge to `valid` for `r` bits per cycle.
pub const fn mul_seq_latency(r: usize) -> usize {
    1 + MUL_B_BITS / r
}

/// One multiplier bit, combinational: add the shifted multiplicand if the bit is set.
#[derive(LogicBlock, Default)]
pub struct MulBit {
    pub acc_in: Signal<In, Bits<MUL_A_BITS>>,
    pub a_in: Signal<In, Bits<MUL_A_BITS>>,
    pub b_in: Signal<In, Bits<MUL_B_BITS>>,
    pub acc_out: Signal<Out, Bits<MUL_A_BITS>>,
    pub a_out: Signal<Out, Bits<MUL_A_BITS>>,
    pub b_out: Signal<Out, Bits<MUL_B_BITS>>,
}

impl Logic for MulBit {
    #[hdl_gen]
    fn update(&mut self) {
        if self.b_in.val().get_bit(0) {
            self.acc_out.next = self.acc_in.val() + self.a_in.val();
        } else {
            self.acc_out.next = self.acc_in.val();
        }
        self.a_out.next = self.a_in.val() << 1;
        self.b_out.next = self.b_in.val() >> 1;
    }
}

#[derive(LogicBlock)]
pub struct MulSeq<const R: usize> {
    pub clock: Signal<In, Clock>,
    pub start: Signal<In, Bit>,
    pub a: Signal<In, Bits<MUL_A_BITS>>,
    pub b: Signal<In, Bits<MUL_B_BITS>>,
    pub product: Signal<Out, Bits<MUL_A_BITS>>,
    pub valid: Signal<Out, Bit>,
    pub busy: Signal<Out, Bit>,
    bits: [MulBit; R],
    acc: DFF<Bits<MUL_A_BITS>>,
    sa: DFF<Bits<MUL_A_BITS>>,
    sb: DFF<Bits<MUL_B_BITS>>,
    ctl: Iterate,
}

impl<const R: usize> Default for MulSeq<R> {
    fn default() -> Self {
        assert!(R >= 1 && MUL_B_BITS % R == 0, "MulSeq<{R}>: R must divide {MUL_B_BITS}");
        MulSeq {
            clock: Default::default(),
            start: Default::default(),
            a: Default::default(),
            b: Default::default(),
            product: Default::default(),
            valid: Default::default(),
            busy: Default::default(),
            bits: std::array::from_fn(|_| Default::default()),
            acc: Default::default(),
            sa: Default::default(),
            sb: Default::default(),
            ctl: Iterate::new(MUL_B_BITS / R),
        }
    }
}

impl<const R: usize> Logic for MulSeq<R> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, acc, sa, sb);
        self.ctl.clock.next = self.clock.val();
        self.ctl.start.next = self.start.val();
        self.bits[0].acc_in.next = self.acc.q.val();
        self.bits[0].a_in.next = self.sa.q.val();
        self.bits[0].b_in.next = self.sb.q.val();
        for i in 1..R {
            self.bits[i].acc_in.next = self.bits[i - 1].acc_out.val();
            self.bits[i].a_in.next = self.bits[i - 1].a_out.val();
            self.bits[i].b_in.next = self.bits[i - 1].b_out.val();
        }
        self.product.next = self.acc.q.val();
        self.valid.next = self.ctl.valid.val();
        self.busy.next = self.ctl.busy.val();
        if self.ctl.step.val() {
            // The last bit's outputs win: later assignments override earlier ones.
            for i in 0..R {
                self.acc.d.next = self.bits[i].acc_out.val();
                self.sa.d.next = self.bits[i].a_out.val();
                self.sb.d.next = self.bits[i].b_out.val();
            }
        } else if self.ctl.load.val() {
            self.acc.d.next = 0.into();
            self.sa.d.next = self.a.val();
            self.sb.d.next = self.b.val();
        }
    }
}
