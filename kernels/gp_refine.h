/* Nearest-point refinement on the patches (paper Section 4.2) with Eq. 15 transitions
 * (design page, "Leaving the domain"): the Newton variant of host/patch_refine.cpp
 * (PatchRefiner, RefineMethod::Newton) in restricted C, for the OpenCL kernel refine.cl and
 * for C++ (host/gp_math.h instantiates it per precision).
 *
 * Same algorithm and acceptance rules as PatchRefiner (see its class comment): Newton on
 * f = |G - HIP|^2 / 2 with the exact gradient J^T r and the Hessian J^T J + sum r_i d2G_i (the
 * second-order part by forward differences of the exact first derivatives), Gauss-Newton where
 * that Hessian is not positive definite, a trust region in the domain (0.5 at the start,
 * doubled after a clipped accepted step up to 2, quartered after a rejected step); an iterate
 * leaving the domain moves onto the neighbour by Eq. 15, or stays on a boundary /
 * non-manifold edge at the edge's nearest point.
 * Differences from PatchRefiner: all arithmetic is in GP_REAL (PatchRefiner computes in double
 * also for float caches), and the HIP is rounded to GP_REAL.
 *
 * Memory: the cache arrays are read through GP_GLOBAL pointers (gp_refine_mesh), because the
 * iterate changes face while it runs and only the loop knows which records to gather next;
 * everything else is private. Part of the single-source math; include after gp_patch.h; no
 * include guard on purpose (one copy per precision). */

#undef GP_RF_FD_EPS
#undef GP_RF_NOISE
#undef GP_RF_TINY
#if GP_IS_DOUBLE
#define GP_RF_FD_EPS GP_R(1.0e-6) /* finite-difference step in the domain */
#define GP_RF_NOISE GP_R(1.0e-14) /* evaluation noise of positions / mesh size */
#define GP_RF_TINY GP_R(1.0e-300)
#else
#define GP_RF_FD_EPS GP_R(1.0e-3)
#define GP_RF_NOISE GP_R(1.0e-6)
#define GP_RF_TINY GP_R(1.0e-37)
#endif
#undef GP_RF_PI
#define GP_RF_PI GP_R(3.14159265358979323846)

/* The cache as the refinement reads it. Counts: #F faces, #C slots (corners). */
typedef struct {
  GP_GLOBAL const int* faceOffsets;    /* #F+1 */
  GP_GLOBAL const GP_REAL* edgeData;   /* GP_E_NFIELDS * #C, field-major [field * #C + slot] */
  GP_GLOBAL const gp_uint* faceStatus; /* #F, GP_ST_* */
  GP_GLOBAL const int* slotTwin;       /* #C: twin slot, or < 0 (boundary / non-manifold) */
  int numFaces, numSlots, mode;        /* mode: GP_CT_* */
  GP_REAL scale;                       /* bounding-box diagonal of the mesh, m */
} gp_refine_mesh;

/* Private scratch: the records of the face last gathered. */
typedef struct {
  int loaded; /* face held in recs, -1 for none */
  GP_REAL recs[GP_MAX_N * GP_E_NFIELDS];
} gp_refine_work;

/* One refinement's result (the fields of host RefineResult). */
typedef struct {
  gp_vec3 scp, normal; /* m; unit outward normal */
  GP_REAL xi, eta;     /* domain point of `face` */
  int face, edge;      /* edge: domain edge the SCP is held on (boundary), else -1 */
  int iterations, transitions;
  gp_uint status; /* GP_TRACK_* | GP_ST_* of the final point */
} gp_refine_result;

typedef struct {
  int face, edge;
  GP_REAL x, y;
  gp_eval_result p;
  GP_REAL f; /* |G - HIP|^2 / 2; GP_BIG when not evaluable */
} gp_rf_iterate;

GP_FN int gp_rf_size(const gp_refine_mesh* m, int f) { return m->faceOffsets[f + 1] - m->faceOffsets[f]; }

/* Face owning a slot: the last f with faceOffsets[f] <= slot. */
GP_FN int gp_rf_slot_face(const gp_refine_mesh* m, int slot) {
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

GP_FN int gp_rf_evaluable(const gp_refine_mesh* m, int f) {
  if (f < 0 || f >= m->numFaces) return 0;
  const int n = gp_rf_size(m, f);
  return n >= 3 && n <= GP_MAX_N && !(m->faceStatus[f] & (GP_ST_TOO_MANY_SIDES | GP_ST_NONFINITE));
}

/* Patch f at (x, y), gathering its records when another face's are loaded. */
GP_FN gp_eval_result gp_rf_eval(const gp_refine_mesh* m, gp_refine_work* w, int f, GP_REAL x, GP_REAL y) {
  if (!gp_rf_evaluable(m, f)) {
    gp_eval_result r;
    r.pos = r.dxi = r.deta = r.normal = gp_zero3();
    r.status = GP_ST_TOO_MANY_SIDES;
    return r;
  }
  const int first = m->faceOffsets[f], n = gp_rf_size(m, f);
  if (w->loaded != f) {
    for (int k = 0; k < n; ++k)
      for (int i = 0; i < GP_E_NFIELDS; ++i)
        w->recs[k * GP_E_NFIELDS + i] = m->edgeData[(size_t)i * (size_t)m->numSlots + (size_t)(first + k)];
    w->loaded = f;
  }
  gp_eval_result r = gp_patch_eval(n, w->recs, m->mode, x, y);
  r.status |= m->faceStatus[f];
  return r;
}

GP_FN gp_rf_iterate gp_rf_at(const gp_refine_mesh* m, gp_refine_work* w, int f, GP_REAL x, GP_REAL y, gp_vec3 hip) {
  gp_rf_iterate it;
  it.face = f;
  it.edge = -1;
  it.x = x;
  it.y = y;
  it.p = gp_rf_eval(m, w, f, x, y);
  it.f = GP_BIG;
  if (!(it.p.status & (GP_ST_OUTSIDE | GP_ST_TOO_MANY_SIDES)) && gp_finite3(it.p.pos)) {
    const gp_vec3 r = gp_sub(it.p.pos, hip);
    const GP_REAL f2 = GP_R(0.5) * gp_dot(r, r);
    if (f2 < GP_BIG) it.f = f2;
  }
  return it;
}

/* max_k X . m_k over the domain's edge normals m_k (Eq. 3), and its k. */
GP_FN GP_REAL gp_rf_edge_max(int n, GP_REAL x, GP_REAL y, int* k) {
  GP_REAL best = -GP_BIG;
  *k = 0;
  for (int j = 0; j < n; ++j) {
    const GP_REAL a = (GP_REAL)(2 * j + 1) * GP_RF_PI / (GP_REAL)n;
    const GP_REAL v = x * GP_COS(a) + y * GP_SIN(a);
    if (v > best) {
      best = v;
      *k = j;
    }
  }
  return best;
}

GP_FN int gp_rf_outside(int n, GP_REAL x, GP_REAL y) {
  int k;
  return gp_rf_edge_max(n, x, y, &k) > GP_COS(GP_RF_PI / (GP_REAL)n);
}

/* Scales a point outside the domain back onto its boundary along the ray from the origin. */
GP_FN void gp_rf_clamp(int n, GP_REAL* x, GP_REAL* y) {
  int k;
  const GP_REAL mx = gp_rf_edge_max(n, *x, *y, &k), c = GP_COS(GP_RF_PI / (GP_REAL)n);
  if (mx > c) {
    const GP_REAL s = c / mx;
    *x = *x * s;
    *y = *y * s;
  }
}

GP_FN GP_REAL gp_rf_clamp01(GP_REAL v) { return v < GP_R(0.0) ? GP_R(0.0) : (v > GP_R(1.0) ? GP_R(1.0) : v); }

/* Eq. 15: maps (x, y) outside face f's domain onto the neighbour (face, point, transitions
 * updated) or, on a boundary / non-manifold edge or an unusable neighbour, onto the nearest
 * point of the edge (edge set, GP_TRACK_BOUNDARY in *st). */
GP_FN void gp_rf_transfer(const gp_refine_mesh* m, int* f, GP_REAL* x, GP_REAL* y, int* edge, int* transitions,
                          gp_uint* st) {
  *edge = -1;
  const int n = gp_rf_size(m, *f);
  int k;
  const GP_REAL mx = gp_rf_edge_max(n, *x, *y, &k), c = GP_COS(GP_RF_PI / (GP_REAL)n);
  if (!(mx > c)) return;
  const GP_REAL i0x = *x * (c / mx), i0y = *y * (c / mx);
  GP_REAL ckx, cky, c1x, c1y;
  gp_domain_corner(n, k, &ckx, &cky);
  gp_domain_corner(n, (k + 1) % n, &c1x, &c1y);
  const GP_REAL ex = c1x - ckx, ey = c1y - cky;
  const GP_REAL el = GP_SQRT(ex * ex + ey * ey);
  const GP_REAL s = gp_rf_clamp01(GP_SQRT((i0x - c1x) * (i0x - c1x) + (i0y - c1y) * (i0y - c1y)) / el);
  const int twin = m->slotTwin[m->faceOffsets[*f] + k];
  const int g = twin >= 0 ? gp_rf_slot_face(m, twin) : -1;
  if (g < 0 || !gp_rf_evaluable(m, g)) {
    const GP_REAL t = gp_rf_clamp01(((*x - ckx) * ex + (*y - cky) * ey) / (ex * ex + ey * ey));
    *x = ckx + t * ex;
    *y = cky + t * ey;
    gp_rf_clamp(n, x, y);
    *edge = k;
    *st |= GP_TRACK_BOUNDARY;
    return;
  }
  const int ng = gp_rf_size(m, g), i = twin - m->faceOffsets[g];
  GP_REAL cix, ciy, ci1x, ci1y;
  gp_domain_corner(ng, i, &cix, &ciy);
  gp_domain_corner(ng, (i + 1) % ng, &ci1x, &ci1y);
  *x = cix + s * (ci1x - cix);
  *y = ciy + s * (ci1y - ciy);
  gp_rf_clamp(ng, x, y);
  *f = g;
  *transitions += 1;
}

/* Moves X inward so that an eps-disc around it fits in the domain (finite differences). */
GP_FN void gp_rf_interior(int n, GP_REAL* x, GP_REAL* y, GP_REAL eps) {
  int k;
  const GP_REAL dmin = GP_COS(GP_RF_PI / (GP_REAL)n) - gp_rf_edge_max(n, *x, *y, &k);
  if (dmin > GP_R(2.0) * eps) return;
  const GP_REAL r = GP_SQRT(*x * *x + *y * *y);
  const GP_REAL s = GP_R(1.0) - GP_R(3.0) * eps / r;
  *x = *x * s;
  *y = *y * s;
}

GP_FN int gp_rf_converged(const gp_refine_mesh* m, const gp_rf_iterate* it, gp_vec3 hip, GP_REAL tol) {
  const gp_vec3 r = gp_sub(it->p.pos, hip);
  const GP_REAL rl = gp_len(r);
  if (rl <= GP_R(1.0e-12) * m->scale) return 1;
  if (it->edge >= 0) { /* held on a boundary edge: stationary along the edge */
    const int n = gp_rf_size(m, it->face);
    GP_REAL ax, ay, bx, by;
    gp_domain_corner(n, it->edge, &ax, &ay);
    gp_domain_corner(n, (it->edge + 1) % n, &bx, &by);
    const GP_REAL el = GP_SQRT((bx - ax) * (bx - ax) + (by - ay) * (by - ay));
    const gp_vec3 ge = gp_add(gp_scale(it->p.dxi, (bx - ax) / el), gp_scale(it->p.deta, (by - ay) / el));
    return GP_FABS(gp_dot(r, ge)) < GP_SIN(tol) * rl * gp_len(ge);
  }
  return GP_ATAN2(gp_len(gp_cross(r, it->p.normal)), GP_FABS(gp_dot(r, it->p.normal))) < tol;
}

GP_FN GP_REAL gp_rf_sine(const gp_rf_iterate* it, gp_vec3 hip) {
  const gp_vec3 r = gp_sub(it->p.pos, hip);
  return gp_len(gp_cross(r, it->p.normal)) / gp_len(r);
}

/* Step acceptance (PatchRefiner::better): f decreases; or the step crossed onto the neighbour
 * with f unchanged up to its evaluation noise; or, off boundary edges, f is unchanged up to
 * its noise and the angle between G - HIP and the normal shrinks. */
GP_FN int gp_rf_better(const gp_refine_mesh* m, const gp_rf_iterate* trial, const gp_rf_iterate* cur, gp_vec3 hip) {
  if (trial->f < cur->f) return 1;
  const GP_REAL pn = GP_RF_NOISE * m->scale;
  const GP_REAL noise = GP_SQRT(GP_R(2.0) * cur->f) * pn + pn * pn + GP_R(1.0e-13) * cur->f;
  if (trial->face != cur->face && trial->f <= cur->f + noise) return 1;
  if (!(trial->f <= cur->f + noise) || trial->edge >= 0 || cur->edge >= 0) return 0;
  return gp_rf_sine(trial, hip) < gp_rf_sine(cur, hip);
}

/* One trust-region Newton step (PatchRefiner::newtonStep). */
GP_FN void gp_rf_newton_step(const gp_refine_mesh* m, gp_refine_work* w, gp_rf_iterate* cur, gp_vec3 hip,
                             GP_REAL* radius, int* transitions, gp_uint* status, int* stalled) {
  const int n = gp_rf_size(m, cur->face);
  const GP_REAL eps = GP_RF_FD_EPS;
  const gp_vec3 r = gp_sub(cur->p.pos, hip), a = cur->p.dxi, b = cur->p.deta;
  const GP_REAL gx = gp_dot(a, r), gy = gp_dot(b, r);
  const GP_REAL A00 = gp_dot(a, a), A01 = gp_dot(a, b), A11 = gp_dot(b, b);
  /* second-order part sum r_i d2G_i from forward differences of the exact first derivatives */
  GP_REAL xc = cur->x, yc = cur->y;
  gp_rf_interior(n, &xc, &yc, eps);
  const gp_eval_result pc = (xc == cur->x && yc == cur->y) ? cur->p : gp_rf_eval(m, w, cur->face, xc, yc);
  const gp_eval_result p1 = gp_rf_eval(m, w, cur->face, xc + eps, yc);
  const gp_eval_result p2 = gp_rf_eval(m, w, cur->face, xc, yc + eps);
  const GP_REAL S00 = gp_dot(r, gp_sub(p1.dxi, pc.dxi)) / eps, S11 = gp_dot(r, gp_sub(p2.deta, pc.deta)) / eps;
  const GP_REAL S01 = GP_R(0.5) * gp_dot(r, gp_add(gp_sub(p1.deta, pc.deta), gp_sub(p2.dxi, pc.dxi))) / eps;
  GP_REAL H00 = A00 + S00, H01 = A01 + S01, H11 = A11 + S11;
  const GP_REAL tr = A00 + A11;
  GP_REAL det = H00 * H11 - H01 * H01;
  if (!(H00 > GP_R(0.0) && det > GP_R(1.0e-10) * tr * tr) || !(GP_FABS(det) <= GP_BIG)) { /* Gauss-Newton */
    const GP_REAL mu = GP_R(1.0e-9) * tr + GP_RF_TINY;
    H00 = A00 + mu;
    H01 = A01;
    H11 = A11 + mu;
    det = H00 * H11 - H01 * H01;
  }
  GP_REAL sx = -(H11 * gx - H01 * gy) / det, sy = -(-H01 * gx + H00 * gy) / det;
  GP_REAL len = GP_SQRT(sx * sx + sy * sy);
  if (!(len <= GP_BIG) || len == GP_R(0.0)) {
    *stalled = 1;
    return;
  }
  const int clipped = len > *radius;
  if (clipped) {
    sx = sx * (*radius / len);
    sy = sy * (*radius / len);
    len = *radius;
  }
  int face = cur->face, tr2 = 0, edge = -1;
  gp_uint st = 0u;
  GP_REAL x = cur->x + sx, y = cur->y + sy;
  if (gp_rf_outside(n, x, y)) gp_rf_transfer(m, &face, &x, &y, &edge, &tr2, &st);
  gp_rf_iterate trial = gp_rf_at(m, w, face, x, y, hip);
  trial.edge = edge;
  if (gp_rf_better(m, &trial, cur, hip)) {
    *cur = trial;
    *transitions += tr2;
    *status = (*status & ~GP_TRACK_BOUNDARY) | st;
    if (clipped) *radius = *radius * GP_R(2.0) < GP_R(2.0) ? *radius * GP_R(2.0) : GP_R(2.0);
  } else {
    *radius = GP_R(0.25) * len;
    if (*radius < GP_R(1.0e-14)) *stalled = 1;
  }
}

/* Refines from (face, xi, eta) (clamped into the domain; startEdge: the domain edge the start
 * is held on, -1 for none) towards the patch point nearest `hip` (m), stopping when the angle
 * between G - HIP and the normal is below `tol` (rad; on a boundary edge: G - HIP orthogonal to
 * the edge), after maxIterations, or when the step vanishes. A start that is not evaluable
 * (bad face, non-finite input) returns GP_TRACK_DEGENERATE with zeros. */
GP_FN gp_refine_result gp_refine_newton(const gp_refine_mesh* m, gp_refine_work* w, gp_vec3 hip, int face, GP_REAL xi,
                                        GP_REAL eta, int startEdge, int maxIterations, GP_REAL tol) {
  gp_refine_result out;
  out.scp = out.normal = gp_zero3();
  out.xi = out.eta = GP_R(0.0);
  out.face = face;
  out.edge = -1;
  out.iterations = out.transitions = 0;
  out.status = 0u;
  if (!gp_finite3(hip) || !gp_rf_evaluable(m, face) || !(GP_FABS(xi) <= GP_BIG) || !(GP_FABS(eta) <= GP_BIG)) {
    out.status = GP_TRACK_DEGENERATE;
    return out;
  }
  const int n0 = gp_rf_size(m, face);
  gp_rf_clamp(n0, &xi, &eta);
  gp_rf_iterate cur = gp_rf_at(m, w, face, xi, eta, hip);
  cur.edge = startEdge >= 0 && startEdge < n0 ? startEdge : -1;
  if (!(cur.f < GP_BIG)) {
    out.status = GP_TRACK_DEGENERATE | cur.p.status;
    return out;
  }
  gp_uint status = 0u;
  int conv = 0, stalled = 0, it = 0;
  GP_REAL radius = GP_R(0.5);
  for (; it < maxIterations; ++it) {
    if ((conv = gp_rf_converged(m, &cur, hip, tol))) break;
    gp_rf_newton_step(m, w, &cur, hip, &radius, &out.transitions, &status, &stalled);
    if (stalled) break;
  }
  if (!conv) conv = gp_rf_converged(m, &cur, hip, tol);
  if (cur.edge >= 0) status |= GP_TRACK_BOUNDARY;
  status |= conv ? GP_TRACK_CONVERGED : (stalled ? GP_TRACK_STALLED : GP_TRACK_MAX_ITER);
  out.scp = cur.p.pos;
  out.normal = cur.p.normal;
  out.face = cur.face;
  out.edge = cur.edge;
  out.xi = cur.x;
  out.eta = cur.y;
  out.iterations = it;
  out.status = status | cur.p.status;
  return out;
}
