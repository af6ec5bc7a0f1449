#pragma once
// A small, valid pipeline made by the tools themselves: the committed straight tube, a rig fitted
// to it by sweep-fit, its binding by sweep-bind, and a scene. Made once per build of the tools (a
// cache folder named after their modification times, created under a temporary name and renamed
// into place, so parallel test processes never see half of it) and copied into each test's folder.
#include <fcntl.h>
#include <sys/file.h>

#include <chrono>
#include <functional>
#include <string>

#include "tool_runner.h"

namespace sweep::test {

// The scene of the brief: a sideways push near the tip for 0.2 s, 6 frames.
inline const char* const kScene =
    R"({"format": "sweep-scene", "version": 1, "duration": 0.5, "fps": 10,
  "forces": [{"sweep": "tube", "t": 1, "theta": 0, "vector": [0, 1, 0], "start": 0, "end": 0.2}]}
)";

inline std::string stamp(const char* exe) {
  return std::to_string(fs::last_write_time(exe).time_since_epoch().count());
}

// A folder made once per build of the tools by `make(folder, io)` (io: a folder for the tools'
// captured streams) and shared by every test process. ctest runs tests in parallel processes: the
// first takes a lock (flock, released when it exits even if it crashes), builds the folder under a
// temporary name and renames it into place; the others wait for the lock and find it there.
inline fs::path cached_dir(const std::string& name, const std::function<void(const fs::path&, const fs::path&)>& make) {
  const fs::path root = fs::path(SWEEP_BINARY_DIR) / "test-scratch" / "tools-cache";
  const fs::path dir =
      root / (name + "-" + stamp(SWEEP_FIT_EXE) + "-" + stamp(SWEEP_BIND_EXE) + "-" + stamp(SWEEP_TUBE_EXE));
  if (fs::exists(dir)) return dir;
  fs::create_directories(root);
  const int lock = ::open((root / (name + ".lock")).c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (lock >= 0) ::flock(lock, LOCK_EX);
  if (!fs::exists(dir)) {
    const fs::path tmp = root / ("tmp-" + name + "-" + std::to_string(::getpid()));
    const fs::path io = root / ("io-" + name + "-" + std::to_string(::getpid()));
    fs::remove_all(tmp);
    fs::create_directories(tmp);
    fs::create_directories(io);
    make(tmp, io);
    fs::remove_all(io);
    if (testing::Test::HasFailure()) {  // never publish a broken cache
      if (lock >= 0) ::close(lock);
      return tmp;
    }
    fs::rename(tmp, dir);
  }
  if (lock >= 0) ::close(lock);
  return dir;
}

// Fits `mesh` (in `dir`) with the seeds of the brief into dir/rig.json and binds it to rig.bind,
// with the paper's springs (--springs): the scenes here push as hard as those springs need.
inline void fit_and_bind(const fs::path& dir, const fs::path& io, const std::string& mesh, const std::string& extra) {
  const ToolRun fit = run_tool(SWEEP_FIT_EXE,
                               quoted(dir / mesh) + " -o " + quoted(dir / "rig.json") +
                                   " --name tube --root 0,0,0.02 --tip 0,0,1 --springs" + extra,
                               io);
  ASSERT_EQ(fit.code, 0) << fit.err;
  const ToolRun bind = run_tool(SWEEP_BIND_EXE, quoted(dir / "rig.json") + " -q", io);
  ASSERT_EQ(bind.code, 0) << bind.err;
}

// The folder holding tube.obj (the committed straight tube), rig.json (mesh "tube.obj", K = 6,
// n = 8), rig.bind and scene.json.
inline fs::path base_pipeline() {
  return cached_dir("tube", [](const fs::path& dir, const fs::path& io) {
    fs::copy_file(fs::path(SWEEP_SOURCE_DIR) / "meshes" / "tube_straight.obj", dir / "tube.obj");
    fit_and_bind(dir, io, "tube.obj", " -k 6 -n 8");
    spit(dir / "scene.json", kScene);
  });
}

// A test's own copy of the base pipeline in a fresh folder `work`, with `io` beside it for the
// captured streams.
struct Workspace {
  fs::path work, io;
  explicit Workspace(const std::string& name) {
    const fs::path top = scratch_dir(name);
    work = top / "work";
    io = top / "io";
    fs::create_directories(io);
    fs::copy(base_pipeline(), work, fs::copy_options::recursive);
  }
  fs::path operator/(const std::string& name) const { return work / name; }
};

}  // namespace sweep::test
