#pragma once
// Shared fixtures of the binding tests: a generated straight tube with a hand-made sweep whose
// every number is visible, the diplodocus tail and neck fitted in the test, temporary folders and
// a runner for the sweep-bind program.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>

#include "diplodocus_seeds.h"
#include "scratch_dir.h"
#include "sweep/assets/mesh_io.h"
#include "sweep/bind/bind.h"
#include "sweep/core/error.h"
#include "sweep/core/rig.h"
#include "sweep/fit/fit.h"
#include "sweep/io/atomic_file.h"
#include "sweep/io/read_file.h"
#include "tube.h"

namespace sweep::test {

namespace fs = std::filesystem;

// A straight circular tube along +z from the origin: length 1, radius 0.1, 41 rings (every
// 0.025) of 24 vertices, both ends capped (vertex 984 = root cap centre, 985 = tip cap centre).
// Expects `body` to throw Error(category) whose message contains every fragment.
template <typename F>
void expect_refused(F&& body, ErrorCategory category, std::initializer_list<const char*> fragments) {
  try {
    body();
    ADD_FAILURE() << "accepted; expected a message containing " << *fragments.begin();
  } catch (const Error& e) {
    EXPECT_EQ(e.category(), category) << e.what();
    for (const char* f : fragments) {
      EXPECT_NE(std::string(e.what()).find(f), std::string::npos)
          << "message: " << e.what() << "\nexpected to contain: " << f;
    }
  }
}

inline tube::TubeParams straight_tube_params() {
  tube::TubeParams p;
  p.length = 1.0;
  p.radius = 0.1;
  p.rings = 41;
  p.segments = 24;
  return p;
}

// The hand-made sweep of that tube: K = 6 sections at t = 0, 0.2, ..., 1 on the z axis, identity
// frames, n = 8 radii of 0.1 (so sample j's angle 2πj/8 falls on mesh segment 3j). With `seeds`
// the part is given as sweep-fit would (root at the origin, tip at the tip cap centre).
inline SweepDef straight_sweep(const std::string& name = "tube", bool seeds = true, double radius = 0.1) {
  SweepShape s;
  s.radial_count = 8;
  for (int i = 0; i < 6; ++i) {
    s.t.push_back(0.2 * i);
    s.frames.push_back({Quat::Identity(), Vec3(0, 0, 0.2 * i)});
    for (int j = 0; j < 8; ++j) s.radii.push_back(radius);
  }
  SweepDef def = make_sweep(name, std::move(s));
  if (seeds) def.part = PartSeeds{Vec3(0, 0, 0), Vec3(0, 0, 1)};
  return def;
}

inline Rig rig_of(std::vector<SweepDef> sweeps, std::string mesh = "") {
  Rig r;
  r.mesh = std::move(mesh);
  r.sweeps = std::move(sweeps);
  return r;
}

// CGAL's diplodocus (tools/setup-deps.sh unpacks it; tests skip without it).
inline fs::path diplodocus_path() {
  return fs::path(SWEEP_SOURCE_DIR) / "meshes/cgal/diplodocus.off";
}

struct Diplodocus {
  Mesh mesh;
  Rig rig;  // tail then neck, fitted with K = 16, n = 16
};

// Fitted once per test executable (fitting builds a CGAL tree: ~1 s).
inline const Diplodocus* diplodocus() {
  static const std::optional<Diplodocus> d = []() -> std::optional<Diplodocus> {
    if (!fs::exists(diplodocus_path())) return std::nullopt;
    Diplodocus out;
    out.mesh = assets::read_mesh(diplodocus_path());
    const fit::SweepFitter fitter(out.mesh);
    for (const Seeds& s : {kDiplodocusTail, kDiplodocusNeck}) {
      fit::FitOptions o;
      o.name = s.name;
      o.root = s.root;
      o.tip = s.tip;
      o.measure_error = false;
      out.rig.sweeps.push_back(fitter.fit(o).sweep);
    }
    out.rig.mesh = diplodocus_path().string();
    return out;
  }();
  return d ? &*d : nullptr;
}

// A fresh empty folder under the build tree for one test.
inline fs::path scratch_dir(const std::string& name) {
  return scratch_dir("bind", name);
}

struct ToolRun {
  int exit_code = -1;
  std::string out, err;
};

// Runs sweep-bind with the given arguments (already quoted where needed).
inline ToolRun run_bind_tool(const std::string& args, const fs::path& dir) {
  const fs::path out = dir / "stdout.txt", err = dir / "stderr.txt";
  const std::string cmd =
      std::string("\"") + SWEEP_BIND_EXE + "\" " + args + " >\"" + out.string() + "\" 2>\"" + err.string() + "\"";
  const int status = std::system(cmd.c_str());
  ToolRun r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = io::read_file(out);
  r.err = io::read_file(err);
  return r;
}

inline std::string quoted(const fs::path& p) {
  return "\"" + p.string() + "\"";
}

}  // namespace sweep::test
