#include "systems/multibody/contact_dynamics.h"

#include "systems/multibody/free_flyer_kernels.h"

#include <Eigen/Dense>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace rome {

namespace {

void CheckActive(const MultibodyModel& model, ContactSet active) {
  const int nc = model.num_contacts();
  if (nc < 64 && (active >> nc) != 0)
    throw std::invalid_argument("robot '" + model.name() + "': contact set has bits beyond its " + std::to_string(nc) +
                                " contacts");
}

void CheckContact(const MultibodyModel& model, int contact) {
  if (contact < 0 || contact >= model.num_contacts())
    throw std::invalid_argument("robot '" + model.name() + "': contact index " + std::to_string(contact) +
                                " out of range");
}

// Unit vectors perpendicular to the (world) line direction d: n1 (most vertical), n2.
void LineNormals(const Eigen::Vector3d& d, Eigen::Vector3d& n1, Eigen::Vector3d& n2) {
  n2 = Eigen::Vector3d::UnitZ().cross(d);
  if (n2.norm() < 1e-6) n2 = Eigen::Vector3d::UnitX().cross(d);
  n2.normalize();
  n1 = d.cross(n2);
}

// Rows row0 .. row0 + R − 1 of ws.J += W J_p, with J_p the 3 x nv Jacobian of the world point p_world fixed on `body`
// (ws.SetPositions done). Only the columns of the body's support are touched.
template <int R>
void AddWeightedPointJacobian(const MultibodyModel& model, MultibodyWorkspace& ws, int body,
                              const Eigen::Vector3d& p_world, const Eigen::Matrix<double, R, 3>& W, int row0) {
  const Eigen::Vector3d r = p_world - ws.reference_point();
  const bool one_joint = ws.free_flyer_as_one_joint();
  for (int m = ws.support_begin[body]; m < ws.support_begin[body + 1]; ++m) {
    const int b = ws.support_body[m];
    if (one_joint && b <= kFreeFlyerRootBody) {  // the base joint's six columns
      ws.J.block<R, 6>(row0, 0).noalias() += W * FreeFlyerPointJacobianColumns(ws, r);
      break;
    }
    const Vector6d& S = ws.S(b);
    const Eigen::Vector3d column = S.tail<3>() + S.head<3>().cross(r);
    ws.J.block<R, 1>(row0, model.body(b).v_index) += W * column;
  }
}

Eigen::Vector3d WorldPoint(const MultibodyWorkspace& ws, int body, const Eigen::Vector3d& p_link) {
  return ws.p_world_link(body) + ws.R_world_link(body) * p_link;
}

// Fills ws.J, ws.phi and (if v) ws.Jdot_qdot. Returns the number of rows.
int FillConstraintRows(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, const VectorRef* v,
                       ContactSet active) {
  const int rows = CountConstraintRows(model, active);  // also checks `active`
  ws.SetPositions(model, q);
  if (v) ws.SetVelocities(model, *v);
  ws.J.topRows(rows).setZero();
  const bool planar = model.is_planar();
  auto J6 = ws.J_point.topRows(6);
  int row = 0;
  for (int c = 0; c < model.num_contacts(); ++c) {
    if (!(active & ContactBit(c))) continue;
    const ContactInfo& info = model.contacts()[c];
    const int body = info.body;
    if (info.type == ContactType::kPoint) {
      const Eigen::Vector3d p = WorldPoint(ws, body, info.points[0]);
      Eigen::Vector3d Jd = Eigen::Vector3d::Zero();
      if (v) Jd = CalcPointJdotQdot(model, ws, q, *v, body, info.points[0]);
      if (planar) {
        Eigen::Matrix<double, 2, 3> W;
        W << 1, 0, 0, 0, 0, 1;  // x and z
        AddWeightedPointJacobian<2>(model, ws, body, p, W, row);
        ws.Jdot_qdot[row] = Jd.x();
        ws.Jdot_qdot[row + 1] = Jd.z();
      } else {
        AddWeightedPointJacobian<3>(model, ws, body, p, Eigen::Matrix3d::Identity(), row);
        ws.Jdot_qdot.segment<3>(row) = Jd;
      }
    } else if (planar) {
      CalcFrameJacobian(model, ws, q, body, info.frame_origin, J6);
      Vector6d Jd = Vector6d::Zero();
      if (v) Jd = CalcFrameJdotQdot(model, ws, q, *v, body, info.frame_origin);
      const int sel[3] = {1, 3, 5};  // omega_y, v_x, v_z
      for (int r = 0; r < 3; ++r) {
        ws.J.row(row + r) = J6.row(sel[r]);
        ws.Jdot_qdot[row + r] = Jd[sel[r]];
      }
    } else if (info.type == ContactType::kLine) {
      AddWeightedPointJacobian<3>(model, ws, body, WorldPoint(ws, body, info.points[0]), Eigen::Matrix3d::Identity(),
                                  row);
      if (v) ws.Jdot_qdot.segment<3>(row) = CalcPointJdotQdot(model, ws, q, *v, body, info.points[0]);
      const Eigen::Vector3d d = (ws.R_world_link(body) * (info.points[1] - info.points[0])).normalized();
      Eigen::Vector3d n1, n2;
      LineNormals(d, n1, n2);
      Eigen::Matrix<double, 2, 3> W;
      W << n1.transpose(), n2.transpose();
      AddWeightedPointJacobian<2>(model, ws, body, WorldPoint(ws, body, info.points[1]), W, row + 3);
      if (v) {
        const Eigen::Vector3d Jd = CalcPointJdotQdot(model, ws, q, *v, body, info.points[1]);
        ws.Jdot_qdot[row + 3] = n1.dot(Jd);
        ws.Jdot_qdot[row + 4] = n2.dot(Jd);
      }
    } else {  // flat, spatial
      CalcFrameJacobian(model, ws, q, body, info.frame_origin, J6);
      ws.J.middleRows(row, 6) = J6;
      if (v) ws.Jdot_qdot.segment<6>(row) = CalcFrameJdotQdot(model, ws, q, *v, body, info.frame_origin);
    }
    ws.phi.segment(row, info.num_rows).setZero();
    if (!v) ws.Jdot_qdot.segment(row, info.num_rows).setZero();
    row += info.num_rows;
  }
  for (const LoopClosureInfo& loop : model.loop_closures()) {
    // phi = |p_a - p_b| - L;  J = u^T (J_a - J_b);
    // Jdot v = u^T (a_a - a_b) + (|ddot|^2 - (u . ddot)^2) / |d|.
    const Eigen::Vector3d pa = CalcPointPosition(model, ws, q, loop.body_a, loop.point_a);
    const Eigen::Vector3d pb = CalcPointPosition(model, ws, q, loop.body_b, loop.point_b);
    const Eigen::Vector3d d = pa - pb;
    const double dist = d.norm();
    if (!(dist > 1e-12))
      throw std::runtime_error("robot '" + model.name() + "': loop closure '" + loop.name +
                               "' has coincident end points");
    const Eigen::Vector3d u = d / dist;
    ws.phi[row] = dist - loop.distance_m;
    AddWeightedPointJacobian<1>(model, ws, loop.body_a, pa, u.transpose(), row);
    AddWeightedPointJacobian<1>(model, ws, loop.body_b, pb, -u.transpose(), row);
    if (v) {
      const Eigen::Vector3d dd = CalcPointVelocity(model, ws, q, *v, loop.body_a, loop.point_a) -
                                 CalcPointVelocity(model, ws, q, *v, loop.body_b, loop.point_b);
      const Eigen::Vector3d ad = CalcPointJdotQdot(model, ws, q, *v, loop.body_a, loop.point_a) -
                                 CalcPointJdotQdot(model, ws, q, *v, loop.body_b, loop.point_b);
      const double ud = u.dot(dd);
      ws.Jdot_qdot[row] = u.dot(ad) + (dd.squaredNorm() - ud * ud) / dist;
    } else {
      ws.Jdot_qdot[row] = 0.0;
    }
    ++row;
  }
  return row;
}

// Lambda = J M^-1 J^T (ws.Lambda) and the Cholesky factor of Lambda + eps I (ws.Lambda_L,
// lower, with a pivot floor). With the tree factor M = L^T D L: Y = J L^-1 D^-1/2 (in ws.JLinv)
// and Lambda = Y Y^T; otherwise ws.Minv_JT = M^-1 J^T and Lambda = J M^-1 J^T.
void FactorDelassus(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, int k,
                    double regularization) {
  auto A = ws.Lambda.topLeftCorner(k, k);
  FactorMassMatrix(model, ws, q);
  if (ws.use_tree_factor) {
    auto Y = ws.JLinv.topRows(k);
    Y = ws.J.topRows(k);
    SolveMassMatrixFactorRows(ws, Y);
    // Lambda = Y D^-1 Y^T, lower triangle (the Cholesky below reads only that).
    const int nv = model.nv();
    for (int i = 0; i < nv; ++i) Y.col(i) *= 1.0 / std::sqrt(ws.D[i]);
    // As a sum of outer products over the columns of Y: the inner loop runs down contiguous columns of Y and A.
    A.setZero();
    const double* y = Y.data();
    const Eigen::Index ld = Y.outerStride();
    double* a = A.data();
    const Eigen::Index lda = A.outerStride();
    for (int c = 0; c < nv; ++c) {
      const double* yc = y + c * ld;
      for (int j = 0; j < k; ++j) {
        const double yj = yc[j];
        if (yj == 0.0) continue;
        double* aj = a + j * lda;
        for (int i = j; i < k; ++i) aj[i] += yc[i] * yj;
      }
    }
    for (int j = 0; j < k; ++j)
      for (int i = j + 1; i < k; ++i) A(j, i) = A(i, j);
  } else {
    auto Z = ws.Minv_JT.leftCols(k);
    Z = ws.J.topRows(k).transpose();
    SolveMassMatrix(model, ws, q, Z);
    A.noalias() = ws.J.topRows(k) * Z;
  }
  double mean_diag = k > 0 ? A.diagonal().mean() : 0.0;
  if (!(mean_diag > 0.0)) mean_diag = 1.0;
  const double eps = regularization * mean_diag;
  const double floor = std::max(eps, 1e-300);
  // Right-looking (column) Cholesky of A + eps I in place, lower triangle: the trailing update runs down contiguous
  // columns. A pivot below the floor (a redundant row) is raised to it.
  auto L = ws.Lambda_L.topLeftCorner(k, k);
  L.triangularView<Eigen::Lower>() = A.triangularView<Eigen::Lower>();
  L.diagonal().array() += eps;
  for (int j = 0; j < k; ++j) {
    const double ljj = std::sqrt(std::max(L(j, j), floor));
    L(j, j) = ljj;
    const int below = k - j - 1;
    if (below == 0) break;
    L.col(j).tail(below) /= ljj;
    for (int c = j + 1; c < k; ++c) L.col(c).tail(k - c) -= L(c, j) * L.col(j).tail(k - c);
  }
}

// x <- (L L^T)^-1 x on the top k entries of x.
void CholeskySolveInPlace(const MultibodyWorkspace& ws, Eigen::Ref<Eigen::VectorXd> x, int k) {
  auto L = ws.Lambda_L.topLeftCorner(k, k);
  for (int i = 0; i < k; ++i) {  // L y = x, by columns
    x[i] /= L(i, i);
    x.segment(i + 1, k - i - 1) -= x[i] * L.col(i).tail(k - i - 1);
  }
  for (int i = k - 1; i >= 0; --i)  // L^T x = y
    x[i] = (x[i] - L.col(i).tail(k - i - 1).dot(x.segment(i + 1, k - i - 1))) / L(i, i);
}

// Solves Lambda x = ws.rhs (top k) into ws.lambda_sol: regularised solve plus iterative
// refinement against the unregularised Lambda, which removes the O(eps) bias when Lambda has
// full rank and leaves redundant (consistent) rows with a bounded solution. The refinement
// contracts by rho ~ eps / lambda_min per step, and the regularised solve's own relative error
// is of the same order, so a first correction of relative size r1 is typically followed by one
// of ~r1^2: when r1 < 3e-8 the second step is skipped (measured, Cassie in double stance:
// 3e-9, then 5e-16). In the worst case the forces keep an error of 3e-8 relative.
constexpr int kRefinementSteps = 2;
void SolveDelassus(MultibodyWorkspace& ws, int k) {
  auto x = ws.lambda_sol.head(k);
  x = ws.rhs.head(k);
  CholeskySolveInPlace(ws, x, k);
  for (int it = 0; it < kRefinementSteps; ++it) {
    auto r = ws.residual.head(k);
    r = ws.rhs.head(k);
    r.noalias() -= ws.Lambda.topLeftCorner(k, k) * x;
    CholeskySolveInPlace(ws, r, k);
    x += r;
    if (k > 0 && r.cwiseAbs().maxCoeff() <= 3e-8 * x.cwiseAbs().maxCoeff()) break;
  }
}

}  // namespace

int CountConstraintRows(const MultibodyModel& model, ContactSet active) {
  CheckActive(model, active);
  int rows = model.num_loop_closures();
  for (int c = 0; c < model.num_contacts(); ++c)
    if (active & ContactBit(c)) rows += model.contacts()[c].num_rows;
  return rows;
}

int CalcConstraintJacobian(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, const VectorRef& v,
                           ContactSet active) {
  return FillConstraintRows(model, ws, q, &v, active);
}

int CalcConstrainedForwardDynamics(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                                   const VectorRef& v, const VectorRef& u, const VectorRef& tau_ext, ContactSet active,
                                   const ConstrainedDynamicsParameters& params, Eigen::Ref<Eigen::VectorXd> qdd,
                                   Eigen::Ref<Eigen::VectorXd> F) {
  if (u.size() != model.nu() || qdd.size() != model.nv() || (tau_ext.size() != 0 && tau_ext.size() != model.nv()))
    throw std::invalid_argument("CalcConstrainedForwardDynamics of robot '" + model.name() +
                                "': u must have size nu = " + std::to_string(model.nu()) +
                                ", qdd and tau_ext size nv = " + std::to_string(model.nv()));
  const int k = FillConstraintRows(model, ws, q, &v, active);
  if (F.size() < k)
    throw std::invalid_argument("CalcConstrainedForwardDynamics of robot '" + model.name() + "': F has size " +
                                std::to_string(F.size()) + " < " + std::to_string(k) + " constraint rows");
  // qdd_free = M^-1 (B u + tau_spring + tau_ext - h)
  const Eigen::VectorXd& h = CalcBiasForces(model, ws, q, v);
  const Eigen::VectorXd& ts = CalcSpringTorques(model, ws, q, v);
  qdd = ts - h;
  qdd.noalias() += model.B() * u;
  if (tau_ext.size() != 0) qdd += tau_ext;
  SolveMassMatrix(model, ws, q, qdd);
  if (k == 0) return 0;
  FactorDelassus(model, ws, q, k, params.regularization);
  const double alpha = params.baumgarte_alpha_per_s, beta = params.baumgarte_beta_per_s;
  auto rhs = ws.rhs.head(k);
  rhs.noalias() = ws.J.topRows(k) * qdd;
  rhs = -rhs - ws.Jdot_qdot.head(k);
  rhs.noalias() -= (2.0 * alpha) * (ws.J.topRows(k) * v);
  rhs -= (beta * beta) * ws.phi.head(k);
  SolveDelassus(ws, k);
  F.head(k) = ws.lambda_sol.head(k);
  // qdd += M^-1 J^T F
  ws.tmp_nv.noalias() = ws.J.topRows(k).transpose() * ws.lambda_sol.head(k);
  SolveMassMatrix(model, ws, q, ws.tmp_nv);
  qdd += ws.tmp_nv;
  return k;
}

int CalcConstrainedForwardDynamics(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                                   const VectorRef& v, const VectorRef& u, ContactSet active,
                                   const ConstrainedDynamicsParameters& params, Eigen::Ref<Eigen::VectorXd> qdd,
                                   Eigen::Ref<Eigen::VectorXd> F) {
  return CalcConstrainedForwardDynamics(model, ws, q, v, u, Eigen::VectorXd(), active, params, qdd, F);
}

int CalcImpactMap(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, const VectorRef& v_minus,
                  ContactSet active, const ConstrainedDynamicsParameters& params, Eigen::Ref<Eigen::VectorXd> v_plus,
                  Eigen::Ref<Eigen::VectorXd> impulse) {
  if (v_minus.size() != model.nv() || v_plus.size() != model.nv())
    throw std::invalid_argument("CalcImpactMap of robot '" + model.name() +
                                "': v_minus and v_plus must have size nv = " + std::to_string(model.nv()));
  const int k = FillConstraintRows(model, ws, q, nullptr, active);
  if (impulse.size() < k)
    throw std::invalid_argument("CalcImpactMap of robot '" + model.name() + "': impulse has size " +
                                std::to_string(impulse.size()) + " < " + std::to_string(k));
  v_plus = v_minus;
  if (k == 0) return 0;
  FactorDelassus(model, ws, q, k, params.regularization);
  ws.rhs.head(k).noalias() = ws.J.topRows(k) * v_minus;
  ws.rhs.head(k) = -ws.rhs.head(k);
  SolveDelassus(ws, k);
  impulse.head(k) = ws.lambda_sol.head(k);
  // v_plus += M^-1 J^T impulse
  ws.tmp_nv.noalias() = ws.J.topRows(k).transpose() * ws.lambda_sol.head(k);
  SolveMassMatrix(model, ws, q, ws.tmp_nv);
  v_plus += ws.tmp_nv;
  return k;
}

Eigen::Vector3d CalcContactPointPosition(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                                         int contact, int point) {
  CheckContact(model, contact);
  const ContactInfo& c = model.contacts()[contact];
  if (point < 0 || point >= static_cast<int>(c.points.size()))
    throw std::invalid_argument("contact '" + c.name + "': point index out of range");
  return CalcPointPosition(model, ws, q, c.body, c.points[point]);
}

Eigen::Vector3d CalcContactPointVelocity(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                                         const VectorRef& v, int contact, int point) {
  CheckContact(model, contact);
  const ContactInfo& c = model.contacts()[contact];
  if (point < 0 || point >= static_cast<int>(c.points.size()))
    throw std::invalid_argument("contact '" + c.name + "': point index out of range");
  return CalcPointVelocity(model, ws, q, v, c.body, c.points[point]);
}

double CalcContactHeight(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, int contact) {
  CheckContact(model, contact);
  const ContactInfo& c = model.contacts()[contact];
  double z = std::numeric_limits<double>::infinity();
  for (const auto& p : c.points) z = std::min(z, CalcPointPosition(model, ws, q, c.body, p).z());
  return z;
}

ContactWrench ExtractContactWrench(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                                   ContactSet active, const Eigen::Ref<const Eigen::VectorXd>& F, int contact) {
  CheckContact(model, contact);
  CheckActive(model, active);
  if (!(active & ContactBit(contact)))
    throw std::invalid_argument("contact '" + model.contacts()[contact].name + "' is not in the active contact set");
  int row = 0;
  for (int c = 0; c < contact; ++c)
    if (active & ContactBit(c)) row += model.contacts()[c].num_rows;
  const ContactInfo& info = model.contacts()[contact];
  if (F.size() < row + info.num_rows)
    throw std::invalid_argument("ExtractContactWrench: F too short for the active set");
  ws.SetPositions(model, q);
  const Eigen::Matrix3d& R = ws.R_world_link(info.body);
  const Eigen::Vector3d& p = ws.p_world_link(info.body);
  ContactWrench w;
  w.origin = p + R * info.frame_origin;
  if (model.is_planar()) {
    if (info.type == ContactType::kPoint) {
      w.force = Eigen::Vector3d(F[row], 0.0, F[row + 1]);
    } else {
      w.torque = Eigen::Vector3d(0.0, F[row], 0.0);
      w.force = Eigen::Vector3d(F[row + 1], 0.0, F[row + 2]);
    }
  } else if (info.type == ContactType::kPoint) {
    w.force = F.segment<3>(row);
  } else if (info.type == ContactType::kLine) {
    const Eigen::Vector3d p0 = p + R * info.points[0], p1 = p + R * info.points[1];
    Eigen::Vector3d n1, n2;
    LineNormals((p1 - p0).normalized(), n1, n2);
    const Eigen::Vector3d f0 = F.segment<3>(row);
    const Eigen::Vector3d f1 = F[row + 3] * n1 + F[row + 4] * n2;
    w.force = f0 + f1;
    w.torque = (p0 - w.origin).cross(f0) + (p1 - w.origin).cross(f1);
  } else {
    w.torque = F.segment<3>(row);
    w.force = F.segment<3>(row + 3);
  }
  return w;
}

Eigen::VectorXd CalcStanceGravityCompensation(const MultibodyModel& model, ContactSet active,
                                              const Eigen::VectorXd& q) {
  MultibodyWorkspace ws(model);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.nv());
  const int rows = CalcConstraintJacobian(model, ws, q, zero, active);
  Eigen::MatrixXd A(model.nv(), model.nu() + rows);
  A << model.B(), ws.J.topRows(rows).transpose();
  const Eigen::VectorXd rhs = CalcBiasForces(model, ws, q, zero) - CalcSpringTorques(model, ws, q, zero);
  return A.completeOrthogonalDecomposition().solve(rhs).head(model.nu());
}

ContactForceCheck CheckContactForce(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                                    int contact, const ContactWrench& wrench,
                                    const ContactForceCheckParameters& params) {
  CheckContact(model, contact);
  const ContactInfo& info = model.contacts()[contact];
  ContactForceCheck out;
  out.normal_force_N = wrench.force.z();
  out.tangential_force_N = wrench.force.head<2>().norm();
  out.friction_ratio =
      out.normal_force_N > 0.0 ? out.tangential_force_N / out.normal_force_N : std::numeric_limits<double>::infinity();
  out.unilateral_ok = out.normal_force_N >= params.min_normal_force_N;
  out.friction_ok =
      out.normal_force_N > 0.0 && out.tangential_force_N <= info.friction_coefficient * out.normal_force_N;
  if (out.normal_force_N <= 0.0) {
    out.cop = wrench.origin.head<2>();
    out.cop_ok = false;
    return out;
  }
  // CoP on the ground plane through the contact frame origin (tau = (cop - o) x f, dz = 0).
  out.cop.x() = wrench.origin.x() - wrench.torque.y() / out.normal_force_N;
  out.cop.y() = wrench.origin.y() + wrench.torque.x() / out.normal_force_N;
  if (info.type == ContactType::kPoint) {
    out.cop_ok = true;
    return out;
  }
  ws.SetPositions(model, q);
  const int n = static_cast<int>(info.points.size());
  std::array<Eigen::Vector2d, 64> pts;
  pts.fill(Eigen::Vector2d::Zero());
  for (int i = 0; i < n; ++i)
    pts[i] = (ws.p_world_link(info.body) + ws.R_world_link(info.body) * info.points[i]).head<2>();
  if (model.is_planar() || info.type == ContactType::kLine) {
    // Segment between the two extreme points along the foot (x for planar models).
    const Eigen::Vector2d a = pts[0], b = pts[n - 1];
    Eigen::Vector2d d = b - a;
    if (model.is_planar()) {
      double lo = pts[0].x(), hi = pts[0].x();
      for (int i = 1; i < n; ++i) {
        lo = std::min(lo, pts[i].x());
        hi = std::max(hi, pts[i].x());
      }
      out.cop_ok = out.cop.x() >= lo + params.cop_margin_m && out.cop.x() <= hi - params.cop_margin_m;
      return out;
    }
    const double len = d.norm();
    const double s = (out.cop - a).dot(d) / (len * len);
    const double lateral = std::abs(d.x() * (out.cop - a).y() - d.y() * (out.cop - a).x()) / len;
    out.cop_ok =
        s * len >= params.cop_margin_m && (1.0 - s) * len >= params.cop_margin_m && lateral <= 1e-9 + 1e-6 * len;
    return out;
  }
  // Flat: CoP inside the convex hull (gift wrapping on <= 64 points, no allocation).
  int start = 0;
  for (int i = 1; i < n; ++i)
    if (pts[i].x() < pts[start].x() || (pts[i].x() == pts[start].x() && pts[i].y() < pts[start].y())) start = i;
  out.cop_ok = true;
  int current = start;
  for (int guard = 0; guard <= n; ++guard) {
    int next = (current + 1) % n;
    for (int i = 0; i < n; ++i) {
      const Eigen::Vector2d e1 = pts[next] - pts[current], e2 = pts[i] - pts[current];
      if (e1.x() * e2.y() - e1.y() * e2.x() < 0.0) next = i;  // i is to the right: wrap tighter
    }
    // Counter-clockwise hull edge current -> next: the CoP must be to its left by the margin.
    const Eigen::Vector2d e = pts[next] - pts[current], r = out.cop - pts[current];
    const double len = e.norm();
    if (len > 0.0 && (e.x() * r.y() - e.y() * r.x()) / len < params.cop_margin_m) out.cop_ok = false;
    current = next;
    if (current == start) break;
  }
  return out;
}

}  // namespace rome
