//! `tdm-stepper sim`: a move, in physical units, written through the EXMC bus model
//! into the exported core and simulated (Verilator by default, or rust-hdl), with a
//! report, an SVG and optionally a VCD window.
//!
//! MOVES.json:
//! ```json
//! { "clock_hz": 50000000,
//!   "axes": [
//!     { "trapezoid": { "steps": 2400, "t_acc_s": 0.02, "t_cruise_s": 0.01, "t_dec_s": 0.02 } },
//!     { "segments": [ { "v0_steps_per_s": 0, "t_s": 0.02, "steps": 600 },
//!                     { "v0_steps_per_s": 60000, "t_s": 0.01, "steps": 600 } ] } ] }
//! ```
//! An axis may also give a jerk-limited (`"jerk"`) or a fourth-order (`"fourth"`)
//! move; a file with one simulates the core exported with `--profiles
//! trapezoid,scurve` (its minimum period is then K·100 ticks for every axis).
//! Every axis starts together (one START with all of them). The bus model drives the
//! documented minimum timing from a 168 MHz MCU into a ≈100 MHz `bus_clk`; `clk` is
//! `clock_hz` (rounded to a whole number of 3 ps half periods). While the bus rests
//! for long, Verilator pauses `bus_clk` (it carries no STEP timing); see
//! [`crate::verify::system::bus_pauses`].

use crate::export::{self, ExportOptions, QUEUE_DEPTH, RADIX_BITS};
use crate::model::{planner, scurve, units, AxisRun, Limits, Motion, Segment};
use crate::verify::bus::{position, stepper_watch, system_spec, BusModel, BusTiming, ReadId};
use crate::verify::system::{gtkw_text, run_system_with, write_vcd, Clocks, RunOptions, SystemTrace, VcdOptions};
use plotters::prelude::*;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The moves file.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MovesFile {
    #[serde(default = "default_clock")]
    pub clock_hz: u32,
    pub axes: Vec<AxisMove>,
}

fn default_clock() -> u32 {
    50_000_000
}

/// One axis: segments in physical units, or the trapezoid shorthand.
#[derive(Clone, Debug, Deserialize)]
#[serde(untagged, deny_unknown_fields)]
pub enum AxisMove {
    Segments { segments: Vec<PhysSegment> },
    Trapezoid { trapezoid: Trapezoid },
    Move {
        #[serde(rename = "move")]
        mv: RateMove,
    },
    Jerk { jerk: JerkMove },
    Fourth { fourth: FourthMove },
}

impl AxisMove {
    /// An S-curve move: it needs the core with polynomial segments.
    pub fn is_scurve(&self) -> bool {
        matches!(self, AxisMove::Jerk { .. } | AxisMove::Fourth { .. })
    }
}

/// A jerk-limited (seven-phase) move, planned by [`scurve::jerk_limited`] (the C
/// planner's `tdm_plan_jerk`).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JerkMove {
    pub steps: i64,
    #[serde(default)]
    pub v_start_steps_per_s: f64,
    #[serde(default)]
    pub v_end_steps_per_s: f64,
    pub speed_steps_per_s: f64,
    pub accel_steps_per_s2: f64,
    pub jerk_steps_per_s3: f64,
    pub decel_steps_per_s2: f64,
    pub decel_jerk_steps_per_s3: f64,
}

/// The fourth-order (snap-limited) profile, rest to rest, planned by
/// [`scurve::fourth_order`] (`tdm_plan_fourth`).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FourthMove {
    pub steps: i64,
    pub speed_steps_per_s: f64,
    pub accel_steps_per_s2: f64,
    pub jerk_steps_per_s3: f64,
    pub snap_steps_per_s4: f64,
}

/// A move as distance, top speed, acceleration and deceleration (integers), planned
/// by [`planner::trapezoid_by_rates`] (the C planner's `tdm_plan_rates`).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RateMove {
    pub steps: i64,
    pub speed_steps_per_s: u32,
    pub accel_steps_per_s2: u32,
    pub decel_steps_per_s2: u32,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PhysSegment {
    pub v0_steps_per_s: f64,
    pub t_s: f64,
    pub steps: i64,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Trapezoid {
    pub steps: i64,
    pub t_acc_s: f64,
    pub t_cruise_s: f64,
    pub t_dec_s: f64,
}

/// Which simulator runs the core.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Engine {
    Verilator,
    RustHdl,
}

impl std::str::FromStr for Engine {
    type Err = String;
    fn from_str(s: &str) -> Result<Engine, String> {
        match s {
            "verilator" => Ok(Engine::Verilator),
            "rust-hdl" => Ok(Engine::RustHdl),
            _ => Err(format!("unknown engine {s:?}: expected verilator or rust-hdl")),
        }
    }
}

/// What to simulate.
#[derive(Clone, Debug)]
pub struct SimOptions {
    pub axes: usize,
    /// The core's minimum period (the export's `--min-period`); `None`: the default.
    pub min_period: Option<u32>,
    pub moves: PathBuf,
    pub engine: Engine,
    pub vcd: Option<PathBuf>,
    /// Seconds from the start of the simulation.
    pub vcd_window: Option<(f64, f64)>,
    pub report: PathBuf,
    /// Scratch folder for the simulator build.
    pub work: PathBuf,
    pub progress: bool,
}

/// STATUS bits (docs/registers.md).
const STATUS_UNDERRUN: u16 = 1 << 6;
const STATUS_OVERFLOW: u16 = 1 << 7;
const STATUS_ERROR: u16 = 1 << 8;

/// Parses `START_S:END_S`.
pub fn parse_window(s: &str) -> Result<(f64, f64), String> {
    let (a, b) = s.split_once(':').ok_or_else(|| format!("--vcd-window {s:?}: expected START_S:END_S"))?;
    let parse = |x: &str| x.trim().parse::<f64>().map_err(|_| format!("--vcd-window {s:?}: {x:?} is not a number of seconds"));
    let (a, b) = (parse(a)?, parse(b)?);
    if !(a.is_finite() && b.is_finite() && a >= 0.0 && b > a) {
        return Err(format!("--vcd-window {s:?}: need 0 ≤ START < END"));
    }
    Ok((a, b))
}

/// The moves file's fields: (object, field, JSON type, meaning). The checker
/// ([`parse_moves`]) and the JSON Schema ([`moves_schema`]) are both made from it.
pub const MOVES_FIELDS: &[(&str, &str, &str, &str)] = &[
    ("file", "clock_hz", "integer", "core clock in Hz (default 50000000; 1 MHz to 400 MHz)"),
    ("file", "axes", "array", "one entry per axis, axis 0 first (at most the core's K)"),
    ("axis", "segments", "array", "the axis's segments, in order"),
    ("axis", "trapezoid", "object", "a trapezoid move by phase times, planned into segments"),
    ("axis", "move", "object", "a move by distance, top speed and accelerations (a triangle when too short to reach the speed), planned into segments"),
    ("segment", "v0_steps_per_s", "number", "start speed, steps/s (>= 0)"),
    ("segment", "t_s", "number", "duration, seconds (> 0)"),
    ("segment", "steps", "integer", "signed steps (negative: DIR = 1)"),
    ("trapezoid", "steps", "integer", "signed distance in steps"),
    ("trapezoid", "t_acc_s", "number", "acceleration time, seconds"),
    ("trapezoid", "t_cruise_s", "number", "cruise time, seconds"),
    ("trapezoid", "t_dec_s", "number", "deceleration time, seconds"),
    ("move", "steps", "integer", "signed distance in steps"),
    ("move", "speed_steps_per_s", "integer", "top speed, steps/s (1 to clock_hz)"),
    ("move", "accel_steps_per_s2", "integer", "acceleration, steps/s^2 (1 to 2147483647)"),
    ("move", "decel_steps_per_s2", "integer", "deceleration, steps/s^2 (1 to 2147483647)"),
    ("axis", "jerk", "object", "a jerk-limited (seven-phase S-curve) move by distance, speeds, accelerations and jerks, planned into polynomial segments (needs the S-curve core)"),
    ("axis", "fourth", "object", "a fourth-order (snap-limited) S-curve move, rest to rest, planned into polynomial segments (needs the S-curve core)"),
    ("jerk", "steps", "integer", "signed distance in steps"),
    ("jerk", "v_start_steps_per_s", "number", "start speed, steps/s (default 0; at most the top speed)"),
    ("jerk", "v_end_steps_per_s", "number", "end speed, steps/s (default 0; at most the top speed)"),
    ("jerk", "speed_steps_per_s", "number", "top speed, steps/s (> 0, at most the core's maximum rate)"),
    ("jerk", "accel_steps_per_s2", "number", "acceleration limit, steps/s^2 (> 0)"),
    ("jerk", "jerk_steps_per_s3", "number", "jerk limit while speeding up, steps/s^3 (> 0)"),
    ("jerk", "decel_steps_per_s2", "number", "deceleration limit, steps/s^2 (> 0)"),
    ("jerk", "decel_jerk_steps_per_s3", "number", "jerk limit while slowing down, steps/s^3 (> 0)"),
    ("fourth", "steps", "integer", "signed distance in steps"),
    ("fourth", "speed_steps_per_s", "number", "top speed, steps/s (> 0, at most the core's maximum rate)"),
    ("fourth", "accel_steps_per_s2", "number", "acceleration limit, steps/s^2 (> 0)"),
    ("fourth", "jerk_steps_per_s3", "number", "jerk limit, steps/s^3 (> 0)"),
    ("fourth", "snap_steps_per_s4", "number", "snap limit, steps/s^4 (> 0)"),
];

/// The `jerk` fields a file may leave out (they default to 0).
const JERK_OPTIONAL: [&str; 2] = ["v_start_steps_per_s", "v_end_steps_per_s"];

/// The `move` fields that are u32 rates (at least 1).
const MOVE_RATE_FIELDS: [&str; 3] = ["speed_steps_per_s", "accel_steps_per_s2", "decel_steps_per_s2"];

fn fields_of(object: &str) -> Vec<&'static str> {
    MOVES_FIELDS.iter().filter(|f| f.0 == object).map(|f| f.1).collect()
}

/// Checks a moves file's shape against [`MOVES_FIELDS`], naming the field that is
/// wrong (`axes[1].segments[0].t_s: ...`), then reads it.
pub fn parse_moves(text: &str) -> Result<MovesFile, String> {
    let v: serde_json::Value = serde_json::from_str(text).map_err(|e| format!("not JSON: {e}"))?;
    fn check(v: &serde_json::Value, object: &str, path: &str, required: &[&str]) -> Result<(), String> {
        let m = v.as_object().ok_or_else(|| format!("{path}: expected an object with {}", fields_of(object).join(", ")))?;
        for (k, x) in m {
            let Some(f) = MOVES_FIELDS.iter().find(|f| f.0 == object && f.1 == k) else {
                return Err(format!("{path}: unknown field {k:?} (the fields are {})", fields_of(object).join(", ")));
            };
            let ok = match f.2 {
                "integer" => x.is_i64() || x.is_u64(),
                "number" => x.is_number(),
                "array" => x.is_array(),
                _ => x.is_object(),
            };
            if !ok {
                return Err(format!("{path}.{k}: expected {} {}, found {x}", if f.2 == "integer" || f.2 == "array" { "an" } else { "a" }, f.2));
            }
        }
        for r in required {
            if !m.contains_key(*r) {
                return Err(format!("{path}: missing field {r:?}"));
            }
        }
        Ok(())
    }
    check(&v, "file", "moves file", &["axes"])?;
    for (a, ax) in v["axes"].as_array().unwrap().iter().enumerate() {
        let path = format!("axes[{a}]");
        check(ax, "axis", &path, &[])?;
        let m = ax.as_object().unwrap();
        if m.len() != 1 {
            return Err(format!("{path}: give exactly one of \"segments\", \"trapezoid\", \"move\", \"jerk\" or \"fourth\""));
        }
        if let Some(t) = m.get("jerk") {
            let required: Vec<&str> = fields_of("jerk").into_iter().filter(|f| !JERK_OPTIONAL.contains(f)).collect();
            check(t, "jerk", &format!("{path}.jerk"), &required)?;
        }
        if let Some(t) = m.get("fourth") {
            check(t, "fourth", &format!("{path}.fourth"), &fields_of("fourth"))?;
        }
        if let Some(t) = m.get("trapezoid") {
            check(t, "trapezoid", &format!("{path}.trapezoid"), &fields_of("trapezoid"))?;
        }
        if let Some(t) = m.get("move") {
            check(t, "move", &format!("{path}.move"), &fields_of("move"))?;
            for f in MOVE_RATE_FIELDS {
                if t[f].as_u64().is_none_or(|x| x > u32::MAX as u64) {
                    return Err(format!("{path}.move.{f}: expected an integer from 1 to {}, found {}", u32::MAX, t[f]));
                }
            }
        }
        if let Some(segs) = m.get("segments").and_then(|s| s.as_array()) {
            for (k, sg) in segs.iter().enumerate() {
                check(sg, "segment", &format!("{path}.segments[{k}]"), &fields_of("segment"))?;
            }
        }
    }
    serde_json::from_value(v).map_err(|e| e.to_string())
}

/// The moves file as a JSON Schema (draft 2020-12), from [`MOVES_FIELDS`]; committed
/// as docs/moves.schema.json.
pub fn moves_schema() -> String {
    use serde_json::{json, Map, Value};
    let props = |object: &str| -> Map<String, Value> {
        MOVES_FIELDS
            .iter()
            .filter(|f| f.0 == object)
            .map(|f| (f.1.to_string(), json!({"type": f.2, "description": f.3})))
            .collect()
    };
    let obj = |object: &str, required: Vec<&str>| json!({"type": "object", "additionalProperties": false, "properties": props(object), "required": required});
    let mut segment = obj("segment", fields_of("segment"));
    segment["properties"]["t_s"]["exclusiveMinimum"] = json!(0);
    segment["properties"]["v0_steps_per_s"]["minimum"] = json!(0);
    let trapezoid = obj("trapezoid", fields_of("trapezoid"));
    let mut rate_move = obj("move", fields_of("move"));
    for f in MOVE_RATE_FIELDS {
        rate_move["properties"][f]["minimum"] = json!(1);
    }
    rate_move["properties"]["accel_steps_per_s2"]["maximum"] = json!(planner::MAX_ACCEL);
    rate_move["properties"]["decel_steps_per_s2"]["maximum"] = json!(planner::MAX_ACCEL);
    let jerk = obj("jerk", fields_of("jerk").into_iter().filter(|f| !JERK_OPTIONAL.contains(f)).collect());
    let fourth = obj("fourth", fields_of("fourth"));
    let mut file = obj("file", vec!["axes"]);
    file["$schema"] = json!("https://json-schema.org/draft/2020-12/schema");
    file["title"] = json!("tdm-stepper sim moves file");
    file["properties"]["clock_hz"]["minimum"] = json!(1_000_000);
    file["properties"]["clock_hz"]["maximum"] = json!(400_000_000);
    file["properties"]["axes"]["minItems"] = json!(1);
    file["properties"]["axes"]["items"] = json!({
        "oneOf": [
            {"type": "object", "additionalProperties": false, "required": ["segments"],
             "properties": {"segments": {"type": "array", "items": segment, "description": MOVES_FIELDS[2].3}}},
            {"type": "object", "additionalProperties": false, "required": ["trapezoid"],
             "properties": {"trapezoid": trapezoid}},
            {"type": "object", "additionalProperties": false, "required": ["move"],
             "properties": {"move": rate_move}},
            {"type": "object", "additionalProperties": false, "required": ["jerk"],
             "properties": {"jerk": jerk}},
            {"type": "object", "additionalProperties": false, "required": ["fourth"],
             "properties": {"fourth": fourth}}
        ]
    });
    serde_json::to_string_pretty(&file).expect("json") + "\n"
}

/// Plans every axis of a moves file into segments that a core with `limits` accepts
/// (polynomial segments for the S-curve moves).
pub fn plan(moves: &MovesFile, limits: &Limits) -> Result<Vec<Vec<Motion>>, String> {
    let tr = |r: Result<Vec<Segment>, String>| r.map(|v| v.into_iter().map(Motion::from).collect::<Vec<_>>());
    let f = moves.clock_hz;
    units::check_clock(f as u64).map_err(|e| format!("clock_hz: {e}"))?;
    moves
        .axes
        .iter()
        .enumerate()
        .map(|(a, m)| match m {
            AxisMove::Trapezoid { trapezoid: t } => tr(planner::trapezoid_by_times(t.steps, t.t_acc_s, t.t_cruise_s, t.t_dec_s, f, limits)
                .map_err(|e| format!("axis {a}: trapezoid: {e}"))),
            AxisMove::Jerk { jerk: j } => scurve::jerk_limited(
                j.steps,
                j.v_start_steps_per_s,
                j.v_end_steps_per_s,
                j.speed_steps_per_s,
                j.accel_steps_per_s2,
                j.jerk_steps_per_s3,
                j.decel_steps_per_s2,
                j.decel_jerk_steps_per_s3,
                f,
                limits,
            )
            .map_err(|e| format!("axis {a}: jerk: {e}")),
            AxisMove::Fourth { fourth: q } => {
                scurve::fourth_order(q.steps, q.speed_steps_per_s, q.accel_steps_per_s2, q.jerk_steps_per_s3, q.snap_steps_per_s4, f, limits)
                    .map_err(|e| format!("axis {a}: fourth: {e}"))
            }
            AxisMove::Move { mv } => tr(planner::trapezoid_by_rates(
                mv.steps,
                mv.speed_steps_per_s,
                mv.accel_steps_per_s2,
                mv.decel_steps_per_s2,
                f,
                limits,
            )
            .map_err(|e| format!("axis {a}: move: {e}"))),
            AxisMove::Segments { segments } => tr(segments
                .iter()
                .enumerate()
                .map(|(k, s)| {
                    let steps = i32::try_from(s.steps).map_err(|_| format!("axis {a} segment {k}: steps {} out of range", s.steps))?;
                    Ok(Segment::new(
                        units::steps_per_s_to_rate(s.v0_steps_per_s, f).map_err(|e| format!("axis {a} segment {k}: {e}"))?,
                        units::seconds_to_ticks(s.t_s, f).map_err(|e| format!("axis {a} segment {k}: {e}"))?,
                        steps,
                    ))
                })
                .collect()),
        })
        .collect()
}

/// Per-axis results.
#[derive(Clone, Debug, Serialize)]
pub struct AxisReport {
    pub axis: usize,
    /// The planned segments, each tagged with its kind (`trapezoid` or `poly`).
    pub segments: Vec<Motion>,
    /// (index, error code) of segments the core rejected, as the model predicts.
    pub rejected: Vec<(usize, u8)>,
    pub steps: usize,
    /// Position read back through the bus (POS_LO, POS_HI) after the move.
    pub final_position: Option<i32>,
    pub expected_position: i64,
    /// clk cycle of every STEP rising edge.
    pub edge_cycles: Vec<u64>,
    /// Cumulative from the release: edge − (release + 1) against exact kinematics (the
    /// measure docs/model.md bounds by 0.625 ticks; not its offset-free edge_i − edge_1).
    pub max_edge_error_ticks: f64,
    pub max_period_error_pct: f64,
    /// Over steps whose exact period is at least 500 ticks.
    pub max_period_error_pct_ge_500_ticks: f64,
    /// STATUS read after the move.
    pub status: Option<u16>,
    pub underrun: bool,
    /// First edge − 1 − the model's first edge tick.
    pub release_cycle: Option<i64>,
    /// What did not go as planned, one sentence each (empty: the move ran as planned,
    /// every edge where the model puts it).
    pub problems: Vec<String>,
}

/// The whole report.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    pub engine: Engine,
    pub axes_in_core: usize,
    /// The core was exported with `--profiles trapezoid,scurve` (the file has an S-curve move).
    pub scurve: bool,
    pub clock_hz: u32,
    pub clk_cycles: u64,
    pub simulated_seconds: f64,
    /// Largest difference between the axes' release cycles.
    pub skew_ticks: Option<i64>,
    pub axes: Vec<AxisReport>,
    pub wall_seconds_build_and_run: f64,
    /// The run's limit: clk cycles from START after which the positions are read. It
    /// covers the planned move, and, when the plan asks for periods or segments near
    /// what the shared unit serves, the time an underrunning move could take.
    pub run_limit_ticks: u64,
    /// No axis has a problem.
    pub ok: bool,
}

/// Clk cycles from START within which every axis of the plan will have finished,
/// even if it underruns. The planned end, plus margin; when some period is shorter
/// than 2·K·t_calc or some segment shorter than 2·K·t_setup (so that an underrun is
/// possible), every step and every setup is allowed the shared unit's whole round.
/// With the S-curve option (`scurve`) t_calc is `POLY_T_CALC` and the longest setup
/// the polynomial one.
pub fn run_limit_ticks(runs: &[AxisRun], k: usize, scurve: bool) -> u64 {
    let o = export::ExportOptions { axes: k, scurve, ..Default::default() };
    let (t_calc, t_setup) = (o.t_calc_cycles() as u64, o.longest_setup_cycles() as u64);
    let k = k as u64;
    let tight = runs.iter().any(|r| {
        r.edge_ticks.windows(2).any(|w| w[1] - w[0] < 2 * k * t_calc)
            || r.motions.iter().any(|s| (s.t_ticks() as u64) < 2 * k * t_setup)
    });
    let planned = runs.iter().map(|r| r.end_tick).max().unwrap_or(0);
    let worst = if tight {
        runs.iter()
            .map(|r| r.end_tick + r.edge_ticks.len() as u64 * k * t_calc + r.motions.len() as u64 * k * t_setup)
            .max()
            .unwrap_or(0)
    } else {
        planned
    };
    worst + 2_000 + 20 * k * RADIX_BITS as u64
}

/// The problems of one axis: rejections, a start that did not complete, an underrun,
/// a refused push, a move that did not finish, an edge away from the model.
fn axis_problems(run: &AxisRun, all: &[AxisRun], rises: &[u64], status: Option<u16>, position: Option<i32>) -> Vec<String> {
    let mut p = Vec::new();
    for r in &run.rejected {
        p.push(format!("segment {} rejected, {}", r.index, r.error));
    }
    let Some(st) = status else {
        p.push("STATUS could not be read (undefined bits)".to_string());
        return p;
    };
    let code = (st >> 12) as u8;
    if st & STATUS_ERROR != 0 && !run.rejected.iter().any(|r| r.error.code() == code) {
        p.push(format!("STATUS.ERROR with code {code}, which the model does not predict"));
    }
    if st & STATUS_OVERFLOW != 0 {
        p.push("a push was refused (STATUS.OVERFLOW: the queue was full)".to_string());
    }
    let underrun = st & STATUS_UNDERRUN != 0;
    if underrun {
        p.push("underrun: the shared unit did not keep up, so some STEP edges are late (periods below K·t_calc, or segments shorter than their setup)".to_string());
    }
    let expected = run.edge_ticks.len();
    if rises.is_empty() && expected > 0 {
        let blockers: Vec<String> = all
            .iter()
            .enumerate()
            .filter(|(_, r)| r.accepted.is_empty())
            .map(|(j, _)| j.to_string())
            .collect();
        if blockers.is_empty() {
            p.push(format!("did not start: no STEP edge of the {expected} planned"));
        } else {
            p.push(format!(
                "did not start: axis {} has no valid segment, so the core cancelled the START (GSTATUS.START_FAILED)",
                blockers.join(", ")
            ));
        }
    } else if rises.len() != expected {
        p.push(format!("did not finish: {} of {expected} steps by the end of the run", rises.len()));
    }
    if let Some(pos) = position {
        if pos as i64 != run.position && !rises.is_empty() {
            p.push(format!("position {pos} at the end, the plan says {}", run.position));
        }
    } else {
        p.push("the position could not be read (undefined bits)".to_string());
    }
    if !underrun && rises.len() == expected && expected > 0 {
        let l0 = rises[0] as i64 - 1 - run.edge_ticks[0] as i64;
        if let Some(i) = (0..expected).find(|&i| rises[i] as i64 != l0 + 1 + run.edge_ticks[i] as i64) {
            p.push(format!(
                "step {i} rose at clk cycle {}, {} ticks from where the model puts it",
                rises[i],
                rises[i] as i64 - (l0 + 1 + run.edge_ticks[i] as i64)
            ));
        }
    }
    p
}

fn clocks_for(clock_hz: u32) -> Clocks {
    let half = (1e12 / (2.0 * clock_hz as f64) / 3.0).round().max(1.0) as u64 * 3;
    Clocks { clk_half_ps: half, bus_half_ps: 5_001 }
}

const MCU_HALF_PS: u64 = 2_976;

/// Runs a simulation and writes the report and the SVG (and the VCD).
pub fn run(opts: &SimOptions) -> Result<(Report, Vec<PathBuf>), String> {
    let text = std::fs::read_to_string(&opts.moves).map_err(|e| format!("cannot read {}: {e}", opts.moves.display()))?;
    let moves: MovesFile = parse_moves(&text).map_err(|e| format!("{}: {e}", opts.moves.display()))?;
    let k = opts.axes;
    let scurve = moves.axes.iter().any(AxisMove::is_scurve);
    let exp = ExportOptions { axes: k, clock_hz: moves.clock_hz, min_period: opts.min_period, scurve, ..Default::default() };
    exp.check()?;
    // The model enforces the exported core's minimum period, as the core does.
    let limits = exp.limits();
    let axes = plan(&moves, &limits)?;
    if axes.is_empty() || axes.len() > k {
        return Err(format!("{} lists {} axes; the core has --axes {k}", opts.moves.display(), axes.len()));
    }
    let capacity = QUEUE_DEPTH + 2;
    for (a, segs) in axes.iter().enumerate() {
        if segs.len() > capacity {
            return Err(format!(
                "axis {a}: {} segments; sim writes every segment before the start, and an axis holds {capacity} (queue {QUEUE_DEPTH} + 2 slots)",
                segs.len()
            ));
        }
    }
    let runs: Vec<AxisRun> = axes.iter().map(|s| AxisRun::run_motions(s, &limits)).collect();
    let clocks = clocks_for(moves.clock_hz);
    let tick_ps = 2 * clocks.clk_half_ps;

    // The bus sequence.
    let mut b = BusModel::new(BusTiming::minimum(clocks.bus_half_ps, MCU_HALF_PS));
    b.reset(40);
    // ENABLE, then time for it to reach the core and come back as ENABLED.
    b.enable(b.cycles_for_ps((400 + 40 * k as u64) * tick_ps.max(2 * clocks.bus_half_ps)));
    let enabled = b.read_reg("GSTATUS", 0);
    // Pushes are paced so that the 4-deep command FIFO never fills, however slow
    // clk is against the bus (it drains one command per clk cycle after a crossing
    // of about 3 cycles).
    let pace = b.cycles_for_ps(8 * tick_ps);
    for (a, segs) in axes.iter().enumerate() {
        for s in segs {
            b.push_motion(a, s);
            b.idle(pace);
        }
    }
    b.idle(100);
    b.write_reg("START", 0, ((1u32 << axes.len()) - 1) as u16);
    let start_ps = b.now_ps();
    let limit = run_limit_ticks(&runs, k, scurve);
    b.idle_until_ps(start_ps + limit * tick_ps);
    let reads: Vec<((ReadId, ReadId), ReadId)> = (0..axes.len()).map(|a| (b.read_position(a), b.read_reg("STATUS", a))).collect();
    let cycles = b.now_ps() / tick_ps + 100;

    let t0 = std::time::Instant::now();
    let watch = stepper_watch(k);
    let trace = match opts.engine {
        Engine::Verilator => {
            let verilog = export::verilog(&exp)?;
            // The probes are always built in (an empty window when no VCD is asked
            // for), so runs with and without a VCD share one Verilator build.
            let vcd = {
                let (w0, w1) = if opts.vcd.is_some() { opts.vcd_window.unwrap_or((0.0, f64::MAX / 4e12)) } else { (0.0, 0.0) };
                // Probe names (documented in the README).
                let mut probes = Vec::new();
                for a in 0..k {
                    probes.push((format!("step_{a}"), 1, format!("dut.step[{a}]")));
                    probes.push((format!("dir_{a}"), 1, format!("dut.dir[{a}]")));
                    probes.push((format!("position_{a}"), 32, format!("dut.core.bank.axes${a}$position")));
                }
                probes.push(("fsm_state".to_string(), crate::hdl::core::STATE_BITS, "dut.fsm_state".to_string()));
                for a in 0..k {
                    probes.push((format!("fifo_level_{a}"), 8, format!("dut.core.bank.axes${a}$level")));
                    // The queue's level is its pushed counter less its taken counter.
                    probes.push((format!("queue_level_{a}"), 8, format!("dut.core.queues.wr${a}$q - dut.core.queues.rd${a}$q")));
                }
                probes.push(("irq".to_string(), 1, "dut.irq".to_string()));
                let to_cycle = |s: f64| ((s * 1e12 / tick_ps as f64) as u64).min(cycles);
                VcdOptions { path: opts.vcd.clone().unwrap_or_default(), window_cycles: (to_cycle(w0), to_cycle(w1)), probes }
            };
            let ropts = RunOptions { vcd: Some(vcd), progress: opts.progress, pause_idle_bus_ps: Some(1_000_000_000), build_cache: None };
            let spec = system_spec(export::TOP_MODULE, watch);
            let work = std::path::absolute(&opts.work).map_err(|e| format!("{}: {e}", opts.work.display()))?;
            let trace = run_system_with(&work, &verilog, &spec, &clocks, b.events(), cycles, &ropts)?;
            if let (Some(v), true) = (&ropts.vcd, opts.vcd.is_some()) {
                if let Some(dir) = v.path.parent().filter(|p| !p.as_os_str().is_empty()) {
                    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
                }
                write_vcd(&v.path, v, &trace, moves.clock_hz)?;
                let name = v.path.file_name().and_then(|n| n.to_str()).unwrap_or("sim.vcd");
                let gtkw = v.path.with_extension("gtkw");
                std::fs::write(&gtkw, gtkw_text(name, v)).map_err(|e| format!("cannot write {}: {e}", gtkw.display()))?;
            }
            trace
        }
        Engine::RustHdl => {
            if opts.vcd.is_some() {
                return Err("--vcd needs --engine verilator".into());
            }
            crate::verify::bus::run_tdm_rust_hdl(exp.params(), &clocks, b.events(), cycles, opts.progress)?
        }
    };
    let wall = t0.elapsed().as_secs_f64();
    if b.value(&trace, enabled).is_none_or(|g| g & 1 == 0) {
        return Err("the core did not report GSTATUS.ENABLED before the first push (no command would be accepted)".into());
    }

    let mut reports = Vec::new();
    for (a, run) in runs.iter().enumerate() {
        let rises = rises(&trace, a);
        let release = rises.first().zip(run.edge_ticks.first()).map(|(&r, &e)| r as i64 - 1 - e as i64);
        let (mut max_e, mut max_p, mut max_p500) = (0f64, 0f64, 0f64);
        if let Some(l0) = release {
            for (i, &r) in rises.iter().enumerate().take(run.exact_ticks.len()) {
                let t = (r as i64 - l0 - 1) as f64;
                max_e = max_e.max((t - run.exact_ticks[i]).abs());
                if i > 0 {
                    let p = (r - rises[i - 1]) as f64;
                    let x = run.exact_ticks[i] - run.exact_ticks[i - 1];
                    let pct = ((p - x) / x * 100.0).abs();
                    max_p = max_p.max(pct);
                    if x >= 500.0 {
                        max_p500 = max_p500.max(pct);
                    }
                }
            }
        }
        let status = b.value(&trace, reads[a].1);
        let final_position = position(&b, &trace, reads[a].0);
        let problems = axis_problems(run, &runs, &rises, status, final_position);
        reports.push(AxisReport {
            axis: a,
            segments: axes[a].clone(),
            rejected: run.rejected.iter().map(|r| (r.index, r.error.code())).collect(),
            steps: rises.len(),
            final_position,
            expected_position: run.position,
            edge_cycles: rises,
            max_edge_error_ticks: max_e,
            max_period_error_pct: max_p,
            max_period_error_pct_ge_500_ticks: max_p500,
            status,
            underrun: status.is_some_and(|s| s & STATUS_UNDERRUN != 0),
            release_cycle: release,
            problems,
        });
    }
    let releases: Vec<i64> = reports.iter().filter_map(|r| r.release_cycle).collect();
    let skew = (!releases.is_empty()).then(|| releases.iter().max().unwrap() - releases.iter().min().unwrap());
    let report = Report {
        engine: opts.engine,
        axes_in_core: k,
        scurve,
        clock_hz: moves.clock_hz,
        clk_cycles: cycles,
        simulated_seconds: cycles as f64 / moves.clock_hz as f64,
        skew_ticks: skew,
        ok: reports.iter().all(|r| r.problems.is_empty()),
        axes: reports,
        wall_seconds_build_and_run: wall,
        run_limit_ticks: limit,
    };
    let mut written = Vec::new();
    if let Some(dir) = opts.report.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    }
    std::fs::write(&opts.report, serde_json::to_string_pretty(&report).expect("json") + "\n")
        .map_err(|e| format!("cannot write {}: {e}", opts.report.display()))?;
    written.push(opts.report.clone());
    let svg = opts.report.with_extension("svg");
    write_svg(&report, &runs, &svg).map_err(|e| format!("cannot write {}: {e}", svg.display()))?;
    written.push(svg);
    if let Some(v) = &opts.vcd {
        written.push(v.clone());
        written.push(v.with_extension("gtkw"));
    }
    Ok((report, written))
}

fn rises(trace: &SystemTrace, a: usize) -> Vec<u64> {
    let mut out = Vec::new();
    let mut prev = 0;
    for (c, v) in &trace.changes {
        let s = (v[0].unwrap_or(0) >> a) & 1;
        if s == 1 && prev == 0 {
            out.push(*c);
        }
        prev = s;
    }
    out
}

/// The exact acceleration of `motions` (of the speed's magnitude, steps/s²) against
/// time (s), 200 samples per segment: a trapezoid segment's is constant,
/// 2(n − v0·T)/T²; a polynomial segment's follows its polynomial.
pub fn planned_acceleration(motions: &[Motion], f: f64) -> Vec<(f64, f64)> {
    let q32 = 2f64.powi(32);
    let mut out = Vec::new();
    let mut t0 = 0f64;
    for m in motions {
        let t = m.t_ticks() as f64;
        for k in 0..=200 {
            let tau = t * k as f64 / 200.0;
            let a = match m {
                Motion::Trapezoid(s) => 2.0 * (s.n_steps() as f64 - s.v0_rate as f64 / q32 * t) / (t * t),
                Motion::Poly(p) => p.derivatives_at(tau).1,
            };
            out.push(((t0 + tau) / f, a * f * f));
        }
        t0 += t;
    }
    out
}

fn write_svg(r: &Report, runs: &[AxisRun], path: &Path) -> Result<(), Box<dyn std::error::Error>> {
    let f = r.clock_hz as f64;
    let rows = r.axes.len();
    // With S-curve moves each axis gets a third plot: the planned acceleration.
    let row_h = if r.scurve { 640 } else { 420 };
    let root = SVGBackend::new(path, (1100, row_h * rows as u32)).into_drawing_area();
    root.fill(&WHITE)?;
    for (ax, area) in r.axes.iter().zip(root.split_evenly((rows, 1))) {
        let run = &runs[ax.axis];
        let (top, rest) = area.split_vertically(260);
        let (accel_area, bottom) = if r.scurve { let (m, b) = rest.split_vertically(220); (Some(m), b) } else { (None, rest) };
        // What went wrong, in words, over the plots (or instead of them).
        let Some(l0) = ax.release_cycle else {
            area.draw(&Text::new(format!("axis {}: no STEP edge", ax.axis), (20, 30), ("sans-serif", 20).into_font().color(&RED)))?;
            for (i, p) in ax.problems.iter().enumerate() {
                area.draw(&Text::new(p.clone(), (20, 60 + 22 * i as i32), ("sans-serif", 15).into_font().color(&RED)))?;
            }
            continue;
        };
        let x = &run.exact_ticks;
        let e: Vec<f64> = ax.edge_cycles.iter().map(|&c| (c as i64 - l0 - 1) as f64).collect();
        let n = x.len().min(e.len());
        let planned: Vec<(f64, f64)> = (1..n).map(|i| (x[i] / f, f / (x[i] - x[i - 1]))).collect();
        let emitted: Vec<(f64, f64)> = (1..n).map(|i| (e[i] / f, f / (e[i] - e[i - 1]))).collect();
        let err: Vec<(f64, f64)> = (0..n).map(|i| (e[i] / f, e[i] - x[i])).collect();
        let t_end = x.last().copied().unwrap_or(1.0) / f;
        let v_max = planned.iter().chain(&emitted).map(|p| p.1).fold(1.0, f64::max) * 1.05;
        let mut c = ChartBuilder::on(&top)
            .caption(format!("axis {}: speed (steps/s), planned and emitted", ax.axis), ("sans-serif", 16))
            .margin(8)
            .x_label_area_size(28)
            .y_label_area_size(70)
            .build_cartesian_2d(0f64..t_end, 0f64..v_max)?;
        c.configure_mesh().x_desc("time (s)").y_desc("steps/s").draw()?;
        c.draw_series(LineSeries::new(planned, BLACK))?.label("planned (exact)").legend(|(x, y)| PathElement::new([(x, y), (x + 16, y)], BLACK));
        c.draw_series(emitted.iter().map(|&p| Circle::new(p, 1, BLUE.filled())))?
            .label("emitted (1/period)")
            .legend(|(x, y)| Circle::new((x + 8, y), 2, BLUE.filled()));
        c.configure_series_labels().background_style(WHITE.mix(0.8)).border_style(BLACK).draw()?;
        let lim = err.iter().map(|p| p.1.abs()).fold(1.0, f64::max) * 1.1;
        let mut c2 = ChartBuilder::on(&bottom)
            .caption(format!("axis {}: edge error against exact time (ticks, cumulative)", ax.axis), ("sans-serif", 16))
            .margin(8)
            .x_label_area_size(28)
            .y_label_area_size(70)
            .build_cartesian_2d(0f64..t_end, -lim..lim)?;
        c2.configure_mesh().x_desc("time (s)").y_desc("ticks").draw()?;
        c2.draw_series(err.iter().map(|&p| Circle::new(p, 1, RED.filled())))?;
        if let Some(m) = accel_area {
            let acc = planned_acceleration(&run.motions, f);
            let lim = acc.iter().map(|p| p.1.abs()).fold(1.0, f64::max) * 1.1;
            let mut c3 = ChartBuilder::on(&m)
                .caption(format!("axis {}: acceleration (steps/s²), planned (exact, of the segments' kinematics)", ax.axis), ("sans-serif", 16))
                .margin(8)
                .x_label_area_size(28)
                .y_label_area_size(70)
                .build_cartesian_2d(0f64..t_end, -lim..lim)?;
            c3.configure_mesh().x_desc("time (s)").y_desc("steps/s²").draw()?;
            c3.draw_series(LineSeries::new(acc, GREEN.stroke_width(2)))?;
        }
        for (i, p) in ax.problems.iter().enumerate() {
            top.draw(&Text::new(format!("PROBLEM: {p}"), (80, 36 + 18 * i as i32), ("sans-serif", 14).into_font().color(&RED)))?;
        }
    }
    root.present()?;
    Ok(())
}
