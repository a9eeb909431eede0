// libFuzzer harness for the robot loader: MultibodyModel::LoadFromText on a URDF and its ROME sidecar.
//
// Input: the URDF's XML, then (optionally) a line "%%sidecar%%" followed by the sidecar's JSON. Without that line
// the model has no sidecar (fixed base).
// Fine: a model, or std::runtime_error (the loader's documented error) whose message is one line.
// A finding: any other exception, a multi-line message, a crash, a sanitizer report, a hang (libFuzzer -timeout),
// or an accepted model whose mass matrix or bias forces at the nominal pose are not finite.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>

#include "systems/multibody/multibody_dynamics.h"
#include "systems/multibody/multibody_model.h"
#include "systems/multibody/multibody_workspace.h"

namespace {

[[noreturn]] void Finding(const char* what, const std::string& detail) {
  std::fprintf(stderr, "urdf_sidecar_fuzzer: %s: %s\n", what, detail.c_str());
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string kSeparator = "\n%%sidecar%%\n";
  const std::string input(reinterpret_cast<const char*>(data), size);
  const size_t at = input.find(kSeparator);
  const std::string urdf = input.substr(0, at);
  const std::string sidecar = at == std::string::npos ? "" : input.substr(at + kSeparator.size());
  try {
    const rome::MultibodyModel model = rome::MultibodyModel::LoadFromText(urdf, sidecar, "fuzz.urdf", "fuzz.rome.json");
    // An accepted model is usable: its dynamics at the nominal pose are finite.
    if (model.nv() > rome::kMaxDofs) Finding("too many degrees of freedom accepted", std::to_string(model.nv()));
    rome::MultibodyWorkspace ws(model);
    const Eigen::VectorXd q = model.q_nominal();
    const Eigen::VectorXd v = Eigen::VectorXd::Zero(model.nv());
    const Eigen::MatrixXd& M = rome::CalcMassMatrix(model, ws, q);
    if (!M.allFinite()) Finding("accepted model has a non-finite mass matrix", model.name());
    const Eigen::VectorXd& h = rome::CalcBiasForces(model, ws, q, v);
    if (!h.allFinite()) Finding("accepted model has non-finite bias forces", model.name());
  } catch (const std::runtime_error& e) {
    if (std::strchr(e.what(), '\n') != nullptr) Finding("multi-line error message", e.what());
  }
  return 0;
}
