//! A motor with an encoder for whole-system runs (`export --encoder`): a Verilog module
//! `enc_rig` around the exported core that closes the loop. Each axis's motor follows
//! the core's STEP and DIR (one step per rising STEP edge, in `clk`), unless its
//! `stall` pin holds it; a rising `slip` pin throws it back [`RigConfig::slip_steps`]
//! steps. Its encoder has `num / 2^shift` counts per step (not an integer: 4,000
//! counts per revolution against 3,200 steps is 5/4) and an index once per revolution:
//! the encoder's position is ⌊steps·num / 2^shift⌋ counts, and its lines A, B step
//! towards it one count every `gap` ticks (A leads B counting up: 00, 10, 11, 01), Z
//! high at the counts ≡ `index_at` (mod `cpr`). With `bounce` high, A bounces: a
//! one-tick glitch three ticks after each count, shorter than a filter of 2 or more.
//!
//! Ports: those of `tdm_stepper` but the encoder pins (and the machine I/O's, tied
//! inactive, with [`RigConfig::io`]), then `stall`, `slip` (K bits)
//! and `bounce` (inputs), and `count0` (axis 0's encoder position, counts; an output
//! to watch).

use std::fmt::Write as _;

/// The motor and encoder of every axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RigConfig {
    /// Counts per step = num / 2^shift.
    pub num: u32,
    pub shift: u32,
    /// clk ticks between two counts of the lines (≥ 1).
    pub gap: u32,
    /// Counts per revolution, and the count of the index within it.
    pub cpr: i32,
    pub index_at: i32,
    /// Steps a slip throws the motor back.
    pub slip_steps: i32,
    /// The core has the machine I/O (`export --io all`): its inputs tied inactive
    /// (estop_n high, the others low), drv_enable left open.
    pub io: bool,
}

impl Default for RigConfig {
    fn default() -> Self {
        RigConfig { num: 5, shift: 2, gap: 6, cpr: 4000, index_at: 1000, slip_steps: 40, io: false }
    }
}

impl RigConfig {
    /// The encoder position of a motor at `steps`.
    pub fn counts(&self, steps: i64) -> i64 {
        (steps * self.num as i64) >> self.shift
    }
    /// The ratio as ENC_RATIO takes it (Q16.16).
    pub fn ratio_q16(&self) -> u32 {
        (self.num << 16) >> self.shift
    }
}

/// The Verilog of `enc_rig` for a core `core` (the exported top module) with `axes`
/// axes and `state_bits` bits of `fsm_state`, appended to the core's Verilog.
pub fn rig_verilog(core: &str, axes: usize, state_bits: usize, cfg: &RigConfig) -> String {
    assert!(cfg.gap >= 1 && cfg.cpr > 0);
    let k = axes;
    let mut v = String::new();
    let _ = writeln!(v, "\n// enc_rig: motors with encoders around {core} (tdm_stepper::verify::encoder).");
    let _ = writeln!(
        v,
        "module enc_rig(input clk, input bus_clk, input reset, input ne, input noe, input nwe, input [8:0] addr, input [15:0] data_in,\n    output [15:0] data_out, output data_oe, output [{km}:0] step, output [{km}:0] dir, output irq, output [{sm}:0] fsm_state,\n    input [{km}:0] stall, input [{km}:0] slip, input bounce, output [31:0] count0);",
        km = k - 1,
        sm = state_bits - 1
    );
    let _ = writeln!(v, "  wire [{}:0] ea;\n  wire [{0}:0] eb;\n  wire [{0}:0] ez;", k - 1);
    let _ = writeln!(
        v,
        "  {core} dut(.clk(clk), .bus_clk(bus_clk), .reset(reset), .ne(ne), .noe(noe), .nwe(nwe), .addr(addr), .data_in(data_in), .data_out(data_out), .data_oe(data_oe), .step(step), .dir(dir), .irq(irq), .fsm_state(fsm_state), .enc_a(ea), .enc_b(eb), .enc_z(ez){io});",
        io = if cfg.io {
            format!(", .estop_n(1'b1), .probe(1'b0), .limit_neg({k}'d0), .limit_pos({k}'d0), .home({k}'d0), .alarm({k}'d0), .drv_enable()")
        } else {
            String::new()
        }
    );
    let _ = writeln!(v, "  genvar i;\n  generate for (i = 0; i < {k}; i = i + 1) begin : m");
    v.push_str("    reg sp, slp;\n    reg signed [31:0] mpos, cnt;\n    reg [15:0] gap;\n    reg [3:0] gl;\n");
    let _ = writeln!(v, "    wire signed [47:0] prod = $signed(mpos) * $signed(48'd{});", cfg.num);
    let _ = writeln!(v, "    wire signed [31:0] target = prod >>> {};", cfg.shift);
    v.push_str("    wire [1:0] ph = cnt[1:0];\n");
    v.push_str("    wire a = (ph == 2'd1) | (ph == 2'd2);\n    wire b = (ph == 2'd2) | (ph == 2'd3);\n");
    let _ = writeln!(v, "    wire signed [31:0] rel = cnt - {};", cfg.index_at);
    let _ = writeln!(v, "    wire signed [31:0] zm = rel % {0};\n    assign ez[i] = (zm == 0);", cfg.cpr);
    v.push_str("    assign ea[i] = a ^ (bounce & (gl == 4'd1));\n    assign eb[i] = b;\n");
    v.push_str("    always @(posedge clk) begin\n");
    v.push_str("      sp <= step[i];\n      slp <= slip[i];\n");
    v.push_str("      if (gl != 0) gl <= gl - 1;\n");
    v.push_str("      if (reset) begin\n        mpos <= 0; cnt <= 0; gap <= 0; gl <= 0;\n      end else begin\n");
    let _ = writeln!(v, "        if (slip[i] & !slp) mpos <= mpos - {};", cfg.slip_steps);
    v.push_str("        else if (step[i] & !sp & !stall[i]) mpos <= dir[i] ? mpos - 1 : mpos + 1;\n");
    let _ = writeln!(
        v,
        "        if (gap != 0) gap <= gap - 1;\n        else if (cnt != target) begin\n          cnt <= (target > cnt) ? cnt + 1 : cnt - 1;\n          gap <= {};\n          gl <= 4'd4;\n        end",
        cfg.gap - 1
    );
    v.push_str("      end\n    end\n  end endgenerate\n");
    v.push_str("  assign count0 = m[0].cnt;\nendmodule\n");
    v
}
