#pragma once
// Linearize: the first-order model of a system about an operating point (Drake's systems::Linearize).
//
// For ẋ = f(t, x, u), y = g(t, x, u) about the point held by `context` (its time t, continuous state x₀, the value
// u₀ fixed on the named input port, and everything else the context holds: discrete state, mode, parameters, other
// fixed inputs, all held constant):
//
//     A = ∂f/∂x (n×n),  B = ∂f/∂u (n×m),  C = ∂g/∂x (p×n),  D = ∂g/∂u (p×m),
//
// so that δẋ ≈ A δx + B δu and δy ≈ C δx + D δu, with δx = x − x₀, δu = u − u₀. For a Diagram, x is the stack of
// its leaves' continuous states in leaf order (the order the Simulator integrates), u an exported input and y an
// exported output.
//
// Method: central differences, one column per perturbed element z_j of x or u, with the per-element step
//     h_j = step_scale · max(1, |z_j|),
//     column j ≈ (F(z + h_j e_j) − F(z − h_j e_j)) / (2 h_j).
// Error of each entry (F ∈ {f, g}, ε = machine epsilon):
//     truncation  ≤ h_j² / 6 · max |∂³F/∂z_j³| over [z_j − h_j, z_j + h_j]             (O(h²)),
//     round-off   ≲ ε · |F| / h_j  (each evaluation of F is exact to about ε |F|).
// The default step_scale = ε^(1/3) ≈ 6.1e-6 balances the two: for F, ∂³F and z of order one the error is of order
// ε^(2/3) ≈ 4e-11 (relative to the size of F and its third derivative).
//
// Exact Jacobians: the framework has no hook through which a leaf system provides ∂f/∂x or ∂g/∂u, so every entry is
// a finite difference. A model that is linear in (x, u) is reproduced up to round-off only.
//
// The context is perturbed in place and restored exactly (the same bits of x₀ and u₀, also when an error is
// thrown), so it is left as it was apart from its cache version. Errors (std::invalid_argument, one line): an
// unknown port (naming the system and the port and listing the ports it has), a typed port, an input port without
// a fixed value, a system without continuous state, a non-finite derivative or output at the operating point or at
// a perturbed point (naming the element), a step_scale that is not positive and finite. A leaf's input that a
// diagram connects cannot be perturbed: the framework's std::logic_error says so (linearize the diagram instead).
#include <string>

#include <Eigen/Core>

#include "framework/context.h"
#include "framework/system.h"

namespace rome {

struct LinearizeParams {
  /// [-] Relative central-difference step: h_j = step_scale · max(1, |z_j|) in the units of z_j. Default ε^(1/3)
  /// (ours, the step that balances O(h²) truncation against O(ε/h) round-off).
  double step_scale = 6.0554544523933395e-06;
};

/// The linear model δẋ = A δx + B δu, δy = C δx + D δu about (x0, u0) at time `time`.
struct LinearSystemMatrices {
  Eigen::MatrixXd A;      ///< ∂f/∂x, n×n
  Eigen::MatrixXd B;      ///< ∂f/∂u, n×m (m = 0 without an input port)
  Eigen::MatrixXd C;      ///< ∂g/∂x, p×n (p = 0 without an output port)
  Eigen::MatrixXd D;      ///< ∂g/∂u, p×m
  Eigen::VectorXd x0;     ///< operating-point state
  Eigen::VectorXd u0;     ///< operating-point input (empty without an input port)
  Eigen::VectorXd y0;     ///< output at the operating point (empty without an output port)
  Eigen::VectorXd xdot0;  ///< f(t, x0, u0): zero at an equilibrium
  double time = 0;        ///< [s]
};

/// Linearizes `system` (a LeafSystem or a Diagram with continuous state) about the operating point held by `context`.
/// `input_port` and `output_port` name vector ports of `system`; an empty name means none (B and D, or C and D, get
/// zero columns or rows). The named input port must have a value fixed in `context`.
LinearSystemMatrices Linearize(const System& system, Context& context, const std::string& input_port,
                               const std::string& output_port, const LinearizeParams& params = {});

}  // namespace rome
