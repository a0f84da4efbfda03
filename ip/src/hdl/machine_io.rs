//! Machine I/O and safety in `clk`: the machine's input pins through [`InputFilter`]s,
//! the e-stop latch, the host watchdog, the hard-stop request, the drivers' enables and
//! the strobes of the home and probe position latches. It equals
//! `model::io::MachineIoModel` clock for clock (tests/hdl_machine_io.rs, three ways).
//!
//! **Inputs** (asynchronous pins): `estop_n`, `probe`, and per axis (bit a = axis a)
//! `limit_neg`, `limit_pos`, `home`, `alarm`. Each has a synchroniser, its group's
//! polarity bit (`polarity`, bit g for group g of `model::io::GROUPS`: estop, probe,
//! limit_neg, limit_pos, home, alarm; 1 = active low at the pin) and its group's filter
//! length (`filter`, 4 bits per group at bits 4g + 3..4g, samples). One prescaler gives
//! every filter its sample strobe: one cycle in `prescale + 1`.
//!
//! A reset puts the e-stop, limit and alarm levels active and the home and probe levels
//! inactive (`model::io`), so an input that stops motion counts as active until its
//! filter has seen it inactive, and no latch fires on the way out of a reset.
//!
//! **Configuration** (`polarity`, `filter`, `prescale`, `edges`, `wd_timeout`) is
//! quasi-static: it must come from registers in `clk` that change only between moves.
//! **Commands** (`estop_rearm`, `wd_feed`, `wd_rearm`) are one-cycle pulses in `clk`.
//! `run` says the core is enabled.
//!
//! **Outputs**:
//! * `hard_stop` (registered, one cycle behind an OR of three): the filtered e-stop is
//!   active, or the e-stop latch is set, or the watchdog has tripped. The core stops
//!   every axis while it is high (category 0). With a sample every tick, a pin change
//!   first sampled at edge e0 raises it after edge e0 + 3 + n. (The register keeps the
//!   OR off the abort's fan-out to every step generator: that was the K = 16 core's
//!   critical path.)
//! * `estop_latched`: set by reset and whenever the filtered e-stop is active; cleared
//!   only by `estop_rearm` in a cycle where the filtered e-stop is inactive, so a
//!   release alone never clears it. `estop_active`, `probe_active`: filtered levels.
//! * `wd_tripped`: with `wd_timeout` ≠ 0, set `wd_timeout`·1024 clk edges after the
//!   edge that took the last `wd_feed` or `wd_rearm` (or after the count restarted when
//!   the watchdog was off), if no feed came since; sticky until `wd_rearm`, which
//!   restarts the count. A feed does not clear a trip. Lowering the timeout below the
//!   time already counted trips at once.
//! * `drv_enable` (bit a, registered, one cycle behind, so it falls with `hard_stop`):
//!   `run`, no hard stop, and axis a's filtered alarm inactive. Low after reset.
//! * `limit_neg_active`, `limit_pos_active`, `home_active`, `alarm_active`: the filtered
//!   levels per axis.
//! * `home_latch` (bit a) and `probe_latch`: high in the cycle before the filtered home
//!   (probe) level changes in the chosen direction (`edges` bit 0 for home, bit 1 for
//!   the probe: 0 = on becoming active, 1 = on becoming inactive), so a position latch
//!   enabled by them takes the position on the edge where the level changes.
//!
//! * `axis_stop` (bit a, registered): the per-axis hard stop. Axis a was moving (`active`,
//!   the core's) toward an active limit (`dir` 0 toward `limit_pos`, 1 toward
//!   `limit_neg`) in this cycle and the one before (a segment that starts away from the
//!   limit shows the old DIR for one tick), or its filtered alarm is active. With a
//!   limit pin first sampled at edge e0 and the axis moving toward it, it rises after
//!   edge e0 + 3 + n. `stop_tog` (bit a) flips each time it stops a moving axis.
//!
//! * `axis_cstop` (bit a, registered): the controlled stop's request, from the sources
//!   `stop_mode` puts in controlled mode (bit 0 the limits, 1 the alarm, 2 the watchdog,
//!   3 the stop on home; 0 = hard, in `axis_stop`): a limit or an alarm for as long as
//!   it holds, a watchdog trip on every axis for as long as it lasts. A controlled
//!   watchdog trip raises `hard_stop` only once no axis is `active` (two ticks later); a
//!   controlled alarm keeps its axis's `drv_enable` while the axis is `active`.
//!   `home_stop` bit a arms the stop on home: axis a's home latch strobe while it is
//!   `active` requests its stop for one cycle, the next. `stop_tog` flips when either
//!   request stops a moving axis. `model::io` states the same.
//!
//! **Groups** (`with_groups`, `regs::IO_GROUPS` bits; `default()` has all): a group
//! left out of the export has its filtered levels, latch strobes and stops ANDed with a
//! constant 0, the e-stop latch resets clear without `estop` and the watchdog never
//! trips without `watchdog`, so their flip-flops have constant inputs and synthesis
//! removes them (`model::io`'s `MachineIoModel::with_groups`).
//!
//! Cost: 7 flip-flops per input (4K + 2), 16 for the prescaler, 27 for the watchdog,
//! 1 for the e-stop latch and K for the enables.

use super::bit_insert::{BitInsert, BitPick};
use super::input_filter::InputFilter;
use rust_hdl::prelude::*;

#[derive(LogicBlock)]
pub struct MachineIo<const K: usize> {
    pub clock: Signal<In, Clock>,
    pub reset: Signal<In, Bit>,
    pub run: Signal<In, Bit>,
    pub estop_n: Signal<In, Bit>,
    pub probe: Signal<In, Bit>,
    pub limit_neg: Signal<In, Bits<K>>,
    pub limit_pos: Signal<In, Bits<K>>,
    pub home: Signal<In, Bits<K>>,
    pub alarm: Signal<In, Bits<K>>,
    pub polarity: Signal<In, Bits<6>>,
    pub filter: Signal<In, Bits<24>>,
    pub prescale: Signal<In, Bits<16>>,
    pub edges: Signal<In, Bits<2>>,
    pub wd_timeout: Signal<In, Bits<16>>,
    pub estop_rearm: Signal<In, Bit>,
    pub wd_feed: Signal<In, Bit>,
    pub wd_rearm: Signal<In, Bit>,
    pub hard_stop: Signal<Out, Bit>,
    pub estop_latched: Signal<Out, Bit>,
    pub estop_active: Signal<Out, Bit>,
    pub probe_active: Signal<Out, Bit>,
    pub wd_tripped: Signal<Out, Bit>,
    pub drv_enable: Signal<Out, Bits<K>>,
    pub limit_neg_active: Signal<Out, Bits<K>>,
    pub limit_pos_active: Signal<Out, Bits<K>>,
    pub home_active: Signal<Out, Bits<K>>,
    pub alarm_active: Signal<Out, Bits<K>>,
    pub home_latch: Signal<Out, Bits<K>>,
    pub probe_latch: Signal<Out, Bit>,
    /// The core's DIR and moving flags, bit a.
    pub dir: Signal<In, Bits<K>>,
    pub active: Signal<In, Bits<K>>,
    pub axis_stop: Signal<Out, Bits<K>>,
    pub stop_tog: Signal<Out, Bits<K>>,
    pub stop_mode: Signal<In, Bits<4>>,
    pub home_stop: Signal<In, Bits<K>>,
    pub axis_cstop: Signal<Out, Bits<K>>,
    cs_q: DFF<Bits<K>>,
    wd_rest: DFF<Bit>,
    /// The groups exported (`regs::IO_GROUPS` bits): the others' levels, latches and
    /// stops are constant 0 (their logic is removed by synthesis).
    c_groups: Constant<Bits<6>>,
    cs_new: Signal<Local, Bits<K>>,
    /// The filtered levels and the home latch strobes as vectors (bit a = axis a), the
    /// moves toward an active limit, the armed home hits, each source's stop split by
    /// its mode (s_ hard, c_ controlled), and the alarms that drop the enables.
    lneg_v: Signal<Local, Bits<K>>,
    lpos_v: Signal<Local, Bits<K>>,
    alarm_v: Signal<Local, Bits<K>>,
    latch_v: Signal<Local, Bits<K>>,
    toward_v: Signal<Local, Bits<K>>,
    limit_v: Signal<Local, Bits<K>>,
    hit_v: Signal<Local, Bits<K>>,
    s_lim: Signal<Local, Bits<K>>,
    c_lim: Signal<Local, Bits<K>>,
    s_al: Signal<Local, Bits<K>>,
    c_al: Signal<Local, Bits<K>>,
    s_hit: Signal<Local, Bits<K>>,
    c_hit: Signal<Local, Bits<K>>,
    c_wd: Signal<Local, Bits<K>>,
    drv_al: Signal<Local, Bits<K>>,
    c_ones: Constant<Bits<K>>,
    toward_q: DFF<Bits<K>>,
    stop_q: DFF<Bits<K>>,
    tog_q: DFF<Bits<K>>,
    stop_new: Signal<Local, Bits<K>>,
    estop_f: InputFilter,
    probe_f: InputFilter,
    lneg_f: [InputFilter; K],
    lpos_f: [InputFilter; K],
    home_f: [InputFilter; K],
    alarm_f: [InputFilter; K],
    lneg_pick: [BitPick<K>; K],
    lpos_pick: [BitPick<K>; K],
    home_pick: [BitPick<K>; K],
    alarm_pick: [BitPick<K>; K],
    lneg_bus: [BitInsert<K>; K],
    lpos_bus: [BitInsert<K>; K],
    home_bus: [BitInsert<K>; K],
    alarm_bus: [BitInsert<K>; K],
    latch_bus: [BitInsert<K>; K],
    prescaler: DFF<Bits<16>>,
    latched: DFF<Bit>,
    wd_count: DFF<Bits<26>>,
    tripped: DFF<Bit>,
    drv: DFF<Bits<K>>,
    sample: Signal<Local, Bit>,
    hard: Signal<Local, Bit>,
    hard_q: DFF<Bit>,
    wd_end: Signal<Local, Bits<26>>,
}

impl<const K: usize> Default for MachineIo<K> {
    fn default() -> Self {
        MachineIo {
            clock: Default::default(),
            reset: Default::default(),
            run: Default::default(),
            estop_n: Default::default(),
            probe: Default::default(),
            limit_neg: Default::default(),
            limit_pos: Default::default(),
            home: Default::default(),
            alarm: Default::default(),
            polarity: Default::default(),
            filter: Default::default(),
            prescale: Default::default(),
            edges: Default::default(),
            wd_timeout: Default::default(),
            estop_rearm: Default::default(),
            wd_feed: Default::default(),
            wd_rearm: Default::default(),
            hard_stop: Default::default(),
            estop_latched: Default::default(),
            estop_active: Default::default(),
            probe_active: Default::default(),
            wd_tripped: Default::default(),
            drv_enable: Default::default(),
            limit_neg_active: Default::default(),
            limit_pos_active: Default::default(),
            home_active: Default::default(),
            alarm_active: Default::default(),
            home_latch: Default::default(),
            probe_latch: Default::default(),
            dir: Default::default(),
            active: Default::default(),
            axis_stop: Default::default(),
            stop_tog: Default::default(),
            stop_mode: Default::default(),
            home_stop: Default::default(),
            axis_cstop: Default::default(),
            cs_q: Default::default(),
            wd_rest: Default::default(),
            c_groups: Constant::new((crate::regs::IO_ALL as u64).into()),
            cs_new: Default::default(),
            lneg_v: Default::default(),
            lpos_v: Default::default(),
            alarm_v: Default::default(),
            latch_v: Default::default(),
            toward_v: Default::default(),
            limit_v: Default::default(),
            hit_v: Default::default(),
            s_lim: Default::default(),
            c_lim: Default::default(),
            s_al: Default::default(),
            c_al: Default::default(),
            s_hit: Default::default(),
            c_hit: Default::default(),
            c_wd: Default::default(),
            drv_al: Default::default(),
            c_ones: Constant::new(((1u64 << K) - 1).into()),
            toward_q: Default::default(),
            stop_q: Default::default(),
            tog_q: Default::default(),
            stop_new: Default::default(),
            estop_f: InputFilter::new(true),
            probe_f: InputFilter::new(false),
            lneg_f: std::array::from_fn(|_| InputFilter::new(true)),
            lpos_f: std::array::from_fn(|_| InputFilter::new(true)),
            home_f: std::array::from_fn(|_| InputFilter::new(false)),
            alarm_f: std::array::from_fn(|_| InputFilter::new(true)),
            lneg_pick: std::array::from_fn(BitPick::new),
            lpos_pick: std::array::from_fn(BitPick::new),
            home_pick: std::array::from_fn(BitPick::new),
            alarm_pick: std::array::from_fn(BitPick::new),
            lneg_bus: std::array::from_fn(BitInsert::new),
            lpos_bus: std::array::from_fn(BitInsert::new),
            home_bus: std::array::from_fn(BitInsert::new),
            alarm_bus: std::array::from_fn(BitInsert::new),
            latch_bus: std::array::from_fn(BitInsert::new),
            prescaler: Default::default(),
            latched: Default::default(),
            wd_count: Default::default(),
            tripped: Default::default(),
            drv: Default::default(),
            sample: Default::default(),
            hard: Default::default(),
            hard_q: Default::default(),
            wd_end: Default::default(),
        }
    }
}

impl<const K: usize> MachineIo<K> {
    /// The block with only the machine I/O groups `groups` (`regs::IO_GROUPS` bits);
    /// `default()` has every group.
    pub fn with_groups(mut self, groups: u8) -> Self {
        self.c_groups = Constant::new((groups as u64).into());
        self
    }

    /// Marks the inputs as driven from outside and connects the block (tests).
    pub fn connect_ports(&mut self) {
        self.clock.connect();
        self.reset.connect();
        self.run.connect();
        self.estop_n.connect();
        self.probe.connect();
        self.limit_neg.connect();
        self.limit_pos.connect();
        self.home.connect();
        self.alarm.connect();
        self.polarity.connect();
        self.filter.connect();
        self.prescale.connect();
        self.edges.connect();
        self.wd_timeout.connect();
        self.estop_rearm.connect();
        self.wd_feed.connect();
        self.wd_rearm.connect();
        self.dir.connect();
        self.active.connect();
        self.stop_mode.connect();
        self.home_stop.connect();
        self.connect_all();
    }
}

impl<const K: usize> Logic for MachineIo<K> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, prescaler, latched, wd_count, tripped, drv, toward_q, stop_q, tog_q, cs_q, wd_rest, hard_q);
        // The filters' shared sample strobe.
        self.sample.next = self.prescaler.q.val() >= self.prescale.val();
        if self.sample.val() {
            self.prescaler.d.next = 0.into();
        } else {
            self.prescaler.d.next = self.prescaler.q.val() + 1;
        }

        self.estop_f.clock.next = self.clock.val();
        self.estop_f.reset.next = self.reset.val();
        self.estop_f.pin.next = self.estop_n.val();
        self.estop_f.invert.next = self.polarity.val().get_bit(0);
        self.estop_f.sample.next = self.sample.val();
        self.estop_f.samples.next = self.filter.val().get_bits::<4>(0);
        self.probe_f.clock.next = self.clock.val();
        self.probe_f.reset.next = self.reset.val();
        self.probe_f.pin.next = self.probe.val();
        self.probe_f.invert.next = self.polarity.val().get_bit(1);
        self.probe_f.sample.next = self.sample.val();
        self.probe_f.samples.next = self.filter.val().get_bits::<4>(4);
        self.estop_active.next = self.estop_f.active.val() & self.c_groups.val().get_bit(0);
        self.probe_active.next = self.probe_f.active.val() & self.c_groups.val().get_bit(1);
        self.probe_latch.next = self.probe_f.rise.val() & self.c_groups.val().get_bit(1);
        if self.edges.val().get_bit(1) {
            self.probe_latch.next = self.probe_f.fall.val() & self.c_groups.val().get_bit(1);
        }

        // Category 0: the filtered e-stop, its latch, the watchdog.
        // (A controlled watchdog trip stops hard once no axis is active: the ramps run.)
        self.hard.next = self.latched.q.val()
            | (self.estop_f.active.val() & self.c_groups.val().get_bit(0))
            | (self.tripped.q.val() & !self.stop_mode.val().get_bit(2))
            | self.wd_rest.q.val();
        self.wd_rest.d.next = self.tripped.q.val() & self.stop_mode.val().get_bit(2) & !self.active.val().any();
        self.hard_q.d.next = self.hard.val();
        self.hard_stop.next = self.hard_q.q.val();
        self.estop_latched.next = self.latched.q.val();
        self.latched.d.next = (self.estop_f.active.val() & self.c_groups.val().get_bit(0)) | (self.latched.q.val() & !self.estop_rearm.val());
        self.wd_tripped.next = self.tripped.q.val();
        self.wd_end.next = bit_cast::<26, 16>(self.wd_timeout.val()) << 10;
        if self.wd_rearm.val() {
            self.tripped.d.next = false;
            self.wd_count.d.next = 1.into();
        } else if (self.wd_timeout.val() == 0) | self.wd_feed.val() | self.tripped.q.val() {
            self.wd_count.d.next = 1.into();
        } else {
            if self.wd_count.q.val() >= self.wd_end.val() {
                self.tripped.d.next = self.c_groups.val().get_bit(5);
            }
            self.wd_count.d.next = self.wd_count.q.val() + 1;
        }

        for i in 0..K {
            self.lneg_pick[i].bus.next = self.limit_neg.val();
            self.lpos_pick[i].bus.next = self.limit_pos.val();
            self.home_pick[i].bus.next = self.home.val();
            self.alarm_pick[i].bus.next = self.alarm.val();
            self.lneg_f[i].clock.next = self.clock.val();
            self.lneg_f[i].reset.next = self.reset.val();
            self.lneg_f[i].pin.next = self.lneg_pick[i].value.val();
            self.lneg_f[i].invert.next = self.polarity.val().get_bit(2);
            self.lneg_f[i].sample.next = self.sample.val();
            self.lneg_f[i].samples.next = self.filter.val().get_bits::<4>(8);
            self.lpos_f[i].clock.next = self.clock.val();
            self.lpos_f[i].reset.next = self.reset.val();
            self.lpos_f[i].pin.next = self.lpos_pick[i].value.val();
            self.lpos_f[i].invert.next = self.polarity.val().get_bit(3);
            self.lpos_f[i].sample.next = self.sample.val();
            self.lpos_f[i].samples.next = self.filter.val().get_bits::<4>(12);
            self.home_f[i].clock.next = self.clock.val();
            self.home_f[i].reset.next = self.reset.val();
            self.home_f[i].pin.next = self.home_pick[i].value.val();
            self.home_f[i].invert.next = self.polarity.val().get_bit(4);
            self.home_f[i].sample.next = self.sample.val();
            self.home_f[i].samples.next = self.filter.val().get_bits::<4>(16);
            self.alarm_f[i].clock.next = self.clock.val();
            self.alarm_f[i].reset.next = self.reset.val();
            self.alarm_f[i].pin.next = self.alarm_pick[i].value.val();
            self.alarm_f[i].invert.next = self.polarity.val().get_bit(5);
            self.alarm_f[i].sample.next = self.sample.val();
            self.alarm_f[i].samples.next = self.filter.val().get_bits::<4>(20);
            self.lneg_bus[i].value.next = self.lneg_f[i].active.val() & self.c_groups.val().get_bit(2);
            self.lpos_bus[i].value.next = self.lpos_f[i].active.val() & self.c_groups.val().get_bit(2);
            self.home_bus[i].value.next = self.home_f[i].active.val() & self.c_groups.val().get_bit(3);
            self.alarm_bus[i].value.next = self.alarm_f[i].active.val() & self.c_groups.val().get_bit(4);
            self.latch_bus[i].value.next = self.home_f[i].rise.val() & self.c_groups.val().get_bit(3);
            if self.edges.val().get_bit(0) {
                self.latch_bus[i].value.next = self.home_f[i].fall.val() & self.c_groups.val().get_bit(3);
            }
        }
        self.lneg_bus[0].bus_in.next = 0.into();
        self.lpos_bus[0].bus_in.next = 0.into();
        self.home_bus[0].bus_in.next = 0.into();
        self.alarm_bus[0].bus_in.next = 0.into();
        self.latch_bus[0].bus_in.next = 0.into();
        for i in 1..K {
            self.lneg_bus[i].bus_in.next = self.lneg_bus[i - 1].bus_out.val();
            self.lpos_bus[i].bus_in.next = self.lpos_bus[i - 1].bus_out.val();
            self.home_bus[i].bus_in.next = self.home_bus[i - 1].bus_out.val();
            self.alarm_bus[i].bus_in.next = self.alarm_bus[i - 1].bus_out.val();
            self.latch_bus[i].bus_in.next = self.latch_bus[i - 1].bus_out.val();
        }
        // The last element of each chain holds the whole vector (last assignment wins).
        for i in 0..K {
            self.lneg_v.next = self.lneg_bus[i].bus_out.val();
            self.lpos_v.next = self.lpos_bus[i].bus_out.val();
            self.home_active.next = self.home_bus[i].bus_out.val();
            self.alarm_v.next = self.alarm_bus[i].bus_out.val();
            self.latch_v.next = self.latch_bus[i].bus_out.val();
        }
        self.limit_neg_active.next = self.lneg_v.val();
        self.limit_pos_active.next = self.lpos_v.val();
        self.alarm_active.next = self.alarm_v.val();
        self.home_latch.next = self.latch_v.val();

        // The enables: a controlled alarm keeps its axis's while the axis is active.
        self.drv_al.next = self.alarm_v.val();
        if self.stop_mode.val().get_bit(1) {
            self.drv_al.next = self.alarm_v.val() & !self.active.val();
        }
        self.drv.d.next = 0.into();
        if self.run.val() & !self.hard.val() {
            self.drv.d.next = !self.drv_al.val();
        }
        self.drv_enable.next = self.drv.q.val();

        // The per-axis stops (see the module docs): a limit toward which the axis moves
        // (DIR 0 toward limit_pos) in this cycle and the one before, its alarm, its home
        // latch when armed; each hard (s_) or controlled (c_) by its mode bit.
        self.toward_v.next = self.active.val() & ((!self.dir.val() & self.lpos_v.val()) | (self.dir.val() & self.lneg_v.val()));
        self.toward_q.d.next = self.toward_v.val();
        self.limit_v.next = self.toward_v.val() & self.toward_q.q.val();
        self.hit_v.next = self.latch_v.val() & self.home_stop.val() & self.active.val();
        self.s_lim.next = self.limit_v.val();
        self.c_lim.next = 0.into();
        if self.stop_mode.val().get_bit(0) {
            self.s_lim.next = 0.into();
            self.c_lim.next = self.limit_v.val();
        }
        self.s_al.next = self.alarm_v.val();
        self.c_al.next = 0.into();
        if self.stop_mode.val().get_bit(1) {
            self.s_al.next = 0.into();
            self.c_al.next = self.alarm_v.val();
        }
        self.s_hit.next = self.hit_v.val();
        self.c_hit.next = 0.into();
        if self.stop_mode.val().get_bit(3) {
            self.s_hit.next = 0.into();
            self.c_hit.next = self.hit_v.val();
        }
        self.c_wd.next = 0.into();
        if self.tripped.q.val() & self.stop_mode.val().get_bit(2) {
            self.c_wd.next = self.c_ones.val();
        }
        self.stop_new.next = self.s_lim.val() | self.s_al.val() | self.s_hit.val();
        self.cs_new.next = self.c_lim.val() | self.c_al.val() | self.c_hit.val() | self.c_wd.val();
        self.stop_q.d.next = self.stop_new.val();
        self.cs_q.d.next = self.cs_new.val();
        self.tog_q.d.next = self.tog_q.q.val()
            ^ ((self.stop_new.val() | self.cs_new.val()) & !(self.stop_q.q.val() | self.cs_q.q.val()) & self.active.val());
        self.axis_stop.next = self.stop_q.q.val();
        self.axis_cstop.next = self.cs_q.q.val();
        self.stop_tog.next = self.tog_q.q.val();

        if self.reset.val() {
            self.prescaler.d.next = 0.into();
            self.latched.d.next = self.c_groups.val().get_bit(0);
            self.hard_q.d.next = self.c_groups.val().get_bit(0);
            self.wd_count.d.next = 1.into();
            self.tripped.d.next = false;
            self.drv.d.next = 0.into();
            self.toward_q.d.next = 0.into();
            self.stop_q.d.next = 0.into();
            self.tog_q.d.next = 0.into();
            self.cs_q.d.next = 0.into();
            self.wd_rest.d.next = false;
        }
    }
}
