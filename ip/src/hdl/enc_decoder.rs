//! One axis's encoder decoder in `clk`: synchronisers, filters, 4× quadrature count,
//! illegal transitions, the index and probe latches of the count, and the reciprocal
//! velocity. The count and its latches are narrow (`model::encoder::NARROW_BITS` = 8
//! bits): the shared extension ([`super::enc_extend::EncExtend`]) visits the axis every
//! K ticks and carries them to 32 bits. It equals the narrow view of
//! `model::encoder::EncoderModel` (`EncOutputs::narrow`) clock for clock
//! (tests/hdl_encoder.rs, three ways); the model's module docs state the behaviour.
//!
//! Ports:
//! * `a`, `b`, `z`: the encoder's pins (asynchronous).
//! * `mode` (quasi-static, `EncConfig::word`, shared by the axes): filter ticks 3..0
//!   (0 = off), Z active low 4, index gated by A and B 5, the gate's A and B levels
//!   7..6; `invert` (quasi-static, the axis's own): count down when A leads B.
//! * `position` (8 bits): the low byte of the axis's step position (the core's
//!   position register); the index latches it (`index_pos`, the model's narrow view).
//! * `arm` (one cycle): arm the clear of the count on the next index. `probe` (one
//!   cycle): the probe latch's strobe (tie to 0 without the probe: its latch is
//!   constant and synthesis removes it). `vel_tick`: the shared velocity prescaler's
//!   tick. `ack` (one cycle): the extension visits the axis in this cycle (it reads
//!   the outputs); the visit flags restart. `reset`: synchronous; the synchronisers
//!   keep running and each filtered level loads its synchronised pin.
//! * Outputs, all flip-flops: `count`, `index_count`, `probe_count` (8 bits,
//!   wrapping), `illegal` (8 bits, wrapping), the visit flags `cnew`, `inew`,
//!   `iafter`, `pnew`, `pafter` (`EncoderModel::clock_visit`), `armed`, `clearing`
//!   (the armed clear was taken: the count restarts from 0 at this tick), `enew` and
//!   `e2` (one, and two or more, counted edges since the visit), `period` and `age`
//!   (the narrow velocity counters, 8 bits, wrapping, 0 after reset: `age8` and
//!   `per8` of the model; the extension makes the 16-bit saturating ones),
//!   `last_dir` (1: the last counted edge went up) and the filtered levels `lev_a`,
//!   `lev_b`, `lev_z`; `visit`: what the extension takes, packed (count 7..0, index
//!   15..8, probe 23..16, period 31..24, age 39..32, illegal 47..40, cnew 48, inew
//!   49, iafter 50, pnew 51, pafter 52, enew 53, e2 54, armed 55, last direction 56,
//!   A, B, Z 59..57); `index_pos` (8 bits, beside `visit`: the stride of the packed
//!   visit words stays 64).
//!
//! Two choices keep the logic per bit to the adders: the armed clear takes effect a
//! tick after the index, as a zero operand of the count's adder (a clear in the
//! strobe's own tick put a multiplexer with the whole index condition on every bit:
//! about 75 LUT), and the velocity registers reset to 0, so the restart at an edge and
//! the reset are one synchronous reset. Everything that would saturate or carry past
//! 8 bits is the shared extension's.
//!
//! Latency: a pin change sampled at clk edge e0 moves the count at edge e0 + 2 + filter
//! (`model::encoder::pin_to_level_ticks`). One count per tick at most; the documented
//! rate keeps `model::encoder::max_count_rate_ticks` ticks between edges.
//!
//! Cost: 9 flip-flops for the lines (synchroniser and level), 12 for the filters, 8
//! for the count, 8 per latch (the index position's too), 8 for `illegal`, 16 for the velocity and 10 more.

use rust_hdl::prelude::*;

#[derive(LogicBlock)]
pub struct EncDecoder {
    pub clock: Signal<In, Clock>,
    pub reset: Signal<In, Bit>,
    pub a: Signal<In, Bit>,
    pub b: Signal<In, Bit>,
    pub z: Signal<In, Bit>,
    pub mode: Signal<In, Bits<8>>,
    pub invert: Signal<In, Bit>,
    pub arm: Signal<In, Bit>,
    pub probe: Signal<In, Bit>,
    pub vel_tick: Signal<In, Bit>,
    pub ack: Signal<In, Bit>,
    pub position: Signal<In, Bits<8>>,
    pub count: Signal<Out, Bits<8>>,
    pub index_count: Signal<Out, Bits<8>>,
    pub probe_count: Signal<Out, Bits<8>>,
    pub illegal: Signal<Out, Bits<8>>,
    pub cnew: Signal<Out, Bit>,
    pub inew: Signal<Out, Bit>,
    pub iafter: Signal<Out, Bit>,
    pub pnew: Signal<Out, Bit>,
    pub pafter: Signal<Out, Bit>,
    pub armed: Signal<Out, Bit>,
    pub clearing: Signal<Out, Bit>,
    pub enew: Signal<Out, Bit>,
    pub e2: Signal<Out, Bit>,
    pub period: Signal<Out, Bits<8>>,
    pub age: Signal<Out, Bits<8>>,
    pub last_dir: Signal<Out, Bit>,
    pub lev_a: Signal<Out, Bit>,
    pub lev_b: Signal<Out, Bit>,
    pub lev_z: Signal<Out, Bit>,
    pub visit: Signal<Out, Bits<64>>,
    pub index_pos: Signal<Out, Bits<8>>,
    a1: DFF<Bit>,
    a2: DFF<Bit>,
    b1: DFF<Bit>,
    b2: DFF<Bit>,
    z1: DFF<Bit>,
    z2: DFF<Bit>,
    la: DFF<Bit>,
    lb: DFF<Bit>,
    lz: DFF<Bit>,
    fa: DFF<Bits<4>>,
    fb: DFF<Bits<4>>,
    fz: DFF<Bits<4>>,
    cnt: DFF<Bits<8>>,
    idx: DFF<Bits<8>>,
    ipos: DFF<Bits<8>>,
    prb: DFF<Bits<8>>,
    ill: DFF<Bits<8>>,
    cnew_q: DFF<Bit>,
    inew_q: DFF<Bit>,
    iafter_q: DFF<Bit>,
    pnew_q: DFF<Bit>,
    pafter_q: DFF<Bit>,
    arm_q: DFF<Bit>,
    clr_q: DFF<Bit>,
    per: DFF<Bits<8>>,
    agec: DFF<Bits<8>>,
    enew_q: DFF<Bit>,
    e2_q: DFF<Bit>,
    ldir: DFF<Bit>,
    c_ones: Constant<Bits<8>>,
    inc: Signal<Local, Bits<8>>,
    /// A clear the visit has not read.
    cl_old: Signal<Local, Bit>,
    age_next: Signal<Local, Bits<8>>,
    /// This tick: the filtered A, B, Z change; exactly one of A and B changed; the
    /// move is up; the count after it; the index strobe.
    ca: Signal<Local, Bit>,
    cb: Signal<Local, Bit>,
    cz: Signal<Local, Bit>,
    counted: Signal<Local, Bit>,
    up: Signal<Local, Bit>,
    after: Signal<Local, Bits<8>>,
    base: Signal<Local, Bits<8>>,
    index: Signal<Local, Bit>,
    q_before: Signal<Local, Bit>,
    q_after: Signal<Local, Bit>,
}

impl Default for EncDecoder {
    fn default() -> Self {
        EncDecoder {
            clock: Default::default(),
            reset: Default::default(),
            a: Default::default(),
            b: Default::default(),
            z: Default::default(),
            mode: Default::default(),
            invert: Default::default(),
            arm: Default::default(),
            probe: Default::default(),
            vel_tick: Default::default(),
            ack: Default::default(),
            position: Default::default(),
            count: Default::default(),
            index_count: Default::default(),
            probe_count: Default::default(),
            illegal: Default::default(),
            cnew: Default::default(),
            inew: Default::default(),
            iafter: Default::default(),
            pnew: Default::default(),
            pafter: Default::default(),
            armed: Default::default(),
            clearing: Default::default(),
            enew: Default::default(),
            e2: Default::default(),
            period: Default::default(),
            age: Default::default(),
            last_dir: Default::default(),
            lev_a: Default::default(),
            lev_b: Default::default(),
            lev_z: Default::default(),
            visit: Default::default(),
            index_pos: Default::default(),
            a1: Default::default(),
            a2: Default::default(),
            b1: Default::default(),
            b2: Default::default(),
            z1: Default::default(),
            z2: Default::default(),
            la: Default::default(),
            lb: Default::default(),
            lz: Default::default(),
            fa: Default::default(),
            fb: Default::default(),
            fz: Default::default(),
            cnt: Default::default(),
            idx: Default::default(),
            ipos: Default::default(),
            prb: Default::default(),
            ill: Default::default(),
            cnew_q: Default::default(),
            inew_q: Default::default(),
            iafter_q: Default::default(),
            pnew_q: Default::default(),
            pafter_q: Default::default(),
            arm_q: Default::default(),
            clr_q: Default::default(),
            per: Default::default(),
            agec: Default::default(),
            enew_q: Default::default(),
            e2_q: Default::default(),
            ldir: Default::default(),
            c_ones: Constant::new(0xFFu64.into()),
            inc: Default::default(),
            cl_old: Default::default(),
            age_next: Default::default(),
            ca: Default::default(),
            cb: Default::default(),
            cz: Default::default(),
            counted: Default::default(),
            up: Default::default(),
            after: Default::default(),
            base: Default::default(),
            index: Default::default(),
            q_before: Default::default(),
            q_after: Default::default(),
        }
    }
}

impl EncDecoder {
    /// Marks the inputs as driven from outside and connects the block (tests).
    pub fn connect_ports(&mut self) {
        self.clock.connect();
        self.reset.connect();
        self.a.connect();
        self.b.connect();
        self.z.connect();
        self.mode.connect();
        self.invert.connect();
        self.arm.connect();
        self.probe.connect();
        self.vel_tick.connect();
        self.ack.connect();
        self.position.connect();
        self.connect_all();
    }
}

impl Logic for EncDecoder {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clock, a1, a2, b1, b2, z1, z2, la, lb, lz, fa, fb, fz, cnt, idx, ipos, prb, ill, cnew_q, inew_q, iafter_q, pnew_q,
            pafter_q, arm_q, clr_q, per, agec, enew_q, e2_q, ldir
        );
        self.a1.d.next = self.a.val();
        self.a2.d.next = self.a1.q.val();
        self.b1.d.next = self.b.val();
        self.b2.d.next = self.b1.q.val();
        self.z1.d.next = self.z.val();
        self.z2.d.next = self.z1.q.val();

        // The filters: a line changes once its synchronised pin has differed from the
        // level at filter + 1 consecutive ticks.
        self.ca.next = false;
        self.fa.d.next = 0.into();
        if self.a2.q.val() != self.la.q.val() {
            if self.fa.q.val() >= self.mode.val().get_bits::<4>(0) {
                self.ca.next = true;
            } else {
                self.fa.d.next = self.fa.q.val() + 1;
            }
        }
        self.cb.next = false;
        self.fb.d.next = 0.into();
        if self.b2.q.val() != self.lb.q.val() {
            if self.fb.q.val() >= self.mode.val().get_bits::<4>(0) {
                self.cb.next = true;
            } else {
                self.fb.d.next = self.fb.q.val() + 1;
            }
        }
        self.cz.next = false;
        self.fz.d.next = 0.into();
        if self.z2.q.val() != self.lz.q.val() {
            if self.fz.q.val() >= self.mode.val().get_bits::<4>(0) {
                self.cz.next = true;
            } else {
                self.fz.d.next = self.fz.q.val() + 1;
            }
        }
        self.la.d.next = self.la.q.val() ^ self.ca.val();
        self.lb.d.next = self.lb.q.val() ^ self.cb.val();
        self.lz.d.next = self.lz.q.val() ^ self.cz.val();

        // 4× decoding: A changing away from B's level, or B changing to A's, is up.
        self.counted.next = self.ca.val() ^ self.cb.val();
        self.up.next = self.la.q.val() ^ self.lb.q.val() ^ self.ca.val() ^ self.invert.val();
        // One adder: the count plus 0, 1 or −1.
        self.inc.next = 0.into();
        if self.counted.val() {
            if self.up.val() {
                self.inc.next = 1.into();
            } else {
                self.inc.next = self.c_ones.val();
            }
        }
        self.base.next = self.cnt.q.val();
        if self.clr_q.q.val() {
            self.base.next = 0.into();
        }
        self.after.next = self.base.val() + self.inc.val();
        self.ill.d.next = self.ill.q.val();
        if self.ca.val() & self.cb.val() {
            self.ill.d.next = self.ill.q.val() + 1;
        }

        // The index: the tick at which Z at its active level (and A and B at the
        // gate's levels) becomes true.
        self.q_before.next = (self.lz.q.val() ^ self.mode.val().get_bit(4))
            & (!self.mode.val().get_bit(5)
                | ((self.la.q.val() == self.mode.val().get_bit(6)) & (self.lb.q.val() == self.mode.val().get_bit(7))));
        self.q_after.next = (self.lz.q.val() ^ self.cz.val() ^ self.mode.val().get_bit(4))
            & (!self.mode.val().get_bit(5)
                | (((self.la.q.val() ^ self.ca.val()) == self.mode.val().get_bit(6))
                    & ((self.lb.q.val() ^ self.cb.val()) == self.mode.val().get_bit(7))));
        self.index.next = self.q_after.val() & !self.q_before.val();
        self.cnt.d.next = self.after.val();
        // The visit flags: what happened since the visit (an event in its own cycle
        // is the next visit's). A clear in this cycle follows an index in the last,
        // so no index comes with it.
        self.cl_old.next = self.cnew_q.q.val() & !self.ack.val();
        self.cnew_q.d.next = self.clr_q.q.val() | self.cl_old.val();
        self.inew_q.d.next = self.index.val() | (self.inew_q.q.val() & !self.ack.val());
        self.pnew_q.d.next = self.probe.val() | (self.pnew_q.q.val() & !self.ack.val());
        self.idx.d.next = self.idx.q.val();
        self.ipos.d.next = self.ipos.q.val();
        self.iafter_q.d.next = self.iafter_q.q.val() & !self.ack.val();
        if self.index.val() {
            self.idx.d.next = self.after.val();
            self.ipos.d.next = self.position.val();
            self.iafter_q.d.next = self.cl_old.val();
        }
        self.clr_q.d.next = self.index.val() & self.arm_q.q.val();
        self.arm_q.d.next = self.arm.val() | (self.arm_q.q.val() & !self.index.val());
        self.prb.d.next = self.prb.q.val();
        self.pafter_q.d.next = self.pafter_q.q.val() & !self.ack.val();
        if self.probe.val() {
            self.prb.d.next = self.cnt.q.val();
            self.pafter_q.d.next = self.cl_old.val();
        }

        // The velocity: ticks since the last counted edge, and between the last two.
        self.per.d.next = self.per.q.val();
        self.agec.d.next = self.agec.q.val();
        self.ldir.d.next = self.ldir.q.val();
        self.age_next.next = self.agec.q.val();
        if self.vel_tick.val() {
            self.age_next.next = self.agec.q.val() + 1;
        }
        self.enew_q.d.next = self.counted.val() | (self.enew_q.q.val() & !self.ack.val());
        self.e2_q.d.next = (self.counted.val() & self.enew_q.q.val() & !self.ack.val()) | (self.e2_q.q.val() & !self.ack.val());
        if self.counted.val() {
            self.per.d.next = self.age_next.val();
            self.agec.d.next = 0.into();
            self.ldir.d.next = self.up.val();
        } else {
            self.agec.d.next = self.age_next.val();
        }

        if self.reset.val() {
            self.la.d.next = self.a2.q.val();
            self.lb.d.next = self.b2.q.val();
            self.lz.d.next = self.z2.q.val();
            self.fa.d.next = 0.into();
            self.fb.d.next = 0.into();
            self.fz.d.next = 0.into();
            self.cnt.d.next = 0.into();
            self.idx.d.next = 0.into();
            self.ipos.d.next = 0.into();
            self.prb.d.next = 0.into();
            self.ill.d.next = 0.into();
            self.cnew_q.d.next = false;
            self.inew_q.d.next = false;
            self.iafter_q.d.next = false;
            self.pnew_q.d.next = false;
            self.pafter_q.d.next = false;
            self.arm_q.d.next = false;
            self.per.d.next = 0.into();
            self.agec.d.next = 0.into();
            self.enew_q.d.next = false;
            self.e2_q.d.next = false;
            self.clr_q.d.next = false;
            self.ldir.d.next = false;
        }

        self.count.next = self.cnt.q.val();
        self.index_count.next = self.idx.q.val();
        self.index_pos.next = self.ipos.q.val();
        self.probe_count.next = self.prb.q.val();
        self.illegal.next = self.ill.q.val();
        self.cnew.next = self.cnew_q.q.val();
        self.inew.next = self.inew_q.q.val();
        self.iafter.next = self.iafter_q.q.val();
        self.pnew.next = self.pnew_q.q.val();
        self.pafter.next = self.pafter_q.q.val();
        self.armed.next = self.arm_q.q.val();
        self.clearing.next = self.clr_q.q.val();
        self.enew.next = self.enew_q.q.val();
        self.e2.next = self.e2_q.q.val();
        self.period.next = self.per.q.val();
        self.age.next = self.agec.q.val();
        self.last_dir.next = self.ldir.q.val();
        self.lev_a.next = self.la.q.val();
        self.lev_b.next = self.lb.q.val();
        self.lev_z.next = self.lz.q.val();
        self.visit.next = bit_cast::<64, 8>(self.cnt.q.val())
            | (bit_cast::<64, 8>(self.idx.q.val()) << 8)
            | (bit_cast::<64, 8>(self.prb.q.val()) << 16)
            | (bit_cast::<64, 8>(self.per.q.val()) << 24)
            | (bit_cast::<64, 8>(self.agec.q.val()) << 32)
            | (bit_cast::<64, 8>(self.ill.q.val()) << 40)
            | (bit_cast::<64, 1>(self.cnew_q.q.val().into()) << 48)
            | (bit_cast::<64, 1>(self.inew_q.q.val().into()) << 49)
            | (bit_cast::<64, 1>(self.iafter_q.q.val().into()) << 50)
            | (bit_cast::<64, 1>(self.pnew_q.q.val().into()) << 51)
            | (bit_cast::<64, 1>(self.pafter_q.q.val().into()) << 52)
            | (bit_cast::<64, 1>(self.enew_q.q.val().into()) << 53)
            | (bit_cast::<64, 1>(self.e2_q.q.val().into()) << 54)
            | (bit_cast::<64, 1>(self.arm_q.q.val().into()) << 55)
            | (bit_cast::<64, 1>(self.ldir.q.val().into()) << 56)
            | (bit_cast::<64, 1>(self.la.q.val().into()) << 57)
            | (bit_cast::<64, 1>(self.lb.q.val().into()) << 58)
            | (bit_cast::<64, 1>(self.lz.q.val().into()) << 59);
    }
}
