//! The register table: the one source of truth for the host interface.
//!
//! The bus decoder ([`crate::hdl::regfile`]) takes every address, reset value and
//! identity value from here; docs/registers.md ([`markdown`]) and the C header
//! `tdm_stepper_regs.h` ([`c_header`]) are generated from it. Tests hold all three to
//! the table: the header is compiled and checked with gcc, the committed files must
//! equal what this module generates, and a bus-level test walks every register.
//!
//! Addresses are **16-bit word addresses** on the EXMC address pins `A[8:0]`; an MCU
//! whose FSMC shifts the AHB address for a 16-bit bus (STM32, GD32) sees each
//! register at byte offset `2 × address` from the bank base. Global registers sit at
//! 0x000–0x0FF; axis `a` has a block of 16 words at `0x100 + 0x10·a`.

use std::fmt::Write as _;

/// Width of the EXMC address bus (word address).
pub const ADDR_BITS: usize = 9;
/// First word address of the per-axis blocks.
pub const AXIS_BASE: u16 = 0x100;
/// Words per axis block.
pub const AXIS_STRIDE: u16 = 0x10;
/// Most axes the register map (16-bit bitmaps, 16 axis blocks) can address.
pub const MAX_AXES: usize = 16;
/// Largest segment queue the 5-bit LEVEL field can show.
pub const MAX_QUEUE_DEPTH: usize = 16;
/// ID_MAGIC's value, "TS".
pub const MAGIC: u16 = 0x5453;
/// ID_VERSION: major in the high byte, minor in the low byte.
pub const VERSION: u16 = 0x0104;
/// Bus clocks from NWE rising at the end of a push (the STEPS_HI write) until STATUS
/// (ERROR, ERROR_CODE, LEVEL) and IRQ_ERROR show the push check's verdict: a STATUS read
/// whose NOE falls this late sees it: NWE's first high sample comes ≤ 1 clock after it
/// rises, the slave's commit cycle ends 2 clocks after that sample, the check takes
/// [`crate::latency::PUSH_CHECK_LATENCY`] more, and a read returns the registers
/// as they are 1 clock after NOE's first low sample: 1 + 2 + 4 − 1 = 6. Measured
/// through the bus by tests/system.rs (which fails with 4).
pub const PUSH_VERDICT_BUS_CLOCKS: u64 = 6;
/// Bus clocks the push check needs between two command writes (STEPS_HI, START, ABORT),
/// commit to commit; the documented write timing always leaves at least this.
pub const COMMAND_SPACING_BUS_CLOCKS: u64 = crate::latency::PUSH_CHECK_LATENCY as u64;

/// Width of a command in the command FIFO: v0 (31..0), T (63..32), steps (95..64),
/// axis (103..96), kind (105..104: 0 push, 1 start with the mask in 15..0, 2 abort).
pub const CMD_BITS: usize = 106;

/// SPI (`--bus spi`): bits 5..0 of the status byte each frame starts with, a fixed
/// pattern so that a MISO stuck at 0 or 1 shows.
pub const SPI_STATUS_PATTERN: u8 = 0x05;
/// SPI: fewest bus clocks CS must stay high between frames.
pub const SPI_CS_HIGH_MIN: u64 = 4;
/// SPI: SCK high and low each at least this many bus clocks (SCK ≤ bus_clk/4).
pub const SPI_SCK_HALF_MIN: u64 = 2;
/// SPI: bus clocks from an SCK rising edge to MISO's next bit.
pub const SPI_MISO_DELAY: u64 = 3;
/// SPI: most words in one frame.
pub const SPI_MAX_BURST: usize = 32;

/// How the host may access a field.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Access {
    /// Read only; writes are ignored.
    Ro,
    /// Read and write.
    Rw,
    /// Write only, with an action; reads return 0.
    Wo,
    /// Sticky flag: set by hardware, cleared by writing 1.
    W1c,
}

impl Access {
    pub fn name(self) -> &'static str {
        match self {
            Access::Ro => "RO",
            Access::Rw => "RW",
            Access::Wo => "WO",
            Access::W1c => "W1C",
        }
    }
}

/// A field of a 16-bit register.
#[derive(Clone, Debug)]
pub struct Field {
    pub name: &'static str,
    pub lsb: u32,
    pub width: u32,
    pub access: Access,
    pub doc: &'static str,
    /// Machine I/O groups ([`IO_GROUPS`] bits) one of which the export must have for
    /// the field to exist; 0: it exists wherever its register does.
    pub groups: u8,
}

/// Where a register's reset (or constant) value comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reset {
    Value(u16),
    Magic,
    Version,
    Axes,
    QueueDepth,
    FifoDepth,
    TCalc,
    ClockHzLo,
    ClockHzHi,
    MinPeriod,
    MaxRateLo,
    MaxRateHi,
    /// ID_OPTIONS: [`CoreParams::options_word`].
    Options,
}

/// The export option a register belongs to: every core has the base registers; the
/// others exist only in a core exported with their option (`export --io`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Feature {
    Base,
    /// Machine I/O and safety (`export --io GROUPS`): a core exported with any of these
    /// groups ([`IO_GROUPS`] bits) has the register.
    Io(u8),
    /// The S-curve option (`export --profiles trapezoid,scurve`): polynomial segments.
    Scurve,
    /// Encoder feedback (`export --encoder`).
    Encoder,
}

/// The machine I/O's groups (`export --io`), defined with their model.
pub use crate::model::io::{IO_ALARM, IO_ALL, IO_ESTOP, IO_GROUPS, IO_HOME, IO_INPUTS, IO_LIMITS, IO_PROBE, IO_WATCHDOG};

/// One 16-bit register. `per_axis` registers repeat in every axis block at
/// `AXIS_BASE + AXIS_STRIDE·a + offset`; global ones sit at `offset`.
#[derive(Clone, Debug)]
pub struct Register {
    pub name: &'static str,
    pub offset: u16,
    pub per_axis: bool,
    pub reset: Reset,
    pub fields: Vec<Field>,
    pub doc: &'static str,
    pub feature: Feature,
}

/// The parameters of one exported core that the identity registers report.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CoreParams {
    pub axes: usize,
    pub clock_hz: u32,
    pub queue_depth: usize,
    pub fifo_depth: usize,
    pub t_calc: usize,
    /// The minimum period the core enforces, ticks (the export's `--min-period`).
    pub min_period: u32,
    /// The core has the machine I/O (`export --io`): its ports, blocks and registers.
    pub io: bool,
    /// With the machine I/O: the groups left out ([`IO_GROUPS`] bits; 0 for `--io all`).
    pub io_omit: u8,
    /// The S-curve option (`export --profiles trapezoid,scurve`): polynomial segments,
    /// their staging registers and check.
    pub scurve: bool,
    /// Encoder feedback (`export --encoder`): the quadrature inputs, their decoders,
    /// the following error and their registers.
    pub encoder: bool,
}

impl CoreParams {
    /// The smallest STOP_DECEL the core accepts ([`crate::model::stop::stop_decel_min`]
    /// for its minimum period).
    pub fn stop_decel_min(&self) -> u32 {
        crate::model::stop::stop_decel_min(&crate::model::Limits { min_period_ticks: self.min_period })
    }

    /// The machine I/O groups the core has ([`IO_GROUPS`] bits; 0 without `--io`).
    pub fn io_groups(&self) -> u8 {
        if self.io {
            IO_ALL & !self.io_omit
        } else {
            0
        }
    }

    /// Whether a core with these parameters has `feature`'s registers.
    pub fn has(&self, feature: Feature) -> bool {
        match feature {
            Feature::Base => true,
            Feature::Io(groups) => self.io_groups() & groups != 0,
            Feature::Scurve => self.scurve,
            Feature::Encoder => self.encoder,
        }
    }

    /// Whether a core with these parameters has a field of `groups` (0: always).
    pub fn has_field(&self, groups: u8) -> bool {
        groups == 0 || self.io_groups() & groups != 0
    }

    /// ID_OPTIONS: the machine I/O groups (bits 5:0, [`IO_GROUPS`] bits), the S-curve
    /// option (bit 8) and encoder feedback (bit 9) the core was exported with.
    pub fn options_word(&self) -> u16 {
        self.io_groups() as u16 | (u16::from(self.scurve) << 8) | (u16::from(self.encoder) << 9)
    }

    /// RMAX, the largest start or end rate (Q0.32) a segment may have.
    pub fn max_rate(&self) -> u32 {
        crate::model::Limits { min_period_ticks: self.min_period }.max_rate()
    }
}

impl Register {
    /// The register's value after reset, for a core with `p`.
    pub fn reset_value(&self, p: &CoreParams) -> u16 {
        match self.reset {
            Reset::Value(v) => v,
            Reset::Magic => MAGIC,
            Reset::Version => VERSION,
            Reset::Axes => p.axes as u16,
            Reset::QueueDepth => p.queue_depth as u16,
            Reset::FifoDepth => p.fifo_depth as u16,
            Reset::TCalc => p.t_calc as u16,
            Reset::ClockHzLo => p.clock_hz as u16,
            Reset::ClockHzHi => (p.clock_hz >> 16) as u16,
            Reset::MinPeriod => p.min_period as u16,
            Reset::MaxRateLo => p.max_rate() as u16,
            Reset::MaxRateHi => (p.max_rate() >> 16) as u16,
            Reset::Options => p.options_word(),
        }
    }

    /// Word address of this register (of axis `axis` if it is per axis).
    pub fn address(&self, axis: usize) -> u16 {
        if self.per_axis {
            AXIS_BASE + AXIS_STRIDE * axis as u16 + self.offset
        } else {
            self.offset
        }
    }

    /// The register's access: that of its fields if they agree, else "mixed".
    pub fn access_name(&self) -> &'static str {
        let first = self.fields[0].access;
        if self.fields.iter().all(|f| f.access == first) {
            first.name()
        } else {
            "mixed"
        }
    }

    pub fn field(&self, name: &str) -> &Field {
        self.fields.iter().find(|f| f.name == name).unwrap_or_else(|| panic!("{}: no field {name}", self.name))
    }
}

fn f(name: &'static str, lsb: u32, width: u32, access: Access, doc: &'static str) -> Field {
    Field { name, lsb, width, access, doc, groups: 0 }
}

/// A field of a machine I/O group (`groups`: [`IO_GROUPS`] bits).
fn fg(groups: u8, name: &'static str, lsb: u32, width: u32, access: Access, doc: &'static str) -> Field {
    Field { name, lsb, width, access, doc, groups }
}

fn reg(name: &'static str, offset: u16, per_axis: bool, reset: Reset, fields: Vec<Field>, doc: &'static str) -> Register {
    Register { name, offset, per_axis, reset, fields, doc, feature: Feature::Base }
}

fn poly_reg(name: &'static str, offset: u16, fields: Vec<Field>, doc: &'static str) -> Register {
    Register { name, offset, per_axis: false, reset: Reset::Value(0), fields, doc, feature: Feature::Scurve }
}

fn enc_reg(name: &'static str, offset: u16, reset: u16, fields: Vec<Field>, doc: &'static str) -> Register {
    Register { name, offset, per_axis: false, reset: Reset::Value(reset), fields, doc, feature: Feature::Encoder }
}

/// Written only while the core is held in reset.
const ENC_CONFIG_RULE: &str = "Encoder configuration: written only while CTRL.ENABLE = 0 and the core is held in reset (else refused: ENC_STATUS.REFUSED, code 3).";

fn io_reg(name: &'static str, offset: u16, per_axis: bool, reset: u16, fields: Vec<Field>, doc: &'static str) -> Register {
    io_reg_of(IO_ALL, name, offset, per_axis, reset, fields, doc)
}

/// A machine I/O register that exists only with one of `groups`.
fn io_reg_of(groups: u8, name: &'static str, offset: u16, per_axis: bool, reset: u16, fields: Vec<Field>, doc: &'static str) -> Register {
    Register { name, offset, per_axis, reset: Reset::Value(reset), fields, doc, feature: Feature::Io(groups) }
}

/// The registers of a core with `p`: the base table and those of its options, each
/// with the fields of the groups it has (a register left with none is not there).
pub fn table_for(p: &CoreParams) -> Vec<Register> {
    table()
        .into_iter()
        .filter(|r| p.has(r.feature))
        .map(|mut r| {
            r.fields.retain(|f| p.has_field(f.groups));
            r
        })
        .filter(|r| !r.fields.is_empty())
        .collect()
}

/// The word addresses this export maps, as a mask over the whole space (bit w for
/// address w): every register of [`table_for`], each per-axis one for axes 0..K. The
/// Wishbone and AXI4-Lite front ends answer an access elsewhere with an error.
pub fn mapped(p: &CoreParams) -> Vec<bool> {
    let mut m = vec![false; 1 << ADDR_BITS];
    for r in table_for(p) {
        for a in 0..if r.per_axis { p.axes } else { 1 } {
            m[r.address(a) as usize] = true;
        }
    }
    m
}

/// Written only while the core is held in reset, like the output timing.
const IO_CONFIG_RULE: &str = "Machine I/O configuration: written only while CTRL.ENABLE = 0 and the core is held in reset (else refused: IO_STATUS.REFUSED).";

/// The register table.
pub fn table() -> Vec<Register> {
    use Access::*;
    let whole = |a: Access, doc: &'static str| vec![f("VALUE", 0, 16, a, doc)];
    let ro = |doc: &'static str| whole(Ro, doc);
    vec![
        reg("ID_MAGIC", 0x00, false, Reset::Magic, ro("0x5453 (\"TS\")"), "Identifies the core."),
        reg("ID_VERSION", 0x01, false, Reset::Version, ro("major (15:8), minor (7:0)"), "Register map version."),
        reg("ID_AXES", 0x02, false, Reset::Axes, ro("K, the number of axes"), "Axes in this core."),
        reg("ID_QUEUE_DEPTH", 0x03, false, Reset::QueueDepth, ro("segments per axis queue"), "Segments an axis can hold queued (LEVEL's maximum)."),
        reg("ID_FIFO_DEPTH", 0x04, false, Reset::FifoDepth, ro("periods per axis FIFO"), "Depth of each axis's period FIFO."),
        reg("ID_T_CALC", 0x05, false, Reset::TCalc, ro("clk cycles per period"), "Cycles the shared unit spends per period (square-root path); an axis's period must stay ≥ K·T_CALC ticks for no underrun."),
        reg("ID_CLOCK_HZ_LO", 0x06, false, Reset::ClockHzLo, ro("bits 15:0 of the core clock in Hz"), "Core clock frequency the export was made for, low half."),
        reg("ID_CLOCK_HZ_HI", 0x07, false, Reset::ClockHzHi, ro("bits 31:16 of the core clock in Hz"), "Core clock frequency, high half."),
        reg(
            "CTRL", 0x08, false, Reset::Value(0),
            vec![f("ENABLE", 0, 1, Rw, "1 runs the core; 0 holds it in reset (positions, queues, flags and counters cleared; a STEP pulse already high finishes its high time). Wait for GSTATUS.ENABLED before writing commands. Writing 1 is refused (GSTATUS.REFUSED) while the output timing does not fit ID_MIN_PERIOD.")],
            "Global control.",
        ),
        reg("START", 0x09, false, Reset::Value(0), vec![f("MASK", 0, 16, Wo, "axes to release together, bit a = axis a")],
            "Synchronised start: the masked axes make their first step period on the same clock edge once each has its first period ready. A masked axis still moving is waited for; a masked axis with nothing to run cancels the start (GSTATUS.START_FAILED)."),
        reg("ABORT", 0x0A, false, Reset::Value(0), vec![f("ALL", 0, 1, Wo, "write 1: hard stop of every axis")],
            "Hard stop: every queue and period FIFO empties, no further STEP edge rises (a pulse already high keeps its high time), positions stay exact."),
        reg("IRQ_DONE", 0x0B, false, Reset::Value(0), vec![f("AXES", 0, 16, W1c, "bit a: a segment of axis a finished (its last period ended)")], "Segment-done events."),
        reg("IRQ_QLOW", 0x0C, false, Reset::Value(0), vec![f("AXES", 0, 16, W1c, "bit a: axis a took a segment and its LEVEL is now ≤ QLOW_LEVEL")], "Queue-low events."),
        reg("IRQ_ERROR", 0x0D, false, Reset::Value(0), vec![f("AXES", 0, 16, W1c, "bit a: axis a set UNDERRUN, OVERFLOW or ERROR in its STATUS, or a START with axis a in its mask failed (GSTATUS.START_FAILED)")], "Error events."),
        reg("IRQ_MASK_DONE", 0x0E, false, Reset::Value(0), vec![f("AXES", 0, 16, Rw, "1 lets IRQ_DONE bit a raise the irq line")], "Enables for IRQ_DONE."),
        reg("IRQ_MASK_QLOW", 0x0F, false, Reset::Value(0), vec![f("AXES", 0, 16, Rw, "1 lets IRQ_QLOW bit a raise the irq line")], "Enables for IRQ_QLOW."),
        reg("IRQ_MASK_ERROR", 0x10, false, Reset::Value(0), vec![f("AXES", 0, 16, Rw, "1 lets IRQ_ERROR bit a raise the irq line")], "Enables for IRQ_ERROR."),
        reg("QLOW_LEVEL", 0x11, false, Reset::Value(1), vec![f("LEVEL", 0, 5, Rw, "queue-low threshold, segments")], "Threshold of the queue-low event."),
        reg(
            "GSTATUS", 0x12, false, Reset::Value(0),
            vec![
                f("ENABLED", 0, 1, Ro, "the core has seen ENABLE = 1 and accepts commands"),
                f("REFUSED", 1, 1, W1c, "a write was refused: a START, ABORT or push while the core was not enabled (ENABLE and ENABLED not both 1) or, for START and ABORT, with no room in the command FIFO (a push refused for a full queue or no room in the command FIFO sets that axis's STATUS.OVERFLOW instead); an output timing write while the core was on or of 0; CTRL.ENABLE = 1 with output timing that does not fit ID_MIN_PERIOD"),
                f("IRQ", 2, 1, Ro, "the irq line"),
                f("START_FAILED", 3, 1, W1c, "a START was cancelled because a masked axis had nothing to run (no segment queued, being set up, computed or moving: e.g. its only segment was rejected); no axis moved, and IRQ_ERROR is set for every axis of that START's mask. Read the masked axes' STATUS (BUSY = 0 marks the empty one, ERROR says why), push valid segments, clear this bit and write START again"),
            ],
            "Global status.",
        ),
        reg("BUSY", 0x13, false, Reset::Value(0), vec![f("AXES", 0, 16, Ro, "bit a: axis a has segments queued, in flight or moving, or its last STEP pulse is still high")], "Busy axes."),
        reg("ID_MIN_PERIOD", 0x14, false, Reset::MinPeriod, ro("minimum period, clk ticks"),
            "The minimum period chosen at export: no STEP period is shorter. A segment whose start or end rate exceeds ID_MAX_RATE is rejected with ERROR_CODE 3."),
        reg("ID_MAX_RATE_LO", 0x15, false, Reset::MaxRateLo, ro("bits 15:0 of RMAX = floor(2^32 / (ID_MIN_PERIOD + 1))"),
            "The largest start or end rate a segment may have (Q0.32 steps per tick), low half."),
        reg("ID_MAX_RATE_HI", 0x16, false, Reset::MaxRateHi, ro("bits 31:16 of RMAX"), "The largest rate, high half."),
        reg(
            "ID_OPTIONS", 0x1B, false, Reset::Options,
            vec![
                f("IO", 0, 6, Ro, "the machine I/O groups (`export --io`): estop 0, probe 1, limits 2, home 3, alarm 4, watchdog 5; 0 without the option"),
                f("SCURVE", 8, 1, Ro, "the S-curve option (`export --profiles trapezoid,scurve`)"),
                f("ENCODER", 9, 1, Ro, "encoder feedback (`export --encoder`)"),
            ],
            "The export's options: a core without an option reads 0 at that option's registers and ignores writes to them. The C driver's tdm_identify() refuses (TDM_E_CONFIG) a core whose options differ from its header's TDM_OPTIONS.",
        ),
        reg("STEP_HIGH", 0x17, false, Reset::Value(1), vec![f("TICKS", 0, 16, Rw, "minimum STEP high time, clk ticks (1..65,535)")],
            "Output timing: no STEP pulse is shorter. Written only while CTRL.ENABLE and GSTATUS.ENABLED are 0, and never 0 (else refused, GSTATUS.REFUSED). The pulse is half the period, clamped between max(STEP_HIGH, DIR_HOLD) and the period less max(STEP_LOW, DIR_SETUP), at most 65,535 ticks."),
        reg("STEP_LOW", 0x18, false, Reset::Value(1), vec![f("TICKS", 0, 16, Rw, "minimum STEP low time between pulses, clk ticks")],
            "Output timing: STEP stays low at least this long between pulses. Same write rules as STEP_HIGH."),
        reg("DIR_SETUP", 0x19, false, Reset::Value(1), vec![f("TICKS", 0, 16, Rw, "minimum DIR setup before a rising STEP edge, clk ticks")],
            "Output timing: DIR is stable at least this long before every rising STEP edge. Same write rules as STEP_HIGH."),
        reg("DIR_HOLD", 0x1A, false, Reset::Value(1), vec![f("TICKS", 0, 16, Rw, "minimum DIR hold after a rising STEP edge, clk ticks")],
            "Output timing: DIR stays stable at least this long after every rising STEP edge. Same write rules as STEP_HIGH. CTRL.ENABLE = 1 is refused while max(STEP_HIGH, DIR_HOLD) + max(STEP_LOW, DIR_SETUP) > ID_MIN_PERIOD."),
        reg("V0_LO", 0x0, true, Reset::Value(0), vec![f("VALUE", 0, 16, Rw, "start speed v0, Q0.32 steps per tick, bits 15:0")], "Staging: start speed, low half."),
        reg("V0_HI", 0x1, true, Reset::Value(0), vec![f("VALUE", 0, 16, Rw, "v0 bits 31:16")], "Staging: start speed, high half."),
        reg("T_LO", 0x2, true, Reset::Value(0), vec![f("VALUE", 0, 16, Rw, "duration T in clk ticks, bits 15:0")], "Staging: duration, low half."),
        reg("T_HI", 0x3, true, Reset::Value(0), vec![f("VALUE", 0, 16, Rw, "T bits 31:16")], "Staging: duration, high half."),
        reg("STEPS_LO", 0x4, true, Reset::Value(0), vec![f("VALUE", 0, 16, Rw, "signed steps θ (two's complement), bits 15:0")], "Staging: steps, low half."),
        reg("STEPS_HI", 0x5, true, Reset::Value(0), vec![f("VALUE", 0, 16, Rw, "θ bits 31:16; the write pushes {V0, T, STEPS} into the axis queue")],
            "Staging: steps, high half. Writing it pushes the staged segment."),
        reg(
            "STATUS", 0x6, true, Reset::Value(0),
            vec![
                f("LEVEL", 0, 5, Ro, "segments pushed and not yet taken by the scheduler (queued or in flight)"),
                f("BUSY", 5, 1, Ro, "segments queued, in flight or moving"),
                f("UNDERRUN", 6, 1, W1c, "a period came late: the pulse was stretched (no step lost)"),
                f("OVERFLOW", 7, 1, W1c, "a push was refused: the queue was full (LEVEL = ID_QUEUE_DEPTH) or the command FIFO had no room for it"),
                f("ERROR", 8, 1, W1c, "a segment was rejected; ERROR_CODE says why. Clearing it clears ERROR_CODE"),
                f("ERROR_CODE", 12, 4, Ro, "1 T = 0, 2 would reverse, 3 period too short, 4 T, 5 steps, 6 v0 out of range; with the machine I/O, 7 toward an active limit, 8 outside the soft limits, 9 axis held stopped or its plan stale"),
            ],
            "Axis status.",
        ),
        reg("POS_LO", 0x7, true, Reset::Value(0), vec![f("VALUE", 0, 16, Ro, "position bits 15:0; reading it latches bits 31:16 for POS_HI")], "Signed position in steps, low half."),
        reg("POS_HI", 0x8, true, Reset::Value(0), vec![f("VALUE", 0, 16, Ro, "position bits 31:16 as latched by the last POS_LO read")], "Position, high half (read POS_LO first)."),
        reg("DONE_COUNT", 0x9, true, Reset::Value(0), vec![f("COUNT", 0, 8, Ro, "segments finished, wrapping at 256")], "Segments done."),
        // Machine I/O (export --io all).
        io_reg(
            "IO_POLARITY", 0x20, false, 0x0001,
            vec![
                fg(IO_ESTOP, "ESTOP", 0, 1, Rw, "1: estop_n is active low (the reset value: the e-stop is active when the pin is low)"),
                fg(IO_PROBE, "PROBE", 1, 1, Rw, "1: probe is active low"),
                fg(IO_LIMITS, "LIMIT_NEG", 2, 1, Rw, "1: every axis's limit_neg is active low"),
                fg(IO_LIMITS, "LIMIT_POS", 3, 1, Rw, "1: every axis's limit_pos is active low"),
                fg(IO_HOME, "HOME", 4, 1, Rw, "1: every axis's home is active low"),
                fg(IO_ALARM, "ALARM", 5, 1, Rw, "1: every axis's alarm is active low"),
            ],
            IO_CONFIG_RULE,
        ),
        io_reg(
            "IO_FILTER_LO", 0x21, false, 0,
            vec![
                fg(IO_ESTOP, "ESTOP", 0, 4, Rw, "e-stop filter, samples (0..15, 0 = off): a new level is taken once seen at n + 1 consecutive samples"),
                fg(IO_PROBE, "PROBE", 4, 4, Rw, "probe filter, samples"),
                fg(IO_LIMITS, "LIMIT_NEG", 8, 4, Rw, "limit_neg filter, samples"),
                fg(IO_LIMITS, "LIMIT_POS", 12, 4, Rw, "limit_pos filter, samples"),
            ],
            IO_CONFIG_RULE,
        ),
        io_reg(
            "IO_FILTER_HI", 0x22, false, 0,
            vec![fg(IO_HOME, "HOME", 0, 4, Rw, "home filter, samples"), fg(IO_ALARM, "ALARM", 4, 4, Rw, "alarm filter, samples")],
            IO_CONFIG_RULE,
        ),
        io_reg_of(IO_INPUTS, "IO_PRESCALE", 0x23, false, 0, vec![f("TICKS", 0, 16, Rw, "the filters take a sample every TICKS + 1 clk ticks (0: every tick)")], IO_CONFIG_RULE),
        io_reg(
            "IO_EDGES", 0x24, false, 0,
            vec![
                fg(IO_HOME, "HOME_RELEASE", 0, 1, Rw, "1: the home latch takes the position when home becomes inactive (0: when it becomes active)"),
                fg(IO_PROBE, "PROBE_RELEASE", 1, 1, Rw, "1: the probe latch takes the positions when probe becomes inactive"),
            ],
            IO_CONFIG_RULE,
        ),
        io_reg_of(IO_WATCHDOG, "WD_TIMEOUT", 0x25, false, 0, vec![f("UNITS", 0, 16, Rw, "watchdog timeout in units of 1,024 clk ticks; 0 = off")], IO_CONFIG_RULE),
        io_reg(
            "IO_CMD", 0x26, false, 0,
            vec![
                fg(IO_ESTOP, "ESTOP_REARM", 0, 1, Wo, "write 1: clear the e-stop latch, if the filtered e-stop is inactive when the command reaches clk (else nothing)"),
                fg(IO_WATCHDOG, "WD_FEED", 1, 1, Wo, "write 1: restart the watchdog's count (a feed does not clear a trip)"),
                fg(IO_WATCHDOG, "WD_REARM", 2, 1, Wo, "write 1: clear a watchdog trip and restart its count"),
            ],
            "Machine I/O commands; each reaches clk 2 to 3 clk ticks after the write commits.",
        ),
        io_reg(
            "IO_STATUS", 0x27, false, 0,
            vec![
                fg(IO_ESTOP, "ESTOP", 0, 1, Ro, "the e-stop latch is set: every axis is held in a hard stop and drv_enable is low. Set by reset, CTRL.ENABLE = 0 and the filtered e-stop; cleared only by IO_CMD.ESTOP_REARM while the e-stop is inactive"),
                fg(IO_ESTOP, "ESTOP_IN", 1, 1, Ro, "the filtered e-stop input is active"),
                fg(IO_WATCHDOG, "WATCHDOG", 2, 1, Ro, "the watchdog has tripped: every axis is held in a hard stop; cleared by IO_CMD.WD_REARM"),
                fg(IO_PROBE, "PROBE_IN", 3, 1, Ro, "the filtered probe input is active"),
                f("REFUSED", 4, 1, W1c, "a machine I/O configuration write was refused (the core was enabled)"),
            ],
            "Machine I/O status, about 3 bus clocks behind clk.",
        ),
        io_reg(
            "IRQ_IO", 0x28, false, 0,
            vec![
                fg(IO_ESTOP, "ESTOP", 0, 1, W1c, "the filtered e-stop became active"),
                fg(IO_WATCHDOG, "WATCHDOG", 1, 1, W1c, "the watchdog tripped"),
                fg(IO_PROBE, "PROBE", 2, 1, W1c, "the probe latch took every axis's position (PROBE_POS)"),
                fg(IO_HOME, "HOME", 3, 1, W1c, "an axis's home latch took its position (IO_AXIS.HOME_LATCHED says which); writing 1 also clears every HOME_LATCHED"),
                f("STOP", 4, 1, W1c, "a moving axis was stopped by a limit in its direction of motion, its alarm, its stop on home or a controlled watchdog trip (IO_AXIS.STOPPED says which); writing 1 also clears every STOPPED"),
            ],
            "Machine I/O events; under IRQ_MASK_IO they raise the irq line (GSTATUS.IRQ shows the other events' part of it only).",
        ),
        io_reg("IRQ_MASK_IO", 0x29, false, 0, vec![f("EVENTS", 0, 5, Rw, "1 lets IRQ_IO bit b raise the irq line")], "Enables for IRQ_IO."),
        io_reg("SL_AXIS", 0x2A, false, 0, vec![f("AXIS", 0, 4, Rw, "the axis SL_APPLY sets and SL_STATUS and PLAN read")], "Soft limits: the axis they address."),
        io_reg("SL_MIN_LO", 0x2B, false, 0, vec![f("VALUE", 0, 16, Rw, "bits 15:0")], "Soft limits, staging: the lowest end position a push may have (signed, inclusive), low half."),
        io_reg("SL_MIN_HI", 0x2C, false, 0, vec![f("VALUE", 0, 16, Rw, "bits 31:16")], "Soft limits, staging: minimum, high half."),
        io_reg("SL_MAX_LO", 0x2D, false, 0, vec![f("VALUE", 0, 16, Rw, "bits 15:0")], "Soft limits, staging: the highest end position a push may have (signed, inclusive), low half."),
        io_reg("SL_MAX_HI", 0x2E, false, 0, vec![f("VALUE", 0, 16, Rw, "bits 31:16")], "Soft limits, staging: maximum, high half."),
        io_reg(
            "SL_APPLY", 0x2F, false, 0,
            vec![f("ENABLE", 0, 1, Wo, "1: the staged SL_MIN..SL_MAX become axis SL_AXIS's soft limits, enabled (refused, SL_STATUS.REFUSED, if SL_MIN > SL_MAX); 0: its soft limits are off")],
            "Soft limits: a write sets those of axis SL_AXIS; they apply to pushes checked after it.",
        ),
        io_reg(
            "SL_STATUS", 0x30, false, 0,
            vec![
                f("ENABLED", 0, 1, Ro, "axis SL_AXIS's soft limits are on"),
                f("STALE", 1, 1, Ro, "axis SL_AXIS's planned position is stale after a stop: its pushes are rejected (code 9) until a status word shows it at rest"),
                f("REFUSED", 2, 1, W1c, "an SL_APPLY was refused (SL_MIN > SL_MAX, or SL_AXIS not an axis of this core)"),
            ],
            "Soft limits and the planned position of axis SL_AXIS.",
        ),
        io_reg(
            "PLAN_LO", 0x31, false, 0,
            vec![f("VALUE", 0, 16, Ro, "bits 15:0 of axis SL_AXIS's planned position; reading it latches bits 31:16 for PLAN_HI")],
            "Planned position: where axis SL_AXIS's accepted pushes end (signed steps); the position itself whenever the axis rests with nothing pushed.",
        ),
        io_reg("PLAN_HI", 0x32, false, 0, vec![f("VALUE", 0, 16, Ro, "bits 31:16 as latched by the last PLAN_LO read")], "Planned position, high half (read PLAN_LO first)."),
        io_reg(
            "STOP", 0x33, false, 0,
            vec![f("AXES", 0, 16, Wo, "write 1 to bit i: a controlled stop of axis i (bits of axes the core lacks are ignored)")],
            "Controlled stop: each axis named decelerates to rest at STOP_DECEL from the speed of its last computed period, after the periods already computed (at most the period FIFO's depth + 2); its queued segments are dropped (counted as taken). An axis not moving (idle, not released, or in a dwell) stops at once, as by a limit's hard stop. The request reaches clk 3 to 4 clk ticks after the write commits.",
        ),
        io_reg(
            "STOP_DECEL_LO", 0x34, false, 0xFFFF,
            vec![f("VALUE", 0, 16, Rw, "write: stages bits 15:0 for STOP_DECEL_HI's write; read: bits 15:0 of the deceleration in use")],
            "Controlled stop's deceleration a = DECEL / 2^57 steps/tick² (at 50 MHz, 1 step/s² is about 57.6), low half.",
        ),
        io_reg(
            "STOP_DECEL_HI", 0x35, false, 0xFFFF,
            vec![f("VALUE", 0, 16, Rw, "write: {this, the staged low half} becomes the deceleration in use, refused (STOP_STATUS.REFUSED) while CTRL.ENABLE = 1 or below TDM_STOP_DECEL_MIN; read: bits 31:16 in use")],
            "Controlled stop's deceleration, high half (write STOP_DECEL_LO first). After reset 2^32 − 1, the hardest.",
        ),
        io_reg(
            "STOP_STATUS", 0x36, false, 0,
            vec![f("REFUSED", 0, 1, W1c, "a STOP_DECEL_HI or STOP_MODE write was refused (the core enabled, or the value below the minimum)")],
            "Controlled stop status.",
        ),
        io_reg(
            "STOP_MODE", 0x37, false, 0,
            vec![
                fg(IO_LIMITS, "LIMITS", 0, 1, Rw, "1: a limit stops its axis with the controlled stop; 0: with the hard stop"),
                fg(IO_ALARM, "ALARM", 1, 1, Rw, "1: an alarm stops its axis with the controlled stop (drv_enable stays high until the axis is at rest); 0: hard"),
                fg(IO_WATCHDOG, "WATCHDOG", 2, 1, Rw, "1: a watchdog trip ramps every axis down, then stops hard (drv_enable low) once none moves; 0: hard at once"),
                fg(IO_HOME, "HOME", 3, 1, Rw, "1: the stop on home (STOP_HOME) is the controlled stop; 0: hard"),
            ],
            "Which stop each source takes. Written only while CTRL.ENABLE = 0 (else refused: STOP_STATUS.REFUSED). A limit, alarm or watchdog in controlled mode ramps the axis down once and keeps it stopped while it holds: segments pushed meanwhile are dropped (counted as taken).",
        ),
        io_reg_of(
            IO_HOME,
            "STOP_HOME", 0x38, false, 0,
            vec![f("AXES", 0, 16, Rw, "bit i: stop axis i when its home latch fires while it moves (bits of axes the core lacks read 0)")],
            "Stop on home: a homing move ends at the home latch (hard or controlled, STOP_MODE.HOME); HOME_POS holds the latched position and POS − HOME_POS at rest is the overshoot. Written at any time; it reaches clk 2 to 3 clk ticks after the write.",
        ),
        io_reg(
            "IO_AXIS", 0xA, true, 0,
            vec![
                fg(IO_LIMITS, "LIMIT_NEG", 0, 1, Ro, "the filtered limit_neg input is active"),
                fg(IO_LIMITS, "LIMIT_POS", 1, 1, Ro, "the filtered limit_pos input is active"),
                fg(IO_HOME, "HOME", 2, 1, Ro, "the filtered home input is active"),
                fg(IO_ALARM, "ALARM", 3, 1, Ro, "the filtered alarm input is active (drv_enable of the axis is low)"),
                f("DRV_ENABLE", 4, 1, Ro, "the axis's drv_enable output"),
                fg(IO_HOME, "HOME_LATCHED", 5, 1, Ro, "the axis's home latch took its position since IRQ_IO.HOME was last cleared"),
                f("STOPPED", 6, 1, Ro, "the axis was stopped by a limit, its alarm, its stop on home or a controlled watchdog trip (hard or controlled, STOP_MODE) since IRQ_IO.STOP was last cleared; its queue was flushed and POS, once BUSY is 0, is where it came to rest"),
            ],
            "Machine I/O inputs of the axis, filtered, about 3 bus clocks behind clk. The e-stop, limit and alarm inputs read active from a reset until their filters have seen them inactive.",
        ),
        io_reg_of(
            IO_HOME,
            "HOME_POS_LO", 0xB, true, 0,
            vec![f("VALUE", 0, 16, Ro, "bits 15:0 of the position the home latch took; reading it latches bits 31:16 for HOME_POS_HI")],
            "Home latch: the axis's position (STEP rising edges, signed) when its filtered home input changed in the IO_EDGES direction; 0 after reset.",
        ),
        io_reg_of(IO_HOME, "HOME_POS_HI", 0xC, true, 0, vec![f("VALUE", 0, 16, Ro, "bits 31:16 as latched by the last HOME_POS_LO or PROBE_POS_LO read")], "Home latch, high half (read HOME_POS_LO first)."),
        io_reg_of(
            IO_PROBE,
            "PROBE_POS_LO", 0xD, true, 0,
            vec![f("VALUE", 0, 16, Ro, "bits 15:0 of the position the probe latch took; reading it latches bits 31:16 for PROBE_POS_HI")],
            "Probe latch: the axis's position when the filtered probe input changed in the IO_EDGES direction (every axis in the same tick); 0 after reset.",
        ),
        io_reg_of(IO_PROBE, "PROBE_POS_HI", 0xE, true, 0, vec![f("VALUE", 0, 16, Ro, "bits 31:16 as latched by the last PROBE_POS_LO or HOME_POS_LO read")], "Probe latch, high half (read PROBE_POS_LO first)."),
        // Encoder feedback (export --encoder).
        enc_reg(
            "ENC_AXIS", 0x50, 0,
            vec![f("AXIS", 0, 4, Rw, "the axis ENC_RATIO, ENC_TOL and the window registers (ENC_COUNT .. ENC_STATE and ENC_INDEX_POS) address; a write of an axis the core lacks is refused (code 4). Writing it empties the window until the axis's next copy (ENC_STATE.VALID)")],
            "Encoder: the axis the window registers address.",
        ),
        enc_reg("ENC_FILTER", 0x51, 0, vec![f("TICKS", 0, 16, Rw, "A, B and Z filter, clk ticks (0..15, 0 = off): a new level is taken once seen at TICKS + 1 consecutive ticks; a larger value is refused (code 2)")], ENC_CONFIG_RULE),
        enc_reg(
            "ENC_INDEX_MODE", 0x52, 0,
            vec![
                f("Z_LOW", 0, 1, Rw, "1: the index (enc_z) is active low"),
                f("GATE", 1, 1, Rw, "1: the index counts only while the filtered A and B equal GATE_A and GATE_B"),
                f("GATE_A", 2, 1, Rw, "A's level for GATE"),
                f("GATE_B", 3, 1, Rw, "B's level for GATE"),
            ],
            ENC_CONFIG_RULE,
        ),
        enc_reg("ENC_INVERT", 0x53, 0, vec![f("AXES", 0, 16, Rw, "bit a: axis a counts down when A leads B (bits of axes the core lacks read 0)")], ENC_CONFIG_RULE),
        enc_reg("ENC_VEL_PRESCALE", 0x54, 0, vec![f("TICKS", 0, 16, Rw, "ENC_PERIOD and ENC_AGE count velocity ticks, one every TICKS + 1 clk ticks")], ENC_CONFIG_RULE),
        enc_reg(
            "ENC_RATIO_LO", 0x55, 0,
            vec![f("VALUE", 0, 16, Rw, "write: stages bits 15:0 for ENC_RATIO_HI's write; read (while CTRL.ENABLE = 0; 0 while enabled): bits 15:0 of axis ENC_AXIS's ratio")],
            "Following error: counts per step of axis ENC_AXIS, unsigned Q16.16 (1.0 = 0x10000 after reset; 0x1..0x1000000, at most 256 counts per step), low half.",
        ),
        enc_reg(
            "ENC_RATIO_HI", 0x56, 0,
            vec![f("VALUE", 0, 16, Rw, "write: {this, the staged low half} becomes axis ENC_AXIS's ratio; refused while enabled (code 3) or for 0 or above 0x1000000 (code 1); read: bits 31:16")],
            "Following error: the ratio, high half (write ENC_RATIO_LO first).",
        ),
        enc_reg(
            "ENC_TOL", 0x57, 0,
            vec![f("COUNTS", 0, 16, Rw, "axis ENC_AXIS's tolerance, counts: ENC_FAIL when |deviation| exceeds it; 0 = no check (after reset); read while CTRL.ENABLE = 0 (0 while enabled)")],
            ENC_CONFIG_RULE,
        ),
        enc_reg("ENC_STOP", 0x58, 0, vec![f("AXES", 0, 16, Rw, "bit a: axis a's ENC_FAIL stops it (a hard stop, or the controlled stop with ENC_STOP_MODE.CONTROLLED; held while ENC_FAIL is set: pushes meanwhile are flushed and counted as taken)")], ENC_CONFIG_RULE),
        enc_reg(
            "ENC_STOP_MODE", 0x6B, 0,
            vec![fg(IO_ALL, "CONTROLLED", 0, 1, Rw, "1: ENC_FAIL stops its axis with the controlled stop (a ramp at STOP_DECEL from the axis's speed, then held); 0: with the hard stop")],
            "Which stop ENC_FAIL takes (with the machine I/O only: its controlled stop). Encoder configuration: written only while CTRL.ENABLE = 0 and the core is held in reset (else refused: ENC_STATUS.REFUSED, code 3).",
        ),
        enc_reg("ENC_ARM", 0x59, 0, vec![f("AXES", 0, 16, Wo, "write 1 to bit a: axis a's count restarts at 0 at its next index (self-clearing; ENC_STATE.ARMED)")], "Encoder: home on the index. Each command reaches clk 3 to 4 clk ticks after the write commits."),
        enc_reg("ENC_ALIGN", 0x5A, 0, vec![f("AXES", 0, 16, Wo, "write 1 to bit a: axis a's deviation becomes 0 at its next visit (the offset takes the difference), and stays relative to that")], "Following error: align. Commands cross as ENC_ARM's."),
        enc_reg("ENC_CLEAR", 0x5B, 0, vec![f("AXES", 0, 16, Wo, "write 1 to bit a: clear axis a's ENC_FAIL (it sets again at the next visit if the deviation is still out of tolerance: align first)")], "Following error: clear ENC_FAIL. Commands cross as ENC_ARM's."),
        enc_reg("ENC_FAIL", 0x5C, 0, vec![f("AXES", 0, 16, Ro, "bit a: axis a's |deviation| exceeded its tolerance since ENC_CLEAR (about 3 bus clocks behind clk)")], "Following error: the sticky ENC_FAIL flags."),
        enc_reg(
            "ENC_STATUS", 0x5D, 0,
            vec![
                f("REFUSED", 0, 1, W1c, "an encoder register write was refused; CODE says why. Clearing it clears CODE"),
                f("CODE", 4, 4, Ro, "the last refusal: 1 ratio 0 or above 0x1000000, 2 filter above 15, 3 configuration while enabled, 4 ENC_AXIS not an axis"),
            ],
            "Encoder status.",
        ),
        enc_reg(
            "IRQ_ENC", 0x5E, 0,
            vec![
                f("FAIL", 0, 1, W1c, "an axis's ENC_FAIL was set (ENC_FAIL says which)"),
                f("ILLEGAL", 1, 1, W1c, "an axis counted an illegal transition (ENC_STATE.ILLEGAL)"),
                f("INDEX", 2, 1, W1c, "an axis's index latch took its count (ENC_INDEX)"),
            ],
            "Encoder events; under IRQ_MASK_ENC they raise the irq line. ILLEGAL and INDEX come with the axis's next copy (at most K·(3 clk + 3 bus clocks) after the event).",
        ),
        enc_reg("IRQ_MASK_ENC", 0x5F, 0, vec![f("EVENTS", 0, 3, Rw, "1 lets IRQ_ENC bit b raise the irq line")], "Enables for IRQ_ENC."),
        enc_reg("ENC_COUNT_LO", 0x60, 0, vec![f("VALUE", 0, 16, Ro, "bits 15:0 of axis ENC_AXIS's count (signed, 4 per line period); reading it latches bits 31:16 for ENC_COUNT_HI")], "Encoder window: the count, low half."),
        enc_reg("ENC_COUNT_HI", 0x61, 0, vec![f("VALUE", 0, 16, Ro, "bits 31:16 as latched by the last ENC_COUNT_LO read")], "Encoder window: the count, high half."),
        enc_reg("ENC_INDEX_LO", 0x62, 0, vec![f("VALUE", 0, 16, Ro, "bits 15:0 of the count the index latch took; reading it latches bits 31:16 for ENC_INDEX_HI")], "Encoder window: the index latch, low half."),
        enc_reg("ENC_INDEX_HI", 0x63, 0, vec![f("VALUE", 0, 16, Ro, "bits 31:16 as latched by the last ENC_INDEX_LO read")], "Encoder window: the index latch, high half."),
        enc_reg("ENC_INDEX_POS_LO", 0x6C, 0, vec![f("VALUE", 0, 16, Ro, "bits 15:0 of axis ENC_AXIS's step position at its last index (the tick the index latch took the count; 0 before an index since the core left reset); reading it latches bits 31:16 for ENC_INDEX_POS_HI")], "Encoder window: the step position at the index, low half."),
        enc_reg("ENC_INDEX_POS_HI", 0x6D, 0, vec![f("VALUE", 0, 16, Ro, "bits 31:16 as latched by the last ENC_INDEX_POS_LO read")], "Encoder window: the step position at the index, high half."),
        enc_reg("ENC_PROBE_LO", 0x64, 0, vec![f("VALUE", 0, 16, Ro, "bits 15:0 of the count the machine I/O's probe latched (0 without it); reading it latches bits 31:16 for ENC_PROBE_HI")], "Encoder window: the probe latch, low half."),
        enc_reg("ENC_PROBE_HI", 0x65, 0, vec![f("VALUE", 0, 16, Ro, "bits 31:16 as latched by the last ENC_PROBE_LO read")], "Encoder window: the probe latch, high half."),
        enc_reg("ENC_DEV_LO", 0x66, 0, vec![f("VALUE", 0, 16, Ro, "bits 15:0 of the deviation ⌊position·ratio/2^16⌋ + offset − count (signed counts, positive when the encoder lags the steps); reading it latches bits 31:16 for ENC_DEV_HI")], "Encoder window: the following error, low half."),
        enc_reg("ENC_DEV_HI", 0x67, 0, vec![f("VALUE", 0, 16, Ro, "bits 31:16 as latched by the last ENC_DEV_LO read")], "Encoder window: the following error, high half."),
        enc_reg("ENC_PERIOD", 0x68, 0, vec![f("TICKS", 0, 16, Ro, "velocity ticks between the last two counted edges (saturating at 65,535)")], "Encoder window: the reciprocal velocity."),
        enc_reg("ENC_AGE", 0x69, 0, vec![f("TICKS", 0, 16, Ro, "velocity ticks since the last counted edge (saturating): a stall shows here")], "Encoder window: the time since the last edge."),
        enc_reg(
            "ENC_STATE", 0x6A, 0,
            vec![
                f("ILLEGAL", 0, 8, Ro, "illegal transitions (A and B changing in one filtered sample), wrapping"),
                f("ARMED", 8, 1, Ro, "the clear on the next index is armed"),
                f("DIR", 9, 1, Ro, "the last counted edge's direction (1 = up)"),
                f("A", 10, 1, Ro, "filtered A"),
                f("B", 11, 1, Ro, "filtered B"),
                f("Z", 12, 1, Ro, "filtered Z"),
                f("FAIL", 13, 1, Ro, "the axis's ENC_FAIL"),
                f("VALID", 15, 1, Ro, "the window holds a copy of axis ENC_AXIS (0 after reset, an ENC_AXIS write or while the core is held in reset)"),
            ],
            "Encoder window: the axis's live state. The window registers are one copy of the axis's word, refreshed at least every K·(3 clk + 3 bus clocks).",
        ),
        // The S-curve option (export --profiles trapezoid,scurve).
        poly_reg("POLY_V1_LO", 0x40, vec![f("VALUE", 0, 16, Rw, "end speed v1, Q0.32 steps per tick, bits 15:0")], "Polynomial staging (global): end speed, low half."),
        poly_reg("POLY_V1_HI", 0x41, vec![f("VALUE", 0, 16, Rw, "v1 bits 31:16")], "Polynomial staging: end speed, high half."),
        poly_reg("POLY_A_0", 0x42, vec![f("VALUE", 0, 16, Rw, "A' = A·2^32 (signed 64-bit, two's complement), bits 15:0")], "Polynomial staging: A' (A = a0·T²/2, the distance the start acceleration a0 alone adds over the segment, in steps), bits 15:0."),
        poly_reg("POLY_A_1", 0x43, vec![f("VALUE", 0, 16, Rw, "A' bits 31:16")], "Polynomial staging: A', bits 31:16."),
        poly_reg("POLY_A_2", 0x44, vec![f("VALUE", 0, 16, Rw, "A' bits 47:32")], "Polynomial staging: A', bits 47:32."),
        poly_reg("POLY_A_3", 0x45, vec![f("VALUE", 0, 16, Rw, "A' bits 63:48 (the sign in bit 15)")], "Polynomial staging: A', bits 63:48."),
        poly_reg(
            "POLY_ARM", 0x46,
            vec![f("ARM", 0, 1, Rw, "1: the next push (a STEPS_HI write of any axis) is a polynomial segment {V0, T, STEPS, POLY_V1, POLY_A}; the push that is taken (not refused) clears it, and so does CTRL.ENABLE = 0")],
            "Polynomial push: arms the next push as a polynomial (S-curve) segment, checked by the polynomial rules (the same ERROR_CODEs).",
        ),
    ]
}

/// The register named `name`.
pub fn register(name: &str) -> Register {
    table().into_iter().find(|r| r.name == name).unwrap_or_else(|| panic!("no register {name}"))
}

/// Word address of global register `name`, or of per-axis register `name` in axis 0.
pub fn addr(name: &str) -> u16 {
    register(name).address(0)
}

/// Checks the table's own consistency: no two registers share an address, fields
/// fit and do not overlap, global registers stay below the axis blocks.
pub fn check_table() -> Result<(), String> {
    let t = table();
    let mut seen = std::collections::BTreeMap::new();
    for r in &t {
        let limit = if r.per_axis { AXIS_STRIDE } else { AXIS_BASE };
        if r.offset >= limit {
            return Err(format!("{}: offset {:#x} outside its space", r.name, r.offset));
        }
        if let Some(other) = seen.insert((r.per_axis, r.offset), r.name) {
            return Err(format!("{} and {other} share offset {:#x}", r.name, r.offset));
        }
        let mut used = 0u32;
        for fl in &r.fields {
            if fl.width == 0 || fl.lsb + fl.width > 16 {
                return Err(format!("{}.{}: bits outside 15:0", r.name, fl.name));
            }
            let mask = ((1u32 << fl.width) - 1) << fl.lsb;
            if used & mask != 0 {
                return Err(format!("{}.{}: overlaps another field", r.name, fl.name));
            }
            used |= mask;
        }
    }
    Ok(())
}

fn bits(fl: &Field) -> String {
    if fl.width == 1 {
        format!("{}", fl.lsb)
    } else {
        format!("{}:{}", fl.lsb + fl.width - 1, fl.lsb)
    }
}

/// The C header `tdm_stepper_regs.h` for a core with `p`.
pub fn c_header(p: &CoreParams, name: &str) -> String {
    let mut h = String::new();
    let _ = writeln!(h, "/* tdm_stepper_regs.h: register map of the tdm-stepper IP core.");
    let _ = writeln!(h, " * Generated by `tdm-stepper export` from the register table (ip/src/regs.rs). Do not edit.");
    let _ = writeln!(h, " * Offsets are in bytes from the EXMC/FSMC bank base (16-bit bus: byte offset = 2 x word address).");
    let _ = writeln!(h, " * Access every register as a 16-bit volatile halfword. */");
    h.push_str("#ifndef TDM_STEPPER_REGS_H\n#define TDM_STEPPER_REGS_H\n\n#include <stdint.h>\n\n");
    let _ = writeln!(
        h,
        "/* This export: K = {}, clk = {} Hz, queue depth {}, period FIFO depth {}, t_calc {} cycles, minimum period {} ticks. */",
        p.axes, p.clock_hz, p.queue_depth, p.fifo_depth, p.t_calc, p.min_period
    );
    let _ = writeln!(h, "#define TDM_AXES {}u", p.axes);
    let _ = writeln!(h, "#define TDM_CLOCK_HZ {}u", p.clock_hz);
    let _ = writeln!(h, "#define TDM_QUEUE_DEPTH {}u", p.queue_depth);
    let _ = writeln!(h, "#define TDM_FIFO_DEPTH {}u", p.fifo_depth);
    let _ = writeln!(h, "#define TDM_T_CALC {}u", p.t_calc);
    let _ = writeln!(h, "#define TDM_MIN_PERIOD {}u /* ticks: no STEP period is shorter */", p.min_period);
    let _ = writeln!(h, "#define TDM_MAX_RATE {}u /* RMAX = floor(2^32 / (TDM_MIN_PERIOD + 1)): the largest start or end rate, Q0.32 */", p.max_rate());
    if p.io {
        let _ = writeln!(
            h,
            "#define TDM_STOP_DECEL_MIN {}u /* the smallest STOP_DECEL (a = DECEL / 2^57 steps/tick^2) this export accepts */",
            p.stop_decel_min()
        );
    }
    let _ = writeln!(h, "#define TDM_OPTIONS 0x{:04X}u /* ID_OPTIONS of this export: machine I/O groups 5:0, S-curve 8, encoder 9 */", p.options_word());
    let _ = writeln!(h, "#define TDM_MAGIC 0x{MAGIC:04X}u");
    let _ = writeln!(h, "#define TDM_VERSION 0x{VERSION:04X}u\n");
    let _ = writeln!(h, "#define TDM_AXIS_BASE 0x{:03X}u /* byte offset of axis 0's block */", 2 * AXIS_BASE);
    let _ = writeln!(h, "#define TDM_AXIS_STRIDE 0x{:02X}u /* bytes per axis block */\n", 2 * AXIS_STRIDE);
    for r in table_for(p) {
        let _ = writeln!(h, "/* {}: {} */", r.name, r.doc);
        if r.per_axis {
            let _ = writeln!(h, "#define TDM_{}(axis) (TDM_AXIS_BASE + (axis) * TDM_AXIS_STRIDE + 0x{:02X}u)", r.name, 2 * r.offset);
        } else {
            let _ = writeln!(h, "#define TDM_{} 0x{:03X}u", r.name, 2 * r.offset);
        }
        for fl in &r.fields {
            if fl.name == "VALUE" {
                continue;
            }
            let mask = ((1u32 << fl.width) - 1) << fl.lsb;
            let _ = writeln!(h, "#define TDM_{}_{}_SHIFT {}u", r.name, fl.name, fl.lsb);
            let _ = writeln!(h, "#define TDM_{}_{}_MASK 0x{:04X}u /* {}: {} */", r.name, fl.name, mask, fl.access.name(), fl.doc);
        }
        let _ = writeln!(h);
    }
    h.push_str("/* Segment error codes (STATUS.ERROR_CODE). */\n");
    for (code, name) in error_codes(p) {
        let _ = writeln!(h, "#define TDM_ERR_{name} {code}u");
    }
    if p.encoder {
        use crate::model::encoder::{EncRefusal, FILTER_MAX, RATIO_MAX, RATIO_ONE};
        h.push_str("\n/* Encoder refusal codes (ENC_STATUS.CODE) and limits. */\n");
        for e in EncRefusal::ALL {
            let _ = writeln!(h, "#define TDM_ENC_ERR_{} {}u", e.name(), e.code());
        }
        let _ = writeln!(h, "#define TDM_ENC_RATIO_ONE 0x{RATIO_ONE:X}u /* ENC_RATIO of 1.0 count per step (Q16.16) */");
        let _ = writeln!(h, "#define TDM_ENC_RATIO_MAX 0x{RATIO_MAX:X}u /* the largest ENC_RATIO accepted */");
        let _ = writeln!(h, "#define TDM_ENC_FILTER_MAX {FILTER_MAX}u");
    }
    h.push_str("\n/* Access helpers: base is the bank's address, e.g. 0x60000000 for FSMC bank 1. */\n");
    h.push_str("#define TDM_REG(base, off) (*(volatile uint16_t *)((uintptr_t)(base) + (off)))\n\n");
    h.push_str("/* The SPI front end (`export --bus spi`): a frame is the command byte, the address\n");
    h.push_str(" * byte (word address bits 7..0), then the words MSB first (a read has one turnaround\n");
    h.push_str(" * byte first). MISO starts each frame with the status byte. */\n");
    h.push_str("#define TDM_SPI_CMD_WRITE 0x80u /* command bit 7: write (else read) */\n");
    h.push_str("#define TDM_SPI_CMD_INC 0x40u /* command bit 6: the address steps after each word */\n");
    h.push_str("#define TDM_SPI_CMD_LEN_SHIFT 1u /* command bits 5..1: words - 1; bit 0: word address bit 8 */\n");
    let _ = writeln!(h, "#define TDM_SPI_MAX_BURST {SPI_MAX_BURST}u /* most words in one frame */");
    h.push_str("#define TDM_SPI_STATUS_IRQ 0x80u /* status bit 7: the irq pin */\n");
    h.push_str("#define TDM_SPI_STATUS_FRAME_ERR 0x40u /* status bit 6: the previous frame was refused in part */\n");
    h.push_str("#define TDM_SPI_STATUS_PATTERN_MASK 0x3Fu\n");
    let _ = writeln!(h, "#define TDM_SPI_STATUS_PATTERN 0x{SPI_STATUS_PATTERN:02X}u /* status bits 5..0, always */\n");
    h.push_str("#endif /* TDM_STEPPER_REGS_H */\n");
    // Outside the guard: a second export's header, included after this one, adds its
    // identity and nothing else (the register offsets are the same in every export).
    let id = format!("{}_IDENTITY", name.to_ascii_uppercase());
    let _ = writeln!(
        h,
        "\n/* This export's identity for tdm_identify_as() (tdm_identity in tdm_driver.h): firmware\n * with several cores includes each export's header and passes each core its own. */"
    );
    let _ = writeln!(h, "#ifndef {id}");
    let _ = writeln!(
        h,
        "#define {id} {{0x{VERSION:04X}u, {}u, {}u, {}u, {}u, {}u, {}u, 0x{:04X}u, {}u}}",
        p.axes,
        p.clock_hz,
        p.queue_depth,
        p.fifo_depth,
        p.min_period,
        p.max_rate(),
        p.options_word(),
        if p.io { p.stop_decel_min() } else { 0 }
    );
    let _ = writeln!(h, "#endif");
    h
}

/// The error codes STATUS.ERROR_CODE can hold in a core with `p`: the segment's own,
/// and with the machine I/O the push guard's ([`crate::model::guard::GuardError`]).
pub fn error_codes(p: &CoreParams) -> Vec<(u8, &'static str)> {
    let mut v = ERROR_CODES.to_vec();
    if p.io {
        v.extend(crate::model::guard::GuardError::ALL.iter().map(|e| (e.code(), e.name())));
    }
    v
}

/// Error codes of STATUS.ERROR_CODE, as the model defines them.
pub const ERROR_CODES: [(u8, &str); 6] = [
    (1, "TICKS_ZERO"),
    (2, "REVERSES"),
    (3, "PERIOD_TOO_SHORT"),
    (4, "TICKS_RANGE"),
    (5, "STEPS_RANGE"),
    (6, "RATE_RANGE"),
];

/// docs/registers.md for a core with `p`: the map, every field, the bus timing and
/// the write sequence of a two-axis synchronised move.
pub fn markdown(p: &CoreParams) -> String {
    let mut m = String::new();
    m.push_str("# tdm-stepper registers\n\n");
    m.push_str("Generated from the register table (`ip/src/regs.rs`) by `tdm-stepper export`; a test fails when this file is stale. ");
    let _ = writeln!(
        m,
        "Values for this export: K = {}, clk = {} Hz, queue depth {}, period FIFO depth {}, t_calc = {} cycles, minimum period {} ticks (RMAX = {}) (docs/registers.md is the default export's).\n",
        p.axes, p.clock_hz, p.queue_depth, p.fifo_depth, p.t_calc, p.min_period, p.max_rate()
    );
    m.push_str(BUS_TEXT);
    m.push_str(&spi_text());
    m.push_str(&mmio_text());
    m.push_str("\n## Register map\n\n");
    m.push_str("Word address on `A[8:0]`; byte offset from the bank base is twice that. Per-axis registers repeat for axis `a` at word `0x100 + 0x10·a + offset`. Unknown addresses read 0 and ignore writes.\n\n");
    m.push_str("| word | byte | name | access | reset | description |\n|---|---|---|---|---|---|\n");
    for r in table_for(p) {
        let (word, byte) = if r.per_axis {
            (format!("0x100 + 0x10·a + 0x{:X}", r.offset), format!("0x200 + 0x20·a + 0x{:02X}", 2 * r.offset))
        } else {
            (format!("0x{:03X}", r.offset), format!("0x{:03X}", 2 * r.offset))
        };
        let _ = writeln!(m, "| {word} | {byte} | {} | {} | 0x{:04X} | {} |", r.name, r.access_name(), r.reset_value(p), r.doc);
    }
    m.push_str("\n## Fields\n\n| register | field | bits | access | meaning |\n|---|---|---|---|---|\n");
    for r in table_for(p) {
        for fl in &r.fields {
            let _ = writeln!(m, "| {} | {} | {} | {} | {} |", r.name, fl.name, bits(fl), fl.access.name(), fl.doc);
        }
    }
    m.push_str("\nError codes: ");
    let codes: Vec<String> = error_codes(p).iter().map(|(c, n)| format!("{c} `{n}`")).collect();
    m.push_str(&codes.join(", "));
    m.push_str(". Segment fields and their ranges: docs/model.md.");
    if p.io {
        m.push_str(" Codes 7 to 9 are the machine I/O's push guard: 7 a push toward an active limit switch, 8 a push whose end position lies outside the axis's soft limits, 9 a push to an axis held stopped (e-stop latch, watchdog trip, its alarm) or whose planned position is stale after a stop (retry once BUSY = 0).");
    }
    m.push('\n');
    contract(&mut m, p);
    m.push_str(SEQUENCE_TEXT);
    m
}

/// The behaviour a host can rely on, with this export's numbers (each held by a test
/// in ip/tests/system.rs).
fn contract(m: &mut String, p: &CoreParams) {
    let q = p.queue_depth;
    let rate = crate::model::units::rate_to_steps_per_s(p.max_rate(), p.clock_hz as u32);
    m.push_str("\n## Contract\n\n");
    let _ = writeln!(
        m,
        "* **Queue.** LEVEL = segments pushed and not yet taken by the scheduler. A push with \
         LEVEL = ID_QUEUE_DEPTH ({q}) is refused (STATUS.OVERFLOW, nothing queued). The scheduler \
         takes segments into the axis's current and next slot before START, so an axis not yet \
         started accepts {} pushes before the first refusal (more when its segments are so short \
         that they are computed into the period FIFO). Pace pushes by LEVEL, not by counting.",
        q + 2
    );
    let _ = writeln!(
        m,
        "* **Errors at push.** Each push is checked in the bus clock, with the rules and codes of \
         docs/model.md, before it is queued. The verdict shows in STATUS (ERROR, ERROR_CODE, LEVEL) \
         and IRQ_ERROR at most {v} bus clocks after NWE rises at the end of the STEPS_HI write, \
         whether the axis is idle, running or has segments queued: a STATUS read whose NOE falls \
         that late sees it (with the minimum FSMC timing, the second read after the push always \
         does). A rejected segment never enters the queue and LEVEL does not count it; the \
         segments before and after it run as pushed, and no other axis is touched. The check \
         takes one command at a time: a write to STEPS_HI, START or ABORT committed fewer than \
         {c} bus clocks after the previous one is refused (GSTATUS.REFUSED), which the \
         documented write timing (NWE low ≥ 3, high ≥ 2 bus clocks) never does. A command \
         is taken only if the command FIFO between the clocks (4 entries, emptied at the \
         core clock's pace) will have room for it when it leaves the check, counting the \
         command still ahead of it: else a push is refused with STATUS.OVERFLOW and a START \
         or ABORT with GSTATUS.REFUSED, and nothing taken is ever dropped. That happens only \
         with `clk` several times slower than `bus_clk`.",
        v = PUSH_VERDICT_BUS_CLOCKS,
        c = COMMAND_SPACING_BUS_CLOCKS
    );
    if p.encoder {
        use crate::model::encoder::{max_count_rate_ticks, RATIO_MAX};
        let k = p.axes;
        let _ = writeln!(
            m,
            "* **Encoder feedback.** Each axis's count is 32-bit signed, 4 counts per line period. \
             With the filter off the decoder counts an edge of A or B every {r0} clk ticks without loss \
             (clk/{r0}, {f0:.1} M counts/s at this clock); with ENC_FILTER = n, one every \
             ⌈(n + 3)/2⌉ ticks, at least 2. The following error of every axis is computed by one \
             shared multiplier, round robin: each axis is refreshed every K = {k} clk ticks, and an \
             ENC_FAIL follows the count or position crossing the tolerance within K + 4 = {fl} clk ticks \
             (plus the count's way through the synchroniser and filter, 2 + n ticks). ENC_RATIO \
             takes 0x1 to 0x{RATIO_MAX:X} (Q16.16 counts per step, at most 256); the deviation is \
             ⌊position·ratio/2^16⌋ + offset − count, where ENC_ALIGN sets the offset that makes it 0. \
             The window registers (ENC_COUNT .. ENC_STATE and ENC_INDEX_POS) show a copy of axis ENC_AXIS refreshed at \
             least every K·(3 clk + 3 bus clocks); reading a *_LO half latches its *_HI half.",
            r0 = max_count_rate_ticks(0),
            f0 = p.clock_hz as f64 / max_count_rate_ticks(0) as f64 / 1e6,
            fl = k + 4,
        );
    }
    if p.scurve {
        let _ = writeln!(
            m,
            "* **Polynomial (S-curve) segments.** Write POLY_V1_LO/HI and POLY_A_0..3 (any order, \
             any time before the push), then POLY_ARM = 1, then the axis's V0, T and STEPS as for \
             any push: the STEPS_HI write pushes {{V0, T, STEPS, POLY_V1, POLY_A}} as a polynomial \
             segment and clears POLY_ARM (a refused push leaves it set, for the retry). The staging \
             is global: push from one context at a time. The segment is checked with the polynomial \
             rules (docs/model.md: the range, then the speed's control points, codes 1 to 6) and its \
             verdict shows {v} bus clocks after NWE rises at the end of the STEPS_HI write (two more \
             than a trapezoid's). A second polynomial push committed fewer than {c} bus clocks after \
             the previous one is refused (GSTATUS.REFUSED); a START, ABORT or trapezoid push is not \
             held by it. Trapezoid and polynomial segments mix freely in an axis's queue.",
            v = PUSH_VERDICT_BUS_CLOCKS + (crate::latency::POLY_PUSH_LATENCY - crate::latency::PUSH_CHECK_LATENCY) as u64,
            c = crate::latency::POLY_PUSH_LATENCY
        );
    }
    let acc = crate::latency::t_setup(crate::latency::RADIX_BITS, false);
    let dec = crate::latency::t_setup(crate::latency::RADIX_BITS, true);
    let _ = writeln!(
        m,
        "* **Setup cost and segment rate.** The shared unit sets up each segment before it runs: \
         {dec} clk cycles for a decelerating segment, {acc} for an accelerating one, fewer for a \
         uniform one or a dwell, during the time the periods leave it (ID_T_CALC cycles per \
         period of every axis). It sets up at most f/{dec} segments per second over all axes \
         together ({:.0} at {:.0} MHz). Keep the load Σ over the axes of (t_setup/T + \
         ID_T_CALC/Δ) below 1, with T each axis's segment duration and Δ its shortest period \
         (the 16-axis streaming test, 1 ms segments at half the maximum rate, runs with no \
         underrun); past that, the FIFOs' slack decides. A train of segments far \
         shorter than t_setup (say one step each) runs late and sets STATUS.UNDERRUN, though \
         every step is still emitted in order.",
        p.clock_hz as f64 / dec as f64,
        p.clock_hz as f64 / 1e6
    );
    let _ = writeln!(
        m,
        "* **Rates from steps/s.** rate = round(v·2^32/f) with f = ID_CLOCK_HZ (the ID_MAX_RATE \
         bound is in the same units). Rounding may put a deceleration to rest a fraction of a \
         rate unit past rest (2θ·2^32 < v0·T by less than T); such a segment is accepted and runs \
         with v0 − 1, exactly |θ| steps in exactly T ticks, so a planner need not round down."
    );
    let _ = writeln!(
        m,
        "* **Minimum period and output timing.** No STEP period is shorter than ID_MIN_PERIOD \
         ({} ticks): a segment whose start or end rate exceeds ID_MAX_RATE ({}) is rejected with \
         code 3, so one axis steps at most {:.0} times per second. STEP_HIGH, STEP_LOW, DIR_SETUP \
         and DIR_HOLD are then met on every edge: CTRL.ENABLE = 1 is refused unless \
         max(STEP_HIGH, DIR_HOLD) + max(STEP_LOW, DIR_SETUP) ≤ ID_MIN_PERIOD, and no segment is \
         rejected or slowed for them.",
        p.min_period,
        p.max_rate(),
        rate.floor()
    );
    m.push_str(
        "* **START.** Releases the masked axes on one clock edge once each has its first period \
         computed. A masked axis still moving is waited for. A masked axis with nothing to run (no \
         segment queued, being set up, computed or moving: it was never pushed, or its only segment \
         was rejected) cancels the START: no axis moves, GSTATUS.START_FAILED and IRQ_ERROR (every \
         masked axis) are set. Then read the masked axes' STATUS (BUSY = 0 marks the empty one), \
         push valid segments, clear START_FAILED and write START again.\n",
    );
    m.push_str(
        "* **BUSY** (and STATUS.BUSY) stays 1 until the last STEP pulse of the axis's move has \
         fallen, so BUSY = 0 means the driver has seen every pulse.\n",
    );
    m.push_str(
        "* **Errors.** STATUS.ERROR_CODE holds the code of the most recent rejection since STATUS.ERROR \
         was last cleared.\n",
    );
    m.push_str(
        "* **Disable and reset.** CTRL.ENABLE = 0 (or the reset pin) stops every axis and clears \
         positions, queues and flags; a STEP pulse already high finishes its high time first, so \
         no pulse shorter than STEP_HIGH ever reaches a driver.\n",
    );
    if p.io_groups() & (IO_ESTOP | IO_WATCHDOG) != 0 {
        m.push_str(
            "* **Machine I/O: hard stop.** While the e-stop latch (IO_STATUS.ESTOP) or the watchdog's \
             trip (IO_STATUS.WATCHDOG) holds, every axis is stopped as by ABORT, continuously: \
             queues and period FIFOs flushed, no new STEP edge (a pulse already high keeps its \
             high time), positions exact, drv_enable low. A segment pushed meanwhile is flushed \
             and counted as taken (LEVEL returns to 0); a START does nothing. From the first clk \
             edge that samples estop_n active, no STEP rising edge comes after 4 + n ticks \
             (3 + n unless a push reaches the core in that tick; n: the e-stop's filter, with \
             IO_PRESCALE = 0).\n",
        );
        m.push_str(
            "* **Machine I/O: arming.** The e-stop latch is set by reset and CTRL.ENABLE = 0. After \
             ENABLE, wait for IO_STATUS.ESTOP_IN = 0, write IO_CMD.ESTOP_REARM (and WD_REARM), and \
             check IO_STATUS.ESTOP = 0 before a move. A release of the e-stop alone never clears \
             the latch. With WD_TIMEOUT set, feed (IO_CMD.WD_FEED) more often than \
             WD_TIMEOUT·1,024 clk ticks.\n",
        );
    }
}

const BUS_TEXT: &str = r#"## The bus

The core is an EXMC/FSMC slave in asynchronous SRAM mode (mode 1), 16-bit data, no
NWAIT. Its pins at the IP boundary: `ne`, `noe`, `nwe` (active low), `addr[8:0]`,
`data_in[15:0]`, `data_out[15:0]` and `data_oe`; your top level owns the pads
(`assign D = data_oe ? data_out : 16'bz; data_in = D`). `data_oe` is `!ne & !noe`
straight from the pins, so the core drives the bus only while the MCU reads it.

The slave samples the strobes, address and data through two flip-flops in
`bus_clk`, which may be unrelated to `clk`. A write is captured while NWE and NE have
been sampled low twice in a row, and committed once either is sampled high: a strobe
too short to be sampled low twice is dropped whole, so a cut-off write never changes
a register. A read loads the register's value when NOE is first sampled low and holds
it until the next read.

**Minimum timing**, in periods of `bus_clk` (T_bus):

| phase | minimum | why |
|---|---|---|
| write: NWE low (DATAST) | 3 T_bus | two samples low, whatever the phase |
| write: address and data | stable while NWE is low | sampled with it |
| NWE or NOE high between accesses (ADDSET + turnaround) | 2 T_bus | the end of the strobe is seen |
| read: NOE low until the MCU samples data (DATAST) | 5 T_bus + board delay | 2 synchroniser stages, the decode register, the output |
| read: address stable before NOE falls | 0 (set during ADDSET) | sampled with NOE |

To program the FSMC (mode 1), convert to HCLK cycles: DATAST ≥ ⌈5·T_bus/T_HCLK⌉ (reads)
and ⌈3·T_bus/T_HCLK⌉ (writes; use the read value for one timing register), ADDSET ≥
⌈2·T_bus/T_HCLK⌉. Example: STM32F407 at HCLK = 168 MHz with bus_clk = 100 MHz:
T_bus/T_HCLK = 1.68, so DATAST = 9 and ADDSET = 4 HCLK (a read then takes about 80 ns).

**Command FIFO.** Pushes, START and ABORT cross into `clk` through a 4-deep FIFO that
drains one command per `clk` cycle, each seen about 3 `clk` cycles after its write.
A push takes six bus writes, so with `clk` faster than about a quarter of the MCU's
write rate the FIFO never fills; with a slower `clk`, space pushes by 8 `clk` cycles
(a refused push sets STATUS.OVERFLOW, a refused START or ABORT GSTATUS.REFUSED, and
nothing already queued is lost).

**32-bit values** are two halfwords. Staging registers may be written in any order;
writing STEPS_HI pushes the segment. A position is read POS_LO first: that read
latches the high half, and the following POS_HI read returns it, so the two halves
are one sample (one latch for all axes: do not interleave two axes' reads).

**Status crossing.** Status and positions come back from `clk` through a handshake
that copies one axis's status word at a time, round robin. So what you read is at
most about K·(4 T_clk + 4 T_bus) old; LEVEL and BUSY count a push at once (they are
kept on the bus side), so a just-pushed segment never reads as idle.
"#;

/// The SPI front end's section of the register map (`export --bus spi`).
fn spi_text() -> String {
    format!(
        r#"
## SPI (`export --bus spi`)

A core exported with `--bus spi` has the pins `cs_n`, `sck`, `mosi`, `miso` and
`miso_oe` in place of the EXMC pins, and the same registers. Its SPI front end runs in
`bus_clk` and makes each register access as an MCU would on the EXMC pins (at the
minimum timing above), so every rule of this map (the push check, its latency, the
status crossing, the IRQ) is the same on both buses.

**Modes 0 and 3**, without a setting: MOSI is taken and MISO advanced on SCK's rising
edges only. Bits go MSB first. A frame is CS low, whole bytes, CS high:

| byte | write frame (MOSI) | read frame (MOSI) | MISO |
|---|---|---|---|
| 0 | command | command | status byte |
| 1 | address bits 7..0 | address bits 7..0 | 0 |
| 2 | word 0, bits 15..8 | turnaround (any) | 0 |
| 3, 4 … | word 0 bits 7..0, word 1 … | any | read: word 0 bits 15..8, bits 7..0, word 1 … (write: 0) |

**Command byte:** bit 7 W (1 write, 0 read); bit 6 INC (the address steps by one after
each word; else every word is the same register); bits 5..1 LEN − 1 (1 to {burst}
words); bit 0 address bit 8. A segment push (V0_LO … STEPS_HI of an axis, six
consecutive registers) is one write frame of 14 bytes: at 10 MHz SCK, 11.2 µs on
the wire, so up to about 89,000 pushes per second with short CS gaps.

**Status byte** (MISO during the command byte): bit 7 IRQ (the `irq` pin), bit 6
FRAME_ERR (the previous frame was refused in part, see below), bits 5..0 = {pattern:#04x} (a
fixed pattern: a MISO stuck at 0 or 1, or a wrong mode, shows as a wrong pattern).

**Writes commit word by word**, each when its 16th bit has arrived. A push's verdict
is in STATUS before any later frame can read it: the write's NWE rises at most
{lat} T_bus after the word's last SCK edge, the verdict follows {v} T_bus later, and
a read frame's header alone takes 64 T_bus at the fastest SCK. **Reads** fetch word 0 when the
address byte is complete (the turnaround byte gives it time) and each next word as
the previous one starts out, never past LEN: a read of POS_LO, POS_HI with INC reads
one sample of the position.

**Refused, with FRAME_ERR in the next frame's status byte:** CS raised mid-word (that
word is discarded; the whole words before it are written); CS raised before the LEN-th
word (a short frame: the words before are written); SCK edges after the LEN-th word
(nothing more is written); a burst whose last address would pass 0x1FF (no access at
all). A frame of exactly 8 SCK edges is a status poll: it reads the status byte and is
not an error. A frame with no SCK edge changes nothing.

**Timing**, in periods of `bus_clk` (T_bus):

| what | minimum | why |
|---|---|---|
| SCK high, SCK low | {half} T_bus each (SCK ≤ bus_clk/4) | each level sampled at least once |
| CS low before the first SCK edge | 1 T_bus | CS and SCK pass the same synchroniser |
| CS high between frames | {cs} T_bus | the frame's verdict and the next status byte |
| MISO valid after SCK rises | {miso} T_bus + board delay | 2 synchroniser stages, the shift register |

So at SCK = bus_clk/4 the host samples MISO at least 1 T_bus after it changes. A frame
faster than this is not lost silently: a word that arrives while the previous access
is still on the EXMC side is refused with FRAME_ERR.
"#,
        burst = SPI_MAX_BURST,
        pattern = SPI_STATUS_PATTERN,
        half = SPI_SCK_HALF_MIN,
        cs = SPI_CS_HIGH_MIN,
        miso = SPI_MISO_DELAY,
        lat = SPI_MISO_DELAY + 3,
        v = PUSH_VERDICT_BUS_CLOCKS,
    )
}

/// The Wishbone and AXI4-Lite front ends' section (`export --bus wb|axil`).
fn mmio_text() -> String {
    use crate::latency::{AXIL_READ_RESP, AXIL_WRITE_RESP, EXMC_MASTER_GAP, WB_READ_ACK, WB_WRITE_ACK};
    format!(
        r#"
## Wishbone and AXI4-Lite (`export --bus wb`, `export --bus axil`)

A core exported with `--bus wb` or `--bus axil` has a 32-bit bus slave in place of
the EXMC pins, with the same registers, and `bus_clk` is the bus's clock. Each
register is one 32-bit word: bits 15..0 are the register, bits 31..16 read 0 and are
ignored on writes. The front end makes each access on the EXMC slave inside, as an MCU
would at the minimum timing above, so every rule of this map (the push check, its
latency, the status crossing, the IRQ) is the same on every bus.

**Mapped addresses.** The registers of the map below (for axes 0..K − 1 only). An
access to any other word address is refused and touches nothing. Firmware on a soft
CPU uses the C driver with `tdm_open_mmio32()` (each register at base + 4·word).

**Wishbone B4, classic cycles** (`wb_cyc`, `wb_stb`, `wb_we`, `wb_adr`, `wb_sel`,
`wb_dat_w`, `wb_dat_r`, `wb_ack`, `wb_err`). `wb_adr` is the word address (9 bits:
the SoC decodes the core's region and passes the low bits of its word address). An
access starts in a cycle with CYC and STB high; ACK is high for one cycle
{wbw} cycles later for a write, {wbr} for a read (with `wb_dat_r`); the master holds
ADR, WE, SEL and DAT_W until then. **ERR** instead, 1 cycle later and with no access:
an unmapped address, or a write whose `wb_sel[1:0]` is not 11. A master that drops
CYC before ACK gets no ACK; the access still completes. Back to back, an access every
{wbr1} cycles (reads) at most.

**AXI4-Lite** (`s_axil_*`: AW, W, B, AR, R, no AxPROT). Byte addresses, 11 bits:
register w at 4·w; bits 1..0 are ignored. Every channel has back-pressure: AWREADY,
WREADY and ARREADY are high while the slave's one-entry buffer of that channel is
empty, so one write and one read can be outstanding while an access is in flight;
BVALID and RVALID stay high until BREADY and RREADY. With the ready signals high,
BVALID comes {axw} cycles after the later of the AW and W handshakes and RVALID
{axr} cycles after AR; reads and writes take turns when both wait.

| access | response | register |
|---|---|---|
| mapped, read | OKAY, the register in RDATA[15:0] | read |
| mapped, write, WSTRB[1:0] = 11 | OKAY | written |
| mapped, write, WSTRB[1:0] = 00 | OKAY | untouched (AXI's empty write) |
| mapped, write, WSTRB[1:0] = 01 or 10 | SLVERR | untouched (half a register) |
| unmapped, read or write | SLVERR (RDATA 0) | untouched |

Between two accesses the EXMC side rests {gap} bus clocks.
"#,
        wbw = WB_WRITE_ACK,
        wbr = WB_READ_ACK,
        wbr1 = WB_READ_ACK + 1,
        axw = AXIL_WRITE_RESP,
        axr = AXIL_READ_RESP,
        gap = EXMC_MASTER_GAP,
    )
}

const SEQUENCE_TEXT: &str = r#"
## A two-axis synchronised move, step by step

The paper's experiment: clk = 50 MHz, axis 0 moves 2,400 steps and axis 1 1,800 steps,
each as 20 ms accelerate, 10 ms cruise, 20 ms decelerate, from rest to rest. The
planner (`tdm_stepper::model::planner::trapezoid_by_ticks`) gives three segments per
axis `{v0 (Q0.32 steps/tick), T (ticks), steps}`. With `R(x) = TDM_REG(base, x)`:

```c
#include "tdm_stepper_regs.h"
#define R(off) TDM_REG(0x60000000u, off)        /* FSMC bank 1, NE1 */

uint16_t tdm_read16(uint32_t off) { return R(off); }

int tdm_init(void) {
    if (R(TDM_ID_MAGIC) != TDM_MAGIC) return -1;  /* wrong bank or timing */
    R(TDM_CTRL) = 1;                              /* ENABLE */
    while (!(R(TDM_GSTATUS) & TDM_GSTATUS_ENABLED_MASK)) {}
    return 0;
}

void tdm_push(unsigned axis, uint32_t v0, uint32_t t, int32_t steps) {
    while ((R(TDM_STATUS(axis)) & TDM_STATUS_LEVEL_MASK) >= TDM_QUEUE_DEPTH) {}
    R(TDM_V0_LO(axis)) = (uint16_t)v0;    R(TDM_V0_HI(axis)) = (uint16_t)(v0 >> 16);
    R(TDM_T_LO(axis)) = (uint16_t)t;      R(TDM_T_HI(axis)) = (uint16_t)(t >> 16);
    R(TDM_STEPS_LO(axis)) = (uint16_t)steps;
    R(TDM_STEPS_HI(axis)) = (uint16_t)((uint32_t)steps >> 16);   /* pushes */
}

int32_t tdm_position(unsigned axis) {
    uint16_t lo = R(TDM_POS_LO(axis));    /* latches the high half */
    uint16_t hi = R(TDM_POS_HI(axis));
    return (int32_t)(((uint32_t)hi << 16) | lo);
}

void paper_move(void) {
    /* the planner's segments {v0, T, steps}: accelerate, cruise, decelerate */
    tdm_push(0, 0, 1000000, 800);  tdm_push(0, 6871948, 500000, 800);  tdm_push(0, 6871947, 1000000, 800);
    tdm_push(1, 0, 1000000, 600);  tdm_push(1, 5153961, 500000, 600);  tdm_push(1, 5153960, 1000000, 600);
    R(TDM_IRQ_MASK_ERROR) = 0x3;          /* optional: irq on any error of axes 0, 1 */
    R(TDM_START) = 0x3;                   /* both axes start on the same clk edge */
    while (R(TDM_BUSY) & 0x3) {}          /* about 50 ms */
    /* tdm_position(0) == 2400, tdm_position(1) == 1800 */
}
```

Check `STATUS.ERROR` after pushing (read STATUS twice after the push: see
"Errors at push" above): a rejected segment is dropped with its code before it is
queued, and the segments around it still run. `ABORT` stops everything at once; the
positions then say exactly where each axis is.
"#;
