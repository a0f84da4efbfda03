//! The identity registers (ID_MAGIC … ID_OPTIONS): a block of the register file
//! ([`super::regfile::RegFile`]), split off along the register map's own seam.
//! Read-only constants of the export, every value from the register table
//! (`Register::reset_value` with the export's [`CoreParams`]); writes to them are
//! ignored, so the block has no write port and no state.
//!
//! Latency: none (`rd_addr` → `rd_data`, combinational; 0 outside its own addresses).
//! Ports: `rd_addr` → `rd_data`. Checked three ways in tests/hdl_regfile.rs
//! (`identity_registers_read_the_register_table_three_ways`: every one of the 512
//! word addresses against the table, rust-hdl, Verilator and Icarus).

use super::regfile::c9;
use crate::regs::{self, CoreParams, ADDR_BITS};
use rust_hdl::prelude::*;

/// The registers this block answers, in address order.
pub const ID_REGISTERS: [&str; 12] = ["ID_MAGIC", "ID_VERSION", "ID_AXES", "ID_QUEUE_DEPTH", "ID_FIFO_DEPTH", "ID_T_CALC", "ID_CLOCK_HZ_LO", "ID_CLOCK_HZ_HI", "ID_MIN_PERIOD", "ID_MAX_RATE_LO", "ID_MAX_RATE_HI", "ID_OPTIONS"];

#[derive(LogicBlock)]
pub struct IdRegs {
    pub rd_addr: Signal<In, Bits<ADDR_BITS>>,
    pub rd_data: Signal<Out, Bits<16>>,
    v_magic: Constant<Bits<16>>,
    a_magic: Constant<Bits<ADDR_BITS>>,
    v_version: Constant<Bits<16>>,
    a_version: Constant<Bits<ADDR_BITS>>,
    v_axes: Constant<Bits<16>>,
    a_axes: Constant<Bits<ADDR_BITS>>,
    v_qdepth: Constant<Bits<16>>,
    a_qdepth: Constant<Bits<ADDR_BITS>>,
    v_fdepth: Constant<Bits<16>>,
    a_fdepth: Constant<Bits<ADDR_BITS>>,
    v_tcalc: Constant<Bits<16>>,
    a_tcalc: Constant<Bits<ADDR_BITS>>,
    v_clk_lo: Constant<Bits<16>>,
    a_clk_lo: Constant<Bits<ADDR_BITS>>,
    v_clk_hi: Constant<Bits<16>>,
    a_clk_hi: Constant<Bits<ADDR_BITS>>,
    v_minp: Constant<Bits<16>>,
    a_minp: Constant<Bits<ADDR_BITS>>,
    v_rmax_lo: Constant<Bits<16>>,
    a_rmax_lo: Constant<Bits<ADDR_BITS>>,
    v_rmax_hi: Constant<Bits<16>>,
    a_rmax_hi: Constant<Bits<ADDR_BITS>>,
    v_opts: Constant<Bits<16>>,
    a_opts: Constant<Bits<ADDR_BITS>>,
}

impl IdRegs {
    pub fn new(p: &CoreParams) -> Self {
        let v = |name: &str| Constant::new((regs::register(name).reset_value(p) as u64).into());
        IdRegs {
            rd_addr: Default::default(),
            rd_data: Default::default(),
            v_magic: v("ID_MAGIC"),
            a_magic: c9("ID_MAGIC"),
            v_version: v("ID_VERSION"),
            a_version: c9("ID_VERSION"),
            v_axes: v("ID_AXES"),
            a_axes: c9("ID_AXES"),
            v_qdepth: v("ID_QUEUE_DEPTH"),
            a_qdepth: c9("ID_QUEUE_DEPTH"),
            v_fdepth: v("ID_FIFO_DEPTH"),
            a_fdepth: c9("ID_FIFO_DEPTH"),
            v_tcalc: v("ID_T_CALC"),
            a_tcalc: c9("ID_T_CALC"),
            v_clk_lo: v("ID_CLOCK_HZ_LO"),
            a_clk_lo: c9("ID_CLOCK_HZ_LO"),
            v_clk_hi: v("ID_CLOCK_HZ_HI"),
            a_clk_hi: c9("ID_CLOCK_HZ_HI"),
            v_minp: v("ID_MIN_PERIOD"),
            a_minp: c9("ID_MIN_PERIOD"),
            v_rmax_lo: v("ID_MAX_RATE_LO"),
            a_rmax_lo: c9("ID_MAX_RATE_LO"),
            v_rmax_hi: v("ID_MAX_RATE_HI"),
            a_rmax_hi: c9("ID_MAX_RATE_HI"),
            v_opts: v("ID_OPTIONS"),
            a_opts: c9("ID_OPTIONS"),
        }
    }
}

impl Logic for IdRegs {
    #[hdl_gen]
    fn update(&mut self) {
        // The addresses are distinct: an OR of the decoded values (see the register
        // file's reads).
        self.rd_data.next = 0.into();
        if self.rd_addr.val() == self.a_magic.val() {
            self.rd_data.next = self.rd_data.val() | self.v_magic.val();
        }
        if self.rd_addr.val() == self.a_version.val() {
            self.rd_data.next = self.rd_data.val() | self.v_version.val();
        }
        if self.rd_addr.val() == self.a_axes.val() {
            self.rd_data.next = self.rd_data.val() | self.v_axes.val();
        }
        if self.rd_addr.val() == self.a_qdepth.val() {
            self.rd_data.next = self.rd_data.val() | self.v_qdepth.val();
        }
        if self.rd_addr.val() == self.a_fdepth.val() {
            self.rd_data.next = self.rd_data.val() | self.v_fdepth.val();
        }
        if self.rd_addr.val() == self.a_tcalc.val() {
            self.rd_data.next = self.rd_data.val() | self.v_tcalc.val();
        }
        if self.rd_addr.val() == self.a_clk_lo.val() {
            self.rd_data.next = self.rd_data.val() | self.v_clk_lo.val();
        }
        if self.rd_addr.val() == self.a_clk_hi.val() {
            self.rd_data.next = self.rd_data.val() | self.v_clk_hi.val();
        }
        if self.rd_addr.val() == self.a_minp.val() {
            self.rd_data.next = self.rd_data.val() | self.v_minp.val();
        }
        if self.rd_addr.val() == self.a_rmax_lo.val() {
            self.rd_data.next = self.rd_data.val() | self.v_rmax_lo.val();
        }
        if self.rd_addr.val() == self.a_rmax_hi.val() {
            self.rd_data.next = self.rd_data.val() | self.v_rmax_hi.val();
        }
        if self.rd_addr.val() == self.a_opts.val() {
            self.rd_data.next = self.rd_data.val() | self.v_opts.val();
        }
    }
}
