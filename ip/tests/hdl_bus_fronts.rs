//! The bus front ends three ways, each in front of the real EXMC slave (which reads
//! `(addr << 7) ^ 0x5a3c` at every address).
//!
//! **SPI** ([`SpiFront`]): the protocol model ([`SpiSlaveModel`]) says which writes
//! and reads each frame makes and what MISO shows; rust-hdl must do exactly that; the
//! exported Verilog in Verilator and Icarus must equal rust-hdl cycle for cycle.
//! Frames come at the fastest documented timing (SCK = bus_clk/4, CS high 4 bus
//! clocks) in modes 0 and 3, and at slower random timings, with bad framing among them.
//!
//! **Wishbone and AXI4-Lite** ([`WbFront`], [`AxilFront`]): the protocol model
//! ([`wb_expect`], [`axil_expect`]) says each access's answer and the register access
//! it makes; rust-hdl, driven by a master with random waits, aborts and back-pressure,
//! must do exactly that; the exported Verilog in Verilator and Icarus must equal
//! rust-hdl cycle for cycle on the same inputs. The documented latencies (ACK, BVALID,
//! RVALID after the handshake) are measured.

mod common;

use common::*;
use rust_hdl::prelude::*;
use tdm_stepper::hdl::exmc::ExmcSlave;
use tdm_stepper::hdl::spi_front::SpiFront;
use tdm_stepper::regs::ADDR_BITS;
use tdm_stepper::verify::spi::{bits_of, header, read_frame, waveform, write_frame, SpiAccess, SpiSlaveModel, SpiTiming};
use tdm_stepper::verify::{run_rust_hdl, Port, TbSpec};
use tdm_stepper::export::ExportOptions;
use tdm_stepper::hdl::axil_front::{AxilFront, AXIL_ADDR_BITS, AXIL_READ_RESP, AXIL_WRITE_RESP};
use tdm_stepper::hdl::wb_front::{WbFront, WB_READ_ACK, WB_WRITE_ACK};
use tdm_stepper::verify::mmio::{axil_expect, wb_expect, AxilMaster, AxilOut, Resp, Txn, WbMaster, AXIL_INPUTS, WB_INPUTS};


/// The front end driving the EXMC slave, which returns [`value`] of the address it
/// reads.
#[derive(LogicBlock)]
struct SpiHarness {
    pub clock: Signal<In, Clock>,
    pub reset: Signal<In, Bit>,
    pub cs_n: Signal<In, Bit>,
    pub sck: Signal<In, Bit>,
    pub mosi: Signal<In, Bit>,
    pub irq: Signal<In, Bit>,
    pub miso: Signal<Out, Bit>,
    pub miso_oe: Signal<Out, Bit>,
    pub wr: Signal<Out, Bit>,
    pub wr_addr: Signal<Out, Bits<ADDR_BITS>>,
    pub wr_data: Signal<Out, Bits<16>>,
    pub rd: Signal<Out, Bit>,
    pub rd_addr: Signal<Out, Bits<ADDR_BITS>>,
    spi: SpiFront,
    exmc: ExmcSlave,
    mix: Constant<Bits<16>>,
}

const MIX: u16 = 0x5a3c;

/// What a register at `addr` reads as in the harness.
fn value(addr: u16) -> u16 {
    (addr << 7) ^ MIX
}

impl Default for SpiHarness {
    fn default() -> Self {
        SpiHarness {
            clock: Default::default(),
            reset: Default::default(),
            cs_n: Default::default(),
            sck: Default::default(),
            mosi: Default::default(),
            irq: Default::default(),
            miso: Default::default(),
            miso_oe: Default::default(),
            wr: Default::default(),
            wr_addr: Default::default(),
            wr_data: Default::default(),
            rd: Default::default(),
            rd_addr: Default::default(),
            spi: Default::default(),
            exmc: Default::default(),
            mix: Constant::new((MIX as u64).into()),
        }
    }
}

impl Logic for SpiHarness {
    #[hdl_gen]
    fn update(&mut self) {
        self.spi.clock.next = self.clock.val();
        self.spi.reset.next = self.reset.val();
        self.spi.cs_n.next = self.cs_n.val();
        self.spi.sck.next = self.sck.val();
        self.spi.mosi.next = self.mosi.val();
        self.spi.irq.next = self.irq.val();
        self.miso.next = self.spi.miso.val();
        self.miso_oe.next = self.spi.miso_oe.val();
        self.exmc.clock.next = self.clock.val();
        self.exmc.reset.next = self.reset.val();
        self.exmc.ne.next = self.spi.ne.val();
        self.exmc.noe.next = self.spi.noe.val();
        self.exmc.nwe.next = self.spi.nwe.val();
        self.exmc.addr.next = self.spi.addr.val();
        self.exmc.data_in.next = self.spi.wdata.val();
        self.spi.rdata.next = self.exmc.data_out.val();
        self.exmc.rd_data.next = (bit_cast::<16, ADDR_BITS>(self.exmc.rd_addr.val()) << 7) ^ self.mix.val();
        self.wr.next = self.exmc.wr.val();
        self.wr_addr.next = self.exmc.wr_addr.val();
        self.wr_data.next = self.exmc.wr_data.val();
        self.rd.next = self.exmc.rd.val();
        self.rd_addr.next = self.exmc.rd_addr.val();
    }
}

fn uut() -> SpiHarness {
    let mut u = SpiHarness::default();
    u.clock.connect();
    u.reset.connect();
    u.cs_n.connect();
    u.sck.connect();
    u.mosi.connect();
    u.irq.connect();
    u.connect_all();
    u
}

const IN: [(&str, usize); 5] = [("reset", 1), ("cs_n", 1), ("sck", 1), ("mosi", 1), ("irq", 1)];
const OUT: [(&str, usize); 7] =
    [("miso", 1), ("miso_oe", 1), ("wr", 1), ("wr_addr", ADDR_BITS), ("wr_data", 16), ("rd", 1), ("rd_addr", ADDR_BITS)];

fn spec() -> TbSpec {
    TbSpec {
        clock: "clock".into(),
        inputs: IN.iter().map(|(n, w)| Port::new(n, *w)).collect(),
        outputs: OUT.iter().map(|(n, w)| Port::new(n, *w)).collect(),
    }
}

/// A mix of frames: good writes and reads of 1 to 6 words (with and without INC),
/// status polls, and bad framing.
fn frames(rng: &mut Rng, n: usize) -> Vec<Vec<bool>> {
    let mut v = vec![];
    for _ in 0..n {
        let len = 1 + (rng.next() % 6) as usize;
        let inc = rng.next() % 4 != 0;
        let addr = (rng.next() % 0x200) as u16;
        let addr = if inc { addr.min(0x200 - len as u16) } else { addr };
        let words: Vec<u16> = (0..len).map(|_| rng.next() as u16).collect();
        let f = match rng.next() % 12 {
            0..=3 => bits_of(&write_frame(addr, inc, &words)),
            4..=6 => bits_of(&read_frame(addr, inc, len)),
            // A status poll (one byte), and an empty frame.
            7 => bits_of(&[0]),
            8 => vec![],
            // CS raised mid-word (a write or a read), or a few bits into the header.
            9 => {
                let mut b = if rng.next() % 2 == 0 { bits_of(&write_frame(addr, inc, &words)) } else { bits_of(&read_frame(addr, inc, len)) };
                let cut = 1 + (rng.next() as usize % (b.len() - 1));
                b.truncate(if cut == 8 || cut % 16 == 0 { cut + 1 } else { cut });
                b
            }
            // One word too many.
            10 => {
                let mut b = bits_of(&header(true, inc, len, addr));
                for w in words.iter().chain(std::iter::once(&0xbeef)) {
                    b.extend(bits_of(&w.to_be_bytes()));
                }
                b
            }
            // A burst past the last address.
            _ => bits_of(&write_frame(0x200 - len as u16, true, &[words.clone(), vec![7]].concat())),
        };
        v.push(f);
    }
    v
}

/// Rows (reset, cs_n, sck, mosi, irq) for `frames` at `timing` (each frame with its
/// own timing and irq level), after 4 rows of reset; the rows where MISO is sampled.
fn rows_for(frames: &[(Vec<bool>, SpiTiming, bool)]) -> (Vec<Vec<u128>>, Vec<usize>) {
    let mut rows: Vec<Vec<u128>> = vec![vec![1, 1, 0, 0, 0]; 4];
    let mut samples = vec![];
    for (f, t, irq) in frames {
        let idle = t.mode == 3;
        let start = rows.len() as u64;
        // The irq level changes as the gap before the frame starts.
        for _ in 0..t.gap {
            rows.push(vec![0, 1, idle as u128, 0, *irq as u128]);
        }
        let (w, end) = waveform(std::slice::from_ref(f), *t, start + t.gap);
        let mut pins = [true, idle, false];
        let mut k = 0;
        for time in start + t.gap..end {
            while k < w.len() && w[k].0 == time {
                pins = w[k].1;
                if w[k].2 {
                    samples.push(rows.len());
                }
                k += 1;
            }
            rows.push(vec![0, pins[0] as u128, pins[1] as u128, pins[2] as u128, *irq as u128]);
        }
    }
    for _ in 0..12 {
        rows.push(vec![0, 1, 0, 0, 0]);
    }
    (rows, samples)
}

#[test]
fn frames_make_the_models_accesses_three_ways() {
    let mut rng = Rng(0x5b1_f407);
    let mut all = vec![];
    for (i, f) in frames(&mut rng, 70).into_iter().enumerate() {
        let irq = rng.next() % 3 == 0;
        let t = match i % 3 {
            0 => SpiTiming::fastest(0),
            1 => SpiTiming::fastest(3),
            _ => {
                let r = |rng: &mut Rng, lo: u64| lo + rng.next() % 4;
                SpiTiming { mode: (rng.next() % 2 * 3) as u8, low: r(&mut rng, 2), high: r(&mut rng, 2), lead: r(&mut rng, 1), lag: r(&mut rng, 1), gap: r(&mut rng, 4) }
            }
        };
        all.push((f, t, irq));
    }
    let (rows, samples) = rows_for(&all);

    // The model: accesses in order, MISO bit by bit.
    let mut model = SpiSlaveModel::default();
    let mut want_acc = vec![];
    let mut want_miso = vec![];
    let mut errs = 0;
    for (f, _, irq) in &all {
        let r = model.frame(f, *irq, value);
        errs += r.err as usize;
        want_acc.extend(r.accesses);
        want_miso.extend(r.miso);
    }
    assert!(errs >= 10 && errs < all.len() / 2, "{errs} bad frames of {}", all.len());
    assert!(want_acc.iter().filter(|a| matches!(a, SpiAccess::Read { .. })).count() > 30);

    let got = run_rust_hdl(
        &mut uut(),
        &rows,
        |u, c| u.clock.next = Clock::from(c),
        |u, r| {
            u.reset.next = r[0] == 1;
            u.cs_n.next = r[1] == 1;
            u.sck.next = r[2] == 1;
            u.mosi.next = r[3] == 1;
            u.irq.next = r[4] == 1;
        },
        |u| {
            vec![
                u.miso.val() as u128,
                u.miso_oe.val() as u128,
                u.wr.val() as u128,
                u.wr_addr.val().to_u64() as u128,
                u.wr_data.val().to_u64() as u128,
                u.rd.val() as u128,
                u.rd_addr.val().to_u64() as u128,
            ]
        },
    );
    let mut got_acc = vec![];
    for o in &got {
        if o[2] == 1 {
            got_acc.push(SpiAccess::Write { addr: o[3] as u16, data: o[4] as u16 });
        }
        if o[5] == 1 {
            got_acc.push(SpiAccess::Read { addr: o[6] as u16 });
        }
    }
    assert_eq!(got_acc.len(), want_acc.len(), "rust-hdl: number of accesses");
    for (k, (g, w)) in got_acc.iter().zip(&want_acc).enumerate() {
        assert_eq!(g, w, "rust-hdl: access {k}");
    }
    let got_miso: Vec<bool> = samples.iter().map(|&r| got[r][0] == 1).collect();
    assert_eq!(got_miso.len(), want_miso.len());
    for (k, (g, w)) in got_miso.iter().zip(&want_miso).enumerate() {
        assert_eq!(g, w, "rust-hdl: MISO bit {k} (row {})", samples[k]);
    }
    for (k, (o, r)) in got.iter().zip(&rows).enumerate() {
        assert_eq!(o[1], 1 - r[1], "miso_oe at row {k}");
    }

    let verilog = generate_verilog(&uut());
    verilog_matches_rust_hdl("spi_front", &verilog, &spec(), &rows, &got, 8);
}

// ---- Wishbone and AXI4-Lite ------------------------------------------------



/// The EXMC slave's side, seen from the harness: wr, wr_addr, wr_data, rd, rd_addr.
const SLAVE_OUT: [(&str, usize); 5] = [("wr", 1), ("wr_addr", ADDR_BITS), ("wr_data", 16), ("rd", 1), ("rd_addr", ADDR_BITS)];

#[derive(LogicBlock)]
struct WbHarness {
    pub clock: Signal<In, Clock>,
    pub reset: Signal<In, Bit>,
    pub wb_cyc: Signal<In, Bit>,
    pub wb_stb: Signal<In, Bit>,
    pub wb_we: Signal<In, Bit>,
    pub wb_adr: Signal<In, Bits<ADDR_BITS>>,
    pub wb_sel: Signal<In, Bits<4>>,
    pub wb_dat_w: Signal<In, Bits<32>>,
    pub wb_dat_r: Signal<Out, Bits<32>>,
    pub wb_ack: Signal<Out, Bit>,
    pub wb_err: Signal<Out, Bit>,
    pub wr: Signal<Out, Bit>,
    pub wr_addr: Signal<Out, Bits<ADDR_BITS>>,
    pub wr_data: Signal<Out, Bits<16>>,
    pub rd: Signal<Out, Bit>,
    pub rd_addr: Signal<Out, Bits<ADDR_BITS>>,
    wb: WbFront,
    exmc: ExmcSlave,
    mix: Constant<Bits<16>>,
}

impl Logic for WbHarness {
    #[hdl_gen]
    fn update(&mut self) {
        self.wb.clock.next = self.clock.val();
        self.wb.reset.next = self.reset.val();
        self.wb.wb_cyc.next = self.wb_cyc.val();
        self.wb.wb_stb.next = self.wb_stb.val();
        self.wb.wb_we.next = self.wb_we.val();
        self.wb.wb_adr.next = self.wb_adr.val();
        self.wb.wb_sel.next = self.wb_sel.val();
        self.wb.wb_dat_w.next = self.wb_dat_w.val();
        self.wb_dat_r.next = self.wb.wb_dat_r.val();
        self.wb_ack.next = self.wb.wb_ack.val();
        self.wb_err.next = self.wb.wb_err.val();
        self.exmc.clock.next = self.clock.val();
        self.exmc.reset.next = self.reset.val();
        self.exmc.ne.next = self.wb.ne.val();
        self.exmc.noe.next = self.wb.noe.val();
        self.exmc.nwe.next = self.wb.nwe.val();
        self.exmc.addr.next = self.wb.addr.val();
        self.exmc.data_in.next = self.wb.wdata.val();
        self.wb.rdata.next = self.exmc.data_out.val();
        self.exmc.rd_data.next = (bit_cast::<16, ADDR_BITS>(self.exmc.rd_addr.val()) << 7) ^ self.mix.val();
        self.wr.next = self.exmc.wr.val();
        self.wr_addr.next = self.exmc.wr_addr.val();
        self.wr_data.next = self.exmc.wr_data.val();
        self.rd.next = self.exmc.rd.val();
        self.rd_addr.next = self.exmc.rd_addr.val();
    }
}

#[derive(LogicBlock)]
struct AxilHarness {
    pub clock: Signal<In, Clock>,
    pub reset: Signal<In, Bit>,
    pub awvalid: Signal<In, Bit>,
    pub awaddr: Signal<In, Bits<AXIL_ADDR_BITS>>,
    pub wvalid: Signal<In, Bit>,
    pub wdata: Signal<In, Bits<32>>,
    pub wstrb: Signal<In, Bits<4>>,
    pub bready: Signal<In, Bit>,
    pub arvalid: Signal<In, Bit>,
    pub araddr: Signal<In, Bits<AXIL_ADDR_BITS>>,
    pub rready: Signal<In, Bit>,
    pub awready: Signal<Out, Bit>,
    pub wready: Signal<Out, Bit>,
    pub bvalid: Signal<Out, Bit>,
    pub bresp: Signal<Out, Bits<2>>,
    pub arready: Signal<Out, Bit>,
    pub rvalid: Signal<Out, Bit>,
    pub rdata: Signal<Out, Bits<32>>,
    pub rresp: Signal<Out, Bits<2>>,
    pub wr: Signal<Out, Bit>,
    pub wr_addr: Signal<Out, Bits<ADDR_BITS>>,
    pub wr_data: Signal<Out, Bits<16>>,
    pub rd: Signal<Out, Bit>,
    pub rd_addr: Signal<Out, Bits<ADDR_BITS>>,
    axil: AxilFront,
    exmc: ExmcSlave,
    mix: Constant<Bits<16>>,
}

impl Logic for AxilHarness {
    #[hdl_gen]
    fn update(&mut self) {
        self.axil.clock.next = self.clock.val();
        self.axil.reset.next = self.reset.val();
        self.axil.awvalid.next = self.awvalid.val();
        self.axil.awaddr.next = self.awaddr.val();
        self.axil.wvalid.next = self.wvalid.val();
        self.axil.wdata.next = self.wdata.val();
        self.axil.wstrb.next = self.wstrb.val();
        self.axil.bready.next = self.bready.val();
        self.axil.arvalid.next = self.arvalid.val();
        self.axil.araddr.next = self.araddr.val();
        self.axil.rready.next = self.rready.val();
        self.awready.next = self.axil.awready.val();
        self.wready.next = self.axil.wready.val();
        self.bvalid.next = self.axil.bvalid.val();
        self.bresp.next = self.axil.bresp.val();
        self.arready.next = self.axil.arready.val();
        self.rvalid.next = self.axil.rvalid.val();
        self.rdata.next = self.axil.rdata.val();
        self.rresp.next = self.axil.rresp.val();
        self.exmc.clock.next = self.clock.val();
        self.exmc.reset.next = self.reset.val();
        self.exmc.ne.next = self.axil.ne.val();
        self.exmc.noe.next = self.axil.noe.val();
        self.exmc.nwe.next = self.axil.nwe.val();
        self.exmc.addr.next = self.axil.x_addr.val();
        self.exmc.data_in.next = self.axil.x_wdata.val();
        self.axil.x_rdata.next = self.exmc.data_out.val();
        self.exmc.rd_data.next = (bit_cast::<16, ADDR_BITS>(self.exmc.rd_addr.val()) << 7) ^ self.mix.val();
        self.wr.next = self.exmc.wr.val();
        self.wr_addr.next = self.exmc.wr_addr.val();
        self.wr_data.next = self.exmc.wr_data.val();
        self.rd.next = self.exmc.rd.val();
        self.rd_addr.next = self.exmc.rd_addr.val();
    }
}

/// The export whose map the fronts decode: K = 3 with the machine I/O (per-axis
/// blocks with holes, axes 3..15 unmapped).
fn mapped() -> Vec<bool> {
    tdm_stepper::regs::mapped(&ExportOptions { axes: 3, io: true, ..Default::default() }.params())
}

fn wb_uut(mapped: &[bool]) -> WbHarness {
    let mut u = WbHarness {
        clock: Default::default(),
        reset: Default::default(),
        wb_cyc: Default::default(),
        wb_stb: Default::default(),
        wb_we: Default::default(),
        wb_adr: Default::default(),
        wb_sel: Default::default(),
        wb_dat_w: Default::default(),
        wb_dat_r: Default::default(),
        wb_ack: Default::default(),
        wb_err: Default::default(),
        wr: Default::default(),
        wr_addr: Default::default(),
        wr_data: Default::default(),
        rd: Default::default(),
        rd_addr: Default::default(),
        wb: WbFront::new(mapped),
        exmc: Default::default(),
        mix: Constant::new((MIX as u64).into()),
    };
    u.clock.connect();
    for p in [&mut u.reset, &mut u.wb_cyc, &mut u.wb_stb, &mut u.wb_we] {
        p.connect();
    }
    u.wb_adr.connect();
    u.wb_sel.connect();
    u.wb_dat_w.connect();
    u.connect_all();
    u
}

fn axil_uut(mapped: &[bool]) -> AxilHarness {
    let mut u = AxilHarness {
        clock: Default::default(),
        reset: Default::default(),
        awvalid: Default::default(),
        awaddr: Default::default(),
        wvalid: Default::default(),
        wdata: Default::default(),
        wstrb: Default::default(),
        bready: Default::default(),
        arvalid: Default::default(),
        araddr: Default::default(),
        rready: Default::default(),
        awready: Default::default(),
        wready: Default::default(),
        bvalid: Default::default(),
        bresp: Default::default(),
        arready: Default::default(),
        rvalid: Default::default(),
        rdata: Default::default(),
        rresp: Default::default(),
        wr: Default::default(),
        wr_addr: Default::default(),
        wr_data: Default::default(),
        rd: Default::default(),
        rd_addr: Default::default(),
        axil: AxilFront::new(mapped),
        exmc: Default::default(),
        mix: Constant::new((MIX as u64).into()),
    };
    u.clock.connect();
    for p in [&mut u.reset, &mut u.awvalid, &mut u.wvalid, &mut u.bready, &mut u.arvalid, &mut u.rready] {
        p.connect();
    }
    u.awaddr.connect();
    u.araddr.connect();
    u.wdata.connect();
    u.wstrb.connect();
    u.connect_all();
    u
}

/// A hand-written clock loop whose inputs come from `master` (row k from the outputs
/// of row k − 1), after 4 rows of reset; it runs until the master is done, then 16
/// idle rows. Returns the rows and the outputs.
fn run_reactive<B: Block>(
    uut: &mut B,
    idle: Vec<u128>,
    set: impl Fn(&mut B, &[u128]),
    get: impl Fn(&B) -> Vec<u128>,
    mut master: impl FnMut(u64, &[u128]) -> Option<Vec<u128>>,
    clock: impl Fn(&mut B, bool),
) -> (Vec<Vec<u128>>, Vec<Vec<u128>>) {
    let mut rows = vec![];
    let mut outs: Vec<Vec<u128>> = vec![];
    let mut tail = 0;
    let mut reset_row = idle.clone();
    reset_row[0] = 1;
    loop {
        let k = rows.len() as u64;
        let row = if k < 4 {
            reset_row.clone()
        } else {
            match master(k, outs.last().unwrap()) {
                Some(r) => r,
                None => {
                    tail += 1;
                    idle.clone()
                }
            }
        };
        if tail > 16 {
            break;
        }
        assert!(k < 200_000, "the master did not finish");
        set(uut, &row);
        clock(uut, false);
        assert!(simulate(uut, 100), "rust-hdl simulation did not settle");
        outs.push(get(uut));
        clock(uut, true);
        assert!(simulate(uut, 100), "rust-hdl simulation did not settle");
        rows.push(row);
    }
    (rows, outs)
}

/// The register accesses the EXMC slave made (its wr and rd pulses), from the last
/// five outputs of each row.
fn accesses(outs: &[Vec<u128>]) -> Vec<SpiAccess> {
    let n = outs[0].len();
    let mut v = vec![];
    for o in outs {
        let s = &o[n - 5..];
        if s[0] == 1 {
            v.push(SpiAccess::Write { addr: s[1] as u16, data: s[2] as u16 });
        }
        if s[3] == 1 {
            v.push(SpiAccess::Read { addr: s[4] as u16 });
        }
    }
    v
}

/// Random accesses: mostly mapped registers, some unmapped, writes with every strobe
/// pattern.
fn txns(rng: &mut Rng, mapped: &[bool], n: usize, write: Option<bool>) -> Vec<Txn> {
    let regs: Vec<u16> = (0..mapped.len() as u16).filter(|&a| mapped[a as usize]).collect();
    let holes: Vec<u16> = (0..mapped.len() as u16).filter(|&a| !mapped[a as usize]).collect();
    (0..n)
        .map(|_| {
            let addr = if rng.next() % 6 == 0 { holes[rng.next() as usize % holes.len()] } else { regs[rng.next() as usize % regs.len()] };
            let strb = if rng.next() % 4 == 0 { (rng.next() % 16) as u8 } else { 0xf };
            Txn { write: write.unwrap_or(rng.next() % 2 == 0), addr, data: rng.next() as u32, strb }
        })
        .collect()
}

fn mmio_spec(inputs: &[(&str, usize)], outputs: &[(&str, usize)]) -> TbSpec {
    TbSpec {
        clock: "clock".into(),
        inputs: inputs.iter().map(|(n, w)| Port::new(n, *w)).collect(),
        outputs: outputs.iter().chain(SLAVE_OUT.iter()).map(|(n, w)| Port::new(n, *w)).collect(),
    }
}

fn slave_outs(wr: bool, wa: u64, wd: u64, rd: bool, ra: u64) -> [u128; 5] {
    [wr as u128, wa as u128, wd as u128, rd as u128, ra as u128]
}

#[test]
fn wishbone_accesses_are_the_models_three_ways() {
    let map = mapped();
    let mut rng = Rng(0x77b_0115);
    let list = txns(&mut rng, &map, 400, None);
    let mut m = WbMaster::new(list.clone(), 0x5eed, true);
    let mut uut = wb_uut(&map);
    let (rows, outs) = run_reactive(
        &mut uut,
        vec![0; WB_INPUTS.len()],
        |u, r| {
            u.reset.next = r[0] == 1;
            u.wb_cyc.next = r[1] == 1;
            u.wb_stb.next = r[2] == 1;
            u.wb_we.next = r[3] == 1;
            u.wb_adr.next = (r[4] as u64).into();
            u.wb_sel.next = (r[5] as u64).into();
            u.wb_dat_w.next = (r[6] as u64).into();
        },
        |u| {
            let mut o = vec![u.wb_dat_r.val().to_u64() as u128, u.wb_ack.val() as u128, u.wb_err.val() as u128];
            o.extend(slave_outs(u.wr.val(), u.wr_addr.val().to_u64(), u.wr_data.val().to_u64(), u.rd.val(), u.rd_addr.val().to_u64()));
            o
        },
        |k, o| if m.finished() { None } else { Some(m.step(k, o[1] == 1, o[2] == 1, o[0] as u32)) },
        |u, c| u.clock.next = Clock::from(c),
    );
    // Every answered access is the model's; aborted ones may have made their access.
    let mut want: Vec<(SpiAccess, bool)> = vec![];
    let (mut errs, mut aborted, mut reads) = (0, 0, 0);
    for (i, t) in list.iter().enumerate() {
        let (resp, acc) = wb_expect(&map, t, value);
        match m.got[i] {
            Some(g) => {
                assert_eq!(g, resp, "access {i} {t:?}");
                errs += (g == Resp::Err) as usize;
                reads += (!t.write && g != Resp::Err) as usize;
                if let Some(a) = acc {
                    want.push((a, false));
                }
            }
            None => {
                aborted += 1;
                if let Some(a) = acc {
                    want.push((a, true));
                }
            }
        }
    }
    assert!(errs > 40 && aborted > 10 && reads > 100, "{errs} refused, {aborted} aborted, {reads} reads");
    let got = accesses(&outs);
    let mut g = got.iter().peekable();
    for (k, (w, optional)) in want.iter().enumerate() {
        if g.peek() == Some(&w) {
            g.next();
        } else {
            assert!(optional, "expected access {k} {w:?}, the slave saw {:?}", g.peek());
        }
    }
    assert_eq!(g.next(), None, "an access the model does not make");
    // Latencies: ACK WB_WRITE_ACK / WB_READ_ACK cycles after STB rose, ERR 1 cycle,
    // for every access after one that was not aborted.
    let mut checked = 0;
    for i in 1..list.len() {
        let (Some(r), Some(_)) = (m.got[i], m.got[i - 1]) else { continue };
        let want = match r {
            Resp::Err => 1,
            _ if list[i].write => WB_WRITE_ACK,
            _ => WB_READ_ACK,
        };
        assert_eq!(m.answered[i] - m.started[i], want, "latency of access {i} {:?}", list[i]);
        checked += 1;
    }
    assert!(checked > 300);

    let verilog = generate_verilog(&wb_uut(&map));
    let s = mmio_spec(&WB_INPUTS, &[("wb_dat_r", 32), ("wb_ack", 1), ("wb_err", 1)]);
    verilog_matches_rust_hdl("wb_front", &verilog, &s, &rows, &outs, 4);
}

/// Drives one row of AXI4-Lite inputs (in `AXIL_INPUTS` order) into the harness.
fn axil_set(u: &mut AxilHarness, r: &[u128]) {
    u.reset.next = r[0] == 1;
    u.awvalid.next = r[1] == 1;
    u.awaddr.next = (r[2] as u64).into();
    u.wvalid.next = r[3] == 1;
    u.wdata.next = (r[4] as u64).into();
    u.wstrb.next = (r[5] as u64).into();
    u.bready.next = r[6] == 1;
    u.arvalid.next = r[7] == 1;
    u.araddr.next = (r[8] as u64).into();
    u.rready.next = r[9] == 1;
}

#[test]
fn axi_lite_accesses_are_the_models_three_ways() {
    let map = mapped();
    let mut rng = Rng(0xa41_1173);
    let writes = txns(&mut rng, &map, 300, Some(true));
    let reads = txns(&mut rng, &map, 300, Some(false));
    let mut m = AxilMaster::new(writes.clone(), reads.clone(), 0xfeed);
    let mut uut = axil_uut(&map);
    let idle = vec![0u128; AXIL_INPUTS.len()];
    let mut both_full = 0;
    let (rows, outs) = run_reactive(
        &mut uut,
        idle,
        axil_set,
        |u| {
            let mut o = vec![
                u.awready.val() as u128,
                u.wready.val() as u128,
                u.bvalid.val() as u128,
                u.bresp.val().to_u64() as u128,
                u.arready.val() as u128,
                u.rvalid.val() as u128,
                u.rdata.val().to_u64() as u128,
                u.rresp.val().to_u64() as u128,
            ];
            o.extend(slave_outs(u.wr.val(), u.wr_addr.val().to_u64(), u.wr_data.val().to_u64(), u.rd.val(), u.rd_addr.val().to_u64()));
            o
        },
        |_, o| {
            if o[0] == 0 && o[4] == 0 {
                both_full += 1;
            }
            let out = AxilOut {
                awready: o[0] == 1,
                wready: o[1] == 1,
                bvalid: o[2] == 1,
                bresp: o[3] as u8,
                arready: o[4] == 1,
                rvalid: o[5] == 1,
                rdata: o[6] as u32,
                rresp: o[7] as u8,
            };
            if m.finished() {
                None
            } else {
                Some(m.step(out))
            }
        },
        |u, c| u.clock.next = Clock::from(c),
    );
    assert!(both_full > 50, "a write and a read outstanding together only {both_full} cycles");
    let want_b: Vec<(Resp, Option<SpiAccess>)> = writes.iter().map(|t| axil_expect(&map, t, value)).collect();
    let want_r: Vec<(Resp, Option<SpiAccess>)> = reads.iter().map(|t| axil_expect(&map, t, value)).collect();
    assert_eq!(m.b_got, want_b.iter().map(|w| w.0).collect::<Vec<_>>(), "write responses");
    assert_eq!(m.r_got, want_r.iter().map(|w| w.0).collect::<Vec<_>>(), "read responses and data");
    let got = accesses(&outs);
    let got_w: Vec<SpiAccess> = got.iter().copied().filter(|a| matches!(a, SpiAccess::Write { .. })).collect();
    let got_r: Vec<SpiAccess> = got.iter().copied().filter(|a| matches!(a, SpiAccess::Read { .. })).collect();
    assert_eq!(got_w, want_b.iter().filter_map(|w| w.1).collect::<Vec<_>>(), "the writes the slave saw");
    assert_eq!(got_r, want_r.iter().filter_map(|w| w.1).collect::<Vec<_>>(), "the reads the slave saw");
    let errs = m.b_got.iter().chain(&m.r_got).filter(|r| **r == Resp::Err).count();
    assert!(errs > 60 && got_w.len() > 150 && got_r.len() > 200, "{errs} refused, {} writes, {} reads", got_w.len(), got_r.len());

    let verilog = generate_verilog(&axil_uut(&map));
    let s = mmio_spec(
        &AXIL_INPUTS,
        &[("awready", 1), ("wready", 1), ("bvalid", 1), ("bresp", 2), ("arready", 1), ("rvalid", 1), ("rdata", 32), ("rresp", 2)],
    );
    verilog_matches_rust_hdl("axil_front", &verilog, &s, &rows, &outs, 4);
}

/// The documented AXI4-Lite latencies with the ready signals high: BVALID
/// AXIL_WRITE_RESP cycles after AW and W are taken, RVALID AXIL_READ_RESP after AR,
/// and a refused read 2 cycles after.
#[test]
fn axi_lite_latencies_are_as_documented() {
    let map = mapped();
    let reg = (0..512).find(|&a| map[a]).unwrap() as u128;
    let hole = (0..512).find(|&a| !map[a]).unwrap() as u128;
    let mut rows: Vec<Vec<u128>> = vec![vec![1, 0, 0, 0, 0, 0, 1, 0, 0, 1]; 4];
    let idle = vec![0, 0, 0, 0, 0, 0, 1, 0, 0, 1];
    // After the reset's synchroniser: a write at row 10, a read at row 30, a read of a
    // hole at row 50 (each handshake taken in its row: the buffers are empty).
    rows.extend(std::iter::repeat_n(idle.clone(), 6));
    rows.push(vec![0, 1, reg << 2, 1, 0x1234, 0xf, 1, 0, 0, 1]);
    rows.extend(std::iter::repeat_n(idle.clone(), 19));
    rows.push(vec![0, 0, 0, 0, 0, 0, 1, 1, reg << 2, 1]);
    rows.extend(std::iter::repeat_n(idle.clone(), 19));
    rows.push(vec![0, 0, 0, 0, 0, 0, 1, 1, hole << 2, 1]);
    rows.extend(std::iter::repeat_n(idle, 12));
    let outs = run_rust_hdl(
        &mut axil_uut(&map),
        &rows,
        |u, c| u.clock.next = Clock::from(c),
        axil_set,
        |u| vec![u.bvalid.val() as u128, u.rvalid.val() as u128, u.rresp.val().to_u64() as u128, u.rdata.val().to_u64() as u128],
    );
    let first = |col: usize, from: usize| (from..outs.len()).find(|&k| outs[k][col] == 1).unwrap();
    assert_eq!(first(0, 10) - 10, AXIL_WRITE_RESP as usize, "BVALID after the write");
    let r = first(1, 30);
    assert_eq!(r - 30, AXIL_READ_RESP as usize, "RVALID after the read");
    assert_eq!(outs[r][2..], [0, value(reg as u16) as u128], "OKAY and the register's value");
    let h = first(1, 50);
    assert_eq!(h - 50, 2, "RVALID after the read of a hole");
    assert_eq!(outs[h][2..], [2, 0], "SLVERR, data 0");
}
