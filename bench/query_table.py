#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""The SCP query before and after, per closed mesh: README table rows.

For every mesh, runs `smoothforce sweep --methods patch --depth 0.1%,0.25%,1%` with the
binary under test (AFTER) and, when given, an older binary (BEFORE) on the same HIPs (the
sampler is deterministic: the HIP hashes are compared), and reports per mesh:
  missed   HIPs inside the patch surface without contact; "inside" is the AFTER sweep's own
           inside test (SF_PROBE_INSIDE, a tessellation at twice the query's level), applied to
           the BEFORE run's records too (same HIPs);
  cap      contact records that stopped at the refinement's iteration cap (SF_TRACK_MAX_ITER);
  |F|/kd   the range of |F| / (k x depth) over the in-contact points of the default trajectory
           (constant-depth section loop), worst depth;
  ratio    the largest consecutive force change at half the step over that at the step, worst
           depth (~0.5 smooth, ~1 a jump);
  us/HIP   probe wall time per HIP (timing.json, all threads; the machine's load applies).
Usage: query_table.py --after BIN [--before BIN] [--samples 20000] [--out DIR] MESH...
"""
import argparse
import json
import os
import struct
import subprocess
import sys

MAX_ITER = 0x20000
PROBE_INSIDE = 0x20000000
PROBE_UNDECIDED = 0x40000000
RECORD = struct.Struct("<3f3ffiIHBB")  # HipResult, 40 bytes


def records(path):
    """(status, contact, done) of every record of results_patch.bin (32-byte header)."""
    with open(path, "rb") as f:
        data = f.read()
    out = []
    for off in range(32, len(data), RECORD.size):
        r = RECORD.unpack_from(data, off)
        out.append((r[8], r[10], r[11]))
    return out


def run_seconds(out, stdout):
    """Probe seconds of the patch method: timing.json, else an older binary's stdout line
    "sweep: patch    N HIPs in S s (...)" (saved in stdout.txt)."""
    timing = os.path.join(out, "timing.json")
    if os.path.exists(timing):
        with open(timing) as f:
            return json.load(f)["methods"]["patch"]["seconds"]
    if not stdout and os.path.exists(os.path.join(out, "stdout.txt")):
        with open(os.path.join(out, "stdout.txt")) as f:
            stdout = f.read()
    for line in stdout.splitlines():
        p = line.split()
        if len(p) > 5 and p[0] == "sweep:" and p[1] == "patch" and p[3] == "HIPs":
            return float(p[5])
    return None


def sweep(binary, mesh, out, samples, extra, reuse=False):
    if reuse and os.path.exists(os.path.join(out, "summary.json")):
        with open(os.path.join(out, "summary.json")) as f:
            summary = json.load(f)
        return summary, run_seconds(out, "")
    cmd = [binary, "sweep", "--mesh", mesh, "--methods", "patch", "--depth", "0.1%,0.25%,1%",
           "--samples", str(samples), "--no-plots", "-o", out] + extra
    res = subprocess.run(cmd, capture_output=True, text=True)
    if res.returncode != 0:
        sys.exit(f"{' '.join(cmd)}: exit {res.returncode}\n{res.stderr}")
    with open(os.path.join(out, "stdout.txt"), "w") as f:
        f.write(res.stdout)
    seconds = run_seconds(out, res.stdout)
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    return summary, seconds


def trajectory_figures(out, stiffness):
    """Per depth label: (|F|/(k d) min, max over the in-contact points, points out of contact,
    half-step ratio) of the default loop."""
    with open(os.path.join(out, "trajectories.json")) as f:
        j = json.load(f)
    series = j["series"] if isinstance(j, dict) else j  # older binaries: a plain list
    per = {}
    for s in series:
        f = s["force"]
        mags = [sum(x * x for x in f[3 * i:3 * i + 3]) ** 0.5 for i in range(len(f) // 3)]
        diffs = [sum((f[3 * i + 3 + a] - f[3 * i + a]) ** 2 for a in range(3)) ** 0.5 for i in range(len(mags) - 1)]
        d = per.setdefault(s["depth_label"], {"lo": float("inf"), "hi": 0.0, "lost": 0})
        if s["half"]:
            d["half"] = max(diffs) if diffs else 0
            continue
        d["full"] = max(diffs) if diffs else 0
        kd = stiffness * s["depth"]
        inc = [m / kd for m, c in zip(mags[1:], s["contact"][1:]) if c]  # the first point is the approach
        d["lost"] += sum(1 for c in s["contact"][1:] if not c)
        if inc:
            d["lo"], d["hi"] = min(d["lo"], min(inc)), max(d["hi"], max(inc))
    for d in per.values():
        d["ratio"] = d["half"] / d["full"] if d.get("full") else float("nan")
    return per


def worst(per, labels):
    """The worst |F|/kd range, lost points and ratio over the given depth labels."""
    sel = [per[k] for k in labels if k in per]
    return (min(d["lo"] for d in sel), max(d["hi"] for d in sel), sum(d["lost"] for d in sel),
            max(d["ratio"] for d in sel))


def row(binary, mesh, out, samples, extra, inside=None, reuse=False):
    summary, seconds = sweep(binary, mesh, out, samples, extra, reuse)
    recs = records(os.path.join(out, "results_patch.bin"))
    n = len(recs)
    if inside is None:
        inside = [bool(s & PROBE_INSIDE) if not s & PROBE_UNDECIDED else None for s, _, _ in recs]
    missed = sum(1 for (s, c, d), i in zip(recs, inside) if d and i and not c)
    undecided = sum(1 for i in inside if i is None)
    cap = sum(1 for s, c, d in recs if d and c and s & MAX_ITER)
    per = trajectory_figures(out, summary["config"]["stiffness"])
    return {"hips": n, "hip_hash": summary["config"]["hip_hash"], "missed": missed, "undecided": undecided,
            "cap": cap, "shallow": worst(per, ["0.1%", "0.25%"]), "deep": worst(per, ["1%"]),
            "us_per_hip": 1e6 * seconds / n if seconds else float("nan"), "inside": inside}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--after", required=True)
    ap.add_argument("--before")
    ap.add_argument("--samples", type=int, default=20000)
    ap.add_argument("--out", default="query_table")
    ap.add_argument("--reuse", action="store_true", help="read the runs already in --out instead of running them")
    ap.add_argument("meshes", nargs="+")
    a = ap.parse_args()
    print("| mesh | HIPs | missed before → after | cap hits before → after | |F|/kd at 0.1, 0.25%: before → after "
          "| ratio at 0.1, 0.25%: before → after | at 1%: |F|/kd, ratio after (before) | µs/HIP before → after "
          "| undecided |")
    print("|---|---:|---:|---:|---|---|---|---:|---:|")
    rng = lambda t: f"{t[0]:.3f}..{t[1]:.3f}" + (f" (lost {t[2]})" if t[2] else "")
    for mesh in a.meshes:
        name = os.path.splitext(os.path.basename(mesh))[0]
        after = row(a.after, mesh, os.path.join(a.out, name, "after"), a.samples, [], reuse=a.reuse)
        before = None
        if a.before:
            before = row(a.before, mesh, os.path.join(a.out, name, "before"), a.samples, [], after["inside"], a.reuse)
            if before["hip_hash"] != after["hip_hash"]:
                sys.exit(f"{mesh}: the two binaries sampled different HIPs")
        def pair(key, fmt=str):
            """'before → after' of one figure (only 'after' without a BEFORE binary)."""
            return (fmt(before[key]) + " → " if before else "") + fmt(after[key])
        deep = f"{rng(after['deep'])}, {after['deep'][3]:.2f}"
        if before:
            deep += f" ({rng(before['deep'])}, {before['deep'][3]:.2f})"
        print(f"| {name} | {after['hips']} | {pair('missed')} | {pair('cap')} | {pair('shallow', rng)} "
              f"| {pair('shallow', lambda t: f'{t[3]:.2f}')} | {deep} | {pair('us_per_hip', lambda x: f'{x:.0f}')} "
              f"| {after['undecided']} |", flush=True)

if __name__ == "__main__":
    main()
