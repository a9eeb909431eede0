#pragma once
// The walking example's outputs beside the summary: the CSV log, the PNG plots (the paper's Fig. 2 S2/L2, 3 S2/L2,
// 5a/b/d and gait tiles) and the HTML animation, recorded by a RunWalking observer.
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "diagrams/walking/walking_diagram.h"
#include "diagrams/walking/walking_run.h"
#include "systems/multibody/multibody_workspace.h"
#include "systems/visualization/animation.h"

namespace rome::examples {

class WalkingRecorder {
 public:
  /// Records what the outputs need: the log if `log`, the plot series if `plots`, frames if `animation`.
  WalkingRecorder(const WalkingDiagram& walking, bool log, bool plots, bool animation);
  /// The RunWalking observer (also prints the progress every 0.5 s of simulated time).
  WalkingRunObserver Observer();
  std::string log() const { return log_.str(); }
  /// PNG plots into `dir` (errors of single plots are printed, the others still written).
  void WritePlots(const std::string& dir, const WalkingPlan& rom_plan, const WalkingPlanReport& nlp,
                  const std::string& scenario, double t_stop) const;
  const visualization::AnimationRecorder* animation() const { return animation_.get(); }

 private:
  void Record(const Context& c, const WalkingRunSample& s);
  const WalkingDiagram& d_;
  MultibodyWorkspace ws_;
  bool logging_, plotting_;
  std::ostringstream log_;
  std::unique_ptr<visualization::AnimationRecorder> animation_;
  std::vector<double> t_, com_[6], vel_[6], force_[4];  // per tick: x, x_d, y, y_d, z, z_d; F_l, F_l ref, F_r, F_r ref
  std::vector<std::pair<double, Eigen::VectorXd>> poses_;  // q every 10 ms, for the gait tiles
};

}  // namespace rome::examples
