// SPDX-License-Identifier: Apache-2.0
// SmoothForce core: every public header of base, mesh, patch, query, force and opencl
// (link SmoothForce::core). The device loop is SmoothForce::runtime
// (<smoothforce/runtime/...>), sweeps SmoothForce::sweep (<smoothforce/sweep/...>).
// opencl_context.h (the OpenCL C++ bindings, only in builds with OpenCL) is left out so that
// this header never pulls <CL/opencl.hpp> in; include it where needed.
#pragma once

#include <smoothforce/config.h>
#include <smoothforce/version.h>

#include <smoothforce/base/coordinate_range.h>
#include <smoothforce/base/csv_reader.h>
#include <smoothforce/base/error.h>
#include <smoothforce/base/hash.h>
#include <smoothforce/base/memory_bytes.h>
#include <smoothforce/base/option_spec.h>
#include <smoothforce/base/staged_output.h>
#include <smoothforce/base/status.h>
#include <smoothforce/base/text_encoding.h>
#include <smoothforce/base/thread_limit.h>

#include <smoothforce/mesh/cage_limit.h>
#include <smoothforce/mesh/creases.h>
#include <smoothforce/mesh/exact_predicates.h>
#include <smoothforce/mesh/mesh.h>
#include <smoothforce/mesh/mesh_check.h>
#include <smoothforce/mesh/mesh_intersect.h>
#include <smoothforce/mesh/mesh_io.h>
#include <smoothforce/mesh/normals.h>
#include <smoothforce/mesh/polygon_split.h>
#include <smoothforce/mesh/seams.h>
#include <smoothforce/mesh/topology.h>

#include <smoothforce/patch/cache_file.h>
#include <smoothforce/patch/fold_repair_record.h>
#include <smoothforce/patch/lazy_patches.h>
#include <smoothforce/patch/limit_distance.h>
#include <smoothforce/patch/mesh_arrays.h>
#include <smoothforce/patch/mesh_pipeline.h>
#include <smoothforce/patch/normal_groups.h>
#include <smoothforce/patch/patch_bounds.h>
#include <smoothforce/patch/patch_build.h>
#include <smoothforce/patch/patch_cache.h>
#include <smoothforce/patch/patch_certificate.h>
#include <smoothforce/patch/patch_eval.h>
#include <smoothforce/patch/patch_option_text.h>
#include <smoothforce/patch/patch_options.h>
#include <smoothforce/patch/patch_simd.h>
#include <smoothforce/patch/straight_corner_split.h>
#include <smoothforce/patch/tangent_fans.h>
#include <smoothforce/patch/tessellate.h>

#include <smoothforce/query/embree_scene.h>
#include <smoothforce/query/lazy_surface.h>
#include <smoothforce/query/global_query.h>
#include <smoothforce/query/mean_value.h>
#include <smoothforce/query/normal_search.h>
#include <smoothforce/query/patch_refine.h>
#include <smoothforce/query/patch_seeds.h>
#include <smoothforce/query/patch_surface.h>
#include <smoothforce/query/point_index.h>
#include <smoothforce/query/polygon_facets.h>
#include <smoothforce/query/refine_options.h>
#include <smoothforce/query/surface_distance.h>
#include <smoothforce/query/surface_faults.h>
#include <smoothforce/query/surface_query.h>

#include <smoothforce/force/force_method.h>
#include <smoothforce/force/force_option_text.h>
#include <smoothforce/force/force_presets.h>
#include <smoothforce/force/force_tracking.h>
#include <smoothforce/force/god_object.h>
#include <smoothforce/force/shared_geometry.h>

#include <smoothforce/opencl/opencl_backend.h>
#include <smoothforce/opencl/opencl_candidates.h>
#include <smoothforce/opencl/opencl_refine.h>
