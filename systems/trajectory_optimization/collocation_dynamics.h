#pragma once
// CollocationDynamicsFromSystem: the dynamics ẋ = f(x, u) of DirectCollocation (solvers/collocation) taken from a
// LeafSystem's time derivatives, so a model is written once (as a block) and used for simulation, linearisation
// and trajectory optimisation alike (Drake's DirectCollocation(system, context, ...)).
//
// The returned StateInputFunction evaluates, at each node (x, u), the system's CalcTimeDerivatives with x written
// into its continuous state and u fixed on `input_port`, in a private copy of `context`: time, discrete state, mode,
// numeric parameters and the other fixed inputs are those of `context` when the function was made, held constant.
// The collocation NLP needs ∂f/∂(x, u): the leaf systems of the framework have no derivative hook, so they are the
// central differences of framework/linearize.h (Linearize, with its documented error O(h²) + O(ε/h), about 1e-10
// relative with the default step), chained onto the AutoDiff seeds of x and u. Cost per node with derivatives:
// 1 + 2 (n_x + n_u) evaluations of f; without derivatives (seeds of size 0): one.
//
// Use the default L-BFGS Hessian of DirectCollocation: SetExactHessian(true) would difference these Jacobians once
// more (forward differences of finite differences), which loses about half of the remaining digits.
//
// Contract: `system` must outlive the returned function. Copies of the function share one context copy, so they
// must not be called from several threads at once (DirectCollocation calls them from one thread).
// Errors (std::invalid_argument, naming the system): a system without continuous state, an unknown or typed input
// port (listing the ports it has), a context of another system or one wired into a diagram; when called: x or u of the
// wrong size, and the errors of Linearize (a non-finite derivative names the element).
#include <string>

#include "framework/linearize.h"
#include "framework/system.h"
#include "solvers/collocation/direct_collocation.h"

namespace rome {

/// ẋ = f(x, u) of `system` for CollocationPhase::dynamics. `input_port` names the vector input that carries u
/// (empty: the system has no input for the collocation, the phase has num_inputs = 0).
StateInputFunction CollocationDynamicsFromSystem(const LeafSystem& system, const LeafContext& context,
                                                 const std::string& input_port, const LinearizeParams& params = {});

}  // namespace rome
