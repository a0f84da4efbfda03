//! The interrupt registers, in the bus clock: a block of the register file
//! ([`super::regfile::RegFile`]), split off along the register map's own seam. Its
//! reads return 0 outside its own addresses.
//!
//! * **IRQ_DONE, IRQ_QLOW, IRQ_ERROR** (one bit per axis): sticky flags, set by the
//!   register file's events (`ev_done`, `ev_qlow`, `ev_err`, one-hot per axis) and
//!   cleared by writing 1 (W1C). An event in the cycle of a write that clears its bit
//!   wins: the flag stays set. While `enable` (CTRL.ENABLE) is 0 the flags clear and
//!   take no events.
//! * **IRQ_MASK_DONE, IRQ_MASK_QLOW, IRQ_MASK_ERROR**: plain read/write, 0 after reset.
//! * **QLOW_LEVEL** (5 bits, 1 after reset): the threshold of the QLOW event, given to
//!   the register file on `qlow_level`.
//! * `irq` = OR of every flag under its mask, registered: high one bus clock after a
//!   flag and its mask bit are both set, low one bus clock after either clears.
//!
//! Latency: a write or an event shows in the registers (`rd_data`, `qlow_level`) one
//! bus clock after it, on `irq` two. Ports: the bus (`wr`, `wr_addr`, `wr_data`,
//! `rd_addr` → `rd_data`, combinational), `enable`, the events → `irq`, `qlow_level`.
//! Checked three ways in tests/hdl_regfile.rs
//! (`irq_registers_follow_the_register_table_three_ways`: a model built from the
//! register table's access types and reset values, rust-hdl, Verilator and Icarus on
//! random traffic with events).

use super::regfile::c9;
use crate::regs::ADDR_BITS;
use rust_hdl::prelude::*;

#[derive(LogicBlock)]
pub struct IrqRegs {
    pub clock: Signal<In, Clock>,
    pub reset: Signal<In, Bit>,
    /// CTRL.ENABLE: while 0 the flags clear.
    pub enable: Signal<In, Bit>,
    pub wr: Signal<In, Bit>,
    pub wr_addr: Signal<In, Bits<ADDR_BITS>>,
    pub wr_data: Signal<In, Bits<16>>,
    pub ev_done: Signal<In, Bits<16>>,
    pub ev_qlow: Signal<In, Bits<16>>,
    pub ev_err: Signal<In, Bits<16>>,
    pub rd_addr: Signal<In, Bits<ADDR_BITS>>,
    pub rd_data: Signal<Out, Bits<16>>,
    pub irq: Signal<Out, Bit>,
    pub qlow_level: Signal<Out, Bits<5>>,
    irq_done: DFF<Bits<16>>,
    irq_qlow: DFF<Bits<16>>,
    irq_err: DFF<Bits<16>>,
    mask_done: DFF<Bits<16>>,
    mask_qlow: DFF<Bits<16>>,
    mask_err: DFF<Bits<16>>,
    qlow: DFF<Bits<5>>,
    irq_q: DFF<Bit>,
    a_irq_done: Constant<Bits<ADDR_BITS>>,
    a_irq_qlow: Constant<Bits<ADDR_BITS>>,
    a_irq_err: Constant<Bits<ADDR_BITS>>,
    a_mask_done: Constant<Bits<ADDR_BITS>>,
    a_mask_qlow: Constant<Bits<ADDR_BITS>>,
    a_mask_err: Constant<Bits<ADDR_BITS>>,
    a_qlow: Constant<Bits<ADDR_BITS>>,
}

impl Default for IrqRegs {
    fn default() -> Self {
        IrqRegs {
            a_irq_done: c9("IRQ_DONE"),
            a_irq_qlow: c9("IRQ_QLOW"),
            a_irq_err: c9("IRQ_ERROR"),
            a_mask_done: c9("IRQ_MASK_DONE"),
            a_mask_qlow: c9("IRQ_MASK_QLOW"),
            a_mask_err: c9("IRQ_MASK_ERROR"),
            a_qlow: c9("QLOW_LEVEL"),
            clock: Default::default(),
            reset: Default::default(),
            enable: Default::default(),
            wr: Default::default(),
            wr_addr: Default::default(),
            wr_data: Default::default(),
            ev_done: Default::default(),
            ev_qlow: Default::default(),
            ev_err: Default::default(),
            rd_addr: Default::default(),
            rd_data: Default::default(),
            irq: Default::default(),
            qlow_level: Default::default(),
            irq_done: Default::default(),
            irq_qlow: Default::default(),
            irq_err: Default::default(),
            mask_done: Default::default(),
            mask_qlow: Default::default(),
            mask_err: Default::default(),
            qlow: Default::default(),
            irq_q: Default::default(),
        }
    }
}

impl Logic for IrqRegs {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, irq_done, irq_qlow, irq_err, mask_done, mask_qlow, mask_err, qlow, irq_q);
        self.irq_done.d.next = self.irq_done.q.val() | self.ev_done.val();
        self.irq_qlow.d.next = self.irq_qlow.q.val() | self.ev_qlow.val();
        self.irq_err.d.next = self.irq_err.q.val() | self.ev_err.val();
        if self.wr.val() {
            if self.wr_addr.val() == self.a_irq_done.val() {
                self.irq_done.d.next = (self.irq_done.q.val() & !self.wr_data.val()) | self.ev_done.val();
            }
            if self.wr_addr.val() == self.a_irq_qlow.val() {
                self.irq_qlow.d.next = (self.irq_qlow.q.val() & !self.wr_data.val()) | self.ev_qlow.val();
            }
            if self.wr_addr.val() == self.a_irq_err.val() {
                self.irq_err.d.next = (self.irq_err.q.val() & !self.wr_data.val()) | self.ev_err.val();
            }
            if self.wr_addr.val() == self.a_mask_done.val() {
                self.mask_done.d.next = self.wr_data.val();
            }
            if self.wr_addr.val() == self.a_mask_qlow.val() {
                self.mask_qlow.d.next = self.wr_data.val();
            }
            if self.wr_addr.val() == self.a_mask_err.val() {
                self.mask_err.d.next = self.wr_data.val();
            }
            if self.wr_addr.val() == self.a_qlow.val() {
                self.qlow.d.next = self.wr_data.val().get_bits::<5>(0);
            }
        }
        self.irq_q.d.next = ((self.irq_done.q.val() & self.mask_done.q.val())
            | (self.irq_qlow.q.val() & self.mask_qlow.q.val())
            | (self.irq_err.q.val() & self.mask_err.q.val()))
            .any();
        if !self.enable.val() {
            self.irq_done.d.next = 0.into();
            self.irq_qlow.d.next = 0.into();
            self.irq_err.d.next = 0.into();
        }
        if self.reset.val() {
            self.irq_done.d.next = 0.into();
            self.irq_qlow.d.next = 0.into();
            self.irq_err.d.next = 0.into();
            self.mask_done.d.next = 0.into();
            self.mask_qlow.d.next = 0.into();
            self.mask_err.d.next = 0.into();
            self.qlow.d.next = 1.into();
            self.irq_q.d.next = false;
        }
        self.irq.next = self.irq_q.q.val();
        self.qlow_level.next = self.qlow.q.val();
        // The addresses are distinct: an OR of the decoded values (see the register
        // file's reads).
        self.rd_data.next = 0.into();
        if self.rd_addr.val() == self.a_irq_done.val() {
            self.rd_data.next = self.rd_data.val() | self.irq_done.q.val();
        }
        if self.rd_addr.val() == self.a_irq_qlow.val() {
            self.rd_data.next = self.rd_data.val() | self.irq_qlow.q.val();
        }
        if self.rd_addr.val() == self.a_irq_err.val() {
            self.rd_data.next = self.rd_data.val() | self.irq_err.q.val();
        }
        if self.rd_addr.val() == self.a_mask_done.val() {
            self.rd_data.next = self.rd_data.val() | self.mask_done.q.val();
        }
        if self.rd_addr.val() == self.a_mask_qlow.val() {
            self.rd_data.next = self.rd_data.val() | self.mask_qlow.q.val();
        }
        if self.rd_addr.val() == self.a_mask_err.val() {
            self.rd_data.next = self.rd_data.val() | self.mask_err.q.val();
        }
        if self.rd_addr.val() == self.a_qlow.val() {
            self.rd_data.next = self.rd_data.val() | bit_cast::<16, 5>(self.qlow.q.val());
        }
    }
}
