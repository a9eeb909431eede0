#include "diagrams/stepping_stones/stepping_stones_output_adapter.h"

#include "systems/plants/contact_plant.h"

namespace rome {

namespace {

// The plant's contact modes (ContactModeGraph::AlternatingSingleSupport).
constexpr int kLeftStance = ContactModeGraph::SingleSupportMode::kLeftStance;
constexpr int kRightStance = ContactModeGraph::SingleSupportMode::kRightStance;

}  // namespace

std::vector<std::string> SteppingStonesOutputAdapter::TaskRowNames() {
  return {"torso_pitch", "com_z", "left_foot_x", "left_foot_z", "right_foot_x", "right_foot_z"};
}

std::vector<std::string> SteppingStonesOutputAdapter::task_row_names() const {
  std::vector<std::string> names = TaskRowNames();
  if (params_.foot_pitch) {
    names.push_back("left_foot_pitch");
    names.push_back("right_foot_pitch");
  }
  return names;
}

SteppingStonesOutputAdapter::SteppingStonesOutputAdapter(std::string name, SteppingStonesOutputAdapterParams params)
    : LeafSystem(std::move(name)), params_(params) {
  const std::vector<std::string> y_names{"torso_pitch", "com_z", "swing_x", "swing_z"};
  DeclareInputPort("y_desired", y_names);
  DeclareInputPort("ydot_desired", y_names);
  DeclareInputPort("yddot_desired", y_names);
  DeclareInputPort("stance_foot", {"x", "z"});
  DeclareTypedInputPort<int>("mode");
  std::vector<std::string> names;
  for (const char* prefix : {"", "d_", "dd_"})
    for (const std::string& n : task_row_names()) names.push_back(prefix + n);
  const int rows = num_task_rows();
  DeclareOutputPort("desired", names, [this, rows](const LeafContext& c, Eigen::VectorXd* out) {
    const Eigen::VectorXd& stance = EvalInput(c, 3);
    const int mode = EvalTypedInput<int>(c, 4);
    // Left stance: the right foot's rows (4, 5) swing; right stance: the left foot's (2, 3); flight: none.
    const int swing_offset = mode == kLeftStance ? 4 : mode == kRightStance ? 2 : -1;
    out->setZero();
    for (int k = 0; k < 3; ++k) {
      const Eigen::VectorXd& y = EvalInput(c, k);
      const double shift_x = k == 0 ? stance[0] : 0.0, shift_z = k == 0 ? stance[1] : 0.0;
      auto seg = out->segment(k * rows, rows);
      seg[0] = y[0];
      seg[1] = y[1] + shift_z;
      if (swing_offset >= 0) {
        seg[swing_offset] = y[2] + shift_x;
        seg[swing_offset + 1] = y[3] + shift_z;
      }
    }
    // Swing-foot pitch: hold the sole horizontal (rate and acceleration 0).
    if (params_.foot_pitch && swing_offset >= 0)
      (*out)[mode == kLeftStance ? 7 : 6] =
          mode == kLeftStance ? params_.right_foot_flat_pitch_rad : params_.left_foot_flat_pitch_rad;
  });
}

}  // namespace rome
