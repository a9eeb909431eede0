#pragma once
// Linear-algebra kernels of rome::DenseQpSolver (internal header, included by solvers/qp/*.cc only) and the
// CPU dispatch of the solver's hot loops.
//
// CPU dispatch: functions marked ROME_QP_HOT are compiled twice on x86-64 with GCC (x86-64-v3 = AVX2/FMA, and
// baseline x86-64) and the dynamic loader picks one at load time (function multi-versioning, target_clones).
// The kernels below are always inlined into those functions, so each clone gets kernels compiled for its ISA;
// they are written as plain loops over contiguous memory (vectorized by the compiler) or with the two-lane GCC
// vector extension (SSE2 on x86-64, generic code elsewhere). Other compilers / architectures get the
// baseline version only (define ROME_QP_NO_TARGET_CLONES to force that).
// Small helpers called from inside the clones' loops must be inlined too (the solver's Rhs, NormalDot,
// SideIsFinite are always_inline): out-of-line baseline bodies, compiled with legacy SSE encodings, made the
// hot start 2.5-6x slower (N = 20 condensed MPC; the samples sat on the first VEX instruction after each call,
// the signature of AVX/SSE transition stalls with the upper YMM state dirty).

#include <Eigen/Core>

#include <cstring>
#include <limits>

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(ROME_QP_NO_TARGET_CLONES)
#define ROME_QP_HOT __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define ROME_QP_HOT
#endif

namespace rome::qp_kernels {

inline constexpr double kInf = std::numeric_limits<double>::infinity();

// Applies the rotation [c s; -s c] to the column pair (a, b) of length n: a <- c a + s b, b <- -s a + c b.
[[gnu::always_inline]] inline void RotateColumns(double* a, double* b, int n, double c, double s) {
  for (int i = 0; i < n; ++i) {
    const double ai = a[i];
    const double bi = b[i];
    a[i] = c * ai + s * bi;
    b[i] = c * bi - s * ai;
  }
}

// y = M v for a column-major block (leading dimension ld): axpys over four columns at a time (one pass over y
// per four columns), vectorized by the compiler.
[[gnu::always_inline]] inline void Gemv(const double* __restrict m, Eigen::Index ld, int rows, int cols,
                                        const double* __restrict v, double* __restrict y) {
  int c = 0;
  if (cols >= 4) {
    const double* __restrict m0 = m;
    const double* __restrict m1 = m + ld;
    const double* __restrict m2 = m + 2 * ld;
    const double* __restrict m3 = m + 3 * ld;
    const double v0 = v[0], v1 = v[1], v2 = v[2], v3 = v[3];
    for (int i = 0; i < rows; ++i) y[i] = v0 * m0[i] + v1 * m1[i] + v2 * m2[i] + v3 * m3[i];
    c = 4;
  } else {
    for (int i = 0; i < rows; ++i) y[i] = 0.0;
  }
  for (; c + 4 <= cols; c += 4) {
    const double* __restrict m0 = m + c * ld;
    const double* __restrict m1 = m0 + ld;
    const double* __restrict m2 = m0 + 2 * ld;
    const double* __restrict m3 = m0 + 3 * ld;
    const double v0 = v[c], v1 = v[c + 1], v2 = v[c + 2], v3 = v[c + 3];
    for (int i = 0; i < rows; ++i) y[i] += v0 * m0[i] + v1 * m1[i] + v2 * m2[i] + v3 * m3[i];
  }
  // Remaining 1-3 columns in one pass.
  const double* __restrict m0 = m + c * ld;
  switch (cols - c) {
    case 3: {
      const double v0 = v[c], v1 = v[c + 1], v2 = v[c + 2];
      for (int i = 0; i < rows; ++i) y[i] += v0 * m0[i] + v1 * m0[i + ld] + v2 * m0[i + 2 * ld];
      break;
    }
    case 2: {
      const double v0 = v[c], v1 = v[c + 1];
      for (int i = 0; i < rows; ++i) y[i] += v0 * m0[i] + v1 * m0[i + ld];
      break;
    }
    case 1: {
      const double v0 = v[c];
      for (int i = 0; i < rows; ++i) y[i] += v0 * m0[i];
      break;
    }
    default: break;
  }
}

// Two-lane double vector (GCC/Clang vector extension; SSE2 on x86-64, generic code elsewhere).
typedef double Double2 __attribute__((vector_size(16)));
[[gnu::always_inline]] inline Double2 Load2(const double* p) {
  Double2 v;
  std::memcpy(&v, p, sizeof(v));
  return v;
}

// y_c = M(:, c) . x for a column-major block: two columns per pass, two-lane vector accumulators.
[[gnu::always_inline]] inline void GemvTransposed(const double* m, Eigen::Index ld, int rows, int cols, const double* x,
                                                  double* y) {
  const int rows2 = rows & ~1;
  int c = 0;
  for (; c + 2 <= cols; c += 2) {
    const double* m0 = m + c * ld;
    const double* m1 = m0 + ld;
    Double2 acc0 = {0.0, 0.0};
    Double2 acc1 = {0.0, 0.0};
    for (int i = 0; i < rows2; i += 2) {
      const Double2 xv = Load2(x + i);
      acc0 += Load2(m0 + i) * xv;
      acc1 += Load2(m1 + i) * xv;
    }
    double s0 = acc0[0] + acc0[1];
    double s1 = acc1[0] + acc1[1];
    if (rows2 < rows) {
      s0 += m0[rows2] * x[rows2];
      s1 += m1[rows2] * x[rows2];
    }
    y[c] = s0;
    y[c + 1] = s1;
  }
  if (c < cols) {
    const double* m0 = m + c * ld;
    Double2 acc0 = {0.0, 0.0};
    for (int i = 0; i < rows2; i += 2) acc0 += Load2(m0 + i) * Load2(x + i);
    double s0 = acc0[0] + acc0[1];
    if (rows2 < rows) s0 += m0[rows2] * x[rows2];
    y[c] = s0;
  }
}

// True when every entry is finite: x * 0 is 0 for finite x and NaN for inf / NaN (vectorized accumulation).
[[gnu::always_inline]] inline bool AllFinite(const double* p, Eigen::Index size) {
  Double2 acc0 = {0.0, 0.0};
  Double2 acc1 = {0.0, 0.0};
  Eigen::Index i = 0;
  for (; i + 4 <= size; i += 4) {
    acc0 += Load2(p + i) * 0.0;
    acc1 += Load2(p + i + 2) * 0.0;
  }
  double tail = 0.0;
  for (; i < size; ++i) tail += p[i] * 0.0;
  const Double2 acc = acc0 + acc1;
  return acc[0] + acc[1] + tail == 0.0;
}

// True when no entry is NaN or +inf (lower sides; sign = +1) or NaN or -inf (upper sides; sign = -1).
[[gnu::always_inline]] inline bool BoundsValid(const double* p, Eigen::Index size, double sign) {
  int ok = 1;
  if (sign > 0) {
    for (Eigen::Index i = 0; i < size; ++i) ok &= static_cast<int>(p[i] < kInf);
  } else {
    for (Eigen::Index i = 0; i < size; ++i) ok &= static_cast<int>(p[i] > -kInf);
  }
  return ok != 0;
}

[[gnu::always_inline]] inline double SquaredNorm(const double* x, int n) {
  return n > 0 ? Eigen::Map<const Eigen::VectorXd>(x, n).squaredNorm() : 0.0;
}

}  // namespace rome::qp_kernels
