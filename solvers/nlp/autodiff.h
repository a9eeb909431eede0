#pragma once
// Forward-mode automatic differentiation helpers on Eigen's AutoDiff module
// (unsupported/Eigen/AutoDiff). A scalar carries its value and a gradient vector.
//
//   VectorXad x = InitializeAutoDiff(x_value);          // seeds ∂x_i/∂x = e_i
//   VectorXad y = f(x);                                 // any template code on the scalar type
//   Eigen::VectorXd value = ExtractValue(y);
//   Eigen::MatrixXd dy_dx = ExtractJacobian(y, x.size());
//
// Two scalar types:
//   AutoDiffXd            gradient of any length, on the heap (every operation allocates);
//   AutoDiffMax<K>        gradient of at most K entries, held inside the scalar (no allocation), for
//                         functions of a few variables evaluated many times (collocation node functions).
// The helpers below are templates over the scalar (default AutoDiffXd).
#include <stdexcept>
#include <string>

#include <Eigen/Dense>
#include <unsupported/Eigen/AutoDiff>

namespace rome {

using AutoDiffXd = Eigen::AutoDiffScalar<Eigen::VectorXd>;
using VectorXad = Eigen::Matrix<AutoDiffXd, Eigen::Dynamic, 1>;

template <int MaxDerivatives>
using AutoDiffMax = Eigen::AutoDiffScalar<Eigen::Matrix<double, Eigen::Dynamic, 1, 0, MaxDerivatives, 1>>;

// Largest number of derivatives a scalar type holds (Eigen::Dynamic: unbounded).
template <class AD>
constexpr int MaxDerivativesOf() {
  return AD::DerType::MaxRowsAtCompileTime;
}

// x with derivatives seeded as columns [offset, offset + size) of a num_derivatives identity.
// num_derivatives = 0 gives constants (empty derivative vectors), e.g. to evaluate templated
// code on plain values. Throws std::invalid_argument if the seed does not fit, or if
// num_derivatives exceeds what the scalar type AD holds.
template <class AD = AutoDiffXd>
Eigen::Matrix<AD, Eigen::Dynamic, 1> InitializeAutoDiff(const Eigen::Ref<const Eigen::VectorXd>& value,
                                                        int num_derivatives, int offset) {
  if (num_derivatives != 0 && (offset < 0 || offset + value.size() > num_derivatives)) {
    throw std::invalid_argument("InitializeAutoDiff: " + std::to_string(value.size()) + " seeds at offset " +
                                std::to_string(offset) +
                                " exceed num_derivatives = " + std::to_string(num_derivatives));
  }
  constexpr int kMax = MaxDerivativesOf<AD>();
  if (kMax != Eigen::Dynamic && num_derivatives > kMax) {
    throw std::invalid_argument("InitializeAutoDiff: num_derivatives = " + std::to_string(num_derivatives) +
                                " exceeds the scalar type's capacity of " + std::to_string(kMax));
  }
  Eigen::Matrix<AD, Eigen::Dynamic, 1> x(value.size());
  for (Eigen::Index i = 0; i < value.size(); ++i) {
    x(i).value() = value(i);
    if (num_derivatives == 0) {
      x(i).derivatives().resize(0);
    } else {
      x(i).derivatives().setZero(num_derivatives);
      x(i).derivatives()(offset + i) = 1.0;
    }
  }
  return x;
}

template <class AD = AutoDiffXd>
Eigen::Matrix<AD, Eigen::Dynamic, 1> InitializeAutoDiff(const Eigen::Ref<const Eigen::VectorXd>& value) {
  return InitializeAutoDiff<AD>(value, static_cast<int>(value.size()), 0);
}

template <class AD>
Eigen::VectorXd ExtractValue(const Eigen::Matrix<AD, Eigen::Dynamic, 1>& y) {
  Eigen::VectorXd v(y.size());
  for (Eigen::Index i = 0; i < y.size(); ++i) v(i) = y(i).value();
  return v;
}

// Rows are outputs, columns derivatives. Entries whose derivative vector is empty (constants)
// give zero rows.
template <class AD>
Eigen::MatrixXd ExtractJacobian(const Eigen::Matrix<AD, Eigen::Dynamic, 1>& y, int num_derivatives) {
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(y.size(), num_derivatives);
  for (Eigen::Index i = 0; i < y.size(); ++i) {
    if (y(i).derivatives().size() == num_derivatives) J.row(i) = y(i).derivatives().transpose();
  }
  return J;
}

}  // namespace rome
