// SPDX-License-Identifier: Apache-2.0
// Internals of the C API: the handles and the exception-to-status boundary.
#pragma once

#include <exception>
#include <memory>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>

#include <smoothforce.h>
#include <smoothforce/base/error.h>
#include <smoothforce/force/force_method.h>
#include <smoothforce/query/surface_query.h>
#include <smoothforce/mesh/mesh_check.h>
#include <smoothforce/patch/patch_cache.h>
#include <smoothforce/runtime/safety.h>
#include <smoothforce/runtime/scene.h>
#include <smoothforce/runtime/servo_step.h>

struct sf_cache {
  std::shared_ptr<const sf::PatchCache> cache;
  sf::Backend backend = sf::Backend::Tbb;
  int threads = 0;
  std::string source;
  std::string error;
  std::unique_ptr<sf::MeshReport> polygons;  ///< checkMesh of the base mesh, made on first request
  /// sf::TangentFans::turnDeg of the cache (#C*2, empty: none turned), made on first request
  std::unique_ptr<std::vector<double>> tangentTurns;
};

struct sf_surface {
  std::unique_ptr<sf::SurfaceQuery> query;
  std::string error;
};

struct sf_haptic {
  sf::rt::Scene scene;
  std::unique_ptr<sf::rt::SafetyFilter> safety;
  std::unique_ptr<sf::rt::ServoStep> step;
  std::string error;
};

namespace sf::capi {

/// The thread's message of the last failed create.
std::string& lastError();

/// Runs f(); maps an exception to a status and stores its message in `message`.
template <class F>
sf_status guarded(std::string& message, F&& f) noexcept {
  try {
    f();
    message.clear();
    return SF_OK;
  } catch (const InputError& e) {
    message = e.what();
    return SF_ERROR_INPUT;
  } catch (const std::bad_alloc&) {
    message = "out of memory";
    return SF_ERROR_MEMORY;
  } catch (const std::length_error& e) {  // a size no container can hold: too much memory asked for
    message = std::string("out of memory: ") + e.what();
    return SF_ERROR_MEMORY;
  } catch (const std::out_of_range& e) {
    message = e.what();
    return SF_ERROR_ARGUMENT;
  } catch (const std::invalid_argument& e) {
    message = e.what();
    return SF_ERROR_ARGUMENT;
  } catch (const std::exception& e) {
    message = std::string("internal error: ") + e.what();
    return SF_ERROR_INTERNAL;
  } catch (...) {
    message = "internal error: unknown exception";
    return SF_ERROR_INTERNAL;
  }
}

/// A create function's boundary: NULL `out` is SF_ERROR_ARGUMENT; *out is NULL until make()
/// returns the new handle (an owning T*); its exception is a status, with the message in the
/// thread's lastError().
template <class T, class F>
sf_status create(T** out, F&& make) noexcept {
  if (!out) {
    lastError() = "out: NULL";
    return SF_ERROR_ARGUMENT;
  }
  *out = nullptr;
  return guarded(lastError(), [&] { *out = make(); });
}

/// A string option: the default when NULL.
inline std::string opt(const char* s, const char* fallback) { return s ? std::string(s) : std::string(fallback); }

/// Force options from the C options (preset first, then stiffness and capacity); validated.
ForceOptions forceOptions(const sf_haptic_options& o, ForceMethod* method);

}  // namespace sf::capi
