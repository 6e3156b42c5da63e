# SPDX-License-Identifier: Apache-2.0
"""The Python module against the engine's command line (the C++ results) and its own invariants:
properties over every face and every HIP, counts asserted."""
import csv
import json
import subprocess

import numpy as np
import pytest
import smoothforce as sf

SHARED = ["polygon_laplacian/hexaSphere.off", "pmp/chamfer-cube.off", "geomview/dodecahedron.off",
          "odedstein/spot_low_resolution.obj", "lagrange/cube.obj", "keenan_crane/spot_control_mesh.obj"]


def run(*args):
    subprocess.run([str(a) for a in args], check=True, capture_output=True)


def read_csv(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return rows


def domain_points(cache):
    """Every face: its centre and one point towards each corner (n + 1 points per face)."""
    off = np.asarray(cache.face_offsets)
    faces, xi, eta = [], [], []
    for f in range(cache.num_faces):
        n = off[f + 1] - off[f]
        faces.append(f), xi.append(0.0), eta.append(0.0)
        for k in range(n):
            a = 2 * np.pi * k / n
            faces.append(f), xi.append(0.6 * np.cos(a)), eta.append(0.6 * np.sin(a))
    return np.array(faces, dtype=np.int32), np.array(xi), np.array(eta)


def test_version():
    assert sf.__version__.count(".") == 2


def test_evaluate_matches_cli_eval_on_every_face(spot, paths, tmp_path):
    cache = sf.Cache.from_file(spot)
    faces, xi, eta = domain_points(cache)
    pts = cache.evaluate(faces, xi, eta)
    assert pts.shape == (len(faces),) and len(faces) == 180 + 4 * 3 + 160 * 4 + 16 * 5
    cache.save(tmp_path / "spot.sfcache")
    with open(tmp_path / "points.csv", "w") as f:
        f.write("face,xi,eta\n")
        for i in range(len(faces)):
            f.write(f"{faces[i]},{float(xi[i])!r},{float(eta[i])!r}\n")  # float: NumPy 2 scalars repr as np.float64(...)
    run(paths["cli"], "eval", tmp_path / "spot.sfcache", "--points", tmp_path / "points.csv", "-o", tmp_path / "e.csv")
    rows = read_csv(tmp_path / "e.csv")
    assert len(rows) == len(faces)
    ref = np.array([[float(r[k]) for k in ("x", "y", "z", "nx", "ny", "nz")] for r in rows])
    np.testing.assert_array_equal(pts["position"], ref[:, :3])
    np.testing.assert_array_equal(pts["normal"], ref[:, 3:])
    assert (pts["status"] & sf.SF_ST_OUTSIDE).sum() == 0  # none outside its domain
    np.testing.assert_allclose(np.linalg.norm(pts["normal"], axis=1), 1.0, atol=1e-12)


def test_evaluate_outside_domain_and_bad_face_are_flagged(spot):
    cache = sf.Cache.from_file(spot)
    pts = cache.evaluate([0, 5, 10_000, -1], [2.0, 0.0, 0.0, 0.0], [0.0, 3.0, 0.0, 0.0])
    assert list(pts["status"] & sf.SF_ST_OUTSIDE) == [sf.SF_ST_OUTSIDE] * 4
    assert not pts["position"].any()


@pytest.mark.parametrize("rel", SHARED)
def test_arrays_and_file_build_the_same_patches(paths, rel):
    path = paths["shared"] / rel
    if not path.exists():
        pytest.skip(f"{path} missing")
    a = sf.Cache.from_file(path, normals="angle", orient="keep")
    b = sf.Cache.from_arrays(np.array(a.positions), np.array(a.face_offsets), np.array(a.face_vertices),
                             normals_mode="angle", orient="keep")
    assert b.num_faces == a.num_faces and b.num_corners == a.num_corners
    np.testing.assert_array_equal(a.corner_normals, b.corner_normals)
    np.testing.assert_array_equal(a.face_status, b.face_status)
    faces, xi, eta = domain_points(a)
    pa, pb = a.evaluate(faces, xi, eta), b.evaluate(faces, xi, eta)
    np.testing.assert_array_equal(pa["position"], pb["position"])
    np.testing.assert_array_equal(pa["normal"], pb["normal"])


def test_arrays_from_the_file_give_the_file_cache_bytes(spot, tmp_path):
    """The positions and faces as read, no normals: the same bytes but the provenance hash."""
    a = sf.Cache.from_file(spot)
    b = sf.Cache.from_arrays(a.positions, a.face_offsets, a.face_vertices)
    a.save(tmp_path / "a.sfcache")
    b.save(tmp_path / "b.sfcache")
    ab, bb = (tmp_path / "a.sfcache").read_bytes(), (tmp_path / "b.sfcache").read_bytes()
    assert len(ab) == len(bb) and ab[128:] == bb[128:]  # payload identical; header has the mesh hash
    assert a.mesh_hash != b.mesh_hash
    assert sf.Cache.from_file(str(tmp_path / "b.sfcache")).num_faces == 180


def test_arrays_views_are_read_only_and_zero_copy(spot):
    c = sf.Cache.from_file(spot)
    p = c.positions
    assert p.shape == (188, 3) and not p.flags.writeable
    assert c.face_offsets.shape == (181,) and c.face_vertices.shape == (c.num_corners,)
    assert c.corner_normals.shape == (c.num_corners, 3) and c.face_status.shape == (180,)
    del c
    assert np.isfinite(p).all()  # the view keeps the cache alive


CUBE_P = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], float)
CUBE_F = np.array([0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4, 1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7])
CUBE_O = np.arange(0, 25, 4)


def bad(spoil):
    p, f, o = CUBE_P.copy(), CUBE_F.copy(), CUBE_O.copy()
    kw = spoil(p, f, o) or {}
    return p, f, o, kw


@pytest.mark.parametrize("spoil,message", [
    (lambda p, f, o: p.__setitem__((5, 1), np.nan), "cube: positions[5][1] (vertex 5): non-finite value nan"),
    (lambda p, f, o: f.__setitem__(9, 8), "cube: faceVertices[9] (face 2, corner 1): vertex index 8 out of range [0, 8)"),
    (lambda p, f, o: f.__setitem__(23, -1), "vertex index -1 out of range [0, 8)"),
    (lambda p, f, o: o.__setitem__(3, 10), "cube: faceOffsets[3] (face 2): 2 corners (8 to 10); a face needs at least 3"),
    (lambda p, f, o: o.__setitem__(0, 1), "cube: faceOffsets[0]: 1 (must be 0)"),
    (lambda p, f, o: {"normals": np.ones((5, 3))}, "cube: normals: 5 rows, expected 8 (one per vertex) or 24"),
    (lambda p, f, o: {"normals": np.ones((8, 3)), "normal_layout": "corner"}, "normals: 8 rows, expected 24 (one per corner)"),
    (lambda p, f, o: {"normals": np.full((24, 3), np.inf)}, "cube: normals[0][0] (corner 0): non-finite value inf"),
    (lambda p, f, o: {"precision": "half"}, "half"),
    (lambda p, f, o: {"normal_layout": "face"}, "normal layout: expected auto, vertex or corner, got 'face'"),
    (lambda p, f, o: p.__setitem__((2, 0), 4e20), "cube: positions[2][0] (vertex 2): value 4e+20 m beyond the"),
    (lambda p, f, o: {"threads": 2**30}, "threads: expected 0 (all cores) to 4096 threads, got 1073741824"),
])
def test_every_bad_input_class_raises_value_error_naming_it(spoil, message):
    p, f, o, kw = bad(spoil)
    normals = kw.pop("normals", None)
    with pytest.raises(ValueError) as e:
        sf.Cache.from_arrays(p, o, f, normals, name="cube", **kw)
    assert message in str(e.value)


def test_wrong_shapes_and_dtypes_raise_value_error():
    with pytest.raises(ValueError, match=r"positions: expected shape \(n, 3\)"):
        sf.Cache.from_arrays(CUBE_P[:, :2], CUBE_O, CUBE_F)
    with pytest.raises(ValueError, match="face_vertices: expected an integer array"):
        sf.Cache.from_arrays(CUBE_P, CUBE_O, CUBE_F.astype(float))
    with pytest.raises(ValueError, match=r"face_vertices\[2\]: 4294967296 does not fit in int32"):
        f = CUBE_F.astype(np.int64)
        f[2] = 2**32
        sf.Cache.from_arrays(CUBE_P, CUBE_O, f)
    with pytest.raises(ValueError, match="has 23 entries"):
        sf.Cache.from_arrays(CUBE_P, CUBE_O, CUBE_F[:-1])


def test_arguments_of_the_wrong_kind_are_refused_naming_them(spot, tmp_path):
    """Every entry point refuses non-numeric arrays (NumPy would cast strings, None and dates to
    numbers or NaN), a preset that is not a str, a thread count beyond 4096 and a sweep of more
    samples than the command line takes, naming the argument; an empty batch is a batch."""
    cache = sf.Cache.from_file(spot)
    refused = 0
    for xi in (np.array(["0.5"]), [None], np.array(["2020-01-01"], dtype="datetime64[D]")):
        with pytest.raises(ValueError, match="xi: expected a numeric array"):
            cache.evaluate([0], xi, [0])
        refused += 1
    for hips in (np.array([["0.1", "0.1", "0.1"]]), [[None, 0, 0]]):
        with pytest.raises(ValueError, match="hips: expected a numeric array"):
            sf.trace(cache, hips)
        refused += 1
    for call in (lambda: sf.trace(cache, np.zeros((1, 3)), preset=5), lambda: sf.Haptic(cache, preset=1)):
        with pytest.raises(TypeError, match="preset: expected a str"):
            call()
        refused += 1
    for kw in ({"threads": -1}, {"threads": 5000}, {"samples": 2**62}):
        with pytest.raises(ValueError, match=list(kw)[0]):
            sf.sweep(cache, **kw)
        refused += 1
    with pytest.raises(TypeError):
        sf.sweep(cache, samples=10, output=5)
    assert refused == 10
    assert len(cache.evaluate([], [], [])) == 0


def test_sweep_paths_bytes_and_failures(spot, tmp_path):
    """A bytes output path is that path; a failed sweep leaves no temporary directory; a mesh
    whose file name is not UTF-8 keeps it (as os.fsdecode) and sweeps; errors keep such names."""
    import glob
    import os
    cache = sf.Cache.from_file(spot)
    out = os.fsencode(tmp_path / "bytes_out")
    r = sf.sweep(cache, samples=20, output=out)
    assert r["directory"] == str(tmp_path / "bytes_out") and (tmp_path / "bytes_out" / "sweep.json").is_file()
    (tmp_path / "a_file").write_text("x")
    with pytest.raises(ValueError, match="a_file"):
        sf.sweep(cache, samples=20, output=str(tmp_path / "a_file"))
    odd = os.fsencode(tmp_path) + b"/tri\xff.obj"
    with open(odd, "wb") as f:
        f.write(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n")
    tet = sf.Cache.from_file(odd)
    assert os.fsencode(tet.source) == odd
    before = set(glob.glob(os.path.join(os.path.realpath("/tmp"), "smoothforce_sweep_*")))
    assert sf.sweep(tet, samples=20)["summary"] is not None
    with pytest.raises(ValueError, match="depths"):
        sf.sweep(tet, samples=20, depths="-1")
    with pytest.raises(ValueError, match="'patch' is listed twice"):  # one result set per method
        sf.sweep(tet, samples=20, methods=["patch", "patch"])
    assert set(glob.glob(os.path.join(os.path.realpath("/tmp"), "smoothforce_sweep_*"))) == before
    with pytest.raises(ValueError, match=r"missing\\xff\.obj: cannot open"):
        sf.Cache.from_file(os.fsencode(tmp_path) + b"/missing\xff.obj")


def test_file_errors_name_the_file_and_line(paths, tmp_path):
    bad_obj = tmp_path / "bad.obj"
    bad_obj.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")
    with pytest.raises(ValueError, match="bad.obj:4"):
        sf.Cache.from_file(str(bad_obj))
    with pytest.raises(ValueError, match="no_such.obj"):
        sf.Cache.from_file(str(tmp_path / "no_such.obj"))


def test_trace_matches_cli_trace_on_every_hip(spot, paths, tmp_path):
    cache = sf.Cache.from_file(spot)
    faces, xi, eta = domain_points(cache)
    pts = cache.evaluate(faces, xi, eta)
    hips = pts["position"] - 0.01 * pts["normal"]  # every face, 1 cm inside
    hips = np.vstack([hips, pts["position"][:50] + 0.05 * pts["normal"][:50]])  # and some outside
    for method in ("patch", "direct", "shading"):
        t = sf.trace(cache, hips, method=method)
        assert t.shape == (len(hips),)
        with open(tmp_path / "hips.csv", "w") as f:
            f.write("x,y,z\n")
            for h in hips:
                f.write(f"{float(h[0])!r},{float(h[1])!r},{float(h[2])!r}\n")
        cache.save(tmp_path / "spot.sfcache")
        run(paths["cli"], "trace", "--cache", tmp_path / "spot.sfcache", "--method", method, "--hips",
            tmp_path / "hips.csv", "-o", tmp_path / "t.csv")
        rows = read_csv(tmp_path / "t.csv")
        assert len(rows) == len(hips)
        ref_force = np.array([[float(r["fx"]), float(r["fy"]), float(r["fz"])] for r in rows])
        ref_scp = np.array([[float(r["scp_x"]), float(r["scp_y"]), float(r["scp_z"])] for r in rows])
        np.testing.assert_array_equal(t["force"], ref_force)
        np.testing.assert_array_equal(t["scp"], ref_scp)
        assert list(t["contact"].astype(int)) == [int(r["contact"]) for r in rows]
        assert list(t["face"]) == [int(r["face"]) for r in rows]
        assert list(t["status"]) == [int(r["status"]) for r in rows]
        assert list(t["iterations"]) == [int(r["iterations"]) for r in rows]
        if method == "patch":  # the god-object methods may lose a jump between faces (same in the CLI)
            assert t["contact"][:-50].sum() > 0.9 * (len(hips) - 50)
            assert (~t["contact"][-50:]).sum() >= 40  # 5 cm outside (a few land inside another part)


def test_surface_query_agrees_with_a_contact_start_at_every_point(spot):
    """Surface.query on the spot cage: every face centre pressed 1 cm in and 5 cm out; the sign of the
    distance is the patch method's contact verdict at a contact start, and inside, the distance is
    the depth of that contact (its SCP is the nearest point) except where a nearer sheet sees the HIP
    from outside (the cage's overlapping sheets: counted, at most 3%). The contact starts come from
    one trace that visits a point ten diagonals away before each HIP (out of contact there, so each
    HIP starts a contact afresh), checked against a fresh trace of one HIP, field for field, on every
    20th. Answers do not depend on the thread count; bad points give NaN; a lazy cache is refused."""
    cache = sf.Cache.from_file(spot)
    pts = cache.evaluate(np.arange(cache.num_faces, dtype=np.int32), np.zeros(cache.num_faces),
                         np.zeros(cache.num_faces))
    hips = np.vstack([pts["position"] - 0.01 * pts["normal"], pts["position"] + 0.05 * pts["normal"]])
    surface = sf.Surface(cache)
    q = surface.query(hips)
    assert q.shape == (len(hips),)
    assert q.dtype.names == ("signed_distance", "point", "normal", "face", "xi", "eta", "status")
    one = surface.query(hips, threads=1)
    for name in q.dtype.names:
        np.testing.assert_array_equal(one[name], q[name])
    lo, hi = hips.min(axis=0), hips.max(axis=0)
    visits = np.empty((2 * len(hips), 3))
    visits[0::2] = hi + 10 * np.linalg.norm(hi - lo)
    visits[1::2] = hips
    trace = sf.trace(cache, visits)
    assert not trace["contact"][0::2].any()
    starts = trace[1::2]
    fresh = 0
    for i in range(0, len(hips), 20):
        t = sf.trace(cache, hips[i][None, :])
        for name in t.dtype.names:
            np.testing.assert_array_equal(t[name][0], starts[name][i], err_msg=f"{name} of HIP {i}")
        fresh += 1
    assert fresh == 18
    other_depth = 0
    for i, h in enumerate(hips):
        t = starts[i]
        assert bool(t["contact"]) == bool(q["signed_distance"][i] < 0), i
        assert bool(q["status"][i] & sf.SF_TRACK_INSIDE) == bool(q["signed_distance"][i] < 0)
        np.testing.assert_allclose(np.linalg.norm(q["point"][i] - h), abs(q["signed_distance"][i]), rtol=1e-12)
        if t["contact"]:
            other_depth += abs(np.linalg.norm(t["scp"] - h) + q["signed_distance"][i]) > 1e-9
    assert (q["signed_distance"][: cache.num_faces] < 0).sum() > 0.9 * cache.num_faces
    assert (q["signed_distance"][cache.num_faces:] > 0).sum() > 0.9 * cache.num_faces
    assert other_depth <= 0.03 * len(hips)
    bad = surface.query(np.array([[np.nan, 0, 0], [1e300, 0, 0]]))
    assert np.isnan(bad["signed_distance"]).all() and (bad["face"] == -1).all()
    assert (bad["status"] == sf.SF_TRACK_BAD_HIP).all()
    with pytest.raises(ValueError, match="points"):
        surface.query(np.zeros((4, 2)))
    with pytest.raises(ValueError, match="prebuilt"):
        sf.Surface(sf.Cache.from_file(spot, lazy=True))


def test_status_bits_are_module_constants():
    """Every status bit by its C++ name: one bit each, distinct; SF_ST_* fill 0x1..0x800, SF_TRACK_*
    0x10000..0x10000000, SF_PROBE_* the top three bits (the values status.h and smoothforce.h give)."""
    bits = {k: getattr(sf, k) for k in dir(sf) if k.startswith(("SF_ST_", "SF_TRACK_", "SF_PROBE_"))}
    assert len(bits) == 28
    union = 0
    for name, v in bits.items():
        assert isinstance(v, int) and v > 0 and v & (v - 1) == 0, name
        assert union & v == 0, name
        union |= v

    def group(prefix):
        return sum(v for k, v in bits.items() if k.startswith(prefix))
    assert group("SF_ST_") == 0xFFF
    assert group("SF_TRACK_") == 0x1FFF0000
    assert group("SF_PROBE_") == 0xE0000000
    assert (sf.SF_ST_OUTSIDE, sf.SF_ST_MODEL_POINT, sf.SF_TRACK_BAD_HIP) == (0x40, 0x400, 0x2000000)


def test_final_step_model_marks_model_points_and_stays_near_evaluated(spot):
    """final_step="model" (as --final-step model): most steps of a slide in contact end on a model
    point (status bit SF_ST_MODEL_POINT), none with the default, the same contacts, and the
    SCPs within 1e-8 m (the spot cage's diagonal is about 2.7 m; measured in C++: 1.1e-10 of it)."""
    cache = sf.Cache.from_file(spot)
    pts = cache.evaluate(np.zeros(200, dtype=np.int32), np.linspace(-0.5, 0.5, 200), np.zeros(200))
    hips = pts["position"] - 0.005 * pts["normal"]
    e = sf.trace(cache, hips)
    m = sf.trace(cache, hips, final_step="model")
    model_bit = sf.SF_ST_MODEL_POINT
    assert model_bit == 0x400  # the value of status.h and the C API
    assert (e["status"] & model_bit).sum() == 0
    assert list(m["contact"]) == list(e["contact"])
    assert e["contact"].sum() == len(hips)
    assert ((m["status"] & model_bit) != 0).sum() >= len(hips) // 2
    assert np.abs(m["scp"] - e["scp"]).max() <= 1e-8
    h = sf.Haptic(cache, final_step="model", ramp_time=0.0)
    assert h.step(hips[0], 0.0)["contact"]
    assert h.step(hips[1], 1e-3)["status"] & model_bit
    with pytest.raises(ValueError, match=r"final_step: expected evaluated\|model, got 'turbo'"):
        sf.trace(cache, hips, final_step="turbo")


def test_haptic_step_applies_safety_and_matches_trace(spot):
    cache = sf.Cache.from_file(spot)
    pts = cache.evaluate(np.zeros(200, dtype=np.int32), np.linspace(-0.5, 0.5, 200), np.zeros(200))
    hips = pts["position"] - 0.005 * pts["normal"]
    # the servo step's renderer holds the bounds index (surface_index auto), a trace the tessellation:
    # the same index gives the same bits, the other the same contacts to rounding
    t = sf.trace(cache, hips, surface_index="bounds")
    t_tessellation = sf.trace(cache, hips)
    np.testing.assert_array_equal(t["contact"], t_tessellation["contact"])
    # within the refinement's position tolerance: 1e-10 of the 2.75 m diagonal at 500 N/m, 1.4e-7 N
    np.testing.assert_allclose(t["force"], t_tessellation["force"], rtol=0, atol=1.4e-7)
    h = sf.Haptic(cache, max_force=2.0, max_force_step=0.5, ramp_time=0.0)
    prev = np.zeros(3)
    for i, hip in enumerate(hips):
        r = h.step(hip, i * 1e-3)
        f = np.array(r["force"])
        np.testing.assert_array_equal(r["rendered"], t["force"][i])  # the renderer's force, before safety
        assert np.linalg.norm(f) <= 2.0 + 1e-12
        assert np.linalg.norm(f - prev) <= 0.5 + 1e-12
        prev = f
    r = h.step([np.nan, 0, 0], 0.3)
    assert r["faulted"] and not any(r["force"])
    h.reset()
    assert not h.step(hips[0], 0.4)["faulted"]
    with pytest.raises(ValueError, match="stiffness"):
        sf.Haptic(cache, stiffness=-1)
    with pytest.raises(ValueError, match=r"max_force: expected a finite force > 0 N, got .0."):
        sf.Haptic(cache, max_force=0)
    with pytest.raises(ValueError, match="pose"):
        h.set_pose([0, 0, 0], [0, 0, 0, 0], 1.0)


def test_lazy_cache_builds_only_touched_patches(spot):
    lazy = sf.Cache.from_file(spot, lazy=True)
    full = sf.Cache.from_file(spot)
    assert lazy.lazy and not full.lazy
    pts = full.evaluate(np.zeros(20, dtype=np.int32), np.linspace(-0.3, 0.3, 20), np.zeros(20))
    hips = pts["position"] - 0.005 * pts["normal"]
    a, b = sf.trace(lazy, hips), sf.trace(full, hips)
    # The same SCPs up to the refinement tolerance (a lazy cache starts from the polygon query).
    assert a["contact"].all() and b["contact"].all() and (a["face"] == b["face"]).all()
    np.testing.assert_allclose(a["force"], b["force"], rtol=0, atol=1e-6)
    with pytest.raises(ValueError, match="lazy"):
        lazy.evaluate([0], [0.0], [0.0])


def test_sweep_and_read_sweep_agree_with_the_cli(spot, paths, tmp_path):
    cache = sf.Cache.from_file(spot)
    cache.save(tmp_path / "spot.sfcache")
    out = tmp_path / "py"
    r = sf.sweep(cache, depths="1%,2%", methods=["patch", "direct"], samples=300, seed=3, output=str(out))
    assert r["complete"] and r["hips"].shape == (600, 3) and r["total"] == 600
    assert set(r["results"]) == {"patch", "direct"}
    for m in ("patch", "direct"):
        res = r["results"][m]
        assert res.shape == (600,) and res["done"].all() and res.dtype.itemsize == 40
    assert r["summary"]["complete"] and "patch" in r["table"]
    cli = tmp_path / "cli"
    run(paths["cli"], "sweep", "--cache", tmp_path / "spot.sfcache", "--depth", "1%,2%", "--methods", "patch,direct",
        "--samples", 300, "--seed", 3, "-o", cli)
    c = sf.read_sweep(str(cli))
    assert c["complete"] and c["table"] is None
    np.testing.assert_array_equal(c["hips"], r["hips"])
    for m in ("patch", "direct"):
        assert c["results"][m].tobytes() == r["results"][m].tobytes()
    assert json.loads((cli / "summary.json").read_text())["results"] == r["summary"]["results"]
    assert len(c["trajectories"]) == len(r["trajectories"]) > 0
    again = sf.read_sweep(str(out))
    assert again["results"]["patch"].tobytes() == r["results"]["patch"].tobytes()
    with pytest.raises(ValueError, match="sweep.json"):
        sf.read_sweep(str(tmp_path / "nothing"))


def two_cubes():
    """[0, 2]^3 and (1, 1, 1) + [0, 2]^3: faces -x, +x, -y, +y, -z, +z of each, outward."""
    pos, fv = [], []
    for c in range(2):
        pos += [[(i & 1) * 2 + c, (i & 2) + c, (i & 4) / 2 + c] for i in range(8)]
        for q in ([0, 4, 6, 2], [1, 3, 7, 5], [0, 1, 5, 4], [2, 6, 7, 3], [0, 2, 3, 1], [4, 5, 7, 6]):
            fv += [v + 8 * c for v in q]
    return np.array(pos, dtype=float), np.arange(0, 49, 4), np.array(fv)


def test_polygons_report_bow_ties_and_intersections_as_the_cli_does(spot, paths, tmp_path):
    cache = sf.Cache.from_file(spot)
    p = cache.polygons()
    assert p["self_crossing_faces"].tolist() == [60, 150]
    assert p["intersecting_pairs"].tolist() == [[70, 71], [70, 72], [160, 161], [160, 162]]
    assert 0 < p["intersecting_area"] < 0.1 * p["area"]
    assert any(line == "self-crossing polygons: 2 (first: 60, 150)" for line in cache.report["mesh"])
    cache.save(tmp_path / "s.sfcache")
    out = subprocess.run([paths["cli"], "cache", "info", str(tmp_path / "s.sfcache"), "--json"], check=True,
                         capture_output=True, text=True).stdout
    cli = json.loads(out)["polygons"]
    assert cli["self_crossing_faces"] == [60, 150] and cli["area_m2"] == p["area"]
    assert cli["intersecting_pairs"] == p["intersecting_pairs"].tolist()
    assert sf.Cache.from_file(str(tmp_path / "s.sfcache")).polygons()["self_crossing_faces"].tolist() == [60, 150]

    cubes = sf.Cache.from_arrays(*two_cubes(), lazy=True)
    q = cubes.polygons()
    assert q["intersecting_pairs"].tolist() == [[1, 8], [1, 10], [3, 6], [3, 10], [5, 6], [5, 8]]
    assert q["intersecting_faces"].tolist() == [1, 3, 5, 6, 8, 10]
    np.testing.assert_array_equal(q["intersecting_pair_areas"], np.full((6, 2), 4.0))
    assert q["intersecting_area"] == 24.0 and q["area"] == 48.0 and q["self_crossing_faces"].size == 0
    assert any(line.startswith("intersecting polygons: 6 pairs") for line in cubes.report["mesh"])


def test_cage_moves_vertices_to_the_limit_and_keeps_it_in_the_cache(spot, paths, tmp_path):
    plain = sf.Cache.from_file(spot)
    cage = sf.Cache.from_file(spot, cage="catmull-clark")
    assert plain.cage == "none" and cage.cage == "catmull-clark"
    assert cage.num_faces == plain.num_faces == 180
    moved = np.linalg.norm(np.asarray(cage.positions) - np.asarray(plain.positions), axis=1)
    assert (moved > 0).sum() == plain.num_vertices  # closed cage: every vertex moves
    # every patch corner is its vertex's limit position (the cache holds the moved mesh)
    offsets, verts = np.asarray(cage.face_offsets), np.asarray(cage.face_vertices)
    faces = np.repeat(np.arange(cage.num_faces), np.diff(offsets))
    k = np.arange(len(verts)) - offsets[faces]
    n = np.diff(offsets)[faces]
    pts = cage.evaluate(faces, np.cos(2 * np.pi * k / n), np.sin(2 * np.pi * k / n))
    np.testing.assert_allclose(pts["position"], np.asarray(cage.positions)[verts], rtol=0, atol=1e-12)
    # the arrays path gives the same cache; the file keeps the cage
    arrays = sf.Cache.from_arrays(plain.positions, plain.face_offsets, plain.face_vertices, cage="catmull-clark")
    np.testing.assert_array_equal(arrays.positions, cage.positions)
    cage.save(tmp_path / "cage.sfcache")
    assert sf.Cache.from_file(str(tmp_path / "cage.sfcache")).cage == "catmull-clark"
    with pytest.raises(ValueError, match=r"^cage: expected none\|catmull-clark"):
        sf.Cache.from_file(spot, cage="loop")
    with pytest.raises(ValueError, match="--normals area cannot be combined"):
        sf.Cache.from_file(spot, cage="catmull-clark", normals="area")


def test_fold_repair_cuts_planar_non_convex_polygons_by_default_and_keeps_their_sources(paths, tmp_path):
    path = paths["shared"] / "polygon_laplacian/L-plane.obj"
    plain = sf.Cache.from_file(path, fold_repair="off")
    cut = sf.Cache.from_file(path)  # the default: on
    assert plain.face_source is None
    src = np.asarray(cut.face_source)
    assert plain.num_faces == 16 and cut.num_faces == 40
    assert np.array_equal(np.unique(src), np.arange(16))  # every face as read cut, in order
    assert np.all(np.diff(src) >= 0)
    fold = sf.SF_ST_FOLD
    assert (np.asarray(plain.face_status) & fold).astype(bool).sum() == 16
    assert (np.asarray(cut.face_status) & fold).astype(bool).sum() == 0
    synonym = sf.Cache.from_file(path, fold_repair="split")
    np.testing.assert_array_equal(synonym.face_vertices, cut.face_vertices)
    arrays = sf.Cache.from_arrays(plain.positions, plain.face_offsets, plain.face_vertices)
    np.testing.assert_array_equal(arrays.face_vertices, cut.face_vertices)
    cut.save(tmp_path / "cut.sfcache")
    np.testing.assert_array_equal(sf.Cache.from_file(str(tmp_path / "cut.sfcache")).face_source, src)
    with pytest.raises(ValueError, match=r"^fold_repair: expected off\|on\|search, got 'sometimes'"):
        sf.Cache.from_file(path, fold_repair="sometimes")


def tilted_cube(path, tilt_deg):
    """A 2 m cube with radial file normals, vertex 7's turned by tilt_deg about (1, -1, 0)."""
    v = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], float)
    n = v / np.linalg.norm(v, axis=1)[:, None]
    a, k = np.radians(tilt_deg), np.array([1.0, -1.0, 0.0]) / np.sqrt(2)
    n[7] = n[7] * np.cos(a) + np.cross(k, n[7]) * np.sin(a) + k * (k @ n[7]) * (1 - np.cos(a))
    faces = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]]
    with open(path, "w") as f:
        f.writelines("v %g %g %g\n" % tuple(p) for p in v)
        f.writelines("vn %.17g %.17g %.17g\n" % tuple(q) for q in n)
        f.writelines("f " + " ".join("%d//%d" % (i + 1, i + 1) for i in face) + "\n" for face in faces)
    return path


def test_fold_repair_search_turns_normals_as_the_command_line_does_and_refuses_lazy(paths, tmp_path):
    cube = str(tilted_cube(tmp_path / "cube.obj", 120))
    on = sf.Cache.from_file(cube, normals="file")
    searched = sf.Cache.from_file(cube, normals="file", fold_repair="search")
    turned = np.any(np.asarray(on.corner_normals) != np.asarray(searched.corner_normals), axis=1)
    assert turned.any() and not turned.all()
    run(paths["cli"], "cache", "build", cube, "--normals", "file", "--fold-repair", "search", "-o", tmp_path / "c.sfcache")
    cli = sf.Cache.from_file(str(tmp_path / "c.sfcache"))
    np.testing.assert_array_equal(cli.corner_normals, searched.corner_normals)
    # the record of what turned: the normals as computed, kept by the cache file too
    assert on.computed_normals is None
    np.testing.assert_array_equal(searched.computed_normals, on.corner_normals)
    np.testing.assert_array_equal(cli.computed_normals, on.corner_normals)
    with pytest.raises(ValueError, match="fold_repair search needs every patch"):
        sf.Cache.from_file(cube, normals="file", fold_repair="search", lazy=True)


def test_fold_repair_on_reports_the_edge_tangents_it_turned(tmp_path):
    """A cube whose file normal at vertex 7 is turned 120 degrees: its vertex fan tangles, and on turns
    edge curves there and nowhere else. Every edge end's turn is the angle between the directions in
    which the patch's boundary leaves the corner, evaluated on the caches built on and off."""
    cube = str(tilted_cube(tmp_path / "cube.obj", 120))
    on = sf.Cache.from_file(cube, normals="file")
    off = sf.Cache.from_file(cube, normals="file", fold_repair="off")
    assert off.tangent_turns is None
    turns = on.tangent_turns
    assert turns.shape == (on.num_corners, 2) and turns.dtype == np.float64
    offsets, verts = np.asarray(on.face_offsets), np.asarray(on.face_vertices)

    def leaving(cache, f, n, a, b):  # unit direction of the boundary from domain corner a towards b
        ca, cb = (np.array([np.cos(2 * np.pi * j / n), np.sin(2 * np.pi * j / n)]) for j in (a, b))
        uv = ca + np.array([[1e-7], [2e-7]]) * (cb - ca)
        p = cache.evaluate(np.array([f, f]), uv[:, 0], uv[:, 1])["position"]
        return (p[1] - p[0]) / np.linalg.norm(p[1] - p[0])

    measured, at7 = np.zeros_like(turns), np.zeros(turns.shape, bool)
    for f in range(on.num_faces):
        n = offsets[f + 1] - offsets[f]
        for k in range(n):
            for end, (a, b) in enumerate(((k, (k + 1) % n), ((k + 1) % n, k))):
                x, y = leaving(on, f, n, a, b), leaving(off, f, n, a, b)
                measured[offsets[f] + k, end] = np.degrees(np.arctan2(np.linalg.norm(np.cross(x, y)), x @ y))
                at7[offsets[f] + k, end] = verts[offsets[f] + a] == 7
    np.testing.assert_allclose(turns, measured, atol=1e-3)
    assert (turns[~at7] == 0).all()
    assert (turns[at7] > 0).sum() >= 2


def test_distance_to_measures_the_repair_against_the_part_and_the_other_construction(paths):
    """An extruded L, creased: the default surface is the part (its polygons) to rounding, the design
    page's folded caps stand off it; the same numbers as the command line's cache distance."""
    import subprocess, json, os, tempfile
    positions = np.array([[0, 0, 0], [2, 0, 0], [2, 1, 0], [1, 1, 0], [1, 3, 0], [0, 3, 0]] * 2, dtype=float)
    positions[6:, 2] = 1
    faces = [[5, 4, 3, 2, 1, 0], [6, 7, 8, 9, 10, 11]] + [[i, (i + 1) % 6, 6 + (i + 1) % 6, 6 + i] for i in range(6)]
    offsets = np.cumsum([0] + [len(f) for f in faces])
    verts = np.concatenate(faces)
    on = sf.Cache.from_arrays(positions, offsets, verts, crease_angle=30)
    off = sf.Cache.from_arrays(positions, offsets, verts, crease_angle=30, fold_repair="off")
    part = sf.Cache.from_arrays(positions, offsets, verts, lazy=True)
    exact = on.distance_to(part, to="polygons", level=6)
    assert set(exact) == {"diagonal_m", "levels_used", "cache_to_other", "other_to_cache", "hausdorff"}
    assert exact["levels_used"] == (6, 6)
    assert set(exact["cache_to_other"]) == {"max", "mean", "points", "worst_face", "worst_point"}
    assert abs(exact["diagonal_m"] - np.sqrt(14)) < 1e-12
    assert exact["hausdorff"] < 1e-12
    folded = off.distance_to(part, to="polygons")
    assert folded["hausdorff"] > 0.05
    moved = on.distance_to(off)
    assert moved["other_to_cache"]["max"] > 0.05 and moved["cache_to_other"]["max"] < 1e-12
    assert moved["hausdorff"] == max(moved["cache_to_other"]["max"], moved["other_to_cache"]["max"])
    with tempfile.TemporaryDirectory() as d:  # the command line measures the same
        on.save(os.path.join(d, "on.sfcache"))
        off.save(os.path.join(d, "off.sfcache"))
        out = subprocess.run([os.environ.get("SF_CLI", "smoothforce"), "cache", "distance", os.path.join(d, "on.sfcache"),
                              "--to", os.path.join(d, "off.sfcache"), "--json"], capture_output=True, text=True, check=True)
        cli = json.loads(out.stdout)
        assert cli["hausdorff"] == moved["hausdorff"]
        assert cli["cache_to_other"]["points"] == moved["cache_to_other"]["points"]
    with pytest.raises(ValueError, match=r"^to: expected patches\|polygons, got 'mesh'"):
        on.distance_to(off, to="mesh")
    with pytest.raises(ValueError, match="level 0 outside 1..64"):
        on.distance_to(off, level=0)
    with pytest.raises(ValueError, match="needs a prebuilt cache"):
        on.distance_to(part)


def test_crease_edges_as_arrays_match_the_crease_angle(paths):
    """Every edge of the cube marked sharp as arrays gives the surface of --crease-angle 30."""
    path = paths["shared"] / "lagrange/cube.obj"
    a = sf.Cache.from_file(path)
    edges = sorted({tuple(sorted((int(fv[k]), int(fv[(k + 1) % len(fv)]))))
                    for fv in np.split(np.asarray(a.face_vertices), np.asarray(a.face_offsets)[1:-1])
                    for k in range(len(fv))})
    assert len(edges) == 12
    b = sf.Cache.from_arrays(np.array(a.positions), np.array(a.face_offsets), np.array(a.face_vertices),
                             crease_edges=np.array(edges, dtype=np.int32))
    c = sf.Cache.from_file(path, crease_angle=30.0)
    f, xi, eta = domain_points(a)
    pa, pb, pc = a.evaluate(f, xi, eta), b.evaluate(f, xi, eta), c.evaluate(f, xi, eta)
    assert np.array_equal(pb["position"], pc["position"])
    assert not np.array_equal(pa["position"], pb["position"])  # uncreased, the cube is rounded
    with pytest.raises(ValueError, match="crease_sharpness: 1 values for 12 crease edges"):
        sf.Cache.from_arrays(np.array(a.positions), np.array(a.face_offsets), np.array(a.face_vertices),
                             crease_edges=np.array(edges, dtype=np.int32), crease_sharpness=[10.0])
    with pytest.raises(ValueError, match=r"^crease_angle: expected degrees in \[0, 180\)"):
        sf.Cache.from_file(path, crease_angle=-1.0)


def test_type_stubs_name_exactly_what_the_module_defines():
    """python/smoothforce.pyi (installed beside the module) parses, and names every public function,
    class, method, property and constant of the compiled module, and nothing it lacks."""
    import ast
    import pathlib
    stub = pathlib.Path(__file__).resolve().parents[1] / "smoothforce.pyi"
    tree = ast.parse(stub.read_text())
    stubbed = {}
    for node in tree.body:
        if isinstance(node, ast.ClassDef):
            stubbed[node.name] = {n.name for n in node.body if isinstance(n, ast.FunctionDef)}
        elif isinstance(node, ast.FunctionDef):
            stubbed[node.name] = None
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            stubbed[node.target.id] = None
    public = {k for k in dir(sf) if not k.startswith("_")} | {"__version__"}
    stubbed.pop("__all__", None)
    assert set(stubbed) == public
    for name, members in stubbed.items():
        if members is None:
            continue
        cls = getattr(sf, name)
        defined = {k for k in vars(cls) if not k.startswith("_") or k == "__init__"}
        defined.discard("__init__") if "__init__" not in members else None
        assert members == defined, name


@pytest.mark.parametrize("key,value,expected", [
    ("precision", "half", "float|double"),
    ("normals", "fancy", "auto|file|angle|area"),
    ("cross_tangent", "sideways", "corrected|paper|blend"),
    ("orient", "inward", "outward|keep"),
    ("cage", "loop", "none|catmull-clark"),
    ("creases", "tags,foo", "a list of tags, groups, normals (each once), or none"),
    ("crease_angle", 200.0, "degrees in [0, 180) (0: off)"),
])
def test_every_bad_patch_option_gets_the_shared_message(spot, key, value, expected):
    """The message the command line, scene files and the C API give for the same bad value
    (patch_option_text.h; tests/cli/test_option_layer.cpp and test_capi.cpp use the same table), for
    both constructors, naming the keyword argument."""
    shown = "200" if key == "crease_angle" else value
    message = f"{key}: expected {expected}, got '{shown}'"
    cache = sf.Cache.from_file(spot)
    for make in (lambda: sf.Cache.from_file(spot, **{key: value}),
                 lambda: sf.Cache.from_arrays(cache.positions, cache.face_offsets, cache.face_vertices,
                                              **({"normals_mode" if key == "normals" else key: value}))):
        with pytest.raises(ValueError) as e:
            make()
        assert str(e.value) == message


@pytest.mark.parametrize("key,value,shown,expected", [
    ("method", "magic", "magic", "patch|direct|shading"),
    ("preset", "turbo", "turbo", "fast|balanced|accurate"),
    ("stiffness", 1e13, "1e+13", "a stiffness in (0, 1e12] N/m"),
    ("stiffness", 0.0, "0", "a stiffness in (0, 1e12] N/m"),
    ("final_step", "turbo", "turbo", "evaluated|model"),
    ("surface_index", "octree", "octree", "auto|bounds|tessellation"),
    ("rate", 0.0, "0", "a rate in [1, 10000] Hz"),
    ("max_force", 0.0, "0", "a finite force > 0 N"),
    ("max_force_step", 0.0, "0", "a force step > 0 N"),
    ("ramp_time", -1.0, "-1", "a finite time >= 0 s"),
])
def test_every_bad_force_option_gets_the_shared_message(spot, key, value, shown, expected):
    """The message the command line, scene files and the C API give for the same bad value
    (force_option_text.h, loop_option_text.h; tests/cli/test_option_layer.cpp and test_capi.cpp use the
    same values), for the servo step and the trace, naming the keyword argument."""
    message = f"{key}: expected {expected}, got '{shown}'"
    cache = sf.Cache.from_file(spot)
    loop = key in ("rate", "max_force", "max_force_step", "ramp_time")  # Haptic's alone (loop_option_text.h)
    for make in (lambda: sf.Haptic(cache, **{key: value}),
                 *(() if loop else (lambda: sf.trace(cache, np.zeros((2, 3)), **{key: value}),))):
        with pytest.raises(ValueError) as e:
            make()
        assert str(e.value) == message


@pytest.mark.parametrize("key,value,expected", [
    ("samples", 0, "an integer in [1, 4294967296]"),
    ("level", 65, "an integer in 1..64"),
    ("sample_on", "mesh", "patch|reference"),
])
def test_every_bad_sweep_option_gets_the_shared_message(spot, key, value, expected):
    """The message of `smoothforce sweep` for the same bad value (sweep_option_text.h;
    tests/cli/test_option_layer.cpp), naming the keyword argument."""
    cache = sf.Cache.from_file(spot)
    with pytest.raises(ValueError) as e:
        sf.sweep(cache, depths="1%", **{key: value})
    assert str(e.value) == f"{key}: expected {expected}, got '{value}'"


def test_certify_margins_match_the_command_line_and_survive_save(paths, tmp_path):
    """Cache.certify() on pmp/L.off as read (its hexagon proven folded) and cut into convex pieces
    (both certified): the margins are None before, a read-only (F,) float32 view after, the same on a
    second call, written by save() and read back bit for bit, and `cache info --json` of the saved
    file counts the same certified, folded and undecided faces with the same smallest margin. A lazy
    cache is refused."""
    path = str(paths["shared"] / "pmp" / "L.off")
    counts = {}
    for repair in ("off", "on"):
        cache = sf.Cache.from_file(path, fold_repair=repair)
        assert cache.certificates is None
        m = cache.certify()
        assert m.dtype == np.float32 and m.shape == (cache.num_faces,) and not m.flags.writeable
        assert np.array_equal(cache.certify(), m) and np.array_equal(cache.certificates, m)
        saved = tmp_path / f"L_{repair}.sfcache"
        cache.save(str(saved))
        assert np.array_equal(sf.Cache.from_file(str(saved)).certificates, m)
        info = json.loads(subprocess.run([paths["cli"], "cache", "info", str(saved), "--json"], check=True,
                                         capture_output=True, text=True).stdout)["certificate"]
        assert info["certified"] == int((m > 0).sum())
        assert info["folded"] == int((m < 0).sum()) and info["undecided"] == int((m == 0).sum())
        assert info["folded_faces"] == [int(f) for f in np.flatnonzero(m < 0)]
        if (m > 0).any():
            assert info["min_margin"] == pytest.approx(float(m[m > 0].min()), rel=1e-6)
        counts[repair] = (int((m > 0).sum()), int((m < 0).sum()), cache.num_faces)
    assert counts == {"off": (0, 1, 1), "on": (2, 0, 2)}
    with pytest.raises(ValueError, match="lazy"):
        sf.Cache.from_file(path, lazy=True).certify()
