# LiteX drop-in proof (soc/, docs/soc.md): the C driver (sw/src, unchanged)
# and the sensor-page tool (sw/tools/twh_page.c) on a VexRiscv in a LiteX SoC
# with twowire-host (3 channels) added by soc/twh_litex.py; the SoC's
# Verilog, Verilated, clocked at 4 MHz against the soak's C++ cell model
# (sim/soak/periph.cpp) on each line; the UART output checked against
# tb/vectors/ by soc/check_page.py, and the interrupt path with it. Then the
# same with SERV for the VexRiscv (the CPU that fits the UP5K beside three
# channels, make bench-soc): no interrupt, the driver polls.
#
#   make soc         build + run + check, both CPUs; prints the wall time
#   make soc-lint    Verilator -Wall on the hand-written top soc/sim_top.v
#   make bench-soc   the SoC synthesized for iCE40 UP5K and ECP5-25F, its table
#                    written into docs/soc.md (scripts/bench_soc.py; part of make bench)
# SOC_CPU=serv: the same SoC with SERV, which takes no interrupts (the
# driver polls), in build/soc-serv; `make soc` runs both
SOC_CPU     ?= vexriscv
SOC_DIR     := build/soc$(if $(filter-out vexriscv,$(SOC_CPU)),-$(SOC_CPU))
SOC_HDR     := $(SOC_DIR)/hdr
SOC_SIM     := $(SOC_DIR)/sim
SOC_FW      := $(SOC_DIR)/fw
SOC_GEN     := $(SOC_DIR)/gen
SOC_CLK_HZ  := 4000000
# SoC time the run may take: SERV, bit-serial, needs about 8.5 s of it for
# what the VexRiscv does in 3.3 (its printing of the pages)
SOC_MAX_MS  := $(if $(filter serv,$(SOC_CPU)),20000,8000)
SOC_BIN     := $(SOC_SIM)/obj/sim_soc
SOC_PY      := soc/twh_soc.py soc/twh_litex.py rdl/twh_regs.rdl
SOC_LITEX   = $(shell $(PY) -c "import litex, os; print(os.path.dirname(litex.__file__))" 2>/dev/null)/soc

# the firmware: Debian's riscv64-unknown-elf-gcc and picolibc, RV32I (the
# "minimal" VexRiscv has no multiplier). The driver and the page tool with
# the strict flags of sw/; main.c includes LiteX's headers (GNU asm), so it
# is gnu99 and needs the Zicsr extension spelled out for its CSR accesses.
SOC_CC      := riscv64-unknown-elf-gcc
SOC_ARCH    := --specs=picolibc.specs -march=rv32i -mabi=ilp32
SOC_CFLAGS  := -std=c99 -Wall -Wextra -Werror -pedantic -Wshadow -Os \
               -ffunction-sections -fdata-sections -Isw/include -Isw/tools
SOC_MAIN_CFLAGS = -std=gnu99 -Wall -Wextra -Werror -Wshadow -Os -march=rv32i_zicsr \
               -Isw/include -Isw/tools -I$(SOC_HDR)/software/include \
               -I$(SOC_LITEX)/software/include -I$(SOC_LITEX)/cores/cpu/$(SOC_CPU)
SOC_FW_OBJ  := $(SOC_FW)/main.o $(SOC_FW)/twh.o $(SOC_FW)/twh_decode.o $(SOC_FW)/twh_page.o

# LiteX's Verilog is not -Wall clean: its warnings are not ours to fix here
SOC_VFLAGS  := --cc --exe --build -j 1 -O3 --x-assign fast --x-initial fast --noassert \
               -Wno-fatal -Wno-lint -Wno-style -Wno-MULTIDRIVEN -Wno-UNOPTFLAT \
               --timescale 1ns/1ps --top-module sim_top -o sim_soc
SOC_VCFLAGS := -std=c++17 -O2 -DSOC_CLK_HZ=$(SOC_CLK_HZ) -I$(CURDIR)/sim/soak -I$(CURDIR)/$(SOC_GEN)

.PHONY: soc soc-run soc-lint bench-soc
BENCH_EXTRA += bench-soc

soc:
	@start=$$(date +%s); \
	$(MAKE) --no-print-directory soc-run SOC_CPU=vexriscv || exit 1; \
	$(MAKE) --no-print-directory soc-run SOC_CPU=serv || exit 1; \
	echo "make soc: PASS (VexRiscv, SERV), wall time $$(( $$(date +%s) - start )) s"

soc-run: $(SOC_BIN) deps
	nice $(SOC_BIN) --mem-dir $(SOC_SIM)/gateware --max-ms $(SOC_MAX_MS) | tee $(SOC_DIR)/uart.log; \
	    test $${PIPESTATUS[0]} -eq 0
	$(PY) soc/check_page.py $(SOC_DIR)/uart.log --clk-khz $$(( $(SOC_CLK_HZ) / 1000 )) \
	    $(if $(filter serv,$(SOC_CPU)),--no-irq)

# 1. the SoC without firmware: the headers (csr.h, soc.h, mem.h) the
#    firmware is compiled against; the map is the same in step 3
$(SOC_HDR)/software/include/generated/soc.h: $(SOC_PY) | deps
	$(PY) soc/twh_soc.py --variant sim --out $(SOC_HDR) --clk-hz $(SOC_CLK_HZ) --cpu $(SOC_CPU)

# 2. the firmware
$(SOC_FW)/main.o: soc/fw/main.c $(SOC_HDR)/software/include/generated/soc.h sw/include/twh.h sw/tools/twh_page.h
	@mkdir -p $(SOC_FW)
	$(SOC_CC) $(SOC_ARCH) $(SOC_MAIN_CFLAGS) -c $< -o $@

$(SOC_FW)/%.o: sw/src/%.c sw/include/twh.h sw/include/twh_regs.h
	@mkdir -p $(SOC_FW)
	$(SOC_CC) $(SOC_ARCH) $(SOC_CFLAGS) -c $< -o $@

$(SOC_FW)/twh_page.o: sw/tools/twh_page.c sw/tools/twh_page.h sw/include/twh.h
	@mkdir -p $(SOC_FW)
	$(SOC_CC) $(SOC_ARCH) $(SOC_CFLAGS) -c $< -o $@

# integer-only printf (picolibc's __i_vfprintf); 4 KiB of stack
$(SOC_FW)/fw.bin: $(SOC_FW_OBJ)
	$(SOC_CC) $(SOC_ARCH) -DPICOLIBC_INTEGER_PRINTF_SCANF -Wl,--gc-sections \
	    $$(cat $(SOC_HDR)/fw_ldflags) -Wl,--defsym=__stack_size=0x1000 \
	    -Wl,-Map=$(SOC_FW)/fw.map -o $(SOC_FW)/fw.elf $(SOC_FW_OBJ)
	riscv64-unknown-elf-size $(SOC_FW)/fw.elf
	riscv64-unknown-elf-objcopy -O binary $(SOC_FW)/fw.elf $@

# 3. the SoC with the firmware in its ROM: the Verilog that is simulated
#    (soc.h gains CONFIG_ROM_INIT; the map, mem.h and csr.h, must not change)
$(SOC_SIM)/gateware/twh_soc.v: $(SOC_PY) $(SOC_FW)/fw.bin | deps
	$(PY) soc/twh_soc.py --variant sim --out $(SOC_SIM) --clk-hz $(SOC_CLK_HZ) --rom $(SOC_FW)/fw.bin \
	    --cpu $(SOC_CPU)
	@for h in mem.h csr.h; do \
	    diff <(grep -v Auto-generated $(SOC_HDR)/software/include/generated/$$h) \
	         <(grep -v Auto-generated $(SOC_SIM)/software/include/generated/$$h) >/dev/null \
	    || { echo "$$h: the SoC's map changed with the firmware"; exit 1; }; done

# the three cells: the vector images in the soak model's device table
$(SOC_GEN)/soak_profiles.h: soc/cells.py sim/soak/gen_profiles.py tb/profiles.py tb/flashmap.py \
                            tb/vectors/flash_o2.json tb/vectors/flash_co2.json | deps
	$(PY) soc/cells.py $@

# 4. Verilator: the SoC, tb_line per channel, the harness and the model
$(SOC_BIN): $(SOC_SIM)/gateware/twh_soc.v $(SOC_GEN)/soak_profiles.h soc/sim_top.v \
            soc/sim_main.cpp sim/soak/periph.cpp sim/soak/periph.h tb/tb_line.v $(RTL) mk/soc.mk
	@rm -rf $(SOC_SIM)/obj
	nice verilator $(SOC_VFLAGS) --Mdir $(SOC_SIM)/obj -f $(SOC_SIM)/gateware/sources.f \
	    $(CURDIR)/tb/tb_line.v $(CURDIR)/soc/sim_top.v $(CURDIR)/soc/sim_main.cpp \
	    $(CURDIR)/sim/soak/periph.cpp -CFLAGS "$(SOC_VCFLAGS)" > $(SOC_SIM)/verilator.log 2>&1 \
	    || { tail -30 $(SOC_SIM)/verilator.log; exit 1; }

# the hand-written top, -Wall; the LiteX SoC it instantiates is read with
# its warnings off (soc/lint.vlt)
soc-lint: $(SOC_SIM)/gateware/twh_soc.v
	verilator --lint-only -Wall --timescale 1ns/1ps soc/lint.vlt -f $(SOC_SIM)/gateware/sources.f \
	    tb/tb_line.v soc/sim_top.v --top-module sim_top

bench-soc: $(SOC_FW)/fw.bin deps
	$(PY) scripts/bench_soc.py --write docs/soc.md
