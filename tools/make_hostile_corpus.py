#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Regenerates tests/data/hostile/: malformed mesh and cache files that every reader must
reject with sf::InputError naming the file (tests/robustness/test_hostile_corpus.cpp), never a crash
and never another exception type. Issue 6 part 4.

Usage: tools/make_hostile_corpus.py [OUTPUT_DIR]   (default: tests/data/hostile)
       tools/make_hostile_corpus.py --seeds        (fuzz/seeds/{obj,off,ply}: valid meshes
                                                   made here plus tests/data/malformed copies)

Deterministic (fixed seeds), python3 stdlib only. Writes INDEX.tsv (file, why) beside the
files; the test checks that the folder and the index agree. Cache files here carry no valid
checksums (python has no XXH64); cache variants with valid checksums are made at run time
by the test from a freshly written cache. tests/data/malformed/ (57 files with expected
line numbers) is not duplicated here.
"""
import os
import random
import struct
import sys

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
SEEDS = len(sys.argv) > 1 and sys.argv[1] == "--seeds"
OUT = sys.argv[1] if len(sys.argv) > 1 and not SEEDS else os.path.join(ROOT, "tests", "data", "hostile")
FILES = {}  # name -> (bytes, why)


def add(name, data, why):
    assert name not in FILES, name
    FILES[name] = (data.encode("latin-1") if isinstance(data, str) else bytes(data), why)


def rnd(seed, n):
    r = random.Random(seed)
    return bytes(r.randrange(256) for _ in range(n))


# ---- valid bases (the truncations and edits below start from these) --------------------
CUBE_V = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
CUBE_F = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
TRI = "v 0 0 0\nv 1 0 0\nv 0 1 0\n"

# OBJ with the faces first (forward references): every proper prefix lacks vertices the
# faces use, so no truncation can leave a valid file.
OBJ = "".join("f %s\n" % " ".join(str(i + 1) for i in f) for f in CUBE_F) + \
      "".join("v %g %g %g\n" % v for v in CUBE_V)
OFF = "OFF\n8 6 0\n" + "".join("%g %g %g\n" % v for v in CUBE_V) + \
      "".join("4 %d %d %d %d\n" % f for f in CUBE_F)


def ply_header(fmt, nv=8, nf=6, face="property list uchar int vertex_indices", extra=""):
    return ("ply\nformat %s 1.0\n%selement vertex %d\nproperty float x\nproperty float y\n"
            "property float z\nelement face %d\n%s\nend_header\n" % (fmt, extra, nv, nf, face))


PLY_ASCII = ply_header("ascii") + "".join("%g %g %g\n" % v for v in CUBE_V) + \
            "".join("4 %d %d %d %d\n" % f for f in CUBE_F)


def ply_binary(big):
    e = ">" if big else "<"
    body = b"".join(struct.pack(e + "fff", *v) for v in CUBE_V)
    body += b"".join(struct.pack(e + "B4i", 4, *f) for f in CUBE_F)
    return ply_header("binary_big_endian" if big else "binary_little_endian").encode() + body


PLY_LE, PLY_BE = ply_binary(False), ply_binary(True)

# ---- truncations -------------------------------------------------------------------------
for name, base in (("obj", OBJ.encode()), ("off", OFF.encode()), ("ply_ascii", PLY_ASCII.encode()),
                   ("ply_le", PLY_LE), ("ply_be", PLY_BE)):
    ext = name[:3]
    n = len(base)
    # never the last two bytes: dropping a final newline (or the newline and a one-digit
    # last value of a text format) can leave a valid file
    for frac in (0.05, 0.2, 0.35, 0.5, 0.65, 0.8, 0.95):
        cut = min(int(n * frac), n - 3)
        add("trunc_%s_%03d.%s" % (name, int(frac * 100), ext), base[:cut], "%s truncated to %d of %d bytes" % (name, cut, n))

# ---- OBJ ---------------------------------------------------------------------------------
obj = [
    ("obj_index_int32_overflow.obj", TRI + "f 2147483648 1 2\n", "index just above INT32_MAX"),
    ("obj_index_4e9.obj", TRI + "f 4000000000 1 2\n", "index 4e9"),
    ("obj_index_int64_overflow.obj", TRI + "f 99999999999999999999 1 2\n", "index overflows int64"),
    ("obj_index_relative_huge.obj", TRI + "f -2147483649 1 2\n", "relative index below -INT32_MAX"),
    ("obj_index_relative_int64_min.obj", TRI + "f -9223372036854775808 1 2\n", "relative index INT64_MIN (negation overflows)"),
    ("obj_index_minus_zero.obj", TRI + "f -0 1 2\n", "index -0"),
    ("obj_index_plus_plus.obj", TRI + "f ++1 2 3\n", "index ++1"),
    ("obj_index_float.obj", TRI + "f 1.0 2 3\n", "index 1.0"),
    ("obj_relative_before_vertices.obj", "f -1 -2 -3\n" + TRI, "relative indices before any vertex"),
    ("obj_texture_out_of_range.obj", TRI + "vt 0 0\nf 1/5 2/1 3/1\n", "texture index 5 of 1"),
    ("obj_empty_vertex_index.obj", TRI + "vt 0 0\nf /1 2/1 3/1\n", "corner without vertex index"),
    ("obj_slashes_repeated.obj", TRI + "f 1/////1 2 3\n", "corner with five slashes"),
    ("obj_nan.obj", "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "nan coordinate"),
    ("obj_nan_payload.obj", "v 0 nan(0x7ff) 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "nan(...) coordinate"),
    ("obj_minus_nan.obj", "v 0 0 -nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "-nan coordinate"),
    ("obj_minus_infinity.obj", "v -infinity 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "-infinity coordinate"),
    ("obj_overflow_negative.obj", "v -1e400 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "-1e400 overflows"),
    ("obj_hex_float.obj", "v 0x1p3 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "hexadecimal float"),
    ("obj_minus_only.obj", "v - 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "a lone minus sign"),
    ("obj_normal_nan.obj", TRI + "vn 0 nan 1\nf 1//1 2//1 3//1\n", "nan normal"),
    ("obj_normal_inf.obj", TRI + "vn inf 0 1\nvn 0 0 1\nvn 0 0 1\nf 1 2 3\n", "inf normal"),
    ("obj_non_utf8_number.obj", "v 1\xff 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "byte 0xff inside a number"),
    ("obj_non_utf8_index.obj", TRI + "f 1 2 \xc3\x283\n", "invalid UTF-8 sequence in an index"),
    ("obj_latin1_only.obj", "".join(chr(c) for c in range(0x80, 0x100)) * 8, "latin-1 bytes only: no faces"),
    ("obj_utf16le.obj", b"\xff\xfe" + (TRI + "f 1 2 3\n").encode("utf-16-le"), "UTF-16 LE text with a byte-order mark: refused as UTF-16"),
    ("obj_double_bom.obj", b"\xef\xbb\xbf\xef\xbb\xbf" + (TRI + "f 1 2 3\n").encode(), "two byte-order marks: first vertex lost, index 3 out of range"),
    ("obj_bom_only.obj", b"\xef\xbb\xbf", "byte-order mark only: empty"),
    ("obj_whitespace_only.obj", "\r\r \t\n\n\x0b\x0c\n", "whitespace only: empty"),
    ("obj_comments_only.obj", "# one\n# two\n#\n", "comments only: no faces"),
    ("obj_old_mac_newlines.obj", TRI.replace("\n", "\r") + "f 1 2 4\r", "CR-only line ends (read as line ends): index 4 out of range"),
    ("obj_nul_after_number.obj", "v 0 0 0\x00\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "NUL after a coordinate"),
    ("obj_nul_in_face.obj", TRI + "f 1 2\x003\n", "NUL inside a face"),
    ("obj_all_nul.obj", b"\x00" * 4096, "4096 NUL bytes"),
    ("obj_binary_garbage.obj", rnd(1, 4096), "random bytes"),
    ("obj_garbage_after_vertices.obj", TRI.encode() + rnd(2, 2048), "vertices, then random bytes"),
    ("obj_repeated_keyword.obj", "v" + " v" * 5000 + "\n", "v v v ... : bad number"),
    ("obj_many_vertex_values.obj", "v" + " 0" * 50000 + "\n" + "f 1 1 1\n", "vertex with 50000 values"),
    ("obj_long_number.obj", "v " + "1" * 100000 + " 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "100000-digit coordinate overflows"),
    ("obj_long_comment_no_faces.obj", "#" + "x" * 100000 + "\n" + TRI, "100 kB comment, no faces"),
    ("obj_long_face_bad_last.obj", TRI + "f" + " 1 2 3" * 25000 + " 4\n", "75001-corner face whose last index is out of range"),
    ("obj_two_corner_face_many.obj", TRI + "f 1 2 3\n" * 1000 + "f 1 2\n", "1000 faces then a 2-corner face"),
]
for name, data, why in obj:
    add(name, data, why)

# ---- OFF ---------------------------------------------------------------------------------
V3 = "0 0 0\n1 0 0\n0 1 0\n"
off = [
    ("off_4e9_vertices.off", "OFF\n4000000000 1 0\n" + V3 + "3 0 1 2\n", "4e9 vertices in a tiny file"),
    ("off_int32max_vertices.off", "OFF\n2147483647 1 0\n" + V3 + "3 0 1 2\n", "INT32_MAX vertices in a tiny file"),
    ("off_int32max_faces.off", "OFF\n3 2147483647 0\n" + V3 + "3 0 1 2\n", "INT32_MAX faces in a tiny file"),
    ("off_both_counts_huge.off", "OFF\n2147483647 2147483647 2147483647\n", "all counts INT32_MAX"),
    ("off_count_int64_overflow.off", "OFF\n99999999999999999999 1 0\n" + V3 + "3 0 1 2\n", "count overflows int64"),
    ("off_count_float.off", "OFF\n3.0 1 0\n" + V3 + "3 0 1 2\n", "count 3.0"),
    ("off_count_hex.off", "OFF\n0x3 1 0\n" + V3 + "3 0 1 2\n", "count 0x3"),
    ("off_zero_vertices.off", "OFF\n0 1 0\n3 0 1 2\n", "a face but no vertices"),
    ("off_edge_count_garbage.off", "OFF\n3 1 x\n" + V3 + "3 0 1 2\n", "edge count x"),
    ("off_extra_count.off", "OFF 3 1 0 5\n" + V3 + "3 0 1 2\n", "four counts"),
    ("off_corner_count_huge.off", "OFF\n3 1 0\n" + V3 + "2147483647 0 1 2\n", "face claims INT32_MAX corners"),
    ("off_corner_count_4e9.off", "OFF\n3 1 0\n" + V3 + "4000000000 0 1 2\n", "face claims 4e9 corners"),
    ("off_corner_count_negative.off", "OFF\n3 1 0\n" + V3 + "-3 0 1 2\n", "face with -3 corners"),
    ("off_index_4e9.off", "OFF\n3 1 0\n" + V3 + "3 0 1 4000000000\n", "vertex index 4e9"),
    ("off_index_float.off", "OFF\n3 1 0\n" + V3 + "3 0 1 2.0\n", "vertex index 2.0"),
    ("off_inf.off", "OFF\n3 1 0\n0 0 0\ninf 0 0\n0 1 0\n3 0 1 2\n", "inf coordinate"),
    ("off_noff_nan_normal.off", "NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 nan 0 1\n0 1 0 0 0 1\n3 0 1 2\n", "nan normal"),
    ("off_4off.off", "4OFF\n3 1 0\n0 0 0 0\n1 0 0 0\n0 1 0 0\n3 0 1 2\n", "4D OFF"),
    ("off_noff_variant.off", "nOFF\n3\n3 1 0\n" + V3 + "3 0 1 2\n", "nOFF (any dimension)"),
    ("off_ccoff.off", "CCOFF\n3 1 0\n" + V3 + "3 0 1 2\n", "CCOFF is not a keyword"),
    ("off_keyword_repeated.off", "OFF" + " OFF" * 5000 + "\n", "OFF OFF OFF ...: bad count"),
    ("off_header_non_utf8.off", "OFF\xff\n3 1 0\n" + V3 + "3 0 1 2\n", "byte 0xff in the keyword"),
    ("off_header_nul.off", "OFF\x00\n3 1 0\n" + V3 + "3 0 1 2\n", "NUL in the keyword"),
    ("off_nul_in_vertex.off", "OFF\n3 1 0\n0 0\x00 0\n1 0 0\n0 1 0\n3 0 1 2\n", "NUL inside a vertex line"),
    ("off_garbage_after_header.off", b"OFF\n3 1 0\n" + rnd(3, 2048), "header, then random bytes"),
    ("off_binary_garbage.off", rnd(4, 4096), "random bytes"),
    ("off_comments_only.off", "# OFF\n# 3 1 0\n", "comments only: empty"),
    ("off_long_vertex_line.off", "OFF\n3 1 0\n0 0 0" + " 0.5" * 30000 + " x\n1 0 0\n0 1 0\n3 0 1 2\n", "vertex line with 30000 values, then x"),
    ("off_long_face_line.off", "OFF\n3 1 0\n" + V3 + "60001" + " 0 1 2" * 20000 + "\n", "60001-corner face with 60000 indices"),
    ("off_utf16le.off", b"\xff\xfe" + ("OFF\n3 1 0\n" + V3 + "3 0 1 2\n").encode("utf-16-le"), "UTF-16 LE text with a byte-order mark: refused as UTF-16"),
]
for name, data, why in off:
    add(name, data, why)

# ---- PLY ---------------------------------------------------------------------------------
A3 = "0 0 0\n1 0 0\n0 1 0\n"
ply = [
    ("ply_4e9_vertices.ply", ply_header("ascii", 4000000000, 1) + A3 + "3 0 1 2\n", "4e9 vertices: count out of range"),
    ("ply_int32max_vertices_binary.ply", ply_header("binary_little_endian", 2147483647, 1).encode() + b"\0" * 40,
     "INT32_MAX binary vertices in a tiny file"),
    ("ply_int32max_faces_ascii.ply", ply_header("ascii", 3, 2147483647) + A3 + "3 0 1 2\n", "INT32_MAX ascii faces"),
    ("ply_list_count_uint_max.ply", ply_header("binary_little_endian", 3, 1, "property list uint int vertex_indices").encode()
     + struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0) + struct.pack("<I3i", 0xFFFFFFFF, 0, 1, 2), "list count 2^32-1"),
    ("ply_list_count_negative.ply", ply_header("ascii", 3, 1, "property list char int vertex_indices") + A3 + "-1 0 1 2\n",
     "list count -1"),
    ("ply_list_count_negative_binary.ply", ply_header("binary_big_endian", 3, 1, "property list int int vertex_indices").encode()
     + struct.pack(">9f", 0, 0, 0, 1, 0, 0, 0, 1, 0) + struct.pack(">4i", -2147483648, 0, 1, 2), "list count INT32_MIN"),
    ("ply_list_count_float_type.ply", ply_header("ascii", 3, 1, "property list float int vertex_indices") + A3 + "3 0 1 2\n",
     "list count type float"),
    ("ply_list_count_huge_ascii.ply", ply_header("ascii", 3, 1, "property list uint int vertex_indices") + A3 + "4000000000 0 1 2\n",
     "ascii list count 4e9 with 3 values"),
    ("ply_vertex_x_is_list.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty list uchar float x\nproperty float y\n"
     "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n1 0 0 0\n1 1 0 0\n1 0 1 0\n3 0 1 2\n",
     "x is a list"),
    ("ply_property_before_element.ply", "ply\nformat ascii 1.0\nproperty float x\nelement vertex 3\nend_header\n", "property first"),
    ("ply_element_twice.ply", ply_header("ascii", 3, 1, extra="element vertex 1\nproperty float q\n") + A3 + "3 0 1 2\n",
     "element vertex declared twice"),
    ("ply_property_twice.ply", ply_header("ascii", 3, 1, "property list uchar int vertex_indices\nproperty float vertex_indices")
     + A3 + "3 0 1 2 0\n", "property declared twice"),
    ("ply_format_middle_endian.ply", ply_header("binary_middle_endian", 3, 1) + A3 + "3 0 1 2\n", "unknown format"),
    ("ply_version_2.ply", ply_header("ascii", 3, 1).replace("1.0", "2.0") + A3 + "3 0 1 2\n", "version 2.0"),
    ("ply_no_format.ply", ply_header("ascii", 3, 1).replace("format ascii 1.0\n", "") + A3 + "3 0 1 2\n", "no format line"),
    ("ply_no_vertex_element.ply", "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n3 0 1 2\n",
     "faces but no vertex element"),
    ("ply_zero_faces.ply", ply_header("ascii", 3, 0) + A3, "face count 0"),
    ("ply_element_without_properties.ply", ply_header("ascii", 3, 1, extra="element empty 5\n") + A3 + "3 0 1 2\n",
     "element with no properties"),
    ("ply_binary_inf.ply", ply_header("binary_little_endian", 3, 1).encode()
     + struct.pack("<9f", 0, 0, float("inf"), 1, 0, 0, 0, 1, 0) + struct.pack("<B3i", 3, 0, 1, 2), "binary inf coordinate"),
    ("ply_binary_nan_double.ply", ply_header("binary_big_endian", 3, 1).replace("float", "double").encode()
     + struct.pack(">9d", 0, 0, 0, 1, float("nan"), 0, 0, 1, 0) + struct.pack(">B3i", 3, 0, 1, 2), "binary nan double"),
    ("ply_index_fraction.ply", ply_header("ascii", 3, 1, "property list uchar float vertex_indices") + A3 + "3 0 1 1.5\n",
     "vertex index 1.5"),
    ("ply_index_nan_binary.ply", ply_header("binary_little_endian", 3, 1, "property list uchar float vertex_indices").encode()
     + struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0) + struct.pack("<B3f", 3, 0, 1, float("nan")), "vertex index nan"),
    ("ply_index_1e300.ply", ply_header("binary_little_endian", 3, 1, "property list uchar double vertex_indices").encode()
     + struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0) + struct.pack("<B3d", 3, 0, 1, 1e300), "vertex index 1e300"),
    ("ply_index_uint_max.ply", ply_header("binary_little_endian", 3, 1, "property list uchar uint vertex_indices").encode()
     + struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0) + struct.pack("<B3I", 3, 0, 1, 0xFFFFFFFF), "vertex index 2^32-1"),
    ("ply_index_negative.ply", ply_header("ascii", 3, 1) + A3 + "3 0 1 -1\n", "vertex index -1"),
    ("ply_header_non_utf8.ply", ply_header("ascii", 3, 1).replace("element face", "elem\xffent face") + A3 + "3 0 1 2\n",
     "byte 0xff in a keyword"),
    ("ply_header_nul.ply", "ply\x00\n" + ply_header("ascii", 3, 1)[4:] + A3 + "3 0 1 2\n", "NUL in the magic line"),
    ("ply_many_properties.ply", "ply\nformat ascii 1.0\nelement vertex 1\n" + "".join("property float p%d\n" % i for i in range(5000))
     + "property float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
     + "0 " * 100 + "\n", "5003 properties, data cut short"),
    ("ply_binary_garbage_body.ply", ply_header("binary_little_endian", 3, 1).encode() + rnd(5, 51), "binary header, random body"),
    ("ply_ascii_garbage_body.ply", ply_header("ascii", 3, 1).encode() + rnd(6, 512), "ascii header, random body"),
    ("ply_binary_trailing_byte.ply", PLY_LE + b"\n", "one byte after the last element"),
    ("ply_no_end_header_binary.ply", PLY_LE.replace(b"end_header\n", b""), "binary without end_header"),
    ("ply_list_255_ascii.ply", ply_header("ascii", 3, 1) + A3 + "255 0 1 2\n", "255 corners listed, 3 given"),
    ("ply_random_bytes.ply", rnd(7, 4096), "random bytes"),
    ("ply_magic_then_garbage.ply", b"ply\n" + rnd(8, 1024), "magic line, random bytes"),
]
for name, data, why in ply:
    add(name, data, why)

# ---- misc: contents that do not match the extension ------------------------------------
add("ply_content.obj", PLY_ASCII, "a PLY file named .obj: no OBJ faces")
add("obj_content.off", TRI + "f 1 2 3\n", "an OBJ file named .off")
add("off_content.ply", OFF, "an OFF file named .ply")
add("cube.stl", "solid cube\nendsolid cube\n", "unknown extension")
add("no_extension", OBJ, "no extension")
add("upper_case_garbage.OBJ", rnd(9, 256), "random bytes, upper-case extension")

# ---- cache files without valid checksums -----------------------------------------------------
MAGIC = b"SFPATCH\0"
add("cache_empty.sfcache", b"", "empty file")
add("cache_7_bytes.sfcache", MAGIC[:7], "7 bytes of the magic")
add("cache_magic_only.sfcache", MAGIC, "the magic and nothing else")
add("cache_header_127.sfcache", MAGIC + struct.pack("<II", 1, 128) + b"\0" * 112 + b"\0" * 7, "127-byte header")
add("cache_zero_header.sfcache", MAGIC + struct.pack("<II", 1, 128) + b"\0" * 112, "header of zeros (checksum 0)")
hdr = MAGIC + struct.pack("<II", 1, 128) + struct.pack("<QQ", 1, 2) + struct.pack("<6I", 0, 0, 0, 0, 56, 64)
hdr += struct.pack("<5Q", 4000000000, 4000000000, 4000000000, 2 ** 63, 0) + b"\0" * 24
add("cache_huge_counts.sfcache", hdr + struct.pack("<Q", 0), "4e9 counts, payload 2^63 bytes, checksum 0")
add("cache_random.sfcache", rnd(10, 4096), "random bytes")
add("cache_magic_random.sfcache", MAGIC + rnd(11, 1024), "magic, then random bytes")
add("cache_obj_text.sfcache", OBJ, "an OBJ file named .sfcache")


def seeds():
    """Small valid meshes for the fuzzers, each format's features once, and the malformed
    files of tests/data/malformed (cache seeds: see fuzz/README.md)."""
    out = {}
    out["obj/cube_faces_first.obj"] = OBJ
    out["obj/cube_normals.obj"] = "".join("v %g %g %g\n" % v for v in CUBE_V) + "vn 0 0 1\nvn 0 0 -1\nvt 0 0\n" + \
        "".join("f %s\n" % " ".join("%d/1/%d" % (i + 1, 1 + k % 2) for i in f) for k, f in enumerate(CUBE_F))
    out["obj/misc_statements.obj"] = "# c\nmtllib a.mtl\no x\ng g\ns 1\nusemtl m\n" + TRI + \
        "v 1 1 0 1.0\nv 2 0 0 0.5 0.5 0.5\nvt 0 0\nvn 0 0 1\nf -4 -3 -2\nf 2/1 5/1 4/1\nl 1 2\np 1\n"
    out["obj/spot_control_mesh.obj"] = open(os.path.join(ROOT, "data", "spot_control_mesh.obj")).read()
    out["off/cube.off"] = OFF
    out["off/noff_inline_counts.off"] = "NOFF 3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n"
    out["off/stcoff_comments.off"] = "# x\nSTCOFF\n# y\n3 1 3\n0 0 0 1 0 0 1 0 0\n1 0 0 0 1 0 1 1 0\n" + \
        "0 1 0 0 0 1 1 0 1\n3 0 1 2 255 0 0\n"
    out["ply/cube_ascii.ply"] = PLY_ASCII
    out["ply/cube_le.ply"] = PLY_LE
    out["ply/cube_be.ply"] = PLY_BE
    out["ply/normals_extra_props.ply"] = ("ply\nformat binary_little_endian 1.0\ncomment c\nelement material 1\n"
        "property uchar id\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\n"
        "property float nx\nproperty float ny\nproperty float nz\nproperty list uchar short extra\n"
        "element face 1\nproperty uchar flags\nproperty list uint8 uint32 vertex_index\nend_header\n").encode() + \
        b"\x07" + b"".join(struct.pack("<3d3fBh", x, y, 0, 0, 0, 1, 1, 5) for x, y in ((0, 0), (1, 0), (0, 1))) + \
        struct.pack("<BB3I", 0, 3, 0, 1, 2)
    mal = os.path.join(ROOT, "tests", "data", "malformed")
    for name in sorted(os.listdir(mal)):
        with open(os.path.join(mal, name), "rb") as f:
            out["%s/malformed_%s" % (name[:3], name)] = f.read()
    for rel, data in sorted(out.items()):
        path = os.path.join(ROOT, "fuzz", "seeds", rel)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "wb") as f:
            f.write(data.encode("latin-1") if isinstance(data, str) else data)
    print("%d seed files in %s" % (len(out), os.path.join(ROOT, "fuzz", "seeds")))


def main():
    if SEEDS:
        seeds()
        return
    os.makedirs(OUT, exist_ok=True)
    for old in os.listdir(OUT):
        os.remove(os.path.join(OUT, old))
    total = 0
    with open(os.path.join(OUT, "INDEX.tsv"), "w") as idx:
        idx.write("# file\twhy it must be rejected (generated by tools/make_hostile_corpus.py)\n")
        for name in sorted(FILES):
            data, why = FILES[name]
            with open(os.path.join(OUT, name), "wb") as f:
                f.write(data)
            total += len(data)
            idx.write("%s\t%s\n" % (name, why))
    print("%d files, %d bytes in %s" % (len(FILES), total, os.path.normpath(OUT)))


if __name__ == "__main__":
    main()
