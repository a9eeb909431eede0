#include "systems/visualization/stick_figure.h"

#include <cmath>

#include "systems/multibody/contact_dynamics.h"
#include "systems/multibody/multibody_kinematics.h"

namespace rome::visualization {

namespace {
void AppendSegment(const Eigen::Vector3d& a, const Eigen::Vector3d& b, int axis, double offset, Series* s) {
  s->x.insert(s->x.end(), {a[axis] + offset, b[axis] + offset, NAN});
  s->y.insert(s->y.end(), {a.z(), b.z(), NAN});
}
}  // namespace

void AppendStickFigure(const MultibodyModel& model, MultibodyWorkspace& ws, const Eigen::VectorXd& q,
                       int horizontal_axis, double offset_m, Series* links, Series* soles) {
  for (int k = 0; k < model.num_contacts(); ++k) {
    const int n = static_cast<int>(model.contacts()[k].points.size());
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int i = 0; i < n; ++i) centroid += CalcContactPointPosition(model, ws, q, k, i) / n;
    if (n > 0)
      AppendSegment(CalcLinkPose(model, ws, q, model.contacts()[k].body).translation(), centroid, horizontal_axis,
                    offset_m, links);
    for (int i = 0; n > 1 && i < n; ++i)
      AppendSegment(CalcContactPointPosition(model, ws, q, k, i),
                    CalcContactPointPosition(model, ws, q, k, (i + 1) % n), horizontal_axis, offset_m, soles);
  }
  for (int b = 0; b < model.num_bodies(); ++b) {
    const int p = model.bodies()[b].parent;
    if (p < 0 || model.bodies()[p].mass <= 0.0) continue;
    AppendSegment(CalcLinkPose(model, ws, q, p).translation(), CalcLinkPose(model, ws, q, b).translation(),
                  horizontal_axis, offset_m, links);
  }
}

}  // namespace rome::visualization
