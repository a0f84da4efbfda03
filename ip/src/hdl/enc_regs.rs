//! The encoder feedback's registers (`regs::Feature::Encoder`), in the bus clock, and
//! their crossings to and from [`super::enc_bank::EncoderBank`] in `clk`. A block beside
//! the register file like [`super::io_regs::IoRegs`]: its reads return 0 outside its
//! own addresses (the top ORs the read buses), and it decodes its own writes. Tested
//! through the top (tests/system.rs), as every dual-clock block is.
//!
//! Ports:
//! * bus side (`bus_clock`, `bus_reset`): `wr`, `wr_addr`, `wr_data` (the EXMC slave's
//!   commit), `rd` and `rd_addr` → `rd_data` (combinational), `enable` (CTRL.ENABLE),
//!   `irq` (IRQ_ENC under IRQ_MASK_ENC, registered), `b_stop_ev` (bit a for one cycle
//!   when axis a's ENC_FAIL rises while ENC_STOP names it: the push guard's stop event);
//! * configuration to `clk`: `mode` (ENC_FILTER and ENC_INDEX_MODE as the decoders'
//!   mode word), `invert`, `vel_prescale`, `stop` (ENC_STOP under the bank's `fail`;
//!   `cstop` instead with ENC_STOP_MODE.CONTROLLED, which only a block built
//!   [`EncRegs::with_io`] has: the machine I/O's controlled stop),
//!   and per axis the ratio and tolerance, in bus-clock LUT RAM read at `pos_axis`
//!   (`ratio`, `tol`): all written only while CTRL.ENABLE = 0 and the core is held in
//!   reset (`running`, synchronised, is 0), so static whenever the bank, held in reset
//!   with the core, uses them; a write at any other time is refused (ENC_STATUS.REFUSED,
//!   code 3). An axis's ratio reads 1.0 and its tolerance 0 until written after a reset
//!   (a flag per axis: the memories have no reset). The memories' read address is
//!   `pos_axis` while CTRL.ENABLE = 1 and ENC_AXIS while it is 0, which lets the bus read
//!   them back while the core is held;
//! * commands to `clk`: ENC_ARM, ENC_ALIGN and ENC_CLEAR collect their bits
//!   and cross as one mask through a [`MaskCross`], as the controlled stop's STOP
//!   does ([`super::stop_regs::StopRegs`]): one cycle of `arm`, `align`, `clear` 3 to 4 `clk`
//!   edges after the write commits;
//! * status from `clk`: `fail` (the bank's ENC_FAIL flags) through two flip-flops per
//!   bit; the window: a [`WordSync`] copies one axis's status word at a time, round
//!   robin (`sel` names it, `word_lo` and `word_hi` are the bank's word), and the copies
//!   of axis ENC_AXIS are kept in `win`, which the window registers read. Reading a
//!   *_LO half latches its *_HI half (one latch for all). `running` (the core out of
//!   reset, `clk`) gates the events.
//!
//! Events (IRQ_ENC): FAIL when a bit of the synchronised `fail` rises, ILLEGAL and INDEX
//! when a copy of an axis shows another illegal-transition count or index toggle than
//! its previous copy (a 9-bit history per axis in LUT RAM); only while CTRL.ENABLE = 1
//! and the core runs; cleared while CTRL.ENABLE = 0.

use super::cdc::{BitSync, BitsSync, MaskCross};
use super::enc_bank::ENC_WORD_BITS;
use super::lut_ram::LutRam;
use super::regfile::c9;
use super::status_sync::WordSync;
use crate::model::encoder::{EncRefusal, FILTER_MAX, RATIO_MAX, RATIO_ONE};
use crate::regs::ADDR_BITS;
use rust_hdl::prelude::*;

#[derive(LogicBlock)]
pub struct EncRegs<const K: usize> {
    pub bus_clock: Signal<In, Clock>,
    pub bus_reset: Signal<In, Bit>,
    pub wr: Signal<In, Bit>,
    pub wr_addr: Signal<In, Bits<ADDR_BITS>>,
    pub wr_data: Signal<In, Bits<16>>,
    pub rd: Signal<In, Bit>,
    pub rd_addr: Signal<In, Bits<ADDR_BITS>>,
    pub rd_data: Signal<Out, Bits<16>>,
    pub enable: Signal<In, Bit>,
    pub irq: Signal<Out, Bit>,
    pub b_stop_ev: Signal<Out, Bits<K>>,
    pub clock: Signal<In, Clock>,
    pub creset: Signal<In, Bit>,
    pub running: Signal<In, Bit>,
    pub mode: Signal<Out, Bits<8>>,
    pub invert: Signal<Out, Bits<K>>,
    pub vel_prescale: Signal<Out, Bits<16>>,
    pub arm: Signal<Out, Bits<K>>,
    pub align: Signal<Out, Bits<K>>,
    pub clear: Signal<Out, Bits<K>>,
    pub pos_axis: Signal<In, Bits<4>>,
    pub ratio: Signal<Out, Bits<32>>,
    pub tol: Signal<Out, Bits<16>>,
    pub sel: Signal<Out, Bits<8>>,
    pub word_lo: Signal<In, Bits<128>>,
    pub word_hi: Signal<In, Bits<81>>,
    pub fail: Signal<In, Bits<K>>,
    pub stop: Signal<Out, Bits<K>>,
    /// The controlled stop's request on ENC_FAIL (ENC_STOP under `fail` with
    /// ENC_STOP_MODE.CONTROLLED; only [`EncRegs::with_io`] has the register, else 0).
    pub cstop: Signal<Out, Bits<K>>,
    // Bus clock: configuration.
    axis_r: DFF<Bits<4>>,
    filt: DFF<Bits<4>>,
    imode: DFF<Bits<4>>,
    inv: DFF<Bits<K>>,
    pre: DFF<Bits<16>>,
    stop_m: DFF<Bits<K>>,
    /// ENC_STOP_MODE.CONTROLLED (with the machine I/O's controlled stop: `c_io`).
    smode: DFF<Bit>,
    c_io: Constant<Bit>,
    a_smode: Constant<Bits<ADDR_BITS>>,
    rlo: DFF<Bits<16>>,
    ratio_ram: LutRam<32, 4>,
    tol_ram: LutRam<16, 4>,
    rset: DFF<Bits<K>>,
    tset: DFF<Bits<K>>,
    refused: DFF<Bit>,
    code: DFF<Bits<4>>,
    // Commands, collected and crossed as one mask (arm 15..0, align 31..16, clear 47..32).
    cmd_x: MaskCross<48>,
    req: Signal<Local, Bits<48>>,
    // Status and events.
    run_s: BitSync,
    fail_s: BitsSync<K>,
    fail_prev: DFF<Bits<K>>,
    wsync: WordSync<K, ENC_WORD_BITS>,
    win: DFF<Bits<ENC_WORD_BITS>>,
    hi_latch: DFF<Bits<16>>,
    hist: LutRam<9, 4>,
    seen: DFF<Bits<K>>,
    events: DFF<Bits<3>>,
    emask: DFF<Bits<3>>,
    irq_q: DFF<Bit>,
    // Locals.
    may_config: Signal<Local, Bit>,
    live: Signal<Local, Bit>,
    staged: Signal<Local, Bits<32>>,
    raddr: Signal<Local, Bits<4>>,
    r_set: Signal<Local, Bit>,
    t_set: Signal<Local, Bit>,
    r_val: Signal<Local, Bits<32>>,
    t_val: Signal<Local, Bits<16>>,
    w_word: Signal<Local, Bits<ENC_WORD_BITS>>,
    w_axis: Signal<Local, Bits<4>>,
    w_seen: Signal<Local, Bit>,
    w_ill: Signal<Local, Bits<8>>,
    w_itog: Signal<Local, Bit>,
    h_old: Signal<Local, Bits<9>>,
    fail_new: Signal<Local, Bits<K>>,
    new_ev: Signal<Local, Bits<3>>,
    e_ill: Signal<Local, Bit>,
    e_idx: Signal<Local, Bit>,
    c_one: Constant<Bits<K>>,
    c_k: Constant<Bits<16>>,
    c_rmax: Constant<Bits<32>>,
    c_rone: Constant<Bits<32>>,
    c_fmax: Constant<Bits<16>>,
    c_code_ratio: Constant<Bits<4>>,
    c_code_filter: Constant<Bits<4>>,
    c_code_enabled: Constant<Bits<4>>,
    c_code_axis: Constant<Bits<4>>,
    a_axis: Constant<Bits<ADDR_BITS>>,
    a_filter: Constant<Bits<ADDR_BITS>>,
    a_imode: Constant<Bits<ADDR_BITS>>,
    a_invert: Constant<Bits<ADDR_BITS>>,
    a_pre: Constant<Bits<ADDR_BITS>>,
    a_rlo: Constant<Bits<ADDR_BITS>>,
    a_rhi: Constant<Bits<ADDR_BITS>>,
    a_tol: Constant<Bits<ADDR_BITS>>,
    a_stop: Constant<Bits<ADDR_BITS>>,
    a_arm: Constant<Bits<ADDR_BITS>>,
    a_align: Constant<Bits<ADDR_BITS>>,
    a_clear: Constant<Bits<ADDR_BITS>>,
    a_fail: Constant<Bits<ADDR_BITS>>,
    a_status: Constant<Bits<ADDR_BITS>>,
    a_irq: Constant<Bits<ADDR_BITS>>,
    a_mask: Constant<Bits<ADDR_BITS>>,
    a_clo: Constant<Bits<ADDR_BITS>>,
    a_chi: Constant<Bits<ADDR_BITS>>,
    a_ilo: Constant<Bits<ADDR_BITS>>,
    a_ihi: Constant<Bits<ADDR_BITS>>,
    a_plo: Constant<Bits<ADDR_BITS>>,
    a_xlo: Constant<Bits<ADDR_BITS>>,
    a_xhi: Constant<Bits<ADDR_BITS>>,
    a_phi: Constant<Bits<ADDR_BITS>>,
    a_dlo: Constant<Bits<ADDR_BITS>>,
    a_dhi: Constant<Bits<ADDR_BITS>>,
    a_period: Constant<Bits<ADDR_BITS>>,
    a_age: Constant<Bits<ADDR_BITS>>,
    a_state: Constant<Bits<ADDR_BITS>>,
}

impl<const K: usize> Default for EncRegs<K> {
    fn default() -> Self {
        assert!((1..=16).contains(&K), "EncRegs: K = {K} outside 1..=16");
        let code = |r: EncRefusal| Constant::new((r.code() as u64).into());
        EncRegs {
            bus_clock: Default::default(),
            bus_reset: Default::default(),
            wr: Default::default(),
            wr_addr: Default::default(),
            wr_data: Default::default(),
            rd: Default::default(),
            rd_addr: Default::default(),
            rd_data: Default::default(),
            enable: Default::default(),
            irq: Default::default(),
            b_stop_ev: Default::default(),
            clock: Default::default(),
            creset: Default::default(),
            running: Default::default(),
            mode: Default::default(),
            invert: Default::default(),
            vel_prescale: Default::default(),
            arm: Default::default(),
            align: Default::default(),
            clear: Default::default(),
            pos_axis: Default::default(),
            ratio: Default::default(),
            tol: Default::default(),
            sel: Default::default(),
            word_lo: Default::default(),
            word_hi: Default::default(),
            fail: Default::default(),
            stop: Default::default(),
            axis_r: Default::default(),
            filt: Default::default(),
            imode: Default::default(),
            inv: Default::default(),
            pre: Default::default(),
            stop_m: Default::default(),
            smode: Default::default(),
            c_io: Constant::new(false),
            a_smode: c9("ENC_STOP_MODE"),
            cstop: Default::default(),
            rlo: Default::default(),
            ratio_ram: Default::default(),
            tol_ram: Default::default(),
            rset: Default::default(),
            tset: Default::default(),
            refused: Default::default(),
            code: Default::default(),
            cmd_x: Default::default(),
            req: Default::default(),
            run_s: Default::default(),
            fail_s: Default::default(),
            fail_prev: Default::default(),
            wsync: Default::default(),
            win: Default::default(),
            hi_latch: Default::default(),
            hist: Default::default(),
            seen: Default::default(),
            events: Default::default(),
            emask: Default::default(),
            irq_q: Default::default(),
            may_config: Default::default(),
            live: Default::default(),
            staged: Default::default(),
            raddr: Default::default(),
            r_set: Default::default(),
            t_set: Default::default(),
            r_val: Default::default(),
            t_val: Default::default(),
            w_word: Default::default(),
            w_axis: Default::default(),
            w_seen: Default::default(),
            w_ill: Default::default(),
            w_itog: Default::default(),
            h_old: Default::default(),
            fail_new: Default::default(),
            new_ev: Default::default(),
            e_ill: Default::default(),
            e_idx: Default::default(),
            c_one: Constant::new(1.into()),
            c_k: Constant::new((K as u64).into()),
            c_rmax: Constant::new((RATIO_MAX as u64).into()),
            c_rone: Constant::new((RATIO_ONE as u64).into()),
            c_fmax: Constant::new((FILTER_MAX as u64).into()),
            c_code_ratio: code(EncRefusal::Ratio),
            c_code_filter: code(EncRefusal::Filter),
            c_code_enabled: code(EncRefusal::Enabled),
            c_code_axis: code(EncRefusal::Axis),
            a_axis: c9("ENC_AXIS"),
            a_filter: c9("ENC_FILTER"),
            a_imode: c9("ENC_INDEX_MODE"),
            a_invert: c9("ENC_INVERT"),
            a_pre: c9("ENC_VEL_PRESCALE"),
            a_rlo: c9("ENC_RATIO_LO"),
            a_rhi: c9("ENC_RATIO_HI"),
            a_tol: c9("ENC_TOL"),
            a_stop: c9("ENC_STOP"),
            a_arm: c9("ENC_ARM"),
            a_align: c9("ENC_ALIGN"),
            a_clear: c9("ENC_CLEAR"),
            a_fail: c9("ENC_FAIL"),
            a_status: c9("ENC_STATUS"),
            a_irq: c9("IRQ_ENC"),
            a_mask: c9("IRQ_MASK_ENC"),
            a_clo: c9("ENC_COUNT_LO"),
            a_chi: c9("ENC_COUNT_HI"),
            a_ilo: c9("ENC_INDEX_LO"),
            a_ihi: c9("ENC_INDEX_HI"),
            a_plo: c9("ENC_PROBE_LO"),
            a_xlo: c9("ENC_INDEX_POS_LO"),
            a_xhi: c9("ENC_INDEX_POS_HI"),
            a_phi: c9("ENC_PROBE_HI"),
            a_dlo: c9("ENC_DEV_LO"),
            a_dhi: c9("ENC_DEV_HI"),
            a_period: c9("ENC_PERIOD"),
            a_age: c9("ENC_AGE"),
            a_state: c9("ENC_STATE"),
        }
    }
}

impl<const K: usize> EncRegs<K> {
    /// With the machine I/O's controlled stop: the ENC_STOP_MODE register (without it
    /// the register reads 0, ignores writes and `cstop` is 0).
    pub fn with_io(mut self, io: bool) -> Self {
        self.c_io = Constant::new(io);
        self
    }
}

impl<const K: usize> Logic for EncRegs<K> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, bus_clock, axis_r, filt, imode, inv, pre, stop_m, smode, rlo, rset, tset, refused, code, fail_prev, win,
            hi_latch, seen, events, emask, irq_q
        );
        // ---- bus clock: configuration ----
        self.run_s.clock.next = self.bus_clock.val();
        self.run_s.sig_in.next = self.running.val();
        self.may_config.next = !self.enable.val() & !self.run_s.sig_out.val();
        self.live.next = self.enable.val() & self.run_s.sig_out.val();
        self.staged.next = (bit_cast::<32, 16>(self.wr_data.val()) << 16) | bit_cast::<32, 16>(self.rlo.q.val());
        self.ratio_ram.clock.next = self.bus_clock.val();
        self.ratio_ram.we.next = false;
        self.ratio_ram.waddr.next = self.axis_r.q.val();
        self.ratio_ram.wdata.next = self.staged.val();
        self.tol_ram.clock.next = self.bus_clock.val();
        self.tol_ram.we.next = false;
        self.tol_ram.waddr.next = self.axis_r.q.val();
        self.tol_ram.wdata.next = self.wr_data.val();
        if self.wr.val() {
            if self.wr_addr.val() == self.a_axis.val() {
                if self.wr_data.val() < self.c_k.val() {
                    self.axis_r.d.next = self.wr_data.val().get_bits::<4>(0);
                    // The window empties until the new axis's next copy.
                    self.win.d.next = 0.into();
                } else {
                    self.refused.d.next = true;
                    self.code.d.next = self.c_code_axis.val();
                }
            }
            if self.wr_addr.val() == self.a_rlo.val() {
                self.rlo.d.next = self.wr_data.val();
            }
            if (self.wr_addr.val() == self.a_filter.val())
                | (self.wr_addr.val() == self.a_imode.val())
                | (self.wr_addr.val() == self.a_invert.val())
                | (self.wr_addr.val() == self.a_pre.val())
                | (self.wr_addr.val() == self.a_rhi.val())
                | (self.wr_addr.val() == self.a_tol.val())
                | (self.wr_addr.val() == self.a_stop.val())
                | ((self.wr_addr.val() == self.a_smode.val()) & self.c_io.val())
            {
                if !self.may_config.val() {
                    self.refused.d.next = true;
                    self.code.d.next = self.c_code_enabled.val();
                } else {
                    if self.wr_addr.val() == self.a_filter.val() {
                        if self.wr_data.val() > self.c_fmax.val() {
                            self.refused.d.next = true;
                            self.code.d.next = self.c_code_filter.val();
                        } else {
                            self.filt.d.next = self.wr_data.val().get_bits::<4>(0);
                        }
                    }
                    if self.wr_addr.val() == self.a_imode.val() {
                        self.imode.d.next = self.wr_data.val().get_bits::<4>(0);
                    }
                    if self.wr_addr.val() == self.a_invert.val() {
                        self.inv.d.next = self.wr_data.val().get_bits::<K>(0);
                    }
                    if self.wr_addr.val() == self.a_pre.val() {
                        self.pre.d.next = self.wr_data.val();
                    }
                    if self.wr_addr.val() == self.a_stop.val() {
                        self.stop_m.d.next = self.wr_data.val().get_bits::<K>(0);
                    }
                    if (self.wr_addr.val() == self.a_smode.val()) & self.c_io.val() {
                        self.smode.d.next = self.wr_data.val().get_bit(0);
                    }
                    if self.wr_addr.val() == self.a_rhi.val() {
                        if !self.staged.val().any() | (self.staged.val() > self.c_rmax.val()) {
                            self.refused.d.next = true;
                            self.code.d.next = self.c_code_ratio.val();
                        } else {
                            self.ratio_ram.we.next = true;
                            self.rset.d.next = self.rset.q.val() | (self.c_one.val() << self.axis_r.q.val());
                        }
                    }
                    if self.wr_addr.val() == self.a_tol.val() {
                        self.tol_ram.we.next = true;
                        self.tset.d.next = self.tset.q.val() | (self.c_one.val() << self.axis_r.q.val());
                    }
                }
            }
            if (self.wr_addr.val() == self.a_status.val()) & self.wr_data.val().get_bit(0) {
                self.refused.d.next = false;
                self.code.d.next = 0.into();
            }
            if self.wr_addr.val() == self.a_mask.val() {
                self.emask.d.next = self.wr_data.val().get_bits::<3>(0);
            }
        }
        // Per axis ratio and tolerance: the bank's axis while enabled, ENC_AXIS while
        // held (bus read-back); 1.0 and 0 until written.
        self.raddr.next = self.axis_r.q.val();
        if self.enable.val() {
            self.raddr.next = self.pos_axis.val();
        }
        self.ratio_ram.raddr.next = self.raddr.val();
        self.tol_ram.raddr.next = self.raddr.val();
        self.r_set.next = (self.rset.q.val() & (self.c_one.val() << self.raddr.val())).any();
        self.t_set.next = (self.tset.q.val() & (self.c_one.val() << self.raddr.val())).any();
        self.r_val.next = self.c_rone.val();
        if self.r_set.val() {
            self.r_val.next = self.ratio_ram.rdata.val();
        }
        self.t_val.next = 0.into();
        if self.t_set.val() {
            self.t_val.next = self.tol_ram.rdata.val();
        }
        self.ratio.next = self.r_val.val();
        self.tol.next = self.t_val.val();
        self.mode.next = bit_cast::<8, 4>(self.filt.q.val()) | (bit_cast::<8, 4>(self.imode.q.val()) << 4);
        self.invert.next = self.inv.q.val();
        self.vel_prescale.next = self.pre.q.val();

        // ---- commands across ----
        self.req.next = 0.into();
        if self.wr.val() & (self.wr_addr.val() == self.a_arm.val()) {
            self.req.next = bit_cast::<48, 16>(self.wr_data.val());
        }
        if self.wr.val() & (self.wr_addr.val() == self.a_align.val()) {
            self.req.next = bit_cast::<48, 16>(self.wr_data.val()) << 16;
        }
        if self.wr.val() & (self.wr_addr.val() == self.a_clear.val()) {
            self.req.next = bit_cast::<48, 16>(self.wr_data.val()) << 32;
        }
        self.cmd_x.bus_clock.next = self.bus_clock.val();
        self.cmd_x.bus_reset.next = self.bus_reset.val();
        self.cmd_x.req.next = self.req.val();
        self.cmd_x.clock.next = self.clock.val();
        self.arm.next = self.cmd_x.out.val().get_bits::<K>(0);
        self.align.next = self.cmd_x.out.val().get_bits::<K>(16);
        self.clear.next = self.cmd_x.out.val().get_bits::<K>(32);
        // The stop on ENC_FAIL (clk: `fail` is a register, ENC_STOP static).
        // Hard, or (ENC_STOP_MODE.CONTROLLED) the controlled stop's request, held while
        // the flag is set.
        self.stop.next = self.fail.val() & self.stop_m.q.val();
        self.cstop.next = 0.into();
        if self.smode.q.val() {
            self.stop.next = 0.into();
            self.cstop.next = self.fail.val() & self.stop_m.q.val();
        }

        // ---- status: ENC_FAIL and the window ----
        self.fail_s.clock.next = self.bus_clock.val();
        self.fail_s.sig_in.next = self.fail.val();
        self.fail_prev.d.next = self.fail_s.sig_out.val();
        self.fail_new.next = self.fail_s.sig_out.val() & !self.fail_prev.q.val();
        self.b_stop_ev.next = self.fail_new.val() & self.stop_m.q.val();
        self.wsync.cclock.next = self.clock.val();
        self.wsync.creset.next = self.creset.val();
        self.wsync.word_in.next = bit_cast::<ENC_WORD_BITS, 128>(self.word_lo.val()) | (bit_cast::<ENC_WORD_BITS, 81>(self.word_hi.val()) << 128);
        self.sel.next = self.wsync.sel.val();
        self.wsync.bclock.next = self.bus_clock.val();
        self.wsync.breset.next = self.bus_reset.val();
        self.w_word.next = self.wsync.word.val();
        self.w_axis.next = self.wsync.axis.val().get_bits::<4>(0);
        self.w_ill.next = self.w_word.val().get_bits::<8>(160);
        self.w_itog.next = self.w_word.val().get_bit(174);
        self.hist.clock.next = self.bus_clock.val();
        self.hist.raddr.next = self.w_axis.val();
        self.hist.waddr.next = self.w_axis.val();
        self.hist.wdata.next = bit_cast::<9, 8>(self.w_ill.val()) | (bit_cast::<9, 1>(self.w_itog.val().into()) << 8);
        self.hist.we.next = false;
        self.h_old.next = self.hist.rdata.val();
        self.w_seen.next = (self.seen.q.val() & (self.c_one.val() << self.w_axis.val())).any();
        self.e_ill.next = false;
        self.e_idx.next = false;
        if self.wsync.valid.val() & self.w_word.val().get_bit(176) {
            if (self.w_axis.val() == self.axis_r.q.val()) & !(self.wr.val() & (self.wr_addr.val() == self.a_axis.val())) {
                self.win.d.next = self.w_word.val();
            }
            if self.live.val() {
                self.hist.we.next = true;
                self.seen.d.next = self.seen.q.val() | (self.c_one.val() << self.w_axis.val());
                if self.w_seen.val() {
                    self.e_ill.next = self.w_ill.val() != self.h_old.val().get_bits::<8>(0);
                    self.e_idx.next = self.w_itog.val() != self.h_old.val().get_bit(8);
                }
            }
        }
        self.new_ev.next = bit_cast::<3, 1>(self.fail_new.val().any().into())
            | (bit_cast::<3, 1>(self.e_ill.val().into()) << 1)
            | (bit_cast::<3, 1>(self.e_idx.val().into()) << 2);
        self.events.d.next = self.events.q.val() | self.new_ev.val();
        if self.wr.val() & (self.wr_addr.val() == self.a_irq.val()) {
            self.events.d.next = (self.events.q.val() & !self.wr_data.val().get_bits::<3>(0)) | self.new_ev.val();
        }
        if !self.live.val() {
            self.events.d.next = 0.into();
            self.seen.d.next = 0.into();
        }
        self.irq_q.d.next = (self.events.q.val() & self.emask.q.val()).any();
        self.irq.next = self.irq_q.q.val();

        // ---- reads ----
        self.rd_data.next = 0.into();
        if self.rd_addr.val() == self.a_axis.val() {
            self.rd_data.next = bit_cast::<16, 4>(self.axis_r.q.val());
        }
        if self.rd_addr.val() == self.a_filter.val() {
            self.rd_data.next = bit_cast::<16, 4>(self.filt.q.val());
        }
        if self.rd_addr.val() == self.a_imode.val() {
            self.rd_data.next = bit_cast::<16, 4>(self.imode.q.val());
        }
        if self.rd_addr.val() == self.a_invert.val() {
            self.rd_data.next = bit_cast::<16, K>(self.inv.q.val());
        }
        if self.rd_addr.val() == self.a_pre.val() {
            self.rd_data.next = self.pre.q.val();
        }
        if (self.rd_addr.val() == self.a_rlo.val()) & !self.enable.val() {
            self.rd_data.next = self.r_val.val().get_bits::<16>(0);
        }
        if (self.rd_addr.val() == self.a_rhi.val()) & !self.enable.val() {
            self.rd_data.next = self.r_val.val().get_bits::<16>(16);
        }
        if (self.rd_addr.val() == self.a_tol.val()) & !self.enable.val() {
            self.rd_data.next = self.t_val.val();
        }
        if (self.rd_addr.val() == self.a_smode.val()) & self.c_io.val() {
            self.rd_data.next = bit_cast::<16, 1>(self.smode.q.val().into());
        }
        if self.rd_addr.val() == self.a_stop.val() {
            self.rd_data.next = bit_cast::<16, K>(self.stop_m.q.val());
        }
        if self.rd_addr.val() == self.a_fail.val() {
            self.rd_data.next = bit_cast::<16, K>(self.fail_s.sig_out.val());
        }
        if self.rd_addr.val() == self.a_status.val() {
            self.rd_data.next = bit_cast::<16, 1>(self.refused.q.val().into()) | (bit_cast::<16, 4>(self.code.q.val()) << 4);
        }
        if self.rd_addr.val() == self.a_irq.val() {
            self.rd_data.next = bit_cast::<16, 3>(self.events.q.val());
        }
        if self.rd_addr.val() == self.a_mask.val() {
            self.rd_data.next = bit_cast::<16, 3>(self.emask.q.val());
        }
        if self.rd_addr.val() == self.a_clo.val() {
            self.rd_data.next = self.win.q.val().get_bits::<16>(0);
        }
        if self.rd_addr.val() == self.a_ilo.val() {
            self.rd_data.next = self.win.q.val().get_bits::<16>(32);
        }
        if self.rd_addr.val() == self.a_plo.val() {
            self.rd_data.next = self.win.q.val().get_bits::<16>(64);
        }
        if self.rd_addr.val() == self.a_dlo.val() {
            self.rd_data.next = self.win.q.val().get_bits::<16>(96);
        }
        if self.rd_addr.val() == self.a_xlo.val() {
            self.rd_data.next = self.win.q.val().get_bits::<16>(177);
        }
        if (self.rd_addr.val() == self.a_chi.val())
            | (self.rd_addr.val() == self.a_xhi.val())
            | (self.rd_addr.val() == self.a_ihi.val())
            | (self.rd_addr.val() == self.a_phi.val())
            | (self.rd_addr.val() == self.a_dhi.val())
        {
            self.rd_data.next = self.hi_latch.q.val();
        }
        if self.rd_addr.val() == self.a_period.val() {
            self.rd_data.next = self.win.q.val().get_bits::<16>(128);
        }
        if self.rd_addr.val() == self.a_age.val() {
            self.rd_data.next = self.win.q.val().get_bits::<16>(144);
        }
        if self.rd_addr.val() == self.a_state.val() {
            self.rd_data.next = bit_cast::<16, 14>(self.win.q.val().get_bits::<14>(160))
                | (bit_cast::<16, 1>(self.win.q.val().get_bit(176).into()) << 15);
        }
        // Reading a low half latches its high half.
        if self.rd.val() {
            if self.rd_addr.val() == self.a_clo.val() {
                self.hi_latch.d.next = self.win.q.val().get_bits::<16>(16);
            }
            if self.rd_addr.val() == self.a_ilo.val() {
                self.hi_latch.d.next = self.win.q.val().get_bits::<16>(48);
            }
            if self.rd_addr.val() == self.a_plo.val() {
                self.hi_latch.d.next = self.win.q.val().get_bits::<16>(80);
            }
            if self.rd_addr.val() == self.a_dlo.val() {
                self.hi_latch.d.next = self.win.q.val().get_bits::<16>(112);
            }
            if self.rd_addr.val() == self.a_xlo.val() {
                self.hi_latch.d.next = self.win.q.val().get_bits::<16>(193);
            }
        }
        if self.bus_reset.val() {
            self.axis_r.d.next = 0.into();
            self.filt.d.next = 0.into();
            self.imode.d.next = 0.into();
            self.inv.d.next = 0.into();
            self.pre.d.next = 0.into();
            self.stop_m.d.next = 0.into();
            self.smode.d.next = false;
            self.rset.d.next = 0.into();
            self.tset.d.next = 0.into();
            self.refused.d.next = false;
            self.code.d.next = 0.into();
            self.win.d.next = 0.into();
            self.events.d.next = 0.into();
            self.emask.d.next = 0.into();
            self.seen.d.next = 0.into();
            self.ratio_ram.we.next = false;
            self.tol_ram.we.next = false;
        }
    }
}
