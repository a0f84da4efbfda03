//! The files `export` writes around the Verilog for the FPGA engineer who integrates
//! the core: the lint waivers, an instantiation template, timing constraints for the
//! two clocks and the asynchronous EXMC pins (XDC, SDC, LPF and a PCF note), and a
//! FuseSoC CAPI2 core description. Each is generated from the same port list as the
//! manifest ([`crate::export::ports`]), so none can name a port the Verilog lacks.

use crate::export::{ports_of, ExportOptions};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The lint waivers for the exported Verilog (Verilator configuration file), the
/// same file the tests lint with.
pub const LINT_WAIVERS: &str = include_str!("../../verilog/lint_waivers.vlt");

/// File names in the export folder.
pub const WAIVER_FILE: &str = "tdm_stepper_waivers.vlt";
pub const TEMPLATE_FILE: &str = "tdm_stepper_inst.vh";
pub const XDC_FILE: &str = "tdm_stepper.xdc";
pub const SDC_FILE: &str = "tdm_stepper.sdc";
pub const LPF_FILE: &str = "tdm_stepper.lpf";
pub const PCF_FILE: &str = "tdm_stepper_pcf.txt";
pub const CORE_FILE: &str = "tdm_stepper.core";

/// The MCU driver and the planners (portable C99), written beside the register
/// header they include: (file name, text). The S-curve planner is written with every
/// export (it plans on the host too); the driver pushes its segments only with a
/// header from an S-curve export.
pub const C_SOURCES: [(&str, &str); 6] = [
    ("tdm_driver.h", include_str!("../../c/tdm_driver.h")),
    ("tdm_driver.c", include_str!("../../c/tdm_driver.c")),
    ("tdm_planner.h", include_str!("../../c/tdm_planner.h")),
    ("tdm_planner.c", include_str!("../../c/tdm_planner.c")),
    ("tdm_scurve.h", include_str!("../../c/tdm_scurve.h")),
    ("tdm_scurve.c", include_str!("../../c/tdm_scurve.c")),
];

/// `bus_clk` frequency the constraints assume (the register file and the slave close
/// timing above it on the measured parts; edit the files for another).
pub const BUS_CLK_HZ: u32 = 100_000_000;

fn ns(hz: u32) -> String {
    format!("{:.3}", 1e9 / hz as f64)
}

fn mhz(hz: u32) -> String {
    format!("{:.3}", hz as f64 / 1e6)
}

/// An instance of the core with every port connected to a signal of the same name
/// and commented (direction, width, clock domain, meaning).
pub fn instantiation_template(opts: &ExportOptions) -> String {
    let top = opts.name.as_str();
    let ps = ports_of(opts);
    let mut t = String::new();
    let _ = writeln!(
        t,
        "// {top}: instantiation template for K = {} axes, core clock {} Hz.\n\
         // Include it where the signals it names exist (or copy it and rename them);\n\
         // registers.md and manifest.json describe every port and register.",
        opts.axes, opts.clock_hz
    );
    let width = ps.iter().map(|p| p.name.len()).max().unwrap_or(0);
    let _ = writeln!(t, "{top} u_{top} (");
    for (i, p) in ps.iter().enumerate() {
        let comma = if i + 1 < ps.len() { "," } else { " " };
        let conn = if p.name == "fsm_state" { String::new() } else { p.name.to_string() };
        let bits = if p.width == 1 { "1 bit".to_string() } else { format!("{} bits", p.width) };
        let _ = writeln!(
            t,
            "    .{:w$} ({:w$}){comma} // {} {bits}, {}: {}",
            p.name,
            conn,
            p.direction,
            if p.clock == "-" { "clock".to_string() } else { format!("domain {}", p.clock) },
            p.description,
            w = width
        );
    }
    t.push_str(");\n");
    ascii(&t)
}

/// ASCII only, for Verilog comments (some tools read Verilog as Latin-1).
/// The `tdm-stepper export` command line that makes this export (every option
/// spelled out).
pub fn export_command(opts: &ExportOptions) -> String {
    let io = if !opts.io {
        "none".to_string()
    } else if opts.io_omit == 0 {
        "all".to_string()
    } else {
        crate::export::io_group_names(crate::regs::IO_ALL & !opts.io_omit)
    };
    format!(
        "tdm-stepper export --axes {} --arch {} --clock-hz {} --fifo-depth {} --min-period {} --name {} --io {io} --profiles {}{} --bus {}",
        opts.axes,
        opts.arch.name(),
        opts.clock_hz,
        opts.fifo_depth,
        opts.min_period_ticks(),
        opts.name.as_str(),
        if opts.scurve { "trapezoid,scurve" } else { "trapezoid" },
        if opts.encoder { " --encoder" } else { "" },
        opts.bus.name()
    )
}

/// The comment the exported Verilog opens with, as hand-written IP does: the core,
/// its register map version, K, options and clocks, the command that made it, and
/// every port with its meaning (the instantiation template's words).
pub fn verilog_header(opts: &ExportOptions) -> String {
    let p = opts.params();
    let v = crate::regs::VERSION;
    let mut t = String::new();
    let _ = writeln!(t, "// {}: a tdm-stepper IP core (time-division multiplexed stepper-motor step generator),", opts.name.as_str());
    let _ = writeln!(t, "// generated Verilog-2001: do not edit, export again.");
    let _ = writeln!(t, "//");
    let _ = writeln!(t, "// Register map version {}.{} (ID_VERSION 0x{v:04X}); K = {} axes; {} architecture.", v >> 8, v & 0xFF, opts.axes, opts.arch.name());
    let _ = writeln!(
        t,
        "// Options: bus {}; machine I/O {}; profiles {}; encoder feedback {} (ID_OPTIONS 0x{:04X}).",
        opts.bus.name(),
        if opts.io { if opts.io_omit == 0 { "all".to_string() } else { crate::export::io_group_names(crate::regs::IO_ALL & !opts.io_omit) } } else { "none".to_string() },
        if opts.scurve { "trapezoid, scurve" } else { "trapezoid" },
        if opts.encoder { "yes" } else { "no" },
        p.options_word()
    );
    let _ = writeln!(
        t,
        "// Clocks: clk {} Hz (every step period is counted in its ticks; minimum period {} ticks);",
        opts.clock_hz,
        opts.min_period_ticks()
    );
    let _ = writeln!(t, "// bus_clk runs the host bus and the register file ({} MHz in the constraints); the two are unrelated.", mhz(BUS_CLK_HZ));
    let _ = writeln!(t, "// Made by: {}", export_command(opts));
    let _ = writeln!(t, "// registers.md and manifest.json, written beside this file, describe every register and port.");
    let _ = writeln!(t, "//");
    let _ = writeln!(t, "// Ports:");
    let ps = ports_of(opts);
    let width = ps.iter().map(|p| p.name.len()).max().unwrap_or(0);
    for q in &ps {
        let bits = if q.width == 1 { "1 bit".to_string() } else { format!("{} bits", q.width) };
        let _ = writeln!(t, "//   {:w$} {:6} {:8} {}", q.name, q.direction, bits, q.description, w = width);
    }
    ascii(&t)
}

pub fn ascii(t: &str) -> String {
    t.replace('≥', ">=").replace('≤', "<=").replace('·', "*").chars().map(|c| if c.is_ascii() { c } else { '?' }).collect()
}

const CONSTRAINT_NOTES: &str = "\
The core has two clocks: clk (every step period is counted in its ticks) and
bus_clk (samples the EXMC pins). They are unrelated: every crossing between them is
a two-flip-flop synchroniser, a Gray-pointer FIFO, a toggle handshake, or the output
timing registers (STEP_HIGH ... DIR_HOLD), which the register file changes only while
the core is held in reset, so no path between them is timed. The EXMC pins (ne, noe, nwe, addr, data_in) and reset are
asynchronous: each enters through two flip-flop stages in bus_clk, and the slave
captures a write only after two equal samples, so no input delay applies to them.
data_out is a bus_clk register held from the read's start until the next read; the
MCU samples it at least 5 bus_clk cycles after NOE falls (registers.md, \"The bus\"),
so it is not timed against a clock either. data_oe = !ne & !noe is combinational
from pins to pad enable: keep that path short so the pads release the bus promptly.
step, dir and irq are registers; step and dir change on clk.";

const SPI_CONSTRAINT_NOTES: &str = "\
With --bus spi the EXMC pins are wires inside: the SPI front end drives them in
bus_clk. cs_n, sck and mosi are asynchronous: each enters through two flip-flops in
bus_clk, and MOSI is taken on SCK edges seen there, so no input delay applies. miso
is a bus_clk register that changes 3 bus_clk cycles after SCK rises, so the host
samples it at its next rising edge at least 1 bus_clk cycle later (at SCK =
bus_clk/4): keep the miso pad path within that cycle.";

const MMIO_CONSTRAINT_NOTES: &str = "\
With --bus wb or --bus axil the EXMC pins are wires inside: the bus front end drives
them in bus_clk, which is the bus's own clock. The bus ports are synchronous to
bus_clk and meant to be nets of your SoC (timed there as any bus_clk path); only
reset is asynchronous.";

/// The notes of the export's bus, if it has its own.
fn bus_notes(opts: &ExportOptions) -> Option<&'static str> {
    match opts.bus {
        crate::export::Bus::Exmc => None,
        crate::export::Bus::Spi => Some(SPI_CONSTRAINT_NOTES),
        crate::export::Bus::Wb | crate::export::Bus::Axil => Some(MMIO_CONSTRAINT_NOTES),
    }
}

fn comment_block(prefix: &str, text: &str) -> String {
    text.lines().map(|l| if l.is_empty() { prefix.trim_end().to_string() } else { format!("{prefix}{l}") }).collect::<Vec<_>>().join("\n")
}

/// Vivado (XDC) or SDC (Quartus, Libero, Gowin and other Synopsys-style tools):
/// the same commands; `xdc` adds Vivado's scoping note.
fn sdc_like(opts: &ExportOptions, xdc: bool) -> String {
    let top = opts.name.as_str();
    let mut t = String::new();
    let _ = writeln!(t, "{}", comment_block("# ", &format!("{top} timing constraints (K = {}, clk {} Hz).", opts.axes, opts.clock_hz)));
    let _ = writeln!(t, "#\n{}", comment_block("# ", CONSTRAINT_NOTES));
    if let Some(notes) = bus_notes(opts) {
        let _ = writeln!(t, "#\n{}", comment_block("# ", notes));
    }
    if xdc {
        let _ = writeln!(
            t,
            "#\n# Read it scoped to the core (read_xdc -ref {top} {XDC_FILE}), so that get_ports names\n\
             # the core's ports; or replace each get_ports with your top level's pins and nets."
        );
    }
    let _ = writeln!(
        t,
        "#\n# Clocks: delete these two lines if your design already creates the clocks that\n\
         # drive clk and bus_clk (the clock group below must then name yours)."
    );
    let _ = writeln!(t, "create_clock -name tdm_clk -period {} [get_ports clk]", ns(opts.clock_hz));
    let _ = writeln!(t, "create_clock -name tdm_bus_clk -period {} [get_ports bus_clk]", ns(BUS_CLK_HZ));
    let _ = writeln!(t, "set_clock_groups -asynchronous -group [get_clocks tdm_clk] -group [get_clocks tdm_bus_clk]");
    let _ = writeln!(t, "# Asynchronous inputs: synchronised in bus_clk.");
    let dp = if xdc { " -datapath_only" } else { "" };
    if matches!(opts.bus, crate::export::Bus::Wb | crate::export::Bus::Axil) {
        let _ = writeln!(t, "set_false_path -from [get_ports {{reset}}]");
        let _ = writeln!(t, "# The bus ports: synchronous to bus_clk, timed inside your SoC (no I/O delays here).");
    } else if opts.bus == crate::export::Bus::Spi {
        let _ = writeln!(t, "set_false_path -from [get_ports {{reset cs_n sck mosi}}]");
        let _ = writeln!(t, "# miso: a bus_clk register the host samples at SCK's next rising edge, at least 1 bus_clk cycle later.");
        let _ = writeln!(t, "set_false_path -to [get_ports {{miso}}]");
        let _ = writeln!(t, "# miso_oe: combinational from cs_n to the pad enable.");
        let _ = writeln!(t, "set_max_delay{dp} 8.000 -from [get_ports {{cs_n}}] -to [get_ports miso_oe]");
    } else {
        let _ = writeln!(t, "set_false_path -from [get_ports {{reset ne noe nwe addr[*] data_in[*]}}]");
        let _ = writeln!(t, "# data_out: held for the MCU, sampled at least 5 bus_clk cycles after NOE falls.");
        let _ = writeln!(t, "set_false_path -to [get_ports {{data_out[*]}}]");
        let _ = writeln!(t, "# data_oe: combinational from the strobes to the pad enable.");
        let _ = writeln!(t, "set_max_delay{dp} 8.000 -from [get_ports {{ne noe}}] -to [get_ports data_oe]");
    }
    let _ = writeln!(t, "# step, dir, irq: registers for motor drivers and the MCU, not timed against an external clock.");
    let _ = writeln!(t, "set_false_path -to [get_ports {{step[*] dir[*] irq fsm_state[*]}}]");
    if opts.io {
        let _ = writeln!(t, "# Machine I/O: the input pins enter through two flip-flops in clk; drv_enable is a clk register.");
        let ins: Vec<String> = ports_of(opts)
            .iter()
            .filter(|p| p.direction == "input" && ["estop_n", "probe", "limit_neg", "limit_pos", "home", "alarm"].contains(&p.name))
            .map(|p| if p.width > 1 || p.name.starts_with("limit") || ["home", "alarm"].contains(&p.name) { format!("{}[*]", p.name) } else { p.name.to_string() })
            .collect();
        if !ins.is_empty() {
            let _ = writeln!(t, "set_false_path -from [get_ports {{{}}}]", ins.join(" "));
        }
        let _ = writeln!(t, "set_false_path -to [get_ports {{drv_enable[*]}}]");
    }
    t
}

pub fn xdc(opts: &ExportOptions) -> String {
    sdc_like(opts, true)
}

pub fn sdc(opts: &ExportOptions) -> String {
    sdc_like(opts, false)
}

/// nextpnr-ecp5 (and Diamond) LPF: the two clock frequencies. nextpnr times each
/// clock domain on its own and does not time cross-domain paths or paths from and
/// to unconstrained I/O, which is what the notes ask for.
pub fn lpf(opts: &ExportOptions) -> String {
    let top = opts.name.as_str();
    let mut t = String::new();
    let _ = writeln!(t, "{}", comment_block("# ", &format!("{top} clock constraints for nextpnr-ecp5 (K = {}).", opts.axes)));
    let _ = writeln!(t, "#\n{}", comment_block("# ", CONSTRAINT_NOTES));
    if let Some(notes) = bus_notes(opts) {
        let _ = writeln!(t, "#\n{}", comment_block("# ", notes));
    }
    let _ = writeln!(
        t,
        "#\n# nextpnr times each clock domain separately and leaves cross-domain paths and\n\
         # paths from and to unconstrained I/O untimed, as the notes above require. Use\n\
         # the names of the nets that drive clk and bus_clk in your design."
    );
    let _ = writeln!(t, "FREQUENCY PORT \"clk\" {} MHz;", mhz(opts.clock_hz));
    let _ = writeln!(t, "FREQUENCY PORT \"bus_clk\" {} MHz;", mhz(BUS_CLK_HZ));
    t
}

/// nextpnr-ice40 and nextpnr-generic read PCF; the clock lines it needs.
pub fn pcf_note(opts: &ExportOptions) -> String {
    let top = opts.name.as_str();
    let mut t = String::new();
    let _ = writeln!(t, "{}", comment_block("# ", &format!("{top} clock constraints, PCF style (nextpnr-ice40), K = {}.", opts.axes)));
    let _ = writeln!(
        t,
        "# Add these lines to your .pcf (with your nets' names); the notes in {LPF_FILE}\n\
         # apply: nextpnr leaves cross-domain paths and unconstrained I/O untimed."
    );
    let _ = writeln!(t, "set_frequency clk {}", mhz(opts.clock_hz));
    let _ = writeln!(t, "set_frequency bus_clk {}", mhz(BUS_CLK_HZ));
    t
}

/// FuseSoC CAPI2 core description: the Verilog, the waivers, the MCU's C files, a lint
/// target (Verilator -Wall) and a simulation target (Icarus) on the smoke testbench.
pub fn fusesoc_core(opts: &ExportOptions) -> String {
    let top = opts.name.as_str();
    format!(
        "CAPI=2:\n\
         name: tdm-stepper:ip:{top}_k{k}:{ver}\n\
         description: TDM multi-axis stepper motor controller, K = {k} axes, clk {hz} Hz\n\
         \n\
         filesets:\n\
         \x20 rtl:\n\
         \x20   files:\n\
         \x20     - tdm_stepper.v\n\
         \x20   file_type: verilogSource\n\
         \x20 waivers:\n\
         \x20   files:\n\
         \x20     - {WAIVER_FILE}\n\
         \x20   file_type: vlt\n\
         \x20 smoke_tb:\n\
         \x20   files:\n\
         \x20     - {TB_FILE}\n\
         \x20   file_type: verilogSource\n\
         \x20 mcu_driver:\n\
         \x20   files:\n\
         {c_files}\
         \x20   file_type: cSource\n\
         \n\
         targets:\n\
         \x20 default:\n\
         \x20   filesets: [rtl]\n\
         \x20   toplevel: {top}\n\
         \x20 lint:\n\
         \x20   default_tool: verilator\n\
         \x20   filesets: [rtl, waivers]\n\
         \x20   toplevel: {top}\n\
         \x20   tools:\n\
         \x20     verilator:\n\
         \x20       mode: lint-only\n\
         \x20       verilator_options: [-Wall]\n\
         \x20 sim:\n\
         \x20   default_tool: icarus\n\
         \x20   filesets: [rtl, smoke_tb]\n\
         \x20   toplevel: {top}_smoke_tb\n",
        k = opts.axes,
        hz = opts.clock_hz,
        ver = env!("CARGO_PKG_VERSION"),
        c_files = mcu_files(),
    )
}

/// The `mcu_driver` fileset's lines: the register header, then the driver and the
/// planner, headers marked as include files (not used by any target: firmware builds
/// take them from here).
fn mcu_files() -> String {
    std::iter::once(crate::export::HEADER_FILE)
        .chain(C_SOURCES.iter().map(|&(name, _)| name))
        .map(|f| {
            if f.ends_with(".h") {
                format!("      - {f}: {{is_include_file: true}}\n")
            } else {
                format!("      - {f}\n")
            }
        })
        .collect()
}

pub const TB_FILE: &str = "tdm_stepper_smoke_tb.v";

/// A smoke testbench for Icarus (and the FuseSoC sim target): resets the core,
/// reads ID_MAGIC and ID_AXES through the export's bus at a slow, safe timing (and,
/// on Wishbone and AXI4-Lite, an unmapped address, which must be refused), and
/// prints PASS or FAIL (with `$fatal` on failure). One generator for every bus: each
/// bus gives its pins and a `read16` task ([`smoke_bus`]).
pub fn smoke_testbench(opts: &ExportOptions) -> String {
    let top = opts.name.as_str();
    let p = opts.params();
    let magic = crate::regs::register("ID_MAGIC").reset_value(&p);
    let axes = crate::regs::register("ID_AXES").reset_value(&p);
    let a_magic = crate::regs::addr("ID_MAGIC");
    let a_axes = crate::regs::addr("ID_AXES");
    let aw = crate::regs::ADDR_BITS;
    let b = smoke_bus(opts);
    // Wishbone and AXI4-Lite also read an unmapped address, which must be refused.
    let (hole_doc, hole_read, hole_ok, hole_msg) = match b.hole {
        Some(h) => (
            ", and an\n// unmapped address, which must be refused",
            format!("    read16({aw}'h{h:03X}, v_hole, e_hole);\n"),
            " && e_hole",
            format!(", address {h:#05x} refused"),
        ),
        None => ("", String::new(), "", String::new()),
    };
    format!(
        "`timescale 1ns/1ps\n\
// Smoke test of the exported {top}{on}: reset, then read ID_MAGIC and ID_AXES\n\
// {how}{hole_doc}. Prints PASS or FAIL.\n\
module {top}_smoke_tb;\n\
  reg clk = 0, bus_clk = 0, reset = 1;\n\
  wire irq;\n\
  wire [{km}:0] step, dir;\n\
  wire [{sm}:0] fsm_state;\n\
{decl}\
  always #10 clk = !clk;\n\
  always #5.003 bus_clk = !bus_clk;\n\
  {top} dut (.clk(clk), .bus_clk(bus_clk), .reset(reset), {conn},\n\
    .step(step), .dir(dir), .irq(irq), .fsm_state(fsm_state));\n\
{task}\
  reg [15:0] v_magic, v_axes, v_hole;\n\
  reg e_magic, e_axes, e_hole;\n\
  initial begin\n\
    #200 reset = 0; #500;\n\
    read16({aw}'h{a_magic:03X}, v_magic, e_magic);\n\
    read16({aw}'h{a_axes:03X}, v_axes, e_axes);\n\
{hole_read}\
    if (v_magic == 16'h{magic:04X} && v_axes == 16'd{axes} && !e_magic && !e_axes{hole_ok}) begin\n\
      $display(\"PASS: ID_MAGIC %h, ID_AXES %0d{hole_msg}\", v_magic, v_axes);\n\
      $finish;\n\
    end else begin\n\
      $display(\"FAIL: ID_MAGIC %h (want {magic:04x}), ID_AXES %0d (want {axes}), errors %b%b%b\", v_magic, v_axes, e_magic, e_axes, e_hole);\n\
      $fatal(1);\n\
    end\n\
  end\n\
endmodule\n",
        on = b.on,
        how = b.how,
        decl = b.decl,
        conn = b.conn,
        task = b.task,
        km = opts.axes - 1,
        sm = crate::hdl::core::STATE_BITS - 1,
    )
}

/// What the smoke testbench needs of one bus: where it reads (for the comment), its
/// declarations and connections, a task `read16(address, value, error)`, and an
/// unmapped address to try if the bus refuses one.
struct SmokeBus {
    on: &'static str,
    how: &'static str,
    decl: String,
    conn: String,
    task: String,
    hole: Option<usize>,
}

fn smoke_bus(opts: &ExportOptions) -> SmokeBus {
    let aw = crate::regs::ADDR_BITS;
    // The first word address that no register maps (Wishbone and AXI4-Lite refuse it).
    let unmapped = crate::regs::mapped(&opts.params()).iter().position(|m| !m);
    match opts.bus {
        crate::export::Bus::Exmc => SmokeBus {
            on: "",
            how: "over the EXMC pins with wide strobes (20 bus_clk cycles)",
            decl: format!("  reg ne = 1, noe = 1, nwe = 1;\n  reg [{}:0] addr = 0;\n  reg [15:0] data_in = 0;\n  wire [15:0] data_out;\n  wire data_oe;\n", aw - 1),
            conn: ".ne(ne), .noe(noe), .nwe(nwe),\n    .addr(addr), .data_in(data_in), .data_out(data_out), .data_oe(data_oe)".into(),
            task: format!(
                "  task read16(input [{}:0] a, output [15:0] v, output bad);\n\
                 \x20   begin\n\
                 \x20     addr = a; ne = 0; #50; noe = 0; #200; v = data_out; bad = 0; noe = 1; ne = 1; #100;\n\
                 \x20   end\n\
                 \x20 endtask\n",
                aw - 1
            ),
            hole: None,
        },
        crate::export::Bus::Spi => SmokeBus {
            on: " on SPI",
            how: "in SPI read frames (mode 0, SCK = bus_clk/20), with the status byte's pattern",
            decl: "  reg cs_n = 1, sck = 0, mosi = 0;\n  wire miso, miso_oe;\n".into(),
            conn: ".cs_n(cs_n), .sck(sck), .mosi(mosi),\n    .miso(miso), .miso_oe(miso_oe)".into(),
            task: format!(
                "  // One byte out on MOSI and in from MISO, MSB first: MISO is sampled at each rising edge.\n\
                 \x20 task xfer(input [7:0] out, output [7:0] in);\n\
                 \x20   integer i;\n\
                 \x20   begin\n\
                 \x20     for (i = 7; i >= 0; i = i - 1) begin\n\
                 \x20       mosi = out[i]; #100; sck = 1; in[i] = miso; #100; sck = 0;\n\
                 \x20     end\n\
                 \x20   end\n\
                 \x20 endtask\n\
                 \x20 reg [7:0] st, junk, hi, lo;\n\
                 \x20 // A one-word read frame: command (read, LEN 1, address bit 8), address, turnaround,\n\
                 \x20 // data; an error if the status byte lacks its pattern (bits 5..0).\n\
                 \x20 task read16(input [8:0] a, output [15:0] v, output bad);\n\
                 \x20   begin\n\
                 \x20     cs_n = 0; #100;\n\
                 \x20     xfer({{7'b0000000, a[8]}}, st); xfer(a[7:0], junk); xfer(8'h00, junk);\n\
                 \x20     xfer(8'h00, hi); xfer(8'h00, lo); v = {{hi, lo}}; bad = st[5:0] != 6'h{:02X};\n\
                 \x20     #100 cs_n = 1; #200;\n\
                 \x20   end\n\
                 \x20 endtask\n",
                crate::regs::SPI_STATUS_PATTERN
            ),
            hole: None,
        },
        crate::export::Bus::Wb => SmokeBus {
            on: " on Wishbone",
            how: "in Wishbone classic cycles",
            decl: format!("  reg cyc = 0, stb = 0, we = 0;\n  reg [{}:0] adr = 0;\n  wire [31:0] dat_r;\n  wire ack, err;\n", aw - 1),
            conn: ".wb_cyc(cyc), .wb_stb(stb), .wb_we(we), .wb_adr(adr), .wb_sel(4'hF), .wb_dat_w(32'd0),\n    .wb_dat_r(dat_r), .wb_ack(ack), .wb_err(err)".into(),
            task: format!(
                "  // One Wishbone classic read: CYC and STB until ACK or ERR.\n\
                 \x20 task read16(input [{}:0] a, output [15:0] v, output bad);\n\
                 \x20   begin\n\
                 \x20     @(negedge bus_clk); adr = a; cyc = 1; stb = 1;\n\
                 \x20     @(posedge bus_clk); while (!ack && !err) @(posedge bus_clk);\n\
                 \x20     v = dat_r[15:0]; bad = err; #1 cyc = 0; stb = 0;\n\
                 \x20   end\n\
                 \x20 endtask\n",
                aw - 1
            ),
            hole: unmapped,
        },
        crate::export::Bus::Axil => SmokeBus {
            on: " on AXI4-Lite",
            how: "in AXI4-Lite reads",
            decl: format!("  reg arvalid = 0;\n  reg [{}:0] araddr = 0;\n  wire arready, rvalid;\n  wire [31:0] rdata;\n  wire [1:0] rresp, bresp;\n  wire awready, wready, bvalid;\n", aw + 1),
            conn: ".s_axil_awaddr(11'd0), .s_axil_awvalid(1'b0), .s_axil_awready(awready), .s_axil_wdata(32'd0),\n    .s_axil_wstrb(4'd0), .s_axil_wvalid(1'b0), .s_axil_wready(wready), .s_axil_bresp(bresp), .s_axil_bvalid(bvalid),\n    .s_axil_bready(1'b1), .s_axil_araddr(araddr), .s_axil_arvalid(arvalid), .s_axil_arready(arready),\n    .s_axil_rdata(rdata), .s_axil_rresp(rresp), .s_axil_rvalid(rvalid), .s_axil_rready(1'b1)".into(),
            task: format!(
                "  // One AXI4-Lite read: AR until ARREADY, then R (RREADY is tied high).\n\
                 \x20 task read16(input [{}:0] a, output [15:0] v, output bad);\n\
                 \x20   begin\n\
                 \x20     @(negedge bus_clk); araddr = {{a, 2'b00}}; arvalid = 1;\n\
                 \x20     @(posedge bus_clk); while (!arready) @(posedge bus_clk);\n\
                 \x20     #1 arvalid = 0;\n\
                 \x20     @(posedge bus_clk); while (!rvalid) @(posedge bus_clk);\n\
                 \x20     v = rdata[15:0]; bad = rresp != 2'b00;\n\
                 \x20   end\n\
                 \x20 endtask\n",
                aw - 1
            ),
            hole: unmapped,
        },
    }
}

/// Every package file: (name, text).
pub fn files(opts: &ExportOptions) -> Vec<(&'static str, String)> {
    vec![
        (WAIVER_FILE, LINT_WAIVERS.to_string()),
        (TEMPLATE_FILE, instantiation_template(opts)),
        (XDC_FILE, xdc(opts)),
        (SDC_FILE, sdc(opts)),
        (LPF_FILE, lpf(opts)),
        (PCF_FILE, pcf_note(opts)),
        (CORE_FILE, fusesoc_core(opts)),
        (TB_FILE, smoke_testbench(opts)),
    ]
    .into_iter()
    .chain(C_SOURCES.iter().map(|&(name, text)| (name, text.to_string())))
    .collect()
}

/// Files written by [`export`].
#[derive(Clone, Debug)]
pub struct Exported {
    pub files: Vec<PathBuf>,
}

/// Writes the IP into `dir`: the Verilog ([`crate::export::verilog`]), the C header,
/// the register map, the manifest and the package files ([`files`]).
pub fn export(opts: &ExportOptions, dir: &Path) -> Result<Exported, String> {
    let v = crate::export::verilog(opts)?;
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let p = opts.params();
    let core = [
        ("tdm_stepper.v", verilog_header(opts) + &v),
        (crate::export::HEADER_FILE, crate::regs::c_header(&p, opts.name.as_str())),
        ("registers.md", crate::regs::markdown(&p)),
        ("manifest.json", crate::export::manifest_json(opts)),
    ];
    let mut out = Vec::new();
    for (name, text) in core.into_iter().chain(files(opts)) {
        let path = dir.join(name);
        std::fs::write(&path, text).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        out.push(path);
    }
    Ok(Exported { files: out })
}
