#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""SmoothForce from Python: a patch cache from a mesh (file and NumPy arrays), a force trace,
a foreign-loop servo step. Run: PYTHONPATH=<build>/python python3 example.py MESH.obj"""
import sys

import numpy as np
import smoothforce as sf


def main(mesh):
    print("SmoothForce", sf.__version__, "(Python)")
    # 1. A cache from a mesh file, and the same mesh as arrays.
    cache = sf.Cache.from_file(mesh)
    same = sf.Cache.from_arrays(cache.positions, cache.face_offsets, cache.face_vertices)
    print(f"cache: {cache.num_faces} faces, {cache.num_vertices} vertices; from arrays: {same.num_faces} faces")

    # 2. A force trace along face 0's patch, 5 mm inside.
    n = 101
    pts = cache.evaluate(np.zeros(n, dtype=np.int32), np.linspace(-0.5, 0.5, n), np.zeros(n))
    hips = pts["position"] - 0.005 * pts["normal"]
    trace = sf.trace(cache, hips, method="patch", stiffness=500.0)
    jump = np.linalg.norm(np.diff(trace["force"], axis=0), axis=1).max()
    print(f"trace: {trace['contact'].sum()} of {n} steps in contact, largest step-to-step change {jump:.4f} N")

    # 3. The servo step from the caller's own loop.
    haptic = sf.Haptic(cache, stiffness=500.0)
    forces, contact = [], 0
    for k in range(2000):
        r = haptic.step(hips[k % n], k * 1e-3)
        forces.append(np.linalg.norm(r["force"]))
        contact += r["contact"]
    print(f"servo: 2000 steps, {contact} in contact, largest commanded force {max(forces):.4f} N (limit 3.3)")

    # 4. Errors: ValueError naming the element.
    try:
        sf.Cache.from_arrays(np.eye(3), [0, 3], [0, 1, 7])
        error = ""
    except ValueError as e:
        error = str(e)
    print("bad arrays:", error)
    ok = trace["contact"].all() and contact == 2000 and max(forces) <= 3.3 + 1e-9 and "vertex index 7" in error
    print("example_py:", "OK" if ok else "FAILED")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
