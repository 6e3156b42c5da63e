// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/patch/fold_repair_record.h>

#include <algorithm>

#include <smoothforce/patch/normal_groups.h>
#include <smoothforce/patch/tangent_fans.h>

namespace sf {

FoldRepairRecord foldRepairRecord(const PatchCache& c) {
  FoldRepairRecord r;
  const int nf = static_cast<int>(c.faceSource.size());
  for (int f = 0; f < nf; ++f) {
    const int s = c.faceSource[f];
    const bool alone = (f == 0 || c.faceSource[f - 1] != s) && (f + 1 == nf || c.faceSource[f + 1] != s);
    if (alone) continue;
    if (r.cuts.empty() || r.cuts.back().faceAsRead != s) r.cuts.push_back({s, {}});
    r.cuts.back().faces.push_back(f);
  }
  const TangentFans fans = untangleTangentFans(c);
  r.untangledVertices = static_cast<int>(fans.vertices.size());
  r.maxTangentTurnDeg = fans.maxTurnDeg;
  const bool searched = c.computedNormals.size() == c.cornerNormals.size();
  if (!searched && fans.tangents.empty()) return r;

  std::vector<double> turn(c.numSlots(), 0.0);
  for (int s = 0; s < c.numSlots() && searched; ++s) turn[s] = c.normalTurnDeg(s);
  // a vertex normal is the computed normal the corners of one vertex share (a crease splits them)
  double sum = 0;
  for (const std::vector<int>& group : searched ? vertexNormalGroups(c, &c.computedNormals)
                                                : std::vector<std::vector<int>>{}) {
    const double deg = turn[group[0]];
    if (deg == 0) continue;
    ++r.turnedNormals;
    sum += deg;
    for (const int s : group) {
      r.turnedCorners += turn[s] != 0;
      r.maxDegrees = std::max(r.maxDegrees, turn[s]);
    }
  }
  r.meanDegrees = r.turnedNormals ? sum / r.turnedNormals : 0;

  std::vector<char> edgeChanged(c.numSlots(), 0);
  for (int f = 0; f < c.numFaces(); ++f) {
    const int n = c.faceSize(f), first = c.faceOffsets[f];
    const bool creased = faceHasCrease(c, f);
    FoldRepairRecord::FaceChange fc;
    fc.face = f;
    for (int k = 0; k < n; ++k) {
      if (turn[first + k] != 0) fc.turns.push_back({k, c.faceVertices[first + k], turn[first + k]});
      bool changed = turn[first + k] != 0 || turn[first + (k + 1) % n] != 0 ||
                     givesEndTangents(fans.tangents, first + k, first + k + 1);
      if (creased && !changed) {
        int32_t a, b;
        acrossCorners(c, f, k, a, b);
        changed = turn[a] != 0 || turn[b] != 0;
      }
      if (changed) {
        fc.edges.push_back(k);
        edgeChanged[first + k] = 1;
      }
    }
    if (!fc.edges.empty()) r.changed.push_back(std::move(fc));
  }
  for (int s = 0; s < c.numSlots(); ++s) {
    const int t = c.slotTwin[s];
    if (edgeChanged[s] || (t >= 0 && edgeChanged[t])) r.edgeCurves += t < 0 || s < t;
  }
  return r;
}

}  // namespace sf
