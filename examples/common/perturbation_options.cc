#include "examples/common/perturbation_options.h"

#include <cmath>
#include <stdexcept>

namespace rome::examples {

void DeclarePerturbationOptions(CommandLine& cli) {
  cli.Option("push-body", "base", "link pushed by --push-force or --push-impulse (base: the floating base's link)")
      .Option("push-time", "1", "[s] start of the push")
      .Option("push-duration", "0.1", "[s] duration of the push (a constant force)")
      .Option("push-force", "0,0,0", "[N] fx,fy,fz of the push, world axes (0,0,0: no push)")
      .Option("push-impulse", "0", "[N s] forward (+x) impulse of the push, instead of --push-force (0: none)")
      .Option("mass-scale", "1", "[-] the plant's link masses and inertias / the controller's model's")
      .Option("friction-scale", "1", "[-] the plant's friction coefficients / the controller's model's")
      .Option("stone-height-error", "0", "[m] std. dev. of each stone's true height about the map (first stone exact)")
      .Option("sensor-noise", "0,0",
              "sigma_q,sigma_v: std. dev. of white noise on each q [m or rad] and v [m/s or rad/s] the controller sees")
      .Option("latency", "0", "[s] delay of the state the controller sees (a whole number of controller periods)")
      .Option("torque-noise", "0", "[N m] std. dev. of white noise added to each actuator torque");
}

PerturbationParams PerturbationsFromCommandLine(const CommandLine& cli, const MultibodyModel& model, std::uint64_t seed,
                                                double period_s) {
  PerturbationParams p;
  p.seed = seed;
  p.sample_period_s = period_s;
  p.mass_scale = cli.GetDouble("mass-scale");
  p.friction_scale = cli.GetDouble("friction-scale");
  p.stone_height_sigma_m = cli.GetDouble("stone-height-error");
  const std::vector<double> noise = cli.GetNumbers("sensor-noise", 2, "sigma_q,sigma_v");
  p.position_noise_sigma = noise[0];
  p.velocity_noise_sigma = noise[1];
  p.torque_noise_sigma_Nm = cli.GetDouble("torque-noise");
  const double latency = cli.GetDouble("latency");
  const double periods = latency / period_s;
  if (!(latency >= 0.0 && latency <= 10.0) || std::abs(periods - std::round(periods)) > 1e-6)
    throw std::invalid_argument("--latency " + cli.Get("latency") + ": must be in [0, 10] s and a whole number of " +
                                FormatNumber(period_s) + " s controller periods");
  p.latency_samples = static_cast<int>(std::round(periods));
  const std::vector<double> force = cli.GetNumbers("push-force", 3, "fx,fy,fz");
  const double impulse = cli.GetDouble("push-impulse");
  const bool has_force = force[0] != 0.0 || force[1] != 0.0 || force[2] != 0.0;
  if (has_force && impulse != 0.0)
    throw std::invalid_argument("--push-impulse " + cli.Get("push-impulse") +
                                ": give --push-force or --push-impulse, "
                                "not both (--push-force " +
                                cli.Get("push-force") + ")");
  if (has_force || impulse != 0.0) {
    ExternalPushParams push;
    push.body = cli.Get("push-body");
    if (push.body == "base") push.body = model.body(model.BodyOfVelocity(model.num_base_dofs() - 1)).name;
    if (!model.HasFrame(push.body))
      throw std::invalid_argument("--push-body " + cli.Get("push-body") + ": robot '" + model.name() +
                                  "' has no such link");
    push.start_time_s = cli.GetDouble("push-time");
    push.duration_s = cli.GetDouble("push-duration");
    if (!(push.duration_s > 0.0 && push.duration_s <= 10.0))
      throw std::invalid_argument("--push-duration " + cli.Get("push-duration") + ": must be in (0, 10] s");
    if (!(push.start_time_s >= 0.0 && push.start_time_s <= 1e6))
      throw std::invalid_argument("--push-time " + cli.Get("push-time") + ": must be in [0, 1e6] s");
    push.force_N = has_force ? Eigen::Vector3d(force[0], force[1], force[2])
                             : Eigen::Vector3d(impulse / push.duration_s, 0.0, 0.0);
    p.push = push;
  }
  p.Validate();
  return p;
}

const std::vector<std::pair<std::string, std::string>> kPerturbationParameterOptions = {
    {"mass_scale", "mass-scale"},
    {"friction_scale", "friction-scale"},
    {"stone_height_sigma_m", "stone-height-error"},
    {"position_noise_sigma", "sensor-noise"},
    {"velocity_noise_sigma", "sensor-noise"},
    {"torque_noise_sigma_Nm", "torque-noise"},
    {"start_time_s", "push-time"},
    {"duration_s", "push-duration"},
    {"force_N", "push-force"}};

PerturbationParams FlatGroundPerturbationsFromCommandLine(const CommandLine& cli, const std::string& program,
                                                          const MultibodyModel& model, std::uint64_t seed,
                                                          double period_s) {
  if (cli.GetDouble("stone-height-error") != 0.0)
    throw std::invalid_argument(program + ": --stone-height-error " + cli.Get("stone-height-error") +
                                ": this example runs on flat ground (no stones); leave it 0");
  PerturbationParams p;
  try {
    p = PerturbationsFromCommandLine(cli, model, seed, period_s);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(cli.NameTheOption(e.what(), kPerturbationParameterOptions));
  }
  return p;
}

}  // namespace rome::examples
