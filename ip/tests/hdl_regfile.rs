//! The register file's command path, in rust-hdl and in its exported Verilog
//! (Verilator and Icarus), against what the contract says: every command reaches the
//! command FIFO PUSH_CHECK_LATENCY bus clocks after its write, in order; a valid push
//! goes through, a bad one is dropped with STATUS.ERROR and its code, and LEVEL counts
//! it only while it is checked; a push captured before a later staging write keeps its
//! values; a rejection and a push of the same axis in one cycle leave LEVEL right; a
//! command written while the check is busy is refused (GSTATUS.REFUSED) and never
//! reaches the FIFO; with the command FIFO one entry short of full, a command taken in
//! the check's last cycle (while the one before it goes into the FIFO) is refused, a
//! push with OVERFLOW, and the same a cycle later is taken.

mod common;

use common::*;
use rust_hdl::prelude::*;
use tdm_stepper::hdl::push_check::PUSH_CHECK_LATENCY;
use tdm_stepper::hdl::regfile::{RegFile, CMD_BITS, W_ENABLED};
use tdm_stepper::hdl::status_sync::STATUS_BITS;
use tdm_stepper::model::{Limits, Segment};
use tdm_stepper::regs::{self, CoreParams, ADDR_BITS};
use tdm_stepper::verify::{run, run_rust_hdl, Port, TbSpec};

const K: usize = 2;
const L: usize = PUSH_CHECK_LATENCY;

fn uut() -> RegFile<K> {
    let p = CoreParams { axes: K, clock_hz: 50_000_000, queue_depth: 16, fifo_depth: 4, t_calc: 22, min_period: 2, io: false, io_omit: 0, scurve: false, encoder: false };
    let mut u = RegFile::<K>::new(p);
    u.clock.connect();
    u.reset.connect();
    u.wr.connect();
    u.wr_addr.connect();
    u.wr_data.connect();
    u.rd.connect();
    u.rd_addr.connect();
    u.rd_axis_next.connect();
    u.wr_next.connect();
    u.wr_axis_next.connect();
    u.st_valid.connect();
    u.st_axis.connect();
    u.st_word.connect();
    u.cmd_full.connect();
    u.cmd_almost_full.connect();
    u.start_fail_toggle.connect();
    u.guard_code.connect();
    u.poly_arm.connect();
    u.poly_extra.connect();
    u.connect_all();
    u
}

fn spec() -> TbSpec {
    TbSpec {
        clock: "clock".into(),
        inputs: vec![
            Port::new("reset", 1),
            Port::new("wr", 1),
            Port::new("wr_addr", ADDR_BITS),
            Port::new("wr_data", 16),
            Port::new("rd", 1),
            Port::new("rd_addr", ADDR_BITS),
            Port::new("st_valid", 1),
            Port::new("st_axis", 8),
            Port::new("st_word", STATUS_BITS),
            Port::new("cmd_full", 1),
            Port::new("start_fail_toggle", 1),
            Port::new("rd_axis_next", 5),
            Port::new("wr_next", 1),
            Port::new("wr_axis_next", 4),
            Port::new("cmd_almost_full", 1),
            // The push guard's code (the machine I/O's), 0 here as without it.
            Port::new("guard_code", 4),
        ],
        outputs: vec![Port::new("cmd_write", 1), Port::new("cmd_data", CMD_BITS), Port::new("rd_data", 16)],
    }
}

/// Rows of stimulus, built cycle by cycle.
struct Stim {
    rows: Vec<Vec<u128>>,
}

impl Stim {
    fn idle(&mut self) -> usize {
        self.rows.push(vec![0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]);
        self.rows.len() - 1
    }
    fn write(&mut self, addr: u16, data: u16) -> usize {
        self.rows.push(vec![0, 1, addr as u128, data as u128, 0, 0, 0, 0, 0, 0, 0]);
        self.rows.len() - 1
    }
    /// A read, at least 2 rows after the last write, as the EXMC slave's timing
    /// allows (strobes high ≥ 2 bus clocks between accesses): the register file shows
    /// a push in LEVEL from then on.
    fn read(&mut self, addr: u16) -> usize {
        while self.rows.iter().rev().take(2).any(|r| r[1] == 1) {
            self.idle();
        }
        self.rows.push(vec![0, 0, 0, 0, 1, addr as u128, 0, 0, 0, 0, 0]);
        self.rows.len() - 1
    }
    /// Idles until row `r` is next.
    fn until(&mut self, r: usize) {
        while self.rows.len() < r {
            self.idle();
        }
    }
}

fn a(name: &str, axis: usize) -> u16 {
    regs::register(name).address(axis)
}

fn push_cmd(seg: &Segment, axis: usize) -> u128 {
    seg.v0_rate as u128 | (seg.t_ticks as u128) << 32 | (seg.steps as u32 as u128) << 64 | (axis as u128) << 96
}

#[test]
fn commands_pass_the_push_check_in_order_and_bad_pushes_never_reach_the_core() {
    let limits = Limits::default();
    let good = Segment::new(0, 1000, 5);
    assert!(good.validate(&limits).is_ok());
    // Axis 1's segment differs from axis 0's, so a push that read another axis's
    // staging would show.
    let good1 = Segment::new(0, 1000, 7);
    assert!(good1.validate(&limits).is_ok());
    assert_eq!(Segment::new(0, 0, 5).validate(&limits).unwrap_err().code(), 1);
    let mut s = Stim { rows: vec![] };
    s.rows.push(vec![1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]);
    s.rows.push(vec![1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]);
    s.write(regs::addr("CTRL"), 1);
    s.idle();
    // The core's view: ENABLED, from the last axis's status word.
    s.rows.push(vec![0, 0, 0, 0, 0, 0, 1, (K - 1) as u128, 1u128 << W_ENABLED, 0, 0]);
    s.idle();
    // 1. A valid push on axis 0, a START 2 cycles later (refused: the check is busy),
    //    and one at the verdict's cycle (taken).
    s.write(a("T_LO", 0), 1000);
    s.write(a("STEPS_LO", 0), 5);
    s.idle();
    let p1 = s.write(a("STEPS_HI", 0), 0);
    s.idle();
    let early = s.write(regs::addr("START"), 0b01);
    s.until(p1 + L);
    let st1 = s.write(regs::addr("START"), 0b01);
    s.until(st1 + L + 2);
    let gstatus = s.read(regs::addr("GSTATUS"));
    // 2. A bad push on axis 1 (T = 0: never written): LEVEL counts it while it is
    //    checked, then STATUS shows ERROR with code 1 and LEVEL 0.
    s.write(a("STEPS_LO", 1), 7);
    s.idle();
    let p2 = s.write(a("STEPS_HI", 1), 0);
    let during = s.read(a("STATUS", 1));
    s.until(p2 + L + 1);
    let after = s.read(a("STATUS", 1));
    s.write(a("STATUS", 1), 1 << 8);
    // 3. Axis 1 again: a bad push, T written while it is checked (the push keeps what it
    //    captured), and a push of the now valid segment at the rejection's cycle.
    s.idle();
    let p3 = s.write(a("STEPS_HI", 1), 0);
    s.idle();
    s.write(a("T_LO", 1), 1000);
    s.until(p3 + L);
    let p4 = s.write(a("STEPS_HI", 1), 0);
    s.idle();
    let level = s.read(a("STATUS", 1));
    s.until(p4 + L + 3);
    let level_end = s.read(a("STATUS", 1));
    for _ in 0..4 {
        s.idle();
    }
    // 4. The command FIFO one entry short of full (`cmd_almost_full`) from here on: a
    //    command taken in the check's last cycle, while the valid one before it goes
    //    into the FIFO, would find no room 4 cycles later. A START there is refused, a
    //    push there is refused with OVERFLOW and not counted; one cycle later both fit.
    s.write(regs::addr("GSTATUS"), 0b10);
    s.idle();
    let almost_from = s.rows.len();
    let p5 = s.write(a("STEPS_HI", 0), 0);
    s.until(p5 + L);
    let st2 = s.write(regs::addr("START"), 0b01);
    s.idle();
    let p6 = s.write(a("STEPS_HI", 0), 0);
    s.until(p6 + L);
    let p7 = s.write(a("STEPS_HI", 0), 0);
    s.until(p7 + L + 1);
    let st3 = s.write(regs::addr("START"), 0b01);
    let gstatus2 = s.read(regs::addr("GSTATUS"));
    let status0 = s.read(a("STATUS", 0));
    for _ in 0..L + 2 {
        s.idle();
    }
    // The look-ahead inputs as the bus slave drives them: the next row's `rd_addr`
    // bits 8..4, `wr` and `wr_addr` bits 7..4.
    let mut rows = s.rows;
    for k in 0..rows.len() {
        let next = rows.get(k + 1).cloned().unwrap_or(vec![0; 11]);
        rows[k].extend([next[5] >> 4, next[1], (next[2] >> 4) & 15, (k >= almost_from) as u128, 0]);
    }

    let out = run_rust_hdl(
        &mut uut(),
        &rows,
        |u, c| u.clock.next = Clock::from(c),
        |u, r| {
            u.reset.next = r[0] == 1;
            u.wr.next = r[1] == 1;
            u.wr_addr.next = (r[2] as u64).into();
            u.wr_data.next = (r[3] as u64).into();
            u.rd.next = r[4] == 1;
            u.rd_addr.next = (r[5] as u64).into();
            u.st_valid.next = r[6] == 1;
            u.st_axis.next = (r[7] as u64).into();
            u.st_word.next = (r[8] as u64).into();
            u.cmd_full.next = r[9] == 1;
            u.start_fail_toggle.next = r[10] == 1;
            u.rd_axis_next.next = (r[11] as u64).into();
            u.wr_next.next = r[12] == 1;
            u.wr_axis_next.next = (r[13] as u64).into();
            u.cmd_almost_full.next = r[14] == 1;
            u.guard_code.next = (r[15] as u64).into();
        },
        |u| vec![u.cmd_write.val() as u128, bits_to_u128(u.cmd_data.val()), u.rd_data.val().to_u64() as u128],
    );
    let writes: Vec<(usize, u128)> = out.iter().enumerate().filter(|(_, o)| o[0] == 1).map(|(k, o)| (k, o[1])).collect();
    let start = |mask: u128| mask | 1 << 104;
    assert_eq!(
        writes,
        vec![
            (p1 + L, push_cmd(&good, 0)),
            (st1 + L, start(0b01)),
            (p4 + L, push_cmd(&good1, 1)),
            (p5 + L, push_cmd(&good, 0)),
            (p6 + L, push_cmd(&good, 0)),
            (st3 + L, start(0b01)),
        ],
        "commands into the FIFO (the early START at row {early} refused, the bad pushes dropped, \
         the START at row {st2} and the push at row {p7} refused for want of room)"
    );
    assert_eq!(out[gstatus2][2] & 0b10, 0b10, "GSTATUS.REFUSED after the START with no room");
    assert_eq!(out[gstatus][2] & 0b10, 0b10, "GSTATUS.REFUSED after the early START");
    let status = |r: usize| out[r][2] as u16;
    assert_eq!(status(during) & 0x11F, 1, "axis 1 while its push is checked: LEVEL 1, no ERROR");
    assert_eq!((status(after) & 0x11F, status(after) >> 12), (0x100, 1), "axis 1 after the verdict");
    assert_eq!(status(level) & 0x11F, 0x101, "reject and push in one cycle: LEVEL 1, ERROR");
    assert_eq!(status(level_end) & 0x1F, 1, "the valid push stays counted");
    assert_eq!(status(status0) & 0x9F, 0x80 | 3, "axis 0: OVERFLOW, LEVEL 3 (the push with no room not counted)");

    let verilog = generate_verilog(&uut());
    let reads = [gstatus, during, after, level, level_end, gstatus2, status0];
    for sim in SIMULATORS {
        let got = run(sim, &sim_dir("regfile_commands", sim), &verilog, &spec(), &rows).unwrap();
        for (k, (g, r)) in got.iter().zip(&out).enumerate().skip(2) {
            let what = |p: usize| g[p].unwrap_or_else(|| panic!("{sim:?}: x at row {k}, output {p}"));
            assert_eq!(what(0), r[0], "{sim:?}: cmd_write at row {k}");
            if r[0] == 1 {
                assert_eq!(what(1), r[1], "{sim:?}: cmd_data at row {k}");
            }
            if reads.contains(&k) {
                assert_eq!(what(2), r[2], "{sim:?}: rd_data at row {k}");
            }
        }
    }
}

/// The S-curve option's registers (`PolyRegs`) three ways: a model of the contract in
/// its module comment (and docs/registers.md), rust-hdl, and its exported Verilog in
/// Verilator and Icarus, on random bus traffic: writes to its seven registers and to
/// addresses beside them (no effect), reads anywhere (its registers read back as
/// written, POLY_ARM bit 0 only, every other address 0), the arm cleared by a push and
/// by ENABLE low (a write in the same cycle loses to both), and resets.
#[test]
fn poly_registers_read_back_and_the_arm_is_taken_by_one_push_three_ways() {
    use tdm_stepper::hdl::poly_regs::PolyRegs;
    let names = ["POLY_V1_LO", "POLY_V1_HI", "POLY_A_0", "POLY_A_1", "POLY_A_2", "POLY_A_3", "POLY_ARM"];
    let ours: Vec<u16> = names.iter().map(|n| regs::addr(n)).collect();
    let others = [regs::addr("CTRL"), regs::addr("GSTATUS"), a("T_LO", 0), a("STEPS_HI", 1), ours.iter().max().unwrap() + 1];
    let mut rng = Rng(0x5eed_2042);
    // Rows: bus_reset, wr, wr_addr, wr_data, rd_addr, enable, pushed.
    let mut rows: Vec<Vec<u128>> = vec![vec![1, 0, 0, 0, 0, 1, 0]; 2];
    for _ in 0..3000 {
        let pick = |rng: &mut Rng| if rng.next() % 5 == 0 { others[(rng.next() % others.len() as u64) as usize] } else { ours[(rng.next() % ours.len() as u64) as usize] };
        let wr = rng.next() % 2;
        let wa = pick(&mut rng);
        let data = if wa == ours[6] { rng.next() % 4 } else { rng.next() & 0xFFFF };
        let ra = pick(&mut rng);
        let enable = (rng.next() % 20 != 0) as u64;
        let pushed = (rng.next() % 6 == 0) as u64;
        let reset = (rng.next() % 400 == 0) as u64;
        rows.push([reset, wr, wa as u64, data, ra as u64, enable, pushed].map(|x| x as u128).to_vec());
    }
    // The model: outputs from the state before the row's clock edge.
    let mut st = [0u16; 6];
    let mut armed = false;
    let mut want = Vec::new();
    let (mut arms, mut taken) = (0, 0);
    for (k, r) in rows.iter().enumerate() {
        let ra = r[4] as u16;
        let rd = match ours.iter().position(|&x| x == ra) {
            Some(6) => armed as u16,
            Some(i) => st[i],
            None => 0,
        };
        let extra = (0..6).fold(0u128, |acc, i| acc | (st[i] as u128) << (16 * i));
        want.push(if k < 2 { vec![None; 3] } else { vec![Some(rd as u128), Some(armed as u128), Some(extra)] });
        let (reset, wr, wa, data, enable, pushed) = (r[0] == 1, r[1] == 1, r[2] as u16, r[3] as u16, r[5] == 1, r[6] == 1);
        let mut next_armed = armed;
        if wr {
            match ours.iter().position(|&x| x == wa) {
                Some(6) => next_armed = data & 1 == 1,
                Some(i) => st[i] = data,
                None => {}
            }
        }
        if pushed && armed {
            taken += 1;
        }
        if pushed || !enable {
            next_armed = false;
        }
        if reset {
            st = [0; 6];
            next_armed = false;
        }
        arms += (!armed && next_armed) as usize;
        armed = next_armed;
    }
    assert!(arms > 50 && taken > 10, "the traffic arms ({arms}) and takes ({taken}) the arm");
    let make = || {
        let mut u = PolyRegs::default();
        u.bus_reset.connect();
        u.wr.connect();
        u.wr_addr.connect();
        u.wr_data.connect();
        u.rd_addr.connect();
        u.enable.connect();
        u.pushed.connect();
        u.connect_all();
        u
    };
    let spec = TbSpec {
        clock: "bus_clock".into(),
        inputs: vec![
            Port::new("bus_reset", 1),
            Port::new("wr", 1),
            Port::new("wr_addr", ADDR_BITS),
            Port::new("wr_data", 16),
            Port::new("rd_addr", ADDR_BITS),
            Port::new("enable", 1),
            Port::new("pushed", 1),
        ],
        outputs: vec![Port::new("rd_data", 16), Port::new("arm", 1), Port::new("extra", 96)],
    };
    three_ways(
        "poly_regs",
        make,
        |u, c| u.bus_clock.next = Clock::from(c),
        |u, r| {
            u.bus_reset.next = r[0] == 1;
            u.wr.next = r[1] == 1;
            u.wr_addr.next = (r[2] as u64).into();
            u.wr_data.next = (r[3] as u64).into();
            u.rd_addr.next = (r[4] as u64).into();
            u.enable.next = r[5] == 1;
            u.pushed.next = r[6] == 1;
        },
        |u| vec![u.rd_data.val().to_u64() as u128, u.arm.val() as u128, bits_to_u128(u.extra.val())],
        &spec,
        &rows,
        &want,
    );
}

/// A register of a register-file block, as the register table says it behaves: its
/// reset value, and a write that sets its Rw fields and clears its W1C bits written 1.
struct TableReg {
    addr: u16,
    reset: u16,
    value: u16,
    rw: u16,
    w1c: u16,
}

impl TableReg {
    fn new(name: &str, p: &CoreParams) -> TableReg {
        let r = regs::register(name);
        let (mut rw, mut w1c) = (0u16, 0u16);
        for f in &r.fields {
            let m = (((1u32 << f.width) - 1) << f.lsb) as u16;
            match f.access {
                regs::Access::Rw => rw |= m,
                regs::Access::W1c => w1c |= m,
                a => panic!("{name}: a {} field in a read/write block", a.name()),
            }
        }
        let reset = r.reset_value(p);
        TableReg { addr: r.address(0), reset, value: reset, rw, w1c }
    }
    fn write(&self, data: u16) -> u16 {
        (self.value & !self.rw & !(self.w1c & data)) | (data & self.rw)
    }
}

fn params() -> CoreParams {
    CoreParams { axes: K, clock_hz: 50_000_000, queue_depth: 16, fifo_depth: 4, t_calc: 22, min_period: 40, io: false, io_omit: 0, scurve: false, encoder: false }
}

/// IrqRegs against the register table on random traffic, three ways: IRQ_DONE,
/// IRQ_QLOW and IRQ_ERROR set by events and cleared by writing 1 (an event in the
/// cycle of its clearing write wins), cleared while ENABLE is 0; the masks and
/// QLOW_LEVEL read back as written; `irq` the registered OR of the flags under their
/// masks; resets; writes and reads of other addresses (no effect, 0).
#[test]
fn irq_registers_follow_the_register_table_three_ways() {
    use tdm_stepper::hdl::irq_regs::IrqRegs;
    let p = params();
    let names = ["IRQ_DONE", "IRQ_QLOW", "IRQ_ERROR", "IRQ_MASK_DONE", "IRQ_MASK_QLOW", "IRQ_MASK_ERROR", "QLOW_LEVEL"];
    let mut regs_: Vec<TableReg> = names.iter().map(|n| TableReg::new(n, &p)).collect();
    assert!(regs_[..3].iter().all(|r| r.w1c == 0xFFFF) && regs_[3..].iter().all(|r| r.w1c == 0), "the table's access types changed");
    let ours: Vec<u16> = regs_.iter().map(|r| r.addr).collect();
    let others = [regs::addr("CTRL"), regs::addr("GSTATUS"), regs::addr("STEP_HIGH"), a("STATUS", 1), regs::addr("ID_MAGIC")];
    let mut rng = Rng(0x5eed_1b0);
    // Rows: reset, enable, wr, wr_addr, wr_data, ev_done, ev_qlow, ev_err, rd_addr.
    let mut rows: Vec<Vec<u128>> = vec![vec![1, 1, 0, 0, 0, 0, 0, 0, 0]; 2];
    for _ in 0..4000 {
        let pick = |rng: &mut Rng| if rng.next() % 5 == 0 { others[(rng.next() % others.len() as u64) as usize] } else { ours[(rng.next() % ours.len() as u64) as usize] };
        let ev = |rng: &mut Rng| if rng.next() % 6 == 0 { 1u64 << (rng.next() % 16) } else { 0 };
        let wr = rng.next() % 2;
        let wa = pick(&mut rng);
        let data = match rng.next() % 3 {
            0 => 0xFFFF,
            1 => 1 << (rng.next() % 16),
            _ => rng.next() & 0xFFFF,
        };
        let (e0, e1, e2) = (ev(&mut rng), ev(&mut rng), ev(&mut rng));
        let ra = pick(&mut rng);
        let enable = (rng.next() % 40 != 0) as u64;
        let reset = (rng.next() % 700 == 0) as u64;
        rows.push([reset, enable, wr, wa as u64, data, e0, e1, e2, ra as u64].map(|x| x as u128).to_vec());
    }
    let mut irq_q = false;
    let mut want = Vec::new();
    let (mut raised, mut cleared_by_write) = (0, 0);
    for (k, r) in rows.iter().enumerate() {
        let (reset, enable, wr, wa, data, ra) = (r[0] == 1, r[1] == 1, r[2] == 1, r[3] as u16, r[4] as u16, r[8] as u16);
        let rd = regs_.iter().find(|x| x.addr == ra).map_or(0, |x| x.value);
        want.push(if k < 2 { vec![None; 3] } else { vec![Some(rd as u128), Some(irq_q as u128), Some(regs_[6].value as u128)] });
        let pending = (0..3).any(|i| regs_[i].value & regs_[i + 3].value != 0);
        let mut next: Vec<u16> = regs_.iter().map(|x| x.value).collect();
        if wr {
            if let Some(i) = ours.iter().position(|&x| x == wa) {
                next[i] = regs_[i].write(data);
                cleared_by_write += (i < 3 && regs_[i].value & data != 0) as usize;
            }
        }
        for i in 0..3 {
            next[i] |= r[5 + i] as u16;
            if !enable {
                next[i] = 0;
            }
        }
        let next_irq = pending && !reset;
        raised += (!irq_q && next_irq) as usize;
        irq_q = next_irq;
        for (x, v) in regs_.iter_mut().zip(next) {
            x.value = if reset { x.reset } else { v };
        }
    }
    assert!(raised > 30 && cleared_by_write > 100, "the traffic raises irq ({raised}) and clears flags ({cleared_by_write})");
    let make = || {
        let mut u = IrqRegs::default();
        u.reset.connect();
        u.enable.connect();
        u.wr.connect();
        u.wr_addr.connect();
        u.wr_data.connect();
        u.ev_done.connect();
        u.ev_qlow.connect();
        u.ev_err.connect();
        u.rd_addr.connect();
        u.connect_all();
        u
    };
    let spec = TbSpec {
        clock: "clock".into(),
        inputs: vec![
            Port::new("reset", 1),
            Port::new("enable", 1),
            Port::new("wr", 1),
            Port::new("wr_addr", ADDR_BITS),
            Port::new("wr_data", 16),
            Port::new("ev_done", 16),
            Port::new("ev_qlow", 16),
            Port::new("ev_err", 16),
            Port::new("rd_addr", ADDR_BITS),
        ],
        outputs: vec![Port::new("rd_data", 16), Port::new("irq", 1), Port::new("qlow_level", 5)],
    };
    three_ways(
        "irq_regs",
        make,
        |u, c| u.clock.next = Clock::from(c),
        |u, r| {
            u.reset.next = r[0] == 1;
            u.enable.next = r[1] == 1;
            u.wr.next = r[2] == 1;
            u.wr_addr.next = (r[3] as u64).into();
            u.wr_data.next = (r[4] as u64).into();
            u.ev_done.next = (r[5] as u64).into();
            u.ev_qlow.next = (r[6] as u64).into();
            u.ev_err.next = (r[7] as u64).into();
            u.rd_addr.next = (r[8] as u64).into();
        },
        |u| vec![u.rd_data.val().to_u64() as u128, u.irq.val() as u128, u.qlow_level.val().to_u64() as u128],
        &spec,
        &rows,
        &want,
    );
}

/// TimingRegs against the register table and the model's timing rule, three ways:
/// STEP_HIGH, STEP_LOW, DIR_SETUP and DIR_HOLD read back as written; a write while
/// `locked` or of 0 is refused (`refuse`, value kept); `high_min`/`low_min` follow a
/// write two cycles on and `timing_ok` (`PulseTiming::check` with the minimum period)
/// three; resets to 1; other addresses have no effect and read 0.
#[test]
fn timing_registers_follow_the_register_table_three_ways() {
    use tdm_stepper::hdl::timing_regs::TimingRegs;
    use tdm_stepper::model::pulse::PulseTiming;
    let p = params();
    let limits = Limits { min_period_ticks: p.min_period };
    let names = ["STEP_HIGH", "STEP_LOW", "DIR_SETUP", "DIR_HOLD"];
    let mut regs_: Vec<TableReg> = names.iter().map(|n| TableReg::new(n, &p)).collect();
    let ours: Vec<u16> = regs_.iter().map(|r| r.addr).collect();
    let others = [regs::addr("CTRL"), regs::addr("QLOW_LEVEL"), regs::addr("ID_MIN_PERIOD"), a("T_LO", 0)];
    let mut rng = Rng(0x5eed_7133);
    // Rows: reset, wr, wr_addr, wr_data, locked, rd_addr.
    let mut rows: Vec<Vec<u128>> = vec![vec![1, 0, 0, 0, 0, 0]; 3];
    for _ in 0..4000 {
        let pick = |rng: &mut Rng| if rng.next() % 5 == 0 { others[(rng.next() % others.len() as u64) as usize] } else { ours[(rng.next() % ours.len() as u64) as usize] };
        let wr = (rng.next() % 3 == 0) as u64;
        let wa = pick(&mut rng);
        let data = match rng.next() % 8 {
            0 => 0,
            1 => 0xFFFF,
            _ => 1 + rng.next() % 30,
        };
        let locked = (rng.next() % 6 == 0) as u64;
        let ra = pick(&mut rng);
        let reset = (rng.next() % 900 == 0) as u64;
        rows.push([reset, wr, wa as u64, data, locked, ra as u64].map(|x| x as u128).to_vec());
    }
    let timing = |t: &[u16]| PulseTiming { step_high: t[0], step_low: t[1], dir_setup: t[2], dir_hold: t[3] };
    let mut t_prev = timing(&[1, 1, 1, 1]); // the values high_min and low_min were taken from
    let (mut hmin, mut lmin, mut ok) = (0u32, 0u32, false);
    let mut want = Vec::new();
    let (mut refusals, mut oks, mut not_oks) = (0, 0, 0);
    for (k, r) in rows.iter().enumerate() {
        let (reset, wr, wa, data, locked, ra) = (r[0] == 1, r[1] == 1, r[2] as u16, r[3] as u16, r[4] == 1, r[5] as u16);
        let rd = regs_.iter().find(|x| x.addr == ra).map_or(0, |x| x.value);
        let ours_w = wr && ours.contains(&wa);
        let refuse = ours_w && (locked || data == 0);
        refusals += refuse as usize;
        // The registers are defined after the first reset edge, high_min/low_min a
        // cycle later, timing_ok two (they have no reset).
        want.push(vec![
            (k >= 1).then_some(rd as u128),
            Some(refuse as u128),
            (k >= 2).then_some(hmin as u128),
            (k >= 2).then_some(lmin as u128),
            (k >= 3).then_some(ok as u128),
        ]);
        if k >= 3 {
            oks += ok as usize;
            not_oks += !ok as usize;
        }
        let now: Vec<u16> = regs_.iter().map(|x| x.value).collect();
        ok = t_prev.check(&limits).is_ok();
        t_prev = timing(&now);
        hmin = t_prev.high_min();
        lmin = t_prev.low_min();
        if ours_w && !refuse {
            let i = ours.iter().position(|&x| x == wa).unwrap();
            regs_[i].value = regs_[i].write(data);
        }
        if reset {
            regs_.iter_mut().for_each(|x| x.value = x.reset);
        }
    }
    assert!(refusals > 100 && oks > 500 && not_oks > 500, "refusals {refusals}, timing ok {oks}, not ok {not_oks}");
    let make = || {
        let mut u = TimingRegs::new(p.min_period);
        u.reset.connect();
        u.wr.connect();
        u.wr_addr.connect();
        u.wr_data.connect();
        u.locked.connect();
        u.rd_addr.connect();
        u.connect_all();
        u
    };
    let spec = TbSpec {
        clock: "clock".into(),
        inputs: vec![
            Port::new("reset", 1),
            Port::new("wr", 1),
            Port::new("wr_addr", ADDR_BITS),
            Port::new("wr_data", 16),
            Port::new("locked", 1),
            Port::new("rd_addr", ADDR_BITS),
        ],
        outputs: vec![
            Port::new("rd_data", 16),
            Port::new("refuse", 1),
            Port::new("high_min", 16),
            Port::new("low_min", 16),
            Port::new("timing_ok", 1),
        ],
    };
    three_ways(
        "timing_regs",
        make,
        |u, c| u.clock.next = Clock::from(c),
        |u, r| {
            u.reset.next = r[0] == 1;
            u.wr.next = r[1] == 1;
            u.wr_addr.next = (r[2] as u64).into();
            u.wr_data.next = (r[3] as u64).into();
            u.locked.next = r[4] == 1;
            u.rd_addr.next = (r[5] as u64).into();
        },
        |u| {
            vec![
                u.rd_data.val().to_u64() as u128,
                u.refuse.val() as u128,
                u.high_min.val().to_u64() as u128,
                u.low_min.val().to_u64() as u128,
                u.timing_ok.val() as u128,
            ]
        },
        &spec,
        &rows,
        &want,
    );
}

/// IdRegs in a clocked harness (the testbenches clock their unit): the block itself is
/// combinational.
#[derive(LogicBlock)]
struct IdHarness {
    clock: Signal<In, Clock>,
    rd_addr: Signal<In, Bits<ADDR_BITS>>,
    rd_data: Signal<Out, Bits<16>>,
    ids: tdm_stepper::hdl::id_regs::IdRegs,
    q: DFF<Bits<16>>,
}

impl Logic for IdHarness {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, q);
        self.ids.rd_addr.next = self.rd_addr.val();
        self.q.d.next = self.ids.rd_data.val();
        self.rd_data.next = self.q.q.val();
    }
}

/// IdRegs, three ways: every one of the 512 word addresses reads the register table's
/// value for an export with every option (K = 5, a 48 MHz clock, M = 97), and 0 where
/// the table has no identity register.
#[test]
fn identity_registers_read_the_register_table_three_ways() {
    use tdm_stepper::hdl::id_regs::{IdRegs, ID_REGISTERS};
    let p = CoreParams { axes: 5, clock_hz: 48_000_000, queue_depth: 8, fifo_depth: 4, t_calc: 31, min_period: 97, io: true, io_omit: 0, scurve: true, encoder: true };
    let ids: Vec<_> = regs::table_for(&p).into_iter().filter(|r| r.name.starts_with("ID_")).collect();
    assert_eq!(ids.iter().map(|r| r.name).collect::<Vec<_>>(), ID_REGISTERS, "IdRegs answers every ID_ register of the table");
    let rows: Vec<Vec<u128>> = (0..=512u128).map(|a| vec![a % 512]).collect();
    // The harness registers the read: row k shows address k − 1.
    let want: Vec<Vec<Option<u128>>> = (0..rows.len())
        .map(|k| {
            if k == 0 {
                return vec![None];
            }
            let a = (k - 1) as u16;
            vec![Some(ids.iter().find(|r| r.address(0) == a).map_or(0, |r| r.reset_value(&p)) as u128)]
        })
        .collect();
    assert!(want.iter().flatten().flatten().filter(|&&v| v != 0).count() >= 10, "the identity reads are mostly non-zero");
    let make = || {
        let mut u = IdHarness { clock: Default::default(), rd_addr: Default::default(), rd_data: Default::default(), ids: IdRegs::new(&p), q: Default::default() };
        u.rd_addr.connect();
        u.connect_all();
        u
    };
    let spec = TbSpec { clock: "clock".into(), inputs: vec![Port::new("rd_addr", ADDR_BITS)], outputs: vec![Port::new("rd_data", 16)] };
    three_ways(
        "id_regs",
        make,
        |u, c| u.clock.next = Clock::from(c),
        |u, r| u.rd_addr.next = (r[0] as u64).into(),
        |u| vec![u.rd_data.val().to_u64() as u128],
        &spec,
        &rows,
        &want,
    );
}
