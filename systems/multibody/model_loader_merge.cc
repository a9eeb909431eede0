// Merging: links welded over fixed joints into one rigid body each, inertia validity judged per body (and repaired if
// asked), principal frames and the degrees of freedom in body order (model_loader.h lists the loader's stages).

#include <limits>
#include <stdexcept>

#include <Eigen/Eigenvalues>

#include "framework/text.h"
#include "systems/multibody/model_checks.h"
#include "systems/multibody/model_loader.h"

namespace rome {

namespace model_loading {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Euclidean projection of principal moments onto the physical cone
// {l : l_i + l_j >= l_k for every permutation} (which implies l >= 0): the nearest physical
// inertia in the Frobenius norm keeps the principal axes. Enumerates the faces of the cone
// (active sets of the 3 constraints); the closest feasible face projection is the projection.
Eigen::Vector3d ProjectPhysicalMoments(const Eigen::Vector3d& l) {
  Eigen::Matrix3d A;  // rows a_k: a_k . x >= 0
  A << 1, 1, -1, 1, -1, 1, -1, 1, 1;
  Eigen::Vector3d best = Eigen::Vector3d::Zero();
  double best_dist = (l - best).squaredNorm();
  for (int mask = 0; mask < 8; ++mask) {
    std::vector<int> rows;
    for (int k = 0; k < 3; ++k)
      if (mask & (1 << k)) rows.push_back(k);
    Eigen::Vector3d x = l;
    if (!rows.empty()) {
      Eigen::MatrixXd Aa(rows.size(), 3);
      for (size_t r = 0; r < rows.size(); ++r) Aa.row(r) = A.row(rows[r]);
      // x = l - Aa^T (Aa Aa^T)^-1 Aa l
      const Eigen::MatrixXd G = Aa * Aa.transpose();
      x = l - Aa.transpose() * G.ldlt().solve(Aa * l);
    }
    if ((A * x).minCoeff() < -1e-14 * (1.0 + l.cwiseAbs().maxCoeff())) continue;
    const double d = (l - x).squaredNorm();
    if (d < best_dist) {
      best_dist = d;
      best = x;
    }
  }
  return best.cwiseMax(0.0);
}

// Mass, COM and rotational inertia about the COM of parts expressed in one frame (exact;
// parallel-axis theorem).
BodyPart CombineParts(const std::vector<BodyPart>& parts) {
  BodyPart total{0.0, Eigen::Vector3d::Zero(), Eigen::Matrix3d::Zero(), "", ""};
  if (parts.size() == 1) {
    total.mass = parts[0].mass;
    total.com = parts[0].com;
    total.inertia = parts[0].inertia;
    return total;
  }
  Eigen::Vector3d first_moment = Eigen::Vector3d::Zero();
  for (const BodyPart& part : parts) {
    total.mass += part.mass;
    first_moment += part.mass * part.com;
  }
  if (total.mass == 0.0) return total;
  total.com = first_moment / total.mass;
  for (const BodyPart& part : parts) {
    const Eigen::Vector3d d = part.com - total.com;
    total.inertia += part.inertia + part.mass * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
  }
  total.inertia = 0.5 * (total.inertia + total.inertia.transpose()).eval();
  return total;
}

}  // namespace

}  // namespace model_loading

using namespace model_loading;

void MultibodyModelLoader::AddFrame(LoadState& s, const std::string& link, int body,
                                    const Eigen::Isometry3d& X_body_link) {
  MultibodyModel& model = s.model;
  model.frame_index_[link] = static_cast<int>(model.frames_.size());
  model.frames_.push_back({link, body, X_body_link});
  model.body_index_[link] = body;
}

// Adds a link's mass properties to `body` (X_body_link: the link's pose in the body, null for the body's own link).
void MultibodyModelLoader::AddPart(LoadState& s, int body, const urdf::Link& link, const LinkMass& lm,
                                   const Eigen::Isometry3d* X_body_link) {
  std::vector<std::vector<BodyPart>>& parts = s.parts;
  if (lm.mass == 0.0) return;
  if (!X_body_link) {
    parts[body].push_back({lm.mass, lm.com, lm.inertia, link.name, lm.problem});
  } else {
    // Zero first: GCC 12 at -O1 warns (maybe-uninitialized) on a Matrix3d built straight from linear().
    Eigen::Matrix3d R = Eigen::Matrix3d::Zero();
    R = X_body_link->linear();
    const Eigen::Matrix3d inertia = R * lm.inertia * R.transpose();
    parts[body].push_back({lm.mass, *X_body_link * lm.com, inertia, link.name, lm.problem});
  }
}

// Physical validity is a property of the rigid body the dynamics sees. A link whose own
// <inertia> is not physical (a dummy value on a sensor, foot or base frame) is accepted, with
// a warning, when it is welded into a body whose combined inertia is physical; otherwise it is
// rejected naming the link (or repaired with LoadOptions::repair_inertia).
void MultibodyModelLoader::CheckBodyInertias(LoadState& s) {
  const std::string& ufile = s.ufile;
  const LoadOptions& options = s.options;
  const std::vector<MultibodyBody>* bodies = s.bodies.get();
  std::vector<std::vector<BodyPart>>& parts = s.parts;
  auto warn = [&](const std::string& w) { Warn(s, w); };
  for (size_t i = 0; i < bodies->size(); ++i) {
    std::vector<BodyPart>& p = parts[i];
    bool any_problem = false;
    for (const BodyPart& part : p) any_problem = any_problem || !part.problem.empty();
    if (!any_problem) continue;
    const std::string body_name = Excerpt((*bodies)[i].name);
    const bool welded = p.size() > 1;
    const BodyPart combined = CombineParts(p);
    const bool body_physical = welded && PhysicalInertiaProblem(combined.inertia, combined.mass).empty();
    for (BodyPart& part : p) {
      if (part.problem.empty()) continue;
      const std::string link = Excerpt(part.link);
      if (body_physical) {
        warn("link '" + link + "': <inertia> " + part.problem + ": accepted, because rigid body '" + body_name +
             "' (its links merged over fixed joints) has a physical combined inertia");
        continue;
      }
      if (!options.repair_inertia)
        throw std::runtime_error(
            ufile + ": link '" + link + "': <inertia> " + part.problem +
            (welded ? ", and so does rigid body '" + body_name + "' (its links merged over fixed joints)" : "") +
            "; fix it, or repair it with model_info --repair-inertia / LoadOptions::repair_inertia");
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(part.inertia);
      const Eigen::Vector3d fixed = ProjectPhysicalMoments(eig.eigenvalues());
      part.inertia = eig.eigenvectors() * fixed.asDiagonal() * eig.eigenvectors().transpose();
      warn("link '" + link + "': <inertia> " + part.problem + ": repaired to the nearest physical inertia " +
           "(principal moments " + Num3(fixed) + " kg m^2)");
    }
  }
}

// Combine the parts of each body (exact; parallel-axis theorem about the combined COM) and
// find its principal frame.
void MultibodyModelLoader::CombineBodyParts(LoadState& s) {
  std::shared_ptr<std::vector<MultibodyBody>>& bodies = s.bodies;
  const std::vector<std::vector<BodyPart>>& parts = s.parts;
  for (size_t i = 0; i < bodies->size(); ++i) {
    MultibodyBody& b = (*bodies)[i];
    const std::vector<BodyPart>& p = parts[i];
    if (!p.empty()) {
      const BodyPart total = CombineParts(p);
      b.mass = total.mass;
      b.com = total.com;
      b.inertia = total.inertia;
    }
    if (b.inertia.isZero(0.0)) {
      b.principal_moments.setZero();
      b.R_link_principal.setIdentity();
    } else {
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(b.inertia);
      b.principal_moments = eig.eigenvalues();
      b.R_link_principal = eig.eigenvectors();
      if (b.R_link_principal.determinant() < 0) b.R_link_principal.col(2) *= -1.0;
      if (b.principal_moments.minCoeff() < 0.0) {  // rounding within the tolerance
        b.principal_moments = b.principal_moments.cwiseMax(0.0);
        b.inertia = b.R_link_principal * b.principal_moments.asDiagonal() * b.R_link_principal.transpose();
      }
    }
  }
}

// Degrees of freedom in body order (matches Bullet's dof order).
void MultibodyModelLoader::IndexDegreesOfFreedom(LoadState& s) {
  MultibodyModel& model = s.model;
  const std::string& ufile = s.ufile;
  std::shared_ptr<std::vector<MultibodyBody>>& bodies = s.bodies;
  const std::vector<std::pair<double, double>>& limits = s.limits;
  int nv = 0;
  for (int i = 0; i < static_cast<int>(bodies->size()); ++i) {
    MultibodyBody& b = (*bodies)[i];
    if (b.is_virtual) model.body_index_[b.name] = i;
    if (b.joint_type != MultibodyJointType::kFixed) {
      b.v_index = nv++;
      model.joint_index_[b.joint_name] = b.v_index;
      model.joint_names_.push_back(b.joint_name);
      model.body_of_v_.push_back(i);
    }
    model.total_mass_ += b.mass;
  }
  model.nv_ = nv;
  model.nq_ = nv;  // UseQuaternionBase adds the quaternion's fourth number
  model.q_lower_.setConstant(nv, -kInf);
  model.q_upper_.setConstant(nv, kInf);
  for (int i = 0; i < static_cast<int>(bodies->size()); ++i) {
    const int k = (*bodies)[i].v_index;
    if (k >= 0) {
      model.q_lower_[k] = limits[i].first;
      model.q_upper_[k] = limits[i].second;
    }
  }
  model.bodies_ = bodies;
  if (model.floating_base_ == FloatingBaseType::kPlanar) CheckPlanarJoints(model, ufile);
}

}  // namespace rome
