#pragma once
// SteppingStonesOutputAdapter: maps the desired outputs Y_d of the stepping-stones paper, Eq. (19), which are relative
// to the stance foot and name "the swing foot", to the world-frame task layout of a planar biped controller, where
// each foot has its own rows.
//
// inputs:  y_desired (4), ydot_desired (4), yddot_desired (4)
//                                   Y_d, Ẏ_d, Ÿ_d in the order [φ_torso (rad), p_com^z (m), p_sw^x (m), p_sw^z (m)],
//                                   positions relative to the stance foot (SteppingStonesOutputsSystem)
//          stance_foot (2)          world (x, z) of the stance foot [m]
//          mode (int, typed)        the plant's contact mode (ContactModeGraph::SingleSupportMode): 0 left stance
//                                   (right foot swings), 1 right stance (left foot swings), anything else (flight) no
//                                   foot swings
// outputs: desired (3 rows)         [y_d; ẏ_d; ÿ_d], each in the controller layout
//                                   [torso pitch (rad), COM z (m), left foot x, left foot z, right foot x, right foot z
//                                   (m)] (rows = 6), followed, with params.foot_pitch (line/flat feet, e.g. planar
//                                   Cassie), by [left foot pitch, right foot pitch (rad)] (rows = 8), in world
//                                   coordinates (positions shifted by the stance foot; rates unchanged). The rows of a
//                                   foot that does not swing are zero (its task is inactive in that mode). The swing
//                                   foot's pitch target is its flat pitch (params; the sole parallel to the horizontal
//                                   stones) with zero rate and acceleration: the fifth output of planar Cassie (hopping
//                                   spec C.12).
// Direct feedthrough from every input; no state.

#include <string>
#include <vector>

#include "framework/system.h"

namespace rome {

struct SteppingStonesOutputAdapterParams {
  /// Add the swing-foot pitch rows (line/flat feet). Off for point feet (AMBER: the 6-row layout).
  bool foot_pitch = false;
  double left_foot_flat_pitch_rad = 0.0;   ///< [rad] pitch of the left foot link when its sole is horizontal
  double right_foot_flat_pitch_rad = 0.0;  ///< [rad] the same for the right foot
};

class SteppingStonesOutputAdapter final : public LeafSystem {
 public:
  static constexpr int kNumTaskRows = 6;  ///< rows of one third of the desired port without foot pitch
  explicit SteppingStonesOutputAdapter(std::string name = "output_adapter",
                                       SteppingStonesOutputAdapterParams params = {});
  /// Element names of one third of the desired port: "torso_pitch", "com_z", "left_foot_x", ... (6 rows).
  static std::vector<std::string> TaskRowNames();
  /// This adapter's rows of one third of the desired port (6, or 8 with foot pitch) and their names.
  int num_task_rows() const { return params_.foot_pitch ? kNumTaskRows + 2 : kNumTaskRows; }
  std::vector<std::string> task_row_names() const;
  const SteppingStonesOutputAdapterParams& params() const { return params_; }

 private:
  SteppingStonesOutputAdapterParams params_;
};

}  // namespace rome
