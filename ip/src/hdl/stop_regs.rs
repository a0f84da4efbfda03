//! The controlled stop's registers (`regs::Feature::Io`), in the bus clock, and the
//! crossing of its commands to `clk`. A block beside the register file like
//! [`super::io_regs::IoRegs`]: its reads return 0 outside its own addresses.
//!
//! * **STOP** (write): bit i requests a controlled stop of axis i. Requests cross into
//!   `clk` through a [`MaskCross`] (written bits ORed in while a mask is crossing, so
//!   none is lost): one cycle of `cstop`, 3 to 4 `clk` edges after the write commits
//!   (plus the bus cycles it waits for the mask before it); `bus_reset` drops requests
//!   not yet sent. A request reaching a core held in reset is dropped there.
//! * **STOP_DECEL_LO/HI**: the deceleration, a = DECEL/2^57 steps/tick²
//!   ([`crate::model::stop`]). LO stages bits 15:0; a write of HI applies {HI, staged
//!   LO} unless the core is enabled (CTRL.ENABLE = 1), or the value is below the
//!   export's minimum ([`crate::model::stop::stop_decel_min`], `c_min`): then it is
//!   refused (STOP_STATUS.REFUSED) and the deceleration in use stays. Reads return the
//!   value in use. After reset it is 2^32 − 1 (the hardest). `decel` is that register,
//!   read in `clk` only while a ramp is formed, which an enabled core alone does.
//! * **STOP_MODE** (bits 3..0: the limits, the alarm, the watchdog, the stop on home;
//!   1 = the controlled stop, 0 = the hard stop; `model::io`): configuration, written
//!   only while CTRL.ENABLE = 0 (else refused: STOP_STATUS.REFUSED), so `mode` is static
//!   whenever the core runs and goes to `clk` as a wire. 0 after reset.
//! * **STOP_HOME** (bit a: stop axis a on its home latch): written at any time; each bit
//!   crosses into `clk` through two flip-flops (`home_arm`, 2 to 3 `clk` edges after the
//!   write). 0 after reset.
//!
//! Ports: the bus (`wr`, `wr_addr`, `wr_data`, `rd_addr` → `rd_data`, combinational),
//! `enable`, `requested` (the axes a STOP write names, as it commits); `clock` with
//! `cstop` (K bits, one cycle), `decel` (32 bits), `mode` (4 bits) and `home_arm` (K bits).

use super::cdc::{BitsSync, MaskCross};
use super::regfile::c9;
use crate::regs::ADDR_BITS;
use rust_hdl::prelude::*;

#[derive(LogicBlock)]
pub struct StopRegs<const K: usize> {
    pub bus_clock: Signal<In, Clock>,
    pub bus_reset: Signal<In, Bit>,
    pub wr: Signal<In, Bit>,
    pub wr_addr: Signal<In, Bits<ADDR_BITS>>,
    pub wr_data: Signal<In, Bits<16>>,
    pub rd_addr: Signal<In, Bits<ADDR_BITS>>,
    pub rd_data: Signal<Out, Bits<16>>,
    pub enable: Signal<In, Bit>,
    pub clock: Signal<In, Clock>,
    pub cstop: Signal<Out, Bits<K>>,
    pub decel: Signal<Out, Bits<32>>,
    /// The axes a STOP write names, in the cycle it commits (bus clock): the push guard
    /// marks their plans stale.
    pub requested: Signal<Out, Bits<K>>,
    pub mode: Signal<Out, Bits<4>>,
    pub home_arm: Signal<Out, Bits<K>>,
    // Bus clock.
    mode_r: DFF<Bits<4>>,
    home_r: DFF<Bits<K>>,
    home_sync: BitsSync<K>,
    stop_x: MaskCross<K>,
    lo: DFF<Bits<16>>,
    dec: DFF<Bits<32>>,
    refused: DFF<Bit>,
    req: Signal<Local, Bits<K>>,
    staged: Signal<Local, Bits<32>>,
    c_min: Constant<Bits<32>>,
    a_stop: Constant<Bits<ADDR_BITS>>,
    a_lo: Constant<Bits<ADDR_BITS>>,
    a_hi: Constant<Bits<ADDR_BITS>>,
    a_status: Constant<Bits<ADDR_BITS>>,
    a_mode: Constant<Bits<ADDR_BITS>>,
    a_home: Constant<Bits<ADDR_BITS>>,
    /// STOP_MODE's bits of the groups exported; STOP_HOME exists (the home group).
    c_mode_m: Constant<Bits<4>>,
    c_has_home: Constant<Bit>,
}

impl<const K: usize> StopRegs<K> {
    /// The registers for an export whose smallest accepted deceleration is `decel_min`.
    pub fn new(decel_min: u32) -> Self {
        assert!((1..=16).contains(&K), "StopRegs: K = {K} outside 1..=16");
        StopRegs {
            bus_clock: Default::default(),
            bus_reset: Default::default(),
            wr: Default::default(),
            wr_addr: Default::default(),
            wr_data: Default::default(),
            rd_addr: Default::default(),
            rd_data: Default::default(),
            enable: Default::default(),
            clock: Default::default(),
            cstop: Default::default(),
            decel: Default::default(),
            requested: Default::default(),
            mode: Default::default(),
            home_arm: Default::default(),
            mode_r: Default::default(),
            home_r: Default::default(),
            home_sync: Default::default(),
            stop_x: Default::default(),
            lo: Default::default(),
            dec: Default::default(),
            refused: Default::default(),
            req: Default::default(),
            staged: Default::default(),
            c_min: Constant::new((decel_min as u64).into()),
            a_stop: c9("STOP"),
            a_lo: c9("STOP_DECEL_LO"),
            a_hi: c9("STOP_DECEL_HI"),
            a_status: c9("STOP_STATUS"),
            a_mode: c9("STOP_MODE"),
            a_home: c9("STOP_HOME"),
            c_mode_m: Constant::new(0xF.into()),
            c_has_home: Constant::new(true),
        }
    }

    /// The registers of an export with the machine I/O groups `groups`
    /// (`regs::IO_GROUPS` bits): STOP_MODE's bits of the others are 0 and not written;
    /// without the home group STOP_HOME is not there and a write to it is refused
    /// (STOP_STATUS.REFUSED).
    pub fn with_groups(mut self, groups: u8) -> Self {
        use crate::regs::{IO_ALARM, IO_HOME, IO_LIMITS, IO_WATCHDOG};
        let m = [IO_LIMITS, IO_ALARM, IO_WATCHDOG, IO_HOME].iter().enumerate().map(|(i, g)| ((groups & g != 0) as u64) << i).sum::<u64>();
        self.c_mode_m = Constant::new(m.into());
        self.c_has_home = Constant::new(groups & IO_HOME != 0);
        self
    }
}

impl<const K: usize> Logic for StopRegs<K> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, bus_clock, lo, dec, refused, mode_r, home_r);
        // ---- bus clock ----
        self.req.next = 0.into();
        if self.wr.val() & (self.wr_addr.val() == self.a_stop.val()) {
            self.req.next = self.wr_data.val().get_bits::<K>(0);
        }
        self.requested.next = self.req.val();
        self.stop_x.bus_clock.next = self.bus_clock.val();
        self.stop_x.bus_reset.next = self.bus_reset.val();
        self.stop_x.req.next = self.req.val();
        self.stop_x.clock.next = self.clock.val();
        self.cstop.next = self.stop_x.out.val();
        self.staged.next = (bit_cast::<32, 16>(self.wr_data.val()) << 16) | bit_cast::<32, 16>(self.lo.q.val());
        if self.wr.val() & (self.wr_addr.val() == self.a_lo.val()) {
            self.lo.d.next = self.wr_data.val();
        }
        if self.wr.val() & (self.wr_addr.val() == self.a_hi.val()) {
            if self.enable.val() | (self.staged.val() < self.c_min.val()) {
                self.refused.d.next = true;
            } else {
                self.dec.d.next = self.staged.val();
            }
        }
        if self.wr.val() & (self.wr_addr.val() == self.a_mode.val()) {
            if self.enable.val() {
                self.refused.d.next = true;
            } else {
                self.mode_r.d.next = self.wr_data.val().get_bits::<4>(0) & self.c_mode_m.val();
            }
        }
        if self.wr.val() & (self.wr_addr.val() == self.a_home.val()) {
            if self.c_has_home.val() {
                self.home_r.d.next = self.wr_data.val().get_bits::<K>(0);
            } else {
                self.refused.d.next = true;
            }
        }
        if self.wr.val() & (self.wr_addr.val() == self.a_status.val()) & self.wr_data.val().get_bit(0) {
            self.refused.d.next = false;
        }
        self.rd_data.next = 0.into();
        if self.rd_addr.val() == self.a_lo.val() {
            self.rd_data.next = self.dec.q.val().get_bits::<16>(0);
        }
        if self.rd_addr.val() == self.a_hi.val() {
            self.rd_data.next = self.dec.q.val().get_bits::<16>(16);
        }
        if self.rd_addr.val() == self.a_mode.val() {
            self.rd_data.next = bit_cast::<16, 4>(self.mode_r.q.val());
        }
        if self.rd_addr.val() == self.a_home.val() {
            self.rd_data.next = bit_cast::<16, K>(self.home_r.q.val());
        }
        if self.rd_addr.val() == self.a_status.val() {
            self.rd_data.next = bit_cast::<16, 1>(self.refused.q.val().into());
        }
        if self.bus_reset.val() {
            self.lo.d.next = 0xFFFF.into();
            self.dec.d.next = 0xFFFF_FFFFu64.into();
            self.refused.d.next = false;
            self.mode_r.d.next = 0.into();
            self.home_r.d.next = 0.into();
        }
        // ---- clk ----
        self.home_sync.clock.next = self.clock.val();
        self.home_sync.sig_in.next = self.home_r.q.val();
        self.home_arm.next = self.home_sync.sig_out.val();
        self.mode.next = self.mode_r.q.val();
        self.decel.next = self.dec.q.val();
    }
}
