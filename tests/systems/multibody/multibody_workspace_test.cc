// MultibodyWorkspace: no heap allocation once constructed (counted with a replaced global
// operator new), state caching, and copies that own an independent Bullet multibody.
#include "systems/multibody/multibody_workspace.h"

#include <atomic>
#include <cstdlib>
#include <random>

#include <gtest/gtest.h>

#include "systems/multibody/contact_dynamics.h"
#include "tests/systems/multibody/test_models.h"

#include "tests/common/allocation_counter.h"  // replaces operator new/malloc in this binary

namespace rome {
namespace {

class WorkspaceAllocationTest : public ::testing::TestWithParam<std::string> {};

TEST_P(WorkspaceAllocationTest, HotPathsDoNotAllocate) {
  if (!ROME_COUNT_MALLOC) GTEST_SKIP() << "malloc cannot be counted under AddressSanitizer";
  const MultibodyModel model = MultibodyModel::Load(GetParam(), "", {.euler_floating_base = true});
  MultibodyWorkspace ws(model);
  const int n = model.nv();
  std::mt19937 rng(5);
  Eigen::VectorXd q, v;
  test::RandomState(model, rng, q, v);
  Eigen::VectorXd q2 = q, v2 = v;
  q2[0] += 0.01;
  v2[0] += 0.01;
  const Eigen::VectorXd u = Eigen::VectorXd::Ones(model.nu());
  const Eigen::VectorXd none;
  Eigen::VectorXd qdd(n), tau(n), f = Eigen::VectorXd::Ones(n), out(n), v_plus(n);
  Eigen::VectorXd F(std::max(1, model.max_constraint_rows()));
  Eigen::MatrixXd J6(6, n), J3(3, n), Jc(3, n), AG(6, n), Mcol(n, 2);
  ContactSet all = 0;
  for (int c = 0; c < model.num_contacts(); ++c) all |= ContactBit(c);
  const ConstrainedDynamicsParameters params;
  const int foot = model.num_contacts() > 0 ? model.contacts()[0].body : model.num_bodies() - 1;
  double sink = 0.0;

  auto run = [&](const Eigen::VectorXd& qq, const Eigen::VectorXd& vv) {
    ws.SetState(model, qq, vv);
    sink += CalcMassMatrix(model, ws, qq)(0, 0);
    sink += CalcBiasForces(model, ws, qq, vv)[0];
    CalcInverseDynamics(model, ws, qq, vv, f, tau);
    CalcForwardDynamics(model, ws, qq, vv, u, none, qdd);
    ApplyInverseMassMatrix(model, ws, qq, f, out);
    Mcol.setOnes();
    SolveMassMatrix(model, ws, qq, Mcol);
    CalcFrameJacobian(model, ws, qq, foot, Eigen::Vector3d(0.1, 0, 0), J6);
    CalcPointJacobian(model, ws, qq, foot, Eigen::Vector3d(0.1, 0, 0), J3);
    sink += CalcFrameJdotQdot(model, ws, qq, vv, foot, Eigen::Vector3d(0.1, 0, 0))[0];
    sink += CalcComPosition(model, ws, qq)[0] + CalcComVelocity(model, ws, qq, vv)[0];
    CalcComJacobian(model, ws, qq, Jc);
    CalcCentroidalMomentumMatrix(model, ws, qq, AG);
    sink += CalcCentroidalMomentumBias(model, ws, qq, vv)[0];
    sink += CalcKineticEnergy(model, ws, qq, vv) + CalcPotentialEnergy(model, ws, qq);
    CalcConstrainedForwardDynamics(model, ws, qq, vv, u, all, params, qdd, F);
    CalcImpactMap(model, ws, qq, vv, all, params, v_plus, F);
    for (int c = 0; c < model.num_contacts(); ++c) {
      const ContactWrench w = ExtractContactWrench(model, ws, qq, all, F, c);
      sink += CheckContactForce(model, ws, qq, c, w).normal_force_N;
      sink += CalcContactPointVelocity(model, ws, qq, vv, c, 0)[0] + CalcContactHeight(model, ws, qq, c);
    }
  };
  run(q, v);  // warm-up (first use may size Bullet's scratch)
  // The counter itself works: a dynamic Eigen vector allocates.
  g_allocations = 0;
  g_counting = true;
  {
    Eigen::VectorXd probe(n + 7);
    probe.setZero();
    sink += probe.sum();
  }
  g_counting = false;
  ASSERT_GE(g_allocations.load(), 1);
  g_allocations = 0;
  g_counting = true;
  run(q2, v2);
  run(q, v);
  g_counting = false;
  EXPECT_EQ(g_allocations.load(), 0) << "heap allocations in hot paths";
  EXPECT_TRUE(std::isfinite(sink));
}

INSTANTIATE_TEST_SUITE_P(AllModels, WorkspaceAllocationTest, ::testing::ValuesIn(test::AllModelUrdfs()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           std::string name = info.param.substr(info.param.find_last_of('/') + 1);
                           return name.substr(0, name.find('.'));
                         });

// The workspace's Eigen forward-kinematics pass must reproduce Bullet's forwardKinematics (the
// reference) to round-off, for every model and several random states.
TEST_P(WorkspaceAllocationTest, EigenKinematicsMatchBulletForwardKinematics) {
  const MultibodyModel model = MultibodyModel::Load(GetParam(), "", {.euler_floating_base = true});
  MultibodyWorkspace ws(model);
  std::mt19937 rng(11);
  std::vector<Eigen::Isometry3d> X_bullet;
  for (int trial = 0; trial < 5; ++trial) {
    Eigen::VectorXd q, v;
    test::RandomState(model, rng, q, v);
    ws.SetPositions(model, q);
    ws.CalcBulletLinkPoses(X_bullet);
    ASSERT_EQ(static_cast<int>(X_bullet.size()), model.num_bodies());
    for (int b = 0; b < model.num_bodies(); ++b) {
      EXPECT_LT((ws.R_world_link(b) - X_bullet[b].linear()).cwiseAbs().maxCoeff(), 1e-12) << model.body(b).name;
      EXPECT_LT((ws.p_world_link(b) - X_bullet[b].translation()).cwiseAbs().maxCoeff(), 1e-12) << model.body(b).name;
      EXPECT_LT((ws.com_world(b) - X_bullet[b] * model.body(b).com).cwiseAbs().maxCoeff(), 1e-12) << model.body(b).name;
    }
  }
}

TEST(MultibodyWorkspaceTest, CopiesAreIndependentAndAgree) {
  const MultibodyModel model = MultibodyModel::Load(test::DataPath("biped3d.urdf"), "", {.euler_floating_base = true});
  MultibodyWorkspace a(model);
  std::mt19937 rng(6);
  Eigen::VectorXd q, v;
  test::RandomState(model, rng, q, v);
  const Eigen::VectorXd u = Eigen::VectorXd::Ones(model.nu());
  Eigen::VectorXd qdd_a(model.nv()), qdd_b(model.nv());
  CalcForwardDynamics(model, a, q, v, u, Eigen::VectorXd(), qdd_a);
  MultibodyWorkspace b(a);
  MultibodyWorkspace c = b;
  c = a;
  // Changing a's state must not affect b.
  CalcForwardDynamics(model, a, q * 0.5, v, u, Eigen::VectorXd(), qdd_b);
  CalcForwardDynamics(model, b, q, v, u, Eigen::VectorXd(), qdd_b);
  EXPECT_LT((qdd_a - qdd_b).norm(), 1e-12);
  CalcForwardDynamics(model, c, q, v, u, Eigen::VectorXd(), qdd_b);
  EXPECT_LT((qdd_a - qdd_b).norm(), 1e-12);
}

TEST(MultibodyWorkspaceTest, StateSizeErrors) {
  const MultibodyModel model = MultibodyModel::Load(test::DataPath("walker2d.urdf"), "", {.euler_floating_base = true});
  MultibodyWorkspace ws(model);
  EXPECT_THROW(ws.SetPositions(model, Eigen::VectorXd::Zero(3)), std::invalid_argument);
  ws.SetPositions(model, model.q_nominal());
  EXPECT_THROW(ws.SetVelocities(model, Eigen::VectorXd::Zero(9)), std::invalid_argument);
}

}  // namespace
}  // namespace rome
