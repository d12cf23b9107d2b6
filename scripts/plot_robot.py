#!/usr/bin/python3
"""Plots robot_bench output: per-step effector error (model, FE plant) and error vs solve time.

Usage: plot_robot.py <dir>   (reads <dir>/robot_bench.csv and robot_summary.csv,
                              writes <dir>/robot_bench.png)
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


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "."
    rows = list(csv.DictReader(open(out + "/robot_bench.csv")))
    summary = list(csv.DictReader(open(out + "/robot_summary.csv")))
    fig, axes = plt.subplots(1, 3, figsize=(16, 4.5))
    series = {}
    for r in rows:
        if r["path"] not in ("circle", "square"):
            continue
        key = r["robot"] + " " + r["path"]
        s = series.setdefault(key, ([], [], [], [], []))
        s[0].append(int(r["step"]))
        s[1].append(1e3 * float(r["model_error_m"]))
        s[2].append(float(r["solve_ms"]))
        pe = float(r["plant_error_m"])
        if not math.isnan(pe):
            s[3].append(int(r["step"]))
            s[4].append(1e3 * pe)
    for key, s in series.items():
        line, = axes[0].semilogy(s[0], [max(v, 1e-6) for v in s[1]], label=key + " model")
        axes[0].semilogy(s[3], s[4], "o--", color=line.get_color(), label=key + " FE plant")
        axes[1].plot(s[0], s[2], label=key)
    axes[0].set_xlabel("control step")
    axes[0].set_ylabel("effector error [mm]")
    axes[0].legend(fontsize=7)
    axes[0].set_title("tracking error (R1, R2)")
    axes[1].set_xlabel("control step")
    axes[1].set_ylabel("solve time [ms]")
    axes[1].legend(fontsize=7)
    axes[1].set_title("inverse solve time per step")
    for robot in sorted({r["robot"] for r in summary}):
        pts = [r for r in summary if r["robot"] == robot]
        axes[2].loglog([float(r["mean_solve_cpu_ms"]) for r in pts],
                       [1e3 * float(r["mean_error_m"]) for r in pts], "o-", label=robot)
        for r in pts:
            axes[2].annotate("%s/%s" % (r["max_iterations"], r["newton_iterations"]),
                             (float(r["mean_solve_cpu_ms"]), 1e3 * float(r["mean_error_m"])),
                             fontsize=7)
    axes[2].set_xlabel("mean solve CPU time per control step [ms]")
    axes[2].set_ylabel("mean effector error [mm]")
    axes[2].set_title("error vs solve time (labels: QP iterations / Newton cap)")
    axes[2].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out + "/robot_bench.png", dpi=110)


if __name__ == "__main__":
    main()
