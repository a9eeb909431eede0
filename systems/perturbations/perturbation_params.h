#pragma once
// What makes a simulated run differ from what its controller assumes, in one parameter struct, and the wiring of the
// perturbation blocks into a diagram between a plant and a controller:
//
//   plant.state → [sensor_noise: AdditiveGaussianNoise] → [sensor_latency: DelayLine] → controller.state
//   controller.u → [torque_noise: AdditiveGaussianNoise] → plant.u
//   plant.state → [push: ExternalPush] → plant.tau_external
//
// (a block is added only when its perturbation is on). Model mismatch (ScaleMassAndFriction, model_scaling.h) and
// stone-height errors (WithStoneHeightErrors) change what the plant is built from, not the wiring. Every random draw
// derives from `seed` (PerturbationStreamSeed), so a run is reproducible from it.

#include <cstdint>
#include <optional>
#include <string>

#include "framework/diagram.h"
#include "systems/multibody/multibody_model.h"
#include "systems/perturbations/delay_line.h"
#include "systems/perturbations/external_push.h"
#include "systems/perturbations/gaussian_noise.h"
#include "systems/plants/terrain.h"

namespace rome {

struct PerturbationParams {
  std::optional<ExternalPushParams> push;  ///< none: no push
  double mass_scale = 1.0;                 ///< [-] plant's link masses and inertias / the controller's (ours: 1)
  double friction_scale = 1.0;             ///< [-] plant's friction coefficients / the controller's (ours: 1)
  double stone_height_sigma_m = 0.0;       ///< [m] std. dev. of each stone's true height about its map height
  double position_noise_sigma = 0.0;       ///< [m or rad] std. dev. of the noise on each q the controller sees
  double velocity_noise_sigma = 0.0;       ///< [m/s or rad/s] the same on each v
  int latency_samples = 0;                 ///< sensor latency in sample periods (0: none)
  double torque_noise_sigma_Nm = 0.0;      ///< [N m] std. dev. of the noise on each actuator torque
  double sample_period_s = 1e-3;           ///< [s] noise and latency sample period (ours: the controllers' 1 kHz)
  std::uint64_t seed = 0;                  ///< every random draw above derives from it

  bool sensor_noise() const { return position_noise_sigma > 0.0 || velocity_noise_sigma > 0.0; }
  bool model_mismatch() const { return mass_scale != 1.0 || friction_scale != 1.0; }
  /// Throws std::invalid_argument naming the field and value (ranges ours): scales in (0, 100], sigmas >= 0 and
  /// finite (stone heights <= 1 m, q <= 1, v <= 100, torque <= 1e4), latency_samples in [0, 10000], sample period in
  /// [1e-6, 10] s, and push->Validate().
  void Validate() const;
};

/// Independent random streams from one seed: 1 sensor noise, 2 torque noise, 3 stone heights.
std::uint64_t PerturbationStreamSeed(std::uint64_t seed, int stream);

/// `terrain` with every stone but the first (where the robot starts) raised by sigma_m · n_i, n_i ~ N(0, 1) drawn
/// from `seed` (StandardNormalDraw); flat ground and sigma_m = 0 unchanged. Stones keep their x and length.
Terrain WithStoneHeightErrors(const Terrain& terrain, double sigma_m, std::uint64_t seed);

/// The blocks AddPerturbationBlocks added (null when off).
struct PerturbationBlocks {
  const AdditiveGaussianNoise* sensor_noise = nullptr;
  const DelayLine* sensor_latency = nullptr;
  const AdditiveGaussianNoise* torque_noise = nullptr;
  const ExternalPush* push = nullptr;
};

/// Adds the blocks of `params` to `b` and makes every connection between `plant` and `controller` that the diagram
/// would otherwise make itself: plant.state → controller.state and controller.u → plant.u, through the blocks that
/// are on. The plant needs a tau_external input when params.push is set (HybridContactPlantParams::
/// external_force_input). `model` is the controller's (sizes nq + nv, the pushed body; on a quaternion base the sensor
/// noise moves the quaternion's four entries by position_noise_sigma / 2, about that angle in rad about each axis, and
/// the controller's kinematics normalise it). `state_source`: the system whose
/// output "state" feeds the sensor path ("" = `plant`; e.g. a QuaternionToEulerState after a quaternion-base plant);
/// the push reads it too. `state_sink`: the system whose input "state" the sensor path ends in ("" = `controller`;
/// e.g. a ContactVelocityProjection in front of the controller).
PerturbationBlocks AddPerturbationBlocks(DiagramBuilder& b, const PerturbationParams& params,
                                         std::shared_ptr<const MultibodyModel> model, const std::string& plant,
                                         const std::string& controller, const std::string& state_source = "",
                                         const std::string& state_sink = "");

}  // namespace rome
