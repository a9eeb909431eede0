// ContactWrenchConstraints, 3D flat contact with corner_wrench_cone (the closed-form contact wrench cone of a sole
// rectangle with a friction pyramid at each corner). Independent references:
//  * necessity: the wrench of any four corner forces inside their pyramids (computed here from the sole's corner
//    points, not from the rows) satisfies every yaw and CoP row;
//  * tightness, by hand: with equal corner loads the largest torsion about the sole's centre is μ (X + Y) F_z (each
//    corner's friction at the pyramid's vertex); a CoP at a corner leaves no torsion at all (a single loaded point
//    with no tangential force); a wrench 1e-6 beyond either violates a row.
#include "systems/controllers/contact_wrench_constraints.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "systems/multibody/multibody_kinematics.h"
#include "tests/systems/controllers/amber_test_setup.h"

namespace rome {
namespace {

struct Sole {
  std::shared_ptr<const MultibodyModel> model;
  int contact = -1;
  Eigen::Matrix3d R;                     // foot frame in the world
  std::vector<Eigen::Vector3d> corners;  // foot frame, relative to the contact frame origin
};

Sole LeftSole() {
  Sole s;
  s.model = test::LoadRobot("exoskeleton");
  s.contact = s.model->ContactIndex("left_foot");
  const ContactInfo& info = s.model->contacts()[s.contact];
  MultibodyWorkspace ws(*s.model);
  s.R = CalcLinkPose(*s.model, ws, s.model->q_nominal(), info.body).linear();
  for (const Eigen::Vector3d& p : info.points) s.corners.push_back(p - info.frame_origin);
  return s;
}

// World wrench F = [τ; f] about the contact frame origin of foot-frame corner forces.
Eigen::Matrix<double, 6, 1> WrenchOf(const Sole& s, const std::vector<Eigen::Vector3d>& forces) {
  Eigen::Vector3d f = Eigen::Vector3d::Zero(), tau = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < forces.size(); ++i) f += forces[i], tau += s.corners[i].cross(forces[i]);
  Eigen::Matrix<double, 6, 1> F;
  F << s.R * tau, s.R * f;
  return F;
}

// Smallest slack of the yaw and CoP rows (negative: a row is violated).
double Slack(const Sole& s, const ContactWrenchConstraints& c, const Eigen::Matrix<double, 6, 1>& F) {
  Eigen::MatrixXd G(c.num_rows(), c.num_force_rows());
  Eigen::VectorXd l(c.num_rows()), u(c.num_rows());
  MultibodyWorkspace ws(*s.model);
  c.Fill(*s.model, ws, s.model->q_nominal(), G, l, u);
  const Eigen::VectorXd g = G * F;
  double slack = std::numeric_limits<double>::infinity();
  for (int r = 0; r < c.num_rows(); ++r) {
    if (c.kind(r) != ContactWrenchConstraints::RowKind::kYawMoment &&
        c.kind(r) != ContactWrenchConstraints::RowKind::kCenterOfPressure)
      continue;
    slack = std::min({slack, g[r] - l[r], u[r] - g[r]});
  }
  return slack;
}

ContactWrenchParams CornerConeParams(double mu) {
  ContactWrenchParams p;
  p.friction_coefficient = mu;
  p.inscribe_pyramid = false;  // the corners' pyramid: |f_x|, |f_y| ≤ μ f_z
  p.corner_wrench_cone = true;
  return p;
}

TEST(ContactWrenchConstraints, CornerWrenchConeHoldsEveryWrenchOfCornerForcesInTheirPyramids) {
  const Sole s = LeftSole();
  ASSERT_NEAR(s.R(2, 2), 1.0, 1e-9) << "the nominal pose's sole is not flat";
  const double mu = 0.6;
  const ContactWrenchConstraints c(*s.model, s.contact, CornerConeParams(mu), "test");
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> unit(0.0, 1.0), sym(-1.0, 1.0);
  double worst = std::numeric_limits<double>::infinity();
  for (int trial = 0; trial < 20000; ++trial) {
    std::vector<Eigen::Vector3d> forces;
    for (size_t i = 0; i < s.corners.size(); ++i) {
      const double fz = unit(rng) < 0.25 ? 0.0 : 100.0 * unit(rng);
      auto tangential = [&] {
        return mu * fz * (unit(rng) < 0.5 ? (unit(rng) < 0.5 ? 1.0 : -1.0) : sym(rng));
      };  // often on the pyramid's edge
      forces.emplace_back(tangential(), tangential(), fz);
    }
    worst = std::min(worst, Slack(s, c, WrenchOf(s, forces)) / 100.0);
  }
  EXPECT_GT(worst, -1e-12);
}

TEST(ContactWrenchConstraints, CornerWrenchConeIsTightAtTheSolesTorsionAndCornerLimits) {
  const Sole s = LeftSole();
  const double mu = 0.6, Fz = 400.0;
  const ContactWrenchConstraints c(*s.model, s.contact, CornerConeParams(mu), "test");
  double X = 0, Y = 0;
  for (const Eigen::Vector3d& d : s.corners) X = std::max(X, std::abs(d.x())), Y = std::max(Y, std::abs(d.y()));
  // Pure torsion about the centre, equal loads: τ_z = μ (X + Y) F_z is the most the corners hold.
  const Eigen::Vector3d ez_world = s.R.col(2);
  Eigen::Matrix<double, 6, 1> twist = Eigen::Matrix<double, 6, 1>::Zero();
  twist.tail<3>() = s.R * Eigen::Vector3d(0, 0, Fz);
  for (const double sign : {1.0, -1.0}) {
    Eigen::Matrix<double, 6, 1> F = twist;
    F.head<3>() = sign * mu * (X + Y) * Fz * ez_world;
    EXPECT_NEAR(Slack(s, c, F), 0.0, 1e-9 * Fz);
    F.head<3>() *= 1.0 + 1e-6;
    EXPECT_LT(Slack(s, c, F), 0.0);
  }
  // The CoP at a corner: all the load on one point, which holds no torsion.
  std::vector<Eigen::Vector3d> one(s.corners.size(), Eigen::Vector3d::Zero());
  one[0] = Eigen::Vector3d(0, 0, Fz);
  Eigen::Matrix<double, 6, 1> F = WrenchOf(s, one);
  EXPECT_NEAR(Slack(s, c, F), 0.0, 1e-9 * Fz);
  F.head<3>() += 1e-6 * Fz * ez_world;
  EXPECT_LT(Slack(s, c, F), 0.0);
}

}  // namespace
}  // namespace rome

namespace rome {
namespace {

// corner_cone_friction_coefficient: the yaw rows use the sole's own μ_c while the friction rows keep their reduced μ'.
// Closed form for a rectangle of half-sizes X, Y (after the CoP margin) with equal corner loads and each corner's
// pyramid inscribed in its cone: |τ_z| ≤ (μ_c/√2)(X + Y) F_z (the walking default: μ_c = 0.8, X = 0.115 m,
// Y = 0.04 m, 0.0877 m F_z). The friction rows are unchanged: |F_x| ≤ (μ' friction_margin/√2) F_z.
TEST(ContactWrenchConstraints, CornerConeFrictionCoefficientSetsTheTorsionBoundOnly) {
  const Sole s = LeftSole();
  const double mu_rows = 0.6, margin = 0.5, mu_c = 0.8, cop_margin = 0.01, Fz = 500.0;
  ContactWrenchParams p;
  p.friction_coefficient = mu_rows;
  p.friction_margin = margin;
  p.cop_margin_m = cop_margin;
  p.corner_wrench_cone = true;
  p.corner_cone_friction_coefficient = mu_c;
  const ContactWrenchConstraints c(*s.model, s.contact, p, "test");
  double X = 0, Y = 0;
  for (const Eigen::Vector3d& d : s.corners) X = std::max(X, std::abs(d.x())), Y = std::max(Y, std::abs(d.y()));
  X -= cop_margin, Y -= cop_margin;
  const double bound = mu_c / std::sqrt(2.0) * (X + Y) * Fz;
  EXPECT_NEAR(bound / Fz, 0.8 / std::sqrt(2.0) * (0.125 + 0.05 - 0.02), 1e-12);  // the exoskeleton's sole, by hand
  const Eigen::Vector3d ez_world = s.R.col(2);
  for (const double sign : {1.0, -1.0}) {
    Eigen::Matrix<double, 6, 1> F = Eigen::Matrix<double, 6, 1>::Zero();
    F.tail<3>() = s.R * Eigen::Vector3d(0, 0, Fz);
    F.head<3>() = sign * bound * ez_world;
    EXPECT_NEAR(Slack(s, c, F), 0.0, 1e-9 * Fz);
    F.head<3>() *= 1.0 + 1e-6;
    EXPECT_LT(Slack(s, c, F), 0.0);
  }
  // Friction rows: the reduced μ', inscribed.
  Eigen::MatrixXd G(c.num_rows(), c.num_force_rows());
  Eigen::VectorXd l(c.num_rows()), u(c.num_rows());
  MultibodyWorkspace ws(*s.model);
  c.Fill(*s.model, ws, s.model->q_nominal(), G, l, u);
  const double fx_max = mu_rows * margin / std::sqrt(2.0) * Fz;
  for (const double scale : {1.0 - 1e-6, 1.0 + 1e-6}) {
    Eigen::Matrix<double, 6, 1> F = Eigen::Matrix<double, 6, 1>::Zero();
    F[3] = scale * fx_max, F[5] = Fz;
    const Eigen::VectorXd g = G * F;
    double slack = std::numeric_limits<double>::infinity();
    for (int r = 0; r < c.num_rows(); ++r)
      if (c.kind(r) == ContactWrenchConstraints::RowKind::kFriction)
        slack = std::min({slack, g[r] - l[r], u[r] - g[r]});
    EXPECT_EQ(slack >= 0.0, scale < 1.0) << "scale " << scale;
  }
}

}  // namespace
}  // namespace rome

namespace rome {
namespace {

// corner_cone_yaw_margin_m: the yaw rows' half-sizes are the whole sole's less that margin, whatever the CoP rows'
// margin: a pure twist about the centre is held up to (μ_c/√2)(X_sole + Y_sole − 2 m) F_z (the exoskeleton's
// 0.25 × 0.10 m sole, by hand: X_sole = 0.125 m, Y_sole = 0.05 m; the corner forces' bound as in the test above).
TEST(ContactWrenchConstraints, CornerConeYawMarginSizesTheYawRowsOnTheWholeSole) {
  const Sole s = LeftSole();
  const double mu_c = 0.8, yaw_margin = 0.002, Fz = 500.0;
  ContactWrenchParams p;
  p.cop_margin_m = 0.01;
  p.corner_wrench_cone = true;
  p.corner_cone_friction_coefficient = mu_c;
  p.corner_cone_yaw_margin_m = yaw_margin;
  const ContactWrenchConstraints c(*s.model, s.contact, p, "test");
  const double bound = mu_c / std::sqrt(2.0) * (0.125 + 0.05 - 2 * yaw_margin) * Fz;
  for (const double sign : {1.0, -1.0}) {
    Eigen::Matrix<double, 6, 1> F = Eigen::Matrix<double, 6, 1>::Zero();
    F.tail<3>() = s.R * Eigen::Vector3d(0, 0, Fz);
    F.head<3>() = sign * bound * s.R.col(2);
    EXPECT_NEAR(Slack(s, c, F), 0.0, 1e-9 * Fz);
    F.head<3>() *= 1.0 + 1e-6;
    EXPECT_LT(Slack(s, c, F), 0.0);
  }
  p.corner_cone_yaw_margin_m = std::numeric_limits<double>::infinity();
  EXPECT_THROW(ContactWrenchConstraints(*s.model, s.contact, p, "test"), std::invalid_argument);
}

}  // namespace
}  // namespace rome
