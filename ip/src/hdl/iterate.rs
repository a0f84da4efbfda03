//! Control of an iterative unit: accepts `start` while idle, then runs a fixed
//! number of cycles, then holds `valid` until the next start.
//!
//! `load` is high in the cycle whose edge accepts a start (the unit loads its
//! operands), `step` in each cycle whose edge performs an iteration. `busy` is high
//! while iterating; `valid` from the edge after the last iteration until the next
//! accepted start. A `start` while busy is ignored. Used by [`super::root`],
//! [`super::mul_seq`] and [`super::divider`]; latency from the start edge to `valid`
//! is `1 + cycles`.

use rust_hdl::prelude::*;

#[derive(LogicBlock)]
pub struct Iterate {
    pub clock: Signal<In, Clock>,
    pub start: Signal<In, Bit>,
    pub load: Signal<Out, Bit>,
    pub step: Signal<Out, Bit>,
    pub valid: Signal<Out, Bit>,
    pub busy: Signal<Out, Bit>,
    count: DFF<Bits<8>>,
    running: DFF<Bit>,
    done: DFF<Bit>,
    cycles: Constant<Bits<8>>,
}

impl Iterate {
    /// A controller that iterates `cycles` (1..=255) times per start.
    pub fn new(cycles: usize) -> Iterate {
        assert!((1..=255).contains(&cycles), "Iterate: {cycles} cycles outside 1..=255");
        Iterate {
            clock: Default::default(),
            start: Default::default(),
            load: Default::default(),
            step: Default::default(),
            valid: Default::default(),
            busy: Default::default(),
            count: Default::default(),
            running: Default::default(),
            done: Default::default(),
            cycles: Constant::new((cycles as u64).into()),
        }
    }
}

impl Logic for Iterate {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, count, running, done);
        self.valid.next = self.done.q.val();
        self.busy.next = self.running.q.val();
        self.step.next = self.running.q.val();
        self.load.next = self.start.val() & !self.running.q.val();
        if self.running.q.val() {
            self.count.d.next = self.count.q.val() - 1;
            if self.count.q.val() == 1 {
                self.running.d.next = false;
                self.done.d.next = true;
            }
        } else {
            // The count loads while idle whether or not a start comes, so `start`
            // drives only `running` and `done`, not the counter's eight flip-flops.
            self.count.d.next = self.cycles.val();
            if self.start.val() {
                self.running.d.next = true;
                self.done.d.next = false;
            }
        }
    }
}
