// SPDX-License-Identifier: Apache-2.0
// The refinement's 2x2 trust-region subproblem (kernels/gp_refine.h): gp_rf_newton_solve, the
// direct Newton step where the model is comfortably convex and the step lies in the region,
// against an independent solve of B s = -g in long double, and bit for bit against
// gp_rf_tr_solve everywhere else. Random models over twelve orders of magnitude: convex (well
// and badly conditioned), indefinite and singular, regions from a tenth to ten times the step.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>

#include <smoothforce/patch/detail/gp_math.h>

namespace sf {
namespace {

using Mat2L = Eigen::Matrix<long double, 2, 2>;
using Vec2L = Eigen::Matrix<long double, 2, 1>;

struct Model {
  double g0, g1, b00, b01, b11, m00, m01, m11, D;
};

struct Counts {
  int direct = 0, fallback = 0, ambiguous = 0;
  int trWorse = 0;  ///< direct cases where gp_rf_tr_solve's step is off by more than the tolerance
};

/// A random model, the region's radius D set from its Newton step's length in the metric M.
Model randomModel(std::mt19937_64& rng, double scaleLo, double scaleHi) {
  std::uniform_real_distribution<double> u(0, 1), ang(0, 2 * M_PI);
  std::normal_distribution<double> nrm;
  auto logu = [&](double lo, double hi) { return std::pow(10.0, lo + (hi - lo) * u(rng)); };
  const double bs = logu(scaleLo, scaleHi), gs = logu(scaleLo, scaleHi);
  double l1 = bs, l2 = bs;
  switch (static_cast<int>(4 * u(rng))) {
    case 0:
      l2 = bs * logu(-2, 0);
      break;  // convex, condition <= 100
    case 1:
      l2 = bs * logu(-6, -2);
      break;  // convex, condition 100..1e6
    case 2:
      l2 = -bs * logu(-3, 0);
      break;  // indefinite
    default:
      l2 = bs * (u(rng) < 0.5 ? 0.0 : 1e-14);
      break;  // singular or nearly
  }
  const double th = ang(rng), c = std::cos(th), sn = std::sin(th);
  Model m{};
  m.b00 = c * c * l1 + sn * sn * l2;
  m.b11 = sn * sn * l1 + c * c * l2;
  m.b01 = c * sn * (l1 - l2);
  m.g0 = gs * nrm(rng);
  m.g1 = gs * nrm(rng);
  // M = J^T J for a random 3x2 Jacobian with columns of different lengths
  Eigen::Matrix<double, 3, 2> J;
  J.col(0) = Eigen::Vector3d(nrm(rng), nrm(rng), nrm(rng)).normalized() * logu(-1, 1);
  J.col(1) = Eigen::Vector3d(nrm(rng), nrm(rng), nrm(rng)).normalized() * logu(-1, 1);
  const Eigen::Matrix2d M = J.transpose() * J;
  m.m00 = M(0, 0);
  m.m01 = M(0, 1);
  m.m11 = M(1, 1);
  Mat2L B;
  B << m.b00, m.b01, m.b01, m.b11;
  const Vec2L s = -(B.inverse() * Vec2L(m.g0, m.g1));
  const long double len = std::sqrt(std::max<long double>(s.dot(M.cast<long double>() * s), 0));
  m.D = std::isfinite(static_cast<double>(len)) && len > 0 ? static_cast<double>(len) * logu(-1, 1) : logu(-3, 3);
  return m;
}

/// A model rounded to precision R, as the solvers take it.
template <typename R>
struct Rounded {
  R g0, g1, b00, b01, b11, m00, m01, m11, D;
  explicit Rounded(const Model& m)
      : g0(R(m.g0)),
        g1(R(m.g1)),
        b00(R(m.b00)),
        b01(R(m.b01)),
        b11(R(m.b11)),
        m00(R(m.m00)),
        m01(R(m.m01)),
        m11(R(m.m11)),
        D(R(m.D)) {}
  /// solve(g0, g1, b00, b01, b11, m00, m01, m11, D, s0, s1, newton): its decrease.
  template <typename Solve>
  R operator()(Solve solve, R* s0, R* s1, int* newton) const {
    return solve(g0, g1, b00, b01, b11, m00, m01, m11, D, s0, s1, newton);
  }
  Mat2L B() const { return (Mat2L() << b00, b01, b01, b11).finished(); }
  Mat2L M() const { return (Mat2L() << m00, m01, m01, m11).finished(); }
};

template <typename R>
bool sameBits(R a, R b) {
  return std::memcmp(&a, &b, sizeof(R)) == 0;  // NaN too: a singular model gives NaN either way
}

/// Checks `count` random models in precision R; relTol: the direct step's error allowed, in the
/// metric M relative to the step's length; margin: the relative band around the branch
/// thresholds where rounding may decide either way.
template <typename R, typename Solve, typename TrSolve>
void checkSolve(Solve solve, TrSolve trSolve, int count, double scaleLo, double scaleHi, double relTol, double margin,
                unsigned seed, Counts& n) {
  std::mt19937_64 rng(seed);
  for (int i = 0; i < count; ++i) {
    const Rounded<R> r(randomModel(rng, scaleLo, scaleHi));
    R s0 = 0, s1 = 0, t0 = 0, t1 = 0;
    int newton = -1, trNewton = -1;
    const R pred = r(solve, &s0, &s1, &newton);
    const R trPred = r(trSolve, &t0, &t1, &trNewton);
    // the reference: the model as rounded to R, B s = -g solved in long double
    const Mat2L B = r.B(), Ml = r.M();
    const long double det = B.determinant();
    const Vec2L g(r.g0, r.g1), sRef = -(B.inverse() * g);
    const long double mn = sRef.dot(Ml * sRef), D2 = static_cast<long double>(r.D) * r.D;
    const bool convex = B(0, 0) > 0 && det > 0;
    const bool comfy = convex && det >= 1e-3L * (1 + margin) * B(0, 0) * B(1, 1);
    const bool notComfy = !convex || det <= 1e-3L * (1 - margin) * B(0, 0) * B(1, 1);
    const bool inside = mn <= D2 * (1 - margin), outside = !(mn < D2 * (1 + margin));
    if (comfy && inside) {
      ++n.direct;
      ASSERT_EQ(newton, 1) << "model " << i;
      auto errM = [&](R x0, R x1) {
        const Vec2L d(x0 - sRef(0), x1 - sRef(1));
        return std::sqrt(std::max<long double>(d.dot(Ml * d), 0));
      };
      const long double len = std::sqrt(mn), err = errM(s0, s1), trErr = errM(t0, t1);
      ASSERT_LE(err, relTol * len) << "model " << i << ": the step off the solution of B s = -g";
      if (trErr > relTol * len) ++n.trWorse;  // the trust-region solve of the same model, less accurate
      const long double predRef = -(g.dot(sRef) + 0.5L * sRef.dot(B * sRef));
      ASSERT_NEAR(static_cast<double>(pred), static_cast<double>(predRef), relTol * std::fabs(double(predRef)))
          << "model " << i;
    } else if (notComfy || outside) {
      ++n.fallback;
      // the trust-region solve itself, the same bits
      ASSERT_EQ(newton, trNewton) << "model " << i;
      ASSERT_TRUE(sameBits(s0, t0) && sameBits(s1, t1) && sameBits(pred, trPred)) << "model " << i;
    } else {
      ++n.ambiguous;  // within rounding of a threshold: either branch is right
    }
  }
}

/// Every model counted once, both branches covered, few within rounding of a threshold.
void expectCoverage(const Counts& n, int count, int maxAmbiguous, const char* precision) {
  EXPECT_EQ(n.direct + n.fallback + n.ambiguous, count);
  EXPECT_GE(n.direct, count / 10) << "the direct step's branch is covered";
  EXPECT_GE(n.fallback, count / 5) << "the trust-region branch is covered";
  EXPECT_LE(n.ambiguous, maxAmbiguous);
  std::printf(
      "%s: %d direct (the trust-region solve off by more than the tolerance in %d), %d trust-region, %d at a "
      "threshold\n",
      precision, n.direct, n.trWorse, n.fallback, n.ambiguous);
}

TEST(RefineSolve, DirectNewtonStepMatchesTheTrustRegionSolveDouble) {
  const int count = 200000;
  Counts n;
  checkSolve<double>([](auto... a) { return gpd::gp_rf_newton_solve(a...); },
                     [](auto... a) { return gpd::gp_rf_tr_solve(a...); }, count, -6, 6, 1e-10, 1e-6, 20261123u, n);
  ASSERT_FALSE(HasFatalFailure());
  expectCoverage(n, count, count / 1000, "double");
}

TEST(RefineSolve, DirectNewtonStepMatchesTheTrustRegionSolveFloat) {
  const int count = 200000;
  Counts n;
  checkSolve<float>([](auto... a) { return gpf::gp_rf_newton_solve(a...); },
                    [](auto... a) { return gpf::gp_rf_tr_solve(a...); }, count, -3, 3, 2e-3, 1e-3, 20261124u, n);
  ASSERT_FALSE(HasFatalFailure());
  expectCoverage(n, count, count / 100, "float");
}

/// The trust-region solve on its own, for every model whose region's D^2 is representable in R
/// (the refinement's D is at most a quarter of the mesh's size): a finite step and decrease, the
/// step inside the region (s^T M s <= D^2 in long double, up to relTol: M is regularised by a
/// few roundings of its trace). taken: how many models were checked.
template <typename R, typename TrSolve>
void checkTrustRegion(TrSolve trSolve, int count, double scaleLo, double scaleHi, double relTol, unsigned seed,
                      int& taken) {
  std::mt19937_64 rng(seed);
  taken = 0;
  for (int i = 0; i < count; ++i) {
    const Rounded<R> r(randomModel(rng, scaleLo, scaleHi));
    if (!(r.D < std::sqrt(std::numeric_limits<R>::max()) / 1024)) continue;  // D^2 overflows R
    ++taken;
    R s0 = 0, s1 = 0;
    int newton = -1;
    const R pred = r(trSolve, &s0, &s1, &newton);
    ASSERT_TRUE(std::isfinite(s0) && std::isfinite(s1) && std::isfinite(pred) && pred >= 0)
        << "model " << i << ": step " << s0 << ", " << s1 << ", decrease " << pred;
    const Vec2L s(s0, s1);
    ASSERT_LE(s.dot(r.M() * s), static_cast<long double>(r.D) * r.D * (1 + relTol))
        << "model " << i << ": the step leaves the region";
  }
}

TEST(RefineSolve, TrustRegionStepIsFiniteAndInsideTheRegion) {
  const int count = 200000;
  int taken = 0;
  checkTrustRegion<double>([](auto... a) { return gpd::gp_rf_tr_solve(a...); }, count, -6, 6, 1e-9, 20261125u, taken);
  ASSERT_FALSE(HasFatalFailure());
  EXPECT_EQ(taken, count);
  checkTrustRegion<float>([](auto... a) { return gpf::gp_rf_tr_solve(a...); }, count, -3, 3, 2e-3, 20261126u, taken);
  ASSERT_FALSE(HasFatalFailure());
  // float: the regions of singular models' huge Newton steps (about one model in ten) are left out
  EXPECT_GE(taken, count * 85 / 100);
  std::printf("float: %d of %d models with D^2 representable\n", taken, count);
}

}  // namespace
}  // namespace sf
