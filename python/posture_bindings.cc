// Python bindings of the stepping-stones pre-impact posture NLP (systems/posture/pre_impact_posture_optimizer.h,
// Eq. (21) of the stepping-stones paper), Ipopt's options, and the step parameters the stepping-stones supervisor
// sends on its typed 'step_parameters' port (systems/planners/output_trajectories.h).
#include <memory>
#include <string>
#include <utility>

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "python/bindings.h"
#include "python/params.h"
#include "solvers/nlp/ipopt_solver.h"
#include "systems/planners/output_trajectories.h"
#include "systems/posture/pre_impact_posture_optimizer.h"

namespace py = pybind11;

namespace rome::python {
namespace {

const char* FallbackName(PreImpactPosture::Fallback fallback) {
  switch (fallback) {
    case PreImpactPosture::Fallback::kNone: return "none";
    case PreImpactPosture::Fallback::kPreviousSolution: return "previous_solution";
    case PreImpactPosture::Fallback::kNominalPose: return "nominal_pose";
  }
  return "unknown";
}

py::dict PostureToDict(const PreImpactPosture& p) {
  py::dict d;
  d["success"] = p.success;
  d["status"] = std::string(ToString(p.status));
  d["fallback"] = std::string(FallbackName(p.fallback));
  d["message"] = p.message;
  d["q"] = p.q;
  d["torso_pitch_rad"] = p.torso_pitch_rad;
  d["com_x_m"] = p.com_x_m;
  d["com_height_m"] = p.com_height_m;
  d["swing_foot"] = Eigen::VectorXd(p.swing_foot);
  d["cost"] = p.cost;
  d["iterations"] = p.iterations;
  d["solve_time_s"] = p.solve_time_s;
  return d;
}

void BindIpoptOptions(py::module_& m) {
  ParamsClass<IpoptSolverOptions>(m, "IpoptSolverOptions", "Ipopt's options (solvers/nlp/ipopt_solver.h).")
      .Field("tolerance", &IpoptSolverOptions::tolerance, "[-] Ipopt tol")
      .Field("constraint_violation_tolerance", &IpoptSolverOptions::constraint_violation_tolerance, "[unit of g]")
      .Field("acceptable_tolerance", &IpoptSolverOptions::acceptable_tolerance, "[-]")
      .Field("max_iterations", &IpoptSolverOptions::max_iterations)
      .Field("max_cpu_time", &IpoptSolverOptions::max_cpu_time, "[s]")
      .Field("linear_solver", &IpoptSolverOptions::linear_solver)
      .Field("print_level", &IpoptSolverOptions::print_level, "0 silent .. 12")
      .Field("bound_relax_factor", &IpoptSolverOptions::bound_relax_factor, "[-]")
      .Field("mu_strategy", &IpoptSolverOptions::mu_strategy, "'monotone' or 'adaptive'");
}

void BindPreImpactPosture(py::module_& m) {
  using P = PreImpactPostureParams;
  ParamsClass<P>(m, "PreImpactPostureParams", "Weights and tolerances of the pre-impact posture NLP, Eq. (21).")
      .Field("com_x_fraction", &P::com_x_fraction, "[-] epsilon: p_com,f^x,d = epsilon l")
      .Field("min_com_height_m", &P::min_com_height_m, "[m] above the lower foot")
      .Field("com_x_weight", &P::com_x_weight, "[1/m^2] w_x")
      .Field("torso_pitch_weight", &P::torso_pitch_weight, "[1/rad^2] w_phi")
      .Field("com_height_weight", &P::com_height_weight, "[1/m^2] w_z (0: not in Eq. (21))")
      .Field("posture_weight", &P::posture_weight, "[1/rad^2] w_r (ours)")
      .Field("hessian_difference_step", &P::hessian_difference_step, "[rad]")
      .Field("ipopt", &P::ipopt);
  using R = PreImpactPostureRequest;
  ParamsClass<R>(m, "PreImpactPostureRequest", "The next stone relative to the stance foot.")
      .Field("stance_contact", &R::stance_contact)
      .Field("swing_contact", &R::swing_contact)
      .Field("step_length_m", &R::step_length_m, "[m] l")
      .Field("step_height_m", &R::step_height_m, "[m] h")
      .Field("com_x_m", &R::com_x_m, "[m] NaN: epsilon l")
      .Field("com_height_m", &R::com_height_m, "[m] target of w_z; NaN: none")
      .Field("stance_foot_position", &R::stance_foot_position, "[m] world (x, z) of the stance foot in q*");
  py::class_<PreImpactPostureOptimizer>(
      m, "PreImpactPostureOptimizer",
      "Eq. (21) of the stepping-stones paper with Ipopt: the pre-impact posture q* that puts the swing contact on the "
      "next stone. solve() returns a dict (success, status, fallback, message, q, torso_pitch_rad, com_x_m, "
      "com_height_m, swing_foot, cost, iterations, solve_time_s); an unreachable stone is success = False with a "
      "fallback posture, a malformed request a ValueError.")
      .def(py::init([](const py::object& model, const P& params) {
             return FromArguments([&] { return new PreImpactPostureOptimizer(SharedModel(model), params); });
           }),
           py::arg("model"), py::arg("params") = P{})
      .def_property_readonly("params", &PreImpactPostureOptimizer::params)
      .def(
          "solve",
          // A malformed request is std::invalid_argument (ValueError); an unreachable stone is success = False.
          [](PreImpactPostureOptimizer& o, const R& request) { return PostureToDict(o.Solve(request)); },
          py::arg("request"))
      .def("reset", &PreImpactPostureOptimizer::Reset, "Forgets the previous solutions (warm starts, fallbacks).");
}

void BindStepOutputParameters(py::module_& m) {
  using S = StepOutputParameters;
  ParamsClass<S>(m, "StepOutputParameters",
                 "One step's output-trajectory parameters (Eq. (19)); the stepping-stones supervisor's typed "
                 "'step_parameters' port.")
      .Field("phi_0", &S::phi_0, "[rad]")
      .Field("phi_f", &S::phi_f, "[rad]")
      .Field("p_com_x0", &S::p_com_x0, "[m]")
      .Field("p_sw0_x", &S::p_sw0_x, "[m]")
      .Field("p_sw0_z", &S::p_sw0_z, "[m]")
      .Field("step_length", &S::step_length, "[m]")
      .Field("step_height", &S::step_height, "[m]")
      .Field("impact_fraction", &S::impact_fraction, "[-]")
      .Field("step_start_time", &S::step_start_time, "[s]")
      .Field("step_duration", &S::step_duration, "[s]");
  RegisterTypedValue<S>([](const S& s) { return py::cast(s); },
                        std::function<S(const py::handle&)>([](const py::handle& h) {
                          try {
                            return h.cast<S>();
                          } catch (const py::cast_error&) {
                            throw py::value_error(
                                "expected a "
                                "rome.StepOutputParameters, got " +
                                std::string(py::str(py::repr(h))));
                          }
                        }));
}

}  // namespace

void BindPosture(py::module_& m) {
  BindIpoptOptions(m);
  BindPreImpactPosture(m);
  BindStepOutputParameters(m);
}

}  // namespace rome::python
