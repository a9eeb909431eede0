#pragma once
// Stick figures for gait tiles (PNG through gnuplot, systems/visualization/plot.h): a projection of the robot onto a
// vertical plane, one segment per link-to-parent joint and the outline of each contact's points.

#include <Eigen/Core>

#include "systems/visualization/plot.h"
#include "systems/multibody/multibody_model.h"
#include "systems/multibody/multibody_workspace.h"

namespace rome::visualization {

/// Appends the robot at configuration q to `links` and `soles` (gnuplot line segments, separated by NaN), projected on
/// the plane spanned by world axis `horizontal_axis` (0 = x: sagittal, 1 = y: frontal) and z, shifted by `offset_m`
/// along the horizontal. Links whose parent is massless (the virtual floating-base chain) are left out; each contact's
/// points are joined in order and closed, and joined to their link's origin by one segment to their centroid.
void AppendStickFigure(const MultibodyModel& model, MultibodyWorkspace& ws, const Eigen::VectorXd& q,
                       int horizontal_axis, double offset_m, Series* links, Series* soles);

}  // namespace rome::visualization
