#!/usr/bin/python3
"""Plots the P2 cutting benchmark (cutting_bench) CSVs of a report directory.

usage: plot_cutting.py DIR
Reads DIR/cutting_update.csv, cutting_step.csv, cutting_error.csv, cutting_t3c.csv and writes
DIR/cutting_update.png (update time per topology change against the sweep index, one series per
mode and mesh size), cutting_step.png (step and cut time per step at ~10k elements, per solver)
and cutting_error.png (cut-surface error against update time, embedded cut surface and element
faces).
"""
import csv
import os
import sys

# --help answers before matplotlib loads (it would write its font cache into $HOME).
if __name__ == "__main__" and ("--help" in sys.argv[1:] or "-h" in sys.argv[1:]):
    print(__doc__)
    sys.exit(0)

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def finish(fig, ax, d, name, xlabel, ylabel, title):
    """Labels, grid and legend of one figure, written to d/name."""
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(d, name), dpi=120)


def plot_update(d):
    series = {}
    for r in rows(os.path.join(d, "cutting_update.csv")):
        if r["topology_changed"] == "1":
            series.setdefault((r["mode"], int(r["elements"])), []).append(
                (int(r["sweep"]), float(r["total_ms"])))
    fig, ax = plt.subplots(figsize=(7.5, 5))
    for (mode, elements), pts in sorted(series.items()):
        ax.plot([p[0] for p in pts], [p[1] for p in pts], "." if mode == "rebuild" else ".-",
                markersize=2, linewidth=0.6, label="%s, %d elements" % (mode, elements))
    ax.axhline(0.5, color="k", linestyle="--", linewidth=0.8, label="0.5 ms target")
    ax.set_yscale("log")
    finish(fig, ax, d, "cutting_update.png", "blade step (10 cuts x 60 steps of 1 mm)",
           "detection + topology update [ms]",
           "P2: cut update time per step that changed the topology")


def plot_step(d):
    data = rows(os.path.join(d, "cutting_step.csv"))
    fig, ax = plt.subplots(figsize=(7.5, 5))
    for solver, style in (("cholmod", "--"), ("pcg_cholesky_background", "-")):
        part = [r for r in data if r["solver"] == solver]
        steps = [int(r["step"]) for r in part]
        for key, label in (("step_ms", "whole step"), ("cut_ms", "cut (topology, model, contact)")):
            ax.plot(steps, [float(r[key]) for r in part], style, linewidth=0.9,
                    label="%s, %s" % (label, solver))
    ax.axhline(30.0, color="k", linestyle=":", linewidth=0.8, label="30 ms target")
    ax.set_yscale("log")
    finish(fig, ax, d, "cutting_step.png", "step (blade active in steps 40-99, 1 mm per step)",
           "wall time [ms]", "P2: palpation organ, %s elements at the end" % data[-1]["elements"])


def plot_error(d):
    data = rows(os.path.join(d, "cutting_error.csv"))
    t = [float(r["update_ms"]) for r in data]
    fig, ax = plt.subplots(figsize=(7.5, 5))
    ax.plot(t, [max(float(r["embedded_max_m"]), 1e-18) for r in data], "o-",
            label="embedded cut surface (max)")
    ax.plot(t, [float(r["faces_rms_m"]) for r in data], "s-", label="element faces of the cut (rms)")
    for r, x in zip(data, t):
        ax.annotate(r["elements"], (x, float(r["faces_rms_m"])), fontsize=7)
    ax.set_xscale("log")
    ax.set_yscale("log")
    finish(fig, ax, d, "cutting_error.png", "cut update time [ms]",
           "distance to the blade's swept surface [m]",
           "P2: cut-surface error vs update time (labels: elements)")


def main(argv):
    if len(argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    plot_update(argv[1])
    plot_step(argv[1])
    plot_error(argv[1])
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
