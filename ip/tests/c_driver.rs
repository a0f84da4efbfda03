//! The C driver and planner that `export` writes (`tdm_driver.[ch]`,
//! `tdm_planner.[ch]`):
//! * compiled with `gcc -std=c99 -Wall -Wextra -Werror -pedantic` and, for a
//!   Cortex-M4, with `arm-none-eabi-gcc -mcpu=cortex-m4 -mthumb -Os` (no warnings;
//!   the code size the README states);
//! * the C planner gives exactly the Rust planner's segments and errors on random
//!   moves (both forms, across and beyond the documented ranges), and so does the C
//!   S-curve planner (`ip/c/tdm_scurve.[ch]`, jerk-limited and fourth-order moves);
//! * the driver against the exported IP in Verilator, through a pin-level EXMC shim
//!   (tests/c/exmc_shim.cpp, the documented minimum FSMC timing): the paper's
//!   experiment and random moves planned in C on three axes, every STEP edge equal to
//!   the Rust model's from one release tick, the positions read back through the
//!   driver; host-side rejections that touch no bus, a full queue that never
//!   overflows, an abort in motion with exact positions, a failed START seen through
//!   the irq helper.

mod common;

use common::*;
use std::path::{Path, PathBuf};
use std::process::Command;
use tdm_stepper::export::{self, ExportOptions};
use tdm_stepper::model::planner::{trapezoid_by_rates, trapezoid_by_ticks, PlanError};
use tdm_stepper::model::scurve::{self, ScurveError};
use tdm_stepper::model::Motion;
use tdm_stepper::model::{AxisRun, Limits, Segment};
use tdm_stepper::verify::Simulator;

const GCC_FLAGS: [&str; 5] = ["-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic"];

fn tests_c() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/c")
}

fn run(cmd: &mut Command, what: &str) -> String {
    let out = cmd.output().unwrap_or_else(|e| panic!("{what}: cannot run: {e}"));
    let text = String::from_utf8_lossy(&out.stdout).to_string() + &String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{what} failed:\n{text}");
    text
}

/// An export of K axes into a fresh folder.
fn export_dir(name: &str, axes: usize) -> (PathBuf, ExportOptions) {
    let dir = sim_dir(name, Simulator::Verilator);
    let _ = std::fs::remove_dir_all(&dir);
    let opts = ExportOptions { axes, ..Default::default() };
    tdm_stepper::package::export(&opts, &dir).unwrap();
    (dir, opts)
}

/// gcc -c of `src` into `dir/<obj>` with the project's flags (warnings are errors).
fn gcc_c(dir: &Path, src: &Path, obj: &str) -> PathBuf {
    gcc_c_with(dir, dir, src, obj, &[])
}

/// gcc -c of `src` into `dir/<obj>`, headers from `include`, the project's flags and `extra`.
fn gcc_c_with(dir: &Path, include: &Path, src: &Path, obj: &str, extra: &[&str]) -> PathBuf {
    let out = dir.join(obj);
    let mut cmd = Command::new("gcc");
    cmd.args(GCC_FLAGS).args(extra).args(["-O2", "-I"]).arg(include).arg("-c").arg(src).arg("-o").arg(&out);
    let text = run(&mut cmd, &format!("gcc {}", src.display()));
    assert!(text.trim().is_empty(), "gcc printed diagnostics for {}:\n{text}", src.display());
    out
}

#[test]
fn driver_and_planner_compile_for_the_host_and_a_cortex_m4_without_warnings() {
    let (dir, _) = export_dir("c_compile", 2);
    for f in ["tdm_driver.c", "tdm_planner.c"] {
        gcc_c(&dir, &dir.join(f), &f.replace(".c", ".o"));
    }
    let mut sizes = Vec::new();
    for f in ["tdm_driver.c", "tdm_planner.c"] {
        let obj = dir.join(f.replace(".c", ".arm.o"));
        let mut cmd = Command::new("arm-none-eabi-gcc");
        cmd.args(["-mcpu=cortex-m4", "-mthumb", "-Os"]).args(GCC_FLAGS).arg("-I").arg(&dir).arg("-c").arg(dir.join(f)).arg("-o").arg(&obj);
        let text = run(&mut cmd, &format!("arm-none-eabi-gcc {f}"));
        assert!(text.trim().is_empty(), "arm-none-eabi-gcc printed diagnostics for {f}:\n{text}");
        let size = run(Command::new("arm-none-eabi-size").arg(&obj), "arm-none-eabi-size");
        // "   text    data     bss     dec     hex filename" then the numbers.
        let nums: Vec<u64> = size.lines().nth(1).unwrap().split_whitespace().take(3).map(|s| s.parse().unwrap()).collect();
        assert_eq!((nums[1], nums[2]), (0, 0), "{f}: no static data, no bss");
        sizes.push(nums[0]);
        println!("{f}: {} bytes of code for a Cortex-M4 (-Os)", nums[0]);
    }
    // With the header of an `--io` export the driver has the machine I/O functions of
    // its groups: it compiles without warnings too (host and Cortex-M4), for every
    // group alone, all of them, and a mix.
    for (i, io) in ["all", "estop", "probe", "limits", "home", "alarm", "watchdog", "limits,home,watchdog"].iter().enumerate() {
        let choice = export::parse_io(io).unwrap();
        let io_dir = sim_dir(&format!("c_compile_io_{i}"), Simulator::Verilator);
        let _ = std::fs::remove_dir_all(&io_dir);
        tdm_stepper::package::export(&ExportOptions { axes: 2, io: choice.io, io_omit: choice.omit, ..Default::default() }, &io_dir).unwrap();
        gcc_c(&io_dir, &io_dir.join("tdm_driver.c"), "tdm_driver.o");
        let mut cmd = Command::new("arm-none-eabi-gcc");
        cmd.args(["-mcpu=cortex-m4", "-mthumb", "-Os"]).args(GCC_FLAGS).arg("-I").arg(&io_dir).arg("-c").arg(io_dir.join("tdm_driver.c")).arg("-o").arg(io_dir.join("d.arm.o"));
        let text = run(&mut cmd, &format!("arm-none-eabi-gcc tdm_driver.c (--io {io})"));
        assert!(text.trim().is_empty(), "arm-none-eabi-gcc printed diagnostics for the --io {io} driver:\n{text}");
        // Each group's functions are there exactly when it was exported.
        let syms = run(Command::new("nm").arg(io_dir.join("tdm_driver.o")), "nm");
        let has = |f: &str| syms.lines().any(|l| l.ends_with(&format!(" T {f}")));
        let groups = tdm_stepper::regs::IO_ALL & !choice.omit;
        assert!(has("tdm_io_configure") && has("tdm_stop") && has("tdm_io_service"), "--io {io}: the common functions");
        for (g, f) in [(tdm_stepper::regs::IO_HOME, "tdm_home"), (tdm_stepper::regs::IO_PROBE, "tdm_probe_position"), (tdm_stepper::regs::IO_WATCHDOG, "tdm_wd_feed")] {
            assert_eq!(has(f), groups & g != 0, "--io {io}: {f}");
        }
    }
    // The README states the sizes; they hold to 15 % (compiler versions differ).
    let readme = std::fs::read_to_string(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../README.md")).unwrap();
    let at = readme.find("bytes of Cortex-M4 code").expect("README states the driver's size");
    let stated: Vec<u64> = readme[at.saturating_sub(200)..at]
        .split(|c: char| !c.is_ascii_digit() && c != ',')
        .filter(|s| !s.is_empty() && s.chars().any(|c| c.is_ascii_digit()))
        .map(|s| s.replace(',', "").parse().unwrap())
        .collect();
    let stated = &stated[stated.len() - 2..];
    for (got, want) in sizes.iter().zip(stated) {
        let ratio = *got as f64 / *want as f64;
        assert!((0.85..=1.15).contains(&ratio), "README says {want} bytes, the compiler gives {got}: update the README");
    }
}

/// tdm_identify() compares ID_OPTIONS with the header's TDM_OPTIONS: against a bank in
/// memory that answers this header's ID values (through the hooks, and as a 32-bit
/// region through tdm_open_mmio32()), every other export's options word is refused
/// with TDM_E_CONFIG and its own is taken. (The bus tests run tdm_identify on
/// the exported cores, so each core's ID_OPTIONS equals its header's.) Each driver
/// compiles without warnings with its header (the machine I/O with the encoders too).
#[test]
fn identify_refuses_a_core_whose_options_differ_from_the_header() {
    let io = |s: &str| export::parse_io(s).unwrap();
    let variants: Vec<(&str, ExportOptions)> = vec![
        ("none", ExportOptions { axes: 2, ..Default::default() }),
        ("io_all", ExportOptions { axes: 2, io: true, io_omit: io("all").omit, ..Default::default() }),
        ("io_limits", ExportOptions { axes: 2, io: true, io_omit: io("limits").omit, ..Default::default() }),
        ("scurve", ExportOptions { axes: 2, scurve: true, ..Default::default() }),
        ("encoder", ExportOptions { axes: 2, encoder: true, ..Default::default() }),
        ("io_encoder", ExportOptions { axes: 2, io: true, encoder: true, ..Default::default() }),
    ];
    let words: Vec<u16> = variants.iter().map(|(_, o)| o.params().options_word()).collect();
    let mut sorted = words.clone();
    sorted.sort();
    sorted.dedup();
    assert_eq!(sorted.len(), words.len(), "each export has its own options word: {words:x?}");
    assert_eq!(words[0], 0, "a core without options reads ID_OPTIONS = 0");
    for (i, (name, opts)) in variants.iter().enumerate() {
        let dir = sim_dir(&format!("c_identify_{name}"), Simulator::Verilator);
        let _ = std::fs::remove_dir_all(&dir);
        tdm_stepper::package::export(opts, &dir).unwrap();
        let header = std::fs::read_to_string(dir.join("tdm_stepper_regs.h")).unwrap();
        assert!(header.contains(&format!("#define TDM_OPTIONS 0x{:04X}u", words[i])), "{name}: the header's TDM_OPTIONS");
        let mut objs = vec![gcc_c(&dir, &tests_c().join("identify_check.c"), "c.o")];
        for f in ["tdm_driver.c", "tdm_planner.c", "tdm_scurve.c"] {
            if dir.join(f).is_file() {
                objs.push(gcc_c(&dir, &dir.join(f), &f.replace(".c", ".o")));
            }
        }
        let bin = dir.join("identify_check");
        run(Command::new("gcc").args(&objs).arg("-lm").arg("-o").arg(&bin), "link identify_check");
        for (j, w) in words.iter().enumerate() {
            let out = run(Command::new(&bin).arg(format!("{w:x}")), "identify_check");
            let want = if i == j { 0 } else { -3 };
            assert_eq!(out.trim(), format!("IDENTIFY {want} {w:x}\nIDENTIFY32 {want} {w:x}"), "header of {name}, core of {}", variants[j].0);
        }
    }
}

/// Two cores of different K (and options) in one firmware build: the driver compiled
/// with the header of the export with more options, the other export's header
/// included after it under another name, and each core identified against its own
/// `<NAME>_IDENTITY` with tdm_identify_as(): each identity takes its own core and
/// refuses the other (TDM_E_CONFIG), without a warning from gcc -Wall -Werror.
#[test]
fn two_cores_of_different_k_share_one_build() {
    use tdm_stepper::export::ModuleName;
    let dir = sim_dir("c_two_cores", Simulator::Verilator);
    let a = dir.join("a");
    let b = dir.join("b");
    let _ = std::fs::remove_dir_all(&dir);
    let io = export::parse_io("all").unwrap();
    tdm_stepper::package::export(&ExportOptions { name: ModuleName::new("motion_a").unwrap(), axes: 2, ..Default::default() }, &a).unwrap();
    tdm_stepper::package::export(&ExportOptions { name: ModuleName::new("motion_b").unwrap(), axes: 4, io: io.io, io_omit: io.omit, ..Default::default() }, &b).unwrap();
    std::fs::copy(a.join("tdm_stepper_regs.h"), b.join("motion_a_regs.h")).unwrap();
    let objs = [
        gcc_c(&b, &b.join("tdm_driver.c"), "tdm_driver.o"),
        gcc_c(&b, &b.join("tdm_planner.c"), "tdm_planner.o"),
        gcc_c(&b, &tests_c().join("two_cores_check.c"), "two.o"),
    ];
    let bin = b.join("two_cores_check");
    run(Command::new("gcc").args(&objs).arg("-o").arg(&bin), "link two_cores_check");
    let out = run(&mut Command::new(&bin), "two_cores_check");
    assert_eq!(field(&out, "AS"), [[0, 0, 0, 2], [0, 1, -3, 2], [1, 0, -3, 4], [1, 1, 0, 4]], "{out}");
    assert_eq!(field(&out, "HEADER_AXES")[0], [4]);
}

/// One planner result as the C programs print it: rc, bad phase, segments.
fn c_form(r: &Result<Vec<Segment>, PlanError>) -> String {
    match r {
        Ok(segs) => {
            let mut s = format!("0 0 {}", segs.len());
            for g in segs {
                s += &format!(" {} {} {}", g.v0_rate, g.t_ticks, g.steps);
            }
            s
        }
        Err(e) => {
            let phase = if let PlanError::Segment { index, .. } = e { *index } else { 0 };
            format!("{} {phase} 0", e.c_code())
        }
    }
}

/// A random value between lo and hi, spread over its orders of magnitude.
fn log_uniform(rng: &mut Rng, lo: f64, hi: f64) -> u64 {
    let x = (rng.next() % 1_000_000) as f64 / 1e6;
    (lo * (hi / lo).powf(x)).round() as u64
}

#[test]
fn the_c_planner_gives_the_rust_planners_segments() {
    let (dir, _) = export_dir("c_plan", 2);
    let bin = dir.join("plan_check");
    let objs = [gcc_c(&dir, &dir.join("tdm_driver.c"), "d.o"), gcc_c(&dir, &dir.join("tdm_planner.c"), "p.o"), gcc_c(&dir, &tests_c().join("plan_check.c"), "c.o")];
    run(Command::new("gcc").args(&objs).arg("-o").arg(&bin), "link plan_check");

    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let mut input = String::new();
    let mut want = Vec::new();
    let (mut ok, mut errs) = (0, 0);
    for k in 0..6000 {
        let clock = [50_000_000u32, 100_000_000, 12_000_000, 400_000_000][k % 4];
        let min_period = [2u32, 44, 66, 1000][(k / 4) % 4];
        let limits = Limits::new(min_period).unwrap();
        let max_rate = limits.max_rate();
        let sign = if rng.next() % 2 == 0 { 1 } else { -1 };
        let r;
        if k % 3 != 2 {
            // Distance, speed, acceleration, deceleration: mostly in range, some not.
            let steps = sign * log_uniform(&mut rng, 1.0, 6e7) as i64;
            let speed = match rng.next() % 20 {
                0 => 0,
                1 => clock as u64 + 1,
                _ => log_uniform(&mut rng, 1.0, clock as f64 / 2.0),
            } as u32;
            let accel = if rng.next() % 25 == 0 { 0 } else { log_uniform(&mut rng, 1.0, 3e9).min(u32::MAX as u64) as u32 };
            let decel = if rng.next() % 4 == 0 { accel } else { log_uniform(&mut rng, 1.0, 3e9).min(u32::MAX as u64) as u32 };
            input += &format!("rates {steps} {speed} {accel} {decel} {clock} {max_rate}\n");
            r = trapezoid_by_rates(steps, speed, accel, decel, clock, &limits);
        } else {
            let steps = if rng.next() % 10 == 0 { 0 } else { sign * log_uniform(&mut rng, 1.0, 6e7) as i64 };
            let mut t = [0u32; 3];
            for x in t.iter_mut() {
                *x = if rng.next() % 5 == 0 { 0 } else { log_uniform(&mut rng, 1.0, 2.2e9) as u32 };
            }
            input += &format!("ticks {steps} {} {} {} {max_rate}\n", t[0], t[1], t[2]);
            r = trapezoid_by_ticks(steps, t, &limits);
        }
        if r.is_ok() { ok += 1 } else { errs += 1 }
        want.push(c_form(&r));
    }
    assert!(ok > 1500 && errs > 1000, "the inputs cover both outcomes: {ok} planned, {errs} errors");
    assert_c_prints(&bin, &dir.join("plans.txt"), &input, &want, "C planner");
}

/// Runs `bin` on `input` (written to `in_path`), one line in and one line out per
/// case, and asserts each output line equals `want`'s (what the Rust planner gives).
fn assert_c_prints(bin: &Path, in_path: &Path, input: &str, want: &[String], what: &str) {
    std::fs::write(in_path, input).unwrap();
    let out = Command::new(bin).stdin(std::fs::File::open(in_path).unwrap()).output().unwrap();
    assert!(out.status.success());
    let got: Vec<String> = String::from_utf8(out.stdout).unwrap().lines().map(|s| s.to_string()).collect();
    assert_eq!(got.len(), want.len(), "one result per input");
    let inputs: Vec<&str> = input.lines().collect();
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        assert_eq!(g, w, "input {i}: `{}`: {what} against Rust planner", inputs[i]);
    }
}

/// One S-curve plan as scurve_check prints it: rc, count (the bad segment's index for
/// a segment error), then v0 v1 A T steps per segment.
fn scurve_c_form(r: &Result<Vec<Motion>, ScurveError>) -> String {
    match r {
        Ok(moves) => {
            let mut s = format!("0 {}", moves.len());
            for m in moves {
                let Motion::Poly(p) = m else { panic!("the S-curve planner plans polynomial segments") };
                s += &format!(" {} {} {} {} {}", p.v0_rate, p.v1_rate, p.a_q32, p.t_ticks, p.steps);
            }
            s
        }
        Err(e) => {
            let index = if let ScurveError::Segment { index, .. } = e { *index } else { 0 };
            format!("{} {index}", e.c_code())
        }
    }
}

/// The C S-curve planner (`tdm_scurve.c`, built with -ffp-contract=off) gives exactly
/// the Rust planner's segments and errors: jerk-limited and fourth-order moves over
/// and beyond the planner's domain, with bad limits, moves too short for their speed
/// change and moves too slow for a segment.
#[test]
fn the_c_scurve_planner_gives_the_rust_planners_segments() {
    let dir = sim_dir("c_scurve", Simulator::Verilator);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let c_dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("c");
    let bin = dir.join("scurve_check");
    let fp = ["-ffp-contract=off"];
    let objs = [
        gcc_c_with(&dir, &c_dir, &c_dir.join("tdm_scurve.c"), "s.o", &fp),
        gcc_c_with(&dir, &c_dir, &tests_c().join("scurve_check.c"), "c.o", &fp),
    ];
    // It builds for a Cortex-M4 (soft double) without a warning too.
    let mut arm = Command::new("arm-none-eabi-gcc");
    arm.args(["-mcpu=cortex-m4", "-mthumb", "-Os", "-ffp-contract=off"]).args(GCC_FLAGS).arg("-c").arg(c_dir.join("tdm_scurve.c")).arg("-o").arg(dir.join("s.arm.o"));
    let text = run(&mut arm, "arm-none-eabi-gcc tdm_scurve.c");
    assert!(text.trim().is_empty(), "arm-none-eabi-gcc printed diagnostics:\n{text}");
    run(Command::new("gcc").args(&objs).arg("-lm").arg("-o").arg(&bin), "link scurve_check");

    let mut rng = Rng(0x2545_f491_4f6c_dd1d);
    let unit = |rng: &mut Rng| (rng.next() % 1_000_000) as f64 / 1e6;
    let (mut input, mut want) = (String::new(), Vec::new());
    let (mut ok, mut errs) = (0, 0);
    for k in 0..1500 {
        let clock = [50_000_000u32, 100_000_000, 10_000_000, 24_000_000][k % 4];
        let limits = Limits::new([2u32, 44, 66, 1000][(k / 4) % 4]).unwrap();
        let max_rate = limits.max_rate();
        let rmax = max_rate as f64 * clock as f64 / 2f64.powi(32);
        let sign = if rng.next() % 2 == 0 { 1 } else { -1 };
        let steps = sign * log_uniform(&mut rng, 1.0, 2e5) as i64;
        // Mostly within the domain, some beyond it (v_max up to 1.2·RMAX, a bad limit).
        let v_max = match rng.next() % 20 {
            0 => 0.0,
            1 => f64::NAN,
            _ => log_uniform(&mut rng, 50.0, 1.2 * rmax) as f64 + unit(&mut rng),
        };
        let lu = |rng: &mut Rng, lo: f64, hi: f64| (lo.ln() + unit(rng) * (hi / lo).ln()).exp();
        let a = lu(&mut rng, v_max.max(1.0) / 2.0, v_max.max(1.0) / 1e-4);
        let j = lu(&mut rng, a / (v_max.max(1.0) / a), 50.0 * a * a / v_max.max(1.0));
        let r;
        if k % 2 == 0 {
            let d = lu(&mut rng, v_max.max(1.0) / 2.0, v_max.max(1.0) / 1e-4);
            let jd = lu(&mut rng, d / (v_max.max(1.0) / d), 50.0 * d * d / v_max.max(1.0));
            let vs = if rng.next() % 2 == 0 { 0.0 } else { unit(&mut rng) * v_max };
            let ve = if rng.next() % 2 == 0 { 0.0 } else { unit(&mut rng) * v_max };
            input += &format!("jerk {steps} {vs:e} {ve:e} {v_max:e} {a:e} {j:e} {d:e} {jd:e} {clock} {max_rate}\n");
            r = scurve::jerk_limited(steps, vs, ve, v_max, a, j, d, jd, clock, &limits);
        } else {
            let s = lu(&mut rng, j / (a / j), 50.0 * j * j / a);
            input += &format!("fourth {steps} {v_max:e} {a:e} {j:e} {s:e} {clock} {max_rate}\n");
            r = scurve::fourth_order(steps, v_max, a, j, s, clock, &limits);
        }
        if r.is_ok() { ok += 1 } else { errs += 1 }
        want.push(scurve_c_form(&r));
    }
    assert!(ok > 600 && errs > 100, "the inputs cover both outcomes: {ok} planned, {errs} errors");
    assert_c_prints(&bin, &dir.join("scurves.txt"), &input, &want, "C S-curve planner");
}

/// Random rest-to-rest moves for the core, kept to what K = 3 axes sustain: at most
/// half the maximum step rate, every segment at least 3,000 ticks, each move at most
/// 12 ms at 50 MHz, so no axis underruns.
fn random_moves(rng: &mut Rng, axis: usize, count: usize, limits: &Limits, clock: u32) -> Vec<(String, Vec<Segment>)> {
    let vmax = limits.max_rate() as f64 * clock as f64 / 2f64.powi(32);
    let mut out = Vec::new();
    while out.len() < count {
        let sign = if rng.next() % 2 == 0 { 1 } else { -1 };
        let steps = sign * log_uniform(rng, 1.0, 3000.0) as i64;
        let speed = log_uniform(rng, 200.0, vmax / 2.0) as u32;
        let accel = log_uniform(rng, 1e4, 1e8) as u32;
        let decel = if rng.next() % 2 == 0 { accel } else { log_uniform(rng, 1e4, 1e8) as u32 };
        let Ok(segs) = trapezoid_by_rates(steps, speed, accel, decel, clock, limits) else { continue };
        let total: u64 = segs.iter().map(|s| s.t_ticks as u64).sum();
        if segs.iter().all(|s| s.t_ticks >= 3000) && total <= 600_000 {
            out.push((format!("rates {axis} {steps} {speed} {accel} {decel}"), segs));
        }
    }
    out
}

/// STEP rising edges of each axis before `until`, as (clk cycle, dir).
fn edges(out: &str, axes: usize, until: u64) -> Vec<Vec<(u64, bool)>> {
    let mut e = vec![Vec::new(); axes];
    for l in out.lines().filter(|l| l.starts_with("E ")) {
        let v: Vec<u64> = l[2..].split_whitespace().map(|s| s.parse().unwrap()).collect();
        if v[1] < until {
            e[v[0] as usize].push((v[1], v[2] == 1));
        }
    }
    e
}

fn field(out: &str, tag: &str) -> Vec<Vec<i64>> {
    out.lines()
        .filter(|l| l.split_whitespace().next() == Some(tag))
        .map(|l| l.split_whitespace().skip(1).map(|s| s.parse().unwrap()).collect())
        .collect()
}

/// Builds the exported core in `dir` with Verilator around tests/c/exmc_shim.cpp,
/// linked with the driver, the planner, `main_c` (each compiled by gcc with the
/// project's flags) and the objects `extra`. Returns the executable.
fn build_with_shim(dir: &Path, main_c: &Path, extra: &[PathBuf]) -> PathBuf {
    build_with_shim_flags(dir, main_c, extra, &[])
}

/// [`build_with_shim`] with more C++ flags for the shim (`-DSHIM_IO`: the machine I/O pins).
fn build_with_shim_flags(dir: &Path, main_c: &Path, extra: &[PathBuf], cflags: &[&str]) -> PathBuf {
    let stem = main_c.file_stem().unwrap().to_str().unwrap().to_string();
    let objs = [
        gcc_c(dir, &dir.join("tdm_driver.c"), "tdm_driver.o"),
        gcc_c(dir, &dir.join("tdm_planner.c"), "tdm_planner.o"),
        gcc_c(dir, main_c, &format!("{stem}.o")),
    ];
    std::fs::copy(tests_c().join("exmc_shim.cpp"), dir.join("exmc_shim.cpp")).unwrap();
    let exe = format!("V{stem}");
    let mut v = Command::new("verilator");
    v.current_dir(dir)
        .args(["--cc", "--exe", "--build", "-j", "2", "-O3", "--x-assign", "fast", "--x-initial", "fast"])
        .args(["-Wno-fatal", "-Wno-lint", "-Wno-style", "--top-module", "tdm_stepper", "-o", &exe])
        .args(cflags.iter().flat_map(|f| ["-CFLAGS", f]))
        .args(["tdm_stepper.v", "exmc_shim.cpp"])
        .args(&objs)
        .args(extra);
    run(&mut v, "verilator build of the shim");
    dir.join("obj_dir").join(exe)
}

/// Every STEP edge the shim printed before `until` is the Rust model's for
/// `per_axis`, every axis from one release tick (zero skew), DIR the segment's sign.
fn check_model_edges(out: &str, per_axis: &[Vec<Segment>], limits: &Limits, until: u64) {
    let motions: Vec<Vec<Motion>> = per_axis.iter().map(|s| s.iter().copied().map(Motion::from).collect()).collect();
    check_model_motion_edges(out, &motions, limits, until);
}

/// [`check_model_edges`] for trapezoid and polynomial segments.
fn check_model_motion_edges(out: &str, per_axis: &[Vec<Motion>], limits: &Limits, until: u64) {
    let e = edges(out, per_axis.len(), until);
    let mut release = None;
    for (a, segs) in per_axis.iter().enumerate() {
        let run = AxisRun::run_motions(segs, limits);
        assert!(run.rejected.is_empty(), "axis {a}: the planner's segments are valid");
        assert_eq!(e[a].len(), run.edge_ticks.len(), "axis {a}: step count");
        let l0 = e[a][0].0 as i64 - 1 - run.edge_ticks[0] as i64;
        assert_eq!(*release.get_or_insert(l0), l0, "axis {a}: released on another tick (skew)");
        let mut s = 0;
        let mut left = segs[0].n_steps();
        for (i, (&(got, dir), &t)) in e[a].iter().zip(&run.edge_ticks).enumerate() {
            assert_eq!(got as i64, l0 + 1 + t as i64, "axis {a} edge {i}");
            while left == 0 {
                s += 1;
                left = segs[s].n_steps();
            }
            assert_eq!(dir, segs[s].steps() < 0, "axis {a} edge {i}: DIR");
            left -= 1;
        }
    }
}

/// The README's MCU worked example, compiled as written and run on the default
/// export (K = 2, 50 MHz) through the shim: it returns 0, and every edge is the
/// model's for the Rust planner's segments of the same two moves.
#[test]
fn readme_mcu_example_runs_as_written() {
    let readme = std::fs::read_to_string(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../README.md")).unwrap();
    let section = readme.split("## MCU driver (C)").nth(1).expect("README has an MCU driver section");
    let code = section.split("```c\n").nth(1).expect("a C block").split("```").next().unwrap();
    let (dir, opts) = export_dir("c_readme_example", 2);
    std::fs::write(dir.join("readme_example.c"), code).unwrap();
    let example = gcc_c(&dir, &dir.join("readme_example.c"), "readme_example.o");
    let exe = build_with_shim(&dir, &tests_c().join("readme_main.c"), &[example]);
    let out = run(Command::new(exe).current_dir(&dir), "the README example");
    assert!(out.contains("RC 0\n"), "two_axis_move failed: {}", out.lines().last().unwrap_or(""));
    let limits = opts.limits();
    let per_axis = vec![
        trapezoid_by_ticks(2400, [1_000_000, 500_000, 1_000_000], &limits).unwrap(),
        trapezoid_by_rates(-1800, 60_000, 6_000_000, 3_000_000, opts.clock_hz, &limits).unwrap(),
    ];
    check_model_edges(&out, &per_axis, &limits, u64::MAX);
}

/// The README's S-curve worked example, compiled as written with the header of an
/// S-curve export (K = 2, 50 MHz) and run through the shim: it returns 0, every edge is
/// the model's for the Rust planner's segments of the same two moves (a jerk-limited
/// and a fourth-order move, from one release tick), and the driver's polynomial push
/// refuses a reversing segment (code 2, no bus access), a bad axis and a null segment;
/// POLY_ARM reads 0 after the pushes (each took its arm). The driver built with a
/// default export's header has no polynomial push (the S-curve header adds it), and it
/// builds for a Cortex-M4 without a warning.
#[test]
fn readme_scurve_example_runs_as_written_through_the_driver() {
    let readme = std::fs::read_to_string(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../README.md")).unwrap();
    let section = readme.split("## S-curve moves").nth(1).expect("README has an S-curve section").split("\n## ").next().unwrap();
    let code = section.split("```c\n").nth(1).expect("a C block").split("```").next().unwrap();
    let dir = sim_dir("c_scurve_example", Simulator::Verilator);
    let _ = std::fs::remove_dir_all(&dir);
    let opts = ExportOptions { axes: 2, scurve: true, ..Default::default() };
    tdm_stepper::package::export(&opts, &dir).unwrap();
    std::fs::write(dir.join("scurve_example.c"), code).unwrap();
    let fp = ["-ffp-contract=off"];
    let objs = [
        gcc_c(&dir, &dir.join("scurve_example.c"), "scurve_example.o"),
        gcc_c_with(&dir, &dir, &dir.join("tdm_scurve.c"), "tdm_scurve.o", &fp),
    ];
    let (plain, _) = export_dir("c_scurve_plain", 2);
    gcc_c(&plain, &plain.join("tdm_driver.c"), "tdm_driver.o");
    let syms = run(Command::new("nm").arg(plain.join("tdm_driver.o")), "nm");
    assert!(!syms.contains("tdm_push_poly"), "a default export's driver has no polynomial push");
    let mut arm = Command::new("arm-none-eabi-gcc");
    arm.args(["-mcpu=cortex-m4", "-mthumb", "-Os"]).args(GCC_FLAGS).arg("-I").arg(&dir).arg("-c").arg(dir.join("tdm_driver.c")).arg("-o").arg(dir.join("d.arm.o"));
    let text = run(&mut arm, "arm-none-eabi-gcc tdm_driver.c (scurve)");
    assert!(text.trim().is_empty(), "arm-none-eabi-gcc printed diagnostics for the S-curve driver:\n{text}");

    let exe = build_with_shim(&dir, &tests_c().join("scurve_main.c"), &objs);
    let out = run(Command::new(exe).current_dir(&dir), "the README S-curve example");
    let syms = run(Command::new("nm").arg(dir.join("tdm_driver.o")), "nm");
    assert!(syms.contains(" T tdm_push_poly\n") && syms.contains(" T tdm_push_poly_some\n"), "the S-curve driver has the polynomial push");
    assert!(out.contains("RC 0\n"), "scurve_move failed: {}", out.lines().find(|l| l.starts_with("RC")).unwrap_or(""));
    let limits = opts.limits();
    let hz = opts.clock_hz;
    let per_axis = vec![
        scurve::jerk_limited(3000, 0.0, 0.0, 60_000.0, 6e6, 6e8, 3e6, 3e8, hz, &limits).unwrap(),
        scurve::fourth_order(-2000, 50_000.0, 5e6, 5e8, 1e11, hz, &limits).unwrap(),
    ];
    assert!(per_axis.iter().all(|ms| ms.len() >= 6 && ms.len() <= export::QUEUE_DEPTH), "{:?}", per_axis.iter().map(|m| m.len()).collect::<Vec<_>>());
    check_model_motion_edges(&out, &per_axis, &limits, u64::MAX);
    assert_eq!(field(&out, "BADPOLY")[0], [2, 0], "a reversing segment: code 2, no bus access");
    assert_eq!(field(&out, "BADSOME")[0], [2, 0], "push_some: code 2, nothing taken");
    assert_eq!(field(&out, "AXISPOLY")[0], [-4]);
    assert_eq!(field(&out, "NULLPOLY")[0], [-7]);
    assert_eq!(field(&out, "ARM")[0], [0], "every push took its arm");
    assert_eq!(field(&out, "LEVEL")[0], [export::QUEUE_DEPTH as i64; 2], "both queues drained, nothing left behind");
}

#[test]
fn the_driver_runs_planned_moves_on_the_exported_ip_through_the_exmc_pins() {
    driver_runs_planned_moves(export::Bus::Exmc);
}

/// The same driver check on an `--bus spi` export through tdm_open_spi() (the core
/// opened by the README's SPI example, as written): every access a frame at SCK =
/// bus_clk/4 (the fastest documented), mode 3, segment pushes one 14-byte frame each;
/// no frame refused, and a frame cut mid-word refused as documented (FRAME_ERR, the
/// register unchanged).
#[test]
fn the_driver_runs_planned_moves_on_the_exported_ip_through_the_spi_pins() {
    driver_runs_planned_moves(export::Bus::Spi);
}

fn driver_runs_planned_moves(bus: export::Bus) {
    const K: usize = 3;
    let spi = bus == export::Bus::Spi;
    let dir = sim_dir(if spi { "c_driver_ip_spi" } else { "c_driver_ip" }, Simulator::Verilator);
    let _ = std::fs::remove_dir_all(&dir);
    let opts = ExportOptions { axes: K, bus, ..Default::default() };
    tdm_stepper::package::export(&opts, &dir).unwrap();
    let limits = Limits::new(opts.min_period_ticks() as u32).unwrap();
    let clock = opts.clock_hz;

    // The moves: the paper's experiment on axes 0 and 1 (ticks form), random moves on
    // every axis, and moves the planner must refuse.
    let mut rng = Rng(0x2545_f491_4f6c_dd1d);
    let mut lines = vec!["ticks 0 2400 1000000 500000 1000000".to_string(), "ticks 1 -1800 1000000 500000 1000000".to_string()];
    let mut per_axis: Vec<Vec<Segment>> = vec![Vec::new(); K];
    per_axis[0] = trapezoid_by_ticks(2400, [1_000_000, 500_000, 1_000_000], &limits).unwrap();
    per_axis[1] = trapezoid_by_ticks(-1800, [1_000_000, 500_000, 1_000_000], &limits).unwrap();
    for (a, segs) in per_axis.iter_mut().enumerate() {
        for (l, s) in random_moves(&mut rng, a, 6, &limits, clock) {
            lines.push(l);
            segs.extend(s);
        }
    }
    let vmax = (limits.max_rate() as u64 * clock as u64 >> 32) as u32;
    let impossible = [
        format!("rates 2 1000000 {} 1000000000 1000000000", vmax + vmax / 100), // faster than the minimum period: 3
        "rates 2 50331649 1000 1000 1000".to_string(),       // more than 3·2^24 steps
        "rates 2 100 1000 0 1000".to_string(),               // no acceleration
        "rates 2 100000 100000 1 1".to_string(),             // a phase longer than 2^30 ticks: 4
        "ticks 2 100 0 0 0".to_string(),                     // no duration
        "ticks 2 5 100 0 100".to_string(),                   // 5 steps in 4 µs: period too short
    ];
    lines.extend(impossible.iter().cloned());
    std::fs::write(dir.join("moves.txt"), lines.join("\n") + "\n").unwrap();

    let flags: &[&str] = if spi { &["-DSHIM_SPI", "-DSHIM_SPI_MODE=3"] } else { &[] };
    // On SPI the core is opened by the README's example, compiled as written.
    let mut extra = vec![];
    if spi {
        let readme = std::fs::read_to_string(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../README.md")).unwrap();
        let section = readme.split("## Picking a bus").nth(1).expect("README has the bus section").split("\n## ").next().unwrap();
        let code = section.split("```c\n").nth(1).expect("a C block").split("```").next().unwrap();
        std::fs::write(dir.join("spi_example.c"), code).unwrap();
        extra.push(gcc_c(&dir, &dir.join("spi_example.c"), "spi_example.o"));
    }
    let t0 = std::time::Instant::now();
    let exe = build_with_shim_flags(&dir, &tests_c().join("driver_check.c"), &extra, flags);
    let out = run(Command::new(exe).current_dir(&dir).arg("moves.txt"), "the driver check");
    eprintln!("driver check on {bus:?}: build and run {:.1} s", t0.elapsed().as_secs_f64());

    // Identification (on SPI first by the README's example) and enable.
    if spi {
        assert_eq!(field(&out, "SPIOPEN")[0], [0], "the README's open_core_on_spi");
    }
    let id = &field(&out, "IDENTIFY")[0];
    assert_eq!(id[..4], [0, K as i64, clock as i64, export::QUEUE_DEPTH as i64], "identify: {out:.400}");
    assert_eq!(id[6], limits.max_rate() as i64);
    assert_eq!(field(&out, "ENABLE_BAD")[0], [-7], "output timing that does not fit is refused on the host");
    assert_eq!(field(&out, "ENABLE")[0], [0]);

    // Every plan is the Rust planner's.
    let plans = field(&out, "PLAN");
    assert_eq!(plans.len(), lines.len());
    for (p, l) in plans.iter().zip(&lines) {
        let w: Vec<i64> = l.split_whitespace().skip(1).map(|s| s.parse().unwrap()).collect();
        let r = if l.starts_with("rates") {
            trapezoid_by_rates(w[1], w[2] as u32, w[3] as u32, w[4] as u32, clock, &limits)
        } else {
            trapezoid_by_ticks(w[1], [w[2] as u32, w[3] as u32, w[4] as u32], &limits)
        };
        let got: Vec<String> = p[1..].iter().map(|x| x.to_string()).collect();
        assert_eq!(got.join(" "), c_form(&r), "plan of `{l}`");
    }
    let refused: Vec<i64> = plans[plans.len() - impossible.len()..].iter().map(|p| p[1]).collect();
    assert_eq!(refused, [3, -22, -21, 4, -20, 3], "the impossible moves' errors");

    // Every STEP edge is the model's, all axes from one release tick; DIR matches.
    let mark = field(&out, "MARK")[0][0] as u64;
    check_model_edges(&out, &per_axis, &limits, mark);
    // Positions read through the driver, no flag raised, every queue drained.
    let pos = field(&out, "POS");
    for (a, segs) in per_axis.iter().enumerate() {
        let total: i64 = segs.iter().map(|s| s.steps as i64).sum();
        assert_eq!(pos[a][2], total, "axis {a}: position read back");
        assert_eq!(pos[a][3..], [0, 0, 0, 0], "axis {a}: underrun, overflow, error, level");
    }
    let irq = &field(&out, "IRQ")[0];
    assert_eq!(irq[0], (1 << K) - 1, "every axis reported segments done");
    assert_eq!(irq[2], 0, "no error event");

    // Host-side rejections: the core's codes, not one bus access.
    assert_eq!(field(&out, "BADPUSH"), [[0, 1, 0], [1, 5, 0], [2, 3, 0], [3, 2, 0]]);
    assert_eq!(field(&out, "AXISPUSH")[0], [-4]);
    assert_eq!(field(&out, "AXISSTART")[0], [-4]);

    // A full queue: pushes stop at TDM_E_FULL with LEVEL = the depth and no overflow.
    let full = &field(&out, "FULL")[0];
    assert_eq!(full[0], -8, "the last push reports a full queue");
    assert!(full[1] >= export::QUEUE_DEPTH as i64, "accepted {} pushes", full[1]);
    assert_eq!(full[2..], [export::QUEUE_DEPTH as i64, 0], "LEVEL full, OVERFLOW never set");
    assert_eq!(field(&out, "START2")[0], [0]);
    // The abort in motion: axis 0 moved backwards for a while and stopped; the
    // position read back counts exactly the edges emitted.
    let abort = field(&out, "ABORT")[0][0] as u64;
    let after: Vec<(u64, bool)> = edges(&out, K, u64::MAX)[0].iter().copied().filter(|&(c, _)| c >= mark).collect();
    assert!(after.len() > 10 && after.iter().all(|&(_, d)| d), "axis 0 stepped backwards before the abort: {}", after.len());
    assert!(after.iter().all(|&(c, _)| c <= abort + 10), "no edge long after the abort");
    let pos2 = &field(&out, "POS")[K];
    assert_eq!(pos2[2], pos[0][2] - after.len() as i64, "axis 0's position after the abort");
    assert_eq!(pos2[6], 0, "the abort emptied the queue");
    // The failed START, through the irq helper, then cleared.
    let irqs = field(&out, "IRQ");
    assert_eq!(field(&out, "START3")[0], [0]);
    assert_eq!(irqs[2][3], 1, "START_FAILED seen");
    assert_eq!(irqs[2][2] & (1 << (K - 1)), 1 << (K - 1), "IRQ_ERROR for the masked axis");
    assert_eq!(irqs[3], [0, 0, 0, 0], "the helper cleared what it returned");
    // No frame refused; the cut frame (SPI) is, and changes nothing.
    assert_eq!(field(&out, "BUSERR")[0], [0], "no bus error in the whole run");
    let qlow = tdm_stepper::regs::register("QLOW_LEVEL").reset_value(&opts.params()) as i64;
    let glitch = if spi { [1, qlow, qlow, 1] } else { [0, qlow, qlow, 0] };
    assert_eq!(field(&out, "GLITCH")[0], glitch, "a frame cut mid-word: refused, QLOW_LEVEL kept");
}

/// The README's homing worked example (Machine I/O), compiled as written with the
/// header of an `--io all` export (K = 2) and run through the shim with the machine
/// I/O pins and a home switch at position −1,234 of axis 0: it returns 0 with the zero
/// at −1,234 and axis 0 resting there; the search crossed the switch once and ramped
/// down past it (the controlled stop on home), the back-off left it and the approach
/// came back to it; tdm_io_service reports the home latch and the stop of axis 0 and
/// then nothing. Then a controlled stop (tdm_stop) of a move of axis 1: its edges are
/// the model's stop (model::stop::cut_run) and its position is read back; and the
/// machine I/O calls that must refuse do, with the documented codes.
#[test]
fn readme_homing_example_runs_as_written_through_the_machine_io() {
    let readme = std::fs::read_to_string(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../README.md")).unwrap();
    let section = readme.split("## Machine I/O").nth(1).expect("README has a Machine I/O section").split("\n## ").next().unwrap();
    let code = section.split("```c\n").nth(1).expect("a C block").split("```").next().unwrap();
    let dir = sim_dir("c_io_homing", Simulator::Verilator);
    let _ = std::fs::remove_dir_all(&dir);
    let opts = ExportOptions { axes: 2, io: true, ..Default::default() };
    tdm_stepper::package::export(&opts, &dir).unwrap();
    std::fs::write(dir.join("home_example.c"), code).unwrap();
    let example = gcc_c(&dir, &dir.join("home_example.c"), "home_example.o");
    let exe = build_with_shim_flags(&dir, &tests_c().join("io_main.c"), &[example], &["-DSHIM_IO"]);
    let out = run(Command::new(exe).current_dir(&dir), "the homing example");
    let limits = opts.limits();
    assert_eq!(field(&out, "HOME")[0], [0, -1234, -1234], "tdm_home: rc, zero, the position at rest");
    // The home pin (the shim's H lines: axis, cycle, position, level).
    let h: Vec<Vec<i64>> = field(&out, "H").into_iter().filter(|l| l[0] == 0).collect();
    assert!(h.len() >= 3, "the switch changed {} times", h.len());
    assert_eq!((h[0][2], h[0][3]), (-1234, 1), "the search reached the switch at -1234");
    assert_eq!((h[1][2], h[1][3]), (-1233, 0), "the back-off left it");
    assert_eq!((h.last().unwrap()[2], h.last().unwrap()[3]), (-1234, 1), "the approach came back to it");
    // The search ramped down past the switch (the controlled stop), by more than one edge.
    let e0 = edges(&out, 2, u64::MAX);
    let mut pos = 0i64;
    let mut lowest = 0i64;
    for &(_, d) in &e0[0] {
        pos += if d { -1 } else { 1 };
        lowest = lowest.min(pos);
    }
    assert_eq!(pos, -1234, "axis 0's edges end at the zero");
    assert!(lowest < -1234 - 10 && lowest > -1234 - 400, "the search's overshoot: {}", -1234 - lowest);
    let ev = field(&out, "EVENTS");
    assert_eq!((ev[0][3] & 1, ev[0][4] & 1), (1, 1), "tdm_io_service: axis 0's home latch and its stop");
    assert_eq!(ev[1], [0, 0, 0, 0, 0], "and nothing after they were cleared");
    // The controlled stop of axis 1.
    let stop_at = field(&out, "STOPAT")[0][0] as u64;
    let st = &field(&out, "STOP")[0];
    assert_eq!(st[0], 0, "tdm_stop and the wait");
    let segs = trapezoid_by_rates(3000, 50_000, 5_000_000, 5_000_000, opts.clock_hz, &limits).unwrap();
    let run1 = AxisRun::run(&segs, &limits);
    let r: Vec<u64> = e0[1].iter().map(|&(c, _)| c).collect();
    let emitted = r.iter().filter(|&&c| c < stop_at).count();
    let e = entries_for_edges(&run1, emitted);
    let decel = 400_000_000;
    let (_, m) = stop_cut_matching(&run1, &r, e..=e + export::FIFO_DEPTH + 3, decel, &limits)
        .unwrap_or_else(|| panic!("no cut near {e} entries gives axis 1's {} edges", r.len()));
    assert_eq!(m.accepted.len(), 1, "a ramp");
    assert!(r.len() < 3000, "the stop shortened the move: {} edges", r.len());
    assert_eq!(st[1], m.position, "the position read back");
    // Refusals.
    assert_eq!(field(&out, "BADFILTER")[0], [-7]);
    assert_eq!(field(&out, "BADDECEL")[0], [-7]);
    assert_eq!(field(&out, "BADMODE")[0], [-7]);
    assert_eq!(field(&out, "ENABLED")[0], [-6], "configuration while enabled: TDM_E_REFUSED");
    assert_eq!(field(&out, "SOFTBAD")[0], [-7]);
    assert_eq!(field(&out, "STOPAXIS")[0], [-4, -4]);
    assert!(out.contains("RC 0\n"));
}

/// The README's encoder worked example (Encoder feedback), compiled as written with the
/// header of an `--encoder` export (K = 2) and run through the shim with a motor per
/// axis that follows STEP and DIR and an encoder of 5/4 counts per step: a 2,000-step
/// move of axis 0 whose motor loses about 40 steps (the shim stalls it) ends with the
/// encoder behind by their counts and ENC_FAIL set (IRQ_ENC.FAIL, tdm_enc_service);
/// `check_and_correct` moves exactly the steps lost and leaves the encoder at the
/// commanded position within a count, the deviation 0 and ENC_FAIL clear; a second
/// call moves nothing; and the calls that must refuse do, with the documented codes.
/// Without the encoder the functions are not in the driver.
#[test]
fn readme_encoder_example_corrects_lost_steps_through_the_driver() {
    let readme = std::fs::read_to_string(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../README.md")).unwrap();
    let section = readme.split("## Encoder feedback").nth(1).expect("README has an Encoder feedback section").split("\n## ").next().unwrap();
    let code = section.split("```c\n").nth(1).expect("a C block").split("```").next().unwrap();
    let dir = sim_dir("c_encoder", Simulator::Verilator);
    let _ = std::fs::remove_dir_all(&dir);
    let opts = ExportOptions { axes: 2, encoder: true, ..Default::default() };
    tdm_stepper::package::export(&opts, &dir).unwrap();
    std::fs::write(dir.join("enc_example.c"), code).unwrap();
    let example = gcc_c(&dir, &dir.join("enc_example.c"), "enc_example.o");
    let exe = build_with_shim_flags(&dir, &tests_c().join("enc_main.c"), &[example], &["-DSHIM_ENC"]);
    let out = run(Command::new(exe).current_dir(&dir), "the encoder example");
    let one = |tag: &str| field(&out, tag).into_iter().next().unwrap_or_else(|| panic!("no {tag} line in:\n{out}"));
    assert_eq!(one("IDENTIFY"), [0]);
    assert_eq!((one("BADRATIO"), one("BIGRATIO"), one("BADFILTER"), one("BADSTOP")), (vec![-7], vec![-7], vec![-7], vec![-4]), "bad configurations");
    assert_eq!((one("SETUP"), one("ENABLE"), one("ENABLED"), one("ALIGN")), (vec![0], vec![0], vec![-6], vec![0, -4]), "setup, enable, setup while enabled, align");
    let lost = one("STALL")[0];
    assert!((38..=42).contains(&lost), "the motor lost {lost} steps");
    assert_eq!(one("MOVE"), [0, 2000], "the move ran to its end");
    let counts = |steps: i64| (steps * 5).div_euclid(4);
    let read = one("READ");
    assert_eq!(read, [0, counts(2000 - lost), counts(2000) - counts(2000 - lost), 1, 0], "the encoder behind by the lost steps' counts, ENC_FAIL, no illegal transition");
    // The encoder's index at 1,000 counts: 800 motor steps, 800 + the lost steps on
    // the core's position (the stall came before it).
    assert_eq!(one("INDEX"), [1000, 800 + lost], "ENC_INDEX and ENC_INDEX_POS: the count and the step position at the index");
    assert_eq!(one("SERVICE"), [0b101, 1], "tdm_enc_service: IRQ_ENC.FAIL and INDEX, ENC_FAIL of axis 0");
    let c = one("CORRECT");
    assert_eq!((c[0], c[1]), (0, lost), "the correction moved the lost steps");
    assert!((c[2] - counts(2000)).abs() <= 1, "after the correction the encoder reads {}, the commanded position is {} counts", c[2], counts(2000));
    assert_eq!((c[3], c[4]), (2000, 2000 + lost), "the motor at the commanded position, POS counting the correction");
    let after = one("AFTER");
    assert_eq!((after[0], after[2], after[3]), (0, 0, 0), "the deviation 0 and ENC_FAIL clear after the correction");
    assert!((after[1] - counts(2000)).abs() <= 1);
    assert_eq!(one("NOTHING"), [0, 0], "nothing to correct");
    assert_eq!(one("BADAXIS"), [-4, -4]);
    assert!(out.contains("RC 0\n"));
    // The encoder functions exist only with an encoder export's header.
    let syms = run(Command::new("nm").arg(dir.join("tdm_driver.o")), "nm");
    assert!(syms.lines().any(|l| l.ends_with(" T tdm_enc_correct")), "tdm_enc_correct with --encoder");
    let (plain, _) = export_dir("c_encoder_plain", 2);
    gcc_c(&plain, &plain.join("tdm_driver.c"), "tdm_driver.o");
    let syms = run(Command::new("nm").arg(plain.join("tdm_driver.o")), "nm");
    assert!(!syms.contains("tdm_enc_"), "no tdm_enc_* without --encoder");
}
