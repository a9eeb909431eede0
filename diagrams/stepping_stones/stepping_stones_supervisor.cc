#include "diagrams/stepping_stones/stepping_stones_supervisor.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "diagrams/stepping_stones/stepping_stones_outputs_system.h"
#include "systems/multibody/contact_dynamics.h"
#include "systems/multibody/multibody_kinematics.h"
#include "systems/plants/contact_plant.h"

namespace rome {

namespace {
// The plant's contact modes (ContactModeGraph::AlternatingSingleSupport).
constexpr int kLeftStance = ContactModeGraph::SingleSupportMode::kLeftStance;
constexpr int kRightStance = ContactModeGraph::SingleSupportMode::kRightStance;
// Discrete-state layout.
constexpr int kMode = 0, kStanceX = 1, kStanceZ = 2, kStone = 3, kSteps = 4, kPhiF = 5, kComFz = 6, kParams = 7;
constexpr int kLastUdes = kParams + SteppingStonesOutputsSystem::kNumStepParameters, kLastLdes = kLastUdes + 1,
              kLastVz = kLastUdes + 2, kPostureFailures = kLastUdes + 3, kStepStart = kLastUdes + 4,
              kInitialized = kLastUdes + 5, kSize = kLastUdes + 6;
}  // namespace

struct SteppingStonesSupervisor::Scratch {
  explicit Scratch(std::shared_ptr<const MultibodyModel> model, const PreImpactPostureParams& p)
      : ws(*model), optimizer(std::make_shared<PreImpactPostureOptimizer>(model, p)) {}
  MultibodyWorkspace ws;
  std::shared_ptr<PreImpactPostureOptimizer> optimizer;  // keeps its previous solution (fallback)
  std::vector<StepRecord> steps;
  // A branch of a simulation (Context::Clone) gets its own optimiser, with the same previous solution.
  Scratch(const Scratch& other)
      : ws(other.ws), optimizer(std::make_shared<PreImpactPostureOptimizer>(*other.optimizer)), steps(other.steps) {}
  Scratch& operator=(const Scratch&) = delete;
};

SteppingStonesSupervisor::SteppingStonesSupervisor(std::string name, std::shared_ptr<const MultibodyModel> model,
                                                   Terrain terrain, SteppingStonesSupervisorParams params)
    : LeafSystem(std::move(name)), model_(std::move(model)), terrain_(std::move(terrain)), params_(params) {
  if (!model_->is_planar())
    ThrowError("robot '" + model_->name() + "' is not planar; the stepping-stones supervisor needs a planar model");
  if (terrain_.is_flat()) ThrowError("needs a stepping-stone terrain (use evenly spaced stones for flat ground)");
  if (!(params_.update_period_s > 0))
    ThrowError("parameter update_period_s must be positive, got " + std::to_string(params_.update_period_s) + " s");
  if (params_.max_steps < 1)
    ThrowError("parameter max_steps must be at least 1, got " + std::to_string(params_.max_steps));
  if (!(params_.max_com_foot_distance_m > 0))
    ThrowError("parameter supervisor.max_com_foot_distance_m must be positive (infinity: no cap), got " +
               std::to_string(params_.max_com_foot_distance_m) + " m");
  if (!(params_.walking_com_height_m > 0))
    ThrowError("parameter walking_com_height_m must be positive, got " + std::to_string(params_.walking_com_height_m) +
               " m");
  contact_[0] = model_->ContactIndex("left_foot");
  contact_[1] = model_->ContactIndex("right_foot");
  for (int side = 0; side < 2; ++side) {
    const ContactInfo& info = model_->contacts()[contact_[side]];
    // The foothold is the contact frame origin (the point, the sole midpoint); L_y is taken about the point foot, or
    // about the foot link's inboard joint (the ankle) of a line/flat foot, where the stance torque is 0.
    foot_point_[side] = info.frame_origin;
    pivot_is_foot_[side] = info.type == ContactType::kPoint;
    pivot_point_[side] = pivot_is_foot_[side] ? info.frame_origin : Eigen::Vector3d::Zero();
  }
  const int nv = model_->nv();
  DeclareInputPort("state", 2 * nv);
  DeclareTypedInputPort<int>("mode");
  DeclareInputPort("u_des", 1);
  DeclareInputPort("L_des", 1);
  DeclareDiscreteState(Eigen::VectorXd::Zero(kSize));
  DeclarePeriodicDiscreteUpdate(params_.update_period_s, 0.0,
                                [this](const LeafContext& c, Eigen::VectorXd* next) { return Update(c, next); });
  DeclareEventUpdate("impact", EventTrigger::AnyGuard(), [this](const LeafContext& c, const EventRecord&, State* next) {
    return ImpactUpdate(c, &next->discrete);
  });
  // Outputs read the committed step (discrete state); the COM outputs also read the plant state.
  const Feedthrough plant_state = Feedthrough::From({0});
  DeclareOutputPort(
      "com_state", {"x", "z", "vx", "vz"}, [this](const LeafContext& c, Eigen::VectorXd* y) { *y = ComState(c); },
      plant_state);
  DeclareOutputPort(
      "angular_momentum", {"L"}, [this](const LeafContext& c, Eigen::VectorXd* y) { ComState(c, &(*y)[0]); },
      plant_state);
  DeclareOutputPort(
      "com_vertical_state", {"z", "vz"},
      [this](const LeafContext& c, Eigen::VectorXd* y) {
        const Eigen::Vector4d com = ComState(c);
        *y << com[1], com[3];
      },
      plant_state);
  DeclareOutputPort(
      "step", {"l", "h"},
      [this](const LeafContext& c, Eigen::VectorXd* y) {
        const StepOutputParameters step = step_parameters(Committed(c));
        *y << step.step_length, step.step_height;
      },
      Feedthrough::None());
  DeclareOutputPort(
      "pre_impact_com_height", {"z"},
      [this](const LeafContext& c, Eigen::VectorXd* y) { (*y)[0] = Committed(c)[kComFz]; }, Feedthrough::None());
  DeclareTypedOutputPort<StepOutputParameters>(
      "step_parameters", [this](const LeafContext& c, StepOutputParameters* y) { *y = step_parameters(Committed(c)); },
      Feedthrough::None());
  DeclareOutputPort(
      "stance_foot", {"x", "z"},
      [this](const LeafContext& c, Eigen::VectorXd* y) {
        const Eigen::VectorXd& xd = Committed(c);
        *y << xd[kStanceX], xd[kStanceZ];
      },
      Feedthrough::None());
  DeclareOutputPort(
      "stone", {"index"}, [this](const LeafContext& c, Eigen::VectorXd* y) { (*y)[0] = Committed(c)[kStone]; },
      Feedthrough::None());
}

const Eigen::VectorXd& SteppingStonesSupervisor::Committed(const LeafContext& context) const {
  const Eigen::VectorXd& xd = context.discrete_state();
  if (xd[kInitialized] == 0.0)
    ThrowError(
        "the first step is not set up: call SetSteppingStonesInitialState(diagram, params, context) before simulating "
        "(SteppingStonesSupervisor::Initialize for a supervisor in a diagram of your own)");
  return xd;
}

StepOutputParameters SteppingStonesSupervisor::step_parameters(const Eigen::VectorXd& xd) {
  return SteppingStonesOutputsSystem::UnpackStepParameters(
      xd.segment(kParams, SteppingStonesOutputsSystem::kNumStepParameters));
}

std::any SteppingStonesSupervisor::AllocateScratch() const { return Scratch(model_, params_.posture); }

const std::vector<StepRecord>& SteppingStonesSupervisor::steps(const LeafContext& context) const {
  return context.scratch<Scratch>().steps;
}

int SteppingStonesSupervisor::posture_failures(const LeafContext& context) const {
  return static_cast<int>(context.discrete_state()[kPostureFailures]);
}

int SteppingStonesSupervisor::stance_mode(const LeafContext& context) const {
  return static_cast<int>(context.discrete_state()[kMode]);
}
int SteppingStonesSupervisor::stone(const LeafContext& context) const {
  return static_cast<int>(context.discrete_state()[kStone]);
}
int SteppingStonesSupervisor::num_steps(const LeafContext& context) const {
  return static_cast<int>(context.discrete_state()[kSteps]);
}
Eigen::Vector2d SteppingStonesSupervisor::stance_foot(const LeafContext& context) const {
  return Eigen::Vector2d(context.discrete_state()[kStanceX], context.discrete_state()[kStanceZ]);
}
StepOutputParameters SteppingStonesSupervisor::step_parameters(const LeafContext& context) const {
  return step_parameters(context.discrete_state());
}
double SteppingStonesSupervisor::pre_impact_com_height(const LeafContext& context) const {
  return context.discrete_state()[kComFz];
}

void SteppingStonesSupervisor::ComRelative(const LeafContext& context, const Eigen::VectorXd& xd,
                                           const Eigen::VectorXd& x, Eigen::Vector4d* com, double* L) const {
  auto& ws = context.scratch<Scratch>().ws;
  const int nv = model_->nv();
  const auto q = x.head(nv);
  const auto v = x.tail(nv);
  const Eigen::Vector3d p = CalcComPosition(*model_, ws, q);
  const Eigen::Vector3d pd = CalcComVelocity(*model_, ws, q, v);
  const Vector6d h = CalcCentroidalMomentum(*model_, ws, q, v);
  const double rx = p.x() - xd[kStanceX], rz = p.z() - xd[kStanceZ];
  *com << rx, rz, pd.x(), pd.z();
  // Eq. (7): L about the stance pivot = centroidal angular momentum + r × m v, per unit mass (y component).
  // A point foot is its own pivot (the committed stance foot); a line/flat foot's ankle is measured.
  const int stance = static_cast<int>(xd[kMode]) == 0 ? 0 : 1;
  const Eigen::Vector3d a =
      pivot_is_foot_[stance]
          ? Eigen::Vector3d(xd[kStanceX], 0.0, xd[kStanceZ])
          : CalcPointPosition(*model_, ws, q, model_->contacts()[contact_[stance]].body, pivot_point_[stance]);
  *L = (p.z() - a.z()) * pd.x() - (p.x() - a.x()) * pd.z() + h[1] / model_->total_mass();
}

Eigen::Vector4d SteppingStonesSupervisor::ComState(const LeafContext& context, double* L) const {
  Eigen::Vector4d com;
  double momentum;
  ComRelative(context, Committed(context), EvalInput(context, 0), &com, &momentum);
  if (L) *L = momentum;
  return com;
}

Eigen::Vector3d SteppingStonesSupervisor::FootPosition(MultibodyWorkspace& ws,
                                                       const Eigen::Ref<const Eigen::VectorXd>& q, int side) const {
  return CalcPointPosition(*model_, ws, q, model_->contacts()[contact_[side]].body, foot_point_[side]);
}

void SteppingStonesSupervisor::Initialize(LeafContext& context, const Eigen::VectorXd& x, int mode) const {
  if (mode != kLeftStance && mode != kRightStance)
    ThrowError("Initialize: mode must be 0 (left stance) or 1 (right stance), got " + std::to_string(mode));
  if (x.size() != 2 * model_->nv())
    ThrowError("Initialize: plant state has size " + std::to_string(x.size()) + ", expected " +
               std::to_string(2 * model_->nv()));
  auto& ws = context.scratch<Scratch>().ws;
  const Eigen::Vector3d foot = FootPosition(ws, x.head(model_->nv()), mode == kLeftStance ? 0 : 1);
  const int stone = terrain_.StoneAt(foot.x(), 1e-9);
  if (stone < 0)
    ThrowError("the initial stance foot at x = " + std::to_string(foot.x()) +
               " m is not on any stone; the robot starts standing on the first stone");
  if (stone + 1 >= static_cast<int>(terrain_.stones().size()))
    ThrowError("the initial stance foot is on the last stone (" + std::to_string(stone) +
               "); there is no next stone to step to");
  Eigen::VectorXd& xd = context.get_mutable_discrete_state();
  xd.setZero();
  xd[kMode] = mode;
  xd[kStanceX] = foot.x();
  xd[kStanceZ] = foot.z();
  xd[kStone] = stone;
  xd[kStepStart] = context.time();
  xd[kInitialized] = 1.0;
  PlanStep(context, x, mode, &xd, context.time());
}

double PreImpactComHeightRequest(const SteppingStonesSupervisorParams& params, double l, double h) {
  // The COM sits ε l ahead of the stance foot and (1 − ε) l behind the landing foot, z above the stance foot and
  // z − h above the landing foot: z is capped so that both distances stay within the reach R.
  const double reach = params.max_com_foot_distance_m;
  const double to_stance = params.impact_fraction * std::abs(l),
               to_landing = (1.0 - params.impact_fraction) * std::abs(l);
  if (!(reach > std::max(to_stance, to_landing)))
    throw std::invalid_argument("SteppingStonesSupervisorParams: supervisor.max_com_foot_distance_m = " +
                                std::to_string(reach) + " m leaves no COM height for a " + std::to_string(l) +
                                " m step (the pre-impact COM is " + std::to_string(std::max(to_stance, to_landing)) +
                                " m ahead of or behind a foot; expected a distance above that)");
  const double nominal = params.walking_com_height_m + std::min(h, 0.0);
  const double stance_cap = std::sqrt(reach * reach - to_stance * to_stance);
  const double landing_cap = h + std::sqrt(reach * reach - to_landing * to_landing);
  return std::min({nominal, stance_cap, landing_cap});
}

void SteppingStonesSupervisor::PlanStep(const LeafContext& context, const Eigen::VectorXd& x, int mode,
                                        Eigen::VectorXd* xd, double time) const {
  Scratch& s = context.scratch<Scratch>();
  const int next_stone = static_cast<int>((*xd)[kStone]) + 1;
  const auto& stones = terrain_.stones();
  const double l = stones[next_stone].x_center_m - (*xd)[kStanceX];
  const double h = stones[next_stone].top_height_m - (*xd)[kStanceZ];
  const int stance = mode == kLeftStance ? 0 : 1, swing = 1 - stance;
  PreImpactPostureRequest request;
  request.stance_contact = model_->contacts()[contact_[stance]].name;
  request.swing_contact = model_->contacts()[contact_[swing]].name;
  request.step_length_m = l;
  request.step_height_m = h;
  request.com_height_m = PreImpactComHeightRequest(params_, l, h);
  const PreImpactPosture posture = s.optimizer->Solve(request);
  if (!posture.success) (*xd)[kPostureFailures] += 1;
  (*xd)[kPhiF] = posture.torso_pitch_rad;
  (*xd)[kComFz] = posture.com_height_m;
  const int nv = model_->nv();
  // α_0 relative to the new stance foot.
  const double com_x0 = CalcComPosition(*model_, s.ws, x.head(nv)).x() - (*xd)[kStanceX];
  const Eigen::Vector3d sw = FootPosition(s.ws, x.head(nv), swing);
  StepOutputParameters step;
  step.phi_0 = x[torso_pitch_index_];
  step.phi_f = posture.torso_pitch_rad;
  step.p_com_x0 = com_x0;
  step.p_sw0_x = sw.x() - (*xd)[kStanceX];
  step.p_sw0_z = sw.z() - (*xd)[kStanceZ];
  step.step_length = l;
  step.step_height = h;
  step.impact_fraction = params_.impact_fraction;
  step.step_start_time = time;
  step.step_duration = params_.nominal_step_duration_s;
  xd->segment(kParams, SteppingStonesOutputsSystem::kNumStepParameters) =
      SteppingStonesOutputsSystem::PackStepParameters(step);
}

void SteppingStonesSupervisor::ApplyImpact(const LeafContext& context, const Eigen::VectorXd& x, int mode,
                                           Eigen::VectorXd* xd_ptr, StepRecord* rec) const {
  Eigen::VectorXd& xd = *xd_ptr;
  Scratch& s = context.scratch<Scratch>();
  const int nv = model_->nv();
  const int stance = mode == kLeftStance ? 0 : 1;
  const Eigen::Vector3d foot = FootPosition(s.ws, x.head(nv), stance);
  const int stone = terrain_.NearestStone(foot.x());  // the plant already ended the run if it is off every stone
  if (rec != nullptr) {
    rec->start_time_s = xd[kStepStart];
    rec->duration_s = context.time() - xd[kStepStart];
    const StepOutputParameters step = SteppingStonesOutputsSystem::UnpackStepParameters(
        xd.segment(kParams, SteppingStonesOutputsSystem::kNumStepParameters));
    rec->step_length_m = step.step_length;
    rec->step_height_m = step.step_height;
    rec->pre_impact_com_vz_mps = xd[kLastVz];
    rec->u_des_mps = xd[kLastUdes];
    rec->L_des = xd[kLastLdes];
    rec->stone = stone;
    rec->planned_stone = static_cast<int>(xd[kStone]) + 1;
    // Measured to the planned stone: a touchdown on another stone is an error of a whole step, not a small one.
    rec->foothold_error_m = std::abs(
        foot.x() -
        terrain_.stones()[std::min(rec->planned_stone, static_cast<int>(terrain_.stones().size()) - 1)].x_center_m);
    const Eigen::Vector3d p = CalcComPosition(*model_, s.ws, x.head(nv));
    const Eigen::Vector3d pd = CalcComVelocity(*model_, s.ws, x.head(nv), x.tail(nv));
    const Vector6d hG = CalcCentroidalMomentum(*model_, s.ws, x.head(nv), x.tail(nv));
    const Eigen::Vector3d a =
        CalcPointPosition(*model_, s.ws, x.head(nv), model_->contacts()[contact_[stance]].body, pivot_point_[stance]);
    rec->post_impact_momentum = (p.z() - a.z()) * pd.x() - (p.x() - a.x()) * pd.z() + hG[1] / model_->total_mass();
  }
  xd[kMode] = mode;
  xd[kStanceX] = foot.x();
  xd[kStanceZ] = foot.z();
  xd[kStone] = stone;
  xd[kSteps] += 1;
  xd[kStepStart] = context.time();
  const int before = static_cast<int>(xd[kPostureFailures]);
  if (stone + 1 < static_cast<int>(terrain_.stones().size())) PlanStep(context, x, mode, &xd, context.time());
  if (rec != nullptr) rec->posture_ok = static_cast<int>(xd[kPostureFailures]) == before;
}

EventStatus SteppingStonesSupervisor::Update(const LeafContext& context, Eigen::VectorXd* next) const {
  Committed(context);  // a forgotten initial state is reported here if no output was evaluated before
  const Eigen::VectorXd& x = EvalInput(context, 0);
  Eigen::VectorXd& xd = *next;
  Eigen::Vector4d com;
  double L;
  ComRelative(context, xd, x, &com, &L);
  xd[kLastUdes] = EvalInput(context, 2)[0];
  xd[kLastLdes] = EvalInput(context, 3)[0];
  xd[kLastVz] = com[3];
  if (com[1] < params_.min_com_height_m)
    return EventStatus::Failed(
        "robot fell: COM " + std::to_string(com[1]) +
        " m above the stance foot, below min_com_height_m = " + std::to_string(params_.min_com_height_m) + " m");
  return EventStatus::Succeeded();
}

EventStatus SteppingStonesSupervisor::ImpactUpdate(const LeafContext& context, Eigen::VectorXd* next) const {
  const int mode = EvalTypedInput<int>(context, 1);
  Eigen::VectorXd& xd = *next;
  // Flight (mode 2), or a touchdown from flight onto the committed stance foot: no new step.
  if ((mode != kLeftStance && mode != kRightStance) || mode == static_cast<int>(xd[kMode]))
    return EventStatus::Succeeded();
  // The swing foot touched down: the new stance foot is on the next stone.
  StepRecord rec;
  ApplyImpact(context, EvalInput(context, 0), mode, &xd, &rec);
  context.scratch<Scratch>().steps.push_back(rec);
  // A step counts only on the planned stone (a touchdown back on the stance stone, or beyond the next one, fails).
  if (rec.stone != rec.planned_stone)
    return EventStatus::Failed("robot missed its stone: touched down on stone " + std::to_string(rec.stone) +
                               " at t = " + std::to_string(context.time()) + " s, " +
                               std::to_string(100.0 * rec.foothold_error_m) +
                               " cm from the centre of the planned stone " + std::to_string(rec.planned_stone));
  if (static_cast<int>(xd[kSteps]) >= params_.max_steps)
    return EventStatus::ReachedTermination("completed " + std::to_string(params_.max_steps) + " steps");
  if (rec.stone + 1 >= static_cast<int>(terrain_.stones().size()))
    return EventStatus::ReachedTermination("completed: the robot reached the last stone");
  return EventStatus::Succeeded();
}

}  // namespace rome
