#pragma once
// The CLF-QP's outputs (clf_qp_controller.h): relative degree 2, a TaskSpaceTask (task_space_tasks.h), or relative
// degree 1, y1 = A(q) q̇, such as the centroidal pitch momentum of the hopping paper (Eq. (38)-(40), N m s).

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "systems/controllers/task_space_tasks.h"
#include "systems/multibody/multibody_kinematics.h"
#include "systems/multibody/multibody_model.h"
#include "systems/multibody/multibody_workspace.h"

namespace rome {

/// A relative-degree-one output y1 = A(q) q̇ (e.g. a momentum): reports y1, A (size × nv) and Ȧ q̇.
class RelativeDegreeOneOutput {
 public:
  RelativeDegreeOneOutput(std::string name, int size, double weight = 1.0, std::vector<int> active_modes = {});
  virtual ~RelativeDegreeOneOutput() = default;
  RelativeDegreeOneOutput(const RelativeDegreeOneOutput&) = delete;
  RelativeDegreeOneOutput& operator=(const RelativeDegreeOneOutput&) = delete;
  const std::string& name() const { return name_; }
  int size() const { return size_; }
  double weight() const { return weight_; }
  const std::vector<int>& active_modes() const { return active_modes_; }
  bool IsActiveIn(int mode) const;
  virtual void Calc(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, const VectorRef& v,
                    Eigen::Ref<Eigen::VectorXd> y1, Eigen::Ref<Eigen::MatrixXd> A,
                    Eigen::Ref<Eigen::VectorXd> Adot_v) const = 0;

 private:
  std::string name_;
  int size_;
  double weight_;
  std::vector<int> active_modes_;
};

/// Centroidal angular momentum about the COM around world y, H_pitch = A_pitch(q) q̇ [N m s] (hopping paper
/// Eq. (38)-(40)); Ȧ_pitch q̇ from the centroidal momentum bias.
class CentroidalPitchMomentumOutput final : public RelativeDegreeOneOutput {
 public:
  explicit CentroidalPitchMomentumOutput(std::string name = "centroidal_pitch_momentum", double weight = 1.0,
                                         std::vector<int> active_modes = {});
  void Calc(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, const VectorRef& v,
            Eigen::Ref<Eigen::VectorXd> y1, Eigen::Ref<Eigen::MatrixXd> A,
            Eigen::Ref<Eigen::VectorXd> Adot_v) const override;
};

/// One output of the CLF-QP: relative degree 2 (a TaskSpaceTask: COM, a point, a body's pitch, a joint; its weight
/// and active modes are used, its PD gains are not) or relative degree 1.
struct ClfOutput {
  std::shared_ptr<const TaskSpaceTask> rd2;
  std::shared_ptr<const RelativeDegreeOneOutput> rd1;
  static ClfOutput RelativeDegreeTwo(std::shared_ptr<const TaskSpaceTask> task) { return {std::move(task), nullptr}; }
  static ClfOutput RelativeDegreeOne(std::shared_ptr<const RelativeDegreeOneOutput> output) {
    return {nullptr, std::move(output)};
  }
  const std::string& name() const { return rd2 ? rd2->name() : rd1->name(); }
  int size() const { return rd2 ? rd2->size() : rd1->size(); }
  bool IsActiveIn(int mode) const { return rd2 ? rd2->IsActiveIn(mode) : rd1->IsActiveIn(mode); }
  double weight() const { return rd2 ? rd2->gains().weight : rd1->weight(); }
};

}  // namespace rome
