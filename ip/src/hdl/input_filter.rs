//! One machine input pin into `clk`: a two-flip-flop synchroniser, the polarity, and a
//! digital filter (`model::io::InputModel`, the model it equals).
//!
//! Ports: `pin` (asynchronous), `invert` (1 = the input is active low at the pin),
//! `sample` (the shared filter strobe: one cycle in `prescale + 1`), `samples` (n, the
//! filter length, 0..=15 samples, 0 = off), `reset` (synchronous: the level goes to
//! its reset value, chosen at construction; the synchroniser keeps running). `active` is the filtered level, active
//! high, a flip-flop; `rise` and `fall` are high in the cycle before it becomes 1 or
//! 0 (combinational from flip-flops and the quasi-static inputs), so a latch enabled by
//! them takes its value on the same clock edge as `active` changes.
//!
//! Latency: the filtered level changes once the synchronised input has differed from it
//! at n + 1 consecutive samples; with a sample every tick, a pin change first sampled
//! at clk edge e0 shows on `active` after edge e0 + 2 + n (`model::io::pin_to_level_ticks`).
//! A pulse or bounce seen at fewer than n + 1 consecutive samples is ignored.
//!
//! Cost: 7 flip-flops (2 synchroniser, the level, a 4-bit count) and a few LUTs.

use rust_hdl::prelude::*;

#[derive(LogicBlock)]
pub struct InputFilter {
    pub clock: Signal<In, Clock>,
    pub reset: Signal<In, Bit>,
    pub pin: Signal<In, Bit>,
    pub invert: Signal<In, Bit>,
    pub sample: Signal<In, Bit>,
    pub samples: Signal<In, Bits<4>>,
    pub active: Signal<Out, Bit>,
    pub rise: Signal<Out, Bit>,
    pub fall: Signal<Out, Bit>,
    s1: DFF<Bit>,
    s2: DFF<Bit>,
    level: DFF<Bit>,
    count: DFF<Bits<4>>,
    /// The level after a reset.
    rest: Constant<Bit>,
    /// The synchronised input after the polarity.
    x: Signal<Local, Bit>,
    /// The level changes at the coming edge.
    change: Signal<Local, Bit>,
}

impl InputFilter {
    /// An input whose level resets to `reset_active` (active for the inputs that stop
    /// motion, so nothing moves until the filter has seen them inactive).
    pub fn new(reset_active: bool) -> Self {
        InputFilter {
            clock: Default::default(),
            reset: Default::default(),
            pin: Default::default(),
            invert: Default::default(),
            sample: Default::default(),
            samples: Default::default(),
            active: Default::default(),
            rise: Default::default(),
            fall: Default::default(),
            s1: Default::default(),
            s2: Default::default(),
            level: Default::default(),
            count: Default::default(),
            rest: Constant::new(reset_active),
            x: Default::default(),
            change: Default::default(),
        }
    }
}

impl Logic for InputFilter {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, s1, s2, level, count);
        self.s1.d.next = self.pin.val();
        self.s2.d.next = self.s1.q.val();
        self.x.next = self.s2.q.val() ^ self.invert.val();
        self.change.next = (self.x.val() != self.level.q.val()) & self.sample.val() & (self.count.q.val() >= self.samples.val());
        self.active.next = self.level.q.val();
        self.rise.next = self.change.val() & !self.level.q.val();
        self.fall.next = self.change.val() & self.level.q.val();
        if self.x.val() == self.level.q.val() {
            self.count.d.next = 0.into();
        } else if self.sample.val() {
            if self.count.q.val() >= self.samples.val() {
                self.level.d.next = self.x.val();
                self.count.d.next = 0.into();
            } else {
                self.count.d.next = self.count.q.val() + 1;
            }
        }
        if self.reset.val() {
            self.level.d.next = self.rest.val();
            self.count.d.next = 0.into();
        }
    }
}
