//! PushCheck and PolyCheck (in `mod poly` below) three ways. PushCheck: the model
//! (`Segment::validate` and `Segment::effective`), rust-hdl, and the exported Verilog in Verilator and Icarus. Pushes at every range
//! boundary (T = 0, 2^30, |θ| = 2^24, v0 = 2^31 − 1, v0 = RMAX, end rate = RMAX, a
//! deceleration that rounds past rest and one rate unit beyond), random segments, and
//! START and ABORT between them, for three minimum periods, offered 4 to 7 cycles
//! apart: each comes out PUSH_CHECK_LATENCY cycles later, a valid push in its effective
//! form, a bad one as a rejection with the model's code and its axis; `busy` covers
//! the cycles in between. A reset drops the command in flight.
//! A further check's code (`ext_code`, the push guard's) in a push's cycle 3 rejects a
//! push the segment's own checks pass, with that code; their own code wins otherwise.

mod common;

use common::*;
use rust_hdl::prelude::*;
use tdm_stepper::hdl::push_check::{PushCheck, POLY_PUSH_LATENCY, PUSH_CHECK_LATENCY};
use tdm_stepper::hdl::regfile::CMD_BITS;
use tdm_stepper::model::{Limits, Segment, MAX_STEPS, MAX_T_TICKS, MAX_V0_RATE};
use tdm_stepper::verify::{Port, TbSpec};

fn push(seg: &Segment, axis: u32) -> u128 {
    seg.v0_rate as u128 | (seg.t_ticks as u128) << 32 | (seg.steps as u32 as u128) << 64 | (axis as u128) << 96
}

fn spec() -> TbSpec {
    TbSpec {
        clock: "clock".into(),
        inputs: vec![
            Port::new("reset", 1),
            Port::new("in_valid", 1),
            Port::new("in_data", CMD_BITS),
            Port::new("in_v0", 32),
            Port::new("ext_code", 4),
        ],
        outputs: vec![
            Port::new("busy", 1),
            Port::new("out_valid", 1),
            Port::new("out_data", CMD_BITS),
            Port::new("rej_valid", 1),
            Port::new("rej_axis", 4),
            Port::new("rej_code", 4),
        ],
    }
}

/// The boundary cases for one RMAX, then random ones.
fn segments(limits: &Limits, rng: &mut Rng) -> Vec<Segment> {
    let rmax = limits.max_rate() as u64;
    let two33 = 1u128 << 33;
    let mut v = vec![
        Segment::new(0, 0, 5),
        Segment::new(0, 0, 0),
        Segment::new(0, MAX_T_TICKS, 0),
        Segment::new(0, MAX_T_TICKS + 1, 0),
        Segment::new(0, u32::MAX, 0),
        Segment::new(0, MAX_T_TICKS, MAX_STEPS as i32),
        Segment::new(0, MAX_T_TICKS, -(MAX_STEPS as i32)),
        Segment::new(0, MAX_T_TICKS, MAX_STEPS as i32 + 1),
        Segment::new(0, MAX_T_TICKS, -(MAX_STEPS as i32) - 1),
        Segment::new(0, 1000, i32::MIN),
        Segment::new(MAX_V0_RATE, 1000, 10),
        Segment::new(MAX_V0_RATE + 1, 1000, 10),
        Segment::new(u32::MAX, u32::MAX, i32::MIN),
        Segment::new(rmax as u32, 1000, 0),
        Segment::new(1, 1000, 0),
        Segment::new(0, 1, 0),
        Segment::dwell(7),
        // The documented decelerate-to-rest pair at 50 MHz (v0 rounded up), and one more.
        Segment::new(10_307_922, 1_000_000, -1200),
        Segment::new(10_307_923, 1_000_000, 1200),
    ];
    // v0 at RMAX, RMAX + 1 and RMAX + 2 with a cruise (end rate = v0), and rounding
    // past rest from v0 = RMAX + 1 and RMAX + 2.
    for dv in 0..3u64 {
        let v0 = rmax + dv;
        let t = 4000u64;
        v.push(Segment::new(v0 as u32, t as u32, ((v0 as u128 * t as u128) >> 32) as i32));
        let exact = v0 as u128 * t as u128; // 2n·2^32 just under v0·T: rounds past rest
        let n = (exact / two33) as i32;
        v.push(Segment::new(v0 as u32, t as u32, n));
    }
    // End rate around RMAX: 2n·2^32 against T·(v0 + RMAX).
    for _ in 0..6 {
        let t = 1 + rng.next() % 100_000;
        let v0 = rng.next() % (rmax + 1);
        let n = ((t as u128 * (v0 + rmax) as u128) / two33) as i64;
        for d in [-1i64, 0, 1] {
            let n = (n + d).clamp(0, MAX_STEPS as i64);
            v.push(Segment::new(v0 as u32, t as u32, n as i32));
        }
    }
    // Random: any kind, valid or not, weighted towards the interesting region.
    while v.len() < 120 {
        let t = match rng.next() % 5 {
            0 => rng.next() as u32,
            _ => (((rng.next() % 31) as f64).exp2() as u64 + rng.next() % 1024).min(u32::MAX as u64) as u32,
        };
        let n_max = ((t as u128 * rmax as u128) >> 32).min(MAX_STEPS as u128 + 4) as u64;
        let n = if n_max == 0 { rng.next() % 3 } else { rng.next() % (n_max + 2) };
        let uniform = ((n as u128) << 32) / t.max(1) as u128;
        let v0 = match rng.next() % 5 {
            0 => 0u64,
            1 => uniform as u64,
            2 => (2 * uniform as u64).saturating_add(rng.next() % 5).saturating_sub(2),
            3 => rng.next() >> 32,
            _ => rng.next() % (2 * uniform as u64 + 2),
        };
        let steps = if rng.next() % 2 == 0 { n as i32 } else { (n as i32).wrapping_neg() };
        v.push(Segment::new(v0.min(u32::MAX as u64) as u32, t, steps));
    }
    v
}

#[test]
fn verdicts_equal_the_model_three_ways() {
    let mut rng = Rng(0x0bad_5e9_c0de);
    for min_period in [2u32, 24, 66] {
        let limits = Limits::new(min_period).unwrap();
        let segs = segments(&limits, &mut rng);
        let mut rows: Vec<Vec<u128>> = vec![vec![1, 0, 0], vec![0, 0, 0]];
        let mut want: Vec<Vec<Option<u128>>> = vec![vec![None; 6]; 2];
        // Rows at which a command is offered and what comes out L cycles later.
        let mut plan: Vec<(usize, Vec<Option<u128>>)> = Vec::new();
        let (mut codes, mut near) = (std::collections::BTreeSet::new(), 0);
        // The push guard's code in each push's cycle 3 (else noise, never read).
        let mut ext_at: Vec<(usize, u128)> = Vec::new();
        let mut ext_seen = 0;
        let mut k = 0;
        while k < segs.len() {
            let r = rows.len();
            let axis = (rng.next() % 16) as u32;
            let (data, out) = match rng.next() % 12 {
                0 => {
                    let mask = rng.next() as u128 & 0xffff;
                    let cmd = mask | 1 << 104;
                    (cmd, vec![Some(1), Some(cmd), Some(0), None, None])
                }
                1 => {
                    let cmd = 2u128 << 104;
                    (cmd, vec![Some(1), Some(cmd), Some(0), None, None])
                }
                _ => {
                    let seg = segs[k];
                    k += 1;
                    let mut ext = [0u128, 0, 0, 7, 8, 9][(rng.next() % 6) as usize];
                    if seg.rounds_past_rest() && near < 2 {
                        ext = 0; // the first two go through (the count below)
                    }
                    ext_at.push((r + 3, ext));
                    match seg.validate(&limits) {
                        Ok(()) if ext != 0 => {
                            ext_seen += 1;
                            (push(&seg, axis), vec![Some(0), None, Some(1), Some(axis as u128), Some(ext)])
                        }
                        Ok(()) => {
                            near += seg.rounds_past_rest() as usize;
                            codes.insert(0);
                            (push(&seg, axis), vec![Some(1), Some(push(&seg.effective(), axis)), Some(0), None, None])
                        }
                        Err(e) => {
                            codes.insert(e.code());
                            (push(&seg, axis), vec![Some(0), None, Some(1), Some(axis as u128), Some(e.code() as u128)])
                        }
                    }
                }
            };
            rows.push(vec![0, 1, data]);
            plan.push((r, out));
            // 4 to 7 cycles to the next command (4: offered as the verdict comes out).
            let gap = 4 + (rng.next() % 4) as usize;
            for _ in 1..gap {
                rows.push(vec![0, 0, rng.next_u128() & ((1 << CMD_BITS) - 1)]);
            }
        }
        // A command cut by a reset in flight, then quiet.
        rows.push(vec![0, 1, push(&Segment::new(0, 0, 1), 3)]);
        rows.push(vec![0, 0, 0]);
        rows.push(vec![1, 0, 0]);
        for _ in 0..8 {
            rows.push(vec![0, 0, 0]);
        }
        // in_v0: the command's low 32 bits, as the register file offers a push's v0
        // (for START and ABORT it is not read).
        for r in rows.iter_mut() {
            let v0 = r[2] & 0xFFFF_FFFF;
            r.push(v0);
            r.push((rng.next() % 16) as u128);
        }
        for (r, ext) in &ext_at {
            rows[*r][4] = *ext;
        }
        assert!(ext_seen >= 10, "only {ext_seen} valid pushes the guard rejects");
        want.resize(rows.len(), vec![None; 6]);
        for w in want.iter_mut().skip(2) {
            *w = vec![Some(0), Some(0), None, Some(0), None, None];
        }
        for (r, out) in &plan {
            for b in 1..PUSH_CHECK_LATENCY {
                want[r + b][0] = Some(1);
            }
            let w = &mut want[r + PUSH_CHECK_LATENCY];
            w[1] = out[0];
            w[2] = out[1];
            w[3] = out[2];
            w[4] = out[3];
            w[5] = out[4];
        }
        // The cut command: busy until the reset takes effect, then nothing comes out.
        let cut = rows.len() - 11;
        want[cut + 1][0] = Some(1);
        want[cut + 2][0] = Some(1);
        assert!(codes.len() == 7, "min period {min_period}: codes seen {codes:?}");
        assert!(near >= 2, "min period {min_period}: only {near} decelerations rounding past rest");
        let name = format!("push_check_{min_period}");
        three_ways(
            &name,
            || {
                let mut u = PushCheck::<0>::new(limits);
                u.clock.connect();
                u.reset.connect();
                u.in_valid.connect();
                u.in_data.connect();
                u.in_v0.connect();
                u.ext_code.connect();
                u.connect_all();
                u
            },
            |u, c| u.clock.next = Clock::from(c),
            |u, r| {
                u.reset.next = r[0] == 1;
                u.in_valid.next = r[1] == 1;
                u.in_data.next = Bits::<CMD_BITS>::from(num_bigint::BigUint::from(r[2]));
                u.in_v0.next = Bits::<32>::from(r[3] as u64);
                u.ext_code.next = Bits::<4>::from(r[4] as u64);
            },
            |u| {
                vec![
                    u.busy.val() as u128,
                    u.out_valid.val() as u128,
                    bits_to_u128(u.out_data.val()),
                    u.rej_valid.val() as u128,
                    u.rej_axis.val().to_u64() as u128,
                    u.rej_code.val().to_u64() as u128,
                ]
            },
            &spec(),
            &rows,
            &want,
        );
    }
}

/// The S-curve option's push check (S = 1), three ways: trapezoid pushes, START and
/// ABORT as above, and polynomial pushes (kind 3, v1 and A' on `in_extra`) mixed
/// among them. A polynomial push comes out POLY_PUSH_LATENCY cycles later, unchanged
/// when valid, else as a rejection with the model's code (`PolySegment::validate`),
/// or the further check's code from its cycle 3 when the segment's own checks pass;
/// a command offered 4 cycles after it (as soon as `busy` falls) comes out after it;
/// `poly_busy` covers its cycles 1 to 5, and `out_extra` gives a valid one's v1 and A'
/// with its verdict.
#[test]
fn polynomial_pushes_three_ways() {
    use tdm_stepper::model::poly::PolySegment;
    let mut rng = Rng(0x5c0e_7e57_1234);
    let limits = Limits::new(24).unwrap();
    let trap = segments(&limits, &mut rng);
    let polys: Vec<PolySegment> = poly::segments(&limits, &mut rng);
    let poly_cmd = |p: &PolySegment, axis: u32| {
        p.v0_rate as u128 | (p.t_ticks as u128) << 32 | (p.steps as u32 as u128) << 64 | (axis as u128) << 96 | 3 << 104
    };
    let extra = tdm_stepper::hdl::poly_lane::poly_fields;
    // Rows: reset, in_valid, in_data, in_v0, ext_code, in_extra.
    let mut rows: Vec<Vec<u128>> = vec![vec![1, 0, 0, 0, 0, 0], vec![0, 0, 0, 0, 0, 0]];
    // (row, latency, what comes out: out_valid, out_data, rej_valid, rej_axis, rej_code)
    let mut plan: Vec<(usize, usize, Vec<Option<u128>>)> = Vec::new();
    let mut ext_at: Vec<(usize, u128)> = Vec::new();
    let mut poly_rows: Vec<usize> = Vec::new();
    // A valid polynomial push's fields on `out_extra` with its verdict.
    let mut extra_out: Vec<(usize, u128)> = Vec::new();
    let (mut ti, mut pi) = (0, 0);
    let mut last_poly: Option<usize> = None;
    let (mut codes, mut ext_wins, mut back_to_back) = (std::collections::BTreeSet::new(), 0, 0);
    while pi < polys.len() {
        let r = rows.len();
        let axis = (rng.next() % 16) as u32;
        let ext = [0u128, 0, 0, 0, 7, 9][(rng.next() % 6) as usize];
        // A polynomial push only once the last one's check is free.
        let poly_ok = last_poly.map_or(true, |l| r >= l + POLY_PUSH_LATENCY);
        let choice = rng.next() % 4;
        if choice < 2 && poly_ok {
            let p = polys[pi];
            pi += 1;
            let cmd = poly_cmd(&p, axis);
            ext_at.push((r + 3, ext));
            let code = match p.validate(&limits) {
                Err(e) => e.code() as u128,
                Ok(()) => ext,
            };
            ext_wins += (p.validate(&limits).is_ok() && ext != 0) as usize;
            codes.insert(code);
            let out = if code == 0 { vec![Some(1), Some(cmd), Some(0), None, None] } else { vec![Some(0), None, Some(1), Some(axis as u128), Some(code)] };
            if code == 0 {
                extra_out.push((r + POLY_PUSH_LATENCY, extra(&p)));
            }
            rows.push(vec![0, 1, cmd, p.v0_rate as u128, 0, extra(&p)]);
            plan.push((r, POLY_PUSH_LATENCY, out));
            poly_rows.push(r);
            last_poly = Some(r);
        } else if choice == 2 {
            let cmd = (rng.next() as u128 & 0xffff) | 1 << 104;
            rows.push(vec![0, 1, cmd, cmd & 0xffff_ffff, 0, rng.next_u128() >> 32]);
            plan.push((r, PUSH_CHECK_LATENCY, vec![Some(1), Some(cmd), Some(0), None, None]));
        } else {
            let seg = trap[ti % trap.len()];
            ti += 1;
            ext_at.push((r + 3, ext));
            let out = match seg.validate(&limits) {
                Ok(()) if ext != 0 => vec![Some(0), None, Some(1), Some(axis as u128), Some(ext)],
                Ok(()) => vec![Some(1), Some(push(&seg.effective(), axis)), Some(0), None, None],
                Err(e) => vec![Some(0), None, Some(1), Some(axis as u128), Some(e.code() as u128)],
            };
            rows.push(vec![0, 1, push(&seg, axis), seg.v0_rate as u128, 0, rng.next_u128() >> 32]);
            plan.push((r, PUSH_CHECK_LATENCY, out));
        }
        if last_poly == Some(r.saturating_sub(4)) && r >= 4 {
            back_to_back += 1;
        }
        // 4 to 7 cycles to the next command.
        let gap = 4 + (rng.next() % 4) as usize;
        for _ in 1..gap {
            rows.push(vec![0, 0, rng.next_u128() & ((1 << CMD_BITS) - 1), rng.next() as u32 as u128, 0, rng.next_u128() >> 32]);
        }
    }
    for _ in 0..10 {
        rows.push(vec![0, 0, 0, 0, 0, 0]);
    }
    for r in rows.iter_mut().skip(2) {
        r[4] = (rng.next() % 16) as u128;
    }
    for (r, ext) in &ext_at {
        rows[*r][4] = *ext;
    }
    assert!(codes.len() >= 6, "polynomial codes seen {codes:?}");
    assert!(ext_wins >= 3, "only {ext_wins} valid polynomial pushes the guard rejects");
    assert!(back_to_back >= 5, "only {back_to_back} commands offered 4 cycles after a polynomial push");
    // busy, out_valid, out_data, rej_valid, rej_axis, rej_code, poly_busy
    let mut want: Vec<Vec<Option<u128>>> = vec![vec![Some(0), Some(0), None, Some(0), None, None, Some(0), None]; rows.len()];
    want[0] = vec![None; 8];
    want[1] = vec![None; 8];
    for &(r, x) in &extra_out {
        want[r][7] = Some(x);
    }
    for (r, lat, out) in &plan {
        for b in 1..PUSH_CHECK_LATENCY {
            want[r + b][0] = Some(1);
        }
        let w = &mut want[r + lat];
        assert_eq!(w[1], Some(0), "two verdicts in one cycle (row {})", r + lat);
        w[1..6].clone_from_slice(out);
    }
    for r in &poly_rows {
        for b in 1..POLY_PUSH_LATENCY {
            want[r + b][6] = Some(1);
        }
    }
    three_ways(
        "push_check_poly",
        || {
            let mut u = PushCheck::<1>::new(limits);
            u.clock.connect();
            u.reset.connect();
            u.in_valid.connect();
            u.in_data.connect();
            u.in_v0.connect();
            u.ext_code.connect();
            u.in_extra.connect();
            u.connect_all();
            u
        },
        |u, c| u.clock.next = Clock::from(c),
        |u, r| {
            u.reset.next = r[0] == 1;
            u.in_valid.next = r[1] == 1;
            u.in_data.next = r[2].to_bits();
            u.in_v0.next = Bits::<32>::from(r[3] as u64);
            u.ext_code.next = Bits::<4>::from(r[4] as u64);
            u.in_extra.next = r[5].to_bits();
        },
        |u| {
            vec![
                u.busy.val() as u128,
                u.out_valid.val() as u128,
                bits_to_u128(u.out_data.val()),
                u.rej_valid.val() as u128,
                u.rej_axis.val().to_u64() as u128,
                u.rej_code.val().to_u64() as u128,
                u.poly_busy.val() as u128,
                bits_to_u128(u.out_extra.val()),
            ]
        },
        &{
            let mut s = spec();
            s.inputs.push(Port::new("in_extra", 96));
            s.outputs.push(Port::new("poly_busy", 1));
            s.outputs.push(Port::new("out_extra", 96));
            s
        },
        &rows,
        &want,
    );
}

/// PolyCheck (the polynomial segment's push check), three ways.
mod poly {
    // PolyCheck three ways: the model (`PolySegment::validate`), rust-hdl, and the
    // exported Verilog in Verilator and Icarus. Segments at every range boundary (T = 0,
    // 2^24, 2^24 + 1, |θ| = 2^24, i32::MIN, either rate at 2^31 − 1 and RMAX and one
    // above), A' at its extremes, each control point exactly at 0 and at the hull
    // `3·RMAX·T` and one unit either side, dwells, the planners' cubics, and random
    // segments, for three minimum periods, offered 6 to 9 cycles apart with a second
    // offer while busy (ignored): each verdict comes out POLY_CHECK_LATENCY cycles later
    // with the model's code, and `busy` covers the cycles in between. A reset drops the
    // segment in flight.
    use super::*;
    use tdm_stepper::hdl::poly_check::{PolyCheck, POLY_CHECK_LATENCY};
    use tdm_stepper::model::poly::{PolySegment, POLY_MAX_T_TICKS};

    fn spec() -> TbSpec {
        TbSpec {
            clock: "clock".into(),
            inputs: vec![
                Port::new("reset", 1),
                Port::new("in_valid", 1),
                Port::new("in_v0", 32),
                Port::new("in_v1", 32),
                Port::new("in_a", 64),
                Port::new("in_t", 32),
                Port::new("in_steps", 32),
            ],
            outputs: vec![Port::new("busy", 1), Port::new("out_valid", 1), Port::new("out_code", 4)],
        }
    }

    fn code(seg: &PolySegment, limits: &Limits) -> u128 {
        seg.validate(limits).err().map_or(0, |e| e.code() as u128)
    }

    /// A' putting β1 (`which` = 1) or β2 (`which` = 2) at `target`, rounded down to an
    /// integer (the caller tries it and one unit either side).
    fn a_for(which: u32, v0: u32, v1: u32, t: u32, n: u32, target: i128) -> i128 {
        let (v0t, v1t) = (v0 as i128 * t as i128, v1 as i128 * t as i128);
        let twice = match which {
            1 => target - 3 * v0t,
            _ => ((12 * n as i128) << 32) - 6 * v0t - 3 * v1t - target,
        };
        twice.div_euclid(2)
    }

    pub(super) fn segments(limits: &Limits, rng: &mut Rng) -> Vec<PolySegment> {
        let rmax = limits.max_rate();
        let big_t = POLY_MAX_T_TICKS;
        let mut v = vec![
            PolySegment::new(0, 0, 0, 0, 5),
            PolySegment::new(0, 0, 0, 0, 0),
            PolySegment::new(0, 0, 0, big_t, 0),
            PolySegment::new(0, 0, 0, big_t + 1, 0),
            PolySegment::new(0, 0, 0, u32::MAX, 0),
            PolySegment::new(0, 0, 0, 1000, MAX_STEPS as i32 + 1),
            PolySegment::new(0, 0, 0, 1000, -(MAX_STEPS as i32) - 1),
            PolySegment::new(0, 0, 0, 1000, i32::MIN),
            PolySegment::new(MAX_V0_RATE + 1, 0, 0, 1000, 10),
            PolySegment::new(0, MAX_V0_RATE + 1, 0, 1000, 10),
            PolySegment::new(u32::MAX, u32::MAX, i64::MIN, u32::MAX, i32::MIN),
            PolySegment::new(MAX_V0_RATE, MAX_V0_RATE, 0, 1000, 10),
            PolySegment::new(rmax, rmax, 0, 1 << 20, ((rmax as u64) << 20 >> 32) as i32),
            PolySegment::new(rmax + 1, rmax, 0, 1 << 20, ((rmax as u64) << 20 >> 32) as i32),
            PolySegment::new(rmax, rmax + 1, 0, 1 << 20, ((rmax as u64) << 20 >> 32) as i32),
            PolySegment::new(0, 0, i64::MAX, 1000, 10),
            PolySegment::new(0, 0, i64::MIN, 1000, 10),
            PolySegment::new(0, 0, i64::MIN, big_t, MAX_STEPS as i32),
            PolySegment::new(0, 0, i64::MAX, big_t, -(MAX_STEPS as i32)),
            PolySegment::new(0, 0, 0, 7, 0), // a dwell
            PolySegment::new(0, 0, 1, 7, 0),
        ];
        // Cubics from rest, to rest and between speeds.
        for _ in 0..12 {
            let t = 1 + (rng.next() % big_t as u64) as u32;
            let v0 = (rng.next() % (rmax as u64 + 1)) as u32;
            let v1 = (rng.next() % (rmax as u64 + 1)) as u32;
            let n = ((v0 as u64 + v1 as u64) * t as u64 >> 33) as i32;
            let n = if rng.next() % 2 == 0 { n } else { -n };
            if let Some(c) = PolySegment::cubic(v0, v1, t, n) {
                v.push(c);
            }
        }
        // Each control point at 0 and at the hull, and one unit either side.
        for _ in 0..8 {
            let t = 1 + (rng.next() % big_t as u64) as u32;
            let v0 = (rng.next() % (rmax as u64 + 1)) as u32;
            let v1 = (rng.next() % (rmax as u64 + 1)) as u32;
            let n = ((v0 as u64 + v1 as u64) * t as u64 >> 33).min(MAX_STEPS as u64) as u32;
            let hull = 3 * rmax as i128 * t as i128;
            for which in [1, 2] {
                for target in [0, hull] {
                    let a0 = a_for(which, v0, v1, t, n, target);
                    for d in [-1i128, 0, 1] {
                        let a = (a0 + d).clamp(i64::MIN as i128, i64::MAX as i128) as i64;
                        v.push(PolySegment::new(v0, v1, a, t, n as i32));
                    }
                }
            }
        }
        // Random: any values, weighted towards the documented range.
        while v.len() < 160 {
            let t = match rng.next() % 4 {
                0 => rng.next() as u32,
                _ => 1 + (rng.next() % big_t as u64) as u32,
            };
            let v0 = (rng.next() >> (32 + rng.next() % 3)) as u32;
            let v1 = (rng.next() >> (32 + rng.next() % 3)) as u32;
            let n = ((v0 as u128 + v1 as u128) * t as u128 >> 33).min(1 << 40) as i64 + (rng.next() % 5) as i64 - 2;
            let n = n.clamp(0, MAX_STEPS as i64 + 1) as i32;
            let a = match rng.next() % 3 {
                0 => rng.next() as i64,
                1 => (rng.next() as i64) >> (rng.next() % 40),
                _ => 0,
            };
            v.push(PolySegment::new(v0, v1, a, t, if rng.next() % 2 == 0 { n } else { -n }));
        }
        v
    }

    fn row(reset: bool, valid: bool, s: &PolySegment) -> Vec<u128> {
        vec![
            reset as u128,
            valid as u128,
            s.v0_rate as u128,
            s.v1_rate as u128,
            s.a_q32 as u64 as u128,
            s.t_ticks as u128,
            s.steps as u32 as u128,
        ]
    }

    #[test]
    fn verdicts_equal_the_model_three_ways() {
        const L: usize = POLY_CHECK_LATENCY;
        let mut rng = Rng(0x5eed_0f_be27_57e1);
        for min_period in [2u32, 24, 66] {
            let limits = Limits::new(min_period).unwrap();
            let segs = segments(&limits, &mut rng);
            let junk = |rng: &mut Rng| PolySegment::new(rng.next() as u32, rng.next() as u32, rng.next() as i64, rng.next() as u32, rng.next() as i32);
            let mut rows: Vec<Vec<u128>> = vec![row(true, false, &junk(&mut rng)), row(false, false, &junk(&mut rng))];
            // The offers (row, code, dropped by a reset in its cycle 3), then the
            // protocol's outputs row by row.
            let mut offers: Vec<(usize, u128, bool)> = Vec::new();
            let mut codes = std::collections::BTreeSet::new();
            for (k, seg) in segs.iter().enumerate() {
                let c = code(seg, &limits);
                codes.insert(c);
                let dropped = k % 11 == 5;
                offers.push((rows.len(), c, dropped));
                rows.push(row(false, true, seg));
                // The next offer 6 to 9 cycles later (6: in the verdict's cycle).
                let gap = L + (rng.next() % 4) as usize;
                for j in 1..gap {
                    // A second offer while busy (ignored); a reset in cycle 3.
                    rows.push(row(dropped && j == 3, j == 2, &junk(&mut rng)));
                }
            }
            rows.push(row(false, false, &junk(&mut rng)));
            let mut want: Vec<Vec<Option<u128>>> = vec![vec![Some(0), Some(0), None]; rows.len()];
            want[0] = vec![None; 3];
            for &(r, c, dropped) in &offers {
                let busy_to = if dropped { 3 } else { L - 1 };
                for j in 1..=busy_to {
                    want[r + j][0] = Some(1);
                }
                if !dropped {
                    want[r + L] = vec![Some(0), Some(1), Some(c)];
                }
            }
            assert_eq!(codes, [0u128, 1, 2, 3, 4, 5, 6].into_iter().collect(), "min period {min_period}: every code is tried");
            three_ways(
                &format!("poly_check_{min_period}"),
                || {
                    let mut u = PolyCheck::new(limits);
                    u.clock.connect();
                    u.reset.connect();
                    u.in_valid.connect();
                    u.in_v0.connect();
                    u.in_v1.connect();
                    u.in_a.connect();
                    u.in_t.connect();
                    u.in_steps.connect();
                    u.connect_all();
                    u
                },
                |u, c| u.clock.next = Clock::from(c),
                |u, r| {
                    u.reset.next = r[0] == 1;
                    u.in_valid.next = r[1] == 1;
                    u.in_v0.next = (r[2] as u64).into();
                    u.in_v1.next = (r[3] as u64).into();
                    u.in_a.next = (r[4] as u64).into();
                    u.in_t.next = (r[5] as u64).into();
                    u.in_steps.next = (r[6] as u64).into();
                },
                |u| vec![u.busy.val() as u128, u.out_valid.val() as u128, u.out_code.val().to_u64() as u128],
                &spec(),
                &rows,
                &want,
            );
        }
    }
}
