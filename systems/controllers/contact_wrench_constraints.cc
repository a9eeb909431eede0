#include "systems/controllers/contact_wrench_constraints.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "systems/multibody/multibody_kinematics.h"

namespace rome {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
}

ContactWrenchConstraints::ContactWrenchConstraints(const MultibodyModel& model, int contact,
                                                   const ContactWrenchParams& params, const std::string& system)
    : contact_(contact),
      planar_(model.is_planar()),
      min_normal_(params.min_normal_force_N),
      offset_(params.friction_cone_offset_N),
      yaw_(params.yaw_moment_coefficient_m),
      cwc_(params.corner_wrench_cone) {
  const ContactInfo& info = model.contacts().at(contact);
  num_force_rows_ = info.num_rows;
  const double mu = params.friction_coefficient >= 0.0 ? params.friction_coefficient : info.friction_coefficient;
  mu_ = params.friction_margin * mu;
  if (!(mu_ >= 0.0) || !std::isfinite(mu_))
    throw std::invalid_argument("system '" + system + "': contact '" + info.name + "' has friction coefficient " +
                                std::to_string(mu_));
  mu_corner_ = params.corner_cone_friction_coefficient >= 0.0 ? params.corner_cone_friction_coefficient : mu_;
  if (!std::isfinite(mu_corner_))
    throw std::invalid_argument("system '" + system + "': contact '" + info.name +
                                "': corner_cone_friction_coefficient = " + std::to_string(mu_corner_) +
                                " is outside [0, inf)");
  // Sole extent relative to the frame origin, in the link (foot) frame.
  x_min_ = y_min_ = kInf;
  x_max_ = y_max_ = -kInf;
  for (const Eigen::Vector3d& p : info.points) {
    const Eigen::Vector3d d = p - info.frame_origin;
    x_min_ = std::min(x_min_, d.x()), x_max_ = std::max(x_max_, d.x());
    y_min_ = std::min(y_min_, d.y()), y_max_ = std::max(y_max_, d.y());
  }
  // The yaw rows' half-sizes: the whole sole's less corner_cone_yaw_margin_m, else the CoP rows' (below).
  const double yaw_margin = params.corner_cone_yaw_margin_m;
  if (!std::isfinite(yaw_margin))
    throw std::invalid_argument("system '" + system + "': contact '" + info.name +
                                "': corner_cone_yaw_margin_m = " + std::to_string(yaw_margin) + " is not finite");
  if (yaw_margin >= 0.0) {
    yaw_x_ = std::max(0.0, 0.5 * (x_max_ - x_min_) - yaw_margin);
    yaw_y_ = std::max(0.0, 0.5 * (y_max_ - y_min_) - yaw_margin);
  }
  // The CoP rows keep the centre of pressure cop_margin_m inside the sole's edges (never past its middle).
  const double mx = std::clamp(params.cop_margin_m, 0.0, 0.5 * (x_max_ - x_min_)),
               my = std::clamp(params.cop_margin_m, 0.0, 0.5 * (y_max_ - y_min_));
  if (info.type != ContactType::kPoint) x_min_ += mx, x_max_ -= mx, y_min_ += my, y_max_ -= my;
  if (yaw_margin < 0.0) yaw_x_ = x_max_, yaw_y_ = y_max_;
  if (planar_) {
    normal_ = num_force_rows_ - 1;
    cop_ = info.type != ContactType::kPoint;
    kinds_ = {RowKind::kNormal, RowKind::kFriction, RowKind::kFriction};
    if (cop_) kinds_.insert(kinds_.end(), {RowKind::kCenterOfPressure, RowKind::kCenterOfPressure});
  } else if (info.type == ContactType::kPoint) {
    normal_ = 2;
    if (params.inscribe_pyramid) mu_ /= std::sqrt(2.0);
    kinds_ = {RowKind::kNormal, RowKind::kFriction, RowKind::kFriction, RowKind::kFriction, RowKind::kFriction};
  } else if (info.type == ContactType::kFlat) {
    flat3d_ = cop_ = true;
    normal_ = 5;
    if (params.inscribe_pyramid) mu_ /= std::sqrt(2.0), mu_corner_ /= std::sqrt(2.0);
    kinds_ = {RowKind::kNormal,           RowKind::kFriction,         RowKind::kFriction,
              RowKind::kFriction,         RowKind::kFriction,         RowKind::kCenterOfPressure,
              RowKind::kCenterOfPressure, RowKind::kCenterOfPressure, RowKind::kCenterOfPressure};
    if (cwc_ && (std::abs(x_max_ + x_min_) > 1e-9 || std::abs(y_max_ + y_min_) > 1e-9))
      throw std::invalid_argument("system '" + system + "': contact '" + info.name +
                                  "': corner_wrench_cone needs a sole centred on the contact frame origin");
    if (cwc_)
      kinds_.insert(kinds_.end(), 8, RowKind::kYawMoment);
    else if (yaw_ >= 0.0)
      kinds_.insert(kinds_.end(), {RowKind::kYawMoment, RowKind::kYawMoment});
  } else if (info.type == ContactType::kLine && info.points.size() == 2) {
    line3d_ = cop_ = true;
    normal_ = 2;  // f_0z; the total F_z is f_0z + f_1z
    if (params.inscribe_pyramid) mu_ /= std::sqrt(2.0);
    kinds_ = {RowKind::kNormal,   RowKind::kFriction,         RowKind::kFriction,        RowKind::kFriction,
              RowKind::kFriction, RowKind::kCenterOfPressure, RowKind::kCenterOfPressure};
  } else {
    throw std::invalid_argument(
        "system '" + system + "': contact '" + info.name + "' of robot '" + model.name() + "' is a " +
        ToString(info.type) + " contact with " + std::to_string(info.points.size()) +
        " points on a 3D model; contact-wrench rows exist for point, two-point line and flat contacts in 3D");
  }
}

void ContactWrenchConstraints::Fill(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                                    Eigen::Ref<Eigen::MatrixXd> G, Eigen::Ref<Eigen::VectorXd> l,
                                    Eigen::Ref<Eigen::VectorXd> u) const {
  G.setZero();
  int r = 0;
  if (line3d_) {
    // Rows over F = [f_0; a; b] with f_1 = a n1 + b n2 (n1, n2 as in contact_dynamics.h: n2 = z × d normalised,
    // n1 = d × n2, d the unit toe-heel direction in the world); the total force is f = f_0 + f_1.
    const Eigen::Vector3d d =
        (CalcContactPointPosition(model, ws, q, contact_, 1) - CalcContactPointPosition(model, ws, q, contact_, 0))
            .normalized();
    Eigen::Vector3d n2 = Eigen::Vector3d::UnitZ().cross(d);
    if (n2.norm() < 1e-6) n2 = Eigen::Vector3d::UnitX().cross(d);
    n2.normalize();
    const Eigen::Vector3d n1 = d.cross(n2);
    Eigen::Matrix<double, 3, 5> total;  // f = total · F
    total << Eigen::Matrix3d::Identity(), n1, n2;
    G.row(r) = total.row(2), l[r] = min_normal_, u[r] = kInf, ++r;  // f_z ≥ F_min
    for (int k = 0; k < 4; ++k) {  // ±f_x − μ (f_z − F_0) ≤ 0, ±f_y − μ (f_z − F_0) ≤ 0
      G.row(r) = ((k % 2 == 0) ? 1.0 : -1.0) * total.row(k < 2 ? 0 : 1) - mu_ * total.row(2);
      l[r] = -kInf, u[r] = -mu_ * offset_, ++r;
    }
    G(r, 2) = 1.0, l[r] = 0.0, u[r] = kInf, ++r;                       // f_0z ≥ 0 (heel/toe point 0)
    G(r, 3) = n1.z(), G(r, 4) = n2.z(), l[r] = 0.0, u[r] = kInf, ++r;  // f_1z ≥ 0 (point 1)
    return;
  }
  // Unilateral: F_z ≥ F_min.
  G(r, normal_) = 1.0, l[r] = min_normal_, u[r] = kInf, ++r;
  if (planar_) {
    const int fx = normal_ - 1;
    G(r, fx) = 1.0, G(r, normal_) = -mu_, l[r] = -kInf, u[r] = -mu_ * offset_, ++r;  // F_x − μ (F_z − F_0) ≤ 0
    G(r, fx) = 1.0, G(r, normal_) = mu_, l[r] = mu_ * offset_, u[r] = kInf, ++r;     // F_x + μ (F_z − F_0) ≥ 0
    if (cop_) {
      // x_min F_z ≤ −τ_y ≤ x_max F_z, x along world x (planar: the foot's x axis is pitched with the foot; the
      // contact points' world x offsets give the extent at this pose).
      const ContactInfo& info = model.contacts()[contact_];
      const double origin_x = CalcPointPosition(model, ws, q, info.body, info.frame_origin).x();
      double lo = kInf, hi = -kInf;
      for (int p = 0; p < static_cast<int>(info.points.size()); ++p) {
        const double dx = CalcContactPointPosition(model, ws, q, contact_, p).x() - origin_x;
        lo = std::min(lo, dx), hi = std::max(hi, dx);
      }
      G(r, 0) = -1.0, G(r, normal_) = -lo, l[r] = 0.0, u[r] = kInf, ++r;   // −τ_y − x_min F_z ≥ 0
      G(r, 0) = -1.0, G(r, normal_) = -hi, l[r] = -kInf, u[r] = 0.0, ++r;  // −τ_y − x_max F_z ≤ 0
    }
    return;
  }
  const int fx = normal_ - 2, fy = normal_ - 1;
  for (int k = 0; k < 4; ++k) {  // ±F_x − μ (F_z − F_0) ≤ 0, ±F_y − μ (F_z − F_0) ≤ 0
    G(r, k < 2 ? fx : fy) = (k % 2 == 0) ? 1.0 : -1.0;
    G(r, normal_) = -mu_;
    l[r] = -kInf, u[r] = -mu_ * offset_, ++r;
  }
  if (!flat3d_) return;
  // Centre of pressure in the foot frame: τ' = Rᵀ τ, CoP_x = −τ'_y / f_z, CoP_y = τ'_x / f_z (flat ground).
  const Eigen::Matrix3d R = CalcLinkPose(model, ws, q, model.contacts()[contact_].body).linear();
  const Eigen::RowVector3d ex = R.col(0).transpose(), ey = R.col(1).transpose();
  G.block<1, 3>(r, 0) = -ey, G(r, normal_) = -x_max_, l[r] = -kInf, u[r] = 0.0, ++r;  // −τ'_y − x_max f_z ≤ 0
  G.block<1, 3>(r, 0) = -ey, G(r, normal_) = -x_min_, l[r] = 0.0, u[r] = kInf, ++r;   // −τ'_y − x_min f_z ≥ 0
  G.block<1, 3>(r, 0) = ex, G(r, normal_) = -y_max_, l[r] = -kInf, u[r] = 0.0, ++r;   // τ'_x − y_max f_z ≤ 0
  G.block<1, 3>(r, 0) = ex, G(r, normal_) = -y_min_, l[r] = 0.0, u[r] = kInf, ++r;    // τ'_x − y_min f_z ≥ 0
  if (cwc_) {
    // Half-sizes of the sole (after the yaw margin) about the frame origin, its centre (checked at construction).
    // Foot-frame rows over F = [τ; f]: τ' = Rᵀ τ, f' = Rᵀ f, with f'_z taken as f_z (the sole is flat on level
    // ground, as the CoP rows assume).
    const double X = yaw_x_, Y = yaw_y_, mu = mu_corner_;
    Eigen::Matrix<double, 1, 6> tx = Eigen::Matrix<double, 1, 6>::Zero(), ty = tx, tz = tx, fx = tx, fy = tx, fz = tx;
    tx.head<3>() = ex;
    ty.head<3>() = ey;
    tz.head<3>() = R.col(2).transpose();
    fx.tail<3>() = ex;
    fy.tail<3>() = ey;
    fz(normal_) = 1.0;
    for (const double s1 : {1.0, -1.0})
      for (const double s2 : {1.0, -1.0}) {
        // τ_z + μ(X+Y) f_z − s1 (Y f_x − μ τ_x) − s2 (X f_y − μ τ_y) ≥ 0
        G.row(r) = tz + mu * (X + Y) * fz - s1 * (Y * fx - mu * tx) - s2 * (X * fy - mu * ty), l[r] = 0.0, u[r] = kInf,
        ++r;
        // −τ_z + μ(X+Y) f_z − s1 (Y f_x + μ τ_x) − s2 (X f_y + μ τ_y) ≥ 0
        G.row(r) = -tz + mu * (X + Y) * fz - s1 * (Y * fx + mu * tx) - s2 * (X * fy + mu * ty), l[r] = 0.0, u[r] = kInf,
        ++r;
      }
  } else if (yaw_ >= 0.0) {
    const Eigen::RowVector3d ez = R.col(2).transpose();
    G.block<1, 3>(r, 0) = ez, G(r, normal_) = -yaw_, l[r] = -kInf, u[r] = 0.0, ++r;  // τ'_z − c f_z ≤ 0
    G.block<1, 3>(r, 0) = ez, G(r, normal_) = yaw_, l[r] = 0.0, u[r] = kInf, ++r;    // τ'_z + c f_z ≥ 0
  }
}

}  // namespace rome
