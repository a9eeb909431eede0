#pragma once
// AnimationRecorder: records a run (q, contact mode, the plant's contact forces) at a fixed frame rate and writes one
// self-contained HTML page that plays it in 3D: three.js from Debian's libjs-three inlined, nothing fetched.
//
// The page: play/pause, a time slider, a speed selector, a camera that follows the COM; the robot drawn from the
// URDF's visual geometry (box, cylinder, sphere) and, for a link without a visual, as capsules between its joint
// origins (and to its contact points); stepping stones or the ground from the terrain; the COM as a sphere; contact
// forces as arrows of length 0.5 m per m g; the contact mode and the time as text.
// Frames are decimated to `fps` and quantised (0.1 mm, 1e-4 for quaternions), so a 30-step run stays well under 5 MB.
// Test hook: page.html#test=t1,t2 renders t1 and t2 and writes a JSON report into <pre id="test-result"> (robot
// pixel centroids at both times, stone checks, JavaScript errors), read by tests through headless Chromium.

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "systems/multibody/multibody_model.h"
#include "systems/multibody/multibody_workspace.h"

namespace rome::visualization {

struct AnimationStone {
  double x_center_m = 0, top_height_m = 0, length_m = 0.1;
};

class AnimationRecorder {
 public:
  /// `three_js_path`: the three.js build to inline (Debian's libjs-three by default).
  AnimationRecorder(const MultibodyModel& model, double fps = 60.0, std::string three_js_path = DefaultThreeJsPath());
  /// A point mass drawn as a sphere of `radius_m` (e.g. the bouncing ball); record it with RecordPoint().
  explicit AnimationRecorder(double radius_m, double fps = 60.0, std::string three_js_path = DefaultThreeJsPath());
  ~AnimationRecorder();
  static std::string DefaultThreeJsPath() { return "/usr/share/javascript/three/three.min.js"; }

  /// Records a frame if at least 1/fps has passed since the last one. contact_forces: 3 per contact, world axes [N].
  void Record(double t, const Eigen::VectorXd& q, const std::string& mode, const Eigen::VectorXd& contact_forces);
  /// Records the point mass at `p` (world, z up) [m].
  void RecordPoint(double t, const Eigen::Vector3d& p, const std::string& mode);
  int num_frames() const { return static_cast<int>(times_.size()); }

  /// Checks before a run that `path` can be written (creates and removes the file); false with `error` otherwise.
  static bool CheckWritable(const std::string& path, std::string* error);
  /// Writes the page; false with `error` (naming the file) if three.js or the output cannot be read or written.
  bool WriteHtml(const std::string& path, const std::string& title, const std::vector<AnimationStone>& stones,
                 std::string* error) const;

 private:
  /// Appends the frame's time and mode unless it comes sooner than 1/fps after the last frame.
  bool BeginFrame(double t, const std::string& mode);
  bool WritePage(const std::string& path, const std::string& title, const std::vector<AnimationStone>& stones,
                 const std::string& three, const std::string& model_json, std::string* error) const;
  const MultibodyModel* model_ = nullptr;  // null: a point mass
  double point_radius_m_ = 0.03;
  double fps_;
  std::string three_js_path_;
  std::unique_ptr<MultibodyWorkspace> ws_;
  std::vector<int> drawn_bodies_;
  std::vector<double> times_;
  std::vector<std::string> modes_;
  std::vector<int> mode_index_;
  std::vector<float> poses_;   // per frame, per drawn body: x, y, z, qx, qy, qz, qw (three.js axes, y up)
  std::vector<float> coms_;    // per frame: x, y, z
  std::vector<float> forces_;  // per frame, per contact: px, py, pz, fx, fy, fz (three.js axes)
};

}  // namespace rome::visualization
