//! Iterative offset root: `x = ⌊√(p² + c)⌋ − p`, the per-step square root of the
//! core, `R` radix-2 digits per clock as R/2 radix-4 pairs (R even, dividing 36).
//!
//! The square-root paths need τ' = isqrt(P'² + C) − P' with P' < 2^64 known at setup
//! and τ' < 2^36 (docs/model.md, "Widths"). Finding only τ' takes 36 digits instead
//! of the 64 of a plain 128-bit square root, and each digit is one 67-bit subtraction
//! whose borrow is the comparison (one carry chain): digit b keeps bit b of x when
//! `rem·2 + c_b ≥ trial`, with `trial = 2p + 2x + 2^b` held in a register and stepped
//! by adders that run beside the subtraction (`+ 2^b + 2^(b−1)` when the bit is kept,
//! `− 2^(b−1)` when not). This is exactly [`crate::model::offset_root`], which the
//! reference model uses, and which equals `u128::isqrt(p² + c) − p`. Two digits are
//! done per [`RootPair`], which compares all outcomes of the second digit beside the
//! first, so each cycle of R = 2 holds one 70-bit carry chain and a 4:1 select
//! instead of two chained 68-bit subtractions.
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
/// 3t + 3m/2, held beside the trial.
const T3_BITS: usize = 68;
/// A pair's working width: rem4 < 2^68 and 3t + 3m/2 < 2^68, with a borrow bit above.
const PAIR_BITS: usize = 70;
// The borrow is read by a literal index (bit 69).
const _: () = assert!(PAIR_BITS == 70);
// The digit reads bit 35 of the shifting low part of c by a literal index, and the
// load splits c at bit 36 (rust-hdl writes a Rust constant's name into the Verilog).
const _: () = assert!(ROOT_X_BITS == 36 && ROOT_C_BITS == 100 && ROOT_P_BITS == 64);
const _: () = assert!(ROOT_X_BITS == crate::model::OFFSET_ROOT_BITS as usize);
const _: () = assert!(ROOT_C_BITS == crate::model::ACC_BITS as usize);

/// Cycles from the `start` edge to `valid` for `r` digits per cycle.
pub const fn root_latency(r: usize) -> usize {
    1 + ROOT_X_BITS / r
}

/// Two radix-2 digits (one radix-4 digit), combinational. Digit b and digit b − 1 of
/// the single-digit recurrence, with the second digit's outcome for both values of the
/// first compared at once, so one cycle holds one carry chain, not two in series. With
/// `m = 2^b`, `t` the trial and `rem4 = 4·rem + (next two bits of c)` (in units of
/// m/2), the pair of digits d = 0..3 keeps the largest d with
///
/// * d ≥ 1: `rem4 ≥ t − m/2` (first digit dropped, second kept),
/// * d ≥ 2: `rem4 ≥ 2t` (first kept: the single digit's own test, doubled),
/// * d = 3: `rem4 ≥ 3t + 3m/2` (both kept),
///
/// and the remainder is rem4 minus that threshold (rem4 when d = 0). The thresholds
/// grow with d (t > m), so the three tests are nested. The two thresholds that are not
/// a shift of t, `t − m/2` and `3t + 3m/2`, come in registered beside t (`tlo_in`,
/// `t3_in`), so each test is one subtraction straight from registers. The trial steps
/// by `−3m/4, +m/4, +5m/4, +9m/4` for d = 0..3 (two single digits' updates: `− m/2`
/// or `+ 3m/2`, then `∓` a quarter), and the next pair's thresholds (with m' = m/4:
/// `t' − m'/2` and `3t' + 3m'/2`) are formed for all four outcomes beside the tests,
/// each one adder from t or from 3t + 3m/2 and a constant that is an OR of shifts of
/// the one-hot m; the tests' borrows only select. m = 2^35, 2^33, …, 2 (36 digits
/// from 2^35), so m/2 is exact in every pair and m/4 and m/8 in every pair but the
/// last, whose outputs are not read.
#[derive(LogicBlock, Default)]
pub struct RootPair {
    pub rem_in: Signal<In, Bits<REM_BITS>>,
    pub trial_in: Signal<In, Bits<TRIAL_BITS>>,
    /// t − m/2 and 3t + 3m/2 for this pair's t and m.
    pub tlo_in: Signal<In, Bits<TRIAL_BITS>>,
    pub t3_in: Signal<In, Bits<T3_BITS>>,
    /// 2^b, one-hot.
    pub mask_in: Signal<In, Bits<ROOT_X_BITS>>,
    pub x_in: Signal<In, Bits<ROOT_X_BITS>>,
    /// The bits of c below the next digit, the next two at the top (bits 35, 34).
    pub c_in: Signal<In, Bits<ROOT_X_BITS>>,
    pub rem_out: Signal<Out, Bits<REM_BITS>>,
    pub trial_out: Signal<Out, Bits<TRIAL_BITS>>,
    pub tlo_out: Signal<Out, Bits<TRIAL_BITS>>,
    pub t3_out: Signal<Out, Bits<T3_BITS>>,
    pub mask_out: Signal<Out, Bits<ROOT_X_BITS>>,
    pub x_out: Signal<Out, Bits<ROOT_X_BITS>>,
    pub c_out: Signal<Out, Bits<ROOT_X_BITS>>,
    rem4: Signal<Local, Bits<PAIR_BITS>>,
    t_w: Signal<Local, Bits<PAIR_BITS>>,
    t3_w: Signal<Local, Bits<PAIR_BITS>>,
    m_w: Signal<Local, Bits<PAIR_BITS>>,
    /// rem4 − (t − m/2), rem4 − 2t, rem4 − (3t + 3m/2); the top bit is the borrow.
    d1: Signal<Local, Bits<PAIR_BITS>>,
    d2: Signal<Local, Bits<PAIR_BITS>>,
    d3: Signal<Local, Bits<PAIR_BITS>>,
}

impl Logic for RootPair {
    #[hdl_gen]
    fn update(&mut self) {
        self.rem4.next = (bit_cast::<PAIR_BITS, REM_BITS>(self.rem_in.val()) << 2)
            | bit_cast::<PAIR_BITS, 2>(self.c_in.val().get_bits::<2>(34));
        self.t_w.next = bit_cast::<PAIR_BITS, TRIAL_BITS>(self.trial_in.val());
        self.t3_w.next = bit_cast::<PAIR_BITS, T3_BITS>(self.t3_in.val());
        self.m_w.next = bit_cast::<PAIR_BITS, ROOT_X_BITS>(self.mask_in.val());
        self.d1.next = self.rem4.val() - bit_cast::<PAIR_BITS, TRIAL_BITS>(self.tlo_in.val());
        self.d2.next = self.rem4.val() - (self.t_w.val() << 1);
        self.d3.next = self.rem4.val() - self.t3_w.val();
        self.mask_out.next = self.mask_in.val() >> 2;
        self.c_out.next = self.c_in.val() << 2;
        // The tests are nested (d = 3 passes only where d = 2 does, d = 2 only where
        // d = 1 does), so the priority of d = 3, 2, 1, 0 is a balanced 4:1 select:
        // the d ≥ 2 borrow picks between two 2:1 selects by the other two, one LUT
        // level after the borrows rather than a chain of three.
        if !self.d2.val().get_bit(69) {
            if !self.d3.val().get_bit(69) {
                self.rem_out.next = bit_cast::<REM_BITS, PAIR_BITS>(self.d3.val());
                self.x_out.next = self.x_in.val() | self.mask_in.val() | (self.mask_in.val() >> 1);
                // t + 9m/4; t + 17m/8; 3t + 3m/2 + 45m/8.
                self.trial_out.next = bit_cast::<TRIAL_BITS, PAIR_BITS>(
                    self.t_w.val() + ((self.m_w.val() << 1) | (self.m_w.val() >> 2)),
                );
                self.tlo_out.next = bit_cast::<TRIAL_BITS, PAIR_BITS>(
                    self.t_w.val() + ((self.m_w.val() << 1) | (self.m_w.val() >> 3)),
                );
                self.t3_out.next = bit_cast::<T3_BITS, PAIR_BITS>(
                    self.t3_w.val()
                        + ((self.m_w.val() << 2) | self.m_w.val() | (self.m_w.val() >> 1) | (self.m_w.val() >> 3)),
                );
            } else {
                self.rem_out.next = bit_cast::<REM_BITS, PAIR_BITS>(self.d2.val());
                self.x_out.next = self.x_in.val() | self.mask_in.val();
                // t + 5m/4; t + 9m/8; 3t + 3m/2 + 21m/8.
                self.trial_out.next =
                    bit_cast::<TRIAL_BITS, PAIR_BITS>(self.t_w.val() + (self.m_w.val() | (self.m_w.val() >> 2)));
                self.tlo_out.next =
                    bit_cast::<TRIAL_BITS, PAIR_BITS>(self.t_w.val() + (self.m_w.val() | (self.m_w.val() >> 3)));
                self.t3_out.next = bit_cast::<T3_BITS, PAIR_BITS>(
                    self.t3_w.val() + ((self.m_w.val() << 1) | (self.m_w.val() >> 1) | (self.m_w.val() >> 3)),
                );
            }
        } else if !self.d1.val().get_bit(69) {
            self.rem_out.next = bit_cast::<REM_BITS, PAIR_BITS>(self.d1.val());
            self.x_out.next = self.x_in.val() | (self.mask_in.val() >> 1);
            // t + m/4; t + m/8; 3t + 3m/2 − 3m/8.
            self.trial_out.next = bit_cast::<TRIAL_BITS, PAIR_BITS>(self.t_w.val() + (self.m_w.val() >> 2));
            self.tlo_out.next = bit_cast::<TRIAL_BITS, PAIR_BITS>(self.t_w.val() + (self.m_w.val() >> 3));
            self.t3_out.next = bit_cast::<T3_BITS, PAIR_BITS>(
                self.t3_w.val() - ((self.m_w.val() >> 2) | (self.m_w.val() >> 3)),
            );
        } else {
            self.rem_out.next = bit_cast::<REM_BITS, PAIR_BITS>(self.rem4.val());
            self.x_out.next = self.x_in.val();
            // t − 3m/4; t − 7m/8; 3t + 3m/2 − 27m/8.
            self.trial_out.next = bit_cast::<TRIAL_BITS, PAIR_BITS>(
                self.t_w.val() - ((self.m_w.val() >> 1) | (self.m_w.val() >> 2)),
            );
            self.tlo_out.next = bit_cast::<TRIAL_BITS, PAIR_BITS>(
                self.t_w.val() - ((self.m_w.val() >> 1) | (self.m_w.val() >> 2) | (self.m_w.val() >> 3)),
            );
            self.t3_out.next = bit_cast::<T3_BITS, PAIR_BITS>(
                self.t3_w.val()
                    - ((self.m_w.val() << 1) | self.m_w.val() | (self.m_w.val() >> 2) | (self.m_w.val() >> 3)),
            );
        }
    }
}

/// The iterative offset root with `R` digits per cycle (`R / 2` pairs; R even).
#[derive(LogicBlock)]
pub struct OffsetRoot<const R: usize> {
    pub clock: Signal<In, Clock>,
    pub start: Signal<In, Bit>,
    pub p: Signal<In, Bits<ROOT_P_BITS>>,
    pub c: Signal<In, Bits<ROOT_C_BITS>>,
    pub x: Signal<Out, Bits<ROOT_X_BITS>>,
    pub valid: Signal<Out, Bit>,
    pub busy: Signal<Out, Bit>,
    pairs: Vec<RootPair>,
    rem: DFF<Bits<REM_BITS>>,
    trial: DFF<Bits<TRIAL_BITS>>,
    tlo: DFF<Bits<TRIAL_BITS>>,
    t3: DFF<Bits<T3_BITS>>,
    /// 4p, 2p and 9·2^34 for the load's 3t + 3m/2 = 6p + 9·2^34, summed carry-save
    /// (one LUT level and one carry chain after `p`).
    ld_a: Signal<Local, Bits<T3_BITS>>,
    ld_b: Signal<Local, Bits<T3_BITS>>,
    ld_s: Signal<Local, Bits<T3_BITS>>,
    ld_c: Signal<Local, Bits<T3_BITS>>,
    c_t3_first: Constant<Bits<T3_BITS>>,
    c_tlo_first: Constant<Bits<TRIAL_BITS>>,
    mask: DFF<Bits<ROOT_X_BITS>>,
    acc: DFF<Bits<ROOT_X_BITS>>,
    clow: DFF<Bits<ROOT_X_BITS>>,
    c_first_mask: Constant<Bits<ROOT_X_BITS>>,
    ctl: Iterate,
}

impl<const R: usize> Default for OffsetRoot<R> {
    fn default() -> Self {
        assert!(R >= 2 && R % 2 == 0 && ROOT_X_BITS % R == 0, "OffsetRoot<{R}>: R must be even and divide {ROOT_X_BITS}");
        OffsetRoot {
            clock: Default::default(),
            start: Default::default(),
            p: Default::default(),
            c: Default::default(),
            x: Default::default(),
            valid: Default::default(),
            busy: Default::default(),
            pairs: (0..R / 2).map(|_| Default::default()).collect(),
            rem: Default::default(),
            trial: Default::default(),
            tlo: Default::default(),
            t3: Default::default(),
            ld_a: Default::default(),
            ld_b: Default::default(),
            ld_s: Default::default(),
            ld_c: Default::default(),
            c_t3_first: Constant::new((9u64 << 34).into()),
            c_tlo_first: Constant::new((1u64 << 34).into()),
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
        dff_setup!(self, clock, rem, trial, tlo, t3, mask, acc, clow);
        self.ctl.clock.next = self.clock.val();
        self.ctl.start.next = self.start.val();
        // The pair chain: pair 0 reads the registers, pair i reads pair i - 1.
        self.pairs[0].rem_in.next = self.rem.q.val();
        self.pairs[0].trial_in.next = self.trial.q.val();
        self.pairs[0].tlo_in.next = self.tlo.q.val();
        self.pairs[0].t3_in.next = self.t3.q.val();
        self.pairs[0].mask_in.next = self.mask.q.val();
        self.pairs[0].x_in.next = self.acc.q.val();
        self.pairs[0].c_in.next = self.clow.q.val();
        for i in 1..self.pairs.len() {
            self.pairs[i].rem_in.next = self.pairs[i - 1].rem_out.val();
            self.pairs[i].trial_in.next = self.pairs[i - 1].trial_out.val();
            self.pairs[i].tlo_in.next = self.pairs[i - 1].tlo_out.val();
            self.pairs[i].t3_in.next = self.pairs[i - 1].t3_out.val();
            self.pairs[i].mask_in.next = self.pairs[i - 1].mask_out.val();
            self.pairs[i].x_in.next = self.pairs[i - 1].x_out.val();
            self.pairs[i].c_in.next = self.pairs[i - 1].c_out.val();
        }
        self.x.next = self.acc.q.val();
        self.valid.next = self.ctl.valid.val();
        self.busy.next = self.ctl.busy.val();
        // The load's 3t + 3m/2 = 6p + 9·2^34 (t = 2p + 2^35, m = 2^35), carry-save.
        self.ld_a.next = bit_cast::<T3_BITS, ROOT_P_BITS>(self.p.val()) << 2;
        self.ld_b.next = bit_cast::<T3_BITS, ROOT_P_BITS>(self.p.val()) << 1;
        self.ld_s.next = self.ld_a.val() ^ self.ld_b.val() ^ self.c_t3_first.val();
        self.ld_c.next = ((self.ld_a.val() & self.ld_b.val())
            | (self.ld_a.val() & self.c_t3_first.val())
            | (self.ld_b.val() & self.c_t3_first.val()))
            << 1;
        if self.ctl.step.val() {
            // The last pair's outputs win: later assignments override earlier ones.
            for i in 0..self.pairs.len() {
                self.rem.d.next = self.pairs[i].rem_out.val();
                self.trial.d.next = self.pairs[i].trial_out.val();
                self.tlo.d.next = self.pairs[i].tlo_out.val();
                self.t3.d.next = self.pairs[i].t3_out.val();
                self.mask.d.next = self.pairs[i].mask_out.val();
                self.acc.d.next = self.pairs[i].x_out.val();
                self.clow.d.next = self.pairs[i].c_out.val();
            }
        } else if self.ctl.load.val() {
            // rem = c >> 36 (the first digit shifts in bit 35); trial = 2p + 2^35, with
            // t − m/2 = 2p + 2^34 and 3t + 3m/2 below.
            self.rem.d.next = bit_cast::<REM_BITS, 64>(self.c.val().get_bits::<64>(36));
            self.clow.d.next = self.c.val().get_bits::<ROOT_X_BITS>(0);
            self.trial.d.next =
                (bit_cast::<TRIAL_BITS, ROOT_P_BITS>(self.p.val()) << 1) + bit_cast::<TRIAL_BITS, ROOT_X_BITS>(self.c_first_mask.val());
            self.tlo.d.next = (bit_cast::<TRIAL_BITS, ROOT_P_BITS>(self.p.val()) << 1) + self.c_tlo_first.val();
            self.t3.d.next = self.ld_s.val() + self.ld_c.val();
            self.mask.d.next = self.c_first_mask.val();
            self.acc.d.next = 0.into();
        }
    }
}
