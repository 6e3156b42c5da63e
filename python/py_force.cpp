// SPDX-License-Identifier: Apache-2.0
// smoothforce.trace (force traces), smoothforce.Haptic (the servo step for a foreign loop) and
// smoothforce.Surface (the stateless batch surface query).
#include <pybind11/stl.h>

#include <array>
#include <cstddef>

#include <smoothforce/force/force_option_text.h>
#include <smoothforce/force/force_tracking.h>
#include <smoothforce/query/surface_query.h>
#include <smoothforce/runtime/loop_option_text.h>
#include <smoothforce/runtime/safety.h>
#include <smoothforce/runtime/scene.h>
#include <smoothforce/runtime/servo_step.h>
#include "py_common.h"

namespace sf::py {
namespace {

/// One trace row, as the structured array holds it.
struct TraceRow {
  double hip[3], scp[3], force[3], normal[3];
  double xi, eta;
  int32_t face, iterations;
  uint32_t status;
  uint8_t contact;
};

pyb::dtype traceDtype() {
  return structDtype({{"hip", "(3,)f8", offsetof(TraceRow, hip)},
                      {"scp", "(3,)f8", offsetof(TraceRow, scp)},
                      {"force", "(3,)f8", offsetof(TraceRow, force)},
                      {"normal", "(3,)f8", offsetof(TraceRow, normal)},
                      {"xi", "f8", offsetof(TraceRow, xi)},
                      {"eta", "f8", offsetof(TraceRow, eta)},
                      {"face", "i4", offsetof(TraceRow, face)},
                      {"iterations", "i4", offsetof(TraceRow, iterations)},
                      {"status", "u4", offsetof(TraceRow, status)},
                      {"contact", "?", offsetof(TraceRow, contact)}},
                     sizeof(TraceRow));
}

ForceOptions forceOptions(const std::string& method, double stiffness, const pyb::object& preset, int capacity,
                          const std::string& finalStep, ForceMethod* m, const std::string& surfaceIndex = "auto") {
  if (!preset.is_none() && !pyb::isinstance<pyb::str>(preset))
    throw pyb::type_error("preset: expected a str (fast, balanced, accurate) or None, got " +
                          std::string(pyb::str(preset.get_type().attr("__name__"))));
  const std::string name = preset.is_none() ? std::string() : preset.cast<std::string>();
  // the shared reader (force_option_text.h): the keyword arguments are its keys
  const ForceSettings f = readHapticForceSettings(method.c_str(), preset.is_none() ? nullptr : name.c_str(), stiffness,
                                                  capacity, finalStep.c_str(), surfaceIndex.c_str());
  *m = f.method;
  return f.options;
}

pyb::array trace(const PyCache& c, const pyb::handle& hipsIn, const std::string& method, double stiffness,
                 const pyb::object& preset, int capacity, const std::string& finalStep,
                 const std::string& surfaceIndex) {
  ForceMethod m{};
  const ForceOptions f = forceOptions(method, stiffness, preset, capacity, finalStep, &m, surfaceIndex);
  const Doubles hips = numericArray(hipsIn, "hips");
  if (hips.ndim() != 2 || hips.shape(1) != 3) throw InputError("hips: expected shape (T, 3)");
  const size_t n = static_cast<size_t>(hips.shape(0));
  pyb::array out(traceDtype(), std::vector<ssize_t>{static_cast<ssize_t>(n)});
  auto* rows = static_cast<TraceRow*>(out.mutable_data());
  const double* h = hips.data();
  {
    pyb::gil_scoped_release release;
    auto renderer = makeForceRenderer(c.cache, m, f);
    for (size_t i = 0; i < n; ++i) {
      const Eigen::Vector3d hip(h[3 * i], h[3 * i + 1], h[3 * i + 2]);
      const ForceSample s = renderer->step(hip);
      TraceRow& r = rows[i];
      for (int k = 0; k < 3; ++k) {
        r.hip[k] = hip[k];
        r.scp[k] = s.scp[k];
        r.force[k] = s.force[k];
        r.normal[k] = s.normal[k];
      }
      r.xi = s.xi;
      r.eta = s.eta;
      r.face = s.contact ? s.face : -1;
      r.iterations = s.iterations;
      r.status = s.status;
      r.contact = s.contact ? 1 : 0;
    }
  }
  return out;
}

/// Renderer + safety + servo step on a one-object scene (what the C API's sf_haptic is).
class Haptic {
 public:
  Haptic(const PyCache& c, const std::string& method, double stiffness, const pyb::object& preset, int capacity,
         double maxForce, double maxForceStep, double rampTime, double rate, const std::string& finalStep,
         const std::string& surfaceIndex) {
    ForceMethod m{};
    const ForceOptions f = forceOptions(method, stiffness, preset, capacity, finalStep, &m, surfaceIndex);
    rt::SafetyOptions so;
    so.maxForce = maxForce;
    so.maxForceStep = maxForceStep;
    so.rampTime = rampTime;
    rt::checkSafetyOptions(so);  // the shared check (loop_option_text.h): the keyword arguments are its keys
    rt::checkLoopOption("rate", rate);
    rt::StepOptions step;
    step.rate = rate;
    scene_ = rt::singleObjectScene(c.cache, c.source, m, f,
                                   [](std::shared_ptr<const PatchCache> cc, ForceMethod mm, const ForceOptions& ff) {
                                     return makeForceRenderer(std::move(cc), mm, ff);
                                   });
    safety_ = std::make_unique<rt::SafetyFilter>(so);
    step_ = std::make_unique<rt::ServoStep>(scene_, *safety_, step);
  }

  pyb::dict step(const std::array<double, 3>& hip, double time) {
    rt::StepTime t;
    t.wake = time;
    rt::DeviceState d;
    d.position = Eigen::Vector3d(hip[0], hip[1], hip[2]);
    const rt::StepOutput s = step_->step(t, d);
    pyb::dict r;
    r["force"] = std::array<double, 3>{s.force.x(), s.force.y(), s.force.z()};
    r["rendered"] = std::array<double, 3>{s.sample.force.x(), s.sample.force.y(), s.sample.force.z()};
    r["scp"] = std::array<double, 3>{s.sample.scp.x(), s.sample.scp.y(), s.sample.scp.z()};
    r["normal"] = std::array<double, 3>{s.sample.normal.x(), s.sample.normal.y(), s.sample.normal.z()};
    r["contact"] = s.sample.contact;
    r["face"] = s.sample.contact ? s.sample.face : -1;
    r["status"] = s.sample.status;
    r["flags"] = s.flags;
    r["faulted"] = s.faulted;
    r["iterations"] = s.sample.iterations;
    return r;
  }

  void setPose(const std::array<double, 3>& t, const std::array<double, 4>& q, double scale) {
    rt::Pose p;
    p.translation = Eigen::Vector3d(t[0], t[1], t[2]);
    p.rotation = Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
    p.scale = scale;
    if (!rt::isValid(p))
      throw InputError("pose: expected a finite translation, a finite quaternion of norm 1e-12 to 1e150 and a finite scale > 0");
    if (!scene_.setPose(0, p)) throw InputError("pose: another thread is publishing a pose for this object");
  }

  void reset() {
    scene_.reset();
    safety_->reset();
  }

  int patchesBuilt() const { return scene_.patchesBuilt(); }

 private:
  rt::Scene scene_;
  std::unique_ptr<rt::SafetyFilter> safety_;
  std::unique_ptr<rt::ServoStep> step_;
};

/// SurfaceQueryResult as a NumPy structured dtype (written in place by SurfaceQuery::query).
pyb::dtype surfacePointDtype() {
  using R = SurfaceQueryResult;
  static_assert(sizeof(Eigen::Vector3d) == 3 * sizeof(double), "Eigen::Vector3d is three packed doubles");
  return structDtype({{"signed_distance", "f8", offsetof(R, signedDistance)},
                      {"point", "(3,)f8", offsetof(R, point)},
                      {"normal", "(3,)f8", offsetof(R, normal)},
                      {"face", "i4", offsetof(R, face)},
                      {"xi", "f8", offsetof(R, xi)},
                      {"eta", "f8", offsetof(R, eta)},
                      {"status", "u4", offsetof(R, status)}},
                     sizeof(R));
}

/// smoothforce.Surface: a SurfaceQuery on a prebuilt cache.
class Surface {
 public:
  Surface(const PyCache& c, const pyb::object& preset) {
    ForceMethod m{};
    const ForceOptions f = forceOptions("patch", 500.0, preset, 256, "evaluated", &m);
    pyb::gil_scoped_release release;
    query_ = std::make_unique<SurfaceQuery>(c.cache, f);
  }
  pyb::array query(const pyb::handle& pointsIn, int threads) const {
    const Doubles pts = numericArray(pointsIn, "points");
    if (pts.ndim() != 2 || pts.shape(1) != 3) throw InputError("points: expected shape (N, 3)");
    const size_t n = static_cast<size_t>(pts.shape(0));
    pyb::array out(surfacePointDtype(), std::vector<ssize_t>{static_cast<ssize_t>(n)});
    auto* rows = static_cast<SurfaceQueryResult*>(out.mutable_data());
    const double* p = pts.data();
    {
      pyb::gil_scoped_release release;
      query_->query(p, n, rows, threads);
    }
    return out;
  }

 private:
  std::unique_ptr<SurfaceQuery> query_;
};

}  // namespace

void bindForce(pyb::module_& m) {
  using namespace pybind11::literals;
  m.def("trace", &trace, "cache"_a, "hips"_a, pyb::kw_only(), "method"_a = "patch", "stiffness"_a = 500.0,
        "preset"_a = pyb::none(), "patch_capacity"_a = 256, "final_step"_a = "evaluated",
        "surface_index"_a = "auto",
        "A force trace: one stateful renderer (method patch, direct or shading; stiffness N/m; preset fast,\n"
        "balanced or accurate; final_step evaluated or model, as --final-step; surface_index auto, bounds or\n"
        "tessellation, as --surface-index: auto is tessellation here) stepped over hips (T, 3), m,\n"
        "in order, as `smoothforce trace` does (no safety layer). Returns a structured array (T,): hip (3,),\n"
        "scp (3,) m, force (3,) N, normal (3,), xi, eta,\n"
        "face (-1 out of contact), iterations, status (SF_ST_*/SF_TRACK_* bits), contact. GIL released.");
  pyb::class_<Surface>(m, "Surface",
                       "The stateless surface query on a prebuilt cache (C++ SurfaceQuery): for many points, the\n"
                       "signed distance to the patch surface and its nearest point, as the patch method's global query\n"
                       "finds them at a contact start. Building it tessellates the patches and builds a BVH once.")
      .def(pyb::init<const PyCache&, const pyb::object&>(), "cache"_a, pyb::kw_only(), "preset"_a = pyb::none(),
           "preset: the refinement tolerances (fast, balanced, accurate) or None. Raises ValueError for a lazy\n"
           "cache (no patches built) or a bad preset.")
      .def("query", &Surface::query, "points"_a, pyb::kw_only(), "threads"_a = 0,
           "points (N, 3), m -> structured array (N,): signed_distance m (negative inside; NaN for a point not\n"
           "finite or beyond 1e15 m), point (3,) m and normal (3,) of the nearest patch point, face (-1: none),\n"
           "xi, eta (its domain point), status (SF_TRACK_*/SF_ST_* bits; SF_TRACK_INSIDE inside). Stateless: the\n"
           "answers do not depend on the order or the thread count (threads <= 0: all cores). GIL released.");
  pyb::class_<Haptic>(m, "Haptic",
                      "The servo step for a loop the caller owns (a device SDK's 1 kHz callback): a renderer on the\n"
                      "cache, the safety layer (force clamp, rate limit, ramp-in, non-finite fault) and deadline\n"
                      "accounting. step() does not allocate in the engine (the returned dict is Python's).")
      .def(pyb::init<const PyCache&, const std::string&, double, const pyb::object&, int, double, double, double,
                     double, const std::string&, const std::string&>(),
           "cache"_a, pyb::kw_only(), "method"_a = "patch", "stiffness"_a = 500.0, "preset"_a = pyb::none(),
           "patch_capacity"_a = 256, "max_force"_a = 3.3, "max_force_step"_a = 0.5, "ramp_time"_a = 0.5,
           "rate"_a = 1000.0, "final_step"_a = "evaluated", "surface_index"_a = "auto",
           "Units: N/m, N, N per step, s, Hz; final_step evaluated or model (as --final-step); surface_index\n"
           "auto, bounds or tessellation (as --surface-index: auto is bounds here, about 3 kB per face of a\n"
           "prebuilt cache instead of 0.1-0.5 MB). Raises ValueError for an option out of range.")
      .def("step", &Haptic::step, "hip"_a, "time"_a,
           "One step at HIP (3,) m and time s (caller's clock). Returns a dict: force (after safety, N; command\n"
           "this), rendered (before safety), scp, normal, contact, face, status, flags (bit 0 clamped, 1 rate\n"
           "limited, 2 ramping, 3 faulted, 4 missed deadline), faulted, iterations.")
      .def("set_pose", &Haptic::setPose, "translation"_a, "quaternion"_a, "scale"_a = 1.0,
           "Moves the object (translation m, quaternion w x y z, uniform scale); applied by the next step.")
      .def("reset", &Haptic::reset, "Forgets the contact; clears the fault latch and the safety counters.")
      .def_property_readonly("patches_built", &Haptic::patchesBuilt);
}

}  // namespace sf::py
