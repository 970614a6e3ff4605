#!/usr/bin/env bash
# Renders every WaveDrom source docs/wavedrom/*.json to an SVG of the same
# name with yowasp-wavedrom (pinned in requirements.txt, installed in .venv).
# Usage: scripts/gen_wavedrom.sh [outdir]   (default: docs/wavedrom)
# The SVGs are committed; `make check-wavedrom` checks they are current.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-docs/wavedrom}
wd=.venv/bin/yowasp-wavedrom
[ -x "$wd" ] || { echo "gen_wavedrom: $wd missing: run 'make deps'" >&2; exit 1; }
mkdir -p "$out"
shopt -s nullglob
srcs=(docs/wavedrom/*.json)
[ ${#srcs[@]} -gt 0 ] || { echo "gen_wavedrom: no docs/wavedrom/*.json" >&2; exit 1; }
for src in "${srcs[@]}"; do
    svg="$out/$(basename "${src%.json}").svg"
    # CLI: yowasp-wavedrom <input.json> <output.svg> (strict JSON input)
    "$wd" "$src" "$svg.tmp"
    # end the file with a newline so diffs and editors stay quiet
    [ -z "$(tail -c1 "$svg.tmp")" ] || echo >> "$svg.tmp"
    mv "$svg.tmp" "$svg"
    echo "gen_wavedrom: $src -> $svg"
done
