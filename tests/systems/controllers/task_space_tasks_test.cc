// Task outputs of the task-space QP: J_y against central finite differences of y(q), J̇_y q̇ against the
// finite-difference time derivative of J_y(q + t q̇) q̇, and closed forms (torso pitch = q[2] on AMBER).
#include "systems/controllers/task_space_tasks.h"

#include <gtest/gtest.h>

#include <random>
#include "tests/common/source_path.h"

namespace rome {
namespace {

std::shared_ptr<const MultibodyModel> Load(const std::string& robot) {
  return std::make_shared<const MultibodyModel>(MultibodyModel::LoadFromSidecar(
      rome::test::SourcePath("robots/" + robot + "/" + robot + ".rome.json"), {.euler_floating_base = true}));
}

void CheckAgainstFiniteDifferences(const MultibodyModel& model, const TaskSpaceTask& task, const Eigen::VectorXd& q,
                                   const Eigen::VectorXd& v) {
  MultibodyWorkspace ws(model);
  const int n = task.size(), nv = model.nv();
  Eigen::VectorXd y(n), yp(n), ym(n), Jdq(n), dummy(n);
  Eigen::MatrixXd J(n, nv), Jp(n, nv), Jm(n, nv);
  task.Calc(model, ws, q, v, y, J, Jdq);
  const double h = 1e-6;
  Eigen::MatrixXd J_fd(n, nv);
  for (int k = 0; k < nv; ++k) {
    Eigen::VectorXd qp = q, qm = q;
    qp[k] += h;
    qm[k] -= h;
    task.Calc(model, ws, qp, v, yp, Jp, dummy);
    task.Calc(model, ws, qm, v, ym, Jm, dummy);
    J_fd.col(k) = (yp - ym) / (2 * h);
  }
  EXPECT_LT((J - J_fd).cwiseAbs().maxCoeff(), 1e-7) << task.name() << "\nJ =\n" << J << "\nfd =\n" << J_fd;
  // d/dt (J(q(t)) q̇) at q̇ fixed = J̇ q̇.
  task.Calc(model, ws, q + h * v, v, yp, Jp, dummy);
  task.Calc(model, ws, q - h * v, v, ym, Jm, dummy);
  const Eigen::VectorXd Jdq_fd = (Jp * v - Jm * v) / (2 * h);
  EXPECT_LT((Jdq - Jdq_fd).cwiseAbs().maxCoeff(), 1e-6)
      << task.name() << ": " << Jdq.transpose() << " vs " << Jdq_fd.transpose();
}

TEST(TaskSpaceTasks, JacobiansAndBiasMatchFiniteDifferencesOnAmber) {
  auto model = Load("amber");
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  Eigen::VectorXd q = model->q_nominal(), v(model->nv());
  for (int i = 0; i < model->nv(); ++i) {
    q[i] += 0.3 * U(rng);
    v[i] = 2.0 * U(rng);
  }
  CheckAgainstFiniteDifferences(*model, ComPositionTask("com", {Axis::kX, Axis::kZ}), q, v);
  CheckAgainstFiniteDifferences(*model, BodyPitchTask("torso_pitch", *model, "torso"), q, v);
  CheckAgainstFiniteDifferences(*model, BodyPitchTask("shin_pitch", *model, "right_shin"), q, v);
  CheckAgainstFiniteDifferences(
      *model, *PointPositionTask::ForContact("swing", *model, "right_foot", {Axis::kX, Axis::kZ}), q, v);
  CheckAgainstFiniteDifferences(*model, JointPositionTask("knee", *model, "left_knee"), q, v);
}

// BodyOrientationTask on the 3D exoskeleton: y = the rotation vector (a base yaw ψ turns the flat foot by ψ about world
// z: y = (0, 0, ψ)), and at a flat, unyawed foot (y = 0, where ẏ = ω exactly) J equals finite differences of y(q).
TEST(TaskSpaceTasks, BodyOrientationIsTheRotationVectorWithTheAngularVelocityJacobian) {
  auto model = Load("exoskeleton");
  const BodyOrientationTask task("foot", *model, "left_foot");
  MultibodyWorkspace ws(*model);
  Eigen::VectorXd q = model->q_nominal(), y(3), Jdq(3);
  Eigen::MatrixXd J(3, model->nv());
  q[model->VelocityIndex("base_yaw")] = 0.3;
  task.Calc(*model, ws, q, Eigen::VectorXd::Zero(model->nv()), y, J, Jdq);
  EXPECT_LT((y - Eigen::Vector3d(0, 0, 0.3)).norm(), 1e-9) << y.transpose();
  q = model->q_nominal();
  task.Calc(*model, ws, q, Eigen::VectorXd::Zero(model->nv()), y, J, Jdq);
  EXPECT_LT(y.norm(), 1e-9);
  const double h = 1e-6;
  Eigen::VectorXd yp(3), ym(3);
  Eigen::MatrixXd Jx(3, model->nv());
  for (int k = 0; k < model->nv(); ++k) {
    Eigen::VectorXd qp = q, qm = q;
    qp[k] += h;
    qm[k] -= h;
    task.Calc(*model, ws, qp, Eigen::VectorXd::Zero(model->nv()), yp, Jx, Jdq);
    task.Calc(*model, ws, qm, Eigen::VectorXd::Zero(model->nv()), ym, Jx, Jdq);
    EXPECT_LT(((yp - ym) / (2 * h) - J.col(k)).norm(), 1e-6) << "column " << k;
  }
  EXPECT_THROW(BodyOrientationTask("bad", *Load("amber"), "torso"), std::invalid_argument);
}

TEST(TaskSpaceTasks, AmberCoordinatesAndTorsoPitchIsTheBasePitch) {
  auto model = Load("amber");
  // q = [x, z, pitch, left_hip, left_knee, right_hip, right_knee].
  EXPECT_EQ(model->VelocityIndex("left_hip"), 3);
  EXPECT_EQ(model->VelocityIndex("left_knee"), 4);
  EXPECT_EQ(model->VelocityIndex("right_hip"), 5);
  EXPECT_EQ(model->VelocityIndex("right_knee"), 6);
  MultibodyWorkspace ws(*model);
  BodyPitchTask pitch("torso_pitch", *model, "torso");
  Eigen::VectorXd q = model->q_nominal(), v = Eigen::VectorXd::Zero(7), y(1), Jdq(1);
  Eigen::MatrixXd J(1, 7);
  q[2] = 0.3;
  q[3] = -0.7;
  pitch.Calc(*model, ws, q, v, y, J, Jdq);
  EXPECT_NEAR(y[0], 0.3, 1e-12);
  EXPECT_NEAR((J - Eigen::RowVectorXd::Unit(7, 2)).norm(), 0.0, 1e-12);
  // The shin's pitch is the sum of base pitch, hip and knee angles (all axes +y).
  BodyPitchTask shin("shin", *model, "left_shin");
  shin.Calc(*model, ws, q, v, y, J, Jdq);
  EXPECT_NEAR(y[0], q[2] + q[3] + q[4], 1e-12);
  // Point foot: the foot of a straight vertical leg at pitch 0 is 0.4064 + 0.4667 m below the hip.
  Eigen::VectorXd q0 = Eigen::VectorXd::Zero(7);
  auto foot = PointPositionTask::ForContact("foot", *model, "left_foot", {Axis::kX, Axis::kZ});
  Eigen::VectorXd p(2), Jdq2(2);
  Eigen::MatrixXd J2(2, 7);
  foot->Calc(*model, ws, q0, v, p, J2, Jdq2);
  EXPECT_NEAR(p[0], 0.0, 1e-12);
  EXPECT_NEAR(p[1], -(0.4064 + 0.4667), 1e-12);
}

TEST(TaskSpaceTasks, BadDefinitionsAreNamed) {
  auto model = Load("amber");
  EXPECT_THROW(ComPositionTask("com", {}), std::invalid_argument);
  EXPECT_THROW(ComPositionTask("com", {Axis::kZ, Axis::kZ}), std::invalid_argument);
  EXPECT_THROW(BodyPitchTask("p", *model, "no_such_link"), std::invalid_argument);
  try {
    ComPositionTask("com_z", {Axis::kZ}, TaskGains{-1.0, 1.0, 1.0});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("com_z"), std::string::npos) << e.what();
  }
  auto exo = Load("exoskeleton");
  EXPECT_THROW(BodyPitchTask("p", *exo, exo->body(exo->num_bodies() - 1).name), std::invalid_argument);
  // Wrong output sizes.
  MultibodyWorkspace ws(*model);
  ComPositionTask com("com", {Axis::kX});
  Eigen::VectorXd y(2), Jdq(1);
  Eigen::MatrixXd J(1, 7);
  EXPECT_THROW(com.Calc(*model, ws, model->q_nominal(), Eigen::VectorXd::Zero(7), y, J, Jdq), std::invalid_argument);
}

}  // namespace
}  // namespace rome
