//! The README's quick start runs what exists, CI runs the README's test command,
//! and the CLI fails cleanly on bad input.

use std::path::PathBuf;
use std::process::Command;

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_tdm-stepper"))
}

/// The fenced block under "## Quick start".
fn quick_start() -> Vec<String> {
    let readme = std::fs::read_to_string(repo().join("README.md")).unwrap();
    let section = readme.split("## Quick start").nth(1).expect("README has a Quick start");
    let block = section.split("```").nth(1).expect("a fenced block");
    block.lines().skip(1).map(|l| l.split('#').next().unwrap().trim().to_string()).filter(|l| !l.is_empty()).collect()
}

#[test]
fn quick_start_commands_exist_and_ci_runs_the_test_command() {
    let cmds = quick_start();
    assert_eq!(cmds.len(), 2, "two commands: {cmds:?}");
    // The first runs a subcommand of our binary.
    let sub = cmds[0].strip_prefix("cargo run --release -- ").expect("cargo run of the binary");
    let out = bin().args(sub.split_whitespace()).arg("--help").output().unwrap();
    assert!(out.status.success(), "`tdm-stepper {sub} --help` failed");
    // The second is the test script, and CI calls exactly it.
    assert_eq!(cmds[1], "scripts/test.sh");
    let ci = std::fs::read_to_string(repo().join(".ci/run")).unwrap();
    assert!(ci.lines().any(|l| l.trim() == "exec scripts/test.sh"), ".ci/run must exec scripts/test.sh");
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
