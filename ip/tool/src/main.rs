//! `tdm-stepper`: the command line of the tdm-stepper IP core.
//!
//! Subcommands: `export` (the IP core), `vectors` (the JSON test vectors) and
//! `accuracy` (the accuracy report).

use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;
use tdm_stepper::export::{self, Arch, ExportOptions};
use tdm_stepper::sim::{self, Engine, SimOptions};
use tdm_stepper::sweep::{self, Family, SweepOptions};
use tdm_stepper::{accuracy, vectors};

#[derive(Parser)]
#[command(name = "tdm-stepper", version, about = "Time-division multiplexed multi-axis stepper motor IP core")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Export the IP core: tdm_stepper.v, tdm_stepper_regs.h, registers.md, manifest.json.
    Export {
        /// Number of axes K (1 to 16).
        #[arg(long, default_value_t = 2)]
        axes: usize,
        /// tdm (one shared unit) or baseline (one unit per axis; K = 1, 2, 4, 8, 16).
        #[arg(long, default_value = "tdm")]
        arch: Arch,
        /// Core clock in Hz (reported by ID_CLOCK_HZ and used for the step rate limit).
        #[arg(long, default_value_t = 50_000_000)]
        clock_hz: u32,
        /// Period FIFO depth per axis (4).
        #[arg(long, default_value_t = export::FIFO_DEPTH)]
        fifo_depth: usize,
        /// The minimum STEP period the core enforces, in clk ticks (2 to 65535). A
        /// segment whose start or end rate is above floor(2^32 / (min + 1)) is rejected
        /// with code 3. Default: the sustainable period, K·t_calc (t_calc for the
        /// baseline); a shorter one lets an axis underrun when several run fast.
        #[arg(long)]
        min_period: Option<u32>,
        /// The top module's name (a Verilog identifier); submodules are NAME__path, so
        /// cores exported under different names coexist in one design.
        #[arg(long, default_value = export::TOP_MODULE)]
        name: export::ModuleName,
        /// Machine I/O and safety: `all` adds the input pins (estop_n, probe, and per
        /// axis limit_neg, limit_pos, home, alarm), drv_enable, the e-stop latch, the
        /// watchdog, the push guard, the controlled stop and their registers; a list of
        /// groups (estop, probe, limits, home, alarm, watchdog) adds only those groups'
        /// pins, logic and registers; `none` (the default) leaves them all out at no cost.
        #[arg(long, default_value = "none", value_parser = export::parse_io, action = clap::ArgAction::Set)]
        io: export::IoChoice,
        /// Segment kinds the core runs: trapezoid, or trapezoid,scurve (the S-curve
        /// option: polynomial segments and their registers; TDM only).
        #[arg(long, default_value = "trapezoid", value_parser = export::parse_profiles, action = clap::ArgAction::Set)]
        profiles: bool,
        /// Encoder feedback: per axis the quadrature pins enc_a, enc_b and enc_z, 4x
        /// decoders with filters, index and probe latches and a reciprocal velocity, the
        /// following error by one shared multiplier with ENC_FAIL and its stop, and their
        /// registers (TDM only).
        #[arg(long)]
        encoder: bool,
        /// The host bus: exmc (EXMC / FSMC asynchronous SRAM, 16-bit; the default),
        /// spi (modes 0 and 3, SCK up to bus_clk/4), wb (Wishbone B4 classic, 32-bit)
        /// or axil (AXI4-Lite, 32-bit); docs/registers.md describes each.
        #[arg(long, default_value = "exmc")]
        bus: export::Bus,
        /// Folder to write into (created if missing).
        #[arg(long)]
        out: PathBuf,
    },
    /// Simulate a move through the EXMC bus into the exported core; write a report,
    /// an SVG beside it, and optionally a VCD.
    Sim {
        /// Number of axes K of the core (1 to 16; rust-hdl: 1, 2, 4 or 8).
        #[arg(long, default_value_t = 2)]
        axes: usize,
        /// The core's minimum period in clk ticks, as `export --min-period` (default:
        /// K·t_calc). Segments faster than it are rejected, as the exported core does.
        #[arg(long)]
        min_period: Option<u32>,
        /// The moves, per axis, in steps/s, seconds and steps (see README).
        #[arg(long)]
        moves: PathBuf,
        /// verilator (fast) or rust-hdl (the same design, about 1000 times slower).
        #[arg(long, default_value = "verilator")]
        engine: Engine,
        /// Write a VCD (GTKWave, Surfer) of STEP, DIR, the scheduler state and the FIFO levels.
        #[arg(long)]
        vcd: Option<PathBuf>,
        /// Only this window of the run, START_S:END_S seconds from its start.
        #[arg(long, value_parser = sim::parse_window)]
        vcd_window: Option<(f64, f64)>,
        /// The JSON report; the SVG is written beside it.
        #[arg(long)]
        report: PathBuf,
        /// Scratch folder for the simulator build.
        #[arg(long, default_value = "target/tdm-stepper-sim")]
        work: PathBuf,
        /// Exit 0 even when an axis did not run as planned (a rejected segment, a
        /// start that did not complete, an underrun, a move that did not finish).
        #[arg(long)]
        allow_problems: bool,
    },
    /// Synthesise the IP over axis counts, TDM against the baseline: sweep.json,
    /// sweep.md and SVG plots (LUT, FF, DSP, saving, cost per axis; Fmax with --fmax).
    Sweep {
        /// Axis counts, comma separated.
        #[arg(long, value_delimiter = ',', default_value = "1,2,4,8,16")]
        axes: Vec<usize>,
        /// Architectures, comma separated: tdm, baseline.
        #[arg(long, value_delimiter = ',', default_value = "tdm,baseline")]
        arch: Vec<Arch>,
        /// FPGA families, comma separated: xc7 (synth_xilinx -flatten), ecp5 (synth_ecp5).
        #[arg(long, value_delimiter = ',', default_value = "xc7,ecp5")]
        family: Vec<Family>,
        /// Place and route the TDM core on ECP5 for these axis counts (needs scripts/install-nextpnr.sh).
        #[arg(long, value_delimiter = ',')]
        fmax: Vec<usize>,
        /// Placement seeds per Fmax point (nextpnr --seed 1..=N); each clock's median is reported.
        #[arg(long, default_value_t = 1)]
        seeds: u32,
        /// Synthesise the TDM core for these axis counts on xc7 without flattening and
        /// tabulate its LUTs and FFs by block (with two or more K: per extra axis).
        #[arg(long, value_delimiter = ',')]
        breakdown: Vec<usize>,
        /// Tool runs in parallel.
        #[arg(long, default_value_t = 2)]
        jobs: usize,
        /// Time limit per tool run, seconds.
        #[arg(long, default_value_t = 3600)]
        timeout_s: u64,
        /// Folder for the results.
        #[arg(long, default_value = "docs/results")]
        out: PathBuf,
        /// Scratch folder for the tool runs (logs stay there). A point whose exported
        /// Verilog and yosys script are unchanged reuses its finished run there.
        #[arg(long, default_value = "target/tdm-stepper-sweep")]
        work: PathBuf,
        /// Run no tool: collect the finished runs in the work folder.
        #[arg(long)]
        cached_only: bool,
        /// Export every point with the machine I/O (`all`, or a list of groups as for
        /// `export --io`; TDM only): the option's cost is the difference from a sweep
        /// without it.
        #[arg(long, default_value = "none", value_parser = export::parse_io, action = clap::ArgAction::Set)]
        io: export::IoChoice,
        /// Segment kinds the core runs: trapezoid, or trapezoid,scurve (the S-curve
        /// option: polynomial segments and their registers; TDM only).
        #[arg(long, default_value = "trapezoid", value_parser = export::parse_profiles, action = clap::ArgAction::Set)]
        profiles: bool,
        /// Encoder feedback: per axis the quadrature pins enc_a, enc_b and enc_z, 4x
        /// decoders with filters, index and probe latches and a reciprocal velocity, the
        /// following error by one shared multiplier with ENC_FAIL and its stop, and their
        /// registers (TDM only).
        #[arg(long)]
        encoder: bool,
        /// The host bus of every point: exmc (the default), spi, wb or axil.
        #[arg(long, default_value = "exmc")]
        bus: export::Bus,
    },
    /// Build the reference board design (Radiona ULX3S, ECP5) to a bitstream: the IP on
    /// SPI (K = 2, clk 50 MHz, bus_clk 100 MHz from the PLL), yosys, nextpnr-ecp5 and
    /// ecppack (scripts/install-nextpnr.sh); prints utilisation and timing, and fails
    /// when a clock misses its frequency.
    Board {
        /// Folder to build in (created if missing): board.bit and the logs.
        #[arg(long, default_value = "build/board")]
        out: PathBuf,
        /// nextpnr's placement seed.
        #[arg(long, default_value_t = 1)]
        seed: u32,
    },
    /// Write the reference-model test vectors (segments in; periods, edges and errors out).
    Vectors {
        /// Folder to write the JSON files into.
        #[arg(long, default_value = "vectors")]
        out: PathBuf,
    },
    /// Compare our period algorithm and the alternatives against exact kinematics.
    Accuracy {
        /// Folder for accuracy.json, accuracy.md and the SVG plots.
        #[arg(long, default_value = "docs/accuracy")]
        out: PathBuf,
    },
}

fn run(cli: Cli) -> Result<(), String> {
    match cli.command {
        Command::Export { axes, arch, clock_hz, fifo_depth, min_period, name, io, profiles, encoder, bus, out } => {
            let opts = ExportOptions { name, axes, arch, clock_hz, fifo_depth, min_period, io: io.io, io_omit: io.omit, scurve: profiles, encoder, bus };
            opts.check()?;
            let t0 = std::time::Instant::now();
            let done = tdm_stepper::package::export(&opts, &out)?;
            println!(
                "exported {} core{}{}, K = {axes}, {clock_hz} Hz: t_calc {} cycles, minimum period {} ticks, max {:.0} steps/s per axis ({:.2} s)",
                arch.name(),
                match (io.io, encoder) {
                    (true, true) => " with machine I/O and encoder feedback",
                    (true, false) => " with machine I/O",
                    (false, true) => " with encoder feedback",
                    (false, false) => "",
                },
                match bus {
                    export::Bus::Exmc => "",
                    export::Bus::Spi => " on SPI",
                    export::Bus::Wb => " on Wishbone",
                    export::Bus::Axil => " on AXI4-Lite",
                },
                opts.params().t_calc,
                opts.min_period_ticks(),
                opts.max_step_rate_hz(),
                t0.elapsed().as_secs_f64()
            );
            for p in done.files {
                println!("wrote {}", p.display());
            }
        }
        Command::Sim { axes, min_period, moves, engine, vcd, vcd_window, report, work, allow_problems } => {
            if vcd_window.is_some() && vcd.is_none() {
                return Err("--vcd-window needs --vcd".into());
            }
            let opts = SimOptions { axes, min_period, moves, engine, vcd, vcd_window, report, work, progress: true };
            let (r, files) = sim::run(&opts)?;
            println!(
                "simulated {:.4} s ({} clk cycles) in {:.1} s (build and run); skew {} ticks",
                r.simulated_seconds,
                r.clk_cycles,
                r.wall_seconds_build_and_run,
                r.skew_ticks.map_or("-".to_string(), |s| s.to_string())
            );
            for a in &r.axes {
                println!(
                    "axis {}: {} steps, position {}, max edge error {:.3} ticks, max period error {:.3} % ({:.3} % for periods >= 500 ticks), underrun {}",
                    a.axis,
                    a.steps,
                    a.final_position.map_or("?".to_string(), |p| p.to_string()),
                    a.max_edge_error_ticks,
                    a.max_period_error_pct,
                    a.max_period_error_pct_ge_500_ticks,
                    if a.underrun { "YES" } else { "no" }
                );
                for p in &a.problems {
                    println!("axis {}: PROBLEM: {p}", a.axis);
                }
            }
            for p in files {
                println!("wrote {}", p.display());
            }
            if !r.ok && !allow_problems {
                let bad: Vec<String> = r.axes.iter().filter(|a| !a.problems.is_empty()).map(|a| a.axis.to_string()).collect();
                return Err(format!(
                    "the move did not run as planned on axis {} (see PROBLEM above and in the report; --allow-problems exits 0)",
                    bad.join(", ")
                )
                .into());
            }
        }
        Command::Sweep { axes, arch, family, fmax, seeds, breakdown, jobs, timeout_s, out, work, cached_only, io, profiles, encoder, bus } => {
            if axes.is_empty() || arch.is_empty() || family.is_empty() {
                return Err("--axes, --arch and --family each need at least one value".into());
            }
            if jobs == 0 {
                return Err("--jobs must be at least 1".into());
            }
            if seeds == 0 {
                return Err("--seeds must be at least 1".into());
            }
            let work = std::path::absolute(&work).map_err(|e| format!("{}: {e}", work.display()))?;
            let opts = SweepOptions {
                axes,
                archs: arch,
                families: family,
                fmax_axes: fmax,
                seeds,
                breakdown_axes: breakdown,
                jobs,
                timeout: std::time::Duration::from_secs(timeout_s),
                out,
                work,
                clock_hz: 50_000_000,
                cached_only,
                io: io.io,
                io_omit: io.omit,
                scurve: profiles,
                encoder,
                bus,
            };
            let repo = std::env::current_dir().map_err(|e| e.to_string())?;
            let (s, files) = sweep::run(&opts, &repo)?;
            print!("{}", sweep::markdown(&s));
            for p in files {
                println!("wrote {}", p.display());
            }
            if s.points.iter().any(|p| p.status != "ok") || s.fmax.iter().any(|p| p.status != "ok") {
                return Err("some tool runs did not finish; see the logs named above".into());
            }
        }
        Command::Board { out, seed } => {
            let repo = std::env::current_dir().map_err(|e| e.to_string())?;
            let r = tdm_stepper::board::build(&repo, &out, seed)?;
            print!("{}", r.markdown());
        }
        Command::Vectors { out } => {
            let paths = vectors::write_all(&out)
                .map_err(|e| format!("cannot write vectors into {}: {e}", out.display()))?;
            for p in paths {
                println!("wrote {}", p.display());
            }
        }
        Command::Accuracy { out } => {
            let (reports, paths) = accuracy::write_report(&out)
                .map_err(|e| format!("cannot write the accuracy report into {}: {e}", out.display()))?;
            print!("{}", accuracy::table(&reports));
            for p in paths {
                println!("wrote {}", p.display());
            }
        }
    }
    Ok(())
}

fn main() -> ExitCode {
    match run(Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(msg) => {
            eprintln!("tdm-stepper: error: {msg}");
            ExitCode::FAILURE
        }
    }
}
