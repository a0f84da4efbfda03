//! EXMC master: one register access at a time on the EXMC slave's pins
//! ([`super::exmc::ExmcSlave`]) in the same bus clock, with the documented minimum
//! timing of an MCU whose clock is the bus clock. Every front end that is not EXMC
//! (SPI, Wishbone, AXI4-Lite) makes its accesses through it, so the register file,
//! its push check and its timing contract stay the one verified piece behind every
//! bus.
//!
//! **Ports.** `req_wr` or `req_rd` (one cycle, with `req_addr` and, for a write,
//! `req_wdata`) starts an access when `busy` is low; a request while `busy` is high is
//! ignored (the front end decides what that means). `done` is high for one cycle, the
//! first after the strobes rise; `rdata_q` then holds a read's data (until the next
//! read). `ne`, `noe`, `nwe`, `addr`, `wdata` go to the slave, `rdata` comes from it.
//!
//! **Latency.** A write holds NE and NWE low [`WRITE_LOW`] cycles; a read holds NE
//! and NOE low [`READ_LOW`] cycles and takes `rdata` at the last; the strobes then stay
//! high [`GAP`] cycles, `busy` with them. From the request: a write is `done` after
//! `WRITE_LOW + 1` cycles, a read after `READ_LOW + 1`, and the next request is taken
//! `GAP` cycles after the strobes rise (tests/hdl_bus_fronts.rs).

use rust_hdl::prelude::*;

use crate::regs::ADDR_BITS;

/// Bus clocks NE and NWE stay low for a write, NE and NOE for a read (`rdata` is
/// taken at the last), and the strobes stay high after an access.
pub use crate::latency::{EXMC_MASTER_GAP as GAP, EXMC_MASTER_READ_LOW as READ_LOW, EXMC_MASTER_WRITE_LOW as WRITE_LOW};
// The counters hold these minus one as literals (rust-hdl writes a constant's name
// into the Verilog).
const _: () = assert!(WRITE_LOW == 3 && READ_LOW == 5 && GAP == 2);

#[derive(LogicBlock, Default)]
pub struct ExmcMaster {
    pub clock: Signal<In, Clock>,
    /// Synchronous, active high.
    pub reset: Signal<In, Bit>,
    pub req_wr: Signal<In, Bit>,
    pub req_rd: Signal<In, Bit>,
    pub req_addr: Signal<In, Bits<ADDR_BITS>>,
    pub req_wdata: Signal<In, Bits<16>>,
    pub busy: Signal<Out, Bit>,
    pub done: Signal<Out, Bit>,
    pub rdata_q: Signal<Out, Bits<16>>,
    pub ne: Signal<Out, Bit>,
    pub noe: Signal<Out, Bit>,
    pub nwe: Signal<Out, Bit>,
    pub addr: Signal<Out, Bits<ADDR_BITS>>,
    pub wdata: Signal<Out, Bits<16>>,
    pub rdata: Signal<In, Bits<16>>,
    /// 0 idle, 1 write, 2 read, 3 gap; the strobes kept active high.
    e_state: DFF<Bits<2>>,
    e_cnt: DFF<Bits<3>>,
    ne_a: DFF<Bit>,
    noe_a: DFF<Bit>,
    nwe_a: DFF<Bit>,
    a_q: DFF<Bits<ADDR_BITS>>,
    w_q: DFF<Bits<16>>,
    r_q: DFF<Bits<16>>,
}

impl Logic for ExmcMaster {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, e_state, e_cnt, ne_a, noe_a, nwe_a, a_q, w_q, r_q);
        self.ne.next = !self.ne_a.q.val();
        self.noe.next = !self.noe_a.q.val();
        self.nwe.next = !self.nwe_a.q.val();
        self.addr.next = self.a_q.q.val();
        self.wdata.next = self.w_q.q.val();
        self.rdata_q.next = self.r_q.q.val();
        self.busy.next = self.e_state.q.val() != 0;
        self.done.next = (self.e_state.q.val() == 3) & (self.e_cnt.q.val() == 1);
        if self.e_state.q.val() == 0 {
            if self.req_wr.val() | self.req_rd.val() {
                self.a_q.d.next = self.req_addr.val();
                self.ne_a.d.next = true;
                if self.req_wr.val() {
                    self.w_q.d.next = self.req_wdata.val();
                    self.nwe_a.d.next = true;
                    self.e_state.d.next = 1.into();
                    self.e_cnt.d.next = 2.into();
                } else {
                    self.noe_a.d.next = true;
                    self.e_state.d.next = 2.into();
                    self.e_cnt.d.next = 4.into();
                }
            }
        } else {
            self.e_cnt.d.next = self.e_cnt.q.val() - 1;
            if self.e_cnt.q.val() == 0 {
                if self.e_state.q.val() == 3 {
                    self.e_state.d.next = 0.into();
                } else {
                    if self.e_state.q.val() == 2 {
                        self.r_q.d.next = self.rdata.val();
                    }
                    self.ne_a.d.next = false;
                    self.noe_a.d.next = false;
                    self.nwe_a.d.next = false;
                    self.e_state.d.next = 3.into();
                    self.e_cnt.d.next = 1.into();
                }
            }
        }
        if self.reset.val() {
            self.e_state.d.next = 0.into();
            self.ne_a.d.next = false;
            self.noe_a.d.next = false;
            self.nwe_a.d.next = false;
        }
    }
}
