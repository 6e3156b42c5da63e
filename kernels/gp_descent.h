/* SPDX-License-Identifier: Apache-2.0 */
/* The paper's descent (Wu et al., Section 4.2, Fig. 8; RefineMethod::PaperDescent): the second
 * nearest-point refinement, beside gp_refine.h's Newton method, whose cache view, iterate,
 * evaluation, residual and tolerance it shares. Compiled as OpenCL C (refine.cl) and as C++
 * (host/patch detail/gp_math.h; host/query/patch_refine.cpp wraps it). Part of the
 * single-source math; include after gp_refine.h; no include guard on purpose.
 *
 * Direction: -grad f from central differences of |G - HIP|^2 (positions only, 4 evaluations
 * around the iterate, moved inward so that they stay in the domain). Step length: the paper's
 * Fig. 8 is not reproduced exactly; the step moves G, along the numerical tangent G_d of the
 * direction d, to the foot of the perpendicular from the HIP (alpha = -(r . G_d) / |G_d|^2),
 * capped at GP_RD_RADIUS domain units, halved until gp_rd_better accepts it (at most 40 times).
 * An iterate leaving the domain crosses domain edge k at I0 on the ray from the origin and goes
 * on at I1 = C_i + s (C_{i+1} - C_i) on the neighbour (Eq. 15 as printed: the rest of the step
 * is dropped); on a boundary or non-manifold edge it stays at the edge's nearest point. The
 * finite-difference step and the noise of positions are those of the cache's records
 * (gp_refine_mesh.floatRecords): a float cache's evaluations round as float even where this
 * runs in double. */
#undef GP_RD_RADIUS
#define GP_RD_RADIUS GP_R(0.5) /* domain units (circumradius 1): the longest step */

/* The descent's evaluation of face f at (x, y): the host's evalNative hook, else gp_rf_eval. */
GP_FN gp_eval_result gp_rd_eval(const gp_refine_mesh* m, gp_refine_work* w, int f, GP_REAL x, GP_REAL y) {
#ifndef GP_OPENCL
  if (m->evalNative) return m->evalNative(m->nativeUser, f, x, y);
#endif
  return gp_rf_eval(m, w, f, x, y);
}

GP_FN gp_rf_iterate gp_rd_at(const gp_refine_mesh* m, gp_refine_work* w, int f, GP_REAL x, GP_REAL y, gp_vec3 hip) {
  return gp_rf_with(f, x, y, gp_rd_eval(m, w, f, x, y), hip);
}

/* Converged: the tangential residual (gp_rf_residual) within gp_rf_tolerance, or within the
 * noise of the records' positions (posNoise, m) for float records. */
GP_FN int gp_rd_converged(const gp_refine_mesh* m, const gp_refine_work* w, const gp_rf_iterate* it, gp_vec3 hip,
                          GP_REAL posNoise) {
  GP_REAL tol = gp_rf_tolerance(m, w, gp_len(it->r), hip);
  if (m->floatRecords && posNoise > tol) tol = posNoise;
  return gp_rf_residual(m, it) <= tol;
}

/* Step acceptance: f decreases; or it stays within its evaluation noise and the step crossed
 * onto the neighbour (it lands on the shared edge, often at the same 3-D point: taken, so that
 * the next step is computed in the neighbour's domain instead of stalling against the edge); or,
 * neither iterate held on an edge, it stays within that noise while the angle between G - HIP
 * and the normal shrinks (else float caches' noise would stall the descent early). */
GP_FN int gp_rd_better(const gp_rf_iterate* trial, const gp_rf_iterate* cur, GP_REAL posNoise) {
  if (trial->f < cur->f) return 1;
  const GP_REAL noise = GP_SQRT(GP_R(2.0) * cur->f) * posNoise + posNoise * posNoise + GP_R(1.0e-13) * cur->f;
  if (trial->face != cur->face && trial->f <= cur->f + noise) return 1;
  if (!(trial->f <= cur->f + noise) || trial->edge >= 0 || cur->edge >= 0) return 0;
  return gp_len(gp_cross(trial->r, trial->p.normal)) / gp_len(trial->r) <
         gp_len(gp_cross(cur->r, cur->p.normal)) / gp_len(cur->r);
}

/* Eq. 15 as printed for an (x, y) outside face *f's domain: onto the neighbour across the edge
 * the ray from the origin leaves by (*transitions + 1), or onto that edge's nearest point when
 * it is a boundary, non-manifold or unusable (*edge set, GP_TRACK_BOUNDARY in *st). */
GP_FN void gp_rd_transfer(const gp_refine_mesh* m, int* f, GP_REAL* x, GP_REAL* y, int* edge, int* transitions,
                          gp_uint* st) {
  *edge = -1;
  const int n = gp_rf_size(m, *f);
  int k;
  const GP_REAL mx = gp_dom_edge_max(n, *x, *y, &k GP_DT_M(m)), c = gp_dom_apothem(n GP_DT_M(m));
  if (!(mx > c)) return;
  const GP_REAL ix = *x * (c / mx), iy = *y * (c / mx); /* I0: the ray from the origin meets edge k */
  GP_REAL ax, ay, bx, by;
  gp_domain_corner(n, k, &ax, &ay GP_DT_M(m));
  gp_domain_corner(n, (k + 1) % n, &bx, &by GP_DT_M(m));
  GP_REAL s = GP_SQRT((ix - bx) * (ix - bx) + (iy - by) * (iy - by)) /
              GP_SQRT((ax - bx) * (ax - bx) + (ay - by) * (ay - by)); /* |I0 - C_{k+1}| / |C_k - C_{k+1}| */
  s = s < GP_R(0.0) ? GP_R(0.0) : (s > GP_R(1.0) ? GP_R(1.0) : s);
  const int twin = m->slotTwin[m->faceOffsets[*f] + k];
  const int g = twin >= 0 ? gp_rf_slot_face(m, twin) : -1;
  if (g < 0 || !gp_rf_evaluable(m, g)) { /* stay on the edge, at its nearest point in the domain */
    gp_dom_edge_point(n, k, gp_dom_edge_param(n, k, *x, *y GP_DT_M(m)), x, y GP_DT_M(m));
    gp_dom_clamp(n, x, y GP_DT_M(m));
    *edge = k;
    *st |= GP_TRACK_BOUNDARY;
    return;
  }
  const int ng = gp_rf_size(m, g);
  gp_dom_edge_point(ng, twin - m->faceOffsets[g], s, x, y GP_DT_M(m));
  gp_dom_clamp(ng, x, y GP_DT_M(m));
  *f = g;
  *transitions += 1;
}

/* One descent step from *cur (see above); returns 1 when it stalled (no direction, or no step
 * of the 40 halvings accepted), *cur unchanged then. eps: the finite-difference step. */
GP_FN int gp_rd_step(const gp_refine_mesh* m, gp_refine_work* w, gp_rf_iterate* cur, gp_vec3 hip, GP_REAL eps,
                     GP_REAL posNoise, int* transitions, gp_uint* status) {
  const int n = gp_rf_size(m, cur->face);
  GP_REAL xc = cur->x, yc = cur->y;
  gp_dom_interior(n, &xc, &yc, eps GP_DT_M(m));
  const gp_vec3 gxp = gp_rd_eval(m, w, cur->face, xc + eps, yc).pos,
                gxm = gp_rd_eval(m, w, cur->face, xc - eps, yc).pos;
  const gp_vec3 gyp = gp_rd_eval(m, w, cur->face, xc, yc + eps).pos,
                gym = gp_rd_eval(m, w, cur->face, xc, yc - eps).pos;
  const gp_vec3 rxp = gp_sub(gxp, hip), rxm = gp_sub(gxm, hip), ryp = gp_sub(gyp, hip), rym = gp_sub(gym, hip);
  const GP_REAL e2 = GP_R(2.0) * eps;
  const GP_REAL dx = -((gp_dot(rxp, rxp) - gp_dot(rxm, rxm)) / e2), dy = -((gp_dot(ryp, ryp) - gp_dot(rym, rym)) / e2);
  const GP_REAL dn = GP_SQRT(dx * dx + dy * dy);
  if (!(dn > GP_R(0.0) && dn <= GP_BIG)) return 1;
  /* tangent of G along d from the same differences; step to the foot of the HIP on it */
  const gp_vec3 t = gp_add(gp_scale(gp_sub(gxp, gxm), dx), gp_scale(gp_sub(gyp, gym), dy));
  const gp_vec3 gd = gp_v3(t.x / e2, t.y / e2, t.z / e2);
  GP_REAL alpha = -gp_dot(cur->r, gd) / gp_dot(gd, gd);
  if (!(alpha > GP_R(0.0) && alpha <= GP_BIG)) alpha = GP_RD_RADIUS / dn;
  GP_REAL sx = alpha * dx, sy = alpha * dy;
  const GP_REAL sl = GP_SQRT(sx * sx + sy * sy);
  if (sl > GP_RD_RADIUS) {
    const GP_REAL q = GP_RD_RADIUS / sl;
    sx *= q;
    sy *= q;
  }
  for (int halving = 0; halving < 40; ++halving, sx *= GP_R(0.5), sy *= GP_R(0.5)) {
    int face = cur->face, tr = 0, edge = -1;
    gp_uint st = 0u;
    GP_REAL x = cur->x + sx, y = cur->y + sy;
    if (!gp_dom_inside(n, x, y GP_DT_M(m))) gp_rd_transfer(m, &face, &x, &y, &edge, &tr, &st);
    gp_rf_iterate trial = gp_rd_at(m, w, face, x, y, hip);
    trial.edge = edge;
    if (gp_rd_better(&trial, cur, posNoise)) {
      *cur = trial;
      *transitions += tr;
      *status = (*status & ~GP_TRACK_BOUNDARY) | st;
      return 0;
    }
  }
  return 1;
}

/* Refines from (face, xi, eta) (clamped into the domain; startEdge: the domain edge the start
 * is held on, -1 for none) towards the patch point nearest `hip` (m) by the paper's descent.
 * The same stopping rule as gp_refine_newton's residual test (without its held-edge KKT and
 * singular-point tests), the same result fields (startMinimum 0) and status bits (CONVERGED,
 * MAX_ITER, STALLED, BOUNDARY, DEGENERATE). Uses w for its records only: a Newton refinement's
 * warm state in w stays as it was. */
GP_FN gp_refine_result gp_refine_descent(const gp_refine_mesh* m, gp_refine_work* w, gp_vec3 hip, int face, GP_REAL xi,
                                         GP_REAL eta, int startEdge, const gp_refine_options* o) {
  const GP_REAL eps = m->floatRecords ? GP_R(1.0e-3) : GP_R(1.0e-6);
  const GP_REAL posNoise = (m->floatRecords ? GP_R(1.0e-6) : GP_R(1.0e-14)) * m->scale;
  gp_refine_result out;
  if (!gp_rf_begin(m, w, hip, face, xi, eta, o, &out)) return out;
  const int n0 = gp_rf_size(m, face);
  gp_dom_clamp(n0, &xi, &eta GP_DT_M(m));
  gp_rf_iterate cur = gp_rd_at(m, w, face, xi, eta, hip);
  cur.edge = startEdge >= 0 && startEdge < n0 ? startEdge : -1;
  if (!(cur.f < GP_BIG)) {
    out.status = GP_TRACK_DEGENERATE | cur.p.status;
    return out;
  }
  gp_uint status = 0u;
  int conv = 0, stalled = 0, it = 0;
  for (; it < o->maxIterations; ++it) {
    if ((conv = gp_rd_converged(m, w, &cur, hip, posNoise))) break;
    if ((stalled = gp_rd_step(m, w, &cur, hip, eps, posNoise, &out.transitions, &status))) break;
  }
  if (!conv) conv = gp_rd_converged(m, w, &cur, hip, posNoise);
  if (cur.edge >= 0) status |= GP_TRACK_BOUNDARY;
  status |= conv ? GP_TRACK_CONVERGED : (stalled ? GP_TRACK_STALLED : GP_TRACK_MAX_ITER);
  gp_rf_finish(&cur, it, status, &out);
  return out;
}
