# Synthesis of the bare bus core with the pinned YoWASP tools (scripts/synth.py).
#   make synth-smoke  one part, one configuration: part of make test, so code
#                     that Yosys or nextpnr cannot take fails CI
#   make bench-synth  the resource/Fmax table (docs/resources.md), part of
#                     make bench; never asserted, only printed and written
.PHONY: synth-smoke bench-synth

TEST_EXTRA  += synth-smoke
BENCH_EXTRA += bench-synth

synth-smoke: deps
	$(PY) scripts/synth.py --part hx8k --top twh_wb -P CHANNELS=1 --freq 48 \
	    --out build/synth/smoke --require-clean

bench-synth: deps
	$(PY) scripts/bench_synth.py --write docs/resources.md
