//! AXI4-Lite front end (`export --bus axil`): an AXI4-Lite slave, 32-bit data, in
//! `bus_clk` (the interconnect's clock), that makes each access on the EXMC slave's
//! pins through an [`ExmcMaster`], so the register file and its contract are the same
//! as on every other bus. Its protocol model is [`crate::verify::mmio::axil_expect`].
//!
//! **Addresses.** Byte addresses, 11 bits: register word w is at byte 4·w, in bits
//! 15..0 of the data word (bits 31..16 read 0 and are ignored on writes); address bits
//! 1..0 are ignored. No AxPROT (every access is treated alike).
//!
//! **Channels.** Every channel has its VALID/READY handshake, with back-pressure:
//! AWREADY, WREADY and ARREADY are high while their one-entry buffer is empty (and
//! low while the synchronised reset is high), so the
//! slave holds one write address, one write datum and one read address while an
//! access is in flight (one outstanding read and one outstanding write). BVALID and
//! RVALID stay high until BREADY and RREADY take them. A write waits for both its
//! address and its data; reads and writes take the EXMC side in turn when both wait.
//!
//! **Responses.** OKAY for a mapped address ([`crate::regs::mapped`]). SLVERR, and no
//! register access: a read or write of an unmapped address (a read returns 0); a
//! write with WSTRB[1:0] = 01 or 10 (half a register). A write with WSTRB[1:0] = 00 is
//! OKAY and writes nothing (AXI's empty write).
//!
//! **Latency** (tests/hdl_bus_fronts.rs): with READY and the buffers empty, BVALID
//! [`AXIL_WRITE_RESP`] cycles after the cycle both AWVALID and WVALID have been
//! taken, RVALID [`AXIL_READ_RESP`] cycles after ARVALID was taken; a refused access
//! answers 2 cycles after.

use super::cdc::BitSync;
use super::exmc_master::ExmcMaster;
use super::wb_front::map_bits;
use crate::regs::ADDR_BITS;
use rust_hdl::prelude::*;

/// Byte address bits: word address plus the two ignored bits.
pub const AXIL_ADDR_BITS: usize = ADDR_BITS + 2;
/// Cycles from the handshake (the later of AW and W; AR) to BVALID and RVALID.
pub use crate::latency::{AXIL_READ_RESP, AXIL_WRITE_RESP};

#[derive(LogicBlock)]
pub struct AxilFront {
    pub clock: Signal<In, Clock>,
    /// Active high, asynchronous (synchronised here).
    pub reset: Signal<In, Bit>,
    pub awvalid: Signal<In, Bit>,
    pub awready: Signal<Out, Bit>,
    pub awaddr: Signal<In, Bits<AXIL_ADDR_BITS>>,
    pub wvalid: Signal<In, Bit>,
    pub wready: Signal<Out, Bit>,
    pub wdata: Signal<In, Bits<32>>,
    pub wstrb: Signal<In, Bits<4>>,
    pub bvalid: Signal<Out, Bit>,
    pub bready: Signal<In, Bit>,
    pub bresp: Signal<Out, Bits<2>>,
    pub arvalid: Signal<In, Bit>,
    pub arready: Signal<Out, Bit>,
    pub araddr: Signal<In, Bits<AXIL_ADDR_BITS>>,
    pub rvalid: Signal<Out, Bit>,
    pub rready: Signal<In, Bit>,
    pub rdata: Signal<Out, Bits<32>>,
    pub rresp: Signal<Out, Bits<2>>,
    /// The EXMC pins of the register file's slave.
    pub ne: Signal<Out, Bit>,
    pub noe: Signal<Out, Bit>,
    pub nwe: Signal<Out, Bit>,
    pub x_addr: Signal<Out, Bits<ADDR_BITS>>,
    pub x_wdata: Signal<Out, Bits<16>>,
    pub x_rdata: Signal<In, Bits<16>>,
    rst: BitSync,
    master: ExmcMaster,
    map: Constant<Bits<512>>,
    aw_full: DFF<Bit>,
    aw_q: DFF<Bits<ADDR_BITS>>,
    w_full: DFF<Bit>,
    w_q: DFF<Bits<16>>,
    s_q: DFF<Bits<2>>,
    ar_full: DFF<Bit>,
    ar_q: DFF<Bits<ADDR_BITS>>,
    b_valid: DFF<Bit>,
    b_err: DFF<Bit>,
    r_valid: DFF<Bit>,
    r_err: DFF<Bit>,
    r_q: DFF<Bits<16>>,
    /// The access on the EXMC side: 0 none, 1 a write, 2 a read.
    on: DFF<Bits<2>>,
    /// The last access taken was a read (a write goes first when both wait).
    last_rd: DFF<Bit>,
    want_w: Signal<Local, Bit>,
    want_r: Signal<Local, Bit>,
    take_w: Signal<Local, Bit>,
    take_r: Signal<Local, Bit>,
}

impl AxilFront {
    /// `mapped[w]`: word address w is a register of this export.
    pub fn new(mapped: &[bool]) -> AxilFront {
        assert_eq!(mapped.len(), 1 << ADDR_BITS);
        AxilFront {
            clock: Default::default(),
            reset: Default::default(),
            awvalid: Default::default(),
            awready: Default::default(),
            awaddr: Default::default(),
            wvalid: Default::default(),
            wready: Default::default(),
            wdata: Default::default(),
            wstrb: Default::default(),
            bvalid: Default::default(),
            bready: Default::default(),
            bresp: Default::default(),
            arvalid: Default::default(),
            arready: Default::default(),
            araddr: Default::default(),
            rvalid: Default::default(),
            rready: Default::default(),
            rdata: Default::default(),
            rresp: Default::default(),
            ne: Default::default(),
            noe: Default::default(),
            nwe: Default::default(),
            x_addr: Default::default(),
            x_wdata: Default::default(),
            x_rdata: Default::default(),
            rst: Default::default(),
            master: Default::default(),
            map: Constant::new(map_bits(mapped)),
            aw_full: Default::default(),
            aw_q: Default::default(),
            w_full: Default::default(),
            w_q: Default::default(),
            s_q: Default::default(),
            ar_full: Default::default(),
            ar_q: Default::default(),
            b_valid: Default::default(),
            b_err: Default::default(),
            r_valid: Default::default(),
            r_err: Default::default(),
            r_q: Default::default(),
            on: Default::default(),
            last_rd: Default::default(),
            want_w: Default::default(),
            want_r: Default::default(),
            take_w: Default::default(),
            take_r: Default::default(),
        }
    }
}

impl Logic for AxilFront {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, aw_full, aw_q, w_full, w_q, s_q, ar_full, ar_q, b_valid, b_err, r_valid, r_err, r_q, on, last_rd);
        self.rst.clock.next = self.clock.val();
        self.rst.sig_in.next = self.reset.val();
        self.master.clock.next = self.clock.val();
        self.master.reset.next = self.rst.sig_out.val();
        self.ne.next = self.master.ne.val();
        self.noe.next = self.master.noe.val();
        self.nwe.next = self.master.nwe.val();
        self.x_addr.next = self.master.addr.val();
        self.x_wdata.next = self.master.wdata.val();
        self.master.rdata.next = self.x_rdata.val();
        // No handshake while the (synchronised) reset is high.
        self.awready.next = !self.aw_full.q.val() & !self.rst.sig_out.val();
        self.wready.next = !self.w_full.q.val() & !self.rst.sig_out.val();
        self.arready.next = !self.ar_full.q.val() & !self.rst.sig_out.val();
        self.bvalid.next = self.b_valid.q.val();
        self.bresp.next = bit_cast::<2, 1>(self.b_err.q.val().into()) << 1;
        self.rvalid.next = self.r_valid.q.val();
        self.rresp.next = bit_cast::<2, 1>(self.r_err.q.val().into()) << 1;
        self.rdata.next = bit_cast::<32, 16>(self.r_q.q.val());

        // The buffers fill on their handshakes.
        if self.awvalid.val() & !self.aw_full.q.val() {
            self.aw_full.d.next = true;
            self.aw_q.d.next = self.awaddr.val().get_bits::<ADDR_BITS>(2);
        }
        if self.wvalid.val() & !self.w_full.q.val() {
            self.w_full.d.next = true;
            self.w_q.d.next = self.wdata.val().get_bits::<16>(0);
            self.s_q.d.next = self.wstrb.val().get_bits::<2>(0);
        }
        if self.arvalid.val() & !self.ar_full.q.val() {
            self.ar_full.d.next = true;
            self.ar_q.d.next = self.araddr.val().get_bits::<ADDR_BITS>(2);
        }
        if self.bready.val() {
            self.b_valid.d.next = false;
        }
        if self.rready.val() {
            self.r_valid.d.next = false;
        }

        // One access at a time on the EXMC side; a write first unless the last was one.
        self.want_w.next = self.aw_full.q.val() & self.w_full.q.val() & !self.b_valid.q.val();
        self.want_r.next = self.ar_full.q.val() & !self.r_valid.q.val();
        self.take_w.next = false;
        self.take_r.next = false;
        if (self.on.q.val() == 0) & !self.master.busy.val() {
            if self.want_w.val() & (self.last_rd.q.val() | !self.want_r.val()) {
                self.take_w.next = true;
            } else if self.want_r.val() {
                self.take_r.next = true;
            }
        }
        self.master.req_addr.next = self.aw_q.q.val();
        self.master.req_wdata.next = self.w_q.q.val();
        self.master.req_wr.next = false;
        self.master.req_rd.next = false;
        if self.take_w.val() {
            self.aw_full.d.next = false;
            self.w_full.d.next = false;
            self.last_rd.d.next = false;
            if self.map.val().get_bit(self.aw_q.q.val().index()) & (self.s_q.q.val() == 3) {
                self.master.req_wr.next = true;
                self.on.d.next = 1.into();
            } else {
                self.b_valid.d.next = true;
                self.b_err.d.next = !self.map.val().get_bit(self.aw_q.q.val().index()) | (self.s_q.q.val() != 0);
            }
        }
        if self.take_r.val() {
            self.ar_full.d.next = false;
            self.last_rd.d.next = true;
            self.master.req_addr.next = self.ar_q.q.val();
            if self.map.val().get_bit(self.ar_q.q.val().index()) {
                self.master.req_rd.next = true;
                self.on.d.next = 2.into();
            } else {
                self.r_valid.d.next = true;
                self.r_err.d.next = true;
                self.r_q.d.next = 0.into();
            }
        }
        if self.master.done.val() {
            if self.on.q.val() == 1 {
                self.b_valid.d.next = true;
                self.b_err.d.next = false;
            }
            if self.on.q.val() == 2 {
                self.r_valid.d.next = true;
                self.r_err.d.next = false;
                self.r_q.d.next = self.master.rdata_q.val();
            }
            self.on.d.next = 0.into();
        }
        if self.rst.sig_out.val() {
            self.aw_full.d.next = false;
            self.w_full.d.next = false;
            self.ar_full.d.next = false;
            self.b_valid.d.next = false;
            self.r_valid.d.next = false;
            self.on.d.next = 0.into();
        }
    }
}
