//! The encoder feedback of K axes in `clk` (`export --encoder`): K narrow
//! [`EncDecoder`]s, the velocity prescaler they share, the [`EncExtend`] and
//! [`FollowErr`] units stepping round robin over them together (the extension visits
//! axis `fe.ax` and hands its 32-bit count to the following error's stage 2), and
//! the status word of one axis for the crossing to the bus. The visit registers the
//! visited decoder's narrow outputs (and acknowledges them); the extension works on
//! that sample a cycle later, so neither cycle holds both the K:1 selection and the
//! 32-bit arithmetic. It equals
//! `model::encoder::EncoderBankModel` clock for clock (tests/hdl_encoder.rs, three
//! ways).
//!
//! Ports:
//! * pins `enc_a`, `enc_b`, `enc_z` (bit a = axis a; asynchronous);
//! * quasi-static configuration: `mode` (every decoder's, `EncConfig::word`), `invert`
//!   (bit a: count axis a down when A leads B), `vel_prescale` (a velocity tick every
//!   `vel_prescale + 1` ticks);
//! * one-cycle commands, bit a for axis a: `arm` (clear the count at the next index),
//!   `align` (make the deviation 0), `clear` (clear ENC_FAIL); `probe`: the machine
//!   I/O's probe strobe (0 without it);
//! * the following error's inputs: `pos_axis` (a register) names the axis whose step
//!   position the parent drives on `position` (the core's) and whose `ratio` and `tol`
//!   it drives, combinationally, in the same cycle; `pos_low` (byte a: the low byte
//!   of axis a's step position, wires from the core's position registers) for the
//!   index latches;
//! * `sel` → `word_lo`, `word_hi` (the status word of [`ENC_WORD_BITS`] = {hi, lo},
//!   read from the extension's and the deviation's LUT RAMs; `sel` < K): axis `sel`'s
//!   count 31..0, index latch 63..32, probe latch 95..64, deviation 127..96
//!   (`word_lo`), period 143..128, age 159..144, illegal transitions 167..160, and the
//!   flags armed 168, last direction 169, filtered A, B, Z 170..172, ENC_FAIL 173,
//!   index toggle 174, probe toggle 175 (each flips when a new latch is written),
//!   valid 176, the step position at the index 208..177 (`word_hi`, bit 128 of the
//!   word is its bit 0). All but ENC_FAIL are as
//!   the last visit of the axis saw them, at most K + 1 ticks old; before the axis's
//!   first visit since reset is written (K + 1 ticks), valid is 0 and the rest
//!   undefined;
//! * `fail` (bit a, a register): axis a's ENC_FAIL.
//!
//! Latency: the decoders' ([`super::enc_decoder`]); the word at most K + 1 ticks old
//! (the last visit); ENC_FAIL within K + 4 ticks of the
//! crossing ([`super::follow_err::FOLLOW_ERR_LATENCY`]).

use super::bit_insert::{BitPick, FieldPick, FieldPlace};
use super::enc_decoder::EncDecoder;
use super::enc_extend::{EncExtend, LIVE_BITS};
use super::follow_err::FollowErr;
use rust_hdl::prelude::*;

/// The packed decoder outputs: 64 bits for each of up to 16 axes.
const PACK_BITS: usize = 1024;

/// Width of an axis's status word ({`word_hi`, `word_lo`}).
pub const ENC_WORD_BITS: usize = 209;

#[derive(LogicBlock)]
pub struct EncoderBank<const K: usize> {
    pub clock: Signal<In, Clock>,
    pub reset: Signal<In, Bit>,
    pub enc_a: Signal<In, Bits<K>>,
    pub enc_b: Signal<In, Bits<K>>,
    pub enc_z: Signal<In, Bits<K>>,
    pub mode: Signal<In, Bits<8>>,
    pub invert: Signal<In, Bits<K>>,
    pub vel_prescale: Signal<In, Bits<16>>,
    pub arm: Signal<In, Bits<K>>,
    pub align: Signal<In, Bits<K>>,
    pub clear: Signal<In, Bits<K>>,
    pub probe: Signal<In, Bit>,
    pub pos_axis: Signal<Out, Bits<4>>,
    pub position: Signal<In, Bits<32>>,
    pub pos_low: Signal<In, Bits<128>>,
    pub ratio: Signal<In, Bits<32>>,
    pub tol: Signal<In, Bits<16>>,
    pub sel: Signal<In, Bits<8>>,
    pub word_lo: Signal<Out, Bits<128>>,
    pub word_hi: Signal<Out, Bits<81>>,
    pub fail: Signal<Out, Bits<K>>,
    dec: [EncDecoder; K],
    a_pick: [BitPick<K>; K],
    b_pick: [BitPick<K>; K],
    z_pick: [BitPick<K>; K],
    inv_pick: [BitPick<K>; K],
    arm_pick: [BitPick<K>; K],
    ext: EncExtend<K>,
    fe: FollowErr<K>,
    pre: DFF<Bits<16>>,
    c_one: Constant<Bits<K>>,
    tick: Signal<Local, Bit>,
    /// The decoders' outputs packed at a stride of 64 bits, and the visited axis's.
    pack: [FieldPlace<64, PACK_BITS>; K],
    all_vis: Signal<Local, Bits<PACK_BITS>>,
    shifted: Signal<Local, Bits<PACK_BITS>>,
    v_word: Signal<Local, Bits<64>>,
    /// The decoders' index positions packed at a stride of 8 bits, the visited axis's.
    ipack: [FieldPlace<8, 128>; K],
    ip_all: Signal<Local, Bits<128>>,
    ip_shift: Signal<Local, Bits<128>>,
    vis_ip: DFF<Bits<8>>,
    pos_pick: [FieldPick<8, 128>; K],
    /// The visit's sample: the visited axis's bits, the axis, taken out of reset.
    vis_q: DFF<Bits<64>>,
    vis_ax: DFF<Bits<4>>,
    vis_ok: DFF<Bit>,
    v_count: Signal<Local, Bits<8>>,
    v_index: Signal<Local, Bits<8>>,
    v_probe: Signal<Local, Bits<8>>,
    v_period: Signal<Local, Bits<8>>,
    v_age: Signal<Local, Bits<8>>,
    v_enew: Signal<Local, Bit>,
    v_e2: Signal<Local, Bit>,
    v_ill: Signal<Local, Bits<8>>,
    v_cnew: Signal<Local, Bit>,
    v_inew: Signal<Local, Bit>,
    v_iafter: Signal<Local, Bit>,
    v_pnew: Signal<Local, Bit>,
    v_pafter: Signal<Local, Bit>,
    v_armed: Signal<Local, Bit>,
    v_dir: Signal<Local, Bit>,
    v_la: Signal<Local, Bit>,
    v_lb: Signal<Local, Bit>,
    v_lz: Signal<Local, Bit>,
    w_fail: Signal<Local, Bit>,
}

impl<const K: usize> Default for EncoderBank<K> {
    fn default() -> Self {
        EncoderBank {
            clock: Default::default(),
            reset: Default::default(),
            enc_a: Default::default(),
            enc_b: Default::default(),
            enc_z: Default::default(),
            mode: Default::default(),
            invert: Default::default(),
            vel_prescale: Default::default(),
            arm: Default::default(),
            align: Default::default(),
            clear: Default::default(),
            probe: Default::default(),
            pos_axis: Default::default(),
            position: Default::default(),
            pos_low: Default::default(),
            ratio: Default::default(),
            tol: Default::default(),
            sel: Default::default(),
            word_lo: Default::default(),
            word_hi: Default::default(),
            fail: Default::default(),
            dec: std::array::from_fn(|_| Default::default()),
            a_pick: std::array::from_fn(BitPick::new),
            b_pick: std::array::from_fn(BitPick::new),
            z_pick: std::array::from_fn(BitPick::new),
            inv_pick: std::array::from_fn(BitPick::new),
            arm_pick: std::array::from_fn(BitPick::new),
            ext: Default::default(),
            fe: Default::default(),
            pre: Default::default(),
            c_one: Constant::new(1.into()),
            tick: Default::default(),
            pack: std::array::from_fn(|i| FieldPlace::new(64 * i)),
            all_vis: Default::default(),
            shifted: Default::default(),
            v_word: Default::default(),
            ipack: std::array::from_fn(|i| FieldPlace::new(8 * i)),
            ip_all: Default::default(),
            ip_shift: Default::default(),
            vis_ip: Default::default(),
            pos_pick: std::array::from_fn(|i| FieldPick::new(8 * i)),
            vis_q: Default::default(),
            vis_ax: Default::default(),
            vis_ok: Default::default(),
            v_count: Default::default(),
            v_index: Default::default(),
            v_probe: Default::default(),
            v_period: Default::default(),
            v_age: Default::default(),
            v_enew: Default::default(),
            v_e2: Default::default(),
            v_ill: Default::default(),
            v_cnew: Default::default(),
            v_inew: Default::default(),
            v_iafter: Default::default(),
            v_pnew: Default::default(),
            v_pafter: Default::default(),
            v_armed: Default::default(),
            v_dir: Default::default(),
            v_la: Default::default(),
            v_lb: Default::default(),
            v_lz: Default::default(),
            w_fail: Default::default(),
        }
    }
}

impl<const K: usize> EncoderBank<K> {
    /// Marks the inputs as driven from outside and connects the block (tests).
    pub fn connect_ports(&mut self) {
        self.clock.connect();
        self.reset.connect();
        self.enc_a.connect();
        self.enc_b.connect();
        self.enc_z.connect();
        self.mode.connect();
        self.invert.connect();
        self.vel_prescale.connect();
        self.arm.connect();
        self.align.connect();
        self.clear.connect();
        self.probe.connect();
        self.position.connect();
        self.pos_low.connect();
        self.ratio.connect();
        self.tol.connect();
        self.sel.connect();
        self.connect_all();
    }
}

impl<const K: usize> Logic for EncoderBank<K> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, pre, vis_q, vis_ax, vis_ok, vis_ip);
        // The velocity ticks, shared.
        self.tick.next = self.pre.q.val() >= self.vel_prescale.val();
        if self.tick.val() | self.reset.val() {
            self.pre.d.next = 0.into();
        } else {
            self.pre.d.next = self.pre.q.val() + 1;
        }

        self.fe.clock.next = self.clock.val();
        self.fe.reset.next = self.reset.val();
        self.fe.position.next = self.position.val();
        self.fe.ratio.next = self.ratio.val();
        self.fe.tol.next = self.tol.val();
        self.fe.align.next = self.align.val();
        self.fe.clear.next = self.clear.val();
        self.fe.dev_axis.next = self.sel.val().get_bits::<4>(0);
        self.pos_axis.next = self.fe.ax.val();
        self.fail.next = self.fe.fail.val();
        self.fe.count.next = self.ext.count1.val();

        // The visited axis's outputs, to the extension, which acknowledges them: each
        // decoder's 60 bits packed at a stride of 64, the axis's picked by a shift
        // (a tree of multiplexers on `ax`'s bits, see `FieldPlace`).
        self.pack[0].bus_in.next = 0.into();
        self.ipack[0].bus_in.next = 0.into();
        for i in 1..K {
            self.pack[i].bus_in.next = self.pack[i - 1].bus_out.val();
            self.ipack[i].bus_in.next = self.ipack[i - 1].bus_out.val();
        }
        for i in 0..K {
            self.a_pick[i].bus.next = self.enc_a.val();
            self.b_pick[i].bus.next = self.enc_b.val();
            self.z_pick[i].bus.next = self.enc_z.val();
            self.inv_pick[i].bus.next = self.invert.val();
            self.arm_pick[i].bus.next = self.arm.val();
            self.dec[i].clock.next = self.clock.val();
            self.dec[i].reset.next = self.reset.val();
            self.dec[i].a.next = self.a_pick[i].value.val();
            self.dec[i].b.next = self.b_pick[i].value.val();
            self.dec[i].z.next = self.z_pick[i].value.val();
            self.dec[i].mode.next = self.mode.val();
            self.dec[i].invert.next = self.inv_pick[i].value.val();
            self.dec[i].arm.next = self.arm_pick[i].value.val();
            self.dec[i].probe.next = self.probe.val();
            self.dec[i].vel_tick.next = self.tick.val();
            self.pos_pick[i].bus.next = self.pos_low.val();
            self.dec[i].position.next = self.pos_pick[i].value.val();
            self.dec[i].ack.next = false;
            if self.fe.ax.val().index() == i {
                self.dec[i].ack.next = true;
            }
            self.pack[i].value.next = self.dec[i].visit.val();
            self.ipack[i].value.next = self.dec[i].index_pos.val();
            // (The last assignment, axis K − 1's, stands.)
            self.all_vis.next = self.pack[i].bus_out.val();
            self.ip_all.next = self.ipack[i].bus_out.val();
        }
        self.shifted.next = self.all_vis.val() >> (bit_cast::<16, 4>(self.fe.ax.val()) << 6);
        self.v_word.next = self.shifted.val().get_bits::<64>(0);
        self.vis_q.d.next = self.v_word.val();
        self.ip_shift.next = self.ip_all.val() >> (bit_cast::<16, 4>(self.fe.ax.val()) << 3);
        self.vis_ip.d.next = self.ip_shift.val().get_bits::<8>(0);
        self.vis_ax.d.next = self.fe.ax.val();
        self.vis_ok.d.next = !self.reset.val();
        self.v_count.next = self.vis_q.q.val().get_bits::<8>(0);
        self.v_index.next = self.vis_q.q.val().get_bits::<8>(8);
        self.v_probe.next = self.vis_q.q.val().get_bits::<8>(16);
        self.v_period.next = self.vis_q.q.val().get_bits::<8>(24);
        self.v_age.next = self.vis_q.q.val().get_bits::<8>(32);
        self.v_ill.next = self.vis_q.q.val().get_bits::<8>(40);
        self.v_cnew.next = self.vis_q.q.val().get_bit(48);
        self.v_inew.next = self.vis_q.q.val().get_bit(49);
        self.v_iafter.next = self.vis_q.q.val().get_bit(50);
        self.v_pnew.next = self.vis_q.q.val().get_bit(51);
        self.v_pafter.next = self.vis_q.q.val().get_bit(52);
        self.v_enew.next = self.vis_q.q.val().get_bit(53);
        self.v_e2.next = self.vis_q.q.val().get_bit(54);
        self.v_armed.next = self.vis_q.q.val().get_bit(55);
        self.v_dir.next = self.vis_q.q.val().get_bit(56);
        self.v_la.next = self.vis_q.q.val().get_bit(57);
        self.v_lb.next = self.vis_q.q.val().get_bit(58);
        self.v_lz.next = self.vis_q.q.val().get_bit(59);
        self.ext.clock.next = self.clock.val();
        self.ext.reset.next = self.reset.val();
        self.ext.ax.next = self.vis_ax.q.val();
        self.ext.ok.next = self.vis_ok.q.val();
        self.ext.next_ax.next = self.fe.ax.val();
        self.ext.count.next = self.v_count.val();
        self.ext.index_count.next = self.v_index.val();
        self.ext.probe_count.next = self.v_probe.val();
        self.ext.cnew.next = self.v_cnew.val();
        self.ext.inew.next = self.v_inew.val();
        self.ext.iafter.next = self.v_iafter.val();
        self.ext.pnew.next = self.v_pnew.val();
        self.ext.pafter.next = self.v_pafter.val();
        self.ext.enew.next = self.v_enew.val();
        self.ext.e2.next = self.v_e2.val();
        self.ext.period.next = self.v_period.val();
        self.ext.age.next = self.v_age.val();
        self.ext.index_pos.next = self.vis_ip.q.val();
        self.ext.pos.next = self.fe.pos1.val();
        self.ext.live.next = bit_cast::<LIVE_BITS, 8>(self.v_ill.val())
            | (bit_cast::<LIVE_BITS, 1>(self.v_armed.val().into()) << 8)
            | (bit_cast::<LIVE_BITS, 1>(self.v_dir.val().into()) << 9)
            | (bit_cast::<LIVE_BITS, 1>(self.v_la.val().into()) << 10)
            | (bit_cast::<LIVE_BITS, 1>(self.v_lb.val().into()) << 11)
            | (bit_cast::<LIVE_BITS, 1>(self.v_lz.val().into()) << 12);

        // Axis `sel`'s word, from memory.
        self.ext.sel.next = self.sel.val().get_bits::<4>(0);
        self.w_fail.next = (self.fe.fail.val() & (self.c_one.val() << self.sel.val())).any();
        self.word_lo.next = bit_cast::<128, 32>(self.ext.s_count.val())
            | (bit_cast::<128, 32>(self.ext.s_index.val()) << 32)
            | (bit_cast::<128, 32>(self.ext.s_probe.val()) << 64)
            | (bit_cast::<128, 32>(self.fe.dev.val()) << 96);
        self.word_hi.next = bit_cast::<81, 16>(self.ext.s_period.val())
            | (bit_cast::<81, 16>(self.ext.s_age.val()) << 16)
            | (bit_cast::<81, LIVE_BITS>(self.ext.s_live.val()) << 32)
            | (bit_cast::<81, 1>(self.w_fail.val().into()) << 45)
            | (bit_cast::<81, 1>(self.ext.s_itog.val().into()) << 46)
            | (bit_cast::<81, 1>(self.ext.s_ptog.val().into()) << 47)
            | (bit_cast::<81, 1>(self.ext.s_valid.val().into()) << 48)
            | (bit_cast::<81, 32>(self.ext.s_ipos.val()) << 49);
    }
}
