//! `tdm-stepper`: the command line of the tdm-stepper IP core.
//!
//! Subcommands: `export` (the IP core), `vectors` (the JSON test vectors) and
//! `accuracy` (the accuracy report).

use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;
use tdm_stepper::export::{self, Arch, ExportOptions};
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
        /// Folder to write into (created if missing).
        #[arg(long)]
        out: PathBuf,
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
        Command::Export { axes, arch, clock_hz, fifo_depth, out } => {
            let opts = ExportOptions { axes, arch, clock_hz, fifo_depth };
            opts.check()?;
            let t0 = std::time::Instant::now();
            let done = export::export(&opts, &out)?;
            println!(
                "exported {} core, K = {axes}, {clock_hz} Hz: t_calc {} cycles, max {:.0} steps/s per axis ({:.2} s)",
                arch.name(),
                opts.params().t_calc,
                opts.max_step_rate_hz(),
                t0.elapsed().as_secs_f64()
            );
            for p in done.files {
                println!("wrote {}", p.display());
            }
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
