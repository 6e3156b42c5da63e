// SPDX-License-Identifier: Apache-2.0
// C API: the servo step (renderer + safety + ServoStep on a one-object scene) and traces.
#include <cmath>
#include <cstring>
#include <iterator>
#include <vector>

#include <smoothforce/force/force_option_text.h>
#include <smoothforce/force/force_tracking.h>
#include <smoothforce/runtime/loop_option_text.h>
#include <smoothforce/runtime/pose.h>
#include "capi_detail.h"

namespace sf::capi {

// The C header's status bits are the library's (one list: smoothforce/base/status.h).
#define SF_CAPI_SAME_BIT(name) static_assert(static_cast<uint32_t>(::name) == sf::name, #name)
SF_CAPI_SAME_BIT(SF_ST_GUARD);
SF_CAPI_SAME_BIT(SF_ST_ZERO_EDGE);
SF_CAPI_SAME_BIT(SF_ST_EDGE_NORMAL);
SF_CAPI_SAME_BIT(SF_ST_CROSS_TANGENT);
SF_CAPI_SAME_BIT(SF_ST_FOLD);
SF_CAPI_SAME_BIT(SF_ST_BULGE);
SF_CAPI_SAME_BIT(SF_ST_OUTSIDE);
SF_CAPI_SAME_BIT(SF_ST_SINGULAR);
SF_CAPI_SAME_BIT(SF_ST_TOO_MANY_SIDES);
SF_CAPI_SAME_BIT(SF_ST_NONFINITE);
SF_CAPI_SAME_BIT(SF_ST_MODEL_POINT);
SF_CAPI_SAME_BIT(SF_ST_AFFINE);
SF_CAPI_SAME_BIT(SF_TRACK_CONVERGED);
SF_CAPI_SAME_BIT(SF_TRACK_MAX_ITER);
SF_CAPI_SAME_BIT(SF_TRACK_STALLED);
SF_CAPI_SAME_BIT(SF_TRACK_BOUNDARY);
SF_CAPI_SAME_BIT(SF_TRACK_DEGENERATE);
SF_CAPI_SAME_BIT(SF_TRACK_GLOBAL);
SF_CAPI_SAME_BIT(SF_TRACK_ENTER);
SF_CAPI_SAME_BIT(SF_TRACK_LEAVE);
SF_CAPI_SAME_BIT(SF_TRACK_NO_POLYGON);
SF_CAPI_SAME_BIT(SF_TRACK_BAD_HIP);
SF_CAPI_SAME_BIT(SF_TRACK_PROXY_LIMIT);
SF_CAPI_SAME_BIT(SF_TRACK_INSIDE);
SF_CAPI_SAME_BIT(SF_TRACK_FOLD_EDGE);
#undef SF_CAPI_SAME_BIT
// the 25 above and the sweep's 3 SF_PROBE_* bits (not in C) are every bit the library names
static_assert(std::size(sf::kStatusBits) == 25 + 3, "a status bit of status.h is missing from smoothforce.h");

ForceOptions forceOptions(const sf_haptic_options& o, ForceMethod* method) {
  // the shared reader (force_option_text.h): the fields are its keys
  const ForceSettings f =
      readHapticForceSettings(o.method, o.preset, o.stiffness, o.patch_capacity, o.final_step, o.surface_index);
  *method = f.method;
  return f.options;
}

namespace {

void fill(sf_step_result& r, const ForceSample& s, const Eigen::Vector3d& force) noexcept {
  for (int k = 0; k < 3; ++k) {
    r.force[k] = force[k];
    r.scp[k] = s.scp[k];
    r.normal[k] = s.normal[k];
  }
  r.contact = s.contact ? 1 : 0;
  r.face = s.contact ? s.face : -1;
  r.xi = s.xi;
  r.eta = s.eta;
  r.iterations = s.iterations;
  r.status = s.status;
  r.flags = 0;
  r.faulted = 0;
}

sf_haptic_options defaults(const sf_haptic_options* o) {
  sf_haptic_options d;
  sf_haptic_options_init(&d);
  return o ? *o : d;
}

}  // namespace
}  // namespace sf::capi

using namespace sf;
using namespace sf::capi;

extern "C" {

void sf_haptic_options_init(sf_haptic_options* o) {
  if (!o) return;
  const rt::SafetyOptions s;
  *o = sf_haptic_options{nullptr,
                         nullptr,
                         ForceOptions{}.stiffness,
                         ForceOptions{}.patchCapacity,
                         s.maxForce,
                         s.maxForceStep,
                         s.rampTime,
                         rt::StepOptions{}.rate,
                         nullptr,
                         nullptr};
}

sf_status sf_haptic_create(sf_cache* cache, const sf_haptic_options* options, sf_haptic** out) {
  return create(out, [&] {
    if (!cache) throw std::invalid_argument("cache: NULL");
    const sf_haptic_options o = defaults(options);
    ForceMethod method{};
    const ForceOptions force = forceOptions(o, &method);
    rt::SafetyOptions so;
    so.maxForce = o.max_force;
    so.maxForceStep = o.max_force_step;
    so.rampTime = o.ramp_time;
    rt::checkSafetyOptions(so);  // the shared check (loop_option_text.h): the fields are its keys
    rt::checkLoopOption("rate", o.rate);
    rt::StepOptions step;
    step.rate = o.rate;
    auto h = std::make_unique<sf_haptic>();
    h->scene = rt::singleObjectScene(cache->cache, cache->source, method, force,
                                     [](std::shared_ptr<const PatchCache> c, ForceMethod m, const ForceOptions& f) {
                                       return makeForceRenderer(std::move(c), m, f);
                                     });
    h->safety = std::make_unique<rt::SafetyFilter>(so);
    h->step = std::make_unique<rt::ServoStep>(h->scene, *h->safety, step);
    return h.release();
  });
}

void sf_haptic_free(sf_haptic* haptic) { delete haptic; }

const char* sf_haptic_error(const sf_haptic* haptic) { return haptic ? haptic->error.c_str() : "haptic: NULL"; }

sf_status sf_haptic_step(sf_haptic* haptic, const double hip[3], double time, sf_step_result* out) {
  if (!haptic || !hip || !out) return SF_ERROR_ARGUMENT;
  rt::StepTime t;
  t.wake = time;
  rt::DeviceState d;
  d.position = Eigen::Vector3d(hip[0], hip[1], hip[2]);
  const rt::StepOutput s = haptic->step->step(t, d);  // noexcept, allocation-free
  fill(*out, s.sample, s.force);
  out->flags = s.flags;
  out->faulted = s.faulted ? 1 : 0;
  return SF_OK;
}

sf_status sf_haptic_set_pose(sf_haptic* haptic, const double translation[3], const double quaternion[4], double scale) {
  if (!haptic || !translation || !quaternion) return SF_ERROR_ARGUMENT;
  rt::Pose p;
  p.translation = Eigen::Vector3d(translation[0], translation[1], translation[2]);
  p.rotation = Eigen::Quaterniond(quaternion[0], quaternion[1], quaternion[2], quaternion[3]);
  p.scale = scale;
  if (!rt::isValid(p)) {
    // Not on the servo path's success branch: a message may allocate here.
    haptic->error = "pose: expected a finite translation, a finite quaternion of norm 1e-12 to 1e150 and a finite scale > 0";
    return SF_ERROR_INPUT;
  }
  if (!haptic->scene.setPose(0, p)) {
    haptic->error = "pose: another thread is publishing a pose for this object";
    return SF_ERROR_INPUT;
  }
  return SF_OK;
}

void sf_haptic_reset(sf_haptic* haptic) {
  if (!haptic) return;
  haptic->scene.reset();
  haptic->safety->reset();
}

sf_status sf_cache_trace(sf_cache* cache, const sf_haptic_options* options, size_t count, const double* hips,
                         sf_step_result* out) {
  if (!cache) return SF_ERROR_ARGUMENT;
  return guarded(cache->error, [&] {
    if (count && (!hips || !out)) throw std::invalid_argument("trace: hips and out must not be NULL");
    const sf_haptic_options o = defaults(options);
    ForceMethod method{};
    const ForceOptions force = forceOptions(o, &method);
    auto renderer = makeForceRenderer(cache->cache, method, force);
    for (size_t i = 0; i < count; ++i) {
      const ForceSample s = renderer->step(Eigen::Vector3d(hips[3 * i], hips[3 * i + 1], hips[3 * i + 2]));
      fill(out[i], s, s.force);
    }
  });
}

sf_status sf_surface_create(sf_cache* cache, const sf_haptic_options* options, sf_surface** out) {
  return create(out, [&] {
    if (!cache) throw std::invalid_argument("cache: NULL");
    const sf_haptic_options o = defaults(options);
    ForceMethod method{};
    const ForceOptions force = forceOptions(o, &method);
    auto s = std::make_unique<sf_surface>();
    s->query = std::make_unique<SurfaceQuery>(cache->cache, force);
    return s.release();
  });
}

void sf_surface_free(sf_surface* surface) { delete surface; }

const char* sf_surface_error(const sf_surface* surface) { return surface ? surface->error.c_str() : "surface: NULL"; }

sf_status sf_surface_query(sf_surface* surface, size_t count, const double* points, int threads,
                           sf_surface_point* out) {
  if (!surface) return SF_ERROR_ARGUMENT;
  return guarded(surface->error, [&] {
    if (count && (!points || !out)) throw std::invalid_argument("surface query: points and out must not be NULL");
    std::vector<SurfaceQueryResult> r(count);
    surface->query->query(points, count, r.data(), threads);
    for (size_t i = 0; i < count; ++i) {
      sf_surface_point& o = out[i];
      o.signed_distance = r[i].signedDistance;
      for (int a = 0; a < 3; ++a) {
        o.point[a] = r[i].point[a];
        o.normal[a] = r[i].normal[a];
      }
      o.face = r[i].face;
      o.xi = r[i].xi;
      o.eta = r[i].eta;
      o.status = r[i].status;
    }
  });
}

}  // extern "C"
