#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Plots of a `smoothforce sweep` output directory (called by the sweep; runs on its own too).

usage: tools/sweep_plots.py OUTDIR

Reads OUTDIR/summary.json and OUTDIR/trajectories.json and writes, each as PNG and, beside it,
as PDF (vector, for papers):
  traj_<trajectory>_<depth>.png  consecutive force differences |F_i+1 - F_i| along the trajectory,
                                 one bar graph per method (the paper's bar graphs), with a dashed
                                 line where the path crosses a crease
  disc_hist_<depth>.png          histogram of the local force-direction discontinuity, all methods
  disc_summary.png               p50 / p99 / p99.9 / max of the discontinuity per method and depth
Needs matplotlib (Debian: python3-matplotlib).
"""
import json
import math
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

COLORS = {"patch": "tab:green", "direct": "tab:red", "shading": "tab:orange"}


def depth_tag(label):
    """The file-name form of a depth label, as sweep_sampling.cpp depthTag()."""
    t = "".join("pct" if c == "%" else c if (c.isalnum() or c in ".-_") else "_" for c in label)
    return t if label.endswith("%") else t + "m"


def safe(name):
    return re.sub(r"[^A-Za-z0-9._-]", "_", name)


def save(fig, png):
    """Writes the figure as PNG and as PDF beside it; returns both paths."""
    fig.savefig(png, dpi=110)
    pdf = os.path.splitext(png)[0] + ".pdf"
    fig.savefig(pdf)
    plt.close(fig)
    return [png, pdf]


def differences(force):
    f = [force[i:i + 3] for i in range(0, len(force), 3)]
    return [math.dist(f[i + 1], f[i]) for i in range(len(f) - 1)]


def plot_trajectories(outdir, trajectories):
    groups = {}
    for t in trajectories:
        if not t["half"]:
            groups.setdefault((t["trajectory"], t["depth_label"]), []).append(t)
    written = []
    for (name, depth), series in sorted(groups.items()):
        fig, axes = plt.subplots(len(series), 1, figsize=(10, 2.2 * len(series) + 0.8), sharex=True, squeeze=False)
        ymax = max([max(differences(s["force"]) or [0]) for s in series] + [1e-12])
        for ax, s in zip(axes[:, 0], series):
            d = differences(s["force"])
            # difference j lies between points j and j + 1: a crossing at point i marks bar i - 1
            creases = [i - 1 for i, c in enumerate(s.get("crease") or []) if c and i > 0]
            for j, x in enumerate(creases):
                ax.axvline(x, color="0.6", linestyle="--", linewidth=0.8, zorder=0,
                           label="crease crossed" if j == 0 else None)
            ax.bar(range(len(d)), d, width=1.0, color=COLORS.get(s["method"], "tab:blue"))
            ax.set_ylim(0, 1.05 * ymax)
            ax.set_ylabel("|dF| (N)")
            ax.set_title(f"{s['method']}: max {max(d or [0]):.3g} N", fontsize=9, loc="left")
            if creases:
                ax.legend(loc="upper right", fontsize=8)
        axes[-1, 0].set_xlabel(f"step along '{name}' (step {series[0]['step'] * 1000:.3g} mm)")
        fig.suptitle(f"Consecutive force differences, depth {depth}")
        fig.tight_layout()
        path = os.path.join(outdir, f"traj_{safe(name)}_{depth_tag(depth)}.png")
        written += save(fig, path)
    return written


def plot_histograms(outdir, results):
    by_depth = {}
    for r in results:
        by_depth.setdefault(r["depth"], []).append(r)
    written = []
    for depth, rs in sorted(by_depth.items()):
        fig, ax = plt.subplots(figsize=(8, 4))
        for r in rs:
            h = r["histogram"]
            lo, hi, n = h["lo"], h["hi"], h["bins"]
            counts = h["counts_below_bins_above"][1:-1]
            edges = [10 ** (lo + (hi - lo) * i / n) for i in range(n + 1)]
            ax.stairs(counts, edges, label=f"{r['method']} (flagged pairs {r['discontinuity']['flagged_pairs']})",
                      color=COLORS.get(r["method"], None), linewidth=1.5)
        ax.set_xscale("log")
        ax.set_yscale("symlog", linthresh=1)
        ax.axvline(1.0, color="k", linestyle=":", linewidth=1)
        ax.set_xlabel("local discontinuity x spacing / threshold angle (1 = threshold over one spacing)")
        ax.set_ylabel("HIPs")
        ax.set_title(f"Force-direction discontinuity, depth {depth}")
        ax.legend(fontsize=8)
        fig.tight_layout()
        path = os.path.join(outdir, f"disc_hist_{depth_tag(depth)}.png")
        written += save(fig, path)
    return written


def plot_summary(outdir, results):
    fig, ax = plt.subplots(figsize=(8, 4))
    labels = [f"{r['method']}\n{r['depth']}" for r in results]
    keys = [("p50", "p50"), ("p99", "p99"), ("p999", "p99.9"), ("max", "max")]
    width = 0.2
    for i, (k, name) in enumerate(keys):
        vals = [r["discontinuity"][k] or 0 for r in results]
        ax.bar([j + (i - 1.5) * width for j in range(len(results))], vals, width, label=name)
    ax.set_xticks(range(len(results)), labels, fontsize=8)
    ax.set_yscale("log")
    ax.set_ylabel("rad/m")
    ax.set_title("Force-direction discontinuity (angle / distance to the nearest HIPs)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    path = os.path.join(outdir, "disc_summary.png")
    return save(fig, path)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    outdir = sys.argv[1]
    with open(os.path.join(outdir, "summary.json")) as f:
        summary = json.load(f)
    trajectories = []
    tpath = os.path.join(outdir, "trajectories.json")
    if os.path.exists(tpath):
        with open(tpath) as f:
            trajectories = json.load(f)
        if isinstance(trajectories, dict):  # {"config_hash": ..., "series": [...]} since checkpoints
            trajectories = trajectories["series"]
    written = plot_trajectories(outdir, trajectories) + plot_histograms(outdir, summary["results"])
    if summary["results"]:
        written += plot_summary(outdir, summary["results"])
    print("sweep_plots: " + ", ".join(os.path.basename(p) for p in written))


if __name__ == "__main__":
    main()
