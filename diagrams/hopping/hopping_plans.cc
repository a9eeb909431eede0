#include "diagrams/hopping/hopping_plans.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace rome {

LegLengthTable::LegLengthTable(const MultibodyModel& model, const std::string& side, int nodes) {
  if (nodes < 2)
    throw std::invalid_argument("LegLengthTable: nodes = " + std::to_string(nodes) + " must be at least 2");
  const CassieVirtualLeg leg(model, side);
  const int k = leg.knee_index();
  const double lo = model.position_lower_limits()[k], hi = model.position_upper_limits()[k];
  if (!std::isfinite(lo) || !std::isfinite(hi) || !(hi > lo))
    throw std::invalid_argument("LegLengthTable: robot '" + model.name() + "': joint '" + side +
                                "_knee' needs finite limits");
  knee_.resize(nodes), length_.resize(nodes), slope_.resize(nodes);
  for (int i = 0; i < nodes; ++i) {
    knee_[i] = lo + (hi - lo) * i / (nodes - 1);
    length_[i] = leg.Length(knee_[i]);
    slope_[i] = leg.LengthJacobian(knee_[i]);
  }
}

void LegLengthTable::operator()(double q_knee, double* L, double* dL_dq) const {
  // Cubic Hermite in q_knee (HoppingReference::Evaluate with the knee angle as the abscissa); outside the joint range
  // the end value is held (slope 0).
  const Eigen::Vector3d y = HoppingReference::Evaluate(knee_, length_, slope_, static_cast<int>(knee_.size()), q_knee);
  *L = y[0];
  *dL_dq = y[1];
}

LegLengthPlan ToLegLengthPlan(const SpringMassParams& rom, const SpringMassPlan& plan) {
  LegLengthPlan out{plan.times,
                    plan.states.row(2).transpose(),
                    plan.states.row(3).transpose(),
                    plan.states.row(0).transpose(),
                    plan.states.row(1).transpose(),
                    plan.leg_force,
                    Eigen::VectorXd(plan.times.size())};
  for (int k = 0; k < plan.times.size(); ++k)
    out.stiffness[k] = rom.n_legs * rom.leg.stiffness.Evaluate(plan.states(2, k));
  return out;
}

HoppingReference::JumpPlanner MakeSpringMassJumpPlanner(const SpringMassParams& rom, const SpringMassJumpParams& params,
                                                        PlannerRecords records, std::shared_ptr<double> rest_height) {
  auto planner = std::make_shared<SpringMassJumpPlanner>(rom, params);
  return [planner, records, rest_height](const RomState& start, LegLengthPlan* out, std::string* message) {
    const Eigen::Vector4d z0 = planner->rom().StaticState(start.L);  // spec A2 [R]: static ROM state at the measured L
    SpringMassPlan plan;
    try {
      plan = planner->Solve(z0);
    } catch (const std::exception& e) {
      *message = e.what();
      return false;
    }
    if (records) records->push_back({PlannerRecord::Kind::kJump, 0.0, plan});
    if (!plan.success()) {
      *message = plan.message;
      return false;
    }
    *rest_height = z0[0];
    *out = ToLegLengthPlan(planner->rom().params(), plan);
    return true;
  };
}

HoppingReference::LandingPlanner MakeSpringMassLandingPlanner(const SpringMassParams& rom,
                                                              const SpringMassLandingParams& params,
                                                              PlannerRecords records,
                                                              std::shared_ptr<double> rest_height) {
  struct State {
    std::unique_ptr<SpringMassLandingPlanner> planner;
    double rest_height = -1;
  };
  auto state = std::make_shared<State>();
  return [rom, params, state, records, rest_height](const RomState& measured, HoppingReference::LandingSolve when,
                                                    LegLengthPlan* out, std::string* message) {
    const bool predicted = when == HoppingReference::LandingSolve::kPredictedAtLiftoff;
    const PlannerRecord::Kind kind = predicted ? PlannerRecord::Kind::kLandingPredicted : PlannerRecord::Kind::kLanding;
    SpringMassPlan plan;
    try {  // any failure below (no upward lift-off, no rest height yet, the NLP) is a recorded, counted failed plan
      RomState post = measured;
      if (predicted) {
        // Ballistic ROM flight from the measured lift-off state with the leg held (PredictFlight): the touchdown state.
        const Eigen::Vector4d td =
            PredictFlight(SpringMassModel(rom), Eigen::Vector4d(measured.x, measured.xdot, measured.L, 0.0))
                .touchdown_state;
        post = RomState{td[0], td[1], td[2], td[3]};
      }
      if (!state->planner || state->rest_height != *rest_height) {
        SpringMassLandingParams p = params;
        p.rest_height = *rest_height;
        state->planner =
            std::make_unique<SpringMassLandingPlanner>(rom, p);  // throws e.g. before any jump set the rest height
        state->rest_height = *rest_height;
      }
      // The measured leg length may sit outside the NLP's L bounds (the knees overshoot the jump's last L in the push
      // and the flight holds them there): clamp it into them (ours), else the NLP rejects its own initial state, and
      // shift the mass height with it so the spring deflection s = L − x (hence the ROM force) stays the measured one.
      // (Clamping L alone once gave s = −5 cm, a plan starting at −1.9 kN, and a robot that rebounded.)
      const double L0 = std::clamp(post.L, params.min_leg_length, params.max_leg_length);
      const Eigen::Vector4d z0(post.x + (L0 - post.L), post.xdot, L0, post.Ldot);
      plan = state->planner->Resolve(z0);  // warm start from the previous landing solution, if any
    } catch (const std::exception& e) {
      *message = e.what();
      plan = SpringMassPlan{};
      plan.message = e.what();
      if (records) records->push_back({kind, 0.0, plan});
      return false;
    }
    if (records) records->push_back({kind, 0.0, plan});
    if (!plan.success()) {
      *message = plan.message;
      return false;
    }
    *out = ToLegLengthPlan(rom, plan);
    return true;
  };
}

namespace {

const SpringMassJumpParams& CheckedJumpParams(const SpringMassJumpParams& p) {
  p.Validate();
  if (!(p.apex_rise <= SpringMassHopPlanners::kMaxApexRise)) {
    std::ostringstream msg;
    msg << "SpringMassJumpParams: apex_rise = " << p.apex_rise
        << " m: outside what the legs can reach (0 < H <= " << SpringMassHopPlanners::kMaxApexRise << " m)";
    throw std::invalid_argument(msg.str());
  }
  return p;
}

const SpringMassLandingParams& CheckedLandingParams(const SpringMassLandingParams& p) {
  p.Validate();
  return p;
}

}  // namespace

SpringMassHopPlanners::SpringMassHopPlanners(const MultibodyModel& model, LegStiffnessVariant variant,
                                             const SpringMassJumpParams& jump_params,
                                             const SpringMassLandingParams& landing_params)
    : variant(variant),
      rom(CassieSpringMassParams(model, variant)),
      jump_params(CheckedJumpParams(jump_params)),
      landing_params(CheckedLandingParams(landing_params)),
      leg_length(model),
      records(std::make_shared<std::vector<PlannerRecord>>()),
      rest_height(std::make_shared<double>(0.0)),
      jump(MakeSpringMassJumpPlanner(rom, this->jump_params, records, rest_height)),
      landing(MakeSpringMassLandingPlanner(rom, this->landing_params, records, rest_height)) {}

}  // namespace rome
