//! The polynomial (S-curve) unit: the setup ([`PolySetup`]) and the edge search
//! ([`PolyStep`]) with every axis's search state in block RAM, two slots per axis
//! (the running segment and the next one, set up ahead of time). It serves one
//! request at a time: the scheduler asks for a slot's setup or for its next period.
//! Bit for bit the model: a slot set up from a [`crate::model::poly::PolySegment`]
//! gives, step by step, the periods E_i − E_{i−1} of
//! [`crate::model::poly::PolyPlan::setup_state`] searched by
//! [`crate::model::poly::PolySearch::next_edge_galloping`] from the digit of the
//! period before (`gallop_start`), and E_n = T for the last step.
//!
//! Per slot the RAM holds the five search words (W1..W4 and Q = ¬(R + S), the next
//! step's remainder with S already added: 161 bits each) and one word of scalars: the
//! last edge E_i (`prev`), T − 1 (`cap`), the steps left, the next start digit and T⁴
//! (S = 2^36·T⁴). A slot's words start at a multiple of 8 (slot address · 8, three
//! entries unused), so no adder stands between the request's axis and slot and the
//! word RAM's read address (on ECP5 the ·5 adder was on the K = 2 core's critical
//! path). Memory per axis: 16 × 161 + 2 × 177 = 2,930 bits, of which 10 × 161 + 2 ×
//! 177 = 1,964 are used (in block RAM the depth costs nothing up to 512 entries, K =
//! 16 is 256).
//!
//! Ports: while idle (`busy` low), pulse
//! * `setup` with `axis`, `slot`, `in_v0`, `in_v1`, `in_a`, `in_t`, `in_n` (a valid
//!   segment's fields, n = |θ| ≥ 1; read on that edge only): [`UNIT_SETUP_CYCLES`]
//!   (274) cycles later `done` pulses (with `period` 0): the slot's
//!   state is at base 1 ([`crate::model::poly::PolyPlan::setup_state`]);
//! * `step` with `axis`, `slot` (a set-up slot with steps left): `done` pulses with
//!   `period` (E_{i+1} − E_i ticks) and `last` (it was step n), after
//!   [`UNIT_LOAD_CYCLES`] + the search's latency
//!   (`GallopStats::unit_cycles`) + 1 cycles, or [`UNIT_LAST_CYCLES`] for step n (no
//!   search: E_n = T). After a searched step's (or a setup's) `done`, `busy` falls
//!   [`UNIT_STORE_CYCLES`] cycles later, once the state is written back; the
//!   scheduler can use the period meanwhile.
//!
//! `done`, `period` and `last` are registered; `period` and `last` hold until the
//! next request. The state moves between the RAM and the search through
//! [`PolyStep`]'s five-word chain, one word a cycle each way; Q − S is formed on the
//! way back (one 161-bit subtractor).

use super::block_ram::BlockRam;
use super::poly_setup::{PolySetup, POLY_SETUP_LATENCY};
use super::poly_step::{ones_at, PolyStep, POLY_REG_BITS};
use rust_hdl::prelude::*;

const W: usize = POLY_REG_BITS;
/// The scalar word: prev (25), cap (25), left (25), b0 (5), T⁴ (97).
const SW: usize = 177;
const _: () = assert!(SW == 25 + 25 + 25 + 5 + 97 && W == 161);

/// Most axes (4 bits of axis).
pub const POLY_UNIT_MAX_AXES: usize = 16;

/// Cycles from `setup`'s edge to `done`, beyond [`POLY_SETUP_LATENCY`]: the words g
/// into the chain (5), the start (1), the search's setup (9) and `done` (1).
pub const UNIT_SETUP_EXTRA: usize = 5 + 1 + 9 + 1;
/// Cycles from `setup`'s edge to `done`.
pub const UNIT_SETUP_CYCLES: usize = POLY_SETUP_LATENCY + UNIT_SETUP_EXTRA;
/// Cycles from `step`'s edge to the search's start: the five words in.
pub const UNIT_LOAD_CYCLES: usize = 6;
/// Cycles from `step`'s edge to `done` for a slot's last step.
pub const UNIT_LAST_CYCLES: usize = 2;
/// Cycles from a searched step's (or a setup's) `done` to `busy` falling: the five
/// words back.
pub const UNIT_STORE_CYCLES: usize = 5;

const ST_IDLE: u64 = 0;
const ST_SETUP: u64 = 1;
const ST_GIN: u64 = 2;
const ST_LOAD: u64 = 3;
const ST_GO: u64 = 4;
const ST_RUN: u64 = 5;
const ST_STORE: u64 = 6;

#[derive(LogicBlock)]
pub struct PolyUnit {
    pub clock: Signal<In, Clock>,
    pub setup: Signal<In, Bit>,
    pub step: Signal<In, Bit>,
    pub axis: Signal<In, Bits<4>>,
    pub slot: Signal<In, Bits<1>>,
    pub in_v0: Signal<In, Bits<32>>,
    pub in_v1: Signal<In, Bits<32>>,
    pub in_a: Signal<In, Bits<64>>,
    pub in_t: Signal<In, Bits<32>>,
    pub in_n: Signal<In, Bits<32>>,
    pub busy: Signal<Out, Bit>,
    pub done: Signal<Out, Bit>,
    pub period: Signal<Out, Bits<32>>,
    pub last: Signal<Out, Bit>,
    ps: PolySetup,
    srch: PolyStep,
    words: BlockRam<W, 8>,
    scalars: BlockRam<SW, 5>,
    st: DFF<Bits<3>>,
    cnt: DFF<Bits<3>>,
    /// The request's slot address (axis·2 + slot) and its first word's address.
    sa: DFF<Bits<5>>,
    wa: DFF<Bits<8>>,
    is_setup: DFF<Bit>,
    prev: DFF<Bits<25>>,
    cap: DFF<Bits<25>>,
    left: DFF<Bits<25>>,
    b0: DFF<Bits<5>>,
    t4: DFF<Bits<97>>,
    fin: DFF<Bit>,
    /// The next start digit, registered when the search ends (0 after a setup): the
    /// scalar word's write takes it from a flip-flop, not through the period's
    /// subtractor and the digit's priority chain (the K = 2 core's critical path).
    nb: DFF<Bits<5>>,
    per: DFF<Bits<32>>,
    lst: DFF<Bit>,
    c_ones: Constant<Bits<W>>,
    k_idle: Constant<Bits<3>>,
    k_setup: Constant<Bits<3>>,
    k_gin: Constant<Bits<3>>,
    k_load: Constant<Bits<3>>,
    k_go: Constant<Bits<3>>,
    k_run: Constant<Bits<3>>,
    k_store: Constant<Bits<3>>,
    /// The request's slot address from the ports, and its first word's (·8).
    in_sa: Signal<Local, Bits<8>>,
    in_wa: Signal<Local, Bits<8>>,
    /// The scalar word as read.
    r_prev: Signal<Local, Bits<25>>,
    r_cap: Signal<Local, Bits<25>>,
    r_left: Signal<Local, Bits<25>>,
    /// The period a searched step found, and its digit (the next start digit).
    d: Signal<Local, Bits<25>>,
    dig: Signal<Local, Bits<5>>,
    s_wide: Signal<Local, Bits<W>>,
    /// The scalar word's fields that a step and a setup write differently.
    w_prev: Signal<Local, Bits<25>>,
    w_left: Signal<Local, Bits<25>>,
    g_word: Signal<Local, Bits<W>>,
}

impl PolyUnit {
    /// A unit for `k` axes (1..=16).
    pub fn new(k: usize) -> PolyUnit {
        assert!((1..=POLY_UNIT_MAX_AXES).contains(&k), "PolyUnit: {k} axes");
        PolyUnit {
            clock: Default::default(),
            setup: Default::default(),
            step: Default::default(),
            axis: Default::default(),
            slot: Default::default(),
            in_v0: Default::default(),
            in_v1: Default::default(),
            in_a: Default::default(),
            in_t: Default::default(),
            in_n: Default::default(),
            busy: Default::default(),
            done: Default::default(),
            period: Default::default(),
            last: Default::default(),
            ps: Default::default(),
            srch: Default::default(),
            words: BlockRam::new(16 * k),
            scalars: BlockRam::new(2 * k),
            st: Default::default(),
            cnt: Default::default(),
            sa: Default::default(),
            wa: Default::default(),
            is_setup: Default::default(),
            prev: Default::default(),
            cap: Default::default(),
            left: Default::default(),
            b0: Default::default(),
            t4: Default::default(),
            fin: Default::default(),
            nb: Default::default(),
            per: Default::default(),
            lst: Default::default(),
            c_ones: ones_at(W, 0),
            k_idle: Constant::new(ST_IDLE.into()),
            k_setup: Constant::new(ST_SETUP.into()),
            k_gin: Constant::new(ST_GIN.into()),
            k_load: Constant::new(ST_LOAD.into()),
            k_go: Constant::new(ST_GO.into()),
            k_run: Constant::new(ST_RUN.into()),
            k_store: Constant::new(ST_STORE.into()),
            in_sa: Default::default(),
            in_wa: Default::default(),
            r_prev: Default::default(),
            r_cap: Default::default(),
            r_left: Default::default(),
            d: Default::default(),
            dig: Default::default(),
            s_wide: Default::default(),
            w_prev: Default::default(),
            w_left: Default::default(),
            g_word: Default::default(),
        }
    }
}

impl Logic for PolyUnit {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, st, cnt, sa, wa, is_setup, prev, cap, left, b0, t4, fin, nb, per, lst);
        self.ps.clock.next = self.clock.val();
        self.srch.clock.next = self.clock.val();
        self.words.clock.next = self.clock.val();
        self.scalars.clock.next = self.clock.val();

        self.in_sa.next = (bit_cast::<8, 4>(self.axis.val()) << 1) | bit_cast::<8, 1>(self.slot.val());
        self.in_wa.next = self.in_sa.val() << 3;
        self.r_prev.next = self.scalars.rdata.val().get_bits::<25>(0);
        self.r_cap.next = self.scalars.rdata.val().get_bits::<25>(25);
        self.r_left.next = self.scalars.rdata.val().get_bits::<25>(50);
        self.s_wide.next = bit_cast::<W, 97>(self.t4.q.val()) << 36;

        // The period a search found and its digit ⌊log2⌋ (≤ 24): the next start.
        self.d.next = self.srch.out_edge.val().get_bits::<25>(0) - self.prev.q.val();
        self.dig.next = 0.into();
        if self.d.val().get_bit(1) {
            self.dig.next = 1.into();
        }
        if self.d.val().get_bit(2) {
            self.dig.next = 2.into();
        }
        if self.d.val().get_bit(3) {
            self.dig.next = 3.into();
        }
        if self.d.val().get_bit(4) {
            self.dig.next = 4.into();
        }
        if self.d.val().get_bit(5) {
            self.dig.next = 5.into();
        }
        if self.d.val().get_bit(6) {
            self.dig.next = 6.into();
        }
        if self.d.val().get_bit(7) {
            self.dig.next = 7.into();
        }
        if self.d.val().get_bit(8) {
            self.dig.next = 8.into();
        }
        if self.d.val().get_bit(9) {
            self.dig.next = 9.into();
        }
        if self.d.val().get_bit(10) {
            self.dig.next = 10.into();
        }
        if self.d.val().get_bit(11) {
            self.dig.next = 11.into();
        }
        if self.d.val().get_bit(12) {
            self.dig.next = 12.into();
        }
        if self.d.val().get_bit(13) {
            self.dig.next = 13.into();
        }
        if self.d.val().get_bit(14) {
            self.dig.next = 14.into();
        }
        if self.d.val().get_bit(15) {
            self.dig.next = 15.into();
        }
        if self.d.val().get_bit(16) {
            self.dig.next = 16.into();
        }
        if self.d.val().get_bit(17) {
            self.dig.next = 17.into();
        }
        if self.d.val().get_bit(18) {
            self.dig.next = 18.into();
        }
        if self.d.val().get_bit(19) {
            self.dig.next = 19.into();
        }
        if self.d.val().get_bit(20) {
            self.dig.next = 20.into();
        }
        if self.d.val().get_bit(21) {
            self.dig.next = 21.into();
        }
        if self.d.val().get_bit(22) {
            self.dig.next = 22.into();
        }
        if self.d.val().get_bit(23) {
            self.dig.next = 23.into();
        }
        if self.d.val().get_bit(24) {
            self.dig.next = 24.into();
        }

        // The setup block takes its request straight from the ports.
        self.ps.start.next = (self.st.q.val() == self.k_idle.val()) & self.setup.val();
        self.ps.in_v0.next = self.in_v0.val();
        self.ps.in_v1.next = self.in_v1.val();
        self.ps.in_a.next = self.in_a.val();
        self.ps.in_t.next = self.in_t.val();
        self.ps.in_n.next = self.in_n.val();

        // The words g into the chain, g1 first (the fifth, Q, is set by the search's
        // setup itself).
        self.g_word.next = self.c_ones.val();
        if self.cnt.q.val() == 0 {
            self.g_word.next = self.ps.out_g1.val();
        } else if self.cnt.q.val() == 1 {
            self.g_word.next = self.ps.out_g2.val();
        } else if self.cnt.q.val() == 2 {
            self.g_word.next = self.ps.out_g3.val();
        } else if self.cnt.q.val() == 3 {
            self.g_word.next = self.ps.out_g4.val();
        }

        self.srch.shift.next = false;
        self.srch.shift_in.next = self.words.rdata.val();
        self.srch.start.next = false;
        self.srch.in_base.next = bit_cast::<32, 25>(self.prev.q.val());
        if self.prev.q.val() == 0 {
            self.srch.in_base.next = 1.into();
        }
        self.srch.in_cap.next = bit_cast::<32, 25>(self.cap.q.val());
        self.srch.in_b0.next = self.b0.q.val();
        self.srch.in_setup.next = self.is_setup.q.val();

        self.words.we.next = false;
        self.words.waddr.next = self.wa.q.val() + bit_cast::<8, 3>(self.cnt.q.val());
        self.words.wdata.next = self.srch.out_w1.val();
        if self.cnt.q.val() == 4 {
            self.words.wdata.next = self.srch.out_w1.val() - self.s_wide.val();
        }
        self.words.raddr.next = self.wa.q.val() + bit_cast::<8, 3>(self.cnt.q.val()) + 1;
        self.scalars.we.next = false;
        self.scalars.waddr.next = self.sa.q.val();
        // The scalar word written back: after a step its edge, one step fewer and
        // the digit of its period; after a setup base 0, n steps and digit 0.
        self.w_prev.next = self.srch.out_edge.val().get_bits::<25>(0);
        self.w_left.next = self.left.q.val() - 1;
        if self.is_setup.q.val() {
            self.w_prev.next = 0.into();
            self.w_left.next = self.left.q.val();
        }
        self.scalars.wdata.next = bit_cast::<SW, 25>(self.w_prev.val())
            | (bit_cast::<SW, 25>(self.cap.q.val()) << 25)
            | (bit_cast::<SW, 25>(self.w_left.val()) << 50)
            | (bit_cast::<SW, 5>(self.nb.q.val()) << 75)
            | (bit_cast::<SW, 97>(self.t4.q.val()) << 80);
        self.scalars.raddr.next = self.sa.q.val();

        self.fin.d.next = false;
        if self.st.q.val() == self.k_idle.val() {
            self.sa.d.next = self.in_sa.val().get_bits::<5>(0);
            self.wa.d.next = self.in_wa.val();
            self.scalars.raddr.next = self.in_sa.val().get_bits::<5>(0);
            self.words.raddr.next = self.in_wa.val();
            self.cnt.d.next = 0.into();
            if self.setup.val() {
                self.is_setup.d.next = true;
                self.cap.d.next = self.in_t.val().get_bits::<25>(0) - 1;
                self.left.d.next = self.in_n.val().get_bits::<25>(0);
                self.st.d.next = self.k_setup.val();
                self.lst.d.next = false;
                self.per.d.next = 0.into();
            } else if self.step.val() {
                self.is_setup.d.next = false;
                self.st.d.next = self.k_load.val();
            }
        } else if self.st.q.val() == self.k_setup.val() {
            if self.ps.done.val() {
                self.t4.d.next = self.ps.out_s.val().get_bits::<97>(36);
                self.st.d.next = self.k_gin.val();
            }
        } else if self.st.q.val() == self.k_gin.val() {
            self.srch.shift.next = true;
            self.srch.shift_in.next = self.g_word.val();
            self.cnt.d.next = self.cnt.q.val() + 1;
            if self.cnt.q.val() == 4 {
                self.st.d.next = self.k_go.val();
            }
        } else if self.st.q.val() == self.k_load.val() {
            // Word cnt arrives (its read was issued the cycle before); the scalars
            // arrive with word 0.
            self.srch.shift.next = true;
            self.cnt.d.next = self.cnt.q.val() + 1;
            if self.cnt.q.val() == 0 {
                self.prev.d.next = self.r_prev.val();
                self.cap.d.next = self.r_cap.val();
                self.left.d.next = self.r_left.val();
                self.b0.d.next = self.scalars.rdata.val().get_bits::<5>(75);
                self.t4.d.next = self.scalars.rdata.val().get_bits::<97>(80);
                if self.r_left.val() == 1 {
                    // Step n: E_n = T, no search; the slot is spent.
                    self.per.d.next = bit_cast::<32, 25>(self.r_cap.val() + 1 - self.r_prev.val());
                    self.lst.d.next = true;
                    self.fin.d.next = true;
                    self.st.d.next = self.k_idle.val();
                }
            }
            if self.cnt.q.val() == 4 {
                self.st.d.next = self.k_go.val();
            }
        } else if self.st.q.val() == self.k_go.val() {
            self.srch.start.next = true;
            self.cnt.d.next = 0.into();
            self.st.d.next = self.k_run.val();
        } else if self.st.q.val() == self.k_run.val() {
            if self.srch.done.val() {
                self.nb.d.next = 0.into();
                if !self.is_setup.q.val() {
                    self.per.d.next = bit_cast::<32, 25>(self.d.val());
                    self.nb.d.next = self.dig.val();
                    self.lst.d.next = false;
                }
                self.fin.d.next = true;
                self.st.d.next = self.k_store.val();
            }
        } else if self.st.q.val() == self.k_store.val() {
            // Word cnt out of the chain into the RAM (Q less S); the scalars last.
            self.srch.shift.next = true;
            self.words.we.next = true;
            self.cnt.d.next = self.cnt.q.val() + 1;
            if self.cnt.q.val() == 4 {
                self.scalars.we.next = true;
                self.st.d.next = self.k_idle.val();
            }
        }

        self.busy.next = self.st.q.val() != self.k_idle.val();
        self.done.next = self.fin.q.val();
        self.period.next = self.per.q.val();
        self.last.next = self.lst.q.val();
    }
}
