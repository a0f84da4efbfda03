//! Push check: every command from the register file passes here, in the bus clock, on
//! its way to the command FIFO. A push (kind 0) is validated with the model's rules and
//! codes ([`crate::model::Segment::validate`], bit for bit); a valid one goes on with
//! its effective start rate ([`crate::model::Segment::effective`]: v0 − 1 for a
//! deceleration that rounds past rest), a bad one is dropped and reported on `rej_*`.
//! START and ABORT pass unchanged, with the same delay, so the order of commands is
//! kept. The core behind the FIFO therefore only ever sees valid segments.
//!
//! Pipeline (one command in flight; latency 4 cycles):
//! * edge 0 registers the command (`in_valid`, `in_data`, layout
//!   [`super::regfile::CMD_BITS`]) and v0 + RMAX (the latter every cycle, from
//!   `in_v0`, the push's v0 on a port of its own, whether or not `in_valid` is 1: the
//!   owner offers it ahead of its decision to write and of the START/ABORT select that
//!   forms `in_data`, so the adder follows only the staging memory's read; it is read
//!   only for a push);
//! * cycle 1: the two 32×32 products v0·T and (v0 + RMAX)·T go into two [`MulReg`]s;
//!   the range codes (T = 0, T, |θ|, v0 above their maxima), n·2^33 and the two
//!   start-rate limits are registered;
//! * cycle 3: the products arrive; three 64-bit compares against 2n·2^32 (reverses:
//!   2n·2^32 < v0·T; rounds past rest: and 2n·2^32 + T > v0·T; too fast at the end:
//!   2n·2^32 > (v0 + RMAX)·T, that is v_end·T·2^32 > T·RMAX) make the verdict's code,
//!   in the model's order, and it is registered with the rounds-past-rest flag;
//!   a push the segment's checks pass takes `ext_code` (a further check's, 0 passes);
//! * cycle 4: the verdict, from those registers. `out_valid`/`out_data` for a valid push, START or ABORT;
//!   `rej_valid` with `rej_axis` and `rej_code` for a rejected push.
//!
//! **Polynomial pushes** (S = 1, the S-curve option; kind 3): the segment's five
//! fields go into a [`PolyCheck`] at edge 0 (v0, T, θ from `in_data`, v1 and A' from
//! `in_extra`), which gives the model's code ([`crate::model::PolySegment::validate`])
//! [`POLY_PUSH_LATENCY`] = 6 cycles later; the further check's code is taken in cycle 3
//! as for any push and wins when the segment's own checks pass. The command comes out
//! unchanged (no effective form) or as a rejection in cycle 6. It does not hold other
//! commands: one offered in cycle 4 or later comes out in cycle 8 or later, after it,
//! so the order is kept and no two verdicts meet. `poly_busy` is 1 in cycles 1 to 5:
//! a second polynomial push offered then would be lost, so the register file refuses
//! it. Without the option (S = 0) there is no [`PolyCheck`] and kind 3 never comes.
//!
//! `busy` is 1 in cycles 1 to 3: a command offered then would be lost, so the register
//! file refuses it (GSTATUS.REFUSED). A command offered in cycle 4 is taken. The bus
//! slave commits writes at least 4 bus clocks apart when the MCU keeps the documented
//! timing (NWE low ≥ 3, high ≥ 2 bus clocks), so a host within the timing is never
//! refused. `reset` (synchronous) drops the command in flight.

use super::mul_wide::MulReg;
use super::poly_check::PolyCheck;
use crate::regs::CMD_BITS;
use crate::model::{Limits, MAX_STEPS, MAX_T_TICKS, MAX_V0_RATE};
use rust_hdl::prelude::*;

/// Cycles from `in_valid` to `out_valid` / `rej_valid` (a trapezoid push, and S = 1).
pub use crate::latency::{POLY_PUSH_LATENCY, PUSH_CHECK_LATENCY};

/// The polynomial fields of a push (S = 1): v1 (31..0) and A' (95..32).
pub const CMD_EXTRA_BITS: usize = 96;

#[derive(LogicBlock)]
pub struct PushCheck<const S: usize = 0> {
    pub clock: Signal<In, Clock>,
    pub reset: Signal<In, Bit>,
    pub in_valid: Signal<In, Bit>,
    pub in_data: Signal<In, Bits<CMD_BITS>>,
    /// The v0 of the push on offer (equal to `in_data`'s low 32 bits whenever a push
    /// is offered; read every cycle, for v0 + RMAX).
    pub in_v0: Signal<In, Bits<32>>,
    /// A further check's code for the push in cycle 3 (the machine I/O's
    /// [`super::push_guard::PushGuard`]; 0 passes): the verdict takes it when the
    /// segment's own checks pass. Tied to 0 without the machine I/O.
    pub ext_code: Signal<In, Bits<4>>,
    /// A polynomial push's v1 (31..0) and A' (95..32), read at its edge 0 (S = 1).
    pub in_extra: Signal<In, Bits<CMD_EXTRA_BITS>>,
    pub busy: Signal<Out, Bit>,
    /// The polynomial check is busy (cycles 1 to 5 of a polynomial push).
    pub poly_busy: Signal<Out, Bit>,
    pub out_valid: Signal<Out, Bit>,
    pub out_data: Signal<Out, Bits<CMD_BITS>>,
    /// A polynomial push's v1 and A' as taken at its edge 0, with its `out_valid`.
    pub out_extra: Signal<Out, Bits<CMD_EXTRA_BITS>>,
    pub rej_valid: Signal<Out, Bit>,
    pub rej_axis: Signal<Out, Bits<4>>,
    pub rej_code: Signal<Out, Bits<4>>,
    /// Which cycle of the check the command is in (1, 2, 3, 4).
    s1: DFF<Bit>,
    s2: DFF<Bit>,
    s3: DFF<Bit>,
    s4: DFF<Bit>,
    cmd: DFF<Bits<CMD_BITS>>,
    vr: DFF<Bits<32>>,
    /// The first failing range check's code (1, 4, 5, 6), or 0.
    rcode: DFF<Bits<4>>,
    n2: DFF<Bits<64>>,
    n2t: DFF<Bits<64>>,
    v0_fast: DFF<Bit>,
    v0_fast1: DFF<Bit>,
    near: DFF<Bit>,
    /// The verdict's code (0: valid), registered at the end of cycle 3.
    code: DFF<Bits<4>>,
    mul_vt: MulReg<32, 32, 64>,
    mul_rt: MulReg<32, 32, 64>,
    /// The S-curve option's check (S = 1), the polynomial push it checks and the
    /// further check's code taken in the push's cycle 3.
    pc: [PolyCheck; S],
    p_cmd: DFF<Bits<CMD_BITS>>,
    p_extra: DFF<Bits<CMD_EXTRA_BITS>>,
    p_ext: DFF<Bits<4>>,
    /// Cycles 1..5 of a polynomial push (`poly_busy` from these flip-flops: the
    /// PolyCheck's own `busy` would follow `in_valid` through its process, a loop to
    /// the register file's process in Verilator's view).
    pb: DFF<Bits<5>>,
    c_poly: Constant<Bit>,
    is_poly: Signal<Local, Bit>,
    in_poly: Signal<Local, Bit>,
    p_valid: Signal<Local, Bit>,
    p_code: Signal<Local, Bits<4>>,
    /// The polynomial check's own code (0 without the S-curve option); `p_code` is it,
    /// or the further check's when it is 0. (Two locals: a local written, read and
    /// written again in one process reads differently in Verilog and rust-hdl.)
    p_own: Signal<Local, Bits<4>>,
    c_rmax: Constant<Bits<32>>,
    c_rmax1: Constant<Bits<32>>,
    c_max_t: Constant<Bits<32>>,
    c_max_n: Constant<Bits<32>>,
    /// 2^32 − MAX_STEPS: a negative count below it (as unsigned) is below −MAX_STEPS.
    c_min_n: Constant<Bits<32>>,
    c_max_v0: Constant<Bits<32>>,
    is_push: Signal<Local, Bit>,
    x_v0: Signal<Local, Bits<32>>,
    x_t: Signal<Local, Bits<32>>,
    x_steps: Signal<Local, Bits<32>>,
    x_n: Signal<Local, Bits<32>>,
    n_big: Signal<Local, Bit>,
    x_v0m1: Signal<Local, Bits<32>>,
    rev: Signal<Local, Bit>,
    near_now: Signal<Local, Bit>,
    fast: Signal<Local, Bit>,
    bad: Signal<Local, Bit>,
}

impl<const S: usize> PushCheck<S> {
    /// The check for a core with these limits (RMAX = [`Limits::max_rate`]); S = 1
    /// checks polynomial pushes too.
    pub fn new(limits: Limits) -> Self {
        assert!(S <= 1, "PushCheck: S = {S}");
        let rmax = limits.max_rate() as u64;
        assert!(rmax + MAX_V0_RATE as u64 <= u32::MAX as u64, "v0 + RMAX must fit 32 bits");
        PushCheck {
            clock: Default::default(),
            reset: Default::default(),
            in_valid: Default::default(),
            in_data: Default::default(),
            in_v0: Default::default(),
            ext_code: Default::default(),
            in_extra: Default::default(),
            busy: Default::default(),
            poly_busy: Default::default(),
            out_valid: Default::default(),
            out_data: Default::default(),
            out_extra: Default::default(),
            rej_valid: Default::default(),
            rej_axis: Default::default(),
            rej_code: Default::default(),
            s1: Default::default(),
            s2: Default::default(),
            s3: Default::default(),
            s4: Default::default(),
            cmd: Default::default(),
            vr: Default::default(),
            rcode: Default::default(),
            n2: Default::default(),
            n2t: Default::default(),
            v0_fast: Default::default(),
            v0_fast1: Default::default(),
            near: Default::default(),
            code: Default::default(),
            mul_vt: Default::default(),
            mul_rt: Default::default(),
            pc: std::array::from_fn(|_| PolyCheck::new(limits)),
            p_cmd: Default::default(),
            p_extra: Default::default(),
            p_ext: Default::default(),
            pb: Default::default(),
            c_poly: Constant::new(S > 0),
            is_poly: Default::default(),
            in_poly: Default::default(),
            p_valid: Default::default(),
            p_code: Default::default(),
            p_own: Default::default(),
            c_rmax: Constant::new(rmax.into()),
            c_rmax1: Constant::new((rmax + 1).into()),
            c_max_t: Constant::new((MAX_T_TICKS as u64).into()),
            c_max_n: Constant::new((MAX_STEPS as u64).into()),
            c_min_n: Constant::new(((1u64 << 32) - MAX_STEPS as u64).into()),
            c_max_v0: Constant::new((MAX_V0_RATE as u64).into()),
            is_push: Default::default(),
            x_v0: Default::default(),
            x_t: Default::default(),
            x_steps: Default::default(),
            x_n: Default::default(),
            n_big: Default::default(),
            x_v0m1: Default::default(),
            rev: Default::default(),
            near_now: Default::default(),
            fast: Default::default(),
            bad: Default::default(),
        }
    }
}

impl<const S: usize> Logic for PushCheck<S> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, s1, s2, s3, s4, cmd, vr, rcode, n2, n2t, v0_fast, v0_fast1, near, code, p_cmd, p_extra, p_ext, pb);
        self.mul_vt.clock.next = self.clock.val();
        self.mul_rt.clock.next = self.clock.val();

        // Cycle 0: take the command.
        self.s1.d.next = self.in_valid.val();
        self.s2.d.next = self.s1.q.val();
        self.s3.d.next = self.s2.q.val();
        self.s4.d.next = self.s3.q.val();
        if self.in_valid.val() {
            self.cmd.d.next = self.in_data.val();
        }
        // v0 + RMAX every cycle (read only in cycle 1, for a push): no enable behind the
        // owner's decision to write and no command select in front, so the adder
        // follows only v0's own path.
        self.vr.d.next = self.in_v0.val() + self.c_rmax.val();
        self.busy.next = self.s1.q.val() | self.s2.q.val() | self.s3.q.val();

        // Cycle 1: the products in, the range checks and 2n·2^32 registered.
        self.x_v0.next = self.cmd.q.val().get_bits::<32>(0);
        self.x_t.next = self.cmd.q.val().get_bits::<32>(32);
        self.x_steps.next = self.cmd.q.val().get_bits::<32>(64);
        if self.x_steps.val().get_bit(31) {
            self.x_n.next = (!self.x_steps.val()) + 1;
        } else {
            self.x_n.next = self.x_steps.val();
        }
        self.is_push.next = self.cmd.q.val().get_bits::<2>(104) == 0;
        self.is_poly.next = (self.cmd.q.val().get_bits::<2>(104) == 3) & self.c_poly.val();
        self.mul_vt.a.next = self.x_v0.val();
        self.mul_vt.b.next = self.x_t.val();
        self.mul_rt.a.next = self.vr.q.val();
        self.mul_rt.b.next = self.x_t.val();
        // |θ| > MAX_STEPS as two compares of θ itself with constants, side by side (not
        // the negation's carry chain and then a compare's): θ ≥ 0 above MAX_STEPS, or
        // θ < 0 below 2^32 − MAX_STEPS as unsigned (θ < −MAX_STEPS; i32::MIN too).
        self.n_big.next = (!self.x_steps.val().get_bit(31) & (self.x_steps.val() > self.c_max_n.val()))
            | (self.x_steps.val().get_bit(31) & (self.x_steps.val() < self.c_min_n.val()));
        if self.x_t.val() == 0 {
            self.rcode.d.next = 1.into();
        } else if self.x_t.val() > self.c_max_t.val() {
            self.rcode.d.next = 4.into();
        } else if self.n_big.val() {
            self.rcode.d.next = 5.into();
        } else if self.x_v0.val() > self.c_max_v0.val() {
            self.rcode.d.next = 6.into();
        } else {
            self.rcode.d.next = 0.into();
        }
        // n ≤ 2^24 when the range check passes, so n·2^33 < 2^58; T < 2^32 fills the
        // bits below 33, so n·2^33 + T is an OR.
        self.n2.d.next = bit_cast::<64, 32>(self.x_n.val()) << 33;
        self.n2t.d.next = (bit_cast::<64, 32>(self.x_n.val()) << 33) | bit_cast::<64, 32>(self.x_t.val());
        self.v0_fast.d.next = self.x_v0.val() > self.c_rmax.val();
        self.v0_fast1.d.next = self.x_v0.val() > self.c_rmax1.val();

        // Cycle 3: the products arrive (MulReg latency 2); the three compares and the
        // verdict's code, in the model's order, registered (cycle 4 reads flip-flops).
        self.rev.next = self.n2.q.val() < self.mul_vt.p.val();
        self.near_now.next = self.rev.val() & (self.n2t.q.val() > self.mul_vt.p.val());
        self.fast.next = self.n2.q.val() > self.mul_rt.p.val();
        self.near.d.next = self.near_now.val();
        if self.rcode.q.val() != 0 {
            self.code.d.next = self.rcode.q.val();
        } else if self.near_now.val() {
            if self.v0_fast1.q.val() {
                self.code.d.next = 3.into();
            } else {
                self.code.d.next = self.ext_code.val();
            }
        } else if self.rev.val() {
            self.code.d.next = 2.into();
        } else if self.v0_fast.q.val() | self.fast.val() {
            self.code.d.next = 3.into();
        } else {
            self.code.d.next = self.ext_code.val();
        }

        // ---- polynomial pushes (S = 1) ---------------------------------------
        self.in_poly.next = self.in_valid.val() & (self.in_data.val().get_bits::<2>(104) == 3) & self.c_poly.val();
        if self.in_poly.val() {
            self.p_cmd.d.next = self.in_data.val();
            self.p_extra.d.next = self.in_extra.val();
        }
        self.out_extra.next = self.p_extra.q.val();
        if self.s3.q.val() & self.is_poly.val() {
            self.p_ext.d.next = self.ext_code.val();
        }
        self.p_valid.next = false;
        self.p_own.next = 0.into();
        for i in 0..S {
            self.pc[i].clock.next = self.clock.val();
            self.pc[i].reset.next = self.reset.val();
            self.pc[i].in_valid.next = self.in_poly.val();
            self.pc[i].in_v0.next = self.in_data.val().get_bits::<32>(0);
            self.pc[i].in_t.next = self.in_data.val().get_bits::<32>(32);
            self.pc[i].in_steps.next = self.in_data.val().get_bits::<32>(64);
            self.pc[i].in_v1.next = self.in_extra.val().get_bits::<32>(0);
            self.pc[i].in_a.next = self.in_extra.val().get_bits::<64>(32);
            self.p_valid.next = self.pc[i].out_valid.val();
            self.p_own.next = self.pc[i].out_code.val();
        }
        // The segment's own code first, then the further check's.
        self.p_code.next = self.p_own.val();
        if self.p_own.val() == 0 {
            self.p_code.next = self.p_ext.q.val();
        }
        // Cycles 1 to 5 of a polynomial push (PolyCheck ignores an offer then).
        self.pb.d.next = self.pb.q.val() << 1;
        if self.in_poly.val() & !self.pb.q.val().any() {
            self.pb.d.next = (self.pb.q.val() << 1) | 1;
        }
        if self.reset.val() {
            self.pb.d.next = 0.into();
        }
        self.poly_busy.next = self.pb.q.val().any();

        // Cycle 4: the verdict (a polynomial push's in cycle 6, below).
        self.bad.next = self.code.q.val() != 0;
        self.out_valid.next = self.s4.q.val() & !self.is_poly.val() & (!self.is_push.val() | !self.bad.val());
        self.x_v0m1.next = self.x_v0.val() - 1;
        self.out_data.next = self.cmd.q.val();
        if self.is_push.val() & self.near.q.val() {
            self.out_data.next = ((self.cmd.q.val() >> 32) << 32) | bit_cast::<CMD_BITS, 32>(self.x_v0m1.val());
        }
        self.rej_valid.next = self.s4.q.val() & self.is_push.val() & self.bad.val();
        self.rej_axis.next = self.cmd.q.val().get_bits::<4>(96);
        self.rej_code.next = self.code.q.val();
        if self.p_valid.val() & self.c_poly.val() {
            self.out_valid.next = self.p_code.val() == 0;
            self.out_data.next = self.p_cmd.q.val();
            self.rej_valid.next = self.p_code.val() != 0;
            self.rej_axis.next = self.p_cmd.q.val().get_bits::<4>(96);
            self.rej_code.next = self.p_code.val();
        }

        if self.reset.val() {
            self.s1.d.next = false;
            self.s2.d.next = false;
            self.s3.d.next = false;
            self.s4.d.next = false;
        }
    }
}
