//! Whole-system runs: the exported `tdm_stepper` with three unrelated clocks.
//!
//! `clk` (the core clock), `bus_clk` (the slave's sampling clock) and the MCU's own
//! clock, at which the bus model changes the EXMC pins. Times are in picoseconds.
//! So that no two edges ever coincide (whose order two simulators could resolve
//! differently), `clk` edges fall on times ≡ 0, `bus_clk` edges on times ≡ 1 and bus
//! events on times ≡ 2 (mod 3): both half periods must be multiples of 3.
//!
//! [`run_system`] runs the exported Verilog in Verilator; [`run_system_rust_hdl`]
//! runs the same schedule on the rust-hdl block. Both return the watched outputs at
//! every `clk` cycle where they change (sampled before the rising edge, as
//! [`super::run_sparse`] does) and the value of the sampled output at every event
//! flagged `sample` (taken just before that event changes the inputs, as an MCU
//! samples the data at the end of a read strobe).

use super::tb::{hex_lines, parse_value, tool, write_file, Change, Port};
use rust_hdl::prelude::*;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The two clocks of the device, in picoseconds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Clocks {
    pub clk_half_ps: u64,
    pub bus_half_ps: u64,
}

impl Clocks {
    pub fn check(&self) {
        assert!(self.clk_half_ps % 3 == 0 && self.clk_half_ps > 0, "clk half period must be a multiple of 3 ps");
        assert!(self.bus_half_ps % 3 == 0 && self.bus_half_ps > 0, "bus_clk half period must be a multiple of 3 ps");
    }
    /// Time of the falling edge that ends `clk` cycle `n` (cycle 0 ends at the first).
    pub fn clk_fall_ps(&self, n: u64) -> u64 {
        self.clk_half_ps * (2 * n + 1)
    }
}

/// Interface of the device: inputs driven by the bus events, outputs watched in
/// `clk` cycles, and the output sampled at flagged events.
#[derive(Clone, Debug)]
pub struct SystemSpec {
    /// Name of the device's module (`top` from rust-hdl, `tdm_stepper` exported).
    pub module: String,
    pub inputs: Vec<Port>,
    pub watch: Vec<Port>,
    pub sample: Port,
}

/// A VCD of a window of `clk` cycles, with named probes: (name, width, Verilog
/// expression inside the testbench, e.g. `dut.step[0]`). The testbench logs a probe
/// line whenever a probe changes (sampled once per `clk` cycle, like the watched
/// outputs) and [`write_vcd`] writes only those changes, so the file stays small.
#[derive(Clone, Debug)]
pub struct VcdOptions {
    pub path: std::path::PathBuf,
    pub window_cycles: (u64, u64),
    pub probes: Vec<(String, usize, String)>,
}

/// Optional parts of a Verilator run.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    pub vcd: Option<VcdOptions>,
    /// Print a progress bar on stderr.
    pub progress: bool,
    /// Pause `bus_clk` where the bus rests longer than this (ps), for speed.
    pub pause_idle_bus_ps: Option<u64>,
    /// A folder of finished simulators named by their build stamp, shared by run
    /// folders: a run whose design, testbench and main loop are there already runs
    /// that simulator instead of building its own, and a run that builds adds its
    /// simulator. The test suites share one across their run folders (the same core
    /// is built once, not once per test).
    pub build_cache: Option<PathBuf>,
}

/// Windows [start, end) in which `bus_clk` may pause: gaps between bus events
/// longer than `min_gap_ps`, less `margin` (20 µs, hundreds of status round trips)
/// at each end. Only the bus clock pauses; `clk`, and so every STEP and DIR edge,
/// runs on. The status mirror and the irq line catch up within the margin, before
/// the next access. [`run_system_rust_hdl`] takes the same windows.
pub fn bus_pauses(events: &[BusEvent], min_gap_ps: u64) -> Vec<(u64, u64)> {
    const MARGIN_PS: u64 = 20_000_000;
    let min_gap = min_gap_ps.max(4 * MARGIN_PS);
    events
        .windows(2)
        .filter(|w| w[1].time_ps - w[0].time_ps > min_gap)
        .map(|w| (w[0].time_ps + MARGIN_PS, w[1].time_ps - MARGIN_PS))
        .collect()
}

/// The next bus_clk edge at or after `next`, skipping a pause window by whole
/// periods (so the clock's phase and level are kept).
fn skip_pause(next: u64, half: u64, pauses: &[(u64, u64)]) -> u64 {
    match pauses.iter().find(|p| next >= p.0 && next < p.1) {
        Some(&(_, end)) => next + (end - next).div_ceil(2 * half) * 2 * half,
        None => next,
    }
}

/// One change of the inputs, at `time_ps` (≡ 2 mod 3).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BusEvent {
    pub time_ps: u64,
    pub inputs: Vec<u128>,
    /// Record the sampled output just before this event.
    pub sample: bool,
}

/// What a run produced.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SystemTrace {
    /// Watched outputs, at `clk` cycle 0 and at every cycle they change.
    pub changes: Vec<Change>,
    /// (event index, sampled value) for every flagged event.
    pub samples: Vec<(usize, Option<u128>)>,
    /// VCD probes, in the window, at its first cycle and whenever they change.
    pub probes: Vec<Change>,
}

fn check_events(events: &[BusEvent], spec: &SystemSpec) {
    assert!(!events.is_empty() && events[0].time_ps == 2, "the first event must be at 2 ps");
    assert!(events.windows(2).all(|w| w[0].time_ps + 3 < w[1].time_ps), "events must be in increasing time, > 3 ps apart");
    assert!(events.iter().all(|e| e.time_ps % 3 == 2), "event times must be ≡ 2 (mod 3)");
    assert!(events.iter().all(|e| e.inputs.len() == spec.inputs.len()), "event width");
}

/// Room for this many bus events in the testbench: a power of two, at least 4,096, so
/// that runs of similar length share one Verilator build (see [`build_verilator`]).
fn event_capacity(n_events: usize) -> usize {
    n_events.next_power_of_two().max(4096)
}

/// The three-clock testbench. What varies from run to run (the number of cycles, the
/// VCD window) is read from plusargs, so the same text (and build) serves every run
/// of a design with as many events.
fn testbench(spec: &SystemSpec, n_events: usize, vcd: Option<&VcdOptions>) -> String {
    let cap = event_capacity(n_events);
    let mut v = String::from("// Generated by tdm_stepper::verify::system. Do not edit.\n");
    v.push_str("module tb(input clk, input bus_clk, input ev_tick);\n");
    let probes = vcd.map_or(&[][..], |o| &o.probes[..]);
    for (k, (_, width, expr)) in probes.iter().enumerate() {
        let _ = writeln!(v, "  wire [{}:0] p_{k} = {expr};\n  reg [{0}:0] lastp_{k};", width - 1);
    }
    for p in &spec.inputs {
        let _ = writeln!(v, "  reg [{}:0] ev_{} [0:{}];\n  reg [{0}:0] in_{1};", p.width - 1, p.name, cap - 1);
    }
    let _ = writeln!(v, "  reg [0:0] ev_sample [0:{}];", cap - 1);
    // Outputs are o_<name>, so that VCD probes may take the plain names.
    for p in spec.watch.iter().chain([&spec.sample]) {
        let _ = writeln!(v, "  wire [{}:0] o_{};", p.width - 1, p.name);
    }
    for p in &spec.watch {
        let _ = writeln!(v, "  reg [{}:0] last_{};", p.width - 1, p.name);
    }
    v.push_str("  reg [63:0] cyc;\n  reg [63:0] last_cyc;\n  reg [63:0] w0;\n  reg [63:0] w1;\n  integer ev;\n  integer fd;\n");
    v.push_str("  initial begin\n    cyc = 0;\n    ev = 1;\n    last_cyc = 0;\n    w0 = 0;\n    w1 = 0;\n");
    v.push_str("    if (!$value$plusargs(\"last_cyc=%d\", last_cyc)) $fatal(1, \"+last_cyc= missing\");\n");
    v.push_str("    if ($value$plusargs(\"w0=%d\", w0)) begin end\n    if ($value$plusargs(\"w1=%d\", w1)) begin end\n");
    for p in &spec.inputs {
        let _ = writeln!(v, "    $readmemh(\"ev_{0}.hex\", ev_{0});\n    in_{0} = ev_{0}[0];", p.name);
    }
    v.push_str("    $readmemh(\"ev_sample.hex\", ev_sample);\n    fd = $fopen(\"out.txt\", \"w\");\n  end\n");
    let mut conns = vec![".clk(clk)".to_string(), ".bus_clk(bus_clk)".to_string()];
    conns.extend(spec.inputs.iter().map(|p| format!(".{0}(in_{0})", p.name)));
    conns.extend(spec.watch.iter().chain([&spec.sample]).map(|p| format!(".{0}(o_{0})", p.name)));
    let _ = writeln!(v, "  {} dut({});", spec.module, conns.join(", "));
    // Bus events: sample first, then change the inputs.
    let _ = writeln!(v, "  always @(posedge ev_tick) begin");
    let _ = writeln!(v, "    if (ev_sample[ev]) $fwrite(fd, \"R %0d %h\\n\", ev, o_{});", spec.sample.name);
    for p in &spec.inputs {
        let _ = writeln!(v, "    in_{0} = ev_{0}[ev];", p.name);
    }
    v.push_str("    ev = ev + 1;\n  end\n");
    let changed: Vec<String> = spec.watch.iter().map(|p| format!("(o_{0} !== last_{0})", p.name)).collect();
    let fmt = vec!["%h"; spec.watch.len()].join(" ");
    let args: Vec<String> = spec.watch.iter().map(|p| format!("o_{}", p.name)).collect();
    v.push_str("  always @(negedge clk) begin\n");
    let _ = writeln!(v, "    if ((cyc == 0) || {}) $fwrite(fd, \"C %0d {fmt}\\n\", cyc, {});", changed.join(" || "), args.join(", "));
    if vcd.is_some_and(|o| !o.probes.is_empty()) {
        let changed: Vec<String> = (0..probes.len()).map(|k| format!("(p_{k} !== lastp_{k})")).collect();
        let fmt = vec!["%h"; probes.len()].join(" ");
        let args: Vec<String> = (0..probes.len()).map(|k| format!("p_{k}")).collect();
        let _ = writeln!(
            v,
            "    if ((cyc >= w0) && (cyc < w1) && ((cyc == w0) || {0})) $fwrite(fd, \"P %0d {fmt}\\n\", cyc, {1});",
            changed.join(" || "),
            args.join(", ")
        );
        for k in 0..probes.len() {
            let _ = writeln!(v, "    lastp_{k} = p_{k};");
        }
    }
    for p in &spec.watch {
        let _ = writeln!(v, "    last_{0} = o_{0};", p.name);
    }
    v.push_str("    if (cyc == last_cyc) begin $fclose(fd); $finish; end\n");
    v.push_str("    cyc = cyc + 1;\n  end\nendmodule\n");
    v
}

/// The Verilator main loop. Clock half periods, the length and the progress bar come
/// from plusargs (`+hc= +hb= +cycles= +progress=`, see [`run_args`]), so the build is
/// the same for every run of a design.
fn verilator_main() -> String {
    String::from(
        r#"// Generated by tdm_stepper::verify::system. Do not edit.
#include "Vtb.h"
#include "verilated.h"
#include <cstdio>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>
static unsigned long long plusarg(VerilatedContext* ctx, const char* name) {
    std::string m = ctx->commandArgsPlusMatch(name);
    if (m.empty()) { fprintf(stderr, "missing +%s\n", name); exit(2); }
    return strtoull(m.c_str() + 1 + strlen(name), 0, 10);
}
int main(int argc, char** argv) {
    std::vector<uint64_t> ev;
    FILE* f = fopen("ev_times.txt", "r");
    unsigned long long t;
    while (f && fscanf(f, "%llu", &t) == 1) ev.push_back(t);
    if (f) fclose(f);
    VerilatedContext* ctx = new VerilatedContext;
    ctx->commandArgs(argc, argv);
    Vtb* top = new Vtb{ctx};
    const uint64_t HC = plusarg(ctx, "hc="), HB = plusarg(ctx, "hb=");
    uint64_t next_c = HC, next_b = 1 + HB;   // clk starts high at 0, bus_clk high at 1
    size_t k = 1;                            // event 0 is applied by the testbench's initial block
    uint64_t tick_low = UINT64_MAX;
    top->clk = 1; top->bus_clk = 1; top->ev_tick = 0;
    const uint64_t END_PS = 2 * HC * plusarg(ctx, "cycles=");
    std::vector<uint64_t> ps0, ps1;
    FILE* pf = fopen("pauses.txt", "r");
    unsigned long long a0, a1;
    while (pf && fscanf(pf, "%llu %llu", &a0, &a1) == 2) { ps0.push_back(a0); ps1.push_back(a1); }
    if (pf) fclose(pf);
    size_t pk = 0;
    const int PROGRESS = (int)plusarg(ctx, "progress=");
    int shown = -1;
    top->eval();
    while (!ctx->gotFinish()) {
        uint64_t next_e = k < ev.size() ? ev[k] : UINT64_MAX;
        uint64_t now = next_c;
        if (next_b < now) now = next_b;
        if (next_e < now) now = next_e;
        if (tick_low < now) now = tick_low;
        if (now == next_c) { top->clk = !top->clk; next_c += HC; }
        else if (now == next_b) {
            top->bus_clk = !top->bus_clk;
            next_b += HB;
            while (pk < ps0.size() && next_b >= ps1[pk]) pk++;
            if (pk < ps0.size() && next_b >= ps0[pk]) next_b += (ps1[pk] - next_b + 2 * HB - 1) / (2 * HB) * (2 * HB);
        }
        else if (now == tick_low) { top->ev_tick = 0; tick_low = UINT64_MAX; }
        else { top->ev_tick = 1; tick_low = now + 3; k++; }
        top->eval();
        if (PROGRESS) {
            int pct = (int)(100.0 * (double)now / (double)END_PS);
            if (pct != shown && pct <= 100) {
                shown = pct;
                fprintf(stderr, "\rsimulating [%-50.*s] %3d%%", pct / 2, "==================================================", pct);
                fflush(stderr);
            }
        }
    }
    if (PROGRESS) fprintf(stderr, "\n");
    top->final();
    delete top;
    delete ctx;
    return 0;
}
"#,
    )
}

fn parse_trace(out: &str) -> Result<SystemTrace, String> {
    let mut changes = Vec::new();
    let mut samples = Vec::new();
    let mut probes = Vec::new();
    for l in out.lines() {
        let mut it = l.split_whitespace();
        let kind = it.next().ok_or("empty output line")?;
        let n = it.next().ok_or("no cycle")?.parse::<u64>().map_err(|e| e.to_string())?;
        let vals = it.map(parse_value).collect::<Result<Vec<_>, _>>()?;
        match kind {
            "C" => changes.push((n, vals)),
            "R" => samples.push((n as usize, vals[0])),
            "P" => probes.push((n, vals)),
            _ => return Err(format!("simulator printed {l:?}")),
        }
    }
    Ok(SystemTrace { changes, samples, probes })
}

/// Builds the exported Verilog (module `top`) with Verilator in `dir` and runs it for
/// `cycles` cycles of `clk`.
pub fn run_system(
    dir: &Path,
    dut_verilog: &str,
    spec: &SystemSpec,
    clocks: &Clocks,
    events: &[BusEvent],
    cycles: u64,
) -> Result<SystemTrace, String> {
    run_system_with(dir, dut_verilog, spec, clocks, events, cycles, &RunOptions::default())
}

/// [`run_system`] with a VCD window and a progress bar.
pub fn run_system_with(
    dir: &Path,
    dut_verilog: &str,
    spec: &SystemSpec,
    clocks: &Clocks,
    events: &[BusEvent],
    cycles: u64,
    opts: &RunOptions,
) -> Result<SystemTrace, String> {
    clocks.check();
    check_events(events, spec);
    let tb = testbench(spec, events.len(), opts.vcd.as_ref());
    let main = verilator_main();
    let stamp = format!("{:016x}\n", fnv1a(&[dut_verilog, &tb, &main, &BUILD_FLAGS.join(" ")]));
    let built = dir.join("obj_dir/Vsim").is_file() && std::fs::read_to_string(dir.join(BUILD_STAMP)).is_ok_and(|s| s == stamp);
    if !built {
        let _ = std::fs::remove_file(dir.join(BUILD_STAMP));
        write_file(dir, "dut.v", dut_verilog)?;
        write_file(dir, "tb.v", &tb)?;
        write_file(dir, "main.cpp", &main)?;
    }
    let mut times = String::new();
    for e in events {
        let _ = writeln!(times, "{}", e.time_ps);
    }
    write_file(dir, "ev_times.txt", &times)?;
    for (k, p) in spec.inputs.iter().enumerate() {
        write_file(dir, &format!("ev_{}.hex", p.name), &hex_lines(p.width, &p.name, events.iter().map(|e| e.inputs[k])))?;
    }
    write_file(dir, "ev_sample.hex", &hex_lines(1, "sample", events.iter().map(|e| e.sample as u128)))?;
    let mut pauses = String::new();
    for (a, b) in opts.pause_idle_bus_ps.map_or(vec![], |g| bus_pauses(events, g)) {
        let _ = writeln!(pauses, "{a} {b}");
    }
    write_file(dir, "pauses.txt", &pauses)?;
    let _ = std::fs::remove_file(dir.join("out.txt"));
    let cached = opts.build_cache.as_ref().map(|c| c.join(stamp.trim())).filter(|exe| exe.is_file());
    let exe = match (built, cached) {
        (false, Some(exe)) => exe,
        _ => {
            if !built {
                build_verilator(dir)?;
                write_file(dir, BUILD_STAMP, &stamp)?;
            }
            if let Some(cache) = &opts.build_cache {
                add_to_cache(cache, stamp.trim(), &dir.join("obj_dir/Vsim"))?;
            }
            dir.join("obj_dir/Vsim")
        }
    };
    let mut run = std::process::Command::new(exe);
    run.args(run_args(clocks, cycles, opts));
    if opts.progress {
        run.stderr(std::process::Stdio::inherit());
    }
    tool(&mut run, dir, "verilator run")?;
    let out = std::fs::read_to_string(dir.join("out.txt")).map_err(|e| format!("no simulator output: {e}"))?;
    parse_trace(&out)
}

/// The build's stamp file in the run folder: the hash of everything the build reads.
/// A run whose design, testbench and main loop hash the same reuses `obj_dir/Vsim`
/// (a second `sim` of the same core and a similar move does not rebuild).
pub const BUILD_STAMP: &str = "build.stamp";

/// Verilator's options for [`build_verilator`]. The C++ is built for this machine
/// with -O3: the paper's experiment (2.5 M clk cycles) runs in about 1.5 s instead of
/// 4 s with Verilator's default -Os.
const BUILD_FLAGS: [&str; 19] = [
    "--cc", "--exe", "--build", "-j", "2", "-O3", "--x-assign", "fast", "--x-initial", "fast", "-Wno-fatal", "-Wno-lint",
    "-Wno-style", "--top-module", "tb", "-CFLAGS", "-march=native", "-MAKEFLAGS", "OPT_FAST=-O3 OPT_SLOW=-O1 OPT_GLOBAL=-O2",
];

/// Copies the simulator `exe` into `cache` as `name` unless it is there: written
/// under a name of its own and renamed, so that runs in other processes sharing the
/// cache see a whole file or none.
fn add_to_cache(cache: &Path, name: &str, exe: &Path) -> Result<(), String> {
    let dest = cache.join(name);
    if dest.is_file() {
        return Ok(());
    }
    std::fs::create_dir_all(cache).map_err(|e| format!("cannot create {}: {e}", cache.display()))?;
    let part = cache.join(format!("{name}.{}.part", std::process::id()));
    std::fs::copy(exe, &part).map_err(|e| format!("cannot copy {} to {}: {e}", exe.display(), part.display()))?;
    std::fs::rename(&part, &dest).map_err(|e| format!("cannot rename {} to {}: {e}", part.display(), dest.display()))
}

/// FNV-1a, 64 bits, over the parts (each followed by a 0 byte): a stable hash for
/// the build stamp.
fn fnv1a(parts: &[&str]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for p in parts {
        for b in p.bytes().chain([0]) {
            h ^= b as u64;
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    h
}

/// The run's plusargs: the clocks, its length, the VCD window and the progress bar.
pub fn run_args(clocks: &Clocks, cycles: u64, opts: &RunOptions) -> Vec<String> {
    let (w0, w1) = opts.vcd.as_ref().map_or((0, 0), |o| o.window_cycles);
    vec![
        format!("+hc={}", clocks.clk_half_ps),
        format!("+hb={}", clocks.bus_half_ps),
        format!("+cycles={cycles}"),
        format!("+last_cyc={}", cycles - 1),
        format!("+w0={w0}"),
        format!("+w1={w1}"),
        format!("+progress={}", opts.progress as u8),
    ]
}

/// Builds `tb.v` + `dut.v` + `main.cpp` in `dir` into `obj_dir/Vsim`.
pub fn build_verilator(dir: &Path) -> Result<(), String> {
    let mut cmd = std::process::Command::new("verilator");
    cmd.args(BUILD_FLAGS);
    cmd.args(["-o", "Vsim", "tb.v", "dut.v", "main.cpp"]);
    tool(&mut cmd, dir, "verilator build")
}

/// One edge of the three-clock schedule.
enum Edge {
    Clk(bool),
    Bus,
    Event(usize),
}

/// The same schedule in rust-hdl. `set_clocks(uut, clk, bus_clk)`, `set(uut, inputs)`,
/// `watch(uut)` and `sample(uut)` connect it to the block.
#[allow(clippy::too_many_arguments)]
pub fn run_system_rust_hdl<B: Block>(
    uut: &mut B,
    clocks: &Clocks,
    events: &[BusEvent],
    cycles: u64,
    pauses: &[(u64, u64)],
    progress: bool,
    mut set_clocks: impl FnMut(&mut B, bool, bool),
    mut set: impl FnMut(&mut B, &[u128]),
    mut watch: impl FnMut(&B) -> Vec<u128>,
    mut sample: impl FnMut(&B) -> u128,
) -> SystemTrace {
    clocks.check();
    let (hc, hb) = (clocks.clk_half_ps, clocks.bus_half_ps);
    let (mut clk, mut bus) = (true, true);
    let (mut next_c, mut next_b) = (hc, 1 + hb);
    let mut k = 1;
    let mut cyc = 0u64;
    let mut changes: Vec<Change> = Vec::new();
    let mut samples = Vec::new();
    let mut last: Option<Vec<u128>> = None;
    set(uut, &events[0].inputs);
    set_clocks(uut, clk, bus);
    assert!(simulate(uut, 100), "rust-hdl simulation did not settle");
    loop {
        let next_e = events.get(k).map_or(u64::MAX, |e| e.time_ps);
        let edge = if next_c < next_b && next_c < next_e {
            clk = !clk;
            next_c += hc;
            Edge::Clk(clk)
        } else if next_b < next_e {
            bus = !bus;
            next_b = skip_pause(next_b + hb, hb, pauses);
            Edge::Bus
        } else {
            k += 1;
            Edge::Event(k - 1)
        };
        match edge {
            Edge::Event(e) => {
                if events[e].sample {
                    samples.push((e, Some(sample(uut))));
                }
                set(uut, &events[e].inputs);
            }
            Edge::Clk(_) | Edge::Bus => set_clocks(uut, clk, bus),
        }
        assert!(simulate(uut, 100), "rust-hdl simulation did not settle");
        if let Edge::Clk(false) = edge {
            let now = watch(uut);
            if last.as_ref() != Some(&now) {
                changes.push((cyc, now.iter().map(|&v| Some(v)).collect()));
                last = Some(now);
            }
            if cyc == cycles - 1 {
                break;
            }
            cyc += 1;
            if progress && cyc % (cycles / 100).max(1) == 0 {
                let pct = (cyc * 100 / cycles) as usize;
                eprint!("\rsimulating [{:<50}] {pct:3}%", "=".repeat(pct / 2));
            }
        }
    }
    SystemTrace { changes, samples, probes: Vec::new() }
}

/// Writes the probes of a run as a VCD.
///
/// The time axis is the user's clock, exactly: the probes are sampled once per `clk`
/// cycle, and the sample of cycle c (what the registers hold after clk's rising edge
/// c, the cycle the report's `edge_cycles` name) is written at c / `clock_hz` seconds, in ps
/// when a clk period is a whole number of ps (20,000 ps at 50 MHz), else in fs,
/// each time rounded on its own (no error accumulates). The simulator's own clk half
/// period is rounded to 3 ps to keep the three clocks' edges apart; that rounding
/// does not reach the VCD.
/// A GTKWave save file for the VCD `vcd_name` (in the same folder) that opens with
/// every probe shown, grouped per axis: STEP and DIR in binary, the position as a
/// signed decimal, the FIFO and queue levels in decimal, the state in hex.
pub fn gtkw_text(vcd_name: &str, vcd: &VcdOptions) -> String {
    let mut t = format!("[*] tdm-stepper sim: open with gtkwave {vcd_name} (or this file)\n[dumpfile] \"{vcd_name}\"\n[timestart] 0\n[treeopen] tdm_stepper.\n");
    let shown = |name: &str, width: usize| if width == 1 { format!("tdm_stepper.{name}") } else { format!("tdm_stepper.{name}[{}:0]", width - 1) };
    for (name, width, _) in &vcd.probes {
        let flags = if name.starts_with("position_") {
            "@424"
        } else if name == "fsm_state" {
            "@22"
        } else if *width == 1 {
            "@28"
        } else {
            "@24"
        };
        let _ = writeln!(t, "{flags}\n{}", shown(name, *width));
    }
    t
}

pub fn write_vcd(path: &Path, vcd: &VcdOptions, trace: &SystemTrace, clock_hz: u32) -> Result<(), String> {
    let f = clock_hz as u128;
    let (unit, per_s): (&str, u128) = if 1_000_000_000_000 % f == 0 { ("1ps", 1_000_000_000_000) } else { ("1fs", 1_000_000_000_000_000) };
    let mut v = format!("$comment tdm-stepper sim: STEP, DIR, scheduler state and FIFO levels; clk {clock_hz} Hz $end\n$timescale {unit} $end\n");
    v.push_str("$scope module tdm_stepper $end\n");
    let id = |k: usize| {
        let mut s = String::new();
        let mut n = k;
        loop {
            s.push((b'!' + (n % 94) as u8) as char);
            n /= 94;
            if n == 0 {
                break s;
            }
        }
    };
    for (k, (name, width, _)) in vcd.probes.iter().enumerate() {
        if *width == 1 {
            let _ = writeln!(v, "$var wire 1 {} {name} $end", id(k));
        } else {
            let _ = writeln!(v, "$var wire {width} {} {name} [{}:0] $end", id(k), width - 1);
        }
    }
    v.push_str("$upscope $end\n$enddefinitions $end\n");
    let mut last: Vec<Option<Option<u128>>> = vec![None; vcd.probes.len()];
    for (cyc, vals) in &trace.probes {
        let _ = writeln!(v, "#{}", (*cyc as u128 * per_s + f / 2) / f);
        for (k, val) in vals.iter().enumerate() {
            if last[k] == Some(*val) {
                continue;
            }
            last[k] = Some(*val);
            let width = vcd.probes[k].1;
            let bits = match val {
                Some(x) => format!("{:0width$b}", x, width = width),
                None => "x".repeat(width),
            };
            if width == 1 {
                let _ = writeln!(v, "{bits}{}", id(k));
            } else {
                let _ = writeln!(v, "b{bits} {}", id(k));
            }
        }
    }
    std::fs::write(path, v).map_err(|e| format!("cannot write {}: {e}", path.display()))
}
