#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Opens every viewer-facing output of `smoothforce` in VTK's readers and NumPy.

usage: test_viewer_outputs.py SMOOTHFORCE DATA_DIR SHARED_MESHES WORK_DIR

Needs python3-vtk9 and python3-numpy (tools/setup). Checks, against independent computations:
- export: the welded surface has V + E (L-1) + sum_f (1 + n L (L-1)/2) vertices (counted from the
  mesh file), one connected component per mesh component, no boundary edge on a closed mesh
  (no open seam), no two vertices closer than the weld tolerance, and the same vertex count as a
  positional merge (vtkCleanPolyData) of the unwelded export; binary PLY per-vertex status, fold
  and bulge against `cache info --json`; OBJ groups per patch; a flat-shaded mesh on its file normals
  (creases everywhere) welds closed: each crease edge is one curve both patches share.
- sweep: every .vtp array against results_METHOD.bin (read with the documented dtype) for every
  HIP, the discontinuity against a brute-force k-nearest computation, the PLY's quality and
  `element face 0`, results_METHOD.npy against the .bin files, a PDF beside every PNG.
"""
import json
import os
import re
import subprocess
import sys

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

FAILURES = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        FAILURES.append(what)


def run(*args):
    r = subprocess.run([str(a) for a in args], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"{' '.join(map(str, args))} exited {r.returncode}:\n{r.stdout}\n{r.stderr}")
    return r.stdout


def read_mesh_faces(path):
    """Face vertex lists of an OBJ or OFF file (independent of smoothforce's readers)."""
    faces, nverts = [], 0
    with open(path) as f:
        if path.endswith(".off"):
            lines = [l.split() for l in f if l.strip() and not l.startswith("#")]
            nv, nf = int(lines[1][0]), int(lines[1][1])
            faces = [[int(x) for x in l[1:1 + int(l[0])]] for l in lines[2 + nv:2 + nv + nf]]
            return nv, faces
        for line in f:
            p = line.split()
            if p and p[0] == "v":
                nverts += 1
            elif p and p[0] == "f":
                faces.append([int(x.split("/")[0]) - 1 for x in p[1:]])
    return nverts, faces


def components(nverts, faces):
    parent = list(range(nverts))

    def root(v):
        while parent[v] != v:
            parent[v] = parent[parent[v]]
            v = parent[v]
        return v

    for fv in faces:
        for v in fv[1:]:
            parent[root(v)] = root(fv[0])
    return len({root(v) for fv in faces for v in fv})


def read_vtk(reader_cls, path):
    r = reader_cls()
    r.SetFileName(path)
    r.Update()
    return r.GetOutput()


def ply_header(path):
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    return data[:end].decode(), data[end:]


def check_export(sf, mesh, work, level, closed, name):
    cache = os.path.join(work, name + ".sfcache")
    run(sf, "cache", "build", mesh, "-o", cache)
    info = json.loads(run(sf, "cache", "info", cache, "--json"))
    nv, faces = read_mesh_faces(mesh)
    edges = {tuple(sorted((fv[k], fv[(k + 1) % len(fv)]))) for fv in faces for k in range(len(fv))}
    L = level
    expected = nv + len(edges) * (L - 1) + sum(1 + len(fv) * L * (L - 1) // 2 for fv in faces)
    triangles = sum(len(fv) * L * L for fv in faces)
    ply, obj, loose = (os.path.join(work, name + s) for s in (".ply", ".obj", "_loose.ply"))
    run(sf, "export", cache, "--level", L, "-o", ply)
    run(sf, "export", cache, "--level", L, "-o", obj)
    run(sf, "export", cache, "--level", L, "-o", loose, "--no-weld", "--ascii")

    out = read_vtk(vtk.vtkPLYReader, ply)
    check(out.GetNumberOfPoints() == expected,
          f"{name}: welded PLY has {out.GetNumberOfPoints()} vertices, V + E(L-1) + interiors = {expected}")
    check(out.GetNumberOfCells() == triangles, f"{name}: {out.GetNumberOfCells()} triangles = sum n L^2 = {triangles}")
    conn = vtk.vtkPolyDataConnectivityFilter()
    conn.SetInputData(out)
    conn.SetExtractionModeToAllRegions()
    conn.Update()
    comp = components(nv, faces)
    check(conn.GetNumberOfExtractedRegions() == comp,
          f"{name}: {conn.GetNumberOfExtractedRegions()} connected pieces = {comp} mesh components")
    fe = vtk.vtkFeatureEdges()
    fe.SetInputData(out)
    fe.BoundaryEdgesOn()
    fe.FeatureEdgesOff()
    fe.ManifoldEdgesOff()
    fe.NonManifoldEdgesOff()
    fe.Update()
    mesh_boundary = sum(1 for e in edges
                        if sum(1 for fv in faces for k in range(len(fv))
                               if tuple(sorted((fv[k], fv[(k + 1) % len(fv)]))) == e) == 1)
    check(fe.GetOutput().GetNumberOfCells() == mesh_boundary * L,
          f"{name}: {fe.GetOutput().GetNumberOfCells()} boundary edges = {mesh_boundary} mesh boundary edges x L"
          + (" (closed: no open seam)" if closed else ""))
    diag = float(np.linalg.norm(np.ptp(vtk_to_numpy(out.GetPoints().GetData()), axis=0)))
    tol = 1e-7 * diag
    for label, poly in (("welded", out), ("unwelded", read_vtk(vtk.vtkPLYReader, loose))):
        clean = vtk.vtkCleanPolyData()
        clean.SetInputData(poly)
        clean.ToleranceIsAbsoluteOn()
        clean.SetAbsoluteTolerance(tol)
        clean.Update()
        n = clean.GetOutput().GetNumberOfPoints()
        check(n == expected, f"{name}: positional merge of the {label} export ({poly.GetNumberOfPoints()} vertices) "
              f"within {tol:.2g} m leaves {n} = {expected}")

    head, body = ply_header(ply)
    check("format binary_little_endian 1.0" in head, f"{name}: export PLY is binary little-endian")
    for prop in ("property uint status", "property uchar fold", "property float bulge", "property int patch"):
        check(prop in head, f"{name}: export PLY declares '{prop}'")
    vdt = np.dtype([("x", "<f8"), ("y", "<f8"), ("z", "<f8"), ("nx", "<f4"), ("ny", "<f4"), ("nz", "<f4"),
                    ("status", "<u4"), ("fold", "u1"), ("bulge", "<f4")])
    fdt = np.dtype([("n", "u1"), ("v", "<i4", (3,)), ("patch", "<i4")])
    verts = np.frombuffer(body, vdt, expected)
    tris = np.frombuffer(body, fdt, triangles, offset=expected * vdt.itemsize)
    check(len(body) == expected * vdt.itemsize + triangles * fdt.itemsize, f"{name}: PLY body size")
    pts = vtk_to_numpy(out.GetPoints().GetData())
    check(np.allclose(pts, np.c_[verts["x"], verts["y"], verts["z"]], rtol=0, atol=1e-6 * diag),
          f"{name}: VTK's points equal the PLY's doubles")
    folds = set(info["patches"]["fold_faces"])
    expect_fold = np.zeros(expected, np.uint8)
    for t in tris:
        if int(t["patch"]) in folds:
            expect_fold[t["v"]] = 1
    check(np.array_equal(verts["fold"], expect_fold),
          f"{name}: per-vertex fold = on a triangle of the {len(folds)} fold faces of `cache info` "
          f"({int(expect_fold.sum())} vertices)")
    check(abs(float(verts["bulge"].max()) - float(info["patches"]["max_bulge"])) <= 1e-6 * max(1.0, verts["bulge"].max()),
          f"{name}: largest per-vertex bulge {verts['bulge'].max():.6g} = cache max_bulge {info['patches']['max_bulge']}")
    check(not (verts["status"] & 0x40).any(), f"{name}: no vertex evaluated outside its domain (status)")

    objp = read_vtk(vtk.vtkOBJReader, obj)
    check(objp.GetNumberOfPoints() == expected, f"{name}: OBJ read by vtkOBJReader: {objp.GetNumberOfPoints()} points")
    groups = re.findall(r"^g patch_(\d+)$", open(obj).read(), re.M)
    check(sorted(map(int, groups)) == list(range(len(faces))), f"{name}: OBJ has one group per patch ({len(groups)})")


def check_crease_export(sf, work):
    """A flat-shaded mesh built on its file normals (--normals file): every edge is a crease, one
    curve both patches build bit for bit, so the export welds closed: no edge left open."""
    knot, flat = os.path.join(work, "knot.obj"), os.path.join(work, "knot_flat.obj")
    run(sf, "generate", "torus-knot", "--segments", 24, "--sides", 6, "-o", knot)
    nv, faces = read_mesh_faces(knot)
    v = np.array([[float(x) for x in l.split()[1:4]] for l in open(knot) if l.startswith("v ")])
    with open(flat, "w") as f:
        f.writelines(f"v {p[0]!r} {p[1]!r} {p[2]!r}\n" for p in v)
        for fv in faces:
            n = np.cross(v[fv[1]] - v[fv[0]], v[fv[2]] - v[fv[0]])
            f.write(f"vn {n[0]!r} {n[1]!r} {n[2]!r}\n")
        for i, fv in enumerate(faces):
            f.write("f " + " ".join(f"{x + 1}//{i + 1}" for x in fv) + "\n")
    cache, ply, L = os.path.join(work, "knot_flat.sfcache"), os.path.join(work, "knot_flat.ply"), 3
    run(sf, "cache", "build", flat, "--normals", "file", "-o", cache)
    text = run(sf, "export", cache, "--level", L, "-o", ply)
    edges = {tuple(sorted((fv[k], fv[(k + 1) % len(fv)]))) for fv in faces for k in range(len(fv))}
    expected = nv + len(edges) * (L - 1) + sum(1 + len(fv) * L * (L - 1) // 2 for fv in faces)
    n = read_vtk(vtk.vtkPLYReader, ply).GetNumberOfPoints()
    check(f"{len(edges)} shared edges" in text and " 0 edges left open" in text and n == expected,
          f"crease: {n} vertices = V + E (L-1) + sum_f (1 + n L (L-1)/2) ({expected}), all {len(edges)} edges welded")


RESULT_DTYPE = np.dtype([("force", "<f4", (3,)), ("scp", "<f4", (3,)), ("ref_distance", "<f4"), ("face", "<i4"),
                         ("status", "<u4"), ("iterations", "<u2"), ("contact", "u1"), ("done", "u1")])


def discontinuity(pos, force, k, normals):
    """Brute force: per valid HIP, max over its k nearest valid HIPs of angle / distance, leaving
    out neighbours whose sample normals point apart (opposite sides of a thin part)."""
    valid = np.linalg.norm(force, axis=1) > 0
    out = np.full(len(pos), np.nan)
    idx = np.nonzero(valid)[0]
    for i in idx:
        d2 = ((pos[idx] - pos[i]) ** 2).sum(axis=1)
        order = np.argsort(d2, kind="stable")[:min(k + 1, len(idx))]
        best = -1.0
        for j in order:
            if d2[j] > 0 and normals[i] @ normals[idx[j]] >= 0:
                a, b = force[i], force[idx[j]]
                ang = np.arctan2(np.linalg.norm(np.cross(a, b)), a @ b)
                best = max(best, ang / np.sqrt(d2[j]))
        if best >= 0:
            out[i] = best
    return out


def check_sweep(sf, cache, work):
    out = os.path.join(work, "sweep")
    n = 150
    run(sf, "sweep", "--cache", cache, "--depth", "0.5%,1%", "--samples", n, "--methods", "patch,direct,shading",
        "--seed", 3, "-o", out)
    summary = json.load(open(os.path.join(out, "summary.json")))
    cfg = summary["config"]
    hips = np.fromfile(os.path.join(out, "hips.bin"), "<f8", offset=32).reshape(-1, 3)
    check(len(hips) == 2 * n, f"hips.bin holds {len(hips)} HIPs = 2 depths x {n}")
    normals = np.fromfile(os.path.join(out, "normals.bin"), "<f8", offset=32).reshape(-1, 3)
    check(len(normals) == 2 * n, f"normals.bin holds {len(normals)} sample normals")
    labels = {"0.5%": "0.5pct", "1%": "1pct"}
    for method in cfg["methods"]:
        res = np.fromfile(os.path.join(out, f"results_{method}.bin"), RESULT_DTYPE, offset=32)
        check(len(res) == 2 * n and res["done"].all(), f"results_{method}.bin: {len(res)} records, all done")
        npy = np.load(os.path.join(out, f"results_{method}.npy"))
        check(npy.shape == (2 * n,), f"results_{method}.npy: shape {npy.shape}")
        for field in ("force", "scp", "ref_distance", "face", "status", "iterations", "contact", "done"):
            check(np.array_equal(npy[field], res[field], equal_nan=npy[field].dtype.kind == "f"),
                  f"results_{method}.npy '{field}' = results_{method}.bin for all {len(res)} HIPs")
        check(np.array_equal(npy["hip"], hips), f"results_{method}.npy 'hip' = hips.bin")
        check(np.array_equal(npy["group"], np.repeat([0, 1], n)), f"results_{method}.npy 'group'")
        for g, label in enumerate(("0.5%", "1%")):
            sl = slice(g * n, (g + 1) * n)
            r, h, nr = res[sl], hips[sl], normals[sl]
            force = r["force"].astype(np.float64)
            valid = (r["contact"] == 1) & (np.linalg.norm(force, axis=1) > 0)
            disc = discontinuity(h, np.where(valid[:, None], force, 0), cfg["knn"], nr)
            tag = f"{method}_{labels[label]}"
            poly = read_vtk(vtk.vtkXMLPolyDataReader, os.path.join(out, tag + ".vtp"))
            pd = poly.GetPointData()
            names = {pd.GetArrayName(i) for i in range(pd.GetNumberOfArrays())}
            want = {"force", "force_magnitude", "discontinuity", "contact", "missed", "face", "status", "iterations",
                    "ref_distance", "scp", "hip_index"}
            check(want <= names, f"{tag}.vtp arrays {sorted(names)}")
            check(poly.GetNumberOfPoints() == n and poly.GetNumberOfVerts() == n,
                  f"{tag}.vtp: {poly.GetNumberOfPoints()} points, {poly.GetNumberOfVerts()} vertex cells = {n} HIPs")
            a = {k: vtk_to_numpy(pd.GetArray(k)) for k in want}
            check(np.array_equal(vtk_to_numpy(poly.GetPoints().GetData()), h), f"{tag}.vtp points = hips.bin")
            check(np.array_equal(a["hip_index"], np.arange(g * n, (g + 1) * n)), f"{tag}.vtp hip_index")
            check(np.array_equal(a["force"], r["force"]), f"{tag}.vtp force = results_{method}.bin")
            check(np.allclose(a["force_magnitude"], np.linalg.norm(force, axis=1), rtol=1e-6, atol=0),
                  f"{tag}.vtp force_magnitude = |force|")
            for k in ("contact", "face", "status", "iterations", "scp"):
                check(np.array_equal(a[k], r[k]), f"{tag}.vtp {k} = results_{method}.bin")
            check(np.array_equal(a["ref_distance"], r["ref_distance"], equal_nan=True), f"{tag}.vtp ref_distance")
            check(np.array_equal(np.isnan(a["discontinuity"]), np.isnan(disc)) and
                  np.allclose(a["discontinuity"], disc, rtol=1e-9, atol=0, equal_nan=True),
                  f"{tag}.vtp discontinuity = brute-force {cfg['knn']}-nearest angle/distance "
                  f"({int(np.isfinite(disc).sum())} HIPs with a value)")
            check(np.array_equal(npy["discontinuity"][sl], a["discontinuity"], equal_nan=True),
                  f"results_{method}.npy discontinuity = {tag}.vtp")
            head, body = ply_header(os.path.join(out, tag + ".ply"))
            check("property float quality" in head and "element face 0" in head,
                  f"{tag}.ply declares 'quality' and 'element face 0'")
            cloud = read_vtk(vtk.vtkPLYReader, os.path.join(out, tag + ".ply"))
            check(cloud.GetNumberOfPoints() == n, f"{tag}.ply read by vtkPLYReader: {cloud.GetNumberOfPoints()} points")
            pdt = np.dtype([("xyz", "<f4", (3,)), ("n", "<f4", (3,)), ("rgb", "u1", (3,)), ("quality", "<f4")])
            q = np.frombuffer(body, pdt, n)["quality"]
            check(np.allclose(q, np.where(np.isnan(disc), -1, disc), rtol=1e-6, atol=0),
                  f"{tag}.ply quality = discontinuity (rad/m, -1 none)")
    pngs = [f for f in os.listdir(out) if f.endswith(".png")]
    check(len(pngs) >= 3, f"{len(pngs)} PNG plots")
    for p in pngs:
        pdf = os.path.join(out, p[:-4] + ".pdf")
        check(os.path.exists(pdf) and open(pdf, "rb").read(5) == b"%PDF-", f"{p[:-4]}.pdf beside {p}")
    html = open(os.path.join(out, "index.html")).read()
    check("Note:" not in html and ".pdf\"" in html and ".vtp\"" in html, "index.html: no note, links PDFs and .vtp")


def main():
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    sf, data, shared, work = sys.argv[1:]
    os.makedirs(work, exist_ok=True)
    check_export(sf, os.path.join(data, "spot_control_mesh.obj"), work, 4, True, "spot")
    check_export(sf, os.path.join(shared, "pmp", "hole_capsule.off"), work, 3, False, "hole_capsule")
    check_crease_export(sf, work)
    check_sweep(sf, os.path.join(work, "spot.sfcache"), work)
    if FAILURES:
        sys.exit(f"{len(FAILURES)} checks failed")
    print("viewer outputs: all checks passed")


if __name__ == "__main__":
    main()
