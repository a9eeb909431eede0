#pragma once
// MultibodyWorkspace: all mutable state and scratch of the multibody computations
// (Pinocchio's "Data"). Sized once from a MultibodyModel; no heap allocation afterwards.
//
// It owns the Bullet btMultiBody (double precision) built from the model, built lazily by the first Bullet call (ABA,
// M⁻¹, CalcBulletLinkPoses, bullet()): the hybrid plant, the controllers and the planners never call Bullet, so their
// workspaces never build one (its construction and copy cost nothing there). A test or benchmark that counts
// allocations makes one Bullet call before counting.
//  * one Bullet link per MultibodyBody, with the fixed Bullet base at the world origin;
//  * Bullet link frames are the principal inertia frames at each COM (Bullet only accepts
//    diagonal inertia); see MultibodyBody::R_link_principal;
//  * Bullet damping is switched off and the coordinate velocity clamp is disabled.
// Bullet provides the articulated-body forward dynamics and the M^-1 operator
// (calcAccelerationDeltasMultiDof). Link world poses come from a fixed-size Eigen pass over the
// joint chain (R_wl = R_wp R_pj R_axis(q)), verified against Bullet's forwardKinematics to 1e-12
// in the tests (CalcBulletLinkPoses); q is pushed into Bullet lazily, only when a Bullet
// algorithm runs. Everything else (M by CRBA, h by RNEA, Jacobians, J̇q̇, COM, centroidal
// momentum) is computed in multibody_kinematics.cc / multibody_dynamics.cc from these poses.
//
// The state is cached by value: SetPositions(q) / SetVelocities(v) recompute only when q or v
// changed, and derived quantities (M, h, ...) are computed lazily once per state.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include "systems/multibody/multibody_model.h"

class btMultiBody;

namespace rome {

using Vector6d = Eigen::Matrix<double, 6, 1>;

// Rigid-body spatial inertia about the workspace reference point O, world axes:
//   I * [omega; v_O] = [I_O omega + h x v_O ; m v_O - h x omega],  h = m (c - O).
struct SpatialInertia {
  double m = 0.0;
  Eigen::Vector3d h = Eigen::Vector3d::Zero();
  Eigen::Matrix3d I = Eigen::Matrix3d::Zero();
  Vector6d operator*(const Vector6d& V) const {
    Vector6d f;
    f.head<3>() = I * V.head<3>() + h.cross(V.tail<3>());
    f.tail<3>() = m * V.tail<3>() - h.cross(V.head<3>());
    return f;
  }
  SpatialInertia& operator+=(const SpatialInertia& o) {
    m += o.m;
    h += o.h;
    I += o.I;
    return *this;
  }
};

class MultibodyWorkspace {
 public:
  explicit MultibodyWorkspace(const MultibodyModel& model);
  ~MultibodyWorkspace();
  MultibodyWorkspace(const MultibodyWorkspace& other);  // its own btMultiBody, built on its first Bullet call
  MultibodyWorkspace& operator=(const MultibodyWorkspace& other);
  MultibodyWorkspace(MultibodyWorkspace&&) noexcept;
  MultibodyWorkspace& operator=(MultibodyWorkspace&&) noexcept;

  // Sets q (nq) and v (nv); throw std::invalid_argument on a size mismatch (and on a zero or non-finite base
  // quaternion; the quaternion is normalised, so q need not be exactly unit).
  void SetPositions(const MultibodyModel& model, const Eigen::Ref<const Eigen::VectorXd>& q);
  void SetVelocities(const MultibodyModel& model, const Eigen::Ref<const Eigen::VectorXd>& v);
  void SetState(const MultibodyModel& model, const Eigen::Ref<const Eigen::VectorXd>& q,
                const Eigen::Ref<const Eigen::VectorXd>& v) {
    SetPositions(model, q);
    SetVelocities(model, v);
  }
  const Eigen::VectorXd& q() const { return q_; }
  const Eigen::VectorXd& v() const { return v_; }
  bool has_positions() const { return has_q_; }
  bool has_velocities() const { return has_v_; }

  // Quaternion base only: true (the default) runs the kernels (CRBA, RNEA, Jacobians, velocity kinematics) with the
  // base as ONE 6-DOF joint of motion subspace [[0, R]; [R, 0]] (world axes at O = the base origin, v = [v_B; w_B]);
  // false runs the generic path over the six 1-DOF virtual joints, kept to compare against (the results agree to
  // rounding; the virtual bodies' V differ: one joint gives all six the base's twist). Invalidates the cached state.
  void SetFreeFlyerAsOneJoint(bool one_joint);
  bool free_flyer_as_one_joint() const { return quaternion_base_ && free_flyer_one_joint_; }

  // ---- per-body kinematics at the current q (world frame) ----
  const Eigen::Matrix3d& R_world_link(int body) const { return R_wl_[body]; }
  const Eigen::Vector3d& p_world_link(int body) const { return p_wl_[body]; }
  const Eigen::Vector3d& com_world(int body) const { return c_w_[body]; }
  // Motion subspace column of the body's inboard joint, [axis; (p_joint - O) x axis] for
  // revolute, [0; axis] for prismatic, zero for fixed (world axes, reference point O).
  const Vector6d& S(int body) const { return S_[body]; }
  const Eigen::Vector3d& reference_point() const { return O_; }
  // Spatial velocity [omega; v_O] at O and velocity-product acceleration (qdd = 0, no gravity).
  const Vector6d& V(int body) const { return V_[body]; }
  const Vector6d& A_bias(int body) const { return A_bias_[body]; }
  const SpatialInertia& inertia(int body) const { return I_[body]; }
  const SpatialInertia& composite_inertia(int body) const { return Ic_[body]; }

  btMultiBody& bullet();  // builds the tree on first use; throws std::logic_error on a quaternion base
  // Pushes the current q into Bullet's joint positions (lazily, once per q). The workspace's own
  // link poses come from an Eigen forward-kinematics pass; Bullet needs q only for its ABA and
  // M^-1 operator. Called by the Bullet-based functions in multibody_dynamics.cc.
  void EnsureBulletPositions();
  // Bullet's own forward kinematics at the current q, converted to link frames (allocates; for
  // verification of the Eigen kinematics pass, not for hot paths).
  void CalcBulletLinkPoses(std::vector<Eigen::Isometry3d>& X_world_link);

  // ---------------- internal scratch (used by the free functions) ----------------
  struct Flags {
    bool M = false, M_factor = false, h = false, bullet_q = false, bullet_v = false, bullet_minv = false,
         armature = false;
  } valid;

  Eigen::MatrixXd M;  // nv x nv
  // The tree factor (below) is used when every dof's parent dof has a smaller index (dof_parent[k] < k); otherwise
  // the dense Cholesky M_llt is used.
  std::vector<int> dof_parent;  // nearest ancestor dof of each dof, -1 for none
  // The bodies with a dof on the path from each body to the root (the body first): those of body b are
  // support_body[support_begin[b] .. support_begin[b + 1]). A point Jacobian of b has columns only there.
  std::vector<int> support_begin;  // num_bodies + 1
  std::vector<int> support_body;
  // Tree factor M = L^T D L (Featherstone's LTDL, RBDA 6.3; L unit lower triangular, L_ki != 0 only for dof i an
  // ancestor of dof k), packed by rows: row k of L holds one entry per ancestor dof of k,
  // nearest first: L(k, ancestor_index[j]) = L_packed[j] for j in [ancestor_begin[k], ancestor_begin[k + 1]). The
  // ancestors of the m-th ancestor of k are the entries after it, so the factorisation's inner loops run over
  // contiguous memory.
  std::vector<int> ancestor_begin;  // nv + 1
  std::vector<int> ancestor_index;
  Eigen::VectorXd L_packed;  // ancestor_index.size()
  Eigen::VectorXd D;         // nv
  bool use_tree_factor = false;
  Eigen::LLT<Eigen::MatrixXd> M_llt;
  Eigen::VectorXd h;           // nv: C v + g
  Eigen::VectorXd tau_spring;  // nv
  Eigen::VectorXd tmp_nv, tmp2_nv, tau_total;
  std::vector<Vector6d> f_;  // per-body spatial forces (RNEA)
  std::vector<Vector6d> a_;  // per-body spatial acceleration from qdd alone (CalcRnea)

  // Bullet scratch (sized 6 + nv) and M^-1 armature correction.
  Eigen::VectorXd bullet_in, bullet_out;
  std::vector<int> armature_dofs;   // dofs with reflected inertia
  Eigen::MatrixXd Minv_P;           // nv x na: rigid M^-1 columns of armature dofs
  Eigen::MatrixXd armature_system;  // na x na: D^-1 + P^T M_rigid^-1 P
  Eigen::LLT<Eigen::MatrixXd> armature_llt;
  Eigen::VectorXd armature_y;

  // Constraint scratch (rows up to model.max_constraint_rows()).
  Eigen::MatrixXd J;           // rows x nv
  Eigen::VectorXd Jdot_qdot;   // rows
  Eigen::VectorXd phi;         // rows (position error; zero for contact rows)
  Eigen::MatrixXd Minv_JT;     // nv x rows: M^-1 J^T (dense factor only)
  Eigen::MatrixXd JLinv;       // rows x nv: J L^-1 D^-1/2 (tree factor only)
  Eigen::MatrixXd solve_rows;  // max(nv, nu, rows) x nv: SolveMassMatrix's transposed operand (tree factor)
  Eigen::MatrixXd Lambda;      // rows x rows: J M^-1 J^T
  Eigen::MatrixXd Lambda_L;    // rows x rows: Cholesky factor of J M^-1 J^T + eps I
  Eigen::VectorXd rhs, lambda_sol, residual;
  Eigen::MatrixXd J_point;  // 6 x nv scratch for point/frame Jacobians

 private:
  void Build(const MultibodyModel& model);
  // Poses the quaternion base's six bodies from q_; returns the first body the joint-chain pass handles.
  int SetFreeFlyerPose(const MultibodyModel& model);
  void BuildBullet();

  std::shared_ptr<const std::vector<MultibodyBody>> bodies_;
  std::unique_ptr<btMultiBody> bullet_;
  struct BulletScratch;
  std::unique_ptr<BulletScratch> scratch_;

  Eigen::VectorXd q_, v_;
  bool has_q_ = false, has_v_ = false;
  // Quaternion free-flyer base (free_flyer.h): its six virtual bodies (0..5) are posed at the base from q[0..7), and
  // their bias acceleration is zero (their motion subspace is fixed in the base). Bullet is refused.
  bool quaternion_base_ = false;
  bool free_flyer_one_joint_ = true;
  std::string robot_name_;           // for the refusal's message
  std::vector<int> position_index_;  // per body: index in q of its joint coordinate (-1: none or free-flyer)
  // Per body, for the forward kinematics: the joint axis as ±(unit axis axis_index_) when it is one (else −1), and
  // whether the joint frame's rotation in the parent is the identity.
  std::vector<int> axis_index_;
  std::vector<double> axis_sign_;
  std::vector<char> joint_rotation_identity_;
  Eigen::Vector3d O_ = Eigen::Vector3d::Zero();
  std::vector<Eigen::Matrix3d> R_wl_;
  std::vector<Eigen::Vector3d> p_wl_, c_w_;
  std::vector<Vector6d> S_, V_, A_bias_;
  std::vector<SpatialInertia> I_, Ic_;

 public:
  // Bullet scratch arrays (opaque to users).
  BulletScratch& bullet_scratch();  // builds the tree on first use
};

}  // namespace rome
