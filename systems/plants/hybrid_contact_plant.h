#pragma once
// HybridContactPlant: a MultibodyModel as an event-accurate hybrid framework system.
//
// inputs:  u (nu)                      actuator torques [N m], joint side, in MultibodyModel::actuators() order
// outputs: q (nv)                      generalized positions (see multibody_model.h for the coordinates)
//          v (nv)                      generalized velocities
//          state (2 nv)                [q; v]
//          mode (int, typed)           index of the active contact mode (ContactModeGraph::modes order)
//          contact_forces (3 nc)       ground force on each contact [N], world axes; zero when not in contact
//          contact_violation (nc)      per contact: 0 ok, +1 negative normal force, +2 outside the friction cone
//          com (6)                     [p_com (m); v_com (m/s)], world; elements x, y, z, vx, vy, vz
// continuous state: [q; v]; discrete state: [time the current mode began (s)]; modes: the graph's modes.
//
// Flow in mode m with active contacts C(m) (plus every loop closure of the model):
//   M q̈ + h = B sat(u) + τ_spring + Jᵀ F,  J q̈ + J̇ q̇ = −2α J q̇ − β² φ   (contact_dynamics.h)
// Guards (all directional, on CVODE's rootfinder):
//   touchdown of contact c ∉ C(m): lowest contact point height above the terrain crosses 0 falling.
//     Armed only min_time_in_mode_s after the mode began (a foot that just lifted off starts at 0).
//     Reset: plastic impact q̇⁺ = (I − M⁻¹Jᵀ(JM⁻¹Jᵀ)⁻¹J) q̇⁻ with the TARGET mode's contact set; on a
//     stepping-stone terrain a touchdown that is not on a stone ends the run ("robot fell: ...").
//   lift-off of contact c ∈ C(m): its normal force crosses 0 falling. Reset: mode change only.
//   fall: base height below min_base_height_m (all modes) ends the run ("robot fell: ...").
// Unilateral and friction violations are not hidden: they appear in contact_violation.

#include <memory>
#include <string>
#include <vector>

#include "framework/system.h"
#include "systems/multibody/contact_dynamics.h"
#include "systems/multibody/multibody_model.h"
#include "systems/plants/terrain.h"

namespace rome {

/// The contact-mode graph is data: each diagram supplies its own (walking SSP→SSP, DSP/SSP, hopping).
struct ContactModeGraph {
  struct Mode {
    std::string name;
    std::vector<std::string> contacts;  ///< contact names (MultibodyModel::contacts()) active in this mode
  };
  enum class Kind { kTouchdown, kLiftoff };
  struct Transition {
    std::string from, to;
    Kind kind = Kind::kTouchdown;
    std::string contact;  ///< the contact that touches down or lifts off
  };
  std::vector<Mode> modes;
  std::vector<Transition> transitions;
  std::string initial_mode;

  /// Point-foot walking: single support on one foot, the swing foot's touchdown swaps stance through an
  /// impact (the old stance foot leaves the ground at once). Modes "<left>_stance", "<right>_stance".
  static ContactModeGraph AlternatingSingleSupport(const std::string& left_contact, const std::string& right_contact,
                                                   bool start_on_left = true);
  /// Walking with double support: left_stance, double_support, right_stance; touchdown leads to double
  /// support, lift-off of the trailing foot to single support.
  static ContactModeGraph WithDoubleSupport(const std::string& left_contact, const std::string& right_contact,
                                            const std::string& initial_mode = "double_support");
  /// Hopping on both feet: stance (both feet) → flight when a foot's normal force reaches zero; flight →
  /// stance at touchdown of either foot (the impact puts both feet in contact).
  static ContactModeGraph Hopping(const std::string& left_contact, const std::string& right_contact);
};

struct HybridContactPlantParams {
  ConstrainedDynamicsParameters dynamics;  ///< Baumgarte gains and regularisation (contact_dynamics.h)
  double min_time_in_mode_s = 0.05;        ///< [s] touchdown guards arm this long after a mode begins.
  double min_base_height_m = 0.2;          ///< [m] base below this height ends the run as a fall.
  double stone_tolerance_m = 0.0;          ///< [m] how far beyond a stone's edge a touchdown still counts.
  bool saturate_torques = true;            ///< clip u to the model's torque limits before applying it.
};

class HybridContactPlant final : public LeafSystem {
 public:
  HybridContactPlant(std::string name, std::shared_ptr<const MultibodyModel> model, ContactModeGraph graph, Terrain terrain,
                     HybridContactPlantParams params = {});

  const MultibodyModel& model() const { return *model_; }
  const Terrain& terrain() const { return terrain_; }
  const ContactModeGraph& graph() const { return graph_; }
  const HybridContactPlantParams& params() const { return params_; }
  /// Active contact set of a mode (bit i = contact i).
  ContactSet active_contacts(int mode) const { return mode_contacts_.at(mode); }
  int base_height_index() const;

  /// Sets q, v and the mode in a context (sizes checked); the mode clock starts at the context time.
  void SetState(LeafContext& context, const Eigen::VectorXd& q, const Eigen::VectorXd& v, const std::string& mode) const;

  struct Scratch;

 private:
  void DoCalcTimeDerivatives(const LeafContext& context, Eigen::VectorXd* xdot) const override;
  std::any AllocateScratch() const override;
  /// Constrained dynamics at the context's state, computed once per context version.
  const Scratch& EvalDynamics(const LeafContext& context) const;
  double TouchdownWitness(const LeafContext& context, int contact) const;

  std::shared_ptr<const MultibodyModel> model_;
  ContactModeGraph graph_;
  Terrain terrain_;
  HybridContactPlantParams params_;
  std::vector<ContactSet> mode_contacts_;
};

}  // namespace rome
