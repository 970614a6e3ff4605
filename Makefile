# twowire-host: host controller IP core for Shearwater's 2-wire sensor link.
# `make demo` and `make test` work on a fresh Debian 12 machine: both install
# what is missing first (scripts/bootstrap.sh).

SHELL  := /bin/bash
PY     := .venv/bin/python
RTL    := $(sort $(wildcard rtl/*.v))
JOBS   ?= 2
# the clocks the engine is linted at with one channel (the link's bench,
# tb/tb_link.v): each one elaborates different logic (the carrier's period
# and stretch, the pin's glitch filter)
LINT_CLOCKS := 4000000 10500000 12000000 27000000 48000000 100000000 200000000

# Each flow beside the core (synthesis, formal, fuzzing, soak, board tops) has
# its own makefile in mk/. One adds what make test must also run to TEST_EXTRA
# (run two at a time with the static checks), or to TEST_LATE when it reuses
# what a TEST_EXTRA target builds (run after them, one at a time), and what
# make bench must also print to BENCH_EXTRA.
TEST_EXTRA  :=
TEST_LATE   :=
BENCH_EXTRA :=
include $(sort $(wildcard mk/*.mk))

.PHONY: all deps test lint pytest swtest demo waves bench clean help regs check-regs
.PHONY: fusesoc wavedrom check-wavedrom
.PHONY: rig

all: test

help:
	@echo "make demo    - scripted session against modelled cells, writes build/demo/demo.vcd"
	@echo "make test    - the whole regression: lint + every test (installs what is missing)"
	@echo "make lint    - Verilator -Wall and a Yosys synthesis check of rtl/"
	@echo "make board-lint - the same for the UART bridge and the board tops (boards/)"
	@echo "make waves   - open the demo waveform in GTKWave (docs/waves.md)"
	@echo "make formal  - SymbiYosys proofs (docs/formal.md)"
	@echo "make fuzz    - libFuzzer on the driver's decoders, FUZZ_SECONDS each (docs/fuzzing.md)"
	@echo "make soak    - SOAK_TRANSACTIONS through the C driver on the Verilated core (docs/soak.md)"
	@echo "make rig     - 16 modelled cells (RIG=32: 32) read at once on the Verilated core, rate vs the limit (docs/rig.md)"
	@echo "make synth   - bitstreams for the three boards (docs/boards.md)"
	@echo "make bench   - resources/Fmax (docs/resources.md), driver size, bus cost"
	@echo "make fusesoc-synth - FuseSoC synthesis targets (synth_ice40, synth_ecp5, the three boards) through the YoWASP shims"

deps: .venv/.requirements.stamp
.venv/.requirements.stamp: requirements.txt scripts/bootstrap.sh
	bash scripts/bootstrap.sh

lint: deps
	@set -e; for clk in $(LINT_CLOCKS); do \
	    echo "verilator -Wall twh_engine CLK_HZ=$$clk CHANNELS=1"; \
	    verilator --lint-only -Wall -Irtl $(RTL) --top-module twh_engine -GCLK_HZ=$$clk -GCHANNELS=1; \
	done
	@set -e; for top in twh_wb twh_axil; do for ch in 1 3 8 16 32; do \
	    echo "verilator -Wall $$top CHANNELS=$$ch"; \
	    verilator --lint-only -Wall -Irtl $(RTL) --top-module $$top -GCHANNELS=$$ch; \
	done; done
	@set -e; for top in twh_wb twh_axil; do for ch in 1 3; do \
	    echo "verilator -Wall $$top CHANNELS=$$ch lean (PROG_TIMING=0 POLLING=0)"; \
	    verilator --lint-only -Wall -Irtl $(RTL) --top-module $$top -GCHANNELS=$$ch \
	        -GPROG_TIMING=0 -GPOLLING=0; \
	done; done
	@set -e; for cfg in 4000000:1 4000000:3 10500000:5 12000000:8 16000000:16 32000000:32 48000000:32; do \
	    echo "verilator -Wall twh_engine CLK_HZ=$${cfg%%:*} CHANNELS=$${cfg#*:}"; \
	    verilator --lint-only -Wall -Irtl $(RTL) --top-module twh_engine \
	        -GCLK_HZ=$${cfg%%:*} -GCHANNELS=$${cfg#*:}; \
	done
	@mkdir -p build/lint
	@# the three Yosys checks two at a time (each is one process), each into
	@# its log; a failed run stops at its wait, a warning at the grep after
	@set -e; run() { yosys -q -l build/lint/yosys_$$1.log -p "read_verilog -Irtl $(RTL); $$2 synth_ice40 -top $$3; check -assert" >/dev/null; }; \
	echo "yosys: synth_ice40 twh_wb, twh_axil"; \
	run twh_wb "" twh_wb & p1=$$!; run twh_axil "" twh_axil & p2=$$!; wait $$p1; wait $$p2; \
	echo "yosys: synth_ice40 twh_engine"; \
	run twh_engine "" twh_engine; \
	for log in twh_wb twh_axil twh_engine; do \
	    ! grep -E "^Warning" build/lint/yosys_$$log.log || (echo "yosys warnings above ($$log)" && false); \
	done
	@echo "lint clean"

# --maxschedchunk=1: a core that is free takes the next test (the long ones
# come first, tb/conftest.py), rather than each core a fixed quarter of the
# list; --durations: the slowest tests of every run, so a slow-down shows
# the day it happens; tb/conftest.py fails any test over its stated budget
PYTEST_ARGS := -n $(JOBS) --maxschedchunk=1 --durations=12 --durations-min=5

pytest: deps
	$(PY) -m pytest $(PYTEST_ARGS) -m "not slow" tb

# the long end-to-end runs (constrained random with coverage, the PC tool
# against the simulated board): CI runs them after make test
.PHONY: test-slow
test-slow: deps
	$(PY) -m pytest $(PYTEST_ARGS) -m slow tb

# the C driver: cmocka unit tests (plain and ASan/UBSan), Cortex-M0 size
swtest: deps
	$(MAKE) -C sw test size

# make test: the static checks and short runs two at a time, then TEST_LATE,
# then the cocotb suite on both cores; scripts/stages.py ends with each
# stage's wall time
empty :=
space := $(empty) $(empty)
TEST_STATIC = check-regs check-wavedrom lint fusesoc swtest $(TEST_EXTRA)
test: deps
	@MAKE="$(MAKE)" python3 scripts/stages.py --jobs $(JOBS) --title "make test" \
	    $(subst $(space),+,$(strip $(TEST_STATIC))) $(TEST_LATE) pytest

# Files generated from rdl/twh_regs.rdl (scripts/gen_regs.sh): committed, and
# check-regs (part of test) fails when they are stale or the header does not
# compile as gnu99 (host gcc; arm-none-eabi-gcc too when installed).
REGS_GEN := sw/include/twh_regs.h docs/registers.md
REGS_CFLAGS := -std=gnu99 -Wall -Wextra -Werror -pedantic -fsyntax-only -Isw/include
regs: deps
	bash scripts/gen_regs.sh

check-regs: deps
	@rm -rf build/gen && bash scripts/gen_regs.sh build/gen
	@set -e; for f in $(REGS_GEN); do \
	    diff -u $$f build/gen/$$f || { echo "$$f is stale: run 'make regs'"; exit 1; }; \
	done
	gcc $(REGS_CFLAGS) sw/test/twh_regs_h_check.c
	@if command -v arm-none-eabi-gcc >/dev/null; then \
	    echo "arm-none-eabi-gcc $(REGS_CFLAGS) -mthumb -mcpu=cortex-m0 sw/test/twh_regs_h_check.c"; \
	    arm-none-eabi-gcc $(REGS_CFLAGS) -mthumb -mcpu=cortex-m0 sw/test/twh_regs_h_check.c; \
	else echo "check-regs: arm-none-eabi-gcc not installed, cross-compile check skipped"; fi
	@echo "generated register files current"

demo: deps
	$(PY) tb/demo.py

waves: build/demo/demo.vcd
	bash scripts/bootstrap.sh --waves
	cp tb/demo.gtkw build/demo/demo.gtkw
	gtkwave build/demo/demo.vcd build/demo/demo.gtkw

# a waveform older than the bench or the session lacks their signals
build/demo/demo.vcd: tb/tb_core.v tb/demo_session.py
	$(MAKE) demo

clean:
	rm -rf build .pytest_cache tb/__pycache__ sw/build

# Figures, never asserted: driver size on Cortex-M0, bus accesses and
# interrupt waits per transaction (co-simulated).
bench: deps $(BENCH_EXTRA)
	$(MAKE) -s -C sw size shared
	$(PY) -c "import sys; sys.path.insert(0, 'tb'); import conftest, simrun; \
	  simrun.run('tb_core', 'bench_driver', 'bench', \
	    parameters={'CLK_HZ': 4000000, 'CHANNELS': 3, 'FIFO_DEPTH': 16, 'BUS': 0}, \
	    tb_sources=['tb_core.v'], \
	    extra_env={'COCOTB_LOG_LEVEL': 'WARNING', 'GPI_LOG_LEVEL': 'WARNING', \
	      'TWH_CLK_HZ': '4000000', 'TWH_CHANNELS': '3', 'TWH_FIFO_DEPTH': '16', 'TWH_BUS': '0'})"

# FuseSoC (twowire-host.core): Verilator -Wall lint of twh_wb and the Icarus
# smoke test tb/tb_link_smoke.v, through fusesoc/edalize (work dir build/fusesoc).
FUSESOC := .venv/bin/fusesoc --cores-root .
fusesoc: deps
	$(FUSESOC) run --build-root build/fusesoc/lint --target=lint open:twowire:host
	$(FUSESOC) run --build-root build/fusesoc/sim --target=sim open:twowire:host

# WaveDrom timing diagrams: docs/wavedrom/*.json -> *.svg (yowasp-wavedrom).
# check-wavedrom renders into build/wavedrom and fails when a committed SVG
# differs from its source.
wavedrom: deps
	bash scripts/gen_wavedrom.sh

check-wavedrom: deps
	@rm -rf build/wavedrom && bash scripts/gen_wavedrom.sh build/wavedrom
	@set -e; for j in docs/wavedrom/*.json; do \
	    s=$${j%.json}.svg; \
	    diff -q $$s build/wavedrom/$$(basename $$s) >/dev/null \
	        || { echo "$$s is stale: run 'make wavedrom'"; exit 1; }; \
	done
	@echo "wavedrom diagrams current"
