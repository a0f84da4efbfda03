//! Simulation and export speed: rust-hdl fast-loop cycles per second of the core
//! (K = 2 and 8), Verilator cycles per second of the exported IP on the paper's
//! experiment through the bus, and the export time for K = 16.
//! Run: `cargo bench -p tdm-stepper-bench --bench hdl`.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use rust_hdl::prelude::*;
use std::time::Duration;
use tdm_stepper::export::{self, ExportOptions, FIFO_DEPTH, QUEUE_DEPTH, RADIX_BITS};
use tdm_stepper::hdl::core::TdmCore;
use tdm_stepper::vectors::paper_experiment_segments;
use tdm_stepper::verify::bus::{system_spec, BusModel, BusTiming};
use tdm_stepper::verify::system::{run_args, run_system_with, Clocks, RunOptions};
use tdm_stepper::verify::Port;

const CYCLES: u64 = 2_000;

fn tick<B: Block>(u: &mut B, clock: impl Fn(&mut B, bool)) {
    clock(u, false);
    simulate(u, 100);
    clock(u, true);
    simulate(u, 100);
}

/// A K-axis core, reset, with the paper's segments on every axis, started.
fn running_core<const K: usize>() -> Box<TdmCore<K, RADIX_BITS, FIFO_DEPTH, QUEUE_DEPTH>> {
    let mut u = Box::new(TdmCore::<K, RADIX_BITS, FIFO_DEPTH, QUEUE_DEPTH>::new());
    u.connect_ports();
    let clk = |u: &mut TdmCore<K, RADIX_BITS, FIFO_DEPTH, QUEUE_DEPTH>, c: bool| u.clock.next = Clock::from(c);
    u.reset.next = true;
    tick(u.as_mut(), clk);
    tick(u.as_mut(), clk);
    u.reset.next = false;
    let segs = paper_experiment_segments();
    for a in 0..K {
        for s in &segs[a % 2] {
            u.cmd_valid.next = true;
            u.cmd_axis.next = (a as u64).into();
            u.cmd_v0.next = (s.v0_rate as u64).into();
            u.cmd_t.next = (s.t_ticks as u64).into();
            u.cmd_steps.next = (s.steps as u32 as u64).into();
            tick(u.as_mut(), clk);
        }
    }
    u.cmd_valid.next = false;
    u.start.next = true;
    u.start_mask.next = ((1u64 << K) - 1).into();
    tick(u.as_mut(), clk);
    u.start.next = false;
    u
}

fn rust_hdl_core(c: &mut Criterion) {
    let mut g = c.benchmark_group("rust_hdl_core");
    g.throughput(Throughput::Elements(CYCLES));
    g.sample_size(10);
    let mut u2 = running_core::<2>();
    g.bench_function("k2_cycles", |b| {
        b.iter(|| {
            for _ in 0..CYCLES {
                tick(u2.as_mut(), |u, c| u.clock.next = Clock::from(c));
            }
        })
    });
    let mut u8 = running_core::<8>();
    g.bench_function("k8_cycles", |b| {
        b.iter(|| {
            for _ in 0..CYCLES {
                tick(u8.as_mut(), |u, c| u.clock.next = Clock::from(c));
            }
        })
    });
    g.finish();
}

fn verilator_ip(c: &mut Criterion) {
    let clocks = Clocks { clk_half_ps: 10_002, bus_half_ps: 5_001 };
    let mut b = BusModel::new(BusTiming::minimum(clocks.bus_half_ps, 2_976));
    b.reset(40);
    b.enable(400);
    let axes = paper_experiment_segments();
    for (a, segs) in axes.iter().enumerate() {
        for s in segs {
            b.push_segment(a, s);
        }
    }
    b.write_reg("START", 0, 3);
    b.idle_until_ps(b.now_ps() + 2_510_000 * 2 * clocks.clk_half_ps);
    let cycles = b.now_ps() / (2 * clocks.clk_half_ps);
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("bench_verilator_paper");
    let verilog = export::verilog(&ExportOptions::default()).unwrap();
    let spec = system_spec(export::TOP_MODULE, vec![Port::new("step", 2), Port::new("dir", 2), Port::new("irq", 1)]);
    let opts = RunOptions { pause_idle_bus_ps: Some(1_000_000_000), ..Default::default() };
    // Build (and run once); the benchmark then times the runs only.
    run_system_with(&dir, &verilog, &spec, &clocks, b.events(), cycles, &opts).expect("verilator");
    let mut g = c.benchmark_group("verilator_ip");
    g.throughput(Throughput::Elements(cycles));
    g.sample_size(10);
    g.measurement_time(Duration::from_secs(20));
    g.bench_function("paper_experiment_clk_cycles", |bch| {
        bch.iter(|| {
            let out = std::process::Command::new(dir.join("obj_dir/Vsim"))
                .args(run_args(&clocks, cycles, &opts))
                .current_dir(&dir)
                .output()
                .unwrap();
            assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        })
    });
    g.finish();
}

fn export_time(c: &mut Criterion) {
    let mut g = c.benchmark_group("export");
    g.sample_size(10);
    g.bench_function("k16_verilog", |b| {
        b.iter(|| export::verilog(&ExportOptions { axes: 16, ..Default::default() }).unwrap().len())
    });
    g.finish();
}

criterion_group!(benches, rust_hdl_core, verilator_ip, export_time);
criterion_main!(benches);
