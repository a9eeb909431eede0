// The sidecar file: found, read and checked at the top level, its "urdf" and "floating_base" entries
// (model_loader.h lists the loader's stages), and the SidecarReader every sidecar entry is read with.

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include "framework/files.h"
#include "framework/text.h"
#include "systems/multibody/model_loader.h"
#include "systems/multibody/robot_file_text.h"

namespace rome {

namespace model_loading {

namespace {

// Levenshtein distance, case-insensitive.
size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const bool same =
          std::tolower(static_cast<unsigned char>(a[i - 1])) == std::tolower(static_cast<unsigned char>(b[j - 1]));
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (same ? 0 : 1)});
    }
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

}  // namespace

void SidecarReader::Fail(const std::string& context, const std::string& problem) const {
  throw std::runtime_error("sidecar " + Excerpt(file, 200) + ": " + context + ": " + problem);
}

std::string SidecarReader::Dump(const json& v) {
  return Excerpt(v.dump(-1, ' ', false, json::error_handler_t::replace), 60);
}

const json& SidecarReader::Get(const json& obj, const std::string& key, const std::string& context) const {
  if (!obj.is_object()) Fail(context, "expected a JSON object, got " + Dump(obj));
  auto it = obj.find(key);
  if (it == obj.end()) Fail(context, "missing required entry '" + key + "'");
  return *it;
}

void SidecarReader::CheckKeys(const json& obj, std::initializer_list<const char*> known,
                              const std::string& context) const {
  if (!obj.is_object()) Fail(context, "expected a JSON object, got " + Dump(obj));
  for (auto it = obj.begin(); it != obj.end(); ++it) {
    bool ok = false;
    for (const char* k : known) ok |= it.key() == k;
    if (ok) continue;
    std::string nearest, all;
    size_t best = std::numeric_limits<size_t>::max();
    for (const char* k : known) {
      const size_t d = it.key().size() > 64 ? it.key().size() : EditDistance(it.key(), k);
      if (d < best) {
        best = d;
        nearest = k;
      }
      all += std::string(all.empty() ? "" : ", ") + k;
    }
    std::string hint = best <= std::max<size_t>(2, nearest.size() / 3) ? " (did you mean '" + nearest + "'?)"
                                                                       : " (known keys: " + all + ")";
    Fail(context, "unknown key '" + Excerpt(it.key(), 60) + "'" + hint);
  }
}

double SidecarReader::Number(const json& obj, const std::string& key, const std::string& context) const {
  const json& v = Get(obj, key, context);
  if (!v.is_number()) Fail(context, "'" + key + "' must be a number, got " + Dump(v));
  const double x = v.get<double>();
  if (!std::isfinite(x)) Fail(context, "'" + key + "' is not finite (" + Dump(v) + ")");
  return x;
}

double SidecarReader::NumberOr(const json& obj, const std::string& key, double fallback,
                               const std::string& context) const {
  if (!obj.contains(key)) return fallback;
  return Number(obj, key, context);
}

std::string SidecarReader::String(const json& obj, const std::string& key, const std::string& context) const {
  const json& v = Get(obj, key, context);
  if (!v.is_string()) Fail(context, "'" + key + "' must be a string, got " + Dump(v));
  return v.get<std::string>();
}

Eigen::Vector3d SidecarReader::Vec3(const json& v, const std::string& context) const {
  if (!v.is_array() || v.size() != 3) Fail(context, "expected [x, y, z], got " + Dump(v));
  Eigen::Vector3d out;
  for (int i = 0; i < 3; ++i) {
    if (!v[i].is_number()) Fail(context, "expected numbers in [x, y, z], got " + Dump(v));
    out[i] = v[i].get<double>();
  }
  if (!out.allFinite() || out.cwiseAbs().maxCoeff() > kMaxLength_m)
    Fail(context, "coordinates " + Num3(out) + " m are not finite or exceed " + Num(kMaxLength_m) + " m");
  return out;
}

const json& SidecarReader::Array(const json& obj, const std::string& key, const std::string& context) const {
  static const json kEmpty = json::array();
  if (!obj.contains(key)) return kEmpty;
  const json& v = obj.at(key);
  if (!v.is_array()) Fail(context, "'" + key + "' must be an array, got " + Dump(v));
  return v;
}

// A magnitude a robot file gives: within [lo, hi], else "<name> <value> <unit> is outside [lo, hi] <unit>".
void CheckMagnitude(const SidecarReader& sc, const std::string& context, const std::string& name, double value,
                    double lo, double hi, const std::string& unit) {
  if (value >= lo && value <= hi) return;
  const std::string u = unit.empty() ? "" : " " + unit;
  sc.Fail(context, name + " " + Num(value) + u + " is outside [" + Num(lo) + ", " + Num(hi) + "]" + u);
}

namespace {

// The sidecar's "urdf" entry when a URDF is loaded with a sidecar: a non-empty path that is not the sidecar itself.
// One that names another URDF than the one loaded is reported as a warning (a sidecar may be shared by variants).
void CheckSidecarNamesUrdf(const SidecarReader& sc, const std::string& entry, const std::string& urdf_path,
                           const LoadOptions& options, std::vector<std::string>* warnings) {
  if (entry.empty()) sc.Fail("urdf", "the entry is empty; name the URDF file, relative to the sidecar");
  std::string named;
  try {
    named = PackageFile(FolderOf(sc.file), entry, "sidecar " + Excerpt(sc.file, 200) + ": \"urdf\"", options);
  } catch (const std::exception& e) {  // not read here (the URDF was given): what is wrong with it is a warning
    warnings->push_back(e.what());
    return;
  }
  if (SameFile(named, sc.file))
    sc.Fail("urdf", "'" + Excerpt(entry) + "' names the sidecar itself; name the URDF file");
  if (!SameFile(named, urdf_path))
    warnings->push_back("sidecar \"urdf\" names '" + Excerpt(entry) + "', but the URDF loaded is '" +
                        Excerpt(urdf_path, 200) + "' (given explicitly)");
}

}  // namespace

}  // namespace model_loading

using namespace model_loading;

void MultibodyModelLoader::ReadSidecarFile(LoadState& s, const std::string& urdf_path, std::string sidecar_path,
                                           bool sidecar_required, const std::string* urdf_text,
                                           const std::string* sidecar_text) {
  MultibodyModel& model = s.model;
  const LoadOptions& options = s.options;
  const std::string& ufile = s.ufile;
  json& sidecar = s.sidecar;
  if (urdf_text) {
    sidecar_required = sidecar_text != nullptr;
    if (!sidecar_text) sidecar_path.clear();
  } else if (sidecar_path.empty()) {
    const std::string beside = std::filesystem::path(urdf_path).stem().string() + ".rome.json";
    std::error_code ec;
    if (std::filesystem::exists(std::filesystem::path(FolderOf(urdf_path)) / beside, ec))
      sidecar_path = PackageFile(FolderOf(urdf_path), beside, ufile + ": its sidecar", options);
  } else {
    sidecar_required = true;
  }
  s.sc.file = sidecar_path;
  const SidecarReader& sc = s.sc;
  if (!sidecar_path.empty() || sidecar_required) {
    const std::string text = sidecar_text ? CheckTextSize(*sidecar_text, "sidecar", sidecar_path, kMaxUrdfBytes)
                                          : ReadRegularFile(sidecar_path, "sidecar", kMaxUrdfBytes);
    sidecar = ParseSidecarJson(text, sidecar_path);
    if (!sidecar.is_object()) sc.Fail("top level", "expected a JSON object");
    sc.CheckKeys(
        sidecar,
        {"robot", "urdf", "floating_base", "actuators", "springs", "contacts", "loop_closures", "nominal_pose"},
        "top level");
  }
  model.sidecar_path_ = sidecar_path;
  if (!urdf_text && sidecar.contains("urdf"))
    CheckSidecarNamesUrdf(sc, sc.String(sidecar, "urdf", "urdf"), urdf_path, options, &model.warnings_);
}

void MultibodyModelLoader::ReadFloatingBaseEntry(LoadState& s) {
  MultibodyModel& model = s.model;
  const SidecarReader& sc = s.sc;
  const json& sidecar = s.sidecar;
  model.floating_base_ = FloatingBaseType::kFixed;
  if (sidecar.contains("floating_base")) {
    const std::string fb = sc.String(sidecar, "floating_base", "floating_base");
    if (fb == "fixed")
      model.floating_base_ = FloatingBaseType::kFixed;
    else if (fb == "planar")
      model.floating_base_ = FloatingBaseType::kPlanar;
    else if (fb == "spatial" || fb == "quaternion")  // the quaternion free-flyer (UseQuaternionBase)
      model.floating_base_ = FloatingBaseType::kSpatial;
    else if (fb == "spatial_euler") {
      model.floating_base_ = FloatingBaseType::kSpatial;
      s.sidecar_euler = true;
    } else
      sc.Fail("floating_base",
              "unknown type '" + Excerpt(fb) + "' (expected fixed, planar, spatial, quaternion or spatial_euler)");
  }
}

}  // namespace rome
