#pragma once
// SteppingStonesOutputAdapter: maps the desired outputs Y_d of the stepping-stones paper, Eq. (19), which are relative
// to the stance foot and name "the swing foot", to the world-frame task layout of a planar biped controller, where
// each foot has its own rows.
//
// inputs:  y_desired (4), ydot_desired (4), yddot_desired (4)
//                                   Y_d, Ẏ_d, Ÿ_d in the order [φ_torso (rad), p_com^z (m), p_sw^x (m), p_sw^z (m)],
//                                   positions relative to the stance foot (SteppingStonesOutputsSystem)
//          stance_foot (2)          world (x, z) of the stance foot [m]
//          mode (int, typed)        the plant's contact mode: 0 left stance (right foot swings), 1 right stance (left
//                                   foot swings), anything else (flight) no foot swings
// outputs: desired (18)             [y_d; ẏ_d; ÿ_d], each in the controller layout
//                                   [torso pitch (rad), COM z (m), left foot x, left foot z, right foot x, right foot z (m)]
//                                   in world coordinates (positions shifted by the stance foot; rates unchanged). The
//                                   rows of a foot that does not swing are zero (its task is inactive in that mode).
// Direct feedthrough from every input; no state.

#include <string>

#include "framework/system.h"

namespace rome {

class SteppingStonesOutputAdapter final : public LeafSystem {
 public:
  static constexpr int kNumTaskRows = 6;  ///< rows of one third of the desired port
  explicit SteppingStonesOutputAdapter(std::string name = "output_adapter");
  /// Element names of one third of the desired port: "torso_pitch", "com_z", "left_foot_x", ... .
  static std::vector<std::string> TaskRowNames();
};

}  // namespace rome
