#pragma once
// GaitGraph: a graph of periodic walking gaits over a grid of the gait range, for changing between two gaits whose
// direct transition has no plan, through intermediate gaits (a gait library's graph, as ref. [6] of the
// stepping-stones paper). A gait is g = (L step length m, T_SSP s, T_DSP s, W step width m).
//
// Nodes: every grid point of [min, max] at `spacing` per axis (each axis also holds max and the two end gaits'
// own values, so that a chain may keep a coordinate the two gaits share); with within_box only those between the
// two end gaits on every axis. Edges (directed: a transition from one gait into another): two nodes are neighbours
// when every coordinate differs by at most `reach` (ours: a change the transition NLP usually plans). Cost of an
// edge: 1 (one transition) + step_cost_weight Σ_i |Δg_i| / reach_i (ours: among chains of as many transitions, the
// smaller steps). Edges are "known feasible" only once tried: ShortestFeasibleChain searches lazily (as lazy PRM): the
// cheapest path over the edges not yet found infeasible, then tries its untried edges in order through the caller's
// callback; an edge u → v that fails is removed with every edge from u that changes each coordinate in the same
// direction at least as much (ours: a larger change from the same gait is assumed to fail too), and the search
// repeats, until a path's edges all succeed or none is left.
#include <array>
#include <functional>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace rome {

using GaitVector = std::array<double, 4>;  ///< (L m, T_SSP s, T_DSP s, W m)

struct GaitGraphParams {
  GaitVector min = {0.2, 0.35, 0.08, 0.2};  ///< the walking issue's gait range (m, s, s, m)
  GaitVector max = {0.45, 0.5, 0.15, 0.3};
  GaitVector spacing = {0.05, 0.05, 0.02, 0.05};  ///< grid spacing per axis (ours)
  /// Largest change per axis along one edge (ours; docs/design-notes.md#walking-gait-graph-reach).
  GaitVector reach = {0.10, 0.05, 0.03, 0.05};
  double step_cost_weight = 0.5;  ///< [-] weight of the edge's size in its cost (ours)
  /// Intermediate gaits lie between the two end gaits on every axis (ours: a chain that moves each coordinate one way;
  /// the full grid has thousands of edges for the lazy search to learn).
  bool within_box = true;
  int max_failed_transitions = 16;  ///< the search gives up after this many failed edges (ours: each is an NLP solve)

  /// Throws std::invalid_argument "GaitGraphParams: FIELD = VALUE is outside RANGE" for the first bad field.
  void Validate() const;
};

/// The caller's transition: `depth` edges of the current chain (from the start) have succeeded, in order; try the next
/// one, from -> to. Return false when it has no plan (the edge is then removed).
using GaitTransitionTry = std::function<bool(int depth, const GaitVector& from, const GaitVector& to)>;

struct GaitChain {
  bool found = false;
  std::vector<GaitVector> gaits;  ///< the chain's gaits, start and goal included (found only)
  int transitions_tried = 0;      ///< callback calls
  int transitions_failed = 0;
  std::string message;  ///< why no chain was found
};

class GaitGraph {
 public:
  /// The grid of `params` with `start` and `goal` added. Throws std::invalid_argument for bad params or a gait
  /// outside [min, max].
  GaitGraph(const GaitGraphParams& params, const GaitVector& start, const GaitVector& goal);

  int num_nodes() const { return static_cast<int>(nodes_.size()); }
  const GaitVector& node(int i) const { return nodes_.at(i); }
  int start() const { return start_; }
  int goal() const { return goal_; }
  bool Neighbours(int i, int j) const;
  double EdgeCost(int i, int j) const;

  /// Removes the edge from node i to node j, e.g. a direct transition already found infeasible.
  void MarkInfeasible(int i, int j);
  /// Removes i → j and every edge i → k whose change k − i has the signs of j − i and is at least as large on every
  /// axis.
  void MarkInfeasibleWithLarger(int i, int j);
  /// The cheapest start → goal path over the remaining edges (node indices; empty when there is none).
  std::vector<int> ShortestPath() const;
  /// The lazy search above.
  GaitChain ShortestFeasibleChain(const GaitTransitionTry& try_transition);

 private:
  int AddNode(const GaitVector& g);
  GaitGraphParams params_;
  std::vector<GaitVector> nodes_;
  int start_ = -1, goal_ = -1;
  std::set<std::pair<int, int>> infeasible_;
};

}  // namespace rome
