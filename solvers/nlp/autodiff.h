#pragma once
// Forward-mode automatic differentiation helpers on Eigen's AutoDiff module
// (unsupported/Eigen/AutoDiff). A scalar carries its value and a dynamic gradient vector.
//
//   VectorXad x = InitializeAutoDiff(x_value);          // seeds ∂x_i/∂x = e_i
//   VectorXad y = f(x);                                 // any template code on the scalar type
//   Eigen::VectorXd value = ExtractValue(y);
//   Eigen::MatrixXd dy_dx = ExtractJacobian(y, x.size());
#include <stdexcept>
#include <string>

#include <Eigen/Dense>
#include <unsupported/Eigen/AutoDiff>

namespace rome {

using AutoDiffXd = Eigen::AutoDiffScalar<Eigen::VectorXd>;
using VectorXad = Eigen::Matrix<AutoDiffXd, Eigen::Dynamic, 1>;

// x with derivatives seeded as columns [offset, offset + size) of a num_derivatives identity.
// num_derivatives = 0 gives constants (empty derivative vectors), e.g. to evaluate templated
// code on plain values. Throws std::invalid_argument if the seed does not fit.
inline VectorXad InitializeAutoDiff(const Eigen::Ref<const Eigen::VectorXd>& value,
                                    int num_derivatives, int offset) {
  if (num_derivatives != 0 &&
      (offset < 0 || offset + value.size() > num_derivatives)) {
    throw std::invalid_argument("InitializeAutoDiff: " + std::to_string(value.size()) +
                                " seeds at offset " + std::to_string(offset) +
                                " exceed num_derivatives = " + std::to_string(num_derivatives));
  }
  VectorXad x(value.size());
  for (Eigen::Index i = 0; i < value.size(); ++i) {
    x(i).value() = value(i);
    if (num_derivatives == 0) {
      x(i).derivatives().resize(0);
    } else {
      x(i).derivatives() = Eigen::VectorXd::Unit(num_derivatives, offset + i);
    }
  }
  return x;
}

inline VectorXad InitializeAutoDiff(const Eigen::Ref<const Eigen::VectorXd>& value) {
  return InitializeAutoDiff(value, static_cast<int>(value.size()), 0);
}

inline Eigen::VectorXd ExtractValue(const VectorXad& y) {
  Eigen::VectorXd v(y.size());
  for (Eigen::Index i = 0; i < y.size(); ++i) v(i) = y(i).value();
  return v;
}

// Rows are outputs, columns derivatives. Entries whose derivative vector is empty (constants)
// give zero rows.
inline Eigen::MatrixXd ExtractJacobian(const VectorXad& y, int num_derivatives) {
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(y.size(), num_derivatives);
  for (Eigen::Index i = 0; i < y.size(); ++i) {
    if (y(i).derivatives().size() == num_derivatives) J.row(i) = y(i).derivatives().transpose();
  }
  return J;
}

}  // namespace rome
