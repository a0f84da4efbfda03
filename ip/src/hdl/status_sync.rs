//! Status crossing, core clock to bus clock: a four-phase-free toggle handshake that
//! copies one axis's status word at a time, round robin over the K axes.
//!
//! Core side (`cclock`): `sel` names the axis whose status word the owner puts on
//! `word_in`. When the previous copy has been acknowledged (the synchronised `ack`
//! equals `req`), the word and its axis go into `hold` and `req` toggles. Bus side
//! (`bclock`): when the synchronised `req` differs from `ack`, `valid` pulses for one
//! cycle with `axis` and `word` taken from `hold` (which does not change until this
//! side toggles `ack` in the same cycle), and `ack` follows. A word is therefore
//! never torn, and each copy takes about 3 core plus 3 bus clocks, so every axis is
//! refreshed at least every K·(3 T_clk + 3 T_bus) or so.
//! `creset` and `breset` (synchronous) must be asserted together.

use rust_hdl::prelude::*;

/// Width of a status word.
pub const STATUS_BITS: usize = 58;

/// The register file's status crossing: words of [`STATUS_BITS`].
pub type StatusSync<const K: usize> = WordSync<K, STATUS_BITS>;

/// The crossing for `W`-bit words (the machine I/O's position latches use it too).
#[derive(LogicBlock)]
pub struct WordSync<const K: usize, const W: usize> {
    pub cclock: Signal<In, Clock>,
    pub creset: Signal<In, Bit>,
    pub sel: Signal<Out, Bits<8>>,
    pub word_in: Signal<In, Bits<W>>,
    pub bclock: Signal<In, Clock>,
    pub breset: Signal<In, Bit>,
    pub valid: Signal<Out, Bit>,
    pub axis: Signal<Out, Bits<8>>,
    pub word: Signal<Out, Bits<W>>,
    idx: DFF<Bits<8>>,
    hold: DFF<Bits<W>>,
    hold_axis: DFF<Bits<8>>,
    req: DFF<Bit>,
    ack_c1: DFF<Bit>,
    ack_c2: DFF<Bit>,
    req_b1: DFF<Bit>,
    req_b2: DFF<Bit>,
    ack: DFF<Bit>,
    c_last: Constant<Bits<8>>,
}

impl<const K: usize, const W: usize> Default for WordSync<K, W> {
    fn default() -> Self {
        assert!((1..=255).contains(&K));
        WordSync {
            cclock: Default::default(),
            creset: Default::default(),
            sel: Default::default(),
            word_in: Default::default(),
            bclock: Default::default(),
            breset: Default::default(),
            valid: Default::default(),
            axis: Default::default(),
            word: Default::default(),
            idx: Default::default(),
            hold: Default::default(),
            hold_axis: Default::default(),
            req: Default::default(),
            ack_c1: Default::default(),
            ack_c2: Default::default(),
            req_b1: Default::default(),
            req_b2: Default::default(),
            ack: Default::default(),
            c_last: Constant::new(((K - 1) as u64).into()),
        }
    }
}

impl<const K: usize, const W: usize> Logic for WordSync<K, W> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, cclock, idx, hold, hold_axis, req, ack_c1, ack_c2);
        dff_setup!(self, bclock, req_b1, req_b2, ack);
        // Core side.
        self.sel.next = self.idx.q.val();
        self.ack_c1.d.next = self.ack.q.val();
        self.ack_c2.d.next = self.ack_c1.q.val();
        if self.ack_c2.q.val() == self.req.q.val() {
            self.hold.d.next = self.word_in.val();
            self.hold_axis.d.next = self.idx.q.val();
            self.req.d.next = !self.req.q.val();
            if self.idx.q.val() == self.c_last.val() {
                self.idx.d.next = 0.into();
            } else {
                self.idx.d.next = self.idx.q.val() + 1;
            }
        }
        if self.creset.val() {
            self.idx.d.next = 0.into();
            self.req.d.next = false;
            self.ack_c1.d.next = false;
            self.ack_c2.d.next = false;
        }
        // Bus side.
        self.req_b1.d.next = self.req.q.val();
        self.req_b2.d.next = self.req_b1.q.val();
        self.valid.next = self.req_b2.q.val() != self.ack.q.val();
        self.axis.next = self.hold_axis.q.val();
        self.word.next = self.hold.q.val();
        self.ack.d.next = self.req_b2.q.val();
        if self.breset.val() {
            self.req_b1.d.next = false;
            self.req_b2.d.next = false;
            self.ack.d.next = false;
            self.valid.next = false;
        }
    }
}
