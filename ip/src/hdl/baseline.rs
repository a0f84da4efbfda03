//! The non-TDM baseline: K one-axis cores, each with its own scheduler and its own
//! multiply / divide / square-root unit, behind the same ports as [`TdmCore`].
//!
//! It exists only to measure what time-division multiplexing saves (the sweep), so
//! it reuses the TDM core itself rather than a copy: each axis is a `TdmCore<1, ..>`.
//! Commands are routed by `cmd_axis`; one [`SyncStart`] releases the masked axes on
//! the same edge through each core's `ext_go`, exactly as the TDM core's own does.
//! `fsm_state` shows axis 0's scheduler.

use super::bit_insert::{BitInsert, BitPick};
use super::axis_bank::LATCH_BITS;
use super::core::{TdmCore, STATE_BITS};
use super::poly_lane::POLY_EXTRA_BITS;
use super::sync_start::SyncStart;
use rust_hdl::prelude::*;

#[derive(LogicBlock)]
pub struct Baseline<const K: usize, const R: usize, const DEPTH: usize, const QDEPTH: usize, const S: usize = 0> {
    pub clock: Signal<In, Clock>,
    pub reset: Signal<In, Bit>,
    pub cmd_valid: Signal<In, Bit>,
    pub cmd_axis: Signal<In, Bits<8>>,
    pub cmd_v0: Signal<In, Bits<32>>,
    pub cmd_t: Signal<In, Bits<32>>,
    pub cmd_steps: Signal<In, Bits<32>>,
    /// Ignored (the baseline has no S-curve option); as [`TdmCore`]'s.
    pub cmd_extra: Signal<In, Bits<POLY_EXTRA_BITS>>,
    pub cmd_ready: Signal<Out, Bit>,
    pub cmd_error: Signal<Out, Bit>,
    pub abort: Signal<In, Bit>,
    /// Per-axis stops, each to its one-axis core.
    pub stop_axes: Signal<In, Bits<K>>,
    stop_pick: [BitPick<K>; K],
    /// Controlled stops and their deceleration, each to its one-axis core.
    pub cstop_axes: Signal<In, Bits<K>>,
    pub decel: Signal<In, Bits<32>>,
    cstop_pick: [BitPick<K>; K],
    pub start: Signal<In, Bit>,
    pub start_mask: Signal<In, Bits<K>>,
    pub ready: Signal<Out, Bits<K>>,
    pub ext_go: Signal<In, Bits<K>>,
    /// As the TDM core's: toggles on each cancelled START.
    pub start_failed: Signal<Out, Bit>,
    fail_tog: DFF<Bit>,
    pub step: Signal<Out, Bits<K>>,
    pub dir: Signal<Out, Bits<K>>,
    pub underrun: Signal<Out, Bits<K>>,
    pub active: Signal<Out, Bits<K>>,
    pub busy: Signal<Out, Bits<K>>,
    pub sel_axis: Signal<In, Bits<8>>,
    pub sel_position: Signal<Out, Bits<32>>,
    pub sel_queue: Signal<Out, Bits<8>>,
    pub sel_fifo: Signal<Out, Bits<8>>,
    pub sel_taken: Signal<Out, Bits<8>>,
    pub sel_done: Signal<Out, Bits<8>>,
    pub sel_underruns: Signal<Out, Bits<8>>,
    pub sel_busy: Signal<Out, Bit>,
    pub fsm_state: Signal<Out, Bits<STATE_BITS>>,
    pub high_min: Signal<In, Bits<16>>,
    pub low_min: Signal<In, Bits<16>>,
    /// Position latches: not in the baseline (`lsel_word` reads 0).
    pub home_latch: Signal<In, Bits<K>>,
    pub probe_latch: Signal<In, Bit>,
    pub lsel_axis: Signal<In, Bits<8>>,
    pub lsel_word: Signal<Out, Bits<LATCH_BITS>>,
    /// Encoder feedback: not in the baseline (`epos` reads 0).
    pub epos_axis: Signal<In, Bits<4>>,
    pub epos: Signal<Out, Bits<32>>,
    cores: [TdmCore<1, R, DEPTH, QDEPTH>; K],
    sync: SyncStart<K>,
    step_bus: [BitInsert<K>; K],
    dir_bus: [BitInsert<K>; K],
    under_bus: [BitInsert<K>; K],
    active_bus: [BitInsert<K>; K],
    busy_bus: [BitInsert<K>; K],
    ready_bus: [BitInsert<K>; K],
    go_pick: [BitPick<K>; K],
    cmd_err: DFF<Bit>,
    c_last_axis: Constant<Bits<8>>,
}

impl<const K: usize, const R: usize, const DEPTH: usize, const QDEPTH: usize, const S: usize> Baseline<K, R, DEPTH, QDEPTH, S> {
    /// As [`TdmCore::with_axis_stops`]: each one-axis core's stop works.
    pub fn with_axis_stops(mut self) -> Self {
        self.cores = self.cores.map(|c| c.with_axis_stops());
        self
    }

    /// Each one-axis core with the controlled stop (and the per-axis stop).
    pub fn with_controlled_stop(mut self) -> Self {
        self.cores = self.cores.map(|c| c.with_controlled_stop());
        self
    }

    pub fn new() -> Self {
        assert!(S == 0, "Baseline: no S-curve option (S = {S})");
        assert!((1..=64).contains(&K), "Baseline: K = {K} outside 1..=64");
        Baseline {
            clock: Default::default(),
            reset: Default::default(),
            cmd_valid: Default::default(),
            cmd_axis: Default::default(),
            cmd_v0: Default::default(),
            cmd_t: Default::default(),
            cmd_steps: Default::default(),
            cmd_extra: Default::default(),
            cmd_ready: Default::default(),
            cmd_error: Default::default(),
            abort: Default::default(),
            stop_axes: Default::default(),
            stop_pick: std::array::from_fn(BitPick::new),
            cstop_axes: Default::default(),
            decel: Default::default(),
            cstop_pick: std::array::from_fn(BitPick::new),
            start: Default::default(),
            start_mask: Default::default(),
            ready: Default::default(),
            ext_go: Default::default(),
            step: Default::default(),
            dir: Default::default(),
            underrun: Default::default(),
            active: Default::default(),
            busy: Default::default(),
            sel_axis: Default::default(),
            sel_position: Default::default(),
            sel_queue: Default::default(),
            sel_fifo: Default::default(),
            sel_taken: Default::default(),
            sel_done: Default::default(),
            sel_underruns: Default::default(),
            sel_busy: Default::default(),
            fsm_state: Default::default(),
            high_min: Default::default(),
            low_min: Default::default(),
            home_latch: Default::default(),
            probe_latch: Default::default(),
            lsel_axis: Default::default(),
            lsel_word: Default::default(),
            epos_axis: Default::default(),
            epos: Default::default(),
            start_failed: Default::default(),
            fail_tog: Default::default(),
            cores: std::array::from_fn(|_| TdmCore::new()),
            sync: Default::default(),
            step_bus: std::array::from_fn(BitInsert::new),
            dir_bus: std::array::from_fn(BitInsert::new),
            under_bus: std::array::from_fn(BitInsert::new),
            active_bus: std::array::from_fn(BitInsert::new),
            busy_bus: std::array::from_fn(BitInsert::new),
            ready_bus: std::array::from_fn(BitInsert::new),
            go_pick: std::array::from_fn(BitPick::new),
            cmd_err: Default::default(),
            c_last_axis: Constant::new(((K - 1) as u64).into()),
        }
    }

    core_connect_ports!();
}

impl<const K: usize, const R: usize, const DEPTH: usize, const QDEPTH: usize, const S: usize> Logic for Baseline<K, R, DEPTH, QDEPTH, S> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, cmd_err, fail_tog);
        self.sync.clock.next = self.clock.val();
        self.sync.reset.next = self.reset.val() | self.abort.val();
        self.sync.start.next = self.start.val();
        self.sync.start_mask.next = self.start_mask.val();
        self.fail_tog.d.next = self.fail_tog.q.val() ^ self.sync.failed.val();
        if self.reset.val() {
            self.fail_tog.d.next = false;
        }
        self.start_failed.next = self.fail_tog.q.val();
        self.cmd_ready.next = true;
        self.cmd_error.next = self.cmd_err.q.val();
        self.fsm_state.next = self.cores[0].fsm_state.val();
        self.sel_position.next = 0.into();
        self.sel_queue.next = 0.into();
        self.sel_fifo.next = 0.into();
        self.sel_taken.next = 0.into();
        self.sel_done.next = 0.into();
        self.sel_underruns.next = 0.into();
        self.sel_busy.next = false;
        self.lsel_word.next = 0.into();
        self.epos.next = 0.into();
        for i in 0..K {
            self.cores[i].home_latch.next = 0.into();
            self.cores[i].probe_latch.next = false;
            self.cores[i].lsel_axis.next = 0.into();
            self.cores[i].epos_axis.next = 0.into();
            self.cores[i].abort.next = self.abort.val();
            self.stop_pick[i].bus.next = self.stop_axes.val();
            self.cores[i].stop_axes.next = self.stop_pick[i].value.val().into();
            self.cstop_pick[i].bus.next = self.cstop_axes.val();
            self.cores[i].cstop_axes.next = self.cstop_pick[i].value.val().into();
            self.cores[i].decel.next = self.decel.val();
            self.cores[i].high_min.next = self.high_min.val();
            self.cores[i].low_min.next = self.low_min.val();
            self.cores[i].clock.next = self.clock.val();
            self.cores[i].reset.next = self.reset.val();
            self.cores[i].cmd_valid.next = self.cmd_valid.val() & (self.cmd_axis.val().index() == i);
            self.cores[i].cmd_axis.next = 0.into();
            self.cores[i].cmd_v0.next = self.cmd_v0.val();
            self.cores[i].cmd_t.next = self.cmd_t.val();
            self.cores[i].cmd_steps.next = self.cmd_steps.val();
            self.cores[i].cmd_extra.next = self.cmd_extra.val();
            self.cores[i].start.next = false;
            self.cores[i].start_mask.next = 0.into();
            self.go_pick[i].bus.next = self.sync.go.val() | self.ext_go.val();
            self.cores[i].ext_go.next = self.go_pick[i].value.val().into();
            self.cores[i].sel_axis.next = 0.into();
            if self.cmd_axis.val().index() == i {
                self.cmd_ready.next = self.cores[i].cmd_ready.val();
            }
            if self.sel_axis.val().index() == i {
                self.sel_position.next = self.cores[i].sel_position.val();
                self.sel_queue.next = self.cores[i].sel_queue.val();
                self.sel_fifo.next = self.cores[i].sel_fifo.val();
                self.sel_taken.next = self.cores[i].sel_taken.val();
                self.sel_done.next = self.cores[i].sel_done.val();
                self.sel_underruns.next = self.cores[i].sel_underruns.val();
                self.sel_busy.next = self.cores[i].sel_busy.val();
            }
            self.step_bus[i].value.next = self.cores[i].step.val().any();
            self.dir_bus[i].value.next = self.cores[i].dir.val().any();
            self.under_bus[i].value.next = self.cores[i].underrun.val().any();
            self.active_bus[i].value.next = self.cores[i].active.val().any();
            self.busy_bus[i].value.next = self.cores[i].busy.val().any();
            self.ready_bus[i].value.next = self.cores[i].ready.val().any();
        }
        self.step_bus[0].bus_in.next = 0.into();
        self.dir_bus[0].bus_in.next = 0.into();
        self.under_bus[0].bus_in.next = 0.into();
        self.active_bus[0].bus_in.next = 0.into();
        self.busy_bus[0].bus_in.next = 0.into();
        self.ready_bus[0].bus_in.next = 0.into();
        for i in 1..K {
            self.step_bus[i].bus_in.next = self.step_bus[i - 1].bus_out.val();
            self.dir_bus[i].bus_in.next = self.dir_bus[i - 1].bus_out.val();
            self.under_bus[i].bus_in.next = self.under_bus[i - 1].bus_out.val();
            self.active_bus[i].bus_in.next = self.active_bus[i - 1].bus_out.val();
            self.busy_bus[i].bus_in.next = self.busy_bus[i - 1].bus_out.val();
            self.ready_bus[i].bus_in.next = self.ready_bus[i - 1].bus_out.val();
        }
        // The last element of each chain holds the whole bus (last assignment wins).
        for i in 0..K {
            self.step.next = self.step_bus[i].bus_out.val();
            self.dir.next = self.dir_bus[i].bus_out.val();
            self.underrun.next = self.under_bus[i].bus_out.val();
            self.active.next = self.active_bus[i].bus_out.val();
            self.busy.next = self.busy_bus[i].bus_out.val();
            self.ready.next = self.ready_bus[i].bus_out.val();
            self.sync.ready.next = self.ready_bus[i].bus_out.val();
            self.sync.empty.next = !(self.ready_bus[i].bus_out.val() | self.busy_bus[i].bus_out.val());
        }
        if self.cmd_axis.val() > self.c_last_axis.val() {
            self.cmd_ready.next = true;
            if self.cmd_valid.val() {
                self.cmd_err.d.next = true;
            }
        }
        if self.reset.val() {
            self.cmd_err.d.next = false;
        }
    }
}
