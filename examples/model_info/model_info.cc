// model_info: load a ROME robot (URDF + sidecar) and print a JSON summary.
//   model_info ROBOT.urdf [--sidecar FILE]
// Default sidecar: ROBOT.rome.json next to the URDF. Exits 1 with a one-line error naming the
// file, the element and the problem for any bad input; never crashes.
#include <cstdio>
#include <exception>
#include <iostream>
#include <string>

#include <Eigen/Eigenvalues>
#include <nlohmann/json.hpp>

#include "systems/multibody/contact_dynamics.h"

namespace {

void PrintHelp() {
  std::cout << "usage: model_info ROBOT.urdf [--sidecar FILE]\n"
               "Loads a ROME robot description (URDF + JSON sidecar; default sidecar is\n"
               "ROBOT.rome.json next to the URDF) and prints JSON with dof, floating_base,\n"
               "total_mass_kg, actuated_joints (with torque limits), spring_joints, contacts,\n"
               "loop_closures and mass_matrix_condition at the nominal pose.\n";
}

std::string OneLine(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  return s;
}

int Run(int argc, char** argv) {
  std::string urdf, sidecar;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      PrintHelp();
      return 0;
    } else if (arg == "--sidecar") {
      if (i + 1 >= argc) throw std::invalid_argument("--sidecar needs a file name");
      sidecar = argv[++i];
    } else if (!arg.empty() && arg[0] == '-') {
      throw std::invalid_argument("unknown option '" + arg + "' (see --help)");
    } else if (urdf.empty()) {
      urdf = arg;
    } else {
      throw std::invalid_argument("unexpected argument '" + arg + "' (see --help)");
    }
  }
  if (urdf.empty()) throw std::invalid_argument("no URDF given (usage: model_info ROBOT.urdf [--sidecar FILE])");

  using rome::MultibodyModel;
  const MultibodyModel model = MultibodyModel::Load(urdf, sidecar);
  rome::MultibodyWorkspace ws(model);
  const Eigen::MatrixXd M = rome::CalcMassMatrix(model, ws, model.q_nominal());
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(M);
  const double cond = eig.eigenvalues().minCoeff() > 0.0
                          ? eig.eigenvalues().maxCoeff() / eig.eigenvalues().minCoeff()
                          : -1.0;

  nlohmann::ordered_json out;
  out["robot"] = model.name();
  out["urdf"] = model.urdf_path();
  out["sidecar"] = model.sidecar_path();
  out["dof"] = model.nv();
  out["floating_base"] = rome::ToString(model.floating_base());
  out["total_mass_kg"] = model.total_mass();
  out["joints"] = model.joint_names();
  auto acts = nlohmann::ordered_json::array();
  for (const auto& a : model.actuators())
    acts.push_back({{"joint", a.joint}, {"torque_limit_Nm", a.torque_limit_Nm}, {"gear_ratio", a.gear_ratio},
                    {"reflected_inertia_kgm2", a.reflected_inertia_kgm2}});
  out["actuated_joints"] = acts;
  auto springs = nlohmann::ordered_json::array();
  for (const auto& s : model.springs())
    springs.push_back({{"joint", s.joint}, {"stiffness_Nm_per_rad", s.stiffness_Nm_per_rad},
                       {"damping_Nms_per_rad", s.damping_Nms_per_rad}, {"rest_angle_rad", s.rest_angle_rad}});
  out["spring_joints"] = springs;
  auto contacts = nlohmann::ordered_json::array();
  for (int c = 0; c < model.num_contacts(); ++c) {
    const auto& info = model.contacts()[c];
    const Eigen::Vector3d p = rome::CalcContactPointPosition(model, ws, model.q_nominal(), c, 0);
    nlohmann::ordered_json j;
    j["name"] = info.name;
    j["link"] = info.link;
    j["type"] = rome::ToString(info.type);
    j["points"] = info.points.size();
    j["constraint_rows"] = info.num_rows;
    j["friction_coefficient"] = info.friction_coefficient;
    j["nominal_height_m"] = rome::CalcContactHeight(model, ws, model.q_nominal(), c);
    j["nominal_first_point_m"] = {p.x(), p.y(), p.z()};
    contacts.push_back(j);
  }
  out["contacts"] = contacts;
  auto loops = nlohmann::ordered_json::array();
  for (const auto& l : model.loop_closures()) {
    const Eigen::Vector3d pa = rome::CalcPointPosition(model, ws, model.q_nominal(), l.body_a, l.point_a);
    const Eigen::Vector3d pb = rome::CalcPointPosition(model, ws, model.q_nominal(), l.body_b, l.point_b);
    loops.push_back({{"name", l.name}, {"link_a", l.link_a}, {"link_b", l.link_b}, {"distance_m", l.distance_m},
                     {"nominal_error_m", (pa - pb).norm() - l.distance_m}});
  }
  out["loop_closures"] = loops;
  const Eigen::Vector3d com = rome::CalcComPosition(model, ws, model.q_nominal());
  out["nominal_com_m"] = {com.x(), com.y(), com.z()};
  out["mass_matrix_condition"] = cond;
  std::cout << out.dump(2) << std::endl;
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return Run(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "model_info: error: " << OneLine(e.what()) << std::endl;
  } catch (...) {
    std::cerr << "model_info: error: unknown exception" << std::endl;
  }
  return 1;
}
