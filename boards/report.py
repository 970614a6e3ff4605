"""Prints what a board build used and reached, from nextpnr's --report JSON:
`python boards/report.py <board> <report.json> [params file]`."""
import json
import sys

board, path = sys.argv[1], sys.argv[2]
params = open(sys.argv[3]).read().strip() if len(sys.argv) > 3 else ""
rep = json.load(open(path))
used = ", ".join(f"{k} {v['used']}/{v['available']}"
                 for k, v in sorted(rep["utilization"].items()) if v["used"])
print(f"{board} ({params}): {used}")
for clk, f in rep["fmax"].items():
    verdict = "met" if f["achieved"] >= f["constraint"] else "NOT MET"
    print(f"{board}: Fmax {f['achieved']:.1f} MHz at a {f['constraint']:.0f} MHz board clock "
          f"({verdict}; {clk})")
