# hfi-sensorless top-level entry points. Everything installs itself: `make test` works on a fresh clone.
SHELL := /bin/bash
.SHELLFLAGS := -eu -o pipefail -c
ENV := source scripts/env.sh &&
PYTEST_ARGS ?=
# Parallel pytest workers (pytest-xdist); the cocotb builds and simulations are independent. `--dist loadgroup`
# keeps the tests of one xdist_group (those sharing an expensive module fixture) on one worker.
PYTEST_JOBS ?= auto

.PHONY: setup run test bench clean distclean

setup:
	bash scripts/setup.sh

# Closed-loop backend of `make run`: rtl (firmware on the Verilated SoC, default), golden (Python model)
# or hls (HLS C++ kernels + host firmware, native).
BACKEND ?= rtl
run: setup
	$(ENV) .venv/bin/hfi run scenarios/fullload_start.toml --backend $(BACKEND)

# pytest exit code 5 ("no tests collected") counts as a failure. make test leaves out the tests marked deep and runs
# the cocotb random runs at the suite's depth (cocotb_tests/hdl_runner.py); make deep runs every test at full depth
# (HFI_DEEP=1: 100 000 random vectors per block under Verilator, the gate-level replay): README, Tests. make test
# builds the co-simulation without the profile-guided training (HFI_SIM_PGO=0: hfi/rtl_backend.py build_sim).
PYTEST = rc=0; $(ENV) .venv/bin/python -m pytest -q -p no:cacheprovider -n $(PYTEST_JOBS) --dist loadgroup
PYTEST_RC = if [[ $$rc -eq 5 ]]; then echo "make $@: pytest collected no tests" >&2; exit 1; fi; exit $$rc
test: setup
	export HFI_SIM_PGO=0; $(PYTEST) -m "not deep" $(PYTEST_ARGS) || rc=$$?; $(PYTEST_RC)

.PHONY: deep
deep: setup
	export HFI_DEEP=1; $(PYTEST) $(PYTEST_ARGS) || rc=$$?; $(PYTEST_RC)

# make test's wall time beside the machine's speed (the plant benchmark before and after), scaled to the speed the
# 15 minutes were set at (scripts/suite_time.py, docs/testing.md). Run it on an otherwise idle machine.
.PHONY: suite-time
suite-time: setup
	$(ENV) .venv/bin/python scripts/suite_time.py --jobs $(PYTEST_JOBS) -- $(PYTEST_ARGS)

# The plant and closed-loop benchmarks (scripts/bench_plant.py, bench_golden.py, bench_rtl.py, bench_hls.py).
bench: setup
	$(ENV) .venv/bin/hfi bench

# The paper's figure groups, full length (out/paper/metrics.json and plots).
.PHONY: paper
paper: setup
	$(ENV) .venv/bin/hfi paper

# The fault matrix of the 002 drive (docs/faults.md): out/faults/matrix.md, matrix.json and a figure per run.
.PHONY: faults
faults: setup
	$(ENV) .venv/bin/hfi faults

# The four systems side by side (docs/compare.md): out/compare/report.md, angle_vs_load.png, ripple_vs_load.png, sensitivity.png
# (30-65 min on 2 cores; cached in out/sweep/, so a second call only reports).
.PHONY: compare
compare: setup
	$(ENV) .venv/bin/hfi compare

# The scale sweep of issue 21 (docs/sweep.md "Measured"): 2000 runs of the 002 start-up on the local cluster, the
# same sweep through a scheduler address (Dask's scheduler and worker commands, scripts/sweep_cluster.py), the same
# design with each remedy tried (--set), the figures (about 40 minutes on 2 cores).
STARTUP_REMEDIES = control.speed_bw=8Hz control.speed_bw=12Hz injection.V_h=140V control.dtc_zone=0.3A control.dtc_zone=1.2A
.PHONY: sweep-scale
sweep-scale: setup
	$(ENV) .venv/bin/hfi sweep sweeps/startup_2000.toml
	$(ENV) .venv/bin/python scripts/sweep_cluster.py sweeps/startup_2000.toml
	$(ENV) for r in $(STARTUP_REMEDIES); do .venv/bin/hfi sweep sweeps/startup_2000.toml --quiet --set $$r || exit 1; done
	$(ENV) .venv/bin/python scripts/startup_2000_figure.py --out out/sweep/startup_2000/startup_2000.png \
	  $(foreach r,$(STARTUP_REMEDIES),--variant "out/sweep/startup_2000+$(r)/results.parquet")
	$(ENV) .venv/bin/python scripts/startup_loss_figure.py --out out/sweep/startup_2000/startup_loss.png

# Self-commissioning of the four papers' motors (docs/commissioning.md): out/commission/<scenario>/commission.json,
# commissioned.toml, figures; then the rotor angle and polarity from 20 random standstill angles per PM motor.
# COMMISSION_BACKEND=rtl runs the identification on the soft core (about 11 minutes per motor; docs/commissioning.md).
COMMISSION_SCENARIOS = fullload_start bench2_loadsteps xue2022_noload tap2023_step varatharajan2020_speedrange
COMMISSION_BACKEND ?= golden
.PHONY: commission
commission: setup
	@for s in $(COMMISSION_SCENARIOS); do $(ENV) .venv/bin/hfi commission scenarios/$$s.toml --out out/commission/$$s \
		--backend $(COMMISSION_BACKEND) \
		|| echo "commission: $$s FAILED (docs/commissioning.md)"; done
	$(ENV) .venv/bin/python scripts/commission_polarity.py --n 20

# Synthesis and timing of the hfi_dsp IP, the hfi_soc SoC and its CPU alone (yowasp Yosys + nextpnr-ecp5): out/synth/report.json + table.
.PHONY: synth
synth: setup
	$(ENV) .venv/bin/python scripts/synth_report.py

# Gate-level replay (docs/rtl.md): the ECP5 netlist of hfi_dsp with Yosys's cell models (Verilator) replays
# the RTL replay's 0.2 s of golden closed loop, bit-exact; make deep runs a short one. Part of make synth.
.PHONY: gatelevel
gatelevel: setup
	$(ENV) .venv/bin/python scripts/gatelevel.py
synth: gatelevel

# Bitstream of the SoC for a board (docs/boards.md): BOARD=ulx3s or tangnano20k; SCENARIO = the firmware's
# configuration; out/bitstream/<board>/ with the timing summary.
BOARD ?= ulx3s
SCENARIO ?= scenarios/fullload_start.toml
.PHONY: bitstream
bitstream: setup
	$(ENV) .venv/bin/python scripts/bitstream.py $(BOARD) --scenario $(SCENARIO)

# Formal proof (SymbiYosys, k-induction) that no leg ever has both switches on (also run by make test).
.PHONY: prove
prove: setup
	$(ENV) .venv/bin/python scripts/prove.py

# Register fuzzing (docs/fuzz.md): FUZZ_TRANSACTIONS random AXI4-Lite transactions on hfi_dsp with every
# clock checked (no shoot-through, no gate on while a fault or STO/DESAT holds, bus answered), then as many
# accesses on the SoC's native bus (hfi_soc_ctl, hfi_soc_acc); FUZZ_SEED=<n> replays a run (default: a
# fresh seed, printed). make test runs short ones. Then FUZZ_SCENARIO_EXAMPLES arbitrary scenario values (Hypothesis,
# a new search each time; a failure prints its example): each is refused in one line or accepted, never a traceback.
FUZZ_TRANSACTIONS ?= 1000000
FUZZ_SCENARIO_EXAMPLES ?= 100000
.PHONY: fuzz
fuzz: setup
	$(ENV) FUZZ_TRANSACTIONS=$(FUZZ_TRANSACTIONS) $(if $(FUZZ_SEED),FUZZ_SEED=$(FUZZ_SEED)) \
	    FUZZ_SCENARIO_EXAMPLES=$(FUZZ_SCENARIO_EXAMPLES) \
	    .venv/bin/python -m pytest -q -s -p no:cacheprovider cocotb_tests/test_reg_fuzz.py cocotb_tests/test_soc_bus_fuzz.py \
	    tests/test_scenario_fuzz.py::test_arbitrary_values_are_accepted_or_refused

# Register maps: rtl/regs/hfi_regs.rdl, hfi_soc.rdl and hfi_acc.rdl -> C headers, golden/regmap.py, socmap.py + accmap.py, docs, Verilog constants.
.PHONY: regs
regs: setup
	$(ENV) .venv/bin/python scripts/gen_regs.py

clean:
	rm -rf out sim_build results.xml .pytest_cache
	find . -path ./.venv -prune -o \( -name __pycache__ -o -name sim_build \) -type d -print0 | xargs -0 rm -rf
	if [[ -f golden/plant/src/Makefile ]]; then $(MAKE) -C golden/plant/src clean; fi

distclean: clean
	rm -rf .venv *.egg-info
