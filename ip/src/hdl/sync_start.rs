//! Synchronised start: `start` with `start_mask` arms a release; the masked axes get
//! `go` on the same clock edge once every one of them reports `ready` (idle with its
//! first period in its FIFO). Then the mask clears. A new `start` re-arms it.
//! A start that cannot complete is cancelled: when a masked axis is `empty` (not ready
//! and not busy: nothing queued, being set up, computed or moving, as after its only
//! segment was rejected), the mask clears, no axis is released and `failed` pulses for
//! one cycle. Latency: `failed` one cycle after the condition (registered mask), `go`
//! two: the release is registered too, so the K-wide test of every axis's FIFO is not in
//! front of the K FIFOs' pops (on ECP5 at K = 16 it was the clock's critical path). An
//! axis that is ready stays ready until its `go` (only a flush empties an idle axis's
//! FIFO, and a step generator ignores `go` with its FIFO empty).
//! Used by the TDM core and by the non-TDM baseline, so both release alike.

use rust_hdl::prelude::*;

#[derive(LogicBlock, Default)]
pub struct SyncStart<const K: usize> {
    pub clock: Signal<In, Clock>,
    pub reset: Signal<In, Bit>,
    pub start: Signal<In, Bit>,
    pub start_mask: Signal<In, Bits<K>>,
    pub ready: Signal<In, Bits<K>>,
    pub empty: Signal<In, Bits<K>>,
    pub go: Signal<Out, Bits<K>>,
    pub failed: Signal<Out, Bit>,
    pending: DFF<Bits<K>>,
    go_q: DFF<Bits<K>>,
    fire: Signal<Local, Bit>,
    stuck: Signal<Local, Bit>,
}

impl<const K: usize> Logic for SyncStart<K> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, pending, go_q);
        self.fire.next = (self.pending.q.val() != 0) & (!self.pending.q.val() | self.ready.val()).all();
        self.stuck.next = (self.pending.q.val() & self.empty.val()).any();
        self.go.next = self.go_q.q.val();
        self.go_q.d.next = 0.into();
        self.failed.next = false;
        if self.fire.val() {
            self.go_q.d.next = self.pending.q.val();
            self.pending.d.next = 0.into();
        }
        if self.stuck.val() {
            self.failed.next = true;
            self.pending.d.next = 0.into();
        }
        if self.start.val() {
            self.pending.d.next = self.start_mask.val();
        }
        if self.reset.val() {
            self.pending.d.next = 0.into();
            self.go_q.d.next = 0.into();
        }
    }
}
