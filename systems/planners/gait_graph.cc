#include "systems/planners/gait_graph.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace rome {

namespace {

constexpr double kSame = 1e-9;  // two gait coordinates this close are one grid value
const char* const kAxis[4] = {"step_length_m", "ssp_duration_s", "dsp_duration_s", "step_width_m"};

void Require(bool ok, const std::string& field, double value, const std::string& range) {
  if (ok) return;
  std::ostringstream os;
  os << "GaitGraphParams: " << field << " = " << value << " is outside " << range;
  throw std::invalid_argument(os.str());
}

bool InRange(const GaitVector& g, const GaitGraphParams& p) {
  for (int i = 0; i < 4; ++i)
    if (!(g[i] >= p.min[i] - kSame && g[i] <= p.max[i] + kSame)) return false;
  return true;
}

std::string Text(const GaitVector& g) {
  std::ostringstream os;
  os << g[0] << "," << g[1] << "," << g[2] << "," << g[3];
  return os.str();
}

}  // namespace

void GaitGraphParams::Validate() const {
  for (int i = 0; i < 4; ++i) {
    const std::string axis = kAxis[i];
    Require(std::isfinite(min[i]) && min[i] > 0, "min." + axis, min[i], "(0, inf)");
    Require(std::isfinite(max[i]) && max[i] >= min[i], "max." + axis, max[i], "[min, inf)");
    Require(std::isfinite(spacing[i]) && spacing[i] > 0, "spacing." + axis, spacing[i], "(0, inf)");
    Require(std::isfinite(reach[i]) && reach[i] >= spacing[i], "reach." + axis, reach[i],
            "[spacing, inf) (a grid step must be an edge)");
  }
  Require(std::isfinite(step_cost_weight) && step_cost_weight >= 0, "step_cost_weight", step_cost_weight, "[0, inf)");
  Require(max_failed_transitions >= 1 && max_failed_transitions <= 1000, "max_failed_transitions",
          max_failed_transitions, "[1, 1000]");
}

GaitGraph::GaitGraph(const GaitGraphParams& params, const GaitVector& start, const GaitVector& goal) : params_(params) {
  params_.Validate();
  for (const GaitVector* g : {&start, &goal})
    if (!InRange(*g, params_))
      throw std::invalid_argument("GaitGraph: gait " + Text(*g) + " is outside the graph's range [" +
                                  Text(params_.min) + "] to [" + Text(params_.max) + "]");
  std::array<std::vector<double>, 4> axes;
  for (int i = 0; i < 4; ++i) {
    std::vector<double>& a = axes[i];
    // Grid values rounded to 1e-9 (0.35, not 0.35000000000000003: they are printed and are plan-cache keys).
    for (int k = 0; params_.min[i] + k * params_.spacing[i] <= params_.max[i] + kSame; ++k)
      a.push_back(std::round((params_.min[i] + k * params_.spacing[i]) * 1e9) / 1e9);
    a.push_back(params_.max[i]);
    a.push_back(start[i]);
    a.push_back(goal[i]);
    if (params_.within_box) {
      const double lo = std::min(start[i], goal[i]) - kSame, hi = std::max(start[i], goal[i]) + kSame;
      a.erase(std::remove_if(a.begin(), a.end(), [&](double x) { return x < lo || x > hi; }), a.end());
    }
    std::sort(a.begin(), a.end());
    a.erase(std::unique(a.begin(), a.end(), [](double x, double y) { return std::abs(x - y) <= kSame; }), a.end());
  }
  for (double l : axes[0])
    for (double ts : axes[1])
      for (double td : axes[2])
        for (double w : axes[3]) AddNode({l, ts, td, w});
  start_ = AddNode(start);
  goal_ = AddNode(goal);
}

int GaitGraph::AddNode(const GaitVector& g) {
  for (size_t i = 0; i < nodes_.size(); ++i) {
    bool same = true;
    for (int k = 0; k < 4 && same; ++k) same = std::abs(nodes_[i][k] - g[k]) <= kSame;
    if (same) return static_cast<int>(i);
  }
  nodes_.push_back(g);
  return static_cast<int>(nodes_.size()) - 1;
}

bool GaitGraph::Neighbours(int i, int j) const {
  if (i == j) return false;
  for (int k = 0; k < 4; ++k)
    if (std::abs(nodes_.at(i)[k] - nodes_.at(j)[k]) > params_.reach[k] + kSame) return false;
  return infeasible_.count({i, j}) == 0;
}

double GaitGraph::EdgeCost(int i, int j) const {
  double size = 0;
  for (int k = 0; k < 4; ++k) size += std::abs(nodes_.at(i)[k] - nodes_.at(j)[k]) / params_.reach[k];
  return 1.0 + params_.step_cost_weight * size;
}

void GaitGraph::MarkInfeasible(int i, int j) { infeasible_.insert({i, j}); }

void GaitGraph::MarkInfeasibleWithLarger(int i, int j) {
  MarkInfeasible(i, j);
  for (int k = 0; k < num_nodes(); ++k) {
    bool larger = k != i;
    for (int a = 0; a < 4 && larger; ++a) {
      const double failed = nodes_[j][a] - nodes_[i][a], change = nodes_[k][a] - nodes_[i][a];
      larger = failed * change >= 0 && std::abs(change) >= std::abs(failed) - kSame;
    }
    if (larger) MarkInfeasible(i, k);
  }
}

std::vector<int> GaitGraph::ShortestPath() const {
  // Dijkstra on the dense neighbour relation (a few thousand nodes: O(V²) is milliseconds).
  const int n = num_nodes();
  std::vector<double> dist(n, std::numeric_limits<double>::infinity());
  std::vector<int> prev(n, -1);
  std::vector<bool> done(n, false);
  dist[start_] = 0;
  for (;;) {
    int u = -1;
    for (int i = 0; i < n; ++i)
      if (!done[i] && std::isfinite(dist[i]) && (u < 0 || dist[i] < dist[u])) u = i;
    if (u < 0 || u == goal_) break;
    done[u] = true;
    for (int v = 0; v < n; ++v) {
      if (done[v] || !Neighbours(u, v)) continue;
      const double d = dist[u] + EdgeCost(u, v);
      if (d < dist[v]) dist[v] = d, prev[v] = u;
    }
  }
  std::vector<int> path;
  if (!std::isfinite(dist[goal_])) return path;
  for (int v = goal_; v >= 0; v = prev[v]) path.push_back(v);
  std::reverse(path.begin(), path.end());
  return path;
}

GaitChain GaitGraph::ShortestFeasibleChain(const GaitTransitionTry& try_transition) {
  GaitChain chain;
  std::vector<int> verified{start_};  // the chain whose edges succeeded, in order
  for (;;) {
    const std::vector<int> path = ShortestPath();
    if (path.empty()) {
      chain.message = "no chain of feasible transitions is left in the gait graph (" +
                      std::to_string(chain.transitions_failed) + " failed)";
      return chain;
    }
    size_t common = 1;  // nodes shared with the verified chain: those edges need no new try
    while (common < path.size() && common < verified.size() && path[common] == verified[common]) ++common;
    verified.resize(common);
    bool failed = false;
    for (size_t k = common - 1; k + 1 < path.size(); ++k) {
      ++chain.transitions_tried;
      if (try_transition(static_cast<int>(k), nodes_[path[k]], nodes_[path[k + 1]])) {
        verified.push_back(path[k + 1]);
        continue;
      }
      ++chain.transitions_failed;
      MarkInfeasibleWithLarger(path[k], path[k + 1]);
      failed = true;
      break;
    }
    if (!failed) {
      chain.found = true;
      for (int v : path) chain.gaits.push_back(nodes_[v]);
      return chain;
    }
    if (chain.transitions_failed >= params_.max_failed_transitions) {
      chain.message =
          "gave up after " + std::to_string(chain.transitions_failed) + " failed transitions (max_failed_transitions)";
      return chain;
    }
  }
}

}  // namespace rome
