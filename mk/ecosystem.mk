# Ecosystem flows around the core (docs/waves.md, twowire-host.core).
#
# make fusesoc-synth: the synth_ice40 (iCE40HX8K-CT256, 12 MHz) and
# synth_ecp5 (LFE5U-25F-CABGA256, 25 MHz) targets of twowire-host.core run
# through FuseSoC, from Yosys to a bitstream. Not part of make test (minutes
# of place and route; `make fusesoc` covers the core file's lint and sim).
# edalize calls nextpnr-ice40, icepack, nextpnr-ecp5 and ecppack by name:
# scripts/shims/ maps them to the pinned YoWASP builds in .venv (the first
# call of each compiles it, ~35 s). Yosys stays the system one (bootstrap
# installs it): edalize drives it through Tcl, which YoWASP's Yosys lacks.
# Without pin constraints the bitstreams only measure the design (see the
# comment in twowire-host.core).

ECO_SHIMS := $(CURDIR)/scripts/shims
FUSESOC_SYNTH_TARGETS := synth_ice40 synth_ecp5 icebreaker hx8k ulx3s

.PHONY: fusesoc-synth
fusesoc-synth: deps
	@mkdir -p build/fusesoc-synth
	@set -e; for t in $(FUSESOC_SYNTH_TARGETS); do \
	    echo "fusesoc run --target=$$t open:twowire:host (log: build/fusesoc-synth/$$t.log)"; \
	    PATH="$(ECO_SHIMS):$$PATH" .venv/bin/fusesoc --cores-root . run \
	        --build-root build/fusesoc-synth/$$t --target=$$t open:twowire:host \
	        > build/fusesoc-synth/$$t.log 2>&1 \
	        || { tail -40 build/fusesoc-synth/$$t.log; exit 1; }; \
	    awk '/Device utilisation/ {f = 1; next} f && !/^Info:[ \t]+[A-Z0-9_]+:/ {f = 0} \
	         f && !/ 0\// {print}' build/fusesoc-synth/$$t/*/*/next.log; \
	    grep -h "^Info: Max frequency" build/fusesoc-synth/$$t/*/*/next.log | tail -1; \
	    ls build/fusesoc-synth/$$t/*/*/*.bin build/fusesoc-synth/$$t/*/*/*.bit 2>/dev/null || true; \
	done
