# Synthesis with the pinned YoWASP tools.
#   make synth        bitstreams for the three boards (mk/boards.mk, docs/boards.md)
#   make synth-smoke  one part, one configuration: part of make test, so code
#                     that Yosys or nextpnr cannot take fails CI
#   make bench-synth  the resource/Fmax table (docs/resources.md), part of
#                     make bench; never asserted, only printed and written
.PHONY: synth synth-smoke bench-synth

synth: boards

TEST_EXTRA  += synth-smoke
BENCH_EXTRA += bench-synth

synth-smoke: deps
	$(PY) scripts/synth.py --part hx8k --top twh_wb -P CHANNELS=1 --freq 48 \
	    --out build/synth/smoke --require-clean

bench-synth: deps
	$(PY) scripts/bench_synth.py --jobs $(JOBS) --write docs/resources.md
