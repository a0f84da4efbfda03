//! The EXMC bus model: an MCU's FSMC in asynchronous SRAM mode 1, 16-bit, clocked by
//! its own HCLK (unrelated to the core's clocks), turned into [`BusEvent`]s for
//! [`super::system`].
//!
//! An access holds NE low for ADDSET cycles with the address out and both strobes
//! high, then DATAST cycles with NWE (data driven) or NOE low, then NE and the strobe
//! rise together and the bus rests one cycle. A read samples the data at the end of
//! DATAST, just before NOE rises. [`BusTiming::minimum`] is the documented minimum
//! (docs/registers.md) for given clocks. Inputs, in order: `reset`, `ne`, `noe`,
//! `nwe`, `addr`, `data_in`.

use super::system::{run_system_rust_hdl, BusEvent, Clocks, SystemSpec, SystemTrace};
use crate::hdl::top::{TdmStepper, TdmStepperEnc, TdmStepperIo};
use rust_hdl::prelude::*;
use super::tb::Port;
use crate::model::Segment;
use crate::regs::{self, ADDR_BITS};

/// FSMC timing, in HCLK cycles.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BusTiming {
    /// Half the HCLK period, ps (a multiple of 3).
    pub mcu_half_ps: u64,
    pub addset: u64,
    pub datast_write: u64,
    pub datast_read: u64,
}

/// Bus clocks the slave needs (docs/registers.md): strobes high, NWE low, NOE low.
pub const MIN_HIGH_BUS_CLOCKS: u64 = 2;
pub const MIN_WRITE_BUS_CLOCKS: u64 = 3;
pub const MIN_READ_BUS_CLOCKS: u64 = 5;

impl BusTiming {
    /// The documented minimum for a slave sampling at `bus_half_ps`:
    /// ADDSET = ⌈2·T_bus/T_HCLK⌉, DATAST = ⌈3·T_bus/T_HCLK⌉ (write), ⌈5·T_bus/T_HCLK⌉ (read).
    pub fn minimum(bus_half_ps: u64, mcu_half_ps: u64) -> BusTiming {
        let cycles = |n: u64| (n * bus_half_ps).div_ceil(mcu_half_ps);
        BusTiming {
            mcu_half_ps,
            addset: cycles(MIN_HIGH_BUS_CLOCKS),
            datast_write: cycles(MIN_WRITE_BUS_CLOCKS),
            datast_read: cycles(MIN_READ_BUS_CLOCKS),
        }
    }
}

/// The interface [`super::system`] drives: the EXMC pins in, `watch` outputs out,
/// `data_out` sampled.
pub fn system_spec(module: &str, watch: Vec<Port>) -> SystemSpec {
    SystemSpec {
        module: module.to_string(),
        inputs: vec![
            Port::new("reset", 1),
            Port::new("ne", 1),
            Port::new("noe", 1),
            Port::new("nwe", 1),
            Port::new("addr", ADDR_BITS),
            Port::new("data_in", 16),
        ],
        watch,
        sample: Port::new("data_out", 16),
    }
}

/// The outputs a simulation of the whole IP watches, in this order: `step`, `dir` (K
/// bits each) and `irq`. [`run_stepper_rust_hdl`] reports the same.
pub fn stepper_watch(axes: usize) -> Vec<Port> {
    vec![Port::new("step", axes), Port::new("dir", axes), Port::new("irq", 1)]
}

/// The two clocks of a whole IP (`TdmStepper` or `TdmStepperIo`) in rust-hdl.
macro_rules! clock_stepper {
    ($u:expr, $c:expr, $bc:expr) => {{
        $u.clk.next = Clock::from($c);
        $u.bus_clk.next = Clock::from($bc);
    }};
}

/// The pins of [`system_spec`] (reset and the EXMC pins, in its order) into a whole IP.
macro_rules! drive_bus_pins {
    ($u:expr, $p:expr) => {{
        $u.reset.next = $p[0] == 1;
        $u.ne.next = $p[1] == 1;
        $u.noe.next = $p[2] == 1;
        $u.nwe.next = $p[3] == 1;
        $u.addr.next = ($p[4] as u64).into();
        $u.data_in.next = ($p[5] as u64).into();
    }};
}

/// Runs bus `events` into a rust-hdl [`TdmStepper`] (connected with `connect_ports`):
/// clk and bus_clk from `clocks`, the pins as [`system_spec`] lists them, the outputs
/// of [`stepper_watch`] watched and `data_out` sampled, as the Verilator run does.
pub fn run_stepper_rust_hdl<const K: usize, const R: usize, const D: usize, const Q: usize, const S: usize>(
    u: &mut TdmStepper<K, R, D, Q, S>,
    clocks: &Clocks,
    events: &[BusEvent],
    cycles: u64,
    pauses: &[(u64, u64)],
    progress: bool,
) -> SystemTrace {
    run_system_rust_hdl(
        u,
        clocks,
        events,
        cycles,
        pauses,
        progress,
        |u, c, bc| clock_stepper!(u, c, bc),
        |u, p| drive_bus_pins!(u, p),
        |u| vec![u.step.val().to_u64() as u128, u.dir.val().to_u64() as u128, u.irq.val() as u128],
        |u| u.data_out.val().to_u64() as u128,
    )
}

/// The exported TDM core (R = [`crate::latency::RADIX_BITS`], the export's FIFO and
/// queue depths) for `params` (K = 1, 2, 4 or 8, each a compiled instance; with or
/// without the S-curve option; no other option), simulated in rust-hdl with [`run_stepper_rust_hdl`]
/// under bus `events`, the bus paused where [`super::system::bus_pauses`] finds it
/// idle for a second or more: what `tdm-stepper sim --engine rust-hdl` runs. The
/// instances are made here, in the optimised IP crate, not in the tool. Err for
/// another K or option.
pub fn run_tdm_rust_hdl(params: regs::CoreParams, clocks: &Clocks, events: &[BusEvent], cycles: u64, progress: bool) -> Result<SystemTrace, String> {
    if params.io || params.encoder {
        return Err("--engine rust-hdl simulates the core without the machine I/O and encoder options".into());
    }
    let (clocks, events) = (*clocks, events.to_vec());
    std::thread::Builder::new()
        .stack_size(256 << 20)
        .spawn(move || {
            let c = &clocks;
            let e = events.as_slice();
            match (params.axes, params.scurve) {
                (1, false) => Ok(tdm_rust_hdl::<1, 0>(params, c, e, cycles, progress)),
                (2, false) => Ok(tdm_rust_hdl::<2, 0>(params, c, e, cycles, progress)),
                (4, false) => Ok(tdm_rust_hdl::<4, 0>(params, c, e, cycles, progress)),
                (8, false) => Ok(tdm_rust_hdl::<8, 0>(params, c, e, cycles, progress)),
                (1, true) => Ok(tdm_rust_hdl::<1, 1>(params, c, e, cycles, progress)),
                (2, true) => Ok(tdm_rust_hdl::<2, 1>(params, c, e, cycles, progress)),
                (4, true) => Ok(tdm_rust_hdl::<4, 1>(params, c, e, cycles, progress)),
                (8, true) => Ok(tdm_rust_hdl::<8, 1>(params, c, e, cycles, progress)),
                (k, _) => Err(format!("--engine rust-hdl supports --axes 1, 2, 4 or 8 (got {k})")),
            }
        })
        .map_err(|e| e.to_string())?
        .join()
        .map_err(|_| "the rust-hdl simulation panicked".to_string())?
}

fn tdm_rust_hdl<const K: usize, const S: usize>(params: regs::CoreParams, clocks: &Clocks, events: &[BusEvent], cycles: u64, progress: bool) -> SystemTrace {
    use crate::latency::{FIFO_DEPTH, QUEUE_DEPTH, RADIX_BITS};
    let mut u = Box::new(TdmStepper::<K, RADIX_BITS, FIFO_DEPTH, QUEUE_DEPTH, S>::new(params));
    u.connect_ports();
    let pauses = super::system::bus_pauses(events, 1_000_000_000);
    let trace = run_stepper_rust_hdl(u.as_mut(), clocks, events, cycles, &pauses, progress);
    if progress {
        eprintln!();
    }
    trace
}

/// [`run_stepper_rust_hdl`] for the core with the machine I/O: each event holds the
/// bus pins, then estop_n, probe, limit_neg, limit_pos, home and alarm (as
/// [`with_extra_inputs`] adds them), and `drv_enable` is watched after `irq`.
pub fn run_stepper_io_rust_hdl<const K: usize, const R: usize, const D: usize, const Q: usize>(
    u: &mut TdmStepperIo<K, R, D, Q>,
    clocks: &Clocks,
    events: &[BusEvent],
    cycles: u64,
) -> SystemTrace {
    run_system_rust_hdl(
        u,
        clocks,
        events,
        cycles,
        &[],
        false,
        |u, c, bc| clock_stepper!(u, c, bc),
        |u, p| {
            drive_bus_pins!(u, p);
            u.estop_n.next = p[6] == 1;
            u.probe.next = p[7] == 1;
            u.limit_neg.next = (p[8] as u64).into();
            u.limit_pos.next = (p[9] as u64).into();
            u.home.next = (p[10] as u64).into();
            u.alarm.next = (p[11] as u64).into();
        },
        |u| vec![u.step.val().to_u64() as u128, u.dir.val().to_u64() as u128, u.irq.val() as u128, u.drv_enable.val().to_u64() as u128],
        |u| u.data_out.val().to_u64() as u128,
    )
}

/// [`run_stepper_rust_hdl`] for the core with encoder feedback: each event holds the
/// bus pins, then enc_a, enc_b and enc_z (as [`with_extra_inputs`] adds them).
pub fn run_stepper_enc_rust_hdl<const K: usize, const R: usize, const D: usize, const Q: usize>(
    u: &mut TdmStepperEnc<K, R, D, Q>,
    clocks: &Clocks,
    events: &[BusEvent],
    cycles: u64,
) -> SystemTrace {
    run_system_rust_hdl(
        u,
        clocks,
        events,
        cycles,
        &[],
        false,
        |u, c, bc| clock_stepper!(u, c, bc),
        |u, p| {
            drive_bus_pins!(u, p);
            u.enc_a.next = (p[6] as u64).into();
            u.enc_b.next = (p[7] as u64).into();
            u.enc_z.next = (p[8] as u64).into();
        },
        |u| vec![u.step.val().to_u64() as u128, u.dir.val().to_u64() as u128, u.irq.val() as u128],
        |u| u.data_out.val().to_u64() as u128,
    )
}

/// Builds a bus transaction list. Starts in reset, pins idle.
#[derive(Clone, Debug)]
pub struct BusModel {
    pub timing: BusTiming,
    pins: [u128; 6],
    /// HCLK cycle of the next access.
    now: u64,
    events: Vec<BusEvent>,
    reads: Vec<(usize, u16)>,
}

/// Handle of a read: [`BusModel::value`] gives what it returned.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ReadId(usize);

impl BusModel {
    pub fn new(timing: BusTiming) -> BusModel {
        assert!(timing.mcu_half_ps % 3 == 0, "HCLK half period must be a multiple of 3 ps");
        let pins = [1, 1, 1, 1, 0, 0];
        BusModel { timing, pins, now: 0, events: vec![BusEvent { time_ps: 2, inputs: pins.to_vec(), sample: false }], reads: vec![] }
    }

    fn time(&self, cycle: u64) -> u64 {
        2 + 2 * self.timing.mcu_half_ps * cycle
    }

    /// HCLK cycles to cover `ps` picoseconds.
    pub fn cycles_for_ps(&self, ps: u64) -> u64 {
        ps.div_ceil(2 * self.timing.mcu_half_ps)
    }

    /// Time of the next access, ps.
    pub fn now_ps(&self) -> u64 {
        self.time(self.now)
    }

    fn set(&mut self, cycle: u64, pins: [u128; 6], sample: bool) {
        let t = self.time(cycle);
        self.pins = pins;
        match self.events.last_mut() {
            Some(e) if e.time_ps == t => {
                e.inputs = pins.to_vec();
                e.sample |= sample;
            }
            _ => {
                assert!(self.events.last().is_none_or(|e| e.time_ps < t), "bus events out of order");
                self.events.push(BusEvent { time_ps: t, inputs: pins.to_vec(), sample });
            }
        }
    }

    /// Holds reset for `cycles` HCLK cycles from now, then releases it.
    pub fn reset(&mut self, cycles: u64) {
        let mut p = self.pins;
        p[0] = 1;
        self.set(self.now, p, false);
        self.now += cycles;
        p[0] = 0;
        self.set(self.now, p, false);
        self.now += 1;
    }

    /// Waits `cycles` HCLK cycles.
    pub fn idle(&mut self, cycles: u64) {
        self.now += cycles;
    }

    /// Waits until `ps`.
    pub fn idle_until_ps(&mut self, ps: u64) {
        self.now = self.now.max(self.cycles_for_ps(ps));
    }

    /// A write whose NWE stays low `low` cycles (DATAST for a normal write).
    pub fn write_with_low(&mut self, addr: u16, data: u16, low: u64) {
        let t = self.timing;
        let mut p = self.pins;
        p[1] = 0;
        p[2] = 1;
        p[3] = 1;
        p[4] = addr as u128;
        self.set(self.now, p, false);
        p[3] = 0;
        p[5] = data as u128;
        self.set(self.now + t.addset, p, false);
        p[1] = 1;
        p[3] = 1;
        self.set(self.now + t.addset + low, p, false);
        self.now += t.addset + low + 1;
    }

    pub fn write(&mut self, addr: u16, data: u16) {
        self.write_with_low(addr, data, self.timing.datast_write);
    }

    pub fn read(&mut self, addr: u16) -> ReadId {
        let t = self.timing;
        let mut p = self.pins;
        p[1] = 0;
        p[2] = 1;
        p[3] = 1;
        p[4] = addr as u128;
        self.set(self.now, p, false);
        p[2] = 0;
        self.set(self.now + t.addset, p, false);
        p[1] = 1;
        p[2] = 1;
        self.set(self.now + t.addset + t.datast_read, p, true);
        self.reads.push((self.events.len() - 1, addr));
        self.now += t.addset + t.datast_read + 1;
        ReadId(self.reads.len() - 1)
    }

    pub fn events(&self) -> &[BusEvent] {
        &self.events
    }

    /// What read `id` returned in `trace` (None: undefined bits).
    pub fn value(&self, trace: &SystemTrace, id: ReadId) -> Option<u16> {
        let ev = self.reads[id.0].0;
        trace.samples.iter().find(|s| s.0 == ev).and_then(|s| s.1).map(|v| v as u16)
    }

    // ---- register-level helpers ---------------------------------------------

    pub fn write_reg(&mut self, name: &str, axis: usize, data: u16) {
        self.write(regs::register(name).address(axis), data);
    }

    pub fn read_reg(&mut self, name: &str, axis: usize) -> ReadId {
        self.read(regs::register(name).address(axis))
    }

    /// Stages `seg` in `axis`'s registers, STEPS_HI last (the push).
    pub fn push_segment(&mut self, axis: usize, seg: &Segment) {
        let steps = seg.steps as u32;
        self.write_reg("V0_LO", axis, seg.v0_rate as u16);
        self.write_reg("V0_HI", axis, (seg.v0_rate >> 16) as u16);
        self.write_reg("T_LO", axis, seg.t_ticks as u16);
        self.write_reg("T_HI", axis, (seg.t_ticks >> 16) as u16);
        self.write_reg("STEPS_LO", axis, steps as u16);
        self.write_reg("STEPS_HI", axis, (steps >> 16) as u16);
    }

    /// Stages `m` in `axis`'s registers and pushes it: a trapezoid as
    /// [`Self::push_segment`]; a polynomial segment (a core exported with the S-curve
    /// option) with POLY_V1, POLY_A and POLY_ARM first.
    pub fn push_motion(&mut self, axis: usize, m: &crate::model::Motion) {
        match m {
            crate::model::Motion::Trapezoid(s) => self.push_segment(axis, s),
            crate::model::Motion::Poly(p) => {
                let a = p.a_q32 as u64;
                self.write_reg("POLY_V1_LO", 0, p.v1_rate as u16);
                self.write_reg("POLY_V1_HI", 0, (p.v1_rate >> 16) as u16);
                for (k, name) in ["POLY_A_0", "POLY_A_1", "POLY_A_2", "POLY_A_3"].iter().enumerate() {
                    self.write_reg(name, 0, (a >> (16 * k)) as u16);
                }
                self.write_reg("POLY_ARM", 0, 1);
                self.push_segment(axis, &crate::model::Segment::new(p.v0_rate, p.t_ticks, p.steps));
            }
        }
    }

    /// Reads the position of `axis`: POS_LO (latching the high half), then POS_HI.
    pub fn read_position(&mut self, axis: usize) -> (ReadId, ReadId) {
        (self.read_reg("POS_LO", axis), self.read_reg("POS_HI", axis))
    }

    /// Sets CTRL.ENABLE and waits `wait_cycles` HCLK cycles for the core to see it.
    pub fn enable(&mut self, wait_cycles: u64) {
        self.write_reg("CTRL", 0, 1);
        self.idle(wait_cycles);
    }
}

/// The position two reads returned.
pub fn position(bus: &BusModel, trace: &SystemTrace, ids: (ReadId, ReadId)) -> Option<i32> {
    let lo = bus.value(trace, ids.0)? as u32;
    let hi = bus.value(trace, ids.1)? as u32;
    Some((hi << 16 | lo) as i32)
}

/// `events` with more input columns (pins beside the bus, e.g. the machine I/O's):
/// `initial` before the first change, then each `(time_ps, values)` of `changes` (in
/// increasing time) from that time on. A change that falls within 3 ps of a bus event
/// is applied with that event; any other becomes an event of its own at the next time
/// ≡ 2 (mod 3), with the bus pins as they were. Returns the events and, for each of
/// `events`, its index among them (a trace's samples name events by index: map them
/// back with it before [`BusModel::value`]).
pub fn with_extra_inputs(events: &[BusEvent], initial: &[u128], changes: &[(u64, Vec<u128>)]) -> (Vec<BusEvent>, Vec<usize>) {
    assert!(changes.windows(2).all(|w| w[0].0 < w[1].0), "pin changes must be in increasing time");
    assert!(changes.iter().all(|c| c.1.len() == initial.len()), "pin change width");
    let mut out: Vec<BusEvent> = Vec::with_capacity(events.len() + changes.len());
    let mut extra = initial.to_vec();
    let bus_width = events[0].inputs.len();
    let mut k = 0;
    let mut emit_changes_before = |out: &mut Vec<BusEvent>, extra: &mut Vec<u128>, limit: u64| {
        while k < changes.len() && changes[k].0 < limit {
            let t = changes[k].0 + (2 + 3 - changes[k].0 % 3) % 3;
            *extra = changes[k].1.clone();
            k += 1;
            let last = out.last_mut().expect("the first bus event comes first");
            if t <= last.time_ps + 3 {
                // With the event just emitted.
                last.inputs.truncate(bus_width);
                last.inputs.extend(extra.iter().copied());
            } else if t + 3 < limit {
                let bus: Vec<u128> = last.inputs[..bus_width].to_vec();
                out.push(BusEvent { time_ps: t, inputs: bus.into_iter().chain(extra.iter().copied()).collect(), sample: false });
            }
            // Else it goes with the next bus event, which takes `extra` as it stands.
        }
    };
    let mut index = Vec::with_capacity(events.len());
    for e in events {
        if !out.is_empty() {
            emit_changes_before(&mut out, &mut extra, e.time_ps);
        }
        index.push(out.len());
        out.push(BusEvent { time_ps: e.time_ps, inputs: e.inputs.iter().chain(extra.iter()).copied().collect(), sample: e.sample });
    }
    emit_changes_before(&mut out, &mut extra, u64::MAX);
    (out, index)
}

/// Renames a trace's samples from the events of [`with_extra_inputs`] back to the bus
/// model's own event numbers (`index` as it returned), for [`BusModel::value`].
pub fn samples_to_bus_events(trace: &mut SystemTrace, index: &[usize]) {
    for s in trace.samples.iter_mut() {
        s.0 = index.iter().position(|&i| i == s.0).expect("a sample at a pin event");
    }
}
