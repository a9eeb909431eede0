// CassieVirtualLeg / IdentifyCassieLegStiffness on robots/cassie: Eq. (13) against the spec's L(q_knee) table and the
// rigid rule q_knee + q_tarsus = 13 deg (robots.md); dL/dq_knee against finite differences of L; Eq. (12) against the
// second difference of the spring energy when the toe joint is displaced along the leg (an independent static
// force-deflection computation: pose solver + energy, no Jacobians); the regression against those samples.
#include "systems/rom/cassie_leg_stiffness.h"

#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "systems/multibody/multibody_kinematics.h"
#include "systems/multibody/pose_constraints.h"
#include "tests/common/source_path.h"

namespace rome {
namespace {

constexpr double kDeg = M_PI / 180.0;

const MultibodyModel& Cassie() {
  static const MultibodyModel model =
      MultibodyModel::Load(rome::test::SourcePath("robots/cassie/cassie.urdf"), "", {.euler_floating_base = true});
  return model;
}

TEST(CassieVirtualLeg, LengthTableAndThirteenDegreeRule) {
  // Spec hopping.md A1.3 [D] (planar computation with the public Caltech geometry).
  const double knee_deg[] = {-37, -45, -54.4, -60, -70, -80, -90, -100, -110, -120};
  const double L[] = {0.9816, 0.9577, 0.9235, 0.9003, 0.8535, 0.8002, 0.7407, 0.6757, 0.6055, 0.5308};
  const double dL[] = {0.155, 0.188, 0.227, 0.249, 0.287, 0.323, 0.357, 0.388, 0.416, 0.440};
  for (const char* side : {"left", "right"}) {
    const CassieVirtualLeg leg(Cassie(), side);
    for (int i = 0; i < 10; ++i) {
      const double q = knee_deg[i] * kDeg;
      EXPECT_NEAR(leg.Length(q), L[i], 1e-3) << side << " knee " << knee_deg[i];
      EXPECT_NEAR((leg.TarsusAngle(q) + q) / kDeg, 13.0, 0.05) << side << " knee " << knee_deg[i];
      // Sign: a more bent knee (more negative) shortens the leg, so dL/dq_knee > 0.
      EXPECT_NEAR(leg.LengthJacobian(q), dL[i], 2e-3) << side << " knee " << knee_deg[i];
      const double h = 1e-6;
      EXPECT_NEAR(leg.LengthJacobian(q), (leg.Length(q + h) - leg.Length(q - h)) / (2 * h), 1e-7);
      // (−37° is 1.8e-7 rad beyond the URDF's knee limit −0.645772 rad, so KneeAngle clamps there.)
      if (i > 0) { EXPECT_NEAR(leg.KneeAngle(leg.Length(q)), q, 1e-9); }
    }
  }
}

TEST(CassieVirtualLeg, BadInputIsNamed) {
  EXPECT_THROW(CassieVirtualLeg(Cassie(), "middle"), std::invalid_argument);
  const CassieVirtualLeg leg(Cassie(), "left");
  try {
    leg.KneeAngle(1.5);
    FAIL();
  } catch (const std::domain_error& e) {
    EXPECT_NE(std::string(e.what()).find("L = 1.5"), std::string::npos) << e.what();
  }
}

// Along-leg stiffness by finite differences of the spring energy: the toe joint is moved by ±e along the leg axis
// (knee held, pelvis fixed, tangential displacement blocked) and the pose solver finds the shin, tarsus and heel that
// keep the rod closed; K = (E(+e) + E(−e) − 2 E(0)) / e² with E = ½ k_shin q_shin² + ½ k_heel q_heel².
double FiniteDifferenceStiffness(const CassieVirtualLeg& leg, double q_knee) {
  const MultibodyModel& model = Cassie();
  MultibodyWorkspace ws(model);
  Eigen::VectorXd q0 = Eigen::VectorXd::Zero(model.nq());
  q0(2) = 1.0;
  q0(leg.knee_index()) = q_knee;
  q0(leg.tarsus_index()) = leg.TarsusAngle(q_knee);
  const int hip = model.BodyIndex("left_hip_pitch"), foot = model.BodyIndex("left_foot");
  const Eigen::Vector3d p_hip = CalcPointPosition(model, ws, q0, hip, Eigen::Vector3d::Zero());
  const Eigen::Vector3d p_toe = CalcPointPosition(model, ws, q0, foot, Eigen::Vector3d::Zero());
  Eigen::Vector3d u = p_toe - p_hip;
  u(1) = 0.0;
  u.normalize();
  const double k_shin = model.spring_stiffness()(leg.shin_index()), k_heel = model.spring_stiffness()(leg.heel_index());
  auto energy = [&](double e) {
    std::vector<PoseConstraint> c;
    for (int i = 0; i < model.nq(); ++i) {
      if (i != leg.shin_index() && i != leg.tarsus_index() && i != leg.heel_index()) {
        c.push_back(PoseConstraint::Coordinate(i, q0(i)));
      }
    }
    c.push_back(PoseConstraint::LoopClosure(0));  // left_achilles
    const Eigen::Vector3d target = p_toe + e * u;
    c.push_back(PoseConstraint::Point(model, "left_foot", Eigen::Vector3d::Zero(), 0, target(0)));
    c.push_back(PoseConstraint::Point(model, "left_foot", Eigen::Vector3d::Zero(), 2, target(2)));
    const Eigen::VectorXd q = SolvePose(model, ws, q0, c);
    const double qs = q(leg.shin_index()), qh = q(leg.heel_index());
    return 0.5 * k_shin * qs * qs + 0.5 * k_heel * qh * qh;
  };
  const double e = 2e-4;
  return (energy(e) + energy(-e) - 2.0 * energy(0.0)) / (e * e);
}

TEST(CassieVirtualLeg, EquationTwelveMatchesEnergyFiniteDifferences) {
  ASSERT_EQ(Cassie().loop_closures()[0].name, "left_achilles");
  const CassieVirtualLeg leg(Cassie(), "left");
  for (double L : {0.62, 0.7, 0.8, 0.88, 0.94}) {
    const double q = leg.KneeAngle(L);
    const double K = leg.Stiffness(q), K_fd = FiniteDifferenceStiffness(leg, q);
    EXPECT_NEAR(K / K_fd, 1.0, 1e-4) << "L = " << L;
    // Damping with the same formula: D/K = d/k of the springs (4.6/2300 = 4.0/2000 = 0.002 s).
    EXPECT_NEAR(leg.Damping(q) / K, 0.002, 1e-9) << "L = " << L;
  }
}

TEST(IdentifyCassieLegStiffness, RegressionMatchesFiniteDifferencesAndReport) {
  const CassieVirtualLeg leg(Cassie(), "left");
  const LegStiffnessIdentification id = IdentifyCassieLegStiffness(leg);
  // The 4-term form (no cubic term) fits Eq. (12) over 0.6-0.92 m to a few percent.
  EXPECT_LT(id.max_relative_fit_error, 0.05);
  const LegStiffness published = PublishedLegStiffness();
  std::printf("identified K(L) = %.1f + %.1f L + %.1f L^2 + %.1f L^4 N/m (fit error %.2f %%)\n", id.leg.stiffness.c0,
              id.leg.stiffness.c1, id.leg.stiffness.c2, id.leg.stiffness.c4, 100 * id.max_relative_fit_error);
  std::printf("identified D(L) = %.3f + %.3f L + %.3f L^2 + %.3f L^4 N s/m\n", id.leg.damping.c0, id.leg.damping.c1,
              id.leg.damping.c2, id.leg.damping.c4);
  std::printf("  L [m]   q_knee [deg]  K_pub [N/m]  K_id [N/m]  K_fd [N/m]  ratio id/pub  D_pub  D_id\n");
  for (double L : {0.60, 0.65, 0.70, 0.75, 0.80, 0.85, 0.90, 0.92}) {
    const double q = leg.KneeAngle(L);
    const double K_fd = FiniteDifferenceStiffness(leg, q);
    const double K_id = id.leg.stiffness.Evaluate(L);
    EXPECT_NEAR(K_id / K_fd, 1.0, id.max_relative_fit_error + 0.005) << "L = " << L;
    std::printf("  %.2f   %8.2f      %8.1f    %8.1f    %8.1f    %6.2f     %6.2f  %6.2f\n", L, q / kDeg,
                published.stiffness.Evaluate(L), K_id, K_fd, K_id / published.stiffness.Evaluate(L),
                published.damping.Evaluate(L), id.leg.damping.Evaluate(L));
  }
}

}  // namespace
}  // namespace rome
