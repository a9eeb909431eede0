// Tests of M (CRBA), h (RNEA), Bullet forward dynamics and M^-1, springs, and conservation
// laws in flight. References: closed forms, finite differences of the kinetic energy built
// from Bullet's link poses, the Lagrangian, and RK4 integration.
#include "systems/multibody/multibody_dynamics.h"

#include <cmath>
#include <cstdio>
#include <functional>
#include <random>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include "tests/systems/multibody/test_models.h"

namespace rome {
namespace {

using test::DataPath;

Eigen::Vector3d RotationLog(const Eigen::Matrix3d& R) {
  Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

// Kinetic energy from finite differences of the link poses (workspace forward kinematics, checked
// against Bullet in multibody_workspace_test):
// T = sum 1/2 m |cdot|^2 + 1/2 w^T I_world w + 1/2 sum I_r v^2. Independent of CRBA.
double KineticEnergyFromPoses(const MultibodyModel& model, MultibodyWorkspace& ws, const Eigen::VectorXd& q,
                              const Eigen::VectorXd& v) {
  const double eps = 1e-6;
  const Eigen::VectorXd qp = q + eps * v, qm = q - eps * v;
  double T = 0.0;
  for (int b = 0; b < model.num_bodies(); ++b) {
    const MultibodyBody& body = model.body(b);
    if (body.mass == 0.0) continue;
    ws.SetPositions(model, qp);
    const Eigen::Vector3d cp = ws.com_world(b);
    const Eigen::Matrix3d Rp = ws.R_world_link(b);
    ws.SetPositions(model, qm);
    const Eigen::Vector3d cm = ws.com_world(b);
    const Eigen::Matrix3d Rm = ws.R_world_link(b);
    ws.SetPositions(model, q);
    const Eigen::Matrix3d R = ws.R_world_link(b);
    const Eigen::Vector3d cdot = (cp - cm) / (2 * eps);
    const Eigen::Vector3d w = RotationLog(Rp * Rm.transpose()) / (2 * eps);
    T += 0.5 * body.mass * cdot.squaredNorm() + 0.5 * w.dot(R * body.inertia * R.transpose() * w);
  }
  T += 0.5 * (model.reflected_inertia().array() * v.array().square()).sum();
  return T;
}

TEST(MultibodyDynamicsTest, DoublePendulumMassMatrixMatchesClosedForm) {
  const MultibodyModel model =
      MultibodyModel::Load(DataPath("double_pendulum.urdf"), "", {.euler_floating_base = true});
  MultibodyWorkspace ws(model);
  ASSERT_EQ(model.nv(), 2);
  // Link 1: m1 = 1.5, COM 0.3 from the shoulder axis (the y offset lies along the axis),
  // I1yy = 0.03; link 2: m2 = 0.8, COM 0.25 below the elbow, l1 = 0.7, I2yy from the rotated
  // inertia tensor (only the component about the y axis matters for rotation about y).
  const double m1 = 1.5, c1 = 0.3, I1 = 0.03, m2 = 0.8, c2 = 0.25, l1 = 0.7;
  const MultibodyBody& lower = model.body(model.BodyIndex("lower"));
  const double I2 = lower.inertia(1, 1);
  for (double q2 : {-1.3, 0.0, 0.4, 2.0}) {
    Eigen::Vector2d q(0.7, q2);
    const Eigen::MatrixXd& M = CalcMassMatrix(model, ws, q);
    const double M11 = I1 + m1 * c1 * c1 + I2 + m2 * (l1 * l1 + c2 * c2 + 2 * l1 * c2 * std::cos(q2));
    const double M12 = I2 + m2 * (c2 * c2 + l1 * c2 * std::cos(q2));
    const double M22 = I2 + m2 * c2 * c2;
    EXPECT_NEAR(M(0, 0), M11, 1e-12);
    EXPECT_NEAR(M(0, 1), M12, 1e-12);
    EXPECT_NEAR(M(1, 0), M12, 1e-12);
    EXPECT_NEAR(M(1, 1), M22, 1e-12);
  }
  // Gravity torque at rest: h = dV/dq, V = -sum m g . c.
  Eigen::Vector2d q(0.7, 0.5), v(0, 0);
  const Eigen::VectorXd& h = CalcBiasForces(model, ws, q, v);
  const double g = 9.81;
  const double h2 = m2 * g * c2 * std::sin(q[0] + q[1]);
  const double h1 = m1 * g * c1 * std::sin(q[0]) + m2 * g * (l1 * std::sin(q[0])) + h2;
  EXPECT_NEAR(h[0], h1, 1e-12);
  EXPECT_NEAR(h[1], h2, 1e-12);
}

TEST(MultibodyDynamicsTest, MassMatrixIsSymmetricPositiveDefiniteAndEqualsKineticEnergyHessian) {
  std::mt19937 rng(1);
  for (const std::string& urdf : test::AllModelUrdfs()) {
    SCOPED_TRACE(urdf);
    const MultibodyModel model = MultibodyModel::Load(urdf, "", {.euler_floating_base = true});
    MultibodyWorkspace ws(model);
    for (int trial = 0; trial < 3; ++trial) {
      Eigen::VectorXd q, v;
      test::RandomState(model, rng, q, v);
      const Eigen::MatrixXd M = CalcMassMatrix(model, ws, q);
      EXPECT_LT((M - M.transpose()).norm(), 1e-12);
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(M);
      EXPECT_GT(eig.eigenvalues().minCoeff(), 0.0);
      // T is quadratic in v: M_ij = T(e_i + e_j) - T(e_i) - T(e_j) (polarisation).
      const int n = model.nv();
      Eigen::VectorXd Tii(n);
      for (int i = 0; i < n; ++i) Tii[i] = KineticEnergyFromPoses(model, ws, q, Eigen::VectorXd::Unit(n, i));
      double max_err = 0.0;
      for (int i = 0; i < n; ++i) {
        for (int j = i; j < n; ++j) {
          const double Mij =
              i == j ? 2.0 * Tii[i]
                     : KineticEnergyFromPoses(model, ws, q, Eigen::VectorXd::Unit(n, i) + Eigen::VectorXd::Unit(n, j)) -
                           Tii[i] - Tii[j];
          max_err = std::max(max_err, std::abs(Mij - M(i, j)));
        }
      }
      EXPECT_LT(max_err, 1e-6 * std::max(1.0, M.norm())) << "max |M - d2T/dv2| = " << max_err;
      // The workspace kinetic energy agrees with 1/2 v^T M v.
      EXPECT_NEAR(CalcKineticEnergy(model, ws, q, v), 0.5 * v.dot(M * v), 1e-10 * M.norm());
    }
  }
}

TEST(MultibodyDynamicsTest, BiasForcesMatchLagrangianFiniteDifferences) {
  std::mt19937 rng(2);
  for (const std::string& urdf : test::AllModelUrdfs()) {
    SCOPED_TRACE(urdf);
    const MultibodyModel model = MultibodyModel::Load(urdf, "", {.euler_floating_base = true});
    MultibodyWorkspace ws(model);
    const int n = model.nv();
    for (int trial = 0; trial < 3; ++trial) {
      Eigen::VectorXd q, v;
      test::RandomState(model, rng, q, v);
      const Eigen::VectorXd h = CalcBiasForces(model, ws, q, v);
      // h = d/dt(dT/dv) - dT/dq + dV_gravity/dq with qdd = 0: Mdot v - dT/dq + dV/dq.
      const double eps = 1e-6;
      Eigen::MatrixXd Mp = CalcMassMatrix(model, ws, q + eps * v);
      Eigen::MatrixXd Mm = CalcMassMatrix(model, ws, q - eps * v);
      Eigen::VectorXd ref = (Mp - Mm) / (2 * eps) * v;
      for (int i = 0; i < n; ++i) {
        const Eigen::VectorXd e = Eigen::VectorXd::Unit(n, i) * eps;
        const double Tp = 0.5 * v.dot(CalcMassMatrix(model, ws, q + e) * v);
        const double Tm = 0.5 * v.dot(CalcMassMatrix(model, ws, q - e) * v);
        // Gravity potential only (springs are not part of h).
        auto Vg = [&](const Eigen::VectorXd& qq) {
          ws.SetPositions(model, qq);
          double V = 0;
          for (int b = 0; b < model.num_bodies(); ++b) V -= model.body(b).mass * model.gravity().dot(ws.com_world(b));
          return V;
        };
        ref[i] += -(Tp - Tm) / (2 * eps) + (Vg(q + e) - Vg(q - e)) / (2 * eps);
      }
      EXPECT_LT((h - ref).norm(), 1e-5 * std::max(1.0, h.norm()))
          << "h = " << h.transpose() << "\nref = " << ref.transpose();
    }
  }
}

TEST(MultibodyDynamicsTest, BulletForwardDynamicsAndInverseMassMatchCrbaAndRnea) {
  std::mt19937 rng(3);
  for (const std::string& urdf : test::AllModelUrdfs()) {
    SCOPED_TRACE(urdf);
    const MultibodyModel model = MultibodyModel::Load(urdf, "", {.euler_floating_base = true});
    MultibodyWorkspace ws(model);
    const int n = model.nv();
    for (int trial = 0; trial < 3; ++trial) {
      Eigen::VectorXd q, v;
      test::RandomState(model, rng, q, v);
      Eigen::VectorXd u = Eigen::VectorXd::Random(model.nu()) * 20.0;
      Eigen::VectorXd tau_ext = Eigen::VectorXd::Random(n) * 5.0;
      Eigen::VectorXd qdd(n);
      CalcForwardDynamics(model, ws, q, v, u, tau_ext, qdd);
      // Residual of M qdd + h - B u - tau_spring - tau_ext.
      Eigen::VectorXd tau(n);
      CalcInverseDynamics(model, ws, q, v, qdd, tau);
      const Eigen::VectorXd rhs = model.B() * u + tau_ext;
      EXPECT_LT((tau - rhs).norm(), 1e-9 * std::max(1.0, rhs.norm() + CalcBiasForces(model, ws, q, v).norm()))
          << "ABA residual " << (tau - rhs).transpose();
      // M^-1 via Bullet's calcAccelerationDeltasMultiDof (+ armature) vs Cholesky of CRBA M.
      Eigen::VectorXd f = Eigen::VectorXd::Random(n), out(n);
      ApplyInverseMassMatrix(model, ws, q, f, out);
      Eigen::VectorXd ref = f;
      SolveMassMatrix(model, ws, q, ref);
      EXPECT_LT((out - ref).norm(), 1e-9 * std::max(1.0, ref.norm()));
    }
  }
}

// The tree-sparse L^T D L factor (Featherstone's LTDL) must invert the CRBA mass matrix to
// round-off: M (M^-1 X) = X for a random block X, and agree with a dense LLT solve.
TEST(MultibodyDynamicsTest, TreeSparseFactorSolvesMassMatrix) {
  for (const std::string& urdf : test::AllModelUrdfs()) {
    SCOPED_TRACE(urdf);
    const MultibodyModel model = MultibodyModel::Load(urdf, "", {.euler_floating_base = true});
    MultibodyWorkspace ws(model);
    EXPECT_TRUE(ws.use_tree_factor) << "dof order is not parent-first";
    std::mt19937 rng(21);
    for (int trial = 0; trial < 3; ++trial) {
      Eigen::VectorXd q, v;
      test::RandomState(model, rng, q, v);
      const int n = model.nv();
      const Eigen::MatrixXd M = CalcMassMatrix(model, ws, q);
      // One column (the per-column solve), 4 (the transposed solve over all columns at once), 3 nv (more columns than
      // the workspace's transposed buffer holds: per column again).
      const int cols = trial == 0 ? 1 : trial == 1 ? 4 : 3 * n;
      const Eigen::MatrixXd B = Eigen::MatrixXd::Random(n, cols);
      if (trial == 2) {
        ASSERT_GT(cols, ws.solve_rows.rows()) << "3 nv columns no longer exceed the transposed buffer";
      }
      Eigen::MatrixXd X = B;
      SolveMassMatrix(model, ws, q, X);
      EXPECT_LT((M * X - B).norm(), 1e-10 * B.norm()) << "M X - B";
      const Eigen::MatrixXd X_dense = M.llt().solve(B);
      EXPECT_LT((X - X_dense).norm(), 1e-9 * X_dense.norm()) << "vs dense LLT";
      // The dense fallback (used when the dof order is not parent-first) gives the same.
      MultibodyWorkspace dense(model);
      dense.use_tree_factor = false;
      Eigen::MatrixXd X_fallback = B;
      SolveMassMatrix(model, dense, q, X_fallback);
      EXPECT_LT((X_fallback - X_dense).norm(), 1e-12 * X_dense.norm()) << "fallback";
    }
  }
}

TEST(MultibodyDynamicsTest, SpringDeflectsByStaticLoadOverStiffness) {
  const MultibodyModel model = MultibodyModel::Load(DataPath("spring_arm.urdf"), "", {.euler_floating_base = true});
  ASSERT_EQ(model.springs().size(), 1u);
  MultibodyWorkspace ws(model);
  const double k = 400.0, m = 2.0, c = 0.4, g = 9.81;
  // Gravity on the horizontal arm (COM at +x, rotation about +y): tau_g(theta) =
  // m g c cos(theta) (a positive rotation about y lowers +x). Equilibrium: k theta = tau_g.
  Eigen::VectorXd q = Eigen::VectorXd::Zero(1), v = Eigen::VectorXd::Zero(1), qdd(1);
  Eigen::VectorXd u(0), none(0);
  const double dt = 1e-3;
  for (int step = 0; step < 20000; ++step) {  // damped: settles within ~20 s of model time
    CalcForwardDynamics(model, ws, q, v, u, none, qdd);
    v += dt * qdd;
    q += dt * v;
  }
  const double theta = q[0];
  EXPECT_NEAR(k * theta, m * g * c * std::cos(theta), 1e-6);
  EXPECT_GT(theta, 0.015);
  // The static equilibrium makes qdd exactly zero.
  Eigen::VectorXd zero = Eigen::VectorXd::Zero(1);
  CalcForwardDynamics(model, ws, q, zero, u, none, qdd);
  EXPECT_NEAR(qdd[0], 0.0, 1e-6);
  // An extra static load tau adds tau / k.
  const double tau = 3.0;
  Eigen::VectorXd ext = Eigen::VectorXd::Constant(1, tau);
  double th = theta;
  for (int it = 0; it < 50; ++it) th = (m * g * c * std::cos(th) + tau) / k;  // fixed point
  Eigen::VectorXd qs = Eigen::VectorXd::Constant(1, th);
  CalcForwardDynamics(model, ws, qs, zero, u, ext, qdd);
  EXPECT_NEAR(qdd[0], 0.0, 1e-9);
  EXPECT_NEAR(th - theta, tau / k, 0.05 * tau / k);  // small-angle: delta theta ~ tau / k
}

// RK4 on x = [q; v; E_dissipated] with Bullet forward dynamics, u = 0. The third component
// integrates the spring-damper dissipation d v^2 so that E + E_dissipated is conserved.
void Rk4Step(const MultibodyModel& model, MultibodyWorkspace& ws, Eigen::VectorXd& q, Eigen::VectorXd& v,
             double& E_diss, double dt) {
  const int n = model.nv();
  Eigen::VectorXd u = Eigen::VectorXd::Zero(model.nu()), none(0);
  auto f = [&](const Eigen::VectorXd& qq, const Eigen::VectorXd& vv, Eigen::VectorXd& dq, Eigen::VectorXd& dv,
               double& dE) {
    dq = vv;
    dv.resize(n);
    CalcForwardDynamics(model, ws, qq, vv, u, none, dv);
    dE = (model.spring_damping().array() * vv.array().square()).sum();
  };
  Eigen::VectorXd k1q, k1v, k2q, k2v, k3q, k3v, k4q, k4v;
  double e1, e2, e3, e4;
  f(q, v, k1q, k1v, e1);
  f(q + 0.5 * dt * k1q, v + 0.5 * dt * k1v, k2q, k2v, e2);
  f(q + 0.5 * dt * k2q, v + 0.5 * dt * k2v, k3q, k3v, e3);
  f(q + dt * k3q, v + dt * k3v, k4q, k4v, e4);
  q += dt / 6.0 * (k1q + 2 * k2q + 2 * k3q + k4q);
  v += dt / 6.0 * (k1v + 2 * k2v + 2 * k3v + k4v);
  E_diss += dt / 6.0 * (e1 + 2 * e2 + 2 * e3 + e4);
}

TEST(MultibodyDynamicsTest, PassiveRobotInFlightConservesEnergyAndMomentum) {
  for (const std::string& file : {std::string("walker2d.urdf"), std::string("biped3d.urdf")}) {
    SCOPED_TRACE(file);
    const MultibodyModel model = MultibodyModel::Load(DataPath(file), "", {.euler_floating_base = true});
    MultibodyWorkspace ws(model);
    std::mt19937 rng(4);
    Eigen::VectorXd q, v;
    test::RandomState(model, rng, q, v);
    v *= 2.0;
    const double m = model.total_mass();
    const double E0 = CalcKineticEnergy(model, ws, q, v) + CalcPotentialEnergy(model, ws, q);
    const Vector6d hG0 = CalcCentroidalMomentum(model, ws, q, v);
    // The biped's ankle spring (300 N m/rad on a light foot) rings at ~400 rad/s: small steps.
    const double T_end = 0.3, dt = 1e-4;
    double E_diss = 0.0;
    for (int i = 0; i < static_cast<int>(T_end / dt + 0.5); ++i) Rk4Step(model, ws, q, v, E_diss, dt);
    const double E1 = CalcKineticEnergy(model, ws, q, v) + CalcPotentialEnergy(model, ws, q);
    const Vector6d hG1 = CalcCentroidalMomentum(model, ws, q, v);
    EXPECT_NEAR(E1 + E_diss, E0, 1e-7 * std::max(1.0, std::abs(E0)))
        << "energy drift " << E1 + E_diss - E0 << " (dissipated " << E_diss << ")";
    // Linear momentum: dP/dt = m g; centroidal angular momentum constant. A planar model's
    // virtual joints exert out-of-plane reactions: only L_y, P_x, P_z are free there.
    const Eigen::Vector3d dP = hG1.tail<3>() - hG0.tail<3>() - m * model.gravity() * T_end;
    const Eigen::Vector3d dL = hG1.head<3>() - hG0.head<3>();
    if (model.is_planar()) {
      EXPECT_LT(std::abs(dP.x()) + std::abs(dP.z()), 1e-8 * m) << dP.transpose();
      EXPECT_LT(std::abs(dL.y()), 1e-8 * std::max(1.0, hG0.head<3>().norm())) << dL.transpose();
    } else {
      EXPECT_LT(dP.norm(), 1e-8 * m) << dP.transpose();
      EXPECT_LT(dL.norm(), 1e-8 * std::max(1.0, hG0.head<3>().norm())) << dL.transpose();
    }
    std::printf("%s: energy error %.3e J, |dP - m g T| %.3e N s, |dL_G| %.3e N m s\n", file.c_str(), E1 + E_diss - E0,
                model.is_planar() ? std::abs(dP.x()) + std::abs(dP.z()) : dP.norm(),
                model.is_planar() ? std::abs(dL.y()) : dL.norm());
  }
}

}  // namespace
}  // namespace rome
