# Formal verification with SymbiYosys (docs/formal.md): the YoWASP build of
# Yosys 0.70 and its sby/smtbmc, with Yices 2 (requirements.txt).
#
#   make formal                    every job below, one at a time; PASS/FAIL
#                                  and time per job, fails if any fails
#   make formal FORMAL_JOBS=twh_fifo:prove_d4    chosen jobs only
#   make formal FORMAL_AT_ONCE=2   two jobs side by side (CI)
#
# A job is <formal/*.sby without .sby>:<task>. Properties live in the RTL
# under `ifdef FORMAL`; the .sby files pick module, parameters and mode.
# Phase 2 (twh_core, the engine's jobs) adds its .sby files and jobs here.

# the longest first (the time-shared engine's, then the core's), so that
# with two at a time the short ones fill in beside them at the end.
# FORMAL_PART=long or rest: the engine's six (about half the proofs' CPU
# time) or the others, for .ci/run, which proves the first beside the
# fuzzing run and the SoC, one at a time, and the rest two at a time after
FORMAL_JOBS_long = \
    twh_engine:ch2 twh_engine:ch3 twh_engine:ch1 twh_engine:fix2 twh_engine:lean2 \
    twh_engine:lean1
FORMAL_JOBS_rest = \
    twh_core:eng1 twh_core:eng2 twh_core:cover_eng2 twh_core:port \
    twh_polls:ch2 twh_polls:ch3 twh_polls:ch3lut twh_polls:cover3 \
    twh_sync2:prove twh_window:prove \
    twh_fifo:prove_d4 twh_fifo:prove_d2 twh_fifo:prove_d4h twh_fifo:cover_d4 \
    twh_wb:prove twh_wb:prove_abort twh_wb:cover \
    twh_axil:prove twh_axil:cover \
    twh_carrier:c4 twh_carrier:c5 twh_carrier:c10_5 twh_carrier:c13_56 \
    twh_carrier:c27 twh_carrier:c48 twh_carrier:c200 twh_carrier:cover_c13_56 \
    twh_rx:prove twh_rx:uart twh_rx:equiv \
    twh_engine_pin:c4 twh_engine_pin:c48 twh_engine_pin:c100 \
    twh_engine_pin:carrier_c4 twh_engine_pin:carrier_c48 twh_engine_pin:carrier_c100 \
    twh_engine_pin:cover_c4 \
    twh_timing:ch1 twh_timing:ch3 twh_timing:ch6 twh_timing:fixed3 twh_timing:lean3
FORMAL_JOBS_all = $(FORMAL_JOBS_long) $(FORMAL_JOBS_rest)
FORMAL_PART ?= all
FORMAL_JOBS ?= $(FORMAL_JOBS_$(FORMAL_PART))

.PHONY: formal
# jobs side by side (formal/run.sh's JOBS): 1 on a shared machine; CI, on
# a machine of its own, runs 2
FORMAL_AT_ONCE ?= 1
formal: deps
	@JOBS=$(FORMAL_AT_ONCE) bash formal/run.sh $(FORMAL_JOBS)

# Each mutant of formal/mutants.tsv and the per-module lists (a deliberate
# RTL bug or broken property) must make its job fail; not part of `formal`
# (JOBS mutants at a time, one core each; time in docs/formal.md).
.PHONY: formal-mutants
formal-mutants: deps
	@mkdir -p build/formal && cat formal/mutants.tsv \
	    formal/twh_core_mutants.tsv formal/twh_timing_mutants.tsv \
	    formal/twh_engine_mutants.tsv formal/twh_polls_mutants.tsv formal/twh_engine_pin_mutants.tsv \
	    > build/formal/all_mutants.tsv
	@JOBS=$(JOBS) bash formal/mutate.sh build/formal/all_mutants.tsv
