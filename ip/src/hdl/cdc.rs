//! Clock-domain crossing: a two-flip-flop bit synchroniser and a small asynchronous
//! FIFO with Gray-coded pointers.
//!
//! [`BitSync`]: `sig_out` is `sig_in` two `clock` edges later (the first stage may go
//! metastable; the second has a cycle to settle). Used for resets, the enable and the
//! handshake flags.
//!
//! [`BitsSync`]: the same for a bus of independent flags.
//!
//! [`MaskCross`]: one-cycle command masks (STOP, ENC_ARM, ...) from the bus clock into
//! `clk`, none lost, 3 to 4 `clk` edges after the write.
//!
//! [`AsyncFifo`]: `W`-bit entries, 4 deep, written in `wclock`, read in `rclock`
//! (unrelated clocks). Show-ahead: `data_out` is the head entry whenever `empty` is
//! low; `read` pops it. `write` is ignored while `full`. `almost_full` (registered)
//! says DEPTH − 1 or more entries were there as the writer saw them a cycle before. Each side keeps a binary
//! and a Gray pointer (3 bits: 2 of address, 1 of wrap); only the Gray pointer
//! crosses, through two flip-flops, so a pointer is seen either before or after one
//! increment, never torn. Hence `full` and `empty` are conservative: an entry is
//! visible to the reader 2–3 `rclock` edges after its write, and a slot is free for
//! the writer 2–3 `wclock` edges after its read. The entries live in a [`LutRam`]
//! (32 words, of which 4 are used, so yosys maps it to LUT RAM: W bits cost W/6
//! RAM32M on xc7 instead of 4·W flip-flops and a 4:1 multiplexer) written in `wclock`
//! and read asynchronously at the read pointer in `rclock`; a slot is never read
//! until its write is two synchroniser stages old. `wreset` and `rreset` (synchronous, each
//! in its own domain) must be asserted together, as the top level's reset is.

use super::lut_ram::LutRam;
use rust_hdl::prelude::*;

#[derive(LogicBlock, Default)]
pub struct BitSync {
    pub clock: Signal<In, Clock>,
    pub sig_in: Signal<In, Bit>,
    pub sig_out: Signal<Out, Bit>,
    s1: DFF<Bit>,
    s2: DFF<Bit>,
}

impl Logic for BitSync {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, s1, s2);
        self.s1.d.next = self.sig_in.val();
        self.s2.d.next = self.s1.q.val();
        self.sig_out.next = self.s2.q.val();
    }
}

/// A two-flip-flop synchroniser per bit of a `W`-bit bus, for independent levels
/// (flags): each bit arrives two `clock` edges after it changes, but bits that change
/// together may arrive a cycle apart, so it is not for a word.
#[derive(LogicBlock, Default)]
pub struct BitsSync<const W: usize> {
    pub clock: Signal<In, Clock>,
    pub sig_in: Signal<In, Bits<W>>,
    pub sig_out: Signal<Out, Bits<W>>,
    s1: DFF<Bits<W>>,
    s2: DFF<Bits<W>>,
}

impl<const W: usize> Logic for BitsSync<W> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, s1, s2);
        self.s1.d.next = self.sig_in.val();
        self.s2.d.next = self.s1.q.val();
        self.sig_out.next = self.s2.q.val();
    }
}

/// One-cycle command masks from the bus clock into `clk`, none lost: the bits of `req`
/// (a write's, one bus cycle) collect in `nxt` (ORed in) and leave as one mask: while
/// no mask is crossing, `nxt` moves into `mask` and a toggle flips; the toggle crosses
/// into `clock` through two flip-flops and leaves as one cycle of `out` = `mask`
/// (stable since before the toggle flipped), 3 to 4 `clock` edges after the bus
/// edge that took `req`, plus the bus cycles it waits while an earlier mask crosses.
/// The `clock` side's copy of the toggle crosses back (two bus-clock flip-flops); the
/// next mask leaves once it is seen, so `mask` never changes while `clock` may read
/// it. `bus_reset` drops requests not yet sent; the toggles are never reset (the
/// `clock` side only copies the synchronised toggle), so the sides agree after a reset
/// of either. `out` is 0 in every other cycle. Cost: 2·W + 6 flip-flops.
#[derive(LogicBlock, Default)]
pub struct MaskCross<const W: usize> {
    pub bus_clock: Signal<In, Clock>,
    pub bus_reset: Signal<In, Bit>,
    pub req: Signal<In, Bits<W>>,
    pub clock: Signal<In, Clock>,
    pub out: Signal<Out, Bits<W>>,
    nxt: DFF<Bits<W>>,
    mask: DFF<Bits<W>>,
    tog: DFF<Bit>,
    ack: BitSync,
    busy: Signal<Local, Bit>,
    tsync: BitSync,
    tprev: DFF<Bit>,
}

impl<const W: usize> Logic for MaskCross<W> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, bus_clock, nxt, mask, tog);
        dff_setup!(self, clock, tprev);
        // Bus clock.
        self.ack.clock.next = self.bus_clock.val();
        self.ack.sig_in.next = self.tprev.q.val();
        self.busy.next = self.tog.q.val() ^ self.ack.sig_out.val();
        self.nxt.d.next = self.nxt.q.val() | self.req.val();
        if !self.busy.val() & self.nxt.q.val().any() {
            self.mask.d.next = self.nxt.q.val();
            self.tog.d.next = !self.tog.q.val();
            self.nxt.d.next = self.req.val();
        }
        if self.bus_reset.val() {
            self.nxt.d.next = 0.into();
        }
        // clk.
        self.tsync.clock.next = self.clock.val();
        self.tsync.sig_in.next = self.tog.q.val();
        self.tprev.d.next = self.tsync.sig_out.val();
        self.out.next = 0.into();
        if self.tsync.sig_out.val() ^ self.tprev.q.val() {
            self.out.next = self.mask.q.val();
        }
    }
}

/// Entries of the [`AsyncFifo`].
pub const ASYNC_FIFO_DEPTH: usize = 4;

#[derive(LogicBlock)]
pub struct AsyncFifo<const W: usize> {
    pub wclock: Signal<In, Clock>,
    pub wreset: Signal<In, Bit>,
    pub write: Signal<In, Bit>,
    pub data_in: Signal<In, Bits<W>>,
    pub full: Signal<Out, Bit>,
    /// At least DEPTH − 1 entries as the writer saw them in the previous cycle
    /// (registered; conservative like `full`, and missing only a write made in the
    /// previous cycle): with `full`, tells a writer that has a second write on the way
    /// whether both fit.
    pub almost_full: Signal<Out, Bit>,
    pub rclock: Signal<In, Clock>,
    pub rreset: Signal<In, Bit>,
    pub read: Signal<In, Bit>,
    pub data_out: Signal<Out, Bits<W>>,
    pub empty: Signal<Out, Bit>,
    ram: LutRam<W, 5>,
    wbin: DFF<Bits<3>>,
    wgray: DFF<Bits<3>>,
    rgray_w1: DFF<Bits<3>>,
    rgray_w2: DFF<Bits<3>>,
    afull: DFF<Bit>,
    rbin: DFF<Bits<3>>,
    rgray: DFF<Bits<3>>,
    wgray_r1: DFF<Bits<3>>,
    wgray_r2: DFF<Bits<3>>,
    wbin_inc: Signal<Local, Bits<3>>,
    rbin_inc: Signal<Local, Bits<3>>,
    is_full: Signal<Local, Bit>,
    rbin_w: Signal<Local, Bits<3>>,
    level_w: Signal<Local, Bits<3>>,
    is_empty: Signal<Local, Bit>,
    c_full: Constant<Bits<3>>,
}

impl<const W: usize> Default for AsyncFifo<W> {
    fn default() -> Self {
        AsyncFifo {
            wclock: Default::default(),
            wreset: Default::default(),
            write: Default::default(),
            data_in: Default::default(),
            full: Default::default(),
            almost_full: Default::default(),
            rclock: Default::default(),
            rreset: Default::default(),
            read: Default::default(),
            data_out: Default::default(),
            empty: Default::default(),
            ram: Default::default(),
            wbin: Default::default(),
            wgray: Default::default(),
            rgray_w1: Default::default(),
            rgray_w2: Default::default(),
            afull: Default::default(),
            rbin: Default::default(),
            rgray: Default::default(),
            wgray_r1: Default::default(),
            wgray_r2: Default::default(),
            wbin_inc: Default::default(),
            rbin_inc: Default::default(),
            is_full: Default::default(),
            rbin_w: Default::default(),
            level_w: Default::default(),
            is_empty: Default::default(),
            // Full: the Gray pointers differ in exactly their two top bits.
            c_full: Constant::new(6u64.into()),
        }
    }
}

impl<const W: usize> Logic for AsyncFifo<W> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, wclock, wbin, wgray, rgray_w1, rgray_w2, afull);
        dff_setup!(self, rclock, rbin, rgray, wgray_r1, wgray_r2);
        // Write side.
        self.rgray_w1.d.next = self.rgray.q.val();
        self.rgray_w2.d.next = self.rgray_w1.q.val();
        self.is_full.next = (self.wgray.q.val() ^ self.rgray_w2.q.val()) == self.c_full.val();
        self.full.next = self.is_full.val();
        // The level the writer sees: its binary pointer less the reader's, decoded from
        // the synchronised Gray pointer (3 bits: b2 = g2, b1 = g2 ^ g1, b0 = b1 ^ g0).
        self.rbin_w.next = self.rgray_w2.q.val() ^ (self.rgray_w2.q.val() >> 1) ^ (self.rgray_w2.q.val() >> 2);
        self.level_w.next = self.wbin.q.val() - self.rbin_w.val();
        self.afull.d.next = self.level_w.val() >= 3;
        self.almost_full.next = self.afull.q.val();
        self.wbin_inc.next = self.wbin.q.val() + 1;
        self.ram.clock.next = self.wclock.val();
        self.ram.we.next = self.write.val() & !self.is_full.val();
        self.ram.waddr.next = bit_cast::<5, 2>(self.wbin.q.val().get_bits::<2>(0));
        self.ram.wdata.next = self.data_in.val();
        if self.write.val() & !self.is_full.val() {
            self.wbin.d.next = self.wbin_inc.val();
            self.wgray.d.next = self.wbin_inc.val() ^ (self.wbin_inc.val() >> 1);
        }
        if self.wreset.val() {
            self.wbin.d.next = 0.into();
            self.wgray.d.next = 0.into();
            self.rgray_w1.d.next = 0.into();
            self.rgray_w2.d.next = 0.into();
            self.afull.d.next = false;
        }
        // Read side.
        self.wgray_r1.d.next = self.wgray.q.val();
        self.wgray_r2.d.next = self.wgray_r1.q.val();
        self.is_empty.next = self.rgray.q.val() == self.wgray_r2.q.val();
        self.empty.next = self.is_empty.val();
        self.rbin_inc.next = self.rbin.q.val() + 1;
        self.ram.raddr.next = bit_cast::<5, 2>(self.rbin.q.val().get_bits::<2>(0));
        self.data_out.next = self.ram.rdata.val();
        if self.read.val() & !self.is_empty.val() {
            self.rbin.d.next = self.rbin_inc.val();
            self.rgray.d.next = self.rbin_inc.val() ^ (self.rbin_inc.val() >> 1);
        }
        if self.rreset.val() {
            self.rbin.d.next = 0.into();
            self.rgray.d.next = 0.into();
            self.wgray_r1.d.next = 0.into();
            self.wgray_r2.d.next = 0.into();
        }
    }
}
