// libsweep through its C interface (sweep/sweep.h), as an engine drives it: the bent tube of
// rigs/tube-bent.rig.json on a mesh with a few vertices no part binds (the body), bound by the
// sweep-bind tool, opened from files, advanced frame by frame with live input.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "sweep/io/binding_file.h"
#include "sweep/io/rig_json.h"
#include "sweep/sweep.h"

namespace {

namespace fs = std::filesystem;

// The vertices appended to the tube: a small tetrahedron beside its root, bound to no part.
constexpr int kBodyVertices = 4;

void write_text(const fs::path& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
  ASSERT_TRUE(out.good()) << path;
}

class CApi : public testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(fs::temp_directory_path() / ("sweep-capi-test-" + std::to_string(::getpid())));
    fs::create_directories(*dir_);
    // The tube's mesh and four more vertices (one more face) away from it.
    std::ifstream in(fs::path(SWEEP_SOURCE_DIR) / "meshes/tube_bent.obj");
    std::stringstream obj;
    obj << in.rdbuf();
    std::string text = obj.str();
    int tube_vertices = 0;
    std::istringstream lines(text);
    for (std::string line; std::getline(lines, line);) tube_vertices += line.rfind("v ", 0) == 0;
    text += "\nv -0.5 -0.5 0.0\nv -0.4 -0.5 0.0\nv -0.5 -0.4 0.0\nv -0.5 -0.5 0.1\n";
    for (const char* face : {"f %d %d %d\n"}) {
      char buf[64];
      const int a = tube_vertices + 1;
      std::snprintf(buf, sizeof buf, face, a, a + 1, a + 2);
      text += buf;
      std::snprintf(buf, sizeof buf, face, a, a + 1, a + 3);
      text += buf;
      std::snprintf(buf, sizeof buf, face, a, a + 2, a + 3);
      text += buf;
      std::snprintf(buf, sizeof buf, face, a + 1, a + 2, a + 3);
      text += buf;
    }
    write_text(*dir_ / "mesh.obj", text);
    // The rig, its mesh this one.
    std::ifstream rig_in(fs::path(SWEEP_SOURCE_DIR) / "rigs/tube-bent.rig.json");
    std::stringstream rig;
    rig << rig_in.rdbuf();
    std::string rig_text = rig.str();
    const std::string from = "\"../meshes/tube_bent.obj\"";
    rig_text.replace(rig_text.find(from), from.size(), "\"mesh.obj\"");
    write_text(*dir_ / "tube.rig.json", rig_text);
    const std::string bind = std::string(SWEEP_BIND_EXE) + " -q " + (*dir_ / "tube.rig.json").string() + " -o " +
                             (*dir_ / "tube.bind").string();
    ASSERT_EQ(std::system(bind.c_str()), 0) << bind;
    // The rest positions, as an engine holds them: floats.
    rest_ = new std::vector<float>;
    std::istringstream v_lines(text);
    for (std::string line; std::getline(v_lines, line);) {
      if (line.rfind("v ", 0) != 0) continue;
      std::istringstream s(line.substr(2));
      float x, y, z;
      s >> x >> y >> z;
      rest_->insert(rest_->end(), {x, y, z});
    }
    length_ = sweep::io::read_rig(*dir_ / "tube.rig.json").sweeps[0].rest.length();
  }
  static void TearDownTestSuite() {
    fs::remove_all(*dir_);
    delete dir_;
    delete rest_;
  }

  static std::string path(const std::string& name) { return (*dir_ / name).string(); }
  static int vertex_count() { return static_cast<int>(rest_->size() / 3); }
  // A scene file of settings `body` (JSON members) in the test folder.
  static std::string scene(const std::string& name, const std::string& body) {
    write_text(*dir_ / name, R"({"format": "sweep-scene", "version": 1, "duration": 2, "fps": 30)" + body + "}");
    return path(name);
  }
  static sweep_instance* open(const char* settings) {
    sweep_instance* in =
        sweep_open(path("tube.rig.json").c_str(), path("tube.bind").c_str(), settings, rest_->data(), vertex_count());
    EXPECT_NE(in, nullptr) << sweep_last_error();
    return in;
  }
  static std::vector<float> positions(const sweep_instance* in) {
    std::vector<float> p(rest_->size());
    EXPECT_EQ(sweep_positions(in, p.data()), SWEEP_OK) << sweep_last_error();
    return p;
  }
  static double max_difference(const std::vector<float>& a, const std::vector<float>& b, int first = 0,
                               int count = -1) {
    double d = 0;
    const int end = count < 0 ? static_cast<int>(a.size() / 3) : first + count;
    for (int v = first; v < end; ++v) {
      double s = 0;
      for (int c = 0; c < 3; ++c) s += std::pow(double(a[3 * v + c]) - double(b[3 * v + c]), 2);
      d = std::max(d, std::sqrt(s));
    }
    return d;
  }

  static fs::path* dir_;
  static std::vector<float>* rest_;
  static double length_;
};

fs::path* CApi::dir_ = nullptr;
std::vector<float>* CApi::rest_ = nullptr;
double CApi::length_ = 0;

// A force given live acts as the same force read from a scene file (same point, vector and times,
// the scene's defaults): frame by frame, a held one and an impulse, switched on between internal
// steps (0.1 s at 1/30 s frames is on the grid; 0.7 s + 1/144 s is not).
TEST_F(CApi, LiveForceEqualsSceneForce) {
  const double t_held = 0.1, t_impulse = 0.7 + 1.0 / 144;
  std::ostringstream forces;
  forces.precision(17);
  forces << R"(, "forces": [{"sweep": "tube", "point": [1.0, 0.1, 0.8], "vector": [0, 2.5, -1], "start": )" << t_held
         << R"(, "end": )" << t_held + 0.4
         << R"(}, {"sweep": "tube", "point": [1.3, 0.0, 1.0], "vector": [0.5, -4, 0], "start": )" << t_impulse << "}]";
  sweep_instance* from_scene = open(scene("forces.scene.json", forces.str()).c_str());
  sweep_instance* live = open(scene("none.scene.json", R"(, "forces": [])").c_str());
  ASSERT_TRUE(from_scene && live);
  const double held_point[3] = {1.0, 0.1, 0.8}, held_force[3] = {0, 2.5, -1};
  const double impulse_point[3] = {1.3, 0.0, 1.0}, impulse_force[3] = {0.5, -4, 0};
  std::vector<double> steps;
  for (int k = 0; k < 3; ++k) steps.push_back(1.0 / 30);   // to 0.1 s
  for (int k = 0; k < 18; ++k) steps.push_back(1.0 / 30);  // to 0.7 s
  steps.push_back(1.0 / 144);
  for (int k = 0; k < 30; ++k) steps.push_back(1.0 / 30);
  double t = 0, largest = 0, moved = 0;
  for (const double dt : steps) {
    if (std::abs(t - t_held) < 1e-12) {
      ASSERT_EQ(sweep_add_force(live, "tube", held_point, held_force, 0.4), SWEEP_OK) << sweep_last_error();
    }
    if (std::abs(t - t_impulse) < 1e-12) {
      ASSERT_EQ(sweep_add_force(live, "tube", impulse_point, impulse_force, 0), SWEEP_OK) << sweep_last_error();
    }
    ASSERT_EQ(sweep_advance(from_scene, dt), SWEEP_OK) << sweep_last_error();
    ASSERT_EQ(sweep_advance(live, dt), SWEEP_OK) << sweep_last_error();
    t += dt;
    const std::vector<float> a = positions(from_scene), b = positions(live);
    largest = std::max(largest, max_difference(a, b));
    moved = std::max(moved, max_difference(a, *rest_));
  }
  EXPECT_LE(largest, 1e-6 * length_);
  EXPECT_GT(moved, 0.01 * length_);  // the forces did move the tube
  sweep_close(from_scene);
  sweep_close(live);
}

// Advancing by irregular frame times (1/60, 1/144, 1/30 mixed) lands on the same pose at the same
// times as regular 1/60 s frames.
TEST_F(CApi, IrregularFrameTimesGiveTheSamePoses) {
  const std::string settings = scene(
      "push.scene.json",
      R"(, "forces": [{"sweep": "tube", "t": 1.0, "theta": 0.0, "vector": [0, 2.0, 0], "start": 0.05, "end": 0.6, "sections": "chain"}])");
  sweep_instance* regular = open(settings.c_str());
  sweep_instance* irregular = open(settings.c_str());
  ASSERT_TRUE(regular && irregular);
  // Times in units of 1/720 s: 1/60 s = 12, 1/144 s = 5, 1/30 s = 24.
  const int pattern[] = {12, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 24, 12, 24, 5, 7, 24, 12};
  int regular_units = 0, irregular_units = 0, compared = 0;
  double largest = 0, moved = 0;
  for (int round = 0; round < 4; ++round) {
    for (const int units : pattern) {
      const double dt = units == 7 ? 7.0 / 720 : units == 5 ? 1.0 / 144 : units == 12 ? 1.0 / 60 : 1.0 / 30;
      ASSERT_EQ(sweep_advance(irregular, dt), SWEEP_OK) << sweep_last_error();
      irregular_units += units;
      if (irregular_units % 12 != 0) continue;
      while (regular_units < irregular_units) {
        ASSERT_EQ(sweep_advance(regular, 1.0 / 60), SWEEP_OK) << sweep_last_error();
        regular_units += 12;
      }
      const std::vector<float> a = positions(regular), b = positions(irregular);
      largest = std::max(largest, max_difference(a, b));
      moved = std::max(moved, max_difference(a, *rest_));
      ++compared;
    }
  }
  EXPECT_GE(compared, 20);
  // The poses agree to 1e-9 of the length (tests/sim/live_test.cpp checks them in double); the
  // positions come out as floats, where a difference that small can still flip a last bit: an ulp
  // of the largest coordinate.
  float largest_coordinate = 0;
  for (const float c : *rest_) largest_coordinate = std::max(largest_coordinate, std::abs(c));
  EXPECT_LE(largest, 1e-9 * length_ + 2 * std::numeric_limits<float>::epsilon() * largest_coordinate);
  EXPECT_GT(moved, 0.01 * length_);
  sweep_close(regular);
  sweep_close(irregular);
}

// The body's pose given every frame: the vertices no part binds move rigidly with it, the part's
// vertices lag behind while it accelerates and settle once it stops.
TEST_F(CApi, BodyPoseMovesTheMeshRigidlyAndThePartLags) {
  sweep_instance* in = open(nullptr);
  ASSERT_TRUE(in);
  const int first_body = vertex_count() - kBodyVertices;
  double body_error = 0, lag = 0, settled = 0;
  const double dt = 1.0 / 60;
  for (int k = 1; k <= 360; ++k) {
    const double t = k * dt;
    // Swing along x and turn about z for 2 s, then hold still.
    const double s = t < 2 ? std::sin(3.14159265358979 * t) : 0.0;
    const double angle = 0.4 * s, c = std::cos(angle), sn = std::sin(angle);
    const double m[16] = {c, sn, 0, 0, -sn, c, 0, 0, 0, 0, 1, 0, 0.5 * s, 0.2 * s, 0, 1};
    ASSERT_EQ(sweep_set_body(in, m), SWEEP_OK) << sweep_last_error();
    ASSERT_EQ(sweep_advance(in, dt), SWEEP_OK) << sweep_last_error();
    // Where the rest mesh goes, rigidly.
    std::vector<float> rigid(rest_->size());
    for (int v = 0; v < vertex_count(); ++v) {
      for (int r = 0; r < 3; ++r) {
        rigid[3 * v + r] = static_cast<float>(m[r] * (*rest_)[3 * v] + m[4 + r] * (*rest_)[3 * v + 1] +
                                              m[8 + r] * (*rest_)[3 * v + 2] + m[12 + r]);
      }
    }
    const std::vector<float> p = positions(in);
    body_error = std::max(body_error, max_difference(p, rigid, first_body, kBodyVertices));
    const double off = max_difference(p, rigid, 0, first_body);
    lag = std::max(lag, off);
    if (k == 360) settled = off;
  }
  EXPECT_LE(body_error, 1e-6 * length_);
  EXPECT_GT(lag, 0.02 * length_);  // the part lags the swinging body
  EXPECT_LT(settled, 0.02 * lag);  // and settles after it stops (4 s at damping ratio 0.3)
  sweep_close(in);
}

// sweep_set_predictor: a body that swings the tube through ~0.7 of its length and turns it, frame by
// frame at the live step (1/60 s), with and without the mid-step predictor, against the bake's step
// (1/480 s, the predictor on, as sweep-sim steps). On is the default (the same bits as not calling
// it); off trades accuracy for half the step's work — README ("Time") gives the figures this
// measures: ~0.11 of the length off, against ~0.006 with the predictor at the same step.
TEST_F(CApi, ThePredictorSwitchTradesAccuracyAsDocumented) {
  const std::string settings = scene("swing.scene.json", R"(, "forces": [])");
  sweep_instance* without = open(settings.c_str());
  sweep_instance* with = open(settings.c_str());
  sweep_instance* by_default = open(settings.c_str());
  sweep_instance* bake =
      open(scene("swing-bake.scene.json", R"(, "step": 0.00208333333333333333, "forces": [])").c_str());
  ASSERT_TRUE(without && with && by_default && bake);
  ASSERT_EQ(sweep_set_predictor(without, 0), SWEEP_OK) << sweep_last_error();
  ASSERT_EQ(sweep_set_predictor(with, 1), SWEEP_OK) << sweep_last_error();
  EXPECT_NE(sweep_set_predictor(with, 2), SWEEP_OK);
  EXPECT_NE(sweep_set_predictor(nullptr, 1), SWEEP_OK);
  double off = 0, on = 0, moved = 0, from_default = 0;
  for (int k = 1; k <= 120; ++k) {
    const double t = k / 60.0, s = std::sin(3.14159265358979 * t);
    const double angle = 0.4 * s, c = std::cos(angle), sn = std::sin(angle);
    const double m[16] = {c, sn, 0, 0, -sn, c, 0, 0, 0, 0, 1, 0, 0.5 * s, 0.2 * s, 0, 1};
    for (sweep_instance* in : {without, with, by_default, bake}) {
      ASSERT_EQ(sweep_set_body(in, m), SWEEP_OK) << sweep_last_error();
      ASSERT_EQ(sweep_advance(in, 1.0 / 60), SWEEP_OK) << sweep_last_error();
    }
    const std::vector<float> reference = positions(bake), predicted = positions(with);
    off = std::max(off, max_difference(positions(without), reference));
    on = std::max(on, max_difference(predicted, reference));
    from_default = std::max(from_default, max_difference(predicted, positions(by_default)));
    std::vector<float> rigid(rest_->size());
    for (int v = 0; v < vertex_count(); ++v) {
      for (int r = 0; r < 3; ++r) {
        rigid[3 * v + r] = static_cast<float>(m[r] * (*rest_)[3 * v] + m[4 + r] * (*rest_)[3 * v + 1] +
                                              m[8 + r] * (*rest_)[3 * v + 2] + m[12 + r]);
      }
    }
    moved = std::max(moved, max_difference(reference, rigid));
  }
  EXPECT_EQ(from_default, 0.0);     // on is the default
  EXPECT_GT(moved, 0.5 * length_);  // the swing does move the part far off its rigid pose
  EXPECT_LE(on, 0.01 * length_);    // measured 0.0064
  EXPECT_LE(off, 0.15 * length_);   // measured 0.109
  EXPECT_GT(off, 5 * on);           // and the switch does act
  for (sweep_instance* in : {without, with, by_default, bake}) sweep_close(in);
}

// sweep_set_all_modes: refused unless 0 or 1 on an instance; on a part of the paper's springs (no
// modes) it changes nothing, either way.
TEST_F(CApi, TheAllModesSwitchTakesZeroOrOneAndLeavesThePapersSpringsAlone) {
  sweep_instance* all = open(nullptr);
  sweep_instance* resolved = open(nullptr);
  ASSERT_TRUE(all && resolved);
  EXPECT_EQ(sweep_set_all_modes(nullptr, 1), SWEEP_ERROR_USAGE);
  EXPECT_NE(std::string(sweep_last_error()).find("instance is NULL"), std::string::npos) << sweep_last_error();
  EXPECT_EQ(sweep_set_all_modes(all, 2), SWEEP_ERROR_USAGE);
  EXPECT_NE(std::string(sweep_last_error()).find("on must be 0 or 1, got 2"), std::string::npos) << sweep_last_error();
  EXPECT_EQ(sweep_set_all_modes(all, -1), SWEEP_ERROR_USAGE);
  ASSERT_EQ(sweep_set_all_modes(all, 1), SWEEP_OK) << sweep_last_error();
  ASSERT_EQ(sweep_set_all_modes(resolved, 0), SWEEP_OK) << sweep_last_error();
  const double point[3] = {1.0, 0.1, 0.8}, force[3] = {0, 2.5, -1};
  double moved = 0;
  for (sweep_instance* in : {all, resolved}) ASSERT_EQ(sweep_add_force(in, "tube", point, force, 1), SWEEP_OK);
  for (int k = 0; k < 30; ++k) {
    for (sweep_instance* in : {all, resolved}) ASSERT_EQ(sweep_advance(in, 1.0 / 60), SWEEP_OK) << sweep_last_error();
    const std::vector<float> a = positions(all);
    EXPECT_EQ(a, positions(resolved)) << "frame " << k;
    moved = std::max(moved, max_difference(a, *rest_));
  }
  EXPECT_GT(moved, 1e-3 * length_);  // the force did move the tube
  for (sweep_instance* in : {all, resolved}) sweep_close(in);
}

TEST_F(CApi, BadCallsReturnErrorsWithMessages) {
  const std::string rig = path("tube.rig.json"), bind = path("tube.bind");
  EXPECT_EQ(sweep_open(nullptr, bind.c_str(), nullptr, rest_->data(), vertex_count()), nullptr);
  EXPECT_NE(std::string(sweep_last_error()).find("rig_path is NULL"), std::string::npos) << sweep_last_error();
  EXPECT_EQ(sweep_open(rig.c_str(), bind.c_str(), nullptr, rest_->data(), vertex_count() - 1), nullptr);
  EXPECT_NE(std::string(sweep_last_error()).find("vertices"), std::string::npos) << sweep_last_error();
  EXPECT_EQ(sweep_open(rig.c_str(), path("missing.bind").c_str(), nullptr, rest_->data(), vertex_count()), nullptr);
  EXPECT_NE(std::string(sweep_last_error()).find("missing.bind"), std::string::npos) << sweep_last_error();
  // Positions of another mesh: the tube moved away by a tenth of its length.
  std::vector<float> moved = *rest_;
  for (std::size_t c = 0; c < moved.size(); c += 3) moved[c] += static_cast<float>(0.1 * length_);
  EXPECT_EQ(sweep_open(rig.c_str(), bind.c_str(), nullptr, moved.data(), vertex_count()), nullptr);
  EXPECT_NE(std::string(sweep_last_error()).find("other vertex positions"), std::string::npos) << sweep_last_error();

  EXPECT_EQ(sweep_advance(nullptr, 0.1), SWEEP_ERROR_USAGE);
  EXPECT_NE(std::string(sweep_last_error()).find("NULL"), std::string::npos);
  float out[3];
  EXPECT_EQ(sweep_positions(nullptr, out), SWEEP_ERROR_USAGE);
  const double identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  EXPECT_EQ(sweep_set_body(nullptr, identity), SWEEP_ERROR_USAGE);
  const double p[3] = {1, 0, 1}, f[3] = {0, 1, 0};
  EXPECT_EQ(sweep_add_force(nullptr, "tube", p, f, 0), SWEEP_ERROR_USAGE);
  sweep_close(nullptr);

  sweep_instance* in = open(nullptr);
  ASSERT_TRUE(in);
  const std::vector<float> before = positions(in);
  const auto refused = [&](int code, const char* words) {
    EXPECT_EQ(code, SWEEP_ERROR_USAGE);
    EXPECT_NE(std::string(sweep_last_error()).find(words), std::string::npos) << sweep_last_error();
  };
  refused(sweep_advance(in, -0.01), "dt must be");
  refused(sweep_advance(in, std::nan("")), "got NaN");
  double bad[16];
  std::copy(identity, identity + 16, bad);
  bad[13] = std::nan("");
  refused(sweep_set_body(in, bad), "world_from_mesh[13] is not finite");
  std::copy(identity, identity + 16, bad);
  bad[0] = 2;  // a scale
  refused(sweep_set_body(in, bad), "not rigid");
  std::copy(identity, identity + 16, bad);
  bad[0] = -1;  // a mirror
  refused(sweep_set_body(in, bad), "mirrors");
  std::copy(identity, identity + 16, bad);
  bad[3] = 1;
  refused(sweep_set_body(in, bad), "last row");
  refused(sweep_set_body(in, nullptr), "world_from_mesh is NULL");
  refused(sweep_add_force(in, "neck", p, f, 0), "no part \"neck\" (its parts: \"tube\")");
  refused(sweep_add_force(in, nullptr, p, f, 0), "part is NULL");
  refused(sweep_add_force(in, "tube", p, f, -1), "seconds must be");
  const double nan_point[3] = {std::nan(""), 0, 0};
  refused(sweep_add_force(in, "tube", nan_point, f, 0), "must be finite");
  refused(sweep_positions(in, nullptr), "out_xyz is NULL");
  refused(sweep_positions_local(in, nullptr), "out_xyz is NULL");
  refused(sweep_bound_positions(in, nullptr), "out_xyz is NULL");
  refused(sweep_bound_indices(in, nullptr), "out_indices is NULL");
  EXPECT_EQ(sweep_positions_local(nullptr, out), SWEEP_ERROR_USAGE);
  EXPECT_EQ(sweep_bound_positions(nullptr, out), SWEEP_ERROR_USAGE);
  int index = 0;
  EXPECT_EQ(sweep_bound_indices(nullptr, &index), SWEEP_ERROR_USAGE);
  EXPECT_EQ(sweep_bound_count(nullptr), -SWEEP_ERROR_USAGE);
  refused(sweep_joints(in, nullptr), "out_16xN is NULL");
  EXPECT_EQ(sweep_joint_count(nullptr), -SWEEP_ERROR_USAGE);
  refused(sweep_set_skin(in, 1, 24), "joints a sweep: expected 2 to 255, got 1");
  refused(sweep_set_skin(in, 24, 65), "ring joints a station: expected 1 to 64, got 65");
  refused(sweep_set_skin(in, 255, 1), "at most one joint a station");
  // None of it changed anything.
  ASSERT_EQ(sweep_advance(in, 0.5), SWEEP_OK) << sweep_last_error();
  EXPECT_EQ(max_difference(positions(in), before), 0.0);
  sweep_close(in);
}

// The mesh-space reads an engine that draws under the body's transform takes: sweep_positions_local
// is sweep_positions mapped back by the body's pose, to the float rounding of that product, with
// every vertex no part binds at its rest position to the bit; the bound vertices are the binding's,
// each once, and sweep_bound_positions gives sweep_positions_local's floats of them, bit for bit.
// Over frames of a body turning and moving, under a held force and gravity.
TEST_F(CApi, MeshSpaceReadsAreTheWorldPositionsMappedBack) {
  sweep_instance* in = open(scene("local.scene.json", R"(, "forces": [], "gravity": [0, -9.81, 0])").c_str());
  ASSERT_TRUE(in);
  // The binding's vertices, as sweep-bind wrote them.
  std::vector<int> bound_by_file;
  for (const auto& part : sweep::io::read_binding(path("tube.bind")).sweeps)
    bound_by_file.insert(bound_by_file.end(), part.vertices.begin(), part.vertices.end());
  std::sort(bound_by_file.begin(), bound_by_file.end());
  const int count = sweep_bound_count(in);
  ASSERT_EQ(count, static_cast<int>(bound_by_file.size())) << sweep_last_error();
  ASSERT_LT(count, vertex_count());  // the body's vertices are not bound
  std::vector<int> indices(static_cast<std::size_t>(count));
  ASSERT_EQ(sweep_bound_indices(in, indices.data()), SWEEP_OK) << sweep_last_error();
  std::vector<int> sorted = indices;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(sorted, bound_by_file);  // the same vertices, each once
  std::vector<char> is_bound(static_cast<std::size_t>(vertex_count()), 0);
  for (const int v : indices) is_bound[static_cast<std::size_t>(v)] = 1;

  const double p[3] = {1.3, 0.0, 1.0}, f[3] = {0, 3, -1};
  ASSERT_EQ(sweep_add_force(in, "tube", p, f, 0.3), SWEEP_OK) << sweep_last_error();
  std::vector<float> world(rest_->size()), local(rest_->size()), moved(3 * static_cast<std::size_t>(count));
  double largest_bend = 0;  // how far a bound vertex got from its rest, mesh space
  for (int k = 1; k <= 30; ++k) {
    const double t = k / 60.0, a = 0.8 * std::sin(3 * t), c = std::cos(a), s = std::sin(a);
    // Turning about an oblique axis (z then x) and moving: no coordinate left alone.
    const double cx = std::cos(0.5 * a), sx = std::sin(0.5 * a);
    const double r[9] = {c, s * cx, s * sx, -s, c * cx, c * sx, 0, -sx, cx};  // columns
    const double m[16] = {r[0], r[1], r[2], 0, r[3], r[4], r[5], 0, r[6], r[7], r[8], 0, 0.7 * t, -0.4 * t, 2 + t, 1};
    ASSERT_EQ(sweep_set_body(in, m), SWEEP_OK) << sweep_last_error();
    ASSERT_EQ(sweep_advance(in, 1.0 / 60), SWEEP_OK) << sweep_last_error();
    ASSERT_EQ(sweep_positions(in, world.data()), SWEEP_OK) << sweep_last_error();
    ASSERT_EQ(sweep_positions_local(in, local.data()), SWEEP_OK) << sweep_last_error();
    ASSERT_EQ(sweep_bound_positions(in, moved.data()), SWEEP_OK) << sweep_last_error();
    for (int v = 0; v < vertex_count(); ++v) {
      const float* w = &world[3 * static_cast<std::size_t>(v)];
      const float* l = &local[3 * static_cast<std::size_t>(v)];
      const float* rest = &(*rest_)[3 * static_cast<std::size_t>(v)];
      // Rᵀ (world − t) in double: the float product R·x + t that made `world` rounds each
      // coordinate within a few ulps of the terms it sums, |R x| ≤ |x| and |t|, and the pose
      // reaches libsweep as floats of R (half an ulp each): 8 ε (|x| + |t|) bounds it all.
      double back[3], size = 0, translation = std::sqrt(m[12] * m[12] + m[13] * m[13] + m[14] * m[14]);
      for (int i = 0; i < 3; ++i) {
        back[i] = 0;
        for (int j = 0; j < 3; ++j) back[i] += r[3 * i + j] * (double(w[j]) - m[12 + j]);
        size += double(l[i]) * l[i];
      }
      const double tolerance = 8 * FLT_EPSILON * (std::sqrt(size) + translation);
      for (int i = 0; i < 3; ++i) EXPECT_NEAR(l[i], back[i], tolerance) << "frame " << k << " vertex " << v;
      if (!is_bound[static_cast<std::size_t>(v)]) {
        for (int i = 0; i < 3; ++i) EXPECT_EQ(l[i], rest[i]) << "frame " << k << " unbound vertex " << v;
      } else {
        largest_bend = std::max(largest_bend, std::sqrt(std::pow(l[0] - rest[0], 2) + std::pow(l[1] - rest[1], 2) +
                                                        std::pow(l[2] - rest[2], 2)));
      }
    }
    for (int i = 0; i < count; ++i) {
      for (int c3 = 0; c3 < 3; ++c3)
        ASSERT_EQ(moved[3 * static_cast<std::size_t>(i) + c3], local[3 * static_cast<std::size_t>(indices[i]) + c3])
            << "frame " << k << " bound vertex " << indices[i];
    }
  }
  EXPECT_GT(largest_bend, 0.01 * length_);  // the parts did move in the mesh's space
  sweep_close(in);
}

// Settings that need the mesh file (a body following a glTF node, the body as a collider) are
// refused by name and place; the same settings without them open and run.
TEST_F(CApi, SettingsThatNeedTheMeshFileAreRefusedByKey) {
  const auto refusal = [&](const char* name, const std::string& body) {
    const std::string settings = scene(name, body);
    sweep_instance* in = sweep_open(path("tube.rig.json").c_str(), path("tube.bind").c_str(), settings.c_str(),
                                    rest_->data(), vertex_count());
    EXPECT_EQ(in, nullptr);
    sweep_close(in);
    return std::string(sweep_last_error());
  };
  EXPECT_NE(refusal("node.scene.json", R"(, "forces": [], "body": {"node": "Hip"})")
                .find("node.scene.json: /body/node: a body that follows a glTF node's animation needs the mesh file"),
            std::string::npos)
      << sweep_last_error();
  EXPECT_NE(refusal("proxy.scene.json", R"(, "forces": [], "body_collider": {"spheres": 8})")
                .find("proxy.scene.json: /body_collider: the body as a collider"),
            std::string::npos)
      << sweep_last_error();
  sweep_instance* plain = open(scene("plain.scene.json", R"(, "forces": [], "gravity": [0, -9.81, 0])").c_str());
  ASSERT_NE(plain, nullptr) << sweep_last_error();
  EXPECT_EQ(sweep_advance(plain, 1.0 / 60), SWEEP_OK) << sweep_last_error();
  sweep_close(plain);
}

// Instances of one creature share what never changes (the rest positions, the parts' modes), and
// nothing else: one stepped and read between another's frames, pushed and posed otherwise, changes
// none of its bits; a mesh that differs in one vertex is its own.
TEST_F(CApi, InstancesOfOneCreatureStayIndependent) {
  const double p[3] = {1.3, 0.0, 1.0}, f[3] = {0, 3, 0}, g[3] = {2, 0, 0};
  std::vector<std::vector<float>> alone;
  {
    sweep_instance* in = open(nullptr);
    ASSERT_TRUE(in);
    ASSERT_EQ(sweep_add_force(in, "tube", p, f, 0.2), SWEEP_OK) << sweep_last_error();
    for (int k = 0; k < 8; ++k) {
      ASSERT_EQ(sweep_advance(in, 1.0 / 60), SWEEP_OK);
      alone.push_back(positions(in));
    }
    sweep_close(in);
  }
  sweep_instance* a = open(nullptr);
  sweep_instance* b = open(nullptr);
  std::vector<float> moved_rest = *rest_;
  moved_rest.back() += 1e-3f;  // the body's last vertex, bound to no part
  sweep_instance* c =
      sweep_open(path("tube.rig.json").c_str(), path("tube.bind").c_str(), nullptr, moved_rest.data(), vertex_count());
  ASSERT_TRUE(a && b && c) << sweep_last_error();
  ASSERT_EQ(sweep_add_force(a, "tube", p, f, 0.2), SWEEP_OK);
  ASSERT_EQ(sweep_add_force(b, "tube", p, g, 0.1), SWEEP_OK);
  double shifted[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0.5, 0, 0, 1};
  for (int k = 0; k < 8; ++k) {
    shifted[12] += 0.01;
    ASSERT_EQ(sweep_set_body(b, shifted), SWEEP_OK);
    ASSERT_EQ(sweep_advance(b, 1.0 / 60), SWEEP_OK);
    const std::vector<float> other = positions(b);
    ASSERT_EQ(sweep_advance(a, 1.0 / 60), SWEEP_OK);
    ASSERT_EQ(sweep_advance(c, 1.0 / 60), SWEEP_OK);
    const std::vector<float> now = positions(a);
    EXPECT_EQ(max_difference(now, alone[k]), 0.0) << "frame " << k;
    EXPECT_GT(max_difference(other, now), 0.0) << "frame " << k;
    const std::vector<float> own = positions(c);
    const int last = vertex_count() - 1;
    EXPECT_EQ(max_difference(own, moved_rest, last, 1), 0.0) << "frame " << k;
    EXPECT_EQ(max_difference(own, *rest_, 0, last), 0.0) << "frame " << k;  // c, unpushed, stays at rest
  }
  sweep_close(b);
  ASSERT_EQ(sweep_advance(a, 1.0 / 60), SWEEP_OK);
  EXPECT_EQ(max_difference(positions(a), *rest_, vertex_count() - kBodyVertices, kBodyVertices), 0.0);
  sweep_close(a);
  sweep_close(c);
}

// Instances opened and closed over and over, each stepped with forces (the sanitizer build checks
// that nothing leaks); each starts from rest, whatever the ones before it did.
TEST_F(CApi, ReopeningStartsAfresh) {
  std::vector<float> first;
  for (int round = 0; round < 5; ++round) {
    sweep_instance* in = open(nullptr);
    ASSERT_TRUE(in);
    EXPECT_EQ(max_difference(positions(in), *rest_), 0.0);
    const double p[3] = {1.3, 0.0, 1.0}, f[3] = {0, 3, 0};
    ASSERT_EQ(sweep_add_force(in, "tube", p, f, 0.2), SWEEP_OK) << sweep_last_error();
    for (int k = 0; k < 10; ++k) ASSERT_EQ(sweep_advance(in, 1.0 / 60), SWEEP_OK);
    const std::vector<float> now = positions(in);
    if (round == 0) first = now;
    EXPECT_EQ(max_difference(now, first), 0.0);
    sweep_close(in);
  }
}

}  // namespace
