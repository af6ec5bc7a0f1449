// Byte-for-byte determinism (DESIGN §5, STYLE "Deterministic bytes"): the same inputs give the same
// rig, binding and baked files (.glb, .pc2, .obj sequence) across runs and thread counts. The mesh
// is a dense tube (400 rings × 128 = 51,202 vertices), above every parallel threshold (binding and
// exact deformation: 16,384 vertices, lib/bind/bind.h; fast deformation: 40,000 bound vertices of
// one sweep, lib/bind/fast_deform.h), so the two-thread runs really run the parallel loops.
#include <gtest/gtest.h>

#include <string>

#include "pipeline.h"

namespace sweep::test {
namespace {

// dense.obj, rig.json (fitted with OMP_NUM_THREADS=1), rig.bind (bound with 1 thread) and
// scene.json, plus rig2.json / rig2.bind made the same way with 2 threads.
fs::path dense_pipeline() {
  return cached_dir("dense", [](const fs::path& dir, const fs::path& io) {
    const ToolRun tube = run_tool(SWEEP_TUBE_EXE, "-q --rings 400 --segments 128 -o " + quoted(dir / "dense.obj"), io);
    ASSERT_EQ(tube.code, 0) << tube.err;
    for (const char* threads : {"1", "2"}) {
      const std::string env = std::string("OMP_NUM_THREADS=") + threads;
      const std::string rig = threads[0] == '1' ? "rig.json" : "rig2.json";
      const ToolRun fit = run_tool(
          SWEEP_FIT_EXE,
          quoted(dir / "dense.obj") + " -o " + quoted(dir / rig) + " --name tube --root 0,0,0.02 --tip 0,0,1", io, env);
      ASSERT_EQ(fit.code, 0) << fit.err;
      const ToolRun bind = run_tool(SWEEP_BIND_EXE, quoted(dir / rig) + " -q", io, env);
      ASSERT_EQ(bind.code, 0) << bind.err;
    }
    spit(dir / "scene.json", kScene);
  });
}

class Determinism : public testing::Test {
 protected:
  void SetUp() override {
#if defined(SWEEP_SANITIZED)
    // Fitting and binding 51,202 vertices unoptimized under ASan takes over ten minutes on two
    // cores; the bytes these tests compare come from the optimized build, where they take seconds.
    GTEST_SKIP() << "dense determinism runs in optimized, unsanitized builds only";
#endif
    dense_ = dense_pipeline();
    ASSERT_FALSE(HasFatalFailure());
    const fs::path top =
        scratch_dir(std::string("determinism-") + testing::UnitTest::GetInstance()->current_test_info()->name());
    io_ = top / "io";
    fs::create_directories(io_);
    out_ = top;
  }

  // Bakes all three formats into out_/<tag>/ with `extra` options; returns the files' names.
  std::set<std::string> bake(const std::string& tag, const std::string& extra) {
    const fs::path dir = out_ / tag;
    fs::create_directories(dir);
    const ToolRun r = run_tool(SWEEP_SIM_EXE,
                               quoted(dense_ / "rig.json") + " -s " + quoted(dense_ / "scene.json") + " -q -o " +
                                   quoted(dir / "bake.glb") + " -o " + quoted(dir / "bake.pc2") + " -o " +
                                   quoted(dir / "bake.obj") + " " + extra,
                               io_);
    EXPECT_EQ(r.code, 0) << r.err;
    return listing(dir);
  }

  void expect_same_files(const std::string& a, const std::string& b) {
    const std::set<std::string> files = listing(out_ / a);
    EXPECT_EQ(files, listing(out_ / b));
    // 6 frames: the .glb, the .pc2 and bake_0000.obj .. bake_0005.obj.
    EXPECT_EQ(files.size(), 8u);
    for (const std::string& f : files) {
      const std::string x = slurp(out_ / a / f), y = slurp(out_ / b / f);
      EXPECT_GT(x.size(), 0u) << f;
      EXPECT_TRUE(x == y) << f << " differs between " << a << " and " << b;
    }
  }

  fs::path dense_, io_, out_;
};

TEST_F(Determinism, RigAndBindingAreTheSameBytesWithOneOrTwoThreads) {
  EXPECT_TRUE(slurp(dense_ / "rig.json") == slurp(dense_ / "rig2.json"));
  EXPECT_TRUE(slurp(dense_ / "rig.bind") == slurp(dense_ / "rig2.bind"));
  // 24 bytes per bound vertex: more than the fast path's parallel threshold (40,000) are bound.
  EXPECT_GT(slurp(dense_ / "rig.bind").size(), 40000u * 24);
  // And again in this process's run: a third binding, two threads, -o elsewhere.
  const ToolRun again = run_tool(SWEEP_BIND_EXE, quoted(dense_ / "rig.json") + " -q -o " + quoted(out_ / "again.bind"),
                                 io_, "OMP_NUM_THREADS=2");
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_TRUE(slurp(out_ / "again.bind") == slurp(dense_ / "rig.bind"));
}

TEST_F(Determinism, FastBakeIsTheSameBytesInEveryFormatWithOneOrTwoThreads) {
  bake("t1", "--threads 1");
  bake("t2", "--threads 2");
  bake("t2-again", "--threads 2");
  expect_same_files("t1", "t2");
  expect_same_files("t2", "t2-again");
}

TEST_F(Determinism, ExactBakeIsTheSameBytesInEveryFormatWithOneOrTwoThreads) {
  bake("t1", "--exact --threads 1");
  bake("t2", "--exact --threads 2");
  expect_same_files("t1", "t2");
}

}  // namespace
}  // namespace sweep::test
