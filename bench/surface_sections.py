#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Sections of a tessellated surface by axis-aligned planes, as `sweep --trajectory` polylines.

Reads an OBJ (`smoothforce export CACHE --level 16 -o s.obj`: the patch surface's triangles),
cuts every triangle by each plane, chains the segments into polylines through shared edges, and
writes the longest of each plane to OUT/<axis><value>.csv (header x,y,z; metres; a closed loop
repeats its first point). The slides of docs/fold-levers.md ("Slides") use x = -0.3 ... 0.3 and
z = -0.4, 0, 0.4, 0.8 on the spot cage.

    bench/surface_sections.py s.obj OUT --plane x=-0.3 --plane x=0 --plane z=0.4 ...
"""
import argparse
import collections
import pathlib
import sys

import numpy as np


def read_obj(path):
    """Vertices (V, 3) and triangles (T, 3) of an OBJ; polygons are fanned."""
    verts, tris = [], []
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                verts.append([float(t) for t in line.split()[1:4]])
            elif line.startswith("f "):
                ids = [int(t.split("/")[0]) for t in line.split()[1:]]
                ids = [i - 1 if i > 0 else len(verts) + i for i in ids]
                tris.extend([ids[0], ids[k], ids[k + 1]] for k in range(1, len(ids) - 1))
    return np.asarray(verts, dtype=float), np.asarray(tris, dtype=np.int64)


def section(verts, tris, axis, value):
    """The longest polyline of the surface's section by the plane coordinate[axis] = value."""
    d = verts[:, axis] - value
    d[d == 0] = 1e-300  # a vertex on the plane counts as above it: every crossing is an edge's interior
    # per triangle, the edges whose ends lie on opposite sides: a point on each, keyed by the edge
    points, links = {}, collections.defaultdict(list)
    for t in tris:
        cut = []
        for a, b in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            if (d[a] > 0) != (d[b] > 0):
                key = (min(a, b), max(a, b))
                if key not in points:
                    s = d[a] / (d[a] - d[b])
                    points[key] = verts[a] + s * (verts[b] - verts[a])
                cut.append(key)
        if len(cut) == 2:
            links[cut[0]].append(cut[1])
            links[cut[1]].append(cut[0])
    seen, best = set(), []
    for start in links:
        if start in seen:
            continue
        # walk one way, then the other, from `start`
        chain = [start]
        seen.add(start)
        for direction in range(2):
            cur = start
            while True:
                nxt = [k for k in links[cur] if k not in seen]
                if not nxt:
                    break
                cur = nxt[0]
                seen.add(cur)
                chain.append(cur) if direction == 0 else chain.insert(0, cur)
        closed = len(chain) > 2 and chain[0] in links[chain[-1]]
        poly = [points[k] for k in chain] + ([points[chain[0]]] if closed else [])
        length = sum(np.linalg.norm(np.subtract(poly[i + 1], poly[i])) for i in range(len(poly) - 1))
        if not best or length > best[0]:
            best = [length, poly]
    return best[1] if best else []


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("obj")
    ap.add_argument("out")
    ap.add_argument("--plane", action="append", required=True, help="AXIS=VALUE, AXIS one of x, y, z (metres)")
    args = ap.parse_args(argv)
    verts, tris = read_obj(args.obj)
    if len(tris) == 0:
        sys.exit(f"{args.obj}: no faces")
    uniq, inverse = np.unique(verts, axis=0, return_inverse=True)
    verts, tris = uniq, inverse.ravel()[tris]
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    for spec in args.plane:
        axis_name, _, value = spec.partition("=")
        if axis_name not in ("x", "y", "z") or not value:
            sys.exit(f"--plane: expected AXIS=VALUE with AXIS x, y or z, got '{spec}'")
        poly = section(verts, tris, "xyz".index(axis_name), float(value))
        if len(poly) < 2:
            print(f"{spec}: no section", file=sys.stderr)
            continue
        path = out / f"{axis_name}{value}.csv"
        with open(path, "w") as f:
            f.write("x,y,z\n")
            for p in poly:
                f.write(f"{p[0]:.17g},{p[1]:.17g},{p[2]:.17g}\n")
        print(f"{path}: {len(poly)} points")


if __name__ == "__main__":
    main(sys.argv[1:])
