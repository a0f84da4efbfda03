//! The SPI front end ([`SpiFront`]) three ways, in front of the real EXMC slave: the
//! protocol model ([`SpiSlaveModel`]) says which writes and reads each frame makes
//! and what MISO shows; rust-hdl must do exactly that; the exported Verilog in
//! Verilator and Icarus must equal rust-hdl cycle for cycle. Frames come at the
//! fastest documented timing (SCK = bus_clk/4, CS high 4 bus clocks) in modes 0 and
//! 3, and at slower random timings, with bad framing among them.

mod common;

use common::*;
use rust_hdl::prelude::*;
use tdm_stepper::hdl::exmc::ExmcSlave;
use tdm_stepper::hdl::spi_front::SpiFront;
use tdm_stepper::regs::ADDR_BITS;
use tdm_stepper::verify::spi::{bits_of, header, read_frame, waveform, write_frame, SpiAccess, SpiSlaveModel, SpiTiming};
use tdm_stepper::verify::{run_rust_hdl, Port, TbSpec};

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
