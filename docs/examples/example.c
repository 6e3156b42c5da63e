/* SPDX-License-Identifier: Apache-2.0 */
/* SmoothForce from C: a patch cache from a mesh, a force trace, a foreign-loop servo step.
 * Build: cc example.c -lsmoothforce_capi (or CMake: target_link_libraries(x SmoothForce::capi)).
 * Run:   ./example_c MESH.obj      prints what it did; exit status 1 on any failure. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <smoothforce.h>

#define CHECK(call, handle_error)                                                  \
  do {                                                                             \
    sf_status st_ = (call);                                                        \
    if (st_ != SF_OK) {                                                            \
      fprintf(stderr, "%s: %s: %s\n", #call, sf_status_name(st_), (handle_error)); \
      return 1;                                                                    \
    }                                                                              \
  } while (0)

int main(int argc, char** argv) {
  if (argc != 2) {
    fprintf(stderr, "usage: %s MESH\n", argv[0]);
    return 2;
  }
  printf("SmoothForce %s (C API)\n", sf_version());

  /* 1. A cache from a mesh file: read, checked, normals, every patch built (oneTBB). */
  sf_cache_options copt;
  sf_cache_options_init(&copt);
  sf_cache* cache = NULL;
  CHECK(sf_cache_from_file(argv[1], &copt, &cache), sf_last_error());
  printf("cache: %d faces, %d vertices\n", sf_cache_num_faces(cache), sf_cache_num_vertices(cache));

  /* 2. A force trace: 101 HIPs along face 0's patch (xi from -0.5 to 0.5), 5 mm inside. */
  enum { N = 101 };
  int32_t faces[N];
  double xi[N], eta[N], pos[3 * N], nrm[3 * N], hips[3 * N];
  uint32_t status[N];
  for (int i = 0; i < N; ++i) {
    faces[i] = 0;
    xi[i] = -0.5 + i / (double)(N - 1);
    eta[i] = 0;
  }
  CHECK(sf_cache_evaluate(cache, N, faces, xi, eta, pos, nrm, status), sf_cache_error(cache));
  for (int i = 0; i < 3 * N; ++i) hips[i] = pos[i] - 0.005 * nrm[i];
  sf_haptic_options hopt;
  sf_haptic_options_init(&hopt);
  hopt.stiffness = 500; /* N/m */
  sf_step_result trace[N];
  CHECK(sf_cache_trace(cache, &hopt, N, hips, trace), sf_cache_error(cache));
  int contacts = 0;
  double maxJump = 0, fmin = 1e30, fmax = 0;
  for (int i = 0; i < N; ++i) {
    const double* f = trace[i].force;
    const double mag = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    contacts += trace[i].contact;
    if (mag < fmin) fmin = mag;
    if (mag > fmax) fmax = mag;
    if (i > 0) {
      const double* g = trace[i - 1].force;
      const double d =
          sqrt((f[0] - g[0]) * (f[0] - g[0]) + (f[1] - g[1]) * (f[1] - g[1]) + (f[2] - g[2]) * (f[2] - g[2]));
      if (d > maxJump) maxJump = d;
    }
  }
  printf("trace: %d of %d steps in contact, |F| %.4f .. %.4f N, largest step-to-step change %.4f N\n", contacts, N,
         fmin, fmax, maxJump);

  /* The same trace with the model final step (one patch evaluation fewer per tracking step):
   * the steps that ended on the refinement's model carry SF_ST_MODEL_POINT. */
  hopt.final_step = "model";
  sf_step_result model[N];
  CHECK(sf_cache_trace(cache, &hopt, N, hips, model), sf_cache_error(cache));
  hopt.final_step = NULL;
  int modelPoints = 0, sameContacts = 1;
  double maxDiff = 0;
  for (int i = 0; i < N; ++i) {
    modelPoints += (model[i].status & SF_ST_MODEL_POINT) != 0;
    sameContacts &= model[i].contact == trace[i].contact;
    for (int a = 0; a < 3; ++a) {
      const double d = fabs(model[i].force[a] - trace[i].force[a]);
      if (d > maxDiff) maxDiff = d;
    }
  }
  printf("trace, final_step model: %d of %d steps end on a model point, forces within %.2e N\n", modelPoints, N,
         maxDiff);

  /* 3. The servo step from the caller's own 1 kHz loop (a device SDK callback): HIP in,
   *    force (after the safety layer: clamp, rate limit, ramp-in) out. */
  sf_haptic* haptic = NULL;
  CHECK(sf_haptic_create(cache, &hopt, &haptic), sf_last_error());
  sf_cache_free(cache); /* the haptic keeps what it needs */
  double maxForce = 0;
  int inContact = 0, steps = 2000;
  for (int k = 0; k < steps; ++k) {
    const double t = k * 1e-3; /* s, the caller's clock */
    const double* h = &hips[3 * (k % N)];
    sf_step_result r;
    CHECK(sf_haptic_step(haptic, h, t, &r), sf_haptic_error(haptic));
    const double mag = sqrt(r.force[0] * r.force[0] + r.force[1] * r.force[1] + r.force[2] * r.force[2]);
    if (mag > maxForce) maxForce = mag;
    inContact += r.contact;
  }
  printf("servo: %d steps, %d in contact, largest commanded force %.4f N (limit 3.3)\n", steps, inContact, maxForce);
  sf_haptic_free(haptic);

  /* 4. Errors: a code and a message naming the element; nothing thrown. */
  const double positions[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const int32_t offsets[] = {0, 3};
  const int32_t bad[] = {0, 1, 7};
  sf_cache* none = NULL;
  const sf_status st = sf_cache_from_arrays(positions, 3, offsets, 1, bad, NULL, 0, NULL, &none);
  printf("bad arrays: %s: %s\n", sf_status_name(st), sf_last_error());

  const int ok = contacts == N && sameContacts && modelPoints > 0 && maxDiff < 1e-6 && inContact == steps &&
                 maxForce <= 3.3 + 1e-9 && st == SF_ERROR_INPUT && !none &&
                 strstr(sf_last_error(), "vertex index 7 out of range") != NULL;
  printf("example_c: %s\n", ok ? "OK" : "FAILED");
  return ok ? 0 : 1;
}
