#include "systems/rom/cassie_leg_stiffness.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include <Eigen/Dense>

#include "systems/multibody/multibody_kinematics.h"
#include "systems/multibody/pose_constraints.h"

namespace rome {
namespace {

std::string Where(const MultibodyModel& model, const std::string& side) {
  return "CassieVirtualLeg (model '" + model.name() + "', leg '" + side + "')";
}

}  // namespace

CassieVirtualLeg::CassieVirtualLeg(const MultibodyModel& model, std::string side)
    : model_(&model), side_(std::move(side)) {
  if (side_ != "left" && side_ != "right") {
    throw std::invalid_argument(Where(model, side_) + ": side must be 'left' or 'right'");
  }
  auto joint = [&](const std::string& suffix) {
    const std::string name = side_ + "_" + suffix;
    if (!model.HasJoint(name)) throw std::invalid_argument(Where(model, side_) + ": no joint '" + name + "'");
    return model.VelocityIndex(name);
  };
  knee_ = joint("knee");
  shin_ = joint("shin_spring");
  tarsus_ = joint("tarsus");
  heel_ = joint("heel_spring");
  auto frame = [&](const std::string& link, int* body, Eigen::Vector3d* origin) {
    if (!model.HasFrame(link)) throw std::invalid_argument(Where(model, side_) + ": no link '" + link + "'");
    const MultibodyFrame& f = model.Frame(link);
    *body = f.body;
    *origin = f.X_body_frame.translation();
  };
  frame(side_ + "_hip_pitch", &hip_body_, &p_hip_link_);
  frame(side_ + "_foot", &foot_body_, &p_foot_link_);
  const std::string loop = side_ + "_achilles";
  for (int i = 0; i < model.num_loop_closures(); ++i) {
    if (model.loop_closures()[i].name == loop) loop_ = i;
  }
  if (loop_ < 0) throw std::invalid_argument(Where(model, side_) + ": no loop closure '" + loop + "'");
  k_shin_ = model.spring_stiffness()(shin_);
  k_heel_ = model.spring_stiffness()(heel_);
  d_shin_ = model.spring_damping()(shin_);
  d_heel_ = model.spring_damping()(heel_);
  if (!(k_shin_ > 0.0 && k_heel_ > 0.0)) {
    std::ostringstream msg;
    msg << Where(model, side_) << ": shin/heel spring stiffness " << k_shin_ << "/" << k_heel_
        << " N m/rad must be positive (sidecar 'springs')";
    throw std::invalid_argument(msg.str());
  }
  ws_ = std::make_unique<MultibodyWorkspace>(model);
}

CassieVirtualLeg::CassieVirtualLeg(const CassieVirtualLeg& other)
    : model_(other.model_),
      side_(other.side_),
      knee_(other.knee_),
      shin_(other.shin_),
      tarsus_(other.tarsus_),
      heel_(other.heel_),
      loop_(other.loop_),
      hip_body_(other.hip_body_),
      foot_body_(other.foot_body_),
      p_hip_link_(other.p_hip_link_),
      p_foot_link_(other.p_foot_link_),
      k_shin_(other.k_shin_),
      k_heel_(other.k_heel_),
      d_shin_(other.d_shin_),
      d_heel_(other.d_heel_),
      ws_(std::make_unique<MultibodyWorkspace>(*other.model_)) {}

CassieVirtualLeg::~CassieVirtualLeg() = default;

Eigen::VectorXd CassieVirtualLeg::LegConfiguration(double q_knee) const {
  const MultibodyModel& model = *model_;
  Eigen::VectorXd q = Eigen::VectorXd::Zero(model.nq());
  if (model.num_base_dofs() >= 3) q(model.is_planar() ? 1 : 2) = 1.0;  // pelvis 1 m up (irrelevant)
  q(knee_) = q_knee;
  // Start from the rigid rule q_knee + q_tarsus = 13 deg (robots.md) and close the rod by Newton on the tarsus.
  q(tarsus_) = 13.0 * M_PI / 180.0 - q_knee;
  const std::vector<PoseConstraint> closure = {PoseConstraint::LoopClosure(loop_)};
  Eigen::VectorXd r(1);
  Eigen::MatrixXd C(1, model.nv());
  for (int it = 0; it < 50; ++it) {
    CalcPoseConstraints(model, *ws_, q, closure, r, C);
    if (std::abs(r(0)) < 1e-13) return q;
    if (std::abs(C(0, tarsus_)) < 1e-9) break;
    q(tarsus_) -= r(0) / C(0, tarsus_);
  }
  std::ostringstream msg;
  msg << Where(model, side_) << ": the achilles rod does not close at q_knee = " << q_knee << " rad (residual " << r(0)
      << " m)";
  throw std::runtime_error(msg.str());
}

double CassieVirtualLeg::TarsusAngle(double q_knee) const { return LegConfiguration(q_knee)(tarsus_); }

double CassieVirtualLeg::RealLength(const Eigen::Ref<const Eigen::VectorXd>& q) const {
  if (q.size() != model_->nq()) {
    throw std::invalid_argument(Where(*model_, side_) + "::RealLength: q has size " + std::to_string(q.size()) +
                                ", expected " + std::to_string(model_->nq()));
  }
  const Eigen::Vector3d p_hip = CalcPointPosition(*model_, *ws_, q, hip_body_, p_hip_link_);
  const Eigen::Vector3d p_toe = CalcPointPosition(*model_, *ws_, q, foot_body_, p_foot_link_);
  return (p_toe - p_hip).norm();
}

double CassieVirtualLeg::Length(double q_knee) const { return RealLength(LegConfiguration(q_knee)); }

namespace {

// Reduced Jacobian columns of p_toe − p_hip (world x, z) for the actuated/spring joints, the tarsus eliminated
// through the closure (Eq. 8-11).
struct ReducedJacobian {
  Eigen::Vector2d knee, shin, heel;
  Eigen::Vector2d axis;        // unit leg axis in the sagittal plane (x, z)
  double length_jacobian = 0;  // dL_r/dq_knee with the 3D distance (the leg has a small lateral offset)
};

ReducedJacobian CalcReducedJacobian(const MultibodyModel& model, MultibodyWorkspace& ws, const Eigen::VectorXd& q,
                                    int loop, int hip_body, const Eigen::Vector3d& p_hip_link, int foot_body,
                                    const Eigen::Vector3d& p_foot_link, int knee, int shin, int tarsus, int heel) {
  Eigen::MatrixXd J_toe(3, model.nv()), J_hip(3, model.nv()), C(1, model.nv());
  Eigen::VectorXd r(1);
  CalcPointJacobian(model, ws, q, foot_body, p_foot_link, J_toe);
  CalcPointJacobian(model, ws, q, hip_body, p_hip_link, J_hip);
  CalcPoseConstraints(model, ws, q, {PoseConstraint::LoopClosure(loop)}, r, C);
  const Eigen::MatrixXd J = J_toe - J_hip;
  auto column = [&](int j) {
    const Eigen::Vector3d c = J.col(j) - J.col(tarsus) * (C(0, j) / C(0, tarsus));
    return Eigen::Vector2d(c(0), c(2));
  };
  ReducedJacobian out;
  out.knee = column(knee);
  out.shin = column(shin);
  out.heel = column(heel);
  const Eigen::Vector3d d =
      CalcPointPosition(model, ws, q, foot_body, p_foot_link) - CalcPointPosition(model, ws, q, hip_body, p_hip_link);
  out.axis = Eigen::Vector2d(d(0), d(2)).normalized();
  const Eigen::Vector3d d_knee = J.col(knee) - J.col(tarsus) * (C(0, knee) / C(0, tarsus));
  out.length_jacobian = d.normalized().dot(d_knee);
  return out;
}

}  // namespace

double CassieVirtualLeg::LengthJacobian(double q_knee) const {
  const Eigen::VectorXd q = LegConfiguration(q_knee);
  const ReducedJacobian J = CalcReducedJacobian(*model_, *ws_, q, loop_, hip_body_, p_hip_link_, foot_body_,
                                                p_foot_link_, knee_, shin_, tarsus_, heel_);
  // L = |p_toe − p_hip|: dL/dq_knee = (p_toe − p_hip)ᵀ/L ∂(p_toe − p_hip)/∂q_knee.
  return J.length_jacobian;
}

double CassieVirtualLeg::KneeAngle(double L) const {
  const double lo = model_->position_lower_limits()(knee_), hi = model_->position_upper_limits()(knee_);
  const double L_lo = Length(lo), L_hi = Length(hi);
  const double slack = 1e-12;  // the range ends themselves are reachable despite rounding
  if (!(L >= std::min(L_lo, L_hi) - slack && L <= std::max(L_lo, L_hi) + slack)) {
    std::ostringstream msg;
    msg << Where(*model_, side_) << "::KneeAngle: leg length L = " << L << " m is outside [" << std::min(L_lo, L_hi)
        << ", " << std::max(L_lo, L_hi) << "] m reachable within the knee range";
    throw std::domain_error(msg.str());
  }
  double q = 0.5 * (lo + hi);
  for (int it = 0; it < 100; ++it) {
    const double r = Length(q) - L;
    if (std::abs(r) < 1e-13) break;
    q = std::clamp(q - r / LengthJacobian(q), lo, hi);
  }
  return q;
}

Eigen::Matrix2d CassieVirtualLeg::Compliance(double q_knee, bool damping) const {
  const Eigen::VectorXd q = LegConfiguration(q_knee);
  const ReducedJacobian J = CalcReducedJacobian(*model_, *ws_, q, loop_, hip_body_, p_hip_link_, foot_body_,
                                                p_foot_link_, knee_, shin_, tarsus_, heel_);
  // Eq. (12) with K_A = diag(∞, k_shin, k_heel, ∞): C = J_A K_A⁻¹ J_Aᵀ.
  const double a = damping ? d_shin_ : k_shin_, b = damping ? d_heel_ : k_heel_;
  return J.shin * J.shin.transpose() / a + J.heel * J.heel.transpose() / b;
}

Eigen::Matrix2d CassieVirtualLeg::CartesianStiffness(double q_knee) const {
  return Compliance(q_knee, false).inverse();
}

double CassieVirtualLeg::AlongLeg(double q_knee, bool damping) const {
  const Eigen::VectorXd q = LegConfiguration(q_knee);
  const ReducedJacobian J = CalcReducedJacobian(*model_, *ws_, q, loop_, hip_body_, p_hip_link_, foot_body_,
                                                p_foot_link_, knee_, shin_, tarsus_, heel_);
  const double a = damping ? d_shin_ : k_shin_, b = damping ? d_heel_ : k_heel_;
  const Eigen::Matrix2d C = J.shin * J.shin.transpose() / a + J.heel * J.heel.transpose() / b;
  return J.axis.dot(C.inverse() * J.axis);  // uᵀ K_leg u: tangential displacement blocked
}

double CassieVirtualLeg::Stiffness(double q_knee) const { return AlongLeg(q_knee, false); }

double CassieVirtualLeg::Damping(double q_knee) const {
  if (!(d_shin_ > 0.0 && d_heel_ > 0.0)) return 0.0;
  return AlongLeg(q_knee, true);
}

LegStiffnessIdentification IdentifyCassieLegStiffness(const CassieVirtualLeg& leg,
                                                      const LegStiffnessIdentificationOptions& options) {
  if (!(options.min_length > 0.0 && options.max_length > options.min_length) || options.num_samples < 5) {
    std::ostringstream msg;
    msg << "IdentifyCassieLegStiffness: need 0 < min_length (" << options.min_length << " m) < max_length ("
        << options.max_length << " m) and num_samples (" << options.num_samples << ") >= 5";
    throw std::invalid_argument(msg.str());
  }
  const int n = options.num_samples;
  LegStiffnessIdentification out;
  out.lengths = Eigen::VectorXd::LinSpaced(n, options.min_length, options.max_length);
  out.stiffness.resize(n);
  out.damping.resize(n);
  Eigen::MatrixXd A(n, 4);
  for (int i = 0; i < n; ++i) {
    const double L = out.lengths(i);
    const double q_knee = leg.KneeAngle(L);
    out.stiffness(i) = leg.Stiffness(q_knee);
    out.damping(i) = leg.Damping(q_knee);
    A.row(i) << 1.0, L, L * L, L * L * L * L;  // footnote 1: no cubic term
  }
  const auto qr = A.colPivHouseholderQr();
  const Eigen::Vector4d ck = qr.solve(out.stiffness), cd = qr.solve(out.damping);
  out.leg.stiffness = {ck(0), ck(1), ck(2), ck(3)};
  out.leg.damping = {cd(0), cd(1), cd(2), cd(3)};
  for (int i = 0; i < n; ++i) {
    const double L = out.lengths(i);
    out.max_relative_fit_error = std::max(
        out.max_relative_fit_error, std::abs(out.leg.stiffness.Evaluate(L) - out.stiffness(i)) / out.stiffness(i));
    if (out.damping(i) > 0.0) {
      out.max_relative_fit_error =
          std::max(out.max_relative_fit_error, std::abs(out.leg.damping.Evaluate(L) - out.damping(i)) / out.damping(i));
    }
  }
  return out;
}

SpringMassParams CassieSpringMassParams(const MultibodyModel& model, LegStiffnessVariant variant) {
  SpringMassParams p;
  p.mass = model.total_mass();
  p.n_legs = 2;
  p.leg = variant == LegStiffnessVariant::kPublished ? PublishedLegStiffness()
                                                     : IdentifyCassieLegStiffness(CassieVirtualLeg(model, "left")).leg;
  return p;
}

}  // namespace rome
