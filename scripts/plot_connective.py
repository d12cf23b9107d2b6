#!/usr/bin/python3
"""Plots a connective_bench CSV.

usage: plot_connective.py CASE CSV OUT.png
CASE t1: |tip error| against DOFs, one series per sweep (cross-section, length).
CASE t5b: tip error against DOFs and against ms per step, one series per model and element.
CASE speed: CPU and wall ms per step against rigid nodes, one series per refresh_interval,
beside Bosman's Table 4.4 and a tenth of it.
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


def finite(text):
    try:
        value = float(text)
    except (TypeError, ValueError):
        return None
    return value if math.isfinite(value) else None


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def series_plot(ax, rows, key, x_column, y_column):
    """One line per key(row) of (x, |y|) points sorted by x (y = 0, the reference itself, left
    out); returns the number of series."""
    series = {}
    for row in rows:
        x, y = finite(row.get(x_column)), finite(row.get(y_column))
        if x is None or y is None or x <= 0 or y == 0:
            continue
        series.setdefault(key(row), []).append((x, abs(y)))
    for name, pts in sorted(series.items()):
        pts.sort()
        ax.plot([p[0] for p in pts], [p[1] for p in pts], "-o", label=name)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.grid(True, which="both", alpha=0.3)
    if series:
        ax.legend(fontsize=7)
    return len(series)


def main(argv):
    if len(argv) != 4 or argv[1] not in ("t1", "t5b", "speed"):
        print(__doc__, file=sys.stderr)
        return 2
    case, csv_path, out_path = argv[1:]
    rows = read_rows(csv_path)
    if case == "t1":
        fig, ax = plt.subplots(figsize=(7, 5))
        n = series_plot(ax, rows, lambda r: "%s sweep" % r["sweep"], "dofs", "error_rel")
        ax.set_xlabel("DOFs (6 per rigid node)")
        ax.set_ylabel("|tip error| against 0.1501 m [-]")
        ax.set_title("T1 steel cantilever, rigid nodes with trilinear weights")
    elif case == "t5b":
        fig, axes = plt.subplots(1, 2, figsize=(12, 5))
        key = lambda r: "%s (%s)" % (r["model"], r["element"])  # noqa: E731
        n = series_plot(axes[0], rows, key, "dofs", "error_rel")
        series_plot(axes[1], rows, key, "ms_per_step", "error_rel")
        axes[0].set_xlabel("DOFs")
        axes[1].set_xlabel("ms per linearized implicit Euler step")
        for ax in axes:
            ax.set_ylabel("|tip error| against the finest tet10 [-]")
        fig.suptitle("T5(b) large deformation 16 x 1 x 1 m, E 40 kPa, 5 kg")
    else:
        fig, ax = plt.subplots(figsize=(7, 5))
        every = lambda r: "factorize every %s step(s)" % r["refresh_interval"]  # noqa: E731
        n = series_plot(ax, rows, lambda r: "thread CPU, " + every(r), "nodes", "cpu_ms_per_step")
        n += series_plot(ax, rows, lambda r: "wall (shared machine), " + every(r), "nodes",
                         "ms_per_step")
        bosman = [(finite(r["nodes"]), finite(r["bosman_ms"])) for r in rows]
        bosman = [p for p in bosman if p[0] and p[1]]
        if bosman:
            ax.plot([p[0] for p in bosman], [p[1] for p in bosman], "ks", label="Bosman Table 4.4")
            ax.plot([p[0] for p in bosman], [p[1] / 10 for p in bosman], "k--",
                    label="Bosman / 10 (target)")
            ax.legend(fontsize=7)
        ax.set_xlabel("rigid nodes")
        ax.set_ylabel("ms per linearized implicit Euler step")
        ax.set_title("Rigid-node step time (27 samples per grid cell)")
    fig.tight_layout()
    fig.savefig(out_path, dpi=110)
    print("wrote %s (%d series)" % (out_path, n))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
