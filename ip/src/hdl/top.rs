//! The whole IP core as exported: `tdm_stepper` (docs/architecture.md).
//!
//! ```text
//!  bus_clk domain                          | clk domain
//!  ExmcSlave -> RegFile --cmd--> AsyncFifo ---> command decode -> TdmCore (or Baseline)
//!                  ^                       |                        |
//!                  +------ StatusSync <----+---- status word <------+
//! ```
//!
//! Ports: `clk` (the core clock, whose ticks every period counts), `bus_clk` (samples
//! the EXMC pins; unrelated to `clk`), `reset` (synchronous, active high, synchronised
//! into each domain; hold it for at least 4 cycles of the slower clock), the EXMC pins
//! (`ne`, `noe`, `nwe`, `addr`, `data_in`, `data_out`, `data_oe`), and per axis `step`
//! and `dir`, plus `irq` (active high, bus clock). `fsm_state` shows the scheduler's
//! Gray-coded state for waveforms.
//!
//! In the core clock, commands leave the FIFO one per cycle into a registered command
//! stage (one clk of latency, the same for every kind): a push goes to the core's
//! command port (the register file's LEVEL accounting guarantees room), START and ABORT
//! pulse the core's `start` (with the mask) and `abort`. While CTRL.ENABLE is 0 (seen
//! through a synchroniser), the core is held in reset and commands are drained and
//! dropped. The status word of the axis the handshake selects is assembled here.
//!
//! **Machine I/O** ([`TdmStepperIo`], `export --io all`): the input pins `estop_n`,
//! `probe`, `limit_neg`, `limit_pos`, `home`, `alarm` and the output `drv_enable` (K
//! bits), the [`MachineIo`] block in clk (held in reset with the core) and its
//! registers ([`IoRegs`]) beside the register file; the read buses are ORed (each
//! reads 0 outside its addresses) and so are the IRQs. Its `hard_stop` holds the
//! core's `abort` high: queues and FIFOs flushed every cycle it lasts, no new STEP edge,
//! a pulse already high keeps its high time, positions exact (a push arriving during
//! it is flushed and counted as taken).
//!
//! `Core` is [`TdmCore`] or the non-TDM [`Baseline`]: both have the same ports, so the
//! same top (`TdmStepper` / `BaselineStepper`) is generated for each by a macro.

use super::baseline::Baseline;
use super::cdc::{AsyncFifo, BitSync};
use super::core::{TdmCore, STATE_BITS};
use super::enc_bank::EncoderBank;
use super::enc_regs::EncRegs;
use super::exmc::ExmcSlave;
use super::io_regs::IoRegs;
use super::machine_io::MachineIo;
use super::push_guard::PushGuard;
use super::stop_regs::StopRegs;
use super::poly_lane::POLY_EXTRA_BITS;
use super::poly_regs::PolyRegs;
use super::push_check::CMD_EXTRA_BITS;
use super::regfile::{RegFile, CMD_BITS};
use super::status_sync::{StatusSync, STATUS_BITS};
use crate::regs::{CoreParams, ADDR_BITS};
use rust_hdl::prelude::*;

macro_rules! stepper_top {
    ($name:ident, $core:ident, $doc:expr $(, $io:ident)? $(; $enc:ident)?) => {
        #[doc = $doc]
        #[derive(LogicBlock)]
        pub struct $name<const K: usize, const R: usize, const DEPTH: usize, const QDEPTH: usize, const S: usize = 0> {
            pub clk: Signal<In, Clock>,
            pub bus_clk: Signal<In, Clock>,
            pub reset: Signal<In, Bit>,
            pub ne: Signal<In, Bit>,
            pub noe: Signal<In, Bit>,
            pub nwe: Signal<In, Bit>,
            pub addr: Signal<In, Bits<ADDR_BITS>>,
            pub data_in: Signal<In, Bits<16>>,
            pub data_out: Signal<Out, Bits<16>>,
            pub data_oe: Signal<Out, Bit>,
            pub step: Signal<Out, Bits<K>>,
            pub dir: Signal<Out, Bits<K>>,
            pub irq: Signal<Out, Bit>,
            pub fsm_state: Signal<Out, Bits<STATE_BITS>>,
            rst_bus: BitSync,
            rst_core: BitSync,
            en_core: BitSync,
            /// The core's cancelled-START toggle, synchronised into bus_clk.
            fail_sync: BitSync,
            pub exmc: ExmcSlave,
            pub regs: RegFile<K, S>,
            cmd_fifo: AsyncFifo<CMD_BITS>,
            status: StatusSync<K>,
            pub core: $core<K, R, DEPTH, QDEPTH, S>,
            /// The S-curve option (S = 1): its registers, and a FIFO beside the command
            /// FIFO, written and read in the same cycles, for a polynomial push's v1
            /// and A'; the command stage's copy and the polynomial flag.
            polys: [PolyRegs; S],
            xfifo: [AsyncFifo<CMD_EXTRA_BITS>; S],
            c_extra: DFF<Bits<CMD_EXTRA_BITS>>,
            c_pflag: DFF<Bit>,
            p_rd: Signal<Local, Bits<16>>,
            cmd_kind: Signal<Local, Bits<2>>,
            /// The core's reset: the core held while the reset pin or CTRL.ENABLE = 0,
            /// from a flip-flop (`core_run`, its inverse, so it powers up holding), so
            /// no gate sits between a register and a net that reaches every flip-flop
            /// of the core and its options (a K = 16 `clk` path across the die).
            core_reset: Signal<Local, Bit>,
            core_run: DFF<Bit>,
            /// The status word's BUSY bit (with the machine I/O, registered).
            w_busy: Signal<Local, Bit>,
            /// The selected axis's BUSY, registered (see `update`; unread without options,
            /// and removed by synthesis then).
            busy_q: DFF<Bit>,
            /// The command stage: the FIFO's head, decoded and registered on its way
            /// to the core (push, START, ABORT and the entry's 104 data bits).
            c_push: DFF<Bit>,
            c_start: DFF<Bit>,
            c_abort: DFF<Bit>,
            c_word: DFF<Bits<104>>,
            /// The read bus, the irq and the per-axis hard stops of the register file
            /// and the machine I/O; the encoder's (0 without it), ORed with them last.
            rd_base: Signal<Local, Bits<16>>,
            irq_base: Signal<Local, Bit>,
            stop_base: Signal<Local, Bits<K>>,
            e_rd: Signal<Local, Bits<16>>,
            e_irq: Signal<Local, Bit>,
            e_stop: Signal<Local, Bits<K>>,
            cstop_base: Signal<Local, Bits<K>>,
            e_cstop: Signal<Local, Bits<K>>,
            e_stop_ev: Signal<Local, Bits<K>>,
            /// The machine I/O's probe strobe, for the encoders' probe latch (0 without it).
            io_probe: Signal<Local, Bit>,
            $(
                /// Machine I/O (`export --io all`): the input pins, per axis (bit a = axis a)
                /// and global, and the drivers' enables.
                pub estop_n: Signal<In, Bit>,
                pub probe: Signal<In, Bit>,
                pub limit_neg: Signal<In, Bits<K>>,
                pub limit_pos: Signal<In, Bits<K>>,
                pub home: Signal<In, Bits<K>>,
                pub alarm: Signal<In, Bits<K>>,
                pub drv_enable: Signal<Out, Bits<K>>,
                pub $io: MachineIo<K>,
                pub io_regs: IoRegs<K>,
                pub guard: PushGuard<K>,
                pub stop_regs: StopRegs<K>,
            )?
            $(
                /// Encoder feedback (`export --encoder`): the quadrature pins (bit a = axis
                /// a; asynchronous), the decoders with the shared following-error unit
                /// ([`EncoderBank`]) in clk, held in reset with the core, and their
                /// registers ([`EncRegs`]).
                pub enc_a: Signal<In, Bits<K>>,
                pub enc_b: Signal<In, Bits<K>>,
                pub enc_z: Signal<In, Bits<K>>,
                pub $enc: EncoderBank<K>,
                pub enc_regs: EncRegs<K>,
            )?
        }

        impl<const K: usize, const R: usize, const DEPTH: usize, const QDEPTH: usize, const S: usize> $name<K, R, DEPTH, QDEPTH, S> {
            /// The core for these parameters (the minimum period among them); `params`
            /// must agree with K, DEPTH and QDEPTH.
            pub fn new(params: CoreParams) -> Self {
                assert_eq!(params.queue_depth, QDEPTH, "queue depth parameter");
                assert_eq!(params.fifo_depth, DEPTH, "period FIFO depth parameter");
                assert_eq!(params.scurve, S == 1, "S-curve parameter");
                let has_io = false $(|| { let _ = stringify!($io); true })?;
                $name {
                    clk: Default::default(),
                    bus_clk: Default::default(),
                    reset: Default::default(),
                    ne: Default::default(),
                    noe: Default::default(),
                    nwe: Default::default(),
                    addr: Default::default(),
                    data_in: Default::default(),
                    data_out: Default::default(),
                    data_oe: Default::default(),
                    step: Default::default(),
                    dir: Default::default(),
                    irq: Default::default(),
                    fsm_state: Default::default(),
                    rst_bus: Default::default(),
                    rst_core: Default::default(),
                    en_core: Default::default(),
                    fail_sync: Default::default(),
                    exmc: Default::default(),
                    regs: RegFile::new(params),
                    cmd_fifo: Default::default(),
                    status: Default::default(),
                    // (The machine I/O's stops need the core's per-axis and controlled stops.)
                    // (The encoders' stop needs the core's per-axis stops.)
                    core: {
                        let c = if has_io { $core::new().with_controlled_stop() } else { $core::new() };
                        $(
                            let _ = stringify!($enc);
                            let c = c.with_axis_stops();
                        )?
                        c
                    },
                    cmd_kind: Default::default(),
                    core_reset: Default::default(),
                    core_run: Default::default(),
                    w_busy: Default::default(),
                    busy_q: Default::default(),
                    c_push: Default::default(),
                    c_start: Default::default(),
                    c_abort: Default::default(),
                    c_word: Default::default(),
                    polys: std::array::from_fn(|_| Default::default()),
                    xfifo: std::array::from_fn(|_| Default::default()),
                    c_extra: Default::default(),
                    c_pflag: Default::default(),
                    p_rd: Default::default(),
                    rd_base: Default::default(),
                    irq_base: Default::default(),
                    stop_base: Default::default(),
                    e_rd: Default::default(),
                    e_irq: Default::default(),
                    e_stop: Default::default(),
                    cstop_base: Default::default(),
                    e_cstop: Default::default(),
                    e_stop_ev: Default::default(),
                    io_probe: Default::default(),
                    $(
                        enc_a: Default::default(),
                        enc_b: Default::default(),
                        enc_z: Default::default(),
                        $enc: Default::default(),
                        enc_regs: EncRegs::default().with_io(has_io),
                    )?
                    $(
                        estop_n: Default::default(),
                        probe: Default::default(),
                        limit_neg: Default::default(),
                        limit_pos: Default::default(),
                        home: Default::default(),
                        alarm: Default::default(),
                        drv_enable: Default::default(),
                        $io: MachineIo::default().with_groups(params.io_groups()),
                        io_regs: IoRegs::default().with_groups(params.io_groups()),
                        guard: Default::default(),
                        stop_regs: StopRegs::new(params.stop_decel_min()).with_groups(params.io_groups()),
                    )?
                }
            }

            /// Marks the top-level inputs as driven from outside and connects the
            /// block, as simulation and Verilog generation need.
            pub fn connect_ports(&mut self) {
                self.clk.connect();
                self.bus_clk.connect();
                self.reset.connect();
                self.ne.connect();
                self.noe.connect();
                self.nwe.connect();
                self.addr.connect();
                self.data_in.connect();
                $(
                    let _ = stringify!($io);
                    self.estop_n.connect();
                    self.probe.connect();
                    self.limit_neg.connect();
                    self.limit_pos.connect();
                    self.home.connect();
                    self.alarm.connect();
                )?
                $(
                    let _ = stringify!($enc);
                    self.enc_a.connect();
                    self.enc_b.connect();
                    self.enc_z.connect();
                )?
                self.connect_all();
            }
        }

        impl<const K: usize, const R: usize, const DEPTH: usize, const QDEPTH: usize, const S: usize> Logic for $name<K, R, DEPTH, QDEPTH, S> {
            #[hdl_gen]
            fn update(&mut self) {
                dff_setup!(self, clk, c_push, c_start, c_abort, c_word, c_extra, c_pflag);
                self.e_rd.next = 0.into();
                self.e_irq.next = false;
                self.e_stop.next = 0.into();
                self.e_stop_ev.next = 0.into();
                self.io_probe.next = false;
                // Resets and the enable, into each domain.
                self.rst_bus.clock.next = self.bus_clk.val();
                self.rst_bus.sig_in.next = self.reset.val();
                self.rst_core.clock.next = self.clk.val();
                self.rst_core.sig_in.next = self.reset.val();
                self.en_core.clock.next = self.clk.val();
                self.en_core.sig_in.next = self.regs.enable.val();
                self.core_run.clock.next = self.clk.val();
                self.core_run.d.next = !self.rst_core.sig_out.val() & self.en_core.sig_out.val();
                self.core_reset.next = !self.core_run.q.val();
                // A cancelled START: the core's toggle across (one event per change).
                self.fail_sync.clock.next = self.bus_clk.val();
                self.fail_sync.sig_in.next = self.core.start_failed.val();
                self.regs.start_fail_toggle.next = self.fail_sync.sig_out.val();

                // Bus side.
                self.exmc.clock.next = self.bus_clk.val();
                self.exmc.reset.next = self.rst_bus.sig_out.val();
                self.exmc.ne.next = self.ne.val();
                self.exmc.noe.next = self.noe.val();
                self.exmc.nwe.next = self.nwe.val();
                self.exmc.addr.next = self.addr.val();
                self.exmc.data_in.next = self.data_in.val();
                self.data_out.next = self.exmc.data_out.val();
                self.data_oe.next = self.exmc.data_oe.val();
                self.regs.clock.next = self.bus_clk.val();
                self.regs.reset.next = self.rst_bus.sig_out.val();
                self.regs.wr.next = self.exmc.wr.val();
                self.regs.wr_addr.next = self.exmc.wr_addr.val();
                self.regs.wr_data.next = self.exmc.wr_data.val();
                self.regs.rd.next = self.exmc.rd.val();
                self.regs.rd_addr.next = self.exmc.rd_addr.val();
                self.regs.rd_axis_next.next = self.exmc.rd_axis_next.val();
                self.regs.wr_next.next = self.exmc.wr_next.val();
                self.regs.wr_axis_next.next = self.exmc.wr_axis_next.val();
                // The S-curve option's registers and extra FIFO (S = 1).
                self.regs.poly_arm.next = false;
                self.regs.poly_extra.next = 0.into();
                self.p_rd.next = 0.into();
                self.c_extra.d.next = 0.into();
                for i in 0..S {
                    self.polys[i].bus_clock.next = self.bus_clk.val();
                    self.polys[i].bus_reset.next = self.rst_bus.sig_out.val();
                    self.polys[i].wr.next = self.exmc.wr.val();
                    self.polys[i].wr_addr.next = self.exmc.wr_addr.val();
                    self.polys[i].wr_data.next = self.exmc.wr_data.val();
                    self.polys[i].rd_addr.next = self.exmc.rd_addr.val();
                    self.polys[i].enable.next = self.regs.enable.val();
                    self.polys[i].pushed.next = self.regs.offer.val() & (self.regs.offer_kind.val() == 3);
                    self.regs.poly_arm.next = self.polys[i].arm.val();
                    self.regs.poly_extra.next = self.polys[i].extra.val();
                    self.p_rd.next = self.polys[i].rd_data.val();
                    self.xfifo[i].wclock.next = self.bus_clk.val();
                    self.xfifo[i].wreset.next = self.rst_bus.sig_out.val();
                    self.xfifo[i].write.next = self.regs.cmd_write.val();
                    self.xfifo[i].data_in.next = self.regs.cmd_extra.val();
                    self.xfifo[i].rclock.next = self.clk.val();
                    self.xfifo[i].rreset.next = self.rst_core.sig_out.val();
                    self.xfifo[i].read.next = true;
                    self.c_extra.d.next = self.xfifo[i].data_out.val();
                }
                self.rd_base.next = self.regs.rd_data.val() | self.p_rd.val();
                self.irq_base.next = self.regs.irq.val();
                // The push guard is the machine I/O's.
                self.regs.guard_code.next = 0.into();

                // Commands across.
                self.cmd_fifo.wclock.next = self.bus_clk.val();
                self.cmd_fifo.wreset.next = self.rst_bus.sig_out.val();
                self.cmd_fifo.write.next = self.regs.cmd_write.val();
                self.cmd_fifo.data_in.next = self.regs.cmd_data.val();
                self.regs.cmd_full.next = self.cmd_fifo.full.val();
                self.regs.cmd_almost_full.next = self.cmd_fifo.almost_full.val();
                self.cmd_fifo.rclock.next = self.clk.val();
                self.cmd_fifo.rreset.next = self.rst_core.sig_out.val();
                self.cmd_fifo.read.next = true;
                self.cmd_kind.next = self.cmd_fifo.data_out.val().get_bits::<2>(104);

                // Core side.
                self.core.clock.next = self.clk.val();
                self.core.reset.next = self.core_reset.val();
                // Quasi-static: the register file changes them only while the core is
                // held in reset (CTRL.ENABLE and GSTATUS.ENABLED both 0).
                self.core.high_min.next = self.regs.high_min.val();
                self.core.low_min.next = self.regs.low_min.val();
                // The command stage: what leaves the FIFO is decoded into registers and
                // reaches the core one cycle later, every kind alike (so order and the
                // spacing of commands are kept); nothing from the FIFO's pointers or
                // memory drives the core's flush or queues combinationally.
                self.c_word.d.next = self.cmd_fifo.data_out.val().get_bits::<104>(0);
                self.c_push.d.next = false;
                self.c_pflag.d.next = false;
                self.c_start.d.next = false;
                self.c_abort.d.next = false;
                if !self.cmd_fifo.empty.val() & !self.core_reset.val() {
                    if self.cmd_kind.val() == 0 {
                        self.c_push.d.next = true;
                    }
                    // A polynomial push (S = 1 only: kind 3 never comes without it).
                    if self.cmd_kind.val() == 3 {
                        self.c_push.d.next = true;
                        self.c_pflag.d.next = true;
                    }
                    if self.cmd_kind.val() == 1 {
                        self.c_start.d.next = true;
                    }
                    if self.cmd_kind.val() == 2 {
                        self.c_abort.d.next = true;
                    }
                }
                self.core.cmd_v0.next = self.c_word.q.val().get_bits::<32>(0);
                self.core.cmd_t.next = self.c_word.q.val().get_bits::<32>(32);
                self.core.cmd_steps.next = self.c_word.q.val().get_bits::<32>(64);
                self.core.cmd_extra.next = bit_cast::<POLY_EXTRA_BITS, CMD_EXTRA_BITS>(self.c_extra.q.val());
                if self.c_pflag.q.val() {
                    self.core.cmd_extra.next = bit_cast::<POLY_EXTRA_BITS, CMD_EXTRA_BITS>(self.c_extra.q.val()) | (bit_cast::<POLY_EXTRA_BITS, 1>(1.into()) << 96);
                }
                self.core.cmd_axis.next = self.c_word.q.val().get_bits::<8>(96);
                self.core.start_mask.next = self.c_word.q.val().get_bits::<K>(0);
                self.core.ext_go.next = 0.into();
                self.core.cmd_valid.next = self.c_push.q.val();
                self.core.start.next = self.c_start.q.val();
                self.core.abort.next = self.c_abort.q.val();
                self.step.next = self.core.step.val();
                self.dir.next = self.core.dir.val();
                self.fsm_state.next = self.core.fsm_state.val();

                // Status back.
                self.status.cclock.next = self.clk.val();
                self.status.creset.next = self.rst_core.sig_out.val();
                self.status.bclock.next = self.bus_clk.val();
                self.status.breset.next = self.rst_bus.sig_out.val();
                self.core.sel_axis.next = self.status.sel.val();
                self.stop_base.next = 0.into();
                self.cstop_base.next = 0.into();
                self.e_cstop.next = 0.into();
                self.core.decel.next = 0.into();
                // Position latches: only the machine I/O drives them.
                self.core.home_latch.next = 0.into();
                self.core.probe_latch.next = false;
                self.core.lsel_axis.next = 0.into();
                self.core.epos_axis.next = 0.into();
                self.w_busy.next = self.core.sel_busy.val();
                self.busy_q.clock.next = self.clk.val();
                self.busy_q.d.next = self.core.sel_busy.val();
                self.regs.st_valid.next = self.status.valid.val();
                self.regs.st_axis.next = self.status.axis.val();
                self.regs.st_word.next = self.status.word.val();

                $(
                    // Machine I/O: its registers beside the register file (the read buses
                    // ORed: each reads 0 outside its addresses), its block in clk, held in
                    // reset with the core; its hard stop holds the core's abort.
                    self.$io.reset.next = self.core_reset.val();
                    // The status word's BUSY a tick behind its position and counts: it
                    // cuts the selected axis's BUSY multiplexer from the word's register
                    // (a K = 8 `clk` path with the machine I/O's spread placement). A
                    // word with BUSY = 0 is still exact: BUSY was 0 a tick earlier, so
                    // no edge moved the position and nothing was taken in between (an
                    // axis with anything queued is BUSY); BUSY = 1 only delays a resync.
                    self.w_busy.next = self.busy_q.q.val();
                    self.$io.run.next = !self.core_reset.val();
                    self.$io.estop_n.next = self.estop_n.val();
                    self.$io.probe.next = self.probe.val();
                    self.$io.limit_neg.next = self.limit_neg.val();
                    self.$io.limit_pos.next = self.limit_pos.val();
                    self.$io.home.next = self.home.val();
                    self.$io.alarm.next = self.alarm.val();
                    self.$io.polarity.next = self.io_regs.polarity.val();
                    self.$io.filter.next = self.io_regs.filter.val();
                    self.$io.prescale.next = self.io_regs.prescale.val();
                    self.$io.edges.next = self.io_regs.edges.val();
                    self.$io.wd_timeout.next = self.io_regs.wd_timeout.val();
                    self.$io.estop_rearm.next = self.io_regs.estop_rearm.val();
                    self.$io.wd_feed.next = self.io_regs.wd_feed.val();
                    self.$io.wd_rearm.next = self.io_regs.wd_rearm.val();
                    self.drv_enable.next = self.$io.drv_enable.val();
                    self.io_regs.bus_clock.next = self.bus_clk.val();
                    self.io_regs.bus_reset.next = self.rst_bus.sig_out.val();
                    self.io_regs.wr.next = self.exmc.wr.val();
                    self.io_regs.wr_addr.next = self.exmc.wr_addr.val();
                    self.io_regs.wr_data.next = self.exmc.wr_data.val();
                    self.io_regs.rd_addr.next = self.exmc.rd_addr.val();
                    self.io_regs.rd_axis_next.next = self.exmc.rd_axis_next.val();
                    self.io_regs.enable.next = self.regs.enable.val();
                    self.io_regs.clock.next = self.clk.val();
                    self.io_regs.running.next = !self.core_reset.val();
                    self.io_regs.estop_latched.next = self.$io.estop_latched.val();
                    self.io_regs.estop_active.next = self.$io.estop_active.val();
                    self.io_regs.wd_tripped.next = self.$io.wd_tripped.val();
                    self.io_regs.probe_active.next = self.$io.probe_active.val();
                    self.io_regs.limit_neg.next = self.$io.limit_neg_active.val();
                    self.io_regs.limit_pos.next = self.$io.limit_pos_active.val();
                    self.io_regs.home.next = self.$io.home_active.val();
                    self.io_regs.alarm.next = self.$io.alarm_active.val();
                    self.io_regs.drv_enable.next = self.$io.drv_enable.val();
                    self.io_regs.rd.next = self.exmc.rd.val();
                    self.io_regs.creset.next = self.rst_core.sig_out.val();
                    self.core.home_latch.next = self.$io.home_latch.val();
                    self.core.probe_latch.next = self.$io.probe_latch.val();
                    self.io_probe.next = self.$io.probe_latch.val();
                    self.core.lsel_axis.next = self.io_regs.lsel.val();
                    self.io_regs.lword.next = self.core.lsel_word.val();
                    // Limits, alarms and the stop on home stop their axes (hard here).
                    self.$io.dir.next = self.core.dir.val();
                    self.$io.active.next = self.core.active.val();
                    self.stop_base.next = self.$io.axis_stop.val();
                    self.io_regs.stop_tog.next = self.$io.stop_tog.val();
                    // The push guard: beside the check, on the status words, with the
                    // machine I/O's levels and stops.
                    self.guard.clock.next = self.bus_clk.val();
                    self.guard.reset.next = self.rst_bus.sig_out.val();
                    self.guard.enable.next = self.regs.enable.val();
                    self.guard.wr.next = self.exmc.wr.val();
                    self.guard.wr_addr.next = self.exmc.wr_addr.val();
                    self.guard.wr_data.next = self.exmc.wr_data.val();
                    self.guard.rd.next = self.exmc.rd.val();
                    self.guard.rd_addr.next = self.exmc.rd_addr.val();
                    self.guard.offer.next = self.regs.offer.val();
                    // A polynomial push (kind 3) is a push to the guard.
                    if self.regs.offer_kind.val() == 3 {
                        self.guard.offer_kind.next = 0.into();
                    } else {
                        self.guard.offer_kind.next = self.regs.offer_kind.val();
                    }
                    self.guard.offer_axis.next = self.regs.offer_axis.val();
                    self.guard.offer_steps.next = self.regs.offer_steps.val();
                    self.guard.accept.next = self.regs.cmd_write.val();
                    self.regs.guard_code.next = self.guard.code.val();
                    self.guard.st_valid.next = self.status.valid.val();
                    self.guard.st_axis.next = self.status.axis.val().get_bits::<4>(0);
                    self.guard.st_pos.next = self.status.word.val().get_bits::<32>(0);
                    self.guard.st_taken.next = self.status.word.val().get_bits::<8>(32);
                    self.guard.st_busy.next = self.status.word.val().get_bit(56);
                    self.guard.st_pushed.next = self.regs.st_pushed.val();
                    self.guard.lim_neg.next = self.io_regs.b_lneg.val();
                    self.guard.lim_pos.next = self.io_regs.b_lpos.val();
                    self.guard.alarm.next = self.io_regs.b_alarm.val();
                    self.guard.held_all.next = self.io_regs.b_held.val();
                    // The controlled stop's registers and their crossing.
                    self.stop_regs.bus_clock.next = self.bus_clk.val();
                    self.stop_regs.bus_reset.next = self.rst_bus.sig_out.val();
                    self.stop_regs.wr.next = self.exmc.wr.val();
                    self.stop_regs.wr_addr.next = self.exmc.wr_addr.val();
                    self.stop_regs.wr_data.next = self.exmc.wr_data.val();
                    self.stop_regs.rd_addr.next = self.exmc.rd_addr.val();
                    self.stop_regs.enable.next = self.regs.enable.val();
                    self.stop_regs.clock.next = self.clk.val();
                    // The host's STOP, and the sources STOP_MODE puts in controlled mode.
                    self.cstop_base.next = self.stop_regs.cstop.val() | self.$io.axis_cstop.val();
                    self.$io.stop_mode.next = self.stop_regs.mode.val();
                    self.$io.home_stop.next = self.stop_regs.home_arm.val();
                    self.core.decel.next = self.stop_regs.decel.val();
                    self.rd_base.next = self.regs.rd_data.val() | self.io_regs.rd_data.val() | self.guard.rd_data.val() | self.stop_regs.rd_data.val() | self.p_rd.val();
                    self.irq_base.next = self.regs.irq.val() | self.io_regs.irq.val();
                    // The hard stop holds the abort, except in a cycle that brings a push:
                    // the queue takes it then and the next cycle's abort flushes it and
                    // counts it as taken (an abort and a push in one cycle would drop the
                    // push uncounted, and LEVEL would never come back to 0). A START does
                    // nothing while the hard stop holds, nor in the tick before it (the
                    // filtered e-stop is active, `hard_stop` is registered from it).
                    self.core.abort.next = self.c_abort.q.val() | (self.$io.hard_stop.val() & !self.c_push.q.val());
                    self.core.start.next = self.c_start.q.val()
                        & !self.$io.hard_stop.val()
                        & !self.$io.wd_tripped.val()
                        & !self.$io.estop_active.val();
                )?
                $(
                    // Encoder feedback: the bank in clk, held in reset with the core, its
                    // position port on the core's, its registers beside the register file.
                    self.$enc.clock.next = self.clk.val();
                    // The status word's BUSY registered, as with the machine I/O (the
                    // option's placement stretches the same path).
                    self.w_busy.next = self.busy_q.q.val();
                    self.$enc.reset.next = self.core_reset.val();
                    self.$enc.enc_a.next = self.enc_a.val();
                    self.$enc.enc_b.next = self.enc_b.val();
                    self.$enc.enc_z.next = self.enc_z.val();
                    self.$enc.mode.next = self.enc_regs.mode.val();
                    self.$enc.invert.next = self.enc_regs.invert.val();
                    self.$enc.vel_prescale.next = self.enc_regs.vel_prescale.val();
                    self.$enc.arm.next = self.enc_regs.arm.val();
                    self.$enc.align.next = self.enc_regs.align.val();
                    self.$enc.clear.next = self.enc_regs.clear.val();
                    self.$enc.probe.next = self.io_probe.val();
                    self.core.epos_axis.next = self.$enc.pos_axis.val();
                    self.$enc.position.next = self.core.epos.val();
                    self.$enc.pos_low.next = self.core.pos_low.val();
                    self.enc_regs.pos_axis.next = self.$enc.pos_axis.val();
                    self.$enc.ratio.next = self.enc_regs.ratio.val();
                    self.$enc.tol.next = self.enc_regs.tol.val();
                    self.$enc.sel.next = self.enc_regs.sel.val();
                    self.enc_regs.word_lo.next = self.$enc.word_lo.val();
                    self.enc_regs.word_hi.next = self.$enc.word_hi.val();
                    self.enc_regs.fail.next = self.$enc.fail.val();
                    self.enc_regs.bus_clock.next = self.bus_clk.val();
                    self.enc_regs.bus_reset.next = self.rst_bus.sig_out.val();
                    self.enc_regs.wr.next = self.exmc.wr.val();
                    self.enc_regs.wr_addr.next = self.exmc.wr_addr.val();
                    self.enc_regs.wr_data.next = self.exmc.wr_data.val();
                    self.enc_regs.rd.next = self.exmc.rd.val();
                    self.enc_regs.rd_addr.next = self.exmc.rd_addr.val();
                    self.enc_regs.enable.next = self.regs.enable.val();
                    self.enc_regs.clock.next = self.clk.val();
                    self.enc_regs.creset.next = self.rst_core.sig_out.val();
                    self.enc_regs.running.next = !self.core_reset.val();
                    self.e_rd.next = self.enc_regs.rd_data.val();
                    self.e_irq.next = self.enc_regs.irq.val();
                    self.e_stop.next = self.enc_regs.stop.val();
                    self.e_cstop.next = self.enc_regs.cstop.val();
                    self.e_stop_ev.next = self.enc_regs.b_stop_ev.val();
                )?
                $(
                    // (A controlled stop, or an encoder's, makes the plan stale as the
                    // limits' stops do.)
                    self.guard.stop_ev.next = self.io_regs.b_stop_ev.val() | self.stop_regs.requested.val() | self.e_stop_ev.val();
                    self.$io.clock.next = self.clk.val();
                )?
                // The status word last: it reads `w_busy`, which the options rewrite (a
                // local written again after a read reads differently in Verilog).
                self.status.word_in.next = bit_cast::<STATUS_BITS, 32>(self.core.sel_position.val())
                    | (bit_cast::<STATUS_BITS, 8>(self.core.sel_taken.val()) << 32)
                    | (bit_cast::<STATUS_BITS, 8>(self.core.sel_done.val()) << 40)
                    | (bit_cast::<STATUS_BITS, 8>(self.core.sel_underruns.val()) << 48)
                    | (bit_cast::<STATUS_BITS, 1>(self.w_busy.val().into()) << 56)
                    | (bit_cast::<STATUS_BITS, 1>((!self.core_reset.val()).into()) << 57);
                self.exmc.rd_data.next = self.rd_base.val() | self.e_rd.val();
                self.irq.next = self.irq_base.val() | self.e_irq.val();
                self.core.stop_axes.next = self.stop_base.val() | self.e_stop.val();
                self.core.cstop_axes.next = self.cstop_base.val() | self.e_cstop.val();
            }
        }
    };
}

stepper_top!(TdmStepper, TdmCore, "The exported IP core around the TDM core (module `tdm_stepper`).");
stepper_top!(BaselineStepper, Baseline, "The same IP core around the non-TDM baseline, for the sweep.");
stepper_top!(
    TdmStepperEnc,
    TdmCore,
    "The exported IP core with encoder feedback (`export --encoder`): `TdmStepper` plus the pins `enc_a`, `enc_b`, `enc_z`, the `EncoderBank` (`enc`) and its registers (`EncRegs`).";
    enc
);
stepper_top!(
    TdmStepperIoEnc,
    TdmCore,
    "The exported IP core with the machine I/O and encoder feedback (`export --io all --encoder`).",
    io;
    enc
);
stepper_top!(
    TdmStepperIo,
    TdmCore,
    "The exported IP core with the machine I/O (`export --io all`): `TdmStepper` plus the input pins, `drv_enable`, the `MachineIo` block (`io`) and its registers (`IoRegs`).",
    io
);
