//! The whole IP core (`tdm_stepper`) driven from the MCU's side: the EXMC bus model
//! at the documented minimum timing, with the MCU clock, the bus clock and the core
//! clock all unrelated. The exported Verilog runs in Verilator; shorter forms also run
//! in rust-hdl, which must give the same trace.

mod common;

use common::*;
use rust_hdl::prelude::*;
use tdm_stepper::vectors::paper_experiment_segments;
use tdm_stepper::hdl::core::t_calc_sqrt;
use tdm_stepper::hdl::top::TdmStepper;
use tdm_stepper::model::{AxisRun, Limits, Segment};
use tdm_stepper::regs::{self, CoreParams};
use tdm_stepper::verify::bus::{position, system_spec, BusModel, BusTiming};
use tdm_stepper::verify::system::{run_system, run_system_rust_hdl, Clocks, SystemTrace};
use tdm_stepper::verify::{Port, Simulator};

const R: usize = 4;
const DEPTH: usize = 4;
const QDEPTH: usize = 16;
/// clk ≈ 50 MHz, bus_clk ≈ 100 MHz, HCLK = 168 MHz: three unrelated clocks.
const CLOCKS: Clocks = Clocks { clk_half_ps: 10_002, bus_half_ps: 5_001 };
const MCU_HALF_PS: u64 = 2_976;

fn params<const K: usize>() -> CoreParams {
    CoreParams { axes: K, clock_hz: 50_000_000, queue_depth: QDEPTH, fifo_depth: DEPTH, t_calc: t_calc_sqrt(R) }
}

fn dut<const K: usize>() -> TdmStepper<K, R, DEPTH, QDEPTH> {
    let mut u = TdmStepper::<K, R, DEPTH, QDEPTH>::new(Limits::default(), params::<K>());
    u.clk.connect();
    u.bus_clk.connect();
    u.reset.connect();
    u.ne.connect();
    u.noe.connect();
    u.nwe.connect();
    u.addr.connect();
    u.data_in.connect();
    u.connect_all();
    u
}

fn watch<const K: usize>() -> Vec<Port> {
    vec![Port::new("step", K), Port::new("dir", K), Port::new("irq", 1)]
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
    run_system(&sim_dir(name, Simulator::Verilator), &verilog, &system_spec(watch::<K>()), &CLOCKS, b.events(), cycles).unwrap()
}

fn rust_hdl<const K: usize>(b: &BusModel, cycles: u64) -> SystemTrace {
    let mut u = dut::<K>();
    run_system_rust_hdl(
        &mut u,
        &CLOCKS,
        b.events(),
        cycles,
        |u, c, bc| {
            u.clk.next = Clock::from(c);
            u.bus_clk.next = Clock::from(bc);
        },
        |u, p| {
            u.reset.next = p[0] == 1;
            u.ne.next = p[1] == 1;
            u.noe.next = p[2] == 1;
            u.nwe.next = p[3] == 1;
            u.addr.next = (p[4] as u64).into();
            u.data_in.next = (p[5] as u64).into();
        },
        |u| vec![u.step.val().to_u64() as u128, u.dir.val().to_u64() as u128, u.irq.val() as u128],
        |u| u.data_out.val().to_u64() as u128,
    )
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

/// Every axis's edges are the model's, from one common release tick (0 skew), and
/// each within 1 tick of exact kinematics. Returns the release tick.
fn check_edges(trace: &SystemTrace, axes: &[Vec<Segment>], what: &str) -> i64 {
    let mut release = None;
    for (a, segs) in axes.iter().enumerate() {
        let run = AxisRun::run(segs, &Limits::default());
        let r = rises(trace, a);
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

fn read16(b: &BusModel, t: &SystemTrace, id: tdm_stepper::verify::bus::ReadId) -> u16 {
    b.value(t, id).expect("read returned undefined bits")
}

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
    let levels: Vec<_> = (0..2).map(|a| b.read_reg("STATUS", a)).collect();
    b.write_reg("START", 0, 0b11);
    let end = AxisRun::run(&axes[0], &Limits::default()).end_tick.max(AxisRun::run(&axes[1], &Limits::default()).end_tick);
    b.idle_until_ps(b.now_ps() + (end + 5_000) * 2 * CLOCKS.clk_half_ps);
    let pos: Vec<_> = (0..2).map(|a| b.read_position(a)).collect();
    let busy = b.read_reg("BUSY", 0);
    let status: Vec<_> = (0..2).map(|a| b.read_reg("STATUS", a)).collect();
    let done: Vec<_> = (0..2).map(|a| b.read_reg("DONE_COUNT", a)).collect();
    let cycles = cycles_after(&b, 200);
    let t0 = std::time::Instant::now();
    let trace = verilator::<2>("system_paper", &b, cycles);
    eprintln!("paper experiment through the bus: {cycles} clk cycles, Verilator build + run {:.1} s", t0.elapsed().as_secs_f64());
    assert_eq!(read16(&b, &trace, magic), regs::MAGIC);
    assert_eq!(read16(&b, &trace, k), 2);
    assert_eq!(read16(&b, &trace, before) & 1, 0, "ENABLED before ENABLE");
    assert_eq!(read16(&b, &trace, enabled) & 1, 1, "not ENABLED");
    for a in 0..2 {
        let s = read16(&b, &trace, levels[a]);
        assert_eq!(s & 0x1F, 3, "axis {a}: LEVEL after three pushes");
        assert_eq!(s & 0x20, 0x20, "axis {a}: BUSY after pushes");
        assert_eq!(s & 0xFFC0, 0, "axis {a}: flags after pushes");
    }
    check_edges(&trace, &axes, "paper via bus");
    assert_eq!(position(&b, &trace, pos[0]), Some(2400));
    assert_eq!(position(&b, &trace, pos[1]), Some(1800));
    assert_eq!(read16(&b, &trace, busy), 0);
    for a in 0..2 {
        assert_eq!(read16(&b, &trace, status[a]), 0, "axis {a}: STATUS at the end");
        assert_eq!(read16(&b, &trace, done[a]), 3, "axis {a}: DONE_COUNT");
    }
}
