// PlantKind and MakeContactPlant: the one builder argument that swaps the plant of a diagram.
//  * ParsePlantKind reads "hybrid" and "bullet" (round trip through ToString) and rejects anything else with one line
//    that names the source (the flag) and the value.
//  * MakeContactPlant builds the plant of the kind asked for, with that kind's parameters, and either plant, given no
//    torque, lets a robot in flight fall freely: its COM follows z0 + vz0 t − g t²/2 (closed form: no external force
//    but gravity, whatever the joints do), to integration accuracy on the hybrid plant and to Bullet's semi-implicit
//    Euler error g t h / 2 on the Bullet plant.
#include "systems/plants/plant_kind.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "framework/simulator.h"
#include "tests/common/source_path.h"

namespace rome {
namespace {

TEST(PlantKind, ParsesBothKindsAndRejectsOthersNamingTheSourceAndValue) {
  for (const PlantKind kind : {PlantKind::kHybrid, PlantKind::kBullet}) EXPECT_EQ(ParsePlantKind(ToString(kind)), kind);
  for (const std::string bad : {"", "Bullet", "hybrid ", "drake"}) {
    try {
      ParsePlantKind(bad, "--plant");
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const std::invalid_argument& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("--plant"), std::string::npos) << what;
      EXPECT_NE(what.find("'" + bad + "'"), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
  }
}

// Issue 43: HybridContactPlant integrates dq/dt = G(q) v and accepts a quaternion free-flyer model (state nq + nv);
// the Bullet plant steps the Euler chain (nq == nv) and refuses it with one line naming the system, the robot and the
// base kind, instead of misreading its state.
TEST(PlantKind, BulletRefusesAQuaternionBaseAndHybridTakesItsState) {
  LoadOptions options;
  options.quaternion_floating_base = true;
  auto model = std::make_shared<const MultibodyModel>(
      MultibodyModel::LoadFromSidecar(rome::test::SourcePath("robots/exoskeleton/exoskeleton.rome.json"), options));
  ASSERT_EQ(model->nq(), model->nv() + 1);
  const ContactModeGraph graph = ContactModeGraph::AlternatingSingleSupport("left_foot", "right_foot");
  try {
    MakeContactPlant(PlantKind::kBullet, "exo_plant", model, graph, Terrain::Flat(), {}, {});
    ADD_FAILURE() << "the Bullet plant accepted a quaternion base";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("system 'exo_plant': robot 'exoskeleton' has a quaternion floating base (nq = " +
                        std::to_string(model->nq()) + ", nv = " + std::to_string(model->nv()) + ")"),
              std::string::npos)
        << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
  std::unique_ptr<ContactPlant> hybrid =
      MakeContactPlant(PlantKind::kHybrid, "exo_plant", model, graph, Terrain::Flat(), {}, {});
  EXPECT_EQ(hybrid->output_port(hybrid->GetOutputPortIndex("q")).size, model->nq());
  EXPECT_EQ(hybrid->output_port(hybrid->GetOutputPortIndex("v")).size, model->nv());
  EXPECT_EQ(hybrid->output_port(hybrid->GetOutputPortIndex("state")).size, model->nq() + model->nv());
}

TEST(PlantKind, EitherPlantLetsAFlyingRobotFallFreely) {
  auto model = std::make_shared<const MultibodyModel>(
      MultibodyModel::LoadFromSidecar(rome::test::SourcePath("robots/amber/amber.rome.json")));
  const ContactModeGraph graph = ContactModeGraph::AlternatingSingleSupport("left_foot", "right_foot");
  HybridContactPlantParams hybrid;
  BulletWorldPlantParams bullet;
  bullet.step_s = 5e-4;  // recognisably the Bullet parameters
  for (const PlantKind kind : {PlantKind::kHybrid, PlantKind::kBullet}) {
    SCOPED_TRACE(ToString(kind));
    std::unique_ptr<ContactPlant> plant =
        MakeContactPlant(kind, "plant", model, graph, Terrain::Flat(), hybrid, bullet);
    const auto* as_bullet = dynamic_cast<const BulletWorldPlant*>(plant.get());
    ASSERT_EQ(as_bullet != nullptr, kind == PlantKind::kBullet);
    if (as_bullet) { EXPECT_EQ(as_bullet->params().step_s, 5e-4); }
    ASSERT_NE(dynamic_cast<const HybridContactPlant*>(plant.get()) != nullptr, kind == PlantKind::kBullet);

    Eigen::VectorXd q = model->q_nominal();
    q[plant->base_height_index()] += 2.0;  // far above the ground: no touchdown within the run
    Eigen::VectorXd v = Eigen::VectorXd::Zero(model->nv());
    v[plant->base_height_index()] = 1.0;  // thrown upwards at 1 m/s
    auto context = plant->CreateDefaultLeafContext();
    plant->SetState(*context, q, v, "flight");
    context->FixInputPort(0, Eigen::VectorXd::Zero(model->nu()));
    const double z0 = plant->EvalOutput(*context, "com")[2], vz0 = plant->EvalOutput(*context, "com")[5];
    EXPECT_NEAR(vz0, 1.0, 1e-12);
    const LeafContext* c = context.get();
    Simulator sim(*plant, std::move(context));
    const double t = 0.4, g = -model->gravity().z();
    ASSERT_TRUE(sim.AdvanceTo(t).ok());
    // The Bullet plant's state after its last update is the state at the next multiple of its step (see its header).
    const double tk = kind == PlantKind::kBullet ? std::ceil(t / bullet.step_s - 1e-6) * bullet.step_s : t;
    const double tolerance = kind == PlantKind::kBullet ? g * tk * bullet.step_s : 1e-6;
    EXPECT_NEAR(plant->EvalOutput(*c, "com")[2], z0 + vz0 * tk - 0.5 * g * tk * tk, tolerance);
    EXPECT_NEAR(plant->EvalOutput(*c, "com")[5], vz0 - g * tk, 1e-6);
    EXPECT_EQ(c->mode(), plant->GetModeIndex("flight"));
  }
}

}  // namespace
}  // namespace rome
