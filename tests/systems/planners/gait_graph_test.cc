// GaitGraph: the cheapest chain over the grid has the fewest transitions the per-axis reach allows (a closed form:
// max_i ceil(|Δg_i| / reach_i) when the grid holds the intermediate values), the lazy search only returns edges the
// caller accepted and calls it with the prefix contract of GaitTransitionTry, and bad input is refused by name.
#include "systems/planners/gait_graph.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace rome {
namespace {

int FewestTransitions(const GaitVector& a, const GaitVector& b, const GaitVector& reach) {
  int n = 0;
  for (int i = 0; i < 4; ++i) n = std::max(n, static_cast<int>(std::ceil(std::abs(b[i] - a[i]) / reach[i] - 1e-9)));
  return n;
}

TEST(GaitGraph, CornerToCornerTakesTheFewestTransitionsTheReachAllows) {
  const GaitGraphParams p;
  const GaitVector a = p.min, b = p.max;
  GaitGraph graph(p, a, b);
  const std::vector<int> path = graph.ShortestPath();
  ASSERT_FALSE(path.empty());
  // L: 0.25 m in 0.1 m reaches, T_SSP 0.15 s in 0.05 s, T_DSP 0.07 s in 0.03 s, W 0.1 m in 0.05 m: 3 transitions.
  EXPECT_EQ(FewestTransitions(a, b, p.reach), 3);
  EXPECT_EQ(static_cast<int>(path.size()) - 1, 3);
  for (size_t k = 0; k + 1 < path.size(); ++k)
    for (int i = 0; i < 4; ++i)
      EXPECT_LE(std::abs(graph.node(path[k + 1])[i] - graph.node(path[k])[i]), p.reach[i] + 1e-9);
}

TEST(GaitGraph, LazySearchReturnsOnlyAcceptedTransitionsAndKeepsThePrefixContract) {
  GaitGraphParams p;
  p.max_failed_transitions = 100;  // every edge with a 0.1 m change of L fails here
  const GaitVector a{0.25, 0.38, 0.09, 0.27}, b{0.42, 0.42, 0.11, 0.27};
  GaitGraph graph(p, a, b);
  std::vector<GaitVector> prefix{a};  // the caller's chain so far
  bool contract_ok = true;
  // Only transitions that change L by at most 0.05 m "have a plan".
  const GaitChain chain = graph.ShortestFeasibleChain([&](int depth, const GaitVector& from, const GaitVector& to) {
    if (depth < 0 || depth + 1 > static_cast<int>(prefix.size())) return contract_ok = false;
    prefix.resize(depth + 1);
    contract_ok = contract_ok && prefix.back() == from;
    if (std::abs(to[0] - from[0]) > 0.05 + 1e-9) return false;
    prefix.push_back(to);
    return true;
  });
  EXPECT_TRUE(contract_ok);
  ASSERT_TRUE(chain.found) << chain.message;
  EXPECT_GT(chain.transitions_failed, 0);
  EXPECT_EQ(chain.gaits.front(), a);
  EXPECT_EQ(chain.gaits.back(), b);
  EXPECT_EQ(prefix, chain.gaits);
  // 0.17 m of L in steps of at most 0.05 m (grid 0.25, 0.3, 0.35, 0.4, 0.42): 4 transitions.
  EXPECT_EQ(static_cast<int>(chain.gaits.size()) - 1, 4);
  for (size_t k = 0; k + 1 < chain.gaits.size(); ++k)
    EXPECT_LE(std::abs(chain.gaits[k + 1][0] - chain.gaits[k][0]), 0.05 + 1e-9);
  // within_box: every gait of the chain lies between A and B on every axis (W stays at the shared 0.27 m).
  for (const GaitVector& g : chain.gaits)
    for (int i = 0; i < 4; ++i) {
      EXPECT_GE(g[i], std::min(a[i], b[i]) - 1e-12);
      EXPECT_LE(g[i], std::max(a[i], b[i]) + 1e-12);
    }
}

TEST(GaitGraph, NoFeasibleTransitionEndsWithAReasonWithinTheFailureBudget) {
  GaitGraphParams p;
  p.max_failed_transitions = 5;
  GaitGraph graph(p, {0.2, 0.4, 0.1, 0.25}, {0.45, 0.4, 0.1, 0.25});
  const GaitChain chain = graph.ShortestFeasibleChain([](int, const GaitVector&, const GaitVector&) { return false; });
  EXPECT_FALSE(chain.found);
  EXPECT_GE(chain.transitions_failed, 1);
  EXPECT_LE(chain.transitions_failed, 5);
  EXPECT_EQ(chain.transitions_tried, chain.transitions_failed);
  EXPECT_FALSE(chain.message.empty());
}

TEST(GaitGraph, AnInfeasibleDirectEdgeIsNotTaken) {
  const GaitGraphParams p;
  const GaitVector a{0.30, 0.40, 0.10, 0.25}, b{0.40, 0.40, 0.10, 0.25};
  GaitGraph graph(p, a, b);
  EXPECT_EQ(graph.ShortestPath().size(), 2u);  // within reach: the direct edge
  graph.MarkInfeasible(graph.start(), graph.goal());
  EXPECT_EQ(graph.ShortestPath().size(), 3u);  // one intermediate gait
}

TEST(GaitGraph, BadInputIsRefusedNamingTheField) {
  GaitGraphParams p;
  p.reach[2] = 0.01;  // below the 0.02 s spacing
  try {
    GaitGraph(p, p.min, p.max);
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("reach.dsp_duration_s = 0.01"), std::string::npos) << e.what();
  }
  try {
    GaitGraph(GaitGraphParams{}, {0.5, 0.4, 0.1, 0.25}, {0.3, 0.4, 0.1, 0.25});
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("gait 0.5,0.4,0.1,0.25 is outside"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rome
