// BulletWorldPlant: the periodic update (push the state, B sat(u) and spring torques, Bullet's stepSimulation with
// collision detection, contact, armature-gear, joint-limit and rod constraints, the manifold forces) allocates no heap
// memory once the world is warm. Global operator new and, outside sanitizer builds, glibc's malloc family (Bullet
// allocates through btAlignedAlloc -> malloc) are replaced in this binary and count allocations. Kept in its own
// binary.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <utility>

#include "systems/plants/bullet_world_plant.h"

#include "tests/common/allocation_counter.h"  // replaces operator new/malloc in this binary
#include "tests/common/source_path.h"

namespace rome {
namespace {

std::shared_ptr<const MultibodyModel> Load(const std::string& sidecar) {
  return std::make_shared<const MultibodyModel>(
      MultibodyModel::LoadFromSidecar(rome::test::SourcePath(sidecar), {.euler_floating_base = true}));
}

TEST(BulletWorldPlantAllocation, CountingWorks) {
  static double* volatile sink = nullptr;
  EXPECT_EQ(rome::test::CountAllocations([] { sink = new double[16]; }), 1);
  delete[] sink;
}

// Runs `steps` periodic updates of `plant` from q_nominal at rest (both feet on the ground, no torque) after `warm`
// updates, twice on the same context (the second run starts again from q_nominal: same world, same scratch); returns
// the allocations counted in the `steps` of each run. The state advances (each update's result is the next).
std::pair<long, long> CountStepAllocations(const BulletWorldPlant& plant, const std::string& mode, int warm,
                                           int steps) {
  const MultibodyModel& model = plant.model();
  auto context = plant.CreateDefaultLeafContext();
  context->FixInputPort(0, Eigen::VectorXd::Zero(model.nu()));
  const auto& update = plant.periodic_events().at(0).update;
  long counts[2] = {0, 0};
  for (int run = 0; run < 2; ++run) {
    plant.SetState(*context, model.q_nominal(), Eigen::VectorXd::Zero(model.nv()), mode);
    Eigen::VectorXd next = context->discrete_state();
    for (int i = 0; i < warm; ++i) {
      next = context->discrete_state();
      EXPECT_TRUE(update(*context, &next).ok());
      context->get_mutable_state().discrete = next;
    }
    for (int i = 0; i < steps; ++i) {
      next = context->discrete_state();  // same size: no allocation
      const long n = test::CountAllocations([&] { EXPECT_TRUE(update(*context, &next).ok()); });
      if (n > 0) std::printf("  run %d, step %d: %ld allocations\n", run, warm + i, n);
      counts[run] += n;
      context->get_mutable_state().discrete = next;
    }
  }
  return {counts[0], counts[1]};
}

// AMBER (planar, point feet, four armature gears, joint limits) standing on flat ground: after 20 warm steps, 500 more
// allocate nothing.
TEST(BulletWorldPlantAllocation, AmberStepDoesNotAllocateOnceWarm) {
  BulletWorldPlant amber("amber", Load("robots/amber/amber.rome.json"),
                         ContactModeGraph::Hopping("left_foot", "right_foot"), Terrain::Flat());
  const auto [first, second] = CountStepAllocations(amber, "stance", 20, 500);
  std::printf("AMBER: %ld allocations in 500 steps, %ld in the repeat\n", first, second);
  EXPECT_EQ(first, 0);
  EXPECT_EQ(second, 0);
}

// 3D Cassie (line feet, ten gears, two achilles rods) collapsing under no torque for 0.5 s: Bullet allocates while its
// work arrays (solver rows, manifold points) reach a new high-water mark the first time more contacts or joint limits
// engage (measured: 30 allocations in 3 steps of the first run), and never again: the same 0.5 s repeated on the same
// world allocates nothing.
TEST(BulletWorldPlantAllocation, CassieStepAllocatesOnlyAtNewHighWaterMarks) {
  BulletWorldPlant cassie("cassie", Load("robots/cassie/cassie.rome.json"),
                          ContactModeGraph::Hopping("left_foot", "right_foot"), Terrain::Flat());
  const auto [first, second] = CountStepAllocations(cassie, "stance", 20, 500);
  std::printf("Cassie: %ld allocations in 500 steps, %ld in the repeat\n", first, second);
  EXPECT_LE(first, 100);
  EXPECT_EQ(second, 0);
}

}  // namespace
}  // namespace rome
