//! Iterative integer square root: root = ⌊√radicand⌋, 128-bit radicand, 64-bit root.
//!
//! Restoring digit recurrence, `R` radix-2 digits per clock (the radix is 2^R per
//! cycle; R must divide 64). Each digit shifts two radicand bits into the partial
//! remainder and keeps a root bit where `rem ≥ 4·root + 1`. This is exactly
//! `u128::isqrt`, which is what the reference model uses (docs/model.md).
//!
//! Ports: pulse `start` with `radicand` valid while idle; `root` and `valid` follow
//! [`sqrt_latency`]`(R)` cycles later, and stay until the next start. `busy` is high
//! in between; a `start` while busy is ignored. No reset is needed: `valid` and
//! `busy` are cleared by the first start, and the testbench checks that nothing is
//! read before.

use super::iterate::Iterate;
use rust_hdl::prelude::*;

/// Width of the radicand.
pub const SQRT_RADICAND_BITS: usize = 128;
/// Width of the root.
pub const SQRT_ROOT_BITS: usize = 64;
const REM_BITS: usize = SQRT_ROOT_BITS + 2;
// SqrtDigit reads radicand bits [127:126] by a literal index.
const _: () = assert!(SQRT_RADICAND_BITS == 128);

/// Cycles from the `start` edge to `valid` for `r` digits per cycle.
pub const fn sqrt_latency(r: usize) -> usize {
    1 + SQRT_ROOT_BITS / r
}

/// One radix-2 digit of the recurrence, combinational.
#[derive(LogicBlock, Default)]
pub struct SqrtDigit {
    pub rem_in: Signal<In, Bits<REM_BITS>>,
    pub root_in: Signal<In, Bits<SQRT_ROOT_BITS>>,
    pub x_in: Signal<In, Bits<SQRT_RADICAND_BITS>>,
    pub rem_out: Signal<Out, Bits<REM_BITS>>,
    pub root_out: Signal<Out, Bits<SQRT_ROOT_BITS>>,
    pub x_out: Signal<Out, Bits<SQRT_RADICAND_BITS>>,
    rem_sh: Signal<Local, Bits<REM_BITS>>,
    trial: Signal<Local, Bits<REM_BITS>>,
}

impl Logic for SqrtDigit {
    #[hdl_gen]
    fn update(&mut self) {
        // The next two radicand bits come from the top of the shifting radicand.
        // A literal index: rust-hdl writes a Rust constant's *name* into the Verilog.
        self.rem_sh.next =
            (self.rem_in.val() << 2) | bit_cast::<REM_BITS, 2>(self.x_in.val().get_bits::<2>(126));
        self.trial.next = (bit_cast::<REM_BITS, SQRT_ROOT_BITS>(self.root_in.val()) << 2) | 1;
        self.x_out.next = self.x_in.val() << 2;
        if self.rem_sh.val() >= self.trial.val() {
            self.rem_out.next = self.rem_sh.val() - self.trial.val();
            self.root_out.next = (self.root_in.val() << 1) | 1;
        } else {
            self.rem_out.next = self.rem_sh.val();
            self.root_out.next = self.root_in.val() << 1;
        }
    }
}

/// The iterative square root with `R` digits per cycle.
#[derive(LogicBlock)]
pub struct Sqrt<const R: usize> {
    pub clock: Signal<In, Clock>,
    pub start: Signal<In, Bit>,
    pub radicand: Signal<In, Bits<SQRT_RADICAND_BITS>>,
    pub root: Signal<Out, Bits<SQRT_ROOT_BITS>>,
    pub valid: Signal<Out, Bit>,
    pub busy: Signal<Out, Bit>,
    digits: [SqrtDigit; R],
    x: DFF<Bits<SQRT_RADICAND_BITS>>,
    rem: DFF<Bits<REM_BITS>>,
    acc: DFF<Bits<SQRT_ROOT_BITS>>,
    ctl: Iterate,
}

impl<const R: usize> Default for Sqrt<R> {
    fn default() -> Self {
        assert!(R >= 1 && SQRT_ROOT_BITS % R == 0, "Sqrt<{R}>: R must divide {SQRT_ROOT_BITS}");
        Sqrt {
            clock: Default::default(),
            start: Default::default(),
            radicand: Default::default(),
            root: Default::default(),
            valid: Default::default(),
            busy: Default::default(),
            digits: std::array::from_fn(|_| Default::default()),
            x: Default::default(),
            rem: Default::default(),
            acc: Default::default(),
            ctl: Iterate::new(SQRT_ROOT_BITS / R),
        }
    }
}

impl<const R: usize> Logic for Sqrt<R> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, x, rem, acc);
        self.ctl.clock.next = self.clock.val();
        self.ctl.start.next = self.start.val();
        // The digit chain: digit 0 reads the registers, digit i reads digit i - 1.
        self.digits[0].rem_in.next = self.rem.q.val();
        self.digits[0].root_in.next = self.acc.q.val();
        self.digits[0].x_in.next = self.x.q.val();
        for i in 1..R {
            self.digits[i].rem_in.next = self.digits[i - 1].rem_out.val();
            self.digits[i].root_in.next = self.digits[i - 1].root_out.val();
            self.digits[i].x_in.next = self.digits[i - 1].x_out.val();
        }
        self.root.next = self.acc.q.val();
        self.valid.next = self.ctl.valid.val();
        self.busy.next = self.ctl.busy.val();
        if self.ctl.step.val() {
            // The last digit's outputs win: later assignments override earlier ones.
            for i in 0..R {
                self.rem.d.next = self.digits[i].rem_out.val();
                self.acc.d.next = self.digits[i].root_out.val();
                self.x.d.next = self.digits[i].x_out.val();
            }
        } else if self.ctl.load.val() {
            self.x.d.next = self.radicand.val();
            self.rem.d.next = 0.into();
            self.acc.d.next = 0.into();
        }
    }
}
