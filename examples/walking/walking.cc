// walking: the 12-joint exoskeleton walks (walking paper: aSLIP + H-LIP planning composed into a 3D COM reference,
// CLF-QP with force matching). --scenario stand-to-walk (standing -> transition -> gait A), gait-change (standing -> A
// -> transition -> B) or periodic (started on gait A's orbit). The ROM plans are built offline (NLPs cached in
// --cache), the COM reference is corrected for the legs' angular momentum (CompensateCentroidalMomentum), then the
// diagram of diagrams/walking runs. Writes a CSV log (--log), a JSON summary (--summary), PNG plots (--plots DIR: the
// paper's Fig. 2 S2/L2 and 3 S2/L2 from this run's plans, COM position and velocity desired vs actual, per-foot normal
// force in its band, gait tiles) and an HTML animation (--animation). Exit 0 success, 3 failed run (fell, slipped, a
// planner failed), 1 bad input.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "diagrams/walking/pre_impact_sampler.h"
#include "diagrams/walking/walking_diagram.h"
#include "examples/common/cli.h"
#include "systems/visualization/animation.h"
#include "systems/visualization/plot.h"
#include "systems/visualization/stick_figure.h"
#include "framework/simulator.h"
#include "framework/text.h"
#include "systems/plants/contact_force_statistics.h"
#include "systems/multibody/multibody_kinematics.h"
#include "framework/interrupt.h"

using namespace rome;

namespace {

// L,T_SSP,T_DSP[,W] from --flag: `n` numbers, each inside [lo, hi] (one line naming the flag, the value and the range).
WalkingGait ParseGaitNumbers(const std::string& flag, const std::string& text, int n, const double* lo, const double* hi) {
  const std::string form = n == 4 ? "L,T_SSP,T_DSP,W" : "L,T_SSP,T_DSP";
  const std::optional<std::vector<double>> parsed = examples::ParseNumberList(text, n);
  if (!parsed) throw std::invalid_argument("walking: --" + flag + " expects " + std::to_string(n) + " numbers " + form + ", got '" + Excerpt(text, 200) + "'");
  const std::vector<double>& v = *parsed;
  const char* names[4] = {"step length L", "T_SSP", "T_DSP", "step width W"};
  const char* units[4] = {"m", "s", "s", "m"};
  for (int i = 0; i < n; ++i)
    if (!(v[i] >= lo[i] - 1e-12 && v[i] <= hi[i] + 1e-12)) {
      std::ostringstream os;
      os << "walking: --" << flag << ": " << names[i] << " = " << v[i] << " " << units[i] << " is outside [" << lo[i] << ", " << hi[i] << "] " << units[i];
      throw std::invalid_argument(os.str());
    }
  return WalkingGait{v[0], v[1], v[2], n == 4 ? v[3] : 0.0};
}

// --gait-a / --gait-b: the range the ROM planners are built and tested for (the walking issue's gait range).
WalkingGait ParseGait(const std::string& flag, const std::string& text) {
  const double lo[4] = {0.2, 0.35, 0.08, 0.2}, hi[4] = {0.45, 0.5, 0.15, 0.3};
  return ParseGaitNumbers(flag, text, 4, lo, hi);
}

// --lead-in / --start-gait L,T_SSP,T_DSP: a gait outside the range may serve as the lead-in or the start gait.
WalkingGait ParseLeadIn(const std::string& text, const std::string& flag) {
  const double lo[3] = {0.1, 0.35, 0.08}, hi[3] = {0.45, 0.6, 0.3};
  return ParseGaitNumbers(flag, text, 3, lo, hi);
}

double Percentile(std::vector<double> x, double p) {
  if (x.empty()) return 0.0;
  std::sort(x.begin(), x.end());
  return x[std::min(x.size() - 1, static_cast<size_t>(p * (x.size() - 1) + 0.5))];
}

using Columns = std::vector<std::vector<double>>;

visualization::Series Line(const std::string& title, std::vector<double> x, std::vector<double> y, const std::string& style = "lines") {
  return visualization::Series{title, std::move(x), std::move(y), style};
}

// One transition's plan on its nodes (Fig. 3 S2 sagittal, L2 lateral): the trajectory with DSP nodes blue and SSP
// nodes red, then each foot's ankle torque between its ZMP bounds (lower yellow, upper black, as the paper draws them).
void WriteTransitionPlots(const WalkingTransitionNodes& n, const std::string& dir, const std::string& name, const std::string& what) {
  if (n.t.size() == 0) return;
  const int N = static_cast<int>(n.t.size());
  auto split = [&](const Eigen::VectorXd& v, const std::string& label) {
    visualization::Series dsp = Line(label + ", DSP", {}, {}, "linespoints pt 7 ps 0.6 lc rgb 'blue'");
    visualization::Series ssp = Line(label + ", SSP", {}, {}, "linespoints pt 7 ps 0.6 lc rgb 'red'");
    for (int j = 0; j < N; ++j) {
      visualization::Series& s = n.single_support[j] ? ssp : dsp;
      if (n.single_support[j] && ssp.x.empty() && j > 0) ssp.x.push_back(n.t[j - 1]), ssp.y.push_back(v[j - 1]);  // join the domains
      s.x.push_back(n.t[j]), s.y.push_back(v[j]);
    }
    return std::vector<visualization::Series>{dsp, ssp};
  };
  auto torque_panel = [&](int foot, const Eigen::MatrixXd& u, double lower, double upper, const std::string& axis, const std::string& eq,
                          const std::string& lname, const std::string& uname) {
    std::vector<double> t(n.t.data(), n.t.data() + N), uu(N), lo(N), hi(N);
    for (int j = 0; j < N; ++j) {
      const double F = std::max(0.0, n.normal_force(foot, j));
      uu[j] = u(foot, j), lo[j] = -lower * F, hi[j] = upper * F;
    }
    const std::string side = foot == 0 ? "left" : "right";
    return visualization::PlotSpec{side + " ankle " + axis + " torque and its ZMP bounds, " + eq, "t [s]", "N m",
                              {Line("-" + lname + " F (lower bound)", t, lo, "lines lw 2 lc rgb '#d0b000'"),
                               Line(uname + " F (upper bound)", t, hi, "lines lw 2 lc rgb 'black'"), Line("u_" + axis, t, uu, "linespoints pt 7 ps 0.5 lc rgb '#3060c0'")},
                              false, 900, 300};
  };
  std::string error;
  visualization::PlotSpec xz{"footed aSLIP transition " + what + ", sagittal (Fig. 3 S2): COM x and z on the NLP's nodes", "t [s]", "m", {}, false, 900, 350};
  for (auto& series : split(n.x, "x")) xz.series.push_back(series);
  for (auto& series : split(n.z, "z")) xz.series.push_back(series);
  const std::vector<visualization::PlotSpec> sagittal = {
      xz, torque_panel(0, n.pitch_torque, n.heel_m, n.toe_m, "y (pitch)", "Eq. (10)", "L_h", "L_t"),
      torque_panel(1, n.pitch_torque, n.heel_m, n.toe_m, "y (pitch)", "Eq. (10)", "L_h", "L_t")};
  if (!visualization::WritePanels(sagittal, dir + "/" + name + "_sagittal.png", &error)) std::cerr << "plot: " << error << "\n";
  visualization::PlotSpec y{"footed H-LIP transition " + what + ", lateral (Fig. 3 L2): COM y on the QP's nodes", "t [s]", "m", {}, false, 900, 350};
  for (auto& series : split(n.y, "y")) y.series.push_back(series);
  const std::vector<visualization::PlotSpec> lateral = {
      y, torque_panel(0, n.roll_torque, n.left_m, n.right_m, "x (roll)", "Eq. (14)", "W1", "W2"),
      torque_panel(1, n.roll_torque, n.left_m, n.right_m, "x (roll)", "Eq. (14)", "W1", "W2")};
  if (!visualization::WritePanels(lateral, dir + "/" + name + "_lateral.png", &error)) std::cerr << "plot: " << error << "\n";
}

// The paper's figures from this run: Fig. 2 S2 (periodic aSLIP: z, F_z per leg, ẋ over one step) and L2 (H-LIP P2
// phase portrait with its σ₂ lines), Fig. 3 S2 / L2 (the transitions), Fig. 5a/b (COM position and velocity, desired
// vs actual), 5d (plant normal forces in their Eq. (25) band) and gait tiles (Fig. 5c) in sagittal and frontal views.
void WritePlots(const std::string& dir, const MultibodyModel& model, const WalkingPlan& rom, const WalkingPlanReport& nlp, double band, double mg,
                const std::string& scenario, double t_stop, const std::vector<double>& t, const Columns& com, const Columns& vel,
                const Columns& force, const std::vector<std::pair<double, Eigen::VectorXd>>& poses) {
  std::string err;
  auto write = [&](const std::vector<visualization::PlotSpec>& panels, const std::string& file) {
    if (!visualization::WritePanels(panels, dir + "/" + file, &err)) std::cerr << "plot: " << err << "\n";
  };
  write({{"COM desired vs actual (Fig. 5a)", "t [s]", "m",
          {Line("x", t, com[0]), Line("x desired", t, com[1]), Line("y", t, com[2]), Line("y desired", t, com[3]), Line("z", t, com[4]),
           Line("z desired", t, com[5])}}},
        "com.png");
  write({{"COM velocity desired vs actual (Fig. 5b)", "t [s]", "m/s",
          {Line("xdot", t, vel[0]), Line("xdot desired", t, vel[1]), Line("ydot", t, vel[2]), Line("ydot desired", t, vel[3]), Line("zdot", t, vel[4]),
           Line("zdot desired", t, vel[5])}}},
        "com_velocity.png");
  {  // Fig. 5d: each foot's plant normal force inside its band [(1 - c) F, (1 + c) F] +- 2 % m g (the summary's measure)
    std::vector<visualization::PlotSpec> panels;
    for (int foot = 0; foot < 2; ++foot) {
      const std::vector<double>& f = force[2 * foot];
      const std::vector<double>& ref = force[2 * foot + 1];
      std::vector<double> lo(ref.size()), hi(ref.size());
      for (size_t i = 0; i < ref.size(); ++i) lo[i] = std::max(0.0, (1 - band) * ref[i] - 0.02 * mg), hi[i] = (1 + band) * ref[i] + 0.02 * mg;
      panels.push_back({std::string(foot == 0 ? "left" : "right") + " foot: plant normal force in its band, c = " + std::to_string(band).substr(0, 4) + " (Fig. 5d)",
                        "t [s]", "N", {Line("band", t, lo, "lines lc rgb '#a0a0a0'"), Line("", t, hi, "lines lc rgb '#a0a0a0'"),
                                        Line("aSLIP F", t, ref, "lines dt 2 lc rgb 'black'"), Line("plant F_z", t, f, "lines lw 2 lc rgb '#c03030'")},
                        false, 900, 350});
    }
    write(panels, "normal_forces.png");
  }
  // Fig. 2 S2 and L2: the last whole periodic step pair (SSP, DSP, SSP, DSP) of the run, on the ROMs' plan.
  const std::vector<WalkingPlanSegment>& segs = rom.segments();
  int last = -1;
  for (int i = 0; i + 3 < static_cast<int>(segs.size()); ++i)
    if (segs[i].domain != WalkingDomain::kDoubleSupport && segs[i].lateral_nodes.cols() == 0 && segs[i + 2].lateral_nodes.cols() == 0 &&
        segs[i + 3].start_time + segs[i + 3].duration <= t_stop + 1e-9)
      last = i;
  if (last >= 0) {
    std::vector<double> tau, z, fL, fR, xd;
    for (int i = last; i < last + 2; ++i) {
      const WalkingPlanSegment& g = segs[i];
      for (int k = 0; k <= 100; ++k) {
        const double s = g.duration * k / 100.0;
        const Eigen::VectorXd x = g.sagittal.Value(s), F = g.normal_forces.Value(s);
        tau.push_back(g.start_time + s - segs[last].start_time), z.push_back(x[1]), xd.push_back(x[2]), fL.push_back(F[0]), fR.push_back(F[1]);
      }
    }
    const std::string stance = segs[last].domain == WalkingDomain::kLeftStance ? "left" : "right";
    write({{"periodic aSLIP, one step (" + stance + " stance, then double support; Fig. 2 S2): COM height", "t from the SSP start [s]", "z [m]", {Line("z", tau, z)}, false, 900, 300},
           {"per-leg vertical force", "t from the SSP start [s]", "N", {Line("F_z left", tau, fL), Line("F_z right", tau, fR)}, false, 900, 300},
           {"forward velocity", "t from the SSP start [s]", "m/s", {Line("xdot", tau, xd)}, false, 900, 300}},
          "aslip_periodic.png");
    // L2: lateral state about the stance foot of each SSP (and, in the DSP after it, about the foot that just landed).
    visualization::Series orbit = Line("H-LIP P2 orbit (two steps)", {}, {}, "lines lw 2 lc rgb '#3060c0'");
    visualization::Series pre = Line("pre-impact states", {}, {}, "points pt 7 ps 1.5 lc rgb 'red'");
    double ymax = 0;
    for (int i = last; i < last + 4; ++i) {
      const WalkingPlanSegment& g = segs[i];
      const bool dsp = g.domain == WalkingDomain::kDoubleSupport;
      const WalkingDomain stance_domain = dsp ? segs[i + 1 < static_cast<int>(segs.size()) ? i + 1 : i].domain : g.domain;
      const double foot_y = stance_domain == WalkingDomain::kLeftStance ? g.left_foothold.y() : g.right_foothold.y();
      for (int k = 0; k <= 100; ++k) {
        const WalkingReference r = rom.Sample(g.start_time + g.duration * k / 100.0);
        orbit.x.push_back(r.com_position.y() - foot_y), orbit.y.push_back(r.com_velocity.y());
        ymax = std::max(ymax, std::abs(orbit.x.back()));
      }
      if (!dsp) pre.x.push_back(orbit.x.back()), pre.y.push_back(orbit.y.back());
      orbit.x.push_back(NAN), orbit.y.push_back(NAN);
    }
    const double lambda = segs[last].lambda, sigma2 = lambda * std::tanh(lambda * segs[last].duration / 2);
    const double e = 1.2 * ymax;
    write({{"H-LIP P2 orbit about the stance foot (Fig. 2 L2), sigma_2 = " + std::to_string(sigma2).substr(0, 5) + " 1/s",
            "y - y_stance [m]", "ydot [m/s]",
            {Line("ydot = sigma_2 y (pre-impact)", {-e, e}, {-sigma2 * e, sigma2 * e}, "lines dt 2 lc rgb 'black'"),
             Line("ydot = -sigma_2 y (start of SSP)", {-e, e}, {sigma2 * e, -sigma2 * e}, "lines dt 3 lc rgb '#808080'"), orbit, pre},
            false, 800, 600}},
          "hlip_p2_portrait.png");
  }
  WriteTransitionPlots(nlp.transition_nodes, dir, "transition",
                       nlp.start_gait_used ? "standing -> start" : nlp.lead_in ? "standing -> lead-in gait" : "standing -> gait A");
  if (nlp.start_gait_used)
    WriteTransitionPlots(nlp.start_change_nodes, dir, "transition_start", nlp.lead_in ? "start -> lead-in" : "start -> gait A");
  if (scenario == "gait-change") WriteTransitionPlots(nlp.transition_b_nodes, dir, "transition_b", "gait A -> gait B");
  if (nlp.lead_in) WriteTransitionPlots(nlp.transition_b_nodes, dir, "transition_b", "lead-in -> gait A");
  // Gait tiles (Fig. 5c): 16 frames over the first 3 s (standing, the transition, the first steps), each 0.35 m (sagittal)
  // or 0.6 m (frontal) further along.
  if (!poses.empty()) {
    MultibodyWorkspace ws(model);
    visualization::Series links[2] = {Line("robot", {}, {}, "lines lw 2 lc rgb '#3060c0'"), Line("robot", {}, {}, "lines lw 2 lc rgb '#3060c0'")};
    visualization::Series soles[2] = {Line("soles", {}, {}, "lines lw 3 lc rgb '#c03030'"), Line("soles", {}, {}, "lines lw 3 lc rgb '#c03030'")};
    const double span = std::min(3.0, poses.back().first - poses.front().first);
    constexpr int kTiles = 16;
    size_t next = 0;
    for (int i = 0; i < kTiles; ++i) {
      const double when = poses.front().first + span * i / (kTiles - 1);
      while (next + 1 < poses.size() && poses[next].first < when - 1e-9) ++next;
      for (int view = 0; view < 2; ++view)
        visualization::AppendStickFigure(model, ws, poses[next].second, view, (view == 0 ? 0.35 : 0.6) * i, &links[view], &soles[view]);
    }
    const std::string when = "16 frames over the first " + std::to_string(span).substr(0, 4) + " s";
    visualization::PlotSpec sag{"gait tiles, sagittal projection (" + when + "; each 0.35 m further)", "x [m] (+ 0.35 m per tile)", "z [m]", {soles[0], links[0]}, true, 1800, 450};
    visualization::PlotSpec front{"gait tiles, frontal projection (" + when + "; each 0.6 m further)", "y [m] (+ 0.6 m per tile)", "z [m]", {soles[1], links[1]}, true, 1800, 450};
    write({sag}, "gait_tiles_sagittal.png");
    write({front}, "gait_tiles_frontal.png");
  }
}

}  // namespace

int main(int argc, char** argv) {
  examples::CommandLine cli("walking", "The exoskeleton walks from standing: aSLIP + H-LIP plan, CLF-QP with force matching (walking paper).");
  cli.Option("scenario", "stand-to-walk", "stand-to-walk (standing side by side -> transition -> --start-gait-steps of the --start-gait -> gait A; a gait faster than the --lead-in gait (shorter T_SSP or T_DSP), or with no plan from the start gait, walks --lead-in-steps of the lead-in first) | gait-change (standing -> gait A as stand-to-walk, but never through the lead-in -> transition -> gait B) | periodic (started on gait A's orbit, no transition; the start and lead-in flags do not apply)")
      .Option("gait-a", "0.30,0.40,0.10,0.25", "gait A: step length L [m], T_SSP [s], T_DSP [s], step width W [m]")
      .Option("gait-b", "0.40,0.40,0.10,0.25", "gait B (gait-change scenario)")
      .Option("steps", "10", "periodic single supports per gait after each transition (1 to 1000)")
      .Option("force-band", "0.1", "c of the force band, Eq. (25)")
      .Option("stance-stagger", "0", "standing stance: 0 = feet side by side (spec [R]; through the start gait), or a step stance with the right foot this far behind the left [m] (StandToWalkParams::StepStance; 0.40 the earlier default)")
      .Option("start-gait", "0.20,0.50,0.15", "the start gait L,T_SSP,T_DSP [m, s, s] (at gait A's W): from standing side by side, the standing transition goes into it (ours; same ranges as --lead-in)")
      .Option("start-gait-steps", "auto", "periodic steps of the start gait before the change into gait A or the lead-in (0 to 20; auto: 6 side by side, 0 from a step stance)")
      .Option("lead-in", "0.30,0.40,0.10", "the lead-in gait L,T_SSP,T_DSP [m, s, s] (at gait A's W): stand-to-walk walks it before gait A when gait A is faster or has no plan otherwise (ours; L 0.1-0.45 m, T_SSP 0.35-0.6 s, T_DSP 0.08-0.3 s)")
      .Option("lead-in-steps", "6", "periodic steps of the lead-in gait before the change to gait A (0: no lead-in; up to 20)")
      .Option("transition-ssp", "0", "lower bound of the standing transition's single-support time [s] (0: the T_SSP of the gait it goes into: the start gait's side by side, gait A's from a step stance)")
      .Option("com-heights", "0.86,0.84,0.90", "the ROM's COM height standing, and the NLPs' height range min,max [m] (ours; spec [R] 0.9 in 0.85-0.95)")
      .Option("gait-change-max-force", "1.6", "the gait-change transition NLPs (A -> B, a lead-in -> A, the start gait -> the next gait) keep each leg's vertical force <= this many m g (ours; 0: no bound, else in (1, 3])")
      .Option("periodic-max-force", "1.5", "a periodic aSLIP plan whose leg force exceeds this many m g is planned again with that bound (ours; 0: never, else in (1, 3])")
      .Option("rom-cop-margin", "0.05", "the footed aSLIP keeps its CoP this far inside the robot's heel and toe [m] (side by side, the standing transition and the start gait's change keep 0.02 m: StandToWalkParams::standing_sagittal_cop_margin_m)")
      .Option("touchdown-speed", "0.1", "the swing sole's downward speed at the planned touchdown [m/s] (spec [R] 0.1; range 0.05 to 0.5, ours)")
      .Option("clf-cost-target", "pd", "pd | min-norm: the CLF-QP cost tracks each output's PD law (ours, default) or its feedforward ÿ_d (spec §5.5 [C22]: minimum-norm μ = 0)")
      .Option("sole-torsion", "coefficient", "coefficient | corner-cone: the CLF-QP bounds each sole's yaw moment by |tau_z| <= 0.1 m f_z (ours, default) or by the contact wrench cone of its four corners (less where the CoP nears an edge or the foot carries a tangential force)")
      .Option("foothold-tolerance", "0.05", "a touchdown counts as a step only this close to its planned foothold [m] (ours)")
      .Option("plant", "hybrid", "hybrid (event-accurate rigid contact, HybridContactPlant) | bullet (Bullet's physics world at 1 kHz, BulletWorldPlant)")
      .Option("joint-limits", "on", "on | off: the Bullet plant enforces the URDF's joint limits (the hybrid plant and the CLF-QP have none)")
      .Option("seed", "1", "seed of the NLP initial guesses")
      .Option("robot", "robots/exoskeleton/exoskeleton.rome.json", "robot sidecar (a relative path is looked up in ROME's data folders; ./PATH reads the current folder)")
      .Option("cache", "walking_plans", "directory of cached ROM plans, created if missing (empty: none, every NLP is solved)")
      .Option("log", "", "CSV log file (empty: none)")
      .Option("summary", "", "JSON summary file (empty: none)")
      .Option("plots", "", "directory for PNG plots (empty: none): the paper's Fig. 2 S2/L2, 3 S2/L2 and 5a/b/d from this run, and gait tiles")
      .Option("animation", "", "FILE.html: a self-contained 3D animation of the run (three.js inlined; empty: none)");
  constexpr int kTrailingSteps = 2;
  double heights[3] = {0.86, 0.84, 0.90};
  double lead_in[3] = {0.30, 0.40, 0.10};
  int lead_in_steps = 6;
  double start_gait[3] = {0.20, 0.50, 0.15};
  int start_gait_steps = -1;  // auto
  int start_steps_used = 0;
  WalkingGait gait_a, gait_b;
  std::string scenario;
  int steps = 0;
  double band = 0.1, touchdown_speed = 0.1, stagger = 0.0, rom_margin = 0.05, transition_ssp = 0.0, foothold_tolerance = 0.05, max_force = 1.6, periodic_max_force = 1.5;
  PlantKind plant_kind = PlantKind::kHybrid;
  std::optional<PlanCache> cache;
  try {
    if (!cli.Parse(argc, argv)) return 0;
    InstallInterruptHandlers();  // SIGINT/SIGTERM: the run stops, its outputs are written, exit 128 + signal
    plant_kind = ParsePlantKind(cli.Get("plant"), "walking: --plant");
    if (cli.Get("joint-limits") != "on" && cli.Get("joint-limits") != "off")
      throw std::invalid_argument("walking: --joint-limits must be 'on' or 'off', got '" + cli.Get("joint-limits") + "'");
    scenario = cli.Get("scenario");
    if (scenario != "stand-to-walk" && scenario != "gait-change" && scenario != "periodic")
      throw std::invalid_argument("walking: --scenario must be stand-to-walk, gait-change or periodic, got '" + scenario + "'");
    gait_a = ParseGait("gait-a", cli.Get("gait-a"));
    gait_b = ParseGait("gait-b", cli.Get("gait-b"));
    if (scenario == "gait-change" && gait_a.step_width_m != gait_b.step_width_m)
      throw std::invalid_argument("walking: --gait-b: step width W = " + std::to_string(gait_b.step_width_m) + " m must equal gait A's " +
                                  std::to_string(gait_a.step_width_m) + " m (a change of W is not built)");
    steps = cli.GetInt("steps");
    if (steps < 1 || steps > 1000) throw std::invalid_argument("walking: --steps must be in [1, 1000], got " + cli.Get("steps"));
    stagger = cli.GetDouble("stance-stagger");
    if (!(stagger >= 0 && stagger <= 0.5)) throw std::invalid_argument("walking: --stance-stagger must be in [0, 0.5] m, got " + cli.Get("stance-stagger"));
    {
      const WalkingGait lead = ParseLeadIn(cli.Get("lead-in"), "lead-in");
      lead_in[0] = lead.step_length_m, lead_in[1] = lead.ssp_duration_s, lead_in[2] = lead.dsp_duration_s;
    }
    {
      const WalkingGait start = ParseLeadIn(cli.Get("start-gait"), "start-gait");
      start_gait[0] = start.step_length_m, start_gait[1] = start.ssp_duration_s, start_gait[2] = start.dsp_duration_s;
    }
    if (cli.Get("start-gait-steps") != "auto") {
      start_gait_steps = cli.GetInt("start-gait-steps");
      if (start_gait_steps < 0 || start_gait_steps > 20)
        throw std::invalid_argument("walking: --start-gait-steps must be auto or in [0, 20], got " + cli.Get("start-gait-steps"));
    }
    lead_in_steps = cli.GetInt("lead-in-steps");
    if (lead_in_steps < 0 || lead_in_steps > 20) throw std::invalid_argument("walking: --lead-in-steps must be in [0, 20], got " + cli.Get("lead-in-steps"));
    rom_margin = cli.GetDouble("rom-cop-margin");
    if (!(rom_margin >= 0 && rom_margin < 0.07)) throw std::invalid_argument("walking: --rom-cop-margin must be in [0, 0.07) m, got " + cli.Get("rom-cop-margin"));
    transition_ssp = cli.GetDouble("transition-ssp");
    if (!(transition_ssp == 0 || (transition_ssp >= 0.3 && transition_ssp <= 1.0)))
      throw std::invalid_argument("walking: --transition-ssp must be 0 or in [0.3, 1.0] s, got " + cli.Get("transition-ssp"));
    band = cli.GetDouble("force-band");
    if (!(band > 0 && band < 1)) throw std::invalid_argument("walking: --force-band: c = " + cli.Get("force-band") + " is outside (0, 1)");
    {
      std::stringstream ss(cli.Get("com-heights"));
      std::string item;
      int n = 0;
      while (std::getline(ss, item, ',')) {
        size_t used = 0;
        double value = std::nan("");
        try {
          value = std::stod(item, &used);
        } catch (const std::exception&) {
        }
        if (n < 3) heights[n] = used == item.size() ? value : std::nan("");
        ++n;
      }
      if (n != 3 || !(heights[1] >= 0.7 && heights[2] <= 1.0 && heights[1] < heights[2] && heights[0] >= heights[1] && heights[0] <= heights[2]))
        throw std::invalid_argument("walking: --com-heights expects H,MIN,MAX with 0.7 <= MIN <= H <= MAX <= 1.0 m and MIN < MAX, got '" +
                                    cli.Get("com-heights") + "'");
    }
    max_force = cli.GetDouble("gait-change-max-force");
    if (!(max_force == 0 || (max_force > 1 && max_force <= 3)))
      throw std::invalid_argument("walking: --gait-change-max-force must be 0 or in (1, 3] (m g), got " + cli.Get("gait-change-max-force"));
    periodic_max_force = cli.GetDouble("periodic-max-force");
    if (!(periodic_max_force == 0 || (periodic_max_force > 1 && periodic_max_force <= 3)))
      throw std::invalid_argument("walking: --periodic-max-force must be 0 or in (1, 3] (m g), got " + cli.Get("periodic-max-force"));
    touchdown_speed = cli.GetDouble("touchdown-speed");
    if (!(touchdown_speed >= 0.05 && touchdown_speed <= 0.5))
      throw std::invalid_argument("walking: --touchdown-speed must be in [0.05, 0.5] m/s, got " + cli.Get("touchdown-speed"));
    if (cli.Get("clf-cost-target") != "pd" && cli.Get("clf-cost-target") != "min-norm")
      throw std::invalid_argument("walking: --clf-cost-target must be 'pd' or 'min-norm', got '" + cli.Get("clf-cost-target") + "'");
    if (cli.Get("sole-torsion") != "coefficient" && cli.Get("sole-torsion") != "corner-cone")
      throw std::invalid_argument("walking: --sole-torsion must be 'coefficient' or 'corner-cone', got '" + cli.Get("sole-torsion") + "'");
    foothold_tolerance = cli.GetDouble("foothold-tolerance");
    if (!(foothold_tolerance > 0 && foothold_tolerance <= 0.5))
      throw std::invalid_argument("walking: --foothold-tolerance must be in (0, 0.5] m, got " + cli.Get("foothold-tolerance"));
    cli.CheckOutputs({"log", "summary", "animation"}, {"plots"});
    // Before any NLP runs: a cache that cannot be written is bad input, not a failed run after the solves.
    if (!cli.Get("cache").empty()) {
      cache.emplace(cli.Get("cache"));
      if (const std::string problem = cache->EnsureDirectory(); !problem.empty()) throw std::invalid_argument("walking: --cache: " + problem);
    }
  } catch (const std::exception& e) {
    std::cerr << e.what() << "\n";
    return 1;
  }

  std::shared_ptr<const MultibodyModel> model;
  try {
    model = std::make_shared<const MultibodyModel>(MultibodyModel::LoadFromSidecar(cli.Get("robot")));
  } catch (const std::exception& e) {
    std::cerr << "walking: --robot: " << e.what() << "\n";
    return 1;
  }
  const PlanCache* plan_cache = cache ? &*cache : nullptr;
  WalkingDiagramParams params;
  params.controller.force_band_halfwidth = band;
  params.swing.touchdown_velocity_mps = touchdown_speed;
  params.controller.cost_pd_feedback = cli.Get("clf-cost-target") == "pd";
  params.controller.contact.corner_wrench_cone = cli.Get("sole-torsion") == "corner-cone";
  params.bullet_plant.enable_joint_limits = cli.Get("joint-limits") == "on";
  WalkingPlanReport nlp;
  WalkingPlan plan;
  try {
    std::cout << "planning: periodic aSLIP, standing transition, footed H-LIP ...\n";
    // Side by side (stagger 0, the default) goes through the start gait; a step stance does not (StepStance).
    StandToWalkParams stand = stagger == 0 ? StandToWalkParams{} : StandToWalkParams::StepStance(stagger);
    if (start_gait_steps >= 0) stand.start_gait_steps = start_gait_steps;
    stand.start_gait_step_length_m = start_gait[0];
    stand.start_gait_ssp_duration_s = start_gait[1];
    stand.start_gait_dsp_duration_s = start_gait[2];
    stand.sole = SoleOf(*model, "left_foot");
    stand.stance_stagger_m = stagger;
    stand.lead_in_steps = lead_in_steps;
    stand.lead_in_step_length_m = lead_in[0];
    stand.lead_in_ssp_duration_s = lead_in[1];
    stand.lead_in_dsp_duration_s = lead_in[2];
    stand.sagittal_cop_margin_m = rom_margin;
    stand.transition_min_ssp_duration_s = transition_ssp;
    stand.gait_change_max_force_fraction = max_force;
    stand.periodic_max_force_fraction = periodic_max_force;
    stand.standing_height_m = heights[0];
    stand.height_min_m = heights[1];
    stand.height_max_m = heights[2];
    stand.plan_check = WalkingPoseCheck(model, params);  // a direct plan the legs cannot follow goes through the lead-in
    const auto seed = static_cast<std::uint32_t>(cli.GetInt("seed"));
    // The plan runs kTrailingSteps steps past the simulated ones, so that the last simulated steps are not the plan's
    // (and the momentum correction's) end.
    if (scenario == "periodic") plan = BuildPeriodicWalkingPlan(gait_a, steps + kTrailingSteps, seed, plan_cache, stand);
    else if (scenario == "gait-change") plan = BuildGaitChangePlan(gait_a, gait_b, steps, seed, plan_cache, &nlp, stand, steps + kTrailingSteps);
    else plan = BuildStandToWalkPlan(gait_a, steps + kTrailingSteps, seed, plan_cache, &nlp, stand);
    start_steps_used = stand.start_gait_steps;
    if (nlp.start_gait_used)
      std::cout << (stagger == 0 ? std::string("standing side by side: ") : "standing in a " + std::to_string(stagger) + " m step stance: ") << stand.start_gait_steps << " steps of the start gait (" << nlp.start_gait.step_length_m << " m, "
                << nlp.start_gait.ssp_duration_s << " s, " << nlp.start_gait.dsp_duration_s << " s), then a gait change\n";
    if (nlp.lead_in)
      std::cout << "starting with " << stand.lead_in_steps << " lead-in steps of (" << nlp.lead_in_gait.step_length_m << " m, "
                << nlp.lead_in_gait.ssp_duration_s << " s, " << nlp.lead_in_gait.dsp_duration_s << " s) and changing gait: "
                << nlp.lead_in_reason << "\n";
    else if (!nlp.lead_in_reason.empty())
      std::cout << "the lead-in " << nlp.lead_in_reason << "\n";
  } catch (const std::exception& e) {
    std::cerr << e.what() << "\n";
    return 3;
  }
  double compensation_s = 0.0;
  WalkingDiagram d;
  try {
    const auto t0 = std::chrono::steady_clock::now();
    d = BuildWalkingDiagram(model, plan, params, plant_kind);
    compensation_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  } catch (const std::exception& e) {
    std::cerr << "walking: " << e.what() << "\n";
    return 3;
  }
  std::printf("angular-momentum compensation: largest CoP shift in single support %.3f m -> %.3f m, COM correction up to %.3f m (%.2f s)\n",
              d.compensation.max_cop_shift_uncorrected_m, d.compensation.max_cop_shift_corrected_m, d.compensation.max_correction_m, compensation_s);
  // The run stops before the plan's trailing steps.
  const WalkingGait& last_gait = scenario == "gait-change" ? gait_b : gait_a;
  const double t_stop = d.plan.end_time() - kTrailingSteps * (last_gait.ssp_duration_s + last_gait.dsp_duration_s);
  // The plan's inverse dynamics (ours): the torques its single supports ask for, against the actuators' limits.
  nlohmann::json plan_torques_json = nullptr;
  try {
    const auto t0 = std::chrono::steady_clock::now();
    const WalkingPlanTorqueReport r = CheckWalkingPlanTorques(*model, d.plan, params, t_stop);
    const double solve_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (r.worst_actuator < 0) throw std::runtime_error("the plan has no single-support sample");
    const ActuatorInfo& worst = model->actuators()[r.worst_actuator];
    std::printf("plan inverse dynamics (%d single-support samples): largest torque for its limit %s %.0f of %.0f N m at t = %.3f s, "
                "peak stance F_z %.2f m g (%.2f s)\n",
                r.samples, worst.joint.c_str(), r.peak_torque_Nm[r.worst_actuator], worst.torque_limit_Nm, r.peak_time_s[r.worst_actuator],
                r.peak_normal_force_N / (model->total_mass() * 9.81), solve_s);
    std::printf("plan inverse dynamics: the stance sole needs |F_t|/F_n up to %.2f (t = %.3f s), its CoP up to %.3f m (x) / %.3f m (y) "
                "from the ankle, |M_z|/F_n up to %.3f m\n",
                r.peak_friction_ratio, r.peak_friction_ratio_time_s, r.peak_cop_offset_m.x(), r.peak_cop_offset_m.y(), r.peak_yaw_moment_ratio_m);
    if (r.worst_limit_fraction > 1.0)
      std::printf("warning: the plan asks %s for %.0f N m, above its %.0f N m limit; the CLF-QP keeps torques within the limits, so it cannot follow the plan exactly there\n", worst.joint.c_str(),
                  r.peak_torque_Nm[r.worst_actuator], worst.torque_limit_Nm);
    nlohmann::json peaks = nlohmann::json::object();
    for (int j = 0; j < model->nu(); ++j) peaks[model->actuators()[j].joint] = r.peak_torque_Nm[j];
    plan_torques_json = {{"peak_torque_Nm", peaks},
                         {"worst_joint", worst.joint},
                         {"worst_limit_fraction", r.worst_limit_fraction},
                         {"worst_time_s", r.peak_time_s[r.worst_actuator]},
                         {"peak_normal_force_N", r.peak_normal_force_N},
                         {"peak_friction_ratio", r.peak_friction_ratio},
                         {"peak_friction_ratio_time_s", r.peak_friction_ratio_time_s},
                         {"peak_cop_offset_m", {r.peak_cop_offset_m.x(), r.peak_cop_offset_m.y()}},
                         {"peak_yaw_moment_ratio_m", r.peak_yaw_moment_ratio_m},
                         {"samples", r.samples},
                         {"solve_s", solve_s}};
  } catch (const std::exception& e) {
    std::printf("warning: plan inverse dynamics not available: %s\n", e.what());
  }
  const WalkingPlan rom_plan = plan;  // the ROMs' own plan, without the momentum correction (Fig. 2 and 3)
  plan = d.plan;
  Simulator sim(*d.diagram, WalkingSimulatorConfig());
  LeafContext& pc = d.diagram->GetMutableSubsystemContext(*d.plant, sim.get_mutable_context());
  // The periodic scenario starts inside the first double support, where both feet carry load (at its first instant
  // the landed foot's planned force is 0).
  const double t_init = scenario == "periodic" ? 0.5 * gait_a.dsp_duration_s : 0.0;
  sim.get_mutable_context().SetTime(t_init);
  const Eigen::VectorXd q_init = WalkingStandingPose(*model, plan, t_init);
  d.plant->SetState(pc, q_init, scenario == "periodic" ? WalkingInitialVelocity(*model, q_init, plan, t_init) : Eigen::VectorXd::Zero(model->nv()), "double_support");

  const double mg = model->total_mass() * 9.81;
  MultibodyWorkspace ws(*model);
  const int right_foot = model->BodyIndex("right_foot");
  // The log is kept in memory and written atomically at the end: an existing log survives a failed or interrupted run.
  std::ostringstream log;
  const bool logging = !cli.Get("log").empty();
  if (logging) {
    log << "t,mode,com_x,com_y,com_z,com_des_x,com_des_y,com_des_z,fz_left,fz_right,fz_ref_left,fz_ref_right,right_ankle_x,right_ankle_y,right_ankle_z,right_ankle_des_x,right_ankle_des_y,right_ankle_des_z,right_ankle_des_ax,V,delta,qp_status,left_ankle_x,left_ankle_y,left_ankle_z,left_ankle_des_x,left_ankle_des_y,left_ankle_des_z,pelvis_roll,pelvis_pitch,pelvis_yaw,qp_fz_left,qp_fz_right,fallback_band,fallback_cop,fallback_hold,right_sole_height";
    for (const ActuatorInfo& a : model->actuators()) log << "," << CsvCell("u_" + a.joint) << "," << CsvCell("q_" + a.joint);
    log << '\n';
  }
  long tick = -1, band_ticks = 0, band_in = 0, n_err = 0;
  int touchdowns = 0, off_target_touchdowns = 0, last_mode = 1;
  double last_touchdown = -1.0, liftoff_max = 0.0, pelvis_max = 0.0, touchdown_error_max = 0.0;
  const int left_foot = model->BodyIndex("left_foot");
  Eigen::Vector2d last_fz = Eigen::Vector2d::Zero();
  Eigen::Vector3d sum_sq = Eigen::Vector3d::Zero(), err_max = Eigen::Vector3d::Zero();
  double clf_delta_max = 0.0;  // the CLF relaxation δ, largest over the control ticks
  std::vector<double> solve_us, t_s, cx, cxd, cy, cyd, cz, czd, fl, fr, fl_ref, fr_ref;
  std::vector<double> vx, vxd, vy, vyd, vz, vzd;         // COM velocity, actual and desired (Fig. 5b)
  std::vector<std::pair<double, Eigen::VectorXd>> poses;  // q every 10 ms, for the gait tiles
  std::unique_ptr<visualization::AnimationRecorder> animation;
  if (!cli.Get("animation").empty()) animation = std::make_unique<visualization::AnimationRecorder>(*model);
  const double after_first_step = plan.segments().size() > 2 ? plan.segments()[2].start_time : 0.0;
  std::vector<std::pair<double, Eigen::Matrix<double, 6, 1>>> pre_impact;  // (touchdown time, COM state just before)
  PreImpactSampler single_support_com;  // the COM state about the stance foot, extrapolated to each touchdown
  ContactForceStatistics contact;  // the plant's own forces after every integrator step and event
  sim.set_monitor([&](const Context& c) {
    const double t = c.time();
    const LeafContext& ctx = d.diagram->GetSubsystemContext(*d.plant, c);
    contact.Record(*d.plant, ctx);
    const int mode = d.plant->EvalTypedOutput<int>(ctx, "mode");
    const Eigen::VectorXd& f = d.plant->EvalOutput(ctx, "contact_forces");
    if (animation) animation->Record(t, d.plant->EvalOutput(ctx, "q"), d.plant->mode_name(mode), f);
    // A touchdown: into double support, or straight from one stance into the other. Mode 0 is left stance (the right
    // foot swings), 2 right stance. It is a step only on its planned foothold (the plan's (x, y) of that ankle).
    if ((mode == 1 && last_mode != 1) || (mode != 1 && last_mode != 1 && mode != last_mode)) {
      const bool right_landed = last_mode == 0;
      pre_impact.push_back({t, single_support_com.At(t)});
      const Eigen::VectorXd& q = d.plant->EvalOutput(ctx, "q");
      const Eigen::Vector2d ankle = CalcLinkPose(*model, ws, q, right_landed ? right_foot : left_foot).translation().head<2>();
      const WalkingReference r = plan.Sample(t);
      const double error = (ankle - (right_landed ? r.right_foothold : r.left_foothold)).norm();
      touchdown_error_max = std::max(touchdown_error_max, error);
      if (error <= foothold_tolerance) ++touchdowns;
      else ++off_target_touchdowns;
      last_touchdown = t;
    }
    if (mode != 1 && last_mode == 1) liftoff_max = std::max(liftoff_max, mode == 0 ? last_fz[1] : last_fz[0]);
    last_mode = mode;
    last_fz << f[2], f[5];
    if (mode != 1) {
      // In single support: the COM state relative to the stance foot, mirrored in y for a right stance (the lateral
      // P2 orbit alternates).
      const Eigen::VectorXd& qq = d.plant->EvalOutput(ctx, "q");
      const Eigen::VectorXd& vv = d.plant->EvalOutput(ctx, "v");
      const Eigen::Vector3d p = CalcComPosition(*model, ws, qq), v = CalcComVelocity(*model, ws, qq, vv);
      const int stance = mode == 0 ? left_foot : right_foot;
      const Eigen::Vector3d foot = CalcLinkPose(*model, ws, qq, stance).translation();
      const double mirror = mode == 0 ? 1.0 : -1.0;
      PreImpactSampler::State com_state;
      com_state << p.x() - foot.x(), mirror * (p.y() - foot.y()), p.z(), v.x(), mirror * v.y(), v.z();
      single_support_com.Record(t, com_state);
    }
    const long k = static_cast<long>(std::floor(t * 1000.0 + 1e-9));
    if (k == tick) return EventStatus::Succeeded();
    tick = k;  // once per control tick
    const Eigen::VectorXd& q = d.plant->EvalOutput(ctx, "q");
    const Eigen::Vector3d com = CalcComPosition(*model, ws, q);
    const Eigen::Vector3d com_v = CalcComVelocity(*model, ws, q, d.plant->EvalOutput(ctx, "v"));
    const WalkingReference r = plan.Sample(t);
    const LeafContext& cc = d.diagram->GetSubsystemContext(*d.controller, c);
    solve_us.push_back(1e6 * d.controller->EvalOutput(cc, "solve_time_s")[0]);
    clf_delta_max = std::max(clf_delta_max, d.controller->EvalOutput(cc, "delta")[0]);
    for (const char* a : {"base_roll", "base_pitch", "base_yaw"}) pelvis_max = std::max(pelvis_max, std::abs(q[model->VelocityIndex(a)]));
    if (t > after_first_step) {
      const Eigen::Vector3d e = (com - r.com_position).cwiseAbs();
      sum_sq += e.cwiseProduct(e);
      err_max = err_max.cwiseMax(e);
      ++n_err;
    }
    if (last_touchdown < 0 || t > last_touchdown + 0.02) {
      for (int foot = 0; foot < 2; ++foot) {
        const double fz = f[3 * foot + 2], ref = r.normal_force[foot];
        band_in += (fz >= (1 - band) * ref - 0.02 * mg && fz <= (1 + band) * ref + 0.02 * mg) ? 1 : 0;
        ++band_ticks;
      }
    }
    if (logging)
      log << t << ',' << mode << ',' << com.x() << ',' << com.y() << ',' << com.z() << ',' << r.com_position.x() << ',' << r.com_position.y() << ','
          << r.com_position.z() << ',' << f[2] << ',' << f[5] << ',' << r.normal_force[0] << ',' << r.normal_force[1];
    if (logging) {
      const Eigen::Vector3d ankle = CalcLinkPose(*model, ws, q, right_foot).translation();
      Eigen::Vector3d p, v, a;
      d.outputs->SwingFoot(1, t, p, v, a);
      log << ',' << ankle.x() << ',' << ankle.y() << ',' << ankle.z() << ',' << p.x() << ',' << p.y() << ',' << p.z() << ',' << a.x() << ',' << d.controller->EvalOutput(cc, "V")[0] << ',' << d.controller->EvalOutput(cc, "delta")[0] << ',' << d.controller->EvalOutput(cc, "qp_status")[0];
      const Eigen::Vector3d la = CalcLinkPose(*model, ws, q, left_foot).translation();
      d.outputs->SwingFoot(0, t, p, v, a);
      log << ',' << la.x() << ',' << la.y() << ',' << la.z() << ',' << p.x() << ',' << p.y() << ',' << p.z() << ',' << q[model->VelocityIndex("base_roll")] << ',' << q[model->VelocityIndex("base_pitch")] << ',' << q[model->VelocityIndex("base_yaw")];
      const Eigen::VectorXd& qf = d.controller->EvalOutput(cc, "contact_forces");
      const Eigen::VectorXd& fbk = d.controller->EvalOutput(cc, "fallbacks");
      log << ',' << qf[2] << ',' << qf[5] << ',' << fbk[0] << ',' << fbk[1] << ',' << fbk[2] << ',' << CalcContactHeight(*model, ws, q, model->ContactIndex("right_foot"));
      const Eigen::VectorXd& u = d.controller->EvalOutput(cc, "u");
      for (int j = 0; j < model->nu(); ++j) log << ',' << u[j] << ',' << q[model->actuators()[j].v_index];
      log << '\n';
    }
    t_s.push_back(t), cx.push_back(com.x()), cxd.push_back(r.com_position.x()), cy.push_back(com.y()), cyd.push_back(r.com_position.y());
    cz.push_back(com.z()), czd.push_back(r.com_position.z()), fl.push_back(f[2]), fr.push_back(f[5]);
    fl_ref.push_back(r.normal_force[0]), fr_ref.push_back(r.normal_force[1]);
    vx.push_back(com_v.x()), vy.push_back(com_v.y()), vz.push_back(com_v.z());
    vxd.push_back(r.com_velocity.x()), vyd.push_back(r.com_velocity.y()), vzd.push_back(r.com_velocity.z());
    if (k % 10 == 0) poses.emplace_back(t, q);
    if (k % 500 == 0) std::cout << "  t = " << t << " s, steps " << touchdowns << "\n";
    return EventStatus::Succeeded();
  });
  std::cout << "simulating " << t_stop << " s on the " << ToString(plant_kind) << " plant ...\n";
  const auto wall0 = std::chrono::steady_clock::now();
  const SimulatorStatus status = sim.AdvanceTo(t_stop);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  const double t_end = sim.get_context().time();
  const LeafContext& cc = d.diagram->GetSubsystemContext(*d.controller, sim.get_context());
  const bool fell = status.kind() != SimulatorStatus::Kind::kLimit && status.kind() != SimulatorStatus::Kind::kInterrupted;
  // Every single support of the plan ends in a touchdown on its foothold.
  int planned_touchdowns = 0;
  std::vector<double> transition_ends;  // end of each transition's single support (footed H-LIP segments)
  for (const WalkingPlanSegment& seg : plan.segments()) {
    if (seg.domain == WalkingDomain::kDoubleSupport || seg.start_time + seg.duration > t_stop + 1e-9) continue;
    ++planned_touchdowns;
    if (seg.lateral_nodes.cols() > 0) transition_ends.push_back(seg.start_time + seg.duration);
  }
  // Convergence after each transition: the step-to-step change (2-norm) of the pre-impact COM state, from the 5th
  // periodic touchdown after it to the next transition.
  std::vector<double> change_from_step5;
  for (size_t j = 0; j < transition_ends.size(); ++j) {
    const double begin = transition_ends[j] - 0.05, end = j + 1 < transition_ends.size() ? transition_ends[j + 1] - 0.05 : 1e9;
    std::vector<Eigen::Matrix<double, 6, 1>> states;
    for (const auto& [time, state] : pre_impact)
      if (time > begin && time < end) states.push_back(state);
    double worst = -1.0;  // states[0] is the transition's own touchdown; states[k] the k-th periodic one
    for (size_t k = 5; k < states.size(); ++k) worst = std::max(worst, (states[k] - states[k - 1]).norm());
    change_from_step5.push_back(worst);
  }
  const bool success = !fell && touchdowns >= planned_touchdowns && off_target_touchdowns == 0 && contact.violations == 0;
  Eigen::Vector3d rms = Eigen::Vector3d::Zero();
  if (n_err > 0) rms = (sum_sq / static_cast<double>(n_err)).cwiseSqrt();
  const Eigen::VectorXd& fb = d.controller->EvalOutput(cc, "fallbacks");
  nlohmann::json s;
  s["success"] = success;
  s["status_kind"] = status.kind() == SimulatorStatus::Kind::kInterrupted ? "interrupted" : fell ? "failed" : "limit";
  s["status"] = status.ToString();
  s["fell"] = fell;
  s["steps_completed"] = touchdowns;
  s["steps_planned"] = planned_touchdowns;
  s["pre_impact_state_change_from_step5"] = change_from_step5;  // per transition; -1: fewer than 6 touchdowns after it
  // Each touchdown's pre-impact COM state about the stance ankle, y mirrored in right stance: [t, x, y, z, ẋ, ẏ, ż].
  s["pre_impact_states"] = nlohmann::json::array();
  for (const auto& [time, state] : pre_impact) {
    nlohmann::json row = {time};
    for (int i = 0; i < 6; ++i) row.push_back(state[i]);
    s["pre_impact_states"].push_back(row);
  }
  s["touchdowns_off_target"] = off_target_touchdowns;
  s["largest_touchdown_error_m"] = touchdown_error_max;
  s["com_rms_error_m"] = {rms.x(), rms.y(), rms.z()};
  s["com_max_error_m"] = {err_max.x(), err_max.y(), err_max.z()};
  s["pelvis_max_orientation_error_rad"] = pelvis_max;
  s["force_in_band_fraction"] = band_ticks ? static_cast<double>(band_in) / band_ticks : 0.0;
  s["liftoff_normal_force_max_N"] = liftoff_max;
  s["contact_violations"] = contact.violations;
  s["first_contact_violation"] = contact.first_violation;
  s["min_stance_normal_force_N"] = contact.samples > 0 ? contact.min_normal_force_N : 0.0;
  s["max_friction_ratio"] = contact.max_friction_ratio;
  s["qp_infeasible_ticks"] = d.controller->EvalOutput(cc, "qp_failures")[0];
  s["qp_fallbacks"] = fb.sum();
  const Eigen::VectorXd& clf_activity = d.controller->EvalOutput(cc, "clf_activity");  // [CLF row active, solved] updates
  s["clf_row_active_fraction"] = clf_activity[1] > 0 ? clf_activity[0] / clf_activity[1] : 0.0;
  s["clf_relaxation_max"] = clf_delta_max;
  s["qp_solve_us_median"] = Percentile(solve_us, 0.5);
  s["qp_solve_us_p99"] = Percentile(solve_us, 0.99);
  auto nlp_json = [](const WalkingNlpReport& r) { return nlohmann::json{{"solve_s", r.solve_s}, {"iterations", r.iterations}, {"constraint_violation", r.violation}}; };
  s["nlp"] = {{"periodic_aslip_a", nlp_json(nlp.periodic)}, {"transition_aslip", nlp_json(nlp.transition)}};
  if (scenario == "gait-change") s["nlp"]["periodic_aslip_b"] = nlp_json(nlp.periodic_b), s["nlp"]["transition_aslip_a_to_b"] = nlp_json(nlp.transition_b);
  // stand-to-walk with a lead-in: periodic_aslip_a / transition_aslip are the lead-in gait's, then its change to gait A.
  s["lead_in"] = nullptr;
  // A lead-in that was tried, had no plan, and left the plan to the direct change from the start gait: its error.
  s["lead_in_tried"] = !nlp.lead_in && !nlp.lead_in_reason.empty() ? nlohmann::json(nlp.lead_in_reason) : nlohmann::json(nullptr);
  if (nlp.lead_in) {
    const WalkingGait& g = nlp.lead_in_gait;
    s["lead_in"] = {{"gait", {g.step_length_m, g.ssp_duration_s, g.dsp_duration_s, g.step_width_m}}, {"reason", nlp.lead_in_reason}};
    s["nlp"]["periodic_aslip_gait_a"] = nlp_json(nlp.periodic_b), s["nlp"]["transition_aslip_lead_in_to_a"] = nlp_json(nlp.transition_b);
  }
  // standing side by side: the standing transition (transition_aslip) goes into the start gait, which changes into the
  // next gait (the lead-in, or gait A).
  s["start_gait"] = nullptr;
  if (nlp.start_gait_used) {
    const WalkingGait& g = nlp.start_gait;
    s["start_gait"] = {{"gait", {g.step_length_m, g.ssp_duration_s, g.dsp_duration_s, g.step_width_m}}, {"steps", start_steps_used}};
    s["nlp"]["periodic_aslip_start_gait"] = nlp_json(nlp.periodic_start), s["nlp"]["transition_aslip_start_to_next"] = nlp_json(nlp.transition_start);
  }
  s["stance_stagger_m"] = stagger;
  s["scenario"] = scenario;
  s["angular_momentum_compensation"] = {{"max_cop_shift_uncorrected_m", d.compensation.max_cop_shift_uncorrected_m},
                                        {"max_cop_shift_corrected_m", d.compensation.max_cop_shift_corrected_m},
                                        {"max_com_correction_m", d.compensation.max_correction_m},
                                        {"solve_s", compensation_s}};
  s["plan_inverse_dynamics"] = plan_torques_json;
  s["realtime_factor"] = wall > 0 ? t_end / wall : 0.0;
  s["simulated_s"] = t_end;
  s["plant"] = ToString(plant_kind);
  if (!cli.Get("summary").empty() && !examples::WriteOutputFile("walking", cli.Get("summary"), s.dump(2) + "\n", "summary")) return 1;
  if (logging && !examples::WriteOutputFile("walking", cli.Get("log"), log.str(), "log")) return 1;
  if (!cli.Get("plots").empty()) WritePlots(cli.Get("plots"), *model, rom_plan, nlp, band, mg, scenario, t_stop, t_s, {cx, cxd, cy, cyd, cz, czd},
                                            {vx, vxd, vy, vyd, vz, vzd}, {fl, fl_ref, fr, fr_ref}, poses);
  if (animation) {
    std::string error;
    if (!animation->WriteHtml(cli.Get("animation"), "ROME walking, " + scenario, {}, &error)) std::cerr << "walking: " << error << "\n";
    else std::cout << "animation: " << cli.Get("animation") << " (" << animation->num_frames() << " frames)\n";
  }
  std::cout << (success ? "walked" : "FAILED") << ": " << status.ToString() << "\n  " << touchdowns << " steps (" << off_target_touchdowns << " touchdowns off their footholds, largest error "
            << touchdown_error_max << " m), COM RMS error (after the first step) "
            << rms.transpose() << " m, force in band " << s["force_in_band_fraction"] << ", real-time factor " << s["realtime_factor"] << "\n  plant "
            << ToString(plant_kind) << ": contact violations " << contact.violations << " (" << contact.samples << " samples)"
            << (contact.violations ? ", first: " + contact.first_violation : "") << ", max |F_t|/F_n " << contact.max_friction_ratio << "\n";
  if (status.kind() == SimulatorStatus::Kind::kInterrupted) {
    std::cout << "result: interrupted (" << status.ToString() << "); outputs written up to there\n";
    return 128 + InterruptSignal();
  }
  return success ? 0 : 3;
}
