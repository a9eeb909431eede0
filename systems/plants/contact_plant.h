#pragma once
// ContactPlant: what every legged-robot plant shares, so that diagrams can swap plants behind one set of ports.
//
// Both plants (HybridContactPlant: event-accurate, rigid; BulletWorldPlant: Bullet's discrete-time physics world)
// declare the same ports, with the same names, sizes, element names and types:
// inputs:  u (nu)                      actuator torques [N m], joint side, in MultibodyModel::actuators() order
// outputs: q (nq)                      generalized positions (see multibody_model.h for the coordinates)
//          v (nv)                      generalized velocities
//          state (nq + nv)             [q; v]; elements q_<joint>..., v_<joint>... (StateElementNames)
// nq == nv except on the quaternion free-flyer base (nq = nv + 1), which only HybridContactPlant accepts so far.
//          mode (int, typed)           index of the active contact mode (ContactModeGraph::modes order)
//          contact_forces (3 nc)       ground force on each contact [N], world axes; elements <contact>_fx, _fy, _fz
//          contact_violation (nc)      per contact: 0 ok, +1 negative normal force, +2 outside the friction cone (or,
//                                      BulletWorldPlant, sliding: SlipDistance)
//          com (6)                     [p_com (m); v_com (m/s)], world; elements x, y, z, vx, vy, vz
// and announce every contact-mode change through a guard named touchdown_<contact> or liftoff_<contact> whose reset
// changes the mode, so that blocks that re-plan at touchdowns (event updates) work with either plant.
// This class checks the contact-mode graph against the model and declares the modes.

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
  /// impact (the old stance foot leaves the ground at once). Modes (fixed indices): 0 "<left>_stance",
  /// 1 "<right>_stance", 2 "flight" (no contacts). Lift-off of the stance foot leads to flight; touchdown
  /// of either foot in flight leads to that foot's stance (plastic impact).
  static ContactModeGraph AlternatingSingleSupport(const std::string& left_contact, const std::string& right_contact,
                                                   bool start_on_left = true);
  /// The fixed mode indices of AlternatingSingleSupport, as the plant's typed `mode` port carries them.
  struct SingleSupportMode {
    static constexpr int kLeftStance = 0, kRightStance = 1, kFlight = 2;
  };
  /// Walking with double support: left_stance, double_support, right_stance; touchdown leads to double
  /// support, lift-off of the trailing foot to single support.
  static ContactModeGraph WithDoubleSupport(const std::string& left_contact, const std::string& right_contact,
                                            const std::string& initial_mode = "double_support");
  /// Hopping on both feet: stance (both feet) → flight when a foot's normal force reaches zero; flight →
  /// stance at touchdown of either foot (the impact puts both feet in contact).
  static ContactModeGraph Hopping(const std::string& left_contact, const std::string& right_contact);
  /// The hopping paper's domain graph (Sec. IV-A, Fig. 5, Eq. (18)-(21)) with its three named domains:
  /// 0 "jump" (both feet) → 1 "flight" when either foot's normal force reaches 0 (Eq. (19); identity reset, no
  /// impact); "flight" → 2 "landing" (both feet) at touchdown of any sole point of either foot (Eq. (21)), with a
  /// plastic impact on both feet at once. Landing is the paper's terminal domain; it also lifts off into "flight"
  /// (a foot's force reaching 0 there is the next hop's take-off: with several hops the landing of one hop is the
  /// crouch of the next, and the controller, not the plant, tells crouch from landing).
  static ContactModeGraph JumpFlightLanding(const std::string& left_contact, const std::string& right_contact);

  /// Index of the mode named `name`; an error naming `system` and the mode otherwise.
  int ModeIndex(const std::string& name, const std::string& system) const;
};

class ContactPlant : public LeafSystem {
 public:
  const MultibodyModel& model() const { return *model_; }
  const std::shared_ptr<const MultibodyModel>& shared_model() const { return model_; }
  const Terrain& terrain() const { return terrain_; }
  const ContactModeGraph& graph() const { return graph_; }
  /// Active contact set of a mode (bit i = contact i).
  ContactSet active_contacts(int mode) const { return mode_contacts_.at(mode); }
  /// Index of the base height in q (planar 1, spatial 2), -1 for a fixed base.
  int base_height_index() const;

  /// Sets q, v and the mode in a context (sizes checked); the mode clock starts at the context time.
  virtual void SetState(LeafContext& context, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                        const std::string& mode) const = 0;
  /// [m] how far contact `contact` has slid along the surface while in contact, when the plant counts that as a slip
  /// although the force stays in the friction cone; 0 otherwise. HybridContactPlant: always 0 (its contacts hold, and a
  /// force reaching the cone ends the run). BulletWorldPlant: the distance slid once it exceeds slip_distance_m.
  virtual double SlipDistance(const LeafContext& context, int contact) const {
    (void)context, (void)contact;
    return 0.0;
  }

 protected:
  /// Checks the graph's modes against the model's contacts and declares them (initial mode: graph.initial_mode, or
  /// the first). Errors name this system, the mode and the contact.
  ContactPlant(std::string name, std::shared_ptr<const MultibodyModel> model, ContactModeGraph graph, Terrain terrain);

  /// A transition of the graph with its modes and contact resolved to indices.
  struct ResolvedTransition {
    int from = -1, to = -1, contact = -1;
    ContactModeGraph::Kind kind = ContactModeGraph::Kind::kTouchdown;
  };
  /// The mode that contact `c` lifts off into from mode `m`: the graph's own lift-off transition if it has one, else
  /// the mode whose contact set is exactly C(m) \ {c}, else -1.
  int LiftoffMode(int m, int c) const;
  /// Whether the graph itself has a lift-off transition of contact `c` from mode `m` (a planned lift-off).
  bool IsGraphLiftoff(int m, int c) const { return graph_liftoff_[m][c] >= 0; }

  std::shared_ptr<const MultibodyModel> model_;
  ContactModeGraph graph_;
  Terrain terrain_;
  std::vector<ContactSet> mode_contacts_;
  std::vector<ResolvedTransition> transitions_;  ///< graph_.transitions, checked (errors name the transition)
  std::vector<std::vector<int>> graph_liftoff_;  ///< [mode][contact]: the first lift-off transition's target, or -1
};

/// Element names of a plant's state port [q; v]: q_<joint>... then v_<joint>...; on the quaternion base q's first seven
/// are q_base_x, q_base_y, q_base_z, q_base_qw, q_base_qx, q_base_qy, q_base_qz and v's first six v_base_vx ..
/// v_base_wz.
std::vector<std::string> StateElementNames(const MultibodyModel& model);

/// The active contact set of every mode of `plant`, in mode order (what a controller needs to know of the plant).
std::vector<ContactSet> ActiveContactsPerMode(const ContactPlant& plant);

}  // namespace rome
