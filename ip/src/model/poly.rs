//! Polynomial segments (S-curves): the position is a polynomial in time of degree
//! at most 4, given by Hermite data, and every step edge is the nearest tick to the
//! exact time, found by an exact integer search (docs/model.md, "Polynomial segments").
//!
//! # The form
//! A polynomial segment is five register values: start speed `v0_rate` and end speed
//! `v1_rate` (Q0.32 steps/tick, as the trapezoid's v0), duration `t_ticks` (T), signed
//! steps `steps` (θ, n = |θ|) and `a_q32` (A·2^32), where A = a0·T²/2 is the distance
//! the start acceleration a0 alone would add over the segment, in Q32 steps. With
//! u = t/T and V0 = v0_rate/2^32, V1 = v1_rate/2^32:
//!
//! ```text
//! x(t) = V0·t + A·u² + C·u³ + Q·u⁴,   x(T) = n,  x'(T) = V1
//! C = 4·Rn − Rv,  Q = Rv − 3·Rn,  Rn = n − V0·T − A,  Rv = (V1 − V0)·T − 2A
//! ```
//!
//! so a segment ends exactly at n steps in exactly T ticks at exactly its end speed,
//! and the next segment, whose v0 is this one's v1, joins with continuous speed. With
//! every value scaled by 2^32 the position is the integer polynomial
//! `N(t) = x(t)·T⁴·2^32 = v0_rate·T⁴·t + A'·T²·t² + C'·T·t³ + Q'·t⁴` (primes: ×2^32,
//! all exact integers). Q' = 0 is a cubic (constant jerk): [`PolySegment::cubic`]
//! chooses `A' = 3n·2^32 − (2·v0_rate + v1_rate)·T`, the one start acceleration that
//! makes it so. Q' ≠ 0 is a quartic (constant snap), whose a0 the host gives.
//!
//! # The edge
//! Step i (1 ≤ i < n) is at `E_i = max{e ≤ T − 1 : x(e − ½) ≤ i}`, the nearest tick to
//! the exact time t_i (|E_i − t_i| ≤ ½); `E_n = T`. In integers: with
//! `M(e) = 16·N(e − ½)` (an integer polynomial in e) and the step scale
//! `S = 16·2^32·T⁴`, `E_i` is the largest e ≤ T − 1 with `M(e) ≤ i·S`. The core finds
//! it by a binary search, digit b = 24 down to 0 (T ≤ 2^24), from the previous edge (E_0 = 0),
//! on the Taylor words `W_k = m_k·2^(k·b)` (m_k the Taylor coefficients of M at the
//! current e): a trial is `W1 + W2 + W3 + W4 = M(e + 2^b) − M(e)`, an accepted digit
//! shifts the words (`W1 += 2·W2 + 3·W3 + 4·W4`, `W2 += 3·W3 + 6·W4`, `W3 += 4·W4`) and
//! every digit halves h (`W_k >>= k`, exact). Only adds, subtracts and fixed shifts:
//! no multiply, no divide, no rounding. [`PolyPlan`] is that search, bit for bit.
//!
//! # Validation
//! [`PolySegment::validate`]: the range (T ≤ [`POLY_MAX_T_TICKS`], |θ| ≤ 2^24, both
//! rates ≤ 2^31 − 1), then the speed's Bernstein control points: with
//! `p(u) = v(t)·T·2^32 = p0 + p1·u + p2·u² + p3·u³` (p0 = v0_rate·T, p1 = 2A',
//! p2 = 3C', p3 = 4Q'), the control points are `β_k/3` with β0 = 3p0, β1 = 3p0 + p1,
//! β2 = 3p0 + 2p1 + p2, β3 = 3·v1_rate·T. The speed lies in the hull of its control
//! points, so `0 ≤ β_k` (else REVERSES) and `β_k ≤ 3·RMAX·T` and both rates ≤ RMAX
//! (else PERIOD_TOO_SHORT) keep the speed within [0, RMAX/2^32] everywhere in the
//! segment, an interior peak included. The check is exact when the speed is a
//! monotone quadratic (every cubic of a jerk-limited profile) and otherwise
//! conservative by at most T²·|jerk|max/18 steps/tick (docs/model.md).

use super::segment::{check_range, Limits, SegmentError, RATE_FRAC_BITS};
use ethnum::I256;
use serde::{Deserialize, Serialize};

/// log2 of the longest polynomial segment.
pub const POLY_T_LOG2: u32 = 24;
/// Longest polynomial segment: 2^24 ticks (168 ms at 100 MHz, 336 ms at 50 MHz).
pub const POLY_MAX_T_TICKS: u32 = 1 << POLY_T_LOG2;
/// The search's top digit: h = 2^b for b = POLY_TOP_DIGIT down to 0 (25 digits).
pub const POLY_TOP_DIGIT: u32 = POLY_T_LOG2;
/// Width of the search's signed words (the Taylor words W_k, the remainder R and
/// every trial): |value| < 2^(POLY_WORD_BITS − 1) over the documented range. The
/// property tests check the largest word seen against it.
pub const POLY_WORD_BITS: u32 = 160;
/// Signed widths (sign included) of the coefficients c_1..c_4 of N
/// ([`PolySegment::n_coefficients`]) over the documented range, the setup's products:
/// c1 = v0·T⁴ < 2^127; |c2| = |A'|·T² < 2^104 and |c3| = |C'|·T < 2^81 and
/// |c4| = |Q'| < 2^57, since validation's control points bound |A'| ≤ 1.5·RMAX·T,
/// |C'| ≤ 4·RMAX·T and |Q'| ≤ 4·RMAX·T with RMAX < 2^31 and T ≤ 2^24 (docs/model.md,
/// "The core's setup"). The property tests check every segment they run against them.
pub const POLY_COEFF_BITS: [u32; 4] = [128, 105, 82, 58];
/// Every edge of a polynomial segment is within this many ticks of exact time.
pub const POLY_EDGE_ERROR_BOUND_TICKS: f64 = 0.5;

/// The galloping search's first digit after a period of `delta` ticks: ⌊log2 Δ⌋,
/// at most [`POLY_TOP_DIGIT`] (0 before the first step, Δ = 0).
pub fn gallop_start(delta: u32) -> u32 {
    if delta == 0 {
        0
    } else {
        (31 - delta.leading_zeros()).min(POLY_TOP_DIGIT)
    }
}

/// What one galloping search did: digits visited (each a trial, or none when it
/// would pass the cap), trials made, trials passed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct GallopStats {
    pub digits: u32,
    pub trials: u32,
    pub passes: u32,
}

impl GallopStats {
    /// The cycles the core's unit ([`crate::hdl::poly_step::PolyStep`]) takes for this
    /// search started from digit `b_start`, from its start to `done`:
    /// `1 + b_start + 2·digits + 2·trials + 4·passes`.
    pub fn unit_cycles(&self, b_start: u32) -> u32 {
        1 + b_start + 2 * self.digits + 2 * self.trials + 4 * self.passes
    }
}

/// One polynomial segment of one axis, in register units.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct PolySegment {
    /// Start speed, Q0.32 steps per tick.
    pub v0_rate: u32,
    /// End speed, Q0.32 steps per tick.
    pub v1_rate: u32,
    /// A·2^32 with A = a0·T²/2 (steps): the start acceleration's share of the distance.
    pub a_q32: i64,
    /// Duration in clock ticks.
    pub t_ticks: u32,
    /// Signed step count θ; the sign gives the direction.
    pub steps: i32,
}

fn w(v: i128) -> I256 {
    I256::from(v)
}

impl PolySegment {
    /// A segment from its five register values.
    pub const fn new(v0_rate: u32, v1_rate: u32, a_q32: i64, t_ticks: u32, steps: i32) -> PolySegment {
        PolySegment { v0_rate, v1_rate, a_q32, t_ticks, steps }
    }

    /// The cubic (constant jerk) through the Hermite data: A' = 3n·2^32 − (2·v0 + v1)·T,
    /// so Q' = 0. None when A' does not fit the register (never within the range).
    pub fn cubic(v0_rate: u32, v1_rate: u32, t_ticks: u32, steps: i32) -> Option<PolySegment> {
        let n = steps.unsigned_abs() as i128;
        let a = 3 * (n << RATE_FRAC_BITS) - (2 * v0_rate as i128 + v1_rate as i128) * t_ticks as i128;
        let a = i64::try_from(a).ok()?;
        Some(PolySegment::new(v0_rate, v1_rate, a, t_ticks, steps))
    }

    /// n = |θ|.
    pub fn n_steps(&self) -> u32 {
        self.steps.unsigned_abs()
    }

    /// True when the segment steps in the negative direction.
    pub fn reverse(&self) -> bool {
        self.steps < 0
    }

    /// (C', Q'): the cubic and quartic coefficients of x in u, ×2^32. Exact.
    pub fn hermite_q32(&self) -> (i128, i128) {
        let t = self.t_ticks as i128;
        let a = self.a_q32 as i128;
        let rn = ((self.n_steps() as i128) << RATE_FRAC_BITS) - self.v0_rate as i128 * t - a;
        let rv = (self.v1_rate as i128 - self.v0_rate as i128) * t - 2 * a;
        (4 * rn - rv, rv - 3 * rn)
    }

    /// 3 for a cubic (Q' = 0, C' ≠ 0), 4 for a quartic, less for lower degrees.
    pub fn degree(&self) -> u32 {
        let (c, q) = self.hermite_q32();
        if q != 0 {
            4
        } else if c != 0 {
            3
        } else if self.a_q32 != 0 {
            2
        } else if self.v0_rate != 0 {
            1
        } else {
            0
        }
    }

    /// The coefficients c_1..c_4 of N(t) = x(t)·T⁴·2^32 = Σ c_k·t^k (c_0 = 0).
    pub fn n_coefficients(&self) -> [I256; 4] {
        let t = w(self.t_ticks as i128);
        let (c, q) = self.hermite_q32();
        let t2 = t * t;
        [w(self.v0_rate as i128) * t2 * t2, w(self.a_q32 as i128) * t2, w(c) * t, w(q)]
    }

    /// N(num/2^s)·2^(4s): the position at the rational time num/2^s ticks, scaled by
    /// T⁴·2^32·2^(4s). Exact (s ≤ 24 and |num| ≤ 2^46 keep it below 2^255).
    pub fn position_scaled(&self, num: i128, s: u32) -> I256 {
        let c = self.n_coefficients();
        let x = w(num);
        // Horner on Σ c_k·num^k·2^(s(4−k)).
        let mut acc = c[3];
        for k in (0..3).rev() {
            acc = acc * x + (c[k] << (s * (3 - k as u32)));
        }
        acc * x
    }

    /// i·T⁴·2^32·2^(4s): step i on the scale of [`Self::position_scaled`].
    pub fn step_scaled(&self, i: u32, s: u32) -> I256 {
        let t = w(self.t_ticks as i128);
        (w(i as i128) * t * t * t * t) << (RATE_FRAC_BITS + 4 * s)
    }

    /// The speed's Bernstein control points ×3 on the scale v·T·2^32:
    /// [β0, β1, β2, β3] (see the module text).
    pub fn speed_bernstein3(&self) -> [i128; 4] {
        let (c, q) = self.hermite_q32();
        let p0 = self.v0_rate as i128 * self.t_ticks as i128;
        let p1 = 2 * self.a_q32 as i128;
        let p2 = 3 * c;
        let p3 = 4 * q;
        let b3 = 3 * (p0 + p1 + p2 + p3);
        debug_assert_eq!(b3, 3 * self.v1_rate as i128 * self.t_ticks as i128);
        [3 * p0, 3 * p0 + p1, 3 * p0 + 2 * p1 + p2, b3]
    }

    /// Checks the segment against the documented range and the limits, in this order:
    /// T = 0, T range, steps range, rate range (either end), reversal (a speed control
    /// point below 0), minimum period (either rate above RMAX or a control point above
    /// it). A dwell (n = 0, v0 = v1 = 0, A = 0) is valid; any other n = 0 segment has a
    /// negative control point (its speed integrates to 0 without being 0).
    pub fn validate(&self, limits: &Limits) -> Result<(), SegmentError> {
        check_range(self.t_ticks, POLY_MAX_T_TICKS, self.n_steps(), self.v0_rate.max(self.v1_rate))?;
        let b = self.speed_bernstein3();
        if b[1] < 0 || b[2] < 0 {
            return Err(SegmentError::Reverses);
        }
        let rmax = limits.max_rate() as i128;
        let hull_max = 3 * rmax * self.t_ticks as i128;
        if self.v0_rate as i128 > rmax || self.v1_rate as i128 > rmax || b[1] > hull_max || b[2] > hull_max {
            return Err(SegmentError::PeriodTooShort);
        }
        Ok(())
    }

    /// Speed (steps/tick), acceleration (steps/tick²) and jerk (steps/tick³) at t ticks.
    pub fn derivatives_at(&self, t_ticks: f64) -> (f64, f64, f64) {
        let t = self.t_ticks as f64;
        let q32 = (1u64 << RATE_FRAC_BITS) as f64;
        let (c, q) = self.hermite_q32();
        let (a, c, q) = (self.a_q32 as f64 / q32, c as f64 / q32, q as f64 / q32);
        let u = t_ticks / t;
        let v = self.v0_rate as f64 / q32 + (2.0 * a * u + 3.0 * c * u * u + 4.0 * q * u * u * u) / t;
        let acc = (2.0 * a + 6.0 * c * u + 12.0 * q * u * u) / (t * t);
        let jerk = (6.0 * c + 24.0 * q * u) / (t * t * t);
        (v, acc, jerk)
    }

    /// Exactly decides |tick − t_i| ≤ tol_eighths/8 ticks for step i (1 ≤ i ≤ n) of a
    /// valid segment: x is nondecreasing on [0, T], so it holds iff
    /// x(lo) ≤ i ≤ x(hi) with lo, hi = tick ∓ tol clamped to [0, T].
    pub fn edge_within(&self, i: u32, tick: i64, tol_eighths: i64) -> bool {
        let t8 = 8 * self.t_ticks as i128;
        let lo = (8 * tick as i128 - tol_eighths as i128).max(0);
        let hi = (8 * tick as i128 + tol_eighths as i128).min(t8);
        if lo > hi {
            return false;
        }
        let target = self.step_scaled(i, 3);
        self.position_scaled(lo, 3) <= target && target <= self.position_scaled(hi, 3)
    }

    /// The exact time of step i (1 ≤ i ≤ n), in ticks after the segment start, to
    /// within 2^−20 tick: bisection with exact comparisons on [E_i − 1, E_i + 1]
    /// (clamped to [0, T]), where `edge` is the nearest tick (within ½ of it).
    pub fn step_time_near(&self, i: u32, edge: u32) -> f64 {
        const S: u32 = 20;
        let target = self.step_scaled(i, S);
        let mut lo = ((edge as i128 - 1) << S).max(0);
        let mut hi = ((edge as i128 + 1) << S).min((self.t_ticks as i128) << S);
        // Invariant: x(lo) ≤ i ≤ x(hi) (x nondecreasing on [0, T]).
        while hi - lo > 1 {
            let mid = (lo + hi) / 2;
            if self.position_scaled(mid, S) < target {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        (lo + hi) as f64 / 2.0 / (1u64 << S) as f64
    }

    /// E_i by its definition, without the search: the largest e ≤ T − 1 with
    /// x(e − ½) ≤ i, by bisection on exact evaluations (E_n = T). For the tests.
    pub fn edge_by_definition(&self, i: u32) -> u32 {
        let n = self.n_steps();
        assert!(i >= 1 && i <= n);
        if i == n {
            return self.t_ticks;
        }
        let target = self.step_scaled(i, 1);
        let ok = |e: u32| self.position_scaled(2 * e as i128 - 1, 1) <= target;
        // ok(0) holds (x(−½) < 1 ≤ i for a valid segment); find the last ok e.
        let (mut lo, mut hi) = (0u32, self.t_ticks); // ok(lo), !ok(hi) (x(T − ½) > n − 1)
        debug_assert!(ok(0) && !ok(self.t_ticks));
        while hi - lo > 1 {
            let mid = lo + (hi - lo) / 2;
            if ok(mid) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        lo
    }
}

/// The per-segment constants of the search (the core's setup): the step scale S and
/// the Taylor coefficients of M at e = 0.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PolyPlan {
    pub segment: PolySegment,
    /// S = 16·2^32·T⁴, the distance of one step on M's scale.
    pub step: I256,
    /// M(0) = 16·N(−½).
    pub m0: I256,
    /// m_1..m_4: M's Taylor coefficients at e = 0.
    pub taylor: [I256; 4],
}

impl PolyPlan {
    /// Setup, once per segment (the segment must be valid).
    ///
    /// With N = Σ c_k t^k: M(0) = −8c1 + 4c2 − 2c3 + c4, m1 = 16c1 − 16c2 + 12c3 − 8c4,
    /// m2 = 16c2 − 24c3 + 24c4, m3 = 16c3 − 32c4, m4 = 16c4.
    pub fn new(segment: PolySegment) -> PolyPlan {
        let [c1, c2, c3, c4] = segment.n_coefficients();
        let k = |v: i128| I256::from(v);
        let t = k(segment.t_ticks as i128);
        PolyPlan {
            segment,
            step: (t * t * t * t) << (RATE_FRAC_BITS + 4),
            m0: k(-8) * c1 + k(4) * c2 - k(2) * c3 + c4,
            taylor: [
                k(16) * c1 - k(16) * c2 + k(12) * c3 - k(8) * c4,
                k(16) * c2 - k(24) * c3 + k(24) * c4,
                k(16) * c3 - k(32) * c4,
                k(16) * c4,
            ],
        }
    }

    /// The search from step 1: the state the core keeps per axis between steps.
    pub fn search(&self) -> PolySearch {
        PolySearch {
            plan: *self,
            i: 0,
            base: 0,
            rem: -self.m0,
            taylor: self.taylor,
            widest_bits: 0,
        }
    }

    /// The search resumed after step i (0 ≤ i < n) whose edge is `edge` (E_i): the
    /// state computed directly from the polynomial, m_k(e) = Σ_{j≥k} C(j,k)·μ_j·e^(j−k)
    /// with μ_j the coefficients of M in e. For sampled checks of long segments.
    pub fn search_after(&self, i: u32, edge: u32) -> PolySearch {
        let mu = [self.m0, self.taylor[0], self.taylor[1], self.taylor[2], self.taylor[3]];
        let e = I256::from(edge as i128);
        const BINOM: [[i128; 5]; 5] =
            [[1, 0, 0, 0, 0], [1, 1, 0, 0, 0], [1, 2, 1, 0, 0], [1, 3, 3, 1, 0], [1, 4, 6, 4, 1]];
        let mut at = [I256::ZERO; 5];
        for (k, slot) in at.iter_mut().enumerate() {
            let mut pow = I256::ONE;
            for (j, &m) in mu.iter().enumerate().skip(k) {
                *slot += I256::from(BINOM[j][k]) * m * pow;
                pow *= e;
            }
        }
        let mut s = self.search();
        s.i = i;
        s.base = edge;
        s.rem = I256::from(i as i128) * self.step - at[0];
        s.taylor = [at[1], at[2], at[3], at[4]];
        s
    }

    /// The setup's words: `g = [8·c1, 4·c2, 2·c3, c4]`, the Taylor words of
    /// 16·N at t = 0 on the half-tick scale (g_k = 16·c_k·(½)^k). All the core's
    /// setup multiplies for (with S = 2^36·T⁴).
    pub fn setup_words(&self) -> [I256; 4] {
        let [c1, c2, c3, c4] = self.segment.n_coefficients();
        [c1 << 3, c2 << 2, c3 << 1, c4]
    }

    /// The search state the core's unit starts a segment from: step 0 at base 1,
    /// reached from [`Self::setup_words`] by one trial at h = ½ tick taken whatever
    /// its verdict (the trial is 16·N(½) = M(1), so Q = ¬(−M(1)) = M(1) − 1, and the
    /// Taylor update moves the words to t = ½, that is e = 1) and one climb (W_k <<= k:
    /// scale ½ tick to 1 tick). Only adds and fixed shifts after the products. The
    /// first edge is found from there: E_1 ≥ 1 always (x(½) ≤ RMAX/2 < 1), and M is
    /// monotone from e = 1 on, so the search gives the same edges as from e = 0.
    pub fn setup_state(&self) -> PolySearch {
        let mut w = self.setup_words();
        let trial = trial_of(&w);
        taylor_shift(&mut w);
        let mut s = self.search();
        s.i = 0;
        s.base = 1;
        s.rem = -trial;
        s.taylor = scaled(w, 1, true);
        s
    }

    /// The edges E_1..E_n, by the search.
    pub fn edges(&self) -> Vec<u32> {
        let mut s = self.search();
        std::iter::from_fn(|| s.next_edge()).collect()
    }
}

/// The search between steps: what the core keeps per axis (`base` = E_{i}, `rem` =
/// i·S − M(base), the Taylor coefficients at `base`), and the widest word it has held
/// (the tests check it against [`POLY_WORD_BITS`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PolySearch {
    pub plan: PolyPlan,
    /// Steps done.
    pub i: u32,
    /// E_i, the tick of the last edge (0 before step 1).
    pub base: u32,
    /// i·S − M(base): the target of the last step minus M at its edge (≥ 0).
    pub rem: I256,
    /// m_1..m_4 at `base`.
    pub taylor: [I256; 4],
    /// The widest signed word the search has held, in bits (sign included).
    pub widest_bits: u32,
}

/// A trial: the four Taylor words' sum, M(e + h) − M(e) at scale h.
fn trial_of(w: &[I256; 4]) -> I256 {
    w[0] + w[1] + w[2] + w[3]
}

/// The Taylor words moved on by one h (at the same scale): `W1 += 2W2 + 3W3 + 4W4`,
/// `W2 += 3W3 + 6W4`, `W3 += 4W4`.
fn taylor_shift(w: &mut [I256; 4]) {
    let [w1, w2, w3, w4] = *w;
    w[0] = w1 + (w2 << 1) + w3 + (w3 << 1) + (w4 << 2);
    w[1] = w2 + w3 + (w3 << 1) + (w4 << 2) + (w4 << 1);
    w[2] = w3 + (w4 << 2);
}

/// The words `d` digits up (`W_k << k·d`) or down (`W_k >> k·d`, exact where the
/// search uses it: W_k has the factor 2^(k·b) there).
fn scaled(w: [I256; 4], d: u32, up: bool) -> [I256; 4] {
    std::array::from_fn(|k| if up { w[k] << ((k as u32 + 1) * d) } else { w[k] >> ((k as u32 + 1) * d) })
}

/// What a step of the search starts from (see [`PolySearch::begin`]).
enum Next {
    /// Every step is done.
    Done,
    /// The last step: E_n = T, no search.
    Last,
    /// Search with this target remainder R = i·S − M(base).
    Search(I256),
}

/// Bits of a signed value, sign included (two's complement width).
pub fn signed_bits(v: I256) -> u32 {
    let mag = if v < 0 { !v } else { v };
    257 - mag.leading_zeros()
}

impl PolySearch {
    fn note(&mut self, v: I256) {
        self.widest_bits = self.widest_bits.max(signed_bits(v));
    }

    /// Counts the next step in and says what it needs: nothing after step n, no
    /// search for step n (E_n = T), else the search's target remainder.
    fn begin(&mut self) -> Next {
        let seg = self.plan.segment;
        if self.i >= seg.n_steps() {
            return Next::Done;
        }
        self.i += 1;
        if self.i == seg.n_steps() {
            self.base = seg.t_ticks;
            return Next::Last;
        }
        // Target i·S: R = i·S − M(base).
        let r = self.rem + self.plan.step;
        self.note(r);
        Next::Search(r)
    }

    /// One digit at h = 2^b: None when e + h would pass the cap (no trial), else
    /// whether the trial passed (then R, e and the words have moved on by h).
    fn digit(&mut self, w: &mut [I256; 4], r: &mut I256, e: &mut u32, b: u32) -> Option<bool> {
        if *e as u64 + (1u64 << b) > self.plan.segment.t_ticks as u64 - 1 {
            return None;
        }
        let trial = trial_of(w);
        self.note(trial);
        if trial > *r {
            return Some(false);
        }
        *r -= trial;
        *e += 1 << b;
        taylor_shift(w);
        for v in [*r, w[0], w[1], w[2]] {
            self.note(v);
        }
        Some(true)
    }

    /// Keeps the state at the edge found, and checks the widths.
    fn end(&mut self, w: [I256; 4], r: I256, e: u32) -> u32 {
        self.taylor = w;
        self.rem = r;
        self.base = e;
        assert!(
            self.widest_bits <= POLY_WORD_BITS,
            "poly search word of {} bits exceeds {POLY_WORD_BITS}: {:?}",
            self.widest_bits,
            self.plan.segment
        );
        e
    }

    /// The next edge E_{i+1} (ticks after the segment start), or None after step n.
    pub fn next_edge(&mut self) -> Option<u32> {
        let mut r = match self.begin() {
            Next::Done => return None,
            Next::Last => return Some(self.base),
            Next::Search(r) => r,
        };
        let mut e = self.base;
        let mut w = scaled(self.taylor, POLY_TOP_DIGIT, true);
        for v in w {
            self.note(v);
        }
        for b in (0..=POLY_TOP_DIGIT).rev() {
            self.digit(&mut w, &mut r, &mut e, b);
            if b > 0 {
                debug_assert!(w[0] % 2 == 0 && w[1] % 4 == 0 && w[2] % 8 == 0 && w[3] % 16 == 0);
                w = scaled(w, 1, false);
            }
        }
        Some(self.end(w, r, e))
    }

    /// The next edge by a galloping search, as the core's polynomial unit does it:
    /// the words go up from scale 1 to scale 2^`b_start` (W_k <<= k, exact), then
    /// trials at h = 2^b with b rising after each accepted one (exponential), and
    /// once one fails or passes the cap, b falls to 0 as in [`Self::next_edge`]
    /// (binary). The unit starts at b_start = ⌊log2 Δ⌋ of the previous period Δ, so
    /// a step near the last one's period takes about log2 Δ trials instead of 25.
    /// The predicate `M(e) ≤ i·S` is monotone from the base on (the speed is ≥ 0
    /// inside a valid segment), so both searches find the same edge; the state after
    /// it (remainder and Taylor words at the edge) depends on the edge alone, so it
    /// equals [`Self::next_edge`]'s too. Returns the edge and what the search did.
    pub fn next_edge_galloping(&mut self, b_start: u32) -> Option<(u32, GallopStats)> {
        let mut r = match self.begin() {
            Next::Done => return None,
            Next::Last => return Some((self.base, GallopStats::default())),
            Next::Search(r) => r,
        };
        assert!(b_start <= POLY_TOP_DIGIT, "b_start {b_start} above the top digit");
        let mut e = self.base;
        let mut b = b_start;
        let mut w = scaled(self.taylor, b, true);
        let mut rising = true;
        let mut stats = GallopStats::default();
        loop {
            stats.digits += 1;
            let verdict = self.digit(&mut w, &mut r, &mut e, b);
            stats.trials += verdict.is_some() as u32;
            let passed = verdict == Some(true);
            stats.passes += passed as u32;
            if rising && passed && b < POLY_TOP_DIGIT {
                b += 1;
                w = scaled(w, 1, true);
                for v in w {
                    self.note(v);
                }
                continue;
            }
            rising = false;
            if b == 0 {
                break;
            }
            b -= 1;
            w = scaled(w, 1, false);
        }
        Some((self.end(w, r, e), stats))
    }
}

/// The corners of the documented range, for the width checks (here and in the
/// hardware's tests): for each T in `ts`, every speed control point at 0 or RMAX
/// (16 segments; n and A rounded, A pulled in by 2^30 at a time where the rounding
/// leaves a control point out), the valid ones with at least one step. There the
/// search's words and the setup's products come within a few bits of their widths.
pub fn corner_segments(limits: &Limits, ts: &[u32]) -> Vec<PolySegment> {
    let rmax = limits.max_rate() as i128;
    let mut v = Vec::new();
    for &t in ts {
        for bits in 0u32..16 {
            let b: Vec<i128> = (0..4).map(|k| if bits >> k & 1 == 1 { rmax } else { 0 }).collect();
            let tt = t as i128;
            let n = ((b.iter().sum::<i128>() * tt + (1 << 33)) >> 34) as i32;
            let a = (3 * (b[1] - b[0]) * tt / 2) as i64;
            let mut seg = PolySegment::new(b[0] as u32, b[3] as u32, a, t, n);
            for _ in 0..64 {
                if seg.validate(limits).is_ok() {
                    break;
                }
                seg.a_q32 -= seg.a_q32.signum() * (1 << 30);
            }
            if seg.validate(limits).is_ok() && seg.n_steps() > 0 {
                v.push(seg);
            }
        }
    }
    v
}
