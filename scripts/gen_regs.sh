#!/usr/bin/env bash
# Regenerates the files derived from the register map rdl/twh_regs.rdl:
#   sw/include/twh_regs.h   peakrdl c-header --std gnu99 (C99 + GNU packed
#                           attribute; no C11 static_assert, see below)
#   docs/registers.md       peakrdl markdown
# Both are committed; `make check-regs` (part of `make test`) regenerates them
# into build/gen/ and fails if the committed ones differ.
#
# Usage: scripts/gen_regs.sh [OUTDIR]
#   without OUTDIR: into the repo (`make regs`);
#   with OUTDIR: into OUTDIR/sw/include/ and OUTDIR/docs/.
# PEAKRDL=... overrides the peakrdl executable (default: .venv/bin/peakrdl,
# else peakrdl on PATH).
#
# --std gnu99: the default (--std latest) output ends with a C11
# `static_assert(sizeof(twh_regs_t) == ..., "Packing error")` and includes
# <assert.h>, which neither gnu99 nor a bare arm-none-eabi-gcc (no newlib)
# accepts. The struct definitions are the same either way; the packing check
# it drops is done more thoroughly by tb/test_regmap_py.py (offsetof of every
# register against the RDL addresses).
set -euo pipefail
out=${1:-}
if [ -n "$out" ]; then
    mkdir -p "$out"
    out=$(cd "$out" && pwd)
fi
cd "$(dirname "$0")/.."
out=${out:-$PWD}
if [ -z "${PEAKRDL:-}" ]; then
    if [ -x .venv/bin/peakrdl ]; then PEAKRDL=.venv/bin/peakrdl; else PEAKRDL=peakrdl; fi
fi
rdl=rdl/twh_regs.rdl               # relative: the markdown records the path
cfg=(--peakrdl-cfg scripts/peakrdl.toml)
note="Generated from $rdl by scripts/gen_regs.sh (make regs): do not edit."
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

"$PEAKRDL" c-header "$rdl" "${cfg[@]}" --std gnu99 -o "$tmp/twh_regs.h"
"$PEAKRDL" markdown "$rdl" "${cfg[@]}" -o "$tmp/registers.md"

# peakrdl-markdown writes the channel block out once per array element (32
# copies that differ only in their absolute addresses): keep CH[0]'s, say
# where CH[n] is, and list the first and last block in the address table.
python3 - "$tmp/registers.md" <<'PY'
import re, sys
path = sys.argv[1]
text = open(path).read()
head, sep, rest = text.partition("\n## CH register file\n")
assert sep, "no channel register file in the markdown"
first = rest.split("\n## CH register file\n")[0]
first = re.sub(r"^- Absolute Address: (0x[0-9A-Fa-f]+)$",
               r"- Absolute Address: \1 (CH[0]; CH[n] at + 0x20 * n)", first, flags=re.M)
rows = re.findall(r"^\|[^\n]*\|\s*CH\[(\d+)\]\s*\|[^\n]*$", head, flags=re.M)
last = max(int(n) for n in rows)
lines = []
for line in head.split("\n"):
    m = re.match(r"^\|[^|]*\|\s*CH\[(\d+)\]\s*\|", line)
    if m and int(m.group(1)) not in (0, last):
        if int(m.group(1)) != 1:
            continue
        line = "| ...  |    ...    |             ...            |"
    lines.append(line)
open(path, "w").write("\n".join(lines) + sep + first.rstrip("\n") + "\n")
PY

mkdir -p "$out/sw/include" "$out/docs"
{ echo "// $note"; cat "$tmp/twh_regs.h"; } > "$out/sw/include/twh_regs.h"
{ echo "<!-- $note -->"; cat "$tmp/registers.md"; } > "$out/docs/registers.md"
