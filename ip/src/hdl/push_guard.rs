//! The push guard (machine I/O), in the bus clock: the checks of
//! [`crate::model::guard`] on every push, beside the [`super::push_check::PushCheck`]
//! and merged into its verdict, the planned position of each axis, the soft limits and
//! their registers (SL_*, PLAN_*). A block beside the register file, like
//! [`super::io_regs::IoRegs`]: its reads return 0 outside its own addresses.
//!
//! Ports and latency:
//! * **The command offered to the check** (`offer` with its kind, 0 push, 2 abort, and
//!   a push's axis and steps: the register file's write into the push check, cycle 0):
//!   a push's axis and steps are registered (cycle
//!   1: the plan, the soft limits, the axis's flags read; cycle 2: the end position
//!   `plan + steps`, 33 bits, registered), and `code` ([`GuardError`]'s, or 0) is valid
//!   in cycle 3, combinational from registers, where the check merges it into its
//!   verdict (the segment's own codes win). The flags are the ones of cycle 1.
//! * **The verdict** (`accept`: the register file's `cmd_write`, cycle 4): a push
//!   accepted moves its axis's plan to its end position.
//! * **Status words** (`st_valid`, `st_axis` and the word's position, taken count and
//!   busy flag, and `st_pushed`, the register file's push count of that axis): a word
//!   that shows its axis at rest (BUSY = 0) with
//!   its taken count equal to the push count makes the word's position the axis's plan
//!   and clears its stale flag (not in a cycle where an accepted push writes a plan: the
//!   word comes again a round later). A push counts from its cycle 0, so no push in
//!   the check is overtaken by this.
//! * **Stale** (K flip-flops): set for every axis by an ABORT offered to the check, by
//!   `held_all` (the e-stop latch or a watchdog trip, a level) and while CTRL.ENABLE
//!   = 0; for axis a by `stop_ev` bit a (a limit or alarm stop, bus clock) and while its
//!   `alarm` is active. A stale axis's pushes are rejected (code 9).
//! * `lim_neg`, `lim_pos`, `alarm` (bit a), `held_all`: the machine I/O's filtered
//!   levels, synchronised into the bus clock ([`super::io_regs::IoRegs`]).
//! * Registers: `wr`, `wr_addr`, `wr_data`, `rd`, `rd_addr` → `rd_data`
//!   (combinational). SL_APPLY takes effect at its write's clock edge.
//!
//! Memories: the plan (32 bits per axis) and the soft limits (64 bits per axis) in LUT
//! RAM; per axis two flip-flops (stale, soft limits on). The plan's one read port
//! serves the check in a push's cycle 1 and PLAN_LO otherwise: a PLAN_LO read in that
//! cycle would see the pushed axis's plan, and the bus never reads then (a read comes
//! at least two cycles after a write commits, with the documented timing).

use super::lut_ram::LutRam;
use super::regfile::c9;
use crate::model::guard::GuardError;
use crate::regs::ADDR_BITS;
use rust_hdl::prelude::*;

/// Cycles from `offer` to the cycle in which `code` is valid.
pub const GUARD_CODE_CYCLE: usize = 3;

#[derive(LogicBlock)]
pub struct PushGuard<const K: usize> {
    pub clock: Signal<In, Clock>,
    pub reset: Signal<In, Bit>,
    pub enable: Signal<In, Bit>,
    pub wr: Signal<In, Bit>,
    pub wr_addr: Signal<In, Bits<ADDR_BITS>>,
    pub wr_data: Signal<In, Bits<16>>,
    pub rd: Signal<In, Bit>,
    pub rd_addr: Signal<In, Bits<ADDR_BITS>>,
    pub rd_data: Signal<Out, Bits<16>>,
    pub offer: Signal<In, Bit>,
    pub offer_kind: Signal<In, Bits<2>>,
    pub offer_axis: Signal<In, Bits<4>>,
    pub offer_steps: Signal<In, Bits<32>>,
    pub accept: Signal<In, Bit>,
    pub code: Signal<Out, Bits<4>>,
    pub st_valid: Signal<In, Bit>,
    pub st_axis: Signal<In, Bits<4>>,
    pub st_pos: Signal<In, Bits<32>>,
    pub st_taken: Signal<In, Bits<8>>,
    pub st_busy: Signal<In, Bit>,
    pub st_pushed: Signal<In, Bits<8>>,
    pub lim_neg: Signal<In, Bits<K>>,
    pub lim_pos: Signal<In, Bits<K>>,
    pub alarm: Signal<In, Bits<K>>,
    pub held_all: Signal<In, Bit>,
    pub stop_ev: Signal<In, Bits<K>>,
    // The pipeline: which cycle a push is in, and its data.
    s1: DFF<Bit>,
    s2: DFF<Bit>,
    s3: DFF<Bit>,
    s4: DFF<Bit>,
    g_axis: DFF<Bits<4>>,
    g_steps: DFF<Bits<32>>,
    g_plan: DFF<Bits<32>>,
    g_min: DFF<Bits<32>>,
    g_max: DFF<Bits<32>>,
    g_soft: DFF<Bit>,
    g_held: DFF<Bit>,
    g_lim: DFF<Bit>,
    /// Cycle 3's registers: the end position (33 bits), soft check on (limits on,
    /// steps ≠ 0), held or stale, toward an active limit.
    e_sum: DFF<Bits<33>>,
    e_soft: DFF<Bit>,
    e_held: DFF<Bit>,
    e_lim: DFF<Bit>,
    stale: DFF<Bits<K>>,
    sl_on: DFF<Bits<K>>,
    // Registers.
    sl_axis: DFF<Bits<4>>,
    sl_min_lo: DFF<Bits<16>>,
    sl_min_hi: DFF<Bits<16>>,
    sl_max_lo: DFF<Bits<16>>,
    sl_max_hi: DFF<Bits<16>>,
    refused: DFF<Bit>,
    hi_latch: DFF<Bits<16>>,
    plan: LutRam<32, 4>,
    sl_ram: LutRam<64, 4>,
    c_one: Constant<Bits<K>>,
    c_ones: Constant<Bits<K>>,
    c_last: Constant<Bits<4>>,
    c_top: Constant<Bits<33>>,
    c_sign32: Constant<Bits<32>>,
    c_limit: Constant<Bits<4>>,
    c_soft: Constant<Bits<4>>,
    c_halted: Constant<Bits<4>>,
    a_axis: Constant<Bits<ADDR_BITS>>,
    a_min_lo: Constant<Bits<ADDR_BITS>>,
    a_min_hi: Constant<Bits<ADDR_BITS>>,
    a_max_lo: Constant<Bits<ADDR_BITS>>,
    a_max_hi: Constant<Bits<ADDR_BITS>>,
    a_apply: Constant<Bits<ADDR_BITS>>,
    a_status: Constant<Bits<ADDR_BITS>>,
    a_plan_lo: Constant<Bits<ADDR_BITS>>,
    a_plan_hi: Constant<Bits<ADDR_BITS>>,
    o_kind: Signal<Local, Bits<2>>,
    g_onehot: Signal<Local, Bits<K>>,
    sl_onehot: Signal<Local, Bits<K>>,
    st_onehot: Signal<Local, Bits<K>>,
    x_plan: Signal<Local, Bits<33>>,
    x_steps: Signal<Local, Bits<33>>,
    x_min: Signal<Local, Bits<33>>,
    x_max: Signal<Local, Bits<33>>,
    /// The end position and the limits in offset binary (sign bit flipped), so an
    /// unsigned compare orders them as signed numbers.
    u_sum: Signal<Local, Bits<33>>,
    u_min: Signal<Local, Bits<33>>,
    u_max: Signal<Local, Bits<33>>,
    w_write: Signal<Local, Bit>,
    resync: Signal<Local, Bit>,
    stale_set: Signal<Local, Bits<K>>,
    stale_clr: Signal<Local, Bits<K>>,
    p_addr: Signal<Local, Bits<4>>,
    p_data: Signal<Local, Bits<32>>,
    sl_bad: Signal<Local, Bit>,
    sl_min: Signal<Local, Bits<32>>,
    sl_max: Signal<Local, Bits<32>>,
}

impl<const K: usize> Default for PushGuard<K> {
    fn default() -> Self {
        assert!((1..=16).contains(&K), "PushGuard<{K}>: 1 to 16 axes");
        PushGuard {
            clock: Default::default(),
            reset: Default::default(),
            enable: Default::default(),
            wr: Default::default(),
            wr_addr: Default::default(),
            wr_data: Default::default(),
            rd: Default::default(),
            rd_addr: Default::default(),
            rd_data: Default::default(),
            offer: Default::default(),
            offer_kind: Default::default(),
            offer_axis: Default::default(),
            offer_steps: Default::default(),
            accept: Default::default(),
            code: Default::default(),
            st_valid: Default::default(),
            st_axis: Default::default(),
            st_pos: Default::default(),
            st_taken: Default::default(),
            st_busy: Default::default(),
            st_pushed: Default::default(),
            lim_neg: Default::default(),
            lim_pos: Default::default(),
            alarm: Default::default(),
            held_all: Default::default(),
            stop_ev: Default::default(),
            s1: Default::default(),
            s2: Default::default(),
            s3: Default::default(),
            s4: Default::default(),
            g_axis: Default::default(),
            g_steps: Default::default(),
            g_plan: Default::default(),
            g_min: Default::default(),
            g_max: Default::default(),
            g_soft: Default::default(),
            g_held: Default::default(),
            g_lim: Default::default(),
            e_sum: Default::default(),
            e_soft: Default::default(),
            e_held: Default::default(),
            e_lim: Default::default(),
            stale: Default::default(),
            sl_on: Default::default(),
            sl_axis: Default::default(),
            sl_min_lo: Default::default(),
            sl_min_hi: Default::default(),
            sl_max_lo: Default::default(),
            sl_max_hi: Default::default(),
            refused: Default::default(),
            hi_latch: Default::default(),
            plan: Default::default(),
            sl_ram: Default::default(),
            c_one: Constant::new(1.into()),
            c_ones: Constant::new(((1u64 << K) - 1).into()),
            c_last: Constant::new(((K - 1) as u64).into()),
            c_top: Constant::new((1u64 << 32).into()),
            c_sign32: Constant::new((1u64 << 31).into()),
            c_limit: Constant::new((GuardError::Limit.code() as u64).into()),
            c_soft: Constant::new((GuardError::SoftLimit.code() as u64).into()),
            c_halted: Constant::new((GuardError::Halted.code() as u64).into()),
            a_axis: c9("SL_AXIS"),
            a_min_lo: c9("SL_MIN_LO"),
            a_min_hi: c9("SL_MIN_HI"),
            a_max_lo: c9("SL_MAX_LO"),
            a_max_hi: c9("SL_MAX_HI"),
            a_apply: c9("SL_APPLY"),
            a_status: c9("SL_STATUS"),
            a_plan_lo: c9("PLAN_LO"),
            a_plan_hi: c9("PLAN_HI"),
            o_kind: Default::default(),
            g_onehot: Default::default(),
            sl_onehot: Default::default(),
            st_onehot: Default::default(),
            x_plan: Default::default(),
            x_steps: Default::default(),
            x_min: Default::default(),
            x_max: Default::default(),
            u_sum: Default::default(),
            u_min: Default::default(),
            u_max: Default::default(),
            w_write: Default::default(),
            resync: Default::default(),
            stale_set: Default::default(),
            stale_clr: Default::default(),
            p_addr: Default::default(),
            p_data: Default::default(),
            sl_bad: Default::default(),
            sl_min: Default::default(),
            sl_max: Default::default(),
        }
    }
}

impl<const K: usize> PushGuard<K> {
    /// Marks the inputs as driven from outside and connects the block (tests).
    pub fn connect_ports(&mut self) {
        self.clock.connect();
        self.reset.connect();
        self.enable.connect();
        self.wr.connect();
        self.wr_addr.connect();
        self.wr_data.connect();
        self.rd.connect();
        self.rd_addr.connect();
        self.offer.connect();
        self.offer_kind.connect();
        self.offer_axis.connect();
        self.offer_steps.connect();
        self.accept.connect();
        self.st_valid.connect();
        self.st_axis.connect();
        self.st_pos.connect();
        self.st_taken.connect();
        self.st_busy.connect();
        self.st_pushed.connect();
        self.lim_neg.connect();
        self.lim_pos.connect();
        self.alarm.connect();
        self.held_all.connect();
        self.stop_ev.connect();
        self.connect_all();
    }
}

impl<const K: usize> Logic for PushGuard<K> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, s1, s2, s3, s4, g_axis, g_steps, g_plan, g_min, g_max, g_soft, g_held, g_lim);
        dff_setup!(self, clock, e_sum, e_soft, e_held, e_lim, stale, sl_on, sl_axis, refused, hi_latch);
        dff_setup!(self, clock, sl_min_lo, sl_min_hi, sl_max_lo, sl_max_hi);
        self.plan.clock.next = self.clock.val();
        self.sl_ram.clock.next = self.clock.val();

        // Cycle 0: a push offered to the check.
        self.o_kind.next = self.offer_kind.val();
        self.s1.d.next = self.offer.val() & (self.o_kind.val() == 0);
        self.s2.d.next = self.s1.q.val();
        self.s3.d.next = self.s2.q.val();
        self.s4.d.next = self.s3.q.val();
        if self.offer.val() & (self.o_kind.val() == 0) {
            self.g_axis.d.next = self.offer_axis.val();
            self.g_steps.d.next = self.offer_steps.val();
        }

        // Cycle 1: the axis's plan, soft limits and flags.
        self.g_onehot.next = self.c_one.val() << self.g_axis.q.val();
        // The plan memory's one read port: the push's axis in its cycle 1, else
        // SL_AXIS for PLAN_LO (a bus read never comes in the cycle after a write).
        self.plan.raddr.next = self.sl_axis.q.val();
        if self.s1.q.val() {
            self.plan.raddr.next = self.g_axis.q.val();
        }
        self.sl_ram.raddr.next = self.g_axis.q.val();
        if self.s1.q.val() {
            self.g_plan.d.next = self.plan.rdata.val();
            self.g_min.d.next = self.sl_ram.rdata.val().get_bits::<32>(0);
            self.g_max.d.next = self.sl_ram.rdata.val().get_bits::<32>(32);
            self.g_soft.d.next = (self.sl_on.q.val() & self.g_onehot.val()).any() & (self.g_steps.q.val() != 0);
            self.g_held.d.next = self.held_all.val() | ((self.alarm.val() | self.stale.q.val()) & self.g_onehot.val()).any();
            self.g_lim.d.next = (!self.g_steps.q.val().get_bit(31) & (self.g_steps.q.val() != 0) & (self.lim_pos.val() & self.g_onehot.val()).any())
                | (self.g_steps.q.val().get_bit(31) & (self.lim_neg.val() & self.g_onehot.val()).any());
        }

        // Cycle 2: the end position, 33 bits, and the limits sign-extended.
        self.x_plan.next = bit_cast::<33, 32>(self.g_plan.q.val());
        if self.g_plan.q.val().get_bit(31) {
            self.x_plan.next = bit_cast::<33, 32>(self.g_plan.q.val()) | self.c_top.val();
        }
        self.x_steps.next = bit_cast::<33, 32>(self.g_steps.q.val());
        if self.g_steps.q.val().get_bit(31) {
            self.x_steps.next = bit_cast::<33, 32>(self.g_steps.q.val()) | self.c_top.val();
        }
        self.x_min.next = bit_cast::<33, 32>(self.g_min.q.val());
        if self.g_min.q.val().get_bit(31) {
            self.x_min.next = bit_cast::<33, 32>(self.g_min.q.val()) | self.c_top.val();
        }
        self.x_max.next = bit_cast::<33, 32>(self.g_max.q.val());
        if self.g_max.q.val().get_bit(31) {
            self.x_max.next = bit_cast::<33, 32>(self.g_max.q.val()) | self.c_top.val();
        }
        if self.s2.q.val() {
            self.e_sum.d.next = self.x_plan.val() + self.x_steps.val();
            self.e_soft.d.next = self.g_soft.q.val();
            self.e_held.d.next = self.g_held.q.val();
            self.e_lim.d.next = self.g_lim.q.val();
        }

        // Cycle 3: the code, in the model's order.
        self.u_sum.next = self.e_sum.q.val() ^ self.c_top.val();
        // (The limits stay in their cycle-1 registers until the next push.)
        self.u_min.next = self.x_min.val() ^ self.c_top.val();
        self.u_max.next = self.x_max.val() ^ self.c_top.val();
        self.code.next = 0.into();
        if self.s3.q.val() {
            if self.e_held.q.val() {
                self.code.next = self.c_halted.val();
            } else if self.e_lim.q.val() {
                self.code.next = self.c_limit.val();
            } else if self.e_soft.q.val() & ((self.u_sum.val() < self.u_min.val()) | (self.u_sum.val() > self.u_max.val())) {
                self.code.next = self.c_soft.val();
            }
        }

        // Cycle 4: an accepted push writes its end as the plan; else a status word
        // of an axis at rest with nothing pushed untaken writes its position.
        self.w_write.next = self.s4.q.val() & self.accept.val();
        self.resync.next = self.st_valid.val() & !self.st_busy.val() & (self.st_taken.val() == self.st_pushed.val());
        self.p_addr.next = self.st_axis.val();
        self.p_data.next = self.st_pos.val();
        if self.w_write.val() {
            self.p_addr.next = self.g_axis.q.val();
            self.p_data.next = self.e_sum.q.val().get_bits::<32>(0);
        }
        self.plan.we.next = self.w_write.val() | self.resync.val();
        self.plan.waddr.next = self.p_addr.val();
        self.plan.wdata.next = self.p_data.val();

        // Stale: set by a stop (set wins), cleared by the resync's word.
        self.st_onehot.next = self.c_one.val() << self.st_axis.val();
        self.stale_clr.next = 0.into();
        if self.resync.val() & !self.w_write.val() {
            self.stale_clr.next = self.st_onehot.val();
        }
        self.stale_set.next = self.stop_ev.val() | self.alarm.val();
        if self.held_all.val() | !self.enable.val() | (self.offer.val() & (self.o_kind.val() == 2)) {
            self.stale_set.next = self.c_ones.val();
        }
        self.stale.d.next = (self.stale.q.val() & !self.stale_clr.val()) | self.stale_set.val();

        // Registers.
        self.sl_onehot.next = self.c_one.val() << self.sl_axis.q.val();
        self.sl_min.next = bit_cast::<32, 16>(self.sl_min_lo.q.val()) | (bit_cast::<32, 16>(self.sl_min_hi.q.val()) << 16);
        self.sl_max.next = bit_cast::<32, 16>(self.sl_max_lo.q.val()) | (bit_cast::<32, 16>(self.sl_max_hi.q.val()) << 16);
        self.sl_bad.next = (self.sl_min.val() ^ self.c_sign32.val()) > (self.sl_max.val() ^ self.c_sign32.val());
        self.sl_ram.we.next = false;
        self.sl_ram.waddr.next = self.sl_axis.q.val();
        self.sl_ram.wdata.next = bit_cast::<64, 32>(self.sl_min.val()) | (bit_cast::<64, 32>(self.sl_max.val()) << 32);
        if self.wr.val() {
            if self.wr_addr.val() == self.a_axis.val() {
                self.sl_axis.d.next = self.wr_data.val().get_bits::<4>(0);
            }
            if self.wr_addr.val() == self.a_min_lo.val() {
                self.sl_min_lo.d.next = self.wr_data.val();
            }
            if self.wr_addr.val() == self.a_min_hi.val() {
                self.sl_min_hi.d.next = self.wr_data.val();
            }
            if self.wr_addr.val() == self.a_max_lo.val() {
                self.sl_max_lo.d.next = self.wr_data.val();
            }
            if self.wr_addr.val() == self.a_max_hi.val() {
                self.sl_max_hi.d.next = self.wr_data.val();
            }
            if self.wr_addr.val() == self.a_apply.val() {
                if (self.sl_axis.q.val() > self.c_last.val()) | (self.wr_data.val().get_bit(0) & self.sl_bad.val()) {
                    self.refused.d.next = true;
                } else if self.wr_data.val().get_bit(0) {
                    self.sl_ram.we.next = true;
                    self.sl_on.d.next = self.sl_on.q.val() | self.sl_onehot.val();
                } else {
                    self.sl_on.d.next = self.sl_on.q.val() & !self.sl_onehot.val();
                }
            }
            if (self.wr_addr.val() == self.a_status.val()) & self.wr_data.val().get_bit(2) {
                self.refused.d.next = false;
            }
        }

        // Reads: 0 outside this block's addresses.
        self.rd_data.next = 0.into();
        if self.rd_addr.val() == self.a_axis.val() {
            self.rd_data.next = bit_cast::<16, 4>(self.sl_axis.q.val());
        }
        if self.rd_addr.val() == self.a_min_lo.val() {
            self.rd_data.next = self.sl_min_lo.q.val();
        }
        if self.rd_addr.val() == self.a_min_hi.val() {
            self.rd_data.next = self.sl_min_hi.q.val();
        }
        if self.rd_addr.val() == self.a_max_lo.val() {
            self.rd_data.next = self.sl_max_lo.q.val();
        }
        if self.rd_addr.val() == self.a_max_hi.val() {
            self.rd_data.next = self.sl_max_hi.q.val();
        }
        if self.rd_addr.val() == self.a_status.val() {
            self.rd_data.next = bit_cast::<16, 1>((self.sl_on.q.val() & self.sl_onehot.val()).any().into())
                | (bit_cast::<16, 1>((self.stale.q.val() & self.sl_onehot.val()).any().into()) << 1)
                | (bit_cast::<16, 1>(self.refused.q.val().into()) << 2);
        }
        if self.rd_addr.val() == self.a_plan_lo.val() {
            self.rd_data.next = self.plan.rdata.val().get_bits::<16>(0);
            if self.rd.val() {
                self.hi_latch.d.next = self.plan.rdata.val().get_bits::<16>(16);
            }
        }
        if self.rd_addr.val() == self.a_plan_hi.val() {
            self.rd_data.next = self.hi_latch.q.val();
        }

        if self.reset.val() | !self.enable.val() {
            self.s1.d.next = false;
            self.s2.d.next = false;
            self.s3.d.next = false;
            self.s4.d.next = false;
        }
        if self.reset.val() {
            self.stale.d.next = self.c_ones.val();
            self.sl_on.d.next = 0.into();
            self.sl_axis.d.next = 0.into();
            self.sl_min_lo.d.next = 0.into();
            self.sl_min_hi.d.next = 0.into();
            self.sl_max_lo.d.next = 0.into();
            self.sl_max_hi.d.next = 0.into();
            self.refused.d.next = false;
            self.hi_latch.d.next = 0.into();
        }
    }
}
