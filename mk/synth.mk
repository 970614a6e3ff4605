# Synthesis with the pinned YoWASP tools.
#   make synth        bitstreams for the three boards (mk/boards.mk, docs/boards.md)
#   make synth-smoke  one part, one configuration: part of make test, so code
#                     that Yosys or nextpnr cannot take fails CI
#   make bench-synth  the resource/Fmax table (docs/resources.md), part of
#                     make bench; never asserted, only printed and written
#   make bench-engine the time-shared engine alone at 1-32 channels on the
#                     HX8K and at 3 and 32 on the ECP5-25F (docs/engine.md),
#                     part of make bench; printed only
.PHONY: synth synth-smoke bench-synth bench-engine

synth: boards

TEST_EXTRA  += synth-smoke
BENCH_EXTRA += bench-synth bench-engine

synth-smoke: deps
	$(PY) scripts/synth.py --part hx8k --top twh_wb -P CHANNELS=1 --freq 48 \
	    --out build/synth/smoke --require-clean

bench-synth: deps
	$(PY) scripts/bench_synth.py --jobs $(JOBS) --write docs/resources.md

bench-engine: deps
	$(PY) scripts/bench_engine.py --parts hx8k --channels 1 3 8 16 32
	$(PY) scripts/bench_engine.py --parts ecp5-25f --channels 3 32

