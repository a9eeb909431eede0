#pragma once
// Internal: Bullet scratch arrays owned by MultibodyWorkspace (kept out of the public header).
#include <BulletDynamics/Featherstone/btMultiBody.h>

#include "systems/multibody/multibody_workspace.h"

namespace rome {

struct MultibodyWorkspace::BulletScratch {
  btAlignedObjectArray<btQuaternion> world_to_local;
  btAlignedObjectArray<btVector3> local_origin;
  btAlignedObjectArray<btScalar> scratch_r, scratch_r2;
  btAlignedObjectArray<btVector3> scratch_v, scratch_v2;
  btAlignedObjectArray<btMatrix3x3> scratch_m;
};

}  // namespace rome
