#!/usr/bin/python3
"""Scaling plot, phase split and fraction of the machine's limits of the organ benchmarks.

usage: plot_scaling.py OUT_DIR PROBE.csv BENCH.csv [BENCH.csv ...]
PROBE.csv is machine_probe's output; each BENCH.csv a tissue_bench or contact_bench CSV. Writes
  OUT_DIR/<stem>_scaling.png   log-log ms per step (mean) against nodes, one series per
                               (variant, solver) (a variant <v>_<n>k continues variant <v>), a
                               dotted twin for the steps after the first where they differ by
                               more than 20 %, and an n^1.2 line through the 1k-node point of
                               the series that reaches the most nodes
  OUT_DIR/<stem>_phases.png    the mean step split into its phases, stacked bars per case
  OUT_DIR/phase_limits.csv     tissue_bench rows: per phase the achieved GFLOP/s and GB/s and the
                               fraction of the roofline limit min(peak, intensity x bandwidth),
                               with the probe's 1-thread and 2-thread triad and dgemm figures
and prints phase_limits as a Markdown table. The dgemm peak is the faster of blas_dgemm and
blocked_dgemm.
"""
import csv
import math
import os
import re
import sys

# --help answers before matplotlib loads (it would write its font cache into $HOME).
if __name__ == "__main__" and ("--help" in sys.argv[1:] or "-h" in sys.argv[1:]):
    print(__doc__)
    sys.exit(0)

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

SCALING_EXPONENT = 1.2
TISSUE_PHASES = [("forces_ms", "forces + tangents"), ("assembly_ms", "assembly"),
                 ("factor_ms", "factor / preconditioner"), ("solve_ms", "linear iterations")]
CONTACT_PHASES = TISSUE_PHASES + [("collision_ms", "detection"),
                                  ("compliance_ms", "compliance solves (Delassus, correction)"),
                                  ("lcp_ms", "LCP"), ("linearization_ms", "linearization")]
# Phase -> (GFLOP/s column, GB/s column) of tissue_bench.
RATE_COLUMNS = [("forces", "forces_gflops", "forces_gbs"),
                ("assembly", "assembly_gflops", "assembly_gbs"),
                ("factorization", "factor_gflops", "factor_gbs"),
                ("linear_solve", "solve_gflops", "solve_gbs")]


def number(row, key):
    try:
        value = float(row.get(key, "nan"))
    except ValueError:
        return float("nan")
    return value


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def read_probe(path):
    """{threads: (triad GB/s, dgemm GFLOP/s)}"""
    limits = {}
    for row in read_rows(path):
        threads = int(row["threads"])
        bw, peak = limits.get(threads, (0.0, 0.0))
        rate = number(row, "rate")
        if row["probe"] == "triad":
            bw = max(bw, rate)
        elif row["probe"].endswith("dgemm"):
            peak = max(peak, rate)
        limits[threads] = (bw, peak)
    return limits


def series_key(row):
    key = row["solver"]
    return "%s: %s" % (row["variant"], key) if row.get("variant") else key


def scaling_key(row):
    """series_key, with a variant named <base>_<n>k (a bigger mesh run on its own, e.g.
    after_64k) continuing the series of variant <base>."""
    variant = re.sub(r"_\d+k$", "", row.get("variant") or "")
    return "%s: %s" % (variant, row["solver"]) if variant else row["solver"]


def plot_scaling(rows, title, out_path):
    series, steady = {}, {}
    for row in rows:
        ms, nodes = number(row, "ms_per_step"), number(row, "nodes")
        if ms > 0 and nodes > 0:
            series.setdefault(scaling_key(row), []).append((nodes, ms))
            after_first = number(row, "ms_after_first")
            if after_first > 0:
                steady.setdefault(scaling_key(row), []).append((nodes, after_first))
    fig, ax = plt.subplots(figsize=(7.5, 5.5))
    for key, pts in sorted(series.items()):
        pts.sort()
        line = ax.plot([p[0] for p in pts], [p[1] for p in pts], "-o", label=key)[0]
        later = sorted(steady.get(key, []))
        if any(abs(a[1] - b[1]) > 0.2 * b[1] for a, b in zip(later, pts)):
            ax.plot([p[0] for p in later], [p[1] for p in later], ":", marker="o",
                    fillstyle="none", color=line.get_color(), label=key + " (after the first step)")
    if series:
        longest = max(series.values(), key=lambda pts: (len(pts), -min(p[0] for p in pts)))
        n0, ms0 = min(longest)
        n_max = max(p[0] for pts in series.values() for p in pts)
        xs = [n0, n_max]
        ax.plot(xs, [ms0 * (x / n0) ** SCALING_EXPONENT for x in xs], "k--", alpha=0.6,
                label="n^%.1f through %d nodes" % (SCALING_EXPONENT, n0))
        ax.legend(fontsize=7)
    ax.set(xscale="log", yscale="log", xlabel="nodes", ylabel="ms per step (mean)",
           title="%s: step time against mesh size" % title)
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(out_path, dpi=110)
    print("wrote %s (%d series)" % (out_path, len(series)))


def plot_phases(rows, title, out_path):
    contact = "collision_ms" in rows[0] if rows else False
    phases = CONTACT_PHASES if contact else TISSUE_PHASES
    labels, stacks = [], []
    for row in rows:
        values = [max(0.0, number(row, key)) for key, _ in phases]
        values = [v if math.isfinite(v) else 0.0 for v in values]
        total = number(row, "ms_per_step")
        rest = total - sum(values)
        values.append(rest if math.isfinite(rest) and rest > 0 else 0.0)
        labels.append("%s\n%d nodes" % (series_key(row), int(number(row, "nodes"))))
        stacks.append(values)
    names = [name for _, name in phases] + ["other"]
    fig, ax = plt.subplots(figsize=(max(7.5, 0.8 * len(rows) + 3), 5.5))
    bottoms = [0.0] * len(rows)
    for k, name in enumerate(names):
        heights = [s[k] for s in stacks]
        ax.bar(range(len(rows)), heights, bottom=bottoms, label=name)
        bottoms = [b + h for b, h in zip(bottoms, heights)]
    ax.set_xticks(range(len(rows)))
    ax.set_xticklabels(labels, fontsize=6, rotation=60, ha="right")
    ax.set_yscale("log" if any(b > 100 * min(bottoms) for b in bottoms if b > 0) else "linear")
    ax.set_ylabel("ms per step (mean%s)" % (", steps in contact" if contact else ""))
    ax.set_title("%s: phase split of a step" % title)
    ax.legend(fontsize=7, loc="upper left", framealpha=0.8)
    ax.grid(True, axis="y", alpha=0.3)
    fig.tight_layout()
    fig.savefig(out_path, dpi=110)
    print("wrote %s (%d cases)" % (out_path, len(rows)))


def roofline_fraction(gflops, gbs, limit):
    """Achieved / min(peak, intensity x bandwidth); NaN without both rates."""
    bw, peak = limit
    if not (gflops > 0 and gbs > 0 and bw > 0 and peak > 0):
        return float("nan")
    intensity = gflops / gbs  # flop per byte
    return gflops / min(peak, intensity * bw)


def phase_limits(rows, limits, out_path):
    header = ["case", "variant", "solver", "nodes", "phase", "ms", "gflops", "gbs",
              "flop_per_byte", "fraction_1_thread", "fraction_2_threads", "bound"]
    out = []
    ms_column = {"forces": "forces_ms", "assembly": "assembly_ms",
                 "factorization": "factor_ms", "linear_solve": "solve_ms"}
    for row in rows:
        for phase, flop_col, byte_col in RATE_COLUMNS:
            gflops, gbs = number(row, flop_col), number(row, byte_col)
            if not (math.isfinite(gflops) and math.isfinite(gbs)):
                continue
            bw, peak = limits.get(1, (0.0, 0.0))
            bound = "memory" if gbs > 0 and gflops / gbs * bw < peak else "compute"
            out.append([row["case"], row.get("variant", ""), row["solver"], row["nodes"], phase,
                        "%.3g" % number(row, ms_column[phase]), "%.3g" % gflops, "%.3g" % gbs,
                        "%.3g" % (gflops / gbs if gbs > 0 else float("nan")),
                        "%.2f" % roofline_fraction(gflops, gbs, limits.get(1, (0, 0))),
                        "%.2f" % roofline_fraction(gflops, gbs, limits.get(2, (0, 0))), bound])
    with open(out_path, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(header)
        writer.writerows(out)
    print("wrote %s (%d rows)" % (out_path, len(out)))
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    for r in out:
        print("| " + " | ".join(r) + " |")


def main(argv):
    if len(argv) < 4:
        print(__doc__, file=sys.stderr)
        return 2
    out_dir, probe_path, bench_paths = argv[1], argv[2], argv[3:]
    limits = read_probe(probe_path)
    for threads, (bw, peak) in sorted(limits.items()):
        print("machine, %d thread(s): triad %.1f GB/s, dgemm %.1f GFLOP/s" % (threads, bw, peak))
    tissue_rows = []
    for path in bench_paths:
        rows = read_rows(path)
        stem = os.path.splitext(os.path.basename(path))[0]
        if not rows:
            print("%s: no rows" % path, file=sys.stderr)
            continue
        plot_scaling(rows, stem, os.path.join(out_dir, stem + "_scaling.png"))
        plot_phases(rows, stem, os.path.join(out_dir, stem + "_phases.png"))
        if "forces_gflops" in rows[0]:
            tissue_rows += rows
    phase_limits(tissue_rows, limits, os.path.join(out_dir, "phase_limits.csv"))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
