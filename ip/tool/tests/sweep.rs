//! The synthesis flow cannot rot: a small sweep (K = 1, TDM and baseline, xc7) runs
//! the exported IP through yosys `synth_xilinx -flatten` and writes its outputs. The
//! full sweep (K up to 16, ECP5, Fmax), and with it the orderings between points (TDM
//! against the baseline, K against K), is a documented command, not a test: K = 1 and
//! 2 took 14 minutes of the test command. The committed sweep's figures are held to
//! the README below.

#[path = "../../tests/common/mod.rs"]
mod common;

use common::*;
use std::process::Command;
use tdm_stepper::verify::Simulator;

#[test]
fn small_sweep_synthesises_tdm_and_baseline_for_one_axis() {
    let out = sim_dir("sweep_small_out", Simulator::Verilator);
    let work = sim_dir("sweep_small_work", Simulator::Verilator);
    let _ = std::fs::remove_dir_all(&out);
    let run = Command::new(env!("CARGO_BIN_EXE_tdm-stepper"))
        .args(["sweep", "--axes", "1", "--arch", "tdm,baseline", "--family", "xc7", "--jobs", "2", "--timeout-s", "900", "--out"])
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
    assert_eq!(points.len(), 2);
    let luts = |arch: &str, k: u64| -> u64 {
        let p = points.iter().find(|p| p["arch"] == arch && p["axes"] == k).unwrap();
        assert_eq!(p["status"], "ok", "{arch} K = {k}");
        p["resources"]["luts"].as_u64().unwrap()
    };
    // Nothing optimised away.
    assert!(luts("tdm", 1) > 1000, "TDM K = 1: {} LUTs", luts("tdm", 1));
    assert!(luts("baseline", 1) > 1000, "baseline K = 1: {} LUTs", luts("baseline", 1));
    let md = std::fs::read_to_string(out.join("sweep.md")).unwrap();
    assert!(md.contains("| 1 | ") && md.contains("6,262"), "the table and the paper's Table 1");

    // --cached-only collects the same results and says they were reused; a value
    // listed twice is one point, not two runs in one folder.
    let again = Command::new(env!("CARGO_BIN_EXE_tdm-stepper"))
        .args(["sweep", "--axes", "1,1", "--arch", "tdm,baseline,tdm", "--family", "xc7,xc7", "--cached-only", "--out"])
        .arg(&out)
        .arg("--work")
        .arg(&work)
        .output()
        .unwrap();
    assert!(again.status.success(), "{}", String::from_utf8_lossy(&again.stderr));
    let s2: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(out.join("sweep.json")).unwrap()).unwrap();
    assert_eq!(s2["points"].as_array().unwrap().len(), 2, "duplicates in the lists make no extra points");
    for p in s2["points"].as_array().unwrap() {
        let first = points.iter().find(|q| q["arch"] == p["arch"] && q["axes"] == p["axes"]).unwrap();
        assert_eq!(p["resources"], first["resources"]);
        assert!(p["message"].as_str().is_some_and(|m| m.starts_with("reused")), "{p}");
        assert!(p["tool_seconds"].as_f64().is_some_and(|t| t > 0.0), "the tool's run time: {p}");
    }
}

#[test]
fn sweep_rejects_bad_arguments() {
    for (args, msg) in [
        (vec!["--axes", "3", "--arch", "baseline"], "baseline is built for"),
        (vec!["--axes", "0"], "axis counts are 1 to 16"),
        (vec!["--family", "ice40"], "expected xc7 or ecp5"),
        (vec!["--jobs", "0"], "--jobs must be at least 1"),
        (vec!["--fmax", "2", "--seeds", "0"], "--seeds must be at least 1"),
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
    // LUTs: 3 + 4 LUT cells, and 2 RAM32M of 4 LUTs each.
    assert_eq!((r.luts, r.ffs, r.dsps, r.carry, r.brams, r.lutram), (15, 6, 2, 7, 1, 2));
    assert_eq!(r.luts_in_memory, 8);
    let ecp5 = r#"{"design": {"num_cells_by_type": {"LUT4": 10, "TRELLIS_FF": 8, "MULT18X18D": 3, "CCU2C": 4, "DP16KD": 1, "TRELLIS_DPR16X4": 2}}}"#;
    let r = parse_stat(ecp5, Family::Ecp5).unwrap();
    // LUTs: 10 LUT4 cells, and 2 TRELLIS_DPR16X4 of 6 LUT4s each.
    assert_eq!((r.luts, r.ffs, r.dsps, r.carry, r.brams, r.lutram), (22, 8, 3, 4, 1, 2));
    assert!(parse_stat("{}", Family::Xc7).is_err());
    let rep: serde_json::Value = serde_json::from_str(
        r#"{"fmax": {"$glbnet$bus_clk$TRELLIS_IO_IN": {"achieved": 79.5, "constraint": 100}, "$glbnet$clk$TRELLIS_IO_IN": {"achieved": 14.7, "constraint": 100}}}"#,
    )
    .unwrap();
    let f = rep["fmax"].as_object().unwrap();
    assert_eq!(fmax_of(f, "clk"), Some(14.7));
    assert_eq!(fmax_of(f, "bus_clk"), Some(79.5));
}

/// Several placement seeds make one Fmax point: each clock's median (the seeds' bus
/// medians taken on their own), the path of the run nearest the clk median, the
/// runs' figures in seed order, and a failed run fails the point.
#[test]
fn fmax_seeds_combine_into_medians() {
    use tdm_stepper::sweep::{combine_seeds, median, FmaxPoint};
    assert_eq!(median(&[]), None);
    assert_eq!(median(&[3.0, 1.0, 2.0]), Some(2.0));
    assert_eq!(median(&[4.0, 1.0, 3.0, 2.0]), Some(2.5));
    let run = |seed: u32, clk: f64, bus: f64| FmaxPoint {
        axes: 8,
        status: "ok".into(),
        fmax_clk_mhz: Some(clk),
        fmax_bus_clk_mhz: Some(bus),
        seeds: vec![seed],
        seed_clk_mhz: vec![clk],
        seed_bus_clk_mhz: vec![bus],
        path_seed: seed,
        max_step_rate_hz_at_fmax: None,
        tool: "nextpnr".into(),
        critical_path: None,
        seconds: 10.0,
        tool_seconds: Some(9.0),
        log: format!("fmax_k8_s{seed}/pnr.log").into(),
        message: None,
    };
    let p = combine_seeds(vec![run(3, 90.0, 70.0), run(1, 80.0, 75.0), run(2, 85.0, 60.0)], false);
    assert_eq!((p.fmax_clk_mhz, p.fmax_bus_clk_mhz), (Some(85.0), Some(70.0)));
    assert_eq!(p.seeds, vec![1, 2, 3]);
    assert_eq!(p.seed_clk_mhz, vec![80.0, 85.0, 90.0]);
    assert_eq!(p.seed_bus_clk_mhz, vec![75.0, 60.0, 70.0]);
    assert_eq!(p.path_seed, 2, "the median run's path and log");
    assert_eq!(p.log, std::path::PathBuf::from("fmax_k8_s2/pnr.log"));
    assert_eq!((p.seconds, p.tool_seconds), (30.0, Some(27.0)));
    assert!(p.max_step_rate_hz_at_fmax.unwrap() > 0.0);
    // With the S-curve option an axis's rate is f / (K·POLY_T_CALC).
    let ps = combine_seeds(vec![run(3, 90.0, 70.0), run(1, 80.0, 75.0), run(2, 85.0, 60.0)], true);
    let want = 85e6 / (8 * tdm_stepper::export::POLY_T_CALC) as f64;
    assert!((ps.max_step_rate_hz_at_fmax.unwrap() - want).abs() < 1e-6, "S-curve rate {:?}, want {want}", ps.max_step_rate_hz_at_fmax);
    let mut bad = run(2, 0.0, 0.0);
    bad.status = "failed".into();
    bad.fmax_clk_mhz = None;
    let p = combine_seeds(vec![run(1, 80.0, 75.0), bad], false);
    assert_eq!((p.status.as_str(), p.fmax_clk_mhz), ("failed", None), "one failed run fails the point");
}

/// The capacity table: the square-root path's t_calc and the decelerating setup
/// without the S-curve option, the option's per-period budget and the longer of the
/// two setups with it.
#[test]
fn capacity_follows_the_profiles() {
    use tdm_stepper::export::{ExportOptions, POLY_T_CALC, RADIX_BITS};
    use tdm_stepper::hdl::core::{t_calc_sqrt, t_setup, T_POLY_SETUP};
    use tdm_stepper::sweep::capacity;
    for k in [2usize, 16] {
        let c = capacity(k, Some(80.0), false);
        assert_eq!(c.min_period_ticks, (k * t_calc_sqrt(RADIX_BITS)) as u64);
        assert_eq!(c.t_setup_cycles, t_setup(RADIX_BITS, true));
        assert!((c.max_step_rate_hz_at_fmax.unwrap() - 80e6 / (k * t_calc_sqrt(RADIX_BITS)) as f64).abs() < 1e-6);
        let s = capacity(k, Some(80.0), true);
        assert_eq!(s.min_period_ticks, (k * POLY_T_CALC) as u64);
        assert_eq!(s.t_setup_cycles, T_POLY_SETUP.max(t_setup(RADIX_BITS, true)));
        assert!((s.max_step_rate_hz_at_fmax.unwrap() - 80e6 / (k * POLY_T_CALC) as f64).abs() < 1e-6);
        assert!((s.periods_per_s_at_50mhz - 50e6 / POLY_T_CALC as f64).abs() < 1e-6);
        assert_eq!(s.min_period_ticks, ExportOptions { axes: k, scurve: true, ..Default::default() }.sustainable_period_ticks());
    }
}

/// The nextpnr critical-path report is summarised right: delays, ends, blocks. The
/// excerpt has the shape of a real nextpnr-ecp5 0.11 log (cut short).
#[test]
fn critical_path_summary_reads_a_nextpnr_report() {
    use tdm_stepper::sweep::critical_path;
    let log = "\
Info: Critical path report for clock '$glbnet$clk$TRELLIS_IO_IN' (posedge -> posedge):
Info:       type curr  total name
Info:   clk-to-q  0.52  0.52 Source core.core.div.den.q_TRELLIS_FF_Q_30.Q
Info:    routing  1.98  2.51 Net core.core.div.den.q[1] (38,35) -> (52,32)
Info:                          Sink core.core.div.digits$0$rem_out_LUT4_Z_7.C
Info:                          Defined in:
Info:                               tdm_stepper.v:1400.26-1409.6
Info:      logic  0.24  2.75 Source core.core.div.digits$0$rem_out_LUT4_Z_7.F
Info:    routing  1.00  3.75 Net x (1,1) -> (2,2)
Info:      logic  0.45  4.20 Source core.regs.w_level_LUT4_Z_6.F
Info:    routing  0.30  4.50 Net y (1,1) -> (2,2)
Info:      logic  0.07  4.57 Source $nextpnr_CCU2C_89$CCU2_COMB0.FCO
Info:    routing  1.58  6.15 Net core.core.div.digits$7.rem_out[1] (49,37) -> (38,33)
Info:                          Sink core.core.div.rem.q_TRELLIS_FF_Q_62.M
Info:      setup  0.00  6.15 Source core.core.div.rem.q_TRELLIS_FF_Q_62.M
Info: 1.28 ns logic, 4.87 ns routing

Info: Critical path report for clock '$glbnet$bus_clk$TRELLIS_IO_IN' (posedge -> posedge):
Info:   clk-to-q  0.52  0.52 Source core.exmc.d1.q_TRELLIS_FF_Q.Q
Info:      setup  0.00  0.52 Source core.exmc.d2.q_TRELLIS_FF_Q.DI
Info: 0.52 ns logic, 0.00 ns routing
";
    let c = critical_path(log, "clk").expect("clk path");
    assert_eq!((c.total_ns, c.logic_ns, c.routing_ns), (6.15, 1.28, 4.87));
    assert_eq!(c.from, "core.core.div.den.q_TRELLIS_FF_Q_30.Q");
    assert_eq!(c.to, "core.core.div.rem.q_TRELLIS_FF_Q_62.M");
    assert_eq!(
        c.blocks,
        vec![
            ("core.core.div".to_string(), 2),
            ("(top)".to_string(), 1),
            ("core.regs".to_string(), 1)
        ]
    );
    let b = critical_path(log, "bus_clk").expect("bus_clk path");
    assert_eq!(
        (b.total_ns, b.from.as_str()),
        (0.52, "core.exmc.d1.q_TRELLIS_FF_Q.Q")
    );
    assert_eq!(critical_path(log, "other"), None);
    assert_eq!(
        critical_path(&log[..log.find("Info: 1.28").unwrap()], "clk"),
        None,
        "a cut report gives nothing"
    );
}

/// The breakdown counts each block's flip-flops exactly on a real (small, hierarchical)
/// yosys run named the way rust-hdl names the exported core's modules, and every module
/// of the exported core belongs to a named block.
#[test]
fn breakdown_counts_cells_by_block() {
    use tdm_stepper::sweep::{block_of, breakdown_blocks, breakdown_script, Family};
    let dir = sim_dir("sweep_breakdown", Simulator::Verilator);
    std::fs::create_dir_all(&dir).unwrap();
    let reg = |name: &str, bits: usize| {
        format!("module \\{name} (input clk, input [{m}:0] d, output reg [{m}:0] q);\n  always @(posedge clk) q <= d;\nendmodule\n", m = bits - 1)
    };
    let mut v = String::from(
        "module tdm_stepper(input clk, input [63:0] d, output [63:0] q0, output [63:0] q1, output [63:0] q2, output [7:0] q3);\n\
         \\tdm_stepper__core__ctx__0 c0(.clk(clk), .d(d[9:0]), .q(q0[9:0]));\n\
         \\tdm_stepper__core__ctx__1 c1(.clk(clk), .d(d[9:0]), .q(q1[9:0]));\n\
         \\tdm_stepper__core__div d0(.clk(clk), .d(d[32:0]), .q(q2[32:0]));\n\
         \\tdm_stepper__regs r0(.clk(clk), .d(d[6:0]), .q(q3[6:0]));\nendmodule\n",
    );
    for (n, b) in [
        ("tdm_stepper__core__ctx__0", 10),
        ("tdm_stepper__core__ctx__1__r_a", 10),
        ("tdm_stepper__core__div", 33),
        ("tdm_stepper__regs", 7),
    ] {
        v += &reg(n, b);
    }
    // A third level, a register whose hold multiplexer is in its parent, as rust-hdl
    // writes them: flattened into its block, the multiplexer becomes a clock enable.
    v += "module \\tdm_stepper__core__ctx__1 (input clk, input [9:0] d, output [9:0] q);\n  wire [9:0] dd = {d[9], d[9] ? d[8:0] : q[8:0]};\n  \\tdm_stepper__core__ctx__1__r_a r(.clk(clk), .d(dd), .q(q));\nendmodule\n";
    std::fs::write(dir.join("tdm_stepper.v"), v).unwrap();
    let run = Command::new("yosys")
        .current_dir(&dir)
        .args([
            "-q",
            "-p",
            &breakdown_script(2, tdm_stepper::export::Bus::Exmc),
        ])
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let stat = std::fs::read_to_string(dir.join("stat.json")).unwrap();
    assert!(!stat.contains("ctx__1__r_a"), "the register module is flattened into its block");
    let blocks = breakdown_blocks(&stat, "tdm_stepper", Family::Xc7).unwrap();
    // yosys 0.23 writes a deep hierarchy as text after "modules": still read.
    let garbled = stat.replacen("\"design\":", "tdm_stepper__core__ctx__1__r_a      1\n \"design\":", 1);
    assert!(serde_json::from_str::<serde_json::Value>(&garbled).is_err());
    assert_eq!(breakdown_blocks(&garbled, "tdm_stepper", Family::Xc7).unwrap(), blocks);
    let ffs = |n: &str| blocks.iter().find(|b| b.name == block_of(n)).map(|b| b.ffs);
    assert_eq!(
        ffs("tdm_stepper__core__ctx__0"),
        Some(20),
        "two contexts of 10 bits: {blocks:?}"
    );
    assert_eq!(ffs("tdm_stepper__core__div"), Some(33));
    let ctx_luts = blocks.iter().find(|b| b.name == block_of("tdm_stepper__core__ctx__1")).unwrap().luts;
    assert_eq!(ctx_luts, 0, "the hold multiplexer must map to clock enables: {blocks:?}");
    assert_eq!(ffs("tdm_stepper__regs"), Some(7));
    assert_eq!(blocks.iter().map(|b| b.ffs).sum::<u64>(), 60);
    assert!(breakdown_blocks("{\"modules\": {}}", "tdm_stepper", Family::Xc7).is_err());

    for bus in tdm_stepper::export::Bus::ALL {
        let exported = tdm_stepper::export::verilog(&tdm_stepper::export::ExportOptions { axes: 2, bus, ..Default::default() }).unwrap();
        let mut names: Vec<&str> = exported
            .lines()
            .filter_map(|l| l.strip_prefix("module "))
            .map(|l| l.split('(').next().unwrap())
            .collect();
        assert!(names.len() > 100);
        names.retain(|n| block_of(n) == "other");
        assert!(names.is_empty(), "{bus:?}: modules in no block: {names:?}");
        // The core's blocks are the same on every bus; the front end is one block.
        assert_eq!(block_of("tdm_stepper__exmc__core__div"), block_of("tdm_stepper__core__div"));
        if bus != tdm_stepper::export::Bus::Exmc {
            let front = format!("tdm_stepper__{}__master", bus.name());
            assert!(block_of(&front).ends_with("front end"), "{front}: {}", block_of(&front));
        }
    }
}

/// 12345 → "12,345", as the README writes counts.
fn grouped(n: u64) -> String {
    let s = n.to_string();
    let mut out = String::new();
    for (i, c) in s.chars().enumerate() {
        if i > 0 && (s.len() - i) % 3 == 0 {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// The README's status row and "Clock limit" paragraph quote the committed full sweep
/// (docs/results/sweep.json), so a rerun of the sweep cannot leave older figures behind.
#[test]
fn readme_quotes_the_committed_sweep() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let s: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(root.join("docs/results/sweep.json")).unwrap()).unwrap();
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let status = readme.lines().find(|l| l.starts_with("| area and timing |")).expect("the README's status row on area and timing");
    let clock = readme.split("**Clock limit").nth(1).expect("the README's \"Clock limit\" paragraph").split("\n\n").next().unwrap();
    let res = |family: &str, arch: &str, k: u64| -> serde_json::Value {
        let p = s["points"].as_array().unwrap().iter().find(|p| p["family"] == family && p["arch"] == arch && p["axes"] == k);
        let p = p.unwrap_or_else(|| panic!("docs/results has no {family} {arch} K = {k}"));
        assert_eq!(p["status"], "ok", "{family} {arch} K = {k}");
        p["resources"].clone()
    };
    let (t2, t16) = (res("xc7", "tdm", 2), res("xc7", "tdm", 16));
    let (b2, b16) = (res("xc7", "baseline", 2), res("xc7", "baseline", 16));
    let n = |v: &serde_json::Value, f: &str| v[f].as_u64().unwrap();
    let quoted = [
        format!("{} LUT6 and {} FF at K = 2", grouped(n(&t2, "luts")), grouped(n(&t2, "ffs"))),
        format!("{} LUT6 at K = 16", grouped(n(&t16, "luts"))),
        format!(
            "{:.1} % / {:.1} % smaller than the baseline",
            tdm_stepper::sweep::saving_pct(n(&t2, "luts"), n(&b2, "luts")),
            tdm_stepper::sweep::saving_pct(n(&t16, "luts"), n(&b16, "luts"))
        ),
    ];
    for q in &quoted {
        assert!(status.contains(q.as_str()), "the README's status row should say \"{q}\" (docs/results/sweep.json):\n{status}");
    }
    let fmax = s["fmax"].as_array().unwrap();
    assert!(fmax.len() >= 3, "the full sweep measures Fmax at K = 2, 8 and 16");
    for f in fmax {
        let k = f["axes"].as_u64().unwrap();
        let clk = format!("{:.1} MHz at K = {k}", f["fmax_clk_mhz"].as_f64().unwrap());
        let bus = format!("{:.1}", f["fmax_bus_clk_mhz"].as_f64().unwrap());
        for q in [&clk, &bus] {
            assert!(status.contains(q.as_str()) && clock.contains(q.as_str()), "the README's status row and \"Clock limit\" should say \"{q}\" (docs/results/sweep.json)");
        }
    }
}

/// The Fmax wrapper connects every port of the core it wraps (yosys `hierarchy -check`
/// on the wrapper and the export, with and without the machine I/O, on every bus), and
/// without them is the text earlier sweeps placed (so their cached runs and figures
/// stay comparable).
#[test]
fn fmax_wrapper_connects_every_port_with_and_without_io() {
    use tdm_stepper::export::Bus;
    for (io, bus) in [(false, Bus::Exmc), (true, Bus::Exmc), (false, Bus::Spi), (true, Bus::Wb), (false, Bus::Axil)] {
        let dir = std::env::temp_dir().join(format!("tdm-fmax-wrapper-{}-{io}-{}", std::process::id(), bus.name()));
        std::fs::create_dir_all(&dir).unwrap();
        let v = tdm_stepper::export::verilog(&tdm_stepper::export::ExportOptions { axes: 3, io, bus, ..Default::default() }).unwrap();
        std::fs::write(dir.join("tdm_stepper.v"), v).unwrap();
        std::fs::write(dir.join("fmax_top.v"), tdm_stepper::sweep::io_wrapper(3, io, bus)).unwrap();
        let out = std::process::Command::new("yosys")
            .current_dir(&dir)
            .args(["-q", "-p", "read_verilog tdm_stepper.v fmax_top.v; hierarchy -check -top fmax_top; proc; opt_clean; check -assert"])
            .output()
            .expect("yosys is installed");
        std::fs::remove_dir_all(&dir).unwrap();
        assert!(out.status.success(), "io {io}, {bus:?}: {}", String::from_utf8_lossy(&out.stderr));
    }
    let plain = tdm_stepper::sweep::io_wrapper(2, false, Bus::Exmc);
    assert!(plain.contains("    .step(step), .dir(dir), .irq(irq), .fsm_state(fsm_state));\n"), "{plain}");
    assert!(plain.contains("begin step_x <= ^step; dir_x"), "{plain}");
    assert!(!plain.contains("estop_n") && tdm_stepper::sweep::io_wrapper(2, true, Bus::Exmc).contains(".estop_n(pins[0])"));
}
