//! The whole IP core (`tdm_stepper`) driven from the MCU's side: the EXMC bus model
//! at the documented minimum timing, with the MCU clock, the bus clock and the core
//! clock all unrelated. The exported Verilog runs in Verilator; shorter forms also run
//! in rust-hdl, which must give the same trace.

mod common;

use common::*;
use rust_hdl::prelude::*;
use tdm_stepper::vectors::paper_experiment_segments;
use tdm_stepper::hdl::core::t_calc_sqrt;
use tdm_stepper::hdl::top::{TdmStepper, TdmStepperEnc, TdmStepperIo};
use tdm_stepper::model::{pulse, AxisRun, Limits, PulseTiming, Segment};
use tdm_stepper::regs::{self, CoreParams};
use tdm_stepper::verify::bus::{
    position, run_stepper_io_rust_hdl, run_stepper_rust_hdl, samples_to_bus_events, stepper_watch, system_spec, BusModel, BusTiming, ReadId,
};
use tdm_stepper::verify::system::{run_system_with, Clocks, RunOptions, SystemTrace};
use tdm_stepper::verify::{Port, Simulator};

// The export's configuration.
const R: usize = tdm_stepper::export::RADIX_BITS;
const DEPTH: usize = tdm_stepper::export::FIFO_DEPTH;
const QDEPTH: usize = tdm_stepper::export::QUEUE_DEPTH;
/// clk ≈ 50 MHz, bus_clk ≈ 100 MHz, HCLK = 168 MHz: three unrelated clocks.
const CLOCKS: Clocks = Clocks { clk_half_ps: 10_002, bus_half_ps: 5_001 };
const MCU_HALF_PS: u64 = 2_976;

fn params<const K: usize>() -> CoreParams {
    CoreParams { axes: K, clock_hz: 50_000_000, queue_depth: QDEPTH, fifo_depth: DEPTH, t_calc: t_calc_sqrt(R), min_period: Limits::default().min_period_ticks, io: false, io_omit: 0, scurve: false, encoder: false }
}

fn dut<const K: usize>() -> TdmStepper<K, R, DEPTH, QDEPTH> {
    let mut u = TdmStepper::<K, R, DEPTH, QDEPTH>::new(params::<K>());
    u.connect_ports();
    u
}


fn bus() -> BusModel {
    let mut b = BusModel::new(BusTiming::minimum(CLOCKS.bus_half_ps, MCU_HALF_PS));
    b.reset(40);
    b
}

/// HCLK cycles to wait for ENABLE to reach the core and come back as ENABLED.
const ENABLE_WAIT: u64 = 400;

/// clk cycles that cover every bus event, plus `extra`.
fn cycles_after(b: &BusModel, extra: u64) -> u64 {
    b.now_ps() / (2 * CLOCKS.clk_half_ps) + extra
}

fn verilator<const K: usize>(name: &str, b: &BusModel, cycles: u64) -> SystemTrace {
    let verilog = generate_verilog(&dut::<K>());
    let opts = RunOptions { build_cache: Some(verilator_cache()), ..Default::default() };
    run_system_with(&sim_dir(name, Simulator::Verilator), &verilog, &system_spec("top", stepper_watch(K)), &CLOCKS, b.events(), cycles, &opts)
        .unwrap()
}

/// The same, on what `tdm-stepper export` writes.
fn verilator_exported<const K: usize>(name: &str, b: &BusModel, cycles: u64) -> SystemTrace {
    verilator_exported_with(name, b, cycles, tdm_stepper::export::ExportOptions { axes: K, ..Default::default() })
}

/// [`verilator_exported`] with other export options.
fn verilator_exported_with(name: &str, b: &BusModel, cycles: u64, opts: tdm_stepper::export::ExportOptions) -> SystemTrace {
    verilator_exported_probed(name, b, cycles, opts, None)
}

/// [`verilator_exported`] that also records each axis's period FIFO level (probes in
/// `trace.probes`, one value per axis).
fn verilator_exported_levels<const K: usize>(name: &str, b: &BusModel, cycles: u64) -> SystemTrace {
    let probes = (0..K).map(|a| (format!("fifo_level_{a}"), 8, format!("dut.core.bank.axes${a}$level"))).collect();
    let vcd = tdm_stepper::verify::system::VcdOptions { path: Default::default(), window_cycles: (0, cycles), probes };
    verilator_exported_probed(name, b, cycles, tdm_stepper::export::ExportOptions { axes: K, ..Default::default() }, Some(vcd))
}

/// The exported core in Verilator, with `vcd`'s probes when given.
fn verilator_exported_probed(
    name: &str,
    b: &BusModel,
    cycles: u64,
    opts: tdm_stepper::export::ExportOptions,
    vcd: Option<tdm_stepper::verify::system::VcdOptions>,
) -> SystemTrace {
    let verilog = tdm_stepper::export::verilog(&opts).unwrap();
    let spec = system_spec(tdm_stepper::export::TOP_MODULE, stepper_watch(opts.axes));
    let opts = RunOptions { pause_idle_bus_ps: Some(PAUSE_GAP_PS), vcd, build_cache: Some(verilator_cache()), ..Default::default() };
    run_system_with(&sim_dir(name, Simulator::Verilator), &verilog, &spec, &CLOCKS, b.events(), cycles, &opts).unwrap()
}

/// Bus rests longer than this pause bus_clk in the exported-core runs (for speed).
const PAUSE_GAP_PS: u64 = 1_000_000_000;

fn rust_hdl<const K: usize>(b: &BusModel, cycles: u64) -> SystemTrace {
    run_stepper_rust_hdl(&mut dut::<K>(), &CLOCKS, b.events(), cycles, &[], false)
}

/// Rising edges of axis `a` (clk cycles).
fn rises(trace: &SystemTrace, a: usize) -> Vec<u64> {
    let mut out = Vec::new();
    let mut prev = 0;
    for (c, v) in &trace.changes {
        let s = (v[0].unwrap_or(0) >> a) & 1;
        if s == 1 && prev == 0 {
            out.push(*c);
        }
        prev = s;
    }
    out
}

/// Cycles where the irq line rises and falls.
fn irq_edges(trace: &SystemTrace) -> (Vec<u64>, Vec<u64>) {
    let (mut up, mut down) = (Vec::new(), Vec::new());
    let mut prev = 0;
    for (c, v) in &trace.changes {
        let s = v[2].unwrap_or(0);
        if s == 1 && prev == 0 {
            up.push(*c);
        }
        if s == 0 && prev == 1 {
            down.push(*c);
        }
        prev = s;
    }
    (up, down)
}

/// The clk cycle in progress at bus time `ps`.
fn clk_cycle_at(ps: u64) -> u64 {
    ps / (2 * CLOCKS.clk_half_ps)
}

/// Every axis's edges are the model's, from one common release tick (0 skew), and
/// each within 1 tick of exact kinematics. Returns the release tick.
fn check_edges(trace: &SystemTrace, axes: &[Vec<Segment>], what: &str) -> i64 {
    check_edges_in(trace, axes, 0..u64::MAX, what)
}

/// [`check_edges`] for the edges in a window of clk cycles.
fn check_edges_in(trace: &SystemTrace, axes: &[Vec<Segment>], window: std::ops::Range<u64>, what: &str) -> i64 {
    let mut release = None;
    for (a, segs) in axes.iter().enumerate() {
        let run = AxisRun::run(segs, &Limits::default());
        let r: Vec<u64> = rises(trace, a).into_iter().filter(|c| window.contains(c)).collect();
        assert_eq!(r.len(), run.edge_ticks.len(), "{what}: axis {a} step count");
        let Some(&first) = r.first() else { continue };
        let l0 = first as i64 - 1 - run.edge_ticks[0] as i64;
        assert_eq!(*release.get_or_insert(l0), l0, "{what}: axis {a} released on another tick (skew)");
        for (i, (&got, &e)) in r.iter().zip(&run.edge_ticks).enumerate() {
            assert_eq!(got as i64, l0 + 1 + e as i64, "{what}: axis {a} edge {i}");
            let err = (got as i64 - l0 - 1) as f64 - run.exact_ticks[i];
            assert!(err.abs() <= 1.0, "{what}: axis {a} edge {i} is {err} ticks from exact time");
        }
    }
    release.expect("no axis moved")
}

/// Falling STEP edges and DIR changes of axis `a` (clk cycles; DIR changes with the new
/// level).
fn falls_and_dir(trace: &SystemTrace, a: usize) -> (Vec<u64>, Vec<(u64, bool)>) {
    let (mut falls, mut dirs) = (Vec::new(), Vec::new());
    let (mut ps, mut pd) = (0, 0);
    for (c, v) in &trace.changes {
        let s = (v[0].unwrap_or(0) >> a) & 1;
        let d = (v[1].unwrap_or(0) >> a) & 1;
        if s == 0 && ps == 1 {
            falls.push(*c);
        }
        if d != pd {
            dirs.push((*c, d == 1));
        }
        (ps, pd) = (s, d);
    }
    (falls, dirs)
}

/// Every falling STEP edge and DIR change of every axis is the pins model's for
/// `timing`, from the release tick `l0` that [`check_edges`] found; the narrowest high,
/// low, setup and hold meet the registers. Returns them per axis.
fn check_pins(trace: &SystemTrace, axes: &[Vec<Segment>], l0: i64, timing: &PulseTiming, what: &str) -> Vec<(u64, u64, u64, u64)> {
    let mut out = Vec::new();
    for (a, segs) in axes.iter().enumerate() {
        let run = AxisRun::run(segs, &Limits::default());
        let pins = pulse::pins(&run.fifo, timing);
        let at = |t: u64| (l0 + 1 + t as i64) as u64;
        let (falls, dirs) = falls_and_dir(trace, a);
        let want: Vec<u64> = pins.falls.iter().map(|&t| at(t)).collect();
        let k = falls.iter().zip(&want).position(|(g, w)| g != w).unwrap_or(falls.len().min(want.len()));
        assert!(
            falls == want,
            "{what}: axis {a}: {} falling edges, the model {}; first difference at {k}: {:?} against {:?} (rise {:?})",
            falls.len(),
            want.len(),
            falls.get(k),
            want.get(k),
            pins.rises.get(k).map(|&t| at(t))
        );
        let want: Vec<(u64, bool)> = pins.dir_changes.iter().map(|&(t, d)| (at(t), d)).collect();
        assert_eq!(dirs, want, "{what}: axis {a} DIR changes");
        let m = pulse::measure(&pins);
        assert!(m.0 >= timing.step_high as u64 && m.0 >= timing.dir_hold as u64, "{what}: axis {a} high {}", m.0);
        assert!(m.1 >= timing.step_low as u64 && m.1 >= timing.dir_setup as u64, "{what}: axis {a} low {}", m.1);
        assert!(m.2 >= timing.dir_setup as u64, "{what}: axis {a} DIR setup {}", m.2);
        assert!(m.3 >= timing.dir_hold as u64, "{what}: axis {a} DIR hold {}", m.3);
        out.push(m);
    }
    out
}

/// Pushes every axis's segments, lets the core take them, and starts all the axes
/// together; returns the bus time of the START write.
fn push_and_start(b: &mut BusModel, axes: &[Vec<Segment>]) -> u64 {
    for (a, segs) in axes.iter().enumerate() {
        for s in segs {
            b.push_segment(a, s);
        }
    }
    b.idle(200);
    b.write_reg("START", 0, (1 << axes.len()) - 1);
    b.now_ps()
}

fn read16(b: &BusModel, t: &SystemTrace, id: tdm_stepper::verify::bus::ReadId) -> u16 {
    b.value(t, id).expect("read returned undefined bits")
}

/// Run folders share finished simulators through `RunOptions::build_cache`: a second
/// folder with the same design runs the cached one (and builds nothing), gives the
/// same trace, and a different design builds its own.
#[test]
fn run_folders_share_a_build_of_the_same_design() {
    use tdm_stepper::verify::{system::{BusEvent, SystemSpec}, Port};
    let counter = |step: &str| {
        format!(
            "module cnt(input clk, input bus_clk, input [7:0] d, output [7:0] q, output [7:0] s);\n\
             reg [7:0] r = 0;\n  always @(posedge clk) r <= r + {step};\n  assign q = r;\n  assign s = r;\nendmodule\n"
        )
    };
    let spec = SystemSpec { module: "cnt".into(), inputs: vec![Port::new("d", 8)], watch: vec![Port::new("q", 8)], sample: Port::new("s", 8) };
    let events = [
        BusEvent { time_ps: 2, inputs: vec![1], sample: false },
        BusEvent { time_ps: 2 + 3 * 40_000, inputs: vec![3], sample: true },
    ];
    let cache = sim_dir("shared_build_cache", Simulator::Verilator);
    let dirs: Vec<_> = ["shared_build_a", "shared_build_b", "shared_build_c"].map(|n| sim_dir(n, Simulator::Verilator)).into();
    for d in dirs.iter().chain([&cache]) {
        let _ = std::fs::remove_dir_all(d);
    }
    let opts = RunOptions { build_cache: Some(cache.clone()), ..Default::default() };
    let run = |dir: &std::path::Path, v: &str| {
        std::fs::create_dir_all(dir).unwrap();
        run_system_with(dir, v, &spec, &CLOCKS, &events, 20, &opts).unwrap()
    };
    let cached = || std::fs::read_dir(&cache).unwrap().count();
    let a = run(&dirs[0], &counter("d"));
    assert!(dirs[0].join("obj_dir/Vsim").is_file(), "the first folder builds");
    assert_eq!(cached(), 1);
    let b = run(&dirs[1], &counter("d"));
    assert!(!dirs[1].join("obj_dir").exists(), "the second folder runs the cached build");
    assert_eq!(a, b);
    assert_eq!(cached(), 1);
    let c = run(&dirs[2], &counter("d + d"));
    assert!(dirs[2].join("obj_dir/Vsim").is_file(), "another design builds its own");
    assert_eq!(cached(), 2);
    assert_ne!(a.changes, c.changes, "and runs it");
}

/// The paper's experiment, written through the bus into the exported core.
#[test]
fn paper_experiment_through_the_bus_in_verilator() {
    let axes = paper_experiment_segments();
    let mut b = bus();
    let magic = b.read_reg("ID_MAGIC", 0);
    let k = b.read_reg("ID_AXES", 0);
    let before = b.read_reg("GSTATUS", 0);
    b.enable(ENABLE_WAIT);
    let enabled = b.read_reg("GSTATUS", 0);
    for (a, segs) in axes.iter().enumerate() {
        for s in segs {
            b.push_segment(a, s);
        }
    }
    // An axis not yet started takes two segments into its current and next slots
    // (setting them up and filling its period FIFO); the third waits in the queue.
    // Wait for both axes' two setups and FIFO fills, one axis after the other, and
    // the status crossing.
    let settle_clk = 2 * (2 * tdm_stepper::hdl::core::t_setup(R, true) + DEPTH * t_calc_sqrt(R)) as u64 + 500;
    let pushed_ps = b.now_ps();
    b.idle(2_000);
    b.idle_until_ps(pushed_ps + settle_clk * 2 * CLOCKS.clk_half_ps);
    let levels: Vec<_> = (0..2).map(|a| b.read_reg("STATUS", a)).collect();
    b.write_reg("START", 0, 0b11);
    let end = AxisRun::run(&axes[0], &Limits::default()).end_tick.max(AxisRun::run(&axes[1], &Limits::default()).end_tick);
    // The last pulse is half the last period (17,677 and 20,412 ticks), and BUSY holds
    // until it falls: 5,000 ticks after the last edges both axes are still busy.
    let start_ps = b.now_ps();
    b.idle_until_ps(start_ps + (end + 5_000) * 2 * CLOCKS.clk_half_ps);
    let busy_in_pulse = b.read_reg("BUSY", 0);
    b.idle_until_ps(start_ps + (end + 30_000) * 2 * CLOCKS.clk_half_ps);
    let pos: Vec<_> = (0..2).map(|a| b.read_position(a)).collect();
    let busy = b.read_reg("BUSY", 0);
    let status: Vec<_> = (0..2).map(|a| b.read_reg("STATUS", a)).collect();
    let done: Vec<_> = (0..2).map(|a| b.read_reg("DONE_COUNT", a)).collect();
    let cycles = cycles_after(&b, 200);
    let t0 = std::time::Instant::now();
    let trace = verilator_exported_levels::<2>("system_paper", &b, cycles);
    eprintln!("paper experiment through the bus: {cycles} clk cycles, Verilator build + run {:.1} s", t0.elapsed().as_secs_f64());
    assert_eq!(read16(&b, &trace, magic), regs::MAGIC);
    assert_eq!(read16(&b, &trace, k), 2);
    assert_eq!(read16(&b, &trace, before) & 1, 0, "ENABLED before ENABLE");
    assert_eq!(read16(&b, &trace, enabled) & 1, 1, "not ENABLED");
    for a in 0..2 {
        let s = read16(&b, &trace, levels[a]);
        assert_eq!(s & 0x1F, 1, "axis {a}: LEVEL after three pushes, two taken");
        assert_eq!(s & 0x20, 0x20, "axis {a}: BUSY after pushes");
        assert_eq!(s & 0xFFC0, 0, "axis {a}: flags after pushes");
    }
    let l0 = check_edges(&trace, &axes, "paper via bus");
    // PICK reads each FIFO's `full` a cycle late, so a FIFO may take one period past
    // DEPTH, never more (docs/architecture.md, "PICK decides from flip-flops").
    for a in 0..2 {
        let top = trace.probes.iter().filter_map(|(_, v)| v[a]).max().expect("FIFO level probed");
        eprintln!("axis {a}: FIFO level up to {top} (DEPTH {DEPTH})");
        assert!((DEPTH as u128..=DEPTH as u128 + 1).contains(&top), "axis {a}: FIFO level up to {top}, DEPTH {DEPTH}");
    }
    // Every falling edge and DIR change too, at the default output timing (the half period).
    check_pins(&trace, &axes, l0, &PulseTiming::default(), "paper via bus");
    assert_eq!(position(&b, &trace, pos[0]), Some(2400));
    assert_eq!(position(&b, &trace, pos[1]), Some(1800));
    assert_eq!(read16(&b, &trace, busy_in_pulse), 0b11, "BUSY during the last pulses");
    assert_eq!(read16(&b, &trace, busy), 0);
    for a in 0..2 {
        assert_eq!(read16(&b, &trace, status[a]), 0, "axis {a}: STATUS at the end");
        assert_eq!(read16(&b, &trace, done[a]), 3, "axis {a}: DONE_COUNT");
    }
}

/// The paper's experiment through the SPI pins of an `--bus spi` export, at the
/// fastest documented SCK (bus_clk/4, mode 0, CS high 4 bus clocks), with burst reads
/// of both axes' status and position while the axes move: every edge is the model's,
/// and every frame's status byte shows the pattern and no frame error.
#[test]
fn paper_experiment_through_spi_in_verilator() {
    use tdm_stepper::verify::spi::{spi_system_spec, SpiBus, SpiTiming, STATUS_PATTERN};
    let axes = paper_experiment_segments();
    let mut b = SpiBus::new(SpiTiming::fastest(0).in_ps(CLOCKS.bus_half_ps, 1));
    b.reset(40 * 2 * CLOCKS.bus_half_ps);
    let id = b.read(regs::register("ID_MAGIC").address(0), 3);
    b.write_reg("CTRL", 0, 1);
    b.idle_until_ps(b.now_ps() + 400 * 2 * CLOCKS.clk_half_ps);
    let enabled = b.read_reg("GSTATUS", 0);
    let mut frames = vec![id, enabled];
    for (a, segs) in axes.iter().enumerate() {
        for s in segs {
            frames.push(b.push_segment(a, s));
        }
    }
    let settle_clk = 2 * (2 * tdm_stepper::hdl::core::t_setup(R, true) + DEPTH * t_calc_sqrt(R)) as u64 + 500;
    b.idle_until_ps(b.now_ps() + settle_clk * 2 * CLOCKS.clk_half_ps);
    frames.push(b.write_reg("START", 0, 0b11));
    let start_ps = b.now_ps();
    let end = AxisRun::run(&axes[0], &Limits::default()).end_tick.max(AxisRun::run(&axes[1], &Limits::default()).end_tick);
    // Traffic while the axes move: STATUS, POS_LO, POS_HI, DONE_COUNT of each axis in
    // one burst, about every 40 µs.
    let mut k = 0;
    while b.now_ps() < start_ps + end * 2 * CLOCKS.clk_half_ps {
        frames.push(b.read(regs::register("STATUS").address(k % 2), 4));
        b.idle_until_ps(b.now_ps() + 40_000_000);
        k += 1;
    }
    b.idle_until_ps(start_ps + (end + 30_000) * 2 * CLOCKS.clk_half_ps);
    let last: Vec<_> = (0..2).map(|a| b.read(regs::register("STATUS").address(a), 4)).collect();
    let busy = b.read_reg("BUSY", 0);
    frames.extend(last.iter().copied());
    frames.push(busy);
    let cycles = b.now_ps() / (2 * CLOCKS.clk_half_ps) + 200;
    let opts = tdm_stepper::export::ExportOptions { axes: 2, bus: tdm_stepper::export::Bus::Spi, ..Default::default() };
    let verilog = tdm_stepper::export::verilog(&opts).unwrap();
    let spec = spi_system_spec(tdm_stepper::export::TOP_MODULE, stepper_watch(2));
    let run = RunOptions { pause_idle_bus_ps: Some(PAUSE_GAP_PS), build_cache: Some(verilator_cache()), ..Default::default() };
    let t0 = std::time::Instant::now();
    let trace = run_system_with(&sim_dir("system_paper_spi", Simulator::Verilator), &verilog, &spec, &CLOCKS, b.events(), cycles, &run).unwrap();
    eprintln!("paper experiment through SPI: {} frames during the move, {cycles} clk cycles, Verilator build + run {:.1} s", k, t0.elapsed().as_secs_f64());
    assert!(k >= 20, "only {k} frames of traffic during the move");
    for &f in &frames {
        let (st, _) = b.words(&trace, f).expect("MISO undefined");
        assert_eq!(st & 0x7f, STATUS_PATTERN, "a frame's status byte: pattern, no FRAME_ERR");
    }
    let (_, w) = b.words(&trace, id).unwrap();
    assert_eq!((w[0], w[2]), (regs::MAGIC, 2), "ID_MAGIC, ID_AXES");
    assert_eq!(b.words(&trace, enabled).unwrap().1[0] & 1, 1, "not ENABLED");
    let l0 = check_edges(&trace, &axes, "paper via SPI");
    check_pins(&trace, &axes, l0, &PulseTiming::default(), "paper via SPI");
    let want_pos = [2400i32, 1800];
    for a in 0..2 {
        let (_, w) = b.words(&trace, last[a]).unwrap();
        assert_eq!(w[0], 0, "axis {a}: STATUS at the end");
        assert_eq!(w[1] as u32 | (w[2] as u32) << 16, want_pos[a] as u32, "axis {a}: position");
        assert_eq!(w[3], 3, "axis {a}: DONE_COUNT");
    }
    assert_eq!(b.words(&trace, busy).unwrap().1[0], 0, "BUSY at the end");
}

const STATUS_UNDERRUN: u16 = 1 << 6;
const STATUS_OVERFLOW: u16 = 1 << 7;
const STATUS_ERROR: u16 = 1 << 8;

/// A uniform segment: `n` steps in `t` ticks from rest-speed n/t.
fn uniform(t: u32, n: i32) -> Segment {
    Segment::new((((n.unsigned_abs() as u64) << 32) / t as u64) as u32, t, n)
}

/// Bad input through the bus: every kind of invalid segment is rejected with its
/// code on an idle axis; invalid segments between valid ones on a moving axis leave
/// the valid ones exact; a push to a full queue is refused with OVERFLOW and nothing
/// queued is lost; unknown addresses read 0 and ignore writes; a cut-off write does
/// not change its register.
#[test]
fn bad_input_through_the_bus_is_refused_and_loses_nothing() {
    let limits = Limits::default();
    let bad = [
        Segment::new(0, 0, 5),
        Segment::new(1 << 28, 1000, 1),
        Segment::new(0, 1000, 600),
        Segment::new(0, (1 << 30) + 1, 5),
        Segment::new(0, 1 << 29, (1 << 24) + 1),
        Segment::new(0x8000_0000, 1000, 1),
    ];
    let codes: Vec<u16> = bad.iter().map(|s| s.validate(&limits).unwrap_err().code() as u16).collect();
    assert_eq!(codes, vec![1, 2, 3, 4, 5, 6], "one bad segment per error code");
    let mut b = bus();
    b.enable(ENABLE_WAIT);
    // Unknown addresses read 0, before and after a write to them.
    let unknown: Vec<u16> = vec![0x01B, 0x0FF, 0x10A, 0x10F, 0x120, 0x1FF];
    for &a in &unknown {
        b.write(a, 0xFFFF);
    }
    let unknown_reads: Vec<_> = unknown.iter().map(|&a| b.read(a)).collect();
    // Each bad segment on idle axis 1: STATUS shows ERROR and the code; W1C clears both.
    let mut per_code = Vec::new();
    for s in &bad {
        b.push_segment(1, s);
        b.idle(400);
        let seen = b.read_reg("STATUS", 1);
        b.write_reg("STATUS", 1, STATUS_ERROR);
        let cleared = b.read_reg("STATUS", 1);
        per_code.push((seen, cleared));
    }
    // A cut-off write (NWE low for one HCLK, under one bus clock) changes nothing.
    // Five tries at different phases of bus_clk; the data pins held another value
    // before each, so a commit of any sample would show.
    b.write_reg("V0_LO", 1, 0x1234);
    for k in 0..5 {
        b.write_reg("T_LO", 1, 0x5555 + k);
        b.idle(1 + k as u64);
        b.write_with_low(regs::addr("V0_LO") + regs::AXIS_STRIDE, 0xBEEF, 1);
    }
    let v0_after_cut = b.read_reg("V0_LO", 1);
    // Axis 0: valid and invalid segments interleaved.
    let axis0 = vec![
        Segment::new(0, 20_000, 40),
        bad[1],
        uniform(10_000, 25),
        bad[0],
        Segment::dwell(3_000),
        bad[2],
        Segment::new(((25u64 << 32) / 10_000) as u32, 20_000, 25),
    ];
    for s in &axis0 {
        b.push_segment(0, s);
    }
    // Axis 1: push past its capacity. An axis not yet started holds QDEPTH + 2
    // segments: its current and next slots (the scheduler takes those at once) and
    // QDEPTH in the queue; later pushes are refused. Each segment has more steps than
    // the period FIFO has entries, so the first is not computed whole into the FIFO
    // before the start (which would free its slot for one more push).
    let small: Vec<Segment> = (0..QDEPTH as i32 + 4).map(|k| uniform(2_000, DEPTH as i32 + 1 + k)).collect();
    for s in &small {
        b.push_segment(1, s);
        b.idle(100);
    }
    let full_status = b.read_reg("STATUS", 1);
    b.write_reg("START", 0, 0b11);
    let run0 = AxisRun::run(&axis0, &limits);
    let accepted1 = &small[..QDEPTH + 2];
    let run1 = AxisRun::run(accepted1, &limits);
    b.idle_until_ps(b.now_ps() + (run0.end_tick.max(run1.end_tick) + 3_000) * 2 * CLOCKS.clk_half_ps);
    let end_status: Vec<_> = (0..2).map(|a| b.read_reg("STATUS", a)).collect();
    let pos: Vec<_> = (0..2).map(|a| b.read_position(a)).collect();
    let ctrl = b.read_reg("CTRL", 0);
    let cycles = cycles_after(&b, 200);
    let trace = verilator::<2>("system_bad_input", &b, cycles);

    for (k, r) in unknown_reads.iter().enumerate() {
        assert_eq!(read16(&b, &trace, *r), 0, "unknown address {:#x} read non-zero", unknown[k]);
    }
    for (k, (seen, cleared)) in per_code.iter().enumerate() {
        let v = read16(&b, &trace, *seen);
        assert_eq!(v & STATUS_ERROR, STATUS_ERROR, "bad segment {k}: no ERROR flag ({v:#06x})");
        assert_eq!(v >> 12, codes[k], "bad segment {k}: ERROR_CODE ({v:#06x})");
        assert_eq!(read16(&b, &trace, *cleared) & 0xF100, 0, "bad segment {k}: W1C did not clear ERROR and its code");
    }
    assert_eq!(read16(&b, &trace, v0_after_cut), 0x1234, "a cut-off write changed V0_LO");
    let fs = read16(&b, &trace, full_status);
    assert_eq!(fs & STATUS_OVERFLOW, STATUS_OVERFLOW, "no OVERFLOW after pushing past the queue ({fs:#06x})");
    assert_eq!((fs & 0x1F) as usize, QDEPTH, "LEVEL of a full queue ({fs:#06x})");
    // Both axes ran exactly what was accepted, from one release.
    check_edges(&trace, &[axis0.clone(), accepted1.to_vec()], "bad input");
    let s0 = read16(&b, &trace, end_status[0]);
    assert_eq!(s0 & STATUS_ERROR, STATUS_ERROR, "axis 0: rejections not flagged");
    assert_eq!(s0 >> 12, run0.rejected.last().unwrap().error.code() as u16, "axis 0: last error code");
    assert_eq!(s0 & 0x3F, 0, "axis 0: LEVEL/BUSY at the end");
    let s1 = read16(&b, &trace, end_status[1]);
    assert_eq!(s1 & (STATUS_OVERFLOW | 0x3F), STATUS_OVERFLOW, "axis 1: OVERFLOW is sticky, queue empty at the end");
    assert_eq!(position(&b, &trace, pos[0]), Some(run0.position as i32));
    assert_eq!(position(&b, &trace, pos[1]), Some(run1.position as i32));
    assert_eq!(read16(&b, &trace, ctrl), 1, "a write to an unknown address changed CTRL");
}

/// Interrupts, random bus traffic during motion, and abort, through the bus:
/// * an error event on a masked axis raises irq; W1C of IRQ_ERROR lowers it;
/// * seeded random reads and writes to every harmless register and unknown address,
///   interleaved with a two-axis move, never disturb it (edges exact, 0 skew);
/// * a masked segment-done event raises irq after that segment's last edge;
/// * ABORT stops every axis at once: no edge after it, position equal to the edges
///   emitted, queues empty; a new move then runs exactly from there.
#[test]
fn interrupts_random_traffic_and_abort_through_the_bus() {
    let limits = Limits::default();
    let tick_ps = 2 * CLOCKS.clk_half_ps;
    let mut b = bus();
    b.enable(ENABLE_WAIT);

    // Phase 1: error interrupt.
    b.write_reg("IRQ_MASK_ERROR", 0, 0b01);
    let p1_push = b.now_ps();
    b.push_segment(0, &Segment::new(0, 0, 5));
    b.idle(400);
    let irq_err = b.read_reg("IRQ_ERROR", 0);
    let gstatus = b.read_reg("GSTATUS", 0);
    let p1_clear = b.now_ps();
    b.write_reg("IRQ_ERROR", 0, 0xFFFF);
    b.write_reg("STATUS", 0, STATUS_ERROR);
    let irq_err_after = b.read_reg("IRQ_ERROR", 0);
    b.write_reg("IRQ_MASK_ERROR", 0, 0);
    let p1_end = b.now_ps();

    // Phase 2: a two-axis move with random harmless traffic.
    let move2 = vec![
        tdm_stepper::model::planner::trapezoid_by_ticks(300, [20_000, 20_000, 20_000], &limits).unwrap(),
        tdm_stepper::model::planner::trapezoid_by_ticks(-200, [15_000, 30_000, 15_000], &limits).unwrap(),
    ];
    for (a, segs) in move2.iter().enumerate() {
        for s in segs {
            b.push_segment(a, s);
        }
    }
    b.write_reg("START", 0, 0b11);
    let p2_start = b.now_ps();
    let end2 = move2.iter().map(|s| AxisRun::run(s, &limits).end_tick).max().unwrap();
    let harmless = ["IRQ_MASK_DONE", "IRQ_MASK_QLOW", "QLOW_LEVEL", "IRQ_DONE", "IRQ_QLOW", "IRQ_ERROR", "GSTATUS"];
    let staging = ["V0_LO", "V0_HI", "T_LO", "T_HI", "STEPS_LO", "STATUS"];
    let mut rng = Rng(0x5eed_b0b5);
    let mut traffic = 0;
    while b.now_ps() < p2_start + (end2 + 2_000) * tick_ps {
        let r = rng.next();
        match r % 4 {
            0 => {
                b.read((r >> 8) as u16 % 0x200);
            }
            1 => b.write_reg(harmless[(r >> 8) as usize % harmless.len()], 0, (r >> 20) as u16),
            2 => b.write_reg(staging[(r >> 8) as usize % staging.len()], (r >> 16) as usize % 2, (r >> 20) as u16),
            _ => {
                // An unknown address: a global gap or an unused axis offset.
                let a = if r & 0x100 != 0 { 0x1B + (r >> 20) as u16 % 0xE5 } else { 0x10A + (r >> 20) as u16 % 6 };
                b.write(a, (r >> 32) as u16);
            }
        }
        traffic += 1;
    }
    b.write_reg("IRQ_MASK_DONE", 0, 0);
    b.write_reg("IRQ_MASK_QLOW", 0, 0);
    b.write_reg("IRQ_DONE", 0, 0xFFFF);
    b.write_reg("IRQ_QLOW", 0, 0xFFFF);
    b.write_reg("IRQ_ERROR", 0, 0xFFFF);
    let pos2: Vec<_> = (0..2).map(|a| b.read_position(a)).collect();
    let p2_end = b.now_ps();

    // Phase 3: segment-done interrupt on axis 0, and its queue-low event (QLOW_LEVEL
    // 0: the scheduler takes both segments into the axis's slots, LEVEL falls to 0).
    b.write_reg("IRQ_MASK_DONE", 0, 0b01);
    b.write_reg("QLOW_LEVEL", 0, 0);
    b.write_reg("IRQ_QLOW", 0, 0xFFFF);
    let qlow_before = b.read_reg("IRQ_QLOW", 0);
    let move3 = vec![Segment::new(0, 10_000, 20), uniform(10_000, 20)];
    for s in &move3 {
        b.push_segment(0, s);
    }
    // Two setups (about 170–200 cycles each at R = 2), the period FIFO filled between
    // them, then the status crossing: well inside 12 µs.
    b.idle(2_000);
    let qlow_after = b.read_reg("IRQ_QLOW", 0);
    b.write_reg("START", 0, 0b01);
    let p3_start = b.now_ps();
    b.idle_until_ps(p3_start + 25_000 * tick_ps);
    let irq_done = b.read_reg("IRQ_DONE", 0);
    b.write_reg("IRQ_DONE", 0, 0b01);
    b.write_reg("IRQ_MASK_DONE", 0, 0);
    let p3_end = b.now_ps();

    // Phase 4: abort a long move part way, then a new move.
    let long = vec![uniform(400_000, 800), uniform(400_000, 800)];
    for s in &long {
        b.push_segment(1, s);
    }
    b.push_segment(0, &uniform(800_000, 1000));
    b.write_reg("START", 0, 0b11);
    b.idle(b.cycles_for_ps(150_000 * tick_ps));
    let p4_abort = b.now_ps();
    b.write_reg("ABORT", 0, 1);
    // BUSY stays set until the pulse in flight (250 of the 500-tick period) has fallen.
    b.idle_until_ps(b.now_ps() + 400 * tick_ps);
    let after_abort: Vec<_> = (0..2).map(|a| b.read_reg("STATUS", a)).collect();
    let busy_after = b.read_reg("BUSY", 0);
    let pos4: Vec<_> = (0..2).map(|a| b.read_position(a)).collect();
    let move5 = vec![vec![Segment::new(0, 20_000, -30)], vec![Segment::new(0, 20_000, 30)]];
    for (a, segs) in move5.iter().enumerate() {
        b.push_segment(a, &segs[0]);
    }
    b.write_reg("START", 0, 0b11);
    let p5_start = b.now_ps();
    b.idle_until_ps(p5_start + 25_000 * tick_ps);
    let pos5: Vec<_> = (0..2).map(|a| b.read_position(a)).collect();
    let cycles = cycles_after(&b, 200);
    let trace = verilator::<2>("system_irq_abort", &b, cycles);

    // Phase 1.
    let (up, down) = irq_edges(&trace);
    assert_eq!(read16(&b, &trace, irq_err), 0b01, "IRQ_ERROR after a rejected segment");
    assert_eq!(read16(&b, &trace, gstatus) & 0b100, 0b100, "GSTATUS.IRQ");
    assert_eq!(read16(&b, &trace, irq_err_after), 0, "IRQ_ERROR after W1C");
    let in_range = |v: &[u64], from: u64, to: u64| v.iter().filter(|&&c| c >= clk_cycle_at(from) && c < clk_cycle_at(to)).count();
    assert_eq!(in_range(&up, p1_push, p1_clear), 1, "irq did not rise on the error event");
    assert_eq!(in_range(&down, p1_clear, p1_end), 1, "irq did not fall after W1C");

    // Phase 2.
    assert!(traffic > 500, "too little random traffic ({traffic} accesses)");
    check_edges_in(&trace, &move2, clk_cycle_at(p2_start)..clk_cycle_at(p2_end), "random traffic");
    assert_eq!(position(&b, &trace, pos2[0]), Some(300));
    assert_eq!(position(&b, &trace, pos2[1]), Some(-200));
    assert_eq!(in_range(&up, p2_end, p3_start), 0, "irq rose with every mask and event cleared");

    // Phase 3: irq rises after the first segment's last edge, within the status latency.
    let r0: Vec<u64> = rises(&trace, 0).into_iter().filter(|&c| c >= clk_cycle_at(p3_start) && c < clk_cycle_at(p3_end)).collect();
    assert_eq!(r0.len(), 40, "phase 3 steps");
    let first_done = r0[19];
    let irq3: Vec<u64> = up.iter().copied().filter(|&c| c >= clk_cycle_at(p3_start) && c < clk_cycle_at(p3_end)).collect();
    assert_eq!(irq3.len(), 1, "phase 3: irq rises once (then stays high until cleared)");
    assert!(irq3[0] > first_done && irq3[0] <= first_done + 100, "irq at {} for a segment done at {first_done}", irq3[0]);
    assert_eq!(read16(&b, &trace, irq_done), 0b01, "IRQ_DONE");
    assert_eq!(read16(&b, &trace, qlow_before), 0, "IRQ_QLOW after W1C");
    assert_eq!(read16(&b, &trace, qlow_after), 0b01, "IRQ_QLOW when axis 0's queue emptied");

    // Phase 4: no edge after the abort's commit (plus the crossing), exact positions.
    let abort_cycle = clk_cycle_at(p4_abort + 2 * 2 * MCU_HALF_PS * (b.timing.addset + b.timing.datast_write)) + 40;
    for a in 0..2 {
        let before: Vec<u64> = rises(&trace, a).into_iter().filter(|&c| c >= clk_cycle_at(p3_end) && c < clk_cycle_at(p5_start)).collect();
        assert!(!before.is_empty(), "axis {a}: no motion before the abort");
        assert!(*before.last().unwrap() <= abort_cycle, "axis {a}: edge at {} after the abort (~{abort_cycle})", before.last().unwrap());
        let base = if a == 0 { 300 + 40 } else { -200 };
        assert_eq!(position(&b, &trace, pos4[a]), Some(base + before.len() as i32), "axis {a}: position after abort");
        let st = read16(&b, &trace, after_abort[a]);
        assert_eq!(st & 0x3F, 0, "axis {a}: LEVEL/BUSY after abort ({st:#06x})");
        assert_eq!(position(&b, &trace, pos5[a]), Some(base + before.len() as i32 + move5[a][0].steps), "axis {a}: after the new move");
    }
    assert_eq!(read16(&b, &trace, busy_after), 0, "BUSY after abort");
    check_edges_in(&trace, &move5, clk_cycle_at(p5_start)..u64::MAX, "after abort");
}

/// A short two-axis move through the bus in rust-hdl and in Verilator: the same
/// trace (STEP, DIR, irq and every read), and the model's edges.
/// An axis asked for periods shorter than the shared unit can serve underruns: its
/// STATUS.UNDERRUN and IRQ_ERROR bit set and irq rises, no step is lost and no period
/// is shortened; an axis within K·t_calc at the same time is untouched. W1C clears it.
#[test]
fn underrun_is_flagged_on_the_late_axis_only_and_loses_no_step() {
    let tick_ps = 2 * CLOCKS.clk_half_ps;
    let min_period = 2 * t_calc_sqrt(R) as u32; // K·t_calc for K = 2
    // A period far below K·t_calc, and one half again above it.
    let (fast, slow) = (10u32, min_period + min_period / 2);
    assert!(fast < min_period && slow >= min_period);
    let (n0, n1) = (200i32, 100i32);
    let mut b = bus();
    b.enable(ENABLE_WAIT);
    b.write_reg("IRQ_MASK_ERROR", 0, 0b01);
    b.push_segment(0, &uniform(fast * n0 as u32, n0));
    b.push_segment(1, &uniform(slow * n1 as u32, n1));
    b.write_reg("START", 0, 0b11);
    let start = b.now_ps();
    b.idle_until_ps(start + 12_000 * tick_ps);
    let status = [b.read_reg("STATUS", 0), b.read_reg("STATUS", 1)];
    let irq_err = b.read_reg("IRQ_ERROR", 0);
    let pos: Vec<_> = (0..2).map(|a| b.read_position(a)).collect();
    let cleared_at = b.now_ps();
    b.write_reg("STATUS", 0, STATUS_UNDERRUN);
    b.write_reg("IRQ_ERROR", 0, 0xFFFF);
    b.idle(200);
    let status_after = b.read_reg("STATUS", 0);
    let irq_err_after = b.read_reg("IRQ_ERROR", 0);
    // Exported with the floor as its minimum period, so that the core accepts periods
    // it cannot sustain (the default export rejects them: see the next test).
    let opts = tdm_stepper::export::ExportOptions { axes: 2, min_period: Some(2), ..Default::default() };
    let trace = verilator_exported_with("system_underrun", &b, cycles_after(&b, 50), opts);

    assert_eq!(read16(&b, &trace, status[0]) & (STATUS_UNDERRUN | STATUS_OVERFLOW | STATUS_ERROR), STATUS_UNDERRUN, "axis 0 STATUS");
    assert_eq!(read16(&b, &trace, status[0]) & 0x3F, 0, "axis 0: LEVEL and BUSY read 0 at the end");
    assert_eq!(read16(&b, &trace, status[1]), 0, "axis 1 (periods ≥ K·t_calc) STATUS");
    assert_eq!(read16(&b, &trace, irq_err), 0b01, "IRQ_ERROR names axis 0 only");
    assert_eq!(position(&b, &trace, pos[0]), Some(n0));
    assert_eq!(position(&b, &trace, pos[1]), Some(n1));
    assert_eq!(read16(&b, &trace, status_after), 0, "W1C clears UNDERRUN");
    assert_eq!(read16(&b, &trace, irq_err_after), 0);
    let (up, down) = irq_edges(&trace);
    assert_eq!((up.len(), down.len()), (1, 1), "irq rises once and falls after the W1C");
    assert!(down[0] >= clk_cycle_at(cleared_at), "irq falls only after the clear");
    for (a, n, period) in [(0, n0, fast), (1, n1, slow)] {
        let r = rises(&trace, a);
        assert_eq!(r.len(), n as usize, "axis {a}: every step emitted");
        let gaps: Vec<u64> = r.windows(2).map(|w| w[1] - w[0]).collect();
        assert!(gaps.iter().all(|&g| g >= period as u64), "axis {a}: a period was shortened: {gaps:?}");
        if a == 1 {
            assert!(gaps.iter().all(|&g| g == period as u64), "axis 1 must be exact: {gaps:?}");
        } else {
            assert!(gaps.iter().any(|&g| g > period as u64), "axis 0 never ran late: the test does not test underrun");
        }
    }
}

/// The minimum period chosen at export is the one the core enforces: the identity
/// registers report it and RMAX; a segment whose start rate is one above RMAX is
/// rejected with code 3 (and nothing moves); two axes that accelerate to RMAX and
/// cruise there run at once without underrun, every period at least the minimum and
/// every edge the model's.
#[test]
fn the_exported_minimum_period_is_enforced_and_sustained() {
    let opts = tdm_stepper::export::ExportOptions { axes: 2, ..Default::default() };
    let limits = opts.limits();
    let min_period = opts.min_period_ticks() as u32;
    assert_eq!(min_period, 2 * t_calc_sqrt(R) as u32, "the default is K·t_calc");
    let rmax = limits.max_rate();
    assert_eq!(rmax as u64, (1u64 << 32) / (min_period as u64 + 1));
    // Just too fast: v0 = RMAX + 1, cruising (v_end = v0).
    let t_bad = 9_000u32;
    let too_fast = Segment::new(rmax + 1, t_bad, (((rmax as u64 + 1) * t_bad as u64) >> 32) as i32);
    assert_eq!(too_fast.validate(&limits).unwrap_err().code(), 3);
    // From rest to RMAX (v_end = 2n/T ≤ RMAX), then on at RMAX (n steps in just over n
    // periods of 2^32/RMAX ticks): every exact period ≥ min_period + 1.
    let n1 = 150i32;
    let t1 = (((2 * n1 as u64) << 32).div_ceil(rmax as u64)) as u32;
    let n2 = 300i32;
    let t2 = (((n2 as u64) << 32).div_ceil(rmax as u64)) as u32;
    let fast = vec![Segment::new(0, t1, n1), Segment::new(rmax, t2, n2)];
    for s in &fast {
        s.validate(&limits).unwrap_or_else(|e| panic!("{s:?} is valid at RMAX: {e:?}"));
    }
    let mut b = bus();
    b.enable(ENABLE_WAIT);
    let ids: Vec<_> = ["ID_MIN_PERIOD", "ID_MAX_RATE_LO", "ID_MAX_RATE_HI"].iter().map(|r| b.read_reg(r, 0)).collect();
    b.push_segment(0, &too_fast);
    b.idle(400);
    let rejected = b.read_reg("STATUS", 0);
    b.write_reg("STATUS", 0, STATUS_ERROR);
    let start = push_and_start(&mut b, &[fast.clone(), fast.clone()]);
    b.idle_until_ps(start + (t1 + t2 + 2_000) as u64 * 2 * CLOCKS.clk_half_ps);
    let status: Vec<_> = (0..2).map(|a| b.read_reg("STATUS", a)).collect();
    let pos: Vec<_> = (0..2).map(|a| b.read_position(a)).collect();
    let trace = verilator_exported::<2>("system_min_period", &b, cycles_after(&b, 50));

    let got: Vec<u16> = ids.iter().map(|&id| read16(&b, &trace, id)).collect();
    assert_eq!(got, vec![min_period as u16, rmax as u16, (rmax >> 16) as u16], "ID_MIN_PERIOD, ID_MAX_RATE");
    let r = read16(&b, &trace, rejected);
    assert_eq!(r & STATUS_ERROR, STATUS_ERROR, "v0 = RMAX + 1 is rejected: STATUS {r:#06x}");
    assert_eq!(r >> 12, 3, "with code 3 (period too short)");
    for a in 0..2 {
        let st = read16(&b, &trace, status[a]);
        assert_eq!(st & (STATUS_UNDERRUN | STATUS_OVERFLOW | STATUS_ERROR), 0, "axis {a} at RMAX: STATUS {st:#06x}");
        assert_eq!(position(&b, &trace, pos[a]), Some(n1 + n2), "axis {a} position");
        let gaps: Vec<u64> = rises(&trace, a).windows(2).map(|w| w[1] - w[0]).collect();
        let shortest = *gaps.iter().min().unwrap();
        assert!(shortest >= min_period as u64, "axis {a}: a period of {shortest} < {min_period} ticks");
        assert!(shortest <= min_period as u64 + 1, "axis {a}: the test does not reach RMAX (shortest period {shortest})");
    }
    check_edges(&trace, &[fast.clone(), fast], "at RMAX");
}

/// "Accelerate, then decelerate to rest", computed in steps/s as a user does: 0 to
/// 120,000 steps/s over 1,200 steps in 20 ms, then back to rest. The stop's v0 rounds
/// up (rate 10,307,922) past the rest value; the exported core accepts it and emits
/// exactly 2,400 steps in 40 ms, edge for edge the model's, on both axes (one reversed).
#[test]
fn decelerate_to_rest_in_steps_per_s_runs_through_the_bus() {
    let f = 50_000_000;
    let v_top = tdm_stepper::model::units::steps_per_s_to_rate(120_000.0, f).unwrap();
    let t = tdm_stepper::model::units::seconds_to_ticks(0.02, f).unwrap();
    let pair = |sign: i32| vec![Segment::new(0, t, sign * 1200), Segment::new(v_top, t, sign * 1200)];
    let axes = vec![pair(1), pair(-1)];
    assert!(axes[0][1].rounds_past_rest(), "the stop segment rounds past rest");
    let limits = tdm_stepper::export::ExportOptions::default().limits();
    for s in axes.iter().flatten() {
        assert_eq!(s.validate(&limits), Ok(()));
    }
    let mut b = bus();
    b.enable(ENABLE_WAIT);
    let start = push_and_start(&mut b, &axes);
    b.idle_until_ps(start + (2 * t as u64 + 2_000) * 2 * CLOCKS.clk_half_ps);
    let status: Vec<_> = (0..2).map(|a| b.read_reg("STATUS", a)).collect();
    let pos: Vec<_> = (0..2).map(|a| b.read_position(a)).collect();
    let trace = verilator_exported::<2>("system_decel_to_rest", &b, cycles_after(&b, 50));
    for a in 0..2 {
        assert_eq!(read16(&b, &trace, status[a]) & (STATUS_UNDERRUN | STATUS_OVERFLOW | STATUS_ERROR), 0, "axis {a} STATUS");
        assert_eq!(position(&b, &trace, pos[a]), Some(if a == 0 { 2400 } else { -2400 }), "axis {a} position");
    }
    check_edges(&trace, &axes, "decelerate to rest");
}

#[test]
fn short_move_through_the_bus_rust_hdl_equals_verilator() {
    let limits = Limits::default();
    let axes = vec![
        tdm_stepper::model::planner::trapezoid_by_ticks(60, [4_000, 2_000, 4_000], &limits).unwrap(),
        tdm_stepper::model::planner::trapezoid_by_ticks(-45, [3_000, 4_000, 3_000], &limits).unwrap(),
    ];
    let mut b = bus();
    let magic = b.read_reg("ID_MAGIC", 0);
    b.enable(ENABLE_WAIT);
    b.write_reg("IRQ_MASK_DONE", 0, 0b10);
    for (a, segs) in axes.iter().enumerate() {
        for s in segs {
            b.push_segment(a, s);
        }
    }
    b.write_reg("START", 0, 0b11);
    let start = b.now_ps();
    b.idle_until_ps(start + 11_000 * 2 * CLOCKS.clk_half_ps);
    let pos: Vec<_> = (0..2).map(|a| b.read_position(a)).collect();
    let cycles = cycles_after(&b, 50);
    let t0 = std::time::Instant::now();
    let reference = rust_hdl::<2>(&b, cycles);
    eprintln!("rust-hdl: {cycles} clk cycles of the whole system in {:.1} s", t0.elapsed().as_secs_f64());
    let trace = verilator::<2>("system_short", &b, cycles);
    assert_eq!(read16(&b, &reference, magic), regs::MAGIC);
    assert_eq!(position(&b, &reference, pos[0]), Some(60));
    assert_eq!(position(&b, &reference, pos[1]), Some(-45));
    check_edges(&reference, &axes, "rust-hdl");
    let strip = |t: &SystemTrace| -> SystemTrace {
        // Before reset reaches every register, Verilator's zeros and rust-hdl's
        // defaults may differ; compare from the first clk cycle after reset.
        let from = clk_cycle_at(b.events()[2].time_ps) + 10;
        SystemTrace { changes: t.changes.iter().filter(|c| c.0 >= from).cloned().collect(), samples: t.samples.clone(), probes: vec![] }
    };
    assert_eq!(strip(&reference), strip(&trace), "rust-hdl and Verilator traces differ");
    assert!(irq_edges(&trace).0.len() == 1, "masked done events of axis 1 raise irq once");
}

/// The register file's memories (staging and mirror in LUT RAM, addressed by axis),
/// K = 4 in rust-hdl and in Verilator: every staging half-word and the mirror's
/// POS and DONE_COUNT read 0 after reset (also after a second reset, with the
/// memories still holding the words of before), a half-word reads back what was written to
/// its own axis (writes interleaved over the axes, one half-word left unwritten), and
/// pushes whose half-words were written axis by axis, interleaved, move each axis by
/// its own segment, edge for edge as the model says.
#[test]
fn staging_and_mirror_memories_hold_each_axis_apart() {
    const K: usize = 4;
    let staging = ["V0_LO", "V0_HI", "T_LO", "T_HI", "STEPS_LO", "STEPS_HI"];
    let value = |a: usize, j: usize| 0x1011u16 + 0x1000 * a as u16 + 0x100 * j as u16;
    let skipped = (3usize, 1usize); // axis 3's V0_HI stays unwritten.
    let mut b = bus();
    let mut at_reset = Vec::new();
    for a in 0..K {
        for name in staging.iter().chain(["POS_LO", "POS_HI", "DONE_COUNT"].iter()) {
            at_reset.push((a, *name, b.read_reg(name, a)));
        }
    }
    // Before ENABLE a STEPS_HI write is refused as a push but still stored.
    for j in 0..staging.len() {
        for a in 0..K {
            if (a, j) != skipped {
                b.write_reg(staging[j], a, value(a, j));
            }
        }
    }
    let mut back = Vec::new();
    for a in (0..K).rev() {
        for (j, name) in staging.iter().enumerate() {
            back.push((a, j, b.read_reg(name, a)));
        }
    }
    // Pushes, each half-word written for every axis before the next half-word.
    b.enable(ENABLE_WAIT);
    let segs: Vec<Segment> = (0..K).map(|a| uniform(3_000 + 500 * a as u32, [7, -11, 13, -17][a])).collect();
    for j in 0..staging.len() {
        for (a, s) in segs.iter().enumerate() {
            let words = [s.v0_rate as u16, (s.v0_rate >> 16) as u16, s.t_ticks as u16, (s.t_ticks >> 16) as u16, s.steps as u16, ((s.steps as u32) >> 16) as u16];
            b.write_reg(staging[j], a, words[j]);
        }
    }
    b.write_reg("START", 0, 0b1111);
    let start = b.now_ps();
    b.idle_until_ps(start + 6_000 * 2 * CLOCKS.clk_half_ps);
    let pos: Vec<_> = (0..K).map(|a| b.read_position(a)).collect();
    let done: Vec<_> = (0..K).map(|a| b.read_reg("DONE_COUNT", a)).collect();
    // A second reset: the memories keep their words, the registers read 0 again.
    b.reset(40);
    for a in 0..K {
        for name in staging.iter().chain(["POS_LO", "POS_HI", "DONE_COUNT"].iter()) {
            at_reset.push((a, *name, b.read_reg(name, a)));
        }
    }
    let cycles = cycles_after(&b, 50);
    let reference = rust_hdl::<K>(&b, cycles);
    let trace = verilator::<K>("system_regfile_memories", &b, cycles);
    for (what, t) in [("rust-hdl", &reference), ("Verilator", &trace)] {
        for &(a, name, id) in &at_reset {
            assert_eq!(read16(&b, t, id), 0, "{what}: axis {a} {name} after reset");
        }
        for &(a, j, id) in &back {
            let want = if (a, j) == skipped { 0 } else { value(a, j) };
            assert_eq!(read16(&b, t, id), want, "{what}: axis {a} {} read back", staging[j]);
        }
        let axes: Vec<Vec<Segment>> = segs.iter().map(|s| vec![*s]).collect();
        check_edges(t, &axes, what);
        for a in 0..K {
            assert_eq!(position(&b, t, pos[a]), Some(segs[a].steps), "{what}: axis {a} position");
            assert_eq!(read16(&b, t, done[a]), 1, "{what}: axis {a} DONE_COUNT");
        }
    }
}

/// A deterministic list of valid segments at the export's limits: uniform, accelerating
/// and decelerating, both directions, and dwells, each 2,000..20,000 ticks.
fn random_segments(seed: u64, count: usize, limits: &Limits) -> Vec<Segment> {
    let mut x = seed | 1;
    let mut next = move || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        x
    };
    let rmax = limits.max_rate() as u128;
    let mut out = Vec::new();
    while out.len() < count {
        let t = 2_000 + next() % 18_000;
        if next() % 6 == 0 {
            out.push(Segment::dwell(t as u32));
            continue;
        }
        let v0 = (next() as u128) % (rmax + 1);
        // n with 0 ≤ v_end = 2n/T − v0 ≤ RMAX: n in [v0·T/2, (v0 + RMAX)·T/2] / 2^32.
        let lo = (v0 * t as u128).div_ceil(2 << 32);
        let hi = ((v0 + rmax) * t as u128) / (2 << 32);
        if hi < lo.max(1) {
            continue;
        }
        let n = (lo.max(1) + (next() as u128) % (hi - lo.max(1) + 1)) as i32;
        let seg = Segment::new(v0 as u32, t as u32, if next() % 2 == 0 { n } else { -n });
        if seg.validate(limits).is_ok() {
            out.push(seg);
        }
    }
    out
}

/// The output timing registers through the bus: a set that does not fit the minimum
/// period makes CTRL.ENABLE = 1 refused; a fitting set (DIR hold and setup the larger,
/// max(H, D) + max(L, S) = 42 of the 44-tick minimum) is taken; a write while enabled
/// is refused and changes nothing. Then axis 0 reverses at the top rate (cruise at RMAX
/// forward, then at RMAX backward) and axis 1 runs random segments: every rise, fall
/// and DIR change is the pins model's, none narrower than the registers. Finally
/// CTRL.ENABLE = 0 in the middle of a pulse: the pulse keeps its whole high time.
#[test]
fn output_timing_registers_hold_on_the_pins_through_the_bus() {
    let limits = tdm_stepper::export::ExportOptions::default().limits();
    let m = limits.min_period_ticks;
    let rmax = limits.max_rate();
    let timing = PulseTiming { step_high: 10, step_low: 8, dir_setup: 20, dir_hold: 22 };
    assert_eq!(timing.check(&limits), Ok(()));
    assert!(timing.high_min() + timing.low_min() + 2 >= m, "the test should sit at the limit");
    let too_wide = PulseTiming { step_high: (m - 19) as u16, ..timing };
    assert!(too_wide.check(&limits).is_err());

    let n1 = 100i32;
    let t_up = (((2 * n1 as u64) << 32).div_ceil(rmax as u64)) as u32;
    let t_down = (((2 * n1 as u64) << 32) / rmax as u64) as u32;
    let t_cruise = (((100u64) << 32).div_ceil(rmax as u64)) as u32;
    let reversal = vec![
        Segment::new(0, t_up, n1),
        Segment::new(rmax, t_cruise, 100),
        Segment::new(rmax, t_cruise, -100),
        Segment::new(rmax, t_down, -n1),
    ];
    let random = random_segments(0x5eed_2026, 8, &limits);
    let axes = vec![reversal, random];
    for s in axes.iter().flatten() {
        assert_eq!(s.validate(&limits), Ok(()), "{s:?}");
    }

    let mut b = bus();
    let write = |b: &mut BusModel, t: &PulseTiming| {
        b.write_reg("STEP_HIGH", 0, t.step_high);
        b.write_reg("STEP_LOW", 0, t.step_low);
        b.write_reg("DIR_SETUP", 0, t.dir_setup);
        b.write_reg("DIR_HOLD", 0, t.dir_hold);
    };
    let reset_values: Vec<_> = ["STEP_HIGH", "STEP_LOW", "DIR_SETUP", "DIR_HOLD"].iter().map(|r| b.read_reg(r, 0)).collect();
    write(&mut b, &too_wide);
    b.enable(ENABLE_WAIT);
    let refused_enable = (b.read_reg("CTRL", 0), b.read_reg("GSTATUS", 0));
    b.write_reg("GSTATUS", 0, 0b10);
    b.write_reg("STEP_HIGH", 0, 0);
    let refused_zero = (b.read_reg("STEP_HIGH", 0), b.read_reg("GSTATUS", 0));
    b.write_reg("GSTATUS", 0, 0b10);
    write(&mut b, &timing);
    b.enable(ENABLE_WAIT);
    let enabled = b.read_reg("GSTATUS", 0);
    b.write_reg("STEP_LOW", 0, 1);
    let refused_on = (b.read_reg("STEP_LOW", 0), b.read_reg("GSTATUS", 0));
    b.write_reg("GSTATUS", 0, 0b10);
    let start = push_and_start(&mut b, &axes);
    let end = axes.iter().map(|s| AxisRun::run(s, &limits).end_tick).max().unwrap();
    b.idle_until_ps(start + (end + 3_000) * 2 * CLOCKS.clk_half_ps);
    let status: Vec<_> = (0..2).map(|a| b.read_reg("STATUS", a)).collect();
    // A slow cruise (10,000-tick periods, 5,000-tick pulses) on axis 0, disabled 2,500
    // ticks after its third edge is due.
    let slow = Segment::new(((1u64 << 32) / 10_000) as u32, 100_000, 10);
    b.push_segment(0, &slow);
    b.idle(200);
    b.write_reg("START", 0, 0b01);
    let slow_start = b.now_ps();
    b.idle_until_ps(slow_start + (3 * 10_000 + 2_500 + 600) * 2 * CLOCKS.clk_half_ps);
    let disable_cycle = clk_cycle_at(b.now_ps());
    b.write_reg("CTRL", 0, 0);
    b.idle_until_ps(b.now_ps() + 10_000 * 2 * CLOCKS.clk_half_ps);
    let trace = verilator_exported::<2>("system_output_timing", &b, cycles_after(&b, 50));

    let got: Vec<u16> = reset_values.iter().map(|&id| read16(&b, &trace, id)).collect();
    assert_eq!(got, vec![1, 1, 1, 1], "output timing reset values");
    let (ctrl, gs) = (read16(&b, &trace, refused_enable.0), read16(&b, &trace, refused_enable.1));
    assert_eq!((ctrl & 1, gs & 0b11), (0, 0b10), "ENABLE with timing over the minimum period: CTRL {ctrl:#x}, GSTATUS {gs:#x}");
    let (v, gs) = (read16(&b, &trace, refused_zero.0), read16(&b, &trace, refused_zero.1));
    assert_eq!((v, gs & 0b10), (too_wide.step_high, 0b10), "a write of 0 is refused");
    assert_eq!(read16(&b, &trace, enabled) & 1, 1, "not ENABLED with fitting timing");
    let (v, gs) = (read16(&b, &trace, refused_on.0), read16(&b, &trace, refused_on.1));
    assert_eq!((v, gs & 0b10), (timing.step_low, 0b10), "a timing write while enabled is refused");
    for a in 0..2 {
        let st = read16(&b, &trace, status[a]);
        assert_eq!(st & (STATUS_UNDERRUN | STATUS_OVERFLOW | STATUS_ERROR), 0, "axis {a}: STATUS {st:#06x}");
    }
    let first_end = clk_cycle_at(slow_start);
    let window = 0..first_end;
    let l0 = check_edges_in(&trace, &axes, window.clone(), "output timing");
    let mut early = trace.clone();
    early.changes.retain(|(c, _)| window.contains(c));
    let meas = check_pins(&early, &axes, l0, &timing, "output timing");
    let reversal_gaps: Vec<u64> = rises(&early, 0).windows(2).map(|w| w[1] - w[0]).collect();
    assert!(*reversal_gaps.iter().min().unwrap() <= m as u64 + 1, "axis 0 does not reach the top rate");
    assert!(meas[0].2 < u64::MAX && meas[0].3 < u64::MAX, "axis 0 has no reversal to measure");
    eprintln!("output timing (high, low, DIR setup, DIR hold), narrowest: axis 0 {:?}, axis 1 {:?}", meas[0], meas[1]);
    // The disable: the pulse high at that moment ends at its full high time.
    let rises0: Vec<u64> = rises(&trace, 0).into_iter().filter(|&c| c >= first_end).collect();
    let (falls0, _) = falls_and_dir(&trace, 0);
    let falls0: Vec<u64> = falls0.into_iter().filter(|&c| c >= first_end).collect();
    assert_eq!(rises0.len(), 3, "the slow move's edges before the disable: {rises0:?}");
    assert_eq!(falls0.len(), 3, "every pulse falls");
    let last = (rises0[2], falls0[2]);
    assert!(last.0 < disable_cycle && disable_cycle < last.1, "the disable did not hit a pulse: {last:?}, disable at {disable_cycle}");
    assert_eq!(last.1 - last.0, timing.high_ticks(10_000) as u64, "the pulse at the disable was cut");
}

/// A START that cannot complete says so. Axis 1's only segment is rejected (code 2), so
/// START 0b11 is cancelled: GSTATUS.START_FAILED and IRQ_ERROR bits 0 and 1 set, the
/// irq line rises (IRQ_MASK_ERROR), no axis moves, axis 0 keeps its segment. A START
/// naming an axis that never had a segment fails the same way. After the host pushes a
/// valid segment to axis 1 and writes START again, both axes run, edge for edge the
/// model's, and START_FAILED stays clear.
#[test]
fn a_start_with_an_empty_axis_is_reported_and_nothing_moves() {
    let limits = tdm_stepper::export::ExportOptions::default().limits();
    let good = vec![Segment::new(0, 20_000, 100)];
    let bad = Segment::new(50_000_000, 20_000, -10);
    assert_eq!(bad.validate(&limits).unwrap_err().code(), 2);
    let mut b = bus();
    b.enable(ENABLE_WAIT);
    b.write_reg("IRQ_MASK_ERROR", 0, 0b11);
    b.push_segment(0, &good[0]);
    b.push_segment(1, &bad);
    b.idle(2_000);
    b.write_reg("START", 0, 0b11);
    b.idle(1_000);
    let failed = (b.read_reg("GSTATUS", 0), b.read_reg("IRQ_ERROR", 0));
    let status = (b.read_reg("STATUS", 0), b.read_reg("STATUS", 1));
    b.write_reg("GSTATUS", 0, 0b1000);
    b.write_reg("IRQ_ERROR", 0, 0xFFFF);
    b.write_reg("STATUS", 1, STATUS_ERROR);
    // An axis that never had a segment (axis 1 now), alone in the mask.
    b.write_reg("START", 0, 0b10);
    b.idle(1_000);
    let failed_empty = (b.read_reg("GSTATUS", 0), b.read_reg("IRQ_ERROR", 0));
    b.write_reg("GSTATUS", 0, 0b1000);
    b.write_reg("IRQ_ERROR", 0, 0xFFFF);
    let cleared = b.read_reg("GSTATUS", 0);
    let fail_end = b.now_ps();
    b.push_segment(1, &good[0]);
    b.idle(2_000);
    b.write_reg("START", 0, 0b11);
    let start = b.now_ps();
    b.idle_until_ps(start + 25_000 * 2 * CLOCKS.clk_half_ps);
    let after = (b.read_reg("GSTATUS", 0), b.read_reg("IRQ_ERROR", 0));
    let pos: Vec<_> = (0..2).map(|a| b.read_position(a)).collect();
    let trace = verilator_exported::<2>("system_start_failed", &b, cycles_after(&b, 50));

    let (gs, ie) = (read16(&b, &trace, failed.0), read16(&b, &trace, failed.1));
    assert_eq!(gs & 0b1000, 0b1000, "START_FAILED not set: GSTATUS {gs:#06x}");
    assert_eq!(ie, 0b11, "IRQ_ERROR for the start's mask");
    let (s0, s1) = (read16(&b, &trace, status.0), read16(&b, &trace, status.1));
    assert_eq!(s0 & 0x3F, 0x20, "axis 0 keeps its segment, BUSY: STATUS {s0:#06x}");
    assert_eq!((s1 & 0x3F, s1 & STATUS_ERROR, s1 >> 12), (0, STATUS_ERROR, 2), "axis 1 empty, ERROR code 2: {s1:#06x}");
    let (gs, ie) = (read16(&b, &trace, failed_empty.0), read16(&b, &trace, failed_empty.1));
    assert_eq!((gs & 0b1000, ie), (0b1000, 0b10), "START of a never-pushed axis: GSTATUS {gs:#06x}");
    assert_eq!(read16(&b, &trace, cleared) & 0b1000, 0, "START_FAILED is W1C");
    let (up, _) = irq_edges(&trace);
    assert!(up.iter().any(|&c| c < clk_cycle_at(fail_end)), "irq did not rise for the failed start");
    assert!(rises(&trace, 0).iter().chain(&rises(&trace, 1)).all(|&c| c > clk_cycle_at(fail_end)), "an axis moved on a failed start");
    let (gs, ie) = (read16(&b, &trace, after.0), read16(&b, &trace, after.1));
    assert_eq!((gs & 0b1000, ie), (0, 0), "the good start: GSTATUS {gs:#06x}, IRQ_ERROR {ie:#x}");
    check_edges(&trace, &[good.clone(), good.clone()], "after the failed starts");
    for a in 0..2 {
        assert_eq!(position(&b, &trace, pos[a]), Some(100), "axis {a} position");
    }
}

/// HCLK cycles to wait after a push (the bus model's write ends one HCLK after NWE
/// rises) so that the next read's NOE falls PUSH_VERDICT_BUS_CLOCKS bus clocks after
/// NWE rose: the documented bound, and not one HCLK more.
fn verdict_wait(b: &BusModel) -> u64 {
    let need = (regs::PUSH_VERDICT_BUS_CLOCKS * 2 * CLOCKS.bus_half_ps).div_ceil(2 * MCU_HALF_PS);
    need.saturating_sub(1 + b.timing.addset)
}

/// Errors at push time (the contract's "Errors at push"), in Verilator and rust-hdl:
/// a bad segment pushed to an axis not started, to a running axis with valid segments
/// queued behind its current one, and to a running axis with nothing queued shows
/// STATUS.ERROR with the model's code in a STATUS read that begins at the documented
/// bound after the push, with LEVEL unchanged; IRQ_ERROR has the axis's bit; the valid
/// segments run edge for edge as the model says, and the other axis never moves.
#[test]
fn a_bad_push_is_reported_at_the_bus_within_the_documented_bound() {
    let limits = tdm_stepper::export::ExportOptions { axes: 2, ..Default::default() }.limits();
    let good = vec![uniform(12_000, 30), Segment::new(((30u64 << 32) / 12_000) as u32, 12_000, 30), uniform(8_000, 10)];
    let bad = [Segment::new(50_000_000, 20_000, -10), Segment::new(0, 1 << 29, (1 << 24) + 1), Segment::new(0, 100, 90)];
    let codes: Vec<u16> = bad.iter().map(|s| s.validate(&limits).unwrap_err().code() as u16).collect();
    assert_eq!(codes, vec![2, 5, 3]);
    let mut b = bus();
    b.enable(ENABLE_WAIT);
    b.write_reg("IRQ_MASK_ERROR", 0, 0b11);
    let wait = verdict_wait(&b);
    // 1. Axis 1, never started and empty.
    let before1 = b.read_reg("STATUS", 1);
    b.push_segment(1, &bad[0]);
    b.idle(wait);
    let seen1 = b.read_reg("STATUS", 1);
    let irq1 = b.read_reg("IRQ_ERROR", 0);
    b.write_reg("IRQ_ERROR", 0, 0xFFFF);
    // 2. Axis 0 running its first segment, the other two queued behind it.
    for s in &good {
        b.push_segment(0, s);
    }
    b.idle(200);
    b.write_reg("START", 0, 0b01);
    let start = b.now_ps();
    b.idle(2_000);
    let before2 = b.read_reg("STATUS", 0);
    b.push_segment(0, &bad[1]);
    b.idle(wait);
    let seen2 = b.read_reg("STATUS", 0);
    b.write_reg("STATUS", 0, STATUS_ERROR);
    // 3. Axis 0 in its last segment, nothing queued.
    b.idle_until_ps(start + 26_000 * 2 * CLOCKS.clk_half_ps);
    let before3 = b.read_reg("STATUS", 0);
    b.push_segment(0, &bad[2]);
    b.idle(wait);
    let seen3 = b.read_reg("STATUS", 0);
    let irq3 = b.read_reg("IRQ_ERROR", 0);
    b.idle_until_ps(start + 40_000 * 2 * CLOCKS.clk_half_ps);
    let end0 = b.read_reg("STATUS", 0);
    let pos = b.read_position(0);
    let cycles = cycles_after(&b, 50);
    let traces = [("Verilator", verilator_exported::<2>("system_push_errors", &b, cycles)), ("rust-hdl", rust_hdl::<2>(&b, cycles))];

    for (sim, trace) in &traces {
        let r = |id| read16(&b, trace, id);
        let level = |s: u16| s & 0x1F;
        let (b1, s1) = (r(before1), r(seen1));
        assert_eq!((b1 & STATUS_ERROR, level(b1)), (0, 0), "{sim}: axis 1 before: {b1:#06x}");
        assert_eq!((s1 & STATUS_ERROR, s1 >> 12, level(s1)), (STATUS_ERROR, codes[0], 0), "{sim}: idle axis: {s1:#06x}");
        assert_eq!(r(irq1), 0b10, "{sim}: IRQ_ERROR after the idle axis's bad push");
        let (b2, s2) = (r(before2), r(seen2));
        assert!(level(b2) >= 1 && b2 & STATUS_ERROR == 0, "{sim}: axis 0 should have segments queued: {b2:#06x}");
        assert_eq!((s2 & STATUS_ERROR, s2 >> 12, level(s2)), (STATUS_ERROR, codes[1], level(b2)), "{sim}: behind queued segments: {s2:#06x}");
        let (b3, s3) = (r(before3), r(seen3));
        assert_eq!((b3 & (STATUS_ERROR | 0x3F)), 0x20, "{sim}: axis 0 moving, nothing queued: {b3:#06x}");
        assert_eq!((s3 & STATUS_ERROR, s3 >> 12, level(s3)), (STATUS_ERROR, codes[2], 0), "{sim}: running axis: {s3:#06x}");
        assert_eq!(r(irq3), 0b01, "{sim}: IRQ_ERROR after axis 0's bad pushes");
        let e0 = r(end0);
        assert_eq!(e0 & 0x3F, 0, "{sim}: axis 0 at the end: {e0:#06x}");
        assert_eq!(position(&b, trace, pos), Some(70), "{sim}: axis 0 position");
    }
    let trace = &traces[0].1;
    check_edges(trace, &[good.clone(), vec![]], "bad pushes between good ones");
    assert!(rises(trace, 1).is_empty(), "axis 1 moved");
    assert_eq!(traces[0].1.changes, traces[1].1.changes, "Verilator and rust-hdl pins differ");
}

// ---- machine I/O (export --io all) ------------------------------------------------

/// The exported core with the machine I/O in Verilator: the bus events with the pins
/// beside them (`pins`: from time 0, then each change), watching step, dir, irq and
/// drv_enable.
fn verilator_io<const K: usize>(name: &str, b: &BusModel, cycles: u64, initial: &[u128], pins: &[(u64, Vec<u128>)]) -> SystemTrace {
    let opts = tdm_stepper::export::ExportOptions { axes: K, io: true, ..Default::default() };
    let verilog = tdm_stepper::export::verilog(&opts).unwrap();
    let mut watch = stepper_watch(K);
    watch.push(Port::new("drv_enable", K));
    let pins_of = [("estop_n", 1), ("probe", 1), ("limit_neg", K), ("limit_pos", K), ("home", K), ("alarm", K)];
    verilator_with_pins(name, &verilog, tdm_stepper::export::TOP_MODULE, watch, &pins_of, b, cycles, initial, pins)
}

/// Runs `verilog` (top `module`, watching `watch`) in Verilator on `b`'s bus events with
/// input pins beyond the bus's (`extra`: names and widths, in the order of `initial`'s
/// values and `pins`' changes, as [`tdm_stepper::verify::bus::with_extra_inputs`] takes
/// them), the idle bus paused; the data samples mapped back to `b`'s reads.
#[allow(clippy::too_many_arguments)]
fn verilator_with_pins(
    name: &str,
    verilog: &str,
    module: &str,
    watch: Vec<Port>,
    extra: &[(&str, usize)],
    b: &BusModel,
    cycles: u64,
    initial: &[u128],
    pins: &[(u64, Vec<u128>)],
) -> SystemTrace {
    let mut spec = system_spec(module, watch);
    for &(n, w) in extra {
        spec.inputs.push(Port::new(n, w));
    }
    let (events, index) = tdm_stepper::verify::bus::with_extra_inputs(b.events(), initial, pins);
    let run = RunOptions { pause_idle_bus_ps: Some(PAUSE_GAP_PS), build_cache: Some(verilator_cache()), ..Default::default() };
    let mut tr = run_system_with(&sim_dir(name, Simulator::Verilator), verilog, &spec, &CLOCKS, &events, cycles, &run).unwrap();
    samples_to_bus_events(&mut tr, &index);
    tr
}

/// [`verilator_io`] in rust-hdl: the same bus events and pins, the same trace form.
fn rust_hdl_io<const K: usize>(b: &BusModel, cycles: u64, initial: &[u128], pins: &[(u64, Vec<u128>)]) -> SystemTrace {
    let (events, index) = tdm_stepper::verify::bus::with_extra_inputs(b.events(), initial, pins);
    let mut u = TdmStepperIo::<K, R, DEPTH, QDEPTH>::new(CoreParams { io: true, ..params::<K>() });
    u.connect_ports();
    let mut rh = run_stepper_io_rust_hdl(&mut u, &CLOCKS, &events, cycles);
    samples_to_bus_events(&mut rh, &index);
    rh
}

/// Pins: estop_n, probe, limit_neg, limit_pos, home, alarm (every input inactive, the
/// e-stop released, with the reset polarities).
fn io_pins(estop_n: bool) -> Vec<u128> {
    vec![estop_n as u128, 0, 0, 0, 0, 0]
}

/// E-stop through the bus, on a move of both axes: the hard stop comes within the
/// documented latency of the pin (no STEP rising edge after clk edge e0 + 4 + n, e0 the
/// first edge that samples the pin; e0 + 3 + n unless a push reaches the core in that
/// cycle), no pulse is cut below STEP_HIGH, the
/// positions read back equal the edges emitted, the queues are empty, drv_enable drops
/// (at e0 + 3 + n),
/// IO_STATUS and IRQ_IO say so; a release alone restarts nothing (a push while latched
/// is rejected at push with code 9, HALTED, and a START moves nothing); only
/// IO_CMD.ESTOP_REARM, written while the e-stop is released, lets the next move run.
/// A machine I/O configuration write while enabled is refused.
#[test]
fn estop_through_the_bus_stops_every_axis_exactly() {
    use tdm_stepper::model::io::pin_to_level_ticks;
    const K: usize = 2;
    const N: u8 = 2; // the e-stop's filter, samples
    const HIGH: u16 = 5;
    let mut b = bus();
    b.write_reg("IO_FILTER_LO", 0, N as u16);
    b.write_reg("STEP_HIGH", 0, HIGH);
    b.enable(ENABLE_WAIT);
    let refused = {
        b.write_reg("IO_FILTER_LO", 0, 7); // while enabled: refused
        (b.read_reg("IO_FILTER_LO", 0), b.read_reg("IO_STATUS", 0))
    };
    b.write_reg("IO_STATUS", 0, 1 << 4);
    let before_rearm = b.read_reg("IO_STATUS", 0);
    b.write_reg("IO_CMD", 0, 1);
    b.idle(50);
    let armed = (b.read_reg("IO_STATUS", 0), b.read_reg("IO_AXIS", 0), b.read_reg("IO_AXIS", 1));
    b.write_reg("IRQ_MASK_IO", 0, 1);
    let rate = |steps_per_tick: f64| (steps_per_tick * 4_294_967_296.0).round() as u32;
    let moves = [
        [Segment { v0_rate: 0, t_ticks: 100_000, steps: 500 }, Segment { v0_rate: rate(0.01), t_ticks: 200_000, steps: 2_000 }],
        [Segment { v0_rate: 0, t_ticks: 100_000, steps: -300 }, Segment { v0_rate: rate(0.006), t_ticks: 200_000, steps: -1_200 }],
    ];
    for (a, segs) in moves.iter().enumerate() {
        for s in segs {
            b.push_segment(a, s);
        }
    }
    b.write_reg("START", 0, 0b11);
    // The e-stop 150,000 ticks (3 ms) into the move: both axes are stepping.
    let t_estop = b.now_ps() + 150_000 * 2 * CLOCKS.clk_half_ps;
    b.idle_until_ps(t_estop + 50_000 * 2 * CLOCKS.clk_half_ps);
    let stopped_pos = [b.read_position(0), b.read_position(1)];
    let stopped = (b.read_reg("IO_STATUS", 0), b.read_reg("IRQ_IO", 0), b.read_reg("BUSY", 0), b.read_reg("STATUS", 0), b.read_reg("STATUS", 1));
    // Released: still latched; a push and a START move nothing.
    let t_release = b.now_ps() + 1_000 * 2 * CLOCKS.clk_half_ps;
    b.idle_until_ps(t_release + 10_000 * 2 * CLOCKS.clk_half_ps);
    let released = b.read_reg("IO_STATUS", 0);
    b.push_segment(0, &Segment { v0_rate: 0, t_ticks: 50_000, steps: 200 });
    b.write_reg("START", 0, 0b01);
    b.idle(60_000);
    let latched_after = (b.read_reg("STATUS", 0), b.read_reg("BUSY", 0), b.read_position(0));
    // Re-armed while released: the next move runs.
    let t_rearm = b.now_ps();
    b.write_reg("IO_CMD", 0, 1);
    b.idle(50);
    let rearmed = b.read_reg("IO_STATUS", 0);
    b.push_segment(0, &Segment { v0_rate: 0, t_ticks: 50_000, steps: 200 });
    b.write_reg("START", 0, 0b01);
    b.idle_until_ps(b.now_ps() + 60_000 * 2 * CLOCKS.clk_half_ps);
    let final_pos = b.read_position(0);
    let cycles = cycles_after(&b, 100);
    let tr = verilator_io::<K>("io_estop", &b, cycles, &io_pins(true), &[(t_estop, io_pins(false)), (t_release, io_pins(true))]);
    let v = |id| b.value(&tr, id).expect("read returned x");

    assert_eq!((v(refused.0), v(refused.1) >> 4 & 1), (N as u16, 1), "a configuration write while enabled is refused");
    assert_eq!(v(before_rearm) & 0b11, 0b01, "the e-stop latch is set after enable, the input released");
    assert_eq!(v(armed.0) & 0b111, 0, "re-armed: IO_STATUS clear");
    assert_eq!((v(armed.1) >> 4 & 1, v(armed.2) >> 4 & 1), (1, 1), "IO_AXIS.DRV_ENABLE");

    // The pin is first sampled by the clk edge after t_estop (rising edges at 2·HC·j).
    let e0 = t_estop.div_ceil(2 * CLOCKS.clk_half_ps);
    let last_allowed = e0 + pin_to_level_ticks(N) + 2;
    let resume = clk_cycle_at(t_rearm);
    for a in 0..K {
        let r = rises(&tr, a);
        let (falls, _) = falls_and_dir(&tr, a);
        let before: Vec<u64> = r.iter().copied().filter(|&c| c < resume).collect();
        assert!(before.iter().any(|&c| c + 500 > e0), "axis {a}: not stepping when the e-stop came");
        let last = *before.last().unwrap();
        assert!(last <= last_allowed, "axis {a}: a STEP edge at clk {last}, {} after the pin was first sampled (bound {})", last - e0, pin_to_level_ticks(N));
        // Every pulse keeps its high time, the one the e-stop caught included.
        for &c in &before {
            let f = falls.iter().find(|&&f| f > c).expect("a pulse never fell");
            assert!(f - c >= HIGH as u64, "axis {a}: a pulse of {} ticks at clk {c}", f - c);
        }
        let pos = position(&b, &tr, stopped_pos[a]).unwrap();
        let sign = if moves[a][0].steps < 0 { -1 } else { 1 };
        assert_eq!(pos, sign * before.len() as i32, "axis {a}: position against the edges emitted");
        assert!((before.len() as i64) < moves[a].iter().map(|s| s.steps.abs() as i64).sum::<i64>(), "axis {a}: the move finished before the e-stop");
    }
    // drv_enable drops one tick after the hard stop, and stays low until the re-arm.
    let drv_low = tr.changes.iter().find(|(c, v)| *c > e0 && v[3] == Some(0)).expect("drv_enable never dropped").0;
    assert!(drv_low <= e0 + pin_to_level_ticks(N) + 2, "drv_enable low at clk {drv_low}, {} after the pin", drv_low - e0);
    assert!(tr.changes.iter().filter(|(c, _)| *c > drv_low && *c < resume).all(|(_, v)| v[3] == Some(0)), "drv_enable rose while latched");
    let (st, irq, busy, s0, s1) = stopped;
    assert_eq!(v(st) & 0b111, 0b011, "IO_STATUS: ESTOP and ESTOP_IN");
    assert_eq!(v(irq) & 1, 1, "IRQ_IO.ESTOP");
    assert_eq!(v(busy), 0, "BUSY after the hard stop");
    assert_eq!((v(s0) & 0x1F, v(s1) & 0x1F), (0, 0), "LEVEL after the hard stop: the queues were flushed");
    assert!(irq_edges(&tr).0.iter().any(|&c| c > e0 && c < e0 + 200), "the irq line rose for IRQ_IO.ESTOP");
    assert_eq!(v(released) & 0b111, 0b001, "released: ESTOP still latched, ESTOP_IN clear");
    let (st0, busy0, pos0) = latched_after;
    assert_eq!((v(st0) & 0x1F, v(busy0)), (0, 0), "a push while latched is not queued");
    assert_eq!((v(st0) >> 8 & 1, v(st0) >> 12), (1, 9), "a push while latched is rejected at push: code 9 (HALTED)");
    assert_eq!(position(&b, &tr, pos0).unwrap(), position(&b, &tr, stopped_pos[0]).unwrap(), "nothing moved while latched");
    assert_eq!(v(rearmed) & 0b111, 0, "re-armed");
    let after: Vec<u64> = rises(&tr, 0).into_iter().filter(|&c| c >= resume).collect();
    assert_eq!(after.len(), 200, "the move after the re-arm");
    assert_eq!(position(&b, &tr, final_pos).unwrap(), position(&b, &tr, stopped_pos[0]).unwrap() + 200);
}

/// The watchdog through the bus: while IO_CMD.WD_FEED comes often enough the move runs;
/// once the feeds stop, every axis stops within WD_TIMEOUT·1024 ticks (plus the
/// command's crossing) of the last feed, IO_STATUS.WATCHDOG and IRQ_IO.WATCHDOG are
/// set, and only IO_CMD.WD_REARM clears the trip.
#[test]
fn the_watchdog_stops_a_move_when_the_host_stops_feeding_it() {
    use tdm_stepper::model::io::WATCHDOG_UNIT_TICKS;
    const K: usize = 2;
    let mut b = bus();
    b.write_reg("WD_TIMEOUT", 0, 2); // 2,048 ticks
    b.enable(ENABLE_WAIT);
    b.write_reg("IO_CMD", 0, 0b101); // re-arm the e-stop and the watchdog
    b.idle(50);
    let fresh = b.read_reg("IO_STATUS", 0);
    b.push_segment(0, &Segment { v0_rate: 0, t_ticks: 400_000, steps: 4_000 });
    b.write_reg("START", 0, 0b01);
    // Feed every 1,000 ticks for 100,000 ticks, then stop.
    let tick_ps = 2 * CLOCKS.clk_half_ps;
    let mut last_feed = 0;
    for _ in 0..100 {
        b.idle_until_ps(b.now_ps() + 1_000 * tick_ps);
        b.write_reg("IO_CMD", 0, 0b010);
        last_feed = b.now_ps();
    }
    b.idle_until_ps(last_feed + 20_000 * tick_ps);
    let tripped = (b.read_reg("IO_STATUS", 0), b.read_reg("IRQ_IO", 0));
    b.write_reg("IO_CMD", 0, 0b010); // a feed does not clear a trip
    b.idle(50);
    let fed = b.read_reg("IO_STATUS", 0);
    b.write_reg("IO_CMD", 0, 0b100);
    b.idle(50);
    let rearmed = b.read_reg("IO_STATUS", 0);
    let cycles = cycles_after(&b, 100);
    let tr = verilator_io::<K>("io_watchdog", &b, cycles, &io_pins(true), &[]);
    let v = |id| b.value(&tr, id).expect("read returned x");
    assert_eq!(v(fresh) & 0b111, 0, "armed");
    let r = rises(&tr, 0);
    let fed_until = clk_cycle_at(last_feed);
    let while_fed = r.iter().filter(|&&c| c + 10_000 > fed_until && c < fed_until).count();
    assert!(while_fed > 20, "stepping while fed: {while_fed} edges in the last 10,000 ticks");
    let last = *r.last().unwrap();
    let limit = 2 * WATCHDOG_UNIT_TICKS;
    assert!(last > fed_until && last <= fed_until + limit + 8, "last edge {} ticks after the last feed's write (timeout {limit})", last as i64 - fed_until as i64);
    assert!(r.len() < 4_000, "the move finished");
    assert_eq!(v(tripped.0) & 0b100, 0b100, "IO_STATUS.WATCHDOG");
    assert_eq!(v(tripped.1) & 0b10, 0b10, "IRQ_IO.WATCHDOG");
    assert_eq!(v(fed) & 0b100, 0b100, "a feed does not clear a trip");
    assert_eq!(v(rearmed) & 0b100, 0, "WD_REARM clears it");
}

/// The filtered inputs read back per axis, and an alarm drops that axis's drv_enable.
/// The same run in rust-hdl gives the Verilator trace (the machine I/O's top, registers
/// and crossings three ways with the block tests).
#[test]
fn io_axis_reads_the_filtered_inputs_and_an_alarm_drops_the_enable() {
    const K: usize = 2;
    let mut b = bus();
    b.write_reg("IO_FILTER_HI", 0, 0x21);
    let filt = b.read_reg("IO_FILTER_HI", 0);
    b.enable(ENABLE_WAIT);
    b.write_reg("IO_CMD", 0, 1);
    b.idle(50);
    let t_pins = b.now_ps();
    b.idle(200);
    let reads: Vec<_> = (0..K).map(|a| b.read_reg("IO_AXIS", a)).collect();
    let st = b.read_reg("IO_STATUS", 0);
    let cycles = cycles_after(&b, 100);
    // Axis 0: limit_pos and alarm; axis 1: limit_neg and home; the probe.
    let pins = vec![1, 1, 0b10, 0b01, 0b10, 0b01];
    let tr = verilator_io::<K>("io_axis", &b, cycles, &io_pins(true), &[(t_pins, pins.clone())]);
    let v = |id| b.value(&tr, id).expect("read returned x");
    assert_eq!(v(reads[0]) & 0x1F, 0b01010, "axis 0: LIMIT_POS, ALARM, drv_enable low");
    assert_eq!(v(reads[1]) & 0x1F, 0b10101, "axis 1: LIMIT_NEG, HOME, drv_enable high");
    assert_eq!(v(st) & 0b1000, 0b1000, "IO_STATUS.PROBE_IN");
    let drv = tr.changes.last().unwrap().1[3];
    assert_eq!(drv, Some(0b10), "drv_enable: axis 0 low (alarm), axis 1 high");
    assert_eq!(v(filt), 0x21, "IO_FILTER_HI written while disabled");

    // rust-hdl on the same events.
    let rh = rust_hdl_io::<K>(&b, cycles, &io_pins(true), &[(t_pins, pins)]);
    let defined = |t: &SystemTrace| t.changes.iter().skip_while(|c| c.0 < 10).cloned().collect::<Vec<_>>();
    assert_eq!(defined(&rh), defined(&tr), "rust-hdl and Verilator differ (watched outputs)");
    assert_eq!(rh.samples, tr.samples, "rust-hdl and Verilator differ (bus reads)");
}

/// The home and probe position latches through the bus, exact to the tick: a first run
/// finds the STEP rising edges of a two-axis move (the inputs do not change the
/// motion); the second puts axis 1's home input so that its filtered level changes at
/// the clk edge of axis 1's k-th rising edge (2 + n ticks after the edge that first
/// samples the pin), and the probe so that its level changes one tick after axis 0's
/// j-th. HOME_POS reads the edges emitted before that edge (−k: axis 1 moves back),
/// PROBE_POS every axis's count one tick after, IRQ_IO.HOME and PROBE and
/// IO_AXIS.HOME_LATCHED (axis 1 only, cleared with IRQ_IO.HOME) say so, and the irq
/// line rises. rust-hdl gives the same trace and reads.
#[test]
fn home_and_probe_latch_the_exact_position() {
    use tdm_stepper::model::io::pin_to_level_ticks;
    const K: usize = 2;
    const N_HOME: u8 = 1;
    const N_PROBE: u8 = 0;
    let mut b = bus();
    b.write_reg("IO_FILTER_HI", 0, N_HOME as u16);
    b.write_reg("IO_FILTER_LO", 0, (N_PROBE as u16) << 4);
    b.enable(ENABLE_WAIT);
    b.write_reg("IO_CMD", 0, 1);
    b.write_reg("IRQ_MASK_IO", 0, 0b1100);
    b.idle(50);
    let before = (b.read_reg("IRQ_IO", 0), b.read_reg("HOME_POS_LO", 1), b.read_reg("PROBE_POS_LO", 0));
    let moves = [Segment { v0_rate: 0, t_ticks: 20_000, steps: 200 }, Segment { v0_rate: 0, t_ticks: 20_000, steps: -150 }];
    for (a, s) in moves.iter().enumerate() {
        b.push_segment(a, s);
    }
    b.write_reg("START", 0, 0b11);
    b.idle_until_ps(b.now_ps() + 25_000 * 2 * CLOCKS.clk_half_ps);
    let irq = b.read_reg("IRQ_IO", 0);
    let axis = [b.read_reg("IO_AXIS", 0), b.read_reg("IO_AXIS", 1)];
    let home = (b.read_reg("HOME_POS_LO", 1), b.read_reg("HOME_POS_HI", 1));
    let home0 = (b.read_reg("HOME_POS_LO", 0), b.read_reg("HOME_POS_HI", 0));
    let probe = [(b.read_reg("PROBE_POS_LO", 0), b.read_reg("PROBE_POS_HI", 0)), (b.read_reg("PROBE_POS_LO", 1), b.read_reg("PROBE_POS_HI", 1))];
    b.write_reg("IRQ_IO", 0, 0b1100);
    b.idle(20);
    let cleared = (b.read_reg("IRQ_IO", 0), b.read_reg("IO_AXIS", 1));
    let cycles = cycles_after(&b, 100);

    let first = verilator_io::<K>("io_latch", &b, cycles, &io_pins(true), &[]);
    let (r0, r1) = (rises(&first, 0), rises(&first, 1));
    assert_eq!((r0.len(), r1.len()), (200, 150), "the move");
    let (k, j) = (97, 123);
    // A pin change half a tick before edge e0 is first sampled by e0.
    let pin_time = |level_edge: u64, n: u8| (2 * (level_edge - pin_to_level_ticks(n)) - 1) * CLOCKS.clk_half_ps;
    let t_home = pin_time(r1[k], N_HOME);
    let t_probe = pin_time(r0[j] + 1, N_PROBE);
    assert!(t_home != t_probe);
    let mut pins = vec![(t_home, vec![1, 0, 0, 0, 0b10, 0]), (t_probe, vec![1, 1, 0, 0, 0, 0])];
    pins.sort();
    // Both stay changed: fix up whichever comes second to keep the first's change.
    pins[1].1 = vec![1, 1, 0, 0, 0b10, 0];
    let tr = verilator_io::<K>("io_latch", &b, cycles, &io_pins(true), &pins);
    assert_eq!((rises(&tr, 0), rises(&tr, 1)), (r0.clone(), r1.clone()), "the inputs changed the motion");
    let probe_edge = r0[j] + 1;
    let expect_probe = [r0.iter().filter(|&&c| c < probe_edge).count() as i32, -(r1.iter().filter(|&&c| c < probe_edge).count() as i32)];

    let check = |sim: &str, t: &SystemTrace| {
        let v = |id| b.value(t, id).expect("read returned x");
        assert_eq!((v(before.0), v(before.1), v(before.2)), (0, 0, 0), "{sim}: before the move");
        assert_eq!(v(irq) & 0b1100, 0b1100, "{sim}: IRQ_IO.PROBE and HOME");
        assert_eq!((v(axis[0]) >> 5 & 1, v(axis[1]) >> 5 & 1), (0, 1), "{sim}: IO_AXIS.HOME_LATCHED");
        assert_eq!(position(&b, t, home), Some(-(k as i32)), "{sim}: HOME_POS of axis 1: the edges before the level changed");
        assert_eq!(position(&b, t, home0), Some(0), "{sim}: HOME_POS of axis 0 (its home never changed)");
        for a in 0..K {
            assert_eq!(position(&b, t, probe[a]), Some(expect_probe[a]), "{sim}: PROBE_POS of axis {a}");
        }
        assert_eq!((v(cleared.0), v(cleared.1) >> 5 & 1), (0, 0), "{sim}: IRQ_IO and HOME_LATCHED cleared");
        let (up, _) = irq_edges(t);
        let first = r1[k].min(probe_edge);
        assert!(up.iter().any(|&c| c > first && c < first + 200), "{sim}: the irq line rose for the first latch (clk {first}): {up:?}");
    };
    check("Verilator", &tr);
    assert_eq!(expect_probe[0], j as i32 + 1, "the probe's edge counts axis 0's j-th edge");

    let rh = rust_hdl_io::<K>(&b, cycles, &io_pins(true), &pins);
    check("rust-hdl", &rh);
    let defined = |t: &SystemTrace| t.changes.iter().skip_while(|c| c.0 < 10).cloned().collect::<Vec<_>>();
    assert_eq!(defined(&rh), defined(&tr), "rust-hdl and Verilator differ (watched outputs)");
}

/// Limit switches through the bus: both axes' `limit_pos` become active in the middle
/// of a move where axis 0 runs toward it (+) and axis 1 away (−). Axis 0 stops with no
/// STEP rising edge after e0 + 4 + n (e0: the edge that first samples the pin), its
/// queue flushed, its position the edges emitted, IO_AXIS.STOPPED and IRQ_IO.STOP set
/// (and the irq line); axis 1 runs its whole move. While the limit stays active a move
/// away from it (−) runs in full, and a push toward it is rejected at push with code 7
/// (LIMIT) while a segment queued before it runs exactly, the model's edges. rust-hdl
/// gives the same trace.
#[test]
fn a_limit_in_the_direction_of_motion_stops_that_axis_alone() {
    use tdm_stepper::model::io::pin_to_level_ticks;
    const K: usize = 2;
    const N: u8 = 1; // limit_pos filter, samples
    let mut b = bus();
    b.write_reg("IO_FILTER_LO", 0, (N as u16) << 12);
    b.enable(ENABLE_WAIT);
    b.write_reg("IO_CMD", 0, 1);
    b.write_reg("IRQ_MASK_IO", 0, 1 << 4);
    b.idle(50);
    let moves = [Segment { v0_rate: 0, t_ticks: 20_000, steps: 200 }, Segment { v0_rate: 0, t_ticks: 20_000, steps: -150 }];
    for (a, s) in moves.iter().enumerate() {
        b.push_segment(a, s);
    }
    // A second segment on axis 0, flushed by the stop.
    b.push_segment(0, &Segment { v0_rate: 0, t_ticks: 10_000, steps: 50 });
    b.write_reg("START", 0, 0b11);
    let t_lim = b.now_ps() + 12_000 * 2 * CLOCKS.clk_half_ps;
    b.idle_until_ps(t_lim + 15_000 * 2 * CLOCKS.clk_half_ps);
    let stopped = (b.read_position(0), b.read_position(1), b.read_reg("STATUS", 0), b.read_reg("IO_AXIS", 0), b.read_reg("IO_AXIS", 1), b.read_reg("IRQ_IO", 0), b.read_reg("BUSY", 0));
    b.write_reg("IRQ_IO", 0, 1 << 4);
    // Away from the limit: runs.
    let t_away = b.now_ps();
    b.push_segment(0, &Segment { v0_rate: 0, t_ticks: 10_000, steps: -100 });
    b.write_reg("START", 0, 0b01);
    b.idle_until_ps(b.now_ps() + 12_000 * 2 * CLOCKS.clk_half_ps);
    let away = (b.read_position(0), b.read_reg("IO_AXIS", 0), b.read_reg("IRQ_IO", 0));
    // Toward it: rejected at push; the segment queued before it runs.
    let t_toward = b.now_ps();
    let last_away = Segment { v0_rate: 0, t_ticks: 10_000, steps: -50 };
    b.push_segment(0, &last_away);
    b.push_segment(0, &Segment { v0_rate: 0, t_ticks: 10_000, steps: 100 });
    b.write_reg("START", 0, 0b01);
    b.idle_until_ps(b.now_ps() + 12_000 * 2 * CLOCKS.clk_half_ps);
    let toward = (b.read_position(0), b.read_reg("IO_AXIS", 0), b.read_reg("STATUS", 0), b.read_reg("BUSY", 0));
    let cycles = cycles_after(&b, 100);
    let pins = vec![(t_lim, vec![1, 0, 0, 0b11, 0, 0])];
    let tr = verilator_io::<K>("io_limit", &b, cycles, &io_pins(true), &pins);

    let check = |sim: &str, t: &SystemTrace| {
        let v = |id| b.value(t, id).expect("read returned x");
        let e0 = t_lim.div_ceil(2 * CLOCKS.clk_half_ps);
        let (r0, r1) = (rises(t, 0), rises(t, 1));
        let (away_c, toward_c) = (clk_cycle_at(t_away), clk_cycle_at(t_toward));
        let first: Vec<u64> = r0.iter().copied().filter(|&c| c < away_c).collect();
        assert!(first.len() > 20 && first.len() < 200, "{sim}: axis 0 stopped mid-move after {} edges", first.len());
        let last = *first.last().unwrap();
        assert!(last + 200 > e0, "{sim}: axis 0 was not stepping when the limit came");
        assert!(last <= e0 + pin_to_level_ticks(N) + 2, "{sim}: axis 0's edge at clk {last}, {} after the pin was first sampled", last - e0);
        let (p0, p1, st0, ax0, ax1, irq, busy) = stopped;
        assert_eq!(position(&b, t, p0), Some(first.len() as i32), "{sim}: axis 0's position: the edges emitted");
        assert_eq!(position(&b, t, p1), Some(-150), "{sim}: axis 1 ran its whole move (away from its limit)");
        assert_eq!(r1.len(), 150, "{sim}: axis 1's edges");
        assert_eq!(v(st0) & 0x1F, 0, "{sim}: axis 0's queue flushed (LEVEL 0)");
        assert_eq!((v(ax0) >> 6 & 1, v(ax1) >> 6 & 1), (1, 0), "{sim}: IO_AXIS.STOPPED");
        assert_eq!((v(ax0) >> 1 & 1, v(ax1) >> 1 & 1), (1, 1), "{sim}: IO_AXIS.LIMIT_POS");
        assert_eq!(v(irq) >> 4 & 1, 1, "{sim}: IRQ_IO.STOP");
        assert_eq!(v(busy), 0, "{sim}: nothing busy");
        let (up, _) = irq_edges(t);
        assert!(up.iter().any(|&c| c > e0 && c < e0 + 100), "{sim}: the irq line rose: {up:?}");
        let second = r0.iter().filter(|&&c| c >= away_c && c < toward_c).count();
        assert_eq!(second, 100, "{sim}: the move away from the limit");
        assert_eq!(position(&b, t, away.0), Some(first.len() as i32 - 100), "{sim}: after the move away");
        assert_eq!((v(away.1) >> 6 & 1, v(away.2) >> 4 & 1), (0, 0), "{sim}: the move away is no stop");
        check_edges_in(t, &[vec![last_away]], toward_c..u64::MAX, &format!("{sim}: the segment queued before the push toward the limit"));
        assert_eq!(position(&b, t, toward.0), Some(first.len() as i32 - 150), "{sim}: after the push toward");
        let st = v(toward.2);
        assert_eq!((st >> 8 & 1, st >> 12, st & 0x1F, v(toward.3)), (1, 7, 0, 0), "{sim}: the push toward: ERROR, code 7 (LIMIT), LEVEL 0, idle");
        assert_eq!(v(toward.1) >> 6 & 1, 0, "{sim}: a rejected push is no stop");
    };
    check("Verilator", &tr);
    let rh = rust_hdl_io::<K>(&b, cycles, &io_pins(true), &pins);
    check("rust-hdl", &rh);
}

/// Soft limits and the planned position through the bus (the push guard), K = 2: axis 0
/// gets soft limits [−100, 300]. SL_APPLY with SL_MIN > SL_MAX, or with SL_AXIS beyond
/// the core's axes, is refused (SL_STATUS.REFUSED) and changes nothing. A push whose end
/// position after everything queued before it lies past a limit is rejected at push
/// with code 8 (SOFT_LIMIT) and the queued segments run exactly (the model's edges);
/// one that ends on a limit is taken (inclusive). PLAN reads where the accepted pushes
/// end. After an ABORT mid-move the plan is stale (SL_STATUS.STALE) until a status word
/// shows the axis at rest, then equals the position it stopped at: a push past the
/// limit from there is rejected, one within it runs, and PLAN follows. rust-hdl gives the
/// same reads.
#[test]
fn soft_limits_reject_pushes_past_them_and_the_plan_follows_an_abort() {
    const K: usize = 2;
    let mut b = bus();
    b.enable(ENABLE_WAIT);
    b.write_reg("IO_CMD", 0, 1);
    b.idle(50);
    let set = |b: &mut BusModel, axis: u16, min: i32, max: i32| {
        b.write_reg("SL_AXIS", 0, axis);
        b.write_reg("SL_MIN_LO", 0, min as u16);
        b.write_reg("SL_MIN_HI", 0, (min >> 16) as u16);
        b.write_reg("SL_MAX_LO", 0, max as u16);
        b.write_reg("SL_MAX_HI", 0, (max >> 16) as u16);
        b.write_reg("SL_APPLY", 0, 1);
    };
    set(&mut b, 0, -100, 300);
    let on = b.read_reg("SL_STATUS", 0);
    set(&mut b, 0, 10, 5);
    let bad_pair = b.read_reg("SL_STATUS", 0);
    b.write_reg("SL_STATUS", 0, 1 << 2);
    set(&mut b, 5, 0, 10);
    let bad_axis = b.read_reg("SL_STATUS", 0);
    b.write_reg("SL_STATUS", 0, 1 << 2);
    b.write_reg("SL_AXIS", 0, 0);
    let cleared = b.read_reg("SL_STATUS", 0);

    let first = Segment { v0_rate: 0, t_ticks: 20_000, steps: 200 };
    let last = Segment { v0_rate: 0, t_ticks: 10_000, steps: 100 };
    let other = Segment { v0_rate: 0, t_ticks: 30_000, steps: -300 };
    b.push_segment(0, &first);
    b.push_segment(0, &Segment { v0_rate: 0, t_ticks: 20_000, steps: 150 }); // ends at 350
    b.idle(10);
    let over = b.read_reg("STATUS", 0);
    b.write_reg("STATUS", 0, 1 << 8);
    b.push_segment(0, &last); // ends at 300: on the limit
    b.push_segment(1, &other);
    b.idle(10);
    let planned = (b.read_reg("STATUS", 0), b.read_reg("PLAN_LO", 0), b.read_reg("PLAN_HI", 0));
    b.write_reg("SL_AXIS", 0, 1);
    let planned1 = (b.read_reg("PLAN_LO", 0), b.read_reg("PLAN_HI", 0));
    b.write_reg("SL_AXIS", 0, 0);
    let t_start = b.now_ps();
    b.write_reg("START", 0, 0b11);
    b.idle_until_ps(b.now_ps() + 32_000 * 2 * CLOCKS.clk_half_ps);
    let done = (b.read_position(0), b.read_position(1), b.read_reg("PLAN_LO", 0), b.read_reg("PLAN_HI", 0));

    // An abort mid-move.
    let t_second = b.now_ps();
    b.push_segment(0, &Segment { v0_rate: 0, t_ticks: 40_000, steps: -350 });
    b.write_reg("START", 0, 0b01);
    b.idle_until_ps(b.now_ps() + 20_000 * 2 * CLOCKS.clk_half_ps);
    b.write_reg("ABORT", 0, 1);
    let just_aborted = b.read_reg("SL_STATUS", 0);
    b.idle(200);
    let rested = (b.read_reg("SL_STATUS", 0), b.read_position(0), b.read_reg("PLAN_LO", 0), b.read_reg("PLAN_HI", 0));
    let t_third = b.now_ps();
    b.push_segment(0, &Segment { v0_rate: 0, t_ticks: 40_000, steps: 400 }); // past 300 from anywhere above −100
    b.idle(10);
    let over2 = b.read_reg("STATUS", 0);
    b.write_reg("STATUS", 0, 1 << 8);
    b.push_segment(0, &Segment { v0_rate: 0, t_ticks: 10_000, steps: -1 });
    b.write_reg("START", 0, 0b01);
    // (The one step's pulse is high for half its 10,000-tick period.)
    b.idle_until_ps(b.now_ps() + 17_000 * 2 * CLOCKS.clk_half_ps);
    let fin = (b.read_reg("STATUS", 0), b.read_position(0), b.read_reg("PLAN_LO", 0), b.read_reg("PLAN_HI", 0));
    let cycles = cycles_after(&b, 100);
    let tr = verilator_io::<K>("io_soft_limits", &b, cycles, &io_pins(true), &[]);

    let check = |sim: &str, t: &SystemTrace| {
        let v = |id| b.value(t, id).expect("read returned x");
        let pair = |lo, hi| (v(lo) as u32 | (v(hi) as u32) << 16) as i32;
        assert_eq!(v(on) & 0b111, 0b001, "{sim}: SL_STATUS after SL_APPLY: ENABLED");
        assert_eq!(v(bad_pair) & 0b111, 0b101, "{sim}: SL_MIN > SL_MAX refused, the limits still on");
        assert_eq!(v(bad_axis) >> 2 & 1, 1, "{sim}: SL_AXIS beyond K refused");
        assert_eq!(v(cleared) & 0b111, 0b001, "{sim}: REFUSED cleared");
        let st = v(over);
        assert_eq!((st >> 8 & 1, st >> 12, st & 0x1F), (1, 8, 1), "{sim}: the push ending at 350: code 8, one segment queued");
        let (st, lo, hi) = planned;
        assert_eq!((v(st) >> 8 & 1, v(st) & 0x1F), (0, 2), "{sim}: the push ending on the limit is taken");
        assert_eq!(pair(lo, hi), 300, "{sim}: PLAN of axis 0 before the start");
        assert_eq!(pair(planned1.0, planned1.1), -300, "{sim}: PLAN of axis 1 (no soft limits)");
        let window = clk_cycle_at(t_start)..clk_cycle_at(t_second);
        check_edges_in(t, &[vec![first, last], vec![other]], window, &format!("{sim}: the segments queued around the rejected push"));
        let (p0, p1, lo, hi) = done;
        assert_eq!((position(&b, t, p0), position(&b, t, p1), pair(lo, hi)), (Some(300), Some(-300), 300), "{sim}: after the move");
        assert_eq!(v(just_aborted) >> 1 & 1, 1, "{sim}: the plan is stale right after the ABORT");
        let (sl, pos, lo, hi) = rested;
        let pos = position(&b, t, pos).unwrap();
        let moved = rises(t, 0).into_iter().filter(|&c| c >= clk_cycle_at(t_second) && c < clk_cycle_at(t_third)).count() as i32;
        assert!(moved > 50 && moved < 349, "{sim}: the abort came mid-move ({moved} edges)");
        assert_eq!(pos, 300 - moved, "{sim}: the position after the abort: the edges emitted");
        assert_eq!((v(sl) >> 1 & 1, pair(lo, hi)), (0, pos), "{sim}: at rest the plan is the position again");
        let st = v(over2);
        assert_eq!((st >> 8 & 1, st >> 12, st & 0x1F), (1, 8, 0), "{sim}: past the limit from the aborted position: code 8");
        let (st, pos2, lo, hi) = fin;
        assert_eq!(v(st) & 0x13F, 0, "{sim}: the push within the limit ran: no error, nothing queued, idle");
        assert_eq!((position(&b, t, pos2), pair(lo, hi)), (Some(pos - 1), pos - 1), "{sim}: the last move and its plan");
    };
    check("Verilator", &tr);
    let rh = rust_hdl_io::<K>(&b, cycles, &io_pins(true), &[]);
    check("rust-hdl", &rh);
}

/// The controlled stop through the bus (Verilator and rust-hdl): STOP_DECEL refused
/// below the export's minimum and while enabled (STOP_STATUS.REFUSED, the value in use
/// unchanged), taken otherwise; then, on a move of both axes, STOP names axis 1 in its
/// cruise: axis 0's edges are all the model's, axis 1's are the model's move cut after
/// c FIFO entries followed by the model's stop segment (model::stop::cut_run), with c at
/// most the FIFO's depth + 3 entries past the edges emitted when the write began;
/// axis 1 comes to rest, its position read back is
/// the edges emitted, its plan is stale right after the STOP and follows the position
/// at rest.
#[test]
fn a_controlled_stop_through_the_bus_ramps_down_from_the_axis_speed() {
    use tdm_stepper::model::planner;
    const K: usize = 2;
    let limits = Limits::default();
    // Below the minimum of any minimum period (the export's and rust-hdl's here).
    let low_decel = 1000;
    let decel: u32 = 0xF000_0000;
    let mut b = bus();
    let put = |b: &mut BusModel, v: u32| {
        b.write_reg("STOP_DECEL_LO", 0, v as u16);
        b.write_reg("STOP_DECEL_HI", 0, (v >> 16) as u16);
    };
    put(&mut b, low_decel);
    let low = (b.read_reg("STOP_STATUS", 0), b.read_reg("STOP_DECEL_LO", 0), b.read_reg("STOP_DECEL_HI", 0));
    b.write_reg("STOP_STATUS", 0, 1);
    put(&mut b, decel);
    let taken = (b.read_reg("STOP_STATUS", 0), b.read_reg("STOP_DECEL_LO", 0), b.read_reg("STOP_DECEL_HI", 0));
    b.enable(ENABLE_WAIT);
    b.write_reg("IO_CMD", 0, 1);
    b.idle(50);
    put(&mut b, 0xFFFF_0000);
    let enabled = (b.read_reg("STOP_STATUS", 0), b.read_reg("STOP_DECEL_LO", 0), b.read_reg("STOP_DECEL_HI", 0));
    b.write_reg("STOP_STATUS", 0, 1);

    let m0 = planner::trapezoid_by_ticks(30, [12_000, 8_000, 12_000], &limits).unwrap();
    let m1 = planner::trapezoid_by_ticks(-60, [16_000, 20_000, 16_000], &limits).unwrap();
    let run1 = AxisRun::run(&m1, &limits);
    for s in &m0 {
        b.push_segment(0, s);
    }
    for s in &m1 {
        b.push_segment(1, s);
    }
    b.idle(10);
    let t_start = b.now_ps();
    b.write_reg("START", 0, 0b11);
    b.idle_until_ps(b.now_ps() + (run1.edge_ticks[30] + 300) * 2 * CLOCKS.clk_half_ps);
    b.write_reg("SL_AXIS", 0, 1);
    let t_stop = b.now_ps();
    b.write_reg("STOP", 0, 0b10);
    let stale = b.read_reg("SL_STATUS", 0);
    b.idle_until_ps(b.now_ps() + 100_000 * 2 * CLOCKS.clk_half_ps);
    let rest = (b.read_reg("STATUS", 1), b.read_position(1), b.read_reg("SL_STATUS", 0), b.read_reg("PLAN_LO", 0), b.read_reg("PLAN_HI", 0));
    let cycles = cycles_after(&b, 100);

    let check = |sim: &str, t: &SystemTrace| {
        let v = |id| b.value(t, id).expect("read returned x");
        let (st, lo, hi) = low;
        assert_eq!((v(st) & 1, v(lo), v(hi)), (1, 0xFFFF, 0xFFFF), "{sim}: a deceleration below the minimum is refused, the reset value stays");
        let (st, lo, hi) = taken;
        assert_eq!((v(st) & 1, v(lo) as u32 | (v(hi) as u32) << 16), (0, decel), "{sim}: STOP_DECEL taken while disabled");
        let (st, lo, hi) = enabled;
        assert_eq!((v(st) & 1, v(lo) as u32 | (v(hi) as u32) << 16), (1, decel), "{sim}: refused while enabled");
        let window = clk_cycle_at(t_start)..cycles;
        check_edges_in(t, &[m0.clone()], window.clone(), &format!("{sim}: axis 0 untouched"));
        let r: Vec<u64> = rises(t, 1).into_iter().filter(|c| window.contains(c)).collect();
        let emitted = r.iter().filter(|&&c| c <= clk_cycle_at(t_stop)).count();
        assert!(emitted > 25 && emitted < 40, "{sim}: the stop came in the cruise ({emitted} edges)");
        let e0 = entries_for_edges(&run1, emitted);
        let (_, m) = stop_cut_matching(&run1, &r, e0..=e0 + DEPTH + 3, decel, &limits)
            .unwrap_or_else(|| panic!("{sim}: no cut after {e0}.. entries gives axis 1's {} edges", r.len()));
        assert_eq!(m.accepted.len(), 1, "{sim}: a ramp");
        // (The test's moves decelerate harder than the hardest STOP_DECEL, 2^-25 steps/tick²,
        // 7.5·10^7 steps/s² at 50 MHz: the ramp runs farther than the move would have.)
        assert_ne!(r.len(), run1.edge_ticks.len(), "{sim}: axis 1's motion changed");
        let (st, pos, sl, lo, hi) = rest;
        assert_eq!(v(st) & 0x13F, 0, "{sim}: axis 1 idle, nothing queued, no error");
        assert_eq!(position(&b, t, pos), Some(m.position as i32), "{sim}: the position at rest is the edges emitted");
        assert_eq!(v(stale) >> 1 & 1, 1, "{sim}: the plan is stale right after the STOP");
        assert_eq!((v(sl) >> 1 & 1, (v(lo) as u32 | (v(hi) as u32) << 16) as i32), (0, m.position as i32), "{sim}: at rest the plan is the position");
    };
    let tr = verilator_io::<K>("io_controlled_stop", &b, cycles, &io_pins(true), &[]);
    check("Verilator", &tr);
    let rh = rust_hdl_io::<K>(&b, cycles, &io_pins(true), &[]);
    check("rust-hdl", &rh);
}

/// The edges `r` of an axis that a controlled stop cut: the model's `cut_run` of `run`
/// for the one cut within DEPTH + 3 entries of the `emitted` edges (two fewer, for a
/// request time known to a few ticks) that gives exactly these edges.
fn the_stop_ramp(sim: &str, r: &[u64], run: &AxisRun, emitted: usize, decel: u32) -> AxisRun {
    let e0 = entries_for_edges(run, emitted);
    let (_, m) = stop_cut_matching(run, r, e0.saturating_sub(2)..=e0 + DEPTH + 3, decel, &Limits::default())
        .unwrap_or_else(|| panic!("{sim}: no cut near {e0} entries gives the {} edges", r.len()));
    assert_eq!(m.accepted.len(), 1, "{sim}: a ramp");
    assert_ne!(r.len(), run.edge_ticks.len(), "{sim}: the motion changed");
    m
}

/// STOP_MODE through the bus (K = 2, Verilator; the blocks are checked three ways in
/// hdl_machine_io and hdl_core). With the limits and the stop on home in controlled
/// mode, axis 0 running into its active limit_pos and axis 1 crossing its home switch
/// (armed in STOP_HOME) each ramp down at STOP_DECEL: their edges are the model's stop
/// after the periods already computed, the positions at rest are the edges emitted,
/// HOME_POS is the position when home changed and POS − HOME_POS the ramp's overshoot;
/// IO_AXIS.STOPPED is set; STOP_MODE is refused while enabled. Then, with the watchdog
/// in controlled mode, a trip ramps both axes down and drv_enable drops only after
/// their last edges.
#[test]
fn stop_modes_through_the_bus_ramp_down_on_a_limit_on_home_and_on_the_watchdog() {
    use tdm_stepper::model::io::{MODE_HOME, MODE_LIMITS, MODE_WATCHDOG};
    use tdm_stepper::model::planner;
    const K: usize = 2;
    let limits = Limits::default();
    let decel: u32 = 0xF000_0000;
    let tick_ps = 2 * CLOCKS.clk_half_ps;
    let m0 = planner::trapezoid_by_ticks(30, [12_000, 8_000, 12_000], &limits).unwrap();
    let m1 = planner::trapezoid_by_ticks(-60, [16_000, 20_000, 16_000], &limits).unwrap();
    let runs = [AxisRun::run(&m0, &limits), AxisRun::run(&m1, &limits)];
    let setup = |b: &mut BusModel, mode: u8| {
        b.write_reg("STOP_DECEL_LO", 0, decel as u16);
        b.write_reg("STOP_DECEL_HI", 0, (decel >> 16) as u16);
        b.write_reg("STOP_MODE", 0, mode as u16);
        b.enable(ENABLE_WAIT);
        b.write_reg("IO_CMD", 0, 0b101);
        b.idle(50);
        for s in &m0 {
            b.push_segment(0, s);
        }
        for s in &m1 {
            b.push_segment(1, s);
        }
        b.idle(10);
    };

    // A limit and home.
    let mut b = bus();
    setup(&mut b, MODE_LIMITS | MODE_HOME);
    b.write_reg("STOP_MODE", 0, 0);
    let refused = (b.read_reg("STOP_STATUS", 0), b.read_reg("STOP_MODE", 0));
    b.write_reg("STOP_STATUS", 0, 1);
    b.write_reg("STOP_HOME", 0, 0b10);
    let armed = b.read_reg("STOP_HOME", 0);
    let t_start = b.now_ps();
    b.write_reg("START", 0, 0b11);
    let t_lim = t_start + (runs[0].edge_ticks[12] + 300) * tick_ps;
    let t_home = t_start + (runs[1].edge_ticks[25] + 300) * tick_ps;
    b.idle_until_ps(t_home + 150_000 * tick_ps);
    let rest = [(b.read_position(0), b.read_reg("IO_AXIS", 0)), (b.read_position(1), b.read_reg("IO_AXIS", 1))];
    let home = (b.read_reg("HOME_POS_LO", 1), b.read_reg("HOME_POS_HI", 1));
    let busy = b.read_reg("BUSY", 0);
    let cycles = cycles_after(&b, 100);
    let pins = vec![(t_lim, vec![1, 0, 0, 0b01, 0, 0]), (t_home, vec![1, 0, 0, 0b01, 0b10, 0])];
    let t = verilator_io::<K>("io_stop_modes", &b, cycles, &io_pins(true), &pins);
    let v = |id| b.value(&t, id).expect("read returned x");
    assert_eq!((v(refused.0) & 1, v(refused.1)), (1, (MODE_LIMITS | MODE_HOME) as u16), "STOP_MODE refused while enabled");
    assert_eq!(v(armed), 0b10, "STOP_HOME reads back");
    let window = clk_cycle_at(t_start)..cycles;
    let mut ramps = Vec::new();
    for (a, t_pin) in [(0, t_lim), (1, t_home)] {
        let r: Vec<u64> = rises(&t, a).into_iter().filter(|c| window.contains(c)).collect();
        let c_pin = clk_cycle_at(t_pin);
        assert!(!r.iter().any(|&c| c >= c_pin && c <= c_pin + 5), "axis {a}: an edge at the pin (move the pin)");
        let emitted = r.iter().filter(|&&c| c < c_pin).count();
        let m = the_stop_ramp(&format!("axis {a}"), &r, &runs[a], emitted, decel);
        assert_eq!(position(&b, &t, rest[a].0), Some(m.position as i32), "axis {a}: the position at rest is the edges emitted");
        assert_eq!(v(rest[a].1) >> 6 & 1, 1, "axis {a}: IO_AXIS.STOPPED");
        ramps.push((emitted, m));
    }
    let (emitted1, m1r) = &ramps[1];
    assert_eq!(position(&b, &t, home), Some(-(*emitted1 as i32)), "HOME_POS: the edges before home changed");
    // The overshoot POS − HOME_POS: the ramp's steps past the switch, in the move's direction.
    let overshoot = m1r.position - -(*emitted1 as i64);
    assert!(overshoot < 0, "the overshoot POS − HOME_POS: {overshoot}");
    assert_eq!(v(busy), 0, "both axes at rest");

    // The watchdog: fed every 1,000 ticks, then starved, to trip near axis 0's 10th edge.
    let wd_ticks = 2 * tdm_stepper::model::io::WATCHDOG_UNIT_TICKS;
    let mut b = bus();
    b.write_reg("WD_TIMEOUT", 0, 2);
    setup(&mut b, MODE_WATCHDOG);
    let t_start = b.now_ps();
    b.write_reg("START", 0, 0b11);
    let mut last_feed = t_start;
    while last_feed + (wd_ticks + 1_000) * tick_ps < t_start + runs[0].edge_ticks[10] * tick_ps {
        b.idle_until_ps(last_feed + 1_000 * tick_ps);
        b.write_reg("IO_CMD", 0, 0b010);
        last_feed = b.now_ps();
    }
    b.idle_until_ps(last_feed + 150_000 * tick_ps);
    let tripped = (b.read_reg("IO_STATUS", 0), b.read_position(0), b.read_position(1), b.read_reg("BUSY", 0));
    let cycles = cycles_after(&b, 100);
    let t = verilator_io::<K>("io_stop_modes", &b, cycles, &io_pins(true), &[]);
    let v = |id| b.value(&t, id).expect("read returned x");
    let trip = clk_cycle_at(last_feed) + wd_ticks;
    let window = clk_cycle_at(t_start)..cycles;
    let mut last_edge = 0;
    for a in 0..K {
        let r: Vec<u64> = rises(&t, a).into_iter().filter(|c| window.contains(c)).collect();
        let emitted = r.iter().filter(|&&c| c < trip).count();
        let m = the_stop_ramp(&format!("watchdog, axis {a}"), &r, &runs[a], emitted, decel);
        assert_eq!(position(&b, &t, [tripped.1, tripped.2][a]), Some(m.position as i32), "watchdog, axis {a}: the position at rest");
        last_edge = last_edge.max(*r.last().unwrap());
    }
    assert_eq!(v(tripped.0) & 0b100, 0b100, "IO_STATUS.WATCHDOG");
    assert_eq!(v(tripped.3), 0, "at rest");
    // drv_enable (watched column 3) stays high through the ramps, drops after the last edge.
    let drop = t.changes.iter().find(|(c, s)| *c > trip && s[3] == Some(0)).expect("drv_enable never dropped").0;
    assert!(drop > last_edge && drop < last_edge + 200, "drv_enable dropped at clk {drop}, the last edge at {last_edge}");
    assert!(t.changes.iter().filter(|(c, _)| *c > clk_cycle_at(t_start) + 100 && *c < drop).all(|(_, s)| s[3] == Some(3)), "drv_enable high while ramping");
}

/// An export with some machine I/O groups only (`--io limits`, K = 2), in Verilator,
/// through the bus: the registers of the groups left out are refused or read 0 (a
/// WD_TIMEOUT write sets IO_STATUS.REFUSED and reads back 0, IO_POLARITY keeps only the
/// limits' bits, a STOP_HOME write sets STOP_STATUS.REFUSED), there is no e-stop latch
/// to re-arm (the core moves right after CTRL.ENABLE), and the limits work as in the
/// whole machine I/O: a move into limit_pos stops with no edge after e0 + 4, at the
/// exact position, with IO_AXIS.STOPPED, while drv_enable was high.
#[test]
fn an_export_with_only_the_limits_has_only_their_pins_and_registers() {
    const K: usize = 2;
    let mut b = bus();
    b.write_reg("WD_TIMEOUT", 0, 2);
    b.write_reg("IO_POLARITY", 0, 0x3F);
    let config = (b.read_reg("IO_STATUS", 0), b.read_reg("WD_TIMEOUT", 0), b.read_reg("IO_POLARITY", 0));
    b.write_reg("IO_STATUS", 0, 1 << 4);
    b.write_reg("IO_POLARITY", 0, 0);
    b.write_reg("STOP_HOME", 0, 1);
    let home = (b.read_reg("STOP_STATUS", 0), b.read_reg("STOP_HOME", 0));
    b.enable(ENABLE_WAIT);
    b.idle(50);
    let status = b.read_reg("IO_STATUS", 0);
    b.push_segment(0, &Segment { v0_rate: 0, t_ticks: 20_000, steps: 200 });
    b.write_reg("START", 0, 0b01);
    let t_lim = b.now_ps() + 12_000 * 2 * CLOCKS.clk_half_ps;
    b.idle_until_ps(t_lim + 15_000 * 2 * CLOCKS.clk_half_ps);
    let stopped = (b.read_position(0), b.read_reg("IO_AXIS", 0), b.read_reg("BUSY", 0));
    let cycles = cycles_after(&b, 100);
    let choice = tdm_stepper::export::parse_io("limits").unwrap();
    let opts = tdm_stepper::export::ExportOptions { axes: K, io: choice.io, io_omit: choice.omit, ..Default::default() };
    let verilog = tdm_stepper::export::verilog(&opts).unwrap();
    let mut watch = stepper_watch(K);
    watch.push(Port::new("drv_enable", K));
    let limits = [("limit_neg", K), ("limit_pos", K)];
    let t = verilator_with_pins("io_limits_only", &verilog, tdm_stepper::export::TOP_MODULE, watch, &limits, &b, cycles, &[0, 0], &[(t_lim, vec![0, 0b01])]);
    let v = |id| b.value(&t, id).expect("read returned x");
    assert_eq!((v(config.0) >> 4 & 1, v(config.1), v(config.2)), (1, 0, 0b1100), "WD_TIMEOUT refused, IO_POLARITY only the limits' bits");
    assert_eq!((v(home.0) & 1, v(home.1)), (1, 0), "STOP_HOME refused");
    assert_eq!(v(status) & 0b111, 0, "no e-stop latch, no watchdog");
    let r = rises(&t, 0);
    let e0 = t_lim.div_ceil(2 * CLOCKS.clk_half_ps);
    assert!(r.len() > 20 && r.len() < 200, "axis 0 stopped mid-move after {} edges", r.len());
    assert!(*r.last().unwrap() <= e0 + 4, "an edge at clk {}, {} after the pin was first sampled", r.last().unwrap(), r.last().unwrap() - e0);
    assert_eq!(position(&b, &t, stopped.0), Some(r.len() as i32), "the position: the edges emitted");
    assert_eq!((v(stopped.1) >> 6 & 1, v(stopped.1) >> 1 & 1, v(stopped.2)), (1, 1, 0), "STOPPED, LIMIT_POS, idle");
    assert!(t.changes.iter().any(|(c, s)| *c > r[0] && *c < e0 && s[3] == Some(0b11)), "drv_enable high while moving");
}


/// The S-curve option through the bus (`export --profiles trapezoid,scurve`, K = 2, in
/// Verilator): axis 0 a seven-phase jerk-limited move out and back with a cubic
/// between whose speed peaks above RMAX inside it though both its ends and its mean
/// are below (rejected at the push: code 3), axis 1 a trapezoid
/// move, cubics from rest to speed and back and a polynomial segment whose speed
/// reverses inside it (rejected at the push: STATUS.ERROR with code 2, counted out of
/// LEVEL: DONE_COUNT at the end counts the accepted ones, the segments around it
/// unchanged). Every edge is the model's from one release
/// tick; the polynomial staging registers read back what was written, and POLY_ARM
/// reads 0 once its push is taken.
#[test]
fn scurve_moves_through_the_bus_in_verilator() {
    use tdm_stepper::model::poly::PolySegment;
    use tdm_stepper::model::scurve::jerk_limited;
    use tdm_stepper::model::Motion;
    let opts = tdm_stepper::export::ExportOptions { axes: 2, scurve: true, ..Default::default() };
    let limits = opts.limits();
    let hz = opts.clock_hz;
    let jl = |steps| jerk_limited(steps, 0.0, 0.0, 50_000.0, 2.0e7, 2.0e10, 2.0e7, 2.0e10, hz, &limits).unwrap();
    let v1 = ((1u64 << 32) / 2000) as u32;
    let cubic = |v0, v1, t, n| Motion::from(PolySegment::cubic(v0, v1, t, n).unwrap());
    let bad = Motion::from(PolySegment::new(0, 0, -(40i64 << 32), 30_000, 5));
    assert_eq!(bad.validate(&limits).err().map(|e| e.code()), Some(2), "the bad segment reverses");
    // From rest to rest: both ends at 0 and the mean speed n/T below RMAX, but the peak
    // inside (1.5·n/T) above it: code 3.
    let peak = Motion::from(PolySegment::cubic(0, 0, 30_000, 120).unwrap());
    assert!(120 * ((1u64 << 32) / 30_000) < limits.max_rate() as u64, "mean speed below RMAX");
    assert_eq!(peak.validate(&limits).err().map(|e| e.code()), Some(3), "the peak inside is too fast");
    let axes: Vec<Vec<Motion>> = vec![
        [jl(300), vec![peak], jl(-300)].concat(),
        [
            tdm_stepper::model::planner::trapezoid_by_ticks(40, [40_000, 20_000, 40_000], &limits).unwrap().into_iter().map(Motion::from).collect::<Vec<_>>(),
            vec![cubic(0, v1, 60_000, 15), bad, cubic(v1, 0, 60_000, 15)],
        ]
        .concat(),
    ];
    let poly: usize = axes.iter().flatten().filter(|m| matches!(m, Motion::Poly(_))).count();
    assert!(poly >= 10, "{poly} polynomial segments");
    let mut b = bus();
    b.enable(ENABLE_WAIT);
    // The staging registers read back; POLY_ARM reads 1 until a push takes it.
    b.write_reg("POLY_V1_LO", 0, 0x1234);
    b.write_reg("POLY_A_3", 0, 0x8765);
    b.write_reg("POLY_ARM", 0, 1);
    let r_v1 = b.read_reg("POLY_V1_LO", 0);
    let r_a3 = b.read_reg("POLY_A_3", 0);
    let r_arm = b.read_reg("POLY_ARM", 0);
    b.write_reg("POLY_ARM", 0, 0);
    for (a, ms) in axes.iter().enumerate() {
        for m in ms {
            b.push_motion(a, m);
        }
    }
    let r_arm_after = b.read_reg("POLY_ARM", 0);
    let r_status = b.read_reg("STATUS", 1);
    let r_status0 = b.read_reg("STATUS", 0);
    b.idle(200);
    b.write_reg("START", 0, 3);
    let end = axes.iter().map(|ms| AxisRun::run_motions(ms, &limits).end_tick).max().unwrap();
    b.idle_until_ps(b.now_ps() + (end + 10_000) * 2 * CLOCKS.clk_half_ps);
    let done: Vec<_> = (0..2).map(|a| b.read_reg("DONE_COUNT", a)).collect();
    let cycles = cycles_after(&b, 2_000);
    let t = verilator_exported_with("system_scurve", &b, cycles, opts);
    assert_eq!(read16(&b, &t, r_v1), 0x1234, "POLY_V1_LO reads back");
    assert_eq!(read16(&b, &t, r_a3), 0x8765, "POLY_A_3 reads back");
    assert_eq!(read16(&b, &t, r_arm), 1, "POLY_ARM reads back");
    assert_eq!(read16(&b, &t, r_arm_after), 0, "the last polynomial push took the arm");
    let st = read16(&b, &t, r_status);
    assert_eq!(st >> 8 & 1, 1, "axis 1's STATUS.ERROR after the reversing segment");
    assert_eq!(st >> 12, 2, "ERROR_CODE 2 (would reverse)");
    let st0 = read16(&b, &t, r_status0);
    assert_eq!((st0 >> 8 & 1, st0 >> 12), (1, 3), "axis 0: ERROR with code 3 (a speed peak inside the segment above RMAX)");
    for (a, id) in done.into_iter().enumerate() {
        assert_eq!(read16(&b, &t, id) as usize, motion_count(&axes[a], &limits), "axis {a}: DONE_COUNT is the accepted segments");
    }
    // Every edge the model's, one release tick.
    let mut release = None;
    for (a, ms) in axes.iter().enumerate() {
        let run = AxisRun::run_motions(ms, &limits);
        let r = rises(&t, a);
        assert_eq!(r.len(), run.edge_ticks.len(), "axis {a} step count");
        let l0 = r[0] as i64 - 1 - run.edge_ticks[0] as i64;
        assert_eq!(*release.get_or_insert(l0), l0, "axis {a} released on another tick (skew)");
        for (i, (&got, &e)) in r.iter().zip(&run.edge_ticks).enumerate() {
            assert_eq!(got as i64, l0 + 1 + e as i64, "axis {a} edge {i}");
        }
    }
}

/// The segments of `ms` that pass validation.
fn motion_count(ms: &[tdm_stepper::model::Motion], limits: &Limits) -> usize {
    ms.iter().filter(|m| m.validate(limits).is_ok()).count()
}

// ---- encoder feedback (export --encoder) --------------------------------------------

/// The exported core with encoder feedback in Verilator, inside `enc_rig`: motors that
/// follow STEP and DIR with encoders of 5/4 counts per step (`verify::encoder`), the
/// bus events with the rig's pins beside them (`stall`, `slip`, `bounce`), watching
/// step, dir, irq and axis 0's encoder position.
fn verilator_enc<const K: usize>(name: &str, b: &BusModel, cycles: u64, rig: &tdm_stepper::verify::encoder::RigConfig, pins: &[(u64, Vec<u128>)]) -> SystemTrace {
    let opts = tdm_stepper::export::ExportOptions { axes: K, encoder: true, io: rig.io, ..Default::default() };
    let verilog = tdm_stepper::export::verilog(&opts).unwrap()
        + &tdm_stepper::verify::encoder::rig_verilog(tdm_stepper::export::TOP_MODULE, K, tdm_stepper::hdl::core::STATE_BITS, rig);
    let mut watch = stepper_watch(K);
    watch.push(Port::new("count0", 32));
    verilator_with_pins(name, &verilog, "enc_rig", watch, &[("stall", K), ("slip", K), ("bounce", 1)], b, cycles, &[0, 0, 1], pins)
}

/// Axis 0's encoder position (the rig's count) at the end of clk cycle `c`.
fn count0_at(tr: &SystemTrace, c: u64) -> i32 {
    tr.changes.iter().take_while(|(cc, _)| *cc <= c).last().map_or(0, |(_, v)| v[3].unwrap_or(0) as u32 as i32)
}

/// The bus script of [`encoder_feedback_through_the_bus_counts_trips_stops_and_corrects`]
/// and what it reads; `correction`: the correction move's steps (known from a first run).
struct EncScript {
    b: BusModel,
    pins: Vec<(u64, Vec<u128>)>,
    r_filter: (ReadId, ReadId),
    r_axis: (ReadId, ReadId),
    r_ratio0: ReadId,
    r_ratio_big: ReadId,
    r_back: (ReadId, ReadId, ReadId, ReadId),
    r_default: (ReadId, ReadId, ReadId),
    r_enabled: (ReadId, ReadId, ReadId),
    out: [ReadId; 4],
    out_idx: [ReadId; 6],
    back: [ReadId; 4],
    back_state: [ReadId; 3],
    back_pos: (ReadId, ReadId),
    stalled: [ReadId; 3],
    stalled_pos: (ReadId, ReadId),
    stalled_dev: (ReadId, ReadId),
    t_stall: u64,
    t_correct: u64,
    corrected: Option<([ReadId; 4], (ReadId, ReadId), ReadId)>,
    t_slip: u64,
    slipped: [ReadId; 2],
}

const ENC_TOL: u16 = 8;
const ENC_PERIOD: u32 = 150;

fn enc_script(rig: &tdm_stepper::verify::encoder::RigConfig, correction: Option<i32>) -> EncScript {
    const K: usize = 2;
    let tick = 2 * CLOCKS.clk_half_ps;
    let mut b = bus();
    let mut pins: Vec<(u64, Vec<u128>)> = Vec::new();
    // Configuration, with every refusal.
    b.write_reg("ENC_FILTER", 0, 16);
    let r_filter = (b.read_reg("ENC_STATUS", 0), b.read_reg("ENC_FILTER", 0));
    b.write_reg("ENC_STATUS", 0, 1);
    b.write_reg("ENC_FILTER", 0, 2);
    b.write_reg("ENC_AXIS", 0, K as u16);
    let r_axis = (b.read_reg("ENC_STATUS", 0), b.read_reg("ENC_AXIS", 0));
    b.write_reg("ENC_STATUS", 0, 1);
    b.write_reg("ENC_RATIO_LO", 0, 0);
    b.write_reg("ENC_RATIO_HI", 0, 0);
    let r_ratio0 = b.read_reg("ENC_STATUS", 0);
    b.write_reg("ENC_STATUS", 0, 1);
    b.write_reg("ENC_RATIO_LO", 0, 1);
    b.write_reg("ENC_RATIO_HI", 0, 0x100);
    let r_ratio_big = b.read_reg("ENC_STATUS", 0);
    b.write_reg("ENC_STATUS", 0, 1);
    let q = rig.ratio_q16();
    b.write_reg("ENC_RATIO_LO", 0, q as u16);
    b.write_reg("ENC_RATIO_HI", 0, (q >> 16) as u16);
    b.write_reg("ENC_TOL", 0, ENC_TOL);
    let r_back = (b.read_reg("ENC_RATIO_LO", 0), b.read_reg("ENC_RATIO_HI", 0), b.read_reg("ENC_TOL", 0), b.read_reg("ENC_STATUS", 0));
    b.write_reg("ENC_AXIS", 0, 1);
    let r_default = (b.read_reg("ENC_RATIO_LO", 0), b.read_reg("ENC_RATIO_HI", 0), b.read_reg("ENC_TOL", 0));
    b.write_reg("ENC_AXIS", 0, 0);
    b.write_reg("ENC_STOP", 0, 0b01);
    b.write_reg("IRQ_MASK_ENC", 0, 0b001);
    b.enable(ENABLE_WAIT);
    b.write_reg("ENC_FILTER", 0, 3);
    let r_enabled = (b.read_reg("ENC_STATUS", 0), b.read_reg("ENC_FILTER", 0), b.read_reg("ENC_RATIO_LO", 0));
    b.write_reg("ENC_STATUS", 0, 1);
    b.write_reg("ENC_ALIGN", 0, 0b11);
    b.idle(200);
    let count_reads = |b: &mut BusModel| [b.read_reg("ENC_COUNT_LO", 0), b.read_reg("ENC_COUNT_HI", 0), b.read_reg("ENC_DEV_LO", 0), b.read_reg("ENC_DEV_HI", 0)];

    // Out 3,200 steps (one revolution of counts, past the index), then back 1,600.
    b.push_segment(0, &uniform(3_200 * ENC_PERIOD, 3_200));
    b.write_reg("START", 0, 0b01);
    b.idle_until_ps(b.now_ps() + (3_200 * ENC_PERIOD as u64 + 2_000) * tick);
    let out = count_reads(&mut b);
    let out_idx = [
        b.read_reg("ENC_INDEX_LO", 0),
        b.read_reg("ENC_INDEX_HI", 0),
        b.read_reg("IRQ_ENC", 0),
        b.read_reg("ENC_STATE", 0),
        b.read_reg("ENC_INDEX_POS_LO", 0),
        b.read_reg("ENC_INDEX_POS_HI", 0),
    ];
    b.write_reg("IRQ_ENC", 0, 0b110);
    b.push_segment(0, &uniform(1_600 * ENC_PERIOD, -1_600));
    b.write_reg("START", 0, 0b01);
    b.idle_until_ps(b.now_ps() + (1_600 * ENC_PERIOD as u64 + 2_000) * tick);
    let back = count_reads(&mut b);
    let back_state = [b.read_reg("ENC_STATE", 0), b.read_reg("ENC_FAIL", 0), b.read_reg("IRQ_ENC", 0)];
    let back_pos = b.read_position(0);

    // A stall 400 steps into a 2,000-step move.
    b.push_segment(0, &uniform(2_000 * ENC_PERIOD, 2_000));
    b.write_reg("START", 0, 0b01);
    let t_stall = b.now_ps() + 400 * ENC_PERIOD as u64 * tick;
    pins.push((t_stall, vec![1, 0, 1]));
    b.idle_until_ps(t_stall + 20_000 * tick);
    let stalled = [b.read_reg("ENC_FAIL", 0), b.read_reg("IRQ_ENC", 0), b.read_reg("BUSY", 0)];
    let stalled_pos = b.read_position(0);
    let stalled_dev = (b.read_reg("ENC_DEV_LO", 0), b.read_reg("ENC_DEV_HI", 0));
    // The motor free again; align (the deviation kept in the offset), clear, and move
    // the steps the motor lost.
    pins.push((b.now_ps() + 1_000 * tick, vec![0, 0, 1]));
    b.idle_until_ps(b.now_ps() + 2_000 * tick);
    b.write_reg("ENC_ALIGN", 0, 0b01);
    b.write_reg("ENC_CLEAR", 0, 0b01);
    b.write_reg("IRQ_ENC", 0, 0b111);
    b.idle(200);
    let t_correct = b.now_ps();
    let mut corrected = None;
    if let Some(n) = correction {
        b.push_segment(0, &uniform(n.unsigned_abs() * 400, n));
        b.write_reg("START", 0, 0b01);
        b.idle_until_ps(b.now_ps() + (n.unsigned_abs() as u64 * 400 + 2_000) * tick);
        corrected = Some((count_reads(&mut b), b.read_position(0), b.read_reg("ENC_FAIL", 0)));
    }
    // A slip 300 steps into a 1,000-step move.
    b.push_segment(0, &uniform(1_000 * ENC_PERIOD, 1_000));
    b.write_reg("START", 0, 0b01);
    let t_slip = b.now_ps() + 300 * ENC_PERIOD as u64 * tick;
    pins.push((t_slip, vec![0, 1, 1]));
    b.idle_until_ps(t_slip + 10_000 * tick);
    let slipped = [b.read_reg("ENC_FAIL", 0), b.read_reg("BUSY", 0)];
    EncScript {
        b,
        pins,
        r_filter,
        r_axis,
        r_ratio0,
        r_ratio_big,
        r_back,
        r_default,
        r_enabled,
        out,
        out_idx,
        back,
        back_state,
        back_pos,
        stalled,
        stalled_pos,
        stalled_dev,
        t_stall,
        t_correct,
        corrected,
        t_slip,
        slipped,
    }
}

/// Encoder feedback through the bus, against motors with 5/4 counts per step (4,000
/// counts per revolution against 3,200 steps), an index once per revolution and
/// contact bounce on A shorter than the filter: bad configuration is refused with its
/// code (filter 16, ratio 0 or above the maximum, an axis the core lacks, a write
/// while enabled) and changes nothing; the ratio and tolerance read back, 1.0 and 0 on
/// an axis never written; a move out and back (a reversal) leaves ENC_COUNT exact, the
/// deviation 0, no illegal transition, and the index latch at the index's count; a
/// stall (counts stop, steps go on) trips ENC_FAIL at the tolerance and, with ENC_STOP,
/// stops the axis on the step that crossed it (IRQ_ENC.FAIL, the irq line, BUSY 0, the
/// position equal to the edges emitted); the correction (ENC_ALIGN and ENC_CLEAR, then
/// a move of the deviation over the ratio) brings the encoder to the commanded position
/// within a count; a slip (the motor thrown back) trips it and stops the axis within
/// the documented latency.
#[test]
fn encoder_feedback_through_the_bus_counts_trips_stops_and_corrects() {
    use tdm_stepper::hdl::follow_err::FOLLOW_ERR_LATENCY;
    use tdm_stepper::model::encoder::{pin_to_level_ticks, EncRefusal};
    const K: usize = 2;
    let rig = tdm_stepper::verify::encoder::RigConfig::default();
    let tick = 2 * CLOCKS.clk_half_ps;
    let dev_of = |b: &BusModel, tr: &SystemTrace, ids: (ReadId, ReadId)| position(b, tr, ids).unwrap();
    // First run: the deviation the stall leaves, for the correction move.
    let first = enc_script(&rig, None);
    let cycles = first.t_correct / tick + 1_000;
    let tr = verilator_enc::<K>("enc_first", &first.b, cycles, &rig, &first.pins);
    let dev = dev_of(&first.b, &tr, first.stalled_dev);
    assert!(dev > ENC_TOL as i32, "the stall left a deviation of {dev} counts, within the tolerance");
    let n = ((dev as i64 * 65_536 + rig.ratio_q16() as i64 / 2) / rig.ratio_q16() as i64) as i32;
    let s = enc_script(&rig, Some(n));
    let cycles = cycles_after(&s.b, 2_000);
    let tr = verilator_enc::<K>("enc", &s.b, cycles, &rig, &s.pins);
    let b = &s.b;
    let v = |id| b.value(&tr, id).expect("read returned x");
    let refused = |code: EncRefusal| 1 | (code.code() as u16) << 4;

    // Configuration.
    assert_eq!((v(s.r_filter.0), v(s.r_filter.1)), (refused(EncRefusal::Filter), 0), "ENC_FILTER = 16 is refused");
    assert_eq!((v(s.r_axis.0), v(s.r_axis.1)), (refused(EncRefusal::Axis), 0), "ENC_AXIS = K is refused");
    assert_eq!(v(s.r_ratio0), refused(EncRefusal::Ratio), "a ratio of 0 is refused");
    assert_eq!(v(s.r_ratio_big), refused(EncRefusal::Ratio), "a ratio above the maximum is refused");
    let q = rig.ratio_q16();
    assert_eq!((v(s.r_back.0), v(s.r_back.1), v(s.r_back.2), v(s.r_back.3)), (q as u16, (q >> 16) as u16, ENC_TOL, 0), "the ratio and tolerance read back");
    assert_eq!((v(s.r_default.0), v(s.r_default.1), v(s.r_default.2)), (0, 1, 0), "an axis never written: ratio 1.0, tolerance 0");
    assert_eq!((v(s.r_enabled.0), v(s.r_enabled.1), v(s.r_enabled.2)), (refused(EncRefusal::Enabled), 2, 0), "a configuration write while enabled is refused; the ratio reads 0");

    // Out and back: exact counts, no deviation, the index latched, no illegal count.
    let out = [v(s.out[0]), v(s.out[1]), v(s.out[2]), v(s.out[3])];
    assert_eq!(((out[1] as u32) << 16 | out[0] as u32) as i32, rig.counts(3_200) as i32, "ENC_COUNT after 3,200 steps");
    assert_eq!(((out[3] as u32) << 16 | out[2] as u32) as i32, 0, "ENC_DEV after 3,200 steps");
    let idx: Vec<u16> = s.out_idx.iter().map(|&r| v(r)).collect();
    assert_eq!(((idx[1] as u32) << 16 | idx[0] as u32) as i32, rig.index_at, "ENC_INDEX: the count at the index");
    // The first step whose counts reach the index's (the motor's counts follow within
    // a few ticks, the steps are ENC_PERIOD apart).
    let at_index_steps = (0..).find(|&k| rig.counts(k) >= rig.index_at as i64).unwrap();
    assert_eq!(((idx[5] as u32) << 16 | idx[4] as u32) as i32 as i64, at_index_steps, "ENC_INDEX_POS: the step position at the index");
    assert_eq!(idx[2] & 0b110, 0b100, "IRQ_ENC: INDEX, no ILLEGAL");
    assert_eq!(idx[3] & 0xFF, 0, "ENC_STATE.ILLEGAL: bounce shorter than the filter is no fault");
    assert_eq!(idx[3] >> 15, 1, "ENC_STATE.VALID");
    assert_eq!(idx[3] >> 9 & 1, 1, "ENC_STATE.DIR after moving up");
    let back = [v(s.back[0]), v(s.back[1]), v(s.back[2]), v(s.back[3])];
    assert_eq!(((back[1] as u32) << 16 | back[0] as u32) as i32, rig.counts(1_600) as i32, "ENC_COUNT after the reversal");
    assert_eq!(((back[3] as u32) << 16 | back[2] as u32) as i32, 0, "ENC_DEV after the reversal");
    assert_eq!((v(s.back_state[0]) & 0xFF, v(s.back_state[0]) >> 9 & 1, v(s.back_state[1]), v(s.back_state[2])), (0, 0, 0, 0), "ENC_STATE, ENC_FAIL, IRQ_ENC after the reversal");
    assert_eq!(position(b, &tr, s.back_pos), Some(1_600));

    // The stall: ENC_FAIL on the step that crossed the tolerance, and the stop.
    let e0 = s.t_stall.div_ceil(tick);
    let r = rises(&tr, 0);
    // The motor's position when it stalled: 1,600 and the third move's steps before it.
    let before = 1_600 + r.iter().filter(|&&c| c < e0).count() as i64 - 4_800;
    let after: Vec<u64> = r.iter().copied().filter(|&c| c >= e0 && c < s.t_correct / tick).collect();
    let stalled_counts = rig.counts(before);
    assert_eq!(count0_at(&tr, e0 + 1_000) as i64, stalled_counts, "the rig's count at the stall");
    let crossing = (1..).find(|&k| rig.counts(before + k) - stalled_counts > ENC_TOL as i64).unwrap();
    assert_eq!(after.len() as i64, crossing, "STEP edges after the stall: the axis stops on the step that crosses the tolerance");
    let (fail, irq_enc, busy) = (v(s.stalled[0]), v(s.stalled[1]), v(s.stalled[2]));
    assert_eq!((fail, irq_enc & 1, busy & 1), (1, 1, 0), "ENC_FAIL, IRQ_ENC.FAIL and BUSY after the stall");
    assert!(irq_edges(&tr).0.iter().any(|&c| c > *after.last().unwrap() && c < after.last().unwrap() + 200), "the irq line rose for IRQ_ENC.FAIL");
    let pos = position(b, &tr, s.stalled_pos).unwrap();
    assert_eq!(pos as i64, before + after.len() as i64, "position against the edges emitted");
    assert_eq!(dev as i64, rig.counts(pos as i64) - stalled_counts, "ENC_DEV after the stop");

    // The correction: the encoder where the steps commanded before it put the motor.
    let (cr, cpos, cfail) = s.corrected.unwrap();
    assert_eq!(v(cfail), 0, "ENC_FAIL after the align, the clear and the correction");
    let cnt = ((v(cr[1]) as u32) << 16 | v(cr[0]) as u32) as i32;
    assert!((cnt as i64 - rig.counts(pos as i64)).abs() <= 1, "after the correction the encoder reads {cnt}, the commanded position is {} counts", rig.counts(pos as i64));
    assert_eq!(position(b, &tr, cpos), Some(pos + n), "the correction moved {n} steps");
    assert_eq!(((v(cr[3]) as u32) << 16 | v(cr[2]) as u32) as i32, 0, "ENC_DEV after the correction (aligned)");

    // The slip: ENC_FAIL and the stop within the latency the docs give.
    let e_slip = s.t_slip.div_ceil(tick);
    let last = *r.last().unwrap();
    // The rig's lines reach a deviation above the tolerance within (TOL + 1) counts
    // (steps only add to it), each count through the synchroniser and filter, seen
    // by the next visit (K + 1 ticks), ENC_FAIL within K + FOLLOW_ERR_LATENCY, and the
    // stop at once.
    let bound = e_slip + 2 + (ENC_TOL as u64 + 1) * rig.gap as u64 + pin_to_level_ticks(2) + (K as u64 + 1) + K as u64 + FOLLOW_ERR_LATENCY + 1;
    assert!(last > e_slip - 2 * ENC_PERIOD as u64 && last <= bound, "last STEP edge at {last}: slip at {e_slip}, bound {bound}");
    assert_eq!((v(s.slipped[0]), v(s.slipped[1]) & 1), (1, 0), "ENC_FAIL and BUSY after the slip");
}

/// ENC_FAIL with ENC_STOP_MODE.CONTROLLED (an export with the machine I/O and the
/// encoders, in Verilator against the rig's motors): the mode reads back and is refused
/// while enabled; a stall in the cruise trips ENC_FAIL on the step that crosses the
/// tolerance, and the axis ramps down at STOP_DECEL from its speed (every edge the
/// model's cut of the move with a stop ramp), not at once; at rest ENC_FAIL and
/// IRQ_ENC.FAIL are set, the axis is idle and its position is the edges emitted.
#[test]
fn a_stall_with_the_controlled_stop_ramps_the_axis_down() {
    use tdm_stepper::model::encoder::EncRefusal;
    use tdm_stepper::model::planner;
    const K: usize = 2;
    let rig = tdm_stepper::verify::encoder::RigConfig { io: true, ..Default::default() };
    let tick = 2 * CLOCKS.clk_half_ps;
    let limits = Limits::default();
    let decel: u32 = 0xF000_0000;
    let mut b = bus();
    let q = rig.ratio_q16();
    b.write_reg("ENC_RATIO_LO", 0, q as u16);
    b.write_reg("ENC_RATIO_HI", 0, (q >> 16) as u16);
    b.write_reg("ENC_TOL", 0, ENC_TOL);
    b.write_reg("ENC_FILTER", 0, 2);
    b.write_reg("ENC_STOP", 0, 0b01);
    b.write_reg("ENC_STOP_MODE", 0, 1);
    let mode = b.read_reg("ENC_STOP_MODE", 0);
    b.write_reg("STOP_DECEL_LO", 0, decel as u16);
    b.write_reg("STOP_DECEL_HI", 0, (decel >> 16) as u16);
    b.write_reg("IRQ_MASK_ENC", 0, 0b001);
    b.enable(ENABLE_WAIT);
    b.write_reg("IO_CMD", 0, 1);
    b.write_reg("ENC_STOP_MODE", 0, 0);
    let mode_enabled = (b.read_reg("ENC_STATUS", 0), b.read_reg("ENC_STOP_MODE", 0));
    b.write_reg("ENC_STATUS", 0, 1);
    b.write_reg("ENC_ALIGN", 0, 0b01);
    b.idle(200);
    // 240 steps: accelerate, cruise at 250 ticks a step, decelerate; the stall at the
    // cruise's 100th edge or so.
    let m = planner::trapezoid_by_ticks(240, [20_000, 40_000, 20_000], &limits).unwrap();
    let run = AxisRun::run(&m, &limits);
    for seg in &m {
        b.push_segment(0, seg);
    }
    b.idle(10);
    let t_start = b.now_ps();
    b.write_reg("START", 0, 0b01);
    let t_stall = t_start + run.edge_ticks[100] * tick;
    let pins = vec![(t_stall, vec![1u128, 0, 1])];
    b.idle_until_ps(t_start + (run.edge_ticks.last().unwrap() + 200_000) * tick);
    let rest = (b.read_reg("ENC_FAIL", 0), b.read_reg("IRQ_ENC", 0), b.read_reg("STATUS", 0), b.read_position(0));
    let cycles = cycles_after(&b, 100);
    let tr = verilator_enc::<K>("enc_controlled_stop", &b, cycles, &rig, &pins);
    let v = |id| b.value(&tr, id).expect("read returned x");

    assert_eq!(v(mode), 1, "ENC_STOP_MODE reads back");
    let refused = 1 | (EncRefusal::Enabled.code() as u16) << 4;
    assert_eq!((v(mode_enabled.0), v(mode_enabled.1)), (refused, 1), "ENC_STOP_MODE is refused while enabled");
    let r: Vec<u64> = rises(&tr, 0).into_iter().filter(|&c| c >= clk_cycle_at(t_start)).collect();
    let e0 = t_stall.div_ceil(tick);
    let before = r.iter().filter(|&&c| c < e0).count() as i64;
    let crossing = (1..).find(|&k| rig.counts(before + k) - rig.counts(before) > ENC_TOL as i64).unwrap();
    let emitted = (before + crossing) as usize;
    assert!(r.len() > emitted + 2, "a ramp, not the hard stop: {} edges, the tolerance crossed at edge {emitted}", r.len());
    let cut = the_stop_ramp("Verilator", &r, &run, emitted, decel);
    let (fail, irq_enc, st, pos) = rest;
    assert_eq!((v(fail), v(irq_enc) & 1), (1, 1), "ENC_FAIL and IRQ_ENC.FAIL at rest");
    assert_eq!(v(st) & 0x13F, 0, "the axis idle, nothing queued, no error");
    assert_eq!(position(&b, &tr, pos), Some(cut.position as i32), "the position at rest is the edges emitted");
    assert_eq!(cut.position, r.len() as i64, "the edges are all up");
}

/// The encoder top's registers in rust-hdl and in Verilator on one script, the encoder
/// pins driven by the script (no motor): a refusal, ratio, tolerance and stop written
/// while disabled; 24 counts up at one every 10 ticks with an index at the tenth, bounce
/// on A shorter than the filter; ENC_COUNT, ENC_INDEX, ENC_DEV (the position 0 against
/// 24 counts), ENC_FAIL and IRQ_ENC; ENC_ALIGN and ENC_CLEAR; then a move with the
/// lines still: the deviation grows 1.25 counts a step and ENC_STOP stops the axis on
/// the step that takes it above the tolerance. Both traces are equal, and say so.
#[test]
fn encoder_registers_rust_hdl_equals_verilator() {
    const K: usize = 2;
    const TOL: u16 = 6;
    let tick = 2 * CLOCKS.clk_half_ps;
    let mut b = bus();
    let mut pins: Vec<(u64, Vec<u128>)> = Vec::new();
    b.write_reg("ENC_FILTER", 0, 16);
    let refused = b.read_reg("ENC_STATUS", 0);
    b.write_reg("ENC_STATUS", 0, 1);
    b.write_reg("ENC_FILTER", 0, 2);
    b.write_reg("ENC_RATIO_LO", 0, 0x4000);
    b.write_reg("ENC_RATIO_HI", 0, 1);
    b.write_reg("ENC_TOL", 0, TOL);
    b.write_reg("ENC_STOP", 0, 0b01);
    b.write_reg("IRQ_MASK_ENC", 0, 0b001);
    b.enable(ENABLE_WAIT);
    b.idle(100);
    let quad = [(0u128, 0u128), (1, 0), (1, 1), (0, 1)];
    let mut t = b.now_ps();
    for i in 1..=24usize {
        t += 10 * tick;
        let (a, bb) = quad[i % 4];
        pins.push((t, vec![a, bb, (i == 10) as u128]));
        // A one-tick glitch on A three ticks later (the filter is 2).
        pins.push((t + 3 * tick, vec![a ^ 1, bb, (i == 10) as u128]));
        pins.push((t + 4 * tick, vec![a, bb, (i == 10) as u128]));
    }
    b.idle_until_ps(t + 300 * tick);
    let counted = [
        b.read_reg("ENC_COUNT_LO", 0),
        b.read_reg("ENC_COUNT_HI", 0),
        b.read_reg("ENC_INDEX_LO", 0),
        b.read_reg("ENC_INDEX_HI", 0),
        b.read_reg("ENC_DEV_LO", 0),
        b.read_reg("ENC_DEV_HI", 0),
        b.read_reg("ENC_FAIL", 0),
        b.read_reg("IRQ_ENC", 0),
        b.read_reg("ENC_STATE", 0),
    ];
    b.write_reg("ENC_ALIGN", 0, 0b01);
    b.write_reg("ENC_CLEAR", 0, 0b01);
    b.write_reg("IRQ_ENC", 0, 0b111);
    b.idle(100);
    let aligned = [b.read_reg("ENC_FAIL", 0), b.read_reg("ENC_DEV_LO", 0), b.read_reg("ENC_DEV_HI", 0), b.read_reg("IRQ_ENC", 0)];
    b.push_segment(0, &uniform(20 * 400, 20));
    b.write_reg("START", 0, 0b01);
    // An index pulse (20 ticks) while the axis steps, the lines still: the index
    // position takes the step position then.
    let t_z = b.now_ps() + 1_300 * tick;
    pins.push((t_z, vec![0, 0, 1]));
    pins.push((t_z + 20 * tick, vec![0, 0, 0]));
    b.idle_until_ps(b.now_ps() + (20 * 400 + 1_000) * tick);
    let stopped = [b.read_reg("ENC_FAIL", 0), b.read_reg("BUSY", 0), b.read_reg("IRQ_ENC", 0)];
    let pos = b.read_position(0);
    let index_pos = [b.read_reg("ENC_INDEX_POS_LO", 0), b.read_reg("ENC_INDEX_POS_HI", 0), b.read_reg("ENC_INDEX_LO", 0), b.read_reg("ENC_INDEX_HI", 0)];
    let cycles = cycles_after(&b, 50);

    let (events, index) = tdm_stepper::verify::bus::with_extra_inputs(b.events(), &[0, 0, 0], &pins);
    let mut u = TdmStepperEnc::<K, R, DEPTH, QDEPTH>::new(CoreParams { encoder: true, ..params::<K>() });
    u.connect_ports();
    let t0 = std::time::Instant::now();
    let mut rh = tdm_stepper::verify::bus::run_stepper_enc_rust_hdl(&mut u, &CLOCKS, &events, cycles);
    eprintln!("rust-hdl: {cycles} clk cycles of the encoder top in {:.1} s", t0.elapsed().as_secs_f64());
    samples_to_bus_events(&mut rh, &index);
    let opts = tdm_stepper::export::ExportOptions { axes: K, encoder: true, ..Default::default() };
    let verilog = tdm_stepper::export::verilog(&opts).unwrap();
    let enc = [("enc_a", K), ("enc_b", K), ("enc_z", K)];
    let vt = verilator_with_pins("enc_regs_three_ways", &verilog, tdm_stepper::export::TOP_MODULE, stepper_watch(K), &enc, &b, cycles, &[0, 0, 0], &pins);

    for (sim, tr) in [("rust-hdl", &rh), ("Verilator", &vt)] {
        let v = |id| b.value(tr, id).unwrap_or_else(|| panic!("{sim}: read returned x"));
        let word = |lo, hi| ((v(hi) as u32) << 16 | v(lo) as u32) as i32;
        assert_eq!(v(refused), 1 | 2 << 4, "{sim}: ENC_FILTER = 16 refused, code 2");
        assert_eq!(word(counted[0], counted[1]), 24, "{sim}: ENC_COUNT");
        assert_eq!(word(counted[2], counted[3]), 10, "{sim}: ENC_INDEX, the count at the index");
        assert_eq!(word(counted[4], counted[5]), -24, "{sim}: ENC_DEV, position 0 against 24 counts");
        assert_eq!((v(counted[6]), v(counted[7])), (1, 0b101), "{sim}: ENC_FAIL; IRQ_ENC FAIL and INDEX, no ILLEGAL");
        assert_eq!(v(counted[8]) & 0xFF, 0, "{sim}: no illegal transition (the glitch is shorter than the filter)");
        assert_eq!((v(aligned[0]), word(aligned[1], aligned[2]), v(aligned[3])), (0, 0, 0), "{sim}: after ENC_ALIGN and ENC_CLEAR");
        let crossing = (1..).find(|&k: &i64| (k * 5) >> 2 > TOL as i64).unwrap();
        assert_eq!(position(&b, tr, pos), Some(crossing as i32), "{sim}: the stop on the step that crosses the tolerance");
        assert_eq!((v(stopped[0]), v(stopped[1]) & 1, v(stopped[2]) & 1), (1, 0, 1), "{sim}: ENC_FAIL, BUSY, IRQ_ENC.FAIL after the stop");
        // The steps before the pulse's latch (2 synchroniser + 2 filter ticks after the
        // pin), none near it.
        let z_cycle = clk_cycle_at(t_z) + 4;
        let r = rises(tr, 0);
        assert!(r.iter().all(|&c| c.abs_diff(z_cycle) > 8), "{sim}: a step edge next to the index pulse: {r:?} against {z_cycle}");
        let before = r.iter().filter(|&&c| c < z_cycle).count() as i32;
        assert!(before >= 2 && (before as i64) < crossing, "{sim}: the pulse falls within the move ({before} steps before it)");
        assert_eq!(word(index_pos[0], index_pos[1]), before, "{sim}: ENC_INDEX_POS, the step position at the second index");
        assert_eq!(word(index_pos[2], index_pos[3]), 24, "{sim}: ENC_INDEX, the count at the second index (the lines still)");
    }
    let strip = |t: &SystemTrace| -> SystemTrace {
        let from = clk_cycle_at(b.events()[2].time_ps) + 10;
        SystemTrace { changes: t.changes.iter().filter(|c| c.0 >= from).cloned().collect(), samples: t.samples.clone(), probes: vec![] }
    };
    assert_eq!(strip(&rh), strip(&vt), "rust-hdl and Verilator traces differ");
}
