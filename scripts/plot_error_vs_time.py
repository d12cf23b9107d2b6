#!/usr/bin/python3
"""Plots relative error against ms per step from one or more tissue_bench / *_bench CSV files.

usage: plot_error_vs_time.py CSV [CSV ...] OUT.png TITLE
Each series is one (model, integrator, solver) triple, prefixed by the variant when the CSV has
one; points are resolutions, labelled by dofs.
"""
import csv
import math
import sys

# --help answers before matplotlib loads (it would write its font cache into $HOME).
if __name__ == "__main__" and ("--help" in sys.argv[1:] or "-h" in sys.argv[1:]):
    print(__doc__)
    sys.exit(0)

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(argv):
    if len(argv) < 4:
        print(__doc__, file=sys.stderr)
        return 2
    csv_paths, out_path, title = argv[1:-2], argv[-2], argv[-1]
    series = {}
    for path in csv_paths:
        with open(path, newline="") as f:
            for row in csv.DictReader(f):
                try:
                    err = float(row["error_rel"])
                    ms = float(row["ms_per_step"])
                except (KeyError, ValueError):
                    continue
                if not (math.isfinite(err) and ms > 0):
                    continue
                key = "%s / %s / %s" % (row["model"], row["integrator"], row["solver"])
                if row.get("variant"):
                    key = "%s: %s" % (row["variant"], key)
                elem = "tet10" if "tet10" in row["case"] else "tet4"
                series.setdefault((key, elem), []).append((ms, max(err, 1e-16), int(row["dofs"])))
    fig, ax = plt.subplots(figsize=(8, 5.5))
    for (key, elem), pts in sorted(series.items()):
        pts.sort(key=lambda p: p[2])
        style = "-o" if elem == "tet4" else "--s"
        ax.plot([p[0] for p in pts], [p[1] for p in pts], style, label="%s (%s)" % (key, elem))
        for ms, err, dofs in pts:
            ax.annotate(str(dofs), (ms, err), fontsize=6, alpha=0.7)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("run time per step [ms]")
    ax.set_ylabel("relative error [-]")
    ax.set_title("%s: error against run time (labels: DOFs)" % title)
    ax.grid(True, which="both", alpha=0.3)
    if series:
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out_path, dpi=110)
    print("wrote %s (%d series)" % (out_path, len(series)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
