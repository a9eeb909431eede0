// Constrained dynamics, impact map and ground-contact helpers: KKT residuals, Newton-Euler
// balance of the extracted contact wrenches, redundant rows, impact-map invariants.
#include "systems/multibody/contact_dynamics.h"

#include <algorithm>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "tests/systems/multibody/test_models.h"

namespace rome {
namespace {

// All contacts, skipping any on a rigid body (links welded by fixed joints) that already has
// an active contact: such rows are redundant and only consistent when J v = 0.
ContactSet AllIndependentContacts(const MultibodyModel& model) {
  auto rigid_root = [&](int b) {
    while (model.body(b).joint_type == MultibodyJointType::kFixed && model.body(b).parent >= 0)
      b = model.body(b).parent;
    return b;
  };
  ContactSet s = 0;
  std::vector<int> used;
  for (int c = 0; c < model.num_contacts(); ++c) {
    const int r = rigid_root(model.contacts()[c].body);
    if (std::find(used.begin(), used.end(), r) != used.end()) continue;
    used.push_back(r);
    s |= ContactBit(c);
  }
  return s;
}

class ContactDynamicsTest : public ::testing::TestWithParam<std::string> {};

TEST_P(ContactDynamicsTest, KktResidualsAndMomentumBalance) {
  const MultibodyModel model = MultibodyModel::Load(GetParam(), "", {.euler_floating_base = true});
  if (model.num_contacts() == 0 && model.num_loop_closures() == 0) GTEST_SKIP();
  MultibodyWorkspace ws(model);
  ConstrainedDynamicsParameters params;
  std::mt19937 rng(11);
  const int n = model.nv();
  for (int trial = 0; trial < 4; ++trial) {
    Eigen::VectorXd q, v;
    test::RandomState(model, rng, q, v);
    if (trial == 0) {
      q = model.q_nominal();
      v.setZero();
    }
    const Eigen::VectorXd u = Eigen::VectorXd::Random(model.nu()) * 10.0;
    const ContactSet active = AllIndependentContacts(model);
    Eigen::VectorXd qdd(n), F(model.max_constraint_rows());
    const int k = CalcConstrainedForwardDynamics(model, ws, q, v, u, active, params, qdd, F);
    ASSERT_EQ(k, CountConstraintRows(model, active));
    // Re-evaluate J, Jdot v, phi independently of the solve's scratch.
    CalcConstraintJacobian(model, ws, q, v, active);
    const Eigen::MatrixXd J = ws.J.topRows(k);
    const Eigen::VectorXd Jd = ws.Jdot_qdot.head(k), phi = ws.phi.head(k);
    Eigen::VectorXd tau(n);
    CalcInverseDynamics(model, ws, q, v, qdd, tau);
    const Eigen::VectorXd eom = tau - model.B() * u - J.transpose() * F.head(k);
    const double scale = std::max(1.0, (J.transpose() * F.head(k)).norm());
    EXPECT_LT(eom.norm(), 1e-8 * scale) << "equation-of-motion residual";
    const double a = params.baumgarte_alpha_per_s, b = params.baumgarte_beta_per_s;
    const Eigen::VectorXd acc = J * qdd + Jd + 2 * a * (J * v) + b * b * phi;
    EXPECT_LT(acc.norm(), 1e-6 * std::max(1.0, qdd.norm())) << "constraint residual " << acc.transpose();
    // Newton-Euler: m cddot = sum f + m g; d/dt k_G = sum (o - c) x f + tau (contacts only;
    // the loop-closure rods are internal forces).
    Eigen::MatrixXd Jc(3, n), AG(6, n);
    CalcComJacobian(model, ws, q, Jc);
    CalcCentroidalMomentumMatrix(model, ws, q, AG);
    const Vector6d hdot = AG * qdd + CalcCentroidalMomentumBias(model, ws, q, v);
    const Eigen::Vector3d com = CalcComPosition(model, ws, q);
    Eigen::Vector3d f_sum = model.total_mass() * model.gravity(), n_sum = Eigen::Vector3d::Zero();
    for (int c = 0; c < model.num_contacts(); ++c) {
      if (!(active & ContactBit(c))) continue;
      const ContactWrench w = ExtractContactWrench(model, ws, q, active, F, c);
      f_sum += w.force;
      n_sum += (w.origin - com).cross(w.force) + w.torque;
    }
    const double fscale = model.total_mass() * 9.81 + F.head(k).norm();
    EXPECT_LT((hdot.tail<3>() - f_sum).norm(), 1e-7 * fscale);
    if (model.is_planar()) {
      EXPECT_NEAR(hdot[1], n_sum.y(), 1e-7 * fscale);
    } else {
      EXPECT_LT((hdot.head<3>() - n_sum).norm(), 1e-7 * fscale);
    }
  }
}

TEST_P(ContactDynamicsTest, ImpactMapStopsContactsAndDissipates) {
  const MultibodyModel model = MultibodyModel::Load(GetParam(), "", {.euler_floating_base = true});
  if (model.num_contacts() == 0) GTEST_SKIP();
  MultibodyWorkspace ws(model);
  ConstrainedDynamicsParameters params;
  std::mt19937 rng(12);
  const int n = model.nv();
  for (int c = 0; c < model.num_contacts(); ++c) {
    Eigen::VectorXd q, v;
    test::RandomState(model, rng, q, v);
    q = model.q_nominal();
    v *= 2.0;
    const ContactSet active = ContactBit(c);
    Eigen::VectorXd v_plus(n), impulse(model.max_constraint_rows());
    const int k = CalcImpactMap(model, ws, q, v, active, params, v_plus, impulse);
    CalcConstraintJacobian(model, ws, q, v_plus, active);
    EXPECT_LT((ws.J.topRows(k) * v_plus).norm(), 1e-9 * std::max(1.0, v.norm()));
    for (size_t p = 0; p < model.contacts()[c].points.size(); ++p)
      EXPECT_LT(CalcContactPointVelocity(model, ws, q, v_plus, c, static_cast<int>(p)).norm(), 1e-9);
    const double T0 = CalcKineticEnergy(model, ws, q, v), T1 = CalcKineticEnergy(model, ws, q, v_plus);
    EXPECT_LE(T1, T0 + 1e-12);
    // Momentum jump equals the contact impulse: m dcdot = sum impulse forces.
    Eigen::MatrixXd Jc(3, n);
    CalcComJacobian(model, ws, q, Jc);
    const ContactWrench w = ExtractContactWrench(model, ws, q, active, impulse, c);
    EXPECT_LT((model.total_mass() * Jc * (v_plus - v) - w.force).norm(), 1e-8 * std::max(1.0, w.force.norm()));
    // Angular momentum about the impact point is conserved for point feet (the impulse acts
    // through it): L_P = k_G + (c - P) x m cdot.
    if (model.contacts()[c].type == ContactType::kPoint) {
      const Eigen::Vector3d P = CalcContactPointPosition(model, ws, q, c, 0);
      const Eigen::Vector3d com = CalcComPosition(model, ws, q);
      auto L_P = [&](const Eigen::VectorXd& vel) {
        const Vector6d hG = CalcCentroidalMomentum(model, ws, q, vel);
        return Eigen::Vector3d(hG.head<3>() + (com - P).cross(hG.tail<3>()));
      };
      const Eigen::Vector3d dL = L_P(v_plus) - L_P(v);
      if (model.is_planar())
        EXPECT_NEAR(dL.y(), 0.0, 1e-9 * std::max(1.0, L_P(v).norm()));
      else
        EXPECT_LT(dL.norm(), 1e-9 * std::max(1.0, L_P(v).norm()));
    }
  }
}

// The tree-sparse path (J M^-1 J^T = Z^T Z, Z = D^-1/2 L^-T J^T) and the dense-Cholesky
// fallback must give the same accelerations, forces and post-impact velocities.
TEST_P(ContactDynamicsTest, TreeFactorAndDenseCholeskyAgree) {
  const MultibodyModel model = MultibodyModel::Load(GetParam(), "", {.euler_floating_base = true});
  MultibodyWorkspace tree(model), dense(model);
  ASSERT_TRUE(tree.use_tree_factor);
  dense.use_tree_factor = false;
  const ContactSet active = AllIndependentContacts(model);
  const ConstrainedDynamicsParameters params;
  std::mt19937 rng(5);
  for (int trial = 0; trial < 3; ++trial) {
    Eigen::VectorXd q, v;
    test::RandomState(model, rng, q, v);
    const Eigen::VectorXd u = Eigen::VectorXd::Ones(model.nu());
    const int rows = std::max(1, model.max_constraint_rows());
    Eigen::VectorXd qdd_t(model.nv()), qdd_d(model.nv()), F_t(rows), F_d(rows);
    const int k = CalcConstrainedForwardDynamics(model, tree, q, v, u, active, params, qdd_t, F_t);
    CalcConstrainedForwardDynamics(model, dense, q, v, u, active, params, qdd_d, F_d);
    EXPECT_LT((qdd_t - qdd_d).norm(), 1e-8 * std::max(1.0, qdd_d.norm()));
    EXPECT_LT((F_t.head(k) - F_d.head(k)).norm(), 1e-8 * std::max(1.0, F_d.head(k).norm()));
    Eigen::VectorXd vp_t(model.nv()), vp_d(model.nv());
    CalcImpactMap(model, tree, q, v, active, params, vp_t, F_t);
    CalcImpactMap(model, dense, q, v, active, params, vp_d, F_d);
    EXPECT_LT((vp_t - vp_d).norm(), 1e-8 * std::max(1.0, vp_d.norm()));
  }
}

INSTANTIATE_TEST_SUITE_P(AllModels, ContactDynamicsTest, ::testing::ValuesIn(test::AllModelUrdfs()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           std::string name = info.param.substr(info.param.find_last_of('/') + 1);
                           return name.substr(0, name.find('.'));
                         });

TEST(ContactDynamicsUnitTest, RedundantRowsDoNotBreakTheSolve) {
  // biped3d: the flat left foot (6 rows) plus the toe point on a link welded to the same foot
  // (3 rows): 3 rows are redundant; the right line foot and the rod are also active.
  const MultibodyModel model = MultibodyModel::Load(test::DataPath("biped3d.urdf"), "", {.euler_floating_base = true});
  MultibodyWorkspace ws(model);
  ConstrainedDynamicsParameters params;
  const int n = model.nv();
  Eigen::VectorXd q = model.q_nominal(), v_rand = Eigen::VectorXd::Random(n);
  const ContactSet active = ContactBit(0) | ContactBit(1) | ContactBit(2);
  // A velocity consistent with the constraints (the post-impact velocity).
  Eigen::VectorXd v(n), impulse0(model.max_constraint_rows());
  CalcImpactMap(model, ws, q, v_rand, active, params, v, impulse0);
  Eigen::VectorXd qdd(n), F(model.max_constraint_rows());
  const int k =
      CalcConstrainedForwardDynamics(model, ws, q, v, Eigen::VectorXd::Zero(model.nu()), active, params, qdd, F);
  EXPECT_EQ(k, 6 + 5 + 3 + 1);
  ASSERT_TRUE(qdd.allFinite());
  ASSERT_TRUE(F.head(k).allFinite());
  CalcConstraintJacobian(model, ws, q, v, active);
  const Eigen::VectorXd acc = ws.J.topRows(k) * qdd + ws.Jdot_qdot.head(k) +
                              2 * params.baumgarte_alpha_per_s * (ws.J.topRows(k) * v) +
                              std::pow(params.baumgarte_beta_per_s, 2) * ws.phi.head(k);
  EXPECT_LT(acc.norm(), 1e-6);
  EXPECT_LT(F.head(k).norm(), 1e5);  // bounded despite the singular J M^-1 J^T
  // Same accelerations as without the redundant toe rows.
  Eigen::VectorXd qdd2(n), F2(model.max_constraint_rows());
  CalcConstrainedForwardDynamics(model, ws, q, v, Eigen::VectorXd::Zero(model.nu()), ContactBit(0) | ContactBit(1),
                                 params, qdd2, F2);
  EXPECT_LT((qdd - qdd2).norm(), 1e-6 * std::max(1.0, qdd.norm()));
  // Impact with redundant rows also works.
  Eigen::VectorXd v_plus(n), impulse(model.max_constraint_rows());
  CalcImpactMap(model, ws, q, v * 10, active, params, v_plus, impulse);
  EXPECT_LT(CalcContactPointVelocity(model, ws, q, v_plus, 2, 0).norm(), 1e-8);
}

TEST(ContactDynamicsUnitTest, NoContactsEqualsForwardDynamics) {
  const MultibodyModel model = MultibodyModel::Load(test::DataPath("walker2d.urdf"), "", {.euler_floating_base = true});
  MultibodyWorkspace ws(model);
  const int n = model.nv();
  Eigen::VectorXd q = model.q_nominal(), v = Eigen::VectorXd::Random(n), u = Eigen::VectorXd::Random(2);
  Eigen::VectorXd qdd(n), qdd_ref(n), F(4);
  EXPECT_EQ(CalcConstrainedForwardDynamics(model, ws, q, v, u, 0, {}, qdd, F), 0);
  CalcForwardDynamics(model, ws, q, v, u, Eigen::VectorXd(), qdd_ref);
  EXPECT_LT((qdd - qdd_ref).norm(), 1e-10 * qdd_ref.norm());
  EXPECT_THROW(CalcConstrainedForwardDynamics(model, ws, q, v, u, ContactBit(5), {}, qdd, F), std::invalid_argument);
}

TEST(ContactDynamicsUnitTest, StandingWalkerForcesAndFrictionCheck) {
  // Symmetric walker standing on both feet with zero velocity: each foot carries roughly half
  // the weight when the hips hold the posture (u from gravity compensation in the stance).
  const MultibodyModel model = MultibodyModel::Load(test::DataPath("walker2d.urdf"), "", {.euler_floating_base = true});
  MultibodyWorkspace ws(model);
  const int n = model.nv();
  Eigen::VectorXd q = model.q_nominal(), v = Eigen::VectorXd::Zero(n), u = Eigen::VectorXd::Zero(2);
  Eigen::VectorXd qdd(n), F(4);
  const ContactSet both = ContactBit(0) | ContactBit(1);
  CalcConstrainedForwardDynamics(model, ws, q, v, u, both, {}, qdd, F);
  const ContactWrench wl = ExtractContactWrench(model, ws, q, both, F, 0);
  const ContactWrench wr = ExtractContactWrench(model, ws, q, both, F, 1);
  EXPECT_NEAR(wl.force.z(), wr.force.z(), 1e-9 * wl.force.z());  // mirror-symmetric posture
  EXPECT_NEAR(wl.force.x(), -wr.force.x(), 1e-9 * wl.force.z());
  const ContactForceCheck cl = CheckContactForce(model, ws, q, 0, wl);
  EXPECT_GT(cl.normal_force_N, 0.0);
  EXPECT_TRUE(cl.unilateral_ok);
  EXPECT_NEAR(cl.friction_ratio, std::abs(wl.force.x()) / wl.force.z(), 1e-12);
  EXPECT_EQ(cl.friction_ok, cl.friction_ratio <= 0.8);
  EXPECT_TRUE(cl.cop_ok);
  // A pulling (negative normal) force fails the unilateral check.
  ContactWrench pull = wl;
  pull.force.z() = -1.0;
  EXPECT_FALSE(CheckContactForce(model, ws, q, 0, pull).ok());
}

TEST(ContactDynamicsUnitTest, FlatFootCenterOfPressureCheck) {
  const MultibodyModel model = MultibodyModel::Load(test::DataPath("biped3d.urdf"), "", {.euler_floating_base = true});
  MultibodyWorkspace ws(model);
  const Eigen::VectorXd q = model.q_nominal();
  ContactWrench w;
  w.origin = CalcPointPosition(model, ws, q, model.contacts()[0].body, model.contacts()[0].frame_origin);
  w.force = Eigen::Vector3d(10.0, 0.0, 300.0);
  EXPECT_TRUE(CheckContactForce(model, ws, q, 0, w).ok());
  // Shift the CoP 0.2 m forward (foot is 0.18 m long): tau_y = -dx F_z.
  w.torque = Eigen::Vector3d(0.0, -0.2 * 300.0, 0.0);
  const ContactForceCheck c = CheckContactForce(model, ws, q, 0, w);
  EXPECT_NEAR(c.cop.x() - w.origin.x(), 0.2, 1e-12);
  EXPECT_FALSE(c.cop_ok);
  // Friction cone violation.
  w.torque.setZero();
  w.force = Eigen::Vector3d(300.0, 0.0, 300.0);
  EXPECT_FALSE(CheckContactForce(model, ws, q, 0, w).friction_ok);
}

}  // namespace
}  // namespace rome
