//! The register file, in the bus clock: the decoder of the register table
//! ([`crate::regs`]), the per-axis staging registers, the mirror of each axis's
//! status, the sticky flags and the events. Every address, identity value and
//! reset value comes from the table through a `Constant`. Three groups of global
//! registers are blocks of their own, each with its three-way test: the identity
//! ([`super::id_regs::IdRegs`]), the output timing ([`super::timing_regs::TimingRegs`])
//! and the interrupt flags, masks and QLOW_LEVEL ([`super::irq_regs::IrqRegs`]); this
//! block decodes the bus for them, feeds them its events and ORs their reads.
//!
//! **Writes** (`wr` from [`super::exmc::ExmcSlave`]) act at once: staging and control
//! registers load, W1C bits clear, and START, ABORT and STEPS_HI put a command on
//! `cmd_data` with `cmd_write` for the command FIFO (layout: [`CMD_BITS`]).
//! **Reads** are combinational on `rd_addr` (`rd_data`); the slave latches them. The
//! read's axis is decoded a cycle ahead from `rd_axis_next` into one-hot flip-flops,
//! and each per-axis field is an OR of the axes' values under their selects, so the
//! path to `rd_data` starts at flip-flops, not at a K:1 multiplexer. A read of POS_LO
//! latches the position's high half for POS_HI.
//!
//! **Memories.** The staging registers and the mirror live in LUT RAM addressed by
//! axis ([`LutRam`], 16 words: one more axis costs memory words, not flip-flops and
//! K:1 multiplexers): one RAM per staging half-word, written by the bus, read at the
//! writing axis while a write commits (a push takes the other five half-words) and
//! at the read address otherwise; the mirror's position and done count read at the
//! read address, and its done, rejected and underrun counters read at the status
//! word's axis. Per axis, a flip-flop per staging half-word and one for the mirror
//! say whether it was written since reset; one not written reads (and pushes) as 0,
//! its reset value. The taken counter, busy flag, push counter and sticky flags stay
//! in flip-flops: LEVEL, BUSY and the queue-full test need every axis at once.
//!
//! **Status** arrives one axis at a time (`st_valid`, `st_axis`, `st_word`, layout
//! [`STATUS_BITS`](super::status_sync::STATUS_BITS), see the `W_*` constants) and is
//! kept in the mirror. Comparing a new word with the mirror makes the events: a change
//! of the done or underrun counters sets IRQ_DONE and STATUS.UNDERRUN; a change of the taken counter with LEVEL now ≤
//! QLOW_LEVEL sets IRQ_QLOW. LEVEL is `pushed − taken` (8-bit counters, kept per axis
//! in a register a cycle behind them, before any read can follow the write), so a
//! push counts at once and a push is refused (OVERFLOW) when LEVEL has reached the queue
//! depth: the core's queue can never overflow and nothing queued is lost.
//!
//! **Commands** (a push, START, ABORT) reach `cmd_write`/`cmd_data` through the
//! [`PushCheck`], 4 cycles after their write: a rejected push sets STATUS.ERROR with
//! its code and IRQ_ERROR, and gives back the push count it took, so LEVEL never
//! counts it. A command written while the check is busy is refused (GSTATUS.REFUSED).
//!
//! **Enable.** While CTRL.ENABLE is 0 the core is held in reset and this side clears
//! its push counters, sticky flags and IRQ status. GSTATUS.ENABLED follows the core's
//! own view, taken from the status word of the last axis, so it says 1 only after a
//! whole round of status words from the running core; commands are accepted only
//! while ENABLE and ENABLED are both 1 (else GSTATUS.REFUSED).

use super::bit_insert::BitInsert;
use super::id_regs::IdRegs;
use super::irq_regs::IrqRegs;
use super::timing_regs::TimingRegs;
use super::lut_ram::LutRam;
use super::push_check::{PushCheck, CMD_EXTRA_BITS};
use crate::model::Limits;
use super::status_sync::STATUS_BITS;
use crate::regs::{self, CoreParams, ADDR_BITS};
use rust_hdl::prelude::*;

pub use crate::regs::CMD_BITS;
/// Status word fields (bit offsets): position (32 bits), segments taken, done,
/// underruns (8 bits each), busy, core enabled.
pub const W_POS: usize = 0;
pub const W_TAKEN: usize = 32;
pub const W_DONE: usize = 40;
pub const W_UNDERRUNS: usize = 48;
pub const W_BUSY: usize = 56;
pub const W_ENABLED: usize = 57;
// (The decoder below writes these offsets as literals: rust-hdl would print a Rust
// constant's name into the Verilog. tests/system.rs reads every field back.)

/// The word address of register `name` (axis 0's for a per-axis one), as a constant.
pub(super) fn c9(name: &str) -> Constant<Bits<ADDR_BITS>> {
    Constant::new((regs::addr(name) as u64).into())
}

fn c4(name: &str) -> Constant<Bits<4>> {
    let r = regs::register(name);
    assert!(r.per_axis);
    Constant::new((r.offset as u64).into())
}

fn c16(v: u16) -> Constant<Bits<16>> {
    Constant::new((v as u64).into())
}

#[derive(LogicBlock)]
pub struct RegFile<const K: usize, const S: usize = 0> {
    pub clock: Signal<In, Clock>,
    pub reset: Signal<In, Bit>,
    pub wr: Signal<In, Bit>,
    pub wr_addr: Signal<In, Bits<ADDR_BITS>>,
    pub wr_data: Signal<In, Bits<16>>,
    /// `wr` and the axis field (bits 7..4) of `wr_addr` of the next cycle (the bus
    /// slave's): the staging memories' read address is chosen a cycle ahead, into a
    /// flip-flop.
    pub wr_next: Signal<In, Bit>,
    pub wr_axis_next: Signal<In, Bits<4>>,
    pub rd: Signal<In, Bit>,
    pub rd_addr: Signal<In, Bits<ADDR_BITS>>,
    /// Bits 8..4 (the per-axis flag and the axis) of the address `rd_addr` will hold
    /// in the next cycle (the bus slave's first address stage): the read's axis is
    /// decoded from them a cycle ahead, into flip-flops, so no K:1 multiplexer
    /// selected by `rd_addr` stands in front of `rd_data`.
    pub rd_axis_next: Signal<In, Bits<5>>,
    pub rd_data: Signal<Out, Bits<16>>,
    pub st_valid: Signal<In, Bit>,
    pub st_axis: Signal<In, Bits<8>>,
    pub st_word: Signal<In, Bits<STATUS_BITS>>,
    pub cmd_full: Signal<In, Bit>,
    /// The command FIFO's `almost_full` (DEPTH − 1 entries or more, a cycle old).
    pub cmd_almost_full: Signal<In, Bit>,
    pub cmd_write: Signal<Out, Bit>,
    pub cmd_data: Signal<Out, Bits<CMD_BITS>>,
    /// CTRL.ENABLE.
    pub enable: Signal<Out, Bit>,
    /// Output timing for the core: max(STEP_HIGH, DIR_HOLD) and max(STEP_LOW,
    /// DIR_SETUP), registers that change only while the core is held in reset.
    pub high_min: Signal<Out, Bits<16>>,
    pub low_min: Signal<Out, Bits<16>>,
    /// Toggles (synchronised from clk) each time the core cancels a START.
    pub start_fail_toggle: Signal<In, Bit>,
    pub irq: Signal<Out, Bit>,
    /// The machine I/O's push guard ([`super::push_guard::PushGuard`]): the command
    /// written into the push check this cycle (`offer`, its kind, axis and steps), the
    /// push count of the status word's axis (`st_pushed`), and the guard's code, which
    /// the check merges into its verdict in cycle 3 (`guard_code`; tied to 0 without it).
    pub offer: Signal<Out, Bit>,
    pub offer_kind: Signal<Out, Bits<2>>,
    pub offer_axis: Signal<Out, Bits<4>>,
    pub offer_steps: Signal<Out, Bits<32>>,
    pub st_pushed: Signal<Out, Bits<8>>,
    pub guard_code: Signal<In, Bits<4>>,
    /// The S-curve option (S = 1; [`super::poly_regs::PolyRegs`]): POLY_ARM makes the
    /// next push polynomial (command kind 3) with `poly_extra` (v1, A'), which the
    /// check takes with it; `cmd_extra` gives them with the push's `cmd_write`.
    pub poly_arm: Signal<In, Bit>,
    pub poly_extra: Signal<In, Bits<CMD_EXTRA_BITS>>,
    pub cmd_extra: Signal<Out, Bits<CMD_EXTRA_BITS>>,

    /// Staging, one LUT RAM per half-word register (V0_LO, V0_HI, T_LO, T_HI,
    /// STEPS_LO, STEPS_HI), addressed by axis.
    st_ram: [LutRam<16, 4>; 6],
    /// Which staging half-words of each axis were written since reset (a half-word
    /// not yet written reads, and pushes, as 0: its reset value).
    st_vld: [DFF<Bits<6>>; K],
    /// Mirror read by the bus: {done count (39..32), position (31..0)} at `r_axis`.
    mb_ram: LutRam<40, 4>,
    /// Mirror read by the event logic: {underruns, done} at `st_axis`.
    mc_ram: LutRam<16, 4>,
    /// Every command on its way to the command FIFO: pushes validated here.
    chk: PushCheck<S>,
    /// The identity, output timing and interrupt registers: blocks of their own.
    ids: IdRegs,
    tim: TimingRegs,
    irqs: IrqRegs,
    c_poly: Constant<Bit>,
    /// A polynomial push while the polynomial check is still busy: refused.
    p_refuse: Signal<Local, Bit>,
    /// A status word of this axis has arrived since reset (POS and DONE_COUNT read 0
    /// before it).
    m_vld: [DFF<Bit>; K],
    pushed: [DFF<Bits<8>>; K],
    /// LEVEL ≥ the queue depth, registered (see "Pushes" below).
    q_full: [DFF<Bit>; K],
    m_taken: [DFF<Bits<8>>; K],
    m_busy: [DFF<Bit>; K],
    /// LEVEL and BUSY of each axis in flip-flops of their own, so the read
    /// multiplexers and BUSY select registers with no subtraction in front:
    /// `pushed − m_taken` of the cycle before, less a push the check rejects in that
    /// cycle (see "Per axis" below).
    lv: [DFF<Bits<8>>; K],
    bz: [DFF<Bit>; K],
    f_under: [DFF<Bit>; K],
    f_over: [DFF<Bit>; K],
    f_err: [DFF<Bit>; K],
    f_code: [DFF<Bits<4>>; K],
    busy_bus: [BitInsert<16>; K],
    /// The read addresses axis i's registers (decoded from `rd_axis_next`, so valid
    /// with `rd_addr`): one-hot, or all 0 for a global register or an axis ≥ K.
    rq_sel: [DFF<Bit>; K],
    /// The staging memories' read address: the writing axis while a write commits,
    /// else the read axis (set a cycle ahead from the `_next` inputs).
    st_aq: DFF<Bits<4>>,
    /// The writing axis's queue-full flag and staging flags (bits 0..4), registered
    /// at `wr_axis_next` a cycle ahead of its write.
    w_fq: DFF<Bit>,
    w_vq: DFF<Bits<5>>,
    ctrl_en: DFF<Bit>,
    core_en: DFF<Bit>,
    refused: DFF<Bit>,
    /// The QLOW test's first stage, registered from a status word: whether its taken
    /// count moved (and events are accepted), the axis's `pushed` and the new taken
    /// count, and the axis. The level test and IRQ_QLOW follow a cycle later, so the
    /// K-way selection of `pushed` and the subtraction are not in one path.
    ql_valid: DFF<Bit>,
    ql_pushed: DFF<Bits<8>>,
    ql_taken: DFF<Bits<8>>,
    ql_axis: DFF<Bits<8>>,
    fail_prev: DFF<Bit>,
    start_failed: DFF<Bit>,
    start_last: DFF<Bits<16>>,
    c_axmask: Constant<Bits<16>>,
    pos_latch: DFF<Bits<16>>,

    accepting: Signal<Local, Bit>,
    w_glob: Signal<Local, Bit>,
    w_ax: Signal<Local, Bit>,
    w_axis: Signal<Local, Bits<4>>,
    w_off: Signal<Local, Bits<4>>,
    w_data32: Signal<Local, Bits<32>>,
    w_ok: Signal<Local, Bit>,
    w_hw: Signal<Local, Bits<6>>,
    h0: Signal<Local, Bits<16>>,
    h1: Signal<Local, Bits<16>>,
    h2: Signal<Local, Bits<16>>,
    h3: Signal<Local, Bits<16>>,
    h4: Signal<Local, Bits<16>>,
    r_ax: Signal<Local, Bit>,
    r_axis: Signal<Local, Bits<4>>,
    r_off: Signal<Local, Bits<4>>,
    s_pos: Signal<Local, Bits<32>>,
    s_taken: Signal<Local, Bits<8>>,
    s_done: Signal<Local, Bits<8>>,
    s_under: Signal<Local, Bits<8>>,
    s_busy: Signal<Local, Bit>,
    s_en: Signal<Local, Bit>,
    o_taken: Signal<Local, Bits<8>>,
    o_done: Signal<Local, Bits<8>>,
    o_under: Signal<Local, Bits<8>>,
    o_pushed: Signal<Local, Bits<8>>,
    s_onehot: Signal<Local, Bits<16>>,
    ql_onehot: Signal<Local, Bits<16>>,
    w_onehot: Signal<Local, Bits<16>>,
    ev_done: Signal<Local, Bits<16>>,
    ev_qlow: Signal<Local, Bits<16>>,
    ev_err: Signal<Local, Bits<16>>,
    push_ok: Signal<Local, Bit>,
    c_busy: Signal<Local, Bit>,
    fifo_full: Signal<Local, Bit>,
    c_write: Signal<Local, Bit>,
    c_data: Signal<Local, Bits<CMD_BITS>>,
    rej_onehot: Signal<Local, Bits<16>>,
    x_v0: Signal<Local, Bits<32>>,
    x_t: Signal<Local, Bits<32>>,
    x_steps: Signal<Local, Bits<32>>,
    r_sel: Signal<Local, Bit>,
    /// The global registers' read value, and the read axis's (0 where none matches).
    g_data: Signal<Local, Bits<16>>,
    a_data: Signal<Local, Bits<16>>,
    rn_axis: Signal<Local, Bits<4>>,
    r_vld: Signal<Local, Bits<6>>,
    r_level: Signal<Local, Bits<8>>,
    r_busy: Signal<Local, Bit>,
    r_fu: Signal<Local, Bit>,
    r_fo: Signal<Local, Bit>,
    r_fe: Signal<Local, Bit>,
    r_code: Signal<Local, Bits<4>>,
    r_mvld: Signal<Local, Bit>,
    r_pos: Signal<Local, Bits<32>>,
    r_done: Signal<Local, Bits<8>>,

    c_one: Constant<Bits<16>>,
    c_qdepth: Constant<Bits<8>>,
    c_last_axis: Constant<Bits<8>>,
    a_ctrl: Constant<Bits<ADDR_BITS>>,
    a_start: Constant<Bits<ADDR_BITS>>,
    a_abort: Constant<Bits<ADDR_BITS>>,
    a_gstatus: Constant<Bits<ADDR_BITS>>,
    a_busy: Constant<Bits<ADDR_BITS>>,
    o_v0_lo: Constant<Bits<4>>,
    o_v0_hi: Constant<Bits<4>>,
    o_t_lo: Constant<Bits<4>>,
    o_t_hi: Constant<Bits<4>>,
    o_steps_lo: Constant<Bits<4>>,
    o_steps_hi: Constant<Bits<4>>,
    o_status: Constant<Bits<4>>,
    o_pos_lo: Constant<Bits<4>>,
    o_pos_hi: Constant<Bits<4>>,
    o_done_count: Constant<Bits<4>>,
}

impl<const K: usize, const S: usize> RegFile<K, S> {
    pub fn new(p: CoreParams) -> Self {
        assert_eq!(p.axes, K, "RegFile: parameters for another K");
        assert!((1..=regs::MAX_AXES).contains(&K), "RegFile: K = {K} outside 1..={}", regs::MAX_AXES);
        assert!((1..=regs::MAX_QUEUE_DEPTH).contains(&p.queue_depth), "RegFile: queue depth {} outside 1..=16", p.queue_depth);
        RegFile {
            clock: Default::default(),
            reset: Default::default(),
            wr: Default::default(),
            wr_addr: Default::default(),
            wr_data: Default::default(),
            wr_next: Default::default(),
            wr_axis_next: Default::default(),
            rd: Default::default(),
            rd_addr: Default::default(),
            rd_axis_next: Default::default(),
            rd_data: Default::default(),
            st_valid: Default::default(),
            st_axis: Default::default(),
            st_word: Default::default(),
            cmd_full: Default::default(),
            cmd_almost_full: Default::default(),
            cmd_write: Default::default(),
            cmd_data: Default::default(),
            enable: Default::default(),
            high_min: Default::default(),
            low_min: Default::default(),
            start_fail_toggle: Default::default(),
            offer: Default::default(),
            offer_kind: Default::default(),
            offer_axis: Default::default(),
            offer_steps: Default::default(),
            st_pushed: Default::default(),
            guard_code: Default::default(),
            irq: Default::default(),
            st_ram: std::array::from_fn(|_| Default::default()),
            st_vld: std::array::from_fn(|_| Default::default()),
            mb_ram: Default::default(),
            mc_ram: Default::default(),
            chk: PushCheck::new(Limits { min_period_ticks: p.min_period }),
            ids: IdRegs::new(&p),
            tim: TimingRegs::new(p.min_period),
            irqs: IrqRegs::default(),
            c_poly: Constant::new(S > 0),
            p_refuse: Default::default(),
            poly_arm: Default::default(),
            poly_extra: Default::default(),
            cmd_extra: Default::default(),
            m_vld: std::array::from_fn(|_| Default::default()),
            pushed: std::array::from_fn(|_| Default::default()),
            q_full: std::array::from_fn(|_| Default::default()),
            m_taken: std::array::from_fn(|_| Default::default()),
            m_busy: std::array::from_fn(|_| Default::default()),
            lv: std::array::from_fn(|_| Default::default()),
            bz: std::array::from_fn(|_| Default::default()),
            f_under: std::array::from_fn(|_| Default::default()),
            f_over: std::array::from_fn(|_| Default::default()),
            f_err: std::array::from_fn(|_| Default::default()),
            f_code: std::array::from_fn(|_| Default::default()),
            busy_bus: std::array::from_fn(BitInsert::new),
            rq_sel: std::array::from_fn(|_| Default::default()),
            st_aq: Default::default(),
            w_fq: Default::default(),
            w_vq: Default::default(),
            ctrl_en: Default::default(),
            core_en: Default::default(),
            refused: Default::default(),
            ql_valid: Default::default(),
            ql_pushed: Default::default(),
            ql_taken: Default::default(),
            ql_axis: Default::default(),
            fail_prev: Default::default(),
            start_failed: Default::default(),
            start_last: Default::default(),
            c_axmask: Constant::new((((1u64 << K) - 1) as u64).into()),
            pos_latch: Default::default(),
            accepting: Default::default(),
            w_glob: Default::default(),
            w_ax: Default::default(),
            w_axis: Default::default(),
            w_off: Default::default(),
            w_data32: Default::default(),
            w_ok: Default::default(),
            w_hw: Default::default(),
            h0: Default::default(),
            h1: Default::default(),
            h2: Default::default(),
            h3: Default::default(),
            h4: Default::default(),
            r_ax: Default::default(),
            r_axis: Default::default(),
            r_off: Default::default(),
            s_pos: Default::default(),
            s_taken: Default::default(),
            s_done: Default::default(),
            s_under: Default::default(),
            s_busy: Default::default(),
            s_en: Default::default(),
            o_taken: Default::default(),
            o_done: Default::default(),
            o_under: Default::default(),
            o_pushed: Default::default(),
            s_onehot: Default::default(),
            ql_onehot: Default::default(),
            w_onehot: Default::default(),
            ev_done: Default::default(),
            ev_qlow: Default::default(),
            ev_err: Default::default(),
            push_ok: Default::default(),
            c_busy: Default::default(),
            fifo_full: Default::default(),
            c_write: Default::default(),
            c_data: Default::default(),
            rej_onehot: Default::default(),
            x_v0: Default::default(),
            x_t: Default::default(),
            x_steps: Default::default(),
            r_sel: Default::default(),
            g_data: Default::default(),
            a_data: Default::default(),
            rn_axis: Default::default(),
            r_vld: Default::default(),
            r_level: Default::default(),
            r_busy: Default::default(),
            r_fu: Default::default(),
            r_fo: Default::default(),
            r_fe: Default::default(),
            r_code: Default::default(),
            r_mvld: Default::default(),
            r_pos: Default::default(),
            r_done: Default::default(),
            c_one: c16(1),
            c_qdepth: Constant::new((p.queue_depth as u64).into()),
            c_last_axis: Constant::new(((K - 1) as u64).into()),
            a_ctrl: c9("CTRL"),
            a_start: c9("START"),
            a_abort: c9("ABORT"),
            a_gstatus: c9("GSTATUS"),
            a_busy: c9("BUSY"),
            o_v0_lo: c4("V0_LO"),
            o_v0_hi: c4("V0_HI"),
            o_t_lo: c4("T_LO"),
            o_t_hi: c4("T_HI"),
            o_steps_lo: c4("STEPS_LO"),
            o_steps_hi: c4("STEPS_HI"),
            o_status: c4("STATUS"),
            o_pos_lo: c4("POS_LO"),
            o_pos_hi: c4("POS_HI"),
            o_done_count: c4("DONE_COUNT"),
        }
    }
}

impl<const K: usize, const S: usize> Logic for RegFile<K, S> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clock, ctrl_en, core_en, refused, pos_latch, fail_prev, start_failed, start_last,
            ql_valid, ql_pushed, ql_taken, ql_axis, st_aq, w_fq, w_vq
        );
        self.rn_axis.next = self.rd_axis_next.val().get_bits::<4>(0);
        // The register map's own blocks: identity, output timing, interrupts.
        self.ids.rd_addr.next = self.rd_addr.val();
        self.tim.clock.next = self.clock.val();
        self.tim.reset.next = self.reset.val();
        self.tim.wr_addr.next = self.wr_addr.val();
        self.tim.wr_data.next = self.wr_data.val();
        self.tim.locked.next = self.ctrl_en.q.val() | self.core_en.q.val();
        self.tim.rd_addr.next = self.rd_addr.val();
        self.high_min.next = self.tim.high_min.val();
        self.low_min.next = self.tim.low_min.val();
        self.irqs.clock.next = self.clock.val();
        self.irqs.reset.next = self.reset.val();
        self.irqs.enable.next = self.ctrl_en.q.val();
        self.irqs.wr_addr.next = self.wr_addr.val();
        self.irqs.wr_data.next = self.wr_data.val();
        self.irqs.rd_addr.next = self.rd_addr.val();
        for i in 0..K {
            self.st_vld[i].clock.next = self.clock.val();
            self.rq_sel[i].clock.next = self.clock.val();
            self.rq_sel[i].d.next = self.rd_axis_next.val().get_bit(4) & (self.rn_axis.val().index() == i);
            self.m_vld[i].clock.next = self.clock.val();
            self.pushed[i].clock.next = self.clock.val();
            self.q_full[i].clock.next = self.clock.val();
            self.lv[i].clock.next = self.clock.val();
            self.bz[i].clock.next = self.clock.val();
            self.m_taken[i].clock.next = self.clock.val();
            self.m_busy[i].clock.next = self.clock.val();
            self.f_under[i].clock.next = self.clock.val();
            self.f_over[i].clock.next = self.clock.val();
            self.f_err[i].clock.next = self.clock.val();
            self.f_code[i].clock.next = self.clock.val();
            self.st_vld[i].d.next = self.st_vld[i].q.val();
            self.m_vld[i].d.next = self.m_vld[i].q.val();
            self.pushed[i].d.next = self.pushed[i].q.val();
            self.m_taken[i].d.next = self.m_taken[i].q.val();
            self.m_busy[i].d.next = self.m_busy[i].q.val();
            self.f_under[i].d.next = self.f_under[i].q.val();
            self.f_over[i].d.next = self.f_over[i].q.val();
            self.f_err[i].d.next = self.f_err[i].q.val();
            self.f_code[i].d.next = self.f_code[i].q.val();
        }
        self.enable.next = self.ctrl_en.q.val();
        self.irq.next = self.irqs.irq.val();
        self.accepting.next = self.ctrl_en.q.val() & self.core_en.q.val();
        self.c_write.next = false;
        // The push check: busy while a command is in flight; its verdict 4 cycles on.
        self.chk.clock.next = self.clock.val();
        self.chk.reset.next = self.reset.val() | !self.ctrl_en.q.val();
        self.c_busy.next = self.chk.busy.val();
        // No room in the command FIFO for a command taken now: full, or one slot left
        // and the check's previous command going into it at this very edge (a command
        // taken in the check's last cycle; else the check's one command at a time
        // means `cmd_full` already counts every write before this one's, 4 cycles on).
        // A polynomial push in flight (S = 1) goes into the FIFO in its cycle 6, after a
        // command taken in its cycle 4 or 5 is decided: that one needs two free slots.
        self.fifo_full.next = self.cmd_full.val()
            | (self.cmd_almost_full.val() & (self.chk.out_valid.val() | (self.chk.poly_busy.val() & self.c_poly.val())));
        self.p_refuse.next = self.poly_arm.val() & self.chk.poly_busy.val() & self.c_poly.val();
        self.cmd_write.next = self.chk.out_valid.val();
        self.cmd_data.next = self.chk.out_data.val();
        self.cmd_extra.next = self.chk.out_extra.val();
        self.rej_onehot.next = 0.into();
        if self.chk.rej_valid.val() {
            self.rej_onehot.next = self.c_one.val() << bit_cast::<16, 4>(self.chk.rej_axis.val());
        }

        // ---- decode ----------------------------------------------------------
        self.w_glob.next = self.wr.val() & !self.wr_addr.val().get_bit(8);
        self.w_ax.next = self.wr.val() & self.wr_addr.val().get_bit(8);
        self.tim.wr.next = self.w_glob.val();
        self.irqs.wr.next = self.w_glob.val();
        self.w_axis.next = self.wr_addr.val().get_bits::<4>(4);
        self.w_off.next = self.wr_addr.val().get_bits::<4>(0);
        self.w_data32.next = bit_cast::<32, 16>(self.wr_data.val());
        self.w_onehot.next = self.c_one.val() << bit_cast::<16, 4>(self.w_axis.val());
        self.r_ax.next = self.rd_addr.val().get_bit(8);
        self.r_axis.next = self.rd_addr.val().get_bits::<4>(4);
        self.r_off.next = self.rd_addr.val().get_bits::<4>(0);
        self.s_pos.next = self.st_word.val().get_bits::<32>(0);
        self.s_taken.next = self.st_word.val().get_bits::<8>(32);
        self.s_done.next = self.st_word.val().get_bits::<8>(40);
        self.s_under.next = self.st_word.val().get_bits::<8>(48);
        self.s_busy.next = self.st_word.val().get_bit(56);
        self.s_en.next = self.st_word.val().get_bit(57);
        self.s_onehot.next = self.c_one.val() << bit_cast::<16, 8>(self.st_axis.val());
        self.w_ok.next = self.w_ax.val() & (self.w_axis.val() <= bit_cast::<4, 8>(self.c_last_axis.val()));
        // Which staging half-word a write addresses (one-hot, V0_LO first).
        self.w_hw.next = 0.into();
        if self.w_off.val() == self.o_v0_lo.val() {
            self.w_hw.next = 1.into();
        }
        if self.w_off.val() == self.o_v0_hi.val() {
            self.w_hw.next = 2.into();
        }
        if self.w_off.val() == self.o_t_lo.val() {
            self.w_hw.next = 4.into();
        }
        if self.w_off.val() == self.o_t_hi.val() {
            self.w_hw.next = 8.into();
        }
        if self.w_off.val() == self.o_steps_lo.val() {
            self.w_hw.next = 16.into();
        }
        if self.w_off.val() == self.o_steps_hi.val() {
            self.w_hw.next = 32.into();
        }

        // ---- memories --------------------------------------------------------
        // Staging: written at the writing axis, read at the same axis while a write
        // commits (the push reads the other five half-words) and at the read axis
        // otherwise (the slave latches a read at `rd`, which never coincides with
        // `wr` when the bus keeps its documented timing).
        if self.wr_next.val() {
            self.st_aq.d.next = self.wr_axis_next.val();
        } else {
            self.st_aq.d.next = self.rn_axis.val();
        }
        for j in 0..6 {
            self.st_ram[j].clock.next = self.clock.val();
            self.st_ram[j].we.next = self.w_ok.val() & self.w_hw.val().get_bit(j);
            self.st_ram[j].waddr.next = self.w_axis.val();
            self.st_ram[j].wdata.next = self.wr_data.val();
            self.st_ram[j].raddr.next = self.st_aq.q.val();
        }
        self.mb_ram.clock.next = self.clock.val();
        self.mb_ram.we.next = self.st_valid.val();
        self.mb_ram.waddr.next = self.st_axis.val().get_bits::<4>(0);
        self.mb_ram.wdata.next = bit_cast::<40, 32>(self.s_pos.val()) | (bit_cast::<40, 8>(self.s_done.val()) << 32);
        self.mb_ram.raddr.next = self.r_axis.val();
        self.mc_ram.clock.next = self.clock.val();
        self.mc_ram.we.next = self.st_valid.val();
        self.mc_ram.waddr.next = self.st_axis.val().get_bits::<4>(0);
        self.mc_ram.wdata.next = bit_cast::<16, 8>(self.s_done.val()) | (bit_cast::<16, 8>(self.s_under.val()) << 8);
        self.mc_ram.raddr.next = self.st_axis.val().get_bits::<4>(0);
        self.o_done.next = self.mc_ram.rdata.val().get_bits::<8>(0);
        self.o_under.next = self.mc_ram.rdata.val().get_bits::<8>(8);

        // The mirror's previous values for the axis in the status word, and the
        // level of the axis being written.
        self.o_taken.next = 0.into();
        self.o_pushed.next = 0.into();
        // The writing axis's queue-full flag and staging flags are taken a cycle ahead,
        // at `wr_axis_next`, into flip-flops (no K:1 multiplexer between the write
        // address and the push's decision or data). A cycle older is still exact for
        // pushes: the slave commits writes at least three cycles apart, so the flags
        // have seen the previous write (see "pushes" below).
        self.w_fq.d.next = false;
        self.w_vq.d.next = 0.into();
        for i in 0..K {
            if self.st_axis.val().index() == i {
                self.o_taken.next = self.m_taken[i].q.val();
                self.o_pushed.next = self.pushed[i].q.val();
            }
            if self.wr_axis_next.val().index() == i {
                self.w_fq.d.next = self.q_full[i].q.val();
                self.w_vq.d.next = self.st_vld[i].q.val().get_bits::<5>(0);
            }
        }
        // The staging half-words of the writing axis (a push reads them while its write
        // commits, when `st_aq` is that axis), 0 where not written since reset.
        self.h0.next = 0.into();
        self.h1.next = 0.into();
        self.h2.next = 0.into();
        self.h3.next = 0.into();
        self.h4.next = 0.into();
        if self.w_vq.q.val().get_bit(0) {
            self.h0.next = self.st_ram[0].rdata.val();
        }
        if self.w_vq.q.val().get_bit(1) {
            self.h1.next = self.st_ram[1].rdata.val();
        }
        if self.w_vq.q.val().get_bit(2) {
            self.h2.next = self.st_ram[2].rdata.val();
        }
        if self.w_vq.q.val().get_bit(3) {
            self.h3.next = self.st_ram[3].rdata.val();
        }
        if self.w_vq.q.val().get_bit(4) {
            self.h4.next = self.st_ram[4].rdata.val();
        }
        self.x_v0.next = bit_cast::<32, 16>(self.h0.val()) | (bit_cast::<32, 16>(self.h1.val()) << 16);
        self.x_t.next = bit_cast::<32, 16>(self.h2.val()) | (bit_cast::<32, 16>(self.h3.val()) << 16);
        self.x_steps.next = bit_cast::<32, 16>(self.h4.val()) | (self.w_data32.val() << 16);

        // ---- events from the status word -------------------------------------
        self.ev_done.next = 0.into();
        self.ev_qlow.next = 0.into();
        self.ev_err.next = 0.into();
        if self.st_valid.val() & self.accepting.val() {
            if self.s_done.val() != self.o_done.val() {
                self.ev_done.next = self.s_onehot.val();
            }
            if self.s_under.val() != self.o_under.val() {
                self.ev_err.next = self.s_onehot.val();
            }
        }
        // QLOW, in two stages: a status word whose taken count moved registers the
        // axis's `pushed` (the value at the word, as a one-stage test would read it)
        // and the new count; the next cycle compares the level with the threshold.
        self.ql_valid.d.next = self.st_valid.val() & self.accepting.val() & (self.s_taken.val() != self.o_taken.val());
        self.ql_pushed.d.next = self.o_pushed.val();
        self.ql_taken.d.next = self.s_taken.val();
        self.ql_axis.d.next = self.st_axis.val();
        self.ql_onehot.next = self.c_one.val() << bit_cast::<16, 8>(self.ql_axis.q.val());
        if self.ql_valid.q.val()
            & self.accepting.val()
            & ((self.ql_pushed.q.val() - self.ql_taken.q.val()) <= bit_cast::<8, 5>(self.irqs.qlow_level.val()))
        {
            self.ev_qlow.next = self.ql_onehot.val();
        }
        if self.reset.val() {
            self.ql_valid.d.next = false;
        }
        if self.st_valid.val() & (self.st_axis.val() == self.c_last_axis.val()) {
            self.core_en.d.next = self.s_en.val();
        }

        // ---- pushes ----------------------------------------------------------
        // The queue-full test reads a registered flag, two cycles behind `pushed` and
        // the mirror (a flag registered from them, taken a cycle ahead at the write's
        // axis), so neither the level subtraction nor an axis multiplexer is on the
        // path into the command FIFO. That is exact for pushes: the slave commits a
        // write at most every third cycle (two samples with NWE low, one high), and
        // the flag has seen the previous push by then. A segment the core takes (or a
        // push the check rejects) in the two cycles before a push is seen later, which
        // can only refuse a push that would just have fitted.
        self.push_ok.next = false;
        if self.w_ok.val() & (self.w_off.val() == self.o_steps_hi.val()) {
            if !self.accepting.val() | self.c_busy.val() | self.p_refuse.val() {
                self.refused.d.next = true;
            } else if self.fifo_full.val() | self.w_fq.q.val() {
                self.ev_err.next = self.ev_err.val() | self.w_onehot.val();
            } else {
                self.push_ok.next = true;
            }
        }

        // A START the core cancelled (a masked axis had nothing to run): GSTATUS.START_FAILED
        // and an error event for each axis of that START's mask.
        self.fail_prev.d.next = self.start_fail_toggle.val();
        if (self.fail_prev.q.val() != self.start_fail_toggle.val()) & self.accepting.val() {
            self.start_failed.d.next = true;
            self.ev_err.next = self.ev_err.val() | self.start_last.q.val();
        }

        // A rejected push: STATUS.ERROR with the code, IRQ_ERROR, and LEVEL no longer
        // counts it (below).
        self.ev_err.next = self.ev_err.val() | self.rej_onehot.val();
        // The command's data is the push's unless the write address is START's or
        // ABORT's, whether or not a command is written (the check's v0 + RMAX adder
        // takes the push's v0 on a port of its own, `in_v0`, before this select).
        self.c_data.next = bit_cast::<CMD_BITS, 32>(self.x_v0.val())
            | (bit_cast::<CMD_BITS, 32>(self.x_t.val()) << 32)
            | (bit_cast::<CMD_BITS, 32>(self.x_steps.val()) << 64)
            | (bit_cast::<CMD_BITS, 4>(self.w_axis.val()) << 96);
        // An armed push is polynomial (kind 3).
        if self.poly_arm.val() & self.c_poly.val() {
            self.c_data.next = self.c_data.val() | (bit_cast::<CMD_BITS, 2>(3.into()) << 104);
        }
        if self.push_ok.val() {
            self.c_write.next = true;
        }
        // START's and ABORT's data, chosen by the write address alone (the decision to
        // write them is `c_write`'s, below).
        if self.wr_addr.val() == self.a_start.val() {
            self.c_data.next = bit_cast::<CMD_BITS, 16>(self.wr_data.val()) | (bit_cast::<CMD_BITS, 2>(1.into()) << 104);
        }
        if self.wr_addr.val() == self.a_abort.val() {
            self.c_data.next = bit_cast::<CMD_BITS, 2>(2.into()) << 104;
        }

        // ---- per axis ----------------------------------------------------------
        for i in 0..K {
            // Staging writes.
            if self.w_ax.val() & (self.w_axis.val().index() == i) {
                self.st_vld[i].d.next = self.st_vld[i].q.val() | self.w_hw.val();
                if self.w_off.val() == self.o_steps_hi.val() {
                    if self.push_ok.val() {
                        self.pushed[i].d.next = self.pushed[i].q.val() + 1;
                    } else if self.accepting.val() & !self.c_busy.val() & !self.p_refuse.val() {
                        self.f_over[i].d.next = true;
                    }
                }
                if self.w_off.val() == self.o_status.val() {
                    if self.wr_data.val().get_bit(6) {
                        self.f_under[i].d.next = false;
                    }
                    if self.wr_data.val().get_bit(7) {
                        self.f_over[i].d.next = false;
                    }
                    if self.wr_data.val().get_bit(8) {
                        self.f_err[i].d.next = false;
                        self.f_code[i].d.next = 0.into();
                    }
                }
            }
            // The status word of axis i.
            if self.st_valid.val() & (self.st_axis.val().index() == i) {
                self.m_vld[i].d.next = true;
                self.m_taken[i].d.next = self.s_taken.val();
                self.m_busy[i].d.next = self.s_busy.val();
                if self.accepting.val() & (self.s_under.val() != self.o_under.val()) {
                    self.f_under[i].d.next = true;
                }
            }
            // A push rejected by the check: counted at its write, uncounted now (a
            // push of the same axis in this cycle keeps the count).
            if self.chk.rej_valid.val() & (self.chk.rej_axis.val().index() == i) {
                self.f_err[i].d.next = true;
                self.f_code[i].d.next = self.chk.rej_code.val();
                if self.push_ok.val() & (self.w_axis.val().index() == i) {
                    self.pushed[i].d.next = self.pushed[i].q.val();
                } else {
                    self.pushed[i].d.next = self.pushed[i].q.val() - 1;
                }
            }
            self.busy_bus[i].value.next = self.bz[i].q.val();
            if !self.ctrl_en.q.val() {
                self.pushed[i].d.next = 0.into();
                self.f_under[i].d.next = false;
                self.f_over[i].d.next = false;
                self.f_err[i].d.next = false;
                self.f_code[i].d.next = 0.into();
            }
            if self.reset.val() {
                self.st_vld[i].d.next = 0.into();
                self.m_vld[i].d.next = false;
                self.pushed[i].d.next = 0.into();
                self.m_taken[i].d.next = 0.into();
                self.m_busy[i].d.next = false;
                self.f_under[i].d.next = false;
                self.f_over[i].d.next = false;
                self.f_err[i].d.next = false;
                self.f_code[i].d.next = 0.into();
            }
            // LEVEL and BUSY from the counters' current values, so a push or a status
            // word shows a cycle after the counters take it. That is never seen: a
            // read starts at least 2 cycles after a write commits (strobes high ≥ 2
            // bus clocks between accesses), and status words arrive unsynchronised
            // with the bus anyway. A rejection takes its push back at once, as
            // `pushed` does, so the verdict is readable when it was before. The
            // queue-full flag is the same value registered: a cycle behind `pushed`
            // and the mirror, as the pushes above need.
            // BUSY's and the full flag's tests read the one difference pushed − taken
            // (L), both ways side by side, and the verdict only selects: L − 1 ≠ 0 is
            // L ≠ 1, and L − 1 ≥ QDEPTH (mod 256) is L > QDEPTH or L = 0. So the
            // verdict's fan-out is not in front of a carry chain (a `bus_clk` path).
            if self.chk.rej_valid.val() & (self.chk.rej_axis.val().index() == i) {
                self.lv[i].d.next = self.pushed[i].q.val() - self.m_taken[i].q.val() - 1;
                self.bz[i].d.next =
                    ((self.pushed[i].q.val() - self.m_taken[i].q.val()) != 1) | self.m_busy[i].q.val();
                self.q_full[i].d.next = ((self.pushed[i].q.val() - self.m_taken[i].q.val()) > self.c_qdepth.val())
                    | ((self.pushed[i].q.val() - self.m_taken[i].q.val()) == 0);
            } else {
                self.lv[i].d.next = self.pushed[i].q.val() - self.m_taken[i].q.val();
                self.bz[i].d.next =
                    ((self.pushed[i].q.val() - self.m_taken[i].q.val()) != 0) | self.m_busy[i].q.val();
                self.q_full[i].d.next = (self.pushed[i].q.val() - self.m_taken[i].q.val()) >= self.c_qdepth.val();
            }
            if self.reset.val() {
                self.lv[i].d.next = 0.into();
                self.bz[i].d.next = false;
                self.q_full[i].d.next = false;
            }
        }
        self.busy_bus[0].bus_in.next = 0.into();
        for i in 1..K {
            self.busy_bus[i].bus_in.next = self.busy_bus[i - 1].bus_out.val();
        }

        // ---- global writes -----------------------------------------------------
        if self.w_glob.val() {
            if self.wr_addr.val() == self.a_ctrl.val() {
                // ENABLE = 1 only with output timing that fits the minimum period.
                if self.wr_data.val().get_bit(0) & !self.tim.timing_ok.val() {
                    self.refused.d.next = true;
                } else {
                    self.ctrl_en.d.next = self.wr_data.val().get_bit(0);
                }
            }
            // Output timing (refused while the core is not off, or 0).
            if self.tim.refuse.val() {
                self.refused.d.next = true;
            }
            if self.wr_addr.val() == self.a_start.val() {
                if self.accepting.val() & !self.fifo_full.val() & !self.c_busy.val() {
                    self.c_write.next = true;
                    self.start_last.d.next = self.wr_data.val() & self.c_axmask.val();
                } else {
                    self.refused.d.next = true;
                }
            }
            if (self.wr_addr.val() == self.a_abort.val()) & self.wr_data.val().get_bit(0) {
                if self.accepting.val() & !self.fifo_full.val() & !self.c_busy.val() {
                    self.c_write.next = true;
                } else {
                    self.refused.d.next = true;
                }
            }
            if (self.wr_addr.val() == self.a_gstatus.val()) & self.wr_data.val().get_bit(1) {
                self.refused.d.next = false;
            }
            if (self.wr_addr.val() == self.a_gstatus.val()) & self.wr_data.val().get_bit(3) {
                self.start_failed.d.next = false;
            }
        }
        // Every command goes through the check (its writes above are all made).
        self.chk.in_valid.next = self.c_write.val();
        self.chk.in_data.next = self.c_data.val();
        // The push's v0 on its own port: v0 + RMAX does not wait for the START/ABORT select.
        self.chk.in_v0.next = self.x_v0.val();
        self.chk.ext_code.next = self.guard_code.val();
        // The S-curve option's fields (a core without it has no polynomial check).
        self.chk.in_extra.next = self.poly_extra.val();
        self.offer.next = self.c_write.val();
        self.offer_kind.next = self.c_data.val().get_bits::<2>(104);
        self.offer_axis.next = self.c_data.val().get_bits::<4>(96);
        self.offer_steps.next = self.c_data.val().get_bits::<32>(64);
        self.st_pushed.next = self.o_pushed.val();
        // The events, complete here (their last terms are the pushes' above).
        self.irqs.ev_done.next = self.ev_done.val();
        self.irqs.ev_qlow.next = self.ev_qlow.val();
        self.irqs.ev_err.next = self.ev_err.val();

        // ---- reads ---------------------------------------------------------------
        // Every register's address is distinct, so at most one test below passes: each
        // ORs its value into `g_data`, which synthesis makes a balanced OR of the
        // decoded values (an if chain that overwrote would be a 25-deep priority
        // multiplexer in front of `rd_data`, which was `bus_clk`'s critical path).
        self.g_data.next = self.ids.rd_data.val() | self.tim.rd_data.val() | self.irqs.rd_data.val();
        if !self.r_ax.val() {
            if self.rd_addr.val() == self.a_ctrl.val() {
                self.g_data.next = self.g_data.val() | bit_cast::<16, 1>(self.ctrl_en.q.val().into());
            }
            if self.rd_addr.val() == self.a_gstatus.val() {
                self.g_data.next = self.g_data.val()
                    | bit_cast::<16, 1>(self.core_en.q.val().into())
                    | (bit_cast::<16, 1>(self.refused.q.val().into()) << 1)
                    | (bit_cast::<16, 1>(self.irqs.irq.val().into()) << 2)
                    | (bit_cast::<16, 1>(self.start_failed.q.val().into()) << 3);
            }
            if self.rd_addr.val() == self.a_busy.val() {
                for i in 0..K {
                    self.g_data.next = self.g_data.val() | self.busy_bus[i].bus_out.val();
                }
            }
        }
        // The read axis's registers: an OR of each axis's, masked by its one-hot select
        // (no multiplexer chain, and nothing decoded from `rd_addr` in front).
        self.r_sel.next = false;
        self.r_mvld.next = false;
        self.r_level.next = 0.into();
        self.r_busy.next = false;
        self.r_fu.next = false;
        self.r_fo.next = false;
        self.r_fe.next = false;
        self.r_code.next = 0.into();
        self.r_vld.next = 0.into();
        self.r_pos.next = 0.into();
        self.r_done.next = 0.into();
        for i in 0..K {
            if self.rq_sel[i].q.val() {
                self.r_sel.next = true;
                self.r_mvld.next = self.r_mvld.val() | self.m_vld[i].q.val();
                self.r_level.next = self.r_level.val() | self.lv[i].q.val();
                self.r_busy.next = self.r_busy.val() | self.bz[i].q.val();
                self.r_fu.next = self.r_fu.val() | self.f_under[i].q.val();
                self.r_fo.next = self.r_fo.val() | self.f_over[i].q.val();
                self.r_fe.next = self.r_fe.val() | self.f_err[i].q.val();
                self.r_code.next = self.r_code.val() | self.f_code[i].q.val();
                self.r_vld.next = self.r_vld.val() | self.st_vld[i].q.val();
            }
        }
        // The mirror's position and done count at the read axis, 0 until its first
        // status word; the POS_LO read latches the high half.
        self.r_pos.next = 0.into();
        self.r_done.next = 0.into();
        if self.r_mvld.val() {
            self.r_pos.next = self.mb_ram.rdata.val().get_bits::<32>(0);
            self.r_done.next = self.mb_ram.rdata.val().get_bits::<8>(32);
        }
        if self.rd.val() & self.r_sel.val() & (self.r_off.val() == self.o_pos_lo.val()) {
            self.pos_latch.d.next = self.r_pos.val().get_bits::<16>(16);
        }
        // (A staging half-word reads at `st_aq`, the read axis when no write commits;
        // 0 where not written since reset.)
        // The read axis's offsets are distinct too: an OR as above.
        self.a_data.next = 0.into();
        if self.r_sel.val() {
            if (self.r_off.val() == self.o_v0_lo.val()) & self.r_vld.val().get_bit(0) {
                self.a_data.next = self.a_data.val() | self.st_ram[0].rdata.val();
            }
            if (self.r_off.val() == self.o_v0_hi.val()) & self.r_vld.val().get_bit(1) {
                self.a_data.next = self.a_data.val() | self.st_ram[1].rdata.val();
            }
            if (self.r_off.val() == self.o_t_lo.val()) & self.r_vld.val().get_bit(2) {
                self.a_data.next = self.a_data.val() | self.st_ram[2].rdata.val();
            }
            if (self.r_off.val() == self.o_t_hi.val()) & self.r_vld.val().get_bit(3) {
                self.a_data.next = self.a_data.val() | self.st_ram[3].rdata.val();
            }
            if (self.r_off.val() == self.o_steps_lo.val()) & self.r_vld.val().get_bit(4) {
                self.a_data.next = self.a_data.val() | self.st_ram[4].rdata.val();
            }
            if (self.r_off.val() == self.o_steps_hi.val()) & self.r_vld.val().get_bit(5) {
                self.a_data.next = self.a_data.val() | self.st_ram[5].rdata.val();
            }
            if self.r_off.val() == self.o_status.val() {
                self.a_data.next = self.a_data.val()
                    | bit_cast::<16, 5>(self.r_level.val().get_bits::<5>(0))
                    | (bit_cast::<16, 1>(self.r_busy.val().into()) << 5)
                    | (bit_cast::<16, 1>(self.r_fu.val().into()) << 6)
                    | (bit_cast::<16, 1>(self.r_fo.val().into()) << 7)
                    | (bit_cast::<16, 1>(self.r_fe.val().into()) << 8)
                    | (bit_cast::<16, 4>(self.r_code.val()) << 12);
            }
            if self.r_off.val() == self.o_pos_lo.val() {
                self.a_data.next = self.a_data.val() | self.r_pos.val().get_bits::<16>(0);
            }
            if self.r_off.val() == self.o_pos_hi.val() {
                self.a_data.next = self.a_data.val() | self.pos_latch.q.val();
            }
            if self.r_off.val() == self.o_done_count.val() {
                self.a_data.next = self.a_data.val() | bit_cast::<16, 8>(self.r_done.val());
            }
        }

        // A per-axis address (the one-hot `rq_sel`, registered from the same address)
        // reads the axis's registers, any other the global ones.
        if self.r_sel.val() {
            self.rd_data.next = self.a_data.val();
        } else {
            self.rd_data.next = self.g_data.val();
        }

        if !self.ctrl_en.q.val() {
            self.start_failed.d.next = false;
        }
        if self.reset.val() {
            self.ctrl_en.d.next = false;
            self.core_en.d.next = false;
            self.refused.d.next = false;
            self.start_failed.d.next = false;
            self.start_last.d.next = 0.into();
            self.pos_latch.d.next = 0.into();
        }
    }
}
