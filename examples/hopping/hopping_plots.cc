#include "examples/hopping/hopping_plots.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <utility>

#include "systems/visualization/plot.h"
#include "systems/visualization/stick_figure.h"

namespace rome::examples {

namespace {

// Jump / Flight / Landing shading (HoppingSample::domain; the reference's settle phase before the first hop is its
// landing domain) behind a plot of the whole run: one filled rectangle per stretch of a domain, from
// y_low to y_high (a NaN row starts the next rectangle).
std::vector<visualization::Series> PhaseShading(const std::vector<HoppingSample>& samples, double y_low,
                                                double y_high) {
  std::vector<visualization::Series> shade{
      {"Jump", {}, {}, "filledcurves closed fs transparent solid 0.15 noborder lc rgb '#d04040'"},
      {"Flight", {}, {}, "filledcurves closed fs transparent solid 0.15 noborder lc rgb '#4060d0'"},
      {"Landing, settle", {}, {}, "filledcurves closed fs transparent solid 0.15 noborder lc rgb '#30a030'"}};
  size_t start = 0;
  for (size_t k = 1; k <= samples.size(); ++k) {
    if (k < samples.size() && samples[k].domain == samples[start].domain) continue;
    const int domain = samples[start].domain;
    if (domain >= 0 && domain < 3) {
      visualization::Series& s = shade[domain];
      const double t0 = samples[start].t, t1 = k < samples.size() ? samples[k].t : samples[k - 1].t;
      if (!s.x.empty()) s.x.push_back(NAN), s.y.push_back(NAN);
      s.x.insert(s.x.end(), {t0, t0, t1, t1}), s.y.insert(s.y.end(), {y_low, y_high, y_high, y_low});
    }
    start = k;
  }
  return shade;
}

}  // namespace

void WriteHoppingPlots(const MultibodyModel& model, const HoppingRunResult& run, const std::string& folder) {
  using visualization::PlotSpec;
  using visualization::Series;
  PlotSpec grf{"Normal GRF: robot vs spring-mass ROM", "t [s]", "F [N]", {}};
  PlotSpec com{"COM height", "t [s]", "z [m]", {}};
  PlotSpec spring{"Shin spring torque (both legs)", "t [s]", "torque [N m]", {}};
  PlotSpec spring_grf{"Robot normal GRF (both feet)", "t [s]", "F [kN]", {}};
  PlotSpec momentum{"Centroidal pitch momentum H_pitch", "t [s]", "H [N m s]", {}};
  PlotSpec pitch{"Pelvis pitch", "t [s]", "pitch [rad]", {}};
  Series robot{"robot", {}, {}, "lines lw 2 lc rgb '#202020'"}, romf{"ROM", {}, {}, "lines dt 2 lw 2 lc rgb '#e07000'"},
      comz{"COM z", {}, {}}, shin{"shin springs", {}, {}}, grf_robot{"robot GRF", {}, {}}, H{"H_pitch", {}, {}},
      theta{"pelvis pitch", {}, {}};
  auto push = [](Series& series, double t, double y) { series.x.push_back(t), series.y.push_back(y); };
  for (const HoppingSample& s : run.samples) {
    push(robot, s.t, s.grf), push(comz, s.t, s.com_z), push(shin, s.t, s.shin_torque),
        push(grf_robot, s.t, 1e-3 * s.grf);
    push(H, s.t, s.pitch_momentum), push(theta, s.t, s.pitch);
    // The ROM has no force without a plan (Flight, rest): a NaN row breaks its line there instead of bridging the gap.
    if (std::isfinite(s.rom_grf))
      push(romf, s.t, s.rom_grf);
    else if (!romf.y.empty() && std::isfinite(romf.y.back()))
      push(romf, s.t, NAN);
  }
  double f_max = 1.0;  // [N] top of the shading: above every plotted force
  for (const double f : robot.y) f_max = std::max(f_max, f);
  for (const double f : romf.y)
    if (std::isfinite(f)) f_max = std::max(f_max, f);
  // Fig. 6 of the paper from our run, over the first hop (jump start − 0.1 s to touchdown + 1 s): desired vs actual
  // outputs in Jump and Landing, energies robot vs ROM, and hop tiles.
  const double t_from = run.jump_start_s > 0 ? run.jump_start_s - 0.1 : 0.0,
               t_to = run.touchdown_s > 0 ? run.touchdown_s + 1.0 : 1e9;
  auto dashed = [](const std::string& title) { return Series{title, {}, {}, "lines dt 2 lw 2"}; };
  Series L_act{"L actual (mean of legs)", {}, {}},
      L_des = dashed("L target (plan + feedback)"), L_plan{"L ROM plan", {}, {}, "lines dt 3 lw 2 lc rgb '#e07000'"},
      cx_act{"COM x actual", {}, {}}, cx_des = dashed("COM x desired"), th_act{"pitch actual", {}, {}},
      th_des = dashed("pitch desired");
  Series ke{"robot kinetic", {}, {}}, pe{"robot potential", {}, {}}, se{"robot springs", {}, {}},
      rke = dashed("ROM kinetic"), rpe = dashed("ROM potential"), rse = dashed("ROM spring");
  for (const HoppingSample& s : run.samples) {
    if (s.t < t_from || s.t > t_to) continue;
    push(L_plan, s.t, s.leg_length_plan);
    push(L_act, s.t, s.leg_length), push(L_des, s.t, s.leg_length_d), push(cx_act, s.t, s.com_x),
        push(cx_des, s.t, s.com_x_d);
    push(th_act, s.t, s.pitch), push(th_des, s.t, s.pitch_d);
    push(ke, s.t, s.kinetic), push(pe, s.t, s.potential), push(se, s.t, s.spring_energy);
    push(rke, s.t, s.rom_kinetic), push(rpe, s.t, s.rom_potential), push(rse, s.t, s.rom_spring);
  }
  PlotSpec out_L{
      "Output: virtual leg length L(q_knee), Jump and Landing (gap: Flight)", "t [s]", "L [m]", {L_act, L_des, L_plan}};
  PlotSpec out_x{"Output: COM x, Jump and Landing", "t [s]", "x [m]", {cx_act, cx_des}};
  PlotSpec out_th{"Output: pelvis pitch, Jump and Landing", "t [s]", "pitch [rad]", {th_act, th_des}};
  PlotSpec energy{
      "Energy relative to the jump start: robot vs spring-mass ROM", "t [s]", "E [J]", {ke, pe, se, rke, rpe, rse}};
  // Hop tiles: the sagittal (x-z) projection of every link-to-parent segment and of each sole line, one frame every
  // 0.07 s from 0.1 s before the jump to 0.3 s after touchdown, side by side.
  Series sticks{"robot", {}, {}, "lines lw 2 lc rgb '#3060c0'"},
      ground{"ground", {}, {}, "lines lw 3 lc rgb '#808080'"};
  MultibodyWorkspace ws(model);
  int tile = 0;
  double next_tile = t_from;
  constexpr double kTileDx = 0.5;  // [m]
  for (const HoppingSample& s : run.samples) {
    if (s.q.size() == 0 || s.t < next_tile || s.t > std::min(t_to - 0.7, t_from + 1.5)) continue;
    next_tile = s.t + 0.07;
    visualization::AppendStickFigure(model, ws, s.q, 0, kTileDx * tile++, &sticks, &sticks);
  }
  ground.x = {-0.4, kTileDx * tile}, ground.y = {0.0, 0.0};
  PlotSpec tiles{
      "Hop tiles, sagittal projection (every 0.07 s from 0.1 s before the jump to 0.3 s after touchdown; 0.5 m apart)",
      "x [m] (+ 0.5 m per tile)",
      "z [m]",
      {ground, sticks}};
  tiles.equal_axes = true;
  tiles.width_px = 1800;
  tiles.height_px = 600;
  grf.title = "Normal GRF: robot vs spring-mass ROM, by domain";
  grf.series = PhaseShading(run.samples, 0.0, 1.05 * f_max);
  grf.series.insert(grf.series.end(), {robot, romf});
  com.series = {comz};
  spring.series = {shin};
  spring_grf.series = {grf_robot};
  momentum.series = {H};
  pitch.series = {theta};
  std::string error;
  for (auto& [spec, file] :
       {std::pair{grf, "grf.png"}, std::pair{com, "com_height.png"}, std::pair{momentum, "pitch_momentum.png"},
        std::pair{pitch, "pelvis_pitch.png"}, std::pair{out_L, "output_leg_length.png"},
        std::pair{out_x, "output_com_x.png"}, std::pair{out_th, "output_pitch.png"}, std::pair{energy, "energy.png"},
        std::pair{tiles, "hop_tiles.png"}})
    if (!visualization::WritePlot(spec, folder + "/" + file, &error))
      std::cerr << "hopping: plot " << file << ": " << error << "\n";
  // Fig. 6d: the spring torque and the force it follows, one quantity per axis, time axes aligned.
  if (!visualization::WritePanels({spring, spring_grf}, folder + "/spring_torque.png", &error))
    std::cerr << "hopping: plot spring_torque.png: " << error << "\n";
}

}  // namespace rome::examples
