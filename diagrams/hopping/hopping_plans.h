#pragma once
// The spring-mass ROM's pieces in the form the hopping diagram takes them (hopping_diagram.h):
//   LegLengthTable            Cassie's virtual leg length L(q_knee) (Eq. (13), CassieVirtualLeg) tabulated once as a
//                             cubic Hermite through (L, dL/dq_knee) over the knee's joint range, so that the control
//                             loop evaluates it without Newton solves or allocation;
//   MakeSpringMassJumpPlanner the jump NLP (Eq. (14)-(15)) from the measured standing state (the ROM's static state at
//                             the measured L, spec A2 [R]);
//   MakeSpringMassLandingPlanner the landing NLP (Eq. (16)) from the measured post-impact state, warm-started from the
//                             previous landing solution; its rest height is the jump's initial mass height (spec A2
//                             [R]).
// Every solve is appended to a shared record (for the example's summary: time, iterations, violation).
#include <memory>
#include <vector>

#include "diagrams/hopping/hopping_reference.h"
#include "systems/planners/spring_mass_hop_planner.h"
#include "systems/rom/cassie_leg_stiffness.h"

namespace rome {

class LegLengthTable {
 public:
  /// `side`: "left" or "right" (both legs are the same; one table serves both). `nodes` ≥ 2 over [q_min, q_max].
  LegLengthTable(const MultibodyModel& model, const std::string& side = "left", int nodes = 241);
  void operator()(double q_knee, double* L, double* dL_dq) const;
  const Eigen::VectorXd& knee() const { return knee_; }
  const Eigen::VectorXd& length() const { return length_; }

 private:
  Eigen::VectorXd knee_, length_, slope_;
};

struct PlannerRecord {
  enum class Kind {
    kJump,
    kLanding,
    kLandingPredicted
  };  ///< kLandingPredicted: solved at lift-off from the predicted touchdown
  Kind kind = Kind::kJump;
  double time_s = 0.0;  ///< simulated time of the solve [s]
  SpringMassPlan plan;
};
using PlannerRecords = std::shared_ptr<std::vector<PlannerRecord>>;

/// The plan as HoppingReference's node plan (times, L, L̇, x, ẋ, F of the collocation nodes, and n_legs K(L) of `rom`).
LegLengthPlan ToLegLengthPlan(const SpringMassParams& rom, const SpringMassPlan& plan);

HoppingReference::JumpPlanner MakeSpringMassJumpPlanner(const SpringMassParams& rom, const SpringMassJumpParams& params,
                                                        PlannerRecords records, std::shared_ptr<double> rest_height);
HoppingReference::LandingPlanner MakeSpringMassLandingPlanner(const SpringMassParams& rom,
                                                              const SpringMassLandingParams& params,
                                                              PlannerRecords records,
                                                              std::shared_ptr<double> rest_height);

/// The spring-mass ROM's pieces for BuildHoppingDiagram in one place: Cassie's ROM (CassieSpringMassParams), the
/// leg-length table, and the jump and landing planners sharing one record of solves and one rest height. The
/// constructor validates the params (SpringMassJumpParams/SpringMassLandingParams::Validate) and the apex rise
/// against what Cassie's legs can reach (0 < H <= kMaxApexRise), naming the field and the value.
struct SpringMassHopPlanners {
  static constexpr double kMaxApexRise = 0.35;  ///< [m] largest apex rise H the hopping diagram accepts (ours)
  SpringMassHopPlanners(const MultibodyModel& model, LegStiffnessVariant variant,
                        const SpringMassJumpParams& jump_params = {},
                        const SpringMassLandingParams& landing_params = {});
  LegStiffnessVariant variant;
  SpringMassParams rom;
  SpringMassJumpParams jump_params;
  SpringMassLandingParams landing_params;
  LegLengthTable leg_length;
  PlannerRecords records;  ///< every solve, in order (time, iterations, violation, plan)
  std::shared_ptr<double> rest_height;
  HoppingReference::JumpPlanner jump;
  HoppingReference::LandingPlanner landing;
};

}  // namespace rome
