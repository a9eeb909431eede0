// QuaternionToEulerState and its maps (issue 43). References, none from the code under test: the rotation rebuilt as
// Rz(yaw) Ry(pitch) Rx(roll) with Eigen's AngleAxis; central finite differences of the mapped Euler angles and position
// along a quaternion trajectory integrated by the exact SE(3) flow of a constant body twist (FreeFlyerIntegrate, tested
// against the tennis racket in free_flyer_test); the kinetic energy 1/2 v^T M v computed on each model from its own
// mass matrix (Cassie, both bases loaded from the same files).
#include <cmath>
#include <memory>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "systems/multibody/free_flyer.h"
#include "systems/multibody/multibody_dynamics.h"
#include "systems/multibody/multibody_workspace.h"
#include "systems/plants/quaternion_to_euler_state.h"
#include "tests/common/source_path.h"

namespace rome {
namespace {

std::shared_ptr<const MultibodyModel> LoadCassie(bool quaternion) {
  LoadOptions options;
  options.quaternion_floating_base = quaternion;
  options.euler_floating_base = !quaternion;
  return std::make_shared<const MultibodyModel>(
      MultibodyModel::LoadFromSidecar(rome::test::SourcePath("robots/cassie/cassie.rome.json"), options));
}

Eigen::Matrix3d ZyxRotation(double yaw, double pitch, double roll) {
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

// A random Euler state: |pitch| < 1.4 rad, yaw and roll in (-3, 3) rad, joints near the nominal pose, rates O(1).
Eigen::VectorXd RandomEulerState(const MultibodyModel& euler, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int nv = euler.nv();
  Eigen::VectorXd x(2 * nv);
  x.head(nv) = euler.q_nominal();
  x[0] = u(rng), x[1] = u(rng), x[2] = 1.0 + 0.1 * u(rng);
  x[3] = 3.0 * u(rng), x[4] = 1.4 * u(rng), x[5] = 3.0 * u(rng);
  for (int i = 6; i < nv; ++i) x[i] += 0.2 * u(rng);
  for (int i = nv; i < 2 * nv; ++i) x[i] = 2.0 * u(rng);
  return x;
}

TEST(QuaternionToEulerState, RoundTripsBothWaysTo1e12) {
  auto euler = LoadCassie(false);
  const int nv = euler->nv();
  for (unsigned seed = 1; seed <= 10; ++seed) {
    std::mt19937 rng(seed);
    for (int k = 0; k < 20; ++k) {
      const Eigen::VectorXd x_e = RandomEulerState(*euler, rng);
      Eigen::VectorXd x_q(2 * nv + 1), back(2 * nv), x_q2(2 * nv + 1);
      EulerStateToQuaternion(x_e, x_q);
      EXPECT_NEAR(x_q.segment<4>(3).norm(), 1.0, 1e-15);
      EXPECT_GE(x_q[3], 0.0);
      QuaternionStateToEuler(x_q, {}, back);
      EXPECT_LT((back - x_e).cwiseAbs().maxCoeff(), 1e-12) << "seed " << seed << " sample " << k;
      EulerStateToQuaternion(back, x_q2);
      EXPECT_LT((x_q2 - x_q).cwiseAbs().maxCoeff(), 1e-12) << "seed " << seed << " sample " << k;
    }
  }
}

TEST(QuaternionToEulerState, AnglesRebuildTheRotationAndRatesMatchFiniteDifferencesAlongAQuaternionTrajectory) {
  const int nj = 3, nv = 6 + nj;
  // A body twist that tumbles the base through large yaw, pitch and roll (pitch up to ~80 deg on this window).
  FreeFlyerTwist xi;
  xi << 0.4, -0.2, 0.3, 0.7, 1.1, -0.5;  // m/s, rad/s, body axes
  const Eigen::Vector3d joint_rate(0.3, -0.8, 1.2);
  Vector7d q0;
  q0 << 0.1, -0.2, 1.0, 1.0, 0.0, 0.0, 0.0;
  const Eigen::Vector3d joint0(0.1, 0.2, -0.3);
  auto state_at = [&](double t) {
    Eigen::VectorXd x(2 * nv + 1);
    x << FreeFlyerIntegrate(q0, t * xi), joint0 + t * joint_rate, xi, joint_rate;
    return x;
  };
  const double h = 1e-5;
  double worst_R = 0, worst_rate = 0, max_pitch = 0;
  for (double t = 0.0; t <= 1.2; t += 0.05) {
    Eigen::VectorXd x_e(2 * nv), x_plus(2 * nv), x_minus(2 * nv);
    QuaternionStateToEuler(state_at(t), {}, x_e);
    QuaternionStateToEuler(state_at(t + h), {}, x_plus);
    QuaternionStateToEuler(state_at(t - h), {}, x_minus);
    max_pitch = std::max(max_pitch, std::abs(x_e[4]));
    Eigen::Quaterniond quat;
    ASSERT_TRUE(FreeFlyerRotation(state_at(t).head<7>(), &quat));
    worst_R = std::max(worst_R, (ZyxRotation(x_e[3], x_e[4], x_e[5]) - quat.toRotationMatrix()).norm());
    Eigen::VectorXd fd = (x_plus.head(nv) - x_minus.head(nv)) / (2 * h);
    for (int i = 3; i < 6; ++i) {  // no angle wraps inside the difference's window
      ASSERT_LT(std::abs(x_plus[i] - x_minus[i]), 1.0) << "t = " << t;
    }
    worst_rate = std::max(worst_rate, (fd - x_e.tail(nv)).cwiseAbs().maxCoeff());
  }
  std::printf("tumbling base: |R(angles) - R| <= %.3g, |FD - rates| <= %.3g, max |pitch| %.3f rad\n", worst_R,
              worst_rate, max_pitch);
  EXPECT_GT(max_pitch, 1.2);  // the trajectory does approach the singularity
  EXPECT_LT(worst_R, 1e-14);
  // Central difference: truncation h^2/6 |x'''| ~ 1e-10 (derivatives O(10) near 80 deg), rounding 1e-16 / h ~ 1e-11.
  EXPECT_LT(worst_rate, 1e-8);
}

TEST(QuaternionToEulerState, KineticEnergyFromEachModelsOwnMassMatrixAgrees) {
  auto euler = LoadCassie(false);
  auto quat = LoadCassie(true);
  const int nv = euler->nv();
  MultibodyWorkspace ws_e(*euler), ws_q(*quat);
  double worst = 0;
  for (unsigned seed = 1; seed <= 10; ++seed) {
    std::mt19937 rng(seed);
    // Start from a quaternion state: a random unit quaternion (pitch kept away from +-90 deg) and a random twist.
    Eigen::VectorXd x_q(2 * nv + 1);
    EulerStateToQuaternion(RandomEulerState(*euler, rng), x_q);
    std::uniform_real_distribution<double> u(-2.0, 2.0);
    for (int i = nv + 1; i < 2 * nv + 1; ++i) x_q[i] = u(rng);
    Eigen::VectorXd x_e(2 * nv);
    QuaternionStateToEuler(x_q, {}, x_e);
    const Eigen::VectorXd v_q = x_q.tail(nv), v_e = x_e.tail(nv);
    const double T_q = 0.5 * v_q.dot(CalcMassMatrix(*quat, ws_q, x_q.head(nv + 1)) * v_q);
    const double T_e = 0.5 * v_e.dot(CalcMassMatrix(*euler, ws_e, x_e.head(nv)) * v_e);
    worst = std::max(worst, std::abs(T_q - T_e) / T_q);
  }
  std::printf("Cassie kinetic energy, quaternion vs Euler model: worst relative difference %.3g\n", worst);
  EXPECT_LT(worst, 1e-12);
}

TEST(QuaternionToEulerState, RefusesPitchNearNinetyDegreesNamingIt) {
  Eigen::VectorXd x_e = Eigen::VectorXd::Zero(12), x_q(13), out(12);
  x_e[4] = 0.5 * M_PI - 0.005;       // within the default 0.01 rad
  EulerStateToQuaternion(x_e, x_q);  // the inverse is defined everywhere
  try {
    QuaternionStateToEuler(x_q, {}, out);
    FAIL() << "no error at pitch pi/2 - 0.005";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("pitch = 1.565"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("singularity_margin_rad = 0.01"), std::string::npos) << e.what();
  }
  EulerStateParams narrow;
  narrow.singularity_margin_rad = 1e-3;
  QuaternionStateToEuler(x_q, narrow, out);
  EXPECT_NEAR(out[4], 0.5 * M_PI - 0.005, 1e-9);  // sqrt(eps) near the singularity: atan2 keeps it
  narrow.singularity_margin_rad = 0.0;
  EXPECT_THROW(narrow.Validate(), std::invalid_argument);
}

TEST(QuaternionToEulerState, BlockOutputsTheMapAndRefusesModelsThatAreNotTwins) {
  auto euler = LoadCassie(false);
  auto quat = LoadCassie(true);
  const int nv = euler->nv();
  QuaternionToEulerState block("euler_state", euler, quat);
  auto context = block.CreateDefaultLeafContext();
  std::mt19937 rng(3);
  Eigen::VectorXd x_q(2 * nv + 1), expected(2 * nv);
  EulerStateToQuaternion(RandomEulerState(*euler, rng), x_q);
  context->FixInputPort(0, x_q);
  QuaternionStateToEuler(x_q, {}, expected);
  EXPECT_EQ(block.EvalOutput(*context, "state"), expected);
  try {
    QuaternionToEulerState swapped("swapped", quat, euler);
    FAIL() << "swapped models accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("(the Euler model) has base 'quaternion', not 'spatial_euler'"),
              std::string::npos)
        << e.what();
  }
  auto twin = LoadQuaternionTwin(*euler);
  EXPECT_TRUE(twin->has_quaternion_base());
  EXPECT_EQ(twin->nv(), nv);
}

}  // namespace
}  // namespace rome
