// The skinned .glb: read back with tinygltf and skinned here, by hand,
// from the file's joints, weights, inverse bind matrices and animation, at sampled frames, against
// the .pc2 of the same bake (the exact positions the simulator baked); the weights' invariants; a
// tube at rest moves no joint; and the Khronos validator.
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <tuple>

#include "bind/support.h"
#include "pc2_reader.h"
#include "sweep/assets/bake_run.h"
#include "sweep/bind/bind.h"

using sweep::assets::run_bake;

namespace sweep::sim {
namespace {

namespace fs = std::filesystem;
using Frames = std::vector<std::vector<bind::Vec3f>>;
using test::read_pc2;

struct Tube {
  Mesh mesh = tube::make_tube(test::straight_tube_params());
  Rig rig = test::rig_of({test::straight_sweep()});
  bind::Binding binding = bind::bind_rig(rig, mesh);
};

Scene scene_with(std::vector<SceneForce> forces, double duration) {
  Scene s;
  s.duration = duration;
  s.fps = 30;
  s.substeps = 4;
  s.forces = std::move(forces);
  for (SceneForce& f : s.forces) f.sweep_index = 0;
  return s;
}

// A push on the tip, about y, that bends the whole tube (chain) and squeezes it.
SceneForce tip_push() {
  SceneForce f;
  f.sweep = "tube";
  f.spec.t = 1.0;
  f.spec.theta = 0.0;
  f.spec.vector = Vec3(0.5, 2, 0);
  f.spec.components = kRotational | kRadial;
  f.spec.target = RotationTarget::chain;
  f.start = 0;
  f.end = 0.5;
  return f;
}

// Every element of a dense accessor as doubles (float, unsigned byte or unsigned short).
std::vector<double> read_numbers(const tinygltf::Model& m, int index) {
  const tinygltf::Accessor& a = m.accessors.at(static_cast<std::size_t>(index));
  EXPECT_FALSE(a.sparse.isSparse);
  const tinygltf::BufferView& view = m.bufferViews.at(static_cast<std::size_t>(a.bufferView));
  EXPECT_EQ(view.byteStride, 0u);
  const int components = tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(a.type));
  const std::size_t count = a.count * static_cast<std::size_t>(components);
  const unsigned char* base = m.buffers[0].data.data() + view.byteOffset + a.byteOffset;
  std::vector<double> out(count);
  for (std::size_t i = 0; i < count; ++i) {
    switch (a.componentType) {
      case TINYGLTF_COMPONENT_TYPE_FLOAT: {
        float f;
        std::memcpy(&f, base + 4 * i, 4);
        out[i] = f;
        break;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        out[i] = base[i];
        break;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        std::uint16_t s;
        std::memcpy(&s, base + 2 * i, 2);
        out[i] = s;
        break;
      }
      default:
        ADD_FAILURE() << "unexpected component type " << a.componentType;
    }
  }
  return out;
}

// A skinned glTF read back: per frame key, the world matrix of every skin joint, and per vertex
// its joints and weights; skinned(k) does linear blend skinning as an engine does.
struct SkinFile {
  tinygltf::Model model;
  std::vector<Eigen::Vector3d> rest;
  std::vector<std::array<int, 4>> joints;
  std::vector<std::array<double, 4>> weights;
  std::vector<Eigen::Matrix4d> inverse_bind;
  std::vector<int> skin_joints;  // node indices
  std::vector<double> times;
  // node → path → flat keys
  std::map<int, std::map<std::string, std::vector<double>>> tracks;
  int channels = 0;

  explicit SkinFile(const fs::path& path) {
    tinygltf::TinyGLTF loader;
    std::string err, warn;
    EXPECT_TRUE(loader.LoadBinaryFromFile(&model, &err, &warn, path.string())) << err;
    EXPECT_EQ(model.meshes.size(), 1u);
    EXPECT_EQ(model.skins.size(), 1u);
    const tinygltf::Primitive& p = model.meshes[0].primitives[0];
    EXPECT_TRUE(p.targets.empty()) << "a skinned bake has no morph targets";
    const std::vector<double> pos = read_numbers(model, p.attributes.at("POSITION"));
    for (std::size_t v = 0; v < pos.size() / 3; ++v) rest.emplace_back(pos[3 * v], pos[3 * v + 1], pos[3 * v + 2]);
    const std::vector<double> j = read_numbers(model, p.attributes.at("JOINTS_0"));
    const std::vector<double> w = read_numbers(model, p.attributes.at("WEIGHTS_0"));
    EXPECT_EQ(model.accessors[static_cast<std::size_t>(p.attributes.at("WEIGHTS_0"))].componentType,
              TINYGLTF_COMPONENT_TYPE_FLOAT);
    for (std::size_t v = 0; v < rest.size(); ++v) {
      joints.push_back({int(j[4 * v]), int(j[4 * v + 1]), int(j[4 * v + 2]), int(j[4 * v + 3])});
      weights.push_back({w[4 * v], w[4 * v + 1], w[4 * v + 2], w[4 * v + 3]});
    }
    const tinygltf::Skin& skin = model.skins[0];
    skin_joints = skin.joints;
    const std::vector<double> ibm = read_numbers(model, skin.inverseBindMatrices);
    for (std::size_t k = 0; k < skin_joints.size(); ++k) {
      Eigen::Matrix4d mat;
      for (int c = 0; c < 16; ++c) mat(c % 4, c / 4) = ibm[16 * k + static_cast<std::size_t>(c)];
      inverse_bind.push_back(mat);
    }
    EXPECT_EQ(model.animations.size(), 1u);
    for (const auto& ch : model.animations[0].channels) {
      const auto& sampler = model.animations[0].samplers[static_cast<std::size_t>(ch.sampler)];
      EXPECT_EQ(sampler.interpolation, "LINEAR");
      times = read_numbers(model, sampler.input);
      tracks[ch.target_node][ch.target_path] = read_numbers(model, sampler.output);
      ++channels;
    }
  }

  // Node `node`'s local matrix at key k (its channels, else its own TRS).
  Eigen::Matrix4d local(int node, std::size_t k) const {
    const tinygltf::Node& n = model.nodes[static_cast<std::size_t>(node)];
    Eigen::Vector3d t = Eigen::Vector3d::Zero(), s = Eigen::Vector3d::Ones();
    Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
    if (n.translation.size() == 3) t = {n.translation[0], n.translation[1], n.translation[2]};
    if (n.rotation.size() == 4) q = Eigen::Quaterniond(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]);
    if (n.scale.size() == 3) s = {n.scale[0], n.scale[1], n.scale[2]};
    if (const auto it = tracks.find(node); it != tracks.end()) {
      for (const auto& [path, v] : it->second) {
        if (path == "translation") t = {v[3 * k], v[3 * k + 1], v[3 * k + 2]};
        if (path == "rotation") q = Eigen::Quaterniond(v[4 * k + 3], v[4 * k], v[4 * k + 1], v[4 * k + 2]);
        if (path == "scale") s = {v[3 * k], v[3 * k + 1], v[3 * k + 2]};
      }
    }
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    m.topLeftCorner<3, 3>() = q.normalized().toRotationMatrix() * s.asDiagonal();
    m.topRightCorner<3, 1>() = t;
    return m;
  }
  Eigen::Matrix4d global(int node, std::size_t k) const {
    for (std::size_t parent = 0; parent < model.nodes.size(); ++parent) {
      const auto& c = model.nodes[parent].children;
      if (std::find(c.begin(), c.end(), node) != c.end()) return global(static_cast<int>(parent), k) * local(node, k);
    }
    return local(node, k);
  }
  std::vector<Eigen::Vector3d> skinned(std::size_t k) const {
    std::vector<Eigen::Matrix4d> m;
    for (std::size_t j = 0; j < skin_joints.size(); ++j) m.push_back(global(skin_joints[j], k) * inverse_bind[j]);
    std::vector<Eigen::Vector3d> out;
    for (std::size_t v = 0; v < rest.size(); ++v) {
      Eigen::Vector4d p = Eigen::Vector4d::Zero();
      for (int c = 0; c < 4; ++c)
        p += weights[v][static_cast<std::size_t>(c)] *
             (m[static_cast<std::size_t>(joints[v][static_cast<std::size_t>(c)])] * rest[v].homogeneous());
      out.push_back(p.head<3>());
    }
    return out;
  }
};

struct SkinBake {
  sweep::assets::BakeReport report;
  Frames pc2;
  fs::path glb;
};

// This test process's bakes: one folder, removed with its files when the process exits (CTest runs
// each test in a process of its own), so that the .glb paths handed out stay valid until then.
const fs::path& skin_dir() {
  struct Scratch {
    fs::path path = fs::temp_directory_path() / ("sweep_skin_test_" + std::to_string(::getpid()));
    Scratch() { fs::create_directories(path); }
    ~Scratch() {
      std::error_code ignored;
      fs::remove_all(path, ignored);
    }
  };
  static const Scratch scratch;
  return scratch.path;
}

SkinBake bake_skinned(const Tube& tube, const Scene& scene, int joints, const std::string& name, int ring = 1,
                      bool fit = false) {
  const fs::path& dir = skin_dir();
  sweep::assets::BakeOptions o;
  o.outputs = {dir / (name + ".glb"), dir / (name + ".pc2")};
  o.joints = joints;
  o.ring_joints = ring;
  o.ring_fit = fit;
  SkinBake b;
  b.report = run_bake(tube.mesh, tube.rig, tube.binding, scene, o);
  b.pc2 = read_pc2(dir / (name + ".pc2"));
  b.glb = dir / (name + ".glb");
  return b;
}

// The Khronos validator's report on `glb` (tests/gltf-validator/validate.js) and its exit code.
std::pair<int, std::string> validate(const fs::path& glb) {
  const fs::path script = fs::path(SWEEP_SOURCE_DIR) / "tests/gltf-validator/validate.js";
  const std::string command = "node '" + script.string() + "' '" + glb.string() + "' 2>&1";
  std::string report;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return {-1, ""};
  char buf[4096];
  std::size_t got;
  while ((got = std::fread(buf, 1, sizeof buf, pipe)) > 0) report.append(buf, got);
  const int status = ::pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, report};
}

// Largest distance between the file skinned at key k and pc2 frame k, over the tube's length (1).
double file_error(const SkinFile& file, const Frames& pc2, std::size_t k) {
  const std::vector<Eigen::Vector3d> got = file.skinned(k);
  double worst = 0;
  for (std::size_t v = 0; v < got.size(); ++v) worst = std::max(worst, (got[v] - pc2[k][v].cast<double>()).norm());
  return worst;
}

TEST(BakeSkin, SkinnedByHandFromTheFileItMatchesTheBakeWithinTheReportedError) {
  const Tube tube;
  for (const int joints : {4, 8}) {
    const SkinBake b = bake_skinned(tube, scene_with({tip_push()}, 2.0), joints, "push" + std::to_string(joints));
    const SkinFile file(b.glb);
    ASSERT_EQ(file.skin_joints.size(), 1u + static_cast<std::size_t>(joints));
    EXPECT_EQ(b.report.skin_joints, 1 + joints);
    ASSERT_EQ(file.times.size(), b.pc2.size());
    const double reported = b.report.skin_error.max_relative;  // the tube is 1 long
    EXPECT_GT(reported, 1e-4) << "the tube bent and squeezed: 2-joint spans cannot be exact";
    EXPECT_LT(reported, 0.05);
    EXPECT_LE(b.report.skin_error.rms_relative, reported);
    EXPECT_GT(b.report.skin_error.rms_relative, 0);
    double seen = 0;
    for (std::size_t k = 0; k < b.pc2.size(); k += 3) {
      const double e = file_error(file, b.pc2, k);
      EXPECT_LE(e, reported * (1 + 1e-5) + 1e-7) << "frame " << k;
      seen = std::max(seen, e);
    }
    // The worst frame the writer reported, skinned here, shows that error.
    const double at_worst = file_error(file, b.pc2, static_cast<std::size_t>(b.report.skin_error.max_frame));
    EXPECT_NEAR(at_worst, reported, 1e-5 * reported + 1e-7);
    EXPECT_GT(seen, 0.3 * reported);
  }
  // A bend alone (no radial push, whose uneven squeeze no joint's in-plane scale can carry): more
  // joints, less error.
  SceneForce bend = tip_push();
  bend.spec.components = kRotational;
  const Tube t2;
  const double e4 = bake_skinned(t2, scene_with({bend}, 2.0), 4, "e4").report.skin_error.max_relative;
  const double e16 = bake_skinned(t2, scene_with({bend}, 2.0), 16, "e16").report.skin_error.max_relative;
  EXPECT_GT(e4, 1e-4);
  EXPECT_LT(e16, 0.5 * e4) << e4;
}

// A skin joint's place from its node's name: "tube.03" is station 3, "tube.03.r05" its ring joint
// 5; the body joint is station −1.
struct JointPlace {
  int station = -1;
  int ring = -1;
};
JointPlace place_of(const SkinFile& file, int joint) {
  const std::string& name =
      file.model.nodes[static_cast<std::size_t>(file.skin_joints[static_cast<std::size_t>(joint)])].name;
  JointPlace p;
  const std::size_t dot = name.find('.');
  if (dot == std::string::npos) return p;
  p.station = std::stoi(name.substr(dot + 1, name.find('.', dot + 1) - dot - 1));
  if (const std::size_t r = name.find(".r"); r != std::string::npos) p.ring = std::stoi(name.substr(r + 2));
  return p;
}

TEST(BakeSkin, WeightsAreAtMostFourNonNegativeSumToOneAndBilinearInTAndTheta) {
  const Tube tube;
  const int joints = 6;
  for (const int ring : {1, 8, 5}) {
    SCOPED_TRACE("ring " + std::to_string(ring));
    const SkinBake b = bake_skinned(tube, scene_with({tip_push()}, 0.5), joints, "weights", ring);
    const SkinFile file(b.glb);
    ASSERT_EQ(file.skin_joints.size(), 1u + joints + (ring > 1 ? (joints - 1) * ring : 0));
    const bind::SweepBinding& bound = tube.binding.sweeps[0];
    std::vector<int> index(tube.mesh.vertex_count(), -1);
    for (std::size_t i = 0; i < bound.size(); ++i) index[bound.vertices[i]] = static_cast<int>(i);
    const double h = 1.0 / (joints - 1);
    int ring_weighted = 0;
    for (std::size_t v = 0; v < file.rest.size(); ++v) {
      double sum = 0;
      int used = 0;
      for (int c = 0; c < 4; ++c) {
        const double w = file.weights[v][static_cast<std::size_t>(c)];
        EXPECT_GE(w, 0) << v;
        sum += w;
        used += w > 0;
      }
      EXPECT_NEAR(sum, 1.0, 2e-7) << v;
      EXPECT_LE(used, 4);
      if (index[v] < 0) {  // unbound: the body joint alone
        EXPECT_EQ(file.joints[v][0], 0) << v;
        EXPECT_EQ(file.weights[v][0], 1.0) << v;
        continue;
      }
      // Bound: the weighted mean of the joints' stations is the vertex's t (hat functions), only
      // the two stations around it carry weight, and at a station the weighted mean of its ring
      // joints' angles is the vertex's θ (hat functions in θ, between two neighbouring joints).
      const double t = bound.t[static_cast<std::size_t>(index[v])];
      const double theta = bound.theta[static_cast<std::size_t>(index[v])];
      double mean = 0, mass = 0;
      std::map<int, std::vector<std::pair<int, double>>> rings;  // station → (ring joint, weight)
      for (int c = 0; c < 4; ++c) {
        const JointPlace p = place_of(file, file.joints[v][static_cast<std::size_t>(c)]);
        const double w = file.weights[v][static_cast<std::size_t>(c)];
        if (w == 0 || p.station < 0) continue;
        EXPECT_LE(std::abs(p.station * h - t), h * (1 + 1e-6)) << v;
        mean += w * p.station * h;
        mass += w;
        if (p.ring >= 0) rings[p.station].push_back({p.ring, w});
        EXPECT_TRUE(ring > 1 || p.ring < 0);
        if (ring > 1 && p.station > 0 && p.ring < 0) ADD_FAILURE() << "vertex " << v << ": no ring split";
      }
      ASSERT_GT(mass, 0) << v;
      EXPECT_NEAR(mean / mass, std::clamp(t, 0.0, 1.0), 1e-5) << v;
      const double cell = 2 * std::numbers::pi / ring;
      for (auto& [station, list] : rings) {
        ASSERT_LE(list.size(), 2u) << v;
        ++ring_weighted;
        double angle = 0, m = 0;
        for (const auto& [r, w] : list) {
          // The joint's angle, unwrapped to within a cell of θ.
          double a = r * cell;
          if (a - theta > std::numbers::pi) a -= 2 * std::numbers::pi;
          if (theta - a > std::numbers::pi) a += 2 * std::numbers::pi;
          EXPECT_LE(std::abs(a - theta), cell * (1 + 1e-6)) << v;
          angle += w * a;
          m += w;
        }
        EXPECT_NEAR(angle / m, theta, 1e-5) << v;
      }
    }
    if (ring > 1) {
      EXPECT_GT(ring_weighted, 500);
    }
  }
}

// A blend zone deeper than a span (0.3 of the tube, spans of 0.2): a blended vertex beyond the
// first span would weigh two stations' ring joints and the body, 5 joints; it keeps the ring split
// at its nearer station and that station joint takes the other's share. Still at most 4, ≥ 0,
// summing to 1, and the file skinned by hand shows the error the writer reported.
TEST(BakeSkin, ADeepBlendZoneKeepsFourInfluences) {
  Tube tube;
  tube.binding = bind::bind_rig(tube.rig, tube.mesh, {.blend = 0.3});
  const SkinBake b = bake_skinned(tube, scene_with({tip_push()}, 1.0), 6, "blend", 8);
  const SkinFile file(b.glb);
  int five = 0;  // vertices that took the fallback: a station joint beside ring joints and the body
  for (std::size_t v = 0; v < file.rest.size(); ++v) {
    double sum = 0;
    bool body = false, station = false, ring = false;
    for (int c = 0; c < 4; ++c) {
      const double w = file.weights[v][static_cast<std::size_t>(c)];
      EXPECT_GE(w, 0) << v;
      sum += w;
      if (w == 0) continue;
      const JointPlace p = place_of(file, file.joints[v][static_cast<std::size_t>(c)]);
      body = body || p.station < 0;
      station = station || (p.station > 0 && p.ring < 0);
      ring = ring || p.ring >= 0;
    }
    EXPECT_NEAR(sum, 1.0, 2e-7) << v;
    five += body && station && ring;
  }
  EXPECT_GT(five, 24) << "a ring of blended vertices in the second span";
  const double reported = b.report.skin_error.max_relative;
  EXPECT_LT(reported, 0.05);
  for (std::size_t k = 0; k < b.pc2.size(); k += 4)
    EXPECT_LE(file_error(file, b.pc2, k), reported * (1 + 1e-5) + 1e-7) << "frame " << k;
}

// A radial push on one handle of one section dents the tube there: the section's other handles
// stay. One joint a station scales or shifts the whole section and cannot follow; ring joints
// around it carry the dent at their angles, and the file, skinned by hand through its joint tree,
// shows the error the writer reported.
TEST(BakeSkin, RingJointsCarryAOneHandleDentThatSectionJointsCannot) {
  const Tube tube;
  SceneForce dent;
  dent.sweep = "tube";
  dent.spec.t = 0.6;      // section 3
  dent.spec.theta = 0.0;  // its handle 0 alone
  dent.spec.vector = Vec3(-10, 0, 0);
  dent.spec.components = kRadial;
  dent.start = 0;
  dent.end = 0.5;
  const Scene scene = scene_with({dent}, 1.0);
  const SkinBake section = bake_skinned(tube, scene, 6, "dent1", 1);
  const SkinBake ring = bake_skinned(tube, scene, 6, "dent8", 8);
  double dent_depth = 0;  // the largest displacement in the bake, mesh units (the tube is 1 long)
  for (const auto& frame : ring.pc2)
    for (std::size_t v = 0; v < frame.size(); ++v)
      dent_depth = std::max(dent_depth, double((frame[v] - tube.mesh.positions[v].cast<float>()).norm()));
  ASSERT_GT(dent_depth, 0.02) << "the push dents the tube by a fifth of its radius or more";
  const double e1 = section.report.skin_error.max_relative, e8 = ring.report.skin_error.max_relative;
  // Measured: a dent of 0.035; section joints 0.022 (RMS 0.0019), 8 ring joints 0.0061 (RMS
  // 0.00052), fitted by least squares 0.0073 (RMS 0.00031): what is left is the sweep's cubics
  // (Hermite in t, Catmull-Rom in θ) against the skin's hats between joints. The bound is the
  // issue's 1 % of the length.
  EXPECT_GT(e1, 0.01) << "section joints miss most of a one-handle dent";
  EXPECT_LT(e8, 0.01) << e1;
  EXPECT_LT(e8, 0.5 * e1);
  EXPECT_LT(ring.report.skin_error.rms_relative, 0.35 * section.report.skin_error.rms_relative);
  const SkinBake fitted = bake_skinned(tube, scene, 6, "dent8fit", 8, true);
  EXPECT_LT(fitted.report.skin_error.max_relative, 0.01);
  EXPECT_LT(fitted.report.skin_error.rms_relative, 0.7 * ring.report.skin_error.rms_relative)
      << "the least-squares fit lowers the RMS error";
  const SkinFile file(ring.glb);
  double seen = 0;
  for (std::size_t k = 0; k < ring.pc2.size(); k += 2) {
    const double e = file_error(file, ring.pc2, k);
    EXPECT_LE(e, e8 * (1 + 1e-5) + 1e-7) << "frame " << k;
    seen = std::max(seen, e);
  }
  EXPECT_NEAR(file_error(file, ring.pc2, static_cast<std::size_t>(ring.report.skin_error.max_frame)), e8,
              1e-5 * e8 + 1e-7);
  // A ring joint is keyed by scale alone, a child of its station joint, which has none.
  for (const auto& [node, paths] : file.tracks) {
    const std::string& name = file.model.nodes[static_cast<std::size_t>(node)].name;
    if (name.find(".r") != std::string::npos) {
      EXPECT_EQ(paths.size(), 1u) << name;
      EXPECT_TRUE(paths.count("scale")) << name;
    } else {
      EXPECT_FALSE(paths.count("scale")) << name;
    }
  }
}

TEST(BakeSkin, AStraightTubeAtRestHasIdentityJointMotionAndNoError) {
  const Tube tube;
  const SkinBake b = bake_skinned(tube, scene_with({}, 1.0), 5, "rest");
  EXPECT_LE(b.report.skin_error.max_relative, 1e-6);
  const SkinFile file(b.glb);
  ASSERT_EQ(file.times.size(), 31u);
  EXPECT_GT(file.channels, 0);
  for (std::size_t k = 0; k < file.times.size(); ++k) {
    for (std::size_t j = 0; j < file.skin_joints.size(); ++j) {
      const Eigen::Matrix4d m = file.global(file.skin_joints[j], k) * file.inverse_bind[j];
      EXPECT_LE((m - Eigen::Matrix4d::Identity()).cwiseAbs().maxCoeff(), 1e-6) << "joint " << j << " key " << k;
    }
  }
  const std::vector<Eigen::Vector3d> last = file.skinned(file.times.size() - 1);
  for (std::size_t v = 0; v < last.size(); ++v) EXPECT_LE((last[v] - tube.mesh.positions[v]).norm(), 1e-6) << v;
}

TEST(BakeSkin, AMovingBodyAnimatesTheRootJointAndTheWorldPositionsFollow) {
  const Tube tube;
  Scene scene = scene_with({tip_push()}, 1.0);
  scene.body = BodyPath(
      {{0.0, Vec3::Zero(), Quat::Identity()}, {1.0, Vec3(0.3, 0.1, 0), Quat(Eigen::AngleAxisd(0.4, Vec3::UnitY()))}},
      BodyInterpolation::cubic);
  for (const int ring : {1, 8}) {
    const SkinBake b = bake_skinned(tube, scene, 8, "body" + std::to_string(ring), ring);
    const SkinFile file(b.glb);
    ASSERT_TRUE(file.tracks.count(0)) << "the body joint is animated";
    const double reported = b.report.skin_error.max_relative;
    for (std::size_t k = 0; k < b.pc2.size(); k += 5)  // .pc2 holds world positions
      EXPECT_LE(file_error(file, b.pc2, k), reported * (1 + 1e-5) + 1e-6) << "ring " << ring << " frame " << k;
    EXPECT_GT((b.pc2.back()[0] - b.pc2.front()[0]).norm(), 0.2f) << "the body moved the mesh";
  }
}

TEST(BakeSkin, TheValidatorFindsNoErrorsOrWarnings) {
  const fs::path package = fs::path(SWEEP_SOURCE_DIR) / "tests/gltf-validator/node_modules/gltf-validator";
  ASSERT_TRUE(fs::exists(package / "package.json")) << "run tools/setup-deps.sh";
  const Tube tube;
  Scene moving = scene_with({tip_push()}, 0.5);
  moving.body = BodyPath({{0.0, Vec3::Zero(), Quat::Identity()}, {0.5, Vec3(0.3, 0.1, 0), Quat::Identity()}},
                         BodyInterpolation::linear);
  for (const auto& [name, scene, joints, ring] :
       {std::tuple{"v-push", scene_with({tip_push()}, 0.5), 8, 1}, std::tuple{"v-rest", scene_with({}, 0.2), 2, 1},
        std::tuple{"v-body", moving, 41, 1}, std::tuple{"v-ring", scene_with({tip_push()}, 0.5), 8, 8},
        std::tuple{"v-ring-body", moving, 5, 3}, std::tuple{"v-ring-rest", scene_with({}, 0.2), 2, 4},
        std::tuple{"v-ring-wide", scene_with({tip_push()}, 0.2), 41, 8}}) {
    const SkinBake b = bake_skinned(tube, scene, joints, name, ring);
    const auto [code, report] = validate(b.glb);
    EXPECT_EQ(code, 0) << name << ": " << report;
    EXPECT_NE(report.find("\"numErrors\": 0"), std::string::npos) << report;
    EXPECT_NE(report.find("\"numWarnings\": 0"), std::string::npos) << report;
  }
}

TEST(BakeSkin, BadJointCountsAreRefusedBeforeAnythingIsWritten) {
  const Tube tube;
  const fs::path dir = fs::temp_directory_path() / ("sweep_skin_bad_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  // The tube has K = 6 sections: 41 stations at 8 a span.
  for (const int joints : {-1, 1, 42, 256}) {
    sweep::assets::BakeOptions o;
    o.outputs = {dir / "bad.glb", dir / "bad.pc2"};
    o.joints = joints;
    try {
      run_bake(tube.mesh, tube.rig, tube.binding, scene_with({tip_push()}, 0.2), o);
      ADD_FAILURE() << joints << " joints accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.category(), ErrorCategory::usage) << e.what();
      EXPECT_NE(std::string(e.what()).find("--joints"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(fs::is_empty(dir)) << joints;
  }
  for (const int ring : {0, -2, 65}) {
    sweep::assets::BakeOptions o;
    o.outputs = {dir / "bad.glb"};
    o.joints = 4;
    o.ring_joints = ring;
    try {
      run_bake(tube.mesh, tube.rig, tube.binding, scene_with({tip_push()}, 0.2), o);
      ADD_FAILURE() << ring << " ring joints accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.category(), ErrorCategory::usage) << e.what();
      EXPECT_NE(std::string(e.what()).find("--ring-joints"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(fs::is_empty(dir)) << ring;
  }
  sweep::assets::BakeOptions o;
  o.outputs = {dir / "only.pc2"};
  o.joints = 8;
  EXPECT_THROW(run_bake(tube.mesh, tube.rig, tube.binding, scene_with({}, 0.2), o), Error);
  EXPECT_TRUE(fs::is_empty(dir));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace sweep::sim
