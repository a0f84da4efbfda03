//! EXMC / FSMC slave, asynchronous SRAM mode 1, 16-bit data (docs/registers.md, "The bus").
//!
//! Runs in `clock` (the bus clock, unrelated to the MCU's HCLK). The strobes `ne`,
//! `noe`, `nwe`, the address and the data pins all pass through the same two
//! flip-flop stages, so a sample of the data is as old as the sample of the strobe
//! taken with it. Stage 3 keeps the previous sample.
//!
//! * **Write.** While NWE and NE are sampled low in two consecutive samples (stages 2
//!   and 3), the older sample's address and data are captured. When NWE or NE is then
//!   sampled high, `wr` pulses for one cycle with the last capture. A strobe too
//!   short to be sampled low twice captures nothing and commits nothing, so a cut-off
//!   write never changes a register. The captured sample was taken while NWE was low
//!   and one sample before any sample near its rising edge, so it needs no data hold.
//! * **Read.** When NOE is first sampled low (stage 2 low, stage 3 high) with NE low,
//!   `rd` pulses with `rd_addr`; the owner returns `rd_data` combinationally, and it
//!   is registered onto `data_out` at that edge, where it stays until the next read.
//!   `data_oe = !ne & !noe`, straight from the pins, so the pads drive only while the
//!   MCU reads. Data is valid at most 4 bus clocks after NOE falls.
//! * **A cycle ahead.** `wr_next` and `wr_axis_next` are what `wr` and `wr_addr`'s
//!   bits 7..4 will be in the next cycle (the inputs of their flip-flops), and
//!   `rd_axis_next` is bits 8..4 of the address a stage earlier (what `rd_addr` holds
//!   in the next cycle), so the owner can decode the axis into flip-flops ahead of the
//!   access. (Bits 8..4 are the register map's per-axis flag and axis field.)
//!
//! Minimum timing (docs/registers.md): NWE low ≥ 3 bus clocks, strobes high ≥ 2 bus
//! clocks between accesses, NOE low ≥ 5 bus clocks before the MCU samples the data.

use crate::regs::ADDR_BITS;
use rust_hdl::prelude::*;

#[derive(LogicBlock, Default)]
pub struct ExmcSlave {
    pub clock: Signal<In, Clock>,
    pub reset: Signal<In, Bit>,
    pub ne: Signal<In, Bit>,
    pub noe: Signal<In, Bit>,
    pub nwe: Signal<In, Bit>,
    pub addr: Signal<In, Bits<ADDR_BITS>>,
    pub data_in: Signal<In, Bits<16>>,
    pub data_out: Signal<Out, Bits<16>>,
    pub data_oe: Signal<Out, Bit>,
    /// One cycle: commit `wr_data` to `wr_addr`.
    pub wr: Signal<Out, Bit>,
    pub wr_addr: Signal<Out, Bits<ADDR_BITS>>,
    pub wr_data: Signal<Out, Bits<16>>,
    /// `wr` and bits 7..4 of `wr_addr` (the register map's axis field) as they will be
    /// in the next cycle (their flip-flops' inputs), for an owner that selects a
    /// memory address a cycle ahead.
    pub wr_next: Signal<Out, Bit>,
    pub wr_axis_next: Signal<Out, Bits<4>>,
    /// One cycle: a read of `rd_addr` begins; `rd_data` is latched at this edge.
    pub rd: Signal<Out, Bit>,
    pub rd_addr: Signal<Out, Bits<ADDR_BITS>>,
    /// Bits 8..4 of the address `rd_addr` holds one cycle later (the first address
    /// stage; the register map's per-axis flag and axis field), for an owner that
    /// decodes the read's axis a cycle ahead.
    pub rd_axis_next: Signal<Out, Bits<5>>,
    pub rd_data: Signal<In, Bits<16>>,
    ne1: DFF<Bit>,
    ne2: DFF<Bit>,
    ne3: DFF<Bit>,
    nwe1: DFF<Bit>,
    nwe2: DFF<Bit>,
    nwe3: DFF<Bit>,
    noe1: DFF<Bit>,
    noe2: DFF<Bit>,
    noe3: DFF<Bit>,
    a1: DFF<Bits<ADDR_BITS>>,
    a2: DFF<Bits<ADDR_BITS>>,
    a3: DFF<Bits<ADDR_BITS>>,
    d1: DFF<Bits<16>>,
    d2: DFF<Bits<16>>,
    d3: DFF<Bits<16>>,
    captured: DFF<Bit>,
    cap_addr: DFF<Bits<ADDR_BITS>>,
    cap_data: DFF<Bits<16>>,
    rdata: DFF<Bits<16>>,
    commit: Signal<Local, Bit>,
    read_start: Signal<Local, Bit>,
}

impl Logic for ExmcSlave {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clock, ne1, ne2, ne3, nwe1, nwe2, nwe3, noe1, noe2, noe3, a1, a2, a3, d1, d2, d3, captured, cap_addr,
            cap_data, rdata
        );
        self.ne1.d.next = self.ne.val();
        self.ne2.d.next = self.ne1.q.val();
        self.ne3.d.next = self.ne2.q.val();
        self.nwe1.d.next = self.nwe.val();
        self.nwe2.d.next = self.nwe1.q.val();
        self.nwe3.d.next = self.nwe2.q.val();
        self.noe1.d.next = self.noe.val();
        self.noe2.d.next = self.noe1.q.val();
        self.noe3.d.next = self.noe2.q.val();
        self.a1.d.next = self.addr.val();
        self.a2.d.next = self.a1.q.val();
        self.a3.d.next = self.a2.q.val();
        self.d1.d.next = self.data_in.val();
        self.d2.d.next = self.d1.q.val();
        self.d3.d.next = self.d2.q.val();
        self.data_oe.next = !self.ne.val() & !self.noe.val();
        self.data_out.next = self.rdata.q.val();

        // Write: capture while stably low, commit when either strobe is seen high.
        self.commit.next = self.captured.q.val() & (self.nwe2.q.val() | self.ne2.q.val());
        self.wr.next = self.commit.val();
        self.wr_addr.next = self.cap_addr.q.val();
        self.wr_data.next = self.cap_data.q.val();
        if !self.nwe2.q.val() & !self.nwe3.q.val() & !self.ne2.q.val() & !self.ne3.q.val() {
            self.captured.d.next = true;
            self.cap_addr.d.next = self.a3.q.val();
            self.cap_data.d.next = self.d3.q.val();
        }
        if self.commit.val() {
            self.captured.d.next = false;
        }
        if self.reset.val() {
            self.captured.d.next = false;
        }
        // The next cycle's commit: its capture flag, and a strobe then seen high (its
        // second stage then is its first stage now).
        self.wr_next.next = self.captured.d.val() & (self.nwe1.q.val() | self.ne1.q.val());
        self.wr_axis_next.next = self.cap_addr.d.val().get_bits::<4>(4);

        // Read: latch the register's value as NOE is first seen low.
        self.read_start.next = !self.noe2.q.val() & self.noe3.q.val() & !self.ne2.q.val();
        self.rd.next = self.read_start.val();
        self.rd_addr.next = self.a2.q.val();
        self.rd_axis_next.next = self.a1.q.val().get_bits::<5>(4);
        if self.read_start.val() {
            self.rdata.d.next = self.rd_data.val();
        }
        if self.reset.val() {
            self.rdata.d.next = 0.into();
        }
    }
}
