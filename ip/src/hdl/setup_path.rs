//! The setup's datapath: the shared unit's multipliers and divider with their operands
//! and the setup's temporaries, driven by the scheduler's state register
//! ([`super::core::TdmCore`] decides; this block computes).
//!
//! It holds the pipelined 32×32 multiplier ([`MulReg`], `narrow`: the product of the
//! operands `op_a`, `op_b` registered one state ahead,
//! [`MUL_REG_LATENCY`](super::mul_wide::MUL_REG_LATENCY) cycles
//! after them), the sequential multiplier ([`MulSeq`]) and the divider ([`Divider`]),
//! R bits per cycle each. The scheduler starts the last two (`mul_start`,
//! `div_start`); their operands are chosen here for every state (they read them only
//! when started), so no zero default sits in their multiplexers:
//!
//! | state | sequential multiplier | divider |
//! |---|---|---|
//! | S_TR | v0·T² (v_end·T² when D < 0) | 2T / 2n (uniform) |
//! | S_X | | P' = round(v·T²·2^4 / (2\|D·2^32\|)) |
//! | S_P | | B' = round(T²·2^41 / (2\|D\|)), or 2T / 2n (the fallback) |
//! | S_B | n·B' | |
//! | C_V0, C_N (controlled stop) | | 2^32/(Δ + 1); v0²/(2^8·DECEL) |
//!
//! Temporaries (each loaded in the state named, from registers or the units' results):
//! S_CHECK takes the queue head (`head`: v0, T, signed steps) into `s_v0`, `s_steps`
//! and the multiplier's operands; S_ISSUE_VT issues v0·T (T² next); S_ISSUE_TR registers
//! n = 0 (`s_nz`, from the working copy's `w_n`); S_VT registers D·2^32 = n·2^32 − v0·T,
//! its sign (`s_neg`), D = 0 (`s_dz`) and v_end·T·2^32; S_TR makes D's magnitude and
//! takes T²; after S_P's quotient, `p_ready` one cycle later with `p_wide` (P' + 2T' ≥
//! 2^64, the fallback test). The controlled stop's ramp: C_V0_WAIT takes v0 and v0²'s
//! operands, C_N_WAIT the signed count (`steps`, from the quotient n − 1 and `crev`) and
//! n·(Δ + 1)'s, C_T v0·T's (T = 2n(Δ + 1)) before the ordinary setup from S_ISSUE_VT.
//! `c_cs_on` (a constant, set by [`SetupPath::with_controlled_stop`] when the core is
//! built with the controlled stop) gates the controlled stop's states. It is a constant
//! of this block, not a port: yosys folds a constant written in the module itself, while
//! one that reaches it through a port leaves the dead states' logic in place (about 100
//! LUT6 at K = 2 on xc7, measured on the exported Verilog).
//!
//! Latencies are the units' ([`super::core::t_setup`] adds them up); its test is the
//! core's (tests/hdl_core.rs and hdl_core_setup.rs, three ways against the model).

use super::divider::{Divider, DIV_DEN_BITS, DIV_NUM_BITS};
use super::mul_seq::{MulSeq, MUL_A_BITS};
use super::mul_wide::MulReg;
use super::sched_states::{state, STATE_BITS};
use super::seg_queue::SEGMENT_BITS;
use super::stop_ramp::LAST_BITS;
use rust_hdl::prelude::*;

#[derive(LogicBlock)]
pub struct SetupPath<const R: usize> {
    pub clock: Signal<In, Clock>,
    /// The scheduler's state register.
    pub st: Signal<In, Bits<STATE_BITS>>,
    /// The controlled stop is built (a constant).
    pub mul_start: Signal<In, Bit>,
    pub div_start: Signal<In, Bit>,
    /// Axis m's queue head (valid in S_CHECK).
    pub head: Signal<In, Bits<SEGMENT_BITS>>,
    /// The working copy's step count and T.
    pub w_n: Signal<In, Bits<32>>,
    pub w_t: Signal<In, Bits<32>>,
    /// The controlled stop: DECEL, the axis's last period + 1 and its direction.
    pub decel: Signal<In, Bits<32>>,
    pub dl1: Signal<In, Bits<LAST_BITS>>,
    pub crev: Signal<In, Bit>,
    pub quotient: Signal<Out, Bits<DIV_NUM_BITS>>,
    pub remainder: Signal<Out, Bits<DIV_DEN_BITS>>,
    pub div_valid: Signal<Out, Bit>,
    pub product: Signal<Out, Bits<MUL_A_BITS>>,
    pub mul_valid: Signal<Out, Bit>,
    /// The sequential multiplier or the divider runs.
    pub busy: Signal<Out, Bit>,
    /// The segment's T and signed step count (from S_ISSUE_VT), for the working copy.
    pub t: Signal<Out, Bits<32>>,
    pub steps: Signal<Out, Bits<32>>,
    pub nz: Signal<Out, Bit>,
    pub dz: Signal<Out, Bit>,
    pub neg: Signal<Out, Bit>,
    pub p_wide: Signal<Out, Bit>,
    pub p_ready: Signal<Out, Bit>,
    mulw: MulReg<32, 32, 64>,
    mul: MulSeq<R>,
    div: Divider<R>,
    s_v0: DFF<Bits<32>>,
    s_steps: DFF<Bits<32>>,
    // |values| < 2^61 (docs/model.md, "Widths"), so 64 bits two's complement.
    /// D·2^32 from S_VT, its magnitude from S_TR on; `s_neg` is D < 0 (decelerating).
    s_d: DFF<Bits<64>>,
    s_neg: DFF<Bit>,
    /// v_end·T·2^32 from S_VT (read in S_TR, as the multiplier starts), T² from S_TR on.
    s_vt2: DFF<Bits<64>>,
    /// S_TR's two tests, registered a state earlier so that S_TR decides from flip-flops:
    /// the step count is 0 (from |steps| in S_ISSUE_TR) and D = 0, i.e. v0·T = n·2^32
    /// (from the product in S_VT, an equality, no subtraction).
    s_nz: DFF<Bit>,
    s_dz: DFF<Bit>,
    /// The pipelined multiplier's operands.
    op_a: DFF<Bits<32>>,
    op_b: DFF<Bits<32>>,
    p_wide_r: DFF<Bit>,
    p_ready_r: DFF<Bit>,
    h_v0: Signal<Local, Bits<32>>,
    h_t: Signal<Local, Bits<32>>,
    h_steps: Signal<Local, Bits<32>>,
    dq: Signal<Local, Bits<64>>,
    vend: Signal<Local, Bits<64>>,
    n64: Signal<Local, Bits<64>>,
    narrow: Signal<Local, Bits<64>>,
    t_num: Signal<Local, Bits<DIV_NUM_BITS>>,
    two_n: Signal<Local, Bits<32>>,
    p_test: Signal<Local, Bits<65>>,
    cs_num: Signal<Local, Bits<DIV_NUM_BITS>>,
    cs_n: Signal<Local, Bits<32>>,
    cs_den: Signal<Local, Bits<64>>,
    c_two32: Constant<Bits<DIV_NUM_BITS>>,
    k_check: Constant<Bits<STATE_BITS>>,
    k_issue_vt: Constant<Bits<STATE_BITS>>,
    k_issue_tr: Constant<Bits<STATE_BITS>>,
    k_vt: Constant<Bits<STATE_BITS>>,
    k_tr: Constant<Bits<STATE_BITS>>,
    k_x: Constant<Bits<STATE_BITS>>,
    k_p: Constant<Bits<STATE_BITS>>,
    k_b: Constant<Bits<STATE_BITS>>,
    k_cv0: Constant<Bits<STATE_BITS>>,
    k_cv0w: Constant<Bits<STATE_BITS>>,
    k_cn: Constant<Bits<STATE_BITS>>,
    k_cnw: Constant<Bits<STATE_BITS>>,
    k_ct: Constant<Bits<STATE_BITS>>,
    c_cs_on: Constant<Bit>,
}

impl<const R: usize> SetupPath<R> {
    /// The block with the controlled stop's states working (the core's
    /// `with_controlled_stop`); the default leaves them out.
    pub fn with_controlled_stop(mut self) -> Self {
        self.c_cs_on = Constant::new(true);
        self
    }
}

// The fallback test reads the quotient's bits 103..64 by literal widths (rust-hdl
// writes a Rust constant's name into the Verilog).
const _: () = assert!(DIV_NUM_BITS == 104);

impl<const R: usize> Default for SetupPath<R> {
    fn default() -> Self {
        SetupPath {
            clock: Default::default(),
            st: Default::default(),
            c_cs_on: Constant::new(false),
            mul_start: Default::default(),
            div_start: Default::default(),
            head: Default::default(),
            w_n: Default::default(),
            w_t: Default::default(),
            decel: Default::default(),
            dl1: Default::default(),
            crev: Default::default(),
            quotient: Default::default(),
            remainder: Default::default(),
            div_valid: Default::default(),
            product: Default::default(),
            mul_valid: Default::default(),
            busy: Default::default(),
            t: Default::default(),
            steps: Default::default(),
            nz: Default::default(),
            dz: Default::default(),
            neg: Default::default(),
            p_wide: Default::default(),
            p_ready: Default::default(),
            mulw: Default::default(),
            mul: Default::default(),
            div: Default::default(),
            s_v0: Default::default(),
            s_steps: Default::default(),
            s_d: Default::default(),
            s_neg: Default::default(),
            s_vt2: Default::default(),
            s_nz: Default::default(),
            s_dz: Default::default(),
            op_a: Default::default(),
            op_b: Default::default(),
            p_wide_r: Default::default(),
            p_ready_r: Default::default(),
            h_v0: Default::default(),
            h_t: Default::default(),
            h_steps: Default::default(),
            dq: Default::default(),
            vend: Default::default(),
            n64: Default::default(),
            narrow: Default::default(),
            t_num: Default::default(),
            two_n: Default::default(),
            p_test: Default::default(),
            cs_num: Default::default(),
            cs_n: Default::default(),
            cs_den: Default::default(),
            c_two32: Constant::new(Bits::<DIV_NUM_BITS>::from(1u64 << 32)),
            k_check: state("S_CHECK"),
            k_issue_vt: state("S_ISSUE_VT"),
            k_issue_tr: state("S_ISSUE_TR"),
            k_vt: state("S_VT"),
            k_tr: state("S_TR"),
            k_x: state("S_X"),
            k_p: state("S_P"),
            k_b: state("S_B"),
            k_cv0: state("C_V0"),
            k_cv0w: state("C_V0_WAIT"),
            k_cn: state("C_N"),
            k_cnw: state("C_N_WAIT"),
            k_ct: state("C_T"),
        }
    }
}

impl<const R: usize> Logic for SetupPath<R> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, s_v0, s_steps, s_d, s_neg, s_vt2, s_nz, s_dz, op_a, op_b, p_wide_r, p_ready_r);
        self.mulw.clock.next = self.clock.val();
        // The pipelined multiplier's operands come from registers, loaded one state
        // ahead of each product's issue: no state decode or operand select sits in
        // front of the multiplier.
        self.mulw.a.next = self.op_a.q.val();
        self.mulw.b.next = self.op_b.q.val();
        self.mul.clock.next = self.clock.val();
        self.div.clock.next = self.clock.val();
        self.mul.start.next = self.mul_start.val();
        self.div.start.next = self.div_start.val();
        self.quotient.next = self.div.quotient.val();
        self.remainder.next = self.div.remainder.val();
        self.div_valid.next = self.div.valid.val();
        self.product.next = self.mul.product.val();
        self.mul_valid.next = self.mul.valid.val();
        self.busy.next = self.mul.busy.val() | self.div.busy.val();
        self.t.next = self.op_b.q.val();
        self.steps.next = self.s_steps.q.val();
        self.nz.next = self.s_nz.q.val();
        self.dz.next = self.s_dz.q.val();
        self.neg.next = self.s_neg.q.val();
        self.p_wide.next = self.p_wide_r.q.val();
        self.p_ready.next = self.p_ready_r.q.val();

        // Axis m's queue head: read at the edge that ends PICK, so valid in S_CHECK.
        self.h_v0.next = self.head.val().get_bits::<32>(0);
        self.h_t.next = self.head.val().get_bits::<32>(32);
        self.h_steps.next = self.head.val().get_bits::<32>(64);
        self.n64.next = bit_cast::<64, 32>(self.w_n.val());
        self.t_num.next = bit_cast::<DIV_NUM_BITS, 32>(self.w_t.val());
        self.two_n.next = self.w_n.val() << 1;
        // The registered 32×32 product (v0·T, T·RMAX, T²), one cycle after its operands.
        self.narrow.next = self.mulw.p.val();
        // D·2^32 = n·2^32 − v0·T and v_end·T·2^32 = 2n·2^32 − v0·T (two's complement).
        self.dq.next = (self.n64.val() << 32) - self.narrow.val();
        self.vend.next = (self.n64.val() << 33) - self.narrow.val();
        // P' + 2T' ≥ 2^64 (the fallback test) without a 128-bit adder: the quotient's high
        // half, or the carry out of its low half plus 2T'. Registered, with `p_ready` one
        // cycle after the quotient is valid in S_P: S_P decides on them, so the 65-bit add
        // is not in front of the next state, the divider's operands and P's enable.
        self.p_test.next = bit_cast::<65, 64>(self.div.quotient.val().get_bits::<64>(0))
            + (bit_cast::<65, 32>(self.w_t.val()) << 5);
        self.p_wide_r.d.next = (self.div.quotient.val().get_bits::<40>(64) != 0) | self.p_test.val().get_bit(64);
        self.p_ready_r.d.next = self.div.valid.val() & (self.st.val() == self.k_p.val());
        // The sequential multiplier: n·B' in S_B, v_end·T² (decelerating) or v0·T² in S_TR.
        if self.st.val() == self.k_b.val() {
            self.mul.a.next = self.div.quotient.val().get_bits::<MUL_A_BITS>(0);
            self.mul.b.next = self.w_n.val();
        } else if self.s_neg.q.val() {
            // P from the end speed, v_end·T² = (v_end·T·2^32)·T / 2^32.
            self.mul.a.next = bit_cast::<MUL_A_BITS, 64>(self.s_vt2.q.val());
            self.mul.b.next = self.w_t.val();
        } else {
            self.mul.a.next = bit_cast::<MUL_A_BITS, 64>(self.narrow.val());
            self.mul.b.next = self.s_v0.q.val();
        }
        // The divider (the table in the module docs). The stop ramp's v0 = ⌊2^32/(Δ + 1)⌋
        // (C_V0) and n − 1 = ⌊v0²/(2^8·DECEL)⌋ (C_N, v0² from the pipelined multiplier).
        self.cs_den.next = bit_cast::<64, 32>(self.decel.val()) << 8;
        self.cs_num.next = bit_cast::<DIV_NUM_BITS, 64>(self.narrow.val());
        self.cs_n.next = self.div.quotient.val().get_bits::<32>(0) + 1;
        if (self.st.val() == self.k_cv0.val()) & self.c_cs_on.val() {
            self.div.numerator.next = self.c_two32.val();
            self.div.denominator.next = bit_cast::<64, LAST_BITS>(self.dl1.val());
        } else if (self.st.val() == self.k_cn.val()) & self.c_cs_on.val() {
            self.div.numerator.next = self.cs_num.val();
            self.div.denominator.next = self.cs_den.val();
        } else if self.st.val() == self.k_x.val() {
            self.div.numerator.next = (bit_cast::<DIV_NUM_BITS, MUL_A_BITS>(self.mul.product.val()) << 4)
                + bit_cast::<DIV_NUM_BITS, 64>(self.s_d.q.val());
            self.div.denominator.next = self.s_d.q.val() << 1;
        } else if (self.st.val() == self.k_p.val()) & !self.p_wide_r.q.val() {
            self.div.numerator.next = (bit_cast::<DIV_NUM_BITS, 64>(self.s_vt2.q.val()) << 41)
                + bit_cast::<DIV_NUM_BITS, 64>(self.s_d.q.val());
            self.div.denominator.next = self.s_d.q.val() << 1;
        } else {
            self.div.numerator.next = self.t_num.val() << 1;
            self.div.denominator.next = bit_cast::<64, 32>(self.two_n.val());
        }

        // ---- the temporaries, by state ----------------------------------------
        if self.st.val() == self.k_check.val() {
            // The queue head goes into registers that take nothing else (v0 and the
            // signed step count), and v0·T's operands into the multiplier's (T stays in
            // op_b): nothing but op_a's two-way select follows the RAM's clock-to-out.
            self.s_v0.d.next = self.h_v0.val();
            self.s_steps.d.next = self.h_steps.val();
            self.op_a.d.next = self.h_v0.val();
            self.op_b.d.next = self.h_t.val();
        } else if self.st.val() == self.k_issue_vt.val() {
            // v0·T goes into the multiplier; T²'s operands are T and T (op_b holds).
            self.op_a.d.next = self.op_b.q.val();
        } else if self.st.val() == self.k_issue_tr.val() {
            self.s_nz.d.next = self.w_n.val() == 0;
        } else if self.st.val() == self.k_vt.val() {
            // v0·T arrived (MulReg, two cycles after S_ISSUE_VT issued it).
            self.s_d.d.next = self.dq.val();
            self.s_neg.d.next = self.dq.val().get_bit(63);
            self.s_dz.d.next = (self.narrow.val().get_bits::<32>(0) == 0)
                & (self.narrow.val().get_bits::<32>(32) == self.w_n.val());
            self.s_vt2.d.next = self.vend.val();
        } else if self.st.val() == self.k_tr.val() {
            // T² arrived; the multiplier takes v_end·T·2^32 at this edge (it starts here).
            if self.s_neg.q.val() {
                self.s_d.d.next = (!self.s_d.q.val()) + 1;
            }
            self.s_vt2.d.next = self.narrow.val();
        } else if (self.st.val() == self.k_cv0w.val()) & self.c_cs_on.val() {
            if self.div.valid.val() {
                // v0 < 2^31; v0² into the pipelined multiplier.
                self.s_v0.d.next = self.div.quotient.val().get_bits::<32>(0);
                self.op_a.d.next = self.div.quotient.val().get_bits::<32>(0);
                self.op_b.d.next = self.div.quotient.val().get_bits::<32>(0);
            }
        } else if (self.st.val() == self.k_cnw.val()) & self.c_cs_on.val() {
            if self.div.valid.val() {
                // n ≤ 2^24 (DECEL ≥ its minimum); n·(Δ + 1) into the multiplier and the
                // signed count in the last step's direction.
                // (−n = ¬(n − 1): the quotient's complement.)
                if self.crev.val() {
                    self.s_steps.d.next = !self.div.quotient.val().get_bits::<32>(0);
                } else {
                    self.s_steps.d.next = self.cs_n.val();
                }
                self.op_a.d.next = self.cs_n.val();
                self.op_b.d.next = bit_cast::<32, LAST_BITS>(self.dl1.val());
            }
        } else if (self.st.val() == self.k_ct.val()) & self.c_cs_on.val() {
            // T = 2n(Δ + 1) ≤ 2^30: the segment (v0, T, ±n) enters the setup as a queue
            // head would after S_CHECK (v0·T's operands in op_a and op_b).
            self.op_a.d.next = self.s_v0.q.val();
            self.op_b.d.next = self.narrow.val().get_bits::<32>(0) << 1;
        }
    }
}
