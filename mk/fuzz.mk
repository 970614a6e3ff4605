# Fuzzing the C driver: libFuzzer harnesses in sw/fuzz/ (docs/fuzzing.md).
#
#   make fuzz [FUZZ_SECONDS=60] [FUZZ_HARNESSES="map driver"]
#       each harness FUZZ_SECONDS seconds, nice'd, one after the other; the
#       corpora grow in build/fuzz/corpus/ (seeded from tb/vectors/*.json);
#       prints executions, coverage, corpus size and time per harness; fails on
#       any crash or property failure (input in build/fuzz/artifacts/)
#   make fuzz-smoke
#       every harness built and run over its seeds and the committed
#       regression inputs (sw/fuzz/regress/), plus 3000 mutations with a
#       fixed seed; a few seconds, part of make test
#   make fuzz-ci [FUZZ_CI_SEED=1]
#       every harness a fixed number of executions (sw/fuzz/run.sh,
#       ci_runs) with a fixed seed, from the generated seeds and the
#       regression inputs only, nice'd: the same run wherever it runs;
#       about 1.5 minutes; a stage of .ci/run
#
# Needs Debian's clang-14 and libclang-rt-14-dev (libFuzzer and the
# sanitizer runtimes; Debian 12 installs clang-14 as clang-14 only).

FUZZ_CC        ?= clang-14
FUZZ_SECONDS   ?= 60
FUZZ_CI_SEED   ?= 1
FUZZ_B         := build/fuzz
FUZZ_HARNESSES ?= map cal_scan text datetime convert encode result driver
# no stack-depth feature: with ASan it depends on where the stack starts,
# so the same input gave different features from run to run (fuzz-ci would
# not repeat itself); the driver has no recursion for it to find
FUZZ_CFLAGS    := -std=c99 -Wall -Wextra -Werror -g -O1 -fno-omit-frame-pointer \
                  -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all \
                  -fno-sanitize-coverage=stack-depth -Isw/include -Isw/fuzz
FUZZ_DRIVER    := sw/src/twh.c sw/src/twh_decode.c
FUZZ_DEPS      := $(FUZZ_DRIVER) sw/include/twh.h sw/include/twh_regs.h \
                  $(wildcard sw/fuzz/*.h) mk/fuzz.mk
FUZZ_BINS      := $(FUZZ_HARNESSES:%=$(FUZZ_B)/bin/fuzz_%)
FUZZ_VEC       := $(sort $(wildcard tb/vectors/*.json))

.PHONY: fuzz fuzz-smoke fuzz-ci fuzz-build fuzz-corpus fuzz-seeds

# the two driver-level harnesses also link the fuzz platform
$(FUZZ_B)/bin/fuzz_result $(FUZZ_B)/bin/fuzz_driver: sw/fuzz/fuzz_core.c
# deps first: bootstrap installs libclang-rt-14-dev, without which the link fails
$(FUZZ_B)/bin/fuzz_%: sw/fuzz/fuzz_%.c $(FUZZ_DEPS) | deps
	@mkdir -p $(@D)
	$(FUZZ_CC) $(FUZZ_CFLAGS) $(filter %.c,$^) -o $@

$(FUZZ_B)/corpus/.stamp: sw/fuzz/gen_corpus.py sw/include/twh_regs.h $(FUZZ_VEC) | deps
	$(PY) sw/fuzz/gen_corpus.py -o $(FUZZ_B)/corpus $(FUZZ_VEC)
	@touch $@

# the same seeds, kept apart from the corpora that make fuzz grows
$(FUZZ_B)/seeds/.stamp: sw/fuzz/gen_corpus.py sw/include/twh_regs.h $(FUZZ_VEC) | deps
	rm -rf $(@D)
	$(PY) sw/fuzz/gen_corpus.py -o $(@D) $(FUZZ_VEC)
	@touch $@

fuzz-build: $(FUZZ_BINS)
fuzz-corpus: $(FUZZ_B)/corpus/.stamp
fuzz-seeds: $(FUZZ_B)/seeds/.stamp

fuzz-smoke: fuzz-build fuzz-corpus
	@bash sw/fuzz/run.sh smoke $(FUZZ_B) $(FUZZ_HARNESSES)

fuzz-ci: fuzz-build fuzz-seeds
	@bash sw/fuzz/run.sh ci $(FUZZ_B) $(FUZZ_CI_SEED) $(FUZZ_HARNESSES)

fuzz: fuzz-build fuzz-corpus
	@bash sw/fuzz/run.sh fuzz $(FUZZ_B) $(FUZZ_SECONDS) $(FUZZ_HARNESSES)

TEST_EXTRA += fuzz-smoke
