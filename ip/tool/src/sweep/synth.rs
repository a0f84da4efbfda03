//! Synthesis points: yosys on the exported Verilog, `stat -json` counted into
//! resources (LUT-RAM and SRL cells as the LUTs they occupy).
use super::*;

/// Counts `stat -json` cells into resource kinds.
pub fn parse_stat(json: &str, family: Family) -> Result<Resources, String> {
    let v: serde_json::Value = serde_json::from_str(json).map_err(|e| format!("stat -json: {e}"))?;
    let design = v.get("design").ok_or("stat -json: no design")?;
    let cells = design.get("num_cells_by_type").and_then(|c| c.as_object()).ok_or("stat -json: no num_cells_by_type")?;
    Ok(count_cells(cells, family))
}

/// Counts cells by type (one module's or the design's) into resource kinds; cells of
/// other types (IO buffers, submodule instances) are kept in `cells_by_type` only.
pub(super) fn count_cells(cells: &serde_json::Map<String, serde_json::Value>, family: Family) -> Resources {
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

/// Runs yosys `script` (which writes `stat.json`) on `verilog` in `dir` and returns
/// `stat.json`. A finished run on the same Verilog and script is reused instead
/// (`reused` is set; delete the work folder to rerun); with `--cached-only` nothing runs.
pub(super) fn yosys_stat(dir: &Path, verilog: &str, script: &str, opts: &SweepOptions, reused: &mut bool) -> Result<String, String> {
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

pub(super) fn synth_point(arch: Arch, axes: usize, family: Family, opts: &SweepOptions) -> Point {
    let dir = opts.work.join(format!("{}_{}_k{axes}{}", family.name(), arch.name(), opts.io_suffix()));
    let log = dir.join("yosys.log");
    let t0 = Instant::now();
    let mut reused = false;
    let result = (|| -> Result<Resources, String> {
        let v = export::verilog(&ExportOptions { axes, arch, clock_hz: opts.clock_hz, io: opts.io, io_omit: opts.io_omit, scurve: opts.scurve, encoder: opts.encoder, bus: opts.bus, ..Default::default() })?;
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
