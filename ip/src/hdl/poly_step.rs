//! One step of the polynomial (S-curve) edge search: from the Taylor words of M at
//! the last edge and the step's remainder, the next edge and the words and remainder
//! there. Bit for bit [`crate::model::poly::PolySearch::next_edge_galloping`]
//! (docs/model.md, "Polynomial segments"): the words go up from scale 1 to 2^`b0`,
//! trials at h = 2^b rise while they pass and fall to b = 0 once one fails or would
//! pass the cap.
//!
//! One three-input adder, 161 bits (every word fits 160 bits signed, so sums of them
//! are exact modulo 2^161), does all the arithmetic, one operation issued per cycle,
//! in two halves a cycle apart: an operation issued in cycle c adds bits 0..80 of its
//! operands in c (a carry-save stage and one 81-bit chain) and writes them to its
//! destination's low half; in c + 1 it adds bits 81..160 (the operands' high halves as
//! they are then, the low half's carry and carry-save bit registered) into the high
//! half. An operation issued in c + 1 reads a low half the one before wrote in c and a
//! high half it writes in c + 1, so dependent operations still issue every cycle, and
//! no carry chain is longer than 81 bits with nothing after it but the registers. A
//! sum's sign (bit 160) is known at the end of its second cycle:
//!
//! | state | adder (issued) | then |
//! |---|---|---|
//! | UP | — | W_k <<= k, b += 1 (b0 times) |
//! | TRY | X = W1 + W2 + W3 | e + 2^b ≤ cap registered |
//! | DEC1 | G = X + W4 + Q | past the cap: no trial, fall |
//! | DEC2 | Z = W3 + 2·W4 | G's sign registered |
//! | A2 | W3 = Z + 2·W4 (written only if G < 0) | G < 0 (trial ≤ R): Q = G, e += 2^b; else fall |
//! | A3, A4 | W1 = X + W2 + 2Z; W2 = W2 + Z + 2Z | |
//! | WT | — | (W2's high half) |
//! | SH | — | rising: W_k <<= k, b += 1; else fall |
//!
//! where "fall" is: b = 0 ends the step, else W_k >>= k (exact: W_k is a multiple of
//! 2^k there), b −= 1, TRY. Q holds ¬R = −R − 1 (R = i·S − M(e), the step's target
//! less M at the current edge), so a trial passes when X + W4 + Q < 0 and Q takes the
//! sum: no subtraction anywhere. The slots: a ∈ {W1, X, Z}, b ∈ {W2, W4, 2·W4},
//! c ∈ {W3, Q, 2·Z}, 0 where unused; every word register takes the chain, its two
//! shifts and the adder.
//!
//! Ports: the state goes in and out through a chain, one word per cycle: `shift`
//! (while idle) moves `shift_in` → Q → W4 → W3 → W2 → W1, so five shifts load
//! W1..W4 and Q in that order while the words held before come out of `out_w1` in the
//! same order (a per-axis state memory swaps one axis's state for another's in five
//! cycles, with no load multiplexer beyond the one each register had). The words are
//! m_1..m_4 at the base, scale 1, sign-extended to 161 bits, and Q = ¬R for the step
//! (¬(rem + S)). Then pulse `start` while idle (not with `shift`) with
//! `in_base` (the last edge, E_i), `in_cap` (T − 1) and `in_b0` (the first digit,
//! [`crate::model::poly::gallop_start`] of the last period). `done` pulses one cycle
//! when the step ends, with `out_edge` (E_{i+1}) and `out_q`, `out_w1`..`out_w4` (the
//! state at E_{i+1}) held until the next start. `busy` from the start's edge to
//! `done`. Latency: `1 + b0 + 2·digits + 2·trials + 4·passes` cycles
//! ([`crate::model::poly::GallopStats`]: digits visited, trials made, trials passed):
//! 77 to 84 on average over every step of planned jerk-limited moves, 273 at most
//! there (`hdl_poly` holds the mean between 70 and 90; docs/architecture.md).
//!
//! **Setup.** `start` with `in_setup` takes W1..W4 as the setup's words
//! g = [8·c1, 4·c2, 2·c3, c4] on the half-tick scale
//! ([`crate::model::poly::PolyPlan::setup_state`], from
//! [`super::poly_setup::PolySetup`]; Q, `in_base`, `in_cap`, `in_b0` are not read)
//! and makes one trial at h = ½ tick that passes whatever its
//! sign from Q = ¬0, then one climb: `done` after 9 cycles with `out_edge` = 1 and
//! the state at base 1 (Q = M(1) − 1 and the Taylor words there), where the search
//! for the first edge starts.
//!
//! Every decision is taken from flip-flops (the trial's sign, e + 2^b ≤ cap, b = 0,
//! rising) and the adder's operand and write selects are registered from the next
//! state (the high half's a cycle later), so the paths are: operand select →
//! carry-save stage → 81-bit chain → word register, and flags → next state. A word
//! shifts (a climb or a fall) only when no operation in flight reads or writes it.

use rust_hdl::prelude::*;

/// Width of every word register: 160 bits signed (the model's
/// [`crate::model::poly::POLY_WORD_BITS`]) plus one, so that sums of two words are exact.
pub const POLY_REG_BITS: usize = 161;
const W: usize = POLY_REG_BITS;
// The sign tests and sign extensions read bit 160 by a literal index (rust-hdl writes
// a Rust constant's name into the Verilog).
const _: () = assert!(W == 161 && crate::model::poly::POLY_WORD_BITS as usize + 1 == W);

/// `k` ones from bit `at` up, as an `N`-bit constant: the sign fills, masks and
/// all-ones words of the polynomial unit's blocks.
pub(crate) fn ones_at<const N: usize>(k: usize, at: usize) -> Constant<Bits<N>> {
    assert!(k + at <= N);
    let ones = (num_bigint::BigUint::from(1u32) << k) - 1u32;
    Constant::new(Bits::<N>::from(ones << at))
}

/// The search's highest digit.
const TOP: u64 = crate::model::poly::POLY_TOP_DIGIT as u64;

const ST_IDLE: u64 = 0;
const ST_UP: u64 = 1;
const ST_TRY: u64 = 2;
const ST_DEC1: u64 = 3;
const ST_DEC2: u64 = 4;
const ST_A2: u64 = 5;
const ST_A3: u64 = 6;
const ST_A4: u64 = 7;
const ST_SH: u64 = 8;
const ST_WT: u64 = 9;

#[derive(LogicBlock)]
pub struct PolyStep {
    pub clock: Signal<In, Clock>,
    pub start: Signal<In, Bit>,
    /// The state chain (see the module docs): `shift_in` → Q → W4 → W3 → W2 → W1 →
    /// `out_w1`, one word per `shift` while idle.
    pub shift: Signal<In, Bit>,
    pub shift_in: Signal<In, Bits<W>>,
    pub in_base: Signal<In, Bits<32>>,
    pub in_cap: Signal<In, Bits<32>>,
    pub in_b0: Signal<In, Bits<5>>,
    /// With `start`: the setup instead of a step (see the module docs).
    pub in_setup: Signal<In, Bit>,
    pub busy: Signal<Out, Bit>,
    pub done: Signal<Out, Bit>,
    pub out_edge: Signal<Out, Bits<32>>,
    pub out_q: Signal<Out, Bits<W>>,
    pub out_w1: Signal<Out, Bits<W>>,
    pub out_w2: Signal<Out, Bits<W>>,
    pub out_w3: Signal<Out, Bits<W>>,
    pub out_w4: Signal<Out, Bits<W>>,
    st: DFF<Bits<4>>,
    w1: DFF<Bits<W>>,
    w2: DFF<Bits<W>>,
    w3: DFF<Bits<W>>,
    w4: DFF<Bits<W>>,
    rq: DFF<Bits<W>>,
    x: DFF<Bits<W>>,
    z: DFF<Bits<W>>,
    g: DFF<Bits<W>>,
    pass: DFF<Bit>,
    /// e + 2^b ≤ cap, registered in TRY for DEC1 (a trial is made only then).
    fit: DFF<Bit>,
    /// 2^b, kept beside b.
    h: DFF<Bits<32>>,
    e: DFF<Bits<32>>,
    cap: DFF<Bits<32>>,
    b: DFF<Bits<5>>,
    b0: DFF<Bits<5>>,
    rising: DFF<Bit>,
    fin: DFF<Bit>,
    /// A setup is running: its one trial passes whatever its sign, and it ends after
    /// the climb that follows.
    forced: DFF<Bit>,
    /// The adder's operand selects for the low half, registered from the next state
    /// (so no state decode lies in front of the adder): a 0 W1 X Z, b 0 W2 W4 2·W4,
    /// c 0 W3 Q 2·Z; and the same a cycle later for the high half.
    oa: DFF<Bits<2>>,
    ob: DFF<Bits<2>>,
    oc: DFF<Bits<2>>,
    oa2: DFF<Bits<2>>,
    ob2: DFF<Bits<2>>,
    oc2: DFF<Bits<2>>,
    /// The low half's carry into bit 81, and the carry-save stage's bit 81 (from
    /// the operands' bit 80), for the high half.
    cy: DFF<Bits<1>>,
    bnd: DFF<Bits<1>>,
    /// W1, W2, W3 take the adder's low half in the next state (A3, A4, A2: W3 only if
    /// the trial passed) and its high half in the state after; registered likewise.
    ws1: DFF<Bit>,
    ws2: DFF<Bit>,
    ws3: DFF<Bit>,
    wh1: DFF<Bit>,
    wh2: DFF<Bit>,
    wh3: DFF<Bit>,
    c_top: Constant<Bits<5>>,
    c_ones: Constant<Bits<W>>,
    /// The top 1, 2, 3 and 4 bits set: the arithmetic right shifts' sign fill.
    c_fill1: Constant<Bits<W>>,
    c_fill2: Constant<Bits<W>>,
    c_fill3: Constant<Bits<W>>,
    c_fill4: Constant<Bits<W>>,
    k_idle: Constant<Bits<4>>,
    k_up: Constant<Bits<4>>,
    k_try: Constant<Bits<4>>,
    k_dec1: Constant<Bits<4>>,
    k_dec2: Constant<Bits<4>>,
    k_a2: Constant<Bits<4>>,
    k_a3: Constant<Bits<4>>,
    k_a4: Constant<Bits<4>>,
    k_sh: Constant<Bits<4>>,
    k_wt: Constant<Bits<4>>,
    c_lo: Constant<Bits<W>>,
    /// The operands, by the low half's selects (bits 0..80 used) and the high half's
    /// (bits 81..160 used).
    opa: Signal<Local, Bits<W>>,
    opb: Signal<Local, Bits<W>>,
    opc: Signal<Local, Bits<W>>,
    opa2: Signal<Local, Bits<W>>,
    opb2: Signal<Local, Bits<W>>,
    opc2: Signal<Local, Bits<W>>,
    /// The low half's carry-save stage (sum and carry vectors, bits 0..81 used) and
    /// sum; the high half's (the majority vector unshifted, bits 81..160 used), its
    /// two operands and sum.
    ls: Signal<Local, Bits<W>>,
    lm: Signal<Local, Bits<W>>,
    lo: Signal<Local, Bits<82>>,
    hs: Signal<Local, Bits<W>>,
    hm: Signal<Local, Bits<W>>,
    hsx: Signal<Local, Bits<80>>,
    hmx: Signal<Local, Bits<80>>,
    hi: Signal<Local, Bits<80>>,
    /// {the high half's sum, the low half's sum}: each half of it is written only
    /// where its operation writes.
    p: Signal<Local, Bits<W>>,
    /// Each word shifted down (arithmetic) and up by its k.
    dn1: Signal<Local, Bits<W>>,
    dn2: Signal<Local, Bits<W>>,
    dn3: Signal<Local, Bits<W>>,
    dn4: Signal<Local, Bits<W>>,
    f1: Signal<Local, Bits<W>>,
    f2: Signal<Local, Bits<W>>,
    f3: Signal<Local, Bits<W>>,
    f4: Signal<Local, Bits<W>>,
    /// Move down a digit (or end at b = 0), or up one.
    fall: Signal<Local, Bit>,
    climb: Signal<Local, Bit>,
    nst: Signal<Local, Bits<4>>,
}

impl Default for PolyStep {
    fn default() -> Self {
        let fill = |k: usize| ones_at::<W>(k, W - k);
        PolyStep {
            clock: Default::default(),
            start: Default::default(),
            shift: Default::default(),
            shift_in: Default::default(),
            in_base: Default::default(),
            in_cap: Default::default(),
            in_b0: Default::default(),
            in_setup: Default::default(),
            busy: Default::default(),
            done: Default::default(),
            out_edge: Default::default(),
            out_q: Default::default(),
            out_w1: Default::default(),
            out_w2: Default::default(),
            out_w3: Default::default(),
            out_w4: Default::default(),
            st: Default::default(),
            w1: Default::default(),
            w2: Default::default(),
            w3: Default::default(),
            w4: Default::default(),
            rq: Default::default(),
            x: Default::default(),
            z: Default::default(),
            g: Default::default(),
            pass: Default::default(),
            fit: Default::default(),
            h: Default::default(),
            e: Default::default(),
            cap: Default::default(),
            b: Default::default(),
            b0: Default::default(),
            rising: Default::default(),
            fin: Default::default(),
            forced: Default::default(),
            oa: Default::default(),
            ob: Default::default(),
            oc: Default::default(),
            oa2: Default::default(),
            ob2: Default::default(),
            oc2: Default::default(),
            cy: Default::default(),
            bnd: Default::default(),
            ws1: Default::default(),
            ws2: Default::default(),
            ws3: Default::default(),
            wh1: Default::default(),
            wh2: Default::default(),
            wh3: Default::default(),
            c_top: Constant::new(TOP.into()),
            c_ones: ones_at(W, 0),
            c_fill1: fill(1),
            c_fill2: fill(2),
            c_fill3: fill(3),
            c_fill4: fill(4),
            k_idle: Constant::new(ST_IDLE.into()),
            k_up: Constant::new(ST_UP.into()),
            k_try: Constant::new(ST_TRY.into()),
            k_dec1: Constant::new(ST_DEC1.into()),
            k_dec2: Constant::new(ST_DEC2.into()),
            k_a2: Constant::new(ST_A2.into()),
            k_a3: Constant::new(ST_A3.into()),
            k_a4: Constant::new(ST_A4.into()),
            k_sh: Constant::new(ST_SH.into()),
            k_wt: Constant::new(ST_WT.into()),
            c_lo: ones_at(81, 0),
            opa: Default::default(),
            opb: Default::default(),
            opc: Default::default(),
            opa2: Default::default(),
            opb2: Default::default(),
            opc2: Default::default(),
            ls: Default::default(),
            lm: Default::default(),
            lo: Default::default(),
            hs: Default::default(),
            hm: Default::default(),
            hsx: Default::default(),
            hmx: Default::default(),
            hi: Default::default(),
            p: Default::default(),
            dn1: Default::default(),
            dn2: Default::default(),
            dn3: Default::default(),
            dn4: Default::default(),
            f1: Default::default(),
            f2: Default::default(),
            f3: Default::default(),
            f4: Default::default(),
            fall: Default::default(),
            climb: Default::default(),
            nst: Default::default(),
        }
    }
}

impl Logic for PolyStep {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clock, st, w1, w2, w3, w4, rq, x, z, g, pass, fit, h, e, cap, b, b0, rising, fin, forced, oa, ob, oc, oa2,
            ob2, oc2, cy, bnd, ws1, ws2, ws3, wh1, wh2, wh3
        );

        // The operands of the operation issued now (low half) and of the one issued
        // a cycle ago (high half), by the registered selects (0 where unused).
        self.opa.next = 0.into();
        if self.oa.q.val() == 1 {
            self.opa.next = self.w1.q.val();
        } else if self.oa.q.val() == 2 {
            self.opa.next = self.x.q.val();
        } else if self.oa.q.val() == 3 {
            self.opa.next = self.z.q.val();
        }
        self.opb.next = 0.into();
        if self.ob.q.val() == 1 {
            self.opb.next = self.w2.q.val();
        } else if self.ob.q.val() == 2 {
            self.opb.next = self.w4.q.val();
        } else if self.ob.q.val() == 3 {
            self.opb.next = self.w4.q.val() << 1;
        }
        self.opc.next = 0.into();
        if self.oc.q.val() == 1 {
            self.opc.next = self.w3.q.val();
        } else if self.oc.q.val() == 2 {
            self.opc.next = self.rq.q.val();
        } else if self.oc.q.val() == 3 {
            self.opc.next = self.z.q.val() << 1;
        }
        self.opa2.next = 0.into();
        if self.oa2.q.val() == 1 {
            self.opa2.next = self.w1.q.val();
        } else if self.oa2.q.val() == 2 {
            self.opa2.next = self.x.q.val();
        } else if self.oa2.q.val() == 3 {
            self.opa2.next = self.z.q.val();
        }
        self.opb2.next = 0.into();
        if self.ob2.q.val() == 1 {
            self.opb2.next = self.w2.q.val();
        } else if self.ob2.q.val() == 2 {
            self.opb2.next = self.w4.q.val();
        } else if self.ob2.q.val() == 3 {
            self.opb2.next = self.w4.q.val() << 1;
        }
        self.opc2.next = 0.into();
        if self.oc2.q.val() == 1 {
            self.opc2.next = self.w3.q.val();
        } else if self.oc2.q.val() == 2 {
            self.opc2.next = self.rq.q.val();
        } else if self.oc2.q.val() == 3 {
            self.opc2.next = self.z.q.val() << 1;
        }
        // Low half: carry-save, then bits 0..80 in one chain; its carry (bit 81) and
        // the carry-save stage's bit 81 are registered for the high half.
        self.ls.next = self.opa.val() ^ self.opb.val() ^ self.opc.val();
        self.lm.next = ((self.opa.val() & self.opb.val())
            | (self.opa.val() & self.opc.val())
            | (self.opb.val() & self.opc.val()))
            << 1;
        self.lo.next = bit_cast::<82, 81>(self.ls.val().get_bits::<81>(0))
            + bit_cast::<82, 81>(self.lm.val().get_bits::<81>(0));
        self.cy.d.next = self.lo.val().get_bits::<1>(81);
        self.bnd.d.next = self.lm.val().get_bits::<1>(81);
        // High half: bits 81..160, with those two.
        self.hs.next = self.opa2.val() ^ self.opb2.val() ^ self.opc2.val();
        self.hm.next = (self.opa2.val() & self.opb2.val())
            | (self.opa2.val() & self.opc2.val())
            | (self.opb2.val() & self.opc2.val());
        self.hsx.next = self.hs.val().get_bits::<80>(81);
        self.hmx.next = (self.hm.val().get_bits::<80>(81) << 1) | bit_cast::<80, 1>(self.bnd.q.val());
        self.hi.next = self.hsx.val() + self.hmx.val() + bit_cast::<80, 1>(self.cy.q.val());
        self.p.next = (bit_cast::<W, 80>(self.hi.val()) << 81) | bit_cast::<W, 81>(self.lo.val().get_bits::<81>(0));

        // The words shifted down a digit (arithmetic, exact) for a fall.
        self.f1.next = 0.into();
        self.f2.next = 0.into();
        self.f3.next = 0.into();
        self.f4.next = 0.into();
        if self.w1.q.val().get_bit(160) {
            self.f1.next = self.c_fill1.val();
        }
        if self.w2.q.val().get_bit(160) {
            self.f2.next = self.c_fill2.val();
        }
        if self.w3.q.val().get_bit(160) {
            self.f3.next = self.c_fill3.val();
        }
        if self.w4.q.val().get_bit(160) {
            self.f4.next = self.c_fill4.val();
        }
        self.dn1.next = (self.w1.q.val() >> 1) | self.f1.val();
        self.dn2.next = (self.w2.q.val() >> 2) | self.f2.val();
        self.dn3.next = (self.w3.q.val() >> 3) | self.f3.val();
        self.dn4.next = (self.w4.q.val() >> 4) | self.f4.val();

        self.fall.next = false;
        self.climb.next = false;
        self.fin.d.next = false;
        self.nst.next = self.st.q.val();

        if self.st.q.val() == self.k_idle.val() {
            if self.shift.val() {
                self.w1.d.next = self.w2.q.val();
                self.w2.d.next = self.w3.q.val();
                self.w3.d.next = self.w4.q.val();
                self.w4.d.next = self.rq.q.val();
                self.rq.d.next = self.shift_in.val();
            }
            if self.start.val() {
                self.e.d.next = self.in_base.val();
                self.cap.d.next = self.in_cap.val();
                self.b0.d.next = self.in_b0.val();
                self.b.d.next = 0.into();
                self.h.d.next = 1.into();
                self.rising.d.next = true;
                self.forced.d.next = self.in_setup.val();
                if self.in_setup.val() {
                    // R = 0 and e = 0: the trial makes Q = M(1) − 1 and e = 1.
                    self.rq.d.next = self.c_ones.val();
                    self.e.d.next = 0.into();
                    self.nst.next = self.k_try.val();
                } else if self.in_b0.val() == 0 {
                    self.nst.next = self.k_try.val();
                } else {
                    self.nst.next = self.k_up.val();
                }
            }
        } else if self.st.q.val() == self.k_up.val() {
            self.climb.next = true;
            if (self.b.q.val() + 1) == self.b0.q.val() {
                self.nst.next = self.k_try.val();
            }
        } else if self.st.q.val() == self.k_try.val() {
            self.x.d.next = (self.x.q.val() & !self.c_lo.val()) | (self.p.val() & self.c_lo.val());
            self.fit.d.next = (self.e.q.val() + self.h.q.val()) <= self.cap.q.val();
            self.nst.next = self.k_dec1.val();
        } else if self.st.q.val() == self.k_dec1.val() {
            self.x.d.next = (self.x.q.val() & self.c_lo.val()) | (self.p.val() & !self.c_lo.val());
            self.g.d.next = (self.g.q.val() & !self.c_lo.val()) | (self.p.val() & self.c_lo.val());
            if self.fit.q.val() | self.forced.q.val() {
                self.nst.next = self.k_dec2.val();
            } else {
                self.fall.next = true;
            }
        } else if self.st.q.val() == self.k_dec2.val() {
            self.g.d.next = (self.g.q.val() & self.c_lo.val()) | (self.p.val() & !self.c_lo.val());
            self.pass.d.next = self.p.val().get_bit(160) | self.forced.q.val();
            self.z.d.next = (self.z.q.val() & !self.c_lo.val()) | (self.p.val() & self.c_lo.val());
            self.nst.next = self.k_a2.val();
        } else if self.st.q.val() == self.k_a2.val() {
            self.z.d.next = (self.z.q.val() & self.c_lo.val()) | (self.p.val() & !self.c_lo.val());
            if self.pass.q.val() {
                self.rq.d.next = self.g.q.val();
                self.e.d.next = self.e.q.val() + self.h.q.val();
                self.nst.next = self.k_a3.val();
            } else {
                self.fall.next = true;
            }
        } else if self.st.q.val() == self.k_a3.val() {
            self.nst.next = self.k_a4.val();
        } else if self.st.q.val() == self.k_a4.val() {
            self.nst.next = self.k_wt.val();
        } else if self.st.q.val() == self.k_wt.val() {
            self.nst.next = self.k_sh.val();
        } else if self.st.q.val() == self.k_sh.val() {
            if self.forced.q.val() {
                // The setup's end: the words to the tick scale, at base 1.
                self.climb.next = true;
                self.nst.next = self.k_idle.val();
                self.fin.d.next = true;
            } else if self.rising.q.val() & (self.b.q.val() != self.c_top.val()) {
                self.climb.next = true;
                self.nst.next = self.k_try.val();
            } else {
                self.fall.next = true;
            }
        }

        // Up a digit: every word times 2^k (exact: the words fit 160 bits there).
        if self.climb.val() {
            self.w1.d.next = self.w1.q.val() << 1;
            self.w2.d.next = self.w2.q.val() << 2;
            self.w3.d.next = self.w3.q.val() << 3;
            self.w4.d.next = self.w4.q.val() << 4;
            self.b.d.next = self.b.q.val() + 1;
            self.h.d.next = self.h.q.val() << 1;
        }
        // Down a digit, or the end at digit 0; the rise is over either way.
        if self.fall.val() {
            self.rising.d.next = false;
            if self.b.q.val() == 0 {
                self.nst.next = self.k_idle.val();
                self.fin.d.next = true;
            } else {
                self.w1.d.next = self.dn1.val();
                self.w2.d.next = self.dn2.val();
                self.w3.d.next = self.dn3.val();
                self.w4.d.next = self.dn4.val();
                self.b.d.next = self.b.q.val() - 1;
                self.h.d.next = self.h.q.val() >> 1;
                self.nst.next = self.k_try.val();
            }
        }

        // The Taylor update's sums, each half where its operation writes it (no
        // shift or load happens to these words then); W3's only if the trial passed.
        if self.ws1.q.val() {
            self.w1.d.next = (self.w1.q.val() & !self.c_lo.val()) | (self.p.val() & self.c_lo.val());
        }
        if self.wh1.q.val() {
            self.w1.d.next = (self.w1.q.val() & self.c_lo.val()) | (self.p.val() & !self.c_lo.val());
        }
        if self.ws2.q.val() {
            self.w2.d.next = (self.w2.q.val() & !self.c_lo.val()) | (self.p.val() & self.c_lo.val());
        }
        if self.wh2.q.val() {
            self.w2.d.next = (self.w2.q.val() & self.c_lo.val()) | (self.p.val() & !self.c_lo.val());
        }
        if self.ws3.q.val() & self.pass.q.val() {
            self.w3.d.next = (self.w3.q.val() & !self.c_lo.val()) | (self.p.val() & self.c_lo.val());
        }
        if self.wh3.q.val() {
            self.w3.d.next = (self.w3.q.val() & self.c_lo.val()) | (self.p.val() & !self.c_lo.val());
        }

        // The next state, and the adder's operand and write selects for it; the high
        // half's a cycle later.
        self.st.d.next = self.nst.val();
        self.ws3.d.next = self.nst.val() == self.k_a2.val();
        self.ws1.d.next = self.nst.val() == self.k_a3.val();
        self.ws2.d.next = self.nst.val() == self.k_a4.val();
        self.wh3.d.next = self.nst.val() == self.k_a3.val();
        self.wh1.d.next = self.nst.val() == self.k_a4.val();
        self.wh2.d.next = self.nst.val() == self.k_wt.val();
        self.oa2.d.next = self.oa.q.val();
        self.ob2.d.next = self.ob.q.val();
        self.oc2.d.next = self.oc.q.val();
        self.oa.d.next = 0.into();
        self.ob.d.next = 0.into();
        self.oc.d.next = 0.into();
        if self.nst.val() == self.k_try.val() {
            self.oa.d.next = 1.into();
            self.ob.d.next = 1.into();
            self.oc.d.next = 1.into();
        } else if self.nst.val() == self.k_dec1.val() {
            self.oa.d.next = 2.into();
            self.ob.d.next = 2.into();
            self.oc.d.next = 2.into();
        } else if self.nst.val() == self.k_dec2.val() {
            self.ob.d.next = 3.into();
            self.oc.d.next = 1.into();
        } else if self.nst.val() == self.k_a2.val() {
            self.oa.d.next = 3.into();
            self.ob.d.next = 3.into();
        } else if self.nst.val() == self.k_a3.val() {
            self.oa.d.next = 2.into();
            self.ob.d.next = 1.into();
            self.oc.d.next = 3.into();
        } else if self.nst.val() == self.k_a4.val() {
            self.oa.d.next = 3.into();
            self.ob.d.next = 1.into();
            self.oc.d.next = 3.into();
        }

        self.busy.next = self.st.q.val() != self.k_idle.val();
        self.done.next = self.fin.q.val();
        self.out_edge.next = self.e.q.val();
        self.out_q.next = self.rq.q.val();
        self.out_w1.next = self.w1.q.val();
        self.out_w2.next = self.w2.q.val();
        self.out_w3.next = self.w3.q.val();
        self.out_w4.next = self.w4.q.val();
    }
}
