//! The SPI front end's protocol (docs/registers.md, "SPI"): the frame builders a host
//! uses, the slave's model at the bit level ([`SpiSlaveModel`], what
//! [`crate::hdl::spi_front::SpiFront`] must do), and an SPI master that turns frames
//! into pin waveforms ([`SpiTiming`], [`waveform`]) for the block's tests (one row
//! per bus clock) and for the whole core ([`SpiBus`], events in picoseconds for
//! [`super::system`]).

use super::system::{BusEvent, SystemSpec, SystemTrace};
use super::tb::Port;
use crate::model::Segment;
use crate::regs;

pub use crate::regs::{SPI_MAX_BURST as MAX_BURST, SPI_STATUS_PATTERN as STATUS_PATTERN};

/// The command byte and address byte of a frame.
pub fn header(write: bool, inc: bool, len: usize, addr: u16) -> [u8; 2] {
    assert!((1..=MAX_BURST).contains(&len), "burst length {len} outside 1..=32");
    assert!(addr < 0x200, "address {addr:#x} outside the map");
    [(write as u8) << 7 | (inc as u8) << 6 | ((len - 1) as u8) << 1 | (addr >> 8) as u8, addr as u8]
}

/// A write frame: the header and the words, MSB first.
pub fn write_frame(addr: u16, inc: bool, words: &[u16]) -> Vec<u8> {
    let mut v = header(true, inc, words.len(), addr).to_vec();
    for w in words {
        v.extend(w.to_be_bytes());
    }
    v
}

/// A read frame of `len` words: the header, the turnaround byte and 2·len bytes of
/// zeros the host clocks out while the words come back.
pub fn read_frame(addr: u16, inc: bool, len: usize) -> Vec<u8> {
    let mut v = header(false, inc, len, addr).to_vec();
    v.resize(3 + 2 * len, 0);
    v
}

/// Bytes to bits, MSB first.
pub fn bits_of(bytes: &[u8]) -> Vec<bool> {
    bytes.iter().flat_map(|b| (0..8).rev().map(move |i| b >> i & 1 == 1)).collect()
}

/// Bits (MSB first) to bytes; a last partial byte is padded with zeros.
pub fn bytes_of(bits: &[bool]) -> Vec<u8> {
    bits.chunks(8).map(|c| c.iter().enumerate().fold(0u8, |a, (i, &b)| a | (b as u8) << (7 - i))).collect()
}

/// One register access the front end makes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpiAccess {
    Write { addr: u16, data: u16 },
    Read { addr: u16 },
}

/// What one frame did.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SpiFrameResult {
    pub accesses: Vec<SpiAccess>,
    /// MISO, one bit per SCK edge of the frame.
    pub miso: Vec<bool>,
    /// FRAME_ERR, as the next frame's status byte shows it.
    pub err: bool,
}

/// The slave at the bit level: the frame rules, without the clocks.
#[derive(Clone, Debug, Default)]
pub struct SpiSlaveModel {
    /// FRAME_ERR of the last frame with at least one SCK edge.
    pub last_err: bool,
}

impl SpiSlaveModel {
    /// The status byte a frame starts with.
    pub fn status(&self, irq: bool) -> u8 {
        (irq as u8) << 7 | (self.last_err as u8) << 6 | STATUS_PATTERN
    }

    /// One frame of `mosi` bits (CS low, then high); `read` gives a register's value
    /// when the front end fetches it.
    pub fn frame(&mut self, mosi: &[bool], irq: bool, mut read: impl FnMut(u16) -> u16) -> SpiFrameResult {
        let n = mosi.len();
        let mut miso = vec![false; n];
        let st = self.status(irq);
        for (i, m) in miso.iter_mut().enumerate().take(8) {
            *m = st >> (7 - i) & 1 == 1;
        }
        let mut accesses = vec![];
        let word_at = |from: usize| mosi[from..from + 16].iter().fold(0u16, |a, &b| a << 1 | b as u16);
        let err = if n < 16 {
            n != 0 && n != 8
        } else {
            let h = word_at(0);
            let (write, inc, len, addr) = (h >> 15 == 1, h >> 14 & 1 == 1, ((h >> 9) & 31) as usize + 1, h & 0x1ff);
            let at = |k: usize| addr + if inc { k as u16 } else { 0 };
            if at(len - 1) > 0x1ff {
                true
            } else if write {
                let whole = (n - 16) / 16;
                for k in 0..whole.min(len) {
                    accesses.push(SpiAccess::Write { addr: at(k), data: word_at(16 + 16 * k) });
                }
                n != 16 + 16 * len
            } else {
                for k in 0..len {
                    // Word 0 is fetched with the header, word k when word k − 1 starts out.
                    let fetched_at = if k == 0 { 16 } else { 24 + 16 * (k - 1) };
                    if n < fetched_at {
                        break;
                    }
                    let v = read(at(k));
                    accesses.push(SpiAccess::Read { addr: at(k) });
                    for i in 0..16 {
                        if let Some(m) = miso.get_mut(24 + 16 * k + i) {
                            *m = v >> (15 - i) & 1 == 1;
                        }
                    }
                }
                n != 24 + 16 * len
            }
        };
        if n > 0 {
            self.last_err = err;
        }
        SpiFrameResult { accesses, miso, err }
    }
}

/// An SPI master's timing, in units of the waveform (bus clocks for the block's rows,
/// picoseconds for the whole core).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SpiTiming {
    /// SPI mode: 0 (SCK idles low) or 3 (idles high). Both sample on rising edges.
    pub mode: u8,
    /// SCK low and high time.
    pub low: u64,
    pub high: u64,
    /// CS low to the first SCK edge, and the last rising edge to CS high.
    pub lead: u64,
    pub lag: u64,
    /// CS high between frames.
    pub gap: u64,
}

impl SpiTiming {
    /// The fastest documented timing, in bus clocks: SCK = bus_clk/4, CS high
    /// [`crate::hdl::spi_front::SPI_CS_HIGH_MIN`] bus clocks.
    pub fn fastest(mode: u8) -> SpiTiming {
        SpiTiming { mode, low: 2, high: 2, lead: 1, lag: 1, gap: crate::hdl::spi_front::SPI_CS_HIGH_MIN }
    }

    /// The same in picoseconds for a bus clock of half period `bus_half_ps`, scaled
    /// by `slow` (1 = the fastest).
    pub fn in_ps(self, bus_half_ps: u64, slow: u64) -> SpiTiming {
        let t = 2 * bus_half_ps * slow;
        SpiTiming { low: self.low * t, high: self.high * t, lead: self.lead * t, lag: self.lag * t, gap: self.gap * t, ..self }
    }
}

/// One pin change: time, (cs_n, sck, mosi), and whether the master samples MISO as
/// it is just before this change (at each rising SCK edge).
pub type PinChange = (u64, [bool; 3], bool);

/// The pins for `frames` (bits each) from time `start`, CS high before the first.
/// Returns the changes and the end time (after the last frame's gap).
pub fn waveform(frames: &[Vec<bool>], t: SpiTiming, start: u64) -> (Vec<PinChange>, u64) {
    assert!(t.mode == 0 || t.mode == 3, "SPI mode {} (0 or 3)", t.mode);
    let idle = t.mode == 3;
    let mut v: Vec<PinChange> = vec![];
    let mut now = start;
    for f in frames {
        v.push((now, [false, idle, false], false));
        now += t.lead;
        for &b in f {
            // The falling edge (or, in mode 0, the idle low) with the bit out, then the
            // rising edge, where the master samples MISO.
            v.push((now, [false, false, b], false));
            now += t.low;
            v.push((now, [false, true, b], true));
            now += t.high;
        }
        if !f.is_empty() {
            now -= t.high;
            now += t.lag.max(t.high);
            if !idle {
                v.push((now, [false, false, false], false));
                now += t.lag;
            }
        }
        v.push((now, [true, idle, false], false));
        now += t.gap;
    }
    (v, now)
}

/// A host on the SPI pins of the whole core: register accesses as frames, turned
/// into [`BusEvent`]s for [`super::system`] (inputs `reset`, `cs_n`, `sck`, `mosi`;
/// `miso` sampled at every rising SCK edge).
#[derive(Clone, Debug)]
pub struct SpiBus {
    pub timing: SpiTiming,
    events: Vec<BusEvent>,
    reset: bool,
    now: u64,
    /// Per frame: the index of its first sampled event and its bit count.
    frames: Vec<(usize, usize)>,
}

/// Handle of a read frame: [`SpiBus::words`] gives what it returned.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FrameId(usize);

/// The interface [`SpiBus`] drives.
pub fn spi_system_spec(module: &str, watch: Vec<Port>) -> SystemSpec {
    SystemSpec {
        module: module.to_string(),
        inputs: vec![Port::new("reset", 1), Port::new("cs_n", 1), Port::new("sck", 1), Port::new("mosi", 1)],
        watch,
        sample: Port::new("miso", 1),
    }
}

impl SpiBus {
    /// `timing` in picoseconds (each a multiple of 3 above 3 ps).
    pub fn new(timing: SpiTiming) -> SpiBus {
        let idle = timing.mode == 3;
        SpiBus {
            timing,
            events: vec![BusEvent { time_ps: 2, inputs: vec![1, 1, idle as u128, 0], sample: false }],
            reset: true,
            now: 2,
            frames: vec![],
        }
    }

    fn push(&mut self, t: u64, pins: [bool; 3], sample: bool) {
        let inputs = vec![self.reset as u128, pins[0] as u128, pins[1] as u128, pins[2] as u128];
        match self.events.last_mut() {
            Some(e) if e.time_ps == t => {
                e.inputs = inputs;
                e.sample |= sample;
            }
            _ => {
                assert!(self.events.last().is_none_or(|e| e.time_ps + 3 < t), "SPI events out of order or too close");
                self.events.push(BusEvent { time_ps: t, inputs, sample });
            }
        }
    }

    /// Holds reset for `ps`, then releases it.
    pub fn reset(&mut self, ps: u64) {
        self.reset = true;
        self.push(self.now, [true, self.timing.mode == 3, false], false);
        self.now += ps;
        self.reset = false;
        self.push(self.now, [true, self.timing.mode == 3, false], false);
        self.now += 3 * self.timing.gap.max(6);
    }

    /// Waits until `ps` (rounded up to the event grid: times ≡ 2 mod 3 ps).
    pub fn idle_until_ps(&mut self, ps: u64) {
        let t = self.now.max(ps);
        self.now = t + (3 - (t + 1) % 3) % 3;
    }

    pub fn now_ps(&self) -> u64 {
        self.now
    }

    /// One frame of `bytes`.
    pub fn frame(&mut self, bytes: &[u8]) -> FrameId {
        let bits = bits_of(bytes);
        let (w, end) = waveform(std::slice::from_ref(&bits), self.timing, self.now);
        let mut first_sample = None;
        for (t, p, s) in w {
            self.push(t, p, s);
            if s && first_sample.is_none() {
                first_sample = Some(self.events.len() - 1);
            }
        }
        self.frames.push((first_sample.unwrap_or(0), bits.len()));
        self.now = end;
        FrameId(self.frames.len() - 1)
    }

    pub fn write(&mut self, addr: u16, words: &[u16]) -> FrameId {
        self.frame(&write_frame(addr, true, words))
    }

    pub fn read(&mut self, addr: u16, len: usize) -> FrameId {
        self.frame(&read_frame(addr, true, len))
    }

    pub fn write_reg(&mut self, name: &str, axis: usize, data: u16) -> FrameId {
        self.write(regs::register(name).address(axis), &[data])
    }

    pub fn read_reg(&mut self, name: &str, axis: usize) -> FrameId {
        self.read(regs::register(name).address(axis), 1)
    }

    /// A segment push: V0, T and STEPS (six consecutive registers) in one frame.
    pub fn push_segment(&mut self, axis: usize, seg: &Segment) -> FrameId {
        let a = regs::register("V0_LO").address(axis);
        assert_eq!(regs::register("STEPS_HI").address(axis), a + 5, "the staging registers are consecutive");
        let w = |x: u32| [x as u16, (x >> 16) as u16];
        let v: Vec<u16> = [w(seg.v0_rate), w(seg.t_ticks), w(seg.steps as u32)].concat();
        self.write(a, &v)
    }

    pub fn events(&self) -> &[BusEvent] {
        &self.events
    }

    /// The MISO bits of frame `id` (None: a bit was undefined or not sampled).
    pub fn miso(&self, trace: &SystemTrace, id: FrameId) -> Option<Vec<bool>> {
        let (first, n) = self.frames[id.0];
        let samples: Vec<usize> = (first..self.events.len()).filter(|&i| self.events[i].sample).take(n).collect();
        if samples.len() != n {
            return None;
        }
        samples.iter().map(|&i| trace.samples.iter().find(|s| s.0 == i).and_then(|s| s.1).map(|v| v == 1)).collect()
    }

    /// The status byte and the words a read frame returned (for a write frame, its
    /// status byte and words of no meaning).
    pub fn words(&self, trace: &SystemTrace, id: FrameId) -> Option<(u8, Vec<u16>)> {
        let bytes = bytes_of(&self.miso(trace, id)?);
        // A read frame's words start after the turnaround byte (a write frame has none).
        let words = bytes.get(3..).unwrap_or(&[]).chunks_exact(2).map(|c| u16::from_be_bytes([c[0], c[1]])).collect();
        Some((bytes[0], words))
    }
}
