#pragma once
// ContactVelocityProjection: the state a controller sees, with its velocity made consistent with the plant's current
// contact mode. A controller that reads a delayed or noisy state (sensor latency, sensor noise) can see a foot that has
// already touched down still moving into the ground: with one sample of latency, the first solves after a touchdown
// see the pre-impact velocities while the mode input already says stance. This block applies the plastic impact map
// of the mode's constraints (the hybrid plant's own touchdown law, contact_dynamics.h; Hurmuzlu and Marghitu 1994)
//   v⁺ = (I − M⁻¹ Jᵀ (J M⁻¹ Jᵀ)⁻¹ J) v
// with J the rows of the mode's active contacts and the robot's loop closures at the measured q. It is the
// M-orthogonal projection of v onto {v : J v = 0}: the identity on a consistent velocity, idempotent, and it never
// adds kinetic energy (½ v⁺ᵀ M v⁺ ≤ ½ vᵀ M v).
//
// inputs:  state (nq + nv)     [q; v] as the controller would read it (e.g. after sensor noise and latency)
//          mode (int, typed)   the plant's contact mode, an index into mode_contacts
// outputs: state (nq + nv)     [q; v⁺] (direct feedthrough; element names StateElementNames(model))
// No state; the output allocates nothing once the run has started (a per-run workspace).
#include <memory>
#include <string>
#include <vector>

#include "framework/system.h"
#include "systems/multibody/contact_dynamics.h"
#include "systems/multibody/multibody_model.h"

namespace rome {

class ContactVelocityProjection final : public LeafSystem {
 public:
  /// `mode_contacts[m]`: the active contacts of mode m (e.g. ActiveContactsPerMode of the plant). `dynamics`: its
  /// regularization of J M⁻¹ Jᵀ is used (α and β are not). Throws, naming the system, on a null model or no modes.
  ContactVelocityProjection(std::string name, std::shared_ptr<const MultibodyModel> model,
                            std::vector<ContactSet> mode_contacts, ConstrainedDynamicsParameters dynamics = {});

  struct Scratch;

 private:
  std::any AllocateScratch() const override;

  std::shared_ptr<const MultibodyModel> model_;
  std::vector<ContactSet> mode_contacts_;
  ConstrainedDynamicsParameters dynamics_;
  int max_rows_ = 0;
  int mode_port_ = -1;
};

}  // namespace rome
