//! PushCheck three ways: the model (`Segment::validate` and `Segment::effective`),
//! rust-hdl, and the exported Verilog in Verilator and Icarus. Pushes at every range
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
use tdm_stepper::hdl::push_check::{PushCheck, PUSH_CHECK_LATENCY};
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
                let mut u = PushCheck::new(limits);
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
