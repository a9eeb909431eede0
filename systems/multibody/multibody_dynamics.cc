#include "systems/multibody/multibody_dynamics.h"

#include <stdexcept>
#include <string>

#include <BulletDynamics/Featherstone/btMultiBody.h>

#include "systems/multibody/bullet_scratch.h"
#include "systems/multibody/free_flyer_kernels.h"

// The loops over rows of a few entries (SolveMassMatrixFactorRows, SolveRowsDiagonalAndTransposeFactor) are compiled
// twice with GCC on x86-64: for x86-64-v3 (AVX2/FMA) and the baseline, and the loader picks one (as solvers/qp's
// kernels do). They call nothing. The AVX2 clone contracts multiply-adds into FMAs, so results differ in the last bits
// between machines (and M^-1 of one column, divided by D, from that of several, multiplied by 1/D).
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(ROME_QP_NO_TARGET_CLONES)
#define ROME_MULTIBODY_HOT __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define ROME_MULTIBODY_HOT
#endif

namespace rome {

namespace {

void CheckSize(const MultibodyModel& model, Eigen::Index got, Eigen::Index expected, const char* what) {
  if (got != expected)
    throw std::invalid_argument("robot '" + model.name() + "': " + what + " has size " + std::to_string(got) +
                                ", expected " + std::to_string(expected));
}

// Runs Bullet's ABA once at the current q so that its cached articulated inertias (needed by
// calcAccelerationDeltasMultiDof) are valid.
void EnsureBulletMinv(const MultibodyModel& model, MultibodyWorkspace& ws) {
  if (ws.valid.bullet_minv) return;
  ws.EnsureBulletPositions();
  btMultiBody& mb = ws.bullet();
  mb.clearForcesAndTorques();
  for (int i = 0; i < model.num_bodies(); ++i)
    if (model.body(i).v_index >= 0) mb.setJointVel(i, 0.0);
  ws.valid.bullet_v = false;
  auto& s = ws.bullet_scratch();
  mb.computeAccelerationsArticulatedBodyAlgorithmMultiDof(0.0, s.scratch_r, s.scratch_v, s.scratch_m, false, false,
                                                          false);
  ws.valid.bullet_minv = true;
}

// Rigid (Bullet) M_r^-1 applied to ws.bullet_in (6 base entries + nv), result in ws.bullet_out.
void BulletMinv(MultibodyWorkspace& ws) {
  auto& s = ws.bullet_scratch();
  ws.bullet().calcAccelerationDeltasMultiDof(ws.bullet_in.data(), ws.bullet_out.data(), s.scratch_r2, s.scratch_v2);
}

void EnsureArmature(const MultibodyModel& model, MultibodyWorkspace& ws) {
  if (ws.valid.armature || ws.armature_dofs.empty()) return;
  EnsureBulletMinv(model, ws);
  const int nv = model.nv();
  const int na = static_cast<int>(ws.armature_dofs.size());
  for (int a = 0; a < na; ++a) {
    ws.bullet_in.setZero();
    ws.bullet_in[6 + ws.armature_dofs[a]] = 1.0;
    BulletMinv(ws);
    ws.Minv_P.col(a) = ws.bullet_out.tail(nv);
  }
  for (int a = 0; a < na; ++a) {
    for (int b = 0; b < na; ++b) ws.armature_system(a, b) = ws.Minv_P(ws.armature_dofs[a], b);
    ws.armature_system(a, a) += 1.0 / model.reflected_inertia()[ws.armature_dofs[a]];
  }
  ws.armature_llt.compute(ws.armature_system);
  ws.valid.armature = true;
}

// x <- x - M_r^-1 P (D^-1 + P^T M_r^-1 P)^-1 P^T x, turning x = M_r^-1 f into M^-1 f.
void ApplyArmatureCorrection(MultibodyWorkspace& ws, Eigen::Ref<Eigen::VectorXd> x) {
  const int na = static_cast<int>(ws.armature_dofs.size());
  if (na == 0) return;
  for (int a = 0; a < na; ++a) ws.armature_y[a] = x[ws.armature_dofs[a]];
  ws.armature_llt.solveInPlace(ws.armature_y);
  x.noalias() -= ws.Minv_P * ws.armature_y;
}

}  // namespace

const Eigen::MatrixXd& CalcMassMatrix(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q) {
  ws.SetPositions(model, q);
  if (ws.valid.M) return ws.M;
  if (ws.free_flyer_as_one_joint()) {
    CalcFreeFlyerMassMatrix(model, ws);
    ws.valid.M = true;
    return ws.M;
  }
  // CRBA in world axes at O: M_kj = S_j^T (Ic_i S_i) for j an ancestor of (or equal to) i.
  for (int i = 0; i < model.num_bodies(); ++i) {
    const int k = model.body(i).v_index;
    if (k < 0) continue;
    const Vector6d F = ws.composite_inertia(i) * ws.S(i);
    ws.M(k, k) = ws.S(i).dot(F) + model.reflected_inertia()[k];
    for (int j = model.body(i).parent; j >= 0; j = model.body(j).parent) {
      const int kj = model.body(j).v_index;
      if (kj < 0) continue;
      const double Mkj = ws.S(j).dot(F);
      ws.M(kj, k) = Mkj;
      ws.M(k, kj) = Mkj;
    }
  }
  // Entries of joints on different branches stay at their initial zero.
  ws.valid.M = true;
  return ws.M;
}

const Eigen::VectorXd& CalcBiasForces(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                                      const VectorRef& v) {
  ws.SetState(model, q, v);
  if (ws.valid.h) return ws.h;
  if (ws.free_flyer_as_one_joint()) {
    CalcFreeFlyerRnea(model, ws, nullptr, ws.h.data());
    ws.valid.h = true;
    return ws.h;
  }
  // RNEA with qdd = 0; gravity enters as a fictitious base acceleration a_0 = [0; -g].
  Vector6d a0 = Vector6d::Zero();
  a0.tail<3>() = -model.gravity();
  const int nb = model.num_bodies();
  for (int b = 0; b < nb; ++b) {
    const SpatialInertia& I = ws.inertia(b);
    if (I.m == 0.0) {
      ws.f_[b].setZero();
      continue;
    }
    const Vector6d& V = ws.V(b);
    const Vector6d IV = I * V;
    Vector6d a = ws.A_bias(b) + a0;
    Vector6d f = I * a;
    // V x* (I V) = [w x n + v x f; w x f]
    f.head<3>() += V.head<3>().cross(IV.head<3>()) + V.tail<3>().cross(IV.tail<3>());
    f.tail<3>() += V.head<3>().cross(IV.tail<3>());
    ws.f_[b] = f;
  }
  for (int b = nb - 1; b >= 0; --b) {
    const int k = model.body(b).v_index;
    if (k >= 0) ws.h[k] = ws.S(b).dot(ws.f_[b]);
    const int p = model.body(b).parent;
    if (p >= 0) ws.f_[p] += ws.f_[b];
  }
  ws.valid.h = true;
  return ws.h;
}

const Eigen::VectorXd& CalcSpringTorques(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                                         const VectorRef& v) {
  CheckSize(model, q.size(), model.nq(), "q");
  CheckSize(model, v.size(), model.nv(), "v");
  // The joint coordinates are q's last n entries (after a quaternion base's extra one, v's last n too).
  const int nv = model.nv(), n = model.has_quaternion_base() ? nv - 6 : nv;
  ws.tau_spring.head(nv - n).setZero();
  ws.tau_spring.tail(n).array() =
      -model.spring_stiffness().tail(n).array() * (q.tail(n) - model.spring_rest().tail(n)).array() -
      model.spring_damping().tail(n).array() * v.tail(n).array();
  return ws.tau_spring;
}

void CalcInverseDynamics(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, const VectorRef& v,
                         const VectorRef& qdd, Eigen::Ref<Eigen::VectorXd> tau) {
  CheckSize(model, qdd.size(), model.nv(), "qdd");
  CheckSize(model, tau.size(), model.nv(), "tau");
  if (ws.free_flyer_as_one_joint()) {  // one O(n) pass: tau = RNEA(q, v, qdd) - tau_spring
    const Eigen::VectorXd& ts = CalcSpringTorques(model, ws, q, v);
    CalcRnea(model, ws, q, v, qdd, tau);
    tau -= ts;
    return;
  }
  const Eigen::MatrixXd& M = CalcMassMatrix(model, ws, q);
  const Eigen::VectorXd& h = CalcBiasForces(model, ws, q, v);
  const Eigen::VectorXd& ts = CalcSpringTorques(model, ws, q, v);
  tau.noalias() = M.selfadjointView<Eigen::Lower>() * qdd;
  tau += h - ts;
}

void CalcRnea(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, const VectorRef& v,
              const VectorRef& qdd, Eigen::Ref<Eigen::VectorXd> tau) {
  CheckSize(model, qdd.size(), model.nv(), "qdd");
  CheckSize(model, tau.size(), model.nv(), "tau");
  ws.SetState(model, q, v);
  if (ws.free_flyer_as_one_joint()) {
    CalcFreeFlyerRnea(model, ws, qdd.data(), tau.data());
    return;
  }
  // Forward: a_b = a_parent + S_b qdd_b (+ A_bias_b, the velocity product, already accumulated); gravity enters as the
  // fictitious base acceleration a_0 = [0; -g]. Backward: f_b = I_b a_b + V_b x* (I_b V_b), tau_k = S_k^T f_b.
  Vector6d a0 = Vector6d::Zero();
  a0.tail<3>() = -model.gravity();
  const int nb = model.num_bodies();
  for (int b = 0; b < nb; ++b) {
    const int p = model.body(b).parent, k = model.body(b).v_index;
    Vector6d& a = ws.a_[b];
    a = p >= 0 ? ws.a_[p] : Vector6d::Zero();
    if (k >= 0) a += ws.S(b) * qdd[k];
    const SpatialInertia& I = ws.inertia(b);
    if (I.m == 0.0) {
      ws.f_[b].setZero();
      continue;
    }
    const Vector6d& V = ws.V(b);
    const Vector6d IV = I * V;
    Vector6d f = I * (a + ws.A_bias(b) + a0);
    f.head<3>() += V.head<3>().cross(IV.head<3>()) + V.tail<3>().cross(IV.tail<3>());
    f.tail<3>() += V.head<3>().cross(IV.tail<3>());
    ws.f_[b] = f;
  }
  for (int b = nb - 1; b >= 0; --b) {
    const int k = model.body(b).v_index;
    if (k >= 0) tau[k] = ws.S(b).dot(ws.f_[b]) + model.reflected_inertia()[k] * qdd[k];
    const int p = model.body(b).parent;
    if (p >= 0) ws.f_[p] += ws.f_[b];
  }
}

void ApplyInverseMassMatrix(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, const VectorRef& f,
                            Eigen::Ref<Eigen::VectorXd> out) {
  CheckSize(model, f.size(), model.nv(), "f");
  CheckSize(model, out.size(), model.nv(), "M^-1 f output");
  if (model.has_quaternion_base()) {  // no Bullet: the tree factor of the CRBA's M
    out = f;
    SolveMassMatrix(model, ws, q, out);
    return;
  }
  ws.SetPositions(model, q);
  EnsureBulletMinv(model, ws);
  EnsureArmature(model, ws);
  ws.bullet_in.head<6>().setZero();
  ws.bullet_in.tail(model.nv()) = f;
  BulletMinv(ws);
  out = ws.bullet_out.tail(model.nv());
  ApplyArmatureCorrection(ws, out);
}

void FactorMassMatrix(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q) {
  CalcMassMatrix(model, ws, q);
  if (ws.valid.M_factor) return;
  const int nv = model.nv();
  if (ws.use_tree_factor) {
    // LTDL (Featherstone, RBDA Table 6.3): M = L^T D L, fill-in confined to ancestor pairs. Row k of L is packed over
    // the ancestors of k (nearest first); the row of its m-th ancestor i covers exactly the ancestors after position m,
    // so H(i, j) -= a H(k, j) over the ancestors j of i is one contiguous axpy.
    const int* begin = ws.ancestor_begin.data();
    const int* index = ws.ancestor_index.data();
    double* L = ws.L_packed.data();
    double* D = ws.D.data();
    for (int k = 0; k < nv; ++k) {
      D[k] = ws.M(k, k);
      for (int m = begin[k]; m < begin[k + 1]; ++m) L[m] = ws.M(k, index[m]);
    }
    for (int k = nv - 1; k >= 0; --k) {
      const double Dk = D[k];
      if (!(Dk > 0.0))
        throw std::runtime_error("robot '" + model.name() + "': mass matrix is not positive definite (pivot " +
                                 std::to_string(Dk) + " at dof " + std::to_string(k) + ")");
      double* Lk = L + begin[k];
      const int nk = begin[k + 1] - begin[k];
      for (int m = 0; m < nk; ++m) {
        const int i = index[begin[k] + m];
        const double a = Lk[m] / Dk;
        D[i] -= a * Lk[m];
        double* Li = L + begin[i];  // nk - m - 1 entries: the ancestors of i
        const double* Lk_tail = Lk + m + 1;
        for (int p = 0; p < nk - m - 1; ++p) Li[p] -= a * Lk_tail[p];
        Lk[m] = a;
      }
    }
  } else {
    ws.M_llt.compute(ws.M);
    if (ws.M_llt.info() != Eigen::Success)
      throw std::runtime_error("robot '" + model.name() + "': mass matrix is not positive definite");
  }
  ws.valid.M_factor = true;
}

void SolveMassMatrixTransposeFactor(const MultibodyWorkspace& ws, Eigen::Ref<Eigen::MatrixXd> inout) {
  const int* begin = ws.ancestor_begin.data();
  const int* index = ws.ancestor_index.data();
  const double* L = ws.L_packed.data();
  const int nv = static_cast<int>(ws.D.size());
  for (Eigen::Index c = 0; c < inout.cols(); ++c) {
    double* x = inout.col(c).data();
    // L^T y = b, leaves to root; zero entries (other branches) cost nothing.
    for (int i = nv - 1; i >= 0; --i) {
      const double xi = x[i];
      if (xi == 0.0) continue;
      for (int m = begin[i]; m < begin[i + 1]; ++m) x[index[m]] -= L[m] * xi;
    }
  }
}

namespace {

// rows <- rows D^-1 L^-T (Z L^T = Y D^-1, root to leaves), the last two steps of rows M^-1.
ROME_MULTIBODY_HOT void SolveRowsDiagonalAndTransposeFactor(const MultibodyWorkspace& ws,
                                                            Eigen::Ref<Eigen::MatrixXd> rows) {
  const int* begin = ws.ancestor_begin.data();
  const int* index = ws.ancestor_index.data();
  const double* L = ws.L_packed.data();
  const double* D = ws.D.data();
  const int nv = static_cast<int>(ws.D.size());
  const Eigen::Index n = rows.rows(), stride = rows.outerStride();
  double* y = rows.data();
  for (int i = 0; i < nv; ++i) {
    double* yi = y + i * stride;
    const double d = 1.0 / D[i];
    for (Eigen::Index r = 0; r < n; ++r) yi[r] *= d;
    for (int m = begin[i]; m < begin[i + 1]; ++m) {
      const double* yj = y + index[m] * stride;
      const double l = L[m];
      for (Eigen::Index r = 0; r < n; ++r) yi[r] -= l * yj[r];
    }
  }
}

}  // namespace

ROME_MULTIBODY_HOT void SolveMassMatrixFactorRows(const MultibodyWorkspace& ws, Eigen::Ref<Eigen::MatrixXd> rows) {
  const int* begin = ws.ancestor_begin.data();
  const int* index = ws.ancestor_index.data();
  const double* L = ws.L_packed.data();
  const int nv = static_cast<int>(ws.D.size());
  // Y L = R, leaves to root: column i of Y is final once its descendants are done; it then leaves its ancestors.
  const Eigen::Index n = rows.rows(), stride = rows.outerStride();
  double* Y = rows.data();
  for (int i = nv - 1; i >= 0; --i) {
    const double* yi = Y + i * stride;
    for (int m = begin[i]; m < begin[i + 1]; ++m) {
      double* yj = Y + index[m] * stride;
      const double l = L[m];
      for (Eigen::Index r = 0; r < n; ++r) yj[r] -= l * yi[r];
    }
  }
}

void SolveMassMatrix(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                     Eigen::Ref<Eigen::MatrixXd> inout) {
  CheckSize(model, inout.rows(), model.nv(), "M^-1 operand rows");
  FactorMassMatrix(model, ws, q);
  if (!ws.use_tree_factor) {
    ws.M_llt.solveInPlace(inout);
    return;
  }
  const int nv = model.nv();
  if (inout.cols() >= 4 && inout.cols() <= ws.solve_rows.rows()) {
    // Several columns: solve X^T M^-1 = X^T L^-1 D^-1 L^-T on the transpose, where every step is an axpy over the
    // columns' entries of one dof (contiguous) instead of a scalar loop per column.
    auto Y = ws.solve_rows.topRows(inout.cols());
    Y = inout.transpose();
    SolveMassMatrixFactorRows(ws, Y);
    SolveRowsDiagonalAndTransposeFactor(ws, Y);
    inout = Y.transpose();
    return;
  }
  SolveMassMatrixTransposeFactor(ws, inout);
  const int* begin = ws.ancestor_begin.data();
  const int* index = ws.ancestor_index.data();
  const double* L = ws.L_packed.data();
  const double* D = ws.D.data();
  for (Eigen::Index c = 0; c < inout.cols(); ++c) {
    double* x = inout.col(c).data();
    // y <- D^-1 y, then L x = y (root to leaves).
    for (int i = 0; i < nv; ++i) {
      double xi = x[i] / D[i];
      for (int m = begin[i]; m < begin[i + 1]; ++m) xi -= L[m] * x[index[m]];
      x[i] = xi;
    }
  }
}

void CalcForwardDynamics(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, const VectorRef& v,
                         const VectorRef& u, const VectorRef& tau_ext, Eigen::Ref<Eigen::VectorXd> qdd) {
  CheckSize(model, u.size(), model.nu(), "u");
  CheckSize(model, qdd.size(), model.nv(), "qdd");
  if (tau_ext.size() != 0) CheckSize(model, tau_ext.size(), model.nv(), "tau_ext");
  ws.SetState(model, q, v);
  const Eigen::VectorXd& ts = CalcSpringTorques(model, ws, q, v);
  ws.tau_total = ts;
  ws.tau_total.noalias() += model.B() * u;
  if (tau_ext.size() != 0) ws.tau_total += tau_ext;
  if (model.has_quaternion_base()) {  // no Bullet: qdd = M^-1 (tau - h) through the CRBA and the tree factor
    qdd = ws.tau_total - CalcBiasForces(model, ws, q, v);
    SolveMassMatrix(model, ws, q, qdd);
    return;
  }

  ws.EnsureBulletPositions();
  btMultiBody& mb = ws.bullet();
  mb.clearForcesAndTorques();
  const btVector3 g(model.gravity().x(), model.gravity().y(), model.gravity().z());
  for (int i = 0; i < model.num_bodies(); ++i) {
    const MultibodyBody& b = model.body(i);
    if (b.mass > 0.0) mb.addLinkForce(i, b.mass * g);
    if (b.v_index >= 0) {
      mb.setJointVel(i, ws.v()[b.v_index]);
      mb.addJointTorque(i, ws.tau_total[b.v_index]);
    }
  }
  auto& s = ws.bullet_scratch();
  mb.computeAccelerationsArticulatedBodyAlgorithmMultiDof(0.0, s.scratch_r, s.scratch_v, s.scratch_m, false, false,
                                                          false);
  mb.clearForcesAndTorques();
  ws.valid.bullet_minv = true;
  ws.valid.bullet_v = true;
  const int nv = model.nv();
  // Bullet's output block: scratch_r[nv .. nv + 6) base, then nv joint accelerations.
  for (int k = 0; k < nv; ++k) qdd[k] = s.scratch_r[nv + 6 + k];
  if (!ws.armature_dofs.empty()) {
    EnsureArmature(model, ws);
    ApplyArmatureCorrection(ws, qdd);
  }
}

}  // namespace rome
