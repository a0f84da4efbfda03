//! The memory-mapped front ends' protocol: what one Wishbone or AXI4-Lite access must
//! do ([`wb_expect`], [`axil_expect`]: its response, its read data, the register
//! access it makes), and masters that drive [`crate::hdl::wb_front::WbFront`] and
//! [`crate::hdl::axil_front::AxilFront`] cycle by cycle with random waits and
//! back-pressure ([`WbMaster`], [`AxilMaster`]), recording what they got.
//!
//! A master sees the block's outputs of cycle k − 1 (sampled before that rising
//! edge, when the handshakes of that edge are decided) and drives the inputs of cycle
//! k, as a synchronous master does.

use super::spi::SpiAccess;
use crate::regs::ADDR_BITS;

/// One access from the host: a write of `data` with byte strobes `strb`, or a read.
/// `addr` is the register's word address.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Txn {
    pub write: bool,
    pub addr: u16,
    pub data: u32,
    pub strb: u8,
}

/// What an access answered: OKAY with its data (a write: 0), or an error (Wishbone
/// ERR, AXI SLVERR).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Resp {
    Ok(u32),
    Err,
}

/// Wishbone: an unmapped address, or a write without both SEL[1:0], is refused with
/// ERR and no access; else one access (a read answers its register in bits 15..0).
pub fn wb_expect(mapped: &[bool], t: &Txn, read: impl Fn(u16) -> u16) -> (Resp, Option<SpiAccess>) {
    if !mapped[t.addr as usize] || (t.write && t.strb & 3 != 3) {
        (Resp::Err, None)
    } else if t.write {
        (Resp::Ok(0), Some(SpiAccess::Write { addr: t.addr, data: t.data as u16 }))
    } else {
        (Resp::Ok(read(t.addr) as u32), Some(SpiAccess::Read { addr: t.addr }))
    }
}

/// AXI4-Lite: an unmapped address is SLVERR with no access (a read returns 0); a write
/// with WSTRB[1:0] = 01 or 10 is SLVERR with no access, with 00 OKAY with no access;
/// else one access.
pub fn axil_expect(mapped: &[bool], t: &Txn, read: impl Fn(u16) -> u16) -> (Resp, Option<SpiAccess>) {
    if !mapped[t.addr as usize] {
        return (Resp::Err, None);
    }
    match (t.write, t.strb & 3) {
        (true, 3) => (Resp::Ok(0), Some(SpiAccess::Write { addr: t.addr, data: t.data as u16 })),
        (true, 0) => (Resp::Ok(0), None),
        (true, _) => (Resp::Err, None),
        (false, _) => (Resp::Ok(read(t.addr) as u32), Some(SpiAccess::Read { addr: t.addr })),
    }
}

/// A tiny deterministic generator for the masters' waits.
#[derive(Clone, Debug)]
pub struct Lcg(pub u64);

impl Lcg {
    pub fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        self.0 >> 33
    }
    /// True with probability 1/n.
    pub fn one_in(&mut self, n: u64) -> bool {
        self.next() % n == 0
    }
    /// 62 random bits.
    pub fn wide(&mut self) -> u128 {
        (self.next() as u128) << 31 | self.next() as u128
    }
}

/// A Wishbone B4 classic master: each access waits 0..3 cycles before STB; with
/// `aborts`, now and then it drops CYC during an access (an abort: no answer).
#[derive(Clone, Debug)]
pub struct WbMaster {
    pub txns: Vec<Txn>,
    rng: Lcg,
    next: usize,
    wait: u64,
    active: bool,
    /// Per access: the answer (None: aborted), the cycle STB rose and the cycle of the
    /// answer (ACK or ERR high; for an abort, the last cycle with CYC high).
    pub got: Vec<Option<Resp>>,
    pub started: Vec<u64>,
    pub answered: Vec<u64>,
    abort_in: Option<u64>,
    aborts: bool,
}

/// Inputs of [`crate::hdl::wb_front::WbFront`]: reset, cyc, stb, we, adr, sel, dat_w.
pub const WB_INPUTS: [(&str, usize); 7] = [("reset", 1), ("wb_cyc", 1), ("wb_stb", 1), ("wb_we", 1), ("wb_adr", ADDR_BITS), ("wb_sel", 4), ("wb_dat_w", 32)];

impl WbMaster {
    pub fn new(txns: Vec<Txn>, seed: u64, aborts: bool) -> WbMaster {
        WbMaster { txns, rng: Lcg(seed), next: 0, wait: 0, active: false, got: vec![], started: vec![], answered: vec![], abort_in: None, aborts }
    }

    pub fn finished(&self) -> bool {
        self.next >= self.txns.len() && !self.active
    }

    /// The inputs of cycle `k`, from the outputs of cycle k − 1 (`ack`, `err`, `dat_r`).
    pub fn step(&mut self, k: u64, ack: bool, err: bool, dat_r: u32) -> Vec<u128> {
        if self.active && (ack || err) {
            self.got.push(Some(if ack { Resp::Ok(if self.txns[self.next].write { 0 } else { dat_r }) } else { Resp::Err }));
            self.answered.push(k - 1);
            self.active = false;
            self.next += 1;
            self.wait = self.rng.next() % 4;
        } else if self.active {
            if let Some(n) = self.abort_in.as_mut() {
                if *n == 0 {
                    self.got.push(None);
                    self.answered.push(k - 1);
                    self.active = false;
                    self.next += 1;
                    self.wait = 1 + self.rng.next() % 4;
                } else {
                    *n -= 1;
                }
            }
        }
        if !self.active && self.next < self.txns.len() {
            if self.wait > 0 {
                self.wait -= 1;
            } else {
                self.active = true;
                self.started.push(k);
                self.abort_in = if self.aborts && self.rng.one_in(12) { Some(self.rng.next() % 6) } else { None };
            }
        }
        if self.active {
            let t = self.txns[self.next];
            vec![0, 1, 1, t.write as u128, t.addr as u128, t.strb as u128, t.data as u128]
        } else {
            // Between accesses: idle, the other signals anything.
            let junk = self.rng.wide();
            vec![0, 0, junk & 1, junk >> 1 & 1, junk >> 2 & 0x1ff, junk >> 11 & 0xf, junk >> 15 & 0xffff_ffff]
        }
    }
}

/// Inputs of [`crate::hdl::axil_front::AxilFront`].
pub const AXIL_INPUTS: [(&str, usize); 10] = [
    ("reset", 1),
    ("awvalid", 1),
    ("awaddr", ADDR_BITS + 2),
    ("wvalid", 1),
    ("wdata", 32),
    ("wstrb", 4),
    ("bready", 1),
    ("arvalid", 1),
    ("araddr", ADDR_BITS + 2),
    ("rready", 1),
];

/// An AXI4-Lite master with independent write and read streams: each VALID comes after
/// 0..3 idle cycles (AW and W each on its own), BREADY and RREADY are low now and then
/// (back-pressure), and the next write (read) is offered while the last one's
/// response is still outstanding.
#[derive(Clone, Debug)]
pub struct AxilMaster {
    pub writes: Vec<Txn>,
    pub reads: Vec<Txn>,
    rng: Lcg,
    aw_next: usize,
    w_next: usize,
    ar_next: usize,
    aw_wait: u64,
    w_wait: u64,
    ar_wait: u64,
    aw_on: bool,
    w_on: bool,
    ar_on: bool,
    bready: bool,
    rready: bool,
    /// The responses, in order, and the cycles they were taken.
    pub b_got: Vec<Resp>,
    pub r_got: Vec<Resp>,
    /// The byte address bits 1..0 each access carries (ignored by the slave).
    low: Vec<u16>,
}

/// The outputs an [`AxilMaster`] reads.
#[derive(Clone, Copy, Debug, Default)]
pub struct AxilOut {
    pub awready: bool,
    pub wready: bool,
    pub bvalid: bool,
    pub bresp: u8,
    pub arready: bool,
    pub rvalid: bool,
    pub rdata: u32,
    pub rresp: u8,
}

impl AxilMaster {
    pub fn new(writes: Vec<Txn>, reads: Vec<Txn>, seed: u64) -> AxilMaster {
        let mut rng = Lcg(seed);
        let low = (0..writes.len().max(reads.len())).map(|_| (rng.next() % 4) as u16).collect();
        AxilMaster {
            writes,
            reads,
            rng,
            aw_next: 0,
            w_next: 0,
            ar_next: 0,
            aw_wait: 0,
            w_wait: 0,
            ar_wait: 0,
            aw_on: false,
            w_on: false,
            ar_on: false,
            bready: false,
            rready: false,
            b_got: vec![],
            r_got: vec![],
            low,
        }
    }

    pub fn finished(&self) -> bool {
        self.b_got.len() == self.writes.len() && self.r_got.len() == self.reads.len()
    }

    fn resp(code: u8, data: u32) -> Resp {
        if code == 0 {
            Resp::Ok(data)
        } else {
            Resp::Err
        }
    }

    /// The inputs of this cycle (reset, awvalid, awaddr, wvalid, wdata, wstrb, bready,
    /// arvalid, araddr, rready) from the outputs of the last.
    pub fn step(&mut self, o: AxilOut) -> Vec<u128> {
        // What the last edge took.
        if self.aw_on && o.awready {
            self.aw_on = false;
            self.aw_next += 1;
            self.aw_wait = self.rng.next() % 4;
        }
        if self.w_on && o.wready {
            self.w_on = false;
            self.w_next += 1;
            self.w_wait = self.rng.next() % 4;
        }
        if self.ar_on && o.arready {
            self.ar_on = false;
            self.ar_next += 1;
            self.ar_wait = self.rng.next() % 4;
        }
        if self.bready && o.bvalid {
            self.b_got.push(Self::resp(o.bresp, 0));
        }
        if self.rready && o.rvalid {
            self.r_got.push(Self::resp(o.rresp, o.rdata));
        }
        // This cycle's offers; a VALID once raised stays until taken.
        for (on, next, wait, n) in [
            (&mut self.aw_on, self.aw_next, &mut self.aw_wait, self.writes.len()),
            (&mut self.w_on, self.w_next, &mut self.w_wait, self.writes.len()),
            (&mut self.ar_on, self.ar_next, &mut self.ar_wait, self.reads.len()),
        ] {
            if !*on && next < n {
                if *wait > 0 {
                    *wait -= 1;
                } else {
                    *on = true;
                }
            }
        }
        self.bready = !self.rng.one_in(3);
        self.rready = !self.rng.one_in(3);
        let junk = self.rng.wide();
        let w = self.writes.get(self.aw_next.min(self.writes.len().saturating_sub(1))).copied();
        let wd = self.writes.get(self.w_next.min(self.writes.len().saturating_sub(1))).copied();
        let r = self.reads.get(self.ar_next.min(self.reads.len().saturating_sub(1))).copied();
        let byte = |t: Option<Txn>, i: usize, low: &[u16]| t.map_or(0, |t| (t.addr as u128) << 2 | low.get(i).copied().unwrap_or(0) as u128);
        vec![
            0,
            self.aw_on as u128,
            if self.aw_on { byte(w, self.aw_next, &self.low) } else { junk & 0x7ff },
            self.w_on as u128,
            if self.w_on { wd.map_or(0, |t| t.data as u128) } else { junk >> 11 & 0xffff_ffff },
            if self.w_on { wd.map_or(0, |t| t.strb as u128) } else { junk >> 43 & 0xf },
            self.bready as u128,
            self.ar_on as u128,
            if self.ar_on { byte(r, self.ar_next, &self.low) } else { junk >> 47 & 0x7ff },
            self.rready as u128,
        ]
    }
}
