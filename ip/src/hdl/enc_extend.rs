//! The extension of K axes' narrow encoder counts to 32 bits, shared and round robin
//! (`export --encoder`). Each cycle it takes the sample the parent registered at the
//! last edge of axis `ax`'s narrow decoder outputs ([`super::enc_decoder::EncDecoder`],
//! 8 bits: the visit, every K ticks, of the axis the following-error unit takes) and,
//! from it and the axis's last count in memory, writes the axis's 32-bit count, its
//! index and probe latches (when the decoder shows a new one) and its live word
//! (velocity, illegal count, flags), and registers the count for the following-error
//! unit's stage 2. It equals
//! `model::encoder::ExtendModel` clock for clock (tests/hdl_encoder.rs, through
//! [`super::enc_bank::EncoderBank`], three ways); the model's example test (tests/model_props.rs) shows the
//! extended values equal the full-width count and latches at every visit.
//!
//! The arithmetic: with `base` the axis's last count (0 before its first visit since
//! reset, or after a clear the decoder reports, `cnew`: the narrow count then counts
//! from the clear), the count is `base + sext(count − base mod 2^8)`; the latches the
//! same with their own flags (`iafter`, `pafter`). Exact while a count moves less than
//! 2^7 between visits: it moves at most once a tick, K ≤ 16 times. The velocity the
//! same way from the decoder's 8-bit wrapping counters: `age` is the narrow one after
//! an edge (`enew`), else the last `age` plus the narrow counter's growth, saturating
//! at 0xFFFF; `period` is written when an edge came: the narrow one after two
//! (`e2`), else the last `age` plus the growth to the edge, saturating.
//!
//! Ports:
//! * `ax`: the axis visited at the last edge (the parent's sample register), `ok`: the
//!   sample was taken out of reset (else nothing is written); `next_ax`: the axis
//!   visited now (whose "visited since reset" bit and last count and age are read from
//!   memory and registered for the next cycle, out of the arithmetic's path; the
//!   parent's `ax` at the next edge); the parent drives the
//!   sample of that axis's decoder outputs `count`, `index_count`, `probe_count`,
//!   `period`, `age` (8 bits), `cnew`, `inew`, `iafter`, `pnew`, `pafter`, `enew`,
//!   `e2` and `live` (`model::encoder::live_word`: illegal 7..0, armed 8, last
//!   direction 9, levels A, B, Z 12..10), registered at the visit, and acknowledged
//!   the visit to the decoder then.
//! * `index_pos` (8 bits, the sample's, with `count`): the low byte of the step
//!   position the axis's decoder latched at its last index; `pos` (a register in the
//!   parent, the following error's stage 1): the axis's step position in the cycle
//!   the sample was taken. With `inew` (or at the first visit) the index position
//!   `pos − sext(pos − index_pos mod 2^8)` is written: exact while the axis moved
//!   fewer than 2^7 steps since the index, which came at most K + 1 ticks earlier.
//! * `count1` (a register): the count of the sample taken at the last edge.
//! * `sel` → `s_count`, `s_index`, `s_probe`, `s_ipos` (32 bits), `s_period`, `s_age` (16
//!   bits), `s_live`, `s_itog`, `s_ptog`
//!   (flip each time a new latch is written), `s_valid` (the axis was visited since
//!   reset: before that the words are undefined): axis `sel`'s words, read from LUT
//!   RAM asynchronously.
//!
//! Latency: a visit's sample is written at the next edge; what the bus reads is at
//! most K + 1 ticks old.
//! Cost: nine 16-word LUT RAMs (the count and the age twice, for their two read
//! addresses; the three latches; the period; the live words: 221 bits), 80 bits of
//! registers (the count for the following error, the next axis's count and age),
//! six 8-bit subtractors, three 32-bit adders, a 32-bit subtractor and two 17-bit
//! adders, and 3 flip-flops per axis.

use super::bit_insert::SignExtend;
use super::lut_ram::LutRam;
use rust_hdl::prelude::*;

/// Bits of the live word ([`crate::model::encoder::LIVE_BITS`]).
pub const LIVE_BITS: usize = 13;

#[derive(LogicBlock)]
pub struct EncExtend<const K: usize> {
    pub clock: Signal<In, Clock>,
    pub reset: Signal<In, Bit>,
    pub ax: Signal<In, Bits<4>>,
    pub ok: Signal<In, Bit>,
    pub next_ax: Signal<In, Bits<4>>,
    pub count: Signal<In, Bits<8>>,
    pub index_count: Signal<In, Bits<8>>,
    pub probe_count: Signal<In, Bits<8>>,
    pub cnew: Signal<In, Bit>,
    pub inew: Signal<In, Bit>,
    pub iafter: Signal<In, Bit>,
    pub pnew: Signal<In, Bit>,
    pub pafter: Signal<In, Bit>,
    pub enew: Signal<In, Bit>,
    pub e2: Signal<In, Bit>,
    pub period: Signal<In, Bits<8>>,
    pub age: Signal<In, Bits<8>>,
    pub live: Signal<In, Bits<LIVE_BITS>>,
    pub index_pos: Signal<In, Bits<8>>,
    pub pos: Signal<In, Bits<32>>,
    pub count1: Signal<Out, Bits<32>>,
    pub sel: Signal<In, Bits<4>>,
    pub s_count: Signal<Out, Bits<32>>,
    pub s_index: Signal<Out, Bits<32>>,
    pub s_probe: Signal<Out, Bits<32>>,
    pub s_ipos: Signal<Out, Bits<32>>,
    pub s_period: Signal<Out, Bits<16>>,
    pub s_age: Signal<Out, Bits<16>>,
    pub s_live: Signal<Out, Bits<LIVE_BITS>>,
    pub s_itog: Signal<Out, Bit>,
    pub s_ptog: Signal<Out, Bit>,
    pub s_valid: Signal<Out, Bit>,
    cnt_ram: LutRam<32, 4>,
    cnt_sel: LutRam<32, 4>,
    idx_ram: LutRam<32, 4>,
    prb_ram: LutRam<32, 4>,
    ipos_ram: LutRam<32, 4>,
    per_ram: LutRam<16, 4>,
    age_ram: LutRam<16, 4>,
    age_sel: LutRam<16, 4>,
    live_ram: LutRam<LIVE_BITS, 4>,
    valid: DFF<Bits<K>>,
    itog: DFF<Bits<K>>,
    ptog: DFF<Bits<K>>,
    c1: DFF<Bits<32>>,
    /// Axis `ax`'s bit of `valid`, registered a cycle ahead.
    v_q: DFF<Bit>,
    c_one: Constant<Bits<K>>,
    oh: Signal<Local, Bits<K>>,
    ohs: Signal<Local, Bits<K>>,
    v: Signal<Local, Bit>,
    /// Per value: the base, the narrow difference, its sign extension (a block), the sum.
    b_c: Signal<Local, Bits<32>>,
    d_c: Signal<Local, Bits<8>>,
    x_c: SignExtend<8, 32>,
    e_c: Signal<Local, Bits<32>>,
    b_i: Signal<Local, Bits<32>>,
    d_i: Signal<Local, Bits<8>>,
    x_i: SignExtend<8, 32>,
    b_p: Signal<Local, Bits<32>>,
    d_p: Signal<Local, Bits<8>>,
    x_p: SignExtend<8, 32>,
    /// The index position: the position's low byte less the latched one, extended.
    d_ip: Signal<Local, Bits<8>>,
    x_ip: SignExtend<8, 32>,
    /// The velocity: the last age, the narrow growths, their saturating sums.
    a_old: Signal<Local, Bits<16>>,
    /// The count's and the age's memory words of the next sample's axis, read a cycle
    /// ahead at `next_ax` (or the words written now, when that is the same axis), so no
    /// LUT RAM read is in front of the arithmetic.
    cnt_pre: DFF<Bits<32>>,
    age_pre: DFF<Bits<16>>,
    same: Signal<Local, Bit>,
    d_a: Signal<Local, Bits<8>>,
    g_a: Signal<Local, Bits<17>>,
    d_q: Signal<Local, Bits<8>>,
    g_q: Signal<Local, Bits<17>>,
    a_new: Signal<Local, Bits<16>>,
    c_max: Constant<Bits<16>>,
}

impl<const K: usize> Default for EncExtend<K> {
    fn default() -> Self {
        assert!((1..=16).contains(&K), "EncExtend<{K}>: 1..=16 axes");
        EncExtend {
            clock: Default::default(),
            reset: Default::default(),
            ax: Default::default(),
            ok: Default::default(),
            next_ax: Default::default(),
            count: Default::default(),
            index_count: Default::default(),
            probe_count: Default::default(),
            cnew: Default::default(),
            inew: Default::default(),
            iafter: Default::default(),
            pnew: Default::default(),
            pafter: Default::default(),
            enew: Default::default(),
            e2: Default::default(),
            period: Default::default(),
            age: Default::default(),
            live: Default::default(),
            index_pos: Default::default(),
            pos: Default::default(),
            count1: Default::default(),
            sel: Default::default(),
            s_count: Default::default(),
            s_index: Default::default(),
            s_probe: Default::default(),
            s_ipos: Default::default(),
            s_period: Default::default(),
            s_age: Default::default(),
            s_live: Default::default(),
            s_itog: Default::default(),
            s_ptog: Default::default(),
            s_valid: Default::default(),
            cnt_ram: Default::default(),
            cnt_sel: Default::default(),
            idx_ram: Default::default(),
            prb_ram: Default::default(),
            ipos_ram: Default::default(),
            per_ram: Default::default(),
            age_ram: Default::default(),
            age_sel: Default::default(),
            live_ram: Default::default(),
            valid: Default::default(),
            itog: Default::default(),
            ptog: Default::default(),
            c1: Default::default(),
            v_q: Default::default(),
            c_one: Constant::new(1.into()),
            oh: Default::default(),
            ohs: Default::default(),
            v: Default::default(),
            b_c: Default::default(),
            d_c: Default::default(),
            x_c: SignExtend::new(),
            e_c: Default::default(),
            b_i: Default::default(),
            d_i: Default::default(),
            x_i: SignExtend::new(),
            b_p: Default::default(),
            d_p: Default::default(),
            x_p: SignExtend::new(),
            d_ip: Default::default(),
            x_ip: SignExtend::new(),
            a_old: Default::default(),
            cnt_pre: Default::default(),
            age_pre: Default::default(),
            same: Default::default(),
            d_a: Default::default(),
            g_a: Default::default(),
            d_q: Default::default(),
            g_q: Default::default(),
            a_new: Default::default(),
            c_max: Constant::new(0xFFFF.into()),
        }
    }
}

impl<const K: usize> Logic for EncExtend<K> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, valid, itog, ptog, c1, v_q, cnt_pre, age_pre);
        self.cnt_ram.clock.next = self.clock.val();
        self.cnt_sel.clock.next = self.clock.val();
        self.idx_ram.clock.next = self.clock.val();
        self.prb_ram.clock.next = self.clock.val();
        self.ipos_ram.clock.next = self.clock.val();
        self.live_ram.clock.next = self.clock.val();
        self.per_ram.clock.next = self.clock.val();
        self.age_ram.clock.next = self.clock.val();
        self.age_sel.clock.next = self.clock.val();

        self.oh.next = self.c_one.val() << self.ax.val();
        self.v.next = self.v_q.q.val();
        // The next sample's axis: visited since reset, or written now.
        self.v_q.d.next = (self.valid.q.val() & (self.c_one.val() << self.next_ax.val())).any() | (self.ok.val() & (self.ax.val() == self.next_ax.val()));
        self.cnt_ram.raddr.next = self.next_ax.val();
        // The count: from the last one, or from 0 (a clear, or the first visit).
        self.b_c.next = 0.into();
        if self.v.val() & !self.cnew.val() {
            self.b_c.next = self.cnt_pre.q.val();
        }
        self.d_c.next = self.count.val() - self.b_c.val().get_bits::<8>(0);
        self.x_c.value.next = self.d_c.val();
        self.e_c.next = self.b_c.val() + self.x_c.wide.val();
        // The latches: the same from the count at the last visit (or from 0).
        self.b_i.next = 0.into();
        if self.v.val() & !self.iafter.val() {
            self.b_i.next = self.cnt_pre.q.val();
        }
        self.d_i.next = self.index_count.val() - self.b_i.val().get_bits::<8>(0);
        self.x_i.value.next = self.d_i.val();
        self.b_p.next = 0.into();
        if self.v.val() & !self.pafter.val() {
            self.b_p.next = self.cnt_pre.q.val();
        }
        self.d_p.next = self.probe_count.val() - self.b_p.val().get_bits::<8>(0);
        self.x_p.value.next = self.d_p.val();
        self.d_ip.next = self.pos.val().get_bits::<8>(0) - self.index_pos.val();
        self.x_ip.value.next = self.d_ip.val();

        // The velocity: from the last age (0 before the first visit).
        self.age_ram.raddr.next = self.next_ax.val();
        self.a_old.next = 0.into();
        if self.v.val() {
            self.a_old.next = self.age_pre.q.val();
        }
        self.d_a.next = self.age.val() - self.a_old.val().get_bits::<8>(0);
        self.g_a.next = bit_cast::<17, 16>(self.a_old.val()) + bit_cast::<17, 8>(self.d_a.val());
        self.d_q.next = self.period.val() - self.a_old.val().get_bits::<8>(0);
        self.g_q.next = bit_cast::<17, 16>(self.a_old.val()) + bit_cast::<17, 8>(self.d_q.val());
        if self.enew.val() {
            self.a_new.next = bit_cast::<16, 8>(self.age.val());
        } else if self.g_a.val().get_bit(16) {
            self.a_new.next = self.c_max.val();
        } else {
            self.a_new.next = self.g_a.val().get_bits::<16>(0);
        }
        self.age_ram.we.next = self.ok.val();
        self.age_ram.waddr.next = self.ax.val();
        self.age_ram.wdata.next = self.a_new.val();
        self.age_sel.we.next = self.ok.val();
        self.age_sel.waddr.next = self.ax.val();
        self.age_sel.wdata.next = self.a_new.val();
        self.per_ram.we.next = self.ok.val() & (self.enew.val() | !self.v.val());
        self.per_ram.waddr.next = self.ax.val();
        if self.e2.val() {
            self.per_ram.wdata.next = bit_cast::<16, 8>(self.period.val());
        } else if self.g_q.val().get_bit(16) {
            self.per_ram.wdata.next = self.c_max.val();
        } else {
            self.per_ram.wdata.next = self.g_q.val().get_bits::<16>(0);
        }

        self.cnt_ram.we.next = self.ok.val();
        self.cnt_ram.waddr.next = self.ax.val();
        self.cnt_ram.wdata.next = self.e_c.val();
        self.same.next = self.ok.val() & (self.ax.val() == self.next_ax.val());
        self.cnt_pre.d.next = self.cnt_ram.rdata.val();
        self.age_pre.d.next = self.age_ram.rdata.val();
        if self.same.val() {
            self.cnt_pre.d.next = self.e_c.val();
            self.age_pre.d.next = self.a_new.val();
        }
        self.cnt_sel.we.next = self.ok.val();
        self.cnt_sel.waddr.next = self.ax.val();
        self.cnt_sel.wdata.next = self.e_c.val();
        self.idx_ram.we.next = self.ok.val() & (self.inew.val() | !self.v.val());
        self.idx_ram.waddr.next = self.ax.val();
        self.idx_ram.wdata.next = self.b_i.val() + self.x_i.wide.val();
        self.ipos_ram.we.next = self.ok.val() & (self.inew.val() | !self.v.val());
        self.ipos_ram.waddr.next = self.ax.val();
        self.ipos_ram.wdata.next = self.pos.val() - self.x_ip.wide.val();
        self.prb_ram.we.next = self.ok.val() & (self.pnew.val() | !self.v.val());
        self.prb_ram.waddr.next = self.ax.val();
        self.prb_ram.wdata.next = self.b_p.val() + self.x_p.wide.val();
        self.live_ram.we.next = self.ok.val();
        self.live_ram.waddr.next = self.ax.val();
        self.live_ram.wdata.next = self.live.val();
        self.c1.d.next = self.e_c.val();
        self.valid.d.next = self.valid.q.val();
        self.itog.d.next = self.itog.q.val();
        self.ptog.d.next = self.ptog.q.val();
        if self.ok.val() {
            self.valid.d.next = self.valid.q.val() | self.oh.val();
            if self.inew.val() {
                self.itog.d.next = self.itog.q.val() ^ self.oh.val();
            }
            if self.pnew.val() {
                self.ptog.d.next = self.ptog.q.val() ^ self.oh.val();
            }
        }
        if self.reset.val() {
            self.v_q.d.next = false;
            self.valid.d.next = 0.into();
            self.itog.d.next = 0.into();
            self.ptog.d.next = 0.into();
        }
        self.count1.next = self.c1.q.val();

        // Axis `sel`'s words.
        self.ohs.next = self.c_one.val() << self.sel.val();
        self.cnt_sel.raddr.next = self.sel.val();
        self.idx_ram.raddr.next = self.sel.val();
        self.prb_ram.raddr.next = self.sel.val();
        self.ipos_ram.raddr.next = self.sel.val();
        self.live_ram.raddr.next = self.sel.val();
        self.per_ram.raddr.next = self.sel.val();
        self.age_sel.raddr.next = self.sel.val();
        self.s_period.next = self.per_ram.rdata.val();
        self.s_age.next = self.age_sel.rdata.val();
        self.s_count.next = self.cnt_sel.rdata.val();
        self.s_index.next = self.idx_ram.rdata.val();
        self.s_probe.next = self.prb_ram.rdata.val();
        self.s_ipos.next = self.ipos_ram.rdata.val();
        self.s_live.next = self.live_ram.rdata.val();
        self.s_itog.next = (self.itog.q.val() & self.ohs.val()).any();
        self.s_ptog.next = (self.ptog.q.val() & self.ohs.val()).any();
        self.s_valid.next = (self.valid.q.val() & self.ohs.val()).any();
    }
}
