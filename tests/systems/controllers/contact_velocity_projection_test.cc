// ContactVelocityProjection on the exoskeleton (Euler base and its quaternion twin), against the M-orthogonal
// projection onto {v : J v = 0} computed independently, by a dense LU of the KKT system
//   [M  Jᵀ] [v⁺]   [M v]
//   [J  0 ] [λ ] = [ 0 ]
// (the block goes through the Delassus matrix J M⁻¹ Jᵀ and a mass-matrix solve instead). Also: J v⁺ = 0, the kinetic
// energy does not grow, the map is idempotent and leaves q alone, a mode without contacts passes v through, bad inputs
// are refused by name, and the output allocates nothing once running (this binary replaces the global allocator).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <Eigen/LU>

#include "systems/controllers/contact_velocity_projection.h"
#include "systems/multibody/multibody_dynamics.h"
#include "systems/plants/quaternion_to_euler_state.h"
#include "tests/common/allocation_counter.h"
#include "tests/systems/controllers/amber_test_setup.h"

namespace rome {
namespace {

struct Reference {
  Eigen::VectorXd v_plus;
  Eigen::MatrixXd J;
};

// v⁺ from the KKT system by a dense LU (independent of the block's Delassus path).
Reference KktProjection(const MultibodyModel& model, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                        ContactSet active) {
  MultibodyWorkspace ws(model);
  const int nv = model.nv();
  const Eigen::MatrixXd M = CalcMassMatrix(model, ws, q);
  const int k = CalcConstraintJacobian(model, ws, q, v, active);
  Reference r{v, ws.J.topRows(k)};
  if (k == 0) return r;
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(nv + k, nv + k);
  K.topLeftCorner(nv, nv) = M;
  K.topRightCorner(nv, k) = r.J.transpose();
  K.bottomLeftCorner(k, nv) = r.J;
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(nv + k);
  rhs.head(nv) = M * v;
  r.v_plus = K.fullPivLu().solve(rhs).head(nv);
  return r;
}

struct Case {
  std::shared_ptr<const MultibodyModel> model;
  Eigen::VectorXd x;
  std::vector<ContactSet> modes;
};

Case MakeCase(bool quaternion) {
  Case c;
  auto euler = test::LoadRobot("exoskeleton");
  // Pitch −0.2, roll 0.1 rad, every coordinate moving: a velocity inconsistent with any contact.
  const Eigen::VectorXd xe = test::GenericEulerState(*euler, -0.2, 0.1);
  c.model = quaternion ? LoadQuaternionTwin(*euler) : euler;
  c.x = xe;
  if (quaternion) {
    c.x.resize(xe.size() + 1);
    EulerStateToQuaternion(xe, c.x);
  }
  const int l = c.model->ContactIndex("left_foot"), r = c.model->ContactIndex("right_foot");
  c.modes = {ContactBit(l), ContactBit(l) | ContactBit(r), ContactBit(r), 0};
  return c;
}

Eigen::VectorXd Project(const ContactVelocityProjection& block, LeafContext& context, const Eigen::VectorXd& x,
                        int mode) {
  context.FixInputPort(0, x);
  context.FixAbstractInputPort(1, std::any(mode));
  context.InvalidateCache();
  return block.EvalOutput(context, "state");
}

class ContactVelocityProjectionTest : public ::testing::TestWithParam<bool> {};

TEST_P(ContactVelocityProjectionTest, IsTheMassOrthogonalProjectionOntoTheModesContacts) {
  const Case c = MakeCase(GetParam());
  const MultibodyModel& m = *c.model;
  const int nq = m.nq(), nv = m.nv();
  ContactVelocityProjection block("projection", c.model, c.modes);
  auto context = block.CreateDefaultLeafContext();
  MultibodyWorkspace ws(m);
  const Eigen::VectorXd q = c.x.head(nq), v = c.x.tail(nv);
  const Eigen::MatrixXd M = CalcMassMatrix(m, ws, q);
  for (int mode = 0; mode < static_cast<int>(c.modes.size()); ++mode) {
    const Eigen::VectorXd y = Project(block, *context, c.x, mode);
    const Reference ref = KktProjection(m, q, v, c.modes[mode]);
    const Eigen::VectorXd v_plus = y.tail(nv);
    EXPECT_EQ(y.head(nq), q) << "mode " << mode;
    EXPECT_LT((v_plus - ref.v_plus).norm(), 1e-9 * (1.0 + v.norm())) << "mode " << mode;
    if (ref.J.rows() > 0) {
      EXPECT_LT((ref.J * v_plus).norm(), 1e-10) << "mode " << mode;
      EXPECT_GT((ref.J * v).norm(), 0.1) << "the test velocity must violate the contacts";
    } else {
      EXPECT_EQ(v_plus, v) << "a mode without contacts passes v through";
    }
    EXPECT_LE(v_plus.dot(M * v_plus), v.dot(M * v) + 1e-12) << "kinetic energy grew in mode " << mode;
    Eigen::VectorXd again = y;
    const Eigen::VectorXd twice = Project(block, *context, again, mode);
    EXPECT_LT((twice - y).norm(), 1e-10) << "not idempotent in mode " << mode;
  }
}

TEST_P(ContactVelocityProjectionTest, AllocatesNothingOnceRunning) {
  const Case c = MakeCase(GetParam());
  ContactVelocityProjection block("projection", c.model, c.modes);
  auto context = block.CreateDefaultLeafContext();
  context->FixInputPort(0, c.x);
  context->FixAbstractInputPort(1, std::any(1));
  block.EvalOutput(*context, "state");  // the cache's first fill
  long allocations = 0;
  for (int tick = 0; tick < 40; ++tick) {
    auto& x = const_cast<Eigen::VectorXd&>(block.EvalInput(*context, 0));
    x[c.model->nq() + 2] = 0.1 + 0.01 * tick;
    auto& mode = const_cast<int&>(block.EvalTypedInput<int>(*context, 1));
    mode = tick % 4;
    context->InvalidateCache();
    allocations += test::CountAllocations([&] { block.EvalOutput(*context, "state"); });
  }
  EXPECT_EQ(allocations, 0);
}

INSTANTIATE_TEST_SUITE_P(Bases, ContactVelocityProjectionTest, ::testing::Values(false, true),
                         [](const auto& info) { return info.param ? "Quaternion" : "Euler"; });

TEST(ContactVelocityProjection, RefusesBadInputsByName) {
  const Case c = MakeCase(false);
  EXPECT_THROW(ContactVelocityProjection("p", nullptr, c.modes), std::runtime_error);
  try {
    ContactVelocityProjection("p", c.model, {});
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "system 'p': no contact modes given (mode_contacts is empty)");
  }
  ContactVelocityProjection block("p", c.model, c.modes);
  auto context = block.CreateDefaultLeafContext();
  try {
    Project(block, *context, c.x, 7);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "system 'p': input port 'mode' has value 7; expected a mode index in [0, 4)");
  }
  Eigen::VectorXd bad = c.x;
  bad[3] = std::nan("");
  try {
    Project(block, *context, bad, 0);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "system 'p': input port 'state' is not finite at t = 0.000000");
  }
}

}  // namespace
}  // namespace rome
