// multibody_benchmark: cost of the multibody model layer per robot (µs per call).
// Every iteration alternates between two states, so each call pays the full kinematics pass
// (Bullet forward kinematics + tree sweep) in addition to the quantity itself.
//   ./multibody_benchmark [--benchmark_filter=cassie]
#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "systems/multibody/contact_dynamics.h"
#include "tests/common/source_path.h"

namespace rome {
namespace {

LoadOptions BaseOptions(bool quaternion) {
  LoadOptions options;
  options.quaternion_floating_base = quaternion;
  options.euler_floating_base = !quaternion;
  return options;
}

struct Fixture {
  explicit Fixture(const std::string& urdf, bool quaternion = false)
      : model(MultibodyModel::Load(urdf, "", BaseOptions(quaternion))), ws(model) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const int n = model.nv();
    Eigen::VectorXd dq(n);
    for (int s = 0; s < 2; ++s) {
      q[s].resize(model.nq());
      v[s].resize(n);
      for (int i = 0; i < n; ++i) {
        dq[i] = 0.05 * u(rng);
        v[s][i] = u(rng);
      }
      model.Integrate(model.q_nominal(), dq, 1.0, q[s]);  // q_nominal + dq on the Euler base
    }
    uin = Eigen::VectorXd::Ones(model.nu());
    f = Eigen::VectorXd::Ones(n);
    out.resize(n);
    qdd.resize(n);
    F.resize(std::max(1, model.max_constraint_rows()));
    J6.resize(6, n);
    AG.resize(6, n);
    for (int c = 0; c < model.num_contacts(); ++c) {
      // Independent contacts (one per rigid body).
      bool dup = false;
      for (int d = 0; d < c; ++d) dup |= model.contacts()[d].body == model.contacts()[c].body;
      if (!dup) contacts |= ContactBit(c);
    }
  }
  MultibodyModel model;
  MultibodyWorkspace ws;
  Eigen::VectorXd q[2], v[2], uin, f, out, qdd, F;
  Eigen::MatrixXd J6, AG;
  ContactSet contacts = 0;
  ConstrainedDynamicsParameters params;
};

using Body = void (*)(Fixture&, int);

void Register(const std::string& robot, const std::shared_ptr<Fixture>& fx, const std::string& what, Body body) {
  benchmark::RegisterBenchmark((robot + "/" + what).c_str(), [fx, body](benchmark::State& state) {
    int s = 0;
    for (auto _ : state) {
      body(*fx, s);
      s ^= 1;
    }
  })->Unit(benchmark::kMicrosecond);
}

// Issue 43: the kernels on the ZYX-Euler base and on the quaternion free-flyer, per spatial robot, at the same
// (randomised) states: BaseCompare/<robot>/<base>/<kernel>, base = euler, quaternion_six_joints (the free-flyer run
// through its six 1-DOF virtual joints, MultibodyWorkspace::SetFreeFlyerAsOneJoint(false)) or quaternion (one 6-DOF
// joint, the default).
void RegisterBaseComparison() {
  std::vector<std::pair<std::string, std::string>> robots;
  for (const std::string name : {"cassie", "exoskeleton"}) {
    const std::string p = rome::test::SourcePath("robots/" + name + "/" + name + ".urdf");
    if (std::filesystem::exists(p)) robots.emplace_back(name, p);
  }
  robots.emplace_back("biped3d_test", rome::test::SourcePath("tests/systems/multibody/data/biped3d.urdf"));
  for (const auto& [name, path] : robots) {
    for (const char* base : {"euler", "quaternion_six_joints", "quaternion"}) {
      const std::string kind = base;
      auto fx = std::make_shared<Fixture>(path, kind != "euler");
      if (kind == "quaternion_six_joints") fx->ws.SetFreeFlyerAsOneJoint(false);
      const std::string prefix = "BaseCompare/" + name + "/" + kind;
      // The position kinematics alone (every kernel below pays it: the states alternate).
      Register(prefix, fx, "Kinematics_q", [](Fixture& x, int s) {
        x.ws.SetPositions(x.model, x.q[s]);
        benchmark::DoNotOptimize(x.ws.R_world_link(x.model.num_bodies() - 1).data());
      });
      Register(prefix, fx, "CRBA",
               [](Fixture& x, int s) { benchmark::DoNotOptimize(CalcMassMatrix(x.model, x.ws, x.q[s]).data()); });
      Register(prefix, fx, "RNEA_h", [](Fixture& x, int s) {
        benchmark::DoNotOptimize(CalcBiasForces(x.model, x.ws, x.q[s], x.v[s]).data());
      });
      Register(prefix, fx, "RNEA_tau(q,v,a)", [](Fixture& x, int s) {
        CalcRnea(x.model, x.ws, x.q[s], x.v[s], x.f, x.out);
        benchmark::DoNotOptimize(x.out.data());
      });
      Register(prefix, fx, "InverseDynamics", [](Fixture& x, int s) {
        CalcInverseDynamics(x.model, x.ws, x.q[s], x.v[s], x.f, x.out);
        benchmark::DoNotOptimize(x.out.data());
      });
      Register(prefix, fx, "ForwardDynamics_CRBA_LTDL", [](Fixture& x, int s) {
        CalcConstrainedForwardDynamics(x.model, x.ws, x.q[s], x.v[s], x.uin, 0, x.params, x.qdd, x.F);
        benchmark::DoNotOptimize(x.qdd.data());
      });
    }
  }
}

void RegisterAll() {
  // Loading (URDF parse + merging fixed joints + checks): a 100-link humanoid, 61 DOF, 38 welded
  // links (issue 18 asks for < 50 ms), and the robots.
  for (const std::string& path : {rome::test::SourcePath("tests/systems/multibody/data/humanoid_100.urdf"),
                                  rome::test::SourcePath("robots/cassie/cassie.urdf")}) {
    const std::string name = std::filesystem::path(path).stem().string();
    benchmark::RegisterBenchmark(("Load/" + name).c_str(), [path](benchmark::State& state) {
      for (auto _ : state) {
        MultibodyModel model = MultibodyModel::Load(path);
        benchmark::DoNotOptimize(model.nv());
      }
    })->Unit(benchmark::kMillisecond);
  }
  std::vector<std::pair<std::string, std::string>> robots;
  for (const std::string name : {"amber", "cassie_planar", "cassie", "exoskeleton"}) {
    const std::string p = rome::test::SourcePath("robots/" + name + "/" + name + ".urdf");
    if (std::filesystem::exists(p)) robots.emplace_back(name, p);
  }
  robots.emplace_back("biped3d_test", rome::test::SourcePath("tests/systems/multibody/data/biped3d.urdf"));
  for (const auto& [name, path] : robots) {
    auto fx = std::make_shared<Fixture>(path);
    Register(name, fx, "Kinematics(q,v)", [](Fixture& x, int s) {
      x.ws.SetState(x.model, x.q[s], x.v[s]);
      benchmark::DoNotOptimize(x.ws.V(x.model.num_bodies() - 1));
    });
    Register(name, fx, "MassMatrix_CRBA",
             [](Fixture& x, int s) { benchmark::DoNotOptimize(CalcMassMatrix(x.model, x.ws, x.q[s]).data()); });
    Register(name, fx, "BiasForces_RNEA",
             [](Fixture& x, int s) { benchmark::DoNotOptimize(CalcBiasForces(x.model, x.ws, x.q[s], x.v[s]).data()); });
    Register(name, fx, "InverseDynamics", [](Fixture& x, int s) {
      CalcInverseDynamics(x.model, x.ws, x.q[s], x.v[s], x.f, x.out);
      benchmark::DoNotOptimize(x.out.data());
    });
    Register(name, fx, "MinvOperator_Bullet", [](Fixture& x, int s) {
      ApplyInverseMassMatrix(x.model, x.ws, x.q[s], x.f, x.out);
      benchmark::DoNotOptimize(x.out.data());
    });
    Register(name, fx, "MinvOperator_CholeskyOfM", [](Fixture& x, int s) {
      x.out = x.f;
      SolveMassMatrix(x.model, x.ws, x.q[s], x.out);
      benchmark::DoNotOptimize(x.out.data());
    });
    Register(name, fx, "ForwardDynamics_BulletABA", [](Fixture& x, int s) {
      CalcForwardDynamics(x.model, x.ws, x.q[s], x.v[s], x.uin, Eigen::VectorXd(), x.qdd);
      benchmark::DoNotOptimize(x.qdd.data());
    });
    Register(name, fx, "ForwardDynamics_CRBA_Cholesky", [](Fixture& x, int s) {
      CalcConstrainedForwardDynamics(x.model, x.ws, x.q[s], x.v[s], x.uin, 0, x.params, x.qdd, x.F);
      benchmark::DoNotOptimize(x.qdd.data());
    });
    Register(name, fx, "ConstrainedForwardDynamics_AllFeet", [](Fixture& x, int s) {
      CalcConstrainedForwardDynamics(x.model, x.ws, x.q[s], x.v[s], x.uin, x.contacts, x.params, x.qdd, x.F);
      benchmark::DoNotOptimize(x.qdd.data());
    });
    Register(name, fx, "ImpactMap_AllFeet", [](Fixture& x, int s) {
      CalcImpactMap(x.model, x.ws, x.q[s], x.v[s], x.contacts, x.params, x.out, x.F);
      benchmark::DoNotOptimize(x.out.data());
    });
    Register(name, fx, "FootJacobians_J_and_JdotV", [](Fixture& x, int s) {
      for (int c = 0; c < x.model.num_contacts(); ++c) {
        const ContactInfo& info = x.model.contacts()[c];
        CalcFrameJacobian(x.model, x.ws, x.q[s], info.body, info.frame_origin, x.J6);
        benchmark::DoNotOptimize(CalcFrameJdotQdot(x.model, x.ws, x.q[s], x.v[s], info.body, info.frame_origin));
      }
      benchmark::DoNotOptimize(x.J6.data());
    });
    Register(name, fx, "CentroidalMomentumMatrix_A_G_and_bias", [](Fixture& x, int s) {
      CalcCentroidalMomentumMatrix(x.model, x.ws, x.q[s], x.AG);
      benchmark::DoNotOptimize(CalcCentroidalMomentumBias(x.model, x.ws, x.q[s], x.v[s]));
      benchmark::DoNotOptimize(x.AG.data());
    });
  }
  RegisterBaseComparison();
}

}  // namespace
}  // namespace rome

int main(int argc, char** argv) {
  rome::RegisterAll();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
