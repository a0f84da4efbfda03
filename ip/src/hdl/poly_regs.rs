//! The S-curve option's registers (`regs::Feature::Scurve`), in the bus clock: the
//! staging of a polynomial segment's two extra fields and the arm that makes the next
//! push polynomial. A block beside the register file like
//! [`super::stop_regs::StopRegs`]: its reads return 0 outside its own addresses.
//!
//! * **POLY_V1_LO/HI** (v1, Q0.32) and **POLY_A_0..3** (A' = A·2^32, 64-bit two's
//!   complement): plain staging, read back as written, 0 after reset; `extra` =
//!   {A', v1} (v1 in 31..0), what a polynomial push takes with it.
//! * **POLY_ARM** (bit 0): written at any time; `arm` is that bit. `pushed` (the register
//!   file offers a polynomial push to its check) clears it, so each arming makes one
//!   push polynomial; `enable` low (CTRL.ENABLE = 0) clears it too.
//!
//! Latency: a write shows on `extra` and `arm` one bus clock after it commits (the
//! register file reads them when a later STEPS_HI write commits). Ports: the bus
//! (`wr`, `wr_addr`, `wr_data`, `rd_addr` → `rd_data`, combinational), `enable`,
//! `pushed` → `arm`, `extra`. Checked three ways in tests/hdl_regfile.rs
//! (`poly_registers_read_back_and_the_arm_is_taken_by_one_push_three_ways`: a model
//! of this contract, rust-hdl, Verilator and Icarus on random traffic) and through the
//! bus on the exported core in tests/system.rs (polynomial pushes reaching the core
//! with their fields).

use super::regfile::c9;
use crate::regs::ADDR_BITS;
use rust_hdl::prelude::*;

/// {A' (95..32), v1 (31..0)}.
pub const POLY_FIELDS_BITS: usize = 96;

#[derive(LogicBlock)]
pub struct PolyRegs {
    pub bus_clock: Signal<In, Clock>,
    pub bus_reset: Signal<In, Bit>,
    pub wr: Signal<In, Bit>,
    pub wr_addr: Signal<In, Bits<ADDR_BITS>>,
    pub wr_data: Signal<In, Bits<16>>,
    pub rd_addr: Signal<In, Bits<ADDR_BITS>>,
    pub rd_data: Signal<Out, Bits<16>>,
    pub enable: Signal<In, Bit>,
    pub pushed: Signal<In, Bit>,
    pub arm: Signal<Out, Bit>,
    pub extra: Signal<Out, Bits<POLY_FIELDS_BITS>>,
    v1_lo: DFF<Bits<16>>,
    v1_hi: DFF<Bits<16>>,
    a0: DFF<Bits<16>>,
    a1: DFF<Bits<16>>,
    a2: DFF<Bits<16>>,
    a3: DFF<Bits<16>>,
    armed: DFF<Bit>,
    a_v1_lo: Constant<Bits<ADDR_BITS>>,
    a_v1_hi: Constant<Bits<ADDR_BITS>>,
    a_a0: Constant<Bits<ADDR_BITS>>,
    a_a1: Constant<Bits<ADDR_BITS>>,
    a_a2: Constant<Bits<ADDR_BITS>>,
    a_a3: Constant<Bits<ADDR_BITS>>,
    a_arm: Constant<Bits<ADDR_BITS>>,
}

impl Default for PolyRegs {
    fn default() -> Self {
        PolyRegs {
            bus_clock: Default::default(),
            bus_reset: Default::default(),
            wr: Default::default(),
            wr_addr: Default::default(),
            wr_data: Default::default(),
            rd_addr: Default::default(),
            rd_data: Default::default(),
            enable: Default::default(),
            pushed: Default::default(),
            arm: Default::default(),
            extra: Default::default(),
            v1_lo: Default::default(),
            v1_hi: Default::default(),
            a0: Default::default(),
            a1: Default::default(),
            a2: Default::default(),
            a3: Default::default(),
            armed: Default::default(),
            a_v1_lo: c9("POLY_V1_LO"),
            a_v1_hi: c9("POLY_V1_HI"),
            a_a0: c9("POLY_A_0"),
            a_a1: c9("POLY_A_1"),
            a_a2: c9("POLY_A_2"),
            a_a3: c9("POLY_A_3"),
            a_arm: c9("POLY_ARM"),
        }
    }
}

impl Logic for PolyRegs {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, bus_clock, v1_lo, v1_hi, a0, a1, a2, a3, armed);
        if self.wr.val() {
            if self.wr_addr.val() == self.a_v1_lo.val() {
                self.v1_lo.d.next = self.wr_data.val();
            }
            if self.wr_addr.val() == self.a_v1_hi.val() {
                self.v1_hi.d.next = self.wr_data.val();
            }
            if self.wr_addr.val() == self.a_a0.val() {
                self.a0.d.next = self.wr_data.val();
            }
            if self.wr_addr.val() == self.a_a1.val() {
                self.a1.d.next = self.wr_data.val();
            }
            if self.wr_addr.val() == self.a_a2.val() {
                self.a2.d.next = self.wr_data.val();
            }
            if self.wr_addr.val() == self.a_a3.val() {
                self.a3.d.next = self.wr_data.val();
            }
            if self.wr_addr.val() == self.a_arm.val() {
                self.armed.d.next = self.wr_data.val().get_bit(0);
            }
        }
        if self.pushed.val() | !self.enable.val() {
            self.armed.d.next = false;
        }
        if self.bus_reset.val() {
            self.v1_lo.d.next = 0.into();
            self.v1_hi.d.next = 0.into();
            self.a0.d.next = 0.into();
            self.a1.d.next = 0.into();
            self.a2.d.next = 0.into();
            self.a3.d.next = 0.into();
            self.armed.d.next = false;
        }
        self.arm.next = self.armed.q.val();
        self.extra.next = bit_cast::<POLY_FIELDS_BITS, 16>(self.v1_lo.q.val())
            | (bit_cast::<POLY_FIELDS_BITS, 16>(self.v1_hi.q.val()) << 16)
            | (bit_cast::<POLY_FIELDS_BITS, 16>(self.a0.q.val()) << 32)
            | (bit_cast::<POLY_FIELDS_BITS, 16>(self.a1.q.val()) << 48)
            | (bit_cast::<POLY_FIELDS_BITS, 16>(self.a2.q.val()) << 64)
            | (bit_cast::<POLY_FIELDS_BITS, 16>(self.a3.q.val()) << 80);
        self.rd_data.next = 0.into();
        if self.rd_addr.val() == self.a_v1_lo.val() {
            self.rd_data.next = self.v1_lo.q.val();
        }
        if self.rd_addr.val() == self.a_v1_hi.val() {
            self.rd_data.next = self.v1_hi.q.val();
        }
        if self.rd_addr.val() == self.a_a0.val() {
            self.rd_data.next = self.a0.q.val();
        }
        if self.rd_addr.val() == self.a_a1.val() {
            self.rd_data.next = self.a1.q.val();
        }
        if self.rd_addr.val() == self.a_a2.val() {
            self.rd_data.next = self.a2.q.val();
        }
        if self.rd_addr.val() == self.a_a3.val() {
            self.rd_data.next = self.a3.q.val();
        }
        if (self.rd_addr.val() == self.a_arm.val()) & self.armed.q.val() {
            self.rd_data.next = 1.into();
        }
    }
}
