//! Bit-accurate integer model of the hardware period algorithm.
//!
//! For a valid segment (see [`Segment::validate`]) the core emits n step edges at
//! ticks `E_1 .. E_n` after the segment start, with `E_n = T` exactly, so segments
//! chain back to back with no gap and the error never accumulates. The periods
//! pushed into the axis FIFO are `Δ_i = E_i − E_{i−1}` (with `E_0 = 0`).
//!
//! # The algorithm (docs/model.md)
//! All time quantities carry [`TAU_FRAC_BITS`] = s fractional bits ("scaled ticks",
//! written with a prime). With `D·2^32 = n·2^32 − v0_rate·T`:
//!
//! * **Setup, once per segment** (two divides):
//!   `B' = round(T²·2^(32+2s) / |D·2^32|)` (= |B|·2^2s, B = T²/D ticks²/step) and
//!   `P' = round(v0_rate·T²·2^s / (2·|D·2^32|))` (= |P|·2^s, P = v0·B/2 ticks).
//! * **Per step** (an add and an integer square root):
//!   accelerate (D > 0): `A_i = P'² + i·B'`, `τ'_i = isqrt(A_i) − P'`,
//!   `E_i = ⌊τ'_i / 2^s + ½⌋ = (τ'_i + 2^(s−1)) >> s`, i.e. ⌊τ_i⌋ taken
//!   on τ_i + ½ so that the edge sits on the nearest tick;
//!   decelerate (D < 0): the same acceleration run backwards from the end speed,
//!   `P'` from v_end instead of v0 (`P' = round(v_end·T·T·2^s / (2|D·2^32|))`, 0 for a
//!   stop to rest), `A_i = P'² + (n − i)·B'`, `E_i = T − ((isqrt(A_i) − P' + 2^(s−1)) >> s)`.
//!   The hardware keeps `C_i = A_i − P'²` rather than A_i: an accumulator,
//!   `C_i = C_{i−1} ± B'` (0 when accelerating, `n·B'` when decelerating, one multiply
//!   at setup), and it computes `τ'_i = isqrt(P'² + C_i) − P'` directly by the
//!   [`offset_root`] recurrence: 36 digits on a 67-bit remainder, where `isqrt(A_i)`
//!   takes 64 digits. The result is the same integer. `E_n = T` is forced.
//!
//!   Why backwards: written forwards, `P'² − i·B'` is a small difference of two large
//!   rounded numbers near the end of a deceleration to rest, where ∂τ/∂P = 1 − P/S
//!   grows without bound as S → 0; half an LSB of P' became 0.4 ticks of edge error.
//!   Backwards, the deceleration has the acceleration's |∂τ/∂P| ≤ 1.
//! * **Uniform** (D = 0): `E_i = ⌊(2·i·T + n) / (2n)⌋`, a divide and a remainder
//!   (Bresenham). A segment whose `P' + 2T'` would not fit [`ROOT_BITS`] is nearly
//!   uniform (|D| tiny) and uses this path too; see the error bound below.
//!
//! # Widths
//! `S = isqrt(A) < 2^64` ([`ROOT_BITS`]), `A < 2^128`, `C = A − P'² < 2^100`
//! ([`ACC_BITS`]) and `τ' = S − P' < 2^36` ([`OFFSET_ROOT_BITS`]), for the whole documented
//! range (T ≤ 2^30, n ≤ 2^24, v0 < ½ step/tick): the sqrt path is taken only when
//! `P' + 2T' < 2^64`, and then `A ≤ (P' + T')² + n/2 < 2^128`. `B' < 2^101`,
//! `P' < 2^64`, `T' = T·2^s ≤ 2^34`. The uniform path needs `2·n·T < 2^56`.
//!
//! # Error bound (derived in docs/model.md, checked by the property tests)
//! Every edge is within [`EDGE_ERROR_BOUND_TICKS`] of the exact time. On the sqrt
//! path: ½ (nearest tick) + 1/16 (isqrt floor, one scaled LSB) + 1/32 (P' rounding,
//! |∂τ/∂P| = 1 − P/S ≤ 1) + 1/1536 (B' rounding: relative error ≤ 1/(2B'),
//! |B·∂τ/∂B| ≤ τ ≤ T, B' ≥ 2^8·T²/n, n/T ≤ 1/3) ≈ 0.595. On the nearly-uniform
//! fallback: ½ + T²/(8P) ≤ ½ + 1/8 (P ≥ 2^60 − 2^31 ticks, T ≤ 2^30). Uniform: ½.

use super::segment::{Segment, RATE_FRAC_BITS};

/// Fractional bits of the internal time τ' (scaled ticks): s.
pub const TAU_FRAC_BITS: u32 = 4;
/// Width of the square root's result: S < 2^ROOT_BITS.
pub const ROOT_BITS: u32 = 64;
/// Digits of the offset root: τ' = isqrt(P'² + C) − P' < 2^OFFSET_ROOT_BITS
/// (τ' ≤ T' + 1 ≤ 2^34 + 1 on the square-root paths).
pub const OFFSET_ROOT_BITS: u32 = 36;
/// Width of the accumulator C = A − P'² and of B': C, B' < 2^ACC_BITS on the
/// square-root paths (C ≤ 2P'T' + T'² + n/2 < 2^100).
pub const ACC_BITS: u32 = 100;

/// The offset root: `x = isqrt(p² + c) − p`, for `x < 2^OFFSET_ROOT_BITS`, by the
/// digit recurrence the hardware runs ([`crate::hdl::root`]), bit for bit.
///
/// Digit b (from `OFFSET_ROOT_BITS − 1` down to 0) keeps bit b of x when
/// `c − x² − 2px ≥ 2^b·(2p + 2x + 2^b)`, x holding the bits above b. Scaled by 2^−b,
/// the remainder `rem` stays below 2^67 (it is < 4(p + x) + 2^(b+2) and p + x < 2^64)
/// and the trial `2p + 2x + 2^b` below 2^66, so each digit is one 67-bit subtraction,
/// where `isqrt` of the 128-bit radicand would need 64 digits. Panics when the root
/// does not fit (x ≥ 2^OFFSET_ROOT_BITS) or c ≥ 2^ACC_BITS: the segment validation
/// rules both out (docs/model.md, "Widths").
pub fn offset_root(p: u64, c: u128) -> u64 {
    const L: u32 = OFFSET_ROOT_BITS;
    assert!(c < 1u128 << ACC_BITS, "offset root: C = {c} needs more than {ACC_BITS} bits");
    let p = p as u128;
    let mut rem = c >> L; // the bits above the first digit's
    let mut trial = 2 * p + (1u128 << (L - 1)); // 2p + 2x + 2^b with x = 0, b = L − 1
    let mut x = 0u128;
    for b in (0..L).rev() {
        let rem_sh = (rem << 1) | ((c >> b) & 1);
        debug_assert!(rem_sh < 1u128 << 67 && trial < 1u128 << 66);
        let half = if b > 0 { 1u128 << (b - 1) } else { 0 };
        if rem_sh >= trial {
            rem = rem_sh - trial;
            x |= 1 << b;
            trial = trial + (1 << b) + half;
        } else {
            rem = rem_sh;
            trial -= half;
        }
    }
    // rem = c − x² − 2px now; x + 1 must not fit, else the root has more digits.
    assert!(rem <= 2 * (p + x), "offset root: x ≥ 2^{L} (p = {p}, c = {c})");
    x as u64
}
/// Proven bound on |E_i − t_i| in ticks for every edge of a valid segment.
pub const EDGE_ERROR_BOUND_TICKS: f64 = 0.625;

/// How the hardware computes a segment's periods.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlanKind {
    /// n = 0: no steps, the axis waits T ticks.
    Dwell,
    /// D = 0, or |D| so small that P' + 2T' overflows the root width
    /// (`nearly` is then true): periods by divide and remainder.
    Uniform { nearly: bool },
    /// D > 0: τ = sqrt(P² + iB) − P.
    Accelerate,
    /// D < 0: τ_i = T − (sqrt(P² + (n−i)|B|) − P), P from the end speed.
    Decelerate,
}

/// The per-segment constants the scheduler computes at setup.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SegmentPlan {
    pub segment: Segment,
    pub kind: PlanKind,
    /// P' = v·B/2·2^s, rounded, with v = v0 accelerating and v = v_end
    /// decelerating (0 for uniform and dwell).
    pub p_scaled: u128,
    /// B' = |B|·2^2s, rounded (0 for uniform and dwell).
    pub b_scaled: u128,
}

/// Rounded quotient ⌊num/den + ½⌋, den > 0.
fn div_round(num: u128, den: u128) -> u128 {
    (num + den / 2) / den
}

impl SegmentPlan {
    /// Per-segment setup. The segment must be valid (see [`Segment::validate`]);
    /// the caller is expected to have validated it, so this only debug-asserts. A
    /// segment that rounds past rest is planned as its [`Segment::effective`] form.
    pub fn new(segment: Segment) -> SegmentPlan {
        let segment = segment.effective();
        let n = segment.n_steps() as u128;
        let t = segment.t_ticks as u128;
        debug_assert!(segment.t_ticks > 0 && segment.v_end_t_q32() >= 0);
        let mut plan = SegmentPlan { segment, kind: PlanKind::Dwell, p_scaled: 0, b_scaled: 0 };
        if n == 0 {
            return plan;
        }
        let d = segment.d_q32();
        if d == 0 {
            plan.kind = PlanKind::Uniform { nearly: false };
            return plan;
        }
        let d_mag = d.unsigned_abs();
        let s = TAU_FRAC_BITS;
        let t_sq = t * t;
        let p = Self::p_unbounded(&segment);
        if p + 2 * (t << s) >= 1u128 << ROOT_BITS {
            plan.kind = PlanKind::Uniform { nearly: true };
            return plan;
        }
        plan.p_scaled = p;
        plan.b_scaled = div_round(t_sq << (RATE_FRAC_BITS + 2 * s), d_mag);
        plan.kind = if d > 0 { PlanKind::Accelerate } else { PlanKind::Decelerate };
        // The hardware's accumulator C (and B' ≤ C_n) has ACC_BITS bits: C_n = n·B' is
        // its largest value (the decelerating start value).
        assert!(plan.b_scaled * n < 1u128 << ACC_BITS, "C_n = n·B' needs more than {ACC_BITS} bits: {plan:?}");
        plan
    }

    /// P' = round(v·T²·2^s / (2|D·2^32|)) before the width check, with v the slower
    /// end (v0 accelerating, v_end decelerating). The segment must have n > 0, D ≠ 0.
    /// The sqrt path is taken when `P' + 2T' < 2^ROOT_BITS`.
    pub fn p_unbounded(segment: &Segment) -> u128 {
        let t = segment.t_ticks as u128;
        let d = segment.d_q32();
        let v_t_sq = if d > 0 {
            (segment.v0_rate as u128) * t * t
        } else {
            (segment.v_end_t_q32() as u128) * t
        };
        div_round(v_t_sq << TAU_FRAC_BITS, 2 * d.unsigned_abs())
    }

    /// Number of steps n.
    pub fn n_steps(&self) -> u32 {
        self.segment.n_steps()
    }

    /// The accumulator C_i = A_i − P'² for step i (sqrt paths only): i·B'
    /// accelerating, (n − i)·B' decelerating. The hardware keeps C, not A: C < 2^ACC_BITS.
    pub fn accumulator(&self, i: u32) -> u128 {
        match self.kind {
            PlanKind::Accelerate => self.b_scaled * i as u128,
            PlanKind::Decelerate => self.b_scaled * (self.n_steps() - i) as u128,
            _ => 0,
        }
    }

    /// E_i from the accumulator C_i of step i (sqrt paths only):
    /// τ'_i = isqrt(P'² + C_i) − P', by [`offset_root`].
    fn edge_from_acc(&self, acc: u128) -> u64 {
        let tau_scaled = offset_root(self.p_scaled as u64, acc) as u128;
        let rounded = ((tau_scaled + (1 << (TAU_FRAC_BITS - 1))) >> TAU_FRAC_BITS) as u64;
        match self.kind {
            PlanKind::Accelerate => rounded,
            _ => self.segment.t_ticks as u64 - rounded,
        }
    }

    /// E_i, the tick of step i after the segment start, for 0 ≤ i ≤ n.
    /// Computed directly (not incrementally); equals what [`Self::periods`] sums to.
    pub fn edge(&self, i: u32) -> u64 {
        let n = self.n_steps();
        let t = self.segment.t_ticks as u64;
        assert!(i <= n, "step {i} beyond n = {n}");
        if i == 0 {
            return 0;
        }
        if i == n {
            return t;
        }
        match self.kind {
            PlanKind::Dwell => unreachable!("a dwell has no steps"),
            PlanKind::Uniform { .. } => (2 * i as u64 * t + n as u64) / (2 * n as u64),
            PlanKind::Accelerate | PlanKind::Decelerate => self.edge_from_acc(self.accumulator(i)),
        }
    }

    /// The periods Δ_1..Δ_n in ticks, computed the way the hardware does: the
    /// accumulator advances by B' each step and the uniform path carries a
    /// remainder; no per-step multiply.
    pub fn periods(&self) -> PeriodIter<'_> {
        let n = self.n_steps() as u64;
        let t = self.segment.t_ticks as u64;
        let acc = self.accumulator(0);
        // Uniform: E_i = ⌊(2iT + n)/(2n)⌋. Keep q = ⌊(2iT+n)/(2n)⌋ and r, the remainder,
        // and step both by 2T = q_step·2n + r_step.
        let (q_step, r_step) = if n > 0 { ((2 * t) / (2 * n), (2 * t) % (2 * n)) } else { (0, 0) };
        let (q0, r0) = if n > 0 { (n / (2 * n), n % (2 * n)) } else { (0, 0) };
        PeriodIter { plan: self, i: 0, prev_edge: 0, acc, q: q0, r: r0, q_step, r_step }
    }
}

/// Iterator over a segment's periods, see [`SegmentPlan::periods`].
pub struct PeriodIter<'a> {
    plan: &'a SegmentPlan,
    i: u32,
    prev_edge: u64,
    acc: u128,
    q: u64,
    r: u64,
    q_step: u64,
    r_step: u64,
}

impl Iterator for PeriodIter<'_> {
    type Item = u32;

    fn next(&mut self) -> Option<u32> {
        let plan = self.plan;
        let n = plan.n_steps();
        if self.i >= n {
            return None;
        }
        self.i += 1;
        let edge = match plan.kind {
            PlanKind::Dwell => unreachable!(),
            PlanKind::Uniform { .. } => {
                let two_n = 2 * n as u64;
                self.q += self.q_step;
                self.r += self.r_step;
                if self.r >= two_n {
                    self.r -= two_n;
                    self.q += 1;
                }
                self.q
            }
            PlanKind::Accelerate => {
                self.acc += plan.b_scaled;
                plan.edge_from_acc(self.acc)
            }
            PlanKind::Decelerate => {
                self.acc -= plan.b_scaled;
                plan.edge_from_acc(self.acc)
            }
        };
        // The last period is forced so that the segment sums to exactly T.
        let edge = if self.i == n { plan.segment.t_ticks as u64 } else { edge };
        let period = edge - self.prev_edge;
        self.prev_edge = edge;
        Some(u32::try_from(period).expect("a period never exceeds T <= 2^30"))
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        let left = (self.plan.n_steps() - self.i) as usize;
        (left, Some(left))
    }
}

impl ExactSizeIterator for PeriodIter<'_> {}
