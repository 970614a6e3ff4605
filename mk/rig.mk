# The rig (issue 34, docs/rig.md): the C driver on the Verilated twh_wb with
# RIG channels (16, or 32) at the engine's clock floor for RIG (RIG MHz, 5
# below five channels: 16 or 32 MHz), one modelled cell a channel
# (soc/cells.py: O2 v18, O2 v15 and CO2 in turn, each with its own serial,
# every fifth from channel 4 injecting one of the soak's faults). The soak's
# harness (sim/soak/) built for it, in --rig mode: every cell's sensor page
# at once (the page tool), then live readings on every line at the
# shortest legal timing; one line a cell, the aggregate rate against the
# physical limit, the lines' waveform. soc/check_page.py --rig then holds
# every page to the shared vectors (tb/vectors/).
#
#   make rig [RIG=16|32] [RIG_LIVE_MS=500] [RIG_ARGS="--seed 7 --rig-fault-rate 0.2"]
#
# Everything of a build is in build/rig<RIG>/: the Verilated model, the
# driver, the harness (soak_rig), pages.txt, rig.vcd and rig.gtkw.
RIG         ?= 16
RIG_LIVE_MS ?= 500
RIG_ARGS    ?=

RIG_CLK_HZ  := $(shell echo $$(( ($(RIG) < 5 ? 5 : $(RIG)) * 1000000 )))
RIG_FIFO    := 32
RIG_DIR     := build/rig$(RIG)
RIG_OBJ     := $(RIG_DIR)/obj
RIG_BIN     := $(RIG_DIR)/soak_rig
RIG_PROF_H  := $(RIG_DIR)/gen/soak_profiles.h
RIG_DRV     := $(RIG_DIR)/twh.o $(RIG_DIR)/twh_decode.o $(RIG_DIR)/twh_page.o
RIG_CXXOBJ  := $(RIG_DIR)/soak_main.o $(RIG_DIR)/periph.o
# soak.mk comes after this file (mk/*.mk in order): its variables only in recipes
RIG_RTL     := $(RTL) tb/tb_line.v sim/soak/soak_top.v
RIG_VLIB    := $(RIG_OBJ)/Vsoak_top__ALL.a $(RIG_OBJ)/verilated.o $(RIG_OBJ)/verilated_threads.o
RIG_CXXFLAGS = -std=c++17 -Wall -Wextra -Werror -O2 \
               -DSOAK_CLK_HZ=$(RIG_CLK_HZ) -DSOAK_CHANNELS=$(RIG) \
               -I$(RIG_OBJ) -I$(RIG_DIR)/gen -Isw/include -Isw/tools \
               -isystem $(SOAK_VINC) -isystem $(SOAK_VINC)/vltstd
RIG_VFLAGS  := --cc -O3 --x-assign fast --x-initial fast --noassert -Wall \
               -Irtl --top-module soak_top -GCLK_HZ=$(RIG_CLK_HZ) \
               -GCHANNELS=$(RIG) -GFIFO_DEPTH=$(RIG_FIFO)

.PHONY: rig rig-build
rig-build: $(RIG_BIN)

rig: $(RIG_BIN) deps
	nice $(RIG_BIN) --rig --live-ms $(RIG_LIVE_MS) --pages $(RIG_DIR)/pages.txt \
	    --vcd $(RIG_DIR)/rig.vcd $(RIG_ARGS)
	$(PY) soc/check_page.py $(RIG_DIR)/pages.txt --rig $(RIG) \
	    --clk-khz $$(( $(RIG_CLK_HZ) / 1000 )) --fifo-depth $(RIG_FIFO)

$(RIG_PROF_H): soc/cells.py sim/soak/gen_profiles.py tb/profiles.py tb/flashmap.py \
               tb/protocol.py tb/vectors/flash_o2.json tb/vectors/flash_co2.json | deps
	@mkdir -p $(dir $@)
	$(PY) soc/cells.py --rig $(RIG) $@

$(RIG_OBJ)/Vsoak_top.mk: $(RIG_RTL) mk/rig.mk
	@mkdir -p $(RIG_OBJ)
	nice verilator $(RIG_VFLAGS) --Mdir $(RIG_OBJ) $(RIG_RTL)

$(RIG_VLIB) &: $(RIG_OBJ)/Vsoak_top.mk
	nice $(MAKE) -s -j 1 -C $(RIG_OBJ) -f Vsoak_top.mk Vsoak_top__ALL.a verilated.o \
	    verilated_threads.o OPT_FAST=-O2 OPT_GLOBAL=-O2

# the driver exactly as the soak builds it (sw/Makefile's warnings)
$(RIG_DIR)/%.o: sw/src/%.c sw/include/twh.h sw/include/twh_regs.h
	@mkdir -p $(RIG_DIR)
	gcc $(SOAK_CFLAGS) -c $< -o $@

$(RIG_DIR)/twh_page.o: sw/tools/twh_page.c sw/tools/twh_page.h sw/include/twh.h
	@mkdir -p $(RIG_DIR)
	gcc $(SOAK_CFLAGS) -Isw/tools -c $< -o $@

$(RIG_DIR)/%.o: sim/soak/%.cpp sim/soak/periph.h $(RIG_PROF_H) $(RIG_OBJ)/Vsoak_top.mk \
                sw/include/twh.h sw/include/twh_regs.h sw/tools/twh_page.h mk/rig.mk
	nice g++ $(RIG_CXXFLAGS) -c $< -o $@

$(RIG_BIN): $(RIG_CXXOBJ) $(RIG_DRV) $(RIG_VLIB)
	g++ -o $@ $(RIG_CXXOBJ) $(RIG_DRV) $(RIG_VLIB) -pthread -latomic
