#pragma once
// The walking tests' contact check from the plant, not the controller: at a sample, the contact wrenches of the
// plant's constrained forward dynamics, each active contact counted against unilaterality and, with a load on it
// (a foot at the instant of lift-off carries ~0 N), against the friction cone and the CoP on the sole.

#include <Eigen/Core>

#include "systems/multibody/contact_dynamics.h"
#include "systems/multibody/multibody_model.h"
#include "systems/multibody/multibody_workspace.h"

namespace rome::test {

struct PlantContactCounts {
  long unilateral_bad = 0, friction_bad = 0, cop_bad = 0;

  // qdd (nv) and F (max_constraint_rows) are scratch.
  void Record(const MultibodyModel& model, MultibodyWorkspace& ws, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
              const Eigen::VectorXd& u, ContactSet active, const ConstrainedDynamicsParameters& dynamics,
              const ContactForceCheckParameters& cop_check, Eigen::VectorXd& qdd, Eigen::VectorXd& F) {
    CalcConstrainedForwardDynamics(model, ws, q, v, u, active, dynamics, qdd, F);
    for (int ci = 0; ci < model.num_contacts(); ++ci) {
      if (!(active & ContactBit(ci))) continue;
      const ContactForceCheck check =
          CheckContactForce(model, ws, q, ci, ExtractContactWrench(model, ws, q, active, F, ci), cop_check);
      unilateral_bad += check.normal_force_N >= -1e-6 ? 0 : 1;
      if (check.normal_force_N > 1.0) {
        friction_bad += check.friction_ok ? 0 : 1;
        cop_bad += check.cop_ok ? 0 : 1;
      }
    }
  }
};

}  // namespace rome::test
