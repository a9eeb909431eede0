#include "systems/visualization/animation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include <Eigen/Geometry>
#include <urdf_parser/urdf_parser.h>

#include "framework/sha256.h"
#include "framework/files.h"
#include "framework/text.h"
#include "systems/multibody/multibody_kinematics.h"
#include "systems/multibody/multibody_model.h"
#include "systems/multibody/multibody_workspace.h"

namespace rome::visualization {

namespace {

// ROME world (z up) → three.js (y up): (x, y, z) ↦ (x, z, −y).
const Eigen::Matrix3d& ToThree() {
  static const Eigen::Matrix3d C = (Eigen::Matrix3d() << 1, 0, 0, 0, 0, 1, 0, -1, 0).finished();
  return C;
}

void AppendVec(std::ostringstream& os, const Eigen::Vector3d& v) {
  const Eigen::Vector3d w = ToThree() * v;
  os << "[" << w.x() << "," << w.y() << "," << w.z() << "]";
}

// The URDF the model was loaded from, parsed again for its visual geometry and read as the loader reads it (only a
// regular file, at most kMaxUrdfBytes). Null for a model loaded from text, or a file that can no longer be read: the
// page then draws the bodies without their visuals.
urdf::ModelInterfaceSharedPtr ParseVisualUrdf(const std::string& path) {
  try {
    return urdf::parseURDF(ReadRegularFile(path, "URDF", kMaxUrdfBytes));
  } catch (const std::exception&) { return nullptr; }
}

std::string ReadThreeJs(const std::string& path, std::string* error) {
  try {
    return ReadRegularFile(path, "three.js", 16u << 20);
  } catch (const std::exception& e) {
    *error = std::string("animation: ") + e.what() + " (install Debian's libjs-three: ./rome setup)";
    return {};
  }
}

std::string Format(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

void AppendFloats(std::ostringstream& os, const std::vector<float>& v, int decimals) {
  os << "[";
  char buf[48];
  for (size_t i = 0; i < v.size(); ++i) {
    std::snprintf(buf, sizeof(buf), "%.*f", decimals, static_cast<double>(v[i]));
    // Trim trailing zeros ("0.1200" -> "0.12", "-0.0000" -> "0").
    std::string s(buf);
    if (s.find('.') != std::string::npos) {
      while (!s.empty() && s.back() == '0') s.pop_back();
      if (!s.empty() && s.back() == '.') s.pop_back();
    }
    if (s == "-0") s = "0";
    os << (i ? "," : "") << s;
  }
  os << "]";
}

// The page in pieces: the Content-Security-Policy names each inline script and the style by its SHA-256, so nothing
// but these runs (no inline handler, no injected element's script, no network).
const char* kStyle = R"PAGE(
 html,body{margin:0;height:100%;overflow:hidden;font:14px sans-serif;background:#f4f4f4}
 #hud{position:absolute;left:10px;top:8px;background:rgba(255,255,255,.85);padding:6px 10px;border-radius:4px}
 #bar{position:absolute;left:0;right:0;bottom:0;display:flex;gap:8px;align-items:center;padding:8px;background:rgba(255,255,255,.9)}
 #slider{flex:1}
 #test-result{display:none}
)PAGE";

// @TITLE@ is replaced by the title as HTML text.
const char* kBody =
    R"PAGE(<div id="hud"><b>@TITLE@</b><br><span id="time"></span> &nbsp; mode: <span id="mode"></span></div>
<div id="bar"><button id="play">pause</button><input id="slider" type="range" min="0" max="1000" value="0">
<select id="speed"><option>0.25</option><option>0.5</option><option selected>1</option><option>2</option></select> &times; real time</div>
<pre id="test-result"></pre>
)PAGE";

const char* kErrorScript =
    "window.__errors=[];window.addEventListener('error',function(e){window.__errors.push(String(e.message));});";

// Follows "const D = <data>;" in the page's last script.
const char* kMainScript = R"PAGE(
const test = /test=/.test(location.hash);
const renderer = new THREE.WebGLRenderer({antialias: !test, preserveDrawingBuffer: true});
renderer.setPixelRatio(1);
renderer.setSize(window.innerWidth, window.innerHeight);
document.body.appendChild(renderer.domElement);
const scene = new THREE.Scene();
scene.background = new THREE.Color(test ? 0xffffff : 0xf4f4f4);
scene.add(new THREE.AmbientLight(0xffffff, 0.55));
const sun = new THREE.DirectionalLight(0xffffff, 0.7); sun.position.set(2, 5, 3); scene.add(sun);
const camera = new THREE.PerspectiveCamera(40, window.innerWidth / window.innerHeight, 0.01, 200);
const robotMat = test ? new THREE.MeshBasicMaterial({color: 0xff0000}) : new THREE.MeshLambertMaterial({color: 0x3060c0});
const stoneMat = test ? new THREE.MeshBasicMaterial({color: 0x0000ff}) : new THREE.MeshLambertMaterial({color: 0x909090});
// Terrain: one box per stone (top at its height), or a ground plane.
if (D.stones.length) {
  for (const s of D.stones) {
    const depth = 1.0, h = s[1] - D.floor;
    const box = new THREE.Mesh(new THREE.BoxGeometry(s[2], Math.max(h, 0.02), 0.4), stoneMat);
    box.position.set(s[0], s[1] - Math.max(h, 0.02) / 2, 0); scene.add(box);
  }
} else {
  const g = new THREE.Mesh(new THREE.BoxGeometry(200, 0.02, 0.6), stoneMat); g.position.set(0, -0.01, 0); scene.add(g);
}
// Robot: a group per body; capsules (cylinder + sphere caps) and URDF visuals in body coordinates.
const groups = D.bodies.map(b => {
  const g = new THREE.Group();
  for (const seg of b.segments) {
    const a = new THREE.Vector3(0, 0, 0), e = new THREE.Vector3(seg[0], seg[1], seg[2]);
    const len = e.length();
    if (len > 1e-6) {
      const cyl = new THREE.Mesh(new THREE.CylinderGeometry(b.radius, b.radius, len, 12), robotMat);
      cyl.position.copy(e.clone().multiplyScalar(0.5));
      cyl.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), e.clone().normalize());
      g.add(cyl);
    }
    const cap = new THREE.Mesh(new THREE.SphereGeometry(b.radius, 12, 8), robotMat); cap.position.copy(e); g.add(cap);
  }
  const joint = new THREE.Mesh(new THREE.SphereGeometry(b.radius * 1.3, 12, 8), robotMat); g.add(joint);
  for (const v of b.visuals) {
    let geo = null;
    if (v.type === 'box') geo = new THREE.BoxGeometry(v.size[0], v.size[1], v.size[2]);
    if (v.type === 'cylinder') geo = new THREE.CylinderGeometry(v.size[0], v.size[0], v.size[1], 16);
    if (v.type === 'sphere') geo = new THREE.SphereGeometry(v.size[0], 16, 12);
    if (!geo) continue;
    const m = new THREE.Mesh(geo, robotMat);
    m.position.set(v.pos[0], v.pos[1], v.pos[2]); m.quaternion.set(v.quat[0], v.quat[1], v.quat[2], v.quat[3]); g.add(m);
  }
  scene.add(g); return g;
});
const com = new THREE.Mesh(new THREE.SphereGeometry(D.com_radius, 16, 12), new THREE.MeshBasicMaterial({color: test ? 0x00ff00 : 0xe08000}));
scene.add(com);
const arrows = D.contacts.map(() => { const a = new THREE.ArrowHelper(new THREE.Vector3(0, 1, 0), new THREE.Vector3(), 0.1, 0xc00000, 0.06, 0.04); scene.add(a); return a; });
const nb = D.bodies.length, nc = D.contacts.length, T = D.t.length;
let t = D.t[0], playing = !test, speed = 1, last = null;
function frameAt(time) { let lo = 0, hi = T - 1; while (lo < hi) { const mid = (lo + hi + 1) >> 1; if (D.t[mid] <= time) lo = mid; else hi = mid - 1; } return lo; }
function show(time) {
  const k = frameAt(time);
  for (let i = 0; i < nb; ++i) {
    const o = 7 * (k * nb + i), p = D.pose;
    groups[i].position.set(p[o], p[o + 1], p[o + 2]); groups[i].quaternion.set(p[o + 3], p[o + 4], p[o + 5], p[o + 6]);
  }
  com.position.set(D.com[3 * k], D.com[3 * k + 1], D.com[3 * k + 2]);
  for (let c = 0; c < nc; ++c) {
    const o = 6 * (k * nc + c), f = new THREE.Vector3(D.force[o + 3], D.force[o + 4], D.force[o + 5]);
    const len = 0.5 * f.length() / D.mg;
    arrows[c].visible = len > 1e-3 && !test;
    if (arrows[c].visible) { arrows[c].position.set(D.force[o], D.force[o + 1], D.force[o + 2]); arrows[c].setDirection(f.normalize()); arrows[c].setLength(len, 0.06, 0.04); }
  }
  camera.position.set(com.position.x + 0.3, com.position.y + 0.4, com.position.z + 3.2);
  camera.lookAt(com.position.x + 0.3, com.position.y - 0.2, com.position.z);
  document.getElementById('time').textContent = 't = ' + D.t[k].toFixed(3) + ' s';
  document.getElementById('mode').textContent = D.modes[D.mode[k]];
  document.getElementById('slider').value = Math.round(1000 * (D.t[k] - D.t[0]) / Math.max(D.t[T - 1] - D.t[0], 1e-9));
  renderer.render(scene, camera);
}
function loop(now) {
  if (playing && last !== null) { t += speed * (now - last) / 1000; if (t > D.t[T - 1]) t = D.t[0]; }
  last = now; show(t); if (!test) requestAnimationFrame(loop);
}
document.getElementById('play').onclick = () => { playing = !playing; document.getElementById('play').textContent = playing ? 'pause' : 'play'; };
document.getElementById('slider').oninput = e => { t = D.t[0] + (D.t[T - 1] - D.t[0]) * e.target.value / 1000; show(t); };
document.getElementById('speed').onchange = e => { speed = parseFloat(e.target.value); };
window.addEventListener('resize', () => { renderer.setSize(window.innerWidth, window.innerHeight); camera.aspect = window.innerWidth / window.innerHeight; camera.updateProjectionMatrix(); });
if (test) {
  // Render two times; report the robot's red-pixel centroid at each and whether each visible stone's top is blue.
  const times = location.hash.split('test=')[1].split(',').map(parseFloat);
  const gl = renderer.getContext(), W = renderer.domElement.width, H = renderer.domElement.height, px = new Uint8Array(4 * W * H);
  const report = {times: times, centroids: [], stones_checked: 0, stones_ok: 0, errors: window.__errors};
  for (const tt of times) {
    show(tt); gl.readPixels(0, 0, W, H, gl.RGBA, gl.UNSIGNED_BYTE, px);
    let n = 0, sx = 0, sy = 0;
    for (let i = 0; i < W * H; ++i) if (px[4 * i] > 200 && px[4 * i + 1] < 60 && px[4 * i + 2] < 60) { ++n; sx += i % W; sy += Math.floor(i / W); }
    report.centroids.push(n ? [sx / n, sy / n, n] : null);
    for (const s of D.stones) {
      const p = new THREE.Vector3(s[0], s[1] - 0.01, 0.19).project(camera);
      const x = Math.round((p.x + 1) / 2 * W), y = Math.round((p.y + 1) / 2 * H);
      if (x < 2 || y < 2 || x >= W - 2 || y >= H - 2) continue;
      const o = 4 * (y * W + x); report.stones_checked++;
      if (px[o + 2] > 200 && px[o] < 60 && px[o + 1] < 60) report.stones_ok++;
    }
  }
  const el = document.getElementById('test-result'); el.textContent = JSON.stringify(report);
} else { requestAnimationFrame(loop); }
)PAGE";

std::string Csp(const std::vector<std::string>& scripts, const std::string& style) {
  std::string csp = "default-src 'none'; script-src";
  for (const std::string& script : scripts) csp += " 'sha256-" + Sha256Base64(script) + "'";
  return csp + "; style-src 'sha256-" + Sha256Base64(style) + "'";
}

std::string JsonStringList(const std::vector<std::string>& items) {
  std::string out = "[";
  for (size_t i = 0; i < items.size(); ++i) out += (i ? "," : "") + JsonStringForScript(items[i]);
  return out + "]";
}

}  // namespace

AnimationRecorder::AnimationRecorder(const MultibodyModel& model, double fps, std::string three_js_path)
    : model_(&model), fps_(fps), three_js_path_(std::move(three_js_path)) {
  for (int b = 0; b < model.num_bodies(); ++b)
    if (model.body(b).name.rfind("floating_base", 0) != 0) drawn_bodies_.push_back(b);
  ws_ = std::make_unique<MultibodyWorkspace>(model);
}

AnimationRecorder::AnimationRecorder(double radius_m, double fps, std::string three_js_path)
    : point_radius_m_(radius_m), fps_(fps), three_js_path_(std::move(three_js_path)) {}

bool AnimationRecorder::BeginFrame(double t, const std::string& mode) {
  if (!times_.empty() && t < times_.back() + 1.0 / fps_ - 1e-9) return false;  // decimate to fps
  times_.push_back(t);
  auto it = std::find(modes_.begin(), modes_.end(), mode);
  if (it == modes_.end()) it = modes_.insert(modes_.end(), mode);
  mode_index_.push_back(static_cast<int>(it - modes_.begin()));
  return true;
}

void AnimationRecorder::RecordPoint(double t, const Eigen::Vector3d& p, const std::string& mode) {
  if (!BeginFrame(t, mode)) return;
  const Eigen::Vector3d c = ToThree() * p;
  for (double v : {c.x(), c.y(), c.z()}) coms_.push_back(static_cast<float>(v));
}

AnimationRecorder::~AnimationRecorder() = default;

bool AnimationRecorder::CheckWritable(const std::string& path, std::string* error) {
  *error = CheckOutputPath(path, "animation");
  return error->empty();
}

void AnimationRecorder::Record(double t, const Eigen::VectorXd& q, const std::string& mode,
                               const Eigen::VectorXd& contact_forces) {
  const MultibodyModel& model_ = *this->model_;
  if (!BeginFrame(t, mode)) return;
  MultibodyWorkspace& ws = *ws_;
  const Eigen::Matrix3d& C = ToThree();
  for (int b : drawn_bodies_) {
    const Eigen::Isometry3d X = CalcLinkPose(model_, ws, q, b);
    const Eigen::Vector3d p = C * X.translation();
    const Eigen::Quaterniond r(Eigen::Matrix3d(C * X.linear() * C.transpose()));
    for (double v : {p.x(), p.y(), p.z(), r.x(), r.y(), r.z(), r.w()}) poses_.push_back(static_cast<float>(v));
  }
  const Eigen::Vector3d c = C * CalcComPosition(model_, ws, q);
  for (double v : {c.x(), c.y(), c.z()}) coms_.push_back(static_cast<float>(v));
  for (int k = 0; k < model_.num_contacts(); ++k) {
    const ContactInfo& info = model_.contacts()[k];
    const Eigen::Vector3d p = C * CalcPointPosition(model_, ws, q, info.body, info.frame_origin);
    const Eigen::Vector3d f = C * contact_forces.segment<3>(3 * k);
    for (double v : {p.x(), p.y(), p.z(), f.x(), f.y(), f.z()}) forces_.push_back(static_cast<float>(v));
  }
}

bool AnimationRecorder::WriteHtml(const std::string& path, const std::string& title,
                                  const std::vector<AnimationStone>& stones, std::string* error) const {
  const std::string three = ReadThreeJs(three_js_path_, error);
  if (three.empty()) return false;
  if (model_ == nullptr) return WritePage(path, title, stones, three, "", error);
  const MultibodyModel& model_ = *this->model_;
  // Visual geometry from the URDF (attached to the body its link was merged into).
  std::vector<std::string> visuals(model_.num_bodies());
  if (urdf::ModelInterfaceSharedPtr urdf = ParseVisualUrdf(model_.urdf_path())) {
    for (const auto& [name, link] : urdf->links_) {
      if (!model_.HasFrame(name)) continue;
      const MultibodyFrame& frame = model_.Frame(name);
      for (const auto& visual : link->visual_array) {
        if (!visual || !visual->geometry) continue;
        std::ostringstream os;
        const Eigen::Vector3d origin(visual->origin.position.x, visual->origin.position.y, visual->origin.position.z);
        double qx, qy, qz, qw;
        visual->origin.rotation.getQuaternion(qx, qy, qz, qw);
        const Eigen::Isometry3d X_frame_visual = Eigen::Translation3d(origin) * Eigen::Quaterniond(qw, qx, qy, qz);
        const Eigen::Isometry3d X = frame.X_body_frame * X_frame_visual;
        Eigen::Matrix3d R = X.linear();
        std::string type;
        std::vector<double> size;
        switch (visual->geometry->type) {
          case urdf::Geometry::BOX: {
            const auto* g = static_cast<const urdf::Box*>(visual->geometry.get());
            type = "box";
            size = {g->dim.x, g->dim.z, g->dim.y};  // three.js axes
            break;
          }
          case urdf::Geometry::CYLINDER: {  // URDF cylinders lie along z; three.js's along y
            const auto* g = static_cast<const urdf::Cylinder*>(visual->geometry.get());
            type = "cylinder";
            size = {g->radius, g->length};
            break;
          }
          case urdf::Geometry::SPHERE: {
            type = "sphere";
            size = {static_cast<const urdf::Sphere*>(visual->geometry.get())->radius};
            break;
          }
          default: continue;  // meshes: drawn as capsules
        }
        const Eigen::Matrix3d& C = ToThree();
        const Eigen::Quaterniond q3(Eigen::Matrix3d(C * R * C.transpose()));
        const Eigen::Vector3d p3 = C * X.translation();
        os << "{\"type\":\"" << type << "\",\"size\":[";
        for (size_t i = 0; i < size.size(); ++i) os << (i ? "," : "") << size[i];
        os << "],\"pos\":[" << p3.x() << "," << p3.y() << "," << p3.z() << "],\"quat\":[" << q3.x() << "," << q3.y()
           << "," << q3.z() << "," << q3.w() << "]}";
        std::string& list = visuals[frame.body];
        list += (list.empty() ? "" : ",") + os.str();
      }
    }
  }
  std::ostringstream data;
  data.precision(6);
  data << "\"bodies\":[";
  for (size_t i = 0; i < drawn_bodies_.size(); ++i) {
    const int b = drawn_bodies_[i];
    data << (i ? "," : "") << "{\"name\":" << JsonStringForScript(model_.body(b).name)
         << ",\"radius\":0.02,\"segments\":[";
    bool first = true;
    if (visuals[b].empty()) {
      // Capsules from the body's joint origin to each child's joint origin and to its contact points.
      for (int c = 0; c < model_.num_bodies(); ++c)
        if (model_.body(c).parent == b) {
          data << (first ? "" : ",");
          AppendVec(data, model_.body(c).X_parent_joint.translation());
          first = false;
        }
      for (const ContactInfo& info : model_.contacts())
        if (info.body == b)
          for (const Eigen::Vector3d& p : info.points) {
            data << (first ? "" : ",");
            AppendVec(data, p);
            first = false;
          }
      // A body whose joints all sit at its origin (a torso carrying the hips): a capsule through its COM.
      double longest = 0.0;
      for (int c = 0; c < model_.num_bodies(); ++c)
        if (model_.body(c).parent == b) longest = std::max(longest, model_.body(c).X_parent_joint.translation().norm());
      for (const ContactInfo& info : model_.contacts())
        if (info.body == b) longest = 1.0;
      if (longest < 1e-3 && model_.body(b).com.norm() > 1e-6) {
        data << (first ? "" : ",");
        AppendVec(data, 2.0 * model_.body(b).com);
      }
    }
    data << "],\"visuals\":[" << visuals[b] << "]}";
  }
  std::vector<std::string> contact_names;
  for (const ContactInfo& info : model_.contacts()) contact_names.push_back(info.name);
  data << "],\"contacts\":" << JsonStringList(contact_names) << ",\"mg\":" << model_.total_mass() * 9.81
       << ",\"com_radius\":0.03,";
  return WritePage(path, title, stones, three, data.str(), error);
}

bool AnimationRecorder::WritePage(const std::string& path, const std::string& title,
                                  const std::vector<AnimationStone>& stones, const std::string& three,
                                  const std::string& model_json, std::string* error) const {
  std::ostringstream data;
  data.precision(6);
  data << "{"
       << (model_json.empty() ? "\"bodies\":[],\"contacts\":[],\"mg\":1,\"com_radius\":" + Format(point_radius_m_) + ","
                              : model_json);
  data << "\"modes\":" << JsonStringList(modes_);
  double floor = 0.0;
  for (const AnimationStone& s : stones) floor = std::min(floor, s.top_height_m - 0.3);
  data << ",\"floor\":" << floor << ",\"stones\":[";
  for (size_t i = 0; i < stones.size(); ++i)
    data << (i ? "," : "") << "[" << stones[i].x_center_m << "," << stones[i].top_height_m << "," << stones[i].length_m
         << "]";
  data << "],\"t\":";
  std::vector<float> t(times_.begin(), times_.end());
  AppendFloats(data, t, 4);
  data << ",\"mode\":[";
  for (size_t i = 0; i < mode_index_.size(); ++i) data << (i ? "," : "") << mode_index_[i];
  data << "],\"pose\":";
  AppendFloats(data, poses_, 4);
  data << ",\"com\":";
  AppendFloats(data, coms_, 4);
  data << ",\"force\":";
  AppendFloats(data, forces_, 2);
  data << "}";
  const std::string main_script = "\nconst D = " + data.str() + ";" + kMainScript;
  const std::vector<std::string> scripts = {kErrorScript, three, main_script};
  std::string body = kBody;
  body.replace(body.find("@TITLE@"), 7, HtmlText(title));
  std::string page =
      "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\">\n<meta http-equiv=\"Content-Security-Policy\" content=\"" +
      Csp(scripts, kStyle) + "\">\n<title>" + HtmlText(title) + "</title>\n<style>" + kStyle +
      "</style></head><body>\n" + body;
  for (const std::string& script : scripts) page += "<script>" + script + "</script>\n";
  page += "</body></html>\n";
  try {
    WriteFileAtomically(path, page, "animation");
  } catch (const std::exception& e) {
    *error = e.what();
    return false;
  }
  return true;
}

}  // namespace rome::visualization
