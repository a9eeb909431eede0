// An outside project against an installed (and then moved) ROME: walks AMBER 3 steps on stepping stones with the robot
// found in the installed data folder, and uses one symbol of every other library (each checked against a closed form or
// a known value), so a library missing from rome::rome fails to link. Prints the robot file it read.
#include <cmath>
#include <iostream>

#include "diagrams/hopping/hopping_diagram.h"
#include "diagrams/stepping_stones/stepping_stones_diagram.h"
#include "diagrams/walking/walking_diagram.h"
#include "framework/install_location.h"
#include "solvers/collocation/piecewise_polynomial.h"
#include "solvers/riccati/continuous_algebraic_riccati_equation.h"
#include "systems/classic/bouncing_ball.h"
#include "systems/multibody/robot_files.h"
#include "systems/rom/spring_mass_model.h"
#include "systems/trajectory_optimization/collocation_dynamics.h"
#include "systems/visualization/plot.h"

int main() {
  using namespace rome;
  bool ok = true;
  std::cout << "data folder: " << InstalledDataFolder() << "\n";
  std::cout << "robot file: " << FindRobotFile("robots/amber/amber.rome.json") << "\n";

  SteppingStonesDiagramParams params;
  params.supervisor.max_steps = 3;
  SteppingStonesDiagram d =
      BuildSteppingStonesDiagram(PeriodicSteppingStones(0.4, 0.0, 6), params, ClfQpControllerFactory(params));
  Simulator sim(*d.diagram, SteppingStonesSimulatorConfig());
  SetSteppingStonesInitialState(d, params, sim.get_mutable_context());
  const SimulatorStatus status = sim.AdvanceTo(10.0);
  std::cout << "stepping stones: " << status.ToString() << "\n";
  ok &= status.kind() == SimulatorStatus::Kind::kSuccess;

  // rome_riccati: the scalar CARE's closed form P = r (a + √(a² + b² q / r)) / b² with a = 0, b = q = r = 1: P = 1.
  ok &=
      std::abs(SolveContinuousAlgebraicRiccatiEquation(Eigen::MatrixXd::Zero(1, 1), Eigen::MatrixXd::Ones(1, 1),
                                                       Eigen::MatrixXd::Ones(1, 1), Eigen::MatrixXd::Ones(1, 1))(0, 0) -
               1.0) < 1e-9;
  // rome_collocation: the first-order hold through (0, 1) and (1, 3) is 1 + 2t: 1.5 at t = 0.25.
  const PiecewisePolynomial line =
      PiecewisePolynomial::FirstOrderHold(Eigen::Vector2d(0.0, 1.0), Eigen::RowVector2d(1.0, 3.0));
  ok &= std::abs(line.Value(0.25)[0] - 1.5) < 1e-12;
  // rome_classic: a ball dropped from 1 m lands at √(2/g).
  BouncingBallParams ball_params;
  ball_params.initial_height = 1.0;
  ball_params.initial_velocity = 0.0;
  BouncingBall ball("ball", ball_params);
  Simulator ball_sim(ball);
  ball_sim.AdvanceTo(0.5);
  ok &= ball_sim.statistics().guard_events == 1 &&
        std::abs(ball_sim.statistics().events.at(0).time - std::sqrt(2.0 / ball_params.gravity)) < 1e-6;
  // rome_trajectory_optimization: collocation dynamics from a leaf system (the ball in flight: ẋ = (v, −g)).
  auto ball_context = ball.CreateDefaultContext();
  ok &= static_cast<bool>(CollocationDynamicsFromSystem(ball, static_cast<const LeafContext&>(*ball_context), ""));
  // rome_rom, rome_walking_diagram, rome_hopping_diagram: referenced so that their archives must be on the link line.
  ok &= PublishedLegStiffness().stiffness.Evaluate(0.9) > 0.0;
  ok &= WalkingSimulatorConfig().relative_tolerance > 0 && HoppingSimulatorConfig().relative_tolerance > 0;
  // rome_visualization: a PNG through gnuplot (skipped without gnuplot, which is not a ROME dependency of the app).
  std::string error;
  const bool plotted =
      visualization::WritePlot({"line", "t", "y", {{"1 + 2t", {0.0, 1.0}, {1.0, 3.0}}}}, "line.png", &error);
  std::cout << "plot: " << (plotted ? "line.png" : error) << "\n";
  std::cout << (ok ? "ok" : "FAIL") << "\n";
  return ok ? 0 : 1;
}
