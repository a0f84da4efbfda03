//! Iterative unsigned divider: 104-bit numerator by 64-bit denominator, giving a
//! 104-bit quotient and a 64-bit remainder, `R` radix-2 digits per clock (R even, as
//! R/2 radix-4 pairs). The setup's numerators are < 2^102 (docs/model.md, "Widths");
//! 104 digits keep R = 2, 4 and 8 whole.
//!
//! Restoring division, two digits at a time: each pair shifts two numerator bits
//! into the partial remainder and keeps the largest q in 0..=3 with `4·rem + bits ≥
//! q·den`, decided by the borrows of three subtractions side by side (one carry
//! chain per cycle at R = 2, where two chained digits had two). Equals u128 `/` and `%` on
//! numerators < 2^104, which the reference model's setup uses. Dividing by 0 gives an all-ones quotient
//! and the numerator's low bits as remainder (the scheduler never does it: D = 0
//! takes the uniform path).
//!
//! Ports and timing as [`crate::hdl::root::OffsetRoot`]: pulse `start` while idle;
//! `quotient`, `remainder` and `valid` follow [`div_latency`]`(R)` cycles later.

use super::iterate::Iterate;
use rust_hdl::prelude::*;

pub use crate::latency::{div_latency, DIV_NUM_BITS};
pub const DIV_DEN_BITS: usize = 64;
const REM_BITS: usize = DIV_DEN_BITS + 1;
// DivPair reads numerator bits 103..102 by a literal index (rust-hdl writes a Rust
// constant's name into the Verilog).
const _: () = assert!(DIV_NUM_BITS == 104);

/// One radix-4 digit (two radix-2 digits), combinational. The quotient bits shift in
/// at the bottom of the numerator register as its bits shift out at the top. The
/// shifted remainder 4·rem + two numerator bits is compared with d, 2d and 3d side
/// by side (three 68-bit subtractions, whose borrows are the comparisons), and the
/// largest that fits is taken: one carry chain and a 4:1 select per pair, the same
/// quotient and remainder as two restoring steps.
#[derive(LogicBlock, Default)]
pub struct DivPair {
    pub rem_in: Signal<In, Bits<REM_BITS>>,
    pub num_in: Signal<In, Bits<DIV_NUM_BITS>>,
    pub den: Signal<In, Bits<DIV_DEN_BITS>>,
    pub den3: Signal<In, Bits<66>>,
    pub rem_out: Signal<Out, Bits<REM_BITS>>,
    pub num_out: Signal<Out, Bits<DIV_NUM_BITS>>,
    rem4: Signal<Local, Bits<68>>,
    d1: Signal<Local, Bits<68>>,
    d2: Signal<Local, Bits<68>>,
    d3: Signal<Local, Bits<68>>,
}

impl Logic for DivPair {
    #[hdl_gen]
    fn update(&mut self) {
        // rem < d < 2^64, so 4·rem + 3 < 2^66 and 3d < 2^66: 68 bits hold each
        // difference with its borrow in bit 67.
        self.rem4.next = (bit_cast::<68, REM_BITS>(self.rem_in.val()) << 2)
            | bit_cast::<68, 2>(self.num_in.val().get_bits::<2>(102));
        self.d1.next = self.rem4.val() - bit_cast::<68, DIV_DEN_BITS>(self.den.val());
        self.d2.next = self.rem4.val() - (bit_cast::<68, DIV_DEN_BITS>(self.den.val()) << 1);
        self.d3.next = self.rem4.val() - bit_cast::<68, 66>(self.den3.val());
        if !self.d3.val().get_bit(67) {
            self.rem_out.next = bit_cast::<REM_BITS, 68>(self.d3.val());
            self.num_out.next = (self.num_in.val() << 2) | 3;
        } else if !self.d2.val().get_bit(67) {
            self.rem_out.next = bit_cast::<REM_BITS, 68>(self.d2.val());
            self.num_out.next = (self.num_in.val() << 2) | 2;
        } else if !self.d1.val().get_bit(67) {
            self.rem_out.next = bit_cast::<REM_BITS, 68>(self.d1.val());
            self.num_out.next = (self.num_in.val() << 2) | 1;
        } else {
            self.rem_out.next = bit_cast::<REM_BITS, 68>(self.rem4.val());
            self.num_out.next = self.num_in.val() << 2;
        }
    }
}

/// The iterative divider with `R` radix-2 digits per cycle, as `R / 2` [`DivPair`]s
/// (R even). 3d is formed once, in the cycle after the load, from the registered d
/// (so no adder follows the caller's operand select).
#[derive(LogicBlock)]
pub struct Divider<const R: usize> {
    pub clock: Signal<In, Clock>,
    pub start: Signal<In, Bit>,
    pub numerator: Signal<In, Bits<DIV_NUM_BITS>>,
    pub denominator: Signal<In, Bits<DIV_DEN_BITS>>,
    pub quotient: Signal<Out, Bits<DIV_NUM_BITS>>,
    pub remainder: Signal<Out, Bits<DIV_DEN_BITS>>,
    pub valid: Signal<Out, Bit>,
    pub busy: Signal<Out, Bit>,
    pairs: Vec<DivPair>,
    num: DFF<Bits<DIV_NUM_BITS>>,
    den: DFF<Bits<DIV_DEN_BITS>>,
    den3: DFF<Bits<66>>,
    prep: DFF<Bit>,
    rem: DFF<Bits<REM_BITS>>,
    ctl: Iterate,
}

impl<const R: usize> Default for Divider<R> {
    fn default() -> Self {
        assert!(R >= 2 && R % 2 == 0 && DIV_NUM_BITS % R == 0, "Divider<{R}>: R must be even and divide {DIV_NUM_BITS}");
        Divider {
            clock: Default::default(),
            start: Default::default(),
            numerator: Default::default(),
            denominator: Default::default(),
            quotient: Default::default(),
            remainder: Default::default(),
            valid: Default::default(),
            busy: Default::default(),
            pairs: (0..R / 2).map(|_| Default::default()).collect(),
            num: Default::default(),
            den: Default::default(),
            den3: Default::default(),
            prep: Default::default(),
            rem: Default::default(),
            ctl: Iterate::new(1 + DIV_NUM_BITS / R),
        }
    }
}

impl<const R: usize> Logic for Divider<R> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, num, den, den3, prep, rem);
        self.ctl.clock.next = self.clock.val();
        self.ctl.start.next = self.start.val();
        self.pairs[0].rem_in.next = self.rem.q.val();
        self.pairs[0].num_in.next = self.num.q.val();
        for i in 0..self.pairs.len() {
            self.pairs[i].den.next = self.den.q.val();
            self.pairs[i].den3.next = self.den3.q.val();
        }
        for i in 1..self.pairs.len() {
            self.pairs[i].rem_in.next = self.pairs[i - 1].rem_out.val();
            self.pairs[i].num_in.next = self.pairs[i - 1].num_out.val();
        }
        self.quotient.next = self.num.q.val();
        self.remainder.next = bit_cast::<DIV_DEN_BITS, REM_BITS>(self.rem.q.val());
        self.valid.next = self.ctl.valid.val();
        self.busy.next = self.ctl.busy.val();
        if self.ctl.step.val() & self.prep.q.val() {
            // The first step cycle forms 3d; the digits start in the next.
            self.den3.d.next =
                bit_cast::<66, DIV_DEN_BITS>(self.den.q.val()) + (bit_cast::<66, DIV_DEN_BITS>(self.den.q.val()) << 1);
            self.prep.d.next = false;
        } else if self.ctl.step.val() {
            // The last pair's outputs win: later assignments override earlier ones.
            for i in 0..self.pairs.len() {
                self.rem.d.next = self.pairs[i].rem_out.val();
                self.num.d.next = self.pairs[i].num_out.val();
            }
        } else if self.ctl.load.val() {
            self.num.d.next = self.numerator.val();
            self.den.d.next = self.denominator.val();
            self.prep.d.next = true;
            self.rem.d.next = 0.into();
        }
    }
}
