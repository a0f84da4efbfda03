//! SPI front end (`export --bus spi`): an SPI slave that turns frames into accesses of
//! the EXMC slave ([`super::exmc::ExmcSlave`]) in the same bus clock, so the register
//! file, its push check and its timing contract stay the one verified piece behind
//! every bus. The frame is in docs/registers.md ("SPI"); its model, which the tests
//! hold this block to bit for bit, is [`crate::verify::spi`].
//!
//! **Pins.** `cs_n`, `sck` and `mosi` are asynchronous: each passes through two
//! flip-flops in `clock` (the same stages, so a MOSI sample is as old as the SCK
//! sample taken with it). MOSI is taken and MISO advanced on SCK's **rising** edges
//! only, so SPI modes 0 and 3 both work without a setting (they differ only in SCK's
//! idle level). `miso` is a flip-flop; `miso_oe = !cs_n`, combinational from the pin.
//!
//! **Frame.** Byte 0 is the command: bit 7 W (1 write, 0 read), bit 6 INC (the address
//! steps by one after each word), bits 5..1 LEN − 1 (1 to 32 words), bit 0 address
//! bit 8; byte 1 is address bits 7..0. A write then carries LEN 16-bit words, MSB
//! first; a read has one turnaround byte and then returns LEN words. MISO carries the
//! status byte during byte 0 ([`STATUS_PATTERN`], IRQ in bit 7, FRAME_ERR in bit 6)
//! and zeros outside read data.
//!
//! * A write commits each word when its 16th bit has arrived; CS rising mid-word
//!   discards the partial word. A read fetches its first word when the header is
//!   complete and each next one when the previous is loaded (never past LEN).
//! * **Refused, FRAME_ERR:** a header whose burst would run past address 0x1FF (no
//!   access at all); SCK edges after the LEN-th word (nothing written); a frame that
//!   ends mid-field or before its LEN-th word (the whole words before stay written);
//!   a word ready while the previous access is still on the EXMC side (only when SCK
//!   is faster than the limit). A frame of exactly 8 SCK edges is a status poll, not
//!   an error. FRAME_ERR in a frame's status byte is the previous frame's (one with
//!   at least one SCK edge).
//!
//! **EXMC side.** An [`ExmcMaster`]: a write holds NE and NWE low [`SPI_WRITE_LOW`]
//! cycles; a read holds NE and NOE low [`SPI_READ_LOW`] cycles and takes `rdata` at the
//! last of them; the strobes then stay high [`SPI_GAP`] cycles: the documented minimum
//! timing of an MCU whose clock is the bus clock.
//!
//! **Limits** (tests/hdl_bus_fronts.rs): SCK high and low each ≥ 2 bus clocks (SCK ≤
//! `bus_clk`/4); CS low ≥ 1 bus clock before the first SCK edge; CS high ≥
//! [`SPI_CS_HIGH_MIN`] bus clocks between frames. MISO changes 3 bus clocks after
//! SCK rises (2 of synchroniser, 1 of register).

use super::cdc::BitSync;
use super::exmc_master::ExmcMaster;
use crate::regs::ADDR_BITS;
use rust_hdl::prelude::*;

/// The EXMC side's timing: bus clocks NE and NWE stay low for a write, NE and NOE for
/// a read, and the strobes stay high after an access.
pub use super::exmc_master::{GAP as SPI_GAP, READ_LOW as SPI_READ_LOW, WRITE_LOW as SPI_WRITE_LOW};
/// Fewest bus clocks CS must stay high between frames, and the status byte's
/// pattern (bits 5..0), from the register table.
pub use crate::regs::{SPI_CS_HIGH_MIN, SPI_STATUS_PATTERN as STATUS_PATTERN};

#[derive(LogicBlock)]
pub struct SpiFront {
    pub clock: Signal<In, Clock>,
    /// Active high, asynchronous (synchronised here).
    pub reset: Signal<In, Bit>,
    pub cs_n: Signal<In, Bit>,
    pub sck: Signal<In, Bit>,
    pub mosi: Signal<In, Bit>,
    pub miso: Signal<Out, Bit>,
    pub miso_oe: Signal<Out, Bit>,
    /// The core's `irq`, for the status byte.
    pub irq: Signal<In, Bit>,
    /// The EXMC pins of the register file's slave.
    pub ne: Signal<Out, Bit>,
    pub noe: Signal<Out, Bit>,
    pub nwe: Signal<Out, Bit>,
    pub addr: Signal<Out, Bits<ADDR_BITS>>,
    pub wdata: Signal<Out, Bits<16>>,
    pub rdata: Signal<In, Bits<16>>,
    rst: BitSync,
    cs1: DFF<Bit>,
    cs2: DFF<Bit>,
    sk1: DFF<Bit>,
    sk2: DFF<Bit>,
    sk3: DFF<Bit>,
    mo1: DFF<Bit>,
    mo2: DFF<Bit>,
    /// Bits in, and the bits MISO shows (bit 15 first).
    sin: DFF<Bits<16>>,
    sout: DFF<Bits<16>>,
    /// SCK edges left in the field, minus one.
    cnt: DFF<Bits<4>>,
    /// 0 header, 1 turnaround, 2 data, 3 done (edges now are an error).
    phase: DFF<Bits<2>>,
    rd_mode: DFF<Bit>,
    inc: DFF<Bit>,
    /// Words left to move.
    left: DFF<Bits<6>>,
    /// The word's address (a read: of the word being fetched).
    waddr: DFF<Bits<ADDR_BITS>>,
    err: DFF<Bit>,
    last_err: DFF<Bit>,
    in_frame: DFF<Bit>,
    master: ExmcMaster,
    c_status: Constant<Bits<16>>,
    rise: Signal<Local, Bit>,
    word: Signal<Local, Bits<16>>,
    h_last: Signal<Local, Bits<10>>,
    h_over: Signal<Local, Bit>,
    n_addr: Signal<Local, Bits<ADDR_BITS>>,
    partial: Signal<Local, Bit>,
    req_wr: Signal<Local, Bit>,
    req_rd: Signal<Local, Bit>,
    req_addr: Signal<Local, Bits<ADDR_BITS>>,
    st_hi: Signal<Local, Bits<16>>,
}

impl Default for SpiFront {
    fn default() -> Self {
        SpiFront {
            clock: Default::default(),
            reset: Default::default(),
            cs_n: Default::default(),
            sck: Default::default(),
            mosi: Default::default(),
            miso: Default::default(),
            miso_oe: Default::default(),
            irq: Default::default(),
            ne: Default::default(),
            noe: Default::default(),
            nwe: Default::default(),
            addr: Default::default(),
            wdata: Default::default(),
            rdata: Default::default(),
            rst: Default::default(),
            cs1: Default::default(),
            cs2: Default::default(),
            sk1: Default::default(),
            sk2: Default::default(),
            sk3: Default::default(),
            mo1: Default::default(),
            mo2: Default::default(),
            sin: Default::default(),
            sout: Default::default(),
            cnt: Default::default(),
            phase: Default::default(),
            rd_mode: Default::default(),
            inc: Default::default(),
            left: Default::default(),
            waddr: Default::default(),
            err: Default::default(),
            last_err: Default::default(),
            in_frame: Default::default(),
            master: Default::default(),
            c_status: Constant::new(((STATUS_PATTERN as u64) << 8).into()),
            rise: Default::default(),
            word: Default::default(),
            h_last: Default::default(),
            h_over: Default::default(),
            n_addr: Default::default(),
            partial: Default::default(),
            req_wr: Default::default(),
            req_rd: Default::default(),
            req_addr: Default::default(),
            st_hi: Default::default(),
        }
    }
}

impl Logic for SpiFront {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clock, cs1, cs2, sk1, sk2, sk3, mo1, mo2, sin, sout, cnt, phase, rd_mode, inc, left, waddr, err,
            last_err, in_frame
        );
        self.rst.clock.next = self.clock.val();
        self.rst.sig_in.next = self.reset.val();
        self.cs1.d.next = self.cs_n.val();
        self.cs2.d.next = self.cs1.q.val();
        self.sk1.d.next = self.sck.val();
        self.sk2.d.next = self.sk1.q.val();
        self.sk3.d.next = self.sk2.q.val();
        self.mo1.d.next = self.mosi.val();
        self.mo2.d.next = self.mo1.q.val();
        self.miso.next = self.sout.q.val().get_bit(15);
        self.miso_oe.next = !self.cs_n.val();
        self.master.clock.next = self.clock.val();
        self.master.reset.next = self.rst.sig_out.val();
        self.ne.next = self.master.ne.val();
        self.noe.next = self.master.noe.val();
        self.nwe.next = self.master.nwe.val();
        self.addr.next = self.master.addr.val();
        self.wdata.next = self.master.wdata.val();
        self.master.rdata.next = self.rdata.val();

        self.rise.next = self.sk2.q.val() & !self.sk3.q.val() & !self.cs2.q.val();
        self.word.next = (self.sin.q.val() << 1) | bit_cast::<16, 1>(self.mo2.q.val().into());
        // The header in `word`: W (15), INC (14), LEN − 1 (13..9), address (8..0); the
        // burst's last address, whose bit 9 says it runs past 0x1FF.
        self.h_last.next = bit_cast::<10, ADDR_BITS>(self.word.val().get_bits::<ADDR_BITS>(0))
            + bit_cast::<10, 5>(self.word.val().get_bits::<5>(9));
        self.h_over.next = (self.h_last.val() > 511) & self.word.val().get_bit(14);
        self.n_addr.next = self.waddr.q.val() + bit_cast::<ADDR_BITS, 1>(self.inc.q.val().into());
        self.req_wr.next = false;
        self.req_rd.next = false;
        self.req_addr.next = self.waddr.q.val();

        // ---- the frame -------------------------------------------------------
        if self.rise.val() {
            self.sin.d.next = self.word.val();
            self.sout.d.next = self.sout.q.val() << 1;
            self.cnt.d.next = self.cnt.q.val() - 1;
            self.in_frame.d.next = true;
            if self.phase.q.val() == 3 {
                self.err.d.next = true;
            }
            if self.cnt.q.val() == 0 {
                self.cnt.d.next = 15.into();
                if self.phase.q.val() == 0 {
                    self.rd_mode.d.next = !self.word.val().get_bit(15);
                    self.inc.d.next = self.word.val().get_bit(14);
                    self.left.d.next = bit_cast::<6, 5>(self.word.val().get_bits::<5>(9)) + 1;
                    self.waddr.d.next = self.word.val().get_bits::<ADDR_BITS>(0);
                    if self.h_over.val() {
                        self.err.d.next = true;
                        self.phase.d.next = 3.into();
                    } else if self.word.val().get_bit(15) {
                        self.phase.d.next = 2.into();
                    } else {
                        self.phase.d.next = 1.into();
                        self.cnt.d.next = 7.into();
                        self.req_rd.next = true;
                        self.req_addr.next = self.word.val().get_bits::<ADDR_BITS>(0);
                    }
                }
                if (self.phase.q.val() == 1) | (self.phase.q.val() == 2) {
                    if self.rd_mode.q.val() {
                        // The fetched word out (the last one has left: done); the next
                        // fetched while it leaves.
                        if self.left.q.val() == 0 {
                            self.phase.d.next = 3.into();
                        } else {
                            self.sout.d.next = self.master.rdata_q.val();
                            self.left.d.next = self.left.q.val() - 1;
                            self.phase.d.next = 2.into();
                            if self.left.q.val() != 1 {
                                self.req_rd.next = true;
                                self.req_addr.next = self.n_addr.val();
                                self.waddr.d.next = self.n_addr.val();
                            }
                        }
                    } else {
                        self.req_wr.next = true;
                        self.left.d.next = self.left.q.val() - 1;
                        self.waddr.d.next = self.n_addr.val();
                        if self.left.q.val() == 1 {
                            self.phase.d.next = 3.into();
                        }
                    }
                }
            }
        }
        // CS high: the frame's verdict, and the next frame's status byte.
        self.partial.next = (self.phase.q.val() == 1)
            | (self.phase.q.val() == 2)
            | ((self.phase.q.val() == 0) & (self.cnt.q.val() != 15) & (self.cnt.q.val() != 7));
        self.st_hi.next = (bit_cast::<16, 1>(self.irq.val().into()) << 15)
            | (bit_cast::<16, 1>(self.last_err.q.val().into()) << 14)
            | self.c_status.val();
        if self.cs2.q.val() {
            if self.in_frame.q.val() {
                self.last_err.d.next = self.err.q.val() | self.partial.val();
            }
            self.in_frame.d.next = false;
            self.phase.d.next = 0.into();
            self.cnt.d.next = 15.into();
            self.err.d.next = false;
            self.sout.d.next = self.st_hi.val();
        }

        // ---- the EXMC side: a word while the previous access is on it is refused.
        self.master.req_wr.next = self.req_wr.val();
        self.master.req_rd.next = self.req_rd.val();
        self.master.req_addr.next = self.req_addr.val();
        self.master.req_wdata.next = self.word.val();
        if (self.req_wr.val() | self.req_rd.val()) & self.master.busy.val() {
            self.err.d.next = true;
        }

        if self.rst.sig_out.val() {
            self.phase.d.next = 0.into();
            self.cnt.d.next = 15.into();
            self.in_frame.d.next = false;
            self.err.d.next = false;
            self.last_err.d.next = false;
        }
    }
}
