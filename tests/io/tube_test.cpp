// The tube generator (tools/sweep-tube): its meshes against the closed-form parametrisation in
// tube.h, its options, and the committed example meshes in meshes/.
#include "tube.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include "sweep/assets/mesh_io.h"
#include "sweep/core/error.h"
#include "sweep/io/atomic_file.h"
#include "sweep/io/read_file.h"
#include "test_constants.h"

namespace sweep::tube {
namespace {

namespace fs = std::filesystem;
using ::sweep::test::kPi;

// Geometry is computed in double from sin/cos: agreement to a few ulps of unit-sized values.
constexpr double kTol = 1e-12;

TEST(Tube, VertexAndFaceCountsFollowTheFormula) {
  for (const bool caps : {true, false}) {
    for (const bool tri : {true, false}) {
      for (const auto& [rings, segments] : {std::pair{2, 3}, std::pair{7, 5}, std::pair{33, 24}}) {
        TubeParams p;
        p.caps = caps;
        p.triangulate = tri;
        p.rings = rings;
        p.segments = segments;
        const Mesh m = make_tube(p);
        const std::size_t quads = static_cast<std::size_t>((rings - 1) * segments);
        EXPECT_EQ(m.vertex_count(), static_cast<std::size_t>(rings * segments) + (caps ? 2 : 0));
        EXPECT_EQ(m.face_count(), quads * (tri ? 2 : 1) + (caps ? 2 * segments : 0));
        EXPECT_EQ(m.vertex_count(), tube_vertex_count(p));
        EXPECT_EQ(m.face_count(), tube_face_count(p));
        EXPECT_NO_THROW(assets::validate_mesh(m, "tube"));
      }
    }
  }
}

TEST(Tube, StraightCircularVerticesLieAtRadiusFromTheZAxis) {
  TubeParams p;
  p.length = 2.5;
  p.radius = 0.3;
  p.rings = 11;
  p.segments = 17;
  const Mesh m = make_tube(p);
  for (int i = 0; i < p.rings; ++i) {
    for (int j = 0; j < p.segments; ++j) {
      const Vec3& v = m.positions[static_cast<std::size_t>(i * p.segments + j)];
      EXPECT_NEAR(std::hypot(v.x(), v.y()), 0.3, kTol) << i << "," << j;
      EXPECT_NEAR(v.z(), 2.5 * i / 10.0, kTol);
      EXPECT_NEAR(std::atan2(v.y(), v.x()), std::remainder(2 * kPi * j / 17, 2 * kPi), kTol);
    }
  }
  EXPECT_EQ(m.positions[p.rings * p.segments], Vec3(0, 0, 0));        // root cap centre
  EXPECT_EQ(m.positions[p.rings * p.segments + 1], Vec3(0, 0, 2.5));  // tip cap centre
}

// Closed tube, outward faces: the divergence theorem gives the volume of the prism over a regular
// n-gon, L * n/2 * r^2 * sin(2 pi / n), positive only if every face points out.
TEST(Tube, ClosedStraightTubeHasThePrismVolumeSoFacesPointOut) {
  for (const bool tri : {false, true}) {
    TubeParams p;
    p.length = 1.7;
    p.radius = 0.4;
    p.segments = 9;
    p.rings = 5;
    p.triangulate = tri;
    const Mesh m = make_tube(p);
    const auto t = m.triangles();
    double volume = 0;
    for (std::size_t k = 0; k < t.size(); k += 3) {
      volume += m.positions[t[k]].dot(m.positions[t[k + 1]].cross(m.positions[t[k + 2]])) / 6;
    }
    EXPECT_NEAR(volume, 1.7 * 9 / 2.0 * 0.16 * std::sin(2 * kPi / 9), 1e-12);
  }
}

TEST(Tube, BentTubeRingCentresLieOnTheDocumentedArc) {
  TubeParams p;
  p.length = 2;
  p.radius = 0.12;
  p.bend = 1.8;
  p.rings = 49;
  p.segments = 24;
  const Mesh m = make_tube(p);
  const double R = p.length / p.bend;  // the arc: centre (R, 0, 0), radius R, in the x-z plane
  for (int i = 0; i < p.rings; ++i) {
    const double s = p.length * i / (p.rings - 1);
    Vec3 centre = Vec3::Zero();
    for (int j = 0; j < p.segments; ++j) centre += m.positions[static_cast<std::size_t>(i * p.segments + j)];
    centre /= p.segments;
    EXPECT_NEAR((centre - Vec3(R, 0, 0)).norm(), R, kTol) << "ring " << i;
    EXPECT_NEAR(centre.y(), 0, kTol);
    // ... at the arc length s: angle s / R from the start, turning from +z towards +x.
    EXPECT_NEAR(centre.x(), R - R * std::cos(s / R), kTol);
    EXPECT_NEAR(centre.z(), R * std::sin(s / R), kTol);
    EXPECT_NEAR((centre - tube_axis_point(p, s)).norm(), 0, kTol);
    // Every ring vertex: in the plane normal to the tangent, at the radius.
    const Vec3 t = tube_axis_tangent(p, s);
    EXPECT_NEAR((t - Vec3(std::sin(s / R), 0, std::cos(s / R))).norm(), 0, kTol);
    for (int j = 0; j < p.segments; ++j) {
      const Vec3 d = m.positions[static_cast<std::size_t>(i * p.segments + j)] - centre;
      EXPECT_NEAR(d.norm(), 0.12, kTol);
      EXPECT_NEAR(d.dot(t), 0, kTol);
    }
  }
  // The tip turned by the full bend.
  EXPECT_NEAR(tube_axis_tangent(p, p.length).dot(Vec3(std::sin(1.8), 0, std::cos(1.8))), 1, kTol);
}

TEST(Tube, FrameIsRightHandedOrthonormalAndStartsAtXYZ) {
  TubeParams p;
  p.bend = -2.0;
  p.length = 3;
  for (const double s : {0.0, 0.3, 1.5, 3.0}) {
    const AxisFrame f = tube_frame(p, s);
    EXPECT_NEAR(f.u.norm(), 1, kTol);
    EXPECT_NEAR(f.v.norm(), 1, kTol);
    EXPECT_NEAR(f.u.dot(f.v), 0, kTol);
    EXPECT_NEAR((f.u.cross(f.v) - f.tangent).norm(), 0, kTol);
    // The axis's derivative is the tangent (central difference).
    const double h = 1e-6;
    const Vec3 d = (tube_axis_point(p, s + h) - tube_axis_point(p, s - h)) / (2 * h);
    EXPECT_NEAR((d - f.tangent).norm(), 0, 1e-8);
  }
  const AxisFrame f0 = tube_frame(p, 0);
  EXPECT_EQ(f0.point, Vec3(0, 0, 0));
  EXPECT_EQ(f0.u, Vec3(1, 0, 0));
  EXPECT_EQ(f0.v, Vec3(0, 1, 0));
  EXPECT_EQ(f0.tangent, Vec3(0, 0, 1));
  EXPECT_LT(tube_axis_point(p, 3).x(), 0);  // negative bend turns towards -x
}

TEST(Tube, VerticesMatchTubeRadiusForEveryShapeAndTaper) {
  for (const CrossSection shape : {CrossSection::circle, CrossSection::ellipse, CrossSection::lobed}) {
    TubeParams p;
    p.shape = shape;
    p.taper = 0.4;
    p.bend = 1.0;
    p.rings = 9;
    p.segments = 20;
    const Mesh m = make_tube(p);
    for (int i = 0; i < p.rings; ++i) {
      const double s = tube_ring_s(p, i);
      const AxisFrame f = tube_frame(p, s);
      for (int j = 0; j < p.segments; ++j) {
        const double theta = tube_segment_theta(p, j);
        const Vec3 d = m.positions[static_cast<std::size_t>(i * p.segments + j)] - f.point;
        EXPECT_NEAR(d.norm(), tube_radius(p, theta, s), kTol);
        EXPECT_NEAR(std::atan2(d.dot(f.v), d.dot(f.u)), std::remainder(theta, 2 * kPi), 1e-9);
      }
    }
  }
  TubeParams p;
  p.radius = 0.2;
  p.taper = 0.4;
  EXPECT_DOUBLE_EQ(tube_radius(p, 0.3, 0), 0.2);
  EXPECT_DOUBLE_EQ(tube_radius(p, 0.3, p.length), 0.08);
  p.shape = CrossSection::ellipse;
  p.ellipse_ratio = 0.6;
  EXPECT_DOUBLE_EQ(tube_radius(p, 0, 0), 0.2);
  EXPECT_DOUBLE_EQ(tube_radius(p, kPi / 2, 0), 0.12);
  // The polar form lies on the ellipse x^2/a^2 + y^2/b^2 = 1.
  const double th = 0.7, r = tube_radius(p, th, 0);
  EXPECT_NEAR(std::pow(r * std::cos(th) / 0.2, 2) + std::pow(r * std::sin(th) / 0.12, 2), 1, kTol);
  p.shape = CrossSection::lobed;
  p.lobes = 5;
  p.lobe_amplitude = 0.25;
  EXPECT_DOUBLE_EQ(tube_radius(p, 0, 0), 0.25);
  EXPECT_DOUBLE_EQ(tube_radius(p, kPi / 5, 0), 0.15);
}

TEST(Tube, BadParametersNameTheOption) {
  auto message = [](TubeParams p) {
    try {
      check_params(p);
    } catch (const Error& e) {
      EXPECT_EQ(e.category(), ErrorCategory::usage);
      return std::string(e.what());
    }
    return std::string("(valid)");
  };
  TubeParams p;
  EXPECT_EQ(message(p), "(valid)");
  p.rings = 1;
  EXPECT_EQ(message(p), "--rings must be at least 2 (got 1)");
  p = {};
  p.segments = 2;
  EXPECT_EQ(message(p), "--segments must be at least 3 (got 2)");
  p = {};
  p.radius = 0;
  EXPECT_EQ(message(p), "--radius must be positive (got 0)");
  p = {};
  p.shape = CrossSection::lobed;
  p.lobe_amplitude = 1;
  EXPECT_EQ(message(p), "--lobe-amplitude must be in [0, 1) (got 1)");
  p = {};
  p.bend = 6;
  p.radius = 0.2;
  EXPECT_NE(message(p).find("the tube would fold through itself"), std::string::npos);
}

// ---- The committed example meshes and the sweep-tube program ----

const fs::path kSource = SWEEP_SOURCE_DIR;
const fs::path kTubeExe = SWEEP_TUBE_EXE;

int run_shell(const std::string& command) {
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

class TubeMeshes : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("sweep_test_tube_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

const char* const kCommitted[] = {"tube_straight.obj", "tube_bent.obj", "tube_tapered.off", "tube_ellipse.ply",
                                  "tube_lobed.obj"};

TEST_F(TubeMeshes, RegeneratedFilesMatchCommittedBytes) {
  const std::string cmd = "bash '" + (kSource / "tools/sweep-tube/regenerate-meshes.sh").string() + "' '" +
                          kTubeExe.string() + "' '" + dir_.string() + "'";
  ASSERT_EQ(run_shell(cmd), 0) << cmd;
  std::size_t count = 0;
  for (const auto& e : fs::directory_iterator(dir_)) {
    ++count;
    const fs::path committed = kSource / "meshes" / e.path().filename();
    ASSERT_TRUE(fs::exists(committed)) << committed << " is generated but not committed";
    EXPECT_TRUE(io::read_file(e.path()) == io::read_file(committed))
        << e.path().filename() << " differs from the committed file: regenerate and review";
  }
  EXPECT_EQ(count, std::size(kCommitted));
}

// The parameters of each committed mesh, as in tools/sweep-tube/regenerate-meshes.sh.
struct Example {
  const char* name;
  TubeParams params;
};
std::vector<Example> examples() {
  std::vector<Example> out(5);
  out[0].name = "tube_straight.obj";
  out[0].params.rings = 33;
  out[1].name = "tube_bent.obj";
  out[1].params.length = 2;
  out[1].params.radius = 0.12;
  out[1].params.bend = 1.8;
  out[1].params.rings = 49;
  out[2].name = "tube_tapered.off";
  out[2].params.length = 1.5;
  out[2].params.radius = 0.15;
  out[2].params.taper = 0.4;
  out[3].name = "tube_ellipse.ply";
  out[3].params.radius = 0.12;
  out[3].params.shape = CrossSection::ellipse;
  out[3].params.ellipse_ratio = 0.6;
  out[3].params.segments = 32;
  out[4].name = "tube_lobed.obj";
  out[4].params.length = 1.2;
  out[4].params.shape = CrossSection::lobed;
  out[4].params.lobes = 5;
  out[4].params.lobe_amplitude = 0.2;
  out[4].params.rings = 41;
  out[4].params.segments = 40;
  return out;
}

TEST_F(TubeMeshes, CommittedMeshesAreTheDocumentedTubes) {
  for (const Example& ex : examples()) {
    const fs::path p = kSource / "meshes" / ex.name;
    EXPECT_LT(fs::file_size(p), 300u * 1024u) << ex.name;
    const Mesh m = assets::read_mesh(p);
    const Mesh expected = make_tube(ex.params);
    ASSERT_EQ(m.vertex_count(), tube_vertex_count(ex.params)) << ex.name;
    EXPECT_EQ(m.face_vertices, expected.face_vertices) << ex.name;
    // OBJ and OFF read back exactly; PLY goes through assimp in single precision.
    const bool single = p.extension() == ".ply";
    for (std::size_t i = 0; i < m.vertex_count(); ++i) {
      if (single) {
        EXPECT_EQ(m.positions[i], expected.positions[i].cast<float>().cast<double>()) << ex.name << i;
      } else {
        EXPECT_EQ(m.positions[i], expected.positions[i]) << ex.name << " vertex " << i;
      }
    }
  }
}

TEST_F(TubeMeshes, ProgramReportsBadOptionsWithUsageExitCode) {
  const std::string exe = "'" + kTubeExe.string() + "'";
  const std::string out = "'" + (dir_ / "t.obj").string() + "'";
  EXPECT_EQ(run_shell(exe + " -q -o " + out + " --rings 1 2>/dev/null"), 1);
  EXPECT_EQ(run_shell(exe + " -q -o " + out + " --shape blob 2>/dev/null"), 1);
  EXPECT_EQ(run_shell(exe + " -q --no-such-flag -o " + out + " 2>/dev/null"), 1);
  EXPECT_EQ(run_shell(exe + " -q -o '" + (dir_ / "t.stl").string() + "' 2>/dev/null"), 1);
  EXPECT_EQ(run_shell(exe + " -q -o '" + (dir_ / "no/such/dir/t.obj").string() + "' 2>/dev/null"), 4);
  EXPECT_TRUE(fs::is_empty(dir_)) << "no partial output";
  EXPECT_EQ(run_shell(exe + " --help >/dev/null"), 0);
  EXPECT_EQ(run_shell(exe + " -q -o " + out + " --rings 3 --segments 4 --no-caps"), 0);
  const Mesh m = assets::read_mesh(dir_ / "t.obj");
  EXPECT_EQ(m.vertex_count(), 12u);
  EXPECT_EQ(m.face_count(), 8u);
}

}  // namespace
}  // namespace sweep::tube
