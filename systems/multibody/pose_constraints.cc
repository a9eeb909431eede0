#include "systems/multibody/pose_constraints.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include <Eigen/Dense>

#include "systems/multibody/multibody_kinematics.h"

namespace rome {
namespace {

const char* AxisName(int axis) { return axis == 0 ? "x" : axis == 1 ? "y" : axis == 2 ? "z" : "?"; }

}  // namespace

PoseConstraint PoseConstraint::ContactPoint(const MultibodyModel& model, const std::string& contact, int axis,
                                            double target) {
  const ContactInfo& info = model.contacts()[model.ContactIndex(contact)];
  PoseConstraint c;
  c.kind = Kind::kPoint;
  c.axis = axis;
  c.body = info.body;
  c.p_link = info.frame_origin;
  c.target = target;
  c.name = std::string(AxisName(axis)) + " of contact " + contact;
  return c;
}

PoseConstraint PoseConstraint::Point(const MultibodyModel& model, const std::string& link,
                                     const Eigen::Vector3d& p_link, int axis, double target) {
  PoseConstraint c;
  c.kind = Kind::kPoint;
  c.axis = axis;
  c.body = model.BodyIndex(link);
  // p_link is in the link's frame; a link merged through a fixed joint is converted to its body.
  c.p_link = model.HasFrame(link) ? Eigen::Vector3d(model.Frame(link).X_body_frame * p_link) : p_link;
  c.target = target;
  return c;
}

PoseConstraint PoseConstraint::Com(int axis, double target) {
  PoseConstraint c;
  c.kind = Kind::kCom;
  c.axis = axis;
  c.target = target;
  return c;
}

PoseConstraint PoseConstraint::Coordinate(int index, double target) {
  PoseConstraint c;
  c.kind = Kind::kCoordinate;
  c.coordinate = index;
  c.target = target;
  return c;
}

PoseConstraint PoseConstraint::LoopClosure(int index) {
  PoseConstraint c;
  c.kind = Kind::kLoopClosure;
  c.loop_closure = index;
  c.target = 0.0;
  return c;
}

std::vector<PoseConstraint> PoseConstraint::LoopClosures(const MultibodyModel& model) {
  std::vector<PoseConstraint> out;
  for (int i = 0; i < model.num_loop_closures(); ++i) out.push_back(LoopClosure(i));
  return out;
}

std::string DescribePoseConstraint(const MultibodyModel& model, const PoseConstraint& c) {
  if (!c.name.empty()) return c.name;
  std::ostringstream s;
  switch (c.kind) {
    case PoseConstraint::Kind::kPoint:
      s << AxisName(c.axis) << " of point (" << c.p_link.x() << ", " << c.p_link.y() << ", " << c.p_link.z() << ") of ";
      if (c.body >= 0 && c.body < model.num_bodies())
        s << "link " << model.body(c.body).name;
      else
        s << "body index " << c.body;
      break;
    case PoseConstraint::Kind::kCom: s << "COM " << AxisName(c.axis); break;
    case PoseConstraint::Kind::kCoordinate:
      s << "q[" << c.coordinate << "]";
      if (c.coordinate >= 0 && c.coordinate < model.nq()) {
        if (!model.has_quaternion_base() || c.coordinate >= 7)
          s << " (" << model.JointName(model.has_quaternion_base() ? c.coordinate - 1 : c.coordinate) << ")";
        else
          s << (c.coordinate < 3 ? " (base position)" : " (base quaternion)");
      }
      break;
    case PoseConstraint::Kind::kLoopClosure:
      s << "loop closure ";
      if (c.loop_closure >= 0 && c.loop_closure < model.num_loop_closures())
        s << model.loop_closures()[c.loop_closure].name;
      else
        s << c.loop_closure;
      break;
  }
  return s.str();
}

void ValidatePoseConstraints(const MultibodyModel& model, const std::vector<PoseConstraint>& constraints) {
  const std::string who = "pose constraints for robot '" + model.name() + "': ";
  if (constraints.empty()) throw std::invalid_argument(who + "no constraints given");
  for (std::size_t i = 0; i < constraints.size(); ++i) {
    const PoseConstraint& c = constraints[i];
    const std::string what = who + "constraint " + std::to_string(i) + " (" + DescribePoseConstraint(model, c) + ") ";
    if (!std::isfinite(c.target)) throw std::invalid_argument(what + "has a non-finite target");
    switch (c.kind) {
      case PoseConstraint::Kind::kPoint:
        if (c.body < 0 || c.body >= model.num_bodies())
          throw std::invalid_argument(what + "names body index " + std::to_string(c.body) + ", the model has " +
                                      std::to_string(model.num_bodies()) + " bodies");
        if (!c.p_link.allFinite()) throw std::invalid_argument(what + "has a non-finite point");
        [[fallthrough]];
      case PoseConstraint::Kind::kCom:
        if (c.axis < 0 || c.axis > 2)
          throw std::invalid_argument(what + "has axis " + std::to_string(c.axis) + ", expected 0 (x), 1 (y) or 2 (z)");
        if (c.axis == 1 && model.is_planar())
          throw std::invalid_argument(
              what + "constrains y, but the model is planar (motion in the x-z plane): y cannot change");
        break;
      case PoseConstraint::Kind::kCoordinate:
        if (c.coordinate < 0 || c.coordinate >= model.nq())
          throw std::invalid_argument(what + "names coordinate " + std::to_string(c.coordinate) +
                                      ", the model has nq = " + std::to_string(model.nq()));
        if (model.has_quaternion_base() && c.coordinate >= 3 && c.coordinate < 7)
          throw std::invalid_argument(what +
                                      "is an entry of the base quaternion, which is not a coordinate of its "
                                      "own: constrain the base's orientation by points on it (Point)");
        break;
      case PoseConstraint::Kind::kLoopClosure:
        if (c.loop_closure < 0 || c.loop_closure >= model.num_loop_closures())
          throw std::invalid_argument(what + "names loop closure " + std::to_string(c.loop_closure) +
                                      ", the model has " + std::to_string(model.num_loop_closures()));
        break;
    }
  }
}

void CalcPoseConstraints(const MultibodyModel& model, MultibodyWorkspace& ws,
                         const Eigen::Ref<const Eigen::VectorXd>& q, const std::vector<PoseConstraint>& constraints,
                         Eigen::Ref<Eigen::VectorXd> residual, Eigen::Ref<Eigen::MatrixXd> jacobian) {
  const int nv = model.nv();
  // Scratch for one 3 x nv Jacobian, on the stack up to 64 dofs (no heap allocation for the robots of ROME).
  constexpr int kMaxStackDofs = 64;
  Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, kMaxStackDofs> J3(3, nv), J_com(3, nv);
  Eigen::Vector3d com = Eigen::Vector3d::Zero();
  bool com_done = false;  // the COM and its Jacobian are computed once, on the first COM row
  for (std::size_t i = 0; i < constraints.size(); ++i) {
    const PoseConstraint& c = constraints[i];
    const Eigen::Index r = static_cast<Eigen::Index>(i);
    switch (c.kind) {
      case PoseConstraint::Kind::kPoint:
        residual[r] = CalcPointPosition(model, ws, q, c.body, c.p_link)[c.axis] - c.target;
        CalcPointJacobian(model, ws, q, c.body, c.p_link, J3);
        jacobian.row(r) = J3.row(c.axis);
        break;
      case PoseConstraint::Kind::kCom:
        if (!com_done) {
          com = CalcComPosition(model, ws, q);
          CalcComJacobian(model, ws, q, J_com);
          com_done = true;
        }
        residual[r] = com[c.axis] - c.target;
        jacobian.row(r) = J_com.row(c.axis);
        break;
      case PoseConstraint::Kind::kCoordinate:
        residual[r] = q[c.coordinate] - c.target;
        jacobian.row(r).setZero();
        if (!model.has_quaternion_base()) {
          jacobian(r, c.coordinate) = 1.0;
        } else if (c.coordinate >= 7) {
          jacobian(r, c.coordinate - 1) = 1.0;  // joint coordinate k is velocity k - 1 after the 7-number base
        } else {  // the base position: dp/dt = R v_B (free_flyer.h); ValidatePoseConstraints refuses quaternion entries
          const Eigen::Quaterniond R(q[3], q[4], q[5], q[6]);
          jacobian.block<1, 3>(r, 0) = R.normalized().toRotationMatrix().row(c.coordinate);
        }
        break;
      case PoseConstraint::Kind::kLoopClosure: {
        const LoopClosureInfo& lc = model.loop_closures()[c.loop_closure];
        const Eigen::Vector3d d = CalcPointPosition(model, ws, q, lc.body_a, lc.point_a) -
                                  CalcPointPosition(model, ws, q, lc.body_b, lc.point_b);
        const double length = d.norm();
        residual[r] = length - lc.distance_m - c.target;
        CalcPointJacobian(model, ws, q, lc.body_a, lc.point_a, J3);
        jacobian.row(r) = (d / length).transpose() * J3;
        CalcPointJacobian(model, ws, q, lc.body_b, lc.point_b, J3);
        jacobian.row(r) -= (d / length).transpose() * J3;
        break;
      }
    }
  }
}

namespace {

// One Newton step of SolvePose inside the joint limits: the minimum-norm step with every coordinate that sits on a
// limit and would move beyond it frozen (its column of C zeroed), then clamped to the limits. Columns are velocities:
// joint coordinate k of a quaternion-base model is velocity k - 1, and the base's twist has no limits.
void BoundedNewtonStep(const MultibodyModel& model, const Eigen::MatrixXd& C, const Eigen::VectorXd& c,
                       Eigen::VectorXd& q) {
  const Eigen::VectorXd &lo = model.position_lower_limits(), &hi = model.position_upper_limits();
  q = q.cwiseMax(lo).cwiseMin(hi);
  Eigen::MatrixXd Cf = C;
  Eigen::VectorXd dv = -Cf.completeOrthogonalDecomposition().solve(c);
  for (Eigen::Index pass = 0; pass < dv.size(); ++pass) {
    bool frozen = false;
    for (Eigen::Index i = 0; i < dv.size(); ++i) {
      const int k = model.PositionIndexOfVelocity(static_cast<int>(i));
      if (k >= 0 && Cf.col(i).squaredNorm() > 0 && ((q[k] >= hi[k] && dv[i] > 0) || (q[k] <= lo[k] && dv[i] < 0))) {
        Cf.col(i).setZero();
        frozen = true;
      }
    }
    if (!frozen) break;
    dv = -Cf.completeOrthogonalDecomposition().solve(c);
  }
  Eigen::VectorXd next(q.size());
  model.Integrate(q, dv, 1.0, next);
  q = next.cwiseMax(lo).cwiseMin(hi);
}

}  // namespace

Eigen::VectorXd SolvePose(const MultibodyModel& model, MultibodyWorkspace& ws, const Eigen::VectorXd& q0,
                          const std::vector<PoseConstraint>& constraints, const PoseSolverOptions& options) {
  const std::string who = "SolvePose (robot '" + model.name() + "'): ";
  if (q0.size() != model.nq())
    throw std::invalid_argument(who + "q0 has size " + std::to_string(q0.size()) +
                                ", the model has nq = " + std::to_string(model.nq()));
  if (!q0.allFinite()) throw std::invalid_argument(who + "q0 is not finite");
  if (options.max_iterations < 0 || !(options.tolerance > 0))
    throw std::invalid_argument(who + "needs max_iterations >= 0 and tolerance > 0, got " +
                                std::to_string(options.max_iterations) + " and " + std::to_string(options.tolerance));
  ValidatePoseConstraints(model, constraints);
  const Eigen::Index m = static_cast<Eigen::Index>(constraints.size());
  Eigen::VectorXd q = q0, c(m);
  Eigen::MatrixXd C(m, model.nv());
  for (int it = 0;; ++it) {
    CalcPoseConstraints(model, ws, q, constraints, c, C);
    if (c.norm() < options.tolerance) return q;
    if (it == options.max_iterations || !c.allFinite()) break;
    if (options.respect_joint_limits) {
      BoundedNewtonStep(model, C, c, q);
    } else {
      const Eigen::VectorXd dv = -C.completeOrthogonalDecomposition().solve(c);
      Eigen::VectorXd next(q.size());
      model.Integrate(q, dv, 1.0, next);  // q + dv, the base quaternion by its exponential
      q = next;
    }
  }
  Eigen::Index worst = 0;
  if (c.allFinite()) c.cwiseAbs().maxCoeff(&worst);
  std::ostringstream s;
  s << who << "Newton did not converge in " << options.max_iterations << " steps: residual norm " << c.norm()
    << " (tolerance " << options.tolerance << "), largest residual " << c[worst] << " in constraint " << worst << " ("
    << DescribePoseConstraint(model, constraints[static_cast<std::size_t>(worst)]) << ", target "
    << constraints[static_cast<std::size_t>(worst)].target << "); the pose is probably out of reach"
    << (options.respect_joint_limits ? " within the joint limits" : "") << " or the constraints contradict each other";
  throw std::runtime_error(s.str());
}

}  // namespace rome
