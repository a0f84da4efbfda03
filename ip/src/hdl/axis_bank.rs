//! The axes' back ends: the pulse stage, K period FIFOs with their step generators
//! ([`StepAxis`]), the synchronised start ([`SyncStart`]) and the K-bit status buses.
//! Everything per axis that is not the scheduler's: one more axis costs one
//! `StepAxis` and a bit of each bus, no arithmetic.
//!
//! Ports and latency:
//! * **Entries** (`push`, `push_axis`, `entry`): the scheduler's period entry, bits
//!   51..35 ignored. It goes through the [`PulseStage`] (which writes the STEP high time
//!   from `high_min` and `low_min`, and the one-tick flag) and is written into axis `push_axis`'s FIFO 2
//!   cycles later.
//! * **Coming** (`pending`, bit i): axis i has work the scheduler has not yet turned
//!   into entries (a segment in progress, set up, or queued). An axis's `more` (the
//!   step generator's underrun test) is `pending` or an entry of its own in flight
//!   (offered now, or in either pulse stage), and its `busy` is `more`, an entry in its
//!   FIFO (a move not yet released counts), moving, or
//!   STEP high.
//! * **Release**: `start` with `start_mask` arms the [`SyncStart`] (`go` 2 cycles after
//!   the last masked axis is ready, `failed` one cycle when it cannot complete);
//!   `ext_go` releases axes at once (the baseline's shared start).
//! * **Flags** (registers or combinations of them, no input to output path except
//!   `all_sat`'s from `pending`): `step`, `dir`, `underrun`, `active`, `busy`,
//!   `ready` (FIFO not empty and not yet moving) and `full` (the FIFO holds DEPTH
//!   entries, a cycle late: see [`StepAxis`]); `all_sat`: every axis has a full FIFO
//!   or nothing to compute.
//! * **Status** of axis `sel_axis` (multiplexers): position, FIFO level, segments
//!   done, underruns begun, busy.
//! * **Position latches** (machine I/O): at a clock edge where `home_latch` bit i (or
//!   `probe_latch`, every axis) is high, axis i's home (probe) latch takes its position
//!   as it was before that edge, the count of the STEP rising edges at earlier edges,
//!   and the latch's toggle flips. `lsel_word` is axis `lsel_axis`'s latches
//!   ([`LATCH_BITS`]: home position 31..0, probe position 63..32, home toggle 64,
//!   probe toggle 65; a multiplexer). A core whose owner ties the strobes to 0 keeps
//!   no latch: synthesis removes them (constant registers).
//! * `stop` (bit i, a level): axis i as under an abort while it is high: no further
//!   edge, its FIFO held empty (entries reaching it are dropped).
//! * `abort` (one cycle): no further edge on any axis, the FIFOs and the pulse stage
//!   flushed; `reset` (synchronous): the axes stop (a pulse in flight finishes) and
//!   their counters and latches clear.

use super::bit_insert::{BitInsert, BitPick, FieldPlace};
use super::pulse_stage::PulseStage;
use super::ram_fifo::ENTRY_BITS;
use super::step_gen::StepAxis;
use super::sync_start::SyncStart;
use rust_hdl::prelude::*;

/// Width of a latch word (`lsel_word`): home position, probe position, their toggles.
pub const LATCH_BITS: usize = 66;

#[derive(LogicBlock)]
pub struct AxisBank<const K: usize, const DEPTH: usize> {
    pub clock: Signal<In, Clock>,
    pub reset: Signal<In, Bit>,
    pub abort: Signal<In, Bit>,
    pub stop: Signal<In, Bits<K>>,
    pub high_min: Signal<In, Bits<16>>,
    pub low_min: Signal<In, Bits<16>>,
    pub push: Signal<In, Bit>,
    pub push_axis: Signal<In, Bits<8>>,
    pub entry: Signal<In, Bits<ENTRY_BITS>>,
    pub pending: Signal<In, Bits<K>>,
    pub start: Signal<In, Bit>,
    pub start_mask: Signal<In, Bits<K>>,
    pub ext_go: Signal<In, Bits<K>>,
    pub failed: Signal<Out, Bit>,
    pub step: Signal<Out, Bits<K>>,
    pub dir: Signal<Out, Bits<K>>,
    pub underrun: Signal<Out, Bits<K>>,
    pub active: Signal<Out, Bits<K>>,
    /// Axis i runs an entry that ends with a step (not a dwell's): [`super::step_gen::StepGen::moving`].
    pub moving: Signal<Out, Bits<K>>,
    pub busy: Signal<Out, Bits<K>>,
    pub ready: Signal<Out, Bits<K>>,
    pub full: Signal<Out, Bits<K>>,
    pub all_sat: Signal<Out, Bit>,
    pub sel_axis: Signal<In, Bits<8>>,
    pub sel_position: Signal<Out, Bits<32>>,
    pub sel_fifo: Signal<Out, Bits<8>>,
    pub sel_done: Signal<Out, Bits<8>>,
    pub sel_underruns: Signal<Out, Bits<8>>,
    pub sel_busy: Signal<Out, Bit>,
    pub home_latch: Signal<In, Bits<K>>,
    pub probe_latch: Signal<In, Bit>,
    pub lsel_axis: Signal<In, Bits<8>>,
    pub lsel_word: Signal<Out, Bits<LATCH_BITS>>,
    /// Encoder feedback: axis `epos_axis`'s position on `epos` (combinational, a tree
    /// of multiplexers; tied to 0 and unread it costs nothing).
    pub epos_axis: Signal<In, Bits<4>>,
    pub epos: Signal<Out, Bits<32>>,
    /// Encoder feedback: every axis's position's low byte (byte a = axis a's; wires,
    /// for the index latches; unread it costs nothing).
    pub pos_low: Signal<Out, Bits<128>>,
    lpack: [FieldPlace<8, 128>; K],
    epack: [FieldPlace<32, 512>; K],
    e_all: Signal<Local, Bits<512>>,
    e_shift: Signal<Local, Bits<512>>,
    axes: [StepAxis<DEPTH>; K],
    home_q: [DFF<Bits<32>>; K],
    probe_q: [DFF<Bits<32>>; K],
    htog: [DFF<Bit>; K],
    ptog: [DFF<Bit>; K],
    hl_pick: [BitPick<K>; K],
    stop_pick: [BitPick<K>; K],
    pulse: PulseStage,
    sync: SyncStart<K>,
    step_bus: [BitInsert<K>; K],
    dir_bus: [BitInsert<K>; K],
    under_bus: [BitInsert<K>; K],
    active_bus: [BitInsert<K>; K],
    moving_bus: [BitInsert<K>; K],
    busy_bus: [BitInsert<K>; K],
    ready_bus: [BitInsert<K>; K],
    full_bus: [BitInsert<K>; K],
    sat_bus: [BitInsert<K>; K],
    go_pick: [BitPick<K>; K],
    pend_pick: [BitPick<K>; K],
    flush: Signal<Local, Bit>,
    /// Axis `lsel_axis`'s latches.
    l_home: Signal<Local, Bits<32>>,
    l_probe: Signal<Local, Bits<32>>,
    l_htog: Signal<Local, Bit>,
    l_ptog: Signal<Local, Bit>,
}

impl<const K: usize, const DEPTH: usize> Default for AxisBank<K, DEPTH> {
    fn default() -> Self {
        AxisBank {
            clock: Default::default(),
            reset: Default::default(),
            abort: Default::default(),
            stop: Default::default(),
            high_min: Default::default(),
            low_min: Default::default(),
            push: Default::default(),
            push_axis: Default::default(),
            entry: Default::default(),
            pending: Default::default(),
            start: Default::default(),
            start_mask: Default::default(),
            ext_go: Default::default(),
            failed: Default::default(),
            step: Default::default(),
            dir: Default::default(),
            underrun: Default::default(),
            active: Default::default(),
            moving: Default::default(),
            busy: Default::default(),
            ready: Default::default(),
            full: Default::default(),
            all_sat: Default::default(),
            sel_axis: Default::default(),
            sel_position: Default::default(),
            sel_fifo: Default::default(),
            sel_done: Default::default(),
            sel_underruns: Default::default(),
            sel_busy: Default::default(),
            home_latch: Default::default(),
            probe_latch: Default::default(),
            lsel_axis: Default::default(),
            lsel_word: Default::default(),
            epos_axis: Default::default(),
            epos: Default::default(),
            pos_low: Default::default(),
            lpack: std::array::from_fn(|i| FieldPlace::new(8 * i)),
            epack: std::array::from_fn(|i| FieldPlace::new(32 * i)),
            e_all: Default::default(),
            e_shift: Default::default(),
            axes: std::array::from_fn(|_| Default::default()),
            home_q: std::array::from_fn(|_| Default::default()),
            probe_q: std::array::from_fn(|_| Default::default()),
            htog: std::array::from_fn(|_| Default::default()),
            ptog: std::array::from_fn(|_| Default::default()),
            hl_pick: std::array::from_fn(BitPick::new),
            stop_pick: std::array::from_fn(BitPick::new),
            pulse: Default::default(),
            sync: Default::default(),
            step_bus: std::array::from_fn(BitInsert::new),
            dir_bus: std::array::from_fn(BitInsert::new),
            under_bus: std::array::from_fn(BitInsert::new),
            active_bus: std::array::from_fn(BitInsert::new),
            moving_bus: std::array::from_fn(BitInsert::new),
            busy_bus: std::array::from_fn(BitInsert::new),
            ready_bus: std::array::from_fn(BitInsert::new),
            full_bus: std::array::from_fn(BitInsert::new),
            sat_bus: std::array::from_fn(BitInsert::new),
            go_pick: std::array::from_fn(BitPick::new),
            pend_pick: std::array::from_fn(BitPick::new),
            flush: Default::default(),
            l_home: Default::default(),
            l_probe: Default::default(),
            l_htog: Default::default(),
            l_ptog: Default::default(),
        }
    }
}

impl<const K: usize, const DEPTH: usize> Logic for AxisBank<K, DEPTH> {
    #[hdl_gen]
    fn update(&mut self) {
        self.flush.next = self.reset.val() | self.abort.val();
        self.pulse.clock.next = self.clock.val();
        self.pulse.flush.next = self.flush.val();
        self.pulse.high_min.next = self.high_min.val();
        self.pulse.low_min.next = self.low_min.val();
        self.pulse.push_in.next = self.push.val();
        self.pulse.axis_in.next = self.push_axis.val();
        self.pulse.entry_in.next = self.entry.val();
        self.sync.clock.next = self.clock.val();
        self.sync.reset.next = self.flush.val();
        self.sync.start.next = self.start.val();
        self.sync.start_mask.next = self.start_mask.val();
        self.failed.next = self.sync.failed.val();
        self.sel_position.next = 0.into();
        self.sel_fifo.next = 0.into();
        self.sel_done.next = 0.into();
        self.sel_underruns.next = 0.into();
        self.sel_busy.next = false;
        self.l_home.next = 0.into();
        self.l_probe.next = 0.into();
        self.l_htog.next = false;
        self.l_ptog.next = false;
        for i in 0..K {
            // Position latches.
            self.home_q[i].clock.next = self.clock.val();
            self.probe_q[i].clock.next = self.clock.val();
            self.htog[i].clock.next = self.clock.val();
            self.ptog[i].clock.next = self.clock.val();
            self.home_q[i].d.next = self.home_q[i].q.val();
            self.probe_q[i].d.next = self.probe_q[i].q.val();
            self.htog[i].d.next = self.htog[i].q.val();
            self.ptog[i].d.next = self.ptog[i].q.val();
            self.hl_pick[i].bus.next = self.home_latch.val();
            if self.hl_pick[i].value.val() {
                self.home_q[i].d.next = self.axes[i].position.val();
                self.htog[i].d.next = !self.htog[i].q.val();
            }
            if self.probe_latch.val() {
                self.probe_q[i].d.next = self.axes[i].position.val();
                self.ptog[i].d.next = !self.ptog[i].q.val();
            }
            if self.reset.val() {
                self.home_q[i].d.next = 0.into();
                self.probe_q[i].d.next = 0.into();
                self.htog[i].d.next = false;
                self.ptog[i].d.next = false;
            }
            // (The loop index cannot sit inside `bit_cast`'s arguments: rust-hdl
            // does not substitute it there.)
            if self.lsel_axis.val().index() == i {
                self.l_home.next = self.home_q[i].q.val();
                self.l_probe.next = self.probe_q[i].q.val();
                self.l_htog.next = self.htog[i].q.val();
                self.l_ptog.next = self.ptog[i].q.val();
            }
            self.axes[i].clock.next = self.clock.val();
            self.axes[i].reset.next = self.reset.val();
            self.stop_pick[i].bus.next = self.stop.val();
            self.axes[i].abort.next = self.abort.val() | self.stop_pick[i].value.val();
            self.axes[i].push.next = self.pulse.push_out.val() & (self.pulse.axis_out.val().index() == i);
            self.axes[i].entry_in.next = self.pulse.entry_out.val();
            self.pend_pick[i].bus.next = self.pending.val();
            self.axes[i].more.next = self.pend_pick[i].value.val()
                // An entry of axis i on its way to the FIFO: offered now, or in either
                // pulse stage.
                | (self.push.val() & (self.push_axis.val().index() == i))
                | (self.pulse.p0_valid.val() & (self.pulse.p0_axis.val().index() == i))
                | (self.pulse.p1_valid.val() & (self.pulse.p1_axis.val().index() == i));
            self.go_pick[i].bus.next = self.sync.go.val() | self.ext_go.val();
            self.axes[i].go.next = self.go_pick[i].value.val();
            self.step_bus[i].value.next = self.axes[i].step.val();
            self.dir_bus[i].value.next = self.axes[i].dir.val();
            self.under_bus[i].value.next = self.axes[i].underrun.val();
            self.active_bus[i].value.next = self.axes[i].active.val();
            self.moving_bus[i].value.next = self.axes[i].moving.val();
            self.busy_bus[i].value.next = self.axes[i].busy.val();
            self.full_bus[i].value.next = self.axes[i].full.val();
            // Satisfied: a full FIFO, or nothing to compute.
            self.sat_bus[i].value.next = self.axes[i].full.val() | !self.pend_pick[i].value.val();
            self.ready_bus[i].value.next = (self.axes[i].level.val() != 0) & !self.axes[i].active.val();
            if self.sel_axis.val().index() == i {
                self.sel_position.next = self.axes[i].position.val();
                self.sel_fifo.next = self.axes[i].level.val();
                self.sel_done.next = self.axes[i].done_count.val();
                self.sel_underruns.next = self.axes[i].under_count.val();
                self.sel_busy.next = self.axes[i].busy.val();
            }
        }
        self.step_bus[0].bus_in.next = 0.into();
        self.dir_bus[0].bus_in.next = 0.into();
        self.under_bus[0].bus_in.next = 0.into();
        self.active_bus[0].bus_in.next = 0.into();
        self.moving_bus[0].bus_in.next = 0.into();
        self.busy_bus[0].bus_in.next = 0.into();
        self.ready_bus[0].bus_in.next = 0.into();
        self.full_bus[0].bus_in.next = 0.into();
        self.sat_bus[0].bus_in.next = 0.into();
        for i in 1..K {
            self.step_bus[i].bus_in.next = self.step_bus[i - 1].bus_out.val();
            self.dir_bus[i].bus_in.next = self.dir_bus[i - 1].bus_out.val();
            self.under_bus[i].bus_in.next = self.under_bus[i - 1].bus_out.val();
            self.active_bus[i].bus_in.next = self.active_bus[i - 1].bus_out.val();
            self.moving_bus[i].bus_in.next = self.moving_bus[i - 1].bus_out.val();
            self.busy_bus[i].bus_in.next = self.busy_bus[i - 1].bus_out.val();
            self.ready_bus[i].bus_in.next = self.ready_bus[i - 1].bus_out.val();
            self.full_bus[i].bus_in.next = self.full_bus[i - 1].bus_out.val();
            self.sat_bus[i].bus_in.next = self.sat_bus[i - 1].bus_out.val();
        }
        // Axis `epos_axis`'s position: the positions packed at a stride of 32 bits,
        // picked by a shift (see `FieldPlace`).
        self.epack[0].bus_in.next = 0.into();
        self.lpack[0].bus_in.next = 0.into();
        for i in 1..K {
            self.epack[i].bus_in.next = self.epack[i - 1].bus_out.val();
            self.lpack[i].bus_in.next = self.lpack[i - 1].bus_out.val();
        }
        for i in 0..K {
            self.epack[i].value.next = self.axes[i].position.val();
            self.lpack[i].value.next = self.axes[i].position.val().get_bits::<8>(0);
            // (The last assignment, axis K − 1's, stands.)
            self.e_all.next = self.epack[i].bus_out.val();
            self.pos_low.next = self.lpack[i].bus_out.val();
        }
        self.e_shift.next = self.e_all.val() >> (bit_cast::<16, 4>(self.epos_axis.val()) << 5);
        self.epos.next = self.e_shift.val().get_bits::<32>(0);
        self.lsel_word.next = bit_cast::<LATCH_BITS, 32>(self.l_home.val())
            | (bit_cast::<LATCH_BITS, 32>(self.l_probe.val()) << 32)
            | (bit_cast::<LATCH_BITS, 1>(self.l_htog.val().into()) << 64)
            | (bit_cast::<LATCH_BITS, 1>(self.l_ptog.val().into()) << 65);
        // The last element of each chain holds the whole bus (last assignment wins).
        for i in 0..K {
            self.step.next = self.step_bus[i].bus_out.val();
            self.dir.next = self.dir_bus[i].bus_out.val();
            self.underrun.next = self.under_bus[i].bus_out.val();
            self.active.next = self.active_bus[i].bus_out.val();
            self.moving.next = self.moving_bus[i].bus_out.val();
            self.busy.next = self.busy_bus[i].bus_out.val();
            self.ready.next = self.ready_bus[i].bus_out.val();
            self.full.next = self.full_bus[i].bus_out.val();
            self.all_sat.next = self.sat_bus[i].bus_out.val().all();
            self.sync.ready.next = self.ready_bus[i].bus_out.val();
            self.sync.empty.next = !(self.ready_bus[i].bus_out.val() | self.busy_bus[i].bus_out.val());
        }
    }
}
