//! The output timing registers, in the bus clock: a block of the register file
//! ([`super::regfile::RegFile`]), split off along the register map's own seam. Its
//! reads return 0 outside its own addresses.
//!
//! * **STEP_HIGH, STEP_LOW, DIR_SETUP, DIR_HOLD** (clk ticks, 1 after reset): written
//!   only while `locked` is 0 (CTRL.ENABLE and GSTATUS.ENABLED both 0) and never 0;
//!   otherwise the write is refused (`refuse` in its cycle, for GSTATUS.REFUSED) and
//!   the value kept.
//! * `high_min` = max(STEP_HIGH, DIR_HOLD) and `low_min` = max(STEP_LOW, DIR_SETUP),
//!   the minima the core applies ([`crate::model::pulse::PulseTiming`]), registered;
//!   `timing_ok` = high_min + low_min ≤ the minimum period M, registered from them
//!   (the register file refuses CTRL.ENABLE = 1 while it is 0).
//!
//! Latency: a write shows on `rd_data` one bus clock after it, on `high_min` and
//! `low_min` two, on `timing_ok` three (the register file needs a write of CTRL after
//! the timing writes anyway: the bus keeps accesses at least 3 bus clocks apart).
//! Ports: the bus (`wr`, `wr_addr`, `wr_data`, `rd_addr` → `rd_data`, combinational),
//! `locked` → `refuse`, `high_min`, `low_min`, `timing_ok`. Checked three ways in
//! tests/hdl_regfile.rs (`timing_registers_follow_the_register_table_three_ways`: a
//! model with `PulseTiming::check` as the verdict, rust-hdl, Verilator and Icarus).

use super::regfile::c9;
use crate::regs::ADDR_BITS;
use rust_hdl::prelude::*;

#[derive(LogicBlock)]
pub struct TimingRegs {
    pub clock: Signal<In, Clock>,
    pub reset: Signal<In, Bit>,
    pub wr: Signal<In, Bit>,
    pub wr_addr: Signal<In, Bits<ADDR_BITS>>,
    pub wr_data: Signal<In, Bits<16>>,
    /// CTRL.ENABLE or GSTATUS.ENABLED: the core is not held off, writes are refused.
    pub locked: Signal<In, Bit>,
    /// A write to one of these registers is refused in this cycle.
    pub refuse: Signal<Out, Bit>,
    pub rd_addr: Signal<In, Bits<ADDR_BITS>>,
    pub rd_data: Signal<Out, Bits<16>>,
    pub high_min: Signal<Out, Bits<16>>,
    pub low_min: Signal<Out, Bits<16>>,
    pub timing_ok: Signal<Out, Bit>,
    t_high: DFF<Bits<16>>,
    t_low: DFF<Bits<16>>,
    t_setup: DFF<Bits<16>>,
    t_hold: DFF<Bits<16>>,
    hmin: DFF<Bits<16>>,
    lmin: DFF<Bits<16>>,
    ok: DFF<Bit>,
    t_write: Signal<Local, Bit>,
    c_minp17: Constant<Bits<17>>,
    a_t_high: Constant<Bits<ADDR_BITS>>,
    a_t_low: Constant<Bits<ADDR_BITS>>,
    a_t_setup: Constant<Bits<ADDR_BITS>>,
    a_t_hold: Constant<Bits<ADDR_BITS>>,
}

impl TimingRegs {
    /// `min_period`: the core's minimum step period M in ticks (ID_MIN_PERIOD).
    pub fn new(min_period: u32) -> Self {
        TimingRegs {
            clock: Default::default(),
            reset: Default::default(),
            wr: Default::default(),
            wr_addr: Default::default(),
            wr_data: Default::default(),
            locked: Default::default(),
            refuse: Default::default(),
            rd_addr: Default::default(),
            rd_data: Default::default(),
            high_min: Default::default(),
            low_min: Default::default(),
            timing_ok: Default::default(),
            t_high: Default::default(),
            t_low: Default::default(),
            t_setup: Default::default(),
            t_hold: Default::default(),
            hmin: Default::default(),
            lmin: Default::default(),
            ok: Default::default(),
            t_write: Default::default(),
            c_minp17: Constant::new((min_period as u64).into()),
            a_t_high: c9("STEP_HIGH"),
            a_t_low: c9("STEP_LOW"),
            a_t_setup: c9("DIR_SETUP"),
            a_t_hold: c9("DIR_HOLD"),
        }
    }
}

impl Logic for TimingRegs {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, t_high, t_low, t_setup, t_hold, hmin, lmin, ok);
        // The two minima the core applies, and whether they fit in the minimum period.
        // Registered: they change only with a timing write, which needs the core off.
        self.hmin.d.next = self.t_high.q.val();
        if self.t_hold.q.val() > self.t_high.q.val() {
            self.hmin.d.next = self.t_hold.q.val();
        }
        self.lmin.d.next = self.t_low.q.val();
        if self.t_setup.q.val() > self.t_low.q.val() {
            self.lmin.d.next = self.t_setup.q.val();
        }
        self.ok.d.next =
            (bit_cast::<17, 16>(self.hmin.q.val()) + bit_cast::<17, 16>(self.lmin.q.val())) <= self.c_minp17.val();
        self.high_min.next = self.hmin.q.val();
        self.low_min.next = self.lmin.q.val();
        self.timing_ok.next = self.ok.q.val();
        self.t_write.next = (self.wr_addr.val() == self.a_t_high.val())
            | (self.wr_addr.val() == self.a_t_low.val())
            | (self.wr_addr.val() == self.a_t_setup.val())
            | (self.wr_addr.val() == self.a_t_hold.val());
        self.refuse.next = false;
        if self.wr.val() & self.t_write.val() {
            if self.locked.val() | (self.wr_data.val() == 0) {
                self.refuse.next = true;
            } else {
                if self.wr_addr.val() == self.a_t_high.val() {
                    self.t_high.d.next = self.wr_data.val();
                }
                if self.wr_addr.val() == self.a_t_low.val() {
                    self.t_low.d.next = self.wr_data.val();
                }
                if self.wr_addr.val() == self.a_t_setup.val() {
                    self.t_setup.d.next = self.wr_data.val();
                }
                if self.wr_addr.val() == self.a_t_hold.val() {
                    self.t_hold.d.next = self.wr_data.val();
                }
            }
        }
        if self.reset.val() {
            self.t_high.d.next = 1.into();
            self.t_low.d.next = 1.into();
            self.t_setup.d.next = 1.into();
            self.t_hold.d.next = 1.into();
        }
        self.rd_data.next = 0.into();
        if self.rd_addr.val() == self.a_t_high.val() {
            self.rd_data.next = self.rd_data.val() | self.t_high.q.val();
        }
        if self.rd_addr.val() == self.a_t_low.val() {
            self.rd_data.next = self.rd_data.val() | self.t_low.q.val();
        }
        if self.rd_addr.val() == self.a_t_setup.val() {
            self.rd_data.next = self.rd_data.val() | self.t_setup.q.val();
        }
        if self.rd_addr.val() == self.a_t_hold.val() {
            self.rd_data.next = self.rd_data.val() | self.t_hold.q.val();
        }
    }
}
