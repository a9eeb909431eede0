#include "systems/perturbations/perturbation_params.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace rome {

namespace {

void RequireIn(const char* field, double value, double lo, double hi, bool lo_open, const char* unit) {
  if ((lo_open ? value > lo : value >= lo) && value <= hi) return;
  std::ostringstream out;
  out << "PerturbationParams: " << field << " = " << value << (*unit ? " " : "") << unit << " is outside "
      << (lo_open ? "(" : "[") << lo << ", " << hi << "]" << (*unit ? " " : "") << unit;
  throw std::invalid_argument(out.str());
}

}  // namespace

void PerturbationParams::Validate() const {
  RequireIn("mass_scale", mass_scale, 0.0, 100.0, true, "");
  RequireIn("friction_scale", friction_scale, 0.0, 100.0, true, "");
  RequireIn("stone_height_sigma_m", stone_height_sigma_m, 0.0, 1.0, false, "m");
  RequireIn("position_noise_sigma", position_noise_sigma, 0.0, 1.0, false, "m or rad");
  RequireIn("velocity_noise_sigma", velocity_noise_sigma, 0.0, 100.0, false, "m/s or rad/s");
  RequireIn("latency_samples", latency_samples, 0, 10000, false, "");
  RequireIn("torque_noise_sigma_Nm", torque_noise_sigma_Nm, 0.0, 1e4, false, "N m");
  RequireIn("sample_period_s", sample_period_s, 1e-6, 10.0, false, "s");
  if (push) push->Validate();
}

std::uint64_t PerturbationStreamSeed(std::uint64_t seed, int stream) {
  return seed * 16 + static_cast<std::uint64_t>(stream);
}

Terrain WithStoneHeightErrors(const Terrain& terrain, double sigma_m, std::uint64_t seed) {
  if (!(sigma_m >= 0.0) || !std::isfinite(sigma_m))
    throw std::invalid_argument("WithStoneHeightErrors: sigma_m = " + std::to_string(sigma_m) +
                                " m must be >= 0 and finite");
  if (terrain.is_flat() || sigma_m == 0.0) return terrain;
  std::vector<SteppingStone> stones = terrain.stones();
  for (size_t i = 1; i < stones.size(); ++i) stones[i].top_height_m += sigma_m * StandardNormalDraw(seed, 0, i);
  return Terrain::Stones(std::move(stones));
}

PerturbationBlocks AddPerturbationBlocks(DiagramBuilder& b, const PerturbationParams& params,
                                         std::shared_ptr<const MultibodyModel> model, const std::string& plant,
                                         const std::string& controller, const std::string& state_source,
                                         const std::string& state_sink) {
  params.Validate();
  PerturbationBlocks out;
  const int nq = model->nq(), nv = model->nv(), nu = model->nu();
  // Sensor path: plant.state → noise → delay → controller.state.
  const std::string state_system = state_source.empty() ? plant : state_source;
  std::string from_system = state_system, from_port = "state";
  if (params.sensor_noise()) {
    Eigen::VectorXd sigma(nq + nv);
    sigma << Eigen::VectorXd::Constant(nq, params.position_noise_sigma),
        Eigen::VectorXd::Constant(nv, params.velocity_noise_sigma);
    // A unit quaternion's entries moved by σ/2 turn it by about σ rad about each axis (2 δ(x, y, z) for w near 1).
    if (model->has_quaternion_base()) sigma.segment(3, 4) *= 0.5;
    out.sensor_noise = b.AddSystem(std::make_unique<AdditiveGaussianNoise>(
        "sensor_noise", sigma,
        AdditiveGaussianNoiseParams{params.sample_period_s, PerturbationStreamSeed(params.seed, 1)}));
    b.Connect(from_system, from_port, "sensor_noise", "u");
    // Move-assigned: GCC 12 warns falsely (-Wstringop-overflow) on assigning a literal here with the PCH.
    from_system = std::string("sensor_noise"), from_port = std::string("y");
  }
  if (params.latency_samples > 0) {
    out.sensor_latency =
        b.AddSystem(std::make_unique<DelayLine>("sensor_latency", Eigen::VectorXd::Zero(nq + nv),
                                                DelayLineParams{params.sample_period_s, params.latency_samples}));
    b.Connect(from_system, from_port, "sensor_latency", "u");
    from_system = std::string("sensor_latency"), from_port = std::string("y");
  }
  b.Connect(from_system, from_port, state_sink.empty() ? controller : state_sink, "state");
  // Actuator path: controller.u → noise → plant.u.
  if (params.torque_noise_sigma_Nm > 0.0) {
    out.torque_noise = b.AddSystem(std::make_unique<AdditiveGaussianNoise>(
        "torque_noise", Eigen::VectorXd::Constant(nu, params.torque_noise_sigma_Nm),
        AdditiveGaussianNoiseParams{params.sample_period_s, PerturbationStreamSeed(params.seed, 2)}));
    b.Connect(controller, "u", "torque_noise", "u");
    b.Connect("torque_noise", "y", plant, "u");
  } else {
    b.Connect(controller, "u", plant, "u");
  }
  if (params.push) {
    out.push = b.AddSystem(std::make_unique<ExternalPush>("push", model, *params.push));
    b.Connect(state_system, "state", "push", "state");
    b.Connect("push", "tau_external", plant, "tau_external");
  }
  return out;
}

}  // namespace rome
