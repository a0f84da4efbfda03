//! Sequential multiplier: `product = a × b mod 2^100`, a 100-bit multiplicand by a
//! 32-bit unsigned multiplier, `R` multiplier bits per clock as `R / 2` radix-4 Booth
//! digits (R even; shift and add, no DSP blocks).
//!
//! The setup's wide products have a multiplier of at most 32 bits: v0·T² (v0),
//! (v_end·T·2^32)·T (T) and n·B' (n), each < 2^100 (docs/model.md, "Widths"), so
//! 100 bits hold every product exactly. Booth recoding turns the 32-bit multiplier
//! into 17 digits in −2..=2, so each digit adds 0, ±a or ±2a: one 100-bit adder per
//! digit, with the select and the negation folded into the adder's input (a radix-4
//! digit without recoding would need 3a, or two chained adders). Arithmetic is mod
//! 2^100, so the negative partial products wrap and the sum is exact. Ports and
//! timing as [`super::divider::Divider`]: pulse `start` while idle; `product` and
//! `valid` follow [`mul_seq_latency`]`(R)` cycles later.

use super::iterate::Iterate;
use rust_hdl::prelude::*;

pub const MUL_A_BITS: usize = 100;
const _: () = assert!(MUL_A_BITS == crate::model::ACC_BITS as usize);
pub use crate::latency::{mul_seq_latency, mul_seq_steps, MUL_B_BITS, MUL_DIGITS};

/// One radix-4 Booth digit, combinational. The digit is read from the multiplier's
/// two low bits and the bit below them (`p_in`, 0 for the first digit): 000 and 111
/// add 0, 001 and 010 add a, 011 adds 2a, 100 subtracts 2a, 101 and 110 subtract a.
/// A subtraction adds the complement with a carry in of 1: `{acc, 1} + {pp, neg}`
/// over 101 bits puts `neg` into the carry chain, so one adder does it.
#[derive(LogicBlock, Default)]
pub struct BoothDigit {
    pub acc_in: Signal<In, Bits<MUL_A_BITS>>,
    pub a_in: Signal<In, Bits<MUL_A_BITS>>,
    pub b_in: Signal<In, Bits<MUL_B_BITS>>,
    pub p_in: Signal<In, Bit>,
    pub acc_out: Signal<Out, Bits<MUL_A_BITS>>,
    pub a_out: Signal<Out, Bits<MUL_A_BITS>>,
    pub b_out: Signal<Out, Bits<MUL_B_BITS>>,
    pub p_out: Signal<Out, Bit>,
    mag: Signal<Local, Bits<MUL_A_BITS>>,
    pp: Signal<Local, Bits<MUL_A_BITS>>,
    booth_sum: Signal<Local, Bits<101>>,
}

impl Logic for BoothDigit {
    #[hdl_gen]
    fn update(&mut self) {
        if self.b_in.val().get_bit(0) != self.p_in.val() {
            self.mag.next = self.a_in.val();
        } else if self.b_in.val().get_bit(1) != self.b_in.val().get_bit(0) {
            self.mag.next = self.a_in.val() << 1;
        } else {
            self.mag.next = 0.into();
        }
        if self.b_in.val().get_bit(1) {
            self.pp.next = !self.mag.val();
        } else {
            self.pp.next = self.mag.val();
        }
        self.booth_sum.next = ((bit_cast::<101, MUL_A_BITS>(self.acc_in.val()) << 1) | 1)
            + ((bit_cast::<101, MUL_A_BITS>(self.pp.val()) << 1) | bit_cast::<101, 1>(self.b_in.val().get_bits::<1>(1)));
        self.acc_out.next = self.booth_sum.val().get_bits::<MUL_A_BITS>(1);
        self.a_out.next = self.a_in.val() << 2;
        self.b_out.next = self.b_in.val() >> 2;
        self.p_out.next = self.b_in.val().get_bit(1);
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
    digits: Vec<BoothDigit>,
    acc: DFF<Bits<MUL_A_BITS>>,
    sa: DFF<Bits<MUL_A_BITS>>,
    sb: DFF<Bits<MUL_B_BITS>>,
    sp: DFF<Bit>,
    ctl: Iterate,
}

impl<const R: usize> Default for MulSeq<R> {
    fn default() -> Self {
        assert!(R >= 2 && R % 2 == 0 && MUL_B_BITS % R == 0, "MulSeq<{R}>: R must be even and divide {MUL_B_BITS}");
        MulSeq {
            clock: Default::default(),
            start: Default::default(),
            a: Default::default(),
            b: Default::default(),
            product: Default::default(),
            valid: Default::default(),
            busy: Default::default(),
            digits: (0..R / 2).map(|_| Default::default()).collect(),
            acc: Default::default(),
            sa: Default::default(),
            sb: Default::default(),
            sp: Default::default(),
            ctl: Iterate::new(mul_seq_steps(R)),
        }
    }
}

impl<const R: usize> Logic for MulSeq<R> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, acc, sa, sb, sp);
        self.ctl.clock.next = self.clock.val();
        self.ctl.start.next = self.start.val();
        self.digits[0].acc_in.next = self.acc.q.val();
        self.digits[0].a_in.next = self.sa.q.val();
        self.digits[0].b_in.next = self.sb.q.val();
        self.digits[0].p_in.next = self.sp.q.val();
        for i in 1..self.digits.len() {
            self.digits[i].acc_in.next = self.digits[i - 1].acc_out.val();
            self.digits[i].a_in.next = self.digits[i - 1].a_out.val();
            self.digits[i].b_in.next = self.digits[i - 1].b_out.val();
            self.digits[i].p_in.next = self.digits[i - 1].p_out.val();
        }
        self.product.next = self.acc.q.val();
        self.valid.next = self.ctl.valid.val();
        self.busy.next = self.ctl.busy.val();
        if self.ctl.step.val() {
            // The last digit's outputs win: later assignments override earlier ones.
            for i in 0..self.digits.len() {
                self.acc.d.next = self.digits[i].acc_out.val();
                self.sa.d.next = self.digits[i].a_out.val();
                self.sb.d.next = self.digits[i].b_out.val();
                self.sp.d.next = self.digits[i].p_out.val();
            }
        } else if self.ctl.load.val() {
            self.acc.d.next = 0.into();
            self.sa.d.next = self.a.val();
            self.sb.d.next = self.b.val();
            self.sp.d.next = false;
        }
    }
}
