#!/usr/bin/python3
"""Prints a short human-readable summary of a tissue_bench CSV: per case the error and ms per
step, and the best configuration (lowest error, then fastest) among the rows whose status is
"ok" or "not_converged" and whose error is finite (an "unsettled" row's error measures motion,
not accuracy).

usage: summarize_bench.py CSV
"""
import csv
import math
import sys


def main(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        print("no rows in %s" % path)
        return 1
    print("%-42s %-14s %-26s %-18s %7s %10s %10s %s" % (
        "case", "model", "integrator", "solver", "dofs", "ms/step", "error", "status"))
    for r in rows:
        print("%-42s %-14s %-26s %-18s %7s %10.3f %10.3g %s" % (
            r["case"], r["model"], r["integrator"], r["solver"], r["dofs"],
            float(r["ms_per_step"]), float(r["error_rel"]), r["status"]))
    finite = [r for r in rows if math.isfinite(float(r["error_rel"]))]
    ok = [r for r in finite if r["status"] in ("ok", "not_converged")]
    if ok:
        best = min(ok, key=lambda r: (float(r["error_rel"]), float(r["ms_per_step"])))
        fastest = min(ok, key=lambda r: float(r["ms_per_step"]))
        print("most accurate: %s %s/%s/%s error %.3g at %.3f ms/step" % (
            best["case"], best["model"], best["integrator"], best["solver"],
            float(best["error_rel"]), float(best["ms_per_step"])))
        print("fastest:       %s %s/%s/%s error %.3g at %.3f ms/step" % (
            fastest["case"], fastest["model"], fastest["integrator"], fastest["solver"],
            float(fastest["error_rel"]), float(fastest["ms_per_step"])))
    print("%d cases, %d without a finite error, %d unsettled" % (
        len(rows), len(rows) - len(finite),
        sum(1 for r in rows if r["status"] == "unsettled")))
    return 0


if __name__ == "__main__":
    if "--help" in sys.argv[1:] or "-h" in sys.argv[1:]:
        print(__doc__)
        sys.exit(0)
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    sys.exit(main(sys.argv[1]))
