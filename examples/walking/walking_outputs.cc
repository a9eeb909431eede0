#include "examples/walking/walking_outputs.h"

#include <algorithm>
#include <cmath>
#include <iostream>

#include "framework/text.h"
#include "systems/multibody/contact_dynamics.h"
#include "systems/multibody/multibody_kinematics.h"
#include "systems/visualization/plot.h"
#include "systems/visualization/stick_figure.h"

namespace rome::examples {

namespace {

using Columns = std::vector<std::vector<double>>;

visualization::Series Line(const std::string& title, std::vector<double> x, std::vector<double> y,
                           const std::string& style = "lines") {
  return visualization::Series{title, std::move(x), std::move(y), style};
}

// One transition's plan on its nodes (Fig. 3 S2 sagittal, L2 lateral): the trajectory with DSP nodes blue and SSP
// nodes red, then each foot's ankle torque between its ZMP bounds (lower yellow, upper black, as the paper draws them).
void WriteTransitionPlots(const WalkingTransitionNodes& n, const std::string& dir, const std::string& name,
                          const std::string& what) {
  if (n.t.size() == 0) return;
  const int N = static_cast<int>(n.t.size());
  auto split = [&](const Eigen::VectorXd& v, const std::string& label) {
    visualization::Series dsp = Line(label + ", DSP", {}, {}, "linespoints pt 7 ps 0.6 lc rgb 'blue'");
    visualization::Series ssp = Line(label + ", SSP", {}, {}, "linespoints pt 7 ps 0.6 lc rgb 'red'");
    for (int j = 0; j < N; ++j) {
      visualization::Series& s = n.single_support[j] ? ssp : dsp;
      if (n.single_support[j] && ssp.x.empty() && j > 0)
        ssp.x.push_back(n.t[j - 1]), ssp.y.push_back(v[j - 1]);  // join the domains
      s.x.push_back(n.t[j]), s.y.push_back(v[j]);
    }
    return std::vector<visualization::Series>{dsp, ssp};
  };
  auto torque_panel = [&](int foot, const Eigen::MatrixXd& u, double lower, double upper, const std::string& axis,
                          const std::string& eq, const std::string& lname, const std::string& uname) {
    std::vector<double> t(n.t.data(), n.t.data() + N), uu(N), lo(N), hi(N);
    for (int j = 0; j < N; ++j) {
      const double F = std::max(0.0, n.normal_force(foot, j));
      uu[j] = u(foot, j), lo[j] = -lower * F, hi[j] = upper * F;
    }
    const std::string side = foot == 0 ? "left" : "right";
    return visualization::PlotSpec{side + " ankle " + axis + " torque and its ZMP bounds, " + eq,
                                   "t [s]",
                                   "torque [N m]",
                                   {Line("-" + lname + " F (lower bound)", t, lo, "lines lw 2 lc rgb '#d0b000'"),
                                    Line(uname + " F (upper bound)", t, hi, "lines lw 2 lc rgb 'black'"),
                                    Line("u_" + axis, t, uu, "linespoints pt 7 ps 0.5 lc rgb '#3060c0'")},
                                   false,
                                   900,
                                   300};
  };
  std::string error;
  visualization::PlotSpec x{"footed aSLIP transition " + what + ", sagittal (Fig. 3 S2): COM x on the NLP's nodes",
                            "t [s]",
                            "x [m]",
                            {},
                            false,
                            900,
                            300};
  visualization::PlotSpec z{"COM height z on the NLP's nodes", "t [s]", "z [m]", {}, false, 900, 300};
  for (auto& series : split(n.x, "x")) x.series.push_back(series);
  for (auto& series : split(n.z, "z")) z.series.push_back(series);
  const std::vector<visualization::PlotSpec> sagittal = {
      x, z, torque_panel(0, n.pitch_torque, n.heel_m, n.toe_m, "y (pitch)", "Eq. (10)", "L_h", "L_t"),
      torque_panel(1, n.pitch_torque, n.heel_m, n.toe_m, "y (pitch)", "Eq. (10)", "L_h", "L_t")};
  if (!visualization::WritePanels(sagittal, dir + "/" + name + "_sagittal.png", &error))
    std::cerr << "plot: " << error << "\n";
  visualization::PlotSpec y{"footed H-LIP transition " + what + ", lateral (Fig. 3 L2): COM y on the QP's nodes",
                            "t [s]",
                            "y [m]",
                            {},
                            false,
                            900,
                            350};
  for (auto& series : split(n.y, "y")) y.series.push_back(series);
  const std::vector<visualization::PlotSpec> lateral = {
      y, torque_panel(0, n.roll_torque, n.left_m, n.right_m, "x (roll)", "Eq. (14)", "W1", "W2"),
      torque_panel(1, n.roll_torque, n.left_m, n.right_m, "x (roll)", "Eq. (14)", "W1", "W2")};
  if (!visualization::WritePanels(lateral, dir + "/" + name + "_lateral.png", &error))
    std::cerr << "plot: " << error << "\n";
}

void WritePlot(const std::vector<visualization::PlotSpec>& panels, const std::string& path) {
  std::string err;
  if (!visualization::WritePanels(panels, path, &err)) std::cerr << "plot: " << err << "\n";
}

// Gait tiles (Fig. 5c): 16 frames over the first 3 s (standing, the transition, the first steps), each 0.35 m
// (sagittal) or 0.6 m (frontal) further along.
void WriteGaitTiles(const std::string& dir, const MultibodyModel& model,
                    const std::vector<std::pair<double, Eigen::VectorXd>>& poses) {
  MultibodyWorkspace ws(model);
  visualization::Series links[2] = {Line("robot", {}, {}, "lines lw 2 lc rgb '#3060c0'"),
                                    Line("robot", {}, {}, "lines lw 2 lc rgb '#3060c0'")};
  visualization::Series soles[2] = {Line("soles", {}, {}, "lines lw 3 lc rgb '#c03030'"),
                                    Line("soles", {}, {}, "lines lw 3 lc rgb '#c03030'")};
  const double span = std::min(3.0, poses.back().first - poses.front().first);
  constexpr int kTiles = 16;
  size_t next = 0;
  for (int i = 0; i < kTiles; ++i) {
    const double when = poses.front().first + span * i / (kTiles - 1);
    while (next + 1 < poses.size() && poses[next].first < when - 1e-9) ++next;
    for (int view = 0; view < 2; ++view)
      visualization::AppendStickFigure(model, ws, poses[next].second, view, (view == 0 ? 0.35 : 0.6) * i, &links[view],
                                       &soles[view]);
  }
  const std::string when = "16 frames over the first " + std::to_string(span).substr(0, 4) + " s";
  visualization::PlotSpec sag{"gait tiles, sagittal projection (" + when + "; each 0.35 m further)",
                              "x [m] (+ 0.35 m per tile)",
                              "z [m]",
                              {soles[0], links[0]},
                              true,
                              1800,
                              450};
  visualization::PlotSpec front{"gait tiles, frontal projection (" + when + "; each 0.6 m further)",
                                "y [m] (+ 0.6 m per tile)",
                                "z [m]",
                                {soles[1], links[1]},
                                true,
                                1800,
                                450};
  WritePlot({sag}, dir + "/gait_tiles_sagittal.png");
  WritePlot({front}, dir + "/gait_tiles_frontal.png");
}

// Fig. 5a/b: one panel per axis (x, y, z: actual solid, desired dashed), then the error desired − actual of all three
// in milli-units, one colour per axis. columns = {x, x_d, y, y_d, z, z_d}.
std::vector<visualization::PlotSpec> TrackingPanels(const std::vector<double>& t, const Columns& columns,
                                                    const std::string& what, const std::string& figure,
                                                    const std::string& unit, const std::string& milli_unit) {
  const char* axes[3] = {"x", "y", "z"};
  const char* colours[3] = {"#1f60c0", "#d03020", "#209040"};
  std::vector<visualization::PlotSpec> panels;
  visualization::PlotSpec error{
      what + " error, desired - actual", "t [s]", "error [" + milli_unit + "]", {}, false, 900, 300};
  for (int a = 0; a < 3; ++a) {
    const std::string colour = std::string(" lc rgb '") + colours[a] + "'";
    const std::vector<double>&actual = columns[2 * a], &desired = columns[2 * a + 1];
    std::vector<double> e(actual.size());
    for (size_t i = 0; i < e.size(); ++i) e[i] = 1e3 * (desired[i] - actual[i]);
    panels.push_back({what + " " + axes[a] + ", desired vs actual (" + figure + ")",
                      "t [s]",
                      std::string(axes[a]) + " [" + unit + "]",
                      {Line(std::string(axes[a]) + " actual", t, actual, "lines lw 2" + colour),
                       Line(std::string(axes[a]) + " desired", t, desired, "lines dt 2 lw 2 lc rgb 'black'")},
                      false,
                      900,
                      260});
    error.series.push_back(Line(std::string(axes[a]) + "_d - " + axes[a], t, e, "lines lw 1.5" + colour));
  }
  panels.push_back(error);
  return panels;
}

// The paper's figures from this run: Fig. 2 S2 (periodic aSLIP: z, F_z per leg, ẋ over one step) and L2 (H-LIP P2
// phase portrait with its σ₂ lines), Fig. 3 S2 / L2 (the transitions), Fig. 5a/b (COM position and velocity, desired
// vs actual), 5d (plant normal forces in their Eq. (25) band) and gait tiles (Fig. 5c) in sagittal and frontal views.
void WriteAllPlots(const std::string& dir, const MultibodyModel& model, const WalkingPlan& rom,
                   const WalkingPlanReport& nlp, double band, double mg, const std::string& scenario, double t_stop,
                   const std::vector<double>& t, const Columns& com, const Columns& vel, const Columns& force,
                   const std::vector<std::pair<double, Eigen::VectorXd>>& poses) {
  auto write = [&](const std::vector<visualization::PlotSpec>& panels, const std::string& file) {
    WritePlot(panels, dir + "/" + file);
  };
  write(TrackingPanels(t, com, "COM position", "Fig. 5a", "m", "mm"), "com.png");
  write(TrackingPanels(t, vel, "COM velocity", "Fig. 5b", "m/s", "mm/s"), "com_velocity.png");
  {  // Fig. 5d: each foot's plant normal force inside its band [(1 - c) F, (1 + c) F] +- 2 % m g (the summary's
     // measure)
    std::vector<visualization::PlotSpec> panels;
    for (int foot = 0; foot < 2; ++foot) {
      const std::vector<double>& f = force[2 * foot];
      const std::vector<double>& ref = force[2 * foot + 1];
      std::vector<double> lo(ref.size()), hi(ref.size());
      for (size_t i = 0; i < ref.size(); ++i)
        lo[i] = std::max(0.0, (1 - band) * ref[i] - 0.02 * mg), hi[i] = (1 + band) * ref[i] + 0.02 * mg;
      panels.push_back({std::string(foot == 0 ? "left" : "right") + " foot: plant normal force in its band, c = " +
                            std::to_string(band).substr(0, 4) + " (Fig. 5d)",
                        "t [s]",
                        "N",
                        {Line("band", t, lo, "lines lc rgb '#a0a0a0'"), Line("", t, hi, "lines lc rgb '#a0a0a0'"),
                         Line("aSLIP F", t, ref, "lines dt 2 lc rgb 'black'"),
                         Line("plant F_z", t, f, "lines lw 2 lc rgb '#c03030'")},
                        false,
                        900,
                        350});
    }
    write(panels, "normal_forces.png");
  }
  // Fig. 2 S2 and L2: the last whole periodic step pair (SSP, DSP, SSP, DSP) of the run, on the ROMs' plan.
  const std::vector<WalkingPlanSegment>& segs = rom.segments();
  int last = -1;
  for (int i = 0; i + 3 < static_cast<int>(segs.size()); ++i)
    if (segs[i].domain != WalkingDomain::kDoubleSupport && segs[i].lateral_nodes.cols() == 0 &&
        segs[i + 2].lateral_nodes.cols() == 0 && segs[i + 3].start_time + segs[i + 3].duration <= t_stop + 1e-9)
      last = i;
  if (last >= 0) {
    std::vector<double> tau, z, fL, fR, xd;
    for (int i = last; i < last + 2; ++i) {
      const WalkingPlanSegment& g = segs[i];
      for (int k = 0; k <= 100; ++k) {
        const double s = g.duration * k / 100.0;
        const Eigen::VectorXd x = g.sagittal.Value(s), F = g.normal_forces.Value(s);
        tau.push_back(g.start_time + s - segs[last].start_time), z.push_back(x[1]), xd.push_back(x[2]),
            fL.push_back(F[0]), fR.push_back(F[1]);
      }
    }
    const std::string stance = segs[last].domain == WalkingDomain::kLeftStance ? "left" : "right";
    write({{"periodic aSLIP, one step (" + stance + " stance, then double support; Fig. 2 S2): COM height",
            "t from the SSP start [s]",
            "z [m]",
            {Line("z", tau, z)},
            false,
            900,
            300},
           {"per-leg vertical force",
            "t from the SSP start [s]",
            "N",
            {Line("F_z left", tau, fL), Line("F_z right", tau, fR)},
            false,
            900,
            300},
           {"forward velocity", "t from the SSP start [s]", "m/s", {Line("xdot", tau, xd)}, false, 900, 300}},
          "aslip_periodic.png");
    // L2: lateral state about the stance foot of each SSP (and, in the DSP after it, about the foot that just landed).
    visualization::Series orbit = Line("H-LIP P2 orbit (two steps)", {}, {}, "lines lw 2 lc rgb '#3060c0'");
    visualization::Series pre = Line("pre-impact states", {}, {}, "points pt 7 ps 1.5 lc rgb 'red'");
    double ymax = 0;
    for (int i = last; i < last + 4; ++i) {
      const WalkingPlanSegment& g = segs[i];
      const bool dsp = g.domain == WalkingDomain::kDoubleSupport;
      const WalkingDomain stance_domain =
          dsp ? segs[i + 1 < static_cast<int>(segs.size()) ? i + 1 : i].domain : g.domain;
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
    write({{"H-LIP P2 orbit (Fig. 2 L2), sigma_2 = " + std::to_string(sigma2).substr(0, 5) + " 1/s",
            "y - y_stance (COM about the stance foot) [m]",
            "ydot [m/s]",
            {Line("sigma_2 line (pre-impact)", {-e, e}, {-sigma2 * e, sigma2 * e}, "lines dt 2 lc rgb 'black'"),
             Line("-sigma_2 line (SSP start)", {-e, e}, {sigma2 * e, -sigma2 * e}, "lines dt 3 lc rgb '#808080'"),
             orbit, pre},
            false,
            800,
            600}},
          "hlip_p2_portrait.png");
  }
  WriteTransitionPlots(nlp.transition_nodes, dir, "transition",
                       nlp.start_gait_used ? "standing -> start"
                       : nlp.lead_in       ? "standing -> lead-in gait"
                                           : "standing -> gait A");
  if (nlp.start_gait_used)
    WriteTransitionPlots(nlp.start_change_nodes, dir, "transition_start",
                         nlp.lead_in ? "start -> lead-in" : "start -> gait A");
  if (scenario == "gait-change" || scenario == "gait-sequence")
    WriteTransitionPlots(nlp.transition_b_nodes, dir, "transition_b", "gait A -> gait B");
  if (nlp.lead_in) WriteTransitionPlots(nlp.transition_b_nodes, dir, "transition_b", "lead-in -> gait A");
  if (!poses.empty()) WriteGaitTiles(dir, model, poses);
}

}  // namespace

WalkingRecorder::WalkingRecorder(const WalkingDiagram& walking, bool log, bool plots, bool animation)
    : d_(walking), ws_(*walking.model), logging_(log), plotting_(plots) {
  if (animation) animation_ = std::make_unique<visualization::AnimationRecorder>(*walking.model);
  if (!logging_) return;
  log_ << "t,mode,com_x,com_y,com_z,com_des_x,com_des_y,com_des_z,fz_left,fz_right,fz_ref_left,fz_ref_right,right_"
          "ankle_x,right_ankle_y,right_ankle_z,right_ankle_des_x,right_ankle_des_y,right_ankle_des_z,right_ankle_des_"
          "ax,V,delta,qp_status,left_ankle_x,left_ankle_y,left_ankle_z,left_ankle_des_x,left_ankle_des_y,left_ankle_"
          "des_z,pelvis_roll,pelvis_pitch,pelvis_yaw,qp_fz_left,qp_fz_right,fallback_band,fallback_cop,fallback_hold,"
          "right_sole_height,fallback_drift";
  for (const ActuatorInfo& a : walking.model->actuators())
    log_ << "," << CsvCell("u_" + a.joint) << "," << CsvCell("q_" + a.joint);
  log_ << '\n';
}

WalkingRunObserver WalkingRecorder::Observer() {
  return [this](const Context& c, const WalkingRunSample& s) { Record(c, s); };
}

void WalkingRecorder::Record(const Context& c, const WalkingRunSample& s) {
  const MultibodyModel& model = *d_.model;
  const Eigen::VectorXd& q = *s.q;
  const Eigen::VectorXd& f = *s.contact_forces;
  if (animation_) animation_->Record(s.t, q, d_.plant->mode_name(s.mode), f);
  if (!s.tick) return;
  const WalkingReference& r = s.reference;
  if (logging_) {
    // The CLF-QP's diagnostics (NaN for a controller without one); u is the torque the plant receives.
    const double nan = std::nan("");
    const LeafContext* cc = d_.clf_qp ? &d_.diagram->GetSubsystemContext(*d_.clf_qp, c) : nullptr;
    auto clf = [&](const char* port, int i) { return cc ? d_.clf_qp->EvalOutput(*cc, port)[i] : nan; };
    const int right_foot = model.BodyIndex("right_foot"), left_foot = model.BodyIndex("left_foot");
    log_ << s.t << ',' << s.mode << ',' << s.com.x() << ',' << s.com.y() << ',' << s.com.z() << ','
         << r.com_position.x() << ',' << r.com_position.y() << ',' << r.com_position.z() << ',' << f[2] << ',' << f[5]
         << ',' << r.normal_force[0] << ',' << r.normal_force[1];
    const Eigen::Vector3d ankle = CalcLinkPose(model, ws_, q, right_foot).translation();
    Eigen::Vector3d p, v, a;
    d_.outputs->SwingFoot(1, s.t, p, v, a);
    log_ << ',' << ankle.x() << ',' << ankle.y() << ',' << ankle.z() << ',' << p.x() << ',' << p.y() << ',' << p.z()
         << ',' << a.x() << ',' << clf("V", 0) << ',' << clf("delta", 0) << ',' << clf("qp_status", 0);
    const Eigen::Vector3d la = CalcLinkPose(model, ws_, q, left_foot).translation();
    d_.outputs->SwingFoot(0, s.t, p, v, a);
    log_ << ',' << la.x() << ',' << la.y() << ',' << la.z() << ',' << p.x() << ',' << p.y() << ',' << p.z() << ','
         << q[model.VelocityIndex("base_roll")] << ',' << q[model.VelocityIndex("base_pitch")] << ','
         << q[model.VelocityIndex("base_yaw")];
    log_ << ',' << clf("contact_forces", 2) << ',' << clf("contact_forces", 5) << ',' << clf("fallbacks", 1) << ','
         << clf("fallbacks", 2) << ',' << clf("fallbacks", 3) << ','
         << CalcContactHeight(model, ws_, q, model.ContactIndex("right_foot")) << ',' << clf("fallbacks", 0);
    const Eigen::VectorXd& u = *s.u;
    for (int j = 0; j < model.nu(); ++j) log_ << ',' << u[j] << ',' << q[model.actuators()[j].v_index];
    log_ << '\n';
  }
  if (plotting_) {
    t_.push_back(s.t);
    const double values[6] = {s.com.x(),          r.com_position.x(), s.com.y(),
                              r.com_position.y(), s.com.z(),          r.com_position.z()};
    const double rates[6] = {s.com_velocity.x(), r.com_velocity.x(), s.com_velocity.y(),
                             r.com_velocity.y(), s.com_velocity.z(), r.com_velocity.z()};
    for (int i = 0; i < 6; ++i) com_[i].push_back(values[i]), vel_[i].push_back(rates[i]);
    const double forces[4] = {f[2], r.normal_force[0], f[5], r.normal_force[1]};
    for (int i = 0; i < 4; ++i) force_[i].push_back(forces[i]);
    if (s.tick_index % 10 == 0) poses_.emplace_back(s.t, q);
  }
  if (s.tick_index % 500 == 0) std::cout << "  t = " << s.t << " s, steps " << s.steps << "\n";
}

void WalkingRecorder::WritePlots(const std::string& dir, const WalkingPlan& rom_plan, const WalkingPlanReport& nlp,
                                 const std::string& scenario, double t_stop) const {
  const MultibodyModel& model = *d_.model;
  const double band =
      d_.clf_qp ? d_.clf_qp->params().force_band_halfwidth : WalkingDiagramParams{}.controller.force_band_halfwidth;
  const auto columns = [](const std::vector<double>* c, int n) { return Columns(c, c + n); };
  WriteAllPlots(dir, model, rom_plan, nlp, band, model.total_mass() * 9.81, scenario, t_stop, t_, columns(com_, 6),
                columns(vel_, 6), columns(force_, 4), poses_);
}

}  // namespace rome::examples
