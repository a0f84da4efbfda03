//! Per-axis scheduler flags: the registers of one axis's context. The wide fields
//! live in the shared context memory ([`super::context_ram::ContextRam`]), two words
//! per axis (current and next slot); these flags say what the words hold.
//!
//! `we` (a step's commit) writes the current segment's `kind` (it becomes 0 when the
//! last period is computed); `nwe` (a setup's commit into the next slot) writes the
//! next slot's kind and `new_dwell`; `promote` makes the next segment current by
//! flipping `slot` (a dwell only clears the next slot: the scheduler pushes its FIFO
//! entry). `reset` empties both slots (slot 0). All writes take effect at the next clock edge (latency 1).
//!
//! | flag | bits | meaning |
//! |---|---|---|
//! | kind | 2 | current segment: 0 idle, 1 uniform, 2 accelerate, 3 decelerate |
//! | slot | 1 | which of the axis's two context words is current |
//! | next kind, next dwell | 2 + 1 | the next slot holds a set-up segment or a dwell |

use rust_hdl::prelude::*;

#[derive(LogicBlock, Default)]
pub struct AxisContext {
    pub clock: Signal<In, Clock>,
    pub reset: Signal<In, Bit>,
    pub we: Signal<In, Bit>,
    pub nwe: Signal<In, Bit>,
    pub promote: Signal<In, Bit>,
    /// A controlled stop's cut: the current segment ends (kind 0) and the next slot
    /// empties; the slot stays.
    pub cut: Signal<In, Bit>,
    pub new_dwell: Signal<In, Bit>,
    pub new_kind: Signal<In, Bits<2>>,
    pub kind: Signal<Out, Bits<2>>,
    pub slot: Signal<Out, Bit>,
    /// The next slot holds a segment (a set-up segment or a dwell).
    pub next_valid: Signal<Out, Bit>,
    pub next_dwell: Signal<Out, Bit>,
    r_kind: DFF<Bits<2>>,
    r_slot: DFF<Bit>,
    x_kind: DFF<Bits<2>>,
    x_dwell: DFF<Bit>,
}

impl Logic for AxisContext {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, r_kind, r_slot, x_kind, x_dwell);
        self.kind.next = self.r_kind.q.val();
        self.slot.next = self.r_slot.q.val();
        self.next_valid.next = (self.x_kind.q.val() != 0) | self.x_dwell.q.val();
        self.next_dwell.next = self.x_dwell.q.val();
        if self.we.val() {
            self.r_kind.d.next = self.new_kind.val();
        }
        if self.nwe.val() {
            self.x_kind.d.next = self.new_kind.val();
            self.x_dwell.d.next = self.new_dwell.val();
        }
        if self.promote.val() {
            if !self.x_dwell.q.val() {
                self.r_kind.d.next = self.x_kind.q.val();
                self.r_slot.d.next = !self.r_slot.q.val();
            }
            self.x_kind.d.next = 0.into();
            self.x_dwell.d.next = false;
        }
        if self.cut.val() {
            self.r_kind.d.next = 0.into();
            self.x_kind.d.next = 0.into();
            self.x_dwell.d.next = false;
        }
        if self.reset.val() {
            self.r_kind.d.next = 0.into();
            self.x_kind.d.next = 0.into();
            self.x_dwell.d.next = false;
            self.r_slot.d.next = false;
        }
    }
}
