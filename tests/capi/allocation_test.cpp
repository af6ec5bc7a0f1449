// libsweep's per-frame calls allocate nothing after the first frame: sweep_set_body, sweep_advance,
// sweep_positions, sweep_positions_local, sweep_bound_positions and sweep_joints over many frames of varying length, a
// held force and an impulse playing, without one call of operator new or malloc on any thread (the shared library's
// allocations go through the counting allocator of tests/allocation_counter.cpp, which this executable defines).
// sweep_add_force may allocate (the instance's force lists grow): the forces are given before the
// counted frames.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "allocation_counter.h"
#include "sweep/sweep.h"

namespace {

namespace fs = std::filesystem;

std::string read_text(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(CApiAllocation, FrameCallsAllocateNothingAfterTheFirstFrame) {
  if (!sweep::test::kCounts)
    GTEST_SKIP() << "AddressSanitizer replaces operator new and malloc: allocations are not counted in this build";
  // The bent tube of rigs/tube-bent.rig.json, bound by the sweep-bind tool, its mesh beside it.
  const fs::path dir = fs::temp_directory_path() / ("sweep-capi-allocation-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string obj = read_text(fs::path(SWEEP_SOURCE_DIR) / "meshes/tube_bent.obj");
  std::ofstream(dir / "mesh.obj") << obj;
  std::string rig = read_text(fs::path(SWEEP_SOURCE_DIR) / "rigs/tube-bent.rig.json");
  const std::string from = "\"../meshes/tube_bent.obj\"";
  rig.replace(rig.find(from), from.size(), "\"mesh.obj\"");
  std::ofstream(dir / "tube.rig.json") << rig;
  const std::string bind =
      std::string(SWEEP_BIND_EXE) + " -q " + (dir / "tube.rig.json").string() + " -o " + (dir / "tube.bind").string();
  ASSERT_EQ(std::system(bind.c_str()), 0) << bind;
  std::vector<float> rest;
  std::istringstream lines(obj);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("v ", 0) != 0) continue;
    std::istringstream s(line.substr(2));
    float x, y, z;
    s >> x >> y >> z;
    rest.insert(rest.end(), {x, y, z});
  }
  const int vertex_count = static_cast<int>(rest.size() / 3);
  sweep_instance* in =
      sweep_open((dir / "tube.rig.json").c_str(), (dir / "tube.bind").c_str(), nullptr, rest.data(), vertex_count);
  fs::remove_all(dir);
  ASSERT_NE(in, nullptr) << sweep_last_error();

  const double held_point[3] = {1.0, 0.1, 0.8}, held_force[3] = {0, 2.5, -1};
  const double impulse_point[3] = {1.3, 0.0, 1.0}, impulse_force[3] = {0.5, -4, 0};
  ASSERT_EQ(sweep_add_force(in, "tube", held_point, held_force, 100), SWEEP_OK) << sweep_last_error();
  std::vector<float> out(rest.size());
  const int joint_count = sweep_joint_count(in);
  ASSERT_GT(joint_count, 0) << sweep_last_error();
  std::vector<float> joints(16 * static_cast<std::size_t>(joint_count));
  std::vector<float> local(rest.size()), bound(3 * static_cast<std::size_t>(std::max(sweep_bound_count(in), 0)));
  ASSERT_FALSE(bound.empty()) << sweep_last_error();
  double t = 0;
  // One frame: the body's pose at its end (turning about z, moving in x and y), advance, read back.
  const auto frame = [&](double dt, int& failures) {
    t += dt;
    const double angle = 0.4 * std::sin(2 * t), c = std::cos(angle), s = std::sin(angle);
    const double m[16] = {c, s, 0, 0, -s, c, 0, 0, 0, 0, 1, 0, 0.5 * std::sin(t), 0.2 * t, 0, 1};
    failures += sweep_set_body(in, m) != SWEEP_OK;
    failures += sweep_advance(in, dt) != SWEEP_OK;
    failures += sweep_positions(in, out.data()) != SWEEP_OK;
    failures += sweep_positions_local(in, local.data()) != SWEEP_OK;
    failures += sweep_bound_positions(in, bound.data()) != SWEEP_OK;
    failures += sweep_joints(in, joints.data()) != SWEEP_OK;
  };
  int failures = 0;
  frame(1.0 / 60, failures);  // the warm-up frame
  ASSERT_EQ(failures, 0) << sweep_last_error();
  // An impulse from now, between internal steps, played within the counted frames.
  ASSERT_EQ(sweep_add_force(in, "tube", impulse_point, impulse_force, 0), SWEEP_OK) << sweep_last_error();
  const double slices[] = {1.0 / 60, 1.0 / 144, 1.0 / 30};
  std::vector<float> first(rest.size());
  double largest = 0;  // largest change of a coordinate since the first counted frame
  sweep::test::open_allocation_window();
  for (int k = 0; k < 300; ++k) {
    frame(slices[k % 3], failures);
    if (k == 0) first = out;  // same size: a copy into the buffer, no allocation
    for (std::size_t c = 0; c < out.size(); ++c) largest = std::max(largest, double(std::abs(out[c] - first[c])));
  }
  const sweep::test::AllocationCounts counts = sweep::test::close_allocation_window();
  EXPECT_EQ(failures, 0) << sweep_last_error();
  EXPECT_EQ(counts.news, 0);
  EXPECT_EQ(counts.mallocs, 0);
  EXPECT_GT(largest, 0.1);  // the frames did move the mesh
  sweep_close(in);
}

// The live frame as a game reads it, one kind of read an instance: the tube in material mode under
// gravity, a settings file giving no step (libsweep's live step, one a 60 fps frame, its fast modes
// quasi-static), the body moving every frame, a held force and an impulse playing; one instance
// reads only the positions, another only the joints, a fourth the positions with every mode moving
// (sweep_set_all_modes). After the first frame none allocates, and the first two's last reads are,
// bit for bit, those of a third instance given the same frames that reads nothing until the end (a
// read depends on the frames alone).
TEST(CApiAllocation, MaterialModeFramesAllocateNothingWithPositionsOrJointsOut) {
  if (!sweep::test::kCounts)
    GTEST_SKIP() << "AddressSanitizer replaces operator new and malloc: allocations are not counted in this build";
  const fs::path dir = fs::temp_directory_path() / ("sweep-capi-allocation-material-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string obj = read_text(fs::path(SWEEP_SOURCE_DIR) / "meshes/tube_bent.obj");
  std::ofstream(dir / "mesh.obj") << obj;
  std::string rig = read_text(fs::path(SWEEP_SOURCE_DIR) / "rigs/tube-bent.rig.json");
  const std::string from = "\"../meshes/tube_bent.obj\"";
  rig.replace(rig.find(from), from.size(), "\"mesh.obj\"");
  // A soft rubber tube, 1 mesh unit a metre.
  const std::string samples = "\"radial_samples\": 12,";
  ASSERT_NE(rig.find(samples), std::string::npos);
  rig.insert(rig.find(samples) + samples.size(),
             R"( "material": {"youngs_modulus_pa": 2e6, "density_kg_m3": 1100, "damping_ratio": 0.1},)");
  std::ofstream(dir / "tube.rig.json") << rig;
  std::ofstream(dir / "settings.scene.json")
      << R"({"format": "sweep-scene", "version": 1, "duration": 10, "fps": 60, "gravity": [0, -9.81, 0], "forces": []})";
  const std::string bind =
      std::string(SWEEP_BIND_EXE) + " -q " + (dir / "tube.rig.json").string() + " -o " + (dir / "tube.bind").string();
  ASSERT_EQ(std::system(bind.c_str()), 0) << bind;
  std::vector<float> rest;
  std::istringstream lines(obj);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("v ", 0) != 0) continue;
    std::istringstream s(line.substr(2));
    float x, y, z;
    s >> x >> y >> z;
    rest.insert(rest.end(), {x, y, z});
  }
  const auto open = [&] {
    return sweep_open((dir / "tube.rig.json").c_str(), (dir / "tube.bind").c_str(),
                      (dir / "settings.scene.json").c_str(), rest.data(), static_cast<int>(rest.size() / 3));
  };
  sweep_instance* by_positions = open();
  sweep_instance* by_joints = open();
  sweep_instance* both = open();  // reads both, once, after the last frame
  sweep_instance* all_modes = open();
  fs::remove_all(dir);
  ASSERT_TRUE(by_positions && by_joints && both && all_modes) << sweep_last_error();
  ASSERT_EQ(sweep_set_all_modes(all_modes, 1), SWEEP_OK) << sweep_last_error();
  const double held_point[3] = {1.0, 0.1, 0.8}, held_force[3] = {0, 2.5, -1};
  const double impulse_point[3] = {1.3, 0.0, 1.0}, impulse_force[3] = {0.5, -4, 0};
  for (sweep_instance* in : {by_positions, by_joints, both, all_modes})
    ASSERT_EQ(sweep_add_force(in, "tube", held_point, held_force, 100), SWEEP_OK) << sweep_last_error();
  const int joint_count = sweep_joint_count(by_joints);
  ASSERT_GT(joint_count, 0) << sweep_last_error();
  std::vector<float> positions(rest.size()), joints(16 * static_cast<std::size_t>(joint_count));
  std::vector<float> positions_both(positions.size()), joints_both(joints.size()), positions_all(positions.size());
  int failures = 0, positions_differ = 0, joints_differ = 0;
  double moved = 0;  // largest distance of a coordinate from its rest
  const auto frame = [&](int k) {
    const double t = k / 60.0;
    const double angle = 0.3 * std::sin(3 * t), c = std::cos(angle), s = std::sin(angle);
    const double m[16] = {c, 0, -s, 0, 0, 1, 0, 0, s, 0, c, 0, 0.4 * std::sin(2 * t), 0.1 * t, 0, 1};
    for (sweep_instance* in : {by_positions, by_joints, both, all_modes}) {
      failures += sweep_set_body(in, m) != SWEEP_OK;
      failures += sweep_advance(in, 1.0 / 60) != SWEEP_OK;
    }
    failures += sweep_positions(by_positions, positions.data()) != SWEEP_OK;
    failures += sweep_joints(by_joints, joints.data()) != SWEEP_OK;
    failures += sweep_positions(all_modes, positions_all.data()) != SWEEP_OK;
  };
  frame(1);  // the first frame
  // An impulse from now, between internal steps, played within the counted frames.
  for (sweep_instance* in : {by_positions, by_joints, both, all_modes})
    ASSERT_EQ(sweep_add_force(in, "tube", impulse_point, impulse_force, 0), SWEEP_OK) << sweep_last_error();
  sweep::test::open_allocation_window();
  for (int k = 2; k <= 150; ++k) frame(k);
  const sweep::test::AllocationCounts counts = sweep::test::close_allocation_window();
  failures += sweep_positions(both, positions_both.data()) != SWEEP_OK;
  failures += sweep_joints(both, joints_both.data()) != SWEEP_OK;
  for (std::size_t c = 0; c < positions.size(); ++c) {
    positions_differ += positions[c] != positions_both[c];
    moved = std::max(moved, double(std::abs(positions[c] - rest[c])));
  }
  for (std::size_t c = 0; c < joints.size(); ++c) joints_differ += joints[c] != joints_both[c];
  EXPECT_EQ(failures, 0) << sweep_last_error();
  EXPECT_EQ(counts.news, 0);
  EXPECT_EQ(counts.mallocs, 0);
  EXPECT_EQ(positions_differ, 0);
  EXPECT_EQ(joints_differ, 0);
  EXPECT_GT(moved, 0.1);  // the body carried the mesh away from its rest
  for (sweep_instance* in : {by_positions, by_joints, both, all_modes}) sweep_close(in);
}

}  // namespace
