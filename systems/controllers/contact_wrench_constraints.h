#pragma once
// ContactWrenchConstraints: the inequality rows l ≤ G F ≤ u that keep one contact's constraint force F physical, per
// contact type, in the row convention of contact_dynamics.h (world axes):
//   planar point   F = [F_x, F_z]          F_z ≥ F_min; |F_x| ≤ μ' F_z                                   (3 rows)
//   planar line / flat  F = [τ_y, F_x, F_z]  the same, plus the centre of pressure between the contact points:
//                                           x_min F_z ≤ −τ_y ≤ x_max F_z (x relative to the frame origin) (5 rows)
//   (planar rows: unilateral 1, friction 2, CoP 2; 3D: unilateral 1, friction 4, CoP 4, yaw 2)
//   3D point       F = [F_x, F_y, F_z]      F_z ≥ F_min; |F_x|, |F_y| ≤ μ' F_z (friction pyramid)        (5 rows)
//   3D flat        F = [τ; f]               f_z ≥ F_min; |f_x|, |f_y| ≤ μ' f_z; centre of pressure inside the
//                                           sole rectangle (in the foot frame, from the contact points):
//                                           x_min f_z ≤ −τ'_y ≤ x_max f_z, y_min f_z ≤ τ'_x ≤ y_max f_z with
//                                           τ' = R_footᵀ τ; optionally |τ'_z| ≤ yaw_coefficient · f_z   (9 or 11 rows)
//   3D line        F = [f_0 (3); f_1 along n1; f_1 along n2] (contact_dynamics.h: point 0's force, point 1's force
//                  in the plane normal to the line; f = f_0 + f_1)
//                                           f_z ≥ F_min; |f_x|, |f_y| ≤ μ' f_z on the total force; centre of
//                                           pressure between toe and heel: each point's own normal force
//                                           f_0z ≥ 0, f_1z ≥ 0 (both points on the ground plane)         (7 rows)
//                                           No yaw-moment rows (the hopping spec bounds none for a line foot; the
//                                           plant checks none).
// μ' = friction_margin · μ (μ: the contact's model value, or friction_coefficient if ≥ 0); for 3D contacts the
// pyramid is inscribed in the cone (μ' /= √2) when inscribe_pyramid is set, as the hopping spec recommends.
// The rows are numbered so that callers can drop a class of rows (the CoP rows) in a fallback: RowKind says which.
// Sole geometry rows depend on the foot pose: Fill() recomputes them at each q (no allocation).
// normal_index() is the single entry of F that is F_z; a 3D line contact has none (has_normal_entry() is false).

#include <string>
#include <vector>

#include <Eigen/Core>

#include "systems/multibody/contact_dynamics.h"

namespace rome {

struct ContactWrenchParams {
  double min_normal_force_N = 0.0;     ///< [N] F_z ≥ this (0: the paper's unilateral contact)
  double friction_coefficient = -1.0;  ///< [-] μ; < 0 uses each contact's model value
  double friction_margin = 1.0;        ///< [-] the pyramid uses friction_margin · μ (1: the full cone)
  /// [N] the pyramid's apex is shifted up to F_z = this: |F_t| ≤ μ' (F_z − offset). At small loads (a foot about to
  /// lift off) the ratio |F_t|/F_z then stays well inside the cone while the plant's forces drift over a held sample.
  /// 0: the paper's cone.
  double friction_cone_offset_N = 0.0;
  bool inscribe_pyramid = true;  ///< 3D: |F_x|, |F_y| ≤ μ'/√2 F_z, inside the cone (hopping spec [R])
  /// [m] line/flat contacts: the CoP rows keep the centre of pressure this far inside the sole's edges (0: the edges;
  /// ours: the plant's CoP drifts over a held sample, so a CoP held on the edge leaves the sole between samples)
  double cop_margin_m = 0.0;
  double yaw_moment_coefficient_m = -1.0;  ///< [m] 3D flat: |τ_z| ≤ this · f_z; < 0: no yaw-moment bound
  /// 3D flat (ours; default off): instead of yaw_moment_coefficient_m, the yaw rows of the contact wrench cone of the
  /// sole rectangle with a friction pyramid (μ') at each corner, in closed form (Caron, Pham, Nakamura, ICRA 2015;
  /// half-sizes X, Y after cop_margin_m, foot frame, τ about the sole's centre, which must be the contact frame
  /// origin):
  ///   −μ'(X+Y) f_z + |Y f_x − μ' τ_x| + |X f_y − μ' τ_y| ≤ τ_z ≤ μ'(X+Y) f_z − |Y f_x + μ' τ_x| − |X f_y + μ' τ_y|
  /// (8 rows): the torsion a sole can hold shrinks as its CoP nears an edge or corner and as it carries a tangential
  /// force, as on BulletWorldPlant's four corner contacts.
  bool corner_wrench_cone = false;
  /// [-] corner_wrench_cone: μ of the corners' pyramids (before inscribe_pyramid; friction_margin does not apply);
  /// < 0: the friction rows' μ'. The torsion a sole holds is the plant's (its sole's μ), while the friction rows' μ'
  /// may be kept low for the force's drift over a held sample (ours).
  double corner_cone_friction_coefficient = -1.0;
  /// [m] corner_wrench_cone: the yaw rows' half-sizes X, Y are the whole sole's less this margin (ours); < 0: the CoP
  /// rows' sole (after cop_margin_m). The corners' torsion is the plant's whole sole's, while the CoP rows keep their
  /// own margin for the CoP's drift; a small margin keeps the plant's torsion inside over a held sample.
  double corner_cone_yaw_margin_m = -1.0;
};

class ContactWrenchConstraints {
 public:
  enum class RowKind { kNormal, kFriction, kCenterOfPressure, kYawMoment };
  ContactWrenchConstraints(const MultibodyModel& model, int contact, const ContactWrenchParams& params,
                           const std::string& system);

  int contact() const { return contact_; }
  int num_force_rows() const { return num_force_rows_; }  ///< size of this contact's F
  int num_rows() const { return static_cast<int>(kinds_.size()); }
  RowKind kind(int row) const { return kinds_[row]; }
  int normal_index() const { return normal_; }  ///< index of F_z in this contact's F (if has_normal_entry())
  /// false for a 3D line contact, whose F_z is the sum f_0z + f_1z of two entries (see the header).
  bool has_normal_entry() const { return !line3d_; }
  /// G (num_rows × num_force_rows), l, u at configuration q (ws is used for the foot pose). Rows are written in place.
  void Fill(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, Eigen::Ref<Eigen::MatrixXd> G,
            Eigen::Ref<Eigen::VectorXd> l, Eigen::Ref<Eigen::VectorXd> u) const;

 private:
  int contact_ = -1;
  int num_force_rows_ = 0;
  int normal_ = 0;
  bool planar_ = false, flat3d_ = false, line3d_ = false, cop_ = false;
  double mu_ = 1.0;
  double mu_corner_ = 1.0;  // the corner cone's μ (inscribed when inscribe_pyramid)
  double min_normal_ = 0.0;
  double offset_ = 0.0;
  double yaw_ = -1.0;
  bool cwc_ = false;
  double x_min_ = 0, x_max_ = 0, y_min_ = 0, y_max_ = 0;  // sole, foot frame, relative to the frame origin
  double yaw_x_ = 0, yaw_y_ = 0;                          // corner_wrench_cone: the yaw rows' half-sizes X, Y
  std::vector<RowKind> kinds_;
};

}  // namespace rome
