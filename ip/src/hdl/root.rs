//! Iterative offset root: `x = ⌊√(p² + c)⌋ − p`, the per-step square root of the
//! core, `R` radix-2 digits per clock (R divides 36).
//!
//! The square-root paths need τ' = isqrt(P'² + C) − P' with P' < 2^64 known at setup
//! and τ' < 2^36 (docs/model.md, "Widths"). Finding only τ' takes 36 digits instead
//! of the 64 of a plain 128-bit square root, and each digit is one 67-bit subtraction
//! whose borrow is the comparison (one carry chain): digit b keeps bit b of x when
//! `rem·2 + c_b ≥ trial`, with `trial = 2p + 2x + 2^b` held in a register and stepped
//! by adders that run beside the subtraction (`+ 2^b + 2^(b−1)` when the bit is kept,
//! `− 2^(b−1)` when not). This is exactly [`crate::model::offset_root`], which the
//! reference model uses, and which equals `u128::isqrt(p² + c) − p`.
//!
//! Ports: pulse `start` with `p` and `c` valid while idle; `x` and `valid` follow
//! [`root_latency`]`(R)` cycles later and stay until the next start. `busy` is high
//! in between; a `start` while busy is ignored. No reset is needed (see
//! [`super::iterate::Iterate`]). Inputs outside the range (c ≥ 2^100, or a root of
//! more than 36 bits) give an unspecified x; the core never presents them.

use super::iterate::Iterate;
use rust_hdl::prelude::*;

/// Width of `p`.
pub const ROOT_P_BITS: usize = 64;
/// Width of `c` (the model's `ACC_BITS`).
pub const ROOT_C_BITS: usize = 100;
/// Width of the result x: the number of digits (the model's `OFFSET_ROOT_BITS`).
pub const ROOT_X_BITS: usize = 36;
/// The scaled remainder after the shift-in of the next bit of c.
const REM_BITS: usize = 67;
/// The trial 2p + 2x + 2^b.
const TRIAL_BITS: usize = 66;
// The digit reads bit 35 of the shifting low part of c by a literal index, and the
// load splits c at bit 36 (rust-hdl writes a Rust constant's name into the Verilog).
const _: () = assert!(ROOT_X_BITS == 36 && ROOT_C_BITS == 100 && ROOT_P_BITS == 64);
const _: () = assert!(ROOT_X_BITS == crate::model::OFFSET_ROOT_BITS as usize);
const _: () = assert!(ROOT_C_BITS == crate::model::ACC_BITS as usize);

/// Cycles from the `start` edge to `valid` for `r` digits per cycle.
pub const fn root_latency(r: usize) -> usize {
    1 + ROOT_X_BITS / r
}

/// One radix-2 digit, combinational.
#[derive(LogicBlock, Default)]
pub struct RootDigit {
    pub rem_in: Signal<In, Bits<REM_BITS>>,
    pub trial_in: Signal<In, Bits<TRIAL_BITS>>,
    /// 2^b, one-hot.
    pub mask_in: Signal<In, Bits<ROOT_X_BITS>>,
    pub x_in: Signal<In, Bits<ROOT_X_BITS>>,
    /// The bits of c below the next digit, the next one at the top (bit 35).
    pub c_in: Signal<In, Bits<ROOT_X_BITS>>,
    pub rem_out: Signal<Out, Bits<REM_BITS>>,
    pub trial_out: Signal<Out, Bits<TRIAL_BITS>>,
    pub mask_out: Signal<Out, Bits<ROOT_X_BITS>>,
    pub x_out: Signal<Out, Bits<ROOT_X_BITS>>,
    pub c_out: Signal<Out, Bits<ROOT_X_BITS>>,
    rem_sh: Signal<Local, Bits<REM_BITS>>,
    diff: Signal<Local, Bits<68>>,
    half: Signal<Local, Bits<TRIAL_BITS>>,
    keep_step: Signal<Local, Bits<TRIAL_BITS>>,
}

impl Logic for RootDigit {
    #[hdl_gen]
    fn update(&mut self) {
        self.rem_sh.next =
            (self.rem_in.val() << 1) | bit_cast::<REM_BITS, 1>(self.c_in.val().get_bits::<1>(35));
        // One subtraction; its borrow (bit 67) is the comparison.
        self.diff.next = bit_cast::<68, REM_BITS>(self.rem_sh.val()) - bit_cast::<68, TRIAL_BITS>(self.trial_in.val());
        // 2^(b−1) and 2^b + 2^(b−1) (an OR: the mask is one-hot).
        self.half.next = bit_cast::<TRIAL_BITS, ROOT_X_BITS>(self.mask_in.val() >> 1);
        self.keep_step.next = bit_cast::<TRIAL_BITS, ROOT_X_BITS>(self.mask_in.val() | (self.mask_in.val() >> 1));
        self.mask_out.next = self.mask_in.val() >> 1;
        self.c_out.next = self.c_in.val() << 1;
        if self.diff.val().get_bit(67) {
            self.rem_out.next = self.rem_sh.val();
            self.x_out.next = self.x_in.val();
            self.trial_out.next = self.trial_in.val() - self.half.val();
        } else {
            self.rem_out.next = bit_cast::<REM_BITS, 68>(self.diff.val());
            self.x_out.next = self.x_in.val() | self.mask_in.val();
            self.trial_out.next = self.trial_in.val() + self.keep_step.val();
        }
    }
}

/// The iterative offset root with `R` digits per cycle.
#[derive(LogicBlock)]
pub struct OffsetRoot<const R: usize> {
    pub clock: Signal<In, Clock>,
    pub start: Signal<In, Bit>,
    pub p: Signal<In, Bits<ROOT_P_BITS>>,
    pub c: Signal<In, Bits<ROOT_C_BITS>>,
    pub x: Signal<Out, Bits<ROOT_X_BITS>>,
    pub valid: Signal<Out, Bit>,
    pub busy: Signal<Out, Bit>,
    digits: [RootDigit; R],
    rem: DFF<Bits<REM_BITS>>,
    trial: DFF<Bits<TRIAL_BITS>>,
    mask: DFF<Bits<ROOT_X_BITS>>,
    acc: DFF<Bits<ROOT_X_BITS>>,
    clow: DFF<Bits<ROOT_X_BITS>>,
    c_first_mask: Constant<Bits<ROOT_X_BITS>>,
    ctl: Iterate,
}

impl<const R: usize> Default for OffsetRoot<R> {
    fn default() -> Self {
        assert!(R >= 1 && ROOT_X_BITS % R == 0, "OffsetRoot<{R}>: R must divide {ROOT_X_BITS}");
        OffsetRoot {
            clock: Default::default(),
            start: Default::default(),
            p: Default::default(),
            c: Default::default(),
            x: Default::default(),
            valid: Default::default(),
            busy: Default::default(),
            digits: std::array::from_fn(|_| Default::default()),
            rem: Default::default(),
            trial: Default::default(),
            mask: Default::default(),
            acc: Default::default(),
            clow: Default::default(),
            c_first_mask: Constant::new((1u64 << (ROOT_X_BITS - 1)).into()),
            ctl: Iterate::new(ROOT_X_BITS / R),
        }
    }
}

impl<const R: usize> Logic for OffsetRoot<R> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, rem, trial, mask, acc, clow);
        self.ctl.clock.next = self.clock.val();
        self.ctl.start.next = self.start.val();
        // The digit chain: digit 0 reads the registers, digit i reads digit i - 1.
        self.digits[0].rem_in.next = self.rem.q.val();
        self.digits[0].trial_in.next = self.trial.q.val();
        self.digits[0].mask_in.next = self.mask.q.val();
        self.digits[0].x_in.next = self.acc.q.val();
        self.digits[0].c_in.next = self.clow.q.val();
        for i in 1..R {
            self.digits[i].rem_in.next = self.digits[i - 1].rem_out.val();
            self.digits[i].trial_in.next = self.digits[i - 1].trial_out.val();
            self.digits[i].mask_in.next = self.digits[i - 1].mask_out.val();
            self.digits[i].x_in.next = self.digits[i - 1].x_out.val();
            self.digits[i].c_in.next = self.digits[i - 1].c_out.val();
        }
        self.x.next = self.acc.q.val();
        self.valid.next = self.ctl.valid.val();
        self.busy.next = self.ctl.busy.val();
        if self.ctl.step.val() {
            // The last digit's outputs win: later assignments override earlier ones.
            for i in 0..R {
                self.rem.d.next = self.digits[i].rem_out.val();
                self.trial.d.next = self.digits[i].trial_out.val();
                self.mask.d.next = self.digits[i].mask_out.val();
                self.acc.d.next = self.digits[i].x_out.val();
                self.clow.d.next = self.digits[i].c_out.val();
            }
        } else if self.ctl.load.val() {
            // rem = c >> 36 (the first digit shifts in bit 35); trial = 2p + 2^35.
            self.rem.d.next = bit_cast::<REM_BITS, 64>(self.c.val().get_bits::<64>(36));
            self.clow.d.next = self.c.val().get_bits::<ROOT_X_BITS>(0);
            self.trial.d.next =
                (bit_cast::<TRIAL_BITS, ROOT_P_BITS>(self.p.val()) << 1) + bit_cast::<TRIAL_BITS, ROOT_X_BITS>(self.c_first_mask.val());
            self.mask.d.next = self.c_first_mask.val();
            self.acc.d.next = 0.into();
        }
    }
}
