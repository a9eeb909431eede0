#pragma once
// Cassie's virtual leg length L(q_knee) (hopping paper Eq. (13)) from the reference table of the hopping spec
// (shared/specs/hopping.md, A1.3: values derived independently of our code, to 1 mm), as a cubic Hermite through
// (L, dL/dq_knee) at the tabulated knee angles. Tests use it as an independent leg-length function.
#include <algorithm>
#include <array>
#include <cmath>

namespace rome::test {

inline void SpecLegLength(double q_knee, double* L, double* dL) {
  constexpr double kDeg = M_PI / 180.0;
  static constexpr std::array<double, 10> q_deg = {-120, -110, -100, -90, -80, -70, -60, -54.4, -45, -37};
  static constexpr std::array<double, 10> L_m = {0.5308, 0.6055, 0.6757, 0.7407, 0.8002,
                                                 0.8535, 0.9003, 0.9235, 0.9577, 0.9816};
  static constexpr std::array<double, 10> dL_m_per_rad = {0.440, 0.416, 0.388, 0.357, 0.323,
                                                          0.287, 0.249, 0.227, 0.188, 0.155};
  const double x = std::clamp(q_knee / kDeg, q_deg.front(), q_deg.back());
  int i = 0;
  while (i < 8 && x > q_deg[i + 1]) ++i;
  const double h = (q_deg[i + 1] - q_deg[i]) * kDeg, t = (x - q_deg[i]) * kDeg / h;
  const double h00 = 2 * t * t * t - 3 * t * t + 1, h10 = t * t * t - 2 * t * t + t, h01 = -2 * t * t * t + 3 * t * t,
               h11 = t * t * t - t * t;
  const double d00 = 6 * t * t - 6 * t, d10 = 3 * t * t - 4 * t + 1, d01 = -6 * t * t + 6 * t, d11 = 3 * t * t - 2 * t;
  *L = h00 * L_m[i] + h10 * h * dL_m_per_rad[i] + h01 * L_m[i + 1] + h11 * h * dL_m_per_rad[i + 1];
  *dL = (d00 * L_m[i] + d01 * L_m[i + 1]) / h + d10 * dL_m_per_rad[i] + d11 * dL_m_per_rad[i + 1];
}

}  // namespace rome::test
