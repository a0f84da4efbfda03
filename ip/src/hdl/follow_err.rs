//! The following error of every axis, by one shared multiplier stepping round robin
//! over the axes: `dev = ⌊position · ratio / 2^16⌋ + offset − count` (mod 2^32, read as
//! signed: positive when the encoder is behind the steps), and the sticky ENC_FAIL
//! flag of each axis whose |dev| exceeds its tolerance. It equals
//! `model::encoder::FollowErrModel` clock for clock (tests/hdl_encoder.rs, three ways).
//!
//! Ports:
//! * `ax` (a register): the axis whose inputs the block takes this cycle: 0, 1, …,
//!   K − 1, 0, … from reset. The parent drives `position` (the core's step position of
//!   axis `ax`), `ratio` (its counts per step, unsigned Q16.16) and `tol` (its
//!   tolerance, counts; 0 = no check) combinationally from registers or static memory.
//!   `ax2` (a register): the axis `ax` named two cycles earlier; the parent drives
//!   `count` with its encoder count as it was in that cycle (the extension's register,
//!   [`super::enc_extend::EncExtend`]'s `count1`). `pos1` (a register): the
//!   `position` taken a cycle earlier (stage 1's; the extension's index position).
//! * `align`, `clear` (bit a, one cycle each): align axis a (its offset becomes the
//!   value that makes its deviation 0 at its next visit; until that visit's write its
//!   deviation reads 0, and from the align until then the axis cannot fail, from a
//!   visit already in flight either: a clear right after an align sticks), clear its
//!   ENC_FAIL flag.
//! * `dev_axis` → `dev`: the last deviation computed for that axis (LUT RAM,
//!   asynchronous read); `fail` (bit a, a register): axis a's |dev| exceeded a non-zero
//!   tolerance since its flag was last cleared (or reset). An axis's `dev` is
//!   undefined until its first visit after power-up has written it (K + 5 ticks).
//!
//! Pipeline (one axis per cycle): stage 0 (`ax` = a) reads the inputs and the offset
//! (0 while an align is pending, and from reset until the axis's first visit writes
//! 0 into the offset RAM, which has no reset), stage 1 registers them and subtracts
//! the sign correction ratio · 2^16 from the offset (for a negative position: the
//! multiplier, [`MulReg`], two stages, takes the position as unsigned), stage 2 takes
//! the count and subtracts it, stage 3 adds the product, stage 4 registers `dev`, and the edge after it writes `dev` and, for an align, the offset, and sets
//! `fail`. **Refresh**: each axis's inputs are taken every K ticks; **latency**: a
//! count or position that crosses the tolerance at clk edge X sets `fail` at an edge
//! ≤ X + K + 4 ([`FOLLOW_ERR_LATENCY`] + K).
//!
//! Cost: one 32×32 multiplier (four DSPs), about 200 flip-flops and two 16×32 LUT RAMs
//! (the offsets and the deviations), K flip-flops for the pending aligns and K for
//! the flags: per axis, two flip-flops and 64 bits of LUT RAM.

use super::lut_ram::LutRam;
use super::mul_wide::MulReg;
use rust_hdl::prelude::*;

/// Edges from an axis's inputs being taken (the end of its stage-0 cycle) to its
/// `fail` flag: a crossing is seen within K ticks plus this.
pub const FOLLOW_ERR_LATENCY: u64 = 4;

#[derive(LogicBlock)]
pub struct FollowErr<const K: usize> {
    pub clock: Signal<In, Clock>,
    pub reset: Signal<In, Bit>,
    pub ax: Signal<Out, Bits<4>>,
    pub ax2: Signal<Out, Bits<4>>,
    pub position: Signal<In, Bits<32>>,
    pub count: Signal<In, Bits<32>>,
    pub ratio: Signal<In, Bits<32>>,
    pub tol: Signal<In, Bits<16>>,
    pub align: Signal<In, Bits<K>>,
    pub clear: Signal<In, Bits<K>>,
    pub dev_axis: Signal<In, Bits<4>>,
    pub dev: Signal<Out, Bits<32>>,
    pub pos1: Signal<Out, Bits<32>>,
    pub fail: Signal<Out, Bits<K>>,
    axq: DFF<Bits<4>>,
    s1_pos: DFF<Bits<32>>,
    s1_ratio: DFF<Bits<32>>,
    s1_off: DFF<Bits<32>>,
    s1_tol: DFF<Bits<16>>,
    s1_ax: DFF<Bits<4>>,
    s1_al: DFF<Bit>,
    s1_z: DFF<Bit>,
    s1_ok: DFF<Bit>,
    s2_v: DFF<Bits<32>>,
    s2_tol: DFF<Bits<16>>,
    s2_ax: DFF<Bits<4>>,
    s2_al: DFF<Bit>,
    s2_z: DFF<Bit>,
    s2_ok: DFF<Bit>,
    s3_v: DFF<Bits<32>>,
    s3_tol: DFF<Bits<16>>,
    s3_ax: DFF<Bits<4>>,
    s3_al: DFF<Bit>,
    s3_z: DFF<Bit>,
    s3_ok: DFF<Bit>,
    s4_dev: DFF<Bits<32>>,
    s4_tol: DFF<Bits<16>>,
    /// The bounds of the check with the sign bit flipped (unsigned compares of a signed
    /// deviation, in parallel, with no negation in series): 2^31 + tol and 2^31 − tol.
    s4_hib: DFF<Bits<32>>,
    s4_lob: DFF<Bits<32>>,
    s4_ax: DFF<Bits<4>>,
    s4_al: DFF<Bit>,
    s4_z: DFF<Bit>,
    s4_ok: DFF<Bit>,
    al_q: DFF<Bits<K>>,
    /// Axis a's offset is in the RAM (written since reset).
    ov_q: DFF<Bits<K>>,
    fail_q: DFF<Bits<K>>,
    mul: MulReg<32, 32, 64>,
    off_ram: LutRam<32, 4>,
    dev_ram: LutRam<32, 4>,
    c_last: Constant<Bits<4>>,
    c_one: Constant<Bits<K>>,
    oh0: Signal<Local, Bits<K>>,
    oh4: Signal<Local, Bits<K>>,
    take: Signal<Local, Bit>,
    fresh: Signal<Local, Bit>,
    off: Signal<Local, Bits<32>>,
    corr: Signal<Local, Bits<32>>,
    flip: Signal<Local, Bits<32>>,
    c_sign: Constant<Bits<32>>,
    over: Signal<Local, Bit>,
}

impl<const K: usize> Default for FollowErr<K> {
    fn default() -> Self {
        assert!((1..=16).contains(&K), "FollowErr<{K}>: 1..=16 axes");
        FollowErr {
            clock: Default::default(),
            reset: Default::default(),
            ax: Default::default(),
            ax2: Default::default(),
            position: Default::default(),
            count: Default::default(),
            ratio: Default::default(),
            tol: Default::default(),
            align: Default::default(),
            clear: Default::default(),
            dev_axis: Default::default(),
            dev: Default::default(),
            pos1: Default::default(),
            fail: Default::default(),
            axq: Default::default(),
            s1_pos: Default::default(),
            s1_ratio: Default::default(),
            s1_off: Default::default(),
            s1_tol: Default::default(),
            s1_ax: Default::default(),
            s1_al: Default::default(),
            s1_z: Default::default(),
            s1_ok: Default::default(),
            s2_v: Default::default(),
            s2_tol: Default::default(),
            s2_ax: Default::default(),
            s2_al: Default::default(),
            s2_z: Default::default(),
            s2_ok: Default::default(),
            s3_v: Default::default(),
            s3_tol: Default::default(),
            s3_ax: Default::default(),
            s3_al: Default::default(),
            s3_z: Default::default(),
            s3_ok: Default::default(),
            s4_dev: Default::default(),
            s4_tol: Default::default(),
            s4_hib: Default::default(),
            s4_lob: Default::default(),
            s4_ax: Default::default(),
            s4_al: Default::default(),
            s4_z: Default::default(),
            s4_ok: Default::default(),
            al_q: Default::default(),
            ov_q: Default::default(),
            fail_q: Default::default(),
            mul: Default::default(),
            off_ram: Default::default(),
            dev_ram: Default::default(),
            c_last: Constant::new(((K - 1) as u64).into()),
            c_one: Constant::new(1.into()),
            oh0: Default::default(),
            oh4: Default::default(),
            take: Default::default(),
            fresh: Default::default(),
            off: Default::default(),
            corr: Default::default(),
            flip: Default::default(),
            c_sign: Constant::new(0x8000_0000u64.into()),
            over: Default::default(),
        }
    }
}

impl<const K: usize> FollowErr<K> {
    /// Marks the inputs as driven from outside and connects the block (tests).
    pub fn connect_ports(&mut self) {
        self.clock.connect();
        self.reset.connect();
        self.position.connect();
        self.count.connect();
        self.ratio.connect();
        self.tol.connect();
        self.align.connect();
        self.clear.connect();
        self.dev_axis.connect();
        self.connect_all();
    }
}

impl<const K: usize> Logic for FollowErr<K> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clock, axq, s1_pos, s1_ratio, s1_off, s1_tol, s1_ax, s1_al, s1_z, s1_ok, s2_v, s2_tol, s2_ax, s2_al, s2_z,
            s2_ok, s3_v, s3_tol, s3_ax, s3_al, s3_z, s3_ok, s4_dev, s4_tol, s4_hib, s4_lob, s4_ax, s4_al, s4_z, s4_ok, al_q, ov_q, fail_q
        );
        self.mul.clock.next = self.clock.val();
        self.off_ram.clock.next = self.clock.val();
        self.dev_ram.clock.next = self.clock.val();

        // Stage 0: axis `axq`'s inputs and offset (0 while its align is pending).
        self.ax.next = self.axq.q.val();
        if self.axq.q.val() == self.c_last.val() {
            self.axq.d.next = 0.into();
        } else {
            self.axq.d.next = self.axq.q.val() + 1;
        }
        self.oh0.next = self.c_one.val() << self.axq.q.val();
        self.take.next = (self.al_q.q.val() & self.oh0.val()).any();
        self.fresh.next = !(self.ov_q.q.val() & self.oh0.val()).any();
        self.off_ram.raddr.next = self.axq.q.val();
        self.off.next = self.off_ram.rdata.val();
        if self.take.val() | self.fresh.val() {
            self.off.next = 0.into();
        }
        self.s1_pos.d.next = self.position.val();
        self.s1_ratio.d.next = self.ratio.val();
        self.s1_off.d.next = self.off.val();
        self.s1_tol.d.next = self.tol.val();
        self.s1_ax.d.next = self.axq.q.val();
        self.s1_al.d.next = self.take.val();
        self.s1_z.d.next = self.fresh.val();
        self.s1_ok.d.next = true;

        // Stages 1 to 3: the product, and offset − count less ratio·2^16 for a
        // negative position (the multiplier takes the position as unsigned).
        self.ax2.next = self.s2_ax.q.val();
        self.pos1.next = self.s1_pos.q.val();
        self.mul.a.next = self.s1_pos.q.val();
        self.mul.b.next = self.s1_ratio.q.val();
        self.corr.next = 0.into();
        if self.s1_pos.q.val().get_bit(31) {
            self.corr.next = bit_cast::<32, 16>(self.s1_ratio.q.val().get_bits::<16>(0)) << 16;
        }
        self.s2_v.d.next = self.s1_off.q.val() - self.corr.val();
        self.s2_tol.d.next = self.s1_tol.q.val();
        self.s2_ax.d.next = self.s1_ax.q.val();
        self.s2_al.d.next = self.s1_al.q.val();
        self.s2_z.d.next = self.s1_z.q.val();
        self.s2_ok.d.next = self.s1_ok.q.val();
        self.s3_v.d.next = self.s2_v.q.val() - self.count.val();
        self.s3_tol.d.next = self.s2_tol.q.val();
        self.s3_ax.d.next = self.s2_ax.q.val();
        self.s3_al.d.next = self.s2_al.q.val();
        self.s3_z.d.next = self.s2_z.q.val();
        self.s3_ok.d.next = self.s2_ok.q.val();
        self.s4_dev.d.next = self.mul.p.val().get_bits::<32>(16) + self.s3_v.q.val();
        self.s4_tol.d.next = self.s3_tol.q.val();
        self.s4_hib.d.next = self.c_sign.val() | bit_cast::<32, 16>(self.s3_tol.q.val());
        self.s4_lob.d.next = self.c_sign.val() - bit_cast::<32, 16>(self.s3_tol.q.val());
        self.s4_ax.d.next = self.s3_ax.q.val();
        self.s4_al.d.next = self.s3_al.q.val();
        self.s4_z.d.next = self.s3_z.q.val();
        self.s4_ok.d.next = self.s3_ok.q.val();

        // Stage 4: write the deviation (0 for an align, whose offset is written
        // instead) and set the flag.
        self.oh4.next = self.c_one.val() << self.s4_ax.q.val();
        self.dev_ram.we.next = self.s4_ok.q.val();
        self.dev_ram.waddr.next = self.s4_ax.q.val();
        self.dev_ram.wdata.next = self.s4_dev.q.val();
        self.off_ram.we.next = self.s4_ok.q.val() & (self.s4_al.q.val() | self.s4_z.q.val());
        self.off_ram.waddr.next = self.s4_ax.q.val();
        self.off_ram.wdata.next = 0.into();
        if self.s4_al.q.val() {
            self.off_ram.wdata.next = !self.s4_dev.q.val() + 1;
            self.dev_ram.wdata.next = 0.into();
        }
        self.ov_q.d.next = self.ov_q.q.val();
        if self.s4_ok.q.val() & (self.s4_al.q.val() | self.s4_z.q.val()) {
            self.ov_q.d.next = self.ov_q.q.val() | self.oh4.val();
        }
        // |dev| > tol, as dev > tol or dev < −tol (signed), each an unsigned compare
        // with the sign bit flipped.
        self.flip.next = self.s4_dev.q.val() ^ self.c_sign.val();
        // (No fail while the axis's align is pending, from a visit in flight either.)
        self.over.next = self.s4_ok.q.val()
            & !self.s4_al.q.val()
            & !((self.al_q.q.val() | self.align.val()) & self.oh4.val()).any()
            & self.s4_tol.q.val().any()
            & ((self.flip.val() > self.s4_hib.q.val()) | (self.flip.val() < self.s4_lob.q.val()));
        self.fail_q.d.next = self.fail_q.q.val() & !self.clear.val();
        if self.over.val() {
            self.fail_q.d.next = (self.fail_q.q.val() & !self.clear.val()) | self.oh4.val();
        }
        // An align stays pending until its offset is written (the visits between
        // take it too, each writing its own exact offset).
        self.al_q.d.next = self.al_q.q.val() | self.align.val();
        if self.s4_ok.q.val() & self.s4_al.q.val() {
            self.al_q.d.next = (self.al_q.q.val() & !self.oh4.val()) | self.align.val();
        }

        if self.reset.val() {
            self.axq.d.next = 0.into();
            self.s1_ok.d.next = false;
            self.s2_ok.d.next = false;
            self.s3_ok.d.next = false;
            self.s4_ok.d.next = false;
            self.al_q.d.next = 0.into();
            self.ov_q.d.next = 0.into();
            self.fail_q.d.next = 0.into();
        }
        self.dev_ram.raddr.next = self.dev_axis.val();
        self.dev.next = self.dev_ram.rdata.val();
        self.fail.next = self.fail_q.q.val();
    }
}
