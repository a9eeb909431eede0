#pragma once
// Shared helpers for the multibody tests: model paths and random states.
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "systems/multibody/multibody_model.h"
#include "tests/common/source_path.h"

namespace rome::test {

inline std::string DataPath(const std::string& file) {
  return rome::test::SourcePath("tests/systems/multibody/data/" + file);
}

// Test models plus any robots/* models present (robots/<name>/<name>.urdf + sidecar).
inline std::vector<std::string> AllModelUrdfs() {
  std::vector<std::string> out = {DataPath("double_pendulum.urdf"), DataPath("walker2d.urdf"), DataPath("biped3d.urdf"),
                                  DataPath("spring_arm.urdf")};
  for (const std::string name : {"amber", "exoskeleton", "cassie", "cassie_planar"}) {
    const std::string p = rome::test::SourcePath("robots/" + name + "/" + name + ".urdf");
    const std::string s = rome::test::SourcePath("robots/" + name + "/" + name + ".rome.json");
    if (std::filesystem::exists(p) && std::filesystem::exists(s)) out.push_back(p);
  }
  return out;
}

// Random state near the nominal pose: joints +-0.5 rad, base orientation +-0.4 rad,
// velocities +-1.
inline void RandomState(const MultibodyModel& model, std::mt19937& rng, Eigen::VectorXd& q, Eigen::VectorXd& v) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  q = model.q_nominal();
  v.resize(model.nv());
  for (int i = 0; i < model.nq(); ++i) {  // nq = nv + 1 on a quaternion base: v has one entry fewer
    q[i] += 0.5 * u(rng);
    const double w = u(rng);  // drawn for every i, so that the sequence does not depend on the base
    if (i < model.nv()) v[i] = w;
  }
}

}  // namespace rome::test
