// SPDX-License-Identifier: Apache-2.0
// The fold repair's untangled vertex fans: edge-curve end tangents put in the fan's order.
#pragma once

#include <vector>

#include <smoothforce/patch/patch_cache.h>

namespace sf {

/// A fan whose consecutive edge tangents are less than this (degrees) or more than 180 minus this
/// apart, or that winds other than once round its normal, is tangled.
inline constexpr double kFanTangledGapDeg = 1.0;
/// Smallest angle (degrees) between two consecutive edge tangents of an untangled fan (at most
/// half the mean, 180 / valence). A corner that narrow is nearly singular and bends its patch
/// sharply: on the spot cage, a 1-degree margin left the angle across face 64's edges shrinking
/// 2.5 times per decade of distance, not tenfold (G1 only very near the edge); 5 degrees left
/// HIPs whose contact start disagreed with the winding number near faces 61 and 66, 20 degrees
/// folded faces 156 and 157 along their shared edge (the certificate proves both folded); 10
/// degrees none of these.
inline constexpr double kFanGapDeg = 10.0;
/// Largest angle (degrees) between an untangled tangent and its chord projected on the tangent
/// plane: the edge curve must leave its vertex forward along its edge (its edge normal n_c is
/// the vertex normal there only while C'(0) . (V_{k+1} - V_k) > 0; design page, Robustness 1).
inline constexpr double kFanMaxChordTurnDeg = 75.0;

/// The end tangents that the fold repair gives the edge curves at vertices whose fan is tangled.
/// At a vertex V with one normal N, the edge curves leave V in the tangent plane of N, each along
/// the projection of its chord (design page, Eq. 8-9). Where the chords project out of the order
/// of the faces around V (the fan winds other than once round N), or two consecutive ones are
/// less than kFanTangledGapDeg or more than 180 - kFanTangledGapDeg apart, the corner of the face between
/// them meets N inside out (its two edge curves leave V in the wrong order about N) or nearly so,
/// and that patch folds at V whatever normal V has. There the fan's directions are moved, in the
/// tangent plane, as little as possible (least squares on their angles) to be in the faces'
/// order with every consecutive gap in [kFanGapDeg, 180 - kFanGapDeg] degrees and each
/// within kFanMaxChordTurnDeg of its chord (where no such fan exists, the vertex keeps its): N, the
/// tangent plane and so G1 on every edge stay as they were; only the edge curves' directions at V
/// turn. Only on closed manifold meshes (every edge shared by two faces), and there not at
/// vertices where several fans meet, with more than one normal (a crease) or with more than
/// GP_MAX_N faces.
struct TangentFans {
  /// #C*6 or empty (no fan untangled): for slot s (edge k of face f, V_k -> V_{k+1}) the unit
  /// direction of C_k'(0) at V_k, then of C_k'(1) at V_{k+1}; zeros where the construction's own
  /// stays. The two slots of an edge hold the same directions, negated and swapped.
  std::vector<double> tangents;
  /// #C*2 or empty (no fan untangled): for slot s, the angle (degrees, in [0, 180]) by which
  /// the direction of C_k'(0) at V_k (index 2 s) and of C_k'(1) at V_{k+1} (2 s + 1) turned from
  /// the construction's own; 0 where it stays.
  std::vector<double> turnDeg;
  std::vector<int> vertices;  ///< the untangled vertices, ascending
  double maxTurnDeg = 0;      ///< largest turn of one edge tangent
};

/// The untangled fans of `cache` from its positions, corner normals and adjacency (its patch
/// arrays are not read): FoldRepairMode::On and Search (from the normals the search turned),
/// empty for Off. A fan depends on the normals at both ends of its edges (the construction's own
/// directions, gp_edge_tangents, use both), so turning one vertex normal can change the fans of
/// its neighbours too. Deterministic, O(#C).
TangentFans untangleTangentFans(const PatchCache& cache);

/// Sets cache.edgeTangents to untangleTangentFans(cache).tangents (construction calls it, so
/// that patches built after a normal changed use fans of the normals they are built from).
void refreshEdgeTangents(PatchCache& cache);

/// True when `tangents` (#C*6 as TangentFans::tangents, or empty) gives an end tangent of one of
/// the slots [first, last).
bool givesEndTangents(const std::vector<double>& tangents, size_t first, size_t last);

/// True when cache.edgeTangents gives some end tangent of face f.
bool faceHasEdgeTangents(const PatchCache& cache, int f);

}  // namespace sf
