#pragma once
// Rapidly exponentially stabilizing control Lyapunov function (RES-CLF) of the hopping paper
// (cassie-hopping-spring-mass-clf-qp, Section on CLF-QP, Eqs. (26)–(33)).
//
// Output dynamics, Eq. (26), with η = [y1, y2, ẏ2] (o1 relative-degree-one outputs y1,
// o2 relative-degree-two outputs y2):
//     η̇ = F η + G μ,   F = [0 0 0; 0 0 I2; 0 0 0],   G = [I1 0; 0 0; 0 I2].
// P solves the CARE  Fᵀ P + P F − P G Gᵀ P + Q = 0  (footnote 3, R = I)
// or the CTLE       Fᵀ P + P F + Q = 0             (footnote 4; F must then be Hurwitz).
// Eq. (29): V_ε(η) = ηᵀ P_ε η,  P_ε = I_ε P I_ε,  I_ε = diag(I1, (1/ε) I2, I2).
// Eq. (30): V̇_ε ≤ −(γ/ε) V_ε with γ = λ_min(Q) / λ_max(P) (the RES-CLF rate of Ames et al.;
// the paper leaves γ generic). Eq. (32)–(33): L_F V_ε = ηᵀ(Fᵀ P_ε + P_ε F)η, L_G V_ε = 2ηᵀ P_ε G.
//
// With the CARE choice, μ = −(1/ε) Gᵀ P I_ε η achieves V̇_ε ≤ −(γ/ε) V_ε (tested).
#include <Eigen/Dense>

namespace rome {

enum class ClfEquation {
  kRiccati,   // CARE with R = I (footnote 3), works for the chain-of-integrators F of Eq. (26)
  kLyapunov,  // CTLE (footnote 4), needs a Hurwitz F
};

struct RapidlyExponentiallyStabilizingClfParameters {
  int num_relative_degree_one_outputs = 0;  // o1 [-]
  int num_relative_degree_two_outputs = 0;  // o2 [-]
  double epsilon = 0.1;                     // ε, convergence tuning, 0 < ε (smaller = faster) [-]
  ClfEquation equation = ClfEquation::kRiccati;
};

struct RapidlyExponentiallyStabilizingClf {
  Eigen::MatrixXd P;          // CARE / CTLE solution, (o1+2 o2)²
  Eigen::MatrixXd I_epsilon;  // diag(I1, (1/ε) I2, I2)
  Eigen::MatrixXd P_epsilon;  // I_ε P I_ε, Eq. (29)
  double gamma{};             // λ_min(Q) / λ_max(P) [-]
  double epsilon{};           // ε [-]
  double convergence_rate{};  // γ / ε [1/s], the rate in Eq. (30)
};

// F and G of Eq. (26) for o1 relative-degree-one and o2 relative-degree-two outputs.
void MakeOutputDynamics(int num_relative_degree_one_outputs, int num_relative_degree_two_outputs, Eigen::MatrixXd* F,
                        Eigen::MatrixXd* G);

// Builds the RES-CLF from F, G, Q (symmetric positive definite) and the parameters.
// Throws std::invalid_argument on inconsistent sizes, ε ≤ 0, Q not positive definite, or when
// the chosen equation has no positive-definite solution (message names the cause).
RapidlyExponentiallyStabilizingClf ComputeRapidlyExponentiallyStabilizingClf(
    const Eigen::Ref<const Eigen::MatrixXd>& F, const Eigen::Ref<const Eigen::MatrixXd>& G,
    const Eigen::Ref<const Eigen::MatrixXd>& Q, const RapidlyExponentiallyStabilizingClfParameters& parameters);

}  // namespace rome
