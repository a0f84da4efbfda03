//! Polynomial push check: the validation of a polynomial (S-curve) segment, with the
//! model's rules and codes ([`crate::model::PolySegment::validate`], bit for bit), in
//! the bus clock. A leaf of the push path: the segment's five fields in, its error code
//! out ([`crate::model::SegmentError::code`], 0 when valid), a fixed number of cycles
//! later.
//!
//! The rules, in the model's order: T = 0 (1), T above 2^24 (4), |θ| above 2^24 (5),
//! either rate above 2^31 − 1 (6); then the speed's Bernstein control points
//! (docs/model.md, "Validation"): with p0 = v0·T,
//! `β1 = 3·v0·T + 2A'` and `β2 = 12n·2^32 − 6·v0·T − 3·v1·T − 2A'`, a negative one
//! reverses (2), and either rate above RMAX or a control point above `3·RMAX·T` is
//! too fast (3). Within the range, |β| < 2^65 (|2A'| ≤ 2^64, the products below 2^58),
//! so 68-bit two's complement holds every sum; outside it the range's code wins
//! whatever the sums.
//!
//! Pipeline (one segment in flight; latency [`POLY_CHECK_LATENCY`] = 6 cycles):
//! * edge 0 registers the fields (`in_valid`, `in_v0`, `in_v1`, `in_a`, `in_t`,
//!   `in_steps`);
//! * cycle 1: v0·T, v1·T and RMAX·T go into three [`MulReg`]s (DSP multipliers);
//!   the range code, the rates' RMAX test, 2A' and `12n·2^32 − 2A'` are registered;
//! * cycle 3: the products arrive; β1 (three terms), `6·v0·T + 3·v1·T` (four) and
//!   the hull `3·RMAX·T` (two) are registered, each one carry chain after a
//!   carry-save stage;
//! * cycle 4: β2 by one subtraction, β1's two compares, registered;
//! * cycle 5: β2's compares and the code, in the model's order, registered;
//! * cycle 6: `out_valid` (one cycle) with `out_code`.
//!
//! `busy` is 1 from cycle 1 to cycle 5: a segment offered then is ignored. `reset`
//! (synchronous) drops the segment in flight.

use super::mul_wide::MulReg;
use crate::model::poly::POLY_MAX_T_TICKS;
use crate::model::{Limits, MAX_STEPS, MAX_V0_RATE};
use rust_hdl::prelude::*;

/// Cycles from `in_valid` to `out_valid`.
pub use crate::latency::POLY_CHECK_LATENCY;

/// Width of the control-point sums (two's complement).
const B: usize = 68;
// The sign tests read bit 67 by a literal index (rust-hdl writes a Rust constant's
// name into the Verilog).
const _: () = assert!(B == 68);

#[derive(LogicBlock)]
pub struct PolyCheck {
    pub clock: Signal<In, Clock>,
    pub reset: Signal<In, Bit>,
    pub in_valid: Signal<In, Bit>,
    /// v0 and v1 (Q0.32 steps/tick), A' = A·2^32 (two's complement), T (ticks), θ
    /// (two's complement): [`crate::model::PolySegment`]'s fields.
    pub in_v0: Signal<In, Bits<32>>,
    pub in_v1: Signal<In, Bits<32>>,
    pub in_a: Signal<In, Bits<64>>,
    pub in_t: Signal<In, Bits<32>>,
    pub in_steps: Signal<In, Bits<32>>,
    pub busy: Signal<Out, Bit>,
    pub out_valid: Signal<Out, Bit>,
    pub out_code: Signal<Out, Bits<4>>,
    s1: DFF<Bit>,
    s2: DFF<Bit>,
    s3: DFF<Bit>,
    s4: DFF<Bit>,
    s5: DFF<Bit>,
    s6: DFF<Bit>,
    v0: DFF<Bits<32>>,
    v1: DFF<Bits<32>>,
    a: DFF<Bits<64>>,
    t: DFF<Bits<32>>,
    steps: DFF<Bits<32>>,
    /// The first failing range check's code (1, 4, 5, 6), or 0; either rate above RMAX.
    rcode: DFF<Bits<4>>,
    fast_rate: DFF<Bit>,
    /// 2A' and 12n·2^32 − 2A' (68-bit two's complement).
    a2: DFF<Bits<B>>,
    k1: DFF<Bits<B>>,
    beta1: DFF<Bits<B>>,
    /// 6·v0·T + 3·v1·T, then β2 = k1 − that.
    s6v: DFF<Bits<B>>,
    beta2: DFF<Bits<B>>,
    hull: DFF<Bits<B>>,
    neg1: DFF<Bit>,
    big1: DFF<Bit>,
    code: DFF<Bits<4>>,
    mul_v0: MulReg<32, 32, 64>,
    mul_v1: MulReg<32, 32, 64>,
    mul_r: MulReg<32, 32, 64>,
    c_rmax: Constant<Bits<32>>,
    c_max_t: Constant<Bits<32>>,
    c_max_n: Constant<Bits<32>>,
    c_max_rate: Constant<Bits<32>>,
    /// Bits 67..64: A's sign extension.
    c_sx: Constant<Bits<B>>,
    n: Signal<Local, Bits<32>>,
    sx: Signal<Local, Bits<B>>,
    a68: Signal<Local, Bits<B>>,
    n68: Signal<Local, Bits<B>>,
    pv0: Signal<Local, Bits<B>>,
    pv1: Signal<Local, Bits<B>>,
    pr: Signal<Local, Bits<B>>,
    neg2: Signal<Local, Bit>,
    big2: Signal<Local, Bit>,
    busy_now: Signal<Local, Bit>,
    take: Signal<Local, Bit>,
}

impl PolyCheck {
    /// The check for a core with these limits (RMAX = [`Limits::max_rate`]).
    pub fn new(limits: Limits) -> Self {
        PolyCheck {
            clock: Default::default(),
            reset: Default::default(),
            in_valid: Default::default(),
            in_v0: Default::default(),
            in_v1: Default::default(),
            in_a: Default::default(),
            in_t: Default::default(),
            in_steps: Default::default(),
            busy: Default::default(),
            out_valid: Default::default(),
            out_code: Default::default(),
            s1: Default::default(),
            s2: Default::default(),
            s3: Default::default(),
            s4: Default::default(),
            s5: Default::default(),
            s6: Default::default(),
            v0: Default::default(),
            v1: Default::default(),
            a: Default::default(),
            t: Default::default(),
            steps: Default::default(),
            rcode: Default::default(),
            fast_rate: Default::default(),
            a2: Default::default(),
            k1: Default::default(),
            beta1: Default::default(),
            s6v: Default::default(),
            beta2: Default::default(),
            hull: Default::default(),
            neg1: Default::default(),
            big1: Default::default(),
            code: Default::default(),
            mul_v0: Default::default(),
            mul_v1: Default::default(),
            mul_r: Default::default(),
            c_rmax: Constant::new((limits.max_rate() as u64).into()),
            c_max_t: Constant::new((POLY_MAX_T_TICKS as u64).into()),
            c_max_n: Constant::new((MAX_STEPS as u64).into()),
            c_max_rate: Constant::new((MAX_V0_RATE as u64).into()),
            c_sx: Constant::new(Bits::<B>::from(0xfu64) << 64),
            n: Default::default(),
            sx: Default::default(),
            a68: Default::default(),
            n68: Default::default(),
            pv0: Default::default(),
            pv1: Default::default(),
            pr: Default::default(),
            neg2: Default::default(),
            big2: Default::default(),
            busy_now: Default::default(),
            take: Default::default(),
        }
    }
}

impl Logic for PolyCheck {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clock, s1, s2, s3, s4, s5, s6, v0, v1, a, t, steps, rcode, fast_rate, a2, k1, beta1, s6v, beta2, hull,
            neg1, big1, code
        );
        self.mul_v0.clock.next = self.clock.val();
        self.mul_v1.clock.next = self.clock.val();
        self.mul_r.clock.next = self.clock.val();

        // Edge 0: take the segment.
        self.busy_now.next =
            self.s1.q.val() | self.s2.q.val() | self.s3.q.val() | self.s4.q.val() | self.s5.q.val();
        self.take.next = self.in_valid.val() & !self.busy_now.val();
        self.s1.d.next = self.take.val();
        self.s2.d.next = self.s1.q.val();
        self.s3.d.next = self.s2.q.val();
        self.s4.d.next = self.s3.q.val();
        self.s5.d.next = self.s4.q.val();
        self.s6.d.next = self.s5.q.val();
        self.busy.next = self.busy_now.val();
        if self.take.val() {
            self.v0.d.next = self.in_v0.val();
            self.v1.d.next = self.in_v1.val();
            self.a.d.next = self.in_a.val();
            self.t.d.next = self.in_t.val();
            self.steps.d.next = self.in_steps.val();
        }

        // Cycle 1: the products in; the range code, 2A' and 12n·2^32 − 2A'.
        self.mul_v0.a.next = self.v0.q.val();
        self.mul_v0.b.next = self.t.q.val();
        self.mul_v1.a.next = self.v1.q.val();
        self.mul_v1.b.next = self.t.q.val();
        self.mul_r.a.next = self.c_rmax.val();
        self.mul_r.b.next = self.t.q.val();
        self.n.next = self.steps.q.val();
        if self.steps.q.val().get_bit(31) {
            self.n.next = (!self.steps.q.val()) + 1;
        }
        if self.t.q.val() == 0 {
            self.rcode.d.next = 1.into();
        } else if self.t.q.val() > self.c_max_t.val() {
            self.rcode.d.next = 4.into();
        } else if self.n.val() > self.c_max_n.val() {
            // |i32::MIN| = 2^31 as unsigned: above the maximum too.
            self.rcode.d.next = 5.into();
        } else if (self.v0.q.val() > self.c_max_rate.val()) | (self.v1.q.val() > self.c_max_rate.val()) {
            self.rcode.d.next = 6.into();
        } else {
            self.rcode.d.next = 0.into();
        }
        self.fast_rate.d.next = (self.v0.q.val() > self.c_rmax.val()) | (self.v1.q.val() > self.c_rmax.val());
        self.sx.next = 0.into();
        if self.a.q.val().get_bit(63) {
            self.sx.next = self.c_sx.val();
        }
        self.a68.next = bit_cast::<B, 64>(self.a.q.val()) | self.sx.val();
        self.n68.next = bit_cast::<B, 32>(self.n.val());
        self.a2.d.next = self.a68.val() << 1;
        // 12n·2^32 − 2A' = n·2^35 + n·2^34 + ¬(2A') + 1.
        self.k1.d.next = (self.n68.val() << 35) + (self.n68.val() << 34) + (!(self.a68.val() << 1)) + 1;

        // Cycle 3: the products arrive (MulReg latency 2).
        self.pv0.next = bit_cast::<B, 64>(self.mul_v0.p.val());
        self.pv1.next = bit_cast::<B, 64>(self.mul_v1.p.val());
        self.pr.next = bit_cast::<B, 64>(self.mul_r.p.val());
        self.beta1.d.next = self.pv0.val() + (self.pv0.val() << 1) + self.a2.q.val();
        self.s6v.d.next = (self.pv0.val() << 2) + (self.pv0.val() << 1) + (self.pv1.val() << 1) + self.pv1.val();
        self.hull.d.next = self.pr.val() + (self.pr.val() << 1);

        // Cycle 4: β2; β1 below 0, above the hull (the hull is ≥ 0).
        self.beta2.d.next = self.k1.q.val() - self.s6v.q.val();
        self.neg1.d.next = self.beta1.q.val().get_bit(67);
        self.big1.d.next = !self.beta1.q.val().get_bit(67) & (self.beta1.q.val() > self.hull.q.val());

        // Cycle 5: β2's compares and the code, in the model's order.
        self.neg2.next = self.beta2.q.val().get_bit(67);
        self.big2.next = !self.beta2.q.val().get_bit(67) & (self.beta2.q.val() > self.hull.q.val());
        if self.rcode.q.val() != 0 {
            self.code.d.next = self.rcode.q.val();
        } else if self.neg1.q.val() | self.neg2.val() {
            self.code.d.next = 2.into();
        } else if self.fast_rate.q.val() | self.big1.q.val() | self.big2.val() {
            self.code.d.next = 3.into();
        } else {
            self.code.d.next = 0.into();
        }

        // Cycle 6: the verdict.
        self.out_valid.next = self.s6.q.val();
        self.out_code.next = self.code.q.val();

        if self.reset.val() {
            self.s1.d.next = false;
            self.s2.d.next = false;
            self.s3.d.next = false;
            self.s4.d.next = false;
            self.s5.d.next = false;
            self.s6.d.next = false;
        }
    }
}
