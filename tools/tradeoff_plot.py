#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Plot of the speed/accuracy trade-off study (bench/study_tradeoff.cpp; run by tools/tradeoff).

usage: tools/tradeoff_plot.py OUTDIR

Reads OUTDIR/tradeoff.csv and writes
  tradeoff.png  median time per call against the max and the median error, pooled over the meshes
                (rows with mesh "all"): patch evaluation (left) and the full SCP query (middle: SCP
                distance error; right: force direction error; both over the queries that found the
                reference's minimum, failures are counted in the labels). The Pareto front (the
                csv's pareto column: median time, median and max error, failures) is ringed
                and labelled.
  pareto.md     a Markdown table of the Pareto points of both parts.
Needs matplotlib (Debian: python3-matplotlib).
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

MARKERS = {("double", "newton"): ("tab:blue", "o"), ("float", "newton"): ("tab:cyan", "s"),
           ("double", "paper"): ("tab:red", "^"), ("float", "paper"): ("tab:orange", "v")}


def label(r):
    """A short name of a configuration, as used in the tables of docs/results.md."""
    if r["part"] == "eval":
        return f'{r["precision"]} {r["cross_tangent"]}'
    fails = int(r["missed"]) + int(r["far"])
    return (f'{r["precision"]} {r["refine"]} tol {float(r["angle_tol"]):g} it {r["max_iter"]} '
            f'{r["initial_guess"]}' + (f" [{fails} fail]" if fails else ""))


def col(stem, stat):
    """The csv column of a statistic: err_max, angle_max_deg, ..."""
    return f"{stem}_{stat}" if stem == "err" else f"angle_{stat}_deg"


def floor(v):
    """Errors of exactly 0 cannot be drawn on a log axis."""
    return max(float(v), 1e-17)


def panel(ax, rows, err, title, ylabel):
    """One scatter: err is the csv column stem ("err" or "angle_deg": ..._median, ..._max)."""
    for r in rows:
        color, marker = MARKERS.get((r["precision"], r["refine"]), ("tab:green", "D"))
        if r["part"] == "eval":
            color, marker = ("tab:blue" if r["precision"] == "double" else "tab:orange",
                             "o" if r["cross_tangent"] == "corrected" else "^")
        hollow = r["initial_guess"] == "tessellation2"
        ax.scatter(float(r["time_median_us"]), floor(r[col(err, "max")]), s=22, marker=marker,
                   facecolors="none" if hollow else color, edgecolors=color, alpha=0.8)
        ax.scatter(float(r["time_median_us"]), floor(r[col(err, "median")]), s=6, marker=marker, color=color,
                   alpha=0.3)
    front = sorted((r for r in rows if r["pareto"] == "1"), key=lambda r: float(r["time_median_us"]))
    ax.scatter([float(r["time_median_us"]) for r in front], [floor(r[col(err, "max")]) for r in front], s=90,
               facecolors="none", edgecolors="k", lw=1.2)
    for r in front:
        tag = r["front_id"] if r["part"] == "query" else label(r)
        ax.annotate(tag, (float(r["time_median_us"]), floor(r[col(err, "max")])), fontsize=7,
                    xytext=(3, 3), textcoords="offset points")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("median time per call (us, one core)")
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=9)
    ax.grid(True, which="both", lw=0.3, alpha=0.5)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    outdir = sys.argv[1]
    with open(os.path.join(outdir, "tradeoff.csv")) as f:
        rows = [r for r in csv.DictReader(f) if r["mesh"] == "all"]
    front = sorted((r for r in rows if r["pareto"] == "1"), key=lambda r: (r["part"], float(r["time_median_us"])))
    for i, r in enumerate(r for r in front if r["part"] == "query"):
        r["front_id"] = f"P{i + 1}"
    ev = [r for r in rows if r["part"] == "eval"]
    qu = [r for r in rows if r["part"] == "query"]
    fig, axes = plt.subplots(1, 3, figsize=(17, 6))
    panel(axes[0], ev, "err", "patch evaluation vs double (corrected)", "position error / diagonal (max; dots: median; 0 at 1e-17)")
    panel(axes[1], qu, "err", "SCP query: SCP distance to the reference", "|SCP - SCP_ref| / diagonal (max; dots: median)")
    panel(axes[2], qu, "angle_deg", "SCP query: force direction", "force direction error, deg (max; dots: median)")
    handles = [plt.Line2D([], [], color=c, marker=m, ls="", label=f"{p} {r}") for (p, r), (c, m) in MARKERS.items()]
    handles.append(plt.Line2D([], [], color="gray", marker="o", ls="", mfc="none", label="hollow: tessellation start"))
    handles.append(plt.Line2D([], [], color="k", marker="o", mfc="none", ms=10, ls="",
                              label="Pareto front (time, median and max error, failures)"))
    axes[2].legend(handles=handles, fontsize=7, loc="upper right")
    axes[0].legend(handles=[plt.Line2D([], [], color="tab:blue", marker="o", ls="", label="double corrected"),
                            plt.Line2D([], [], color="tab:orange", marker="^", ls="", label="float blend"),
                            plt.Line2D([], [], color="k", marker="o", mfc="none", ms=10, ls="",
                                       label="Pareto front")], fontsize=7)
    fig.suptitle("SmoothForce speed against accuracy (spot, quad-sphere, generated torus; pooled)", fontsize=11)
    fig.tight_layout()
    png = os.path.join(outdir, "tradeoff.png")
    fig.savefig(png, dpi=90)
    lines = ["| id | part | configuration | median us | p99 us | err median | err max | angle median deg | "
             "angle max deg | failures (missed + far) / queries | mean iterations |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in front:
        lines.append(f'| {r.get("front_id", "")} | {r["part"]} | {label(r)} | {r["time_median_us"]} | {r["time_p99_us"]} | {r["err_median"]} | '
                     f'{r["err_max"]} | {r["angle_median_deg"]} | {r["angle_max_deg"]} | '
                     f'{int(r["missed"]) + int(r["far"])} / {r["queries"]} | {r["iter_mean"]} |')
    with open(os.path.join(outdir, "pareto.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print(f"wrote {png} and {os.path.join(outdir, 'pareto.md')}")


if __name__ == "__main__":
    main()
