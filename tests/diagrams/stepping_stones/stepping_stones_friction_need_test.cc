#include "diagrams/stepping_stones/stepping_stones_friction_need.h"

#include <cstdio>

#include <gtest/gtest.h>

namespace rome {
namespace {

TEST(PlanFrictionNeed, Print) {
  for (double eps : {0.5, 0.55, 0.6})
    for (double e : {0.3, 0.5, 0.8, 1.0, 1.2, 1.5, 2.0}) {
      MomentumRegulationPlannerParams p;
      p.target_orbital_energy = e;
      p.impact_fraction = eps;
      const PlanFrictionNeed n = CalcPeriodicPlanFrictionNeed(0.8, 0.0, 0.8, p, {});
      std::printf("eps %.2f E %.1f: ratio %.3f at %.3f of T %.3f, Fn %.3f, udes %.3f, v %.3f\n", eps, e, n.max_ratio,
                  n.time_of_max_s, n.step_duration_s, n.min_normal_force_fraction, n.u_des_mps, n.mean_speed_mps);
    }
}

}  // namespace
}  // namespace rome
