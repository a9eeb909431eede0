// BulletWorldPlant: the periodic update (push the state, B sat(u) and spring torques, Bullet's stepSimulation with
// collision detection, contact, armature-gear, joint-limit and rod constraints, the manifold forces) allocates no heap
// memory once the world is warm. Global operator new and, outside sanitizer builds, glibc's malloc family (Bullet
// allocates through btAlignedAlloc -> malloc) are replaced in this binary and count allocations. Kept in its own binary.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "systems/plants/bullet_world_plant.h"

#include "tests/common/allocation_counter.h"  // replaces operator new/malloc in this binary

namespace rome {
namespace {

std::shared_ptr<const MultibodyModel> Load(const std::string& sidecar) {
  return std::make_shared<const MultibodyModel>(MultibodyModel::LoadFromSidecar(std::string(ROME_SOURCE_DIR) + "/" + sidecar));
}

TEST(BulletWorldPlantAllocation, CountingWorks) {
  static double* volatile sink = nullptr;
  g_allocations = 0;
  g_counting = true;
  sink = new double[16];
  g_counting = false;
  delete[] sink;
  EXPECT_EQ(g_allocations, 1);
}

// Runs `steps` periodic updates of `plant` standing from q_nominal (both feet on the ground) after `warm` updates;
// returns the allocations counted during the last `steps`. The state advances (each update's result is the next).
long CountStepAllocations(const BulletWorldPlant& plant, const std::string& mode, int warm, int steps) {
  const MultibodyModel& model = plant.model();
  auto context = plant.CreateDefaultLeafContext();
  plant.SetState(*context, model.q_nominal(), Eigen::VectorXd::Zero(model.nv()), mode);
  context->FixInputPort(0, Eigen::VectorXd::Zero(model.nu()));
  const auto& update = plant.periodic_events().at(0).update;
  Eigen::VectorXd next = context->discrete_state();
  for (int i = 0; i < warm; ++i) {
    next = context->discrete_state();
    EXPECT_TRUE(update(*context, &next).ok());
    context->get_mutable_state().discrete = next;
  }
  long count = 0;
  for (int i = 0; i < steps; ++i) {
    next = context->discrete_state();  // same size: no allocation
    const long n = test::CountAllocations([&] { EXPECT_TRUE(update(*context, &next).ok()); });
    if (n > 0) std::printf("  step %d: %ld allocations\n", warm + i, n);
    count += n;
    context->get_mutable_state().discrete = next;
  }
  return count;
}

// AMBER (planar, point feet, four armature gears, joint limits) on flat ground, and 3D Cassie (line feet, ten gears,
// two achilles rods): after 20 warm steps, 500 more allocate nothing.
TEST(BulletWorldPlantAllocation, StepDoesNotAllocateOnceWarm) {
  {
    BulletWorldPlant amber("amber", Load("robots/amber/amber.rome.json"), ContactModeGraph::Hopping("left_foot", "right_foot"), Terrain::Flat());
    const long n = CountStepAllocations(amber, "stance", 20, 500);
    std::printf("AMBER: %ld allocations in 500 steps\n", n);
    EXPECT_EQ(n, 0);
  }
  {
    BulletWorldPlant cassie("cassie", Load("robots/cassie/cassie.rome.json"), ContactModeGraph::Hopping("left_foot", "right_foot"), Terrain::Flat());
    const long n = CountStepAllocations(cassie, "stance", 20, 500);
    std::printf("Cassie: %ld allocations in 500 steps\n", n);
    EXPECT_EQ(n, 0);
  }
}

}  // namespace
}  // namespace rome
