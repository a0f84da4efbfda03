//! The machine I/O registers (`regs::Feature::Io`), in the bus clock, and their
//! crossings to and from [`super::machine_io::MachineIo`] in `clk`. A block beside the
//! register file, not in it: its reads return 0 outside its own addresses, so the top
//! ORs the two read buses, and it decodes its own writes.
//!
//! Ports:
//! * bus side (`bus_clock`, `bus_reset`): `wr`, `wr_addr`, `wr_data` (the EXMC slave's
//!   commit, one cycle), `rd_addr` → `rd_data` (combinational, like the register file's;
//!   the read's axis is decoded a cycle ahead from `rd_axis_next` into one-hot
//!   flip-flops),
//!   `enable` (CTRL.ENABLE), `irq` (IRQ_IO under IRQ_MASK_IO, registered);
//! * configuration to `clk` (`polarity`, `filter`, `prescale`, `edges`, `wd_timeout`):
//!   bus-clock registers written only while CTRL.ENABLE = 0 and the core is held in
//!   reset (seen through `running`), so they are static whenever the machine I/O, held
//!   in reset with the core, uses them; a write at any other time is refused
//!   (IO_STATUS.REFUSED) and changes nothing;
//! * commands to `clk` (`clock`): IO_CMD's bits toggle a flip-flop each; the toggles
//!   cross through two flip-flops and leave as one-cycle pulses (`estop_rearm`,
//!   `wd_feed`, `wd_rearm`) 2 to 3 `clk` edges after the write commits;
//! * status from `clk`: `running` (the core is out of reset), the e-stop latch and
//!   input, the watchdog trip, the probe input, and per axis the filtered inputs and
//!   `drv_enable`, each level through its own two flip-flops (independent flags).
//!
//! * for the push guard ([`super::push_guard::PushGuard`]): the synchronised limits
//!   and alarms, the e-stop latch or trip, and the stops' events, in the bus clock;
//! * position latches from `clk`: a [`WordSync`] copies one axis's latch word at a
//!   time, round robin (`lsel` names the axis, `lword` is the core's word for it, see
//!   [`LATCH_BITS`]), into a mirror in LUT RAM that HOME_POS and PROBE_POS read. A word
//!   whose home toggle differs from the mirror's sets the axis's home event; the probe
//!   event is set once every axis's word shows the new probe toggle, so the host reads
//!   every axis's new PROBE_POS after it. Either event comes at most about one round of
//!   copies, K·(3 clk + 3 bus clocks), after the latch, with its position. Two latches
//!   of one input within one round are one event with the later position (a probe's
//!   two latches within a round may be lost as a pair). Reading HOME_POS_LO or
//!   PROBE_POS_LO latches that register's high half for the next HOME_POS_HI or
//!   PROBE_POS_HI read (one latch for both).
//!
//! Events: IRQ_IO.ESTOP when the synchronised filtered e-stop rises, IRQ_IO.WATCHDOG
//! when the synchronised trip rises, IRQ_IO.PROBE and IRQ_IO.HOME (any axis; IO_AXIS.
//! HOME_LATCHED says which) as above, all only while CTRL.ENABLE = 1 and the core runs
//! (a reset puts the e-stop input active and clears the latches, which is no event);
//! cleared while CTRL.ENABLE = 0, as the register file clears its own.

use super::axis_bank::LATCH_BITS;
use super::cdc::BitsSync;
use super::lut_ram::LutRam;
use super::status_sync::WordSync;
use super::regfile::c9;
use crate::regs::{self, ADDR_BITS};
use rust_hdl::prelude::*;

#[derive(LogicBlock)]
pub struct IoRegs<const K: usize> {
    pub bus_clock: Signal<In, Clock>,
    pub bus_reset: Signal<In, Bit>,
    pub wr: Signal<In, Bit>,
    pub wr_addr: Signal<In, Bits<ADDR_BITS>>,
    pub wr_data: Signal<In, Bits<16>>,
    pub rd_addr: Signal<In, Bits<ADDR_BITS>>,
    pub rd_axis_next: Signal<In, Bits<5>>,
    pub rd_data: Signal<Out, Bits<16>>,
    pub enable: Signal<In, Bit>,
    pub irq: Signal<Out, Bit>,
    pub clock: Signal<In, Clock>,
    pub polarity: Signal<Out, Bits<6>>,
    pub filter: Signal<Out, Bits<24>>,
    pub prescale: Signal<Out, Bits<16>>,
    pub edges: Signal<Out, Bits<2>>,
    pub wd_timeout: Signal<Out, Bits<16>>,
    pub estop_rearm: Signal<Out, Bit>,
    pub wd_feed: Signal<Out, Bit>,
    pub wd_rearm: Signal<Out, Bit>,
    pub running: Signal<In, Bit>,
    pub estop_latched: Signal<In, Bit>,
    pub estop_active: Signal<In, Bit>,
    pub wd_tripped: Signal<In, Bit>,
    pub probe_active: Signal<In, Bit>,
    pub limit_neg: Signal<In, Bits<K>>,
    pub limit_pos: Signal<In, Bits<K>>,
    pub home: Signal<In, Bits<K>>,
    pub alarm: Signal<In, Bits<K>>,
    pub drv_enable: Signal<In, Bits<K>>,
    /// `clk` side of the latch crossing: the core's reset (the top's synchronised
    /// reset, not CTRL.ENABLE), the axis selected and its latch word.
    pub creset: Signal<In, Bit>,
    pub rd: Signal<In, Bit>,
    pub lsel: Signal<Out, Bits<8>>,
    pub lword: Signal<In, Bits<LATCH_BITS>>,
    /// The per-axis stops' toggles (`MachineIo::stop_tog`, clk).
    pub stop_tog: Signal<In, Bits<K>>,
    /// For the push guard, in the bus clock: the filtered limits and alarms (bit a),
    /// the e-stop latch or a watchdog trip (`b_held`), and a stop's event (`b_stop_ev`,
    /// one cycle per stop).
    pub b_lneg: Signal<Out, Bits<K>>,
    pub b_lpos: Signal<Out, Bits<K>>,
    pub b_alarm: Signal<Out, Bits<K>>,
    pub b_held: Signal<Out, Bit>,
    pub b_stop_ev: Signal<Out, Bits<K>>,
    // Bus clock: configuration, flags, events, command toggles.
    pol: DFF<Bits<6>>,
    filt_lo: DFF<Bits<16>>,
    filt_hi: DFF<Bits<8>>,
    pre: DFF<Bits<16>>,
    edg: DFF<Bits<2>>,
    wdt: DFF<Bits<16>>,
    refused: DFF<Bit>,
    lacks: Signal<Local, Bit>,
    events: DFF<Bits<5>>,
    mask: DFF<Bits<5>>,
    stop_s: BitsSync<K>,
    stop_prev: DFF<Bits<K>>,
    stopped: DFF<Bits<K>>,
    new_stop: Signal<Local, Bits<K>>,
    r_stopped: Signal<Local, Bit>,
    toggles: DFF<Bits<3>>,
    prev: DFF<Bits<2>>,
    irq_q: DFF<Bit>,
    g_sync: BitsSync<5>,
    lneg_s: BitsSync<K>,
    lpos_s: BitsSync<K>,
    home_s: BitsSync<K>,
    alarm_s: BitsSync<K>,
    drv_s: BitsSync<K>,
    /// The latch crossing, its mirror (home 31..0, probe 63..32), which axes' mirror
    /// words are written, the mirror's toggles, the probe toggle last announced, the
    /// axes' home events and the high half latched by a LO read.
    lsync: WordSync<K, 67>,
    lmirror: LutRam<64, 4>,
    lvld: DFF<Bits<K>>,
    htog_b: DFF<Bits<K>>,
    ptog_b: DFF<Bits<K>>,
    pann: DFF<Bit>,
    home_ev: DFF<Bits<K>>,
    hi_latch: DFF<Bits<16>>,
    c_one: Constant<Bits<K>>,
    c_ones: Constant<Bits<K>>,
    l_word: Signal<Local, Bits<67>>,
    /// The copy brings a home latch of its axis (a running core, a new toggle).
    l_home: Signal<Local, Bit>,
    l_onehot: Signal<Local, Bits<K>>,
    l_hbits: Signal<Local, Bits<K>>,
    l_pbits: Signal<Local, Bits<K>>,
    /// The copy's axis, if its word brings a new home toggle from a running core.
    l_hnew: Signal<Local, Bits<K>>,
    p_new: Signal<Local, Bits<K>>,
    /// The probe event: every axis's mirror shows a probe toggle not yet announced.
    p_event: Signal<Local, Bit>,
    r_lat: Signal<Local, Bits<64>>,
    r_lvld: Signal<Local, Bit>,
    r_hev: Signal<Local, Bit>,
    o_hlo: Constant<Bits<4>>,
    o_hhi: Constant<Bits<4>>,
    o_plo: Constant<Bits<4>>,
    o_phi: Constant<Bits<4>>,
    // Core clock: the commands' toggles, synchronised, and their last values.
    cmd_sync: BitsSync<3>,
    cmd_prev: DFF<Bits<3>>,
    // Addresses.
    a_pol: Constant<Bits<ADDR_BITS>>,
    a_flo: Constant<Bits<ADDR_BITS>>,
    a_fhi: Constant<Bits<ADDR_BITS>>,
    a_pre: Constant<Bits<ADDR_BITS>>,
    a_edg: Constant<Bits<ADDR_BITS>>,
    a_wdt: Constant<Bits<ADDR_BITS>>,
    a_cmd: Constant<Bits<ADDR_BITS>>,
    a_st: Constant<Bits<ADDR_BITS>>,
    a_irq: Constant<Bits<ADDR_BITS>>,
    a_mask: Constant<Bits<ADDR_BITS>>,
    /// IO_AXIS's offset in an axis block.
    o_axis: Constant<Bits<4>>,
    pol_reset: Constant<Bits<6>>,
    /// Masks of the fields the export has (`with_groups`), and the configuration
    /// registers it lacks (bit 0 IO_PRESCALE, 1 IO_EDGES, 2 WD_TIMEOUT): a write to one
    /// of them is refused.
    c_pol_m: Constant<Bits<6>>,
    c_flo_m: Constant<Bits<16>>,
    c_fhi_m: Constant<Bits<8>>,
    c_edg_m: Constant<Bits<2>>,
    c_absent: Constant<Bits<3>>,
    /// The synchronised global flags: running, e-stop latch, e-stop input, trip, probe.
    g: Signal<Local, Bits<5>>,
    may_config: Signal<Local, Bit>,
    rd_axis_reg: Signal<Local, Bit>,
    /// The read addresses axis i's block (bit i; 0 for a global register or an axis
    /// ≥ K), decoded a cycle ahead from `rd_axis_next`, as the register file does.
    rsel: DFF<Bits<K>>,
    /// The e-stop input (bit 0) and the trip (bit 1), synchronised.
    now: Signal<Local, Bits<2>>,
    /// This cycle's new events (IRQ_IO's bits).
    new_ev: Signal<Local, Bits<5>>,
    /// The commands' toggles that changed (clk).
    pulses: Signal<Local, Bits<3>>,
    /// IO_AXIS of the read's axis, bit by bit.
    r_hit: Signal<Local, Bit>,
    r_lneg: Signal<Local, Bit>,
    r_lpos: Signal<Local, Bit>,
    r_home: Signal<Local, Bit>,
    r_alarm: Signal<Local, Bit>,
    r_drv: Signal<Local, Bit>,
}

impl<const K: usize> Default for IoRegs<K> {
    fn default() -> Self {
        let r = regs::register("IO_AXIS");
        assert!(r.per_axis);
        assert!((1..=16).contains(&K), "IoRegs<{K}>: the latch mirror holds 16 axes");
        IoRegs {
            bus_clock: Default::default(),
            bus_reset: Default::default(),
            wr: Default::default(),
            wr_addr: Default::default(),
            wr_data: Default::default(),
            rd_addr: Default::default(),
            rd_axis_next: Default::default(),
            rd_data: Default::default(),
            enable: Default::default(),
            irq: Default::default(),
            clock: Default::default(),
            polarity: Default::default(),
            filter: Default::default(),
            prescale: Default::default(),
            edges: Default::default(),
            wd_timeout: Default::default(),
            estop_rearm: Default::default(),
            wd_feed: Default::default(),
            wd_rearm: Default::default(),
            running: Default::default(),
            estop_latched: Default::default(),
            estop_active: Default::default(),
            wd_tripped: Default::default(),
            probe_active: Default::default(),
            limit_neg: Default::default(),
            limit_pos: Default::default(),
            home: Default::default(),
            alarm: Default::default(),
            drv_enable: Default::default(),
            creset: Default::default(),
            rd: Default::default(),
            lsel: Default::default(),
            lword: Default::default(),
            stop_tog: Default::default(),
            b_lneg: Default::default(),
            b_lpos: Default::default(),
            b_alarm: Default::default(),
            b_held: Default::default(),
            b_stop_ev: Default::default(),
            pol: Default::default(),
            filt_lo: Default::default(),
            filt_hi: Default::default(),
            pre: Default::default(),
            edg: Default::default(),
            wdt: Default::default(),
            refused: Default::default(),
            lacks: Default::default(),
            events: Default::default(),
            mask: Default::default(),
            stop_s: Default::default(),
            stop_prev: Default::default(),
            stopped: Default::default(),
            new_stop: Default::default(),
            r_stopped: Default::default(),
            toggles: Default::default(),
            prev: Default::default(),
            irq_q: Default::default(),
            g_sync: Default::default(),
            lneg_s: Default::default(),
            lpos_s: Default::default(),
            home_s: Default::default(),
            alarm_s: Default::default(),
            drv_s: Default::default(),
            lsync: Default::default(),
            lmirror: Default::default(),
            lvld: Default::default(),
            htog_b: Default::default(),
            ptog_b: Default::default(),
            pann: Default::default(),
            home_ev: Default::default(),
            hi_latch: Default::default(),
            c_one: Constant::new(1.into()),
            c_ones: Constant::new(((1u64 << K) - 1).into()),
            l_word: Default::default(),
            l_home: Default::default(),
            l_onehot: Default::default(),
            l_hbits: Default::default(),
            l_pbits: Default::default(),
            l_hnew: Default::default(),
            p_new: Default::default(),
            p_event: Default::default(),
            r_lat: Default::default(),
            r_lvld: Default::default(),
            r_hev: Default::default(),
            o_hlo: o4("HOME_POS_LO"),
            o_hhi: o4("HOME_POS_HI"),
            o_plo: o4("PROBE_POS_LO"),
            o_phi: o4("PROBE_POS_HI"),
            cmd_sync: Default::default(),
            cmd_prev: Default::default(),
            a_pol: c9("IO_POLARITY"),
            a_flo: c9("IO_FILTER_LO"),
            a_fhi: c9("IO_FILTER_HI"),
            a_pre: c9("IO_PRESCALE"),
            a_edg: c9("IO_EDGES"),
            a_wdt: c9("WD_TIMEOUT"),
            a_cmd: c9("IO_CMD"),
            a_st: c9("IO_STATUS"),
            a_irq: c9("IRQ_IO"),
            a_mask: c9("IRQ_MASK_IO"),
            o_axis: Constant::new((r.offset as u64).into()),
            pol_reset: Constant::new((regs::register("IO_POLARITY").reset_value(&IO_PARAMS) as u64).into()),
            c_pol_m: Constant::new(0x3F.into()),
            c_flo_m: Constant::new(0xFFFF.into()),
            c_fhi_m: Constant::new(0xFF.into()),
            c_edg_m: Constant::new(0x3.into()),
            c_absent: Constant::new(0.into()),
            g: Default::default(),
            may_config: Default::default(),
            rd_axis_reg: Default::default(),
            rsel: Default::default(),
            now: Default::default(),
            new_ev: Default::default(),
            pulses: Default::default(),
            r_hit: Default::default(),
            r_lneg: Default::default(),
            r_lpos: Default::default(),
            r_home: Default::default(),
            r_alarm: Default::default(),
            r_drv: Default::default(),
        }
    }
}

/// A per-axis register's offset in the axis block.
fn o4(name: &str) -> Constant<Bits<4>> {
    let r = regs::register(name);
    assert!(r.per_axis, "{name} is per axis");
    Constant::new((r.offset as u64).into())
}

/// Reset values of the I/O registers do not depend on the core's parameters.
const IO_PARAMS: regs::CoreParams =
    regs::CoreParams { axes: 1, clock_hz: 1, queue_depth: 2, fifo_depth: 2, t_calc: 1, min_period: 2, io: true, io_omit: 0, scurve: false, encoder: false };

impl<const K: usize> IoRegs<K> {
    /// The registers of an export with the machine I/O groups `groups`
    /// (`regs::IO_GROUPS` bits): the fields of the others are 0 and not written, and a
    /// write to a configuration register the export lacks is refused
    /// (IO_STATUS.REFUSED). `default()` has every group.
    pub fn with_groups(mut self, groups: u8) -> Self {
        let p = regs::CoreParams { io_omit: regs::IO_ALL & !groups, ..IO_PARAMS };
        let table = regs::table_for(&p);
        let find = |name: &str| table.iter().find(|r| r.name == name);
        let mask = |name: &str| find(name).map_or(0u64, |r| r.fields.iter().map(|f| ((1u64 << f.width) - 1) << f.lsb).sum());
        let pol = mask("IO_POLARITY");
        self.c_pol_m = Constant::new(pol.into());
        self.c_flo_m = Constant::new(mask("IO_FILTER_LO").into());
        self.c_fhi_m = Constant::new(mask("IO_FILTER_HI").into());
        self.c_edg_m = Constant::new(mask("IO_EDGES").into());
        let absent = ["IO_PRESCALE", "IO_EDGES", "WD_TIMEOUT"].iter().enumerate().map(|(i, n)| (find(n).is_none() as u64) << i).sum::<u64>();
        self.c_absent = Constant::new(absent.into());
        self.pol_reset = Constant::new((regs::register("IO_POLARITY").reset_value(&p) as u64 & pol).into());
        self
    }

    /// Marks the inputs as driven from outside and connects the block (tests).
    pub fn connect_ports(&mut self) {
        self.bus_clock.connect();
        self.bus_reset.connect();
        self.wr.connect();
        self.wr_addr.connect();
        self.wr_data.connect();
        self.rd_addr.connect();
        self.rd_axis_next.connect();
        self.enable.connect();
        self.clock.connect();
        self.running.connect();
        self.estop_latched.connect();
        self.estop_active.connect();
        self.wd_tripped.connect();
        self.probe_active.connect();
        self.limit_neg.connect();
        self.limit_pos.connect();
        self.home.connect();
        self.alarm.connect();
        self.drv_enable.connect();
        self.creset.connect();
        self.rd.connect();
        self.lword.connect();
        self.stop_tog.connect();
        self.connect_all();
    }
}

impl<const K: usize> Logic for IoRegs<K> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, bus_clock, pol, filt_lo, filt_hi, pre, edg, wdt, refused, events, mask, toggles, prev, irq_q);
        dff_setup!(self, bus_clock, lvld, htog_b, ptog_b, pann, home_ev, hi_latch, stop_prev, stopped, rsel);
        // The per-axis stops' events: their toggles across.
        self.stop_s.clock.next = self.bus_clock.val();
        self.stop_s.sig_in.next = self.stop_tog.val();
        self.stop_prev.d.next = self.stop_s.sig_out.val();
        self.new_stop.next = self.stop_s.sig_out.val() ^ self.stop_prev.q.val();
        self.stopped.d.next = self.stopped.q.val() | self.new_stop.val();
        dff_setup!(self, clock, cmd_prev);
        // Status into the bus clock.
        self.g_sync.clock.next = self.bus_clock.val();
        self.g_sync.sig_in.next = bit_cast::<5, 1>(self.running.val().into())
            | (bit_cast::<5, 1>(self.estop_latched.val().into()) << 1)
            | (bit_cast::<5, 1>(self.estop_active.val().into()) << 2)
            | (bit_cast::<5, 1>(self.wd_tripped.val().into()) << 3)
            | (bit_cast::<5, 1>(self.probe_active.val().into()) << 4);
        self.g.next = self.g_sync.sig_out.val();
        self.lneg_s.clock.next = self.bus_clock.val();
        self.lneg_s.sig_in.next = self.limit_neg.val();
        self.lpos_s.clock.next = self.bus_clock.val();
        self.lpos_s.sig_in.next = self.limit_pos.val();
        self.home_s.clock.next = self.bus_clock.val();
        self.home_s.sig_in.next = self.home.val();
        self.alarm_s.clock.next = self.bus_clock.val();
        self.alarm_s.sig_in.next = self.alarm.val();
        self.drv_s.clock.next = self.bus_clock.val();
        self.drv_s.sig_in.next = self.drv_enable.val();
        self.b_lneg.next = self.lneg_s.sig_out.val();
        self.b_lpos.next = self.lpos_s.sig_out.val();
        self.b_alarm.next = self.alarm_s.sig_out.val();
        self.b_held.next = self.g.val().get_bit(1) | self.g.val().get_bit(3);
        self.b_stop_ev.next = self.new_stop.val();

        // Configuration out (static while used: see the module comment).
        self.polarity.next = self.pol.q.val();
        self.filter.next = bit_cast::<24, 16>(self.filt_lo.q.val()) | (bit_cast::<24, 8>(self.filt_hi.q.val()) << 16);
        self.prescale.next = self.pre.q.val();
        self.edges.next = self.edg.q.val();
        self.wd_timeout.next = self.wdt.q.val();

        // Commands: toggles across, pulses out.
        self.cmd_sync.clock.next = self.clock.val();
        self.cmd_sync.sig_in.next = self.toggles.q.val();
        self.cmd_prev.d.next = self.cmd_sync.sig_out.val();
        // (A bit of an expression would be `(a ^ b)[0]` in the Verilog, which is not
        // Verilog: select from a signal.)
        self.pulses.next = self.cmd_sync.sig_out.val() ^ self.cmd_prev.q.val();
        self.estop_rearm.next = self.pulses.val().get_bit(0);
        self.wd_feed.next = self.pulses.val().get_bit(1);
        self.wd_rearm.next = self.pulses.val().get_bit(2);

        // Writes.
        self.may_config.next = !self.enable.val() & !self.g.val().get_bit(0);
        // (A configuration register of a group the export lacks: a write is refused.)
        self.lacks.next = ((self.wr_addr.val() == self.a_pre.val()) & self.c_absent.val().get_bit(0))
            | ((self.wr_addr.val() == self.a_edg.val()) & self.c_absent.val().get_bit(1))
            | ((self.wr_addr.val() == self.a_wdt.val()) & self.c_absent.val().get_bit(2));
        if self.wr.val() {
            if (self.wr_addr.val() == self.a_pol.val())
                | (self.wr_addr.val() == self.a_flo.val())
                | (self.wr_addr.val() == self.a_fhi.val())
                | (self.wr_addr.val() == self.a_pre.val())
                | (self.wr_addr.val() == self.a_edg.val())
                | (self.wr_addr.val() == self.a_wdt.val())
            {
                if !self.may_config.val() {
                    self.refused.d.next = true;
                }
            }
            if self.lacks.val() {
                self.refused.d.next = true;
            }
            if self.may_config.val() & !self.lacks.val() {
                if self.wr_addr.val() == self.a_pol.val() {
                    self.pol.d.next = self.wr_data.val().get_bits::<6>(0) & self.c_pol_m.val();
                }
                if self.wr_addr.val() == self.a_flo.val() {
                    self.filt_lo.d.next = self.wr_data.val() & self.c_flo_m.val();
                }
                if self.wr_addr.val() == self.a_fhi.val() {
                    self.filt_hi.d.next = self.wr_data.val().get_bits::<8>(0) & self.c_fhi_m.val();
                }
                if self.wr_addr.val() == self.a_pre.val() {
                    self.pre.d.next = self.wr_data.val();
                }
                if self.wr_addr.val() == self.a_edg.val() {
                    self.edg.d.next = self.wr_data.val().get_bits::<2>(0) & self.c_edg_m.val();
                }
                if self.wr_addr.val() == self.a_wdt.val() {
                    self.wdt.d.next = self.wr_data.val();
                }
            }
            if self.wr_addr.val() == self.a_cmd.val() {
                self.toggles.d.next = self.toggles.q.val() ^ self.wr_data.val().get_bits::<3>(0);
            }
            if (self.wr_addr.val() == self.a_st.val()) & self.wr_data.val().get_bit(4) {
                self.refused.d.next = false;
            }
            if self.wr_addr.val() == self.a_mask.val() {
                self.mask.d.next = self.wr_data.val().get_bits::<5>(0);
            }
        }

        // Position latches: the crossing, the mirror, the toggles and their events.
        self.lsync.cclock.next = self.clock.val();
        self.lsync.creset.next = self.creset.val();
        self.lsync.bclock.next = self.bus_clock.val();
        self.lsync.breset.next = self.bus_reset.val();
        self.lsel.next = self.lsync.sel.val();
        self.lsync.word_in.next = bit_cast::<67, LATCH_BITS>(self.lword.val()) | (bit_cast::<67, 1>(self.running.val().into()) << 66);
        self.l_word.next = self.lsync.word.val();
        self.lmirror.clock.next = self.bus_clock.val();
        self.lmirror.we.next = self.lsync.valid.val();
        self.lmirror.waddr.next = self.lsync.axis.val().get_bits::<4>(0);
        self.lmirror.wdata.next = self.l_word.val().get_bits::<64>(0);
        self.lmirror.raddr.next = self.rd_addr.val().get_bits::<4>(4);
        // (Shifts and constants, not a BitInsert chain: a chain built and read in this
        // block is a combinational cycle to Verilator.)
        self.l_onehot.next = 0.into();
        if self.lsync.valid.val() {
            self.l_onehot.next = self.c_one.val() << self.lsync.axis.val();
        }
        self.l_hbits.next = 0.into();
        if self.l_word.val().get_bit(64) {
            self.l_hbits.next = self.c_ones.val();
        }
        self.l_pbits.next = 0.into();
        if self.l_word.val().get_bit(65) {
            self.l_pbits.next = self.c_ones.val();
        }
        self.lvld.d.next = self.lvld.q.val() | self.l_onehot.val();
        self.htog_b.d.next = (self.htog_b.q.val() & !self.l_onehot.val()) | (self.l_hbits.val() & self.l_onehot.val());
        self.ptog_b.d.next = (self.ptog_b.q.val() & !self.l_onehot.val()) | (self.l_pbits.val() & self.l_onehot.val());
        self.l_hnew.next = 0.into();
        if self.l_word.val().get_bit(66) {
            self.l_hnew.next = (self.l_hbits.val() ^ self.htog_b.q.val()) & self.l_onehot.val();
        }
        self.l_home.next = self.l_hnew.val().any();
        self.home_ev.d.next = self.home_ev.q.val() | self.l_hnew.val();
        // The probe event: every axis's mirror shows a toggle other than `pann`.
        if self.pann.q.val() {
            self.p_new.next = !self.ptog_b.q.val();
        } else {
            self.p_new.next = self.ptog_b.q.val();
        }
        self.p_event.next = self.p_new.val().all();
        if self.p_event.val() {
            self.pann.d.next = !self.pann.q.val();
        }
        // A word from a core held in reset (latches clear), or the core disabled: the
        // toggles restart from 0 with the core's, and nothing is an event.
        if self.lsync.valid.val() & !self.l_word.val().get_bit(66) {
            self.pann.d.next = false;
        }
        if !self.enable.val() {
            self.htog_b.d.next = 0.into();
            self.ptog_b.d.next = 0.into();
            self.pann.d.next = false;
        }

        // Events: the e-stop input and the trip rising, while the core runs.
        self.now.next = bit_cast::<2, 1>(self.g.val().get_bit(2).into()) | (bit_cast::<2, 1>(self.g.val().get_bit(3).into()) << 1);
        self.prev.d.next = self.now.val();
        self.new_ev.next = bit_cast::<5, 2>(self.now.val() & !self.prev.q.val())
            | (bit_cast::<5, 1>(self.p_event.val().into()) << 2)
            | (bit_cast::<5, 1>(self.l_home.val().into()) << 3)
            | (bit_cast::<5, 1>(self.new_stop.val().any().into()) << 4);
        self.events.d.next = self.events.q.val() | self.new_ev.val();
        if self.wr.val() & (self.wr_addr.val() == self.a_irq.val()) {
            self.events.d.next = (self.events.q.val() & !self.wr_data.val().get_bits::<5>(0)) | self.new_ev.val();
            if self.wr_data.val().get_bit(3) {
                self.home_ev.d.next = self.l_hnew.val();
            }
            if self.wr_data.val().get_bit(4) {
                self.stopped.d.next = self.new_stop.val();
            }
        }
        if !self.enable.val() | !self.g.val().get_bit(0) {
            self.events.d.next = 0.into();
            self.home_ev.d.next = 0.into();
            self.stopped.d.next = 0.into();
        }
        self.irq_q.d.next = (self.events.q.val() & self.mask.q.val()).any();
        self.irq.next = self.irq_q.q.val();

        // Reads: 0 outside this block's addresses.
        self.rd_data.next = 0.into();
        if self.rd_addr.val() == self.a_pol.val() {
            self.rd_data.next = bit_cast::<16, 6>(self.pol.q.val());
        }
        if self.rd_addr.val() == self.a_flo.val() {
            self.rd_data.next = self.filt_lo.q.val();
        }
        if self.rd_addr.val() == self.a_fhi.val() {
            self.rd_data.next = bit_cast::<16, 8>(self.filt_hi.q.val());
        }
        if self.rd_addr.val() == self.a_pre.val() {
            self.rd_data.next = self.pre.q.val();
        }
        if self.rd_addr.val() == self.a_edg.val() {
            self.rd_data.next = bit_cast::<16, 2>(self.edg.q.val());
        }
        if self.rd_addr.val() == self.a_wdt.val() {
            self.rd_data.next = self.wdt.q.val();
        }
        if self.rd_addr.val() == self.a_st.val() {
            self.rd_data.next = bit_cast::<16, 1>(self.g.val().get_bit(1).into())
                | (bit_cast::<16, 1>(self.g.val().get_bit(2).into()) << 1)
                | (bit_cast::<16, 1>(self.g.val().get_bit(3).into()) << 2)
                | (bit_cast::<16, 1>(self.g.val().get_bit(4).into()) << 3)
                | (bit_cast::<16, 1>(self.refused.q.val().into()) << 4);
        }
        if self.rd_addr.val() == self.a_irq.val() {
            self.rd_data.next = bit_cast::<16, 5>(self.events.q.val());
        }
        if self.rd_addr.val() == self.a_mask.val() {
            self.rd_data.next = bit_cast::<16, 5>(self.mask.q.val());
        }
        self.rd_axis_reg.next = self.rd_addr.val().get_bit(8) & (self.rd_addr.val().get_bits::<4>(0) == self.o_axis.val());
        // Each per-axis field: an OR of the axes' values under the one-hot select, so
        // the path to `rd_data` starts at flip-flops, not at a K:1 multiplexer.
        self.rsel.d.next = 0.into();
        if self.rd_axis_next.val().get_bit(4) {
            self.rsel.d.next = self.c_one.val() << self.rd_axis_next.val().get_bits::<4>(0);
        }
        self.r_lvld.next = (self.lvld.q.val() & self.rsel.q.val()).any();
        self.r_hev.next = (self.home_ev.q.val() & self.rsel.q.val()).any();
        self.r_stopped.next = (self.stopped.q.val() & self.rsel.q.val()).any();
        self.r_hit.next = self.rd_axis_reg.val() & self.rsel.q.val().any();
        self.r_lneg.next = (self.lneg_s.sig_out.val() & self.rsel.q.val()).any();
        self.r_lpos.next = (self.lpos_s.sig_out.val() & self.rsel.q.val()).any();
        self.r_home.next = (self.home_s.sig_out.val() & self.rsel.q.val()).any();
        self.r_alarm.next = (self.alarm_s.sig_out.val() & self.rsel.q.val()).any();
        self.r_drv.next = (self.drv_s.sig_out.val() & self.rsel.q.val()).any();
        if self.r_hit.val() {
            self.rd_data.next = bit_cast::<16, 1>(self.r_lneg.val().into())
                | (bit_cast::<16, 1>(self.r_lpos.val().into()) << 1)
                | (bit_cast::<16, 1>(self.r_home.val().into()) << 2)
                | (bit_cast::<16, 1>(self.r_alarm.val().into()) << 3)
                | (bit_cast::<16, 1>(self.r_drv.val().into()) << 4)
                | (bit_cast::<16, 1>(self.r_hev.val().into()) << 5)
                | (bit_cast::<16, 1>(self.r_stopped.val().into()) << 6);
        }
        // The latch mirror at the read's axis (0 until its first word).
        self.r_lat.next = 0.into();
        if self.r_lvld.val() {
            self.r_lat.next = self.lmirror.rdata.val();
        }
        if self.rd_addr.val().get_bit(8) {
            if self.rd_addr.val().get_bits::<4>(0) == self.o_hlo.val() {
                self.rd_data.next = self.r_lat.val().get_bits::<16>(0);
                if self.rd.val() {
                    self.hi_latch.d.next = self.r_lat.val().get_bits::<16>(16);
                }
            }
            if self.rd_addr.val().get_bits::<4>(0) == self.o_plo.val() {
                self.rd_data.next = self.r_lat.val().get_bits::<16>(32);
                if self.rd.val() {
                    self.hi_latch.d.next = self.r_lat.val().get_bits::<16>(48);
                }
            }
            if (self.rd_addr.val().get_bits::<4>(0) == self.o_hhi.val()) | (self.rd_addr.val().get_bits::<4>(0) == self.o_phi.val()) {
                self.rd_data.next = self.hi_latch.q.val();
            }
        }

        if self.bus_reset.val() {
            self.pol.d.next = self.pol_reset.val();
            self.filt_lo.d.next = 0.into();
            self.filt_hi.d.next = 0.into();
            self.pre.d.next = 0.into();
            self.edg.d.next = 0.into();
            self.wdt.d.next = 0.into();
            self.refused.d.next = false;
            self.events.d.next = 0.into();
            self.mask.d.next = 0.into();
            self.toggles.d.next = 0.into();
            self.irq_q.d.next = false;
            self.lvld.d.next = 0.into();
            self.htog_b.d.next = 0.into();
            self.ptog_b.d.next = 0.into();
            self.pann.d.next = false;
            self.home_ev.d.next = 0.into();
            self.hi_latch.d.next = 0.into();
            self.stop_prev.d.next = 0.into();
            self.stopped.d.next = 0.into();
        }
    }
}
