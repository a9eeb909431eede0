#include "diagrams/stepping_stones/stepping_stones_diagram.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include <Eigen/Dense>

#include "systems/controllers/task_space_tasks.h"

namespace rome {

namespace {

// Maps Y_d of Eq. (19) (relative to the stance foot, order [φ_torso, p_com^z, p_sw^x, p_sw^z]) to the task
// layout of the controller, in world coordinates: [torso pitch, COM z, left foot (x, z), right foot (x, z)],
// stacked as [y_d; ẏ_d; ÿ_d]. The swing foot's rows go to the foot that swings in the current mode
// (mode 0 = left stance → right foot swings); the stance foot's rows are unused (inactive task).
class OutputAdapter final : public LeafSystem {
 public:
  static constexpr int kNy = 6;
  OutputAdapter() : LeafSystem("output_adapter") {
    DeclareInputPort("y_desired", 4);
    DeclareInputPort("ydot_desired", 4);
    DeclareInputPort("yddot_desired", 4);
    DeclareInputPort("stance_foot", 2);
    DeclareInputPort("mode", 1);
    DeclareOutputPort("desired", 3 * kNy, [this](const LeafContext& c, Eigen::VectorXd* out) {
      const Eigen::VectorXd& st = EvalInput(c, 3);
      const int mode = static_cast<int>(EvalInput(c, 4)[0]);
      const int swing_offset = mode == 0 ? 4 : 2;  // right foot rows in left stance
      out->setZero();
      for (int k = 0; k < 3; ++k) {
        const Eigen::VectorXd& y = EvalInput(c, k);
        const double shift_x = k == 0 ? st[0] : 0.0, shift_z = k == 0 ? st[1] : 0.0;
        auto seg = out->segment(k * kNy, kNy);
        seg[0] = y[0];
        seg[1] = y[1] + shift_z;
        seg[swing_offset] = y[2] + shift_x;
        seg[swing_offset + 1] = y[3] + shift_z;
      }
    });
  }
};

}  // namespace

SteppingStonesDiagram BuildSteppingStonesDiagram(const Terrain& terrain, const SteppingStonesDiagramParams& params) {
  SteppingStonesDiagram d;
  d.model = std::make_shared<const MultibodyModel>(MultibodyModel::LoadFromSidecar(params.robot_sidecar));
  const auto& model = *d.model;
  DiagramBuilder b;
  auto graph = ContactModeGraph::AlternatingSingleSupport("left_foot", "right_foot", true);
  // The plant's fall guard compares the absolute base height with min_base_height_m; here that parameter is read as
  // a height above the lowest stone, so that walking down stairs is not taken for a fall (the supervisor watches
  // the COM height above the stance foot).
  HybridContactPlantParams plant_params = params.plant;
  double lowest_stone = 0.0;
  for (const SteppingStone& s : terrain.stones()) lowest_stone = std::min(lowest_stone, s.top_height_m);
  plant_params.min_base_height_m += lowest_stone;
  d.plant = b.AddSystem(std::make_unique<HybridContactPlant>("plant", d.model, graph, terrain, plant_params));

  SteppingStonesSupervisorParams sp = params.supervisor;
  sp.impact_fraction = params.impact_fraction;
  sp.posture.com_x_fraction = params.impact_fraction;
  d.supervisor = b.AddSystem(std::make_unique<SteppingStonesSupervisor>("supervisor", d.model, terrain, sp));

  MomentumRegulationPlannerParams pp = params.planner;
  pp.target_orbital_energy = params.target_orbital_energy;
  pp.impact_fraction = params.impact_fraction;
  d.planner = b.AddSystem(std::make_unique<MomentumRegulationPlannerSystem>("planner", pp));
  d.mpc = b.AddSystem(std::make_unique<VerticalComMpcSystem>("vertical_com_mpc", params.mpc));
  SteppingStonesOutputsSystemParams op = params.outputs;
  if (std::isnan(op.swing_foot.stance_stone_half_length)) {
    op.swing_foot.stance_stone_half_length = 0.0;
    for (const SteppingStone& stone : terrain.stones()) op.swing_foot.stance_stone_half_length = std::max(op.swing_foot.stance_stone_half_length, 0.5 * stone.length_m);
  }
  d.outputs = b.AddSystem(std::make_unique<SteppingStonesOutputsSystem>("outputs", op));
  b.AddSystem(std::make_unique<OutputAdapter>());

  const int left_stance = 0, right_stance = 1;
  std::vector<std::shared_ptr<const TaskSpaceTask>> tasks = {
      std::make_shared<BodyPitchTask>("torso_pitch", model, model.body(model.BodyOfVelocity(model.num_base_dofs() - 1)).name,
                                      params.torso_gains),
      std::make_shared<ComPositionTask>("com_height", std::vector<Axis>{Axis::kZ}, params.com_height_gains),
      PointPositionTask::ForContact("left_swing_foot", model, "left_foot", {Axis::kX, Axis::kZ}, params.swing_foot_gains, {right_stance}),
      PointPositionTask::ForContact("right_swing_foot", model, "right_foot", {Axis::kX, Axis::kZ}, params.swing_foot_gains, {left_stance}),
  };
  d.controller = b.AddSystem(std::make_unique<TaskSpaceQpController>("controller", d.model, ActiveContactsPerMode(*d.plant), tasks, params.controller));

  b.Connect("plant", "state", "supervisor", "state");
  b.Connect("plant", "mode", "supervisor", "mode");
  b.Connect("planner", "u_des", "supervisor", "u_des");
  b.Connect("planner", "L_des", "supervisor", "L_des");
  b.Connect("supervisor", "com_state", "planner", "com_state");
  b.Connect("supervisor", "angular_momentum", "planner", "angular_momentum");
  b.Connect("supervisor", "step", "planner", "step");
  b.Connect("supervisor", "pre_impact_com_height", "planner", "pre_impact_com_height");
  b.Connect("supervisor", "com_vertical_state", "vertical_com_mpc", "com_vertical_state");
  b.Connect("planner", "vertical_com_target", "vertical_com_mpc", "target");
  b.Connect("supervisor", "com_state", "outputs", "com_state");
  b.Connect("supervisor", "step_parameters", "outputs", "step_parameters");
  b.Connect("vertical_com_mpc", "com_height_desired", "outputs", "com_height_desired");
  b.Connect("outputs", "y_desired", "output_adapter", "y_desired");
  b.Connect("outputs", "ydot_desired", "output_adapter", "ydot_desired");
  b.Connect("outputs", "yddot_desired", "output_adapter", "yddot_desired");
  b.Connect("supervisor", "stance_foot", "output_adapter", "stance_foot");
  b.Connect("plant", "mode", "output_adapter", "mode");
  b.Connect("plant", "state", "controller", "state");
  b.Connect("plant", "mode", "controller", "mode");
  b.Connect("output_adapter", "desired", "controller", "desired");
  b.Connect("controller", "u", "plant", "u");
  d.logger = AddVectorLogger(b,
                             "logger",
                             {{"plant", "state"},
                              {"plant", "mode"},
                              {"plant", "com"},
                              {"supervisor", "com_state"},
                              {"supervisor", "angular_momentum"},
                              {"supervisor", "stance_foot"},
                              {"planner", "u_des"},
                              {"planner", "L_des"},
                              {"planner", "time_to_impact"},
                              {"supervisor", "pre_impact_com_height"},
                              {"vertical_com_mpc", "com_height_desired"},
                              {"controller", "u"},
                              {"controller", "qp_status"},
                              {"vertical_com_mpc", "qp_status"},
                              {"outputs", "y_desired"},
                              {"outputs", "phase"}},
                             params.log_period_s);
  d.diagram = b.Build("stepping_stones");
  return d;
}

Terrain PeriodicSteppingStones(double step_length_m, double step_height_m, int num_stones, double stone_length_m) {
  if (!(step_length_m > stone_length_m))
    throw std::invalid_argument("PeriodicSteppingStones: step length " + std::to_string(step_length_m) + " m must exceed the stone length " +
                                std::to_string(stone_length_m) + " m");
  if (num_stones < 2) throw std::invalid_argument("PeriodicSteppingStones: needs at least 2 stones, got " + std::to_string(num_stones));
  std::vector<SteppingStone> stones;
  for (int k = 0; k < num_stones; ++k) stones.push_back({k * step_length_m, k * step_height_m, stone_length_m});
  return Terrain::Stones(stones);
}

Terrain RandomSteppingStones(const RandomSteppingStonesParams& p) {
  if (!(p.min_gap_m > p.stone_length_m && p.max_gap_m >= p.min_gap_m && p.max_rise_m >= 0))
    throw std::invalid_argument("RandomSteppingStones: needs stone_length_m < min_gap_m <= max_gap_m and max_rise_m >= 0, got " +
                                std::to_string(p.stone_length_m) + ", " + std::to_string(p.min_gap_m) + ", " + std::to_string(p.max_gap_m) + ", " +
                                std::to_string(p.max_rise_m));
  if (p.num_stones < 2) throw std::invalid_argument("RandomSteppingStones: needs at least 2 stones, got " + std::to_string(p.num_stones));
  std::mt19937 rng(p.seed);
  std::uniform_real_distribution<double> gap(p.min_gap_m, p.max_gap_m);
  std::uniform_real_distribution<double> rise(-p.max_rise_m, p.max_rise_m);
  std::vector<SteppingStone> stones;
  double x = 0, z = 0;
  stones.push_back({0, 0, p.stone_length_m});
  for (int k = 1; k < p.num_stones; ++k) {
    x += gap(rng);
    z += rise(rng);
    stones.push_back({x, z, p.stone_length_m});
  }
  return Terrain::Stones(stones);
}

SimulatorConfig SteppingStonesSimulatorConfig() {
  SimulatorConfig config;
  config.scheme = IntegrationScheme::kExplicitRungeKutta;
  config.explicit_rk_method = ExplicitRungeKuttaMethod::kBogackiShampine32;
  config.relative_tolerance = 1e-6;
  config.absolute_tolerance = 1e-8;
  config.initial_step_s = 1e-3;
  return config;
}

Eigen::VectorXd SteppingStonesInitialState(const MultibodyModel& model, const Terrain& terrain, const SteppingStonesDiagramParams& params) {
  const int nv = model.nv();
  if (terrain.stones().empty()) throw std::runtime_error("SteppingStonesInitialState: the terrain has no stones");
  const auto& stones = terrain.stones();
  MultibodyWorkspace ws(model);
  const ContactInfo& L = model.contacts()[model.ContactIndex("left_foot")];
  const ContactInfo& R = model.contacts()[model.ContactIndex("right_foot")];
  const Eigen::Vector2d stone(stones[0].x_center_m, stones[0].top_height_m);
  const double com_height = params.supervisor.walking_com_height_m;
  const int pitch = model.num_base_dofs() - 1;
  // Configuration: Newton with minimum-norm steps from the nominal pose.
  Eigen::VectorXd q = model.q_nominal();
  q[0] += stone.x();
  q[1] += stone.y();
  Eigen::MatrixXd J3(3, nv), C(7, nv);
  Eigen::VectorXd c(7);
  auto constraint_rows = [&](const Eigen::VectorXd& qq) {
    CalcPointJacobian(model, ws, qq, L.body, L.frame_origin, J3);
    C.row(0) = J3.row(0);
    C.row(1) = J3.row(2);
    CalcPointJacobian(model, ws, qq, R.body, R.frame_origin, J3);
    C.row(2) = J3.row(0);
    C.row(3) = J3.row(2);
    CalcComJacobian(model, ws, qq, J3);
    C.row(4) = J3.row(0);
    C.row(5) = J3.row(2);
    C.row(6) = Eigen::RowVectorXd::Unit(nv, pitch);
  };
  bool converged = false;
  for (int it = 0; it < 100 && !converged; ++it) {
    const Eigen::Vector3d pl = CalcPointPosition(model, ws, q, L.body, L.frame_origin);
    const Eigen::Vector3d pr = CalcPointPosition(model, ws, q, R.body, R.frame_origin);
    const Eigen::Vector3d com = CalcComPosition(model, ws, q);
    c << pl.x() - stone.x(), pl.z() - stone.y(), pr.x() - stone.x(), pr.z() - stone.y(), com.x() - stone.x() - params.initial_com_x_m,
        com.z() - stone.y() - com_height,
        q[pitch];
    if (c.norm() < 1e-12) {
      converged = true;
      break;
    }
    constraint_rows(q);
    q -= C.completeOrthogonalDecomposition().solve(c);
  }
  if (!converged)
    throw std::runtime_error("SteppingStonesInitialState: robot '" + model.name() + "' cannot stand on the first stone with its COM " +
                             std::to_string(com_height) + " m above the feet (supervisor.walking_com_height_m); residual " + std::to_string(c.norm()));
  constraint_rows(q);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(7);
  const double lambda_squared = params.planner.gravity / com_height;
  rhs[4] = std::sqrt(std::max(params.target_orbital_energy + lambda_squared * params.initial_com_x_m * params.initial_com_x_m, 0.0));
  const Eigen::VectorXd v = C.completeOrthogonalDecomposition().solve(rhs);
  if (!((C * v - rhs).norm() < 1e-9))
    throw std::runtime_error("SteppingStonesInitialState: no joint velocity moves the COM of robot '" + model.name() + "' with both feet at rest");
  Eigen::VectorXd x(2 * nv);
  x << q, v;
  return x;
}

void SetSteppingStonesInitialState(const SteppingStonesDiagram& d, const SteppingStonesDiagramParams& params, Context& context) {
  const int nv = d.model->nv();
  const Eigen::VectorXd x = SteppingStonesInitialState(*d.model, d.plant->terrain(), params);
  d.plant->SetState(d.diagram->GetMutableSubsystemContext(*d.plant, context), x.head(nv), x.tail(nv), "left_foot_stance");
  d.supervisor->Initialize(d.diagram->GetMutableSubsystemContext(*d.supervisor, context), x, 0);
}

}  // namespace rome
