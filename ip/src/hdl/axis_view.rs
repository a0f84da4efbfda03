//! The scheduler's view of the axes: every axis's context flags ([`AxisContext`]) and
//! what PICK decides from, axis m's flags registered a cycle ahead.
//!
//! **Context flags.** Axis m's flags are written by the scheduler's strobes for axis m
//! (`m`): `we` (a step's commit: the current kind), `nwe` (a setup's commit into the
//! next slot: its kind and dwell flag), `promote`, `cut` (a controlled stop), with
//! `new_kind` and `new_dwell`; `axis_reset` empties axis m's two slots, `abort` every
//! axis's (both with `reset`). Latency 1, as [`AxisContext`].
//!
//! **PICK's inputs** (`pk_*`). Every cycle axis m + 1's (`next_m`) flags go through
//! K:1 multiplexers into registers: its kind, its next slot's valid and dwell flags,
//! its slot, its queue not empty (bit of `nonempty`), its FIFO full (bit of `full`),
//! its stop requests (bits of `stop_all`, `cs_pend`, `cd_pend`), and `all_sat`. The
//! scheduler moves m to m + 1 on every way into PICK, so in PICK the registers hold
//! axis m's flags from one cycle earlier (latency 1; see [`super::core::TdmCore`] for
//! why that is exact or safe). K = 1 gives the flags directly (latency 0): axis m + 1
//! is axis m, which the state before PICK may just have changed. The stop requests
//! (`pk_stop`, `pk_cs`, `pk_cd`) come from the registers at every K: at K = 1 the
//! scheduler reads its own requests directly, since an output here that followed
//! `stop_all` combinationally would close a loop between the two blocks' processes
//! (Verilator's UNOPTFLAT). `reset` loads the registers with an idle axis 0 (nothing
//! to do, FIFO full).
//!
//! **Other outputs.** `slots`: bit i is axis i's slot, from registers only (the
//! scheduler picks axis m + 1's for the context memory's next read address: an output
//! that depended on `next_m` would close a loop between the two blocks' combinational
//! processes, which Verilator's lint reports as UNOPTFLAT). `pending`: bit i when axis i has work not yet turned
//! into period entries (a current or next segment, a queued one, or its stop ramp being
//! formed: `cs_act` on axis m).
//!
//! The block holds what the scheduler (in [`super::core::TdmCore`]) keeps per axis in
//! registers; its test is the core's (tests/hdl_core.rs, three ways against the model).

use super::bit_insert::{BitInsert, BitPick};
use super::context::AxisContext;
use rust_hdl::prelude::*;

#[derive(LogicBlock)]
pub struct AxisView<const K: usize> {
    pub clock: Signal<In, Clock>,
    pub reset: Signal<In, Bit>,
    pub abort: Signal<In, Bit>,
    /// Axis m (the writes) and axis m + 1 (the flags registered for the next PICK).
    pub m: Signal<In, Bits<8>>,
    pub next_m: Signal<In, Bits<8>>,
    pub we: Signal<In, Bit>,
    pub nwe: Signal<In, Bit>,
    pub promote: Signal<In, Bit>,
    pub cut: Signal<In, Bit>,
    pub axis_reset: Signal<In, Bit>,
    pub new_kind: Signal<In, Bits<2>>,
    pub new_dwell: Signal<In, Bit>,
    pub cs_act: Signal<In, Bit>,
    pub nonempty: Signal<In, Bits<K>>,
    pub full: Signal<In, Bits<K>>,
    pub all_sat: Signal<In, Bit>,
    pub stop_all: Signal<In, Bits<K>>,
    pub cs_pend: Signal<In, Bits<K>>,
    pub cd_pend: Signal<In, Bits<K>>,
    pub pk_kind: Signal<Out, Bits<2>>,
    pub pk_queued: Signal<Out, Bit>,
    pub pk_full: Signal<Out, Bit>,
    pub pk_next_valid: Signal<Out, Bit>,
    pub pk_next_dwell: Signal<Out, Bit>,
    pub pk_slot: Signal<Out, Bit>,
    pub pk_sat: Signal<Out, Bit>,
    pub pk_stop: Signal<Out, Bit>,
    pub pk_cs: Signal<Out, Bit>,
    pub pk_cd: Signal<Out, Bit>,
    pub slots: Signal<Out, Bits<K>>,
    pub pending: Signal<Out, Bits<K>>,
    /// Per-axis context flags; public so that simulations can inspect them.
    pub ctx: [AxisContext; K],
    q_pick: [BitPick<K>; K],
    full_pick: [BitPick<K>; K],
    pend_bus: [BitInsert<K>; K],
    slot_bus: [BitInsert<K>; K],
    slot_nm: Signal<Local, Bit>,
    nx_kind: Signal<Local, Bits<2>>,
    nx_queued: Signal<Local, Bit>,
    nx_full: Signal<Local, Bit>,
    nx_next_valid: Signal<Local, Bit>,
    nx_next_dwell: Signal<Local, Bit>,
    /// `stop_all`, `cs_pend`, `cd_pend` shifted down by axis m + 1 (bit 0 is its
    /// request: a shift, not a BitPick, whose bus would be built and read here).
    stop_sh: Signal<Local, Bits<K>>,
    cs_sh: Signal<Local, Bits<K>>,
    cd_sh: Signal<Local, Bits<K>>,
    nx_stop: Signal<Local, Bit>,
    nx_cs: Signal<Local, Bit>,
    nx_cd: Signal<Local, Bit>,
    flush: Signal<Local, Bit>,
    pf_kind: DFF<Bits<2>>,
    pf_queued: DFF<Bit>,
    pf_full: DFF<Bit>,
    pf_next_valid: DFF<Bit>,
    pf_next_dwell: DFF<Bit>,
    pf_slot: DFF<Bit>,
    pf_sat: DFF<Bit>,
    pf_stop: DFF<Bit>,
    pf_cs: DFF<Bit>,
    pf_cd: DFF<Bit>,
    c_one_k: Constant<Bits<K>>,
    c_single: Constant<Bit>,
    /// The stop requests and the controlled stop's strobes are used only when the core
    /// is built with them: constants of this block (set by [`AxisView::with_axis_stops`]
    /// and [`AxisView::with_controlled_stop`]), so that yosys folds the unused logic
    /// away here, which a constant reaching the block through a port does not ensure.
    c_stops: Constant<Bit>,
    c_cs: Constant<Bit>,
}

impl<const K: usize> AxisView<K> {
    /// The view with `stop_all` working (the core's `with_axis_stops`).
    pub fn with_axis_stops(mut self) -> Self {
        self.c_stops = Constant::new(true);
        self
    }

    /// The view with the controlled stop's inputs working (`cs_pend`, `cd_pend`, `cut`,
    /// `cs_act`; the core's `with_controlled_stop`).
    pub fn with_controlled_stop(mut self) -> Self {
        self.c_cs = Constant::new(true);
        self
    }
}

impl<const K: usize> Default for AxisView<K> {
    fn default() -> Self {
        AxisView {
            clock: Default::default(),
            reset: Default::default(),
            abort: Default::default(),
            m: Default::default(),
            next_m: Default::default(),
            we: Default::default(),
            nwe: Default::default(),
            promote: Default::default(),
            cut: Default::default(),
            axis_reset: Default::default(),
            new_kind: Default::default(),
            new_dwell: Default::default(),
            cs_act: Default::default(),
            nonempty: Default::default(),
            full: Default::default(),
            all_sat: Default::default(),
            stop_all: Default::default(),
            cs_pend: Default::default(),
            cd_pend: Default::default(),
            pk_kind: Default::default(),
            pk_queued: Default::default(),
            pk_full: Default::default(),
            pk_next_valid: Default::default(),
            pk_next_dwell: Default::default(),
            pk_slot: Default::default(),
            pk_sat: Default::default(),
            pk_stop: Default::default(),
            pk_cs: Default::default(),
            pk_cd: Default::default(),
            slots: Default::default(),
            slot_nm: Default::default(),
            pending: Default::default(),
            ctx: std::array::from_fn(|_| Default::default()),
            q_pick: std::array::from_fn(BitPick::new),
            full_pick: std::array::from_fn(BitPick::new),
            pend_bus: std::array::from_fn(BitInsert::new),
            slot_bus: std::array::from_fn(BitInsert::new),
            nx_kind: Default::default(),
            nx_queued: Default::default(),
            nx_full: Default::default(),
            nx_next_valid: Default::default(),
            nx_next_dwell: Default::default(),
            stop_sh: Default::default(),
            cs_sh: Default::default(),
            cd_sh: Default::default(),
            nx_stop: Default::default(),
            nx_cs: Default::default(),
            nx_cd: Default::default(),
            flush: Default::default(),
            pf_kind: Default::default(),
            pf_queued: Default::default(),
            pf_full: Default::default(),
            pf_next_valid: Default::default(),
            pf_next_dwell: Default::default(),
            pf_slot: Default::default(),
            pf_sat: Default::default(),
            pf_stop: Default::default(),
            pf_cs: Default::default(),
            pf_cd: Default::default(),
            c_one_k: Constant::new(1.into()),
            c_single: Constant::new(K == 1),
            c_stops: Constant::new(false),
            c_cs: Constant::new(false),
        }
    }
}

impl<const K: usize> Logic for AxisView<K> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, pf_kind, pf_queued, pf_full, pf_next_valid, pf_next_dwell, pf_slot, pf_sat, pf_stop, pf_cs, pf_cd);
        self.flush.next = self.reset.val() | self.abort.val();
        // ---- axis m + 1 through the multiplexers ------------------------------
        self.nx_kind.next = 0.into();
        self.nx_queued.next = false;
        self.nx_full.next = true;
        self.nx_next_valid.next = false;
        self.nx_next_dwell.next = false;
        self.slot_nm.next = false;
        for i in 0..K {
            if self.next_m.val().index() == i {
                self.nx_kind.next = self.ctx[i].kind.val();
                self.nx_queued.next = self.q_pick[i].value.val();
                self.nx_full.next = self.full_pick[i].value.val();
                self.nx_next_valid.next = self.ctx[i].next_valid.val();
                self.nx_next_dwell.next = self.ctx[i].next_dwell.val();
                self.slot_nm.next = self.ctx[i].slot.val();
            }
        }
        // (Bit 0 by a mask: at K = 1 the Verilog is a scalar, which takes no select.)
        self.stop_sh.next = self.stop_all.val() >> self.next_m.val();
        self.nx_stop.next = (self.stop_sh.val() & self.c_one_k.val()).any() & self.c_stops.val();
        self.cs_sh.next = self.cs_pend.val() >> self.next_m.val();
        self.nx_cs.next = (self.cs_sh.val() & self.c_one_k.val()).any() & self.c_cs.val();
        self.cd_sh.next = self.cd_pend.val() >> self.next_m.val();
        self.nx_cd.next = (self.cd_sh.val() & self.c_one_k.val()).any() & self.c_cs.val();
        self.pf_kind.d.next = self.nx_kind.val();
        self.pf_queued.d.next = self.nx_queued.val();
        self.pf_full.d.next = self.nx_full.val();
        self.pf_next_valid.d.next = self.nx_next_valid.val();
        self.pf_next_dwell.d.next = self.nx_next_dwell.val();
        self.pf_slot.d.next = self.slot_nm.val();
        self.pf_sat.d.next = self.all_sat.val();
        self.pf_stop.d.next = self.nx_stop.val();
        self.pf_cs.d.next = self.nx_cs.val();
        self.pf_cd.d.next = self.nx_cd.val();
        if self.c_single.val() {
            self.pk_kind.next = self.nx_kind.val();
            self.pk_queued.next = self.nx_queued.val();
            self.pk_full.next = self.nx_full.val();
            self.pk_next_valid.next = self.nx_next_valid.val();
            self.pk_next_dwell.next = self.nx_next_dwell.val();
            self.pk_slot.next = self.slot_nm.val();
            self.pk_sat.next = self.all_sat.val();
        } else {
            self.pk_kind.next = self.pf_kind.q.val();
            self.pk_queued.next = self.pf_queued.q.val();
            self.pk_full.next = self.pf_full.q.val();
            self.pk_next_valid.next = self.pf_next_valid.q.val();
            self.pk_next_dwell.next = self.pf_next_dwell.q.val();
            self.pk_slot.next = self.pf_slot.q.val();
            self.pk_sat.next = self.pf_sat.q.val();
        }
        // The stop requests from registers at every K (the scheduler picks axis m's
        // itself at K = 1: see the module comment).
        self.pk_stop.next = self.pf_stop.q.val();
        self.pk_cs.next = self.pf_cs.q.val();
        self.pk_cd.next = self.pf_cd.q.val();

        // ---- per-axis contexts and the pending bus ----------------------------
        for i in 0..K {
            self.q_pick[i].bus.next = self.nonempty.val();
            self.full_pick[i].bus.next = self.full.val();
            self.pend_bus[i].value.next = (self.ctx[i].kind.val() != 0)
                | self.ctx[i].next_valid.val()
                | self.q_pick[i].value.val()
                | (self.cs_act.val() & self.c_cs.val() & (self.m.val().index() == i));
            self.ctx[i].clock.next = self.clock.val();
            self.ctx[i].reset.next = self.flush.val() | (self.axis_reset.val() & (self.m.val().index() == i));
            self.ctx[i].we.next = self.we.val() & (self.m.val().index() == i);
            self.ctx[i].nwe.next = self.nwe.val() & (self.m.val().index() == i);
            self.ctx[i].promote.next = self.promote.val() & (self.m.val().index() == i);
            self.ctx[i].cut.next = self.cut.val() & self.c_cs.val() & (self.m.val().index() == i);
            self.ctx[i].new_dwell.next = self.new_dwell.val();
            self.ctx[i].new_kind.next = self.new_kind.val();
        }
        for i in 0..K {
            self.slot_bus[i].value.next = self.ctx[i].slot.val();
        }
        self.pend_bus[0].bus_in.next = 0.into();
        self.slot_bus[0].bus_in.next = 0.into();
        for i in 1..K {
            self.pend_bus[i].bus_in.next = self.pend_bus[i - 1].bus_out.val();
            self.slot_bus[i].bus_in.next = self.slot_bus[i - 1].bus_out.val();
        }
        // The last element of a chain holds the whole bus (last assignment wins).
        for i in 0..K {
            self.pending.next = self.pend_bus[i].bus_out.val();
            self.slots.next = self.slot_bus[i].bus_out.val();
        }
        if self.reset.val() {
            // Axis 0 after reset: idle, nothing queued (PICK moves on).
            self.pf_kind.d.next = 0.into();
            self.pf_queued.d.next = false;
            self.pf_full.d.next = true;
            self.pf_next_valid.d.next = false;
            self.pf_next_dwell.d.next = false;
            self.pf_slot.d.next = false;
            self.pf_sat.d.next = false;
            self.pf_stop.d.next = false;
            self.pf_cs.d.next = false;
            self.pf_cd.d.next = false;
        }
    }
}
