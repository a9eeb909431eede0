// Python bindings of the walking plan and its trajectory-source block (systems/planners/walking_plan.h,
// walking_trajectory_source.h): a periodic aSLIP + H-LIP plan built from Python, sampled on the global clock, and
// played by WalkingTrajectorySource in a diagram. WalkingDomain is also the value of the source's typed 'domain' port.
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "python/bindings.h"
#include "systems/planners/walking_trajectory_source.h"

namespace py = pybind11;

namespace rome::python {
namespace {

py::dict ReferenceToDict(const WalkingReference& r) {
  py::dict d;
  d["com_position"] = Eigen::VectorXd(r.com_position);
  d["com_velocity"] = Eigen::VectorXd(r.com_velocity);
  d["com_acceleration"] = Eigen::VectorXd(r.com_acceleration);
  d["left_foothold"] = Eigen::VectorXd(r.left_foothold);
  d["right_foothold"] = Eigen::VectorXd(r.right_foothold);
  d["normal_force"] = Eigen::VectorXd(r.normal_force);
  d["domain"] = r.domain;
  return d;
}

/// WalkingPlan.periodic: `steps` periodic steps of the gait the planner solves from `seed`.
WalkingPlan PeriodicPlan(const AslipPeriodicGaitPlanner& planner, int steps, std::uint32_t seed,
                         WalkingDomain first_stance, double stance_x, double step_width) {
  if (steps < 1 || steps > 1000)
    throw py::value_error("WalkingPlan.periodic: steps = " + std::to_string(steps) + " is outside [1, 1000]");
  if (!std::isfinite(step_width) || step_width <= 0.0)
    throw py::value_error("WalkingPlan.periodic: step_width = " + Number(step_width) + " m must be > 0");
  if (!std::isfinite(stance_x))
    throw py::value_error("WalkingPlan.periodic: stance_x = " + Number(stance_x) + " is not finite");
  if (first_stance == WalkingDomain::kDoubleSupport)
    throw py::value_error("WalkingPlan.periodic: first_stance must be left_stance or right_stance");
  // The GIL stays held: it serialises the Ipopt solve (Ipopt 3.11 is not thread-safe).
  const AslipPeriodicGait gait = planner.Solve(seed);
  if (!gait.collocation.success())
    throw std::runtime_error("WalkingPlan.periodic: the aSLIP periodic gait NLP failed (seed " + std::to_string(seed) +
                             "): " + gait.collocation.nlp.message);
  WalkingPlan plan;
  plan.AppendPeriodicSteps(planner, gait, steps, first_stance, stance_x, step_width);
  return plan;
}

}  // namespace

void BindWalkingPlan(py::module_& m) {
  py::enum_<WalkingDomain>(m, "WalkingDomain")
      .value("double_support", WalkingDomain::kDoubleSupport)
      .value("left_stance", WalkingDomain::kLeftStance)
      .value("right_stance", WalkingDomain::kRightStance);
  RegisterTypedValue<WalkingDomain>([](WalkingDomain d) { return py::cast(d); },
                                    std::function<WalkingDomain(const py::handle&)>([](const py::handle& h) {
                                      try {
                                        return h.cast<WalkingDomain>();
                                      } catch (const py::cast_error&) {
                                        throw py::value_error(
                                            "expected a "
                                            "rome.WalkingDomain, got " +
                                            std::string(py::str(py::repr(h))));
                                      }
                                    }));
  py::class_<WalkingPlan>(m, "WalkingPlan",
                          "Composed aSLIP (sagittal) + H-LIP (lateral) walking plan on a global clock "
                          "(systems/planners/walking_plan.h).")
      .def_static("periodic", &PeriodicPlan, py::arg("planner"), py::arg("steps"), py::arg("seed") = 1,
                  py::arg("first_stance") = WalkingDomain::kLeftStance, py::arg("stance_x") = 0.0,
                  py::arg("step_width") = 0.25,
                  "`steps` steps (SSP then DSP) of the periodic gait `planner` (AslipPeriodicGaitPlanner) solves from "
                  "`seed`; feet at y = +-step_width/2 [m], the first stance foot at x = stance_x [m]. ValueError for "
                  "bad arguments, RuntimeError if the gait NLP fails.")
      .def_property_readonly("end_time", &WalkingPlan::end_time, "[s]")
      .def_property_readonly("num_segments", [](const WalkingPlan& p) { return p.segments().size(); })
      .def(
          "segment",
          [](const WalkingPlan& p, int i) {
            if (i < 0 || i >= static_cast<int>(p.segments().size()))
              throw py::index_error("WalkingPlan.segment: index " + std::to_string(i) + " is outside [0, " +
                                    std::to_string(p.segments().size()) + ")");
            const WalkingPlanSegment& s = p.segments()[i];
            py::dict d;
            d["start_time"] = s.start_time;
            d["duration"] = s.duration;
            d["domain"] = s.domain;
            d["lambda_"] = s.lambda;
            d["lateral_pivot_y"] = s.lateral_pivot_y;
            d["left_foothold"] = Eigen::VectorXd(s.left_foothold);
            d["right_foothold"] = Eigen::VectorXd(s.right_foothold);
            return d;
          },
          py::arg("index"), "dict: start_time, duration (s), domain, lambda_ (1/s), lateral_pivot_y, footholds (m)")
      .def(
          "sample",
          [](const WalkingPlan& p, double t) {
            if (p.segments().empty()) throw py::value_error("WalkingPlan.sample: the plan is empty");
            return ReferenceToDict(p.Sample(t));
          },
          py::arg("t"),
          "The references at global time t [s] (clamped to [0, end_time]): com_position, com_velocity, "
          "com_acceleration (world, SI), left/right_foothold (x, y), normal_force [F_L, F_R] (N), domain.");
  py::class_<WalkingTrajectorySource, LeafSystem, Holder<WalkingTrajectorySource>>(
      m, "WalkingTrajectorySource",
      "Plays a WalkingPlan on the global clock (systems/planners/walking_trajectory_source.h). No inputs; outputs "
      "com (9: position, velocity, acceleration, world SI), footholds (4: left x, y, right x, y; m), "
      "normal_force_reference (2: F_L, F_R; N), domain (typed WalkingDomain).")
      .def(py::init([](std::string name, const WalkingPlan& plan) {
             return FromArguments([&] { return new WalkingTrajectorySource(std::move(name), plan); });
           }),
           py::arg("name"), py::arg("plan"))
      .def_property_readonly("plan", &WalkingTrajectorySource::plan);
}

}  // namespace rome::python
