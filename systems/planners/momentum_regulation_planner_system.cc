#include "systems/planners/momentum_regulation_planner_system.h"

#include <stdexcept>

namespace rome {

MomentumRegulationPlannerSystem::MomentumRegulationPlannerSystem(std::string name,
                                                                 MomentumRegulationPlannerParams params)
    : LeafSystem(std::move(name)), planner_(params) {
  com_port_ = DeclareInputPort("com_state", 4);
  momentum_port_ = DeclareInputPort("angular_momentum", 1);
  step_port_ = DeclareInputPort("step", 2);
  height_port_ = DeclareInputPort("pre_impact_com_height", 1);
  DeclareOutputPort("u_des", 1, [this](const LeafContext& c, Eigen::VectorXd* y) { (*y)[0] = CalcPlan(c).u_des; });
  DeclareOutputPort("L_des", 1, [this](const LeafContext& c, Eigen::VectorXd* y) { (*y)[0] = CalcPlan(c).L_des; });
  DeclareOutputPort("predicted_pre_impact_momentum", 1,
                    [this](const LeafContext& c, Eigen::VectorXd* y) { (*y)[0] = CalcPlan(c).L_pre_impact; });
  DeclareOutputPort("time_to_impact", 1,
                    [this](const LeafContext& c, Eigen::VectorXd* y) { (*y)[0] = CalcPlan(c).time_to_impact; });
  DeclareOutputPort("slope_adjusted_height", 1,
                    [this](const LeafContext& c, Eigen::VectorXd* y) { (*y)[0] = CalcPlan(c).slope_adjusted_height; });
  DeclareOutputPort("vertical_com_target", 3, [this](const LeafContext& c, Eigen::VectorXd* y) {
    const MomentumRegulationPlan plan = CalcPlan(c);
    *y << EvalInput(c, height_port_)[0], plan.u_des, plan.time_to_impact;
  });
  DeclareOutputPort("status", 1, [this](const LeafContext& c, Eigen::VectorXd* y) {
    (*y)[0] = static_cast<double>(CalcPlan(c).status);
  });
}

MomentumRegulationPlan MomentumRegulationPlannerSystem::CalcPlan(const LeafContext& context) const {
  const Eigen::VectorXd& com = EvalInput(context, com_port_);
  const Eigen::VectorXd& step = EvalInput(context, step_port_);
  MomentumRegulationInput in;
  in.p_com_x = com[0];
  in.p_com_z = com[1];
  in.pdot_com_x = com[2];
  in.L_y = EvalInput(context, momentum_port_)[0];
  in.step_length = step[0];
  in.step_height = step[1];
  in.pre_impact_com_height = EvalInput(context, height_port_)[0];
  try {
    return planner_.Plan(in);
  } catch (const std::invalid_argument& e) {
    ThrowError(std::string("inputs rejected at t = ") + std::to_string(context.time()) + " s: " + e.what());
  }
}

}  // namespace rome
