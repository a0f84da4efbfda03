//! Iterative unsigned divider: 104-bit numerator by 64-bit denominator, giving a
//! 104-bit quotient and a 64-bit remainder, `R` radix-2 digits per clock. The setup's
//! numerators are < 2^102 (docs/model.md, "Widths"); 104 digits keep R = 1, 2, 4 and 8
//! whole.
//!
//! Restoring division: each digit shifts one numerator bit into the partial
//! remainder and keeps a quotient bit where `rem ≥ den`, decided by the borrow of
//! the one 66-bit subtraction `rem − den` (a single carry chain per digit). Equals u128 `/` and `%` on
//! numerators < 2^104, which the reference model's setup uses. Dividing by 0 gives an all-ones quotient
//! and the numerator's low bits as remainder (the scheduler never does it: D = 0
//! takes the uniform path).
//!
//! Ports and timing as [`crate::hdl::sqrt::Sqrt`]: pulse `start` while idle;
//! `quotient`, `remainder` and `valid` follow [`div_latency`]`(R)` cycles later.

use super::iterate::Iterate;
use rust_hdl::prelude::*;

pub const DIV_NUM_BITS: usize = 104;
pub const DIV_DEN_BITS: usize = 64;
const REM_BITS: usize = DIV_DEN_BITS + 1;
// DivDigit reads numerator bit 103 by a literal index (rust-hdl writes a Rust
// constant's name into the Verilog).
const _: () = assert!(DIV_NUM_BITS == 104);

/// Cycles from the `start` edge to `valid` for `r` digits per cycle.
pub const fn div_latency(r: usize) -> usize {
    1 + DIV_NUM_BITS / r
}

/// One radix-2 digit, combinational. The quotient bits shift in at the bottom of
/// the numerator register as its bits shift out at the top.
#[derive(LogicBlock, Default)]
pub struct DivDigit {
    pub rem_in: Signal<In, Bits<REM_BITS>>,
    pub num_in: Signal<In, Bits<DIV_NUM_BITS>>,
    pub den: Signal<In, Bits<DIV_DEN_BITS>>,
    pub rem_out: Signal<Out, Bits<REM_BITS>>,
    pub num_out: Signal<Out, Bits<DIV_NUM_BITS>>,
    rem_sh: Signal<Local, Bits<REM_BITS>>,
    diff: Signal<Local, Bits<66>>,
}

impl Logic for DivDigit {
    #[hdl_gen]
    fn update(&mut self) {
        self.rem_sh.next =
            (self.rem_in.val() << 1) | bit_cast::<REM_BITS, 1>(self.num_in.val().get_bits::<1>(103));
        // One subtraction; its borrow (bit 65) is the comparison rem_sh < den.
        self.diff.next = bit_cast::<66, REM_BITS>(self.rem_sh.val()) - bit_cast::<66, DIV_DEN_BITS>(self.den.val());
        if self.diff.val().get_bit(65) {
            self.rem_out.next = self.rem_sh.val();
            self.num_out.next = self.num_in.val() << 1;
        } else {
            self.rem_out.next = bit_cast::<REM_BITS, 66>(self.diff.val());
            self.num_out.next = (self.num_in.val() << 1) | 1;
        }
    }
}

/// The iterative divider with `R` digits per cycle.
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
    digits: [DivDigit; R],
    num: DFF<Bits<DIV_NUM_BITS>>,
    den: DFF<Bits<DIV_DEN_BITS>>,
    rem: DFF<Bits<REM_BITS>>,
    ctl: Iterate,
}

impl<const R: usize> Default for Divider<R> {
    fn default() -> Self {
        assert!(R >= 1 && DIV_NUM_BITS % R == 0, "Divider<{R}>: R must divide {DIV_NUM_BITS}");
        Divider {
            clock: Default::default(),
            start: Default::default(),
            numerator: Default::default(),
            denominator: Default::default(),
            quotient: Default::default(),
            remainder: Default::default(),
            valid: Default::default(),
            busy: Default::default(),
            digits: std::array::from_fn(|_| Default::default()),
            num: Default::default(),
            den: Default::default(),
            rem: Default::default(),
            ctl: Iterate::new(DIV_NUM_BITS / R),
        }
    }
}

impl<const R: usize> Logic for Divider<R> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, num, den, rem);
        self.ctl.clock.next = self.clock.val();
        self.ctl.start.next = self.start.val();
        self.digits[0].rem_in.next = self.rem.q.val();
        self.digits[0].num_in.next = self.num.q.val();
        for i in 0..R {
            self.digits[i].den.next = self.den.q.val();
        }
        for i in 1..R {
            self.digits[i].rem_in.next = self.digits[i - 1].rem_out.val();
            self.digits[i].num_in.next = self.digits[i - 1].num_out.val();
        }
        self.quotient.next = self.num.q.val();
        self.remainder.next = bit_cast::<DIV_DEN_BITS, REM_BITS>(self.rem.q.val());
        self.valid.next = self.ctl.valid.val();
        self.busy.next = self.ctl.busy.val();
        if self.ctl.step.val() {
            // The last digit's outputs win: later assignments override earlier ones.
            for i in 0..R {
                self.rem.d.next = self.digits[i].rem_out.val();
                self.num.d.next = self.digits[i].num_out.val();
            }
        } else if self.ctl.load.val() {
            self.num.d.next = self.numerator.val();
            self.den.d.next = self.denominator.val();
            self.rem.d.next = 0.into();
        }
    }
}
