// model_info: load a ROME robot (URDF + sidecar) and print a JSON summary.
//   model_info ROBOT.urdf [--sidecar FILE] [--repair-inertia] [--allow-files-outside-package]
//              [--euler-base | --quaternion-base]
//   model_info ROBOT.rome.json [...]   (a sidecar alone: its "urdf" entry names the URDF, as for --robot)
// Default sidecar: ROBOT.rome.json next to the URDF. Exits 1 with a one-line error naming the
// file, the element and the problem for any bad input; never crashes.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>
#include <nlohmann/json.hpp>

#include "examples/common/cli.h"
#include "systems/multibody/contact_dynamics.h"

namespace {

void PrintHelp() {
  std::cout << "usage: model_info ROBOT.urdf [--sidecar FILE] [--repair-inertia] [--allow-files-outside-package]\n"
               "                  [--euler-base | --quaternion-base]\n"
               "       model_info ROBOT.rome.json [--repair-inertia] [--allow-files-outside-package]\n"
               "                  [--euler-base | --quaternion-base]\n"
               "Loads a ROME robot description (URDF + JSON sidecar; default sidecar is\n"
               "ROBOT.rome.json next to the URDF; a sidecar given alone names its URDF in its\n"
               "\"urdf\" entry) and prints JSON with dof (= nv), nq, nv, floating_base (fixed,\n"
               "planar, quaternion: the default for a spatial base, nq = nv + 1; or\n"
               "spatial_euler: ZYX Euler, nq = nv),\n"
               "total_mass_kg, warnings (one line per merged link, massless frame, repaired\n"
               "inertia, ...), bodies (after merging fixed joints), frames (every URDF link),\n"
               "actuated_joints (with torque limits), spring_joints, contacts, loop_closures,\n"
               "load_time_ms and mass_matrix_condition at the nominal pose (omitted for a\n"
               "robot with 0 degrees of freedom, or when M is singular: see warnings).\n"
               "  --repair-inertia  project a non-physical <inertia> onto the nearest physical\n"
               "                    one (with a warning) instead of rejecting the file\n"
               "  --allow-files-outside-package  for a package you trust: its sidecar may name\n"
               "                    files outside its own folder (an absolute path, ../, a link)\n"
               "  --euler-base      load a spatial floating base as the ZYX-Euler chain (nq = nv),\n"
               "                    as the sidecar's \"floating_base\": \"spatial_euler\"\n"
               "  --quaternion-base  load a spatial floating base as the quaternion free-flyer\n"
               "                    even if the sidecar says \"spatial_euler\"\n"
               "A relative path is looked up in ROME's data folders; write ./PATH for a file in\n"
               "the current folder.\n";
}

int Run(int argc, char** argv) {
  std::string urdf, sidecar;
  rome::LoadOptions options;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      PrintHelp();
      return 0;
    } else if (arg == "--sidecar") {
      if (i + 1 >= argc) throw std::invalid_argument("--sidecar needs a file name");
      sidecar = argv[++i];
    } else if (arg == "--repair-inertia") {
      options.repair_inertia = true;
    } else if (arg == "--allow-files-outside-package") {
      options.allow_files_outside_package = true;
    } else if (arg == "--quaternion-base") {
      options.quaternion_floating_base = true;
    } else if (arg == "--euler-base") {
      options.euler_floating_base = true;
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
  const auto t0 = std::chrono::steady_clock::now();
  const bool sidecar_alone = urdf.size() >= 5 && urdf.compare(urdf.size() - 5, 5, ".json") == 0;
  if (sidecar_alone && !sidecar.empty())
    throw std::invalid_argument(
        "--sidecar: '" + urdf +
        "' is a sidecar already (it names its URDF); give ROBOT.urdf --sidecar FILE, or the sidecar alone");
  const MultibodyModel model =
      sidecar_alone ? MultibodyModel::LoadFromSidecar(urdf, options) : MultibodyModel::Load(urdf, sidecar, options);
  const double load_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  rome::MultibodyWorkspace ws(model);
  std::vector<std::string> warnings = model.warnings();
  // cond(M) from the eigenvalues only (O(n^3) with a small constant; the loader caps n at
  // rome::kMaxDofs). A 0-DOF robot has no mass matrix and no condition number.
  double cond = 0.0;
  bool has_cond = false;
  if (model.nv() > 0) {
    const Eigen::MatrixXd M = rome::CalcMassMatrix(model, ws, model.q_nominal());
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(M, Eigen::EigenvaluesOnly);
    const double lo = eig.eigenvalues().minCoeff(), hi = eig.eigenvalues().maxCoeff();
    if (eig.info() == Eigen::Success && lo > 0.0 && std::isfinite(hi / lo)) {
      cond = hi / lo;
      has_cond = true;
    } else {
      warnings.push_back("the mass matrix at the nominal pose is singular or not finite: no condition number");
    }
  }

  nlohmann::ordered_json out;
  out["robot"] = model.name();
  out["urdf"] = model.urdf_path();
  out["sidecar"] = model.sidecar_path();
  out["dof"] = model.nv();
  out["nq"] = model.nq();
  out["nv"] = model.nv();
  out["floating_base"] = model.base_kind();
  out["total_mass_kg"] = model.total_mass();
  out["warnings"] = warnings;
  auto bodies = nlohmann::ordered_json::array();
  for (const auto& b : model.bodies()) {
    if (b.is_virtual) continue;
    nlohmann::ordered_json j;
    j["name"] = b.name;
    j["joint"] = b.joint_name;
    j["mass_kg"] = b.mass;
    j["merged_links"] = b.merged_links;
    bodies.push_back(j);
  }
  out["bodies"] = bodies;
  auto frames = nlohmann::ordered_json::array();
  for (const auto& f : model.frames()) {
    const Eigen::Vector3d p = f.X_body_frame.translation();
    frames.push_back(
        {{"name", f.name}, {"body", model.body(f.body).name}, {"position_in_body_m", {p.x(), p.y(), p.z()}}});
  }
  out["frames"] = frames;
  out["joints"] = model.joint_names();
  auto acts = nlohmann::ordered_json::array();
  for (const auto& a : model.actuators())
    acts.push_back({{"joint", a.joint},
                    {"torque_limit_Nm", a.torque_limit_Nm},
                    {"gear_ratio", a.gear_ratio},
                    {"reflected_inertia_kgm2", a.reflected_inertia_kgm2}});
  out["actuated_joints"] = acts;
  auto springs = nlohmann::ordered_json::array();
  for (const auto& s : model.springs())
    springs.push_back({{"joint", s.joint},
                       {"stiffness_Nm_per_rad", s.stiffness_Nm_per_rad},
                       {"damping_Nms_per_rad", s.damping_Nms_per_rad},
                       {"rest_angle_rad", s.rest_angle_rad}});
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
    loops.push_back({{"name", l.name},
                     {"link_a", l.link_a},
                     {"link_b", l.link_b},
                     {"distance_m", l.distance_m},
                     {"nominal_error_m", (pa - pb).norm() - l.distance_m}});
  }
  out["loop_closures"] = loops;
  const Eigen::Vector3d com = rome::CalcComPosition(model, ws, model.q_nominal());
  out["nominal_com_m"] = {com.x(), com.y(), com.z()};
  out["load_time_ms"] = load_ms;
  if (has_cond) out["mass_matrix_condition"] = cond;
  // The loader rejects names that are not valid UTF-8; replace is a backstop, never a throw.
  std::cout << out.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) << std::endl;
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return Run(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "model_info: error: " << rome::examples::OneLine(e.what()) << std::endl;
  } catch (...) { std::cerr << "model_info: error: unknown exception" << std::endl; }
  return 1;
}
