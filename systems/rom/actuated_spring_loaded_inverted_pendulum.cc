#include "systems/rom/actuated_spring_loaded_inverted_pendulum.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace rome {

double AslipRestLengthForForce(const ActuatedSpringLoadedInvertedPendulumParams& params, double r, double F) {
  auto fail = [&](const char* why) {
    std::ostringstream msg;
    msg << "AslipRestLengthForForce: " << why << " (r = " << r << " m, F = " << F << " N)";
    throw std::invalid_argument(msg.str());
  };
  if (!(r > 0) || !(F >= 0) || !std::isfinite(r) || !std::isfinite(F)) fail("needs r > 0 and F >= 0, finite");
  double L = r + F / std::max(AslipStiffness(params, r), 1.0);
  for (int it = 0; it < 50; ++it) {
    // φ(L) = K(L)(L − r) − F, φ'(L) = K'(L)(L − r) + K(L).
    const double K = AslipStiffness(params, L);
    const double dK = params.spring_scale * (4 * params.k4 * L * L * L + 2 * params.k2 * L + params.k1);
    const double step = (K * (L - r) - F) / (dK * (L - r) + K);
    L -= step;
    if (!(L > 0.2807)) fail("Newton left the range L > 0.2807 m where K > 0");
    if (std::abs(step) < 1e-12) return L;
  }
  fail("Newton did not converge in 50 steps");
  return L;
}

}  // namespace rome
