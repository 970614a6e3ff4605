# Board tops (boards/, docs/boards.md): bitstreams with the YoWASP tools, a
# lint of the bridge and the tops, the PC command-line tool, and the board
# simulation. A board build reads the core (rtl/), the logic every board
# shares (boards/common/: the UART bridge, reset and LEDs) and its own top
# (boards/<board>/).
#
#   make boards                 every bitstream below
#   make board-icebreaker       iCEBreaker   iCE40UP5K-SG48  12 MHz  -> .bin
#   make board-hx8k             HX8K board   iCE40HX8K-CT256 12 MHz  -> .bin
#   make board-ulx3s            ULX3S 85F    ECP5-85F CABGA381 25 MHz -> .bit
#        CHANNELS=1..3 (default 3), BOARD_BAUD=115200
#   make board-lint             Verilator -Wall + Yosys check of the bridge and the
#                               tops (make test; make lint checks rtl/ only)
#   make board-cli              sw/tools/twh_cli (the PC tool)
#   make board-sim              tb/test_board_top.py (the iCEBreaker top simulated)
#   make board-sim-full         the CLI's whole sensor page against the simulated
#                               board at 115200 baud (long: several minutes)
#
# Each board builds into build/boards/<board>/ (yosys.log, pnr.log, the
# bitstream, nextpnr's report.json with utilisation and Fmax). A build fails
# when a tool warns, or when timing is not met at the board clock (nextpnr
# stops with an error then). A different CHANNELS or BOARD_BAUD rebuilds.

BOARD_CHANNELS := $(or $(CHANNELS),3)
BOARD_BAUD     ?= 115200
BOARD_DIR      := build/boards
YOWASP         := .venv/bin/yowasp-
BOARD_COMMON   := $(sort $(wildcard boards/common/*.v))
BOARD_SRC      := $(sort $(wildcard rtl/*.v)) $(BOARD_COMMON)
BOARD_RTL      := $(BOARD_SRC) rtl/twh_defs.vh
BOARDS         := icebreaker hx8k ulx3s

BOARD_TOP_icebreaker := twh_icebreaker
BOARD_FAM_icebreaker := ice40
BOARD_MHZ_icebreaker := 12
BOARD_PNR_icebreaker := --up5k --package sg48 --pcf constraints/icebreaker.pcf
BOARD_CON_icebreaker := constraints/icebreaker.pcf

BOARD_TOP_hx8k := twh_hx8k
BOARD_FAM_hx8k := ice40
BOARD_MHZ_hx8k := 12
BOARD_PNR_hx8k := --hx8k --package ct256 --pcf constraints/hx8k.pcf
BOARD_CON_hx8k := constraints/hx8k.pcf

BOARD_TOP_ulx3s := twh_ulx3s
BOARD_FAM_ulx3s := ecp5
BOARD_MHZ_ulx3s := 25
BOARD_PNR_ulx3s := --85k --package CABGA381 --speed 6 --lpf constraints/ulx3s.lpf
BOARD_CON_ulx3s := constraints/ulx3s.lpf

TEST_EXTRA += board-lint

.PHONY: boards board-lint board-cli board-sim board-sim-full board-force
.PHONY: $(addprefix board-,$(BOARDS))

boards: $(addprefix board-,$(BOARDS))

# fails the build on any "Warning" line of a tool's log
BOARD_NO_WARN = if grep -E '^Warning' $(1); then echo "$(1): warnings above"; exit 1; fi

# $(1) = board
define BOARD_RULES
$(BOARD_DIR)/$(1)/params: board-force
	@mkdir -p $$(@D)
	@echo "CHANNELS=$(BOARD_CHANNELS) BAUD=$(BOARD_BAUD)" > $$@.new
	@if cmp -s $$@.new $$@; then rm $$@.new; else mv $$@.new $$@; fi

$(BOARD_DIR)/$(1)/synth.json: $(BOARD_RTL) $(wildcard boards/$(1)/*.v) $(BOARD_DIR)/$(1)/params scripts/synth.py | deps
	@echo "yosys: synth_$(BOARD_FAM_$(1)) $(BOARD_TOP_$(1)) CHANNELS=$(BOARD_CHANNELS) BAUD=$(BOARD_BAUD)"
	@$(YOWASP)yosys -q -l $$(@D)/yosys.log -p "read_verilog -Irtl $(BOARD_SRC) $(wildcard boards/$(1)/*.v); \
	    hierarchy -top $(BOARD_TOP_$(1)) -chparam CHANNELS $(BOARD_CHANNELS) -chparam BAUD $(BOARD_BAUD); \
	    synth_$(BOARD_FAM_$(1)) $$$$($(PY) scripts/synth.py --synth-flow $(BOARD_FAM_$(1))) -top $(BOARD_TOP_$(1)) -json $$@" >/dev/null
	@$(call BOARD_NO_WARN,$$(@D)/yosys.log)

board-$(1): $(BOARD_DIR)/$(1)/$(BOARD_TOP_$(1)).$(if $(filter ice40,$(BOARD_FAM_$(1))),bin,bit)
	@$(PY) boards/report.py $(1) $(BOARD_DIR)/$(1)/report.json $(BOARD_DIR)/$(1)/params
endef
$(foreach b,$(BOARDS),$(eval $(call BOARD_RULES,$(b))))

# iCE40: nextpnr-ice40 + icepack
define BOARD_ICE40
$(BOARD_DIR)/$(1)/$(BOARD_TOP_$(1)).bin: $(BOARD_DIR)/$(1)/synth.json $(BOARD_CON_$(1))
	@echo "nextpnr-ice40 $(BOARD_PNR_$(1)) --freq $(BOARD_MHZ_$(1))"
	@$(YOWASP)nextpnr-ice40 -q -l $$(@D)/pnr.log $(BOARD_PNR_$(1)) --freq $(BOARD_MHZ_$(1)) \
	    --json $$< --asc $$(@D)/$(BOARD_TOP_$(1)).asc --report $$(@D)/report.json
	@$(call BOARD_NO_WARN,$$(@D)/pnr.log)
	@$(YOWASP)icepack $$(@D)/$(BOARD_TOP_$(1)).asc $$@
endef
$(foreach b,$(BOARDS),$(if $(filter ice40,$(BOARD_FAM_$(b))),$(eval $(call BOARD_ICE40,$(b)))))

# ECP5: nextpnr-ecp5 + ecppack
define BOARD_ECP5
$(BOARD_DIR)/$(1)/$(BOARD_TOP_$(1)).bit: $(BOARD_DIR)/$(1)/synth.json $(BOARD_CON_$(1))
	@echo "nextpnr-ecp5 $(BOARD_PNR_$(1)) --freq $(BOARD_MHZ_$(1))"
	@$(YOWASP)nextpnr-ecp5 -q -l $$(@D)/pnr.log $(BOARD_PNR_$(1)) --freq $(BOARD_MHZ_$(1)) \
	    --json $$< --textcfg $$(@D)/$(BOARD_TOP_$(1)).config --report $$(@D)/report.json
	@$(call BOARD_NO_WARN,$$(@D)/pnr.log)
	@$(YOWASP)ecppack --compress $$(@D)/$(BOARD_TOP_$(1)).config $$@
endef
$(foreach b,$(BOARDS),$(if $(filter ecp5,$(BOARD_FAM_$(b))),$(eval $(call BOARD_ECP5,$(b)))))

board-force:

# Verilator -Wall on the bridge at the board clocks and the simulation baud,
# and on every top with 1 and 3 channels; Yosys synthesizes the bridge for
# iCE40 and elaborates each top down to its three-state pads (the core
# itself is synthesized by make lint). Seconds.
board-lint: deps
	@set -e; for p in "12000000 115200" "12000000 1000000" "25000000 115200"; do \
	    set -- $$p; echo "verilator -Wall twh_uart_bridge CLK_HZ=$$1 BAUD=$$2"; \
	    verilator --lint-only -Wall -Irtl $(BOARD_SRC) --top-module twh_uart_bridge \
	        -GCLK_HZ=$$1 -GBAUD=$$2; \
	done
	@set -e; for b in $(BOARDS); do for ch in 1 3; do \
	    top=$$(basename boards/$$b/twh_*.v .v); \
	    echo "verilator -Wall $$top CHANNELS=$$ch"; \
	    verilator --lint-only -Wall -Irtl $(BOARD_SRC) boards/$$b/$$top.v \
	        --top-module $$top -GCHANNELS=$$ch; \
	done; done
	@mkdir -p $(BOARD_DIR)
	@echo "yosys: synth_ice40 twh_uart_bridge"
	@yosys -q -l $(BOARD_DIR)/lint_bridge.log -p "read_verilog -Irtl $(BOARD_SRC); \
	    synth_ice40 -top twh_uart_bridge; check -assert" >/dev/null
	@$(call BOARD_NO_WARN,$(BOARD_DIR)/lint_bridge.log)
	@set -e; for b in $(BOARDS); do \
	    top=$$(basename boards/$$b/twh_*.v .v); echo "yosys: elaborate $$top"; \
	    yosys -q -l $(BOARD_DIR)/lint_$$b.log -p "read_verilog -Irtl $(BOARD_SRC) \
	        boards/$$b/$$top.v; hierarchy -check -top $$top; proc; flatten; tribuf; check -assert" >/dev/null; \
	    if grep -E '^Warning' $(BOARD_DIR)/lint_$$b.log; then echo "$$b: warnings above"; exit 1; fi; \
	done
	@echo "board tops lint clean"

board-cli:
	$(MAKE) -C sw/tools

board-sim: deps board-cli
	$(PY) -m pytest -q -n $(JOBS) tb/test_board_top.py

board-sim-full: deps board-cli
	TWH_BOARD_FULL=1 $(PY) -m pytest -q -s tb/test_board_top.py -k full_page
