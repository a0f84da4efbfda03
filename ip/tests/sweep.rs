//! The synthesis flow cannot rot: a small sweep (K = 1 and 2, TDM and baseline, xc7)
//! runs the exported IP through yosys `synth_xilinx -flatten` and writes its outputs.
//! The full sweep (K up to 16, ECP5, Fmax) is a documented command, not a test.

mod common;

use common::*;
use std::process::Command;
use tdm_stepper::verify::Simulator;

#[test]
fn small_sweep_synthesises_tdm_and_baseline_for_one_and_two_axes() {
    let out = sim_dir("sweep_small_out", Simulator::Verilator);
    let work = sim_dir("sweep_small_work", Simulator::Verilator);
    let _ = std::fs::remove_dir_all(&out);
    let run = Command::new(env!("CARGO_BIN_EXE_tdm-stepper"))
        .args(["sweep", "--axes", "1,2", "--arch", "tdm,baseline", "--family", "xc7", "--jobs", "2", "--timeout-s", "900", "--out"])
        .arg(&out)
        .arg("--work")
        .arg(&work)
        .output()
        .unwrap();
    assert!(run.status.success(), "sweep failed:\n{}", String::from_utf8_lossy(&run.stderr));
    for f in ["sweep.json", "sweep.md", "xc7_luts.svg", "xc7_ffs.svg", "xc7_dsps.svg", "xc7_saving.svg", "xc7_marginal.svg"] {
        assert!(out.join(f).is_file(), "{f} not written");
    }
    let s: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(out.join("sweep.json")).unwrap()).unwrap();
    let points = s["points"].as_array().unwrap();
    assert_eq!(points.len(), 4);
    let luts = |arch: &str, k: u64| -> u64 {
        let p = points.iter().find(|p| p["arch"] == arch && p["axes"] == k).unwrap();
        assert_eq!(p["status"], "ok", "{arch} K = {k}");
        p["resources"]["luts"].as_u64().unwrap()
    };
    // Nothing optimised away, and the orderings that must hold.
    assert!(luts("tdm", 1) > 1000, "TDM K = 1: {} LUTs", luts("tdm", 1));
    assert!(luts("tdm", 2) > luts("tdm", 1));
    assert!(luts("baseline", 2) > luts("baseline", 1));
    assert!(luts("tdm", 2) < luts("baseline", 2), "TDM must be smaller than two one-axis cores");
    let md = std::fs::read_to_string(out.join("sweep.md")).unwrap();
    assert!(md.contains("| 2 | ") && md.contains("6,262"), "the table and the paper's Table 1");
}

#[test]
fn sweep_rejects_bad_arguments() {
    for (args, msg) in [
        (vec!["--axes", "3", "--arch", "baseline"], "baseline is built for"),
        (vec!["--axes", "0"], "axis counts are 1 to 16"),
        (vec!["--family", "ice40"], "expected xc7 or ecp5"),
        (vec!["--jobs", "0"], "--jobs must be at least 1"),
    ] {
        let run = Command::new(env!("CARGO_BIN_EXE_tdm-stepper")).arg("sweep").args(&args).args(["--out", "/tmp/tdm-sweep-never"]).output().unwrap();
        let err = String::from_utf8_lossy(&run.stderr);
        assert!(!run.status.success() && err.contains(msg) && !err.contains("panicked"), "{args:?}: {err}");
    }
}

#[test]
fn stat_and_fmax_reports_are_read_right() {
    use tdm_stepper::sweep::{fmax_of, parse_stat, Family};
    let xc7 = r#"{"design": {"num_cells": 9, "num_cells_by_type": {"LUT2": 3, "LUT6": 4, "FDRE": 5, "FDSE": 1, "DSP48E1": 2, "CARRY4": 7, "RAMB18E1": 1, "RAM32M": 2, "IBUF": 9}}}"#;
    let r = parse_stat(xc7, Family::Xc7).unwrap();
    assert_eq!((r.luts, r.ffs, r.dsps, r.carry, r.brams, r.lutram), (7, 6, 2, 7, 1, 2));
    let ecp5 = r#"{"design": {"num_cells_by_type": {"LUT4": 10, "TRELLIS_FF": 8, "MULT18X18D": 3, "CCU2C": 4, "DP16KD": 1, "TRELLIS_DPR16X4": 2}}}"#;
    let r = parse_stat(ecp5, Family::Ecp5).unwrap();
    assert_eq!((r.luts, r.ffs, r.dsps, r.carry, r.brams, r.lutram), (10, 8, 3, 4, 1, 2));
    assert!(parse_stat("{}", Family::Xc7).is_err());
    let rep: serde_json::Value = serde_json::from_str(
        r#"{"fmax": {"$glbnet$bus_clk$TRELLIS_IO_IN": {"achieved": 79.5, "constraint": 100}, "$glbnet$clk$TRELLIS_IO_IN": {"achieved": 14.7, "constraint": 100}}}"#,
    )
    .unwrap();
    let f = rep["fmax"].as_object().unwrap();
    assert_eq!(fmax_of(f, "clk"), Some(14.7));
    assert_eq!(fmax_of(f, "bus_clk"), Some(79.5));
}
