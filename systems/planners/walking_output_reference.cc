#include "systems/planners/walking_output_reference.h"

#include <Eigen/LU>

namespace rome {
namespace {

Eigen::Vector2d Foothold(const WalkingPlanSegment& s, int foot) {
  return foot == 0 ? s.left_foothold : s.right_foothold;
}

bool Swings(const WalkingPlanSegment& s, int foot) {
  return (foot == 0 && s.domain == WalkingDomain::kRightStance) ||
         (foot == 1 && s.domain == WalkingDomain::kLeftStance);
}

// Quintic h(τ), τ ∈ [0, T]: h(0) = 0, ḣ(0) = 0, h(T/2) = apex, ḣ(T/2) = 0, h(T) = 0, ḣ(T) = −v_td.
Eigen::Matrix<double, 6, 1> HeightCoefficients(double T, double apex, double v_td) {
  Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> b;
  const double ts[3] = {0.0, 0.5 * T, T};
  for (int k = 0; k < 3; ++k) {
    for (int i = 0; i < 6; ++i) {
      A(2 * k, i) = std::pow(ts[k], i);
      A(2 * k + 1, i) = i == 0 ? 0.0 : i * std::pow(ts[k], i - 1);
    }
  }
  b << 0.0, 0.0, apex, 0.0, 0.0, -v_td;
  return A.partialPivLu().solve(b);
}

}  // namespace

WalkingOutputReference::WalkingOutputReference(std::string name, WalkingPlan plan, SwingFootTrajectoryParams params)
    : LeafSystem(std::move(name)), plan_(std::move(plan)), params_(params) {
  if (plan_.segments().empty()) ThrowError("the walking plan is empty");
  if (!(params_.apex_height_m > 0.0))
    ThrowError("parameter apex_height_m must be > 0, got " + std::to_string(params_.apex_height_m));
  // > 0: after T_SSP a late foot keeps descending at this speed; at 0 it would hover on the ground and never land.
  if (!(params_.touchdown_velocity_mps > 0.0))
    ThrowError("parameter touchdown_velocity_mps must be > 0, got " + std::to_string(params_.touchdown_velocity_mps));
  if (!(params_.pitch_max_rad >= 0.0 && params_.pitch_max_rad < 1.0))
    ThrowError("parameter pitch_max_rad must be in [0, 1) rad, got " + std::to_string(params_.pitch_max_rad));
  const int com = DeclareInputPort("com", 9);
  DeclareOutputPort(
      "desired", 3 * kNumOutputs,
      [this, com](const LeafContext& c, Eigen::VectorXd* y) {
        const Eigen::VectorXd& r = EvalInput(c, com);
        constexpr int n = kNumOutputs;
        y->setZero();
        for (int i = 0; i < 3; ++i) {
          (*y)[i] = r[i];
          (*y)[n + i] = r[3 + i];
          (*y)[2 * n + i] = r[6 + i];
        }
        Eigen::Vector3d p, v, a;
        for (int foot = 0; foot < 2; ++foot) {
          SwingFoot(foot, c.time(), p, v, a);
          const int o = 6 + 6 * foot;
          y->segment<3>(o) = p;
          y->segment<3>(n + o) = v;
          y->segment<3>(2 * n + o) = a;
          double th = 0, thd = 0, thdd = 0;
          SwingFootPitch(foot, c.time(), &th, &thd, &thdd);
          (*y)[o + 4] = th;  // rotation vector (0, θ, 0): a pure pitch, whose rate is the world ω_y
          (*y)[n + o + 4] = thd;
          (*y)[2 * n + o + 4] = thdd;
        }
      },
      Feedthrough::All());
}

void WalkingOutputReference::SwingFoot(int foot, double t, Eigen::Ref<Eigen::Vector3d> p, Eigen::Ref<Eigen::Vector3d> v,
                                       Eigen::Ref<Eigen::Vector3d> a) const {
  const auto& segs = plan_.segments();
  const size_t i = plan_.SegmentIndexAt(t);
  v.setZero();
  a.setZero();
  const double ankle = params_.ankle_height_m;
  // The swing this instant belongs to: the current segment, or the previous one during a late touchdown.
  const WalkingPlanSegment* swing = nullptr;
  size_t si = i;
  if (Swings(segs[i], foot)) {
    swing = &segs[i];
  } else if (i > 0 && Swings(segs[i - 1], foot)) {
    swing = &segs[i - 1];
    si = i - 1;
  }
  if (swing == nullptr) {
    p << Foothold(segs[i], foot), ankle;
    return;
  }
  const Eigen::Vector2d start = si > 0 ? Foothold(segs[si - 1], foot) : Foothold(*swing, foot);
  const Eigen::Vector2d end = Foothold(*swing, foot);
  const double T = swing->duration, tau = t - swing->start_time;
  if (tau >= T) {  // late touchdown: keep descending at the touchdown velocity
    const double vz = params_.touchdown_velocity_mps;
    p << end, ankle - vz * (tau - T);
    v.z() = -vz;
    return;
  }
  const double s = std::max(0.0, tau) / T;
  const double s2 = s * s, s3 = s2 * s;
  const double blend = s3 * (10.0 - 15.0 * s + 6.0 * s2);
  const double dblend = s2 * (30.0 - 60.0 * s + 30.0 * s2) / T;
  const double ddblend = s * (60.0 - 180.0 * s + 120.0 * s2) / (T * T);
  const Eigen::Vector2d d = end - start;
  p.head<2>() = start + blend * d;
  v.head<2>() = dblend * d;
  a.head<2>() = ddblend * d;
  const Eigen::Matrix<double, 6, 1> c = HeightCoefficients(T, params_.apex_height_m, params_.touchdown_velocity_mps);
  const double x = std::max(0.0, tau);
  double h = 0, hd = 0, hdd = 0;
  for (int k = 0; k < 6; ++k) {
    h += c[k] * std::pow(x, k);
    if (k >= 1) hd += k * c[k] * std::pow(x, k - 1);
    if (k >= 2) hdd += k * (k - 1) * c[k] * std::pow(x, k - 2);
  }
  p.z() = ankle + h;
  v.z() = hd;
  a.z() = hdd;
}

void WalkingOutputReference::SwingFootPitch(int foot, double t, double* pitch, double* rate,
                                            double* acceleration) const {
  Eigen::Vector3d p, v, a;
  SwingFoot(foot, t, p, v, a);
  const double k = params_.pitch_max_rad / params_.apex_height_m;
  // Flat on its foothold and during a late touchdown's descent below the standing height.
  const bool lifted = p.z() > params_.ankle_height_m;
  *pitch = lifted ? k * (p.z() - params_.ankle_height_m) : 0.0;
  *rate = lifted ? k * v.z() : 0.0;
  *acceleration = lifted ? k * a.z() : 0.0;
}

}  // namespace rome
