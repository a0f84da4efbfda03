//! `tdm-stepper export`: the IP core for a chosen axis count, as Verilog with its C
//! header, register document and manifest, and the integration package around it
//! ([`crate::package`]: lint waivers, instantiation template, constraints, FuseSoC
//! core, smoke testbench).
//!
//! The design is generic over K (and its internal widths) at compile time, so the
//! supported configurations are instantiated here: K = 1..=16 ([`MAX_AXES`]), the
//! TDM core (the non-TDM baseline for K in [`BASELINE_AXES`]), period FIFO depth 8 ([`FIFO_DEPTH`]). The shared
//! unit retires R = 2 bits per cycle ([`RADIX_BITS`]): t_calc = 22 cycles per period.
//! The segment queue holds [`QUEUE_DEPTH`] segments per axis.

use crate::hdl::core::t_calc_sqrt;
use crate::hdl::top::{BaselineStepper, TdmStepper, TdmStepperEnc, TdmStepperIo, TdmStepperIoEnc};
use crate::model::Limits;
use crate::regs::{self, CoreParams};
use rust_hdl::prelude::*;
use serde::Serialize;

/// Bits per cycle of the shared multiplier, divider and square root.
pub use crate::latency::RADIX_BITS;
/// Segments per axis queue (defined beside the radix, in the IP crate).
pub use crate::latency::QUEUE_DEPTH;
/// Most axes an export supports (the register map's limit).
pub const MAX_AXES: usize = regs::MAX_AXES;
/// The period FIFO depth of an export (defined beside the radix, in the IP crate).
pub use crate::latency::FIFO_DEPTH;

/// Cycles per period the S-curve option plans for on each axis (`--profiles
/// trapezoid,scurve`): the sustainable period is K times this. A polynomial period
/// takes the scheduler `t_poly_step` (the search + 9: 78 median on planned moves,
/// 4 for a segment's last step) and the next polynomial request waits the unit's
/// five-cycle write-back; the period FIFO (depth 8) carries the longer searches. Held
/// by the core's streaming test at half the rate it allows.
pub const POLY_T_CALC: usize = 100;
/// Period FIFO depths an export supports.
pub const FIFO_DEPTHS: [usize; 1] = [FIFO_DEPTH];
/// Core clock range, Hz (the identity register holds it; every period is in ticks).
pub const CLOCK_HZ_RANGE: std::ops::RangeInclusive<u32> = 1_000_000..=400_000_000;
/// Name of the exported top module.
pub const TOP_MODULE: &str = "tdm_stepper";
/// The C register header written by `export`.
pub const HEADER_FILE: &str = "tdm_stepper_regs.h";

/// TDM core or the non-TDM baseline (K one-axis cores behind the same registers).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Arch {
    Tdm,
    Baseline,
}

impl std::str::FromStr for Arch {
    type Err = String;
    fn from_str(s: &str) -> Result<Arch, String> {
        match s {
            "tdm" => Ok(Arch::Tdm),
            "baseline" => Ok(Arch::Baseline),
            _ => Err(format!("unknown architecture {s:?}: expected tdm or baseline")),
        }
    }
}

impl Arch {
    pub fn name(self) -> &'static str {
        match self {
            Arch::Tdm => "tdm",
            Arch::Baseline => "baseline",
        }
    }
}

/// What to export.
/// The exported top module's name (`--name`): a Verilog-2001 identifier of letters,
/// digits and `_` that does not start with a digit, at most [`ModuleName::MAX_LEN`]
/// characters, not a keyword. Every submodule is named `<name>__<path>` (no `$`), so
/// cores exported under different names live in one design.
/// The host bus in front of the register file (`--bus`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Bus {
    /// EXMC / FSMC asynchronous SRAM, 16-bit (the register file's own slave).
    #[default]
    Exmc,
    /// SPI, modes 0 and 3 ([`crate::hdl::spi_front::SpiFront`] in front of the EXMC slave).
    Spi,
    /// Wishbone B4 classic, 32-bit data ([`crate::hdl::wb_front::WbFront`]).
    Wb,
    /// AXI4-Lite, 32-bit data ([`crate::hdl::axil_front::AxilFront`]).
    Axil,
}

impl std::str::FromStr for Bus {
    type Err = String;
    fn from_str(s: &str) -> Result<Bus, String> {
        match s {
            "exmc" => Ok(Bus::Exmc),
            "spi" => Ok(Bus::Spi),
            "wb" => Ok(Bus::Wb),
            "axil" => Ok(Bus::Axil),
            _ => Err(format!("unknown bus {s:?}: expected exmc, spi, wb or axil")),
        }
    }
}

impl Bus {
    pub fn name(self) -> &'static str {
        match self {
            Bus::Exmc => "exmc",
            Bus::Spi => "spi",
            Bus::Wb => "wb",
            Bus::Axil => "axil",
        }
    }

    /// Every bus, in the order the docs list them.
    pub const ALL: [Bus; 4] = [Bus::Exmc, Bus::Spi, Bus::Wb, Bus::Axil];

    /// The bus's pins in place of the EXMC pins (none for EXMC itself).
    pub fn ports(self) -> Vec<PortDoc> {
        match self {
            Bus::Exmc => vec![],
            Bus::Spi => spi_ports(),
            Bus::Wb => wb_ports(),
            Bus::Axil => axil_ports(),
        }
    }

    /// What `bus_clk` does with this bus.
    fn bus_clk_description(self) -> &'static str {
        match self {
            Bus::Exmc => "samples the EXMC pins and runs the register file",
            Bus::Spi => "samples the SPI pins and runs the register file; may be unrelated to clk; SCK at most bus_clk/4",
            Bus::Wb => "the Wishbone clock (the SoC's): the front end and the register file run in it; may be unrelated to clk",
            Bus::Axil => "ACLK of the AXI4-Lite port: the front end and the register file run in it; may be unrelated to clk",
        }
    }
}

#[derive(Clone, Copy, PartialEq, Eq)]
pub struct ModuleName {
    bytes: [u8; ModuleName::MAX_LEN],
    len: u8,
}

impl ModuleName {
    pub const MAX_LEN: usize = 40;

    pub fn new(s: &str) -> Result<ModuleName, String> {
        const KEYWORDS: [&str; 24] = [
            "module", "endmodule", "input", "output", "inout", "wire", "reg", "integer", "assign", "always", "initial",
            "begin", "end", "if", "else", "case", "endcase", "for", "function", "task", "parameter", "localparam",
            "posedge", "negedge",
        ];
        let ok = !s.is_empty()
            && s.len() <= Self::MAX_LEN
            && s.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_')
            && !s.as_bytes()[0].is_ascii_digit()
            && !KEYWORDS.contains(&s);
        if !ok {
            return Err(format!(
                "--name {s:?}: a module name is 1 to {} letters, digits and _, not starting with a digit, and not a Verilog keyword",
                Self::MAX_LEN
            ));
        }
        let mut bytes = [0u8; Self::MAX_LEN];
        bytes[..s.len()].copy_from_slice(s.as_bytes());
        Ok(ModuleName { bytes, len: s.len() as u8 })
    }

    pub fn as_str(&self) -> &str {
        std::str::from_utf8(&self.bytes[..self.len as usize]).expect("ASCII")
    }
}

impl Default for ModuleName {
    fn default() -> Self {
        ModuleName::new(TOP_MODULE).expect("the default name is valid")
    }
}

impl std::fmt::Debug for ModuleName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{:?}", self.as_str())
    }
}

impl std::fmt::Display for ModuleName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

impl std::str::FromStr for ModuleName {
    type Err = String;
    fn from_str(s: &str) -> Result<ModuleName, String> {
        ModuleName::new(s)
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ExportOptions {
    /// The top module's name; submodules are `<name>__<path>`.
    pub name: ModuleName,
    pub axes: usize,
    pub arch: Arch,
    pub clock_hz: u32,
    pub fifo_depth: usize,
    /// The minimum period the core enforces, ticks (`--min-period`); `None` is the
    /// sustainable period ([`ExportOptions::sustainable_period_ticks`]).
    pub min_period: Option<u32>,
    /// The machine I/O (`--io`): its ports, blocks and registers.
    pub io: bool,
    /// With the machine I/O: the groups left out (`regs::IO_GROUPS` bits; 0 for `--io
    /// all`). Their ports are not in the Verilog, their registers and fields not in the
    /// table, and their logic is gated off by constants (synthesis removes it).
    pub io_omit: u8,
    /// The S-curve option (`--profiles trapezoid,scurve`): polynomial segments beside
    /// the trapezoid ones (TDM only).
    pub scurve: bool,
    /// Encoder feedback (`--encoder`): per axis the pins `enc_a`, `enc_b`, `enc_z`,
    /// the decoders, the shared following-error unit and their registers (TDM only).
    pub encoder: bool,
    /// The host bus (`--bus`): EXMC, or SPI in front of it.
    pub bus: Bus,
}

impl Default for ExportOptions {
    fn default() -> Self {
        ExportOptions {
            name: ModuleName::default(),
            axes: 2,
            arch: Arch::Tdm,
            clock_hz: 50_000_000,
            fifo_depth: FIFO_DEPTH,
            min_period: None,
            io: false,
            io_omit: 0,
            scurve: false,
            encoder: false,
            bus: Bus::Exmc,
        }
    }
}

/// `--profiles LIST`: the segment kinds the core runs: `trapezoid` (always) and
/// `scurve` (polynomial segments: the S-curve option). Returns whether `scurve` is in.
pub fn parse_profiles(s: &str) -> Result<bool, String> {
    let mut scurve = false;
    let mut trapezoid = false;
    for p in s.split(',').map(str::trim) {
        match p {
            "trapezoid" => trapezoid = true,
            "scurve" => scurve = true,
            other => return Err(format!("--profiles {s:?}: unknown profile {other:?}; profiles are trapezoid, scurve")),
        }
    }
    if !trapezoid {
        return Err(format!("--profiles {s:?}: trapezoid is always built (the stop ramps are trapezoids): use trapezoid or trapezoid,scurve"));
    }
    Ok(scurve)
}

/// The machine I/O's groups, as `--io` names them.
pub use crate::regs::IO_GROUPS;

/// What `--io` chose: whether the core has the machine I/O, and the groups left out.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct IoChoice {
    pub io: bool,
    /// `regs::IO_GROUPS` bits of the groups left out.
    pub omit: u8,
}

/// `--io GROUPS`: `all`, `none`, or a comma-separated list of [`IO_GROUPS`] (the
/// groups exported; every other one is left out).
pub fn parse_io(s: &str) -> Result<IoChoice, String> {
    match s {
        "all" => return Ok(IoChoice { io: true, omit: 0 }),
        "none" => return Ok(IoChoice { io: false, omit: 0 }),
        _ => {}
    }
    let mut groups = 0u8;
    for g in s.split(',').map(str::trim) {
        let Some(i) = IO_GROUPS.iter().position(|x| *x == g) else {
            return Err(format!("--io {s:?}: unknown group {g:?}; groups are {} (or all, none)", IO_GROUPS.join(", ")));
        };
        groups |= 1 << i;
    }
    Ok(IoChoice { io: true, omit: regs::IO_ALL & !groups })
}

/// The names of the groups in `groups` (`regs::IO_GROUPS` bits), in that order.
pub fn io_group_list(groups: u8) -> Vec<&'static str> {
    IO_GROUPS.iter().enumerate().filter(|(i, _)| groups >> i & 1 == 1).map(|(_, g)| *g).collect()
}

/// [`io_group_list`], comma-separated.
pub fn io_group_names(groups: u8) -> String {
    io_group_list(groups).join(",")
}

/// Largest `--min-period` (ID_MIN_PERIOD is a 16-bit register).
pub const MAX_MIN_PERIOD_TICKS: u32 = 0xFFFF;

impl ExportOptions {
    /// Checks the options; the message says what is supported.
    pub fn check(&self) -> Result<(), String> {
        if !(1..=MAX_AXES).contains(&self.axes) {
            return Err(format!("--axes {}: supported axis counts are 1 to {MAX_AXES}", self.axes));
        }
        if self.arch == Arch::Baseline && !BASELINE_AXES.contains(&self.axes) {
            return Err(format!("--arch baseline --axes {}: the baseline is built for {BASELINE_AXES:?} axes", self.axes));
        }
        if !CLOCK_HZ_RANGE.contains(&self.clock_hz) {
            return Err(format!(
                "--clock-hz {}: supported core clocks are {} to {} Hz",
                self.clock_hz,
                CLOCK_HZ_RANGE.start(),
                CLOCK_HZ_RANGE.end()
            ));
        }
        if !FIFO_DEPTHS.contains(&self.fifo_depth) {
            return Err(format!("--fifo-depth {}: supported period FIFO depths are {FIFO_DEPTHS:?}", self.fifo_depth));
        }
        if !self.io && self.io_omit != 0 {
            return Err("io_omit without the machine I/O".into());
        }
        if self.io && self.io_omit & regs::IO_ALL == regs::IO_ALL {
            return Err("--io: no group left to export".into());
        }
        if self.scurve && self.arch == Arch::Baseline {
            return Err("--profiles scurve with --arch baseline: the S-curve option is built for the TDM core only".into());
        }
        if self.encoder && self.arch == Arch::Baseline {
            return Err("--encoder with --arch baseline: encoder feedback is built for the TDM core only".into());
        }
        if self.io && self.arch == Arch::Baseline {
            return Err("--io with --arch baseline: the machine I/O is built for the TDM core only".into());
        }
        if let Some(m) = self.min_period {
            let floor = crate::model::segment::MIN_PERIOD_FLOOR_TICKS;
            if !(floor..=MAX_MIN_PERIOD_TICKS).contains(&m) {
                return Err(format!("--min-period {m}: supported minimum periods are {floor} to {MAX_MIN_PERIOD_TICKS} ticks"));
            }
        }
        Ok(())
    }

    /// The limits the exported core enforces.
    pub fn limits(&self) -> Limits {
        Limits::new(self.min_period_ticks() as u32).expect("the minimum period is in range (ExportOptions::check)")
    }

    pub fn params(&self) -> CoreParams {
        CoreParams {
            axes: self.axes,
            clock_hz: self.clock_hz,
            queue_depth: QUEUE_DEPTH,
            fifo_depth: self.fifo_depth,
            t_calc: self.t_calc_cycles(),
            min_period: self.min_period_ticks() as u32,
            io: self.io,
            io_omit: if self.io { self.io_omit } else { 0 },
            scurve: self.scurve,
            encoder: self.encoder,
        }
    }

    /// The minimum period the core enforces, ticks: `--min-period`, else the
    /// sustainable period.
    pub fn min_period_ticks(&self) -> u64 {
        self.min_period.map_or_else(|| self.sustainable_period_ticks(), u64::from)
    }

    /// Cycles the shared unit plans per period on each axis: the square-root path's
    /// t_calc, or [`POLY_T_CALC`] with the S-curve option.
    pub fn t_calc_cycles(&self) -> usize {
        if self.scurve {
            POLY_T_CALC
        } else {
            t_calc_sqrt(RADIX_BITS)
        }
    }

    /// The shared unit's longest segment setup, cycles: the decelerating trapezoid's,
    /// or the polynomial one's with the S-curve option when it is longer.
    pub fn longest_setup_cycles(&self) -> usize {
        let trap = crate::hdl::core::t_setup(RADIX_BITS, true);
        if self.scurve {
            trap.max(crate::hdl::core::T_POLY_SETUP)
        } else {
            trap
        }
    }

    /// Shortest step period an axis sustains without underrun, in ticks: K·t_calc
    /// for the TDM core (the shared unit serves K axes), t_calc for the baseline,
    /// and never below the 2-tick minimum of the step generator.
    pub fn sustainable_period_ticks(&self) -> u64 {
        let t = self.t_calc_cycles() as u64;
        let k = match self.arch {
            Arch::Tdm => self.axes as u64,
            Arch::Baseline => 1,
        };
        (k * t).max(crate::model::segment::MIN_PERIOD_FLOOR_TICKS as u64)
    }

    /// The highest step rate a segment may reach, steps/s: f·RMAX/2^32 with
    /// RMAX = ⌊2^32/(min_period + 1)⌋ (a little below f/(min_period + 1)).
    pub fn max_step_rate_hz(&self) -> f64 {
        crate::model::units::rate_to_steps_per_s(self.limits().max_rate(), self.clock_hz)
    }
}

macro_rules! stepper_fn {
    ($fname:ident, $top:ident) => {
        #[inline(never)]
        fn $fname<const K: usize, const S: usize>(params: CoreParams) -> String {
            let mut u = Box::new($top::<K, RADIX_BITS, FIFO_DEPTH, QUEUE_DEPTH, S>::new(params));
            u.connect_ports();
            generate_verilog(u.as_ref())
        }
    };
}
stepper_fn!(tdm_verilog, TdmStepper);
stepper_fn!(baseline_verilog, BaselineStepper);
stepper_fn!(tdm_io_verilog, TdmStepperIo);
stepper_fn!(tdm_enc_verilog, TdmStepperEnc);
stepper_fn!(tdm_io_enc_verilog, TdmStepperIoEnc);

macro_rules! dispatch {
    ($opts:expr, $params:expr, [$($k:literal),*], [$($kb:literal),*]) => {{
        let o = $opts;
        match o.arch {
            Arch::Tdm if o.io && o.encoder && o.scurve => match o.axes { $($k => tdm_io_enc_verilog::<$k, 1>($params),)* _ => unreachable!() },
            Arch::Tdm if o.io && o.encoder => match o.axes { $($k => tdm_io_enc_verilog::<$k, 0>($params),)* _ => unreachable!() },
            Arch::Tdm if o.encoder && o.scurve => match o.axes { $($k => tdm_enc_verilog::<$k, 1>($params),)* _ => unreachable!() },
            Arch::Tdm if o.encoder => match o.axes { $($k => tdm_enc_verilog::<$k, 0>($params),)* _ => unreachable!() },
            Arch::Tdm if o.io && o.scurve => match o.axes { $($k => tdm_io_verilog::<$k, 1>($params),)* _ => unreachable!() },
            Arch::Tdm if o.io => match o.axes { $($k => tdm_io_verilog::<$k, 0>($params),)* _ => unreachable!() },
            Arch::Tdm if o.scurve => match o.axes { $($k => tdm_verilog::<$k, 1>($params),)* _ => unreachable!() },
            Arch::Tdm => match o.axes { $($k => tdm_verilog::<$k, 0>($params),)* _ => unreachable!() },
            Arch::Baseline => match o.axes { $($kb => baseline_verilog::<$kb, 0>($params),)* _ => unreachable!() },
        }
    }};
}

/// Axis counts of the non-TDM baseline (it exists for the sweep; each count costs
/// compile time).
pub const BASELINE_AXES: [usize; 5] = [1, 2, 4, 8, 16];

/// The exported Verilog: top module `opts.name` ([`TOP_MODULE`] by default), each
/// submodule `<name>__<path>`.
pub fn verilog(opts: &ExportOptions) -> Result<String, String> {
    opts.check()?;
    if opts.bus != Bus::Exmc {
        return front_verilog(opts);
    }
    let params = opts.params();
    let o = *opts;
    // The blocks are large; build them on a thread with room for them.
    let text = std::thread::Builder::new()
        .stack_size(256 << 20)
        .spawn(move || dispatch!(o, params, [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16], [1, 2, 4, 8, 16]))
        .map_err(|e| format!("cannot start the generator thread: {e}"))?
        .join()
        .map_err(|_| "the Verilog generator panicked".to_string())?;
    let params = opts.params();
    if params.io && params.io_omit != 0 {
        // The machine I/O top has every group's pins; a wrapper of the export's name
        // leaves out those of the groups not exported (tied to 0: the core gates the
        // groups off by constants, so the level does not matter).
        let full = format!("{}__io_top", opts.name.as_str());
        let text = rename_top(&text, &full)?;
        return Ok(text + &io_wrapper_module(opts.name.as_str(), &full, opts.axes, params.io_groups(), params.encoder));
    }
    rename_top(&text, opts.name.as_str())
}

/// An export on a bus other than EXMC: the EXMC export as `<name>__exmc`, the bus's
/// front end as `<name>__<bus>` (its submodules `<name>__<bus>__<path>`), and the top
/// `<name>` that joins them: the EXMC pins become wires between the two.
fn front_verilog(opts: &ExportOptions) -> Result<String, String> {
    use std::fmt::Write as _;
    let name = opts.name.as_str();
    let bus = opts.bus.name();
    let inner_name = format!("{name}__exmc");
    let inner = ExportOptions { bus: Bus::Exmc, name: ModuleName::new(&inner_name).map_err(|e| format!("--name {name}: too long for the {bus} export ({e})"))?, ..*opts };
    let core = verilog(&inner)?;
    let mapped = regs::mapped(&opts.params());
    let (front, conn, what) = match opts.bus {
        Bus::Spi => {
            let mut f = crate::hdl::spi_front::SpiFront::default();
            f.clock.connect();
            f.reset.connect();
            f.cs_n.connect();
            f.sck.connect();
            f.mosi.connect();
            f.irq.connect();
            f.rdata.connect();
            f.connect_all();
            (
                generate_verilog(&f),
                ".cs_n(cs_n), .sck(sck), .mosi(mosi), .miso(miso), .miso_oe(miso_oe), .irq(irq),\n        .ne(x_ne), .noe(x_noe), .nwe(x_nwe), .addr(x_addr), .wdata(x_wdata), .rdata(x_rdata)".to_string(),
                "SPI (export --bus spi): the SPI front end",
            )
        }
        Bus::Wb => {
            let mut f = crate::hdl::wb_front::WbFront::new(&mapped);
            f.clock.connect();
            f.reset.connect();
            f.wb_cyc.connect();
            f.wb_stb.connect();
            f.wb_we.connect();
            f.wb_adr.connect();
            f.wb_sel.connect();
            f.wb_dat_w.connect();
            f.rdata.connect();
            f.connect_all();
            (
                generate_verilog(&f),
                ".wb_cyc(wb_cyc), .wb_stb(wb_stb), .wb_we(wb_we), .wb_adr(wb_adr), .wb_sel(wb_sel), .wb_dat_w(wb_dat_w),\n        .wb_dat_r(wb_dat_r), .wb_ack(wb_ack), .wb_err(wb_err),\n        .ne(x_ne), .noe(x_noe), .nwe(x_nwe), .addr(x_addr), .wdata(x_wdata), .rdata(x_rdata)".to_string(),
                "Wishbone B4 classic (export --bus wb): the Wishbone front end",
            )
        }
        Bus::Axil => {
            let mut f = crate::hdl::axil_front::AxilFront::new(&mapped);
            f.clock.connect();
            f.reset.connect();
            f.awvalid.connect();
            f.awaddr.connect();
            f.wvalid.connect();
            f.wdata.connect();
            f.wstrb.connect();
            f.bready.connect();
            f.arvalid.connect();
            f.araddr.connect();
            f.rready.connect();
            f.x_rdata.connect();
            f.connect_all();
            let ch = ["awaddr", "awvalid", "awready", "wdata", "wstrb", "wvalid", "wready", "bresp", "bvalid", "bready", "araddr", "arvalid", "arready", "rdata", "rresp", "rvalid", "rready"];
            let pins: Vec<String> = ch.iter().map(|c| format!(".{c}(s_axil_{c})")).collect();
            (
                generate_verilog(&f),
                format!("{},\n        .ne(x_ne), .noe(x_noe), .nwe(x_nwe), .x_addr(x_addr), .x_wdata(x_wdata), .x_rdata(x_rdata)", pins.join(", ")),
                "AXI4-Lite (export --bus axil): the AXI4-Lite front end",
            )
        }
        Bus::Exmc => unreachable!("the EXMC export has no front end"),
    };
    let front = rename_top(&front, &format!("{name}__{bus}"))?;
    let mine = ports_of(opts);
    let all = ports_of(&inner);
    let mut m = module_head(name, &format!("{name}: the core on {what} {name}__{bus} drives\n// the EXMC slave of {inner_name} inside bus_clk."), &mine);
    let aw = regs::ADDR_BITS;
    let _ = writeln!(m, "    wire x_ne, x_noe, x_nwe;\n    /* verilator lint_off UNUSEDSIGNAL */\n    wire x_oe; // the EXMC pad enable: no pads inside\n    /* verilator lint_on UNUSEDSIGNAL */\n    wire [{}:0] x_addr;\n    wire [15:0] x_wdata, x_rdata;", aw - 1);
    let _ = writeln!(m, "    {name}__{bus} bus(.clock(bus_clk), .reset(reset), {conn});");
    let _ = writeln!(m, "    {inner_name} core(");
    let exmc = |n: &str| match n {
        "ne" => Some("x_ne"),
        "noe" => Some("x_noe"),
        "nwe" => Some("x_nwe"),
        "addr" => Some("x_addr"),
        "data_in" => Some("x_wdata"),
        "data_out" => Some("x_rdata"),
        "data_oe" => Some("x_oe"),
        _ => None,
    };
    let conns: Vec<String> = all.iter().map(|p| format!("        .{}({})", p.name, exmc(p.name).unwrap_or(p.name))).collect();
    m += &conns.join(",\n");
    m += "\n    );\nendmodule\n";
    Ok(core + &front + &m)
}

/// The opening of a generated wrapper module: a comment line (`comment`, whose
/// further lines carry their own `// `), the port list and each port's declaration.
fn module_head(name: &str, comment: &str, ports: &[PortDoc]) -> String {
    use std::fmt::Write as _;
    let names: Vec<&str> = ports.iter().map(|p| p.name).collect();
    let mut m = format!("\n// {comment}\nmodule {name}({});\n", names.join(","));
    for p in ports {
        let kind = if p.direction == "input" { "input wire" } else { "output wire" };
        if p.width == 1 {
            let _ = writeln!(m, "    {kind} {};", p.name);
        } else {
            let _ = writeln!(m, "    {kind} [{}:0] {};", p.width - 1, p.name);
        }
    }
    m
}

/// The top module of an export with some machine I/O groups: `name`, with the ports
/// of [`ports`] for `groups`, around `full` (the machine I/O top with every group).
fn io_wrapper_module(name: &str, full: &str, axes: usize, groups: u8, encoder: bool) -> String {
    use std::fmt::Write as _;
    let mut mine = ports(axes, groups);
    let mut all = ports(axes, regs::IO_ALL);
    if encoder {
        mine.extend(encoder_ports(axes));
        all.extend(encoder_ports(axes));
    }
    let mut m = module_head(
        name,
        &format!(
            "{name}: the machine I/O core with the groups {} only (export --io); the input pins of\n// the others are not ports and are tied to 0 inside.",
            io_group_names(groups)
        ),
        &mine,
    );
    let _ = writeln!(m, "    {full} core(");
    let conns: Vec<String> = all
        .iter()
        .map(|p| {
            if mine.iter().any(|q| q.name == p.name) {
                format!("        .{}({})", p.name, p.name)
            } else {
                format!("        .{}({}'d0)", p.name, p.width)
            }
        })
        .collect();
    m += &conns.join(",\n");
    m += "\n    );\nendmodule\n";
    m
}

/// rust-hdl calls the top module `top` and each submodule `top$path$to$it`; the IP's
/// are `name` and `name__path__to__it` (no `$`: a plain Verilog-2001 identifier). The
/// names stay distinct (checked).
fn rename_top(text: &str, name: &str) -> Result<String, String> {
    let from = "\nmodule top(";
    if text.matches(from).count() != 1 {
        return Err("generated Verilog has no single `module top(`".into());
    }
    let text = text.replacen(from, &format!("\nmodule {name}("), 1);
    let ident = |c: char| c.is_ascii_alphanumeric() || c == '_' || c == '$';
    let mut out = String::with_capacity(text.len() + 4096);
    let mut rest = text.as_str();
    while let Some(k) = rest.find("top$") {
        let boundary = rest[..k].chars().last().is_none_or(|c| !ident(c));
        out.push_str(&rest[..k]);
        rest = &rest[k..];
        if boundary {
            let end = rest.find(|c: char| !ident(c)).unwrap_or(rest.len());
            out.push_str(name);
            out.push_str(&rest[3..end].replace('$', "__"));
            rest = &rest[end..];
        } else {
            out.push_str("top$");
            rest = &rest[4..];
        }
    }
    out.push_str(rest);
    let modules: Vec<&str> = out.lines().filter_map(|l| l.strip_prefix("module ")).map(|l| l.split('(').next().unwrap_or(l).trim()).collect();
    let distinct: std::collections::HashSet<&&str> = modules.iter().collect();
    if distinct.len() != modules.len() {
        return Err("renaming the submodules made two of them equal".into());
    }
    Ok(out)
}

/// One port of the exported module.
#[derive(Clone, Debug, Serialize, PartialEq, Eq)]
pub struct PortDoc {
    pub name: &'static str,
    pub direction: &'static str,
    pub width: usize,
    pub clock: &'static str,
    pub description: &'static str,
}

/// The ports of `tdm_stepper` for K axes, with those of the machine I/O groups in
/// `groups` (`regs::IO_GROUPS` bits; `drv_enable` with any group; a test holds this
/// list to the Verilog).
pub fn ports(axes: usize, groups: u8) -> Vec<PortDoc> {
    let p = |name, direction, width, clock, description| PortDoc { name, direction, width, clock, description };
    let mut v = vec![
        p("clk", "input", 1, "-", "core clock: every step period is counted in its ticks"),
        p("bus_clk", "input", 1, "-", "samples the EXMC pins; may be unrelated to clk"),
        p("reset", "input", 1, "async", "active high, synchronised into each clock; hold ≥ 4 cycles of the slower clock"),
        p("ne", "input", 1, "async", "EXMC chip select, active low"),
        p("noe", "input", 1, "async", "EXMC output enable (read strobe), active low"),
        p("nwe", "input", 1, "async", "EXMC write enable (write strobe), active low"),
        p("addr", "input", regs::ADDR_BITS, "async", "EXMC address, 16-bit word address"),
        p("data_in", "input", 16, "async", "EXMC data from the pads"),
        p("data_out", "output", 16, "bus_clk", "EXMC data to the pads"),
        p("data_oe", "output", 1, "async", "drive data_out onto the pads: !ne & !noe, combinational"),
        p("step", "output", axes, "clk", "STEP of axis a in bit a: one pulse per step, rising edge = the step; high half the period, at least STEP_HIGH and leaving STEP_LOW"),
        p("dir", "output", axes, "clk", "DIR of axis a in bit a: 1 = negative steps; changes while STEP is low or as it falls, DIR_SETUP before and DIR_HOLD after a rising edge"),
        p("irq", "output", 1, "bus_clk", "interrupt, active high: IRQ_* status under IRQ_MASK_*"),
        p("fsm_state", "output", crate::hdl::core::STATE_BITS, "clk", "scheduler state (Gray code), for waveforms; leave open"),
    ];
    let io = [
        (regs::IO_ESTOP, p("estop_n", "input", 1, "async", "emergency stop, active low by default (IO_POLARITY.ESTOP); synchronised and filtered: a hard stop of every axis, latched until IO_CMD.ESTOP_REARM")),
        (regs::IO_PROBE, p("probe", "input", 1, "async", "probe input, synchronised and filtered (IO_POLARITY, IO_FILTER_LO); its chosen edge latches every axis's position in the same tick (PROBE_POS)")),
        (regs::IO_LIMITS, p("limit_neg", "input", axes, "async", "limit switch at the negative end of axis a, bit a; synchronised and filtered, read in IO_AXIS; while active it stops the axis moving toward it (hard or controlled stop, STOP_MODE)")),
        (regs::IO_LIMITS, p("limit_pos", "input", axes, "async", "limit switch at the positive end of axis a, bit a; synchronised and filtered, read in IO_AXIS; while active it stops the axis moving toward it (hard or controlled stop, STOP_MODE)")),
        (regs::IO_HOME, p("home", "input", axes, "async", "home switch of axis a, bit a; synchronised and filtered, read in IO_AXIS; its chosen edge latches the axis's position (HOME_POS) and, armed in STOP_HOME, stops the moving axis")),
        (regs::IO_ALARM, p("alarm", "input", axes, "async", "driver alarm of axis a, bit a; synchronised and filtered: while active, drv_enable of the axis is low and the axis is held in a hard stop (in controlled mode: ramped down, drv_enable low once it is at rest)")),
        (regs::IO_ALL, p("drv_enable", "output", axes, "clk", "driver enable of axis a, bit a, registered: high only while the core runs, no hard stop holds (e-stop latch, watchdog; a controlled watchdog trip once every axis is at rest) and the axis's alarm is inactive (a controlled alarm: or the axis still moves)")),
    ];
    v.extend(io.into_iter().filter(|(g, _)| groups & g != 0).map(|(_, port)| port));
    v
}

/// The encoder feedback's ports (`--encoder`), after the machine I/O's.
pub fn encoder_ports(axes: usize) -> Vec<PortDoc> {
    let p = |name, description| PortDoc { name, direction: "input", width: axes, clock: "async", description };
    vec![
        p("enc_a", "quadrature line A of axis a's encoder, bit a; synchronised and filtered (ENC_FILTER), 4x decoded"),
        p("enc_b", "quadrature line B of axis a's encoder, bit a: the count goes up when A leads B (ENC_INVERT swaps)"),
        p("enc_z", "index of axis a's encoder, bit a: its active edge (ENC_INDEX_MODE) latches the count (ENC_INDEX) and, armed (ENC_ARM), clears it; tie to 0 without an index"),
    ]
}

/// The ports of the core `opts` exports: [`ports`], then the encoder's.
pub fn ports_of(opts: &ExportOptions) -> Vec<PortDoc> {
    let mut v = ports(opts.axes, opts.params().io_groups());
    if opts.bus != Bus::Exmc {
        let exmc = ["ne", "noe", "nwe", "addr", "data_in", "data_out", "data_oe"];
        let at = v.iter().position(|p| p.name == "ne").expect("EXMC pins");
        v.retain(|p| !exmc.contains(&p.name));
        v.splice(at..at, opts.bus.ports());
        for p in v.iter_mut().filter(|p| p.name == "bus_clk") {
            p.description = opts.bus.bus_clk_description();
        }
    }
    if opts.encoder {
        v.extend(encoder_ports(opts.axes));
    }
    v
}

/// The SPI front end's pins (`--bus spi`), in place of the EXMC pins.
pub fn spi_ports() -> Vec<PortDoc> {
    let p = |name, direction, clock, description| PortDoc { name, direction, width: 1, clock, description };
    vec![
        p("cs_n", "input", "async", "SPI chip select, active low; high ends the frame (a partial word is discarded)"),
        p("sck", "input", "async", "SPI clock, mode 0 or 3: MOSI is taken and MISO advanced on rising edges; high and low each at least 2 bus_clk cycles"),
        p("mosi", "input", "async", "SPI data from the host, MSB first"),
        p("miso", "output", "bus_clk", "SPI data to the host: the status byte, then read data; changes 3 bus_clk cycles after SCK rises"),
        p("miso_oe", "output", "async", "drive miso onto the pad: !cs_n, combinational"),
    ]
}

/// The Wishbone front end's pins (`--bus wb`), in place of the EXMC pins.
pub fn wb_ports() -> Vec<PortDoc> {
    let p = |name, direction, width, description| PortDoc { name, direction, width, clock: "bus_clk", description };
    vec![
        p("wb_cyc", "input", 1, "Wishbone CYC: a bus cycle is in progress"),
        p("wb_stb", "input", 1, "Wishbone STB: an access is requested (with CYC)"),
        p("wb_we", "input", 1, "Wishbone WE: 1 write, 0 read"),
        p("wb_adr", "input", regs::ADDR_BITS, "Wishbone ADR: the register's word address (each register is one 32-bit word)"),
        p("wb_sel", "input", 4, "Wishbone SEL: a write needs bits 1..0 (the register's 16 bits); bits 3..2 are ignored"),
        p("wb_dat_w", "input", 32, "Wishbone DAT_W: bits 15..0 are written"),
        p("wb_dat_r", "output", 32, "Wishbone DAT_R: the register in bits 15..0, bits 31..16 are 0; valid with ACK"),
        p("wb_ack", "output", 1, "Wishbone ACK: the access is done (one cycle)"),
        p("wb_err", "output", 1, "Wishbone ERR: refused, nothing accessed (an unmapped address, or a write without SEL[1:0])"),
    ]
}

/// The AXI4-Lite front end's pins (`--bus axil`), in place of the EXMC pins.
pub fn axil_ports() -> Vec<PortDoc> {
    use crate::hdl::axil_front::AXIL_ADDR_BITS;
    let p = |name, direction, width, description| PortDoc { name, direction, width, clock: "bus_clk", description };
    vec![
        p("s_axil_awaddr", "input", AXIL_ADDR_BITS, "write address, bytes: register w at 4·w (bits 1..0 ignored)"),
        p("s_axil_awvalid", "input", 1, "write address valid"),
        p("s_axil_awready", "output", 1, "write address ready: high while the slave's one-entry buffer is empty"),
        p("s_axil_wdata", "input", 32, "write data: bits 15..0 are the register's"),
        p("s_axil_wstrb", "input", 4, "write strobes: bits 1..0 both set write the register, neither writes nothing, one alone is SLVERR; bits 3..2 ignored"),
        p("s_axil_wvalid", "input", 1, "write data valid"),
        p("s_axil_wready", "output", 1, "write data ready: high while the slave's one-entry buffer is empty"),
        p("s_axil_bresp", "output", 2, "write response: OKAY (0), or SLVERR (2) for an unmapped address or half a register"),
        p("s_axil_bvalid", "output", 1, "write response valid, until BREADY"),
        p("s_axil_bready", "input", 1, "write response ready"),
        p("s_axil_araddr", "input", AXIL_ADDR_BITS, "read address, bytes: register w at 4·w (bits 1..0 ignored)"),
        p("s_axil_arvalid", "input", 1, "read address valid"),
        p("s_axil_arready", "output", 1, "read address ready: high while the slave's one-entry buffer is empty"),
        p("s_axil_rdata", "output", 32, "read data: the register in bits 15..0, bits 31..16 are 0"),
        p("s_axil_rresp", "output", 2, "read response: OKAY (0), or SLVERR (2, data 0) for an unmapped address"),
        p("s_axil_rvalid", "output", 1, "read data valid, until RREADY"),
        p("s_axil_rready", "input", 1, "read data ready"),
    ]
}

#[derive(Serialize)]
struct Manifest {
    top_module: String,
    arch: Arch,
    axes: usize,
    clock_hz: u32,
    radix_bits: usize,
    t_calc_cycles: usize,
    t_calc_uniform_cycles: usize,
    queue_depth: usize,
    period_fifo_depth: usize,
    command_fifo_depth: usize,
    min_period_ticks: u64,
    sustainable_period_ticks: u64,
    max_rate_q32: u32,
    max_step_rate_hz: f64,
    register_map_version: String,
    /// The machine I/O is in this core (`--io`).
    io: bool,
    /// With the machine I/O: the groups exported (else absent).
    #[serde(skip_serializing_if = "Option::is_none")]
    io_groups: Option<Vec<&'static str>>,
    /// With the machine I/O: the smallest STOP_DECEL the core accepts (else absent).
    #[serde(skip_serializing_if = "Option::is_none")]
    stop_decel_min: Option<u32>,
    /// Encoder feedback is in this core (`--encoder`; absent without it).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    encoder: bool,
    /// The host bus (`--bus`).
    bus: Bus,
    ports: Vec<PortDoc>,
    tools: Tools,
}

#[derive(Serialize)]
struct Tools {
    tdm_stepper: &'static str,
    rust_hdl: &'static str,
}

/// The manifest (manifest.json) as pretty JSON.
pub fn manifest_json(opts: &ExportOptions) -> String {
    serde_json::to_string_pretty(&manifest(opts)).expect("json") + "\n"
}

fn manifest(opts: &ExportOptions) -> Manifest {
    Manifest {
        top_module: opts.name.to_string(),
        arch: opts.arch,
        axes: opts.axes,
        clock_hz: opts.clock_hz,
        radix_bits: RADIX_BITS,
        t_calc_cycles: opts.params().t_calc,
        t_calc_uniform_cycles: crate::hdl::core::T_CALC_UNIFORM,
        queue_depth: QUEUE_DEPTH,
        period_fifo_depth: opts.fifo_depth,
        command_fifo_depth: crate::hdl::cdc::ASYNC_FIFO_DEPTH,
        min_period_ticks: opts.min_period_ticks(),
        sustainable_period_ticks: opts.sustainable_period_ticks(),
        max_rate_q32: opts.limits().max_rate(),
        max_step_rate_hz: opts.max_step_rate_hz(),
        register_map_version: format!("{}.{}", regs::VERSION >> 8, regs::VERSION & 0xFF),
        io: opts.io,
        io_groups: opts.io.then(|| io_group_list(opts.params().io_groups())),
        stop_decel_min: opts.io.then(|| opts.params().stop_decel_min()),
        encoder: opts.encoder,
        bus: opts.bus,
        ports: ports_of(opts),
        tools: Tools { tdm_stepper: env!("CARGO_PKG_VERSION"), rust_hdl: "0.46.0" },
    }
}
