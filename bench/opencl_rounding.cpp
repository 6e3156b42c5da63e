// SPDX-License-Identifier: Apache-2.0
// Where an OpenCL device's own arithmetic rounds the patch math differently from the host's:
//   domain   the regular n-gon's constants (cos(pi/n), edge normals m_k, corners C_k; Eq. 3) for
//            n = 3..GP_MAX_N, computed by gp_domain_init on the device (its cos and sin) and on
//            the host (the C library's): how many differ, by how many units in the last place.
//            The kernels read the host's table instead (kernels/gp_config.h GP_DT_PARAM); this
//            shows what that spares them
//   contract a * b + c under `#pragma OPENCL FP_CONTRACT OFF` for random a, b, c: how many equal
//            the host's separately rounded product and sum, and how many equal fma(a, b, c)
//            (a device compiler that fuses anyway)
// Float and double (double where the device has cl_khr_fp64). Prints one line per check.
//   build/bench/opencl_rounding [--cl-device NAME]
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <smoothforce/opencl/opencl_context.h>
#include <smoothforce/patch/detail/gp_math.h>
#include "sf_kernel_sources.h"

namespace {

using namespace sf;

const char* kKernels = R"CL(
/* in the layout of the kernels' table (gp_tables.h) */
__kernel void domain_table(__global GP_REAL* out) {
  const int n = (int)get_global_id(0) + 3;
  if (n > GP_MAX_N) return;
  gp_domain d;
  gp_domain_init(n, &d, 1);
  __global GP_REAL* o = out + GP_DOMAIN_FLAT_OFFSET(n);
  o[0] = d.apothem;
  for (int k = 0; k < n; ++k) {
    o[1 + 4 * k] = d.mx[k];
    o[2 + 4 * k] = d.my[k];
    o[3 + 4 * k] = d.cx[k];
    o[4 + 4 * k] = d.cy[k];
  }
}
__kernel void contract(__global const GP_REAL* a, __global const GP_REAL* b, __global const GP_REAL* c,
                       __global GP_REAL* out) {
  const size_t i = get_global_id(0);
  out[i] = a[i] * b[i] + c[i];
}
)CL";

/// Comments out `#include` lines: the headers are concatenated in include order.
std::string embedded(const char* text) {
  std::string out, line;
  for (const char* p = text; *p; ++p) {
    if (*p != '\n') {
      line += *p;
      continue;
    }
    if (line.rfind("#include", 0) == 0) line = "// " + line;
    out += line + '\n';
    line.clear();
  }
  return out + line + '\n';
}

template <class Real>
long long ulps(Real a, Real b) {
  using Int = std::conditional_t<sizeof(Real) == 8, long long, int>;
  Int ia, ib;
  std::memcpy(&ia, &a, sizeof a);
  std::memcpy(&ib, &b, sizeof b);
  if (ia < 0) ia = std::numeric_limits<Int>::min() - ia;
  if (ib < 0) ib = std::numeric_limits<Int>::min() - ib;
  return std::llabs(static_cast<long long>(ia) - static_cast<long long>(ib));
}

template <class Real, class Domain, class Init>
void run(OpenCLContext& ctx, const char* name, Init init) {
  constexpr bool dbl = sizeof(Real) == 8;
  std::string options = "-cl-std=CL1.2 -DGP_EMBEDDED=1";
  options += dbl ? " -DGP_REAL=double -DGP_IS_DOUBLE=1" : " -DGP_REAL=float -DGP_IS_DOUBLE=0";
  if (!dbl && ctx.hasCorrectlyRoundedDivSqrt()) options += " -cl-fp32-correctly-rounded-divide-sqrt";
  const std::vector<std::string> src = {"#if GP_IS_DOUBLE\n#pragma OPENCL EXTENSION cl_khr_fp64 : enable\n#endif\n",
                                        embedded(kernels::gp_config_h), embedded(kernels::gp_vec_h),
                                        embedded(kernels::gp_tables_h), kKernels};
  const BuiltProgram prog = ctx.buildProgram(src, options, {false, ""});
  // domain table
  const int count = GP_DOMAIN_FLAT_SIZE;
  cl::Buffer table(ctx.context(), CL_MEM_WRITE_ONLY, count * sizeof(Real));
  cl::Kernel k(prog.program, "domain_table");
  k.setArg(0, table);
  ctx.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(GP_MAX_N - 2));
  std::vector<Real> dev(count);
  ctx.queue().enqueueReadBuffer(table, CL_TRUE, 0, count * sizeof(Real), dev.data());
  int differ = 0, nDiffer = 0;
  long long worst = 0;
  std::string which;
  for (int n = 3; n <= GP_MAX_N; ++n) {
    Domain d;
    init(n, &d);
    const Real* o = dev.data() + GP_DOMAIN_FLAT_OFFSET(n);
    std::vector<Real> host = {d.apothem};
    for (int j = 0; j < n; ++j) host.insert(host.end(), {d.mx[j], d.my[j], d.cx[j], d.cy[j]});
    int here = 0;
    for (size_t i = 0; i < host.size(); ++i) {
      const long long u = ulps(host[i], o[i]);
      here += u != 0;
      if (u > worst) {
        worst = u;
        which = "n " + std::to_string(n) + " entry " + std::to_string(i);
      }
    }
    differ += here;
    nDiffer += here > 0;
    if (n == 3 || n == 4)
      std::printf("%s n=%d: apothem host %a device %a; %d of %zu entries differ\n", name, n, double(host[0]),
                  double(o[0]), here, host.size());
  }
  std::printf("%s domain constants: %d of %d differ from the host's (in %d of %d polygon sizes), worst %lld ulp (%s)\n",
              name, differ, count, nDiffer, GP_MAX_N - 2, worst, which.c_str());
  // contraction
  const size_t m = 1 << 16;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Real> a(m), b(m), c(m), r(m);
  for (size_t i = 0; i < m; ++i) a[i] = Real(u(rng)), b[i] = Real(u(rng)), c[i] = Real(u(rng));
  auto up = [&](const std::vector<Real>& v) {
    return cl::Buffer(ctx.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, m * sizeof(Real),
                      const_cast<Real*>(v.data()));
  };
  cl::Buffer ba = up(a), bb = up(b), bc = up(c), br(ctx.context(), CL_MEM_WRITE_ONLY, m * sizeof(Real));
  cl::Kernel kc(prog.program, "contract");
  kc.setArg(0, ba), kc.setArg(1, bb), kc.setArg(2, bc), kc.setArg(3, br);
  ctx.queue().enqueueNDRangeKernel(kc, cl::NullRange, cl::NDRange(m));
  ctx.queue().enqueueReadBuffer(br, CL_TRUE, 0, m * sizeof(Real), r.data());
  size_t separate = 0, fused = 0, distinct = 0;
  for (size_t i = 0; i < m; ++i) {
    const volatile Real p = a[i] * b[i];
    const Real s = p + c[i], f = std::fma(a[i], b[i], c[i]);
    distinct += s != f;
    separate += r[i] == s;
    fused += r[i] == f;
  }
  std::printf("%s a*b+c under FP_CONTRACT OFF: %zu of %zu equal the separately rounded result, %zu equal fma "
              "(%zu inputs where the two differ)\n",
              name, separate, m, fused, distinct);
}

}  // namespace

int main(int argc, char** argv) {
  std::string device;
  for (int i = 1; i + 1 < argc; ++i)
    if (std::string(argv[i]) == "--cl-device") device = argv[i + 1];
  try {
    OpenCLContext ctx(device);
    std::printf("device: %s (%s)\n", ctx.info().name.c_str(), ctx.info().driverVersion.c_str());
    run<float, gpf::gp_domain>(ctx, "float", [](int n, gpf::gp_domain* d) { gpf::gp_domain_init(n, d, 1); });
    if (ctx.hasExtension("cl_khr_fp64"))
      run<double, gpd::gp_domain>(ctx, "double", [](int n, gpd::gp_domain* d) { gpd::gp_domain_init(n, d, 1); });
  } catch (const std::exception& e) {
    std::fprintf(stderr, "opencl_rounding: %s\n", e.what());
    return 1;
  }
  return 0;
}
