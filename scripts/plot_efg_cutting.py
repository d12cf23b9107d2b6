#!/usr/bin/python3
"""Plots the meshless (EFG) cutting benchmark (cutting_bench --efg) CSVs of a report directory.

usage: plot_efg_cutting.py DIR
Reads those of DIR/efg_cut_update.csv, DIR/efg_cut_progressive.csv, DIR/efg_cut_independence.csv,
DIR/efg_cut_node.csv and DIR/cutting_t3c.csv that exist and writes DIR/efg_cut_update.png
(crossing detection and topology update per blade sweep that cut, ~20k IPs, for the scalpel and
the spanning blade), DIR/efg_cut_progressive.png (cut update and implicit step time per sweep
over the progressive cuts, raw and as a moving mean over 50 sweeps), DIR/efg_cut_independence.png
(cut update of the same probe sweeps on a fresh body and on one cut elsewhere before),
DIR/efg_cut_node.png (step and cut time per step of the node's path) and DIR/cutting_t3c.png
(T3(c) tip error of the cut beams against the fine duplicated-node reference, against ms per
step, per cutter and load).
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
from plot_cutting import finish, rows  # noqa: E402  (same folder)

def moving_mean(values, width):
    out, total = [], 0.0
    for i, v in enumerate(values):
        total += v
        if i >= width:
            total -= values[i - width]
        out.append(total / min(i + 1, width))
    return out


def plot_update(d):
    data = [r for r in rows(os.path.join(d, "efg_cut_update.csv"))
            if int(r["severed_links"]) > 0 or int(r["crossed_edges"]) > 0]
    runs = [("update", "2 cm scalpel"), ("update_span", "blade spanning the body")]
    fig, axes = plt.subplots(1, len(runs), figsize=(11, 5))
    for ax, (run, label) in zip(axes, runs):
        part = [r for r in data if r["run"] == run]
        bottom = [0.0] * len(part)
        for key, name in (("detect_ms", "crossing detection"), ("topology_ms", "topology update")):
            values = [float(r[key]) for r in part]
            ax.bar(range(len(part)), values, bottom=bottom, label=name)
            bottom = [b + v for b, v in zip(bottom, values)]
        ax.plot(range(len(part)), [float(r["positions_ms"]) for r in part], "k.", markersize=3,
                label="surface positions (display)")
        ax.set_title(label)
        ax.set_xlabel("blade sweep that cut")
        ax.grid(True, alpha=0.3)
    if data:
        fig.suptitle("EFG cut update per sweep: %s IPs, %s surface triangles" % (
            data[0]["ips"], data[0]["surface_triangles"]))
    finish(fig, axes[0], d, "efg_cut_update.png", "blade sweep that cut", "time [ms]",
           runs[0][1])


def plot_progressive(d):
    data = rows(os.path.join(d, "efg_cut_progressive.csv"))
    index = list(range(len(data)))
    fig, ax = plt.subplots(figsize=(7.5, 5))
    for key, label, color in (("update_ms", "cut update", "tab:blue"),
                              ("step_ms", "implicit step", "tab:orange")):
        values = [float(r[key]) for r in data]
        ax.plot(index, values, ".", color=color, alpha=0.25, markersize=2)
        ax.plot(index, moving_mean(values, 50), "-", color=color, label=label + " (mean of 50)")
    if data:
        ax.set_yscale("log")
        title = "EFG progressive cuts: %s IPs, %s cuts, DOFs %s" % (
            data[0]["ips"], int(data[-1]["cut"]) + 1, data[-1]["dofs"])
    else:
        title = "EFG progressive cuts (no sweep)"
    finish(fig, ax, d, "efg_cut_progressive.png", "blade sweep", "time [ms]", title)


def plot_independence(d):
    data = rows(os.path.join(d, "efg_cut_independence.csv"))
    fresh = [r for r in data if r["body"] == "fresh"]
    after = [r for r in data if r["body"] == "after"]
    # The sweeps that cut the fresh body, in order; the same sweep on the other body beside it.
    pairs = [(f, a) for f, a in zip(fresh, after)
             if int(f["severed_links"]) > 0 or int(f["crossed_edges"]) > 0]
    fig, ax = plt.subplots(figsize=(7.5, 5))
    for k, label, color in ((0, "fresh body", "tab:blue"), (1, "after the background cuts",
                                                              "tab:red")):
        values = [float(p[k]["update_ms"]) for p in pairs]
        ax.plot(range(len(values)), values, "o", color=color, markersize=3, alpha=0.6,
                label="%s (mean %.3f ms)" % (label, sum(values) / max(len(values), 1)))
    title = "EFG cut independence (no sweep)"
    if pairs:
        title = "Same probe cuts, %s IPs: fresh vs after %s cuts elsewhere (%s triangles)" % (
            pairs[0][0]["ips"], pairs[0][1]["background_cuts"], pairs[0][1]["triangles"])
    finish(fig, ax, d, "efg_cut_independence.png", "probe sweep that cut", "cut update [ms]",
           title)


def plot_t3c(d):
    series = {}
    for r in rows(os.path.join(d, "cutting_t3c.csv")):
        series.setdefault((r["cutter"], r["load"]), []).append(
            (float(r["step_ms"]), 100.0 * abs(float(r["error_rel"]))))
    fig, ax = plt.subplots(figsize=(7.5, 5))
    for (cutter, load), pts in sorted(series.items()):
        pts.sort()
        ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-" if cutter == "efg" else "s--",
                label="%s, %s" % (cutter, load))
    for target, load, style in ((0.8, "bend", ":"), (3.7, "stretch", "-.")):
        ax.axhline(target, color="grey", linestyle=style, linewidth=1,
                   label="Magnoux cut %s %.1f %%" % (load, target))
    ax.set_xscale("log")
    ax.set_yscale("log")
    finish(fig, ax, d, "cutting_t3c.png", "implicit step [ms]",
           "|tip error| against the duplicated-node reference [%]",
           "T3(c) hexagonal beam cut through half the width at mid-length")


def plot_node(d):
    data = rows(os.path.join(d, "efg_cut_node.csv"))
    fig, ax = plt.subplots(figsize=(7.5, 5))
    index = [int(r["step"]) for r in data]
    for key, label, style in (("step_ms", "step", "-"), ("cut_ms", "cut (in the step)", ".")):
        ax.plot(index, [float(r[key]) for r in data], style, label=label)
    title = "EFG cutting in the node's path (liver_efg.yaml)"
    if data:
        title += ": %s -> %s triangles" % (data[0]["triangles"], data[-1]["triangles"])
    finish(fig, ax, d, "efg_cut_node.png", "step", "time [ms]", title)


def main():
    if len(sys.argv) != 2:
        print(__doc__)
        sys.exit(2)
    d = sys.argv[1]
    for name, plot in (("efg_cut_update.csv", plot_update),
                       ("efg_cut_progressive.csv", plot_progressive),
                       ("efg_cut_independence.csv", plot_independence),
                       ("efg_cut_node.csv", plot_node),
                       ("cutting_t3c.csv", plot_t3c)):
        if os.path.exists(os.path.join(d, name)):
            plot(d)


if __name__ == "__main__":
    main()
