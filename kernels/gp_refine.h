/* SPDX-License-Identifier: Apache-2.0 */
/* Nearest-point refinement on the patches (paper Section 4.2) with Eq. 15 transitions (design
 * page, "Leaving the domain"): the one definition of the Newton refinement, and what the paper's
 * descent (gp_descent.h) shares with it, compiled as OpenCL C (refine.cl) and as C++
 * (host/patch detail/gp_math.h; host/query/patch_refine.cpp wraps them).
 *
 * Minimises f(X) = |G(X) - HIP|^2 / 2 over the patch surface by a trust-region Newton method:
 * - model: gradient g = J^T r (exact), Hessian B = J^T J + sum_i r_i d2G_i, the second-order part
 *   by forward differences of the exact first derivatives (2 extra evaluations);
 * - the trust region is measured in metres on the surface: |J s| <= Delta (the metric J^T J), so it
 *   means the same on patches of any size and across patch edges; the 2x2 subproblem is solved
 *   exactly (eigen-decomposition, secular equation), so indefinite models are handled;
 * - a step is accepted when the actual decrease of f is at least 1% of the model's (ratio test;
 *   computed as (G_c - G_t) . (r_c + r_t) / 2, without cancellation), or, where the model's
 *   decrease is at the evaluation noise of f, when it is a full Newton step of a convex model
 *   that does not increase f beyond that noise. Every accepted step decreases f (up to noise),
 *   and with a bounded model Hessian the iterates converge to a stationary point (Nocedal &
 *   Wright, Numerical Optimization, Thm. 4.5-4.6);
 * - a step that leaves the domain through edge k stops at the exit point I0, which Eq. 15 maps to
 *   I1 on the neighbour (the same surface point: the edge parameter is linear along a domain
 *   side); the rest of the step continues in the neighbour's domain as the same 3-D
 *   displacement (least squares through the neighbour's Jacobian at I1), crossing again if
 *   needed (vertices of any valence, up to GP_RF_MAX_CROSS crossings per step);
 * - on a boundary or non-manifold edge the iterate stops at the exit point and is held there;
 *   held, it moves by 1-D Newton along the edge until it is stationary along the edge, and is
 *   released when the free step points back inside.
 * Converged when the tangential residual (|r x n|, or |r . G_e| / |G_e| along a held edge) is at
 * most min(sin(angleTol) |r|, positionTol), or at most the evaluation noise of positions
 * (64 eps times the coordinate magnitude), and, on a held edge, f does not decrease into the
 * face faster than that tolerance (a KKT point of the held problem: the iterate of a tracker
 * whose HIP moved back over the face leaves the edge); at a singular point of the patch (a fold line, where
 * r lies along no normal), also when the point is a strict local minimum of the model whose
 * Newton step would decrease f by at most that tolerance squared over 2 (gp_rf_stationary).
 *
 * Memory: the cache arrays are read through GP_GLOBAL pointers (gp_refine_mesh), because the
 * iterate changes face while it runs; on the host a loader hook may supply the records instead
 * (lazy construction, float records widened to double). Everything else is private. Part of the
 * single-source math; include after gp_patch.h and gp_domain.h; no include guard on purpose. */

#undef GP_RF_FD_EPS
#undef GP_RF_TINY
#undef GP_RF_MAX_CROSS
#if GP_IS_DOUBLE
#define GP_RF_FD_EPS GP_R(1.0e-6) /* finite-difference step in the domain */
#define GP_RF_TINY GP_R(1.0e-300)
#else
#define GP_RF_FD_EPS GP_R(1.0e-3)
#define GP_RF_TINY GP_R(1.0e-37)
#endif
#define GP_RF_MAX_CROSS 8
#undef GP_RF_CREASE_COS
#define GP_RF_CREASE_COS GP_R(0.99995) /* normals more than 0.01 rad apart across an edge: a crease */
#undef GP_RF_EDGE_NEAR
#define GP_RF_EDGE_NEAR (GP_R(1024.0) * GP_EPS) /* domain distance (1-norm) at which an iterate is on an edge */
#undef GP_RF_D2_REUSE
/* Second derivatives are taken again once the iterate is this far (domain units, per coordinate;
 * the domain's circumradius is 1) from where they were taken, or on another face: lagged ones
 * perturb the model by O(lag x |G - HIP|), which slows the local convergence only by a factor of
 * that order (the Newton error is multiplied by it), while saving the two evaluations. */
#define GP_RF_D2_REUSE GP_R(0.01)
/* ... and after a step that reused them without the model predicting the decrease to within
 * this fraction (|rho - 1|: a lagged model that is off slows the convergence by about that
 * factor), after a rejected step, and after GP_RF_D2_MAX_USES steps in a row. */
#undef GP_RF_D2_RHO
#define GP_RF_D2_RHO GP_R(0.1)
#undef GP_RF_D2_MAX_USES
#define GP_RF_D2_MAX_USES 3
#undef GP_RF_MODEL_STEP
/* With gp_refine_options.modelFinal, a step predicted to converge that stays on its face, moves at
 * most this far (domain units, per coordinate) and starts where its second differences were
 * taken takes its trial point from the model instead of evaluating the patch: the model's error
 * is O(|G'''| |s|^3) in the position and O(|G'''| |s|^2) in the derivatives. */
#define GP_RF_MODEL_STEP GP_R(1.0e-4)
#undef GP_RF_AT_ONCE
#define GP_RF_AT_ONCE (GP_R(64.0) * GP_EPS) /* an exit this early in a step leaves from where it is */

/* The cache as the refinement reads it. Counts: #F faces, #C slots (corners). */
typedef struct {
  GP_GLOBAL const int* faceOffsets;    /* #F+1 */
  GP_GLOBAL const GP_REAL* edgeData;   /* GP_E_NFIELDS * #C, field-major [field * #C + slot] */
  GP_GLOBAL const gp_uint* faceStatus; /* #F, GP_ST_* */
  GP_GLOBAL const int* slotTwin;       /* #C: twin slot, or < 0 (boundary / non-manifold) */
  GP_GLOBAL const int* slotFace;       /* #C: face owning each slot; 0: found by binary search */
  int numFaces, numSlots, mode;        /* mode: GP_CT_* */
  GP_REAL scale;                       /* bounding-box diagonal of the mesh, m */
  /* 1: the cache's records are float's (its evaluations round as float): the paper's descent
   * takes its finite-difference step and position noise from that precision, not GP_REAL's */
  int floatRecords;
#ifdef GP_OPENCL
  /* the host's domain table (gp_tables.h GP_DOMAIN_FLAT_OFFSET; GP_DT_M passes it on) */
  __global const GP_REAL* domainTable;
#else
  /* Host only: when set, face records come from here instead of edgeData/faceStatus. Writes
   * face f's n records (record-major) to recs, or only reports when recs is null; returns the
   * face's GP_ST_* bits (GP_ST_TOO_MANY_SIDES when it has no patch). */
  gp_uint (*load)(void* user, int f, GP_REAL* recs);
  void* user;
  /* Host only: when set, evaluates count (1..4) points of face f at once (a point, or a point
   * and its finite differences; SIMD lanes, the same bits as gp_patch_eval on the face's records,
   * whether they come from `load` or edgeData) into out[0..count). Every evaluation of the Newton
   * refinement goes through it. */
  void (*evalPoints)(void* pointsUser, int f, const GP_REAL* x, const GP_REAL* y, int count, gp_eval_result* out);
  void* pointsUser;
  /* Host only: when set, the paper's descent evaluates face f at (x, y) through it instead of
   * gp_rf_eval: in the records' own precision (a float cache in float), its status with the
   * face's GP_ST_* bits. */
  gp_eval_result (*evalNative)(void* nativeUser, int f, GP_REAL x, GP_REAL y);
  void* nativeUser;
#endif
} gp_refine_mesh;

/* What one refinement leaves for the next (a warm start): the second differences of the last
 * finite-difference evaluation (reused within GP_RF_D2_REUSE of their point on the same face)
 * and the final point with its evaluation (a start from exactly there reuses it). A copy of it
 * restores that state (the host keeps a seed's this way). */
typedef struct {
  int d2Face;               /* face of the differences below, -1 for none */
  int d2Uses;               /* steps that reused them since they were taken */
  GP_REAL d2x, d2y;         /* their domain point */
  gp_vec3 d2xx, d2yy, d2xy; /* eps G_xx, eps G_yy, 2 eps G_xy: differences of exact first derivatives */
  /* estimate of |G'''| (m per domain unit^3) from these and the differences taken before them on
   * the same face (the change of the second derivatives between the two points); -1 unknown
   * (or not wanted: gp_refine_options.modelFinal 0) */
  GP_REAL g3;
  int lastFace;             /* face of the last refinement's final point, -1 for none */
  GP_REAL lastX, lastY;
  gp_eval_result lastP;
} gp_refine_kept;

/* Private scratch: the records of the face last loaded, what the last refinement left (kept),
 * and this refinement's step bookkeeping. */
typedef struct {
  int loaded; /* face held in recs, -1 for none */
  gp_uint loadedStatus;
  GP_REAL recs[GP_MAX_N * GP_E_NFIELDS];
  gp_refine_kept kept;
  GP_REAL lastLen;  /* m: |J s| of the last accepted step of this refinement, 0 for none */
  GP_REAL tol;      /* m: this refinement's position tolerance */
  GP_REAL sinAngle; /* sin(sinOf): the sine of the angle tolerance, computed once per tolerance */
  GP_REAL sinOf;    /* the tolerance it is for; NaN before the first refinement (zeroed work: sin 0 = 0) */
  int modelFinal;   /* this refinement's gp_refine_options.modelFinal */
} gp_refine_work;

/* Stopping rules (see the file comment). */
typedef struct {
  int maxIterations;   /* >= 0 (0: the start is evaluated and tested only) */
  GP_REAL angleTol;    /* rad */
  GP_REAL positionTol; /* m: tangential residual allowed */
  /* 1: the trial point of a converging step may come from the model (GP_RF_MODEL_STEP; the
   * point then carries GP_ST_MODEL_POINT); 0: every point is evaluated */
  int modelFinal;
} gp_refine_options;

/* One refinement's result (the fields of host RefineResult). */
typedef struct {
  gp_vec3 scp, normal; /* m; unit outward normal */
  GP_REAL xi, eta;     /* domain point of `face` */
  GP_REAL distance;    /* |SCP - HIP|, m */
  int face, edge;      /* edge: domain edge the SCP is held on (boundary), else -1 */
  int iterations, transitions;
  gp_uint status; /* GP_TRACK_* | GP_ST_* of the final point */
  /* 1: converged at its start, not held on an edge, and a strict local minimum there (the
   * model Hessian J^T J + sum r_i d2G_i, second differences taken at the start, positive
   * definite): a start on the HIP's normal line that is no saddle or maximum of the distance */
  int startMinimum;
} gp_refine_result;

typedef struct {
  int face, edge;
  GP_REAL x, y;
  gp_eval_result p;
  gp_vec3 r; /* G - HIP */
  GP_REAL f; /* |G - HIP|^2 / 2; GP_BIG when not evaluable */
} gp_rf_iterate;

GP_FN int gp_rf_size(const gp_refine_mesh* m, int f) { return m->faceOffsets[f + 1] - m->faceOffsets[f]; }

/* Face owning a slot. */
GP_FN int gp_rf_slot_face(const gp_refine_mesh* m, int slot) {
  if (m->slotFace) return m->slotFace[slot];
  int lo = 0, hi = m->numFaces;
  while (hi - lo > 1) {
    const int mid = (lo + hi) / 2;
    if (m->faceOffsets[mid] <= slot)
      lo = mid;
    else
      hi = mid;
  }
  return lo;
}

/* GP_ST_* bits of face f (GP_ST_TOO_MANY_SIDES when out of range or not 3..GP_MAX_N sided). */
GP_FN gp_uint gp_rf_face_status(const gp_refine_mesh* m, int f) {
  if (f < 0 || f >= m->numFaces) return GP_ST_TOO_MANY_SIDES;
  const int n = gp_rf_size(m, f);
  if (n < 3 || n > GP_MAX_N) return GP_ST_TOO_MANY_SIDES;
#ifndef GP_OPENCL
  if (m->load) return m->load(m->user, f, 0);
#endif
  return m->faceStatus[f];
}

GP_FN int gp_rf_evaluable(const gp_refine_mesh* m, int f) { return !(gp_rf_face_status(m, f) & GP_ST_NOT_BUILT); }

/* Patch f at (x, y), loading its records when another face's are held. f must be evaluable.
 * With the host's evalPoints hook, one point of it: the same bits, about two thirds of the
 * scalar instantiation's time per point on x86 SIMD (the hook keeps the face's records as
 * vectors across the refinement's calls). */
GP_FN gp_eval_result gp_rf_eval(const gp_refine_mesh* m, gp_refine_work* w, int f, GP_REAL x, GP_REAL y) {
#ifndef GP_OPENCL
  if (m->evalPoints) {
    gp_eval_result e;
    m->evalPoints(m->pointsUser, f, &x, &y, 1, &e);
    return e;
  }
#endif
  const int n = gp_rf_size(m, f);
  if (w->loaded != f) {
#ifndef GP_OPENCL
    if (m->load) {
      w->loadedStatus = m->load(m->user, f, w->recs);
    } else
#endif
    {
      const int first = m->faceOffsets[f];
      for (int k = 0; k < n; ++k)
        for (int i = 0; i < GP_E_NFIELDS; ++i)
          w->recs[k * GP_E_NFIELDS + i] = m->edgeData[(size_t)i * (size_t)m->numSlots + (size_t)(first + k)];
      w->loadedStatus = m->faceStatus[f];
    }
    w->loaded = f;
  }
  gp_eval_result r = gp_patch_eval(n, w->recs, gp_eval_mode(m->mode, w->loadedStatus), x, y GP_DT_M(m));
  r.status |= w->loadedStatus;
  return r;
}

/* Patch f at (x[0], y[0]) and (x[1], y[1]) into out[0..2): gp_rf_eval twice, or the host's
 * evalPoints hook. */
GP_FN void gp_rf_eval_pair(const gp_refine_mesh* m, gp_refine_work* w, int f, const GP_REAL* x, const GP_REAL* y,
                           gp_eval_result* out) {
#ifndef GP_OPENCL
  if (m->evalPoints) {
    m->evalPoints(m->pointsUser, f, x, y, 2, out);
    return;
  }
#endif
  out[0] = gp_rf_eval(m, w, f, x[0], y[0]);
  out[1] = gp_rf_eval(m, w, f, x[1], y[1]);
}

/* The iterate at (f, x, y) whose evaluation there is p. */
GP_FN gp_rf_iterate gp_rf_with(int f, GP_REAL x, GP_REAL y, gp_eval_result p, gp_vec3 hip) {
  gp_rf_iterate it;
  it.face = f;
  it.edge = -1;
  it.x = x;
  it.y = y;
  it.p = p;
  it.r = gp_sub(it.p.pos, hip);
  it.f = GP_BIG;
  if (!(it.p.status & (GP_ST_OUTSIDE | GP_ST_TOO_MANY_SIDES)) && gp_finite3(it.p.pos)) {
    const GP_REAL f2 = GP_R(0.5) * gp_dot(it.r, it.r);
    if (f2 < GP_BIG) it.f = f2;
  }
  return it;
}

GP_FN gp_rf_iterate gp_rf_at(const gp_refine_mesh* m, gp_refine_work* w, int f, GP_REAL x, GP_REAL y, gp_vec3 hip) {
  return gp_rf_with(f, x, y, gp_rf_eval(m, w, f, x, y), hip);
}

/* The estimate of |G'''| (m per domain unit^3) from new second differences (xx, yy, xy) of face
 * f at (xc, yc) and the ones kept (k): |H_new - H_old| / |X_new - X_old| with H = d2 / eps, or
 * -1 where the kept ones are of another face or of the same point. */
GP_FN GP_REAL gp_rf_g3(const gp_refine_kept* k, int f, GP_REAL xc, GP_REAL yc, gp_vec3 xx, gp_vec3 yy, gp_vec3 xy) {
  if (k->d2Face != f) return GP_R(-1.0);
  const GP_REAL dl = gp_max(GP_FABS(xc - k->d2x), GP_FABS(yc - k->d2y));
  if (!(dl > GP_R(0.0))) return GP_R(-1.0);
  const GP_REAL dh = gp_max(gp_max(gp_len(gp_sub(xx, k->d2xx)), gp_len(gp_sub(yy, k->d2yy))),
                            GP_R(0.5) * gp_len(gp_sub(xy, k->d2xy)));
  const GP_REAL g3 = dh / (GP_RF_FD_EPS * dl);
  return g3 < GP_BIG ? g3 : GP_R(-1.0);
}

/* Stores the second differences of face f at (xc, yc) from the evaluations there (pc) and at
 * (xc + eps, yc), (xc, yc + eps) (p1, p2), with the |G'''| estimate where modelFinal wants it. */
GP_FN void gp_rf_store_d2(gp_refine_work* w, int f, GP_REAL xc, GP_REAL yc, const gp_eval_result* pc,
                          const gp_eval_result* p1, const gp_eval_result* p2) {
  const gp_vec3 xx = gp_sub(p1->dxi, pc->dxi), yy = gp_sub(p2->deta, pc->deta);
  const gp_vec3 xy = gp_add(gp_sub(p1->deta, pc->deta), gp_sub(p2->dxi, pc->dxi));
  w->kept.g3 = w->modelFinal ? gp_rf_g3(&w->kept, f, xc, yc, xx, yy, xy) : GP_R(-1.0);
  w->kept.d2xx = xx;
  w->kept.d2yy = yy;
  w->kept.d2xy = xy;
  w->kept.d2Face = f;
  w->kept.d2x = xc;
  w->kept.d2y = yc;
  w->kept.d2Uses = 0;
}

/* Takes the second differences of face f at (xc, yc), whose evaluation there is pc: the pair
 * (xc + eps, yc), (xc, yc + eps), stored in w. */
GP_FN void gp_rf_take_d2(const gp_refine_mesh* m, gp_refine_work* w, int f, GP_REAL xc, GP_REAL yc,
                         const gp_eval_result* pc) {
  const GP_REAL eps = GP_RF_FD_EPS;
  const GP_REAL fx[2] = {xc + eps, xc}, fy[2] = {yc, yc + eps};
  gp_eval_result fd[2];
  gp_rf_eval_pair(m, w, f, fx, fy, fd);
  gp_rf_store_d2(w, f, xc, yc, pc, &fd[0], &fd[1]);
}

/* gp_rf_at, and the second differences that the next step from this point takes (the same
 * values; w->d2*): with the host's evalPoints hook the point and its differences in one call of
 * 3 or 4 SIMD lanes (about 1.5 single evaluations instead of 2.5), else one by one. Every
 * caller (CPU, lazy, OpenCL) thus takes the same steps with the same values. */
GP_FN gp_rf_iterate gp_rf_at_d2(const gp_refine_mesh* m, gp_refine_work* w, int f, GP_REAL x, GP_REAL y,
                                gp_vec3 hip) {
  const GP_REAL eps = GP_RF_FD_EPS;
  GP_REAL xc = x, yc = y;
  gp_dom_interior(gp_rf_size(m, f), &xc, &yc, eps GP_DT_M(m));
  const int shifted = !(xc == x && yc == y);
#ifndef GP_OPENCL
  if (m->evalPoints) {
    const GP_REAL px[4] = {x, xc + eps, xc, xc}, py[4] = {y, yc, yc + eps, yc};
    gp_eval_result e[4];
    m->evalPoints(m->pointsUser, f, px, py, shifted ? 4 : 3, e);
    gp_rf_store_d2(w, f, xc, yc, shifted ? &e[3] : &e[0], &e[1], &e[2]);
    return gp_rf_with(f, x, y, e[0], hip);
  }
#endif
  const gp_eval_result p = gp_rf_eval(m, w, f, x, y);
  const gp_eval_result pc = shifted ? gp_rf_eval(m, w, f, xc, yc) : p;
  gp_rf_take_d2(m, w, f, xc, yc, &pc);
  return gp_rf_with(f, x, y, p, hip);
}

/* Unit direction C_{k+1} - C_k of domain edge k, and its tangent J e on the surface. */
GP_FN gp_vec3 gp_rf_edge_tangent(int n, int k, const gp_eval_result* p, GP_REAL* ex, GP_REAL* ey GP_DT_PARAM) {
  GP_REAL ax, ay, bx, by;
  gp_domain_corner(n, k, &ax, &ay GP_DT_ARG);
  gp_domain_corner(n, (k + 1) % n, &bx, &by GP_DT_ARG);
  *ex = bx - ax;
  *ey = by - ay;
  return gp_add(gp_scale(p->dxi, *ex), gp_scale(p->deta, *ey));
}

/* The tangential residual: |r x n|, or along a held edge |r . G_e| / |G_e|. */
GP_FN GP_REAL gp_rf_residual(const gp_refine_mesh* m, const gp_rf_iterate* it) {
  if (it->edge >= 0) {
    GP_REAL ex, ey;
    const gp_vec3 ge = gp_rf_edge_tangent(gp_rf_size(m, it->face), it->edge, &it->p, &ex, &ey GP_DT_M(m));
    const GP_REAL gl = gp_len(ge);
    return gl > GP_R(0.0) ? GP_FABS(gp_dot(it->r, ge)) / gl : gp_len(it->r);
  }
  return gp_len(gp_cross(it->r, it->p.normal));
}

/* Largest coordinate magnitude of a point: the scale of its rounding. */
GP_FN GP_REAL gp_rf_mag(gp_vec3 a) { return gp_max(GP_FABS(a.x), gp_max(GP_FABS(a.y), GP_FABS(a.z))); }

/* The stopping tolerance (m) at an iterate whose distance to the HIP is rl: min(sin(angleTol) rl,
 * positionTol), or the evaluation noise of positions where that is larger. */
GP_FN GP_REAL gp_rf_tolerance(const gp_refine_mesh* m, const gp_refine_work* w, GP_REAL rl, gp_vec3 hip) {
  GP_REAL tol = w->sinAngle * rl; /* sin(angleTol), once per refinement */
  if (w->tol < tol) tol = w->tol;
  const GP_REAL noise = GP_R(64.0) * GP_EPS * (gp_rf_mag(hip) + m->scale);
  return gp_max(tol, noise);
}

GP_FN int gp_rf_converged(const gp_refine_mesh* m, const gp_refine_work* w, const gp_rf_iterate* it, gp_vec3 hip) {
  const GP_REAL tol = gp_rf_tolerance(m, w, gp_len(it->r), hip);
  if (!(gp_rf_residual(m, it) <= tol)) return 0;
  if (it->edge < 0) return 1;
  /* held on an edge: also a KKT point of the held problem, f not decreasing into the domain
   * faster than the tolerance allows (a HIP that moved back over the face leaves the edge; at a
   * crease whose sides meet at a valley the iterate rests on the edge while the HIP turns under
   * it, and leaves it once the HIP is under one side's interior) */
  GP_REAL ex, ey;
  const int n = gp_rf_size(m, it->face);
  (void)gp_rf_edge_tangent(n, it->edge, &it->p, &ex, &ey GP_DT_M(m));
  const gp_vec3 ju = gp_add(gp_scale(it->p.dxi, -ey), gp_scale(it->p.deta, ex)); /* J of the inward normal */
  const GP_REAL jl = gp_len(ju);
  return !(jl > GP_R(0.0)) || gp_dot(ju, it->r) >= -tol * jl;
}

/* Whether iterate it is a strict local minimum of f by the model there: B = J^T J + sum r_i d2G_i
 * positive definite, with the second differences w->d2* taken at its point (else 0). */
GP_FN int gp_rf_minimum(const gp_refine_mesh* m, const gp_refine_work* w, const gp_rf_iterate* it) {
  const GP_REAL eps = GP_RF_FD_EPS;
  GP_REAL xc = it->x, yc = it->y;
  gp_dom_interior(gp_rf_size(m, it->face), &xc, &yc, eps GP_DT_M(m));
  if (!(w->kept.d2Face == it->face && w->kept.d2x == xc && w->kept.d2y == yc)) return 0;
  const gp_vec3 r = it->r, a = it->p.dxi, b = it->p.deta;
  const GP_REAL b00 = gp_dot(a, a) + gp_dot(r, w->kept.d2xx) / eps, b11 = gp_dot(b, b) + gp_dot(r, w->kept.d2yy) / eps;
  const GP_REAL b01 = gp_dot(a, b) + GP_R(0.5) * gp_dot(r, w->kept.d2xy) / eps;
  return b00 > GP_R(0.0) && b00 * b11 - b01 * b01 > GP_R(0.0);
}

/* The trial point of the step (sx, sy) from cur on cur's face by the quadratic model there
 * (gp_refine_options.modelFinal): G + J s + s^T H s / 2, the derivatives J + H s and their unit
 * normal, H from the second differences taken at cur's point (w->kept), flagged
 * GP_ST_MODEL_POINT. Returns 0 (and *p unset) where the model may not stand in for the patch:
 * differences taken elsewhere, a step beyond GP_RF_MODEL_STEP, a point cur's evaluation flags
 * (outside, singular), a model normal that is not defined, or an estimated model error that
 * could move the tangential residual by more than half the stopping tolerance: with g3 the
 * estimate of |G'''| (w->kept.g3) and l = |sx| + |sy|, the derivatives are off by about
 * g3 l^2 / 2, the normal by that times (|G_xi| + |G_eta|) / |G_xi x G_eta|, the point by
 * g3 l^3 / 6, and the residual by |G - HIP| times the normal's error plus the point's. */
GP_FN int gp_rf_model_point(const gp_refine_work* w, const gp_rf_iterate* cur, GP_REAL sx, GP_REAL sy,
                            gp_eval_result* p) {
  if (!(w->kept.d2Face == cur->face && w->kept.d2x == cur->x && w->kept.d2y == cur->y)) return 0;
  if (!(GP_FABS(sx) <= GP_RF_MODEL_STEP && GP_FABS(sy) <= GP_RF_MODEL_STEP) || !(w->kept.g3 >= GP_R(0.0))) return 0;
  if (cur->p.status & GP_ST_NOT_A_PATCH_POINT) return 0;
  const GP_REAL ie = GP_R(1.0) / GP_RF_FD_EPS;
  /* H s per component: G_xx sx + G_xy sy and G_xy sx + G_yy sy (d2xy holds 2 eps G_xy) */
  const gp_vec3 hx = gp_add(gp_scale(w->kept.d2xx, sx * ie), gp_scale(w->kept.d2xy, GP_R(0.5) * sy * ie));
  const gp_vec3 hy = gp_add(gp_scale(w->kept.d2xy, GP_R(0.5) * sx * ie), gp_scale(w->kept.d2yy, sy * ie));
  const gp_vec3 dxi = gp_add(cur->p.dxi, hx), deta = gp_add(cur->p.deta, hy);
  const gp_vec3 nn = gp_cross(dxi, deta);
  const GP_REAL la = gp_len(dxi), lb = gp_len(deta), jmax = gp_max(la, lb), lnn = gp_len(nn);
  if (!(lnn > GP_TINY * jmax * jmax) || !gp_finite3(nn)) return 0;
  const GP_REAL l = GP_FABS(sx) + GP_FABS(sy), dj = GP_R(0.5) * w->kept.g3 * l * l;
  const GP_REAL rl = gp_len(cur->r);
  const GP_REAL err = rl * dj * (la + lb) / lnn + dj * l / GP_R(3.0);
  if (!(err <= GP_R(0.5) * gp_min(w->sinAngle * rl, w->tol))) return 0;
  p->pos = gp_add(cur->p.pos, gp_add(gp_scale(gp_madd(cur->p.dxi, hx, GP_R(0.5)), sx),
                                     gp_scale(gp_madd(cur->p.deta, hy, GP_R(0.5)), sy)));
  p->dxi = dxi;
  p->deta = deta;
  p->normal = gp_scale(nn, GP_R(1.0) / lnn);
  p->status = cur->p.status | GP_ST_MODEL_POINT;
  return 1;
}

/* s^T A s for the symmetric 2x2 A = [a00 a01; a01 a11] and s = (x, y). */
GP_FN GP_REAL gp_rf_form(GP_REAL a00, GP_REAL a01, GP_REAL a11, GP_REAL x, GP_REAL y) {
  return x * (a00 * x + a01 * y) + y * (a01 * x + a11 * y);
}

/* The model's decrease -(g.s + s^T B s / 2) for the step s = (x, y). */
GP_FN GP_REAL gp_rf_decrease(GP_REAL g0, GP_REAL g1, GP_REAL b00, GP_REAL b01, GP_REAL b11, GP_REAL x, GP_REAL y) {
  return -(g0 * x + g1 * y + GP_R(0.5) * gp_rf_form(b00, b01, b11, x, y));
}

/* Minimises g.s + s^T B s / 2 subject to s^T M s <= D^2 (2x2; M positive definite up to a
 * regularisation), exactly: Cholesky M = L L^T, z = L^T s, then the eigen-decomposition of
 * L^-1 B L^-T and the secular equation |z(lambda)| = D (bisection; the hard case included).
 * Writes s, sets *newton when s is the interior minimiser of a convex model; returns the
 * model's decrease (>= 0). */
GP_FN GP_REAL gp_rf_tr_solve(GP_REAL g0, GP_REAL g1, GP_REAL b00, GP_REAL b01, GP_REAL b11, GP_REAL m00, GP_REAL m01,
                             GP_REAL m11, GP_REAL D, GP_REAL* s0, GP_REAL* s1, int* newton) {
  *newton = 0;
  *s0 = *s1 = GP_R(0.0);
  const GP_REAL tr = m00 + m11;
  const GP_REAL reg = GP_R(16.0) * GP_EPS * tr + GP_RF_TINY;
  m00 += reg;
  m11 += reg;
  const GP_REAL l00 = GP_SQRT(m00), l10 = m01 / l00;
  GP_REAL q = m11 - l10 * l10;
  if (!(q > reg)) q = reg;
  const GP_REAL l11 = GP_SQRT(q);
  const GP_REAL i00 = GP_R(1.0) / l00, i11 = GP_R(1.0) / l11, i10 = -l10 / (l00 * l11);
  const GP_REAL h0 = g0 * i00, h1 = g0 * i10 + g1 * i11; /* L^-1 g */
  /* T = L^-1 B L^-T */
  const GP_REAL c00 = i00 * b00, c01 = i00 * b01, c10 = i10 * b00 + i11 * b01, c11 = i10 * b01 + i11 * b11;
  const GP_REAL t00 = c00 * i00, t11 = c10 * i10 + c11 * i11;
  const GP_REAL t01 = GP_R(0.5) * (c00 * i10 + c01 * i11 + c10 * i00);
  const GP_REAL mean = GP_R(0.5) * (t00 + t11), dif = GP_R(0.5) * (t00 - t11);
  const GP_REAL rad = GP_SQRT(dif * dif + t01 * t01);
  const GP_REAL mu1 = mean - rad, mu2 = mean + rad;
  GP_REAL e1x = GP_R(1.0), e1y = GP_R(0.0);
  if (rad > GP_R(0.0)) {
    const GP_REAL ax = t01, ay = mu1 - t00, bx = mu1 - t11, by = t01;
    const GP_REAL la = ax * ax + ay * ay, lb = bx * bx + by * by;
    if (la >= lb && la > GP_R(0.0)) {
      e1x = ax / GP_SQRT(la);
      e1y = ay / GP_SQRT(la);
    } else if (lb > GP_R(0.0)) {
      e1x = bx / GP_SQRT(lb);
      e1y = by / GP_SQRT(lb);
    }
  }
  const GP_REAL e2x = -e1y, e2y = e1x;
  const GP_REAL ga = e1x * h0 + e1y * h1, gb = e2x * h0 + e2y * h1;
  GP_REAL za = GP_R(0.0), zb = GP_R(0.0);
  int done = 0;
  if (mu1 > GP_R(0.0)) {
    za = -ga / mu1;
    zb = -gb / mu2;
    if (za * za + zb * zb <= D * D) {
      done = 1;
      *newton = 1;
    }
  }
  if (!done) {
    const GP_REAL lo = mu1 < GP_R(0.0) ? -mu1 : GP_R(0.0);
    const GP_REAL hl = GP_SQRT(h0 * h0 + h1 * h1);
    /* hard case: no gradient along the lowest curvature, the boundary not reached at lambda = lo */
    const GP_REAL zbl = (mu2 + lo) > GP_R(0.0) ? -gb / (mu2 + lo) : GP_R(0.0);
    if (GP_FABS(ga) <= GP_EPS * hl && mu1 <= GP_R(0.0) && zbl * zbl < D * D) {
      zb = zbl;
      za = GP_SQRT(D * D - zb * zb);
    } else {
      GP_REAL a = lo, b = lo + hl / D + GP_EPS * (GP_FABS(mu1) + GP_FABS(mu2)) + GP_R(1.0e-30);
      for (int i = 0; i < 100; ++i) { /* |z(lambda)| decreases in lambda; find |z| = D */
        const GP_REAL l = GP_R(0.5) * (a + b);
        if (!(l > a && l < b)) break;
        const GP_REAL ya = ga / (mu1 + l), yb = gb / (mu2 + l);
        if (ya * ya + yb * yb > D * D)
          a = l;
        else
          b = l;
      }
      za = -ga / (mu1 + b);
      zb = -gb / (mu2 + b);
    }
  }
  const GP_REAL pred = -(ga * za + gb * zb + GP_R(0.5) * (mu1 * za * za + mu2 * zb * zb));
  const GP_REAL w0 = za * e1x + zb * e2x, w1 = za * e1y + zb * e2y;
  *s0 = i00 * w0 + i10 * w1; /* s = L^-T z */
  *s1 = i11 * w1;
  return pred > GP_R(0.0) ? pred : GP_R(0.0);
}

/* gp_rf_tr_solve where the model is comfortably convex (B positive definite with
 * det B >= 1e-3 b00 b11: B scaled to a unit diagonal has a condition number below about 4000,
 * and Cramer's rule, unchanged by that scaling, solves it to about that many roundings) and its
 * Newton step s = -B^-1 g lies inside the region (s^T M s <= D^2): that step directly, without
 * the Cholesky factor of M, the eigenvectors and their chain of square roots and divisions
 * (about a tenth of a tracking step on the CPU). The same step up to rounding, and no less
 * accurate: the eigenvalues of L^-1 B L^-T lose the smaller one to cancellation where M is
 * badly scaled (tests/query/test_refine_solve.cpp). Elsewhere gp_rf_tr_solve. */
GP_FN GP_REAL gp_rf_newton_solve(GP_REAL g0, GP_REAL g1, GP_REAL b00, GP_REAL b01, GP_REAL b11, GP_REAL m00,
                                 GP_REAL m01, GP_REAL m11, GP_REAL D, GP_REAL* s0, GP_REAL* s1, int* newton) {
  const GP_REAL det = b00 * b11 - b01 * b01;
  if (b00 > GP_R(0.0) && det >= GP_R(1.0e-3) * (b00 * b11) && det > GP_R(0.0)) {
    const GP_REAL x0 = (b01 * g1 - b11 * g0) / det, x1 = (b01 * g0 - b00 * g1) / det;
    if (gp_rf_form(m00, m01, m11, x0, x1) <= D * D && GP_FABS(x0) + GP_FABS(x1) <= GP_BIG) {
      const GP_REAL pred = gp_rf_decrease(g0, g1, b00, b01, b11, x0, x1);
      *s0 = x0;
      *s1 = x1;
      *newton = 1;
      return pred > GP_R(0.0) ? pred : GP_R(0.0);
    }
  }
  return gp_rf_tr_solve(g0, g1, b00, b01, b11, m00, m01, m11, D, s0, s1, newton);
}

/* Moves (f, x, y) by the domain step (dx, dy) of face f, whose Jacobian there is (ja, jb):
 * across patch edges by Eq. 15 with the rest of the step carried over as the same 3-D
 * displacement; on a boundary / non-manifold edge (or an unusable neighbour) it stops at the
 * exit point with *edge set and GP_TRACK_BOUNDARY in *st; where the carried step points straight
 * back out of the neighbour through the edge it came in by (the surface folds back over the
 * edge), it stops on that edge of the neighbour with *edge set and GP_TRACK_FOLD_EDGE. */
GP_FN void gp_rf_move(const gp_refine_mesh* m, gp_refine_work* w, int* f, GP_REAL* x, GP_REAL* y, GP_REAL dx,
                      GP_REAL dy, gp_vec3 ja, gp_vec3 jb, int* edge, int* transitions, gp_uint* st) {
  *edge = -1;
  int from = -1; /* edge of *f we entered through */
  for (int c = 0;; ++c) {
    const int n = gp_rf_size(m, *f);
    int k;
    const GP_REAL tau = gp_dom_exit(n, *x, *y, dx, dy, &k GP_DT_M(m));
    if (!(tau < GP_R(1.0))) { /* stays inside */
      *x += dx;
      *y += dy;
      return;
    }
    const GP_REAL ix = *x + tau * dx, iy = *y + tau * dy;
    const GP_REAL t = gp_dom_edge_param(n, k, ix, iy GP_DT_M(m));
    const int twin = m->slotTwin[m->faceOffsets[*f] + k];
    const int g = twin >= 0 ? gp_rf_slot_face(m, twin) : -1;
    const int blocked = g < 0 || !gp_rf_evaluable(m, g);
    /* a straight step that entered the convex domain through edge `from` cannot leave through it:
     * when it does, the carried direction points back out (the surface folds back over the edge) */
    const int folded = k == from;
    if (blocked || folded || c == GP_RF_MAX_CROSS) {
      gp_dom_edge_point(n, k, t, x, y GP_DT_M(m)); /* stop on the edge, held there when it cannot be crossed */
      if (blocked || folded) {
        *edge = k;
        *st |= blocked ? GP_TRACK_BOUNDARY : GP_TRACK_FOLD_EDGE;
      }
      return;
    }
    const int ng = gp_rf_size(m, g), i = twin - m->faceOffsets[g];
    GP_REAL gx, gy;
    gp_dom_edge_point(ng, i, GP_R(1.0) - t, &gx, &gy GP_DT_M(m));
    gp_dom_off_corner(ng, &gx, &gy);
    const GP_REAL rx = (GP_R(1.0) - tau) * dx, ry = (GP_R(1.0) - tau) * dy;
    const gp_vec3 D = gp_add(gp_scale(ja, rx), gp_scale(jb, ry));
    const gp_eval_result pe = gp_rf_eval(m, w, g, gx, gy);
    if (c == 0 && tau > GP_RF_AT_ONCE && GP_FABS(ix - *x) + GP_FABS(iy - *y) > GP_RF_EDGE_NEAR) {
      /* a step from inside the face that leaves it across a crease (the two sides' normals apart
       * at the exit point) stops on the edge: the rest of the step, a displacement along this
       * side's tangent plane, means nothing on the other side's, and carried over it took the
       * iterate off a sheet whose own nearest point lay just inside the edge (a flat cap's curved
       * rim). The next step starts on the edge and crosses at once if it still points out (an
       * iterate within GP_RF_EDGE_NEAR of the edge in the domain is on it: one stopped there lies
       * a rounding inside, and stopping again moved it nowhere). */
      const gp_eval_result pf = gp_rf_eval(m, w, *f, ix, iy);
      if (gp_dot(pf.normal, pe.normal) < GP_RF_CREASE_COS) {
        gp_dom_edge_point(n, k, t, x, y GP_DT_M(m));
        return;
      }
    }
    const GP_REAL a00 = gp_dot(pe.dxi, pe.dxi), a01 = gp_dot(pe.dxi, pe.deta), a11 = gp_dot(pe.deta, pe.deta);
    const GP_REAL v0 = gp_dot(pe.dxi, D), v1 = gp_dot(pe.deta, D);
    const GP_REAL det = a00 * a11 - a01 * a01;
    dx = dy = GP_R(0.0);
    if (det > GP_R(64.0) * GP_EPS * (a00 * a11) && gp_finite3(pe.dxi) && gp_finite3(pe.deta)) {
      dx = (a11 * v0 - a01 * v1) / det;
      dy = (a00 * v1 - a01 * v0) / det;
    }
    *f = g;
    *x = gx;
    *y = gy;
    ja = pe.dxi;
    jb = pe.deta;
    from = i;
    *transitions += 1;
  }
}

#undef GP_RF_STEP_OK
#undef GP_RF_STEP_STALLED
#undef GP_RF_STEP_KKT
#define GP_RF_STEP_OK 0
#define GP_RF_STEP_STALLED 1
#define GP_RF_STEP_KKT 2 /* held at a corner of a boundary edge that the step pushes against */
#undef GP_RF_STEP_HELD
#define GP_RF_STEP_HELD 3 /* moved onto an edge it cannot cross, without moving on the surface */
#undef GP_RF_STEP_STATIONARY
#define GP_RF_STEP_STATIONARY 4 /* at a singular point that is a local minimum within the tolerance */
#undef GP_RF_SINGULAR
/* An iterate is at a singular point of its patch when |G_xi x G_eta| <= this x |G_xi| |G_eta|
 * (the sine of the angle between the two tangents): a fold, where J has rank about 1. */
#define GP_RF_SINGULAR GP_R(1.0e-3)

/* Whether iterate it, at a singular point, is a local minimum of f within the stopping tolerance:
 * the model there is convex (B positive definite) and its Newton step would decrease f by at most
 * tol^2 / 2, tol the angle test's min(sin(angleTol) |r|, positionTol) (or the noise of positions).
 * At a regular point that is the angle test itself up to the curvature term of B (the decrease
 * of the Gauss-Newton step is |P r|^2 / 2, P the projection onto the tangent plane); where the
 * nearest point lies on a fold of the patch (a HIP beyond the fold line), r is not along any
 * normal and only this test can be met. */
GP_FN int gp_rf_stationary(const gp_refine_mesh* m, const gp_refine_work* w, const gp_rf_iterate* it, gp_vec3 hip,
                           GP_REAL g0, GP_REAL g1, GP_REAL b00, GP_REAL b01, GP_REAL b11) {
  const GP_REAL det = b00 * b11 - b01 * b01;
  if (!(b00 > GP_R(0.0) && det > GP_R(0.0))) return 0;
  const GP_REAL twicePred = (b11 * g0 * g0 - GP_R(2.0) * b01 * g0 * g1 + b00 * g1 * g1) / det;
  const GP_REAL tol = gp_rf_tolerance(m, w, gp_len(it->r), hip);
  return twicePred <= tol * tol;
}

/* Whether iterate it, held on domain edge a and stopped at once on edge b (both edges it cannot
 * cross), sits at their common corner as a KKT point: f does not decrease, to first order, along
 * either edge away from the corner (g = (g0, g1) = J^T r at it; over the domain's cone at the
 * corner the directional derivative is least along one of the two edges). Without this the
 * iterate switched between the two edges, an evaluation each, until a held step found the corner. */
GP_FN int gp_rf_corner_kkt(int n, const gp_rf_iterate* it, int a, int b, GP_REAL g0, GP_REAL g1 GP_DT_PARAM) {
  int endA; /* the corner as an end of edge a: 1 at C_{a+1} (b follows a), 0 at C_a (a follows b) */
  if (b == (a + 1) % n)
    endA = 1;
  else if (a == (b + 1) % n)
    endA = 0;
  else
    return 0;
  const GP_REAL t = gp_dom_edge_param(n, a, it->x, it->y GP_DT_ARG);
  if (!(endA ? t >= GP_R(1.0) - GP_RF_AT_ONCE : t <= GP_RF_AT_ONCE)) return 0;
  GP_REAL ax, ay, bx, by, cx, cy;
  gp_domain_corner(n, a, &ax, &ay GP_DT_ARG);
  gp_domain_corner(n, (a + 1) % n, &bx, &by GP_DT_ARG);
  gp_domain_corner(n, endA ? (a + 2) % n : (a + n - 1) % n, &cx, &cy GP_DT_ARG);
  /* from the corner into edge a, and into edge b */
  const GP_REAL intoA = endA ? g0 * (ax - bx) + g1 * (ay - by) : g0 * (bx - ax) + g1 * (by - ay);
  const GP_REAL intoB = endA ? g0 * (cx - bx) + g1 * (cy - by) : g0 * (cx - ax) + g1 * (cy - ay);
  return intoA > GP_R(0.0) && intoB > GP_R(0.0);
}

/* One trust-region step from *cur (see the file comment); D: the radius (m), updated. */
GP_FN int gp_rf_step(const gp_refine_mesh* m, gp_refine_work* w, gp_rf_iterate* cur, gp_vec3 hip, GP_REAL* D,
                     GP_REAL Dmax, int* transitions, gp_uint* status) {
  const int n = gp_rf_size(m, cur->face);
  const GP_REAL eps = GP_RF_FD_EPS;
  const gp_vec3 r = cur->r, a = cur->p.dxi, b = cur->p.deta;
  const GP_REAL g0 = gp_dot(a, r), g1 = gp_dot(b, r);
  const GP_REAL m00 = gp_dot(a, a), m01 = gp_dot(a, b), m11 = gp_dot(b, b);
  /* second-order part sum r_i d2G_i from forward differences of the exact first derivatives,
   * taken again only GP_RF_D2_REUSE away from where they were last taken (or on another face) */
  GP_REAL xc = cur->x, yc = cur->y;
  gp_dom_interior(n, &xc, &yc, eps GP_DT_M(m));
  /* at a singular point the stationarity test below decides on the model: its differences are
   * taken there */
  const int singular = cur->edge < 0 && !(gp_len(gp_cross(a, b)) > GP_RF_SINGULAR * GP_SQRT(m00 * m11));
  const int exact = w->kept.d2Face == cur->face && w->kept.d2x == xc && w->kept.d2y == yc; /* taken here already */
  const int lagged = !exact && !singular && w->kept.d2Face == cur->face &&
                     GP_FABS(xc - w->kept.d2x) <= GP_RF_D2_REUSE && GP_FABS(yc - w->kept.d2y) <= GP_RF_D2_REUSE &&
                     w->kept.d2Uses < GP_RF_D2_MAX_USES;
  if (lagged) w->kept.d2Uses += 1;
  if (!exact && !lagged) {
    const gp_eval_result pc = (xc == cur->x && yc == cur->y) ? cur->p : gp_rf_eval(m, w, cur->face, xc, yc);
    gp_rf_take_d2(m, w, cur->face, xc, yc, &pc);
  }
  const GP_REAL s00 = gp_dot(r, w->kept.d2xx) / eps, s11 = gp_dot(r, w->kept.d2yy) / eps;
  const GP_REAL s01 = GP_R(0.5) * gp_dot(r, w->kept.d2xy) / eps;
  const GP_REAL b00 = m00 + s00, b01 = m01 + s01, b11 = m11 + s11;
  if (!(GP_FABS(b00) + GP_FABS(b01) + GP_FABS(b11) <= GP_BIG)) {
    w->kept.d2Face = -1; /* not evaluable there: nothing to reuse */
    return GP_RF_STEP_STALLED;
  }
  if (singular && xc == cur->x && yc == cur->y && gp_rf_stationary(m, w, cur, hip, g0, g1, b00, b01, b11))
    return GP_RF_STEP_STATIONARY;

  GP_REAL sx, sy, pred;
  int newton, face = cur->face, edge = -1, tr = 0;
  gp_uint st = 0u;
  GP_REAL x = cur->x, y = cur->y;
  pred = gp_rf_newton_solve(g0, g1, b00, b01, b11, m00, m01, m11, *D, &sx, &sy, &newton);
  int kx = -1;
  const GP_REAL tau = gp_dom_exit(n, x, y, sx, sy, &kx GP_DT_M(m));
  if (cur->edge >= 0 && kx == cur->edge && tau <= GP_RF_AT_ONCE) {
    /* held on a boundary edge and the free step points out: 1-D Newton along the edge */
    GP_REAL ex, ey;
    (void)gp_rf_edge_tangent(n, cur->edge, &cur->p, &ex, &ey GP_DT_M(m));
    const GP_REAL ge = g0 * ex + g1 * ey, be = gp_rf_form(b00, b01, b11, ex, ey);
    const GP_REAL me = gp_rf_form(m00, m01, m11, ex, ey);
    const GP_REAL smax = me > GP_R(0.0) ? *D / GP_SQRT(me) : GP_R(0.0);
    GP_REAL sig = be > GP_R(0.0) ? -ge / be : (ge > GP_R(0.0) ? -smax : smax);
    newton = be > GP_R(0.0) && GP_FABS(sig) <= smax;
    if (sig > smax) sig = smax;
    if (sig < -smax) sig = -smax;
    const GP_REAL t0 = gp_dom_edge_param(n, cur->edge, x, y GP_DT_M(m));
    GP_REAL t1 = t0 + sig;
    const int cut = t1 < GP_R(0.0) || t1 > GP_R(1.0);
    if (cut) newton = 0; /* cut at the edge's end */
    t1 = t1 < GP_R(0.0) ? GP_R(0.0) : (t1 > GP_R(1.0) ? GP_R(1.0) : t1);
    sig = t1 - t0;
    pred = -(ge * sig + GP_R(0.5) * be * sig * sig);
    /* blocked at a corner of the held edge; also where the iterate is at that corner up to the
     * rounding of its domain point (a corner reached along the other edge there lies a few eps
     * off this edge's end: the step of that size was rejected at the noise of f and the radius
     * shrank until the refinement stalled) */
    if (!(pred > GP_R(0.0)) || (cut && GP_FABS(sig) <= GP_RF_AT_ONCE)) return GP_RF_STEP_KKT;
    gp_dom_edge_point(n, cur->edge, t1, &x, &y GP_DT_M(m));
    edge = cur->edge;
    st |= *status & (GP_TRACK_BOUNDARY | GP_TRACK_FOLD_EDGE);
  } else {
    gp_rf_move(m, w, &face, &x, &y, sx, sy, a, b, &edge, &tr, &st);
    /* at once: at the start of the step, or within rounding of the start in the domain (an
     * iterate on the edge up to its last bits, whose step leaves by a fraction above
     * GP_RF_AT_ONCE: the move of a few eps was rejected at the noise of f and the radius shrank
     * until the refinement stalled) */
    const int atOnce = tau <= GP_RF_AT_ONCE || (face == cur->face && GP_FABS(x - cur->x) <= GP_RF_AT_ONCE &&
                                                GP_FABS(y - cur->y) <= GP_RF_AT_ONCE);
    if (edge >= 0 && atOnce && face == cur->face && cur->edge >= 0 && edge != cur->edge &&
        gp_rf_corner_kkt(n, cur, cur->edge, edge, g0, g1 GP_DT_M(m)))
      return GP_RF_STEP_KKT;
    if (edge >= 0 && atOnce && (face == cur->face || (st & GP_TRACK_FOLD_EDGE))) {
      /* stopped at once on an edge it cannot cross (the same surface point): hold it there and
       * step along it next */
      gp_rf_iterate held = gp_rf_at(m, w, face, x, y, hip);
      if (held.f < GP_BIG) {
        held.edge = edge;
        *cur = held;
        *transitions += tr;
        *status = (*status & ~(GP_TRACK_BOUNDARY | GP_TRACK_FOLD_EDGE)) | st;
        return GP_RF_STEP_HELD;
      }
      return GP_RF_STEP_STALLED;
    }
    if (face == cur->face) { /* the model's decrease for the displacement actually taken */
      const GP_REAL u = x - cur->x, v = y - cur->y;
      pred = gp_rf_decrease(g0, g1, b00, b01, b11, u, v);
      sx = u;
      sy = v;
    }
  }
  if (face == cur->face) {
    sx = x - cur->x;
    sy = y - cur->y;
  }
  const GP_REAL len =
      GP_SQRT(gp_max(gp_rf_form(m00, m01, m11, sx, sy), GP_R(0.0))); /* |J s|, m */
  /* the trial point with its second differences, unless this step is expected to converge: the
   * last two steps' lengths predict the next one's (len^3 / prev^2, quadratic convergence) */
  const GP_REAL next = w->lastLen > GP_R(0.0) ? len * len * len / (w->lastLen * w->lastLen) : GP_BIG;
  gp_rf_iterate trial;
  gp_eval_result mp; /* converging with modelFinal, on the same face: the model's point */
  if (!(next > w->tol) && w->modelFinal && face == cur->face && edge < 0 && tr == 0 &&
      gp_rf_model_point(w, cur, sx, sy, &mp))
    trial = gp_rf_with(face, x, y, mp, hip);
  else
    trial = next > w->tol ? gp_rf_at_d2(m, w, face, x, y, hip) : gp_rf_at(m, w, face, x, y, hip);
  trial.edge = edge;
  int accept = 0, atNoise = 0;
  GP_REAL rho = GP_R(0.0);
  if (trial.f < GP_BIG && pred > GP_R(0.0)) {
    const GP_REAL ared = GP_R(0.5) * gp_dot(gp_sub(cur->p.pos, trial.p.pos), gp_add(cur->r, trial.r));
    const GP_REAL noise = GP_R(16.0) * GP_EPS * (gp_rf_mag(hip) + gp_rf_mag(cur->p.pos)) * gp_len(cur->r) +
                          GP_R(1.0e-30) * m->scale * m->scale;
    rho = ared / pred;
    accept = ared >= GP_R(0.01) * pred;
    if (!accept && pred <= GP_R(16.0) * noise && newton && ared >= -noise) {
      accept = atNoise = 1; /* a full Newton step below the noise of f: the model knows better than f */
      rho = GP_R(0.5);      /* and says nothing about the radius */
    }
    /* stopped by an edge it cannot cross (boundary, fold) after crossing others: the model of
     * the first face says nothing of the cut step; take it when it does not go uphill */
    if (!accept && edge >= 0 && face != cur->face && ared >= -noise) {
      accept = 1;
      rho = GP_R(0.5); /* keep the radius */
    }
  }
  if (lagged && !(accept && (atNoise || GP_FABS(rho - GP_R(1.0)) <= GP_RF_D2_RHO)))
    w->kept.d2Face = -1; /* the lagged model was off: take the differences again */
  if (!accept && (cur->p.status & GP_ST_MODEL_POINT)) {
    /* from a model point (modelFinal) the step measured its decrease against the model's point,
     * off the patch by the model's error: take the patch there and step again from it, the
     * radius kept */
    gp_rf_iterate ev = gp_rf_at(m, w, cur->face, cur->x, cur->y, hip);
    if (ev.f < GP_BIG) {
      ev.edge = cur->edge;
      *cur = ev;
      return GP_RF_STEP_OK;
    }
  }
  if (!accept || rho < GP_R(0.25)) {
    const GP_REAL shrink = GP_R(0.25) * len;
    *D = shrink < *D ? shrink : GP_R(0.25) * *D;
  } else if (rho > GP_R(0.75) && len > GP_R(0.99) * *D) {
    *D = GP_R(2.0) * *D < Dmax ? GP_R(2.0) * *D : Dmax;
  }
  if (accept) {
    *cur = trial;
    w->lastLen = len;
    *transitions += tr;
    *status = (*status & ~(GP_TRACK_BOUNDARY | GP_TRACK_FOLD_EDGE)) | st;
  }
  const GP_REAL floor = GP_R(16.0) * GP_EPS * (gp_rf_mag(hip) + m->scale);
  return *D < floor ? GP_RF_STEP_STALLED : GP_RF_STEP_OK;
}

/* The start of a refinement (Newton or the paper's descent, gp_descent.h): the stopping
 * tolerances in w (the residual allowed, at most, and the sine of the angle tolerance, computed
 * once per tolerance) and *out for `face` with nothing found. Returns 0, with *out's status
 * GP_TRACK_DEGENERATE, where the start cannot be refined (a HIP or start point not finite, a
 * face not evaluable). */
GP_FN int gp_rf_begin(const gp_refine_mesh* m, gp_refine_work* w, gp_vec3 hip, int face, GP_REAL xi, GP_REAL eta,
                      const gp_refine_options* o, gp_refine_result* out) {
  w->tol = o->positionTol; /* it also decides what the Newton steps evaluate ahead */
  if (!(w->sinOf == o->angleTol)) {
    w->sinAngle = GP_SIN(o->angleTol);
    w->sinOf = o->angleTol;
  }
  out->scp = out->normal = gp_zero3();
  out->xi = out->eta = out->distance = GP_R(0.0);
  out->face = face;
  out->edge = -1;
  out->iterations = out->transitions = 0;
  out->status = 0u;
  out->startMinimum = 0;
  if (!gp_finite3(hip) || !gp_rf_evaluable(m, face) || !(GP_FABS(xi) <= GP_BIG) || !(GP_FABS(eta) <= GP_BIG)) {
    out->status = GP_TRACK_DEGENERATE;
    return 0;
  }
  return 1;
}

/* The result's point, iterations and status (GP_TRACK_* bits | the point's GP_ST_* bits) from
 * the final iterate. */
GP_FN void gp_rf_finish(const gp_rf_iterate* cur, int iterations, gp_uint status, gp_refine_result* out) {
  out->scp = cur->p.pos;
  out->normal = cur->p.normal;
  out->face = cur->face;
  out->edge = cur->edge;
  out->xi = cur->x;
  out->eta = cur->y;
  out->distance = gp_len(cur->r);
  out->iterations = iterations;
  out->status = status | cur->p.status;
}

/* Refines from (face, xi, eta) (clamped into the domain; startEdge: the domain edge the start
 * is held on, -1 for none) towards the patch point nearest `hip` (m). A start that is not
 * evaluable (bad face, non-finite input) returns GP_TRACK_DEGENERATE with zeros. The result is
 * the last accepted iterate: every accepted step decreased the distance, so a refinement that
 * stops early (GP_TRACK_MAX_ITER, GP_TRACK_STALLED) reports a point no farther than its start.
 * warm = 0: the result depends on the arguments only. warm = 1 (a tracker's next step): w's
 * state from the previous refinement is used: its final evaluation when this start is exactly
 * its final point (the same bits as evaluating again), its second differences when near (see
 * GP_RF_D2_REUSE; the path, not the convergence test, depends on them). */
GP_FN gp_refine_result gp_refine_newton_warm(const gp_refine_mesh* m, gp_refine_work* w, gp_vec3 hip, int face,
                                             GP_REAL xi, GP_REAL eta, int startEdge, const gp_refine_options* o,
                                             int warm) {
  if (!warm) w->kept.d2Face = w->kept.lastFace = -1;
  w->lastLen = GP_R(0.0);
  w->modelFinal = o->modelFinal;
  gp_refine_result out;
  if (!gp_rf_begin(m, w, hip, face, xi, eta, o, &out)) return out;
  const int n0 = gp_rf_size(m, face);
  /* a start at exactly the last refinement's final point (warm) is that iterate, a corner
   * included: moving it off the corner would walk it back there, an evaluation or more a step */
  int last = w->kept.lastFace == face && w->kept.lastX == xi && w->kept.lastY == eta;
  if (!last) {
    gp_dom_clamp(n0, &xi, &eta GP_DT_M(m));
    gp_dom_off_corner(n0, &xi, &eta);
    last = w->kept.lastFace == face && w->kept.lastX == xi && w->kept.lastY == eta;
  }
  gp_rf_iterate cur = last ? gp_rf_with(face, xi, eta, w->kept.lastP, hip) : gp_rf_at_d2(m, w, face, xi, eta, hip);
  w->kept.lastFace = -1;
  cur.edge = startEdge >= 0 && startEdge < n0 ? startEdge : -1;
  if (!(cur.f < GP_BIG)) {
    out.status = GP_TRACK_DEGENERATE | cur.p.status;
    return out;
  }
  /* trust radius: half the patch's size (|dG/dxi|, |dG/deta| per domain unit), at most the mesh size */
  GP_REAL D = GP_R(0.5) * GP_SQRT(gp_dot(cur.p.dxi, cur.p.dxi) + gp_dot(cur.p.deta, cur.p.deta));
  const GP_REAL Dmax = GP_R(0.25) * m->scale;
  if (!(D > GP_R(0.0)) || D > Dmax) D = Dmax;
  gp_uint status = 0u;
  if (cur.edge >= 0) { /* held: on a boundary edge, or on a fold where the neighbour turns back */
    const int twin = m->slotTwin[m->faceOffsets[face] + cur.edge];
    status = twin >= 0 && gp_rf_evaluable(m, gp_rf_slot_face(m, twin)) ? GP_TRACK_FOLD_EDGE : GP_TRACK_BOUNDARY;
  }
  int conv = 0, stalled = 0, it = 0, idle = 0;
  gp_rf_iterate best = cur; /* the nearest iterate so far */
  for (; it < o->maxIterations; ++it) {
    if ((conv = gp_rf_converged(m, w, &cur, hip))) break;
    const int s = gp_rf_step(m, w, &cur, hip, &D, Dmax, &out.transitions, &status);
    if (s == GP_RF_STEP_KKT || s == GP_RF_STEP_STATIONARY) {
      conv = 1;
      break;
    }
    /* held on edges it cannot cross where they meet (a vertex on a fold or a boundary), the
     * iterate can circle between them without getting nearer: after 6 steps without a decrease
     * beyond the noise of f, the best point is a stationary point of the constrained problem */
    const GP_REAL noise =
        GP_R(16.0) * GP_EPS * (gp_rf_mag(hip) + gp_rf_mag(best.p.pos)) * GP_SQRT(GP_R(2.0) * best.f);
    if (cur.f < best.f - noise) {
      best = cur;
      idle = 0;
    } else {
      if (cur.f < best.f) best = cur;
      if (++idle >= 6 && (best.edge >= 0 || cur.edge >= 0) && s != GP_RF_STEP_STALLED) {
        cur = best;
        conv = 1;
        break;
      }
    }
    stalled = s == GP_RF_STEP_STALLED;
    if (stalled) break;
  }
  if (!conv) conv = gp_rf_converged(m, w, &cur, hip);
  if (cur.edge < 0) status &= ~(GP_TRACK_BOUNDARY | GP_TRACK_FOLD_EDGE);
  status |= conv ? GP_TRACK_CONVERGED : (stalled ? GP_TRACK_STALLED : GP_TRACK_MAX_ITER);
  gp_rf_finish(&cur, it, status, &out);
  out.startMinimum = it == 0 && conv && cur.edge < 0 && gp_rf_minimum(m, w, &cur);
  w->kept.lastFace = cur.face;
  w->kept.lastX = cur.x;
  w->kept.lastY = cur.y;
  w->kept.lastP = cur.p;
  return out;
}

/* gp_refine_newton_warm without the previous refinement's state: the same result for the same
 * arguments, whatever ran before. */
GP_FN gp_refine_result gp_refine_newton(const gp_refine_mesh* m, gp_refine_work* w, gp_vec3 hip, int face, GP_REAL xi,
                                        GP_REAL eta, int startEdge, const gp_refine_options* o) {
  return gp_refine_newton_warm(m, w, hip, face, xi, eta, startEdge, o, 0);
}
