//! ExmcSlave three ways: the bus's contract (a model of the MCU's accesses), rust-hdl,
//! and the exported Verilog in Verilator and Icarus. Writes and reads at the documented
//! minimum timing and slower, random address and data, and strobes too short to be
//! sampled twice: every well-formed write commits once (`wr`) with its address and
//! data, a cut-off write commits nothing, every read pulses `rd` once with its address
//! and drives `data_out` with the owner's `rd_data` of that cycle. The look-ahead
//! outputs hold what their registers will: `wr_next`/`wr_axis_next` are the next
//! cycle's `wr` and `wr_addr` bits 7..4, `rd_axis_next` the next cycle's `rd_addr`
//! bits 8..4, in every cycle.

mod common;

use common::*;
use rust_hdl::prelude::*;
use tdm_stepper::hdl::exmc::ExmcSlave;
use tdm_stepper::regs::ADDR_BITS;
use tdm_stepper::verify::bus::{MIN_HIGH_BUS_CLOCKS, MIN_READ_BUS_CLOCKS, MIN_WRITE_BUS_CLOCKS};
use tdm_stepper::verify::{run_rust_hdl, Port, TbSpec};

fn uut() -> ExmcSlave {
    let mut u = ExmcSlave::default();
    u.clock.connect();
    u.reset.connect();
    u.ne.connect();
    u.noe.connect();
    u.nwe.connect();
    u.addr.connect();
    u.data_in.connect();
    u.rd_data.connect();
    u.connect_all();
    u
}

const IN: [(&str, usize); 7] =
    [("reset", 1), ("ne", 1), ("noe", 1), ("nwe", 1), ("addr", ADDR_BITS), ("data_in", 16), ("rd_data", 16)];
const OUT: [(&str, usize); 10] = [
    ("wr", 1),
    ("wr_addr", ADDR_BITS),
    ("wr_data", 16),
    ("wr_next", 1),
    ("wr_axis_next", 4),
    ("rd", 1),
    ("rd_addr", ADDR_BITS),
    ("rd_axis_next", 5),
    ("data_out", 16),
    ("data_oe", 1),
];

fn spec() -> TbSpec {
    TbSpec {
        clock: "clock".into(),
        inputs: IN.iter().map(|(n, w)| Port::new(n, *w)).collect(),
        outputs: OUT.iter().map(|(n, w)| Port::new(n, *w)).collect(),
    }
}

/// What the MCU did, for the contract's checks.
enum Access {
    Write { addr: u16, data: u16, complete: bool },
    Read { addr: u16 },
}

#[test]
fn commits_reads_and_look_ahead_outputs() {
    let mut rng = Rng(0x5eed_e3c0);
    // Rows: reset, ne, noe, nwe, addr, data_in, rd_data (junk, changing every cycle).
    let mut rows: Vec<Vec<u128>> = vec![vec![1, 1, 1, 1, 0, 0, 0]; 3];
    let mut accesses = vec![];
    let idle = |rows: &mut Vec<Vec<u128>>, rng: &mut Rng, n: u64| {
        for _ in 0..n {
            rows.push(vec![0, 1, 1, 1, rng.next() as u128 & 0x1ff, rng.next() as u128 & 0xffff, rng.next() as u128 & 0xffff]);
        }
    };
    for _ in 0..300 {
        let addr = (rng.next() & 0x1ff) as u16;
        let data = rng.next() as u16;
        // Strobes high for the documented minimum between accesses, or longer.
        let gap = MIN_HIGH_BUS_CLOCKS + rng.next() % 3;
        idle(&mut rows, &mut rng, gap);
        match rng.next() % 5 {
            0 | 1 => {
                // A write with NWE low for the documented minimum or up to 3 bus clocks more.
                let low = MIN_WRITE_BUS_CLOCKS + rng.next() % 4;
                for _ in 0..low {
                    rows.push(vec![0, 0, 1, 0, addr as u128, data as u128, rng.next() as u128 & 0xffff]);
                }
                accesses.push(Access::Write { addr, data, complete: true });
            }
            2 => {
                // A glitch: NWE low for one bus clock, too short to be sampled twice.
                rows.push(vec![0, 0, 1, 0, addr as u128, data as u128, 0]);
                accesses.push(Access::Write { addr, data, complete: false });
            }
            _ => {
                // A read with NOE low for the documented minimum or up to 3 bus clocks more.
                let low = MIN_READ_BUS_CLOCKS + rng.next() % 4;
                for _ in 0..low {
                    rows.push(vec![0, 0, 0, 1, addr as u128, 0, rng.next() as u128 & 0xffff]);
                }
                accesses.push(Access::Read { addr });
            }
        }
    }
    idle(&mut rows, &mut rng, 6);

    let out = run_rust_hdl(
        &mut uut(),
        &rows,
        |u, c| u.clock.next = Clock::from(c),
        |u, r| {
            u.reset.next = r[0] == 1;
            u.ne.next = r[1] == 1;
            u.noe.next = r[2] == 1;
            u.nwe.next = r[3] == 1;
            u.addr.next = (r[4] as u64).into();
            u.data_in.next = (r[5] as u64).into();
            u.rd_data.next = (r[6] as u64).into();
        },
        |u| {
            vec![
                u.wr.val() as u128,
                u.wr_addr.val().to_u64() as u128,
                u.wr_data.val().to_u64() as u128,
                u.wr_next.val() as u128,
                u.wr_axis_next.val().to_u64() as u128,
                u.rd.val() as u128,
                u.rd_addr.val().to_u64() as u128,
                u.rd_axis_next.val().to_u64() as u128,
                u.data_out.val().to_u64() as u128,
                u.data_oe.val() as u128,
            ]
        },
    );

    // The contract: the commits and reads, in order, with their addresses and data.
    let commits: Vec<(u16, u16)> =
        out.iter().filter(|o| o[0] == 1).map(|o| (o[1] as u16, o[2] as u16)).collect();
    let want_commits: Vec<(u16, u16)> = accesses
        .iter()
        .filter_map(|a| match a {
            Access::Write { addr, data, complete: true } => Some((*addr, *data)),
            _ => None,
        })
        .collect();
    assert!(want_commits.len() > 50 && accesses.iter().any(|a| matches!(a, Access::Write { complete: false, .. })));
    assert_eq!(commits, want_commits, "one commit per complete write, none for a glitch");
    let reads: Vec<usize> = (0..out.len()).filter(|&k| out[k][5] == 1).collect();
    let want_reads: Vec<u16> =
        accesses.iter().filter_map(|a| if let Access::Read { addr } = a { Some(*addr) } else { None }).collect();
    assert_eq!(reads.iter().map(|&k| out[k][6] as u16).collect::<Vec<_>>(), want_reads, "one rd per read");
    for &k in &reads {
        // The owner's rd_data of the rd cycle is on data_out from the next cycle on.
        assert_eq!(out[k + 1][8], rows[k][6], "data_out after the read at row {k}");
        // Data valid at most 4 bus clocks after NOE falls: a bus clock before the MCU
        // samples it at the earliest (NOE low for the documented minimum).
        let fall = (0..=k).rev().find(|&j| rows[j][2] == 1).unwrap() + 1;
        let due = MIN_READ_BUS_CLOCKS as usize - 1;
        assert!(k + 1 - fall <= due, "read at row {k}: data {} bus clocks after NOE fell", k + 1 - fall);
    }
    for (k, r) in rows.iter().enumerate() {
        assert_eq!(out[k][9], (r[1] == 0 && r[2] == 0) as u128, "data_oe at row {k}");
    }
    // The look-ahead outputs, in every cycle.
    for k in 3..out.len() - 1 {
        assert_eq!(out[k][3], out[k + 1][0], "wr_next at row {k}");
        if out[k + 1][0] == 1 {
            assert_eq!(out[k][4], (out[k + 1][1] >> 4) & 15, "wr_axis_next at row {k}");
        }
        assert_eq!(out[k][7], out[k + 1][6] >> 4, "rd_axis_next at row {k}");
    }

    verilog_matches_rust_hdl("exmc", &generate_verilog(&uut()), &spec(), &rows, &out, 3);
}
