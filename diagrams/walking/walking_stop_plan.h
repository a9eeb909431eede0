#pragma once
// The walk-to-stand plan (walking issue 39, §2): the reverse of the stand-to-walk start. Standing → gait (as
// BuildGaitChangePlan), the change into the stop gait (the start gait's timing at the gait's W: short, slow steps, as
// the start walks them), stop_gait_steps steps of it, then the stop, replacing the stop gait's last double support:
//   settle (double support, after the last touchdown, 1 s): the COM comes to rest over the front ankle at the standing
//     height, or at the NLPs' height_max_m if the standing height is above it (quintics in x, z and y from the
//     touchdown's position, velocity and acceleration) and the weight moves onto the front foot; the rear foot keeps
//     at least settle_rear_force_fraction of the load until the last node, where it is unloaded and lifts;
//   step (single support on the front foot, 0.6 s): the rear foot steps beside it at the same W (no step width
//     change), the COM at rest over the front ankle;
//   shift (double support, 1 s): the COM to the midpoint between the ankles (a rest-to-rest quintic in y) and up to
//     the standing height (likewise in z), the weight back onto both feet;
//   hold (double support, 1.5 s): standing still, m g / 2 on each foot.
// The split of m (g + z̈) between the feet puts the point mass's lateral centre of pressure, y − z ÿ / (g + z̈), where
// the lateral quintics need it (clipped to the feet; reasons in docs/design-notes.md#walking-walk-to-stand).
// Sagittally the stop is this COM plan (the builder checks that its centre of pressure stays on the loaded soles);
// laterally it is one footed H-LIP QP (Eq. (11)-(15), FootedHlipTransitionPlanner with normal-force pivots and node
// heights, as the stand-to-walk transitions) over settle, step and shift on that split, from the touchdown's lateral
// state to the midpoint at rest; the hold keeps the COM there.
#include <cstdint>
#include <string>

#include "diagrams/walking/walking_diagram.h"

namespace rome {

/// The stop's durations and grid (all ours).
struct WalkToStandParams {
  int stop_gait_steps = 6;  ///< [-] steps of the stop gait before the stop (6: as the start gait's, see there)
  /// [s] settle: the COM travels about half a stop-gait step to rest; 3 × that distance / the touchdown speed keeps the
  /// quintic monotone (no backward motion) for the stop gait's ~0.3 m/s.
  double settle_duration_s = 1.0;
  /// [-] the settle's rear foot carries at least this fraction of the load until the settle's last node, where it is
  /// unloaded and lifts (ours). 0: the split alone, which unloads it as soon as the lateral centre of pressure reaches
  /// the front foot, 0.7 s early, and the plant then releases it in a double support
  /// (docs/design-notes.md#walking-walk-to-stand-rear-floor).
  double settle_rear_force_fraction = 0.05;
  double step_duration_s = 0.6;   ///< [s] the last single support (the start gait's T_SSP is 0.5 s)
  double shift_duration_s = 1.0;  ///< [s] the weight back onto both feet
  double hold_duration_s = 1.5;   ///< [s] standing still at the plan's end
  int nodes_per_phase = 21;       ///< [-] nodes of the lateral QP and of the sagittal polynomials per phase
  /// Throws std::invalid_argument "WHO: FIELD = VALUE is outside RANGE" for the first field out of its range.
  void Validate(const std::string& who = "WalkToStandParams") const;
};

/// The walk-to-stand plan above: `steps` steps of `gait` after the standing start, then the stop. The stop gait is
/// (sp.start_gait_step_length_m, sp.start_gait_ssp_duration_s, sp.start_gait_dsp_duration_s, gait W); a gait with that
/// timing walks stop.stop_gait_steps more steps of itself instead of changing. report: as BuildGaitChangePlan's (its
/// gait B is the stop gait). Throws std::invalid_argument for a bad parameter, std::runtime_error naming the problem
/// that failed (an NLP, the lateral QP, or a settle whose centre of pressure leaves the feet).
WalkingPlan BuildWalkToStandPlan(const WalkingGait& gait, int steps, std::uint32_t seed, const PlanCache* cache,
                                 WalkingPlanReport* report = nullptr, const StandToWalkParams& sp = {},
                                 const WalkToStandParams& stop = {});

}  // namespace rome
