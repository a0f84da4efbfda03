//! Encoder feedback, clock by clock: the model of `hdl::enc_decoder` (plain Rust, no
//! HDL). One incremental encoder per axis, with quadrature lines A and B and an index
//! line Z.
//!
//! **Lines.** Each of A, B and Z goes through two synchroniser flip-flops and a digital
//! filter: the filtered level takes a new value once the synchronised pin has differed
//! from it at `filter + 1` consecutive clk ticks (`filter` = 0..=[`FILTER_MAX`], 0 =
//! off). A pin change sampled at clk edge e0 reaches the filtered level at edge
//! e0 + 2 + filter ([`pin_to_level_ticks`]); a pulse or bounce shorter than
//! `filter + 1` ticks is ignored. A reset loads each filtered level from its
//! synchronised pin (no count, no index on the way out of a reset).
//!
//! **Count** (4× decoding). At a tick where exactly one of the filtered A and B
//! changes, the count (signed 32 bits, wrapping) moves by one: up when A changes away
//! from the level B has, or B changes to A's (A leads B: 00 → 10 → 11 → 01 → 00), down
//! the other way; `invert` swaps the two. A tick where both change is an **illegal
//! transition**: the count keeps its value and `illegal` (8 bits, wrapping) counts it.
//! With the filter off and the pins moving with the clock, one edge per tick is
//! counted; a real encoder's pins are asynchronous, so the documented rate
//! ([`max_count_rate_ticks`]) keeps two ticks between edges.
//!
//! **Index.** The index is qualified: the filtered Z at its active level (`z_low`: 0 =
//! high, 1 = low) and, when `gate` is set, the filtered A and B equal to `gate_ab`
//! (bit 0 A, bit 1 B). The index strobe is the tick at which the qualified index
//! becomes true, so an index pulse whose edges fall a tick before or after the A or B
//! edge it is gated with is taken at the same count either way (at the AB state's
//! count, in both directions). At the strobe `index_count` takes the count after the
//! tick (with the tick's move) and `index_tog` flips; if the clear is armed (`arm`, a
//! command, self-clearing) the count restarts at the index: at the strobe it still
//! takes `index_count`, and from the next tick it counts from 0 (that tick's move
//! added to 0), so it is always the count since the index, a tick late. (The clear
//! folds into the count adder's operand: a clear in the strobe's own tick cost a
//! multiplexer on every bit.) **Probe**: at a `probe` strobe (the machine
//! I/O's probe latch) `probe_count` takes the count as it was before the tick and
//! `probe_tog` flips.
//!
//! **Index position.** At the strobe `index_pos` also takes the axis's step position
//! as the decoder's `position` input shows it in that tick (the position register
//! before the tick's edge), 0 after reset. The HDL decoder keeps its low 8 bits; the
//! extension makes it 32 bits from the axis's position at its next visit, which is at
//! most K + 1 ≤ 17 ticks later: with at most a step a tick, fewer than 2^7 steps.
//!
//! **Velocity.** `age` counts velocity ticks (`vel_tick`, one clk tick in
//! `prescale + 1`, shared by the axes) since the last counted edge (or the reset),
//! saturating at [`VEL_MAX`]; at a counted edge `period` takes age + this tick's
//! velocity tick (saturating) and `age` restarts at 0, and `last_dir` says which way it
//! went. With a velocity tick every clk tick, `period` is the clk ticks between the
//! last two counted edges. After reset both read 0, and the first edge's period counts
//! from the reset.
//!
//! **Narrow counts, shared extension.** The HDL decoder keeps the count and its
//! latches [`NARROW_BITS`] wide ([`EncOutputs::narrow`]), with visit flags
//! ([`EncoderModel::clock_visit`]); [`ExtendModel`], round robin with the
//! following-error unit, carries them to 32 bits in memory. A count moves at most
//! once a tick and each axis is visited every K ≤ 16 ticks, so the extension is
//! exact (`encoder_examples` in tests/model_props.rs checks it at every visit).

/// The largest filter length, ticks (a 4-bit register field).
pub const FILTER_MAX: u8 = 15;
/// The velocity registers' saturation value (16 bits).
pub const VEL_MAX: u16 = 0xFFFF;

/// ENC_RATIO after reset: 1.0 count per step (unsigned Q16.16).
pub const RATIO_ONE: u32 = 1 << 16;
/// ENC_RATIO's largest accepted value: 256 counts per step (a 10,000-line encoder's
/// 40,000 counts per revolution against 200 full steps is 200); 0 is refused too.
pub const RATIO_MAX: u32 = 1 << 24;

/// Why the encoder registers refused a write (ENC_STATUS.CODE).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EncRefusal {
    /// ENC_RATIO of 0 or above [`RATIO_MAX`].
    Ratio = 1,
    /// ENC_FILTER above [`FILTER_MAX`].
    Filter = 2,
    /// A configuration register written while CTRL.ENABLE = 1 or the core still ran.
    Enabled = 3,
    /// ENC_AXIS naming an axis the core lacks.
    Axis = 4,
}

impl EncRefusal {
    pub const ALL: [EncRefusal; 4] = [EncRefusal::Ratio, EncRefusal::Filter, EncRefusal::Enabled, EncRefusal::Axis];
    pub fn code(self) -> u8 {
        self as u8
    }
    pub fn name(self) -> &'static str {
        match self {
            EncRefusal::Ratio => "RATIO",
            EncRefusal::Filter => "FILTER",
            EncRefusal::Enabled => "ENABLED",
            EncRefusal::Axis => "AXIS",
        }
    }
}

/// Clk edges from a pin change sampled at edge e0 to the filtered level: e0 + this.
pub fn pin_to_level_ticks(filter: u8) -> u64 {
    2 + filter as u64
}

/// The shortest spacing of A and B edges (clk ticks) the decoder counts without loss
/// or an illegal transition, for asynchronous pins: each level must be seen at
/// `filter + 1` ticks even when the synchroniser takes it a tick late, and two edges
/// must never fall in one sample. The maximum count rate is `clk` / this.
pub fn max_count_rate_ticks(filter: u8) -> u64 {
    // A level held for 2·d ticks between its two edges (the other line's edge between)
    // must survive a tick of sampling jitter at each end: 2d − 1 ≥ filter + 1 + 1.
    (filter as u64 + 3).div_ceil(2).max(2)
}

/// One axis's configuration (quasi-static: it changes only while the core is reset).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct EncConfig {
    /// Filter length, ticks (0..=[`FILTER_MAX`], 0 = off).
    pub filter: u8,
    /// Count down when A leads B.
    pub invert: bool,
    /// Z is active low (else high).
    pub z_low: bool,
    /// The index is qualified by the filtered A and B equal to `gate_ab`.
    pub gate: bool,
    /// Bit 0: A's level, bit 1: B's, for `gate`.
    pub gate_ab: u8,
}

impl EncConfig {
    /// The shared part of the configuration as the HDL's `mode` port: filter 3..0,
    /// z_low 4, gate 5, gate_ab 7..6 (`invert` is a port of its own).
    pub fn word(&self) -> u8 {
        (self.filter & 0xF) | (self.z_low as u8) << 4 | (self.gate as u8) << 5 | (self.gate_ab & 3) << 6
    }
}

/// The encoder's pins in one tick.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct EncPins {
    pub a: bool,
    pub b: bool,
    pub z: bool,
}

/// What the decoder shows (flip-flops, before the coming edge).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct EncOutputs {
    pub count: u32,
    pub index_count: u32,
    pub probe_count: u32,
    /// The step position input at the last index strobe (0 after reset).
    pub index_pos: u32,
    pub illegal: u8,
    pub index_tog: bool,
    pub probe_tog: bool,
    pub armed: bool,
    /// The armed clear was taken at the last tick: the count restarts at this one.
    pub clearing: bool,
    pub period: u16,
    pub age: u16,
    pub last_dir: bool,
    /// The filtered levels: bit 0 A, 1 B, 2 Z.
    pub levels: u8,
    /// The visit flags (see [`EncoderModel::clock_visit`]): since the last visit, a
    /// clear restarted the count (`cnew`), an index latched (`inew`; `iafter`: after
    /// such a clear, so `index_count` counts from it), a probe latched (`pnew`,
    /// `pafter`).
    pub cnew: bool,
    pub inew: bool,
    pub iafter: bool,
    pub pnew: bool,
    pub pafter: bool,
    /// Since the last visit: a counted edge (`enew`), two or more (`e2`).
    pub enew: bool,
    pub e2: bool,
    /// The narrow velocity counters the HDL decoder keeps: `age8` counts velocity
    /// ticks since the last edge (wrapping, not saturating), `per8` takes `age8` + the
    /// edge's own velocity tick at each edge ([`Self::narrow`] shows them as `age`
    /// and `period`).
    pub age8: u8,
    pub per8: u8,
}

/// The bits of the count and its latches the HDL decoder keeps per axis: the shared
/// extension ([`ExtendModel`]) visits each axis every K ≤ 16 ticks, and a count moves
/// at most one per tick, so 8 bits hold every change between two visits.
pub const NARROW_BITS: u32 = 8;

impl EncOutputs {
    /// The narrow view the HDL decoder shows: the count and the latches modulo
    /// 2^[`NARROW_BITS`], the velocity's narrow counters as `age` and `period`, the
    /// rest as is.
    pub fn narrow(&self) -> EncOutputs {
        let m = (1u32 << NARROW_BITS) - 1;
        EncOutputs {
            count: self.count & m,
            index_count: self.index_count & m,
            probe_count: self.probe_count & m,
            index_pos: self.index_pos & m,
            age: self.age8 as u16,
            period: self.per8 as u16,
            ..*self
        }
    }
}

/// One axis's decoder.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EncoderModel {
    s1: u8,
    s2: u8,
    level: u8,
    cnt: [u8; 3],
    out: EncOutputs,
}

impl Default for EncoderModel {
    fn default() -> Self {
        Self::new()
    }
}

impl EncoderModel {
    pub fn new() -> Self {
        EncoderModel {
            s1: 0,
            s2: 0,
            level: 0,
            cnt: [0; 3],
            out: EncOutputs::default(),
        }
    }

    pub fn outputs(&self) -> EncOutputs {
        EncOutputs { levels: self.level, ..self.out }
    }

    /// One clk edge. `arm` arms the clear on the next index, `probe` is the probe
    /// latch's strobe, `vel_tick` the velocity prescaler's tick; `reset` is
    /// synchronous (the synchroniser keeps running). No visit (see
    /// [`Self::clock_visit`]) and a step position of 0.
    pub fn clock(&mut self, cfg: &EncConfig, pins: EncPins, arm: bool, probe: bool, vel_tick: bool, reset: bool) {
        self.clock_visit(cfg, pins, arm, probe, vel_tick, false, 0, reset);
    }

    /// One clk edge, `ack` when the extension visits the axis in this cycle (it reads
    /// the outputs as they are before the edge). The visit flags collect what happened
    /// since the last visit: `cnew` a clear (the count counts from 0 since it), `inew`
    /// an index (the last one's count in `index_count`; `iafter`: it came with or
    /// after such a clear, so it counts from the clear), `pnew` and `pafter` the same
    /// for the probe. An event in the visit's own cycle is the next visit's.
    /// `position`: the axis's step position in this tick (`index_pos` takes it at an
    /// index).
    #[allow(clippy::too_many_arguments)]
    pub fn clock_visit(&mut self, cfg: &EncConfig, pins: EncPins, arm: bool, probe: bool, vel_tick: bool, ack: bool, position: u32, reset: bool) {
        let x = self.s2;
        self.s2 = self.s1;
        self.s1 = pins.a as u8 | (pins.b as u8) << 1 | (pins.z as u8) << 2;
        if reset {
            self.level = x;
            self.cnt = [0; 3];
            self.out = EncOutputs::default();
            return;
        }
        let mut change = 0u8;
        for i in 0..3 {
            let bit = 1 << i;
            if (x ^ self.level) & bit == 0 {
                self.cnt[i] = 0;
            } else if self.cnt[i] >= cfg.filter {
                change |= bit;
                self.cnt[i] = 0;
            } else {
                self.cnt[i] += 1;
            }
        }
        let a = self.level & 1 != 0;
        let b = self.level & 2 != 0;
        let ca = change & 1 != 0;
        let cb = change & 2 != 0;
        let o = &mut self.out;
        let counted = ca != cb;
        let up = (if ca { a == b } else { a != b }) ^ cfg.invert;
        let inc: u32 = if !counted {
            0
        } else if up {
            1
        } else {
            u32::MAX
        };
        if ca && cb {
            o.illegal = o.illegal.wrapping_add(1);
        }
        let after = if o.clearing { 0 } else { o.count }.wrapping_add(inc);
        let qualified = |lev: u8| ((lev & 4 != 0) != cfg.z_low) && (!cfg.gate || lev & 3 == cfg.gate_ab & 3);
        let index = qualified(self.level ^ change) && !qualified(self.level);
        // A clear the visit has not read: the count (before and after this tick)
        // counts from it. (A clear in this cycle follows an index at the last one, so
        // no index comes in this one: the qualified index was already true.)
        let cl_old = o.cnew && !ack;
        if probe {
            o.probe_count = o.count;
            o.probe_tog = !o.probe_tog;
            o.pafter = cl_old;
        } else if ack {
            o.pafter = false;
        }
        o.pnew = probe || (o.pnew && !ack);
        if index {
            o.iafter = cl_old;
        } else if ack {
            o.iafter = false;
        }
        o.inew = index || (o.inew && !ack);
        o.cnew = o.clearing || cl_old;
        o.count = after;
        o.clearing = index && o.armed;
        if index {
            o.index_count = after;
            o.index_pos = position;
            o.index_tog = !o.index_tog;
        }
        o.armed = arm || (o.armed && !index);
        o.e2 = (counted && o.enew && !ack) || (o.e2 && !ack);
        o.enew = counted || (o.enew && !ack);
        if counted {
            o.per8 = o.age8.wrapping_add(vel_tick as u8);
            o.age8 = 0;
        } else if vel_tick {
            o.age8 = o.age8.wrapping_add(1);
        }
        if counted {
            o.period = o.age.saturating_add(vel_tick as u16);
            o.age = 0;
            o.last_dir = up;
        } else if vel_tick {
            o.age = o.age.saturating_add(1);
        }
        self.level ^= change;
    }
}

/// A quadrature encoder for test benches: it follows a target position in counts,
/// one edge at a time with at least `spacing` ticks between edges, with an index
/// pulse (Z = 1) while the position modulo `counts_per_rev` is 0 (one count wide, A
/// and B both 0 there).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct QuadratureGen {
    /// The position the lines show, counts.
    pub pos: i64,
    pub counts_per_rev: i64,
    pub spacing: u64,
    wait: u64,
}

impl QuadratureGen {
    pub fn new(counts_per_rev: i64, spacing: u64) -> Self {
        QuadratureGen { pos: 0, counts_per_rev, spacing, wait: 0 }
    }

    /// The lines for position `pos`: the Gray sequence 00, 10 (A), 11, 01 counting up.
    pub fn lines(pos: i64, counts_per_rev: i64) -> EncPins {
        let q = pos.rem_euclid(4);
        EncPins { a: q == 1 || q == 2, b: q == 2 || q == 3, z: pos.rem_euclid(counts_per_rev) == 0 }
    }

    /// One tick toward `target`: an edge if one is due and the spacing allows.
    pub fn tick(&mut self, target: i64) -> EncPins {
        if self.wait > 0 {
            self.wait -= 1;
        }
        if self.wait == 0 && target != self.pos {
            self.pos += (target - self.pos).signum();
            self.wait = self.spacing;
        }
        Self::lines(self.pos, self.counts_per_rev)
    }
}

/// One stage of [`FollowErrModel`]'s pipeline.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct FeStage {
    ok: bool,
    ax: usize,
    /// An align takes this visit; the offset RAM is written 0 at it (first visit).
    al: bool,
    z: bool,
    tol: u16,
    pos: u32,
    ratio: u32,
    /// Stage 1: the offset; 2: less the sign correction; 3: less the count; 4: the
    /// deviation.
    v: u32,
    prod: u64,
}

/// The following error of K axes by one shared multiplier, round robin: the model of
/// `hdl::follow_err` (its module docs state the behaviour), clock for clock.
/// `dev = ⌊position · ratio / 2^16⌋ + offset − count` mod 2^32 (ratio unsigned
/// Q16.16), and a sticky fail flag per axis when |dev| > tol ≠ 0.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FollowErrModel {
    k: usize,
    ax: usize,
    s: [FeStage; 4],
    al: u32,
    ov: u32,
    fail: u32,
    off_ram: [u32; 16],
    dev_ram: [Option<u32>; 16],
}

/// Ticks between two visits of an axis by the following-error unit: K.
pub fn follow_refresh_ticks(axes: usize) -> u64 {
    axes as u64
}

/// The deviation of an axis at `position` steps with `count` counts, `ratio` counts per
/// step (Q16.16) and `offset`, as the unit computes it (signed).
pub fn deviation(position: i32, count: i32, ratio: u32, offset: u32) -> i32 {
    let prod = ((position as i64 * ratio as i64) >> 16) as u32;
    prod.wrapping_add(offset).wrapping_sub(count as u32) as i32
}

impl FollowErrModel {
    pub fn new(k: usize) -> Self {
        assert!((1..=16).contains(&k));
        FollowErrModel { k, ax: 0, s: [FeStage::default(); 4], al: 0, ov: 0, fail: 0, off_ram: [0; 16], dev_ram: [None; 16] }
    }

    /// The axis whose inputs the next edge takes.
    pub fn ax(&self) -> usize {
        self.ax
    }

    pub fn fail(&self) -> u32 {
        self.fail
    }

    /// Axis `a`'s last deviation (`None` before its first visit since power-up).
    pub fn dev(&self, a: usize) -> Option<u32> {
        self.dev_ram[a]
    }

    /// The axis whose count the next edge takes (the one [`Self::ax`] named two
    /// cycles earlier).
    pub fn ax2(&self) -> usize {
        self.s[1].ax
    }

    /// One clk edge with axis [`Self::ax`]'s position, ratio and tolerance and axis
    /// [`Self::ax2`]'s count (as it was when axis `ax2`'s other inputs were taken).
    #[allow(clippy::too_many_arguments)]
    pub fn clock(&mut self, position: u32, count: u32, ratio: u32, tol: u16, align: u32, clear: u32, reset: bool) {
        let a = self.ax;
        let oh0 = 1u32 << a;
        let take = self.al & oh0 != 0;
        let fresh = self.ov & oh0 == 0;
        let off = if take || fresh { 0 } else { self.off_ram[a] };
        let n1 = FeStage { ok: true, ax: a, al: take, z: fresh, tol, pos: position, ratio, v: off, prod: 0 };
        let s1 = self.s[0];
        let corr = if s1.pos >> 31 == 1 { (s1.ratio & 0xFFFF) << 16 } else { 0 };
        let n2 = FeStage { v: s1.v.wrapping_sub(corr), prod: s1.pos as u64 * s1.ratio as u64, ..s1 };
        let s2 = self.s[1];
        let n3 = FeStage { v: s2.v.wrapping_sub(count), ..s2 };
        let s3 = self.s[2];
        let n4 = FeStage { v: ((s3.prod >> 16) as u32).wrapping_add(s3.v), ..s3 };
        let s4 = self.s[3];
        let oh4 = 1u32 << s4.ax;
        if s4.ok {
            self.dev_ram[s4.ax] = Some(if s4.al { 0 } else { s4.v });
        }
        let mut ov = self.ov;
        if s4.ok && (s4.al || s4.z) {
            self.off_ram[s4.ax] = if s4.al { s4.v.wrapping_neg() } else { 0 };
            ov |= oh4;
        }
        let mag = if (s4.v as i32) < 0 { s4.v.wrapping_neg() } else { s4.v };
        // No fail while the axis's align is pending: not even from a visit already in
        // flight when the align came (it took the old offset), so that a clear right
        // after an align sticks.
        let over = s4.ok && !s4.al && (self.al | align) & oh4 == 0 && s4.tol != 0 && mag > s4.tol as u32;
        let mut fail = self.fail & !clear;
        if over {
            fail |= oh4;
        }
        let mut al = self.al | align;
        if s4.ok && s4.al {
            al = (self.al & !oh4) | align;
        }
        self.s = [n1, n2, n3, n4];
        self.ax = if a + 1 == self.k { 0 } else { a + 1 };
        self.al = al;
        self.ov = ov;
        self.fail = fail;
        if reset {
            self.ax = 0;
            for st in &mut self.s {
                st.ok = false;
            }
            self.al = 0;
            self.ov = 0;
            self.fail = 0;
        }
    }
}

/// The bits of an axis's `live` word in [`ExtendModel`]: illegal 7..0, armed 8, last
/// direction 9, filtered A, B, Z 12..10.
pub const LIVE_BITS: u32 = 13;

/// The live part of a decoder's outputs as [`ExtendModel`] stores it.
pub fn live_word(o: &EncOutputs) -> u16 {
    o.illegal as u16 | (o.armed as u16) << 8 | (o.last_dir as u16) << 9 | ((o.levels & 7) as u16) << 10
}

/// `a + b`, saturating at [`VEL_MAX`].
fn sat_add(a: u16, b: u8) -> u16 {
    a.saturating_add(b as u16)
}

/// Sign-extends a narrow difference.
fn sext_narrow(d: u32) -> u32 {
    let sh = 32 - NARROW_BITS;
    (((d << sh) as i32) >> sh) as u32
}

/// The extension of the narrow counts to 32 bits: the model of `hdl::enc_extend`,
/// clock for clock. Each cycle the bank registers the narrow outputs of the axis the
/// following-error unit takes (round robin, every K ticks: the visit), and the
/// extension, a cycle later, from that sample and the axis's last count in memory,
/// writes its 32-bit count, its index and probe latches (when new) and its live word,
/// and registers the count for the following-error unit's stage 2. Exact while the count moves less than 2^7
/// between two visits (at most K ≤ 16 moves: one per tick). The velocity the same
/// way: `age` from the last one plus the narrow counter's growth (saturating), or
/// the narrow `age` after an edge; `period` when an edge came: the narrow one after
/// two edges, else the last `age` plus the growth to the edge (saturating).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ExtendModel {
    /// Axis a has been visited since reset (its memory words are written).
    pub valid: u32,
    /// Flip when the axis's index or probe latch is written with a new latch.
    pub itog: u32,
    pub ptog: u32,
    pub cnt: [u32; 16],
    pub idx: [u32; 16],
    pub prb: [u32; 16],
    /// The step position at the index.
    pub ipos: [u32; 16],
    pub per: [u16; 16],
    pub age: [u16; 16],
    pub live: [u16; 16],
    /// The count of the axis visited at the last edge.
    pub count1: u32,
}

impl Default for ExtendModel {
    fn default() -> Self {
        ExtendModel { valid: 0, itog: 0, ptog: 0, cnt: [0; 16], idx: [0; 16], prb: [0; 16], ipos: [0; 16], per: [0; 16], age: [0; 16], live: [0; 16], count1: 0 }
    }
}

impl ExtendModel {
    /// One clk edge with the sample `o` of axis `ax`'s narrow view taken at the last
    /// edge and the axis's step position `pos` of that cycle; `ok`: the sample was
    /// taken out of reset (else nothing is written). The index position is
    /// `pos − sext(pos − index_pos mod 2^8)`: exact while the axis moved fewer than
    /// 2^7 steps since the index (the index came after the last visit).
    pub fn clock(&mut self, ax: usize, o: &EncOutputs, pos: u32, ok: bool, reset: bool) {
        if !ok {
            if reset {
                self.valid = 0;
                self.itog = 0;
                self.ptog = 0;
            }
            return;
        }
        let m = (1u32 << NARROW_BITS) - 1;
        let valid = self.valid >> ax & 1 == 1;
        let old = if valid { self.cnt[ax] } else { 0 };
        let ext = |lo: u32, from_clear: bool| {
            let base = if from_clear { 0 } else { old };
            base.wrapping_add(sext_narrow(lo.wrapping_sub(base) & m))
        };
        let count = ext(o.count, o.cnew);
        self.cnt[ax] = count;
        if o.inew || !valid {
            self.idx[ax] = ext(o.index_count, o.iafter);
            self.ipos[ax] = pos.wrapping_sub(sext_narrow(pos.wrapping_sub(o.index_pos) & m));
        }
        if o.pnew || !valid {
            self.prb[ax] = ext(o.probe_count, o.pafter);
        }
        let age_old = if valid { self.age[ax] } else { 0 };
        let grow = |narrow: u16| sat_add(age_old, (narrow as u8).wrapping_sub(age_old as u8));
        if o.enew || !valid {
            self.per[ax] = if o.e2 { o.period } else { grow(o.period) };
        }
        self.age[ax] = if o.enew { o.age } else { grow(o.age) };
        self.live[ax] = live_word(o);
        self.itog ^= (o.inew as u32) << ax;
        self.ptog ^= (o.pnew as u32) << ax;
        self.valid |= 1 << ax;
        self.count1 = count;
        if reset {
            self.valid = 0;
            self.itog = 0;
            self.ptog = 0;
        }
    }
}

/// The inputs of [`EncoderBankModel`] in one cycle (bit a = axis a).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BankInputs {
    pub a: u32,
    pub b: u32,
    pub z: u32,
    /// [`EncConfig::word`], shared.
    pub mode: u8,
    pub invert: u32,
    pub vel_prescale: u16,
    pub arm: u32,
    pub align: u32,
    pub clear: u32,
    pub probe: bool,
    /// For the axis [`EncoderBankModel::pos_axis`] names.
    pub position: u32,
    /// Every axis's step position's low byte (byte a = axis a's, for the index
    /// latches).
    pub pos_low: u128,
    pub ratio: u32,
    pub tol: u16,
}

/// K decoders, their velocity prescaler, the extension and the following-error unit:
/// the model of `hdl::enc_bank`, clock for clock. The decoders are full-width models;
/// the extension sees their narrow view, as the HDL's narrow decoders show it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct EncoderBankModel {
    pub dec: Vec<EncoderModel>,
    pub ext: ExtendModel,
    pub fe: FollowErrModel,
    pre: u16,
    /// The visit's sample register: axis, narrow view, taken out of reset, and the
    /// following error's register of the axis's position.
    vis: (usize, EncOutputs, bool, u32),
}

impl EncoderBankModel {
    pub fn new(k: usize) -> Self {
        EncoderBankModel { dec: vec![EncoderModel::new(); k], ext: ExtendModel::default(), fe: FollowErrModel::new(k), pre: 0, vis: (0, EncOutputs::default(), false, 0) }
    }

    /// The configuration of axis `a` from the shared mode and its invert bit.
    pub fn config(mode: u8, invert: bool) -> EncConfig {
        EncConfig { filter: mode & 0xF, invert, z_low: mode >> 4 & 1 == 1, gate: mode >> 5 & 1 == 1, gate_ab: mode >> 6 & 3 }
    }

    pub fn pos_axis(&self) -> usize {
        self.fe.ax()
    }

    /// Axis `sel`'s status word as (lo, hi) (`hdl::enc_bank`'s layout); `None` before
    /// the axis's first visit since reset (the deviation: since power-up).
    pub fn word(&self, sel: usize) -> (Option<u128>, Option<u128>) {
        let e = &self.ext;
        if e.valid >> sel & 1 == 0 {
            return (None, None);
        }
        let lo = self.fe.dev(sel).map(|d| {
            e.cnt[sel] as u128 | (e.idx[sel] as u128) << 32 | (e.prb[sel] as u128) << 64 | (d as u128) << 96
        });
        let hi = e.per[sel] as u128
            | (e.age[sel] as u128) << 16
            | (e.live[sel] as u128) << 32
            | ((self.fe.fail() >> sel & 1) as u128) << 45
            | ((e.itog >> sel & 1) as u128) << 46
            | ((e.ptog >> sel & 1) as u128) << 47
            | 1 << 48
            | (e.ipos[sel] as u128) << 49;
        (lo, Some(hi))
    }

    pub fn clock(&mut self, i: &BankInputs, reset: bool) {
        let tick = self.pre >= i.vel_prescale;
        let ax = self.fe.ax();
        self.fe.clock(i.position, self.ext.count1, i.ratio, i.tol, i.align, i.clear, reset);
        let (pax, view, ok, pos) = self.vis;
        self.ext.clock(pax, &view, pos, ok, reset);
        self.vis = (ax, self.dec[ax].outputs().narrow(), !reset, i.position);
        for (a, d) in self.dec.iter_mut().enumerate() {
            let pins = EncPins { a: i.a >> a & 1 == 1, b: i.b >> a & 1 == 1, z: i.z >> a & 1 == 1 };
            d.clock_visit(&Self::config(i.mode, i.invert >> a & 1 == 1), pins, i.arm >> a & 1 == 1, i.probe, tick, a == ax, (i.pos_low >> (8 * a)) as u32 & 0xFF, reset);
        }
        self.pre = if tick || reset { 0 } else { self.pre + 1 };
    }
}
