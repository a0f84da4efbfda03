//! `tdm-stepper export` as a user runs it, and what it writes: the four files, the
//! committed docs/registers.md and docs/tdm_stepper_regs.h (they must equal what the
//! register table generates), the C header under gcc -Wall -Werror, the module's
//! ports against the documented list, Verilator -Wall lint for K = 1, 2, 8 and 16
//! (with the machine I/O at K = 1, 2, 3 and 16, the S-curve option at K = 1, 3 and 16, and the
//! baseline), and clear errors
//! for bad arguments.

#[path = "../../tests/common/mod.rs"]
mod common;

use common::*;
use std::path::{Path, PathBuf};
use std::process::Command;
use tdm_stepper::export::{self, ExportOptions};
use tdm_stepper::regs;
use tdm_stepper::verify::Simulator;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_tdm-stepper"))
}

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn export_to(args: &[&str], name: &str) -> PathBuf {
    let dir = sim_dir(name, Simulator::Verilator);
    let _ = std::fs::remove_dir_all(&dir);
    let out = bin().args(["export", "--out"]).arg(&dir).args(args).output().unwrap();
    assert!(out.status.success(), "export {args:?} failed: {}", String::from_utf8_lossy(&out.stderr));
    dir
}

#[test]
fn default_export_writes_the_ip_and_the_committed_docs_are_current() {
    let dir = export_to(&[], "export_default");
    for f in ["tdm_stepper.v", "tdm_stepper_regs.h", "registers.md", "manifest.json"] {
        assert!(dir.join(f).is_file(), "{f} not written");
    }
    let read = |p: &Path| std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    assert_eq!(
        read(&dir.join("registers.md")),
        read(&repo().join("docs/registers.md")),
        "docs/registers.md is stale: run `cargo run --release -- export --out /tmp/ip` and copy registers.md"
    );
    assert_eq!(
        read(&dir.join("tdm_stepper_regs.h")),
        read(&repo().join("docs/tdm_stepper_regs.h")),
        "docs/tdm_stepper_regs.h is stale: copy it from a default export"
    );
    let m: serde_json::Value = serde_json::from_str(&read(&dir.join("manifest.json"))).unwrap();
    let o = ExportOptions::default();
    assert_eq!(m["top_module"], "tdm_stepper");
    assert_eq!(m["axes"], 2);
    assert_eq!(m["clock_hz"], 50_000_000);
    assert_eq!(m["t_calc_cycles"], o.params().t_calc as u64);
    assert_eq!(m["queue_depth"], export::QUEUE_DEPTH as u64);
    assert_eq!(m["period_fifo_depth"], export::FIFO_DEPTH as u64);
    assert_eq!(m["min_period_ticks"], 2 * o.params().t_calc as u64);
    assert_eq!(m["sustainable_period_ticks"], 2 * o.params().t_calc as u64);
    let rmax = (1u64 << 32) / (2 * o.params().t_calc as u64 + 1);
    assert_eq!(m["max_rate_q32"], rmax);
    assert!((m["max_step_rate_hz"].as_f64().unwrap() - 50e6 * rmax as f64 / 2f64.powi(32)).abs() < 1e-6);
    assert_eq!(m["tools"]["rust_hdl"], "0.46.0");
    assert_eq!(m["ports"].as_array().unwrap().len(), export::ports(2, 0).len());
    regs::check_table().unwrap();
}

/// The module header and port declarations of the exported Verilog, as
/// (name, direction, width).
fn verilog_ports(v: &str) -> Vec<(String, String, usize)> {
    let start = v.find("\nmodule tdm_stepper(").expect("module tdm_stepper");
    let body = &v[start..];
    let header_end = body.find(");").unwrap();
    let names: Vec<&str> = body["\nmodule tdm_stepper(".len()..header_end].split(',').map(|s| s.trim()).collect();
    names
        .iter()
        .map(|n| {
            let decl = body
                .lines()
                .map(|l| l.trim())
                .find(|l| (l.starts_with("input ") || l.starts_with("output ")) && l.trim_end_matches(';').ends_with(&format!(" {n}")))
                .unwrap_or_else(|| panic!("no declaration of port {n}"));
            let dir = decl.split_whitespace().next().unwrap().to_string();
            let width = match (decl.find('['), decl.find(':')) {
                (Some(a), Some(b)) => decl[a + 1..b].parse::<usize>().unwrap() + 1,
                _ => 1,
            };
            (n.to_string(), dir, width)
        })
        .collect()
}

/// Locals that a combinational process writes, reads into another signal and then
/// writes again on one path through its branches: Verilog's blocking assignments give
/// that read the first value, rust-hdl's simulation the last (it settles each signal to
/// its final `next`), so the exported Verilog would differ from the simulation it was
/// checked with (a trap of rust-hdl's generator: read after the last write, or use two
/// locals). A line-based scan of the generated `always @(*)` blocks (one statement per
/// line, `if`/`else` chains with `begin`/`end`, as rust-hdl writes them): branches of one
/// chain exclude each other. Returns `(module, signal, line of the second write)`.
fn rewritten_after_read(v: &str) -> Vec<(String, String, usize)> {
    // Drops sized literals (32'h1f): their digits are not names.
    let strip = |t: &str| -> String {
        let mut out = String::new();
        let b = t.as_bytes();
        let mut i = 0;
        while i < b.len() {
            if b[i] == b'\'' && i + 1 < b.len() && b"hbdo".contains(&b[i + 1]) {
                while out.ends_with(|c: char| c.is_ascii_digit()) {
                    out.pop();
                }
                i += 2;
                while i < b.len() && (b[i].is_ascii_hexdigit() || b[i] == b'_' || b[i] == b'x' || b[i] == b'z') {
                    i += 1;
                }
                out.push(' ');
            } else {
                out.push(b[i] as char);
                i += 1;
            }
        }
        out
    };
    let names = |t: &str| -> Vec<String> {
        let mut v = Vec::new();
        let mut cur = String::new();
        for c in t.chars().chain(std::iter::once(' ')) {
            if c.is_ascii_alphanumeric() || c == '_' || c == '$' {
                cur.push(c);
            } else {
                if cur.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_') {
                    v.push(cur.clone());
                }
                cur.clear();
            }
        }
        v
    };
    // A path: the (chain, branch) pairs of the enclosing ifs. Two lines can run in one
    // pass unless some chain holds them in different branches.
    type Path = Vec<(usize, usize)>;
    let together = |a: &Path, b: &Path| !a.iter().any(|&(c, x)| b.iter().any(|&(d, y)| c == d && x != y));
    let lines: Vec<&str> = v.lines().collect();
    let mut found = Vec::new();
    let mut module = String::new();
    let mut i = 0;
    while i < lines.len() {
        let l = lines[i].trim();
        if let Some(m) = l.strip_prefix("module ") {
            module = m.split('(').next().unwrap_or("").trim().to_string();
        }
        if !(l.starts_with("always @(*)") && l.ends_with("begin")) {
            i += 1;
            continue;
        }
        let mut path: Path = Vec::new();
        let mut chains = 0usize;
        let mut closed: Option<(usize, usize)> = None;
        // Per signal: its writes, and reads that follow one of them, with their paths.
        let mut writes = std::collections::HashMap::<String, Vec<(usize, Path)>>::new();
        let mut reads = std::collections::HashMap::<String, Vec<(usize, Path)>>::new();
        let mut j = i + 1;
        while j < lines.len() {
            let t = lines[j].trim();
            j += 1;
            if t == "end" {
                match path.pop() {
                    Some(p) => closed = Some(p),
                    None => break,
                }
                continue;
            }
            let (cond, opens) = if let Some(c) = t.strip_prefix("else if") {
                let (chain, branch) = closed.expect("else after an if");
                path.push((chain, branch + 1));
                (Some(c), true)
            } else if t.starts_with("else") {
                let (chain, branch) = closed.expect("else after an if");
                path.push((chain, branch + 1));
                (None, false)
            } else if t.starts_with("if") {
                (Some(t), true)
            } else {
                (None, false)
            };
            if let Some(c) = cond {
                assert!(c.ends_with("begin"), "{module}: an if without begin: {t}");
                for r in names(&strip(c)) {
                    if writes.get(&r).is_some_and(|w| w.iter().any(|(_, p)| together(p, &path))) {
                        reads.entry(r).or_default().push((j, path.clone()));
                    }
                }
                if opens && t.starts_with("if") {
                    chains += 1;
                    path.push((chains, 0));
                }
                continue;
            }
            if t.starts_with("else") {
                continue;
            }
            // An assignment: `name = ...;` or `name[...] = ...;`.
            let Some(eq) = t.char_indices().find(|&(p, c)| c == '=' && t[p + 1..].chars().next() != Some('=') && !t[..p].ends_with(['=', '!', '<', '>'])).map(|(p, _)| p) else {
                continue;
            };
            let lhs = t[..eq].split('[').next().unwrap_or("").trim().to_string();
            for r in names(&strip(&t[eq + 1..])) {
                if r != lhs && writes.get(&r).is_some_and(|w| w.iter().any(|(_, p)| together(p, &path))) {
                    reads.entry(r).or_default().push((j, path.clone()));
                }
            }
            let trap = reads.get(&lhs).is_some_and(|rs| {
                rs.iter().any(|(r, rp)| together(rp, &path) && writes[&lhs].iter().any(|(w, wp)| w < r && together(wp, rp) && together(wp, &path)))
            });
            if trap {
                found.push((module.clone(), lhs.clone(), j));
            }
            writes.entry(lhs).or_default().push((j, path.clone()));
        }
        i = j;
    }
    found
}

#[test]
fn exported_verilog_lints_clean_and_has_the_documented_ports() {
    // The scan itself: it finds the trap and passes an accumulator and a read after the last write.
    let trap = "module m(a, y);\n    always @(*) begin\n        x = a;\n        y = x & 32'h1;\n        if (a) begin\n            x = 32'h0;\n        end\n    end\nendmodule\n";
    assert_eq!(rewritten_after_read(trap), vec![("m".to_string(), "x".to_string(), 6)]);
    let branches = "module m(a, y);\n    always @(*) begin\n        x = a;\n        if (a) begin\n            y = x;\n        end\n        else begin\n            x = 32'h0;\n            y = x;\n        end\n    end\nendmodule\n";
    assert!(rewritten_after_read(branches).is_empty(), "a read and a write in exclusive branches");
    let fine = "module m(a, y);\n    always @(*) begin\n        x = 32'h0;\n        x = x | a;\n        if (x == 32'h0) begin\n            x = a;\n        end\n    end\nendmodule\n";
    assert_eq!(rewritten_after_read(fine).len(), 1, "a condition on x then a write of x is the trap too");
    let fine = "module m(a, y);\n    always @(*) begin\n        x = 32'h0;\n        x = x | a;\n        y = x;\n    end\nendmodule\n";
    assert!(rewritten_after_read(fine).is_empty());
    let cases = [
        (1, "tdm", "none", "trapezoid"),
        (2, "tdm", "none", "trapezoid"),
        (8, "tdm", "none", "trapezoid"),
        (16, "tdm", "none", "trapezoid"),
        (2, "baseline", "none", "trapezoid"),
        (1, "tdm", "all", "trapezoid"),
        (3, "tdm", "all", "trapezoid"),
        (16, "tdm", "all", "trapezoid"),
        (2, "tdm", "limits,watchdog", "trapezoid"),
        (1, "tdm", "estop,probe", "trapezoid"),
        // The S-curve option (export --profiles trapezoid,scurve), with and without the machine I/O.
        (1, "tdm", "none", "trapezoid,scurve"),
        (16, "tdm", "all", "trapezoid,scurve"),
        (3, "tdm", "limits,home", "trapezoid,scurve"),
        // Encoder feedback (export --encoder): alone, with every machine I/O group, with
        // some groups and the S-curve option.
        (1, "tdm", "none", "trapezoid+enc"),
        (16, "tdm", "none", "trapezoid+enc"),
        (2, "tdm", "all", "trapezoid+enc"),
        (3, "tdm", "probe,limits", "trapezoid,scurve+enc"),
        // The bus front ends (export --bus spi|wb|axil): alone, and with every other option.
        (2, "tdm", "none", "trapezoid+spi"),
        (3, "tdm", "all", "trapezoid,scurve+enc+spi"),
        (2, "tdm", "none", "trapezoid+wb"),
        (1, "tdm", "limits,home", "trapezoid+enc+wb"),
        (2, "tdm", "none", "trapezoid+axil"),
        (2, "tdm", "all", "trapezoid,scurve+axil"),
    ];
    for (k, arch, io, profiles) in cases {
        let (profiles, bus) = match profiles.rsplit_once('+') {
            Some((p, b)) if ["spi", "wb", "axil"].contains(&b) => (p, b.parse::<export::Bus>().unwrap()),
            _ => (profiles, export::Bus::Exmc),
        };
        let wrapped = bus != export::Bus::Exmc; // a front end in front of the EXMC core
        let (profiles, enc) = match profiles.strip_suffix("+enc") {
            Some(p) => (p, true),
            None => (profiles, false),
        };
        let tag = if profiles == "trapezoid" { String::new() } else { "_scurve".into() };
        let tag = if enc { tag + "_enc" } else { tag };
        let tag = if wrapped { format!("{tag}_{}", bus.name()) } else { tag };
        let mut args = vec!["--axes".to_string(), k.to_string(), "--arch".into(), arch.into(), "--io".into(), io.into(), "--profiles".into(), profiles.into()];
        if enc {
            args.push("--encoder".into());
        }
        if wrapped {
            args.extend(["--bus".into(), bus.name().into()]);
        }
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let dir = export_to(&args, &format!("export_lint_{arch}_{k}_{io}{tag}"));
        let v = std::fs::read_to_string(dir.join("tdm_stepper.v")).unwrap();
        let mut want_ports = export::ports(k, { let c = export::parse_io(io).unwrap(); if c.io { tdm_stepper::regs::IO_ALL & !c.omit } else { 0 } });
        if enc {
            want_ports.extend(export::encoder_ports(k));
        }
        if wrapped {
            // The EXMC pins' place taken by the bus's pins, in the documented order.
            let exmc = ["ne", "noe", "nwe", "addr", "data_in", "data_out", "data_oe"];
            let at = want_ports.iter().position(|p| p.name == "ne").unwrap();
            want_ports.retain(|p| !exmc.contains(&p.name));
            want_ports.splice(at..at, bus.ports());
        }
        let want: Vec<(String, String, usize)> = want_ports.iter().map(|p| (p.name.to_string(), p.direction.to_string(), p.width)).collect();
        assert_eq!(verilog_ports(&v), want, "K = {k} {arch}: ports differ from export::ports (and the manifest)");
        // No system tasks or delays. (rust-hdl's flip-flops carry `initial q = 0`
        // blocks: power-up values, which FPGA synthesis honours.)
        let b = v.as_bytes();
        for (i, &c) in b.iter().enumerate() {
            let prev_ident = i > 0 && (b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_' || b[i - 1] == b'$');
            assert!(!(c == b'$' && !prev_ident), "K = {k}: a system task at byte {i}: {}", &v[i..(i + 20).min(v.len())]);
            assert!(!(c == b'#' && b.get(i + 1).is_some_and(|d| d.is_ascii_digit())), "K = {k}: a delay at byte {i}");
        }
        for l in v.lines().filter(|l| l.contains("initial")) {
            assert_eq!(l.trim(), "initial begin", "K = {k}: unexpected initial: {l}");
        }
        let inits = v.split("initial begin").skip(1).all(|rest| {
            let block = &rest[..rest.find("end").unwrap()];
            block.lines().map(|l| l.trim()).filter(|l| !l.is_empty()).all(|l| l.starts_with("q = ") && l.ends_with(';'))
        });
        assert!(inits, "K = {k}: an initial block does more than set a register's power-up value");
        let rw = rewritten_after_read(&v);
        assert!(rw.is_empty(), "K = {k} {arch} {io} {profiles}: locals written again after a read in one process (module, signal, line): {rw:?}");
        // The export folder alone: its own waiver file.
        let out = Command::new("verilator")
            .current_dir(&dir)
            .args(["--lint-only", "-Wall", "--top-module", "tdm_stepper"])
            .arg(tdm_stepper::package::WAIVER_FILE)
            .arg("tdm_stepper.v")
            .output()
            .expect("verilator is installed (scripts/test.sh installs it)");
        assert!(out.status.success(), "K = {k} {arch}: verilator -Wall:\n{}", String::from_utf8_lossy(&out.stderr));
    }
    // No true combinational loop (the waived UNOPTFLAT are block-level only).
    for case in ["export_lint_tdm_2_none", "export_lint_tdm_3_all", "export_lint_tdm_2_all_enc"] {
        let dir = sim_dir(case, Simulator::Verilator);
        let out = Command::new("yosys")
            .current_dir(&dir)
            .args(["-q", "-p", "read_verilog tdm_stepper.v; hierarchy -top tdm_stepper; proc; flatten; check -assert"])
            .output()
            .expect("yosys is installed");
        assert!(out.status.success(), "{case}: yosys check found a problem:\n{}", String::from_utf8_lossy(&out.stderr));
    }
}

/// `--io` takes `all`, `none` or the full list of groups; a partial list or an unknown
/// group is refused with a message naming the groups, and the baseline has no I/O.
#[test]
fn io_option_refuses_what_is_not_built() {
    for (args, says) in [
        (&["--io", "brakes"][..], "unknown group"),
        (&["--io", ""][..], "unknown group"),
        (&["--io", "all", "--arch", "baseline"][..], "TDM core only"),
    ] {
        let dir = sim_dir("export_io_refused", Simulator::Verilator);
        let out = bin().args(["export", "--out"]).arg(&dir).args(args).output().unwrap();
        assert!(!out.status.success(), "{args:?} exited 0");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(says), "{args:?}: {err}");
    }
    let dir = export_to(&["--io", "estop,probe,limits,home,alarm,watchdog"], "export_io_list");
    let m: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(dir.join("manifest.json")).unwrap()).unwrap();
    assert_eq!(m["io"], true, "every group listed is --io all");
    assert!(m["ports"].as_array().unwrap().iter().any(|p| p["name"] == "drv_enable"));
    // The controlled stop's smallest deceleration: the model's for the export's minimum
    // period, in the manifest and the header alike (absent without --io).
    let opts = tdm_stepper::export::ExportOptions { io: true, ..Default::default() };
    let want = tdm_stepper::model::stop::stop_decel_min(&opts.limits());
    assert_eq!(m["stop_decel_min"], want);
    let header = std::fs::read_to_string(dir.join("tdm_stepper_regs.h")).unwrap();
    assert!(header.contains(&format!("#define TDM_STOP_DECEL_MIN {want}u ")), "header's TDM_STOP_DECEL_MIN");
    // Some groups: the manifest names them, and only their ports are there.
    let dir = export_to(&["--io", "home,limits"], "export_io_some");
    let m: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(dir.join("manifest.json")).unwrap()).unwrap();
    assert_eq!(m["io_groups"], serde_json::json!(["limits", "home"]));
    let names: Vec<&str> = m["ports"].as_array().unwrap().iter().map(|p| p["name"].as_str().unwrap()).collect();
    assert!(names.contains(&"limit_neg") && names.contains(&"home") && names.contains(&"drv_enable"));
    assert!(!names.contains(&"estop_n") && !names.contains(&"probe") && !names.contains(&"alarm"));
    let plain = export_to(&[], "export_io_none");
    let m: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(plain.join("manifest.json")).unwrap()).unwrap();
    assert!(m.get("stop_decel_min").is_none() && !std::fs::read_to_string(plain.join("tdm_stepper_regs.h")).unwrap().contains("STOP_DECEL"));
}

#[test]
fn c_header_compiles_with_gcc_and_matches_the_table() {
    // The default export, and one with the machine I/O: each header has its own registers.
    for (args, io, omit) in [(&[][..], false, 0), (&["--io", "all"][..], true, 0), (&["--io", "limits,home"][..], true, regs::IO_ALL & !(regs::IO_LIMITS | regs::IO_HOME))] {
        let dir = export_to(args, &format!("export_header_{}", args.last().unwrap_or(&"none").replace(',', "_")));
        let params = tdm_stepper::export::ExportOptions { io, io_omit: omit, ..Default::default() }.params();
        let header = std::fs::read_to_string(dir.join("tdm_stepper_regs.h")).unwrap();
        assert_eq!(header.contains("TDM_IO_STATUS"), io, "the machine I/O's registers follow --io");
        let doc = std::fs::read_to_string(dir.join("registers.md")).unwrap();
        assert_eq!(doc.contains("| IO_STATUS |"), io, "registers.md follows --io");
        // The hard stop's contract only where there is an e-stop or a watchdog.
        assert_eq!(doc.contains("Machine I/O: hard stop"), params.io_groups() & (regs::IO_ESTOP | regs::IO_WATCHDOG) != 0, "{args:?}: the hard stop's contract");
        // A group not exported has no register or field in the header or the doc.
        let some = omit != 0;
        for (what, present) in [
            ("TDM_WD_TIMEOUT ", io && !some),
            ("TDM_PROBE_POS_LO(", io && !some),
            ("TDM_IO_AXIS_ALARM_MASK", io && !some),
            ("TDM_IO_CMD ", io && !some),
            ("TDM_IO_POLARITY_ESTOP_MASK", io && !some),
            ("TDM_STOP_HOME ", io),
            ("TDM_IO_AXIS_LIMIT_POS_MASK", io),
            ("TDM_IO_POLARITY_HOME_MASK", io),
            ("TDM_STOP_MODE_LIMITS_MASK", io),
        ] {
            assert_eq!(header.contains(what), present, "{args:?}: {what} in the header");
        }
        assert_eq!(doc.contains("| WD_TIMEOUT |"), io && !some, "{args:?}: WD_TIMEOUT in registers.md");
        let mut c = String::from("#include <assert.h>\n#include \"tdm_stepper_regs.h\"\nint main(void) {\n");
        // Every register's byte offset, for axes 0 and K-1, from the table.
        for r in regs::table_for(&params) {
            if r.per_axis {
                for a in [0usize, 1] {
                    c += &format!("    assert(TDM_{}({a}) == 0x{:X}u);\n", r.name, 2 * r.address(a));
                }
            } else {
                c += &format!("    assert(TDM_{} == 0x{:X}u);\n", r.name, 2 * r.address(0));
            }
            for f in r.fields.iter().filter(|f| f.name != "VALUE") {
                c += &format!("    assert(TDM_{}_{}_MASK == 0x{:X}u);\n", r.name, f.name, ((1u32 << f.width) - 1) << f.lsb);
            }
        }
        // A few by hand, as an MCU engineer reads them in docs/registers.md.
        c += "    assert(TDM_CTRL == 0x10u);\n    assert(TDM_STATUS(1) == 0x22Cu);\n    assert(TDM_POS_LO(0) == 0x20Eu);\n";
        c += "    assert(TDM_AXES == 2u && TDM_MAGIC == 0x5453u);\n    return 0;\n}\n";
        std::fs::write(dir.join("check.c"), c).unwrap();
        let out = Command::new("gcc")
            .current_dir(&dir)
            .args(["-std=c11", "-Wall", "-Wextra", "-Werror", "-o", "check", "check.c"])
            .output()
            .expect("gcc is installed");
        assert!(out.status.success(), "gcc:\n{}", String::from_utf8_lossy(&out.stderr));
        let run = Command::new(dir.join("check")).output().unwrap();
        assert!(run.status.success(), "header values differ from the table:\n{}", String::from_utf8_lossy(&run.stderr));
    }
}

#[test]
fn bad_arguments_get_a_clear_error_and_no_panic() {
    let tmp = sim_dir("export_bad", Simulator::Verilator);
    std::fs::create_dir_all(&tmp).unwrap();
    let file = tmp.join("a_file");
    std::fs::write(&file, "x").unwrap();
    let under_file = file.join("sub");
    let cases: Vec<(Vec<String>, &str)> = vec![
        (vec!["--axes".into(), "0".into()], "axis counts are 1 to 16"),
        (vec!["--axes".into(), "17".into()], "axis counts are 1 to 16"),
        (vec!["--clock-hz".into(), "999".into()], "supported core clocks"),
        (vec!["--clock-hz".into(), "500000000".into()], "supported core clocks"),
        (vec!["--fifo-depth".into(), "3".into()], "period FIFO depths"),
        (vec!["--arch".into(), "fast".into()], "expected tdm or baseline"),
        (vec!["--arch".into(), "baseline".into(), "--axes".into(), "3".into()], "baseline is built for"),
        (vec!["--name".into(), "9lives".into()], "a module name is 1 to 40"),
        (vec!["--name".into(), "my$core".into()], "a module name is 1 to 40"),
        (vec!["--name".into(), "module".into()], "not a Verilog keyword"),
        (vec!["--name".into(), "x".repeat(41)], "a module name is 1 to 40"),
        (vec!["--profiles".into(), "scurve".into()], "trapezoid is always built"),
        (vec!["--profiles".into(), "trapezoid,quintic".into()], "unknown profile"),
        (vec!["--profiles".into(), "trapezoid,scurve".into(), "--arch".into(), "baseline".into()], "TDM core only"),
    ];
    for (args, msg) in cases {
        let out = bin().args(["export", "--out"]).arg(tmp.join("x")).args(&args).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} succeeded");
        assert!(err.contains(msg), "{args:?}: message {err:?} lacks {msg:?}");
        assert!(!err.contains("panicked"), "{args:?} panicked: {err}");
    }
    let out = bin().args(["export", "--out"]).arg(&under_file).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("cannot create") && !err.contains("panicked"), "unwritable DIR: {err}");
}

/// The write sequence in docs/registers.md pushes exactly the planner's segments of
/// the paper's experiment.
#[test]
fn registers_md_sequence_pushes_the_planners_segments() {
    let md = std::fs::read_to_string(repo().join("docs/registers.md")).unwrap();
    let mut pushed: Vec<Vec<(u32, u32, i32)>> = vec![vec![], vec![]];
    for call in md.split("tdm_push(").skip(1) {
        let args: Vec<&str> = call.split(')').next().unwrap().split(',').map(|a| a.trim()).collect();
        if args.len() != 4 || args[0].parse::<usize>().is_err() {
            continue; // the function's definition
        }
        let axis: usize = args[0].parse().unwrap();
        pushed[axis].push((args[1].parse().unwrap(), args[2].parse().unwrap(), args[3].parse().unwrap()));
    }
    let want: Vec<Vec<(u32, u32, i32)>> = tdm_stepper::vectors::paper_experiment_segments()
        .iter()
        .map(|a| a.iter().map(|s| (s.v0_rate, s.t_ticks, s.steps)).collect())
        .collect();
    assert_eq!(pushed, want, "docs/registers.md's sequence differs from the planner");
}


/// The integration package in the export folder, used from that folder alone (K = 3):
/// the smoke testbench passes in Icarus; the instantiation template names every port
/// once and elaborates in yosys and Icarus inside a wrapper; the constraints name only
/// the core's ports, with clk's period from --clock-hz; the FuseSoC core lists files
/// that are there.
#[test]
fn export_package_works_from_the_folder_alone() {
    use tdm_stepper::package as pkg;
    let dir = export_to(&["--axes", "3", "--clock-hz", "40000000"], "export_package");
    let read = |f: &str| std::fs::read_to_string(dir.join(f)).unwrap_or_else(|e| panic!("{f}: {e}"));
    let ports = export::ports(3, 0);

    // Smoke testbench in Icarus.
    let out = Command::new("iverilog")
        .current_dir(&dir)
        .args(["-g2005", "-Wall", "-o", "smoke.vvp", "tdm_stepper.v", pkg::TB_FILE])
        .output()
        .expect("iverilog is installed");
    assert!(out.status.success(), "iverilog: {}", String::from_utf8_lossy(&out.stderr));
    let out = Command::new("vvp").current_dir(&dir).args(["-n", "smoke.vvp"]).output().unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success() && text.contains("PASS: ID_MAGIC") && !text.contains("FAIL"), "smoke test: {text}");

    // The template: each port once, in a wrapper that declares the signals.
    let tpl = read(pkg::TEMPLATE_FILE);
    for p in &ports {
        assert_eq!(tpl.matches(&format!(".{} ", p.name)).count(), 1, "template: port {}", p.name);
        assert!(tpl.contains(&pkg::ascii(p.description)), "template: {}'s comment", p.name);
    }
    let mut wrap = String::from("module wrap;\n");
    for p in ports.iter().filter(|p| p.name != "fsm_state") {
        let kind = if p.direction == "input" { "reg" } else { "wire" };
        wrap += &format!("  {kind} [{}:0] {};\n", p.width - 1, p.name);
    }
    wrap += &format!("`include \"{}\"\nendmodule\n", pkg::TEMPLATE_FILE);
    std::fs::write(dir.join("wrap.v"), wrap).unwrap();
    let out = Command::new("yosys")
        .current_dir(&dir)
        .args(["-q", "-p", "read_verilog -I. wrap.v tdm_stepper.v; hierarchy -check -top wrap"])
        .output()
        .expect("yosys is installed");
    assert!(out.status.success(), "yosys with the template: {}", String::from_utf8_lossy(&out.stderr));
    let out = Command::new("iverilog").current_dir(&dir).args(["-g2005", "-I.", "-o", "wrap.vvp", "wrap.v", "tdm_stepper.v"]).output().unwrap();
    assert!(out.status.success(), "iverilog with the template: {}", String::from_utf8_lossy(&out.stderr));

    // Constraints: only the core's ports; clk at 40 MHz.
    let names: Vec<&str> = ports.iter().map(|p| p.name).collect();
    for f in [pkg::XDC_FILE, pkg::SDC_FILE] {
        let t = read(f);
        assert!(t.contains("create_clock -name tdm_clk -period 25.000 [get_ports clk]"), "{f}");
        assert!(t.contains("set_clock_groups -asynchronous"), "{f}");
        for l in t.lines().filter(|l| !l.starts_with('#')) {
            let mut rest = l;
            while let Some(i) = rest.find("[get_ports ") {
                let inner = &rest[i + 11..];
                let end = inner.find(']').unwrap();
                let inner = &inner[..end].trim_matches(|c| c == '{' || c == '}');
                for n in inner.split_whitespace() {
                    let base = n.trim_matches(|c| c == '{' || c == '}').split('[').next().unwrap();
                    assert!(names.contains(&base), "{f}: {base} is not a port: {l}");
                }
                rest = &rest[i + 11 + end..];
            }
        }
    }
    assert!(read(pkg::LPF_FILE).contains("FREQUENCY PORT \"clk\" 40.000 MHz;"));
    assert!(read(pkg::PCF_FILE).contains("set_frequency clk 40.000"));

    // FuseSoC (installed by scripts/test.sh): the lint and sim targets, run from a
    // scratch folder with the export as the cores root.
    let fusesoc = repo().join("target/venv-tools/bin/fusesoc");
    assert!(fusesoc.is_file(), "{} is missing: scripts/test.sh installs it", fusesoc.display());
    let name = read(pkg::CORE_FILE).lines().find_map(|l| l.strip_prefix("name: ")).unwrap().to_string();
    let fs_work = dir.join("fusesoc_work");
    std::fs::create_dir_all(&fs_work).unwrap();
    for target in ["lint", "sim"] {
        let out = Command::new(&fusesoc)
            .current_dir(&fs_work)
            .arg("--cores-root")
            .arg(&dir)
            .args(["run", "--target", target, &name])
            .output()
            .unwrap();
        let all = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
        assert!(out.status.success(), "fusesoc {target}: {all}");
        if target == "sim" {
            assert!(all.contains("PASS: ID_MAGIC"), "fusesoc sim: {all}");
        }
    }

    // FuseSoC: every listed file is in the folder.
    let core = read(pkg::CORE_FILE);
    assert!(core.starts_with("CAPI=2:"));
    let listed: Vec<&str> = core.lines().filter_map(|l| l.trim().strip_prefix("- ")).map(|f| f.split(':').next().unwrap()).collect();
    // The Verilog, the waivers, the smoke testbench, the register header and the C files.
    assert_eq!(listed.len(), 4 + pkg::C_SOURCES.len(), "{core}");
    for f in [tdm_stepper::export::HEADER_FILE].into_iter().chain(pkg::C_SOURCES.iter().map(|&(n, _)| n)) {
        assert!(listed.contains(&f), "{} does not list {f}", pkg::CORE_FILE);
    }
    for f in listed {
        assert!(dir.join(f).is_file(), "{} lists {f}, which is not in the export", pkg::CORE_FILE);
    }
}

/// `--min-period` is the one minimum period: the manifest, the header and the core's
/// RMAX constant in the Verilog all follow it; out-of-range values fail with the
/// supported range and a non-zero exit.
#[test]
fn min_period_option_sets_the_manifest_header_and_core() {
    let dir = export_to(&["--axes", "4", "--min-period", "500"], "export_min_period");
    let read = |f: &str| std::fs::read_to_string(dir.join(f)).unwrap();
    let m: serde_json::Value = serde_json::from_str(&read("manifest.json")).unwrap();
    let rmax = (1u64 << 32) / 501;
    assert_eq!(m["min_period_ticks"], 500);
    assert_eq!(m["max_rate_q32"], rmax);
    let sustainable = ExportOptions { axes: 4, ..Default::default() }.sustainable_period_ticks();
    assert_eq!(m["sustainable_period_ticks"], sustainable);
    let h = read("tdm_stepper_regs.h");
    assert!(h.contains("#define TDM_MIN_PERIOD 500u"), "header: TDM_MIN_PERIOD");
    assert!(h.contains(&format!("#define TDM_MAX_RATE {rmax}u")), "header: TDM_MAX_RATE");
    // The identity registers' constants and the core's RMAX are in the Verilog.
    let v = read("tdm_stepper.v");
    assert!(v.contains(&format!("32'h{rmax:x}")), "the core's RMAX constant is not in the Verilog");
    assert!(v.contains("16'h1f4"), "ID_MIN_PERIOD's value (500) is not in the Verilog");
    for bad in ["1", "65536"] {
        let out = bin().args(["export", "--out"]).arg(dir.join("bad")).args(["--min-period", bad]).output().unwrap();
        assert!(!out.status.success(), "--min-period {bad} must fail");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains("supported minimum periods are 2 to 65535"), "--min-period {bad}: {err}");
    }
}

/// `--name`: two cores with different names and K in one design. Every module of an
/// export is `<name>` or `<name>__path` (no `$`), each folder lints clean alone with
/// its waivers, and yosys reads both exports with the two instantiation templates and
/// synthesises them together (generic coarse synthesis, flattened).
#[test]
fn two_named_exports_live_in_one_design() {
    use tdm_stepper::package as pkg;
    let a = export_to(&["--name", "motion_a", "--axes", "2"], "export_named_a");
    let b = export_to(&["--name", "motion_b", "--axes", "3", "--clock-hz", "40000000"], "export_named_b");
    for (dir, name) in [(&a, "motion_a"), (&b, "motion_b")] {
        let v = std::fs::read_to_string(dir.join("tdm_stepper.v")).unwrap();
        let modules: Vec<&str> = v.lines().filter_map(|l| l.strip_prefix("module ")).map(|l| l.split('(').next().unwrap().trim()).collect();
        assert!(modules.len() > 50, "{name}: {} modules", modules.len());
        for m in &modules {
            assert!(!m.contains('$'), "{name}: module {m} has a $");
            assert!(*m == name || m.starts_with(&format!("{name}__")), "{name}: module {m}");
        }
        assert!(!v.contains("tdm_stepper"), "{name}: the default name is left in the Verilog");
        let out = Command::new("verilator")
            .current_dir(dir)
            .args(["--lint-only", "-Wall", pkg::WAIVER_FILE, "tdm_stepper.v", "--top-module", name])
            .output()
            .unwrap();
        let text = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success() && !text.contains("%Warning"), "{name}: lint: {text}");
        let m: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(dir.join("manifest.json")).unwrap()).unwrap();
        assert_eq!(m["top_module"], name);
        let tpl = std::fs::read_to_string(dir.join(pkg::TEMPLATE_FILE)).unwrap();
        assert!(tpl.contains(&format!("{name} u_{name} (")), "{name}: template");
        let core = std::fs::read_to_string(dir.join(pkg::CORE_FILE)).unwrap();
        assert!(core.contains(&format!("toplevel: {name}\n")), "{name}: core file");
    }
    // One wrapper per core around its template, and a top with both.
    let mut v = String::new();
    for (dir, tag, k) in [(&a, "a", 2), (&b, "b", 3)] {
        let ports = export::ports(k, 0);
        let decl: Vec<String> = ports
            .iter()
            .filter(|p| p.name != "fsm_state")
            .map(|p| format!("{} [{}:0] {}", p.direction, p.width - 1, p.name))
            .collect();
        v += &format!("module w{tag}({});\n`include \"{}\"\nendmodule\n", decl.join(", "), dir.join(pkg::TEMPLATE_FILE).display());
    }
    v += "module both(input clk, input bus_clk, input reset, input ne_a, input ne_b, input noe, input nwe, input [8:0] addr, input [15:0] data_in,\n\
          output [15:0] d_a, output [15:0] d_b, output oe_a, output oe_b, output [4:0] step, output [4:0] dir, output [1:0] irq);\n\
          wa ua(.clk(clk), .bus_clk(bus_clk), .reset(reset), .ne(ne_a), .noe(noe), .nwe(nwe), .addr(addr), .data_in(data_in), .data_out(d_a), .data_oe(oe_a), .step(step[1:0]), .dir(dir[1:0]), .irq(irq[0]));\n\
          wb ub(.clk(clk), .bus_clk(bus_clk), .reset(reset), .ne(ne_b), .noe(noe), .nwe(nwe), .addr(addr), .data_in(data_in), .data_out(d_b), .data_oe(oe_b), .step(step[4:2]), .dir(dir[4:2]), .irq(irq[1]));\n\
          endmodule\n";
    let top = sim_dir("export_named_both", Simulator::Verilator);
    let _ = std::fs::remove_dir_all(&top);
    std::fs::create_dir_all(&top).unwrap();
    std::fs::write(top.join("both.v"), v).unwrap();
    let script = format!(
        "read_verilog {} {} both.v; hierarchy -check -top both; synth -top both -flatten -run :fine; tee -q -o stat.txt stat",
        a.join("tdm_stepper.v").display(),
        b.join("tdm_stepper.v").display()
    );
    let out = Command::new("yosys").current_dir(&top).args(["-p", &script]).output().unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "yosys, both cores: {}{}", text, String::from_utf8_lossy(&out.stderr));
    assert!(!text.contains("Warning: Replacing memory") && !text.contains("Re-definition"), "yosys: {text}");
    let stat = std::fs::read_to_string(top.join("stat.txt")).unwrap();
    let cells: u64 = stat.lines().find_map(|l| l.trim().strip_prefix("Number of cells:")).expect("cell count").trim().parse().unwrap();
    assert!(cells > 2000, "both cores synthesised: {cells} coarse cells");
}

/// An export on each bus other than EXMC from its folder alone (K = 2): the smoke
/// testbench reads the identity through the bus in Icarus (SPI: and checks the status
/// byte; Wishbone and AXI4-Lite: and sees an unmapped address refused); the manifest
/// says the bus and lists the Verilog's ports; the constraints name only the core's
/// ports and no EXMC pin; the Verilog opens with its header comment (the export
/// command that made it, and every port).
#[test]
fn bus_export_packages_work_from_the_folder_alone() {
    use tdm_stepper::package as pkg;
    for bus in ["spi", "wb", "axil"] {
        let dir = export_to(&["--axes", "2", "--bus", bus], &format!("export_package_{bus}"));
        let read = |f: &str| std::fs::read_to_string(dir.join(f)).unwrap_or_else(|e| panic!("{f}: {e}"));
        let out = Command::new("iverilog")
            .current_dir(&dir)
            .args(["-g2005", "-Wall", "-o", "smoke.vvp", "tdm_stepper.v", pkg::TB_FILE])
            .output()
            .expect("iverilog is installed");
        assert!(out.status.success(), "{bus}: iverilog: {}", String::from_utf8_lossy(&out.stderr));
        let out = Command::new("vvp").current_dir(&dir).args(["-n", "smoke.vvp"]).output().unwrap();
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(out.status.success() && text.contains("PASS: ID_MAGIC") && !text.contains("FAIL"), "{bus} smoke test: {text}");
        let manifest: serde_json::Value = serde_json::from_str(&read("manifest.json")).unwrap();
        assert_eq!(manifest["bus"], bus);
        let names: Vec<String> = manifest["ports"].as_array().unwrap().iter().map(|p| p["name"].as_str().unwrap().to_string()).collect();
        let v = read("tdm_stepper.v");
        let got: Vec<String> = verilog_ports(&v).into_iter().map(|p| p.0).collect();
        assert_eq!(got, names, "{bus}: manifest ports against the Verilog");
        for f in [pkg::XDC_FILE, pkg::SDC_FILE] {
            let c = read(f);
            let commands: String = c.lines().filter(|l| !l.starts_with('#')).collect::<Vec<_>>().join("\n");
            if bus == "spi" {
                assert!(commands.contains("cs_n sck mosi") && commands.contains("miso_oe"), "{f}: SPI pins");
            } else {
                assert!(commands.contains("set_false_path -from [get_ports {reset}]"), "{bus} {f}: reset");
            }
            assert!(!commands.contains(" ne ") && !commands.contains("data_in"), "{bus} {f}: an EXMC pin");
        }
        let tpl = read(pkg::TEMPLATE_FILE);
        for n in &names {
            assert_eq!(tpl.matches(&format!(".{n} ")).count(), 1, "{bus} template: port {n}");
        }
        // The header comment: the command that made it, and each port on its own line.
        let head: Vec<&str> = v.lines().take_while(|l| l.starts_with("//")).collect();
        assert!(head.iter().any(|l| l.contains(&format!("Made by: tdm-stepper export --axes 2 ")) && l.ends_with(&format!("--bus {bus}"))), "{bus}: {head:?}");
        for n in &names {
            assert!(head.iter().any(|l| l.starts_with(&format!("//   {n} "))), "{bus}: header lacks port {n}");
        }
        // The command, run again, makes the same Verilog.
        let cmd = head.iter().find_map(|l| l.strip_prefix("// Made by: tdm-stepper export ")).unwrap();
        let args: Vec<&str> = cmd.split_whitespace().collect();
        let again = export_to(&args, &format!("export_package_{bus}_again"));
        assert!(std::fs::read_to_string(again.join("tdm_stepper.v")).unwrap() == v, "{bus}: `{cmd}` makes other Verilog");
    }
}

/// The cocotb bench (bench/cocotb/test_buses.py, run by run_bench.py with the venv of
/// scripts/test.sh) on the SPI, Wishbone and AXI4-Lite exports, side by side,
/// with the ecosystem's masters (cocotbext-spi, cocotbext-wishbone, cocotbext-axi) in
/// Verilator: every register reads its documented reset value and the read/write
/// ones read back what was written; bad framing is refused and changes nothing; the
/// paper's experiment (the segments of vectors/paper_experiment.json) with random
/// register traffic gives every STEP edge of the model, from one release tick.
#[test]
fn cocotb_bench_drives_each_bus_with_the_ecosystems_masters() {
    use tdm_stepper::export::Bus;
    use tdm_stepper::model::{AxisRun, Limits, Segment};
    use tdm_stepper::regs::{table_for, Access};
    let python = repo().join("target/venv-tools/bin/python");
    assert!(python.is_file(), "{} is missing: scripts/test.sh installs the venv", python.display());
    let vectors: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(repo().join("vectors/paper_experiment.json")).unwrap()).unwrap();
    let segments: Vec<Vec<Segment>> = vectors["axes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| {
            a["segments"]
                .as_array()
                .unwrap()
                .iter()
                .map(|s| Segment { v0_rate: s["v0_rate"].as_u64().unwrap() as u32, t_ticks: s["t_ticks"].as_u64().unwrap() as u32, steps: s["steps"].as_i64().unwrap() as i32 })
                .collect()
        })
        .collect();
    // The experiment at a tenth of its durations and steps (the same speeds and shape,
    // 420 edges in 5 ms) in the test command; TDM_COCOTB_FULL=1 runs it whole (50 ms,
    // 4,200 edges: minutes per bus with cocotb).
    let scale: u32 = if std::env::var_os("TDM_COCOTB_FULL").is_some() { 1 } else { 10 };
    let segments: Vec<Vec<Segment>> = segments
        .iter()
        .map(|a| a.iter().map(|s| Segment { t_ticks: s.t_ticks / scale, steps: s.steps / scale as i32, ..*s }).collect())
        .collect();
    let runs: Vec<AxisRun> = segments.iter().map(|s| AxisRun::run(s, &Limits::default())).collect();
    for (r, s) in runs.iter().zip(&segments) {
        let steps: u64 = s.iter().map(|g| g.steps.unsigned_abs() as u64).sum();
        assert!(r.rejected.is_empty() && r.edge_ticks.len() as u64 == steps, "the experiment (scale 1/{scale}) runs whole in the model");
    }
    let mut jobs = vec![];
    for bus in [Bus::Spi, Bus::Wb, Bus::Axil] {
        let opts = ExportOptions { axes: 2, bus, ..Default::default() };
        let p = opts.params();
        let dir = sim_dir(&format!("cocotb_{}", bus.name()), Simulator::Verilator);
        let _ = std::fs::remove_dir_all(&dir);
        tdm_stepper::package::export(&opts, &dir).unwrap();
        let mut registers = serde_json::Map::new();
        let mut rw = vec![];
        for r in table_for(&p) {
            let mask: u32 = r.fields.iter().map(|f| ((1u32 << f.width) - 1) << f.lsb).fold(0, |a, b| a | b);
            registers.insert(r.name.into(), serde_json::json!({"word": r.address(0), "per_axis": r.per_axis, "reset": r.reset_value(&p), "mask": mask}));
            if !r.per_axis && r.name != "CTRL" && r.fields.iter().all(|f| f.access == Access::Rw) {
                rw.push(r.name);
            }
        }
        let mapped = regs::mapped(&p);
        let holes: Vec<usize> = [mapped.iter().position(|m| !m).unwrap(), regs::register("STATUS").address(2) as usize, 0x1ff]
            .into_iter()
            .inspect(|&h| assert!(!mapped[h], "{h:#x} is mapped"))
            .collect();
        let case = serde_json::json!({
            "bus": bus.name(),
            "axes": 2,
            "clk_ps": 1_000_000_000_000u64 / opts.clock_hz as u64,
            // About 100 MHz, unrelated to clk.
            "bus_clk_ps": 9_994,
            "sck_hz": 25e6,
            "spi_gap_ns": 50,
            "spi_status_pattern": regs::SPI_STATUS_PATTERN,
            "axis_stride": regs::AXIS_STRIDE,
            "registers": registers,
            "rw": rw,
            "holes": holes,
            "gstatus_enabled": 1u32 << regs::register("GSTATUS").field("ENABLED").lsb,
            "segments": segments.iter().map(|s| s.iter().map(|g| [g.v0_rate as i64, g.t_ticks as i64, g.steps as i64]).collect::<Vec<_>>()).collect::<Vec<_>>(),
            "edges": runs.iter().map(|r| r.edge_ticks.clone()).collect::<Vec<_>>(),
            "dirs": segments.iter().map(|s| (s[0].steps < 0) as u8).collect::<Vec<_>>(),
            "positions": runs.iter().map(|r| r.position).collect::<Vec<_>>(),
            "settle_us": 100,
            "min_traffic": 1000 / scale,
            // Simulated time the test may take: the experiment and its setup, twice over.
            "timeout_ms": 2 * (60 / scale as u64 + 5),
        });
        assert!(rw.len() >= 5, "{rw:?}");
        std::fs::write(dir.join("case.json"), serde_json::to_string_pretty(&case).unwrap()).unwrap();
        // The three benches run side by side (each builds and runs its own Verilator model).
        let python = python.clone();
        jobs.push(std::thread::spawn(move || {
            let t0 = std::time::Instant::now();
            let out = Command::new(&python)
                .arg(repo().join("bench/cocotb/run_bench.py"))
                .arg("--verilog")
                .arg(dir.join("tdm_stepper.v"))
                .arg("--case")
                .arg(dir.join("case.json"))
                .arg("--build")
                .arg(dir.join("cocotb"))
                .output()
                .unwrap();
            let all = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
            (bus, out.status.success(), all, t0.elapsed().as_secs_f64())
        }));
    }
    let mut failed = vec![];
    for j in jobs {
        let (bus, ok, all, secs) = j.join().unwrap();
        eprintln!("cocotb bench on {bus:?}: {secs:.0} s");
        if !(ok && all.contains(&format!("PASS {}", bus.name())) && all.contains("run_bench: 1 test(s), 0 failed")) {
            failed.push(format!("{bus:?}:\n{}", &all[all.len().saturating_sub(6000)..]));
        }
    }
    assert!(failed.is_empty(), "cocotb bench failed on:\n{}", failed.join("\n"));
}
