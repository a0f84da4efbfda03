//! `tdm-stepper`: the command line of the tdm-stepper IP core.
//!
//! Subcommands so far: `vectors` (write the JSON test vectors) and `accuracy`
//! (the accuracy report). `export`, `sim` and `sweep` arrive with the core.

use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;
use tdm_stepper::{accuracy, vectors};

#[derive(Parser)]
#[command(name = "tdm-stepper", version, about = "Time-division multiplexed multi-axis stepper motor IP core")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
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
