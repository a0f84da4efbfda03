//! The TDM core: K axes served by one shared multiply / divide / square-root unit,
//! scheduled round robin by a Gray-coded FSM (the paper's Fig. 7; docs/architecture.md).
//!
//! Per axis: a segment queue (`QDEPTH` × 96 bits, every axis's in one [`SegQueue`]), a
//! context (its flags in the [`AxisView`], its wide fields in the shared
//! [`ContextRam`]), and a period FIFO with its step generator (every axis's, with the
//! pulse stage and the synchronised start, in one [`AxisBank`]). Shared: the setup's
//! multipliers and divider ([`SetupPath`]) and one [`OffsetRoot`] (`R` bits per cycle
//! each), and the scheduler: this block holds the state register, the transitions and
//! the working copy of axis m's context; the blocks around it decode the state.
//!
//! **Scheduler.** In `PICK` it looks at axis m: if m has an active segment and room
//! in its period FIFO, it computes m's next period; else if m's segment is done and the
//! next is set up, it promotes it; else if m has a queued segment and no next one, it
//! sets it up into m's next slot (at once if m is idle, else ahead of time while every
//! axis's FIFO is full); else it moves to m + 1. After each piece of work it moves on.
//! PICK decides from axis m's flags registered in the cycle before (K ≥ 2: the
//! scheduler registers axis m + 1's flags every cycle, and every way into PICK moves
//! to m + 1), so no K:1 multiplexer sits between m and the next state; the queue count
//! and the FIFO's `full` may be a cycle old, which at worst skips an axis for a turn
//! or lets its FIFO reach DEPTH + 1 entries ([`super::step_gen::StepAxis`]). The setup and the
//! per-step work are exactly the reference model's (docs/model.md), which the tests
//! hold it to period by period. The working copy lives here rather than in its own
//! block because rust-hdl cannot pass arrays of wide ports between blocks.
//!
//! **Commands.** `cmd_valid` with `cmd_axis`, `cmd_v0` (Q0.32 rate), `cmd_t` (ticks)
//! and `cmd_steps` (signed) pushes a segment into that axis's queue when
//! `cmd_ready`. The core takes only valid, effective segments
//! ([`crate::model::Segment::validate`] passed, and [`crate::model::Segment::effective`]
//! applied): in the exported IP the push check ([`super::push_check::PushCheck`], bus
//! clock) rejects bad segments before they reach the command FIFO, so the core checks
//! nothing and a bad segment given to it directly runs undefined. A command to an
//! axis ≥ K is dropped and sets the sticky `cmd_error`.
//!
//! **Start.** `start` with `start_mask` arms a synchronised release ([`super::sync_start::SyncStart`], in the [`AxisBank`]):
//! the masked axes get `go` on the same clock edge once each is idle with its first
//! period ready. `ext_go` releases axes directly (the non-TDM baseline uses it to
//! release its one-axis cores together); `ready` says which axes could be released.
//!
//! **Abort.** `abort` (one cycle) is a hard stop of every axis: the segment queues,
//! next slots and period FIFOs empty, no further STEP edge rises (a pulse already high
//! keeps its high time), positions stay exact, and the scheduler waits in `S_DRAIN`
//! until the shared unit is idle before it takes new work.
//!
//! **Stop (per axis).** `stop_axes` bit i (a level) stops axis i as an abort stops
//! every axis, and leaves the others running: at once its step generator raises no
//! further edge (a pulse already high keeps its high time) and its period FIFO is held
//! empty; the request is kept (`stop_pend`) until the scheduler next reaches the axis in
//! PICK, where, with nothing of the axis in the shared unit, it empties the axis's
//! queue (counted as taken), clears its context (current and next segment) and
//! moves on; the FIFO stays held one cycle more, for the entry still in the pulse
//! stage. The axis is idle after that, with an exact position, and takes new segments
//! once the bit is low. Only a core built [`TdmCore::with_axis_stops`] has it (the
//! machine I/O's); in one built with `new` the input is ignored and costs nothing.
//!
//! **Controlled stop (per axis).** `cstop_axes` bit i (a pulse; a level repeats it)
//! decelerates axis i to rest at `decel` (a = `decel`/2^57 steps/tick²) with a segment
//! the core forms itself ([`crate::model::stop`]). The request waits in the
//! [`StopRamp`] until PICK reaches the axis; there the axis's queue is dropped (counted
//! as taken) with its next slot, and its current segment ends after the periods already
//! computed (they stay in the period FIFO and run); if the axis had more to compute, the
//! scheduler forms the ramp from the last period pushed, Δ: v0 = ⌊2^32/(Δ + 1)⌋ and n =
//! ⌊v0²/(2^8·decel)⌋ + 1 by two divides, T = 2n(Δ + 1) by a product, and sets it up as a
//! decelerating segment into the next slot ([`t_stop_form`] cycles from PICK to its
//! commit), to run after those periods. An axis that is not moving when the request
//! waits (idle, not yet released, or in a dwell) is at rest: the request becomes its
//! hard stop (above). Segments pushed after the request queue behind the ramp. Only a
//! core built [`TdmCore::with_controlled_stop`] has it.
//!
//! **S-curve lane** (S = 1; the default S = 0 has none and costs nothing). A
//! polynomial segment ([`crate::model::poly::PolySegment`]) is pushed with its fields
//! in `cmd_extra` (v1, A', the flag) and queued like any other; the [`PolyLane`]
//! keeps those fields beside the queue and every axis's polynomial flags. S_ISSUE_VT
//! (the cycle after S_CHECK) sends a polynomial head to `Y_SETUP`, which asks the lane's unit to set it up into
//! axis m's next slot ([`T_POLY_SETUP`] cycles in all); PICK asks it for the next
//! period of a running polynomial segment ([`t_poly_step`]) and waits in `Y_WAIT`. The
//! context holds such a segment as kind 1 (running); the periods go through the FIFO
//! entry and the commit as a trapezoid's do, so stops, the start and the counters
//! treat both kinds alike (a controlled stop forms a trapezoid ramp from the last
//! period). Every use is gated by the localparam `c_poly`.
//!
//! **Counters** for the register bus (8 bits each, wrapping, per axis, read through
//! `sel_axis`): segments taken from the queue (`sel_taken`, counting the ones an abort
//! flushes), done (`sel_done`: their last period ended) and underruns begun
//! (`sel_underruns`).

use super::axis_view::AxisView;
use super::sched_states::state;
pub use super::sched_states::{gray, STATES, STATE_BITS};
use super::setup_path::SetupPath;
use super::context_ram::{ContextRam, ContextWord, CTX_ADDR_BITS, CTX_MAX_AXES};
use super::divider::{div_latency, DIV_NUM_BITS};
use super::ram_fifo::ENTRY_BITS;
use super::root::{root_latency, OffsetRoot};
use super::block_ram::BlockRam;
use super::seg_queue::{SegQueue, SEG_ADDR_BITS};
pub use super::seg_queue::{MAX_QUEUE_DEPTH, SEGMENT_BITS};
use super::axis_bank::{AxisBank, LATCH_BITS};
use super::stop_ramp::{StopRamp, LAST_BITS};
use super::poly_lane::{PolyLane, POLY_EXTRA_BITS};
use super::poly_unit::{POLY_UNIT_MAX_AXES, UNIT_LAST_CYCLES, UNIT_LOAD_CYCLES, UNIT_SETUP_CYCLES};
use rust_hdl::prelude::*;

/// Cycles the scheduler spends per period on the square-root paths (accelerating and
/// decelerating segments): PICK, P_START, the offset root ([`root_latency`]) and the
/// commit. 22 at R = 2, 13 at R = 4. Measured by tests/hdl_core.rs.
pub const fn t_calc_sqrt(r: usize) -> usize {
    3 + root_latency(r)
}

/// Cycles per period on the uniform path: PICK, U_ADD (the running quotient and
/// remainder plus their per-step increments, registered), U_STEP (the remainder's
/// compare and subtract), commit.
pub const T_CALC_UNIFORM: usize = 4;

pub use crate::latency::t_setup;

/// Cycles the scheduler spends forming a controlled stop's ramp, from the PICK that
/// takes the request to the commit of the ramp's setup (inclusive): two divides (v0,
/// then n), two products on the pipelined multiplier (v0², n·(Δ + 1)) and the
/// decelerating setup from its S_ISSUE_VT on. Measured by tests/hdl_core.rs.
pub const fn t_stop_form(r: usize) -> usize {
    7 + 2 * div_latency(r) + t_setup(r, true)
}

/// Cycles the scheduler spends on a polynomial segment's setup (S = 1), from S_CHECK
/// to S_COMMIT_SETUP inclusive: S_CHECK, S_ISSUE_VT (which branches on the lane's
/// registered flag), Y_SETUP, the unit's setup ([`UNIT_SETUP_CYCLES`]) and the commit.
/// Measured by tests/hdl_core.rs.
pub const T_POLY_SETUP: usize = UNIT_SETUP_CYCLES + 4;

/// Cycles from PICK to S_COMMIT_STEP inclusive for a polynomial period whose search
/// takes `search` cycles ([`crate::model::poly::GallopStats::unit_cycles`]): PICK, the
/// unit's load ([`UNIT_LOAD_CYCLES`]), the search, its `done`, the commit. A segment's
/// last step has no search: [`T_POLY_LAST`]. Measured by tests/hdl_core.rs.
pub const fn t_poly_step(search: usize) -> usize {
    UNIT_LOAD_CYCLES + search + 3
}

/// [`t_poly_step`] for a segment's last step (E_n = T, no search).
pub const T_POLY_LAST: usize = UNIT_LAST_CYCLES + 2;

const _: () = assert!(CTX_MAX_AXES == super::seg_queue::MAX_QUEUE_AXES);


#[derive(LogicBlock)]
pub struct TdmCore<const K: usize, const R: usize, const DEPTH: usize, const QDEPTH: usize, const S: usize = 0> {
    pub clock: Signal<In, Clock>,
    pub reset: Signal<In, Bit>,
    pub cmd_valid: Signal<In, Bit>,
    pub cmd_axis: Signal<In, Bits<8>>,
    pub cmd_v0: Signal<In, Bits<32>>,
    pub cmd_t: Signal<In, Bits<32>>,
    pub cmd_steps: Signal<In, Bits<32>>,
    /// The command's polynomial fields ([`PolyLane`]: v1, A', the flag); only a core
    /// with the S-curve option (S = 1) reads them.
    pub cmd_extra: Signal<In, Bits<POLY_EXTRA_BITS>>,
    pub cmd_ready: Signal<Out, Bit>,
    pub cmd_error: Signal<Out, Bit>,
    /// Hard stop of every axis (one cycle); see the module docs.
    pub abort: Signal<In, Bit>,
    /// Hard stop of axis i while bit i is high; see the module docs.
    pub stop_axes: Signal<In, Bits<K>>,
    /// Controlled stop of axis i (bit i, a pulse or a level); see the module docs.
    pub cstop_axes: Signal<In, Bits<K>>,
    /// The controlled stop's deceleration, a = `decel`/2^57 steps/tick² (quasi-static,
    /// at least [`crate::model::stop::stop_decel_min`]).
    pub decel: Signal<In, Bits<32>>,
    pub start: Signal<In, Bit>,
    pub start_mask: Signal<In, Bits<K>>,
    /// Axes idle with their first period ready (what the start waits for).
    pub ready: Signal<Out, Bits<K>>,
    /// Releases axes directly (the baseline's shared start drives it; else 0).
    pub ext_go: Signal<In, Bits<K>>,
    /// Toggles (a register) each time a START is cancelled because a masked axis had
    /// nothing to run; 0 after reset.
    pub start_failed: Signal<Out, Bit>,
    fail_tog: DFF<Bit>,
    pub step: Signal<Out, Bits<K>>,
    pub dir: Signal<Out, Bits<K>>,
    pub underrun: Signal<Out, Bits<K>>,
    pub active: Signal<Out, Bits<K>>,
    pub busy: Signal<Out, Bits<K>>,
    /// Status of axis `sel_axis`: position, last error code, queue and FIFO levels.
    pub sel_axis: Signal<In, Bits<8>>,
    pub sel_position: Signal<Out, Bits<32>>,
    pub sel_queue: Signal<Out, Bits<8>>,
    pub sel_fifo: Signal<Out, Bits<8>>,
    pub sel_taken: Signal<Out, Bits<8>>,
    pub sel_done: Signal<Out, Bits<8>>,
    pub sel_underruns: Signal<Out, Bits<8>>,
    pub sel_busy: Signal<Out, Bit>,
    /// The scheduler's state register (Gray code), for waveforms.
    pub fsm_state: Signal<Out, Bits<STATE_BITS>>,
    /// Output timing: minimum STEP high and low times in ticks (max(STEP_HIGH, DIR_HOLD)
    /// and max(STEP_LOW, DIR_SETUP)); quasi-static, see [`super::pulse_stage::PulseStage`].
    pub high_min: Signal<In, Bits<16>>,
    pub low_min: Signal<In, Bits<16>>,
    /// Position latches (machine I/O; tie to 0 without it): see [`AxisBank`].
    pub home_latch: Signal<In, Bits<K>>,
    pub probe_latch: Signal<In, Bit>,
    pub lsel_axis: Signal<In, Bits<8>>,
    pub lsel_word: Signal<Out, Bits<LATCH_BITS>>,
    /// Encoder feedback (tie to 0 without it): axis `epos_axis`'s position on `epos`,
    /// combinationally (see [`AxisBank`]).
    pub epos_axis: Signal<In, Bits<4>>,
    pub epos: Signal<Out, Bits<32>>,
    /// Encoder feedback: every axis's position's low byte (byte a = axis a's, wires).
    pub pos_low: Signal<Out, Bits<128>>,

    /// Every axis's segment queue ([`SegQueue`]: one RAM, two counters per axis). Its
    /// registered read holds axis m's head from PICK into S_CHECK.
    queues: SegQueue<K, QDEPTH>,
    /// The axes' back ends: pulse stage, period FIFOs, step generators, start, buses.
    bank: AxisBank<K, DEPTH>,
    /// Every axis's context flags and PICK's registered view of axis m ([`AxisView`]).
    pub view: AxisView<K>,
    /// The wide context fields of every axis, two words each (see [`Self::context`]).
    ctx_ram: ContextRam,
    /// The setup's datapath: the multipliers, the divider and their temporaries.
    setup: SetupPath<R>,
    root: OffsetRoot<R>,
    /// The S-curve option's lane (S = 1), or none (S = 0: no Verilog, no cost).
    lanes: [PolyLane<K>; S],
    /// The queued segments' polynomial fields ([`PolyLane`]'s `head_extra`), at the
    /// segment queue's addresses (its RAM ports).
    xram: [BlockRam<POLY_EXTRA_BITS, SEG_ADDR_BITS>; S],
    /// S = 1, a localparam gating every state and write of the lane (see
    /// [`SetupPath`] for why not a port).
    c_poly: Constant<Bit>,
    // The lane's requests and outputs (0 without it).
    y_setup: Signal<Local, Bit>,
    y_step: Signal<Local, Bit>,
    y_slot: Signal<Local, Bit>,
    y_head_go: Signal<Local, Bit>,
    y_pk_poly: Signal<Local, Bit>,
    y_busy: Signal<Local, Bit>,
    y_done: Signal<Local, Bit>,
    y_was_setup: Signal<Local, Bit>,
    y_period: Signal<Local, Bits<32>>,
    y_last: Signal<Local, Bit>,
    h_steps: Signal<Local, Bits<32>>,

    st: DFF<Bits<STATE_BITS>>,
    m: DFF<Bits<8>>,
    /// Axis m + 1 (mod K), registered: it moves with m, so no carry chain lies between
    /// m and the next axis's flags and context address.
    nm: DFF<Bits<8>>,
    /// Axis m + 2 (mod K), what `nm` takes when m moves on.
    nn: Signal<Local, Bits<8>>,
    c_first_next: Constant<Bits<8>>,
    /// The context memory's read address, registered: `{axis, slot}` of the word the
    /// next state reads (the next PICK's axis, or the next slot for S_PROMOTE), decided
    /// one cycle ahead so that no flag multiplexer sits in front of the RAM's read.
    ra: DFF<Bits<CTX_ADDR_BITS>>,
    cmd_err: DFF<Bit>,
    /// Per-axis stops: requested and not yet flushed by PICK; the axis flushed in the
    /// last cycle, whose FIFO stays held for the pulse stage's last entry.
    stop_pend: DFF<Bits<K>>,
    fl_v: DFF<Bit>,
    fl_a: DFF<Bits<8>>,
    stop_all: Signal<Local, Bits<K>>,
    /// PICK flushes axis m in this cycle.
    axis_flush: Signal<Local, Bit>,
    m_bit: Signal<Local, Bits<K>>,
    fl_bit: Signal<Local, Bits<K>>,
    c_one_k: Constant<Bits<K>>,
    /// All ones with the per-axis stop built in ([`Self::with_axis_stops`]), else 0:
    /// then every stop register has a constant input and synthesis removes them (a
    /// request register kept in a loop with PICK would not be provably 0 otherwise).
    c_stops: Constant<Bits<K>>,
    /// The controlled stop ([`Self::with_controlled_stop`]): its requests' mask (all
    /// ones, else 0) and a one-bit switch that gates every state and write of it, so
    /// that a core without it has none of its logic.
    c_cs: Constant<Bits<K>>,
    c_cs_on: Constant<Bit>,
    /// Per-axis requests and last periods ([`StopRamp`]).
    ramp: StopRamp<K>,
    /// A pending controlled stop on an axis that is not running becomes its hard stop.
    cs_hard: Signal<Local, Bits<K>>,
    /// Axis m's stop requests in PICK: AxisView's registers, or at K = 1 the requests
    /// themselves (latency 0, so that a stop handled in PICK is not seen again in the
    /// next cycle's PICK; AxisView cannot give them without a loop, see there).
    cs_pend: Signal<Local, Bits<K>>,
    cd_pend: Signal<Local, Bits<K>>,
    pk_stop: Signal<Local, Bit>,
    pk_cs: Signal<Local, Bit>,
    pk_cd: Signal<Local, Bit>,
    axis_drop: Signal<Local, Bit>,
    /// PICK cuts axis m (its queue and next slot dropped, its current segment ended).
    axis_cut: Signal<Local, Bit>,
    /// The scheduler takes axis m's controlled-stop request in this cycle.
    cs_clear: Signal<Local, Bit>,
    /// Axis m's stop ramp is being formed (from PICK to its setup's commit).
    cs_act: DFF<Bit>,
    /// Axis m's last period + 1, its direction and whether it is at rest (from PICK).
    s_dl1: DFF<Bits<LAST_BITS>>,
    s_rest: DFF<Bit>,
    s_crev: DFF<Bit>,
    pe_delta: Signal<Local, Bits<32>>,
    // Working copy of axis m's context.
    w_kind: DFF<Bits<2>>,
    w_dwell: DFF<Bit>,
    w_rev: DFF<Bit>,
    w_n: DFF<Bits<32>>,
    w_i: DFF<Bits<32>>,
    w_t: DFF<Bits<32>>,
    w_e: DFF<Bits<32>>,
    w_p: DFF<Bits<64>>,
    w_b: DFF<Bits<100>>,
    w_a: DFF<Bits<100>>,
    w_uq: DFF<Bits<32>>,
    w_ur: DFF<Bits<32>>,
    w_uqs: DFF<Bits<32>>,
    w_urs: DFF<Bits<32>>,
    /// Axis m's current slot, loaded in PICK from the registered flags (`pk_slot`): the
    /// context RAM's write address takes it from here, not through the K:1 slot
    /// multiplexer. Writes happen in S_COMMIT_STEP and S_COMMIT_SETUP, on the axis and
    /// slot PICK chose (the slot flips only in S_PROMOTE, which moves on to axis m + 1
    /// through PICK or S_PUSH_DWELL and never reaches a commit).
    w_slot: DFF<Bit>,
    /// A period entry to push into axis m's FIFO, formed from registers one cycle
    /// after it is decided, so that no path runs from the arithmetic (or the context
    /// memory's read) into the FIFO RAMs in one cycle: a step's E computed in P_WAIT
    /// or U_STEP, pushed in S_COMMIT_STEP (m unchanged), or a promoted dwell's T
    /// (loaded into w_e in S_PROMOTE with E_prev = 0), pushed in S_PUSH_DWELL.
    pe_valid: DFF<Bit>,
    /// The entry's step and last flags, and E before the step (Δ = w_e − s_eprev).
    pe_step: DFF<Bit>,
    pe_last: DFF<Bit>,
    s_eprev: DFF<Bits<32>>,
    pe_entry: Signal<Local, Bits<ENTRY_BITS>>,

    /// Axis m's next slot holds a dwell, loaded in PICK for S_PROMOTE.
    w_nd: DFF<Bit>,
    promote_now: Signal<Local, Bit>,
    nwe_now: Signal<Local, Bit>,
    /// The scheduler moves on to axis m + 1 at this edge: m, `nm` and `ra` advance
    /// together (set by every state that leaves axis m for the next PICK).
    advance: Signal<Local, Bit>,
    next_m: Signal<Local, Bits<8>>,
    // Read addresses for `ra`: axis m's next slot, and axis m + 1's current slot as it
    // will be after this clock edge.
    addr_promote: Signal<Local, Bits<CTX_ADDR_BITS>>,
    addr_next: Signal<Local, Bits<CTX_ADDR_BITS>>,
    /// Axis m + 1's slot: the view's slot bus shifted down by m + 1, bit 0.
    slot_sh: Signal<Local, Bits<K>>,
    slot_nm: Signal<Local, Bit>,
    other_slot: Signal<Local, Bit>,
    // |steps| of the head.
    h_n: Signal<Local, Bits<32>>,
    last: DFF<Bit>,
    a_step: Signal<Local, Bits<100>>,
    /// E from the root's τ' in one addition: ⌊(τ' + 8)/16⌋ accelerating, and
    /// decelerating T − ⌊(τ' + 8)/16⌋ = ⌊(¬τ' + 16T + 8)/16⌋ (equal modulo 2^32, 37-bit
    /// two's complement). `e_dec` (decelerating) is the kind's bit 0: PICK loads the
    /// kind and the square-root path (kind 2 or 3) holds it until P_WAIT reads E, so
    /// the mask (¬ or not) and the addend (8 or 16T + 8, T being held too) are one
    /// small LUT per bit from flip-flops, side by side in front of the one carry chain
    /// between the root and E.
    e_dec: Signal<Local, Bit>,
    e_mask: Signal<Local, Bits<37>>,
    e_add: Signal<Local, Bits<37>>,
    e_x: Signal<Local, Bits<37>>,
    e_sum: Signal<Local, Bits<37>>,
    rounded: Signal<Local, Bits<32>>,
    c_ones37: Constant<Bits<37>>,
    e_next: Signal<Local, Bits<32>>,
    i_next: Signal<Local, Bits<32>>,
    two_n: Signal<Local, Bits<32>>,
    u_q1: DFF<Bits<32>>,
    u_r1: DFF<Bits<32>>,
    /// w_ur + w_urs − 2n, registered with u_r1 (34 bits, negative when bit 33 is set), so
    /// U_STEP chooses from registers: the sum's carry chain does not drive the selects.
    /// One carry chain: the three operands first go through a carry-save stage.
    u_r2: DFF<Bits<34>>,
    ur_x: Signal<Local, Bits<34>>,
    ur_y: Signal<Local, Bits<34>>,
    ur_n: Signal<Local, Bits<34>>,
    ur_z: Signal<Local, Bits<34>>,
    ur_s: Signal<Local, Bits<34>>,
    ur_c: Signal<Local, Bits<34>>,
    // Actions on axis m.
    pop_now: Signal<Local, Bit>,
    commit: Signal<Local, Bit>,
    cmd_ok_axis: Signal<Local, Bit>,

    c_last_axis: Constant<Bits<8>>,
    /// K = 1: axis m + 1 is axis m, so a promote flips the slot the next PICK reads, and
    /// PICK reads the flags directly (the previous state may just have changed them).
    c_single: Constant<Bit>,
    flush: Signal<Local, Bit>,
    k_pick: Constant<Bits<STATE_BITS>>,
    k_check: Constant<Bits<STATE_BITS>>,
    k_issue_vt: Constant<Bits<STATE_BITS>>,
    k_issue_tr: Constant<Bits<STATE_BITS>>,
    k_vt: Constant<Bits<STATE_BITS>>,
    k_tr: Constant<Bits<STATE_BITS>>,
    k_dwell: Constant<Bits<STATE_BITS>>,
    k_udiv: Constant<Bits<STATE_BITS>>,
    k_x: Constant<Bits<STATE_BITS>>,
    k_p: Constant<Bits<STATE_BITS>>,
    k_b: Constant<Bits<STATE_BITS>>,
    k_nb: Constant<Bits<STATE_BITS>>,
    k_commit_setup: Constant<Bits<STATE_BITS>>,
    k_pstart: Constant<Bits<STATE_BITS>>,
    k_pwait: Constant<Bits<STATE_BITS>>,
    k_uadd: Constant<Bits<STATE_BITS>>,
    k_ustep: Constant<Bits<STATE_BITS>>,
    k_commit_step: Constant<Bits<STATE_BITS>>,
    k_promote: Constant<Bits<STATE_BITS>>,
    k_push_dwell: Constant<Bits<STATE_BITS>>,
    k_drain: Constant<Bits<STATE_BITS>>,
    k_cv0: Constant<Bits<STATE_BITS>>,
    k_cv0w: Constant<Bits<STATE_BITS>>,
    k_csq1: Constant<Bits<STATE_BITS>>,
    k_csq2: Constant<Bits<STATE_BITS>>,
    k_cn: Constant<Bits<STATE_BITS>>,
    k_cnw: Constant<Bits<STATE_BITS>>,
    k_ct1: Constant<Bits<STATE_BITS>>,
    k_ct2: Constant<Bits<STATE_BITS>>,
    k_ct: Constant<Bits<STATE_BITS>>,
    k_ysetup: Constant<Bits<STATE_BITS>>,
    k_ywait: Constant<Bits<STATE_BITS>>,
}

impl<const K: usize, const R: usize, const DEPTH: usize, const QDEPTH: usize, const S: usize> TdmCore<K, R, DEPTH, QDEPTH, S> {
    /// A core for segments already validated (by the push check, against the
    /// export's minimum period); the core itself checks nothing.
    /// The core with the per-axis stop (`stop_axes`) working; [`Self::new`] builds it
    /// with `stop_axes` ignored, which costs nothing (the machine I/O's top uses this).
    pub fn with_axis_stops(mut self) -> Self {
        self.c_stops = Constant::new(((1u64 << K) - 1).into());
        self.view = self.view.with_axis_stops();
        self
    }

    /// The core with the controlled stop (`cstop_axes`, `decel`) working, and the
    /// per-axis hard stop it falls back on; [`Self::new`] ignores both inputs.
    pub fn with_controlled_stop(mut self) -> Self {
        self.c_cs = Constant::new(((1u64 << K) - 1).into());
        self.c_cs_on = Constant::new(true);
        self.setup = self.setup.with_controlled_stop();
        self.view = self.view.with_controlled_stop();
        self.with_axis_stops()
    }

    pub fn new() -> Self {
        assert!((1..=CTX_MAX_AXES).contains(&K), "TdmCore: K = {K} outside 1..={CTX_MAX_AXES}");
        assert!(
            QDEPTH.is_power_of_two() && (2..=MAX_QUEUE_DEPTH).contains(&QDEPTH),
            "TdmCore: queue depth {QDEPTH} is not a power of two in 2..={MAX_QUEUE_DEPTH}"
        );
        assert!(S <= 1, "TdmCore: S = {S}: one polynomial lane at most");
        assert!(S == 0 || K <= POLY_UNIT_MAX_AXES, "TdmCore: K = {K} above the polynomial unit's {POLY_UNIT_MAX_AXES} axes");
        TdmCore {
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
            cstop_axes: Default::default(),
            decel: Default::default(),
            start: Default::default(),
            start_mask: Default::default(),
            ready: Default::default(),
            ext_go: Default::default(),
            step: Default::default(),
            dir: Default::default(),
            underrun: Default::default(),
            active: Default::default(),
            busy: Default::default(),
            start_failed: Default::default(),
            fail_tog: Default::default(),
            high_min: Default::default(),
            low_min: Default::default(),
            home_latch: Default::default(),
            probe_latch: Default::default(),
            lsel_axis: Default::default(),
            lsel_word: Default::default(),
            epos_axis: Default::default(),
            epos: Default::default(),
            pos_low: Default::default(),
            sel_axis: Default::default(),
            sel_position: Default::default(),
            sel_queue: Default::default(),
            sel_fifo: Default::default(),
            sel_taken: Default::default(),
            sel_done: Default::default(),
            sel_underruns: Default::default(),
            sel_busy: Default::default(),
            fsm_state: Default::default(),
            queues: SegQueue::new(),
            bank: Default::default(),
            view: Default::default(),
            ctx_ram: Default::default(),
            root: Default::default(),
            setup: Default::default(),
            lanes: std::array::from_fn(|_| Default::default()),
            xram: std::array::from_fn(|_| BlockRam::new(1 << SEG_ADDR_BITS)),
            c_poly: Constant::new(S > 0),
            y_setup: Default::default(),
            y_step: Default::default(),
            y_slot: Default::default(),
            y_head_go: Default::default(),
            y_pk_poly: Default::default(),
            y_busy: Default::default(),
            y_done: Default::default(),
            y_was_setup: Default::default(),
            y_period: Default::default(),
            y_last: Default::default(),
            h_steps: Default::default(),
            st: Default::default(),
            m: Default::default(),
            nm: Default::default(),
            nn: Default::default(),
            c_first_next: Constant::new(((1 % K) as u64).into()),
            ra: Default::default(),
            cmd_err: Default::default(),
            stop_pend: Default::default(),
            fl_v: Default::default(),
            fl_a: Default::default(),
            stop_all: Default::default(),
            axis_flush: Default::default(),
            m_bit: Default::default(),
            fl_bit: Default::default(),
            c_one_k: Constant::new(1.into()),
            c_stops: Constant::new(0.into()),
            c_cs: Constant::new(0.into()),
            c_cs_on: Constant::new(false),
            ramp: Default::default(),
            cs_hard: Default::default(),
            cs_pend: Default::default(),
            cd_pend: Default::default(),
            pk_stop: Default::default(),
            pk_cs: Default::default(),
            pk_cd: Default::default(),
            axis_drop: Default::default(),
            axis_cut: Default::default(),
            cs_clear: Default::default(),
            cs_act: Default::default(),
            s_dl1: Default::default(),
            s_rest: Default::default(),
            s_crev: Default::default(),
            pe_delta: Default::default(),
            w_kind: Default::default(),
            w_dwell: Default::default(),
            w_rev: Default::default(),
            w_n: Default::default(),
            w_i: Default::default(),
            w_t: Default::default(),
            w_e: Default::default(),
            w_p: Default::default(),
            w_b: Default::default(),
            w_a: Default::default(),
            w_uq: Default::default(),
            w_ur: Default::default(),
            w_uqs: Default::default(),
            w_urs: Default::default(),
            w_slot: Default::default(),
            pe_valid: Default::default(),
            pe_step: Default::default(),
            pe_last: Default::default(),
            s_eprev: Default::default(),
            pe_entry: Default::default(),
            w_nd: Default::default(),
            promote_now: Default::default(),
            nwe_now: Default::default(),
            advance: Default::default(),
            next_m: Default::default(),
            addr_promote: Default::default(),
            addr_next: Default::default(),
            slot_sh: Default::default(),
            slot_nm: Default::default(),
            other_slot: Default::default(),
            h_n: Default::default(),
            last: Default::default(),
            a_step: Default::default(),
            e_dec: Default::default(),
            e_mask: Default::default(),
            e_add: Default::default(),
            e_x: Default::default(),
            e_sum: Default::default(),
            rounded: Default::default(),
            c_ones37: Constant::new(Bits::<37>::mask()),
            e_next: Default::default(),
            i_next: Default::default(),
            two_n: Default::default(),
            u_q1: Default::default(),
            u_r1: Default::default(),
            u_r2: Default::default(),
            ur_x: Default::default(),
            ur_y: Default::default(),
            ur_n: Default::default(),
            ur_z: Default::default(),
            ur_s: Default::default(),
            ur_c: Default::default(),
            pop_now: Default::default(),
            commit: Default::default(),
            cmd_ok_axis: Default::default(),
            c_last_axis: Constant::new(((K - 1) as u64).into()),
            c_single: Constant::new(K == 1),
            flush: Default::default(),
            k_pick: state("PICK"),
            k_check: state("S_CHECK"),
            k_issue_vt: state("S_ISSUE_VT"),
            k_issue_tr: state("S_ISSUE_TR"),
            k_vt: state("S_VT"),
            k_tr: state("S_TR"),
            k_dwell: state("S_DWELL"),
            k_udiv: state("S_UDIV"),
            k_x: state("S_X"),
            k_p: state("S_P"),
            k_b: state("S_B"),
            k_nb: state("S_NB"),
            k_commit_setup: state("S_COMMIT_SETUP"),
            k_pstart: state("P_START"),
            k_pwait: state("P_WAIT"),
            k_uadd: state("U_ADD"),
            k_ustep: state("U_STEP"),
            k_commit_step: state("S_COMMIT_STEP"),
            k_promote: state("S_PROMOTE"),
            k_push_dwell: state("S_PUSH_DWELL"),
            k_drain: state("S_DRAIN"),
            k_cv0: state("C_V0"),
            k_cv0w: state("C_V0_WAIT"),
            k_csq1: state("C_SQ1"),
            k_csq2: state("C_SQ2"),
            k_cn: state("C_N"),
            k_cnw: state("C_N_WAIT"),
            k_ct1: state("C_T1"),
            k_ct2: state("C_T2"),
            k_ct: state("C_T"),
            k_ysetup: state("Y_SETUP"),
            k_ywait: state("Y_WAIT"),
        }
    }

    core_connect_ports!();

    /// Axis `axis`'s current segment as the simulation holds it: its kind (0 idle,
    /// 1 uniform, 2 accelerate, 3 decelerate) and context word.
    pub fn context(&self, axis: usize) -> (u8, ContextWord) {
        let c = &self.view.ctx[axis];
        let addr = 2 * axis + c.slot.val() as usize;
        (c.kind.val().to_u64() as u8, self.ctx_ram.word(addr))
    }
}

impl<const K: usize, const R: usize, const DEPTH: usize, const QDEPTH: usize, const S: usize> Logic
    for TdmCore<K, R, DEPTH, QDEPTH, S>
{
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clock, st, m, nm, ra, cmd_err, w_kind, w_dwell, w_rev, w_n, w_i, w_t, w_e, w_p, w_b, w_a, w_uq, w_ur,
            w_uqs, w_urs, u_q1, u_r1, u_r2, w_slot, pe_valid, w_nd, pe_step, pe_last, s_eprev, fail_tog,
            last, stop_pend, fl_v, fl_a, cs_act, s_dl1, s_rest, s_crev
        );
        self.root.clock.next = self.clock.val();
        self.setup.mul_start.next = false;
        self.setup.div_start.next = false;
        self.root.start.next = false;
        self.root.p.next = self.w_p.q.val();
        self.pe_valid.d.next = false;
        self.pe_last.d.next = self.last.q.val();
        self.pop_now.next = false;
        self.commit.next = false;
        self.promote_now.next = false;
        self.nwe_now.next = false;
        self.advance.next = false;
        self.axis_flush.next = false;
        self.axis_cut.next = false;
        self.axis_drop.next = false;
        self.cs_clear.next = false;
        self.y_setup.next = false;
        self.y_step.next = false;
        self.y_slot.next = self.w_slot.q.val();
        self.fsm_state.next = self.st.q.val();
        self.cmd_error.next = self.cmd_err.q.val();

        // ---- axis m + 1 through the multiplexers, registered for PICK ---------
        // The queues read axis m's head (registered: valid in S_CHECK after PICK).
        self.queues.axis.next = self.m.q.val();
        self.next_m.next = self.nm.q.val();
        if self.nm.q.val() == self.c_last_axis.val() {
            self.nn.next = 0.into();
        } else {
            self.nn.next = self.nm.q.val() + 1;
        }
        // A controlled stop pending on an axis that is not moving (idle, its move not yet
        // released, or in a dwell) stops it as the hard stop does: it is at rest, so
        // there is no motion to ramp down. The hard stop's request latches it.
        self.cs_hard.next = self.ramp.pend.val() & !self.bank.moving.val() & self.c_cs.val();
        self.stop_all.next = (self.stop_pend.q.val() | self.stop_axes.val() | self.cs_hard.val()) & self.c_stops.val();
        // A request on an axis already ramping down cuts nothing: it drops the queue.
        self.cs_pend.next = self.ramp.pend.val() & !self.ramp.stopping.val() & self.c_cs.val();
        self.cd_pend.next = self.ramp.pend.val() & self.ramp.stopping.val() & self.c_cs.val();
        self.view.cs_pend.next = self.cs_pend.val();
        self.view.cd_pend.next = self.cd_pend.val();
        self.view.stop_all.next = self.stop_all.val();
        if self.c_single.val() {
            self.pk_stop.next = self.stop_all.val().any();
            self.pk_cs.next = self.cs_pend.val().any();
            self.pk_cd.next = self.cd_pend.val().any();
        } else {
            self.pk_stop.next = self.view.pk_stop.val();
            self.pk_cs.next = self.view.pk_cs.val();
            self.pk_cd.next = self.view.pk_cd.val();
        }
        // PICK's inputs: axis m + 1's flags, registered (AxisView).
        self.view.clock.next = self.clock.val();
        self.view.reset.next = self.reset.val();
        self.view.abort.next = self.abort.val();
        self.view.m.next = self.m.q.val();
        self.view.next_m.next = self.nm.q.val();
        self.view.nonempty.next = self.queues.nonempty.val();
        self.view.full.next = self.bank.full.val();
        // Every axis satisfied: a full FIFO, or nothing to compute.
        self.view.all_sat.next = self.bank.all_sat.val();
        // Axis m's context word is read at `ra`, set one cycle ahead: in PICK axis m's
        // next slot for S_PROMOTE (a dwell's FIFO entry needs its T), and on every move
        // to axis m + 1 its current slot. Writes: a step's commit into the current slot,
        // a setup's commit into the next one.
        // (The other slot as a one-bit signal of its own: `~` inside a wider expression
        // inverts the zero-extended bits in the Verilog.)
        self.other_slot.next = !self.view.pk_slot.val();
        self.addr_promote.next = (bit_cast::<CTX_ADDR_BITS, 8>(self.m.q.val()) << 1)
            | bit_cast::<CTX_ADDR_BITS, 1>(self.other_slot.val().into());
        self.slot_sh.next = self.view.slots.val() >> self.next_m.val();
        self.slot_nm.next = (self.slot_sh.val() & self.c_one_k.val()).any();
        self.addr_next.next = (bit_cast::<CTX_ADDR_BITS, 8>(self.next_m.val()) << 1)
            | bit_cast::<CTX_ADDR_BITS, 1>(
                (self.slot_nm.val() ^ (self.c_single.val() & (self.st.q.val() == self.k_promote.val()))).into(),
            );
        self.ctx_ram.clock.next = self.clock.val();
        self.ctx_ram.raddr.next = self.ra.q.val();
        // `ra` holds unless set below (only PICK and S_PROMOTE read the context memory).
        self.ra.d.next = self.ra.q.val();

        // ---- datapath -------------------------------------------------------
        // |steps| of the head, from the signed count and its sign loaded into w_n and
        // w_rev in S_ISSUE_VT (read in S_ISSUE_TR).
        if self.w_rev.q.val() {
            self.h_n.next = (!self.w_n.q.val()) + 1;
        } else {
            self.h_n.next = self.w_n.q.val();
        }
        // C + B' accelerating (kind 2), C − B' decelerating.
        if self.w_kind.q.val() == 2 {
            self.a_step.next = self.w_a.q.val() + self.w_b.q.val();
        } else {
            self.a_step.next = self.w_a.q.val() - self.w_b.q.val();
        }
        // E = (τ' + 8) >> 4 (accelerating) or T − that (decelerating), τ' = x < 2^35.
        // Decelerating: kind 3 on the square-root path (kinds 2 and 3), its bit 0.
        self.e_dec.next = self.w_kind.q.val().get_bit(0);
        // 16T + 8 is T's bits above a constant 8 (an OR, no adder).
        if self.e_dec.val() {
            self.e_mask.next = self.c_ones37.val();
            self.e_add.next = (bit_cast::<37, 32>(self.w_t.q.val()) << 4) | 8;
        } else {
            self.e_mask.next = 0.into();
            self.e_add.next = 8.into();
        }
        self.e_x.next = bit_cast::<37, 36>(self.root.x.val()) ^ self.e_mask.val();
        self.e_sum.next = self.e_x.val() + self.e_add.val();
        self.rounded.next = bit_cast::<32, 37>(self.e_sum.val() >> 4);
        self.i_next.next = self.w_i.q.val() + 1;
        // The last-step test i + 1 = n, registered: w_i and w_n are loaded in PICK and
        // hold through P_START/P_WAIT and U_ADD/U_STEP, which read it, so the compare is
        // not in front of the kind's and E's enables.
        self.last.d.next = self.i_next.val() == self.w_n.q.val();
        if self.last.q.val() {
            self.e_next.next = self.w_t.q.val();
        } else {
            self.e_next.next = self.rounded.val();
        }
        self.two_n.next = self.w_n.q.val() << 1;
        // Registered every cycle, read in U_STEP (one carry chain per cycle).
        self.u_q1.d.next = self.w_uq.q.val() + self.w_uqs.q.val();
        self.u_r1.d.next = self.w_ur.q.val() + self.w_urs.q.val();
        // u_r2 = w_ur + w_urs + ~2n + 1 (mod 2^34): sum and carry of the three, the +1 in
        // the carry word's empty bit 0. (The complement as a signal of its own: `~`
        // inside a wider expression inverts the zero-extended bits in the Verilog.)
        self.ur_x.next = bit_cast::<34, 32>(self.w_ur.q.val());
        self.ur_y.next = bit_cast::<34, 32>(self.w_urs.q.val());
        self.ur_n.next = bit_cast::<34, 32>(self.two_n.val());
        self.ur_z.next = !self.ur_n.val();
        self.ur_s.next = self.ur_x.val() ^ self.ur_y.val() ^ self.ur_z.val();
        self.ur_c.next = (((self.ur_x.val() & self.ur_y.val())
            | (self.ur_x.val() & self.ur_z.val())
            | (self.ur_y.val() & self.ur_z.val()))
            << 1)
            | 1;
        self.u_r2.d.next = self.ur_s.val() + self.ur_c.val();
        // The root reads c and p only at its start (P_START).
        self.root.c.next = self.a_step.val();
        // The setup's datapath decodes the state (SetupPath).
        self.setup.clock.next = self.clock.val();
        self.setup.st.next = self.st.q.val();
        self.setup.head.next = self.queues.head.val();
        self.setup.w_n.next = self.w_n.q.val();
        self.setup.w_t.next = self.w_t.q.val();
        self.setup.decel.next = self.decel.val();
        self.setup.dl1.next = self.s_dl1.q.val();
        self.setup.crev.next = self.s_crev.q.val();

        // ---- the S-curve option's lane (S = 1): its outputs -----------------
        self.h_steps.next = self.queues.head.val().get_bits::<32>(64);
        self.y_head_go.next = false;
        self.y_pk_poly.next = false;
        self.y_busy.next = false;
        self.y_done.next = false;
        self.y_was_setup.next = false;
        self.y_period.next = 0.into();
        self.y_last.next = false;
        for i in 0..S {
            self.xram[i].clock.next = self.clock.val();
            self.xram[i].we.next = self.queues.ram_we.val();
            self.xram[i].waddr.next = self.queues.ram_waddr.val();
            self.xram[i].wdata.next = self.cmd_extra.val();
            self.xram[i].raddr.next = self.queues.ram_raddr.val();
        }
        for i in 0..S {
            self.y_pk_poly.next = self.lanes[i].pk_poly.val();
            self.y_head_go.next = self.lanes[i].head_go.val();
            self.y_busy.next = self.lanes[i].busy.val();
            self.y_done.next = self.lanes[i].done.val();
            self.y_was_setup.next = self.lanes[i].was_setup.val();
            self.y_period.next = self.lanes[i].period.val();
            self.y_last.next = self.lanes[i].last.val();
        }

        // ---- the scheduler --------------------------------------------------
        if self.st.q.val() == self.k_pick.val() {
            // The lane's slot is axis m's in all of PICK, whatever PICK decides: the
            // unit's read address (axis and slot) then does not wait for the decision
            // (on ECP5 that path closed the K = 16 option core's `clk` at 77.4 MHz).
            self.y_slot.next = self.view.pk_slot.val();
            self.w_kind.d.next = self.view.pk_kind.val();
            self.w_nd.d.next = self.view.pk_next_dwell.val();
            self.w_slot.d.next = self.view.pk_slot.val();
            self.w_rev.d.next = self.ctx_ram.r_rev.val();
            self.w_n.d.next = self.ctx_ram.r_n.val();
            self.w_i.d.next = self.ctx_ram.r_i.val();
            self.w_t.d.next = self.ctx_ram.r_t.val();
            self.w_e.d.next = self.ctx_ram.r_e.val();
            self.w_p.d.next = self.ctx_ram.r_p.val();
            self.w_b.d.next = self.ctx_ram.r_b.val();
            self.w_a.d.next = self.ctx_ram.r_a.val();
            self.w_uq.d.next = self.ctx_ram.r_uq.val();
            self.w_ur.d.next = self.ctx_ram.r_ur.val();
            self.w_uqs.d.next = self.ctx_ram.r_uqs.val();
            self.w_urs.d.next = self.ctx_ram.r_urs.val();
            self.s_dl1.d.next = self.ramp.d1.val();
            self.s_rest.d.next = self.ramp.rest.val();
            self.s_crev.d.next = self.ramp.rev.val();
            if self.pk_stop.val() {
                // Axis m is stopped: nothing of it is in the shared unit, so its
                // queue, context and in-flight entries are flushed here (with a
                // controlled stop pending on it).
                self.axis_flush.next = true;
                self.cs_clear.next = true;
                self.advance.next = true;
            } else if self.pk_cs.val() & self.c_cs_on.val() {
                // A controlled stop of running axis m: its queue and next slot are
                // dropped and its current segment ends after the periods computed so
                // far; if it had more to compute, the ramp is formed from its last period.
                self.axis_cut.next = true;
                self.cs_clear.next = true;
                if (self.view.pk_kind.val() != 0) | self.view.pk_next_valid.val() | self.view.pk_queued.val() {
                    self.cs_act.d.next = true;
                    self.st.d.next = self.k_cv0.val();
                } else {
                    self.advance.next = true;
                }
            } else if self.pk_cd.val() & self.view.pk_queued.val() & self.c_cs_on.val() {
                // A stop request on axis m while it ramps down: what was pushed behind
                // the ramp is dropped (counted as taken); the ramp runs on.
                self.axis_drop.next = true;
                self.cs_clear.next = true;
                self.advance.next = true;
            } else if (self.view.pk_kind.val() != 0) & !self.view.pk_full.val() {
                // Axis m's next period.
                if self.y_pk_poly.val() & self.c_poly.val() {
                    // A polynomial segment (kind 1 in the context): the lane's unit
                    // computes it; while the unit still stores its last request's
                    // state, the axis waits for its next turn.
                    if self.y_busy.val() {
                        self.advance.next = true;
                    } else {
                        self.y_step.next = true;
                        self.st.d.next = self.k_ywait.val();
                    }
                } else if self.view.pk_kind.val() == 1 {
                    self.st.d.next = self.k_uadd.val();
                } else {
                    self.st.d.next = self.k_pstart.val();
                }
            } else if (self.view.pk_kind.val() == 0) & self.view.pk_next_valid.val() & !self.view.pk_full.val() {
                // Its current segment is done and the next one is set up.
                self.ra.d.next = self.addr_promote.val();
                self.st.d.next = self.k_promote.val();
            } else if !self.view.pk_next_valid.val()
                & self.view.pk_queued.val()
                & ((self.view.pk_kind.val() == 0) | self.view.pk_sat.val())
            {
                // Set up its next segment: at once if it is idle, else ahead of time while
                // every axis has a full FIFO (or nothing to do), so the setup takes only
                // spare time and no FIFO runs dry behind it.
                self.st.d.next = self.k_check.val();
            } else {
                self.advance.next = true;
            }
        } else if self.st.q.val() == self.k_check.val() {
            // The queue head into the setup's temporaries (SetupPath).
            self.st.d.next = self.k_issue_vt.val();
        } else if (self.st.q.val() == self.k_ysetup.val()) & self.c_poly.val() {
            // The head (still read at axis m) into the lane's unit, for axis m's next
            // slot; the working copy takes its T, signed steps and sign, and the
            // context kind 1 (running) with i = E = 0.
            if !self.y_busy.val() {
                self.y_setup.next = true;
                self.w_dwell.d.next = false;
                self.w_kind.d.next = 1.into();
                self.w_t.d.next = self.queues.head.val().get_bits::<32>(32);
                self.w_n.d.next = self.h_steps.val();
                self.w_rev.d.next = self.h_steps.val().get_bit(31);
                self.w_i.d.next = 0.into();
                self.w_e.d.next = 0.into();
                self.st.d.next = self.k_ywait.val();
            }
        } else if (self.st.q.val() == self.k_ywait.val()) & self.c_poly.val() {
            if self.y_done.val() {
                if self.y_was_setup.val() {
                    // w_n takes |steps|.
                    self.w_n.d.next = self.h_n.val();
                    self.st.d.next = self.k_commit_setup.val();
                } else {
                    // The period into the FIFO entry (E_prev = 0, E = the period).
                    self.pe_valid.d.next = true;
                    self.pe_step.d.next = true;
                    self.pe_last.d.next = self.y_last.val();
                    self.s_eprev.d.next = 0.into();
                    self.w_e.d.next = self.y_period.val();
                    self.w_i.d.next = self.i_next.val();
                    if self.y_last.val() {
                        self.w_kind.d.next = 0.into();
                    }
                    self.st.d.next = self.k_commit_step.val();
                }
            }
        } else if self.st.q.val() == self.k_issue_vt.val() {
            // v0·T goes into the multiplier; T²'s operands are T and T (op_b holds).
            // T, the signed step count and its sign into the working copy. A
            // polynomial head with steps (the lane's registered `head_go`, so no state
            // decision follows the queue RAMs' read ports) goes to the lane instead:
            // Y_SETUP overwrites the working copy, and nothing else here has effect.
            // A stop ramp (`cs_act`: from C_T, not S_CHECK) is never the queue's head.
            self.w_dwell.d.next = false;
            self.w_t.d.next = self.setup.t.val();
            self.w_n.d.next = self.setup.steps.val();
            self.w_rev.d.next = self.setup.steps.val().get_bit(31);
            if self.y_head_go.val() & !self.cs_act.q.val() & self.c_poly.val() {
                self.st.d.next = self.k_ysetup.val();
            } else {
                self.st.d.next = self.k_issue_tr.val();
            }
        } else if self.st.q.val() == self.k_issue_tr.val() {
            // T² goes in; w_n takes |steps| (0 exactly when the signed count is 0).
            self.w_n.d.next = self.h_n.val();
            self.st.d.next = self.k_vt.val();
        } else if self.st.q.val() == self.k_vt.val() {
            // v0·T arrived (MulReg, two cycles after S_ISSUE_VT issued it): D and its tests.
            self.st.d.next = self.k_tr.val();
        } else if self.st.q.val() == self.k_tr.val() {
            // T² arrived. The segment is valid and effective (the push check in the bus
            // clock dropped bad ones and ran a deceleration that rounds past rest with
            // v0 − 1), so the setup only chooses its path.
            // The multiplier takes v_end·T·2^32 at this edge (it starts here).
            if self.setup.nz.val() {
                self.st.d.next = self.k_dwell.val();
            } else if self.setup.dz.val() {
                self.setup.div_start.next = true;
                self.st.d.next = self.k_udiv.val();
            } else {
                // v·T² needs the wide multiplier.
                self.setup.mul_start.next = true;
                self.st.d.next = self.k_x.val();
            }
        } else if self.st.q.val() == self.k_dwell.val() {
            // A dwell goes into the next slot like any segment; its FIFO entry is pushed
            // when it is promoted, so the FIFO stays in segment order.
            self.w_dwell.d.next = true;
            self.w_kind.d.next = 0.into();
            self.st.d.next = self.k_commit_setup.val();
        } else if self.st.q.val() == self.k_udiv.val() {
            if self.setup.div_valid.val() {
                self.w_uqs.d.next = bit_cast::<32, DIV_NUM_BITS>(self.setup.quotient.val());
                self.w_urs.d.next = bit_cast::<32, 64>(self.setup.remainder.val());
                self.w_uq.d.next = 0.into();
                self.w_ur.d.next = self.w_n.q.val();
                self.w_kind.d.next = 1.into();
                self.w_i.d.next = 0.into();
                self.w_e.d.next = 0.into();
                self.st.d.next = self.k_commit_setup.val();
            }
        } else if self.st.q.val() == self.k_x.val() {
            if self.setup.mul_valid.val() {
                // P' (the operands above).
                self.setup.div_start.next = true;
                self.st.d.next = self.k_p.val();
            }
        } else if self.st.q.val() == self.k_p.val() {
            if self.setup.p_ready.val() {
                if self.setup.p_wide.val() {
                    // P' + 2T' does not fit the root: the nearly-uniform fallback.
                    self.setup.div_start.next = true;
                    self.st.d.next = self.k_udiv.val();
                } else {
                    self.w_p.d.next = self.setup.quotient.val().get_bits::<64>(0);
                    // B' (the operands above).
                    self.setup.div_start.next = true;
                    self.st.d.next = self.k_b.val();
                }
            }
        } else if self.st.q.val() == self.k_b.val() {
            if self.setup.div_valid.val() {
                // B' < 2^100 on the square-root paths (docs/model.md, "Widths").
                self.w_b.d.next = self.setup.quotient.val().get_bits::<100>(0);
                self.w_i.d.next = 0.into();
                self.w_e.d.next = 0.into();
                if self.setup.neg.val() {
                    // Decelerating: C starts at n·B' (the operands above).
                    self.setup.mul_start.next = true;
                    self.st.d.next = self.k_nb.val();
                } else {
                    // Accelerating: C starts at 0.
                    self.w_a.d.next = 0.into();
                    self.w_kind.d.next = 2.into();
                    self.st.d.next = self.k_commit_setup.val();
                }
            }
        } else if self.st.q.val() == self.k_nb.val() {
            if self.setup.mul_valid.val() {
                self.w_a.d.next = self.setup.product.val();
                self.w_kind.d.next = 3.into();
                self.st.d.next = self.k_commit_setup.val();
            }
        } else if self.st.q.val() == self.k_commit_setup.val() {
            self.nwe_now.next = true;
            // A stop ramp comes from no queue entry (the queue was dropped in PICK).
            self.pop_now.next = !self.cs_act.q.val();
            self.cs_act.d.next = false;
            self.advance.next = true;
            self.st.d.next = self.k_pick.val();
        } else if self.st.q.val() == self.k_promote.val() {
            self.promote_now.next = true;
            if self.w_nd.q.val() {
                // The dwell's one entry (T, no step, last), formed in S_PUSH_DWELL from
                // the working copy, which the promote does not write back.
                self.w_e.d.next = self.ctx_ram.r_t.val();
                self.s_eprev.d.next = 0.into();
                self.pe_step.d.next = false;
                self.pe_last.d.next = true;
                self.pe_valid.d.next = true;
                self.st.d.next = self.k_push_dwell.val();
            } else {
                self.advance.next = true;
                self.st.d.next = self.k_pick.val();
            }
        } else if self.st.q.val() == self.k_push_dwell.val() {
            self.advance.next = true;
            self.st.d.next = self.k_pick.val();
        } else if self.st.q.val() == self.k_pstart.val() {
            // C moves on here; the working copy reaches the context memory only at the
            // step's commit.
            self.w_a.d.next = self.a_step.val();
            self.root.start.next = true;
            self.st.d.next = self.k_pwait.val();
        } else if self.st.q.val() == self.k_pwait.val() {
            if self.root.valid.val() {
                self.pe_valid.d.next = true;
                self.pe_step.d.next = true;
                self.s_eprev.d.next = self.w_e.q.val();
                self.w_e.d.next = self.e_next.val();
                self.w_i.d.next = self.i_next.val();
                if self.last.q.val() {
                    self.w_kind.d.next = 0.into();
                }
                self.st.d.next = self.k_commit_step.val();
            }
        } else if self.st.q.val() == self.k_uadd.val() {
            self.st.d.next = self.k_ustep.val();
        } else if self.st.q.val() == self.k_ustep.val() {
            // E_i = ⌊(2iT + n)/(2n)⌋ as a quotient and a remainder.
            // (u_r1 ≥ 2n: u_r2 = u_r1 − 2n is not negative; every operand is < 2^26.)
            if !self.u_r2.q.val().get_bit(33) {
                self.w_uq.d.next = self.u_q1.q.val() + 1;
                self.w_ur.d.next = self.u_r2.q.val().get_bits::<32>(0);
                self.e_next.next = self.u_q1.q.val() + 1;
            } else {
                self.w_uq.d.next = self.u_q1.q.val();
                self.w_ur.d.next = self.u_r1.q.val();
                self.e_next.next = self.u_q1.q.val();
            }
            if self.last.q.val() {
                self.e_next.next = self.w_t.q.val();
                self.w_kind.d.next = 0.into();
            }
            self.pe_valid.d.next = true;
            self.pe_step.d.next = true;
            self.s_eprev.d.next = self.w_e.q.val();
            self.w_e.d.next = self.e_next.val();
            self.w_i.d.next = self.i_next.val();
            self.st.d.next = self.k_commit_step.val();
        } else if self.st.q.val() == self.k_commit_step.val() {
            self.commit.next = true;
            self.advance.next = true;
            self.st.d.next = self.k_pick.val();
        } else if (self.st.q.val() == self.k_cv0.val()) & self.c_cs_on.val() {
            // The stop ramp (model::stop): at rest (a dwell last, or a very long period)
            // there is none; else v0 = ⌊2^32/(Δ + 1)⌋.
            if self.s_rest.q.val() {
                self.cs_act.d.next = false;
                self.advance.next = true;
                self.st.d.next = self.k_pick.val();
            } else {
                self.setup.div_start.next = true;
                self.st.d.next = self.k_cv0w.val();
            }
        } else if (self.st.q.val() == self.k_cv0w.val()) & self.c_cs_on.val() {
            if self.setup.div_valid.val() {
                // v0 < 2^31; v0² into the pipelined multiplier (SetupPath).
                self.st.d.next = self.k_csq1.val();
            }
        } else if (self.st.q.val() == self.k_csq1.val()) & self.c_cs_on.val() {
            self.st.d.next = self.k_csq2.val();
        } else if (self.st.q.val() == self.k_csq2.val()) & self.c_cs_on.val() {
            self.st.d.next = self.k_cn.val();
        } else if (self.st.q.val() == self.k_cn.val()) & self.c_cs_on.val() {
            // v0² arrived: n = ⌊v0²/(2^8·DECEL)⌋ + 1.
            self.setup.div_start.next = true;
            self.st.d.next = self.k_cnw.val();
        } else if (self.st.q.val() == self.k_cnw.val()) & self.c_cs_on.val() {
            if self.setup.div_valid.val() {
                // n ≤ 2^24 (DECEL ≥ its minimum): the signed count and n·(Δ + 1) into
                // the multiplier (SetupPath).
                self.st.d.next = self.k_ct1.val();
            }
        } else if (self.st.q.val() == self.k_ct1.val()) & self.c_cs_on.val() {
            self.st.d.next = self.k_ct2.val();
        } else if (self.st.q.val() == self.k_ct2.val()) & self.c_cs_on.val() {
            self.st.d.next = self.k_ct.val();
        } else if (self.st.q.val() == self.k_ct.val()) & self.c_cs_on.val() {
            // T = 2n(Δ + 1) ≤ 2^30: the segment (v0, T, ±n) enters the setup as a queue
            // head would after S_CHECK (v0·T's operands in op_a and op_b).
            self.st.d.next = self.k_issue_vt.val();
        } else if self.st.q.val() == self.k_drain.val() {
            // After an abort: wait until no unit still runs an abandoned operation. Like
            // every way into PICK, it moves to axis m + 1 (PICK's flags are axis m + 1's).
            if !(self.setup.busy.val() | self.root.busy.val() | self.y_busy.val()) {
                self.advance.next = true;
                self.st.d.next = self.k_pick.val();
            }
        } else {
            self.advance.next = true;
            self.st.d.next = self.k_pick.val();
        }

        // Moving on to axis m + 1: its number, the one after it, and its context word's
        // address (its current slot), all registered.
        if self.advance.val() {
            self.m.d.next = self.next_m.val();
            self.nm.d.next = self.nn.val();
            self.ra.d.next = self.addr_next.val();
        }

        // The period entry (pe_valid): Δ = E − E_prev from registers (w_e holds the new
        // E, s_eprev the one before; a dwell's T and 0), with its step, direction (a
        // step's only) and last flags.
        self.pe_delta.next = self.w_e.q.val() - self.s_eprev.q.val();
        self.pe_entry.next = bit_cast::<ENTRY_BITS, 32>(self.pe_delta.val())
            | (bit_cast::<ENTRY_BITS, 1>(self.pe_step.q.val().into()) << 32)
            | (bit_cast::<ENTRY_BITS, 1>((self.w_rev.q.val() & self.pe_step.q.val()).into()) << 33)
            | (bit_cast::<ENTRY_BITS, 1>(self.pe_last.q.val().into()) << 34);

        // ---- context memory writes (after the scheduler decided them) ---------
        self.ctx_ram.we.next = self.commit.val() | self.nwe_now.val();
        self.ctx_ram.waddr.next = (bit_cast::<CTX_ADDR_BITS, 8>(self.m.q.val()) << 1)
            | bit_cast::<CTX_ADDR_BITS, 1>((self.w_slot.q.val() ^ self.nwe_now.val()).into());
        self.ctx_ram.w_rev.next = self.w_rev.q.val();
        self.ctx_ram.w_n.next = self.w_n.q.val();
        self.ctx_ram.w_i.next = self.w_i.q.val();
        self.ctx_ram.w_t.next = self.w_t.q.val();
        self.ctx_ram.w_e.next = self.w_e.q.val();
        self.ctx_ram.w_p.next = self.w_p.q.val();
        self.ctx_ram.w_b.next = self.w_b.q.val();
        self.ctx_ram.w_a.next = self.w_a.q.val();
        self.ctx_ram.w_uq.next = self.w_uq.q.val();
        self.ctx_ram.w_ur.next = self.w_ur.q.val();
        self.ctx_ram.w_uqs.next = self.w_uqs.q.val();
        self.ctx_ram.w_urs.next = self.w_urs.q.val();

        // ---- the S-curve option's lane: its inputs ---------------------------
        for i in 0..S {
            self.lanes[i].clock.next = self.clock.val();
            self.lanes[i].reset.next = self.reset.val();
            self.lanes[i].abort.next = self.abort.val();
            self.lanes[i].head.next = self.queues.head.val();
            self.lanes[i].head_extra.next = self.xram[i].rdata.val();
            self.lanes[i].setup.next = self.y_setup.val();
            self.lanes[i].step.next = self.y_step.val();
            self.lanes[i].axis.next = self.m.q.val();
            self.lanes[i].slot.next = self.y_slot.val();
            self.lanes[i].next_m.next = self.nm.q.val();
            self.lanes[i].nwe.next = self.nwe_now.val();
            // A setup's commit: from the queue unless it is a stop ramp or a dwell.
            self.lanes[i].from_queue.next = !self.cs_act.q.val() & !self.w_dwell.q.val();
            self.lanes[i].promote.next = self.promote_now.val();
            self.lanes[i].cut.next = self.axis_cut.val();
            self.lanes[i].axis_reset.next = self.axis_flush.val();
        }

        // ---- per-axis wiring ------------------------------------------------
        self.cmd_ok_axis.next = self.cmd_axis.val() <= self.c_last_axis.val();
        self.flush.next = self.reset.val() | self.abort.val();
        // The scheduler's period entries go through the bank's pulse stage to the FIFOs.
        self.bank.clock.next = self.clock.val();
        self.bank.reset.next = self.reset.val();
        self.bank.abort.next = self.abort.val();
        self.bank.high_min.next = self.high_min.val();
        self.bank.low_min.next = self.low_min.val();
        self.bank.push.next = self.pe_valid.q.val();
        self.bank.push_axis.next = self.m.q.val();
        self.bank.entry.next = self.pe_entry.val();
        self.bank.start.next = self.start.val();
        self.bank.start_mask.next = self.start_mask.val();
        self.bank.ext_go.next = self.ext_go.val();
        self.bank.sel_axis.next = self.sel_axis.val();
        self.bank.home_latch.next = self.home_latch.val();
        self.bank.probe_latch.next = self.probe_latch.val();
        self.bank.lsel_axis.next = self.lsel_axis.val();
        self.lsel_word.next = self.bank.lsel_word.val();
        self.bank.epos_axis.next = self.epos_axis.val();
        self.epos.next = self.bank.epos.val();
        self.pos_low.next = self.bank.pos_low.val();
        self.step.next = self.bank.step.val();
        self.dir.next = self.bank.dir.val();
        self.underrun.next = self.bank.underrun.val();
        self.active.next = self.bank.active.val();
        self.busy.next = self.bank.busy.val();
        self.ready.next = self.bank.ready.val();
        self.sel_position.next = self.bank.sel_position.val();
        self.sel_fifo.next = self.bank.sel_fifo.val();
        self.sel_done.next = self.bank.sel_done.val();
        self.sel_underruns.next = self.bank.sel_underruns.val();
        self.sel_busy.next = self.bank.sel_busy.val();
        // Commands into the queues; a command to an axis ≥ K is dropped (cmd_error).
        self.queues.clock.next = self.clock.val();
        self.queues.reset.next = self.reset.val();
        self.queues.abort.next = self.abort.val();
        self.queues.flush.next = self.axis_flush.val() | self.axis_cut.val() | self.axis_drop.val();
        self.ramp.clock.next = self.clock.val();
        self.ramp.reset.next = self.flush.val();
        self.ramp.request.next = self.cstop_axes.val() & self.c_cs.val();
        self.ramp.clear.next = self.cs_clear.val() & self.c_cs_on.val();
        self.ramp.clear_axis.next = self.m.q.val();
        self.ramp.last_we.next = self.pe_valid.q.val() & self.c_cs_on.val();
        self.ramp.last_axis.next = self.m.q.val().get_bits::<4>(0);
        self.ramp.last_delta.next = self.pe_delta.val();
        self.ramp.last_step.next = self.pe_step.q.val();
        self.ramp.last_rev.next = self.w_rev.q.val();
        self.ramp.raxis.next = self.m.q.val().get_bits::<4>(0);
        self.ramp.set_next.next = (self.st.q.val() == self.k_commit_setup.val()) & self.cs_act.q.val() & self.c_cs_on.val();
        self.ramp.promote.next = self.promote_now.val() & self.c_cs_on.val();
        self.ramp.active.next = self.bank.active.val();
        // Per-axis stops: kept until PICK flushes the axis (while the request is still
        // high it stays), the FIFO held one cycle more after the flush.
        self.m_bit.next = self.c_one_k.val() << self.m.q.val();
        self.fl_bit.next = 0.into();
        if self.fl_v.q.val() {
            self.fl_bit.next = self.c_one_k.val() << self.fl_a.q.val();
        }
        self.fl_v.d.next = self.axis_flush.val();
        self.fl_a.d.next = self.m.q.val();
        self.stop_pend.d.next = self.stop_all.val();
        if self.axis_flush.val() {
            self.stop_pend.d.next = ((self.stop_pend.q.val() & !self.m_bit.val()) | self.stop_axes.val()) & self.c_stops.val();
        }
        self.bank.stop.next = self.stop_all.val() | self.fl_bit.val();
        self.queues.pop.next = self.pop_now.val();
        self.queues.sel_axis.next = self.sel_axis.val();
        self.queues.push_valid.next = self.cmd_valid.val();
        self.queues.push_axis.next = self.cmd_axis.val();
        self.cmd_ready.next = self.queues.push_ready.val();
        self.sel_queue.next = self.queues.sel_level.val();
        self.sel_taken.next = self.queues.sel_taken.val();
        self.queues.push_word.next = bit_cast::<SEGMENT_BITS, 32>(self.cmd_v0.val())
            | (bit_cast::<SEGMENT_BITS, 32>(self.cmd_t.val()) << 32)
            | (bit_cast::<SEGMENT_BITS, 32>(self.cmd_steps.val()) << 64);
        // Axis m's context flags: a step's commit (kind), a setup's commit (next slot),
        // a promote, a controlled stop's cut, a stop's flush.
        self.view.we.next = self.commit.val();
        self.view.nwe.next = self.nwe_now.val();
        self.view.promote.next = self.promote_now.val();
        self.view.cut.next = self.axis_cut.val();
        self.view.axis_reset.next = self.axis_flush.val();
        self.view.new_dwell.next = self.w_dwell.q.val();
        self.view.new_kind.next = self.w_kind.q.val();
        self.view.cs_act.next = self.cs_act.q.val();
        // Work of each axis not yet turned into entries (the bank adds the entries in
        // flight for its `more`).
        self.bank.pending.next = self.view.pending.val();
        // (A command to an axis ≥ K is taken: the queues' `push_ready` is 1 for it.)
        if !self.cmd_ok_axis.val() {
            if self.cmd_valid.val() {
                self.cmd_err.d.next = true;
            }
        }
        self.fail_tog.d.next = self.fail_tog.q.val() ^ self.bank.failed.val();
        if self.reset.val() {
            self.fail_tog.d.next = false;
        }
        self.start_failed.next = self.fail_tog.q.val();
        if self.abort.val() {
            self.st.d.next = self.k_drain.val();
            self.pe_valid.d.next = false;
            self.cs_act.d.next = false;
        }
        if self.reset.val() {
            self.st.d.next = self.k_pick.val();
            self.m.d.next = 0.into();
            self.nm.d.next = self.c_first_next.val();
            self.ra.d.next = 0.into();
            self.cs_act.d.next = false;
            self.stop_pend.d.next = 0.into();
            self.fl_v.d.next = false;
            self.cmd_err.d.next = false;
            self.pe_valid.d.next = false;
        }
    }
}
