//! The polynomial (S-curve) segment's setup: from its five register values the
//! products the edge search starts from, exact. Bit for bit the model's
//! [`crate::model::poly::PolyPlan::setup_words`] (g = [8·c1, 4·c2, 2·c3, c4]) and its
//! step scale S = 2^36·T⁴ ([`crate::model::poly::PolyPlan`]'s `step`), with
//! c1 = v0·T⁴, c2 = A'·T², c3 = C'·T, c4 = Q' and
//! C' = 4n·2^32 − (3·v0 + v1)·T − 2A', Q' = (2·v0 + v1)·T + A' − 3n·2^32
//! (docs/model.md, "Polynomial segments").
//!
//! One shift-and-add multiplier, one multiplier bit per cycle, most significant first
//! (Horner: `acc = 2·acc + bit·x`, exact for a signed x and an unsigned multiplier),
//! runs a fixed program of eleven operations. The accumulator is kept in carry-save
//! form (a sum and a carry word, 130 bits each: one level of logic a cycle, no carry
//! chain), and each operation ends with two cycles of carry-propagate addition, the
//! low 65 bits and then the high 65 with the low half's carry registered, so no
//! carry chain is longer than 65 bits:
//!
//! | op | multiplier | x | acc after | kept |
//! |---|---|---|---|---|
//! | 0 | T | T | T² | |
//! | 1 | T | acc | T³ | |
//! | 2 | T | acc | T⁴ | S = T⁴·2^36 |
//! | 3 | v0 | acc | v0·T⁴ | c1 |
//! | 4 | T | A' | A'·T | |
//! | 5 | T | acc | A'·T² | c2 |
//! | 6 | T | 3·v0 + v1 | (3·v0 + v1)·T | |
//! | 7 | x − acc | 4n·2^32 − 2A' | C' | |
//! | 8 | T | acc | C'·T | c3 |
//! | 9 | T | 2·v0 + v1 | (2·v0 + v1)·T | |
//! | 10 | x + acc | A' − 3n·2^32 | Q' | c4 |
//!
//! A multiply by T takes 25 cycles (T ≤ 2^24 has 25 bits) and by v0 32, an add
//! (the operands into the sum and carry words) one, each then two for the
//! carry-propagate addition; the sums of the inputs (3·v0 + v1, 2·v0 + v1,
//! 4n·2^32 − 2A', A' − 3n·2^32) are
//! registered at the start. Widths: x holds 98 bits signed (T⁴ ≤ 2^96 is the widest
//! multiplicand), the accumulator 130 (v0·T⁴ < 2^127, and every partial sum of a
//! product is below the multiplicand times 2^32), the kept values their
//! [`crate::model::poly::POLY_COEFF_BITS`] and 97 bits for T⁴: exact for every valid
//! segment (the push check rejects the others before they reach the setup; for an
//! invalid one the outputs are not defined).
//!
//! Ports: pulse `start` while idle with `in_v0`, `in_v1` (Q0.32 steps/tick), `in_a`
//! (A', two's complement), `in_t` (T ≤ 2^24) and `in_n` (n = |θ| ≤ 2^24); they are
//! read on that edge only. `done` pulses one cycle [`POLY_SETUP_LATENCY`] cycles after
//! the start's edge, with `out_g1`..`out_g4` (the words g on the half-tick scale, as
//! [`super::poly_step::PolyStep`]'s setup takes them) and `out_s` (S), each 161 bits
//! two's complement, held until the next start. `busy` from the start's edge to
//! `done`. The block has no DSP and runs beside the edge search: a segment's setup
//! can proceed while the search serves other axes.

use super::poly_step::{ones_at, POLY_REG_BITS};
use crate::model::poly::{POLY_COEFF_BITS, POLY_T_LOG2};
use rust_hdl::prelude::*;

const W: usize = POLY_REG_BITS;
/// The accumulator and the adder.
const ACC: usize = 130;
/// The multiplicand.
const X: usize = 98;
/// Kept values: c1..c4 (signed) and T⁴ (unsigned).
const C1: usize = 128;
const C2: usize = 105;
const C3: usize = 82;
const C4: usize = 58;
const T4: usize = 97;
// Sign bits are read by literal indices (rust-hdl writes a constant's name into the
// Verilog); these hold the literals to the model's widths.
const _: () = assert!(
    ACC == 130
        && X == 98
        && C1 as u32 == POLY_COEFF_BITS[0]
        && C2 as u32 == POLY_COEFF_BITS[1]
        && C3 as u32 == POLY_COEFF_BITS[2]
        && C4 as u32 == POLY_COEFF_BITS[3]
        && T4 as u32 == 4 * POLY_T_LOG2 + 1
        && W == 161
);

/// Bits of T (T ≤ 2^24) and of v0: the cycles of a multiply by each. The update
/// writes them as the literals 25 and 32, T's shift to the top as 7.
const T_BITS: u64 = POLY_T_LOG2 as u64 + 1;
const V_BITS: u64 = 32;
const _: () = assert!(T_BITS == 25 && V_BITS == 32);

/// Cycles from the `start` edge to `done`: one to register the inputs' sums, eight
/// multiplies by T, one by v0 and two adds (each with its two cycles of
/// carry-propagate addition), and one for `done`: 258.
pub const POLY_SETUP_LATENCY: usize = 1 + 8 * (T_BITS as usize + 2) + (V_BITS as usize + 2) + 2 * (1 + 2) + 1;
const _: () = assert!(POLY_SETUP_LATENCY == 258);

#[derive(LogicBlock)]
pub struct PolySetup {
    pub clock: Signal<In, Clock>,
    pub start: Signal<In, Bit>,
    pub in_v0: Signal<In, Bits<32>>,
    pub in_v1: Signal<In, Bits<32>>,
    pub in_a: Signal<In, Bits<64>>,
    pub in_t: Signal<In, Bits<32>>,
    pub in_n: Signal<In, Bits<32>>,
    pub busy: Signal<Out, Bit>,
    pub done: Signal<Out, Bit>,
    pub out_g1: Signal<Out, Bits<W>>,
    pub out_g2: Signal<Out, Bits<W>>,
    pub out_g3: Signal<Out, Bits<W>>,
    pub out_g4: Signal<Out, Bits<W>>,
    pub out_s: Signal<Out, Bits<W>>,
    /// Running: 0 idle, 1 the start's sums, 2 the program.
    run: DFF<Bits<2>>,
    /// The operation (0..10) and the cycles left in it.
    pc: DFF<Bits<4>>,
    cnt: DFF<Bits<6>>,
    /// The first cycle of a multiply: the accumulator reads as 0.
    first: DFF<Bit>,
    /// 0: the operation's cycles (carry-save); 1, 2: the low and high halves of the
    /// carry-propagate addition.
    ph: DFF<Bits<2>>,
    /// The accumulator in carry-save form, and the last result (`res`, its low half
    /// first, with the low half's carry `rc`; `cin`: add 1 at the low end, x − acc).
    acc_s: DFF<Bits<ACC>>,
    acc_c: DFF<Bits<ACC>>,
    res: DFF<Bits<ACC>>,
    rc: DFF<Bits<1>>,
    cin: DFF<Bits<1>>,
    x: DFF<Bits<X>>,
    /// The multiplier, most significant bit first (T aligned to the top).
    y: DFF<Bits<32>>,
    t: DFF<Bits<32>>,
    v0: DFF<Bits<32>>,
    a: DFF<Bits<64>>,
    u3: DFF<Bits<34>>,
    u2: DFF<Bits<34>>,
    k_c: DFF<Bits<X>>,
    k_q: DFF<Bits<X>>,
    c1: DFF<Bits<C1>>,
    c2: DFF<Bits<C2>>,
    c3: DFF<Bits<C3>>,
    c4: DFF<Bits<C4>>,
    t4: DFF<Bits<T4>>,
    fin: DFF<Bit>,
    fill_x64: Constant<Bits<X>>,
    fill_acc: Constant<Bits<ACC>>,
    fill_c2: Constant<Bits<W>>,
    fill_c3: Constant<Bits<W>>,
    fill_c4: Constant<Bits<W>>,
    /// A' on the multiplicand's width (from the register, and from the port), and
    /// n·2^32.
    a_x: Signal<Local, Bits<X>>,
    in_a_x: Signal<Local, Bits<X>>,
    n32: Signal<Local, Bits<X>>,
    /// The carry-save step's inputs (2·sum, 2·carry, bit·x) and the halves' sums.
    xs: Signal<Local, Bits<ACC>>,
    op_a: Signal<Local, Bits<ACC>>,
    op_b: Signal<Local, Bits<ACC>>,
    op_x: Signal<Local, Bits<ACC>>,
    lo: Signal<Local, Bits<66>>,
    hi: Signal<Local, Bits<65>>,
    sum: Signal<Local, Bits<ACC>>,
    /// The operation after this one and its multiplicand.
    nxt: Signal<Local, Bits<4>>,
    nx: Signal<Local, Bits<X>>,
    sum_x: Signal<Local, Bits<X>>,
}

impl Default for PolySetup {
    fn default() -> Self {
        PolySetup {
            clock: Default::default(),
            start: Default::default(),
            in_v0: Default::default(),
            in_v1: Default::default(),
            in_a: Default::default(),
            in_t: Default::default(),
            in_n: Default::default(),
            busy: Default::default(),
            done: Default::default(),
            out_g1: Default::default(),
            out_g2: Default::default(),
            out_g3: Default::default(),
            out_g4: Default::default(),
            out_s: Default::default(),
            run: Default::default(),
            pc: Default::default(),
            cnt: Default::default(),
            first: Default::default(),
            ph: Default::default(),
            acc_s: Default::default(),
            acc_c: Default::default(),
            res: Default::default(),
            rc: Default::default(),
            cin: Default::default(),
            x: Default::default(),
            y: Default::default(),
            t: Default::default(),
            v0: Default::default(),
            a: Default::default(),
            u3: Default::default(),
            u2: Default::default(),
            k_c: Default::default(),
            k_q: Default::default(),
            c1: Default::default(),
            c2: Default::default(),
            c3: Default::default(),
            c4: Default::default(),
            t4: Default::default(),
            fin: Default::default(),
            fill_x64: ones_at(X - 64, 64),
            fill_acc: ones_at(ACC - X, X),
            fill_c2: ones_at(W - C2, C2),
            fill_c3: ones_at(W - C3, C3),
            fill_c4: ones_at(W - C4, C4),
            a_x: Default::default(),
            in_a_x: Default::default(),
            n32: Default::default(),
            xs: Default::default(),
            op_a: Default::default(),
            op_b: Default::default(),
            op_x: Default::default(),
            lo: Default::default(),
            hi: Default::default(),
            sum: Default::default(),
            nxt: Default::default(),
            nx: Default::default(),
            sum_x: Default::default(),
        }
    }
}

impl Logic for PolySetup {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clock, run, pc, cnt, first, ph, acc_s, acc_c, res, rc, cin, x, y, t, v0, a, u3, u2, k_c, k_q, c1, c2,
            c3, c4, t4, fin
        );

        // A' sign-extended to the multiplicand's width (from the register and the port).
        self.a_x.next = bit_cast::<X, 64>(self.a.q.val());
        if self.a.q.val().get_bit(63) {
            self.a_x.next = bit_cast::<X, 64>(self.a.q.val()) | self.fill_x64.val();
        }
        self.in_a_x.next = bit_cast::<X, 64>(self.in_a.val());
        if self.in_a.val().get_bit(63) {
            self.in_a_x.next = bit_cast::<X, 64>(self.in_a.val()) | self.fill_x64.val();
        }
        self.n32.next = bit_cast::<X, 32>(self.in_n.val()) << 32;

        // The carry-save step: 2·acc + bit·x with acc = sum + carry (0 + bit·x first).
        self.xs.next = bit_cast::<ACC, X>(self.x.q.val());
        if self.x.q.val().get_bit(97) {
            self.xs.next = bit_cast::<ACC, X>(self.x.q.val()) | self.fill_acc.val();
        }
        self.op_a.next = self.acc_s.q.val() << 1;
        self.op_b.next = self.acc_c.q.val() << 1;
        if self.first.q.val() {
            self.op_a.next = 0.into();
            self.op_b.next = 0.into();
        }
        self.op_x.next = 0.into();
        if self.y.q.val().get_bit(31) {
            self.op_x.next = self.xs.val();
        }
        // The carry-propagate addition of sum and carry: the low 65 bits (with the
        // carry in of x − acc), then the high 65 with the low half's carry.
        self.lo.next = bit_cast::<66, 65>(self.acc_s.q.val().get_bits::<65>(0))
            + bit_cast::<66, 65>(self.acc_c.q.val().get_bits::<65>(0))
            + bit_cast::<66, 1>(self.cin.q.val());
        self.hi.next = self.acc_s.q.val().get_bits::<65>(65)
            + self.acc_c.q.val().get_bits::<65>(65)
            + bit_cast::<65, 1>(self.rc.q.val());
        self.sum.next = (bit_cast::<ACC, 65>(self.hi.val()) << 65) | bit_cast::<ACC, 65>(self.res.q.val().get_bits::<65>(0));
        self.sum_x.next = self.sum.val().get_bits::<X>(0);

        // The next operation's multiplicand.
        self.nxt.next = self.pc.q.val() + 1;
        self.nx.next = self.sum_x.val();
        if self.nxt.val() == 4 {
            self.nx.next = self.a_x.val();
        } else if self.nxt.val() == 6 {
            self.nx.next = bit_cast::<X, 34>(self.u3.q.val());
        } else if self.nxt.val() == 7 {
            self.nx.next = self.k_c.q.val();
        } else if self.nxt.val() == 9 {
            self.nx.next = bit_cast::<X, 34>(self.u2.q.val());
        } else if self.nxt.val() == 10 {
            self.nx.next = self.k_q.q.val();
        }

        self.fin.d.next = false;
        if self.run.q.val() == 0 {
            if self.start.val() {
                self.t.d.next = self.in_t.val();
                self.v0.d.next = self.in_v0.val();
                self.a.d.next = self.in_a.val();
                self.run.d.next = 1.into();
            }
        } else if self.run.q.val() == 1 {
            // Operation 0: T·T.
            self.run.d.next = 2.into();
            self.pc.d.next = 0.into();
            self.ph.d.next = 0.into();
            self.cnt.d.next = 25.into();
            self.first.d.next = true;
            self.cin.d.next = 0.into();
            self.x.d.next = bit_cast::<X, 32>(self.t.q.val());
            self.y.d.next = self.t.q.val() << 7;
        } else if self.ph.q.val() == 0 {
            // The operation's cycles: a multiply step, or an add's operands into the
            // sum and carry words (x + res, or x + ¬res + 1 for x − res).
            if self.pc.q.val() == 7 {
                self.acc_s.d.next = self.xs.val();
                self.acc_c.d.next = !self.res.q.val();
                self.cin.d.next = 1.into();
            } else if self.pc.q.val() == 10 {
                self.acc_s.d.next = self.xs.val();
                self.acc_c.d.next = self.res.q.val();
            } else {
                self.acc_s.d.next = self.op_a.val() ^ self.op_b.val() ^ self.op_x.val();
                self.acc_c.d.next = ((self.op_a.val() & self.op_b.val())
                    | (self.op_a.val() & self.op_x.val())
                    | (self.op_b.val() & self.op_x.val()))
                    << 1;
            }
            self.first.d.next = false;
            self.y.d.next = self.y.q.val() << 1;
            self.cnt.d.next = self.cnt.q.val() - 1;
            if self.cnt.q.val() == 1 {
                self.ph.d.next = 1.into();
            }
        } else if self.ph.q.val() == 1 {
            self.res.d.next = bit_cast::<ACC, 65>(self.lo.val().get_bits::<65>(0));
            self.rc.d.next = self.lo.val().get_bits::<1>(65);
            self.cin.d.next = 0.into();
            self.ph.d.next = 2.into();
        } else {
            // The operation's end: its result, kept where the table says; the next.
            self.res.d.next = self.sum.val();
            if self.pc.q.val() == 2 {
                self.t4.d.next = self.sum.val().get_bits::<T4>(0);
            } else if self.pc.q.val() == 3 {
                self.c1.d.next = self.sum.val().get_bits::<C1>(0);
            } else if self.pc.q.val() == 5 {
                self.c2.d.next = self.sum.val().get_bits::<C2>(0);
            } else if self.pc.q.val() == 8 {
                self.c3.d.next = self.sum.val().get_bits::<C3>(0);
            } else if self.pc.q.val() == 10 {
                self.c4.d.next = self.sum.val().get_bits::<C4>(0);
            }
            self.ph.d.next = 0.into();
            self.pc.d.next = self.nxt.val();
            self.x.d.next = self.nx.val();
            self.first.d.next = true;
            self.y.d.next = self.t.q.val() << 7;
            self.cnt.d.next = 25.into();
            if self.nxt.val() == 3 {
                self.y.d.next = self.v0.q.val();
                self.cnt.d.next = 32.into();
            } else if (self.nxt.val() == 7) | (self.nxt.val() == 10) {
                self.cnt.d.next = 1.into();
            }
            if self.pc.q.val() == 10 {
                self.run.d.next = 0.into();
                self.fin.d.next = true;
            }
        }
        // The inputs' sums, registered on the start's edge (from the ports) and kept.
        if (self.run.q.val() == 0) & self.start.val() {
            self.u3.d.next = bit_cast::<34, 32>(self.in_v0.val())
                + (bit_cast::<34, 32>(self.in_v0.val()) << 1)
                + bit_cast::<34, 32>(self.in_v1.val());
            self.u2.d.next = (bit_cast::<34, 32>(self.in_v0.val()) << 1) + bit_cast::<34, 32>(self.in_v1.val());
            self.k_c.d.next = (self.n32.val() << 2) - (self.in_a_x.val() << 1);
            self.k_q.d.next = self.in_a_x.val() - (self.n32.val() << 1) - self.n32.val();
        }

        self.busy.next = self.run.q.val() != 0;
        self.done.next = self.fin.q.val();
        self.out_g1.next = bit_cast::<W, C1>(self.c1.q.val()) << 3;
        self.out_g2.next = bit_cast::<W, C2>(self.c2.q.val()) << 2;
        if self.c2.q.val().get_bit(104) {
            self.out_g2.next = (bit_cast::<W, C2>(self.c2.q.val()) | self.fill_c2.val()) << 2;
        }
        self.out_g3.next = bit_cast::<W, C3>(self.c3.q.val()) << 1;
        if self.c3.q.val().get_bit(81) {
            self.out_g3.next = (bit_cast::<W, C3>(self.c3.q.val()) | self.fill_c3.val()) << 1;
        }
        self.out_g4.next = bit_cast::<W, C4>(self.c4.q.val());
        if self.c4.q.val().get_bit(57) {
            self.out_g4.next = bit_cast::<W, C4>(self.c4.q.val()) | self.fill_c4.val();
        }
        self.out_s.next = bit_cast::<W, T4>(self.t4.q.val()) << 36;
    }
}
