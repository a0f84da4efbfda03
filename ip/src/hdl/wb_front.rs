//! Wishbone front end (`export --bus wb`): a Wishbone B4 **classic** slave, 32-bit
//! data port, in `bus_clk` (the SoC's clock), that makes each access on the EXMC
//! slave's pins through an [`ExmcMaster`], so the register file and its contract are
//! the same as on every other bus. Its protocol model is [`crate::verify::mmio::wb_expect`].
//!
//! **Ports.** `wb_adr` is the register's word address (9 bits: the SoC decodes its
//! region and passes the low bits of its word address); each 16-bit register sits in
//! bits 15..0 of its 32-bit word and bits 31..16 read 0. `wb_sel` bits 1..0 must both
//! be set for a write; bits 3..2 are ignored.
//!
//! **Cycle.** An access starts in a cycle with CYC and STB high (and no ACK or ERR in
//! that cycle); ACK (with `wb_dat_r` for a read) is high for one cycle when it is done;
//! the master keeps ADR, WE, SEL and DAT_W steady until then, as classic cycles do. A
//! master that drops CYC (or STB) before ACK does not get it, not even in its next
//! cycle: the access still completes (it cannot be taken back) and the next one waits
//! for it. Nothing is taken while the (synchronised) reset is high. ACK and ERR are gated by CYC
//! and STB (combinationally), so neither is ever high outside a cycle.
//!
//! **Refused with ERR** (one cycle, no register access): an address this export does
//! not map ([`crate::regs::mapped`]); a write with `wb_sel[1:0]` not both set.
//!
//! **Latency** (tests/hdl_bus_fronts.rs): ACK of a write [`WB_WRITE_ACK`] cycles after
//! the cycle STB rose, of a read [`WB_READ_ACK`]; ERR 1 cycle after. Back-to-back
//! accesses: one every `WB_*_ACK + 1` cycles at most (the EXMC side rests between).

use super::cdc::BitSync;
use super::exmc_master::ExmcMaster;
use crate::regs::ADDR_BITS;
use rust_hdl::prelude::*;

/// Cycles from the STB cycle to ACK, a write and a read.
pub use crate::latency::{WB_READ_ACK, WB_WRITE_ACK};

#[derive(LogicBlock)]
pub struct WbFront {
    pub clock: Signal<In, Clock>,
    /// Active high, asynchronous (synchronised here).
    pub reset: Signal<In, Bit>,
    pub wb_cyc: Signal<In, Bit>,
    pub wb_stb: Signal<In, Bit>,
    pub wb_we: Signal<In, Bit>,
    pub wb_adr: Signal<In, Bits<ADDR_BITS>>,
    pub wb_sel: Signal<In, Bits<4>>,
    pub wb_dat_w: Signal<In, Bits<32>>,
    pub wb_dat_r: Signal<Out, Bits<32>>,
    pub wb_ack: Signal<Out, Bit>,
    pub wb_err: Signal<Out, Bit>,
    /// The EXMC pins of the register file's slave.
    pub ne: Signal<Out, Bit>,
    pub noe: Signal<Out, Bit>,
    pub nwe: Signal<Out, Bit>,
    pub addr: Signal<Out, Bits<ADDR_BITS>>,
    pub wdata: Signal<Out, Bits<16>>,
    pub rdata: Signal<In, Bits<16>>,
    rst: BitSync,
    master: ExmcMaster,
    /// The mapped addresses, bit w for word address w.
    map: Constant<Bits<512>>,
    /// An access is on the EXMC side (its ACK still to come, or dropped).
    issued: DFF<Bit>,
    /// The master dropped CYC or STB while the access was issued: its end gets no ACK.
    orphan: DFF<Bit>,
    ack: DFF<Bit>,
    err: DFF<Bit>,
    dat: DFF<Bits<16>>,
    pending: Signal<Local, Bit>,
    bad: Signal<Local, Bit>,
}

impl WbFront {
    /// `mapped[w]`: word address w is a register of this export.
    pub fn new(mapped: &[bool]) -> WbFront {
        assert_eq!(mapped.len(), 1 << ADDR_BITS);
        WbFront {
            clock: Default::default(),
            reset: Default::default(),
            wb_cyc: Default::default(),
            wb_stb: Default::default(),
            wb_we: Default::default(),
            wb_adr: Default::default(),
            wb_sel: Default::default(),
            wb_dat_w: Default::default(),
            wb_dat_r: Default::default(),
            wb_ack: Default::default(),
            wb_err: Default::default(),
            ne: Default::default(),
            noe: Default::default(),
            nwe: Default::default(),
            addr: Default::default(),
            wdata: Default::default(),
            rdata: Default::default(),
            rst: Default::default(),
            master: Default::default(),
            map: Constant::new(map_bits(mapped)),
            issued: Default::default(),
            orphan: Default::default(),
            ack: Default::default(),
            err: Default::default(),
            dat: Default::default(),
            pending: Default::default(),
            bad: Default::default(),
        }
    }
}

/// The mapped-address mask as a 512-bit constant.
pub fn map_bits(mapped: &[bool]) -> Bits<512> {
    let mut b = Bits::<512>::default();
    for (i, &m) in mapped.iter().enumerate() {
        b = b.replace_bit(i, m);
    }
    b
}

impl Logic for WbFront {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, issued, orphan, ack, err, dat);
        self.rst.clock.next = self.clock.val();
        self.rst.sig_in.next = self.reset.val();
        self.master.clock.next = self.clock.val();
        self.master.reset.next = self.rst.sig_out.val();
        self.ne.next = self.master.ne.val();
        self.noe.next = self.master.noe.val();
        self.nwe.next = self.master.nwe.val();
        self.addr.next = self.master.addr.val();
        self.wdata.next = self.master.wdata.val();
        self.master.rdata.next = self.rdata.val();
        self.wb_ack.next = self.ack.q.val() & self.wb_cyc.val() & self.wb_stb.val();
        self.wb_err.next = self.err.q.val() & self.wb_cyc.val() & self.wb_stb.val();
        self.wb_dat_r.next = bit_cast::<32, 16>(self.dat.q.val());

        self.pending.next = self.wb_cyc.val()
            & self.wb_stb.val()
            & !self.issued.q.val()
            & !self.ack.q.val()
            & !self.err.q.val()
            & !self.rst.sig_out.val();
        self.bad.next = !self.map.val().get_bit(self.wb_adr.val().index())
            | (self.wb_we.val() & (self.wb_sel.val().get_bits::<2>(0) != 3));
        self.master.req_addr.next = self.wb_adr.val();
        self.master.req_wdata.next = self.wb_dat_w.val().get_bits::<16>(0);
        self.master.req_wr.next = false;
        self.master.req_rd.next = false;
        self.ack.d.next = false;
        self.err.d.next = false;
        if self.pending.val() {
            if self.bad.val() {
                self.err.d.next = true;
            } else if !self.master.busy.val() {
                self.master.req_wr.next = self.wb_we.val();
                self.master.req_rd.next = !self.wb_we.val();
                self.issued.d.next = true;
            }
        }
        if self.issued.q.val() & !(self.wb_cyc.val() & self.wb_stb.val()) {
            self.orphan.d.next = true;
        }
        if self.issued.q.val() & self.master.done.val() {
            self.issued.d.next = false;
            self.orphan.d.next = false;
            self.ack.d.next = self.wb_cyc.val() & self.wb_stb.val() & !self.orphan.q.val();
            self.dat.d.next = self.master.rdata_q.val();
        }
        if self.rst.sig_out.val() {
            self.issued.d.next = false;
            self.orphan.d.next = false;
            self.ack.d.next = false;
            self.err.d.next = false;
        }
    }
}
