#!/usr/bin/python3
"""Plots the H1 rendered-force error against the tissue update rate from a trocar_bench CSV.

usage: plot_haptics.py CSV OUT.png
One series per model (zero_order_hold, local_linear); x: tissue update rate [Hz] (top axis labels:
ms per update), y: relative RMS force error, both logarithmic.
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
    if len(argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    csv_path, out_path = argv[1], argv[2]
    series = {}
    with open(csv_path, newline="") as f:
        for row in csv.DictReader(f):
            try:
                rate = float(row["update_rate_hz"])
                err = float(row["force_error_rel"])
            except (KeyError, ValueError):
                continue
            if row.get("status") != "ok" or not (math.isfinite(err) and rate > 0):
                continue
            key = "%s (%s, loop %s Hz)" % (row["model"], row["case"], row["loop_rate_hz"])
            series.setdefault(key, []).append((rate, max(err, 1e-16)))
    fig, ax = plt.subplots(figsize=(7.5, 5))
    for key, pts in sorted(series.items()):
        pts.sort()
        ax.plot([p[0] for p in pts], [p[1] for p in pts], "-o", label=key)
        for rate, err in pts:
            ax.annotate("%.1f ms" % (1e3 / rate), (rate, err), fontsize=6, alpha=0.7)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("tissue (contact model) update rate [Hz]")
    ax.set_ylabel("relative RMS rendered-force error [-]")
    ax.set_title("H1: rendered force error vs tissue update rate")
    ax.grid(True, which="both", alpha=0.3)
    if series:
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out_path, dpi=120)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
