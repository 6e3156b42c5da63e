// SPDX-License-Identifier: Apache-2.0
// Private to mesh: a cage's topology handed to OpenSubdiv (Far::TopologyDescriptor), with the
// Sdc options every cage computation shares.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefiner.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <smoothforce/mesh/mesh.h>
#include <smoothforce/mesh/mesh_check.h>

namespace sf::osd_cage {

namespace Far = OpenSubdiv::Far;
namespace Sdc = OpenSubdiv::Sdc;

/// Catmull-Clark with VTX_BOUNDARY_EDGE_AND_CORNER (cage_limit.h, CageMode), Catmark weights
/// on triangles, uniform creasing (no crease is ever given). Face-varying data are not used.
Sdc::Options sdcOptions();

/// The referenced vertices of a mesh, renumbered densely in file order (OpenSubdiv gives every
/// vertex of the descriptor a limit, so unreferenced vertices are left out).
struct Compact {
  std::vector<int> toCompact;    ///< #V: compact index, -1 for an unreferenced vertex
  std::vector<int> fromCompact;  ///< compact index -> vertex
  std::vector<int> faceSizes;    ///< #F
  std::vector<int> faceVerts;    ///< #C, compact indices
};
Compact compact(const PolygonMesh& mesh);

/// The unrefined TopologyRefiner of a cage. Throws InputError (prefixed by the mesh's source
/// path) when cageProblem(mesh, report) is not empty or OpenSubdiv refuses the topology.
std::unique_ptr<Far::TopologyRefiner> makeRefiner(const PolygonMesh& mesh, const MeshReport& report, const Compact& c);

/// "PATH: " or "mesh: " for messages.
std::string where(const PolygonMesh& mesh);

}  // namespace sf::osd_cage
