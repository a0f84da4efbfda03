//! `tdm-stepper sweep`: resources (and Fmax) of the exported IP against the axis
//! count, TDM against the non-TDM baseline, with Debian's yosys and, for Fmax,
//! nextpnr-ecp5 (yowasp, installed by `scripts/install-nextpnr.sh`, version pinned).
//!
//! Each point exports `tdm_stepper` and synthesises it (`synth_xilinx -flatten` for
//! xc7, `synth_ecp5` for ECP5), reading `stat -json`. Points run in parallel
//! (`--jobs`), each under a time limit; a failed or timed-out tool run is reported with
//! its log's path and the other points go on. Outputs: `sweep.json`, `sweep.md` (with
//! the paper's Table 1 beside ours) and SVG plots of LUT, FF and DSP against K, the
//! saving in % and the marginal cost of one more axis.
//!
//! **Axis capacity**: an axis sustains step periods down to K·t_calc ticks (TDM; the
//! underrun boundary that `tests/hdl_core.rs` measures), so its highest step rate at
//! clock f is f / (K·t_calc) ([`max_step_rate_hz`]); with `--fmax`, f is the placed
//! design's Fmax.
//!
//! Files, one per stage of a point: `synth.rs` (yosys resources), `fmax.rs` (nextpnr
//! placement, seeds, critical path), `breakdown.rs` (the per-block table),
//! `report.rs` (sweep.md, sweep.json, plots); this file holds the options, the
//! result types and [`run`], which schedules the points.

use crate::export::{self, Arch, ExportOptions};
use plotters::prelude::*;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

mod breakdown;
mod fmax;
mod report;
mod synth;

pub use breakdown::*;
pub use fmax::*;
pub use report::*;
pub use synth::*;

/// FPGA family of a synthesis run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Family {
    Xc7,
    Ecp5,
}

impl std::str::FromStr for Family {
    type Err = String;
    fn from_str(s: &str) -> Result<Family, String> {
        match s {
            "xc7" => Ok(Family::Xc7),
            "ecp5" => Ok(Family::Ecp5),
            _ => Err(format!("unknown family {s:?}: expected xc7 or ecp5")),
        }
    }
}

impl Family {
    pub fn name(self) -> &'static str {
        match self {
            Family::Xc7 => "xc7",
            Family::Ecp5 => "ecp5",
        }
    }
    fn synth(self) -> &'static str {
        match self {
            Family::Xc7 => "synth_xilinx -flatten -top tdm_stepper",
            Family::Ecp5 => "synth_ecp5 -top tdm_stepper",
        }
    }
}

/// What to sweep.
#[derive(Clone, Debug)]
pub struct SweepOptions {
    pub axes: Vec<usize>,
    pub archs: Vec<Arch>,
    pub families: Vec<Family>,
    /// Place and route on ECP5 for these axis counts (TDM).
    pub fmax_axes: Vec<usize>,
    /// Placement seeds per Fmax point (1..=seeds); the point reports the median.
    pub seeds: u32,
    /// Hierarchical xc7 synthesis of the TDM core for these axis counts: where the LUTs go.
    pub breakdown_axes: Vec<usize>,
    pub jobs: usize,
    pub timeout: Duration,
    pub out: PathBuf,
    pub work: PathBuf,
    pub clock_hz: u32,
    /// Only collect finished runs from the work folder; run no tool.
    pub cached_only: bool,
    /// Export every point with the machine I/O (`--io`; TDM only).
    pub io: bool,
    /// With `io`: the groups left out (`regs::IO_GROUPS` bits; 0 for `--io all`).
    pub io_omit: u8,
    /// Export every point with the S-curve option (`--profiles trapezoid,scurve`).
    pub scurve: bool,
    /// Export every point with encoder feedback (`--encoder`).
    pub encoder: bool,
    /// The host bus of every point (`--bus`).
    pub bus: export::Bus,
}

impl SweepOptions {
    /// Appended to the work folder of each point: runs with and without the machine I/O
    /// (and with different groups of it) keep their own folders (and cached results).
    pub(crate) fn io_suffix(&self) -> String {
        let io = match (self.io, self.io_omit) {
            (false, _) => String::new(),
            (true, 0) => "_io".into(),
            (true, omit) => format!("_io_{}", export::io_group_names(crate::regs::IO_ALL & !omit).replace(',', "_")),
        };
        let io = if self.scurve { io + "_scurve" } else { io };
        let io = if self.encoder { io + "_enc" } else { io };
        match self.bus {
            export::Bus::Exmc => io,
            b => format!("{io}_{}", b.name()),
        }
    }
}

/// Resources of one synthesis run, by kind.
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct Resources {
    /// LUTs, counting the LUTs that LUT-RAM and shift-register cells occupy
    /// ([`lut_occupancy`]): the figure a device's LUT budget is spent by.
    pub luts: u64,
    /// Of `luts`, the LUTs that LUT-RAM and SRL cells occupy.
    pub luts_in_memory: u64,
    pub ffs: u64,
    pub dsps: u64,
    pub brams: u64,
    pub lutram: u64,
    pub carry: u64,
    pub cells_by_type: BTreeMap<String, u64>,
}

/// One point of the sweep.
#[derive(Clone, Debug, Serialize)]
pub struct Point {
    pub arch: Arch,
    pub axes: usize,
    pub family: Family,
    /// "ok", "failed" or "timeout".
    pub status: String,
    pub resources: Option<Resources>,
    /// Time of this sweep's work on the point (short when a finished run was reused:
    /// `message` says so).
    pub seconds: f64,
    /// Wall time of the tool run that gave the result (from the work folder's file
    /// times: input written to result written), reused or not.
    pub tool_seconds: Option<f64>,
    pub log: PathBuf,
    pub message: Option<String>,
}

/// Place-and-route result.
#[derive(Clone, Debug, Serialize)]
pub struct FmaxPoint {
    pub axes: usize,
    pub status: String,
    /// The median over the seeds (each clock's own median).
    pub fmax_clk_mhz: Option<f64>,
    pub fmax_bus_clk_mhz: Option<f64>,
    /// nextpnr's placement seed of each run, and what each measured: the spread
    /// between seeds is placement, not design.
    pub seeds: Vec<u32>,
    pub seed_clk_mhz: Vec<f64>,
    pub seed_bus_clk_mhz: Vec<f64>,
    /// The seed of the run whose critical path and log are reported.
    pub path_seed: u32,
    pub max_step_rate_hz_at_fmax: Option<f64>,
    pub tool: String,
    /// The clk domain's critical path, from the nextpnr log.
    pub critical_path: Option<CriticalPath>,
    pub seconds: f64,
    pub tool_seconds: Option<f64>,
    pub log: PathBuf,
    pub message: Option<String>,
}

/// A critical path as nextpnr reports it.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct CriticalPath {
    pub total_ns: f64,
    pub logic_ns: f64,
    pub routing_ns: f64,
    /// The launching cell and pin, and the capturing one.
    pub from: String,
    pub to: String,
    /// Cells on the path by hierarchical block (the instance path without the cell
    /// name, cut to three levels), most first.
    pub blocks: Vec<(String, usize)>,
}

/// One block of the hierarchical synthesis (see [`block_of`]).
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Block {
    pub name: String,
    pub luts: u64,
    pub ffs: u64,
    pub dsps: u64,
    /// Block RAMs (xc7 RAMB18/36, ECP5 DP16KD), which are not LUTs.
    pub brams: u64,
    pub carry: u64,
}

/// The resources of the TDM core by block, from `synth_xilinx -flatten` with the
/// blocks kept ([`breakdown_script`]).
#[derive(Clone, Debug, Serialize)]
pub struct Breakdown {
    pub axes: usize,
    pub status: String,
    pub blocks: Vec<Block>,
    pub seconds: f64,
    pub tool_seconds: Option<f64>,
    pub log: PathBuf,
    pub message: Option<String>,
}

/// The whole result.
#[derive(Clone, Debug, Serialize)]
pub struct Sweep {
    /// The points were exported with the machine I/O (`--io`).
    pub io: bool,
    /// With `io`: the groups exported, comma-separated.
    pub io_groups: String,
    pub yosys: String,
    pub t_calc_cycles: usize,
    /// The points were exported with the S-curve option (`--profiles trapezoid,scurve`).
    pub scurve: bool,
    pub points: Vec<Point>,
    pub fmax: Vec<FmaxPoint>,
    pub breakdown: Vec<Breakdown>,
    pub capacity: Vec<Capacity>,
}

/// Highest sustained step rate per axis, and what the shared unit computes per second
/// over all axes: periods (one per t_calc) and segment setups (one per t_setup of
/// spare time; the decelerating setup, the longer one).
#[derive(Clone, Debug, Serialize)]
pub struct Capacity {
    pub axes: usize,
    pub min_period_ticks: u64,
    pub max_step_rate_hz_at_50mhz: f64,
    pub max_step_rate_hz_at_fmax: Option<f64>,
    pub fmax_mhz: Option<f64>,
    pub periods_per_s_at_50mhz: f64,
    pub periods_per_s_at_fmax: Option<f64>,
    pub t_setup_cycles: usize,
    pub setups_per_s_at_50mhz: f64,
    pub setups_per_s_at_fmax: Option<f64>,
}

/// The [`Capacity`] of K axes, with the `clk` Fmax when it was measured; with the
/// S-curve option (`scurve`) t_calc is the option's per-period budget and t_setup the
/// longest setup of either kind.
pub fn capacity(axes: usize, fmax_mhz: Option<f64>, scurve: bool) -> Capacity {
    let o = ExportOptions { axes, scurve, ..Default::default() };
    let t_calc = o.t_calc_cycles() as f64;
    let t_setup = o.longest_setup_cycles();
    Capacity {
        axes,
        min_period_ticks: o.sustainable_period_ticks(),
        max_step_rate_hz_at_50mhz: step_rate_hz(&o, 50e6),
        max_step_rate_hz_at_fmax: fmax_mhz.map(|f| step_rate_hz(&o, f * 1e6)),
        fmax_mhz,
        periods_per_s_at_50mhz: 50e6 / t_calc,
        periods_per_s_at_fmax: fmax_mhz.map(|f| f * 1e6 / t_calc),
        t_setup_cycles: t_setup,
        setups_per_s_at_50mhz: 50e6 / t_setup as f64,
        setups_per_s_at_fmax: fmax_mhz.map(|f| f * 1e6 / t_setup as f64),
    }
}

/// f / (K·t_calc): the step rate an axis sustains without underrun (TDM), with or
/// without the S-curve option.
pub fn max_step_rate_hz(axes: usize, clock_hz: f64, scurve: bool) -> f64 {
    step_rate_hz(&ExportOptions { axes, scurve, ..Default::default() }, clock_hz)
}

fn step_rate_hz(o: &ExportOptions, clock_hz: f64) -> f64 {
    clock_hz / o.sustainable_period_ticks() as f64
}

/// Runs `cmd` in `dir` with its output in `log`, killed after `timeout`.
fn run_logged(mut cmd: Command, dir: &Path, log: &Path, timeout: Duration) -> Result<(), String> {
    let f = std::fs::File::create(log).map_err(|e| format!("{}: {e}", log.display()))?;
    let f2 = f.try_clone().map_err(|e| e.to_string())?;
    let mut child = cmd
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::from(f))
        .stderr(Stdio::from(f2))
        .spawn()
        .map_err(|e| format!("cannot start {:?}: {e} (is it installed?)", cmd.get_program()))?;
    let t0 = Instant::now();
    loop {
        if let Some(st) = child.try_wait().map_err(|e| e.to_string())? {
            return if st.success() { Ok(()) } else { Err(format!("exited with {st}; see {}", log.display())) };
        }
        if t0.elapsed() > timeout {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!("timeout after {} s; see {}", timeout.as_secs(), log.display()));
        }
        std::thread::sleep(Duration::from_millis(200));
    }
}

/// The status of a run that gave error `e`: "timeout", "not_run" or "failed".
fn status_of(e: &str) -> String {
    if e.starts_with("timeout") {
        "timeout".into()
    } else if e.starts_with(NOT_RUN) {
        "not_run".into()
    } else {
        "failed".into()
    }
}

/// Seconds from writing `input` to writing `output` in `dir`: the tool run's wall time.
fn run_seconds(dir: &Path, input: &str, output: &str) -> Option<f64> {
    let t = |f: &str| std::fs::metadata(dir.join(f)).and_then(|m| m.modified()).ok();
    t(output)?.duration_since(t(input)?).ok().map(|d| d.as_secs_f64())
}

/// The message of a point whose finished run in the work folder was reused.
fn reused_note(reused: bool) -> Option<String> {
    reused.then(|| "reused the finished run in the work folder (its input is unchanged); seconds is the time to collect it".to_string())
}

const NOT_RUN: &str = "not run: no finished result in the work folder (--cached-only)";


enum Task {
    Synth(Arch, usize, Family),
    Fmax(usize, u32),
    Breakdown(usize),
}

/// The values of `v` without repeats, in the order they first appear.
pub fn unique<T: PartialEq + Copy>(v: &[T]) -> Vec<T> {
    let mut u: Vec<T> = Vec::new();
    for &x in v {
        if !u.contains(&x) {
            u.push(x);
        }
    }
    u
}

/// Runs the sweep and writes its outputs into `opts.out`. A value listed twice (say
/// `--fmax 2,2`) is one point: two tasks would share one work folder.
pub fn run(opts: &SweepOptions, repo: &Path) -> Result<(Sweep, Vec<PathBuf>), String> {
    let opts = &SweepOptions {
        axes: unique(&opts.axes),
        archs: unique(&opts.archs),
        families: unique(&opts.families),
        fmax_axes: unique(&opts.fmax_axes),
        breakdown_axes: unique(&opts.breakdown_axes),
        ..opts.clone()
    };
    for &k in &opts.axes {
        for &a in &opts.archs {
            ExportOptions { axes: k, arch: a, clock_hz: opts.clock_hz, io: opts.io, io_omit: opts.io_omit, scurve: opts.scurve, encoder: opts.encoder, bus: opts.bus, ..Default::default() }.check()?;
        }
    }
    for &k in opts.fmax_axes.iter().chain(&opts.breakdown_axes) {
        ExportOptions { axes: k, clock_hz: opts.clock_hz, io: opts.io, io_omit: opts.io_omit, scurve: opts.scurve, encoder: opts.encoder, bus: opts.bus, ..Default::default() }.check()?;
    }
    if !opts.fmax_axes.is_empty() && opts.io && opts.io_omit != 0 {
        return Err("--fmax with some machine I/O groups: the Fmax wrapper drives every group's pins; use --io all".into());
    }
    let nextpnr = nextpnr_command(repo);
    if !opts.fmax_axes.is_empty() && !nextpnr.exists() {
        return Err(format!("--fmax needs {}: run scripts/install-nextpnr.sh", nextpnr.display()));
    }
    std::fs::create_dir_all(&opts.out).map_err(|e| format!("cannot create {}: {e}", opts.out.display()))?;
    std::fs::create_dir_all(&opts.work).map_err(|e| format!("cannot create {}: {e}", opts.work.display()))?;
    let yosys = Command::new("yosys").arg("-V").output().map_err(|e| format!("yosys: {e} (is it installed?)"))?;
    let yosys = String::from_utf8_lossy(&yosys.stdout).trim().to_string();
    // Biggest first, so the long runs start early.
    let mut tasks: Vec<Task> = Vec::new();
    let mut fmax_axes = opts.fmax_axes.clone();
    fmax_axes.sort_by_key(|&k| std::cmp::Reverse(k));
    for &k in &fmax_axes {
        for seed in 1..=opts.seeds.max(1) {
            tasks.push(Task::Fmax(k, seed));
        }
    }
    for &k in opts.breakdown_axes.iter().rev() {
        tasks.push(Task::Breakdown(k));
    }
    let mut synth: Vec<(Arch, usize, Family)> = Vec::new();
    for &f in &opts.families {
        for &a in &opts.archs {
            for &k in &opts.axes {
                synth.push((a, k, f));
            }
        }
    }
    synth.sort_by_key(|&(a, k, _)| std::cmp::Reverse(if a == Arch::Baseline { 2 * k } else { k }));
    tasks.extend(synth.into_iter().map(|(a, k, f)| Task::Synth(a, k, f)));
    let total = tasks.len();
    let queue = Arc::new(Mutex::new(tasks.into_iter().rev().collect::<Vec<_>>()));
    let points = Arc::new(Mutex::new(Vec::new()));
    let fmaxes = Arc::new(Mutex::new(Vec::new()));
    let breakdowns = Arc::new(Mutex::new(Vec::new()));
    let done = Arc::new(Mutex::new(0usize));
    // One ECP5 synthesis per Fmax K, shared by its seeds.
    let synth_locks: std::collections::HashMap<usize, Mutex<()>> = opts.fmax_axes.iter().map(|&k| (k, Mutex::new(()))).collect();
    let synth_locks = &synth_locks;
    std::thread::scope(|s| {
        for _ in 0..opts.jobs.max(1) {
            let (queue, points, fmaxes, breakdowns, done) = (queue.clone(), points.clone(), fmaxes.clone(), breakdowns.clone(), done.clone());
            let nextpnr = nextpnr.clone();
            s.spawn(move || loop {
                let Some(task) = queue.lock().unwrap().pop() else { break };
                let line = match task {
                    Task::Synth(a, k, f) => {
                        let p = synth_point(a, k, f, opts);
                        let line = match &p.resources {
                            Some(r) => format!("{} {} K={k}: {} LUT, {} FF, {} DSP ({:.0} s)", f.name(), a.name(), r.luts, r.ffs, r.dsps, p.seconds),
                            None => format!("{} {} K={k}: {}: {}", f.name(), a.name(), p.status, p.message.clone().unwrap_or_default()),
                        };
                        points.lock().unwrap().push(p);
                        line
                    }
                    Task::Fmax(k, seed) => {
                        let p = fmax_point(k, seed, opts, &nextpnr, &synth_locks[&k]);
                        let line = match p.fmax_clk_mhz {
                            Some(m) => format!(
                                "fmax ecp5 tdm K={k} seed {seed}: clk {m:.1} MHz, bus_clk {} MHz ({:.0} s)",
                                p.fmax_bus_clk_mhz.map_or("—".into(), |b| format!("{b:.1}")),
                                p.seconds
                            ),
                            None => format!("fmax ecp5 tdm K={k} seed {seed}: {}: {}", p.status, p.message.clone().unwrap_or_default()),
                        };
                        fmaxes.lock().unwrap().push(p);
                        line
                    }
                    Task::Breakdown(k) => {
                        let b = breakdown_point(k, opts);
                        let line = match b.status.as_str() {
                            "ok" => format!("breakdown xc7 tdm K={k}: {} blocks ({:.0} s)", b.blocks.len(), b.seconds),
                            _ => format!("breakdown xc7 tdm K={k}: {}: {}", b.status, b.message.clone().unwrap_or_default()),
                        };
                        breakdowns.lock().unwrap().push(b);
                        line
                    }
                };
                let mut d = done.lock().unwrap();
                *d += 1;
                eprintln!("[{}/{total}] {line}", *d);
            });
        }
    });
    let mut points = Arc::try_unwrap(points).unwrap().into_inner().unwrap();
    points.sort_by_key(|p| (p.family, p.arch.name(), p.axes));
    let runs: Vec<FmaxPoint> = Arc::try_unwrap(fmaxes).unwrap().into_inner().unwrap();
    let mut fmax: Vec<FmaxPoint> = opts
        .fmax_axes
        .iter()
        .map(|&k| combine_seeds(runs.iter().filter(|r| r.axes == k).cloned().collect(), opts.scurve))
        .collect();
    fmax.sort_by_key(|p| p.axes);
    let mut breakdown = Arc::try_unwrap(breakdowns).unwrap().into_inner().unwrap();
    breakdown.sort_by_key(|b| b.axes);
    // Log paths in the outputs are relative to the repository when under it.
    let rel = |p: &mut PathBuf| {
        if let Ok(r) = p.strip_prefix(repo) {
            *p = r.to_path_buf();
        }
    };
    points.iter_mut().for_each(|p| rel(&mut p.log));
    fmax.iter_mut().for_each(|p| rel(&mut p.log));
    breakdown.iter_mut().for_each(|p| rel(&mut p.log));
    let capacity = opts.axes.iter().map(|&k| capacity(k, fmax.iter().find(|f| f.axes == k).and_then(|f| f.fmax_clk_mhz), opts.scurve)).collect();
    let sweep = Sweep { io: opts.io, io_groups: if opts.io { export::io_group_names(crate::regs::IO_ALL & !opts.io_omit) } else { String::new() }, yosys, t_calc_cycles: ExportOptions { scurve: opts.scurve, ..Default::default() }.t_calc_cycles(), scurve: opts.scurve, points, fmax, breakdown, capacity };
    let files = write_outputs(&sweep, &opts.out).map_err(|e| format!("cannot write into {}: {e}", opts.out.display()))?;
    Ok((sweep, files))
}
