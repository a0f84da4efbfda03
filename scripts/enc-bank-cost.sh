#!/usr/bin/env bash
# The encoder option's clk-side block alone (EncoderBank: K decoders, the velocity
# prescaler, the extension and the following-error unit), while the
# option is not yet in an exported core: xc7 cells from yosys synth_xilinx -flatten
# at K = 1, 2, 8 and 16, and the slope per axis. Every port is a pin, so nothing is
# removed: the probe latch is counted (a core without the probe ties it off).
# Usage: scripts/enc-bank-cost.sh. Needs yosys; builds the Verilog by running one
# hdl_encoder test. Writes only to a temporary folder.
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
