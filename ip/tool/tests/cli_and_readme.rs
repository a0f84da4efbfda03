//! The README's quick start runs what exists, CI runs the README's test command,
//! and the CLI fails cleanly on bad input.

use std::path::{Path, PathBuf};
use std::process::Command;
use tdm_stepper::board;

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_tdm-stepper"))
}

/// The commands of the first fenced block under `heading`.
fn commands_under(heading: &str) -> Vec<String> {
    let readme = std::fs::read_to_string(repo().join("README.md")).unwrap();
    let section = readme.split(heading).nth(1).unwrap_or_else(|| panic!("README has {heading}"));
    let block = section.split("```").nth(1).expect("a fenced block");
    block.lines().skip(1).map(|l| l.split('#').next().unwrap().trim().to_string()).filter(|l| !l.is_empty()).collect()
}

fn readme() -> String {
    std::fs::read_to_string(repo().join("README.md")).unwrap()
}

#[test]
fn quick_start_commands_exist_and_ci_runs_the_test_command() {
    let cmds = commands_under("## Quick start");
    assert_eq!(cmds.len(), 3, "three commands: {cmds:?}");
    // The first runs a subcommand of our binary.
    let sub = cmds[0].strip_prefix("cargo run --release -- ").expect("cargo run of the binary");
    let out = bin().args(sub.split_whitespace()).arg("--help").output().unwrap();
    assert!(out.status.success(), "`tdm-stepper {sub} --help` failed");
    // The last is the test script, and CI calls exactly it.
    assert_eq!(cmds[2], "scripts/test.sh");
    let ci = std::fs::read_to_string(repo().join(".ci/run")).unwrap();
    assert!(ci.lines().any(|l| l.trim() == "exec scripts/test.sh"), ".ci/run must exec scripts/test.sh");
}

/// The worked example, run as written from the repository root: export, then the
/// paper's experiment through the bus in Verilator with a VCD. The report must show
/// ≤ 1 tick of edge error, 0 skew and the positions; the VCD must open (parsed here
/// with the `vcd` crate) and hold every step.
#[test]
fn readme_worked_example_runs_as_written() {
    let cmds = commands_under("## Worked example");
    let ours: Vec<&String> = cmds.iter().filter(|c| c.starts_with("cargo run --release -- ")).collect();
    assert_eq!(ours.len(), 2, "export and sim: {cmds:?}");
    assert!(ours[0].contains(" export ") && ours[1].contains(" sim "), "{ours:?}");
    let arg = |c: &str, flag: &str| -> String {
        let w: Vec<&str> = c.split_whitespace().collect();
        w[w.iter().position(|x| *x == flag).unwrap_or_else(|| panic!("{flag} in {c}")) + 1].to_string()
    };
    // Run as written, in a scratch copy of the working folder (its examples/), so that
    // the test writes nothing into the repository.
    let work = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("readme_example");
    let _ = std::fs::remove_dir_all(&work);
    std::fs::create_dir_all(work.join("examples")).unwrap();
    for e in std::fs::read_dir(repo().join("examples")).unwrap() {
        let e = e.unwrap().path();
        std::fs::copy(&e, work.join("examples").join(e.file_name().unwrap())).unwrap();
    }
    for c in &ours {
        let args: Vec<&str> = c.strip_prefix("cargo run --release -- ").unwrap().split_whitespace().collect();
        let out = bin().current_dir(&work).args(&args).output().unwrap();
        assert!(out.status.success(), "{c}: {}", String::from_utf8_lossy(&out.stderr));
    }
    let ip = work.join(arg(ours[0], "--out"));
    for f in ["tdm_stepper.v", "tdm_stepper_regs.h", "registers.md", "manifest.json"] {
        assert!(ip.join(f).is_file(), "{f}");
    }
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(work.join(arg(ours[1], "--report"))).unwrap()).unwrap();
    assert_eq!(report["skew_ticks"], 0);
    for (a, pos) in [(0, 2400), (1, 1800)] {
        let ax = &report["axes"][a];
        assert_eq!(ax["final_position"], pos, "axis {a}");
        assert_eq!(ax["steps"], pos, "axis {a}");
        assert!(ax["max_edge_error_ticks"].as_f64().unwrap() <= 1.0, "axis {a}");
        assert_eq!(ax["underrun"], false, "axis {a}");
    }
    assert!(work.join(arg(ours[1], "--report")).with_extension("svg").is_file());
    let vcd_path = work.join(arg(ours[1], "--vcd"));
    let size = std::fs::metadata(&vcd_path).unwrap().len();
    assert!(size < 50 << 20, "VCD is {size} bytes");
    let mut parser = vcd::Parser::new(std::io::BufReader::new(std::fs::File::open(&vcd_path).unwrap()));
    let header = parser.parse_header().unwrap();
    let step0 = header.find_var(&["tdm_stepper", "step_0"]).expect("step_0 in the VCD").code;
    for name in ["dir_0", "step_1", "dir_1", "fsm_state", "fifo_level_0", "queue_level_1", "irq", "position_0", "position_1"] {
        assert!(header.find_var(&["tdm_stepper", name]).is_some(), "{name} in the VCD");
    }
    let pos_codes = [0, 1].map(|a| header.find_var(&["tdm_stepper", &format!("position_{a}")]).unwrap().code);
    // The GTKWave save file beside it shows exactly the VCD's signals.
    let gtkw = std::fs::read_to_string(vcd_path.with_extension("gtkw")).expect("a .gtkw beside the VCD");
    assert!(gtkw.contains(&format!("[dumpfile] \"{}\"", vcd_path.file_name().unwrap().to_str().unwrap())));
    let shown: Vec<&str> = gtkw.lines().filter_map(|l| l.strip_prefix("tdm_stepper.")).collect();
    assert_eq!(shown.len(), 5 * 2 + 2, "every probe once: {shown:?}");
    for s in &shown {
        let name = s.split('[').next().unwrap();
        let var = header.find_var(&["tdm_stepper", name]).unwrap_or_else(|| panic!(".gtkw names {s}, not in the VCD"));
        let width: u32 = var.size;
        assert_eq!(s.contains('['), width > 1, "{s}: the range GTKWave shows");
    }
    // The time axis is the user's clock exactly: 50 MHz is 20,000 ps, and each STEP
    // rise sits at its edge cycle (the report's) times that period.
    assert_eq!(header.timescale, Some((1, vcd::TimescaleUnit::PS)));
    let (mut now, mut rise_ps, mut pos) = (0u64, Vec::new(), [0i64; 2]);
    for cmd in parser {
        match cmd.unwrap() {
            vcd::Command::Timestamp(t) => now = t,
            vcd::Command::ChangeScalar(code, vcd::Value::V1) if code == step0 => rise_ps.push(now),
            vcd::Command::ChangeVector(code, bits) if pos_codes.contains(&code) => {
                let a = pos_codes.iter().position(|c| *c == code).unwrap();
                pos[a] = bits.iter().fold(0u32, |acc, b| (acc << 1) | (*b == vcd::Value::V1) as u32) as i32 as i64;
            }
            _ => {}
        }
    }
    assert_eq!(pos, [2400, 1800], "the position traces end at the positions");
    assert_eq!(rise_ps.len(), 2400, "STEP rising edges of axis 0 in the VCD");
    let edges: Vec<u64> = report["axes"][0]["edge_cycles"].as_array().unwrap().iter().map(|c| c.as_u64().unwrap()).collect();
    let want: Vec<u64> = edges.iter().map(|c| c * 20_000).collect();
    if let Some(i) = (0..want.len()).find(|&i| rise_ps[i] != want[i]) {
        panic!("VCD STEP rise {i} at {} ps, edge cycle {} × 20,000 ps = {} ps", rise_ps[i], edges[i], want[i]);
    }
}

/// The quick start's S-curve `sim`, run as written (in a scratch copy of examples/):
/// it exits 0 with the S-curve core, both axes end where the moves go with no
/// underrun, every edge within 0.625 tick of exact kinematics, zero skew, and the SVG
/// has the acceleration plot for both axes.
#[test]
fn readme_quick_start_scurve_sim_runs_as_written() {
    let cmds = commands_under("## Quick start");
    let c = &cmds[1];
    assert!(c.starts_with("cargo run --release -- sim ") && c.contains("examples/scurve_move.json"), "{c}");
    let work = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("readme_scurve_sim");
    let _ = std::fs::remove_dir_all(&work);
    std::fs::create_dir_all(work.join("examples")).unwrap();
    std::fs::copy(repo().join("examples/scurve_move.json"), work.join("examples/scurve_move.json")).unwrap();
    let args: Vec<&str> = c.strip_prefix("cargo run --release -- ").unwrap().split_whitespace().collect();
    let out = bin().current_dir(&work).args(&args).arg("--work").arg(work.join("sim")).output().unwrap();
    assert!(out.status.success(), "{c}: {}", String::from_utf8_lossy(&out.stderr));
    let w: Vec<&str> = c.split_whitespace().collect();
    let report_path = work.join(w[w.iter().position(|x| *x == "--report").unwrap() + 1]);
    let report: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&report_path).unwrap()).unwrap();
    assert_eq!(report["scurve"], true);
    assert_eq!(report["ok"], true, "{}", report["axes"]);
    assert_eq!(report["skew_ticks"], 0);
    for (a, pos) in [(0, 3000i64), (1, -2000)] {
        let ax = &report["axes"][a];
        assert_eq!(ax["final_position"], pos, "axis {a}");
        assert_eq!(ax["steps"], pos.abs(), "axis {a}");
        assert!(ax["max_edge_error_ticks"].as_f64().unwrap() <= 0.625, "axis {a}: {}", ax["max_edge_error_ticks"]);
        assert_eq!(ax["underrun"], false, "axis {a}");
        let segs = ax["segments"].as_array().unwrap();
        assert!(segs.len() >= 6 && segs.iter().all(|s| s["kind"] == "poly"), "axis {a}: polynomial segments");
    }
    let svg = std::fs::read_to_string(report_path.with_extension("svg")).unwrap();
    for a in 0..2 {
        assert!(svg.contains(&format!("axis {a}: acceleration")), "axis {a}'s acceleration plot in the SVG");
    }
}

/// The README's port table is the exported module's (export::ports, which
/// ip/tool/tests/export.rs holds to the Verilog).
#[test]
fn readme_port_table_matches_the_export() {
    let text = readme();
    let k = 3;
    // The base ports' table and the machine I/O's ("Machine I/O"), row for row.
    for p in tdm_stepper::export::ports(k, tdm_stepper::regs::IO_ALL) {
        let width = if p.width == k { "K".to_string() } else { p.width.to_string() };
        let row = format!("| `{}` | {} | {} | {} | {} |", p.name, p.direction, width, p.clock, p.description);
        assert!(text.contains(&row), "README lacks the port row {row}");
    }
}

#[test]
fn vectors_command_writes_what_the_library_generates() {
    let dir = std::env::temp_dir().join(format!("tdm-vectors-{}", std::process::id()));
    let out = bin().args(["vectors", "--out"]).arg(&dir).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    for v in tdm_stepper::vectors::all() {
        let text = std::fs::read_to_string(dir.join(format!("{}.json", v.name))).unwrap();
        assert_eq!(text, tdm_stepper::vectors::to_json(&v));
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn unwritable_output_is_a_clear_error_not_a_panic() {
    for sub in ["vectors", "accuracy"] {
        let out = bin().args([sub, "--out", "/proc/tdm-stepper-cannot-write-here"]).output().unwrap();
        assert_eq!(out.status.code(), Some(1), "{sub}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.starts_with("tdm-stepper: error: cannot write"), "{sub}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
    let out = bin().arg("no-such-command").output().unwrap();
    assert!(!out.status.success());
}

fn write_moves(name: &str, text: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("sim_cli");
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn sim_rejects_bad_input_with_a_clear_message() {
    let ok = write_moves("ok.json", r#"{"clock_hz": 1000000, "axes": [{"trapezoid": {"steps": 10, "t_acc_s": 0.002, "t_cruise_s": 0, "t_dec_s": 0.002}}]}"#);
    let seg = r#"{"v0_steps_per_s": 0, "t_s": 0.001, "steps": 1}"#;
    let many = write_moves("many.json", &format!(r#"{{"axes": [{{"segments": [{}]}}]}}"#, vec![seg; 19].join(",")));
    let unknown = write_moves("unknown.json", r#"{"axes": [{"trapezoid": {"steps": 10, "t_acc": 0.1, "t_cruise_s": 0, "t_dec_s": 0.1}}]}"#);
    let missing = write_moves("missing.json", r#"{"axes": [{"segments": [{"v0_steps_per_s": 0, "steps": 1}]}]}"#);
    let wrong_type = write_moves("wrong_type.json", r#"{"axes": [{"segments": [{"v0_steps_per_s": 0, "t_s": 0.1, "steps": 1.5}]}]}"#);
    let both = write_moves("both.json", &format!(r#"{{"axes": [{{"segments": [{seg}], "trapezoid": {{"steps": 10, "t_acc_s": 0.1, "t_cruise_s": 0, "t_dec_s": 0.1}}}}]}}"#));
    let three = write_moves("three.json", &format!(r#"{{"axes": [{{"segments": [{seg}]}}, {{"segments": [{seg}]}}, {{"segments": [{seg}]}}]}}"#));
    let neg = write_moves("neg.json", r#"{"axes": [{"segments": [{"v0_steps_per_s": 0, "t_s": -1, "steps": 1}]}]}"#);
    let report = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("sim_cli/r.json");
    let cases: Vec<(Vec<String>, &str)> = vec![
        (vec!["--moves".into(), "/no/such/file.json".into()], "cannot read"),
        (vec!["--moves".into(), many.display().to_string()], "holds 18"),
        (vec!["--moves".into(), unknown.display().to_string()], "axes[0].trapezoid: unknown field \"t_acc\" (the fields are steps, t_acc_s, t_cruise_s, t_dec_s)"),
        (vec!["--moves".into(), missing.display().to_string()], "axes[0].segments[0]: missing field \"t_s\""),
        (vec!["--moves".into(), wrong_type.display().to_string()], "axes[0].segments[0].steps: expected an integer, found 1.5"),
        (vec!["--moves".into(), both.display().to_string()], "axes[0]: give exactly one of"),
        (vec!["--moves".into(), three.display().to_string()], "lists 3 axes"),
        (vec!["--moves".into(), neg.display().to_string()], "axis 0 segment 0"),
        (vec!["--moves".into(), ok.display().to_string(), "--axes".into(), "17".into()], "axis counts are 1 to 16"),
        (vec!["--moves".into(), ok.display().to_string(), "--vcd-window".into(), "0:1".into()], "--vcd-window needs --vcd"),
        (vec!["--moves".into(), ok.display().to_string(), "--vcd".into(), "x.vcd".into(), "--vcd-window".into(), "2:1".into()], "START < END"),
        (vec!["--moves".into(), ok.display().to_string(), "--engine".into(), "rust-hdl".into(), "--vcd".into(), "x.vcd".into()], "--vcd needs --engine verilator"),
        (vec!["--moves".into(), ok.display().to_string(), "--engine".into(), "spice".into()], "expected verilator or rust-hdl"),
    ];
    for (args, msg) in cases {
        let out = bin().arg("sim").args(&args).arg("--report").arg(&report).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} succeeded");
        assert!(err.contains(msg), "{args:?}: {err:?} lacks {msg:?}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
}

/// The same short move in both engines gives the same edges, and the model's.
#[test]
fn sim_engines_agree_on_a_short_move() {
    let moves = write_moves(
        "short.json",
        r#"{"clock_hz": 1000000, "axes": [
            {"trapezoid": {"steps": 40, "t_acc_s": 0.004, "t_cruise_s": 0.002, "t_dec_s": 0.004}},
            {"segments": [{"v0_steps_per_s": 0, "t_s": 0.004, "steps": -10}, {"v0_steps_per_s": 5000, "t_s": 0.002, "steps": -10}]}]}"#,
    );
    let mut reports = Vec::new();
    for engine in ["verilator", "rust-hdl"] {
        let report = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("sim_cli/short_{engine}.json"));
        let work = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("sim_cli/work_{engine}"));
        let out = bin().arg("sim").arg("--moves").arg(&moves).args(["--engine", engine]).arg("--report").arg(&report).arg("--work").arg(&work).output().unwrap();
        assert!(out.status.success(), "{engine}: {}", String::from_utf8_lossy(&out.stderr));
        let r: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
        assert_eq!(r["skew_ticks"], 0, "{engine}");
        assert_eq!(r["axes"][0]["final_position"], 40, "{engine}");
        assert_eq!(r["axes"][1]["final_position"], -20, "{engine}");
        for a in 0..2 {
            assert!(r["axes"][a]["max_edge_error_ticks"].as_f64().unwrap() <= 1.0, "{engine} axis {a}");
        }
        reports.push(r);
    }
    for a in 0..2 {
        assert_eq!(reports[0]["axes"][a]["edge_cycles"], reports[1]["axes"][a]["edge_cycles"], "axis {a}: engines differ");
    }
}

/// `sim` tells the truth: a rejected segment (and the start it blocks) and an
/// underrun are printed on the axis's console line with the reason, in the report
/// and in the SVG, and make the exit status non-zero unless --allow-problems; an
/// underrunning move still runs to its end.
#[test]
fn sim_reports_rejections_blocked_starts_and_underruns() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("sim_cli");
    let rejected = write_moves(
        "rejected.json",
        r#"{"clock_hz": 1000000, "axes": [
            {"trapezoid": {"steps": 20, "t_acc_s": 0.002, "t_cruise_s": 0, "t_dec_s": 0.002}},
            {"segments": [{"v0_steps_per_s": 100000, "t_s": 0.001, "steps": 10}]}]}"#,
    );
    // 300 steps at 20 ticks each: below K·t_calc. The default core (minimum period
    // K·t_calc) rejects it; one exported with --min-period 2 takes it and underruns.
    let fast = write_moves("fast.json", r#"{"clock_hz": 1000000, "axes": [{"segments": [{"v0_steps_per_s": 50000, "t_s": 0.006, "steps": 300}]}]}"#);
    let run = |moves: &PathBuf, name: &str, extra: &[&str]| {
        let report = dir.join(format!("report_{name}.json"));
        let work = dir.join("work_truth");
        let out = bin().arg("sim").arg("--moves").arg(moves).arg("--report").arg(&report).arg("--work").arg(&work).args(extra).output().unwrap();
        let r: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
        let svg = std::fs::read_to_string(report.with_extension("svg")).unwrap();
        (out, r, svg)
    };

    let (out, r, svg) = run(&rejected, "rejected", &[]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "exit 0 with a rejected segment:\n{stdout}");
    assert!(stdout.contains("axis 1: PROBLEM: segment 0 rejected, error 2"), "{stdout}");
    assert!(stdout.contains("axis 0: PROBLEM: did not start: axis 1 has no valid segment, so the core cancelled the START (GSTATUS.START_FAILED)"), "{stdout}");
    assert!(stderr.contains("did not run as planned on axis 0, 1"), "{stderr}");
    assert_eq!(r["ok"], false);
    assert_eq!(r["axes"][0]["steps"], 0, "axis 0 moved although axis 1's start could not complete");
    assert!(svg.contains("no STEP edge") && svg.contains("rejected"), "the SVG does not say what went wrong");

    let (out, r, _) = run(&fast, "fast_default", &[]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(!out.status.success(), "exit 0 with a rejected segment:\n{stdout}");
    assert!(stdout.contains("axis 0: PROBLEM: segment 0 rejected, error 3 (PERIOD_TOO_SHORT)"), "{stdout}");
    assert_eq!(r["axes"][0]["steps"], 0, "{stdout}");

    let (out, r, _) = run(&fast, "fast", &["--min-period", "2"]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(!out.status.success(), "exit 0 with an underrun:\n{stdout}");
    assert!(stdout.contains("axis 0: PROBLEM: underrun"), "{stdout}");
    assert_eq!(r["axes"][0]["underrun"], true);
    // The run continued until the late move finished: every step, the right position.
    assert_eq!(r["axes"][0]["steps"], 300, "{stdout}");
    assert_eq!(r["axes"][0]["final_position"], 300, "{stdout}");
    let (out, r, _) = run(&fast, "fast_allowed", &["--min-period", "2", "--allow-problems"]);
    assert!(out.status.success(), "--allow-problems: {}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(r["ok"], false);
}


/// docs/moves.schema.json is the schema the code makes from the same field table as
/// its checker, and every committed example follows the checker.
#[test]
fn moves_schema_is_committed_and_the_examples_follow_it() {
    let committed = std::fs::read_to_string(repo().join("docs/moves.schema.json")).unwrap();
    assert_eq!(committed, tdm_stepper::sim::moves_schema(), "docs/moves.schema.json is stale: write tdm_stepper::sim::moves_schema() into it");
    let schema: serde_json::Value = serde_json::from_str(&committed).unwrap();
    for (object, field, ty, _) in tdm_stepper::sim::MOVES_FIELDS {
        assert!(committed.contains(&format!("\"{field}\"")), "{object}.{field} not in the schema");
        let _ = ty;
    }
    assert_eq!(schema["properties"]["axes"]["items"]["oneOf"].as_array().unwrap().len(), 5);
    for e in std::fs::read_dir(repo().join("examples")).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "json") {
            tdm_stepper::sim::parse_moves(&std::fs::read_to_string(&p).unwrap()).unwrap_or_else(|err| panic!("{}: {err}", p.display()));
        }
    }
}

/// The README's promise about errors at push is the contract's number, which
/// system::a_bad_push_is_reported_at_the_bus_within_the_documented_bound measures.
#[test]
fn readme_push_error_bound_is_the_contracts() {
    let n = tdm_stepper::regs::PUSH_VERDICT_BUS_CLOCKS;
    let text = readme().split_whitespace().collect::<Vec<_>>().join(" ");
    assert!(text.contains(&format!("STATUS.ERROR shows it within {n} bus clocks")), "README's push-error bound is not {n} bus clocks");
    let regs_md = std::fs::read_to_string(repo().join("docs/registers.md")).unwrap();
    assert!(regs_md.contains(&format!("at most {n} bus clocks after NWE rises")), "docs/registers.md's push-error bound is not {n}");
}

/// The README's FPGA integration example, run as written in a scratch folder: the
/// named export, then each shell line (lint, the smoke testbench in Icarus, yosys).
/// The lint and yosys print nothing; the smoke test passes.
#[test]
fn readme_fpga_example_runs_as_written() {
    let cmds = commands_under("**Worked example** (run as written, from the repository root, by a test)");
    assert_eq!(cmds.len(), 4, "{cmds:?}");
    let work = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("readme_fpga_example");
    let _ = std::fs::remove_dir_all(&work);
    std::fs::create_dir_all(&work).unwrap();
    let export = cmds[0].strip_prefix("cargo run --release -- ").expect("the export first");
    let out = bin().current_dir(&work).args(export.split_whitespace()).output().unwrap();
    assert!(out.status.success(), "{}: {}", cmds[0], String::from_utf8_lossy(&out.stderr));
    let mut printed = Vec::new();
    for c in &cmds[1..] {
        let out = Command::new("sh").current_dir(&work).args(["-c", c]).output().unwrap();
        let text = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
        assert!(out.status.success(), "{c}: {text}");
        printed.push(text);
    }
    assert_eq!(printed[0].trim(), "", "lint: {}", printed[0]);
    assert!(printed[1].contains("PASS: ID_MAGIC 5453, ID_AXES 3"), "smoke: {}", printed[1]);
    assert_eq!(printed[2].trim(), "", "yosys: {}", printed[2]);
    assert!(readme().contains("the smoke test prints `PASS: ID_MAGIC 5453, ID_AXES 3`"));
}

#[test]
fn readme_io_example_runs_as_written() {
    let cmds = commands_under("**Machine I/O worked example** (run as written, from the repository root, by a test)");
    assert_eq!(cmds.len(), 2, "{cmds:?}");
    let work = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("readme_io_example");
    let _ = std::fs::remove_dir_all(&work);
    std::fs::create_dir_all(&work).unwrap();
    let export = cmds[0].strip_prefix("cargo run --release -- ").expect("the export first");
    let out = bin().current_dir(&work).args(export.split_whitespace()).output().unwrap();
    assert!(out.status.success(), "{}: {}", cmds[0], String::from_utf8_lossy(&out.stderr));
    let out = Command::new("sh").current_dir(&work).args(["-c", &cmds[1]]).output().unwrap();
    let text = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success() && text.trim().is_empty(), "{}: {text}", cmds[1]);
    let m: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(work.join("build/io/manifest.json")).unwrap()).unwrap();
    assert_eq!(m["io"], true);
    let names: Vec<&str> = m["ports"].as_array().unwrap().iter().map(|p| p["name"].as_str().unwrap()).collect();
    for n in ["estop_n", "probe", "limit_neg", "limit_pos", "home", "alarm", "drv_enable"] {
        assert!(names.contains(&n), "manifest lacks {n}");
    }
}

/// The Verilator build is cached by what it is built from (the exported Verilog, the
/// testbench, the main loop): a second `sim` of the same core, even with another move
/// of a similar length and a VCD window, reuses it and gives the first run's result
/// for the same move; another core (K = 3) rebuilds.
#[test]
fn sim_reuses_the_verilator_build_of_the_same_core() {
    let moves = write_moves(
        "cache.json",
        r#"{"clock_hz": 1000000, "axes": [{"move": {"steps": 30, "speed_steps_per_s": 4000, "accel_steps_per_s2": 2000000, "decel_steps_per_s2": 1000000}}]}"#,
    );
    let other = write_moves("cache2.json", r#"{"clock_hz": 1000000, "axes": [{"trapezoid": {"steps": -25, "t_acc_s": 0.003, "t_cruise_s": 0.001, "t_dec_s": 0.003}}]}"#);
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("sim_cli/cache");
    let _ = std::fs::remove_dir_all(&dir);
    let work = dir.join("work");
    let exe = work.join("obj_dir/Vsim");
    let sim = |moves: &PathBuf, name: &str, extra: &[&str]| -> serde_json::Value {
        let report = dir.join(format!("{name}.json"));
        let out = bin().arg("sim").arg("--moves").arg(moves).arg("--report").arg(&report).arg("--work").arg(&work).args(extra).output().unwrap();
        assert!(out.status.success(), "{name}: {}", String::from_utf8_lossy(&out.stderr));
        serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap()
    };
    let modified = || std::fs::metadata(&exe).unwrap().modified().unwrap();
    let first = sim(&moves, "first", &[]);
    let built = modified();
    let vcd = dir.join("second.vcd");
    let second = sim(&other, "second", &["--vcd", vcd.to_str().unwrap()]);
    assert_eq!(second["axes"][0]["final_position"], -25);
    let third = sim(&moves, "third", &[]);
    assert_eq!(modified(), built, "the same core was rebuilt");
    assert_eq!(first["axes"][0]["edge_cycles"], third["axes"][0]["edge_cycles"]);
    assert_eq!(first["axes"][0]["final_position"], 30);
    assert!(std::fs::metadata(&vcd).unwrap().len() > 1000, "the VCD of the reused build");
    let k3 = sim(&moves, "k3", &["--axes", "3"]);
    assert_ne!(modified(), built, "another core must rebuild");
    let rel = |r: &serde_json::Value| -> Vec<i64> {
        let e: Vec<i64> = r["axes"][0]["edge_cycles"].as_array().unwrap().iter().map(|c| c.as_i64().unwrap()).collect();
        e.iter().map(|c| c - e[0]).collect()
    };
    assert_eq!(rel(&k3), rel(&first), "the same move on K = 3, from its release");
}

/// The README's controlled-stop latency is `t_stop_form` at the export's radix, which
/// hdl_core::controlled_stop_ramps_down_from_every_kind_of_segment measures.
#[test]
fn readme_controlled_stop_latency_is_the_measured_constant() {
    let n = tdm_stepper::hdl::core::t_stop_form(tdm_stepper::export::RADIX_BITS);
    let text = readme().split_whitespace().collect::<Vec<_>>().join(" ");
    assert!(text.contains(&format!("forms the ramp in {n} clk cycles")), "README's controlled-stop latency is not {n} cycles");
}

/// The crate's source files under `dir` (recursively), with their text.
fn sources_under(dir: &Path) -> Vec<(PathBuf, String)> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            out.extend(sources_under(&p));
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push((p.clone(), std::fs::read_to_string(&p).unwrap()));
        }
    }
    out
}

/// The crate paths a file names outside its comments.
fn crate_refs(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    for line in text.lines() {
        let code = line.split("//").next().unwrap();
        let mut rest = code;
        while let Some(i) = rest.find("crate::") {
            let tail = &rest[i + 7..];
            let name: String = tail.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
            out.push(name);
            rest = tail;
        }
    }
    out
}

#[test]
fn layers_point_one_way() {
    let src = repo().join("ip/src");
    // (files, the crate modules they may name)
    let bottom: &[&str] = &["model", "regs", "latency"];
    let mut layers: Vec<(Vec<(PathBuf, String)>, Vec<&str>)> = vec![
        (sources_under(&src.join("model")), bottom.to_vec()),
        (
            ["regs.rs", "latency.rs"].iter().map(|f| (src.join(f), std::fs::read_to_string(src.join(f)).unwrap())).collect(),
            bottom.to_vec(),
        ),
    ];
    let mut hdl_allowed = bottom.to_vec();
    hdl_allowed.push("hdl");
    layers.push((sources_under(&src.join("hdl")), hdl_allowed.clone()));
    let mut export_allowed = hdl_allowed;
    export_allowed.push("export");
    let export = repo().join("ip/tool/src/export.rs");
    layers.push((vec![(export.clone(), std::fs::read_to_string(&export).unwrap())], export_allowed));
    let mut checked = 0;
    for (files, allowed) in &layers {
        for (path, text) in files {
            checked += 1;
            for r in crate_refs(text) {
                assert!(allowed.contains(&r.as_str()), "{} names crate::{r}; its layer may name only {allowed:?}", path.display());
            }
        }
    }
    assert!(checked > 40, "only {checked} files checked");
    // And the check sees a violation when there is one.
    assert_eq!(crate_refs("use crate::hdl::core::t_setup; // crate::export"), vec!["hdl".to_string()]);
}

/// The README's bus exports, run as written (in a scratch folder): each manifest names
/// its bus and has its pins in place of the EXMC pins; each export's smoke testbench
/// passes in Icarus; the latencies the README states are the code's.
#[test]
fn readme_bus_exports_run_as_written() {
    let cmds = commands_under("## Picking a bus (`export --bus exmc|spi|wb|axil`)");
    assert_eq!(cmds.len(), 3, "{cmds:?}");
    let work = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("readme_bus_example");
    let _ = std::fs::remove_dir_all(&work);
    std::fs::create_dir_all(&work).unwrap();
    let pins: [(&str, &[&str]); 3] = [
        ("spi", &["cs_n", "sck", "mosi", "miso", "miso_oe"]),
        ("wb", &["wb_cyc", "wb_stb", "wb_we", "wb_adr", "wb_sel", "wb_dat_w", "wb_dat_r", "wb_ack", "wb_err"]),
        ("axil", &["s_axil_awaddr", "s_axil_wstrb", "s_axil_bresp", "s_axil_araddr", "s_axil_rdata", "s_axil_rready"]),
    ];
    for (cmd, (bus, names_wanted)) in cmds.iter().zip(pins) {
        let export = cmd.strip_prefix("cargo run --release -- ").expect("an export");
        let out = bin().current_dir(&work).args(export.split_whitespace()).output().unwrap();
        assert!(out.status.success(), "{cmd}: {}", String::from_utf8_lossy(&out.stderr));
        let dir = work.join(format!("build/ip_{bus}"));
        let m: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(dir.join("manifest.json")).unwrap()).unwrap();
        assert_eq!(m["bus"], bus);
        let names: Vec<&str> = m["ports"].as_array().unwrap().iter().map(|p| p["name"].as_str().unwrap()).collect();
        for n in names_wanted {
            assert!(names.contains(n), "{bus}: manifest lacks {n}");
        }
        assert!(!names.contains(&"ne") && !names.contains(&"data_out"), "an EXMC pin in a {bus} export");
        // The export's own smoke testbench passes in Icarus (for Wishbone and
        // AXI4-Lite it also sees an unmapped address refused).
        let tb = tdm_stepper::package::TB_FILE;
        let vvp = dir.join("smoke.vvp");
        let out = std::process::Command::new("iverilog").current_dir(&dir).args(["-g2005", "-o"]).arg(&vvp).args([tb, "tdm_stepper.v"]).output().unwrap();
        assert!(out.status.success(), "{bus}: iverilog: {}", String::from_utf8_lossy(&out.stderr));
        let out = std::process::Command::new("vvp").arg(&vvp).output().unwrap();
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(out.status.success() && text.contains("PASS"), "{bus} smoke test: {text}");
        if bus != "spi" {
            assert!(text.contains("refused"), "{bus} smoke test: {text}");
        }
    }
    // The limits and latencies the README states are the register table's.
    let text = readme();
    assert!(text.contains("up to `bus_clk`/4") && tdm_stepper::regs::SPI_SCK_HALF_MIN == 2);
    assert!(text.contains("up to 32 16-bit") && tdm_stepper::regs::SPI_MAX_BURST == 32);
    use tdm_stepper::latency::{AXIL_READ_RESP, AXIL_WRITE_RESP, WB_READ_ACK, WB_WRITE_ACK};
    assert!(text.contains(&format!("acknowledged {WB_WRITE_ACK} (write) or {WB_READ_ACK} (read) cycles")), "README: Wishbone latency");
    assert!(text.contains(&format!("AXI4-Lite answers {AXIL_WRITE_RESP} and {AXIL_READ_RESP}")), "README: AXI4-Lite latency");
}

/// The README's board build, run as written from a scratch folder inside the
/// repository (the tools of its `.venv-nextpnr/`): the bitstream is written, both PLL
/// clocks meet their frequency, and the utilisation is reported.
#[test]
fn readme_board_build_runs_as_written() {
    let cmds = commands_under("## Reference board design (Radiona ULX3S)");
    assert_eq!(cmds.len(), 2, "{cmds:?}");
    assert_eq!(cmds[0], "scripts/install-nextpnr.sh");
    let work = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("readme_board");
    let _ = std::fs::remove_dir_all(&work);
    std::fs::create_dir_all(&work).unwrap();
    let args = cmds[1].strip_prefix("cargo run --release -- ").expect("a board build");
    let t0 = std::time::Instant::now();
    let out = bin().current_dir(&work).args(args.split_whitespace()).output().unwrap();
    let text = String::from_utf8_lossy(&out.stdout).to_string() + &String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{}: {text}", cmds[1]);
    eprintln!("board build: {:.0} s\n{text}", t0.elapsed().as_secs_f64());
    let bit = work.join("build/board/board.bit");
    assert!(std::fs::metadata(&bit).map(|m| m.len() > 100_000).unwrap_or(false), "{} missing or small", bit.display());
    assert!(text.contains("Timing met") && text.contains("| clk | 50.0 |") && text.contains("| bus_clk | 100.0 |"), "{text}");
    assert!(text.contains("TRELLIS_COMB") && text.contains("TRELLIS_IO"), "utilisation: {text}");
}

/// The words of `text` that follow `prefix` up to the next non-identifier
/// character (e.g. the port names of `.name(` connections).
fn names_after<'a>(text: &'a str, prefix: &str) -> Vec<&'a str> {
    text.match_indices(prefix)
        .map(|(i, _)| {
            let rest = &text[i + prefix.len()..];
            let end = rest.find(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).unwrap_or(rest.len());
            &rest[..end]
        })
        .collect()
}

/// The board's top level connects every port of the IP it exports (the machine I/O
/// included), and the constraint file places every pin of the top level, each bit
/// of a bus, on a site of its own.
#[test]
fn the_top_level_connects_every_ip_port_and_the_lpf_places_every_pin() {
    let core = board::TOP_V.split("tdm_stepper core (").nth(1).expect("the IP instance").split(");").next().unwrap();
    let connected = names_after(core, ".");
    for p in tdm_stepper::export::ports_of(&board::ip_options()) {
        assert!(connected.contains(&p.name), "top.v leaves the IP's port {} unconnected", p.name);
    }
    for io in ["estop_n", "limit_neg", "home", "alarm", "drv_enable", "probe"] {
        assert!(connected.contains(&io), "the board has the machine I/O ({io})");
    }
    let header = board::TOP_V.split("module ulx3s_top (").nth(1).unwrap().split(");").next().unwrap();
    let mut sites = std::collections::BTreeSet::new();
    for line in header.lines().map(str::trim).filter(|l| l.starts_with("input") || l.starts_with("output")) {
        let name = line.trim_end_matches(',').split_whitespace().last().unwrap();
        let width = match line.split_once('[') {
            Some((_, r)) => r.split(':').next().unwrap().parse::<usize>().unwrap() + 1,
            None => 1,
        };
        for b in 0..width {
            let comp = if line.contains('[') { format!("{name}[{b}]") } else { name.to_string() };
            let loc = board::LPF
                .lines()
                .find(|l| l.starts_with("LOCATE COMP") && l.contains(&format!("\"{comp}\"")))
                .unwrap_or_else(|| panic!("ulx3s.lpf does not place {comp}"));
            assert!(board::LPF.lines().any(|l| l.starts_with("IOBUF") && l.contains(&format!("\"{comp}\""))), "no IOBUF for {comp}");
            let site = names_after(loc, "SITE \"")[0];
            assert!(sites.insert(site.to_string()), "site {site} used twice ({comp})");
        }
    }
    assert!(sites.len() >= 31, "{} pins placed", sites.len());
}
