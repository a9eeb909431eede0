// Dynamics and Jacobians on the quaternion free-flyer base. References: the closed-form spatial inertia and
// Newton-Euler equations of one rigid body; the Euler-base model (and Bullet's ABA on it) at the same physical state,
// mapped through the Euler-rate-to-twist map T written here; finite differences taken on the manifold (Integrate);
// conservation laws and the free-fall parabola of a spinning body (the tennis-racket effect).
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "systems/multibody/free_flyer.h"
#include "systems/multibody/multibody_dynamics.h"
#include "tests/systems/multibody/test_models.h"

namespace rome {
namespace {

using test::DataPath;

MultibodyModel LoadBiped(bool quaternion) {
  LoadOptions options;
  options.quaternion_floating_base = quaternion;
  options.euler_floating_base = !quaternion;
  return MultibodyModel::Load(DataPath("biped3d.urdf"), "", options);
}

Eigen::Vector3d RotationLog(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

// One rigid body: mass m, COM c and a non-diagonal inertia about the COM, in the link frame (test values).
const double kMass = 3.0;
const Eigen::Vector3d kCom(0.1, -0.05, 0.2);
std::string BodyUrdf(const Eigen::Matrix3d& I) {
  char buf[600];
  std::snprintf(buf, sizeof(buf),
                R"(<robot name="body"><link name="body"><inertial><origin xyz="%.17g %.17g %.17g"/><mass value="%.17g"/>
      <inertia ixx="%.17g" iyy="%.17g" izz="%.17g" ixy="%.17g" ixz="%.17g" iyz="%.17g"/></inertial></link></robot>)",
                kCom.x(), kCom.y(), kCom.z(), kMass, I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(0, 2), I(1, 2));
  return buf;
}
MultibodyModel LoadBody(const Eigen::Matrix3d& I) {
  return MultibodyModel::LoadFromText(BodyUrdf(I), R"({"floating_base": "quaternion"})", "body.urdf", "body.rome.json");
}
Eigen::Matrix3d Skew(const Eigen::Vector3d& a) {
  Eigen::Matrix3d S;
  S << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return S;
}

TEST(FreeFlyerDynamicsTest, SingleBodyMassMatrixIsItsSpatialInertiaAndBiasIsNewtonEuler) {
  Eigen::Matrix3d Ic;
  Ic << 0.30, 0.02, -0.01, 0.02, 0.40, 0.03, -0.01, 0.03, 0.50;
  const MultibodyModel model = LoadBody(Ic);
  MultibodyWorkspace ws(model);
  // Body frame, [v; w] at the link origin: T = 1/2 m |v + w x c|^2 + 1/2 w^T Ic w.
  Eigen::Matrix<double, 6, 6> M_expected;
  M_expected << kMass * Eigen::Matrix3d::Identity(), -kMass * Skew(kCom), kMass * Skew(kCom),
      Ic - kMass * Skew(kCom) * Skew(kCom);
  std::mt19937 rng(4);
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::VectorXd q(7), v(6);
  for (int trial = 0; trial < 10; ++trial) {
    q << n(rng), n(rng), n(rng), n(rng), n(rng), n(rng), n(rng);
    if (trial == 0) q.segment<4>(3) << std::cos(M_PI / 4), 0.0, std::sin(M_PI / 4), 0.0;  // pitch +90 deg
    q.segment<4>(3).normalize();
    for (int i = 0; i < 6; ++i) v[i] = n(rng);
    const Eigen::MatrixXd& M = CalcMassMatrix(model, ws, q);
    EXPECT_LT((M - M_expected).cwiseAbs().maxCoeff(), 1e-14);
    // h = nu x* (M nu) - gravity in body axes: momentum [l; k] = M nu, h = [w x l; w x k + v x l] - [m g_B; c x m g_B].
    const Eigen::Matrix3d R = Eigen::Quaterniond(q[3], q[4], q[5], q[6]).toRotationMatrix();
    const Eigen::Vector3d g_B = R.transpose() * Eigen::Vector3d(0.0, 0.0, -9.81);
    const Eigen::Matrix<double, 6, 1> mom = M_expected * v;
    const Eigen::Vector3d vl = v.head<3>(), w = v.tail<3>();
    Eigen::VectorXd h_expected(6);
    h_expected << w.cross(mom.head<3>()) - kMass * g_B,
        w.cross(mom.tail<3>()) + vl.cross(mom.head<3>()) - kCom.cross(kMass * g_B);
    EXPECT_LT((CalcBiasForces(model, ws, q, v) - h_expected).cwiseAbs().maxCoeff(), 1e-12);
  }
}

// The Euler base's rates [pdot; yaw', pitch', roll'] to the twist [v_B; w_B]: v_B = R^T pdot,
// w_B = R^T (e_z yaw' + Rz e_y pitch' + Rz Ry e_x roll'), R = Rz Ry Rx; joints unchanged.
Eigen::MatrixXd EulerRatesToTwist(const Eigen::VectorXd& q_euler) {
  const int nv = static_cast<int>(q_euler.size());
  const Eigen::Matrix3d Rz = Eigen::AngleAxisd(q_euler[3], Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Matrix3d Ry = Eigen::AngleAxisd(q_euler[4], Eigen::Vector3d::UnitY()).toRotationMatrix();
  const Eigen::Matrix3d Rx = Eigen::AngleAxisd(q_euler[5], Eigen::Vector3d::UnitX()).toRotationMatrix();
  const Eigen::Matrix3d R = Rz * Ry * Rx;
  Eigen::Matrix3d E;
  E << Eigen::Vector3d::UnitZ(), Rz * Eigen::Vector3d::UnitY(), Rz * Ry * Eigen::Vector3d::UnitX();
  Eigen::MatrixXd T = Eigen::MatrixXd::Identity(nv, nv);
  T.block<3, 3>(0, 0) = R.transpose();
  T.block<3, 3>(3, 3) = R.transpose() * E;
  return T;
}

Eigen::VectorXd QuaternionConfiguration(const Eigen::VectorXd& q_euler) {
  const Eigen::Quaterniond R(Eigen::AngleAxisd(q_euler[3], Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(q_euler[4], Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(q_euler[5], Eigen::Vector3d::UnitX()));
  Eigen::VectorXd q(q_euler.size() + 1);
  q << q_euler.head<3>(), R.w(), R.x(), R.y(), R.z(), q_euler.tail(q_euler.size() - 6);
  return q;
}

double MaxRelative(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(1.0, b.cwiseAbs().maxCoeff());
}

TEST(FreeFlyerDynamicsTest, CrbaRneaAndForwardDynamicsAgreeWithTheEulerBaseAtTheSameState) {
  const MultibodyModel euler = LoadBiped(false), quat = LoadBiped(true);
  MultibodyWorkspace we(euler), wq(quat);
  const int nv = euler.nv();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::VectorXd qe, ve, ae(nv), tau_e(nv), tau_q(nv), tau_q_crba(nv), u_in(euler.nu()), qdd_e(nv), qdd_q(nv);
  for (int trial = 0; trial < 10; ++trial) {
    test::RandomState(euler, rng, qe, ve);
    qe[4] = 1.2 * u(rng);  // pitch up to +-69 deg (the Euler reference is singular at 90)
    for (int i = 0; i < nv; ++i) ae[i] = u(rng);
    for (int i = 0; i < euler.nu(); ++i) u_in[i] = 20.0 * u(rng);
    const Eigen::VectorXd qq = QuaternionConfiguration(qe);
    const Eigen::MatrixXd T = EulerRatesToTwist(qe);
    const double eps = 1e-5;  // Tdot v_e by a central difference along the motion
    const Eigen::MatrixXd Tdot = (EulerRatesToTwist(qe + eps * ve) - EulerRatesToTwist(qe - eps * ve)) / (2 * eps);
    const Eigen::VectorXd vq = T * ve, aq = T * ae + Tdot * ve;
    // M_e = T^T M_q T (kinetic energy is one quantity).
    const Eigen::MatrixXd Me = CalcMassMatrix(euler, we, qe), Mq = CalcMassMatrix(quat, wq, qq);
    EXPECT_LT(MaxRelative(T.transpose() * Mq * T, Me), 1e-12);
    // tau_e = T^T tau_q (virtual work), with tau = RNEA(q, v, a).
    CalcRnea(euler, we, qe, ve, ae, tau_e);
    CalcRnea(quat, wq, qq, vq, aq, tau_q);
    EXPECT_LT(MaxRelative(T.transpose() * tau_q, tau_e), 1e-8) << "trial " << trial;
    // RNEA = M a + h on the quaternion base.
    tau_q_crba = Mq * aq + CalcBiasForces(quat, wq, qq, vq);
    EXPECT_LT(MaxRelative(tau_q, tau_q_crba), 1e-12);
    // Forward dynamics (CRBA + tree factor) against Bullet's ABA on the Euler base: qdd_q = T qdd_e + Tdot v_e.
    CalcForwardDynamics(euler, we, qe, ve, u_in, Eigen::VectorXd(), qdd_e);
    CalcForwardDynamics(quat, wq, qq, vq, u_in, Eigen::VectorXd(), qdd_q);
    EXPECT_LT(MaxRelative(qdd_q, T * qdd_e + Tdot * ve), 1e-7) << "trial " << trial;
  }
}

TEST(FreeFlyerDynamicsTest, JacobiansAndJdotVMatchFiniteDifferencesOnTheManifold) {
  const MultibodyModel model = LoadBiped(true);
  MultibodyWorkspace ws(model);
  const int nv = model.nv();
  std::mt19937 rng(6);
  Eigen::VectorXd q, v, qp(model.nq()), qm(model.nq()), e(nv);
  Eigen::MatrixXd J(6, nv), Jp(3, nv), J_fd(6, nv);
  const Eigen::Vector3d p_link(0.1, 0.05, -0.05);
  for (const std::string link : {"pelvis", "left_foot", "right_shin"}) {
    const int body = model.BodyIndex(link);
    for (int trial = 0; trial < 3; ++trial) {
      test::RandomState(model, rng, q, v);
      q.segment<4>(3).normalize();
      const double eps = 1e-6;
      for (int k = 0; k < nv; ++k) {
        e = Eigen::VectorXd::Unit(nv, k);
        model.Integrate(q, e, eps, qp);
        model.Integrate(q, e, -eps, qm);
        const Eigen::Isometry3d Xp = CalcLinkPose(model, ws, qp, body), Xm = CalcLinkPose(model, ws, qm, body);
        J_fd.col(k).head<3>() = RotationLog(Xp.linear() * Xm.linear().transpose()) / (2 * eps);
        J_fd.col(k).tail<3>() = (Xp * p_link - Xm * p_link) / (2 * eps);
      }
      CalcFrameJacobian(model, ws, q, body, p_link, J);
      EXPECT_LT((J - J_fd).cwiseAbs().maxCoeff(), 1e-8) << link;
      CalcPointJacobian(model, ws, q, body, p_link, Jp);
      EXPECT_LT((Jp - J.bottomRows<3>()).cwiseAbs().maxCoeff(), 1e-14) << link;
      // Jdot v: d/dt [w; v_p] along q(t) = Integrate(q, v, t), the motion with constant v.
      const double h = 1e-5;
      model.Integrate(q, v, h, qp);
      model.Integrate(q, v, -h, qm);
      const Vector6d fd =
          (CalcFrameVelocity(model, ws, qp, v, body, p_link) - CalcFrameVelocity(model, ws, qm, v, body, p_link)) /
          (2 * h);
      EXPECT_LT((CalcFrameJdotQdot(model, ws, q, v, body, p_link) - fd).cwiseAbs().maxCoeff(), 1e-6) << link;
    }
  }
}

struct TumbleResult {
  double max_energy_error = 0, max_momentum_error = 0, max_com_error = 0, max_norm_drift = 0, min_w_intermediate = 0;
  double max_euler_error = 0;  // |w_B - w_Euler| (rad/s), w_Euler from Euler's equations integrated independently
  double max_sin_pitch = 0;    // max |sin(pitch)| of the ZYX angles: 1 at the Euler base's singularity
  int flips = 0;
};

// Euler's equations of a torque-free body in its principal axes: I dw/dt = (I w) x w.
Eigen::Vector3d EulerEquations(const Eigen::Vector3d& I, const Eigen::Vector3d& w) {
  return (I.cwiseProduct(w)).cross(w).cwiseQuotient(I);
}

// RK4 in the embedding (q in R^7, v in R^6) with dq/dt = G(q) v, the quaternion projected onto |quat| = 1 after
// each step (its drift before the projection is recorded). Returns the largest errors over the run.
TumbleResult Tumble(const MultibodyModel& model, const Eigen::Vector3d& principal_moments, double dt, double duration) {
  MultibodyWorkspace ws(model);
  Eigen::VectorXd q(7), v(6), u(0), qd[4], vd[4], qs(7), vs(6);
  for (auto& x : qd) x.resize(7);
  for (auto& x : vd) x.resize(6);
  // Near the intermediate axis (y, I = 2 kg m^2): w_B = (0.01, 5, 0.01) rad/s, plus a translation.
  // A yaw only: the spin axis (body y) starts horizontal, so body x sweeps through the vertical (pitch +-90 deg).
  const Eigen::Quaterniond R0 = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()));
  q << 0.0, 0.0, 1.0, R0.w(), R0.x(), R0.y(), R0.z();
  v << 0.3, -0.2, 1.0, 0.01, 5.0, 0.01;
  const Eigen::Vector3d g(0.0, 0.0, -9.81);
  const double m = model.total_mass();
  auto rotational_energy = [&] {  // T - 1/2 m |cdot|^2: conserved by a free body under uniform gravity
    return CalcKineticEnergy(model, ws, q, v) - 0.5 * m * CalcComVelocity(model, ws, q, v).squaredNorm();
  };
  const double E0 = rotational_energy();
  const Eigen::Vector3d k0 = CalcCentroidalMomentum(model, ws, q, v).head<3>();
  const Eigen::Vector3d c0 = CalcComPosition(model, ws, q), cdot0 = CalcComVelocity(model, ws, q, v);
  TumbleResult r;
  double sign = 1.0;
  Eigen::Vector3d w_euler = v.tail<3>();
  const int steps = static_cast<int>(std::lround(duration / dt));
  for (int n = 1; n <= steps; ++n) {
    for (int s = 0; s < 4; ++s) {
      const double c = s == 0 ? 0.0 : (s == 3 ? 1.0 : 0.5);
      qs = s == 0 ? q : Eigen::VectorXd(q + c * dt * qd[s - 1]);
      vs = s == 0 ? v : Eigen::VectorXd(v + c * dt * vd[s - 1]);
      model.MapVelocityToQDot(qs, vs, qd[s]);
      CalcForwardDynamics(model, ws, qs, vs, u, Eigen::VectorXd(), vd[s]);
    }
    const Eigen::Vector3d k1 = EulerEquations(principal_moments, w_euler),
                          k2 = EulerEquations(principal_moments, w_euler + 0.5 * dt * k1),
                          k3 = EulerEquations(principal_moments, w_euler + 0.5 * dt * k2),
                          k4 = EulerEquations(principal_moments, w_euler + dt * k3);
    w_euler += dt / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4);
    q += dt / 6.0 * (qd[0] + 2 * qd[1] + 2 * qd[2] + qd[3]);
    v += dt / 6.0 * (vd[0] + 2 * vd[1] + 2 * vd[2] + vd[3]);
    r.max_norm_drift = std::max(r.max_norm_drift, std::abs(q.segment<4>(3).norm() - 1.0));
    q.segment<4>(3).normalize();
    const double t = n * dt;
    r.max_energy_error = std::max(r.max_energy_error, std::abs(rotational_energy() - E0) / E0);
    r.max_momentum_error =
        std::max(r.max_momentum_error, (CalcCentroidalMomentum(model, ws, q, v).head<3>() - k0).norm() / k0.norm());
    r.max_com_error =
        std::max(r.max_com_error, (CalcComPosition(model, ws, q) - (c0 + cdot0 * t + 0.5 * g * t * t)).norm());
    r.min_w_intermediate = std::min(r.min_w_intermediate, v[4]);
    r.max_euler_error = std::max(r.max_euler_error, (v.tail<3>() - w_euler).norm());
    const Eigen::Matrix3d R = Eigen::Quaterniond(q[3], q[4], q[5], q[6]).toRotationMatrix();
    r.max_sin_pitch = std::max(r.max_sin_pitch, std::abs(R(2, 0)));  // pitch = asin(-R(2, 0))
    if (v[4] * sign < 0.0) {
      ++r.flips;
      sign = -sign;
    }
  }
  return r;
}

TEST(FreeFlyerDynamicsTest, TennisRacketFlipsWhileEnergyAndAngularMomentumAreConserved) {
  const Eigen::Vector3d I(1.0, 2.0, 3.0);  // principal moments about the COM, along the link axes, kg m^2
  const MultibodyModel model = LoadBody(I.asDiagonal().toDenseMatrix());
  const TumbleResult fine = Tumble(model, I, 1e-3, 10.0), coarse = Tumble(model, I, 2e-3, 10.0);
  std::printf(
      "tennis racket, 10 s: dt 1e-3 s: energy %.3g, momentum %.3g, COM %.3g m, |quat| drift per step %.3g, "
      "flips %d, |w - w_Euler| %.3g rad/s, max |sin pitch| %.12f; dt 2e-3 s: energy %.3g, momentum %.3g, "
      "COM %.3g m\n",
      fine.max_energy_error, fine.max_momentum_error, fine.max_com_error, fine.max_norm_drift, fine.flips,
      fine.max_euler_error, fine.max_sin_pitch, coarse.max_energy_error, coarse.max_momentum_error,
      coarse.max_com_error);
  // It tumbles through the Euler base's singularity (pitch +-90 deg) with no loss of accuracy: its angular velocity
  // follows Euler's equations, integrated here on their own with the same RK4 step.
  EXPECT_GT(fine.max_sin_pitch, std::sin(89.0 * M_PI / 180.0));
  EXPECT_LT(fine.max_euler_error, 1e-8);
  // The body turns over about its intermediate axis: w_y goes from +5 rad/s to nearly -5 and back, several times.
  EXPECT_LT(fine.min_w_intermediate, -4.5);
  EXPECT_GE(fine.flips, 2);
  // Conserved to RK4's tolerance, which shrinks as dt^4 (a factor 16 per halving; > 8 asked).
  EXPECT_LT(fine.max_energy_error, 1e-8);
  EXPECT_LT(fine.max_momentum_error, 1e-8);
  EXPECT_GT(coarse.max_energy_error / fine.max_energy_error, 8.0);
  EXPECT_GT(coarse.max_momentum_error / fine.max_momentum_error, 8.0);
  // The COM falls on the parabola of uniform gravity (490 m in 10 s), to the same tolerance, and the quaternion leaves
  // the unit sphere by rounding only.
  EXPECT_LT(fine.max_com_error, 1e-6);
  EXPECT_GT(coarse.max_com_error / fine.max_com_error, 8.0);
  EXPECT_LT(fine.max_norm_drift, 1e-12);
}

}  // namespace
}  // namespace rome
