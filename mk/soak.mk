# Soak (sim/soak/, docs/soak.md): the C driver on the Verilated twh_wb with
# three channels, each answered by a C++ O2-cell model injecting faults.
#
#   make soak [SOAK_TRANSACTIONS=10000] [SOAK_SEED=n] [SOAK_FAULT_RATE=0.2]
#             [SOAK_ICARUS_TRANSACTIONS=12]   (Icarus comparison, 0: skip)
#   make soak-smoke            build + 200 transactions, seed 1 unless SOAK_SEED
#                              is given (part of make test: ~15 s CPU)
#   make soak-logic            the C++ device logic against tb/periph_model.py
#   make soak-icarus [SOAK_ICARUS_TRANSACTIONS=12]
#                              the same traffic through the cocotb
#                              co-simulation on Icarus, for the rate figures
#   make cosim-session         the driver session of tb/test_cosim.py on the
#                              Verilated core, the SoC's cells (part of make
#                              test; see build/demo/session_verilator.txt)
#
# An empty SOAK_SEED draws a fresh seed; the run prints it for a replay.
SOAK_TRANSACTIONS ?= 10000
SOAK_SEED         ?=
SOAK_FAULT_RATE   ?= 0.2
SOAK_ICARUS_TRANSACTIONS ?= 12
SOAK_ARGS         ?=

SOAK_CLK_HZ   := 4000000
SOAK_CHANNELS := 3
SOAK_DIR      := build/soak
SOAK_OBJ      := $(SOAK_DIR)/obj
SOAK_BIN      := $(SOAK_DIR)/soak
SOAK_PROF_H   := $(SOAK_DIR)/gen/soak_profiles.h
SOAK_RTL      := $(RTL) tb/tb_line.v sim/soak/soak_top.v
SOAK_DRV      := $(SOAK_DIR)/twh.o $(SOAK_DIR)/twh_decode.o $(SOAK_DIR)/twh_page.o
SOAK_CXXOBJ   := $(SOAK_DIR)/soak_main.o $(SOAK_DIR)/periph.o
SOAK_VLIB     := $(SOAK_OBJ)/Vsoak_top__ALL.a $(SOAK_OBJ)/verilated.o $(SOAK_OBJ)/verilated_threads.o
SOAK_VINC      = $(shell verilator --getenv VERILATOR_ROOT 2>/dev/null)/include

# the driver exactly as sw/Makefile builds it (C99, its strict warnings)
SOAK_CFLAGS   := -std=c99 -Wall -Wextra -Werror -pedantic -Wshadow -Wconversion \
                 -Wstrict-prototypes -Wmissing-prototypes -O2 -Isw/include
SOAK_CXXFLAGS  = -std=c++17 -Wall -Wextra -Werror -O2 \
                 -DSOAK_CLK_HZ=$(SOAK_CLK_HZ) -DSOAK_CHANNELS=$(SOAK_CHANNELS) \
                 -I$(SOAK_OBJ) -I$(SOAK_DIR)/gen -Isw/include -Isw/tools \
                 -isystem $(SOAK_VINC) -isystem $(SOAK_VINC)/vltstd
# -O3 / --x-assign fast: speed; the model is one clock, synchronous reset
SOAK_VFLAGS   := --cc -O3 --x-assign fast --x-initial fast --noassert -Wall \
                 -Irtl --top-module soak_top -GCLK_HZ=$(SOAK_CLK_HZ) \
                 -GCHANNELS=$(SOAK_CHANNELS) -GFIFO_DEPTH=16

.PHONY: soak soak-smoke soak-logic soak-icarus soak-build
TEST_EXTRA += soak-smoke

soak-build: $(SOAK_BIN)

# After the Verilator run, a short run of the same traffic through the cocotb
# co-simulation on Icarus (SOAK_ICARUS_TRANSACTIONS, 0 skips it), then both
# rates side by side.
soak: $(SOAK_BIN)
	@rm -f $(SOAK_DIR)/verilator_rate.txt
	nice $(SOAK_BIN) --transactions $(SOAK_TRANSACTIONS) --fault-rate $(SOAK_FAULT_RATE) \
	    --rate-file $(SOAK_DIR)/verilator_rate.txt $(if $(SOAK_SEED),--seed $(SOAK_SEED)) $(SOAK_ARGS)
	@if [ "$(SOAK_ICARUS_TRANSACTIONS)" != 0 ]; then \
	    $(MAKE) -s soak-icarus SOAK_ICARUS_TRANSACTIONS=$(SOAK_ICARUS_TRANSACTIONS) SOAK_SEED=$(SOAK_SEED); fi
	@echo; echo "== simulation speed, same soak traffic (docs/soak.md) =="
	@cat $(SOAK_DIR)/verilator_rate.txt
	@if [ -f $(SOAK_DIR)/icarus_rate.txt ]; then cat $(SOAK_DIR)/icarus_rate.txt; fi

# a fixed seed keeps make test reproducible; make soak draws fresh ones
soak-smoke: $(SOAK_BIN)
	nice $(SOAK_BIN) --transactions 200 --progress 0 --seed $(or $(SOAK_SEED),1)

# Every frame the C++ device handled, replayed through tb/periph_model.py's
# PeripheralLogic: both must answer alike (the soak checks the core against
# the C++ model, this checks the model against the Python one).
soak-logic: $(SOAK_BIN) deps
	nice $(SOAK_BIN) --transactions 600 --progress 0 --trace-logic $(SOAK_DIR)/logic.txt \
	    $(if $(SOAK_SEED),--seed $(SOAK_SEED))
	$(PY) sim/soak/check_logic.py $(SOAK_DIR)/logic.txt

soak-icarus: deps
	$(MAKE) -s -C sw shared
	SOAK_FAULT_RATE=$(SOAK_FAULT_RATE) nice $(PY) sim/soak/icarus_soak.py \
	    $(SOAK_ICARUS_TRANSACTIONS) $(SOAK_SEED)

$(SOAK_PROF_H): sim/soak/gen_profiles.py tb/profiles.py tb/flashmap.py tb/protocol.py | deps
	$(PY) sim/soak/gen_profiles.py $@ o2_v18 o2_v26 o2_v15

# Verilator writes the C++ model; its makefile compiles it (-O2 on the fast
# path) and the runtime; our own sources get the full warning set below.
$(SOAK_OBJ)/Vsoak_top.mk: $(SOAK_RTL) mk/soak.mk
	@mkdir -p $(SOAK_OBJ)
	nice verilator $(SOAK_VFLAGS) --Mdir $(SOAK_OBJ) $(SOAK_RTL)

$(SOAK_VLIB) &: $(SOAK_OBJ)/Vsoak_top.mk
	nice $(MAKE) -s -j 1 -C $(SOAK_OBJ) -f Vsoak_top.mk Vsoak_top__ALL.a verilated.o \
	    verilated_threads.o OPT_FAST=-O2 OPT_GLOBAL=-O2

$(SOAK_DIR)/%.o: sw/src/%.c sw/include/twh.h sw/include/twh_regs.h
	@mkdir -p $(SOAK_DIR)
	gcc $(SOAK_CFLAGS) -c $< -o $@

$(SOAK_DIR)/twh_page.o: sw/tools/twh_page.c sw/tools/twh_page.h sw/include/twh.h
	@mkdir -p $(SOAK_DIR)
	gcc $(SOAK_CFLAGS) -Isw/tools -c $< -o $@

$(SOAK_DIR)/%.o: sim/soak/%.cpp sim/soak/periph.h $(SOAK_PROF_H) $(SOAK_OBJ)/Vsoak_top.mk \
                 sw/include/twh.h sw/include/twh_regs.h mk/soak.mk
	nice g++ $(SOAK_CXXFLAGS) -c $< -o $@

$(SOAK_BIN): $(SOAK_CXXOBJ) $(SOAK_DRV) $(SOAK_VLIB)
	g++ -o $@ $(SOAK_CXXOBJ) $(SOAK_DRV) $(SOAK_VLIB) -pthread -latomic

# The soak harness compiled again against the LiteX SoC's three cells
# (soc/cells.py: O2 v18, O2 v15, CO2); the Verilated model is the soak's.
# make demo (Makefile) runs it in --page mode: the sensor-page tool on every
# channel. make test runs it in --session mode (cosim-session): the driver
# session of tb/test_cosim.py, step for step, with its transcript of frames,
# which make test-slow holds to the same session co-simulated on Icarus.
DEMO_DIR      := build/demo
CELLS_SOAK    := $(DEMO_DIR)/soak_cells
DEMO_PROF_H   := $(DEMO_DIR)/gen/soak_profiles.h
DEMO_CXXOBJ   := $(DEMO_DIR)/soak_main.o $(DEMO_DIR)/periph.o

$(DEMO_PROF_H): soc/cells.py sim/soak/gen_profiles.py tb/profiles.py tb/flashmap.py \
                tb/protocol.py tb/vectors/flash_o2.json tb/vectors/flash_co2.json | deps
	@mkdir -p $(dir $@)
	$(PY) soc/cells.py $@

$(DEMO_DIR)/%.o: sim/soak/%.cpp sim/soak/periph.h $(DEMO_PROF_H) $(SOAK_OBJ)/Vsoak_top.mk \
                 sw/include/twh.h sw/include/twh_regs.h sw/tools/twh_page.h mk/soak.mk
	nice g++ -I$(DEMO_DIR)/gen $(SOAK_CXXFLAGS) -c $< -o $@

$(CELLS_SOAK): $(DEMO_CXXOBJ) $(SOAK_DRV) $(SOAK_VLIB)
	g++ -o $@ $(DEMO_CXXOBJ) $(SOAK_DRV) $(SOAK_VLIB) -pthread -latomic

# make test runs cosim-session in the group after the static checks (TEST_LATE):
# soak-smoke, among them, builds this binary too, so that two makes never
# build the Verilated model and the driver objects both binaries share at once.
soak-smoke: $(CELLS_SOAK)
.PHONY: cosim-session
TEST_LATE += cosim-session
cosim-session: $(CELLS_SOAK)
	nice $(CELLS_SOAK) --session --transcript $(DEMO_DIR)/session_verilator.txt
