// What every bake writer promises: deterministic bytes, atomic outputs, clear errors.
#include <limits>

#include "bake_test_util.h"
#include "sweep/core/error.h"

namespace sweep::test {
namespace {

namespace fs = std::filesystem;

const char* const kFormats[] = {"glb", "pc2", "obj"};

ErrorCategory category_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.category();
  }
  ADD_FAILURE() << "no sweep::Error was thrown";
  return ErrorCategory::internal;
}

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(BakeWriters, ChosenByExtension) {
  for (const char* name : {"a.glb", "a.GLB", "a.pc2", "a.obj", "dir/a.Obj"}) {
    EXPECT_TRUE(assets::is_bake_extension(name)) << name;
    EXPECT_NE(assets::make_bake_writer(name), nullptr) << name;
  }
  for (const char* name : {"a.gltf", "a.fbx", "a", "a.abc"}) {
    EXPECT_FALSE(assets::is_bake_extension(name)) << name;
    EXPECT_EQ(category_of([&] { assets::make_bake_writer(name); }), ErrorCategory::unsupported) << name;
  }
  EXPECT_NE(message_of([] { assets::make_bake_writer("x.fbx"); }).find("x.fbx"), std::string::npos);
}

TEST(BakeWriters, SameBakeTwiceGivesIdenticalBytes) {
  const TestBake bake = make_test_bake(10, 6, 5, 0.3);
  const fs::path a = fresh_dir("a"), b = fresh_dir("b");
  for (const char* ext : kFormats) {
    write_bake(a / (std::string("bake.") + ext), bake);
    write_bake(b / (std::string("other.") + ext), bake);  // the name does not enter the bytes
  }
  const auto names_a = list_dir(a);
  ASSERT_EQ(names_a.size(), 2u + 5u);  // .glb, .pc2, five .obj
  for (const std::string& name : names_a) {
    const std::string other = "other" + name.substr(4);
    const std::string bytes = slurp(a / name);
    EXPECT_FALSE(bytes.empty()) << name;
    EXPECT_TRUE(bytes == slurp(b / other)) << name << " differs between two identical bakes";
  }
}

TEST(BakeWriters, MissingDirectoryIsAnOutputErrorBeforeAnyFrame) {
  const TestBake bake = make_test_bake(4, 4, 2);
  const fs::path dir = fresh_dir("");
  for (const char* ext : kFormats) {
    const fs::path out = dir / "no-such-dir" / (std::string("bake.") + ext);
    auto writer = assets::make_bake_writer(out);
    const std::string msg = message_of([&] { writer->begin(bake.mesh, bake.info); });
    EXPECT_NE(msg.find(out.string()), std::string::npos) << msg;
    auto again = assets::make_bake_writer(out);
    EXPECT_EQ(category_of([&] { again->begin(bake.mesh, bake.info); }), ErrorCategory::output) << ext;
  }
  EXPECT_TRUE(list_dir(dir).empty());
}

TEST(BakeWriters, NonFinitePositionIsDivergedAndLeavesNothing) {
  const TestBake bake = make_test_bake(6, 4, 3, 0.5);
  const fs::path dir = fresh_dir("");
  const std::uint32_t bad_vertex = 21;  // a moving one
  for (const char* ext : kFormats) {
    for (const float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(), 1e31f}) {
      const fs::path out = dir / (std::string("bake.") + ext);
      auto writer = assets::make_bake_writer(out);
      writer->begin(bake.mesh, bake.info);
      writer->frame(0, bake.frames[0]);
      std::vector<Eigen::Vector3f> frame = bake.frames[1];
      frame[bad_vertex].y() = bad;
      std::string msg;
      try {
        writer->frame(1, frame);
        ADD_FAILURE() << ext << ": no error for " << bad;
      } catch (const Error& e) {
        EXPECT_EQ(e.category(), ErrorCategory::diverged);
        msg = e.what();
      }
      EXPECT_NE(msg.find("frame 1"), std::string::npos) << msg;
      EXPECT_NE(msg.find("vertex 21"), std::string::npos) << msg;
      EXPECT_TRUE(list_dir(dir).empty()) << ext << ": left " << list_dir(dir).size() << " files";
      // The writer is closed: it refuses to go on.
      EXPECT_EQ(category_of([&] { writer->finish(); }), ErrorCategory::internal);
      EXPECT_TRUE(list_dir(dir).empty());
    }
  }
}

TEST(BakeWriters, DestroyedWithoutFinishLeavesNothing) {
  const TestBake bake = make_test_bake(6, 4, 3);
  const fs::path dir = fresh_dir("");
  for (const char* ext : kFormats) {
    auto writer = assets::make_bake_writer(dir / (std::string("bake.") + ext));
    writer->begin(bake.mesh, bake.info);
    writer->frame(0, bake.frames[0]);
    writer->frame(1, bake.frames[1]);
    writer.reset();
    EXPECT_TRUE(list_dir(dir).empty()) << ext;
  }
}

TEST(BakeWriters, ProtocolErrorsAreInternalAndLeaveNothing) {
  const TestBake bake = make_test_bake(6, 4, 3, 0.5);
  const fs::path dir = fresh_dir("");
  for (const char* ext : kFormats) {
    const fs::path out = dir / (std::string("bake.") + ext);
    {  // a frame skipped
      auto w = assets::make_bake_writer(out);
      w->begin(bake.mesh, bake.info);
      EXPECT_EQ(category_of([&] { w->frame(1, bake.frames[1]); }), ErrorCategory::internal);
    }
    {  // finish before the last frame
      auto w = assets::make_bake_writer(out);
      w->begin(bake.mesh, bake.info);
      w->frame(0, bake.frames[0]);
      EXPECT_EQ(category_of([&] { w->finish(); }), ErrorCategory::internal);
    }
    {  // a vertex outside the animated list moved
      auto w = assets::make_bake_writer(out);
      w->begin(bake.mesh, bake.info);
      std::vector<Eigen::Vector3f> frame = bake.frames[0];
      frame[1].x() += 0.5f;
      const std::string msg = message_of([&] { w->frame(0, frame); });
      EXPECT_NE(msg.find("vertex 1 "), std::string::npos) << msg;
    }
    {  // wrong vertex count
      auto w = assets::make_bake_writer(out);
      w->begin(bake.mesh, bake.info);
      std::vector<Eigen::Vector3f> frame = bake.frames[0];
      frame.pop_back();
      EXPECT_EQ(category_of([&] { w->frame(0, frame); }), ErrorCategory::internal);
    }
    {  // no frames
      auto w = assets::make_bake_writer(out);
      assets::BakeInfo info = bake.info;
      info.frame_count = 0;
      EXPECT_EQ(category_of([&] { w->begin(bake.mesh, info); }), ErrorCategory::internal);
    }
    EXPECT_TRUE(list_dir(dir).empty()) << ext;
  }
}

TEST(BakeWriters, BadRestMeshesAreRefused) {
  const fs::path dir = fresh_dir("");
  assets::BakeInfo info;
  info.frame_count = 1;
  for (const char* ext : kFormats) {
    const fs::path out = dir / (std::string("bake.") + ext);
    Mesh empty;
    EXPECT_EQ(category_of([&] { assets::make_bake_writer(out)->begin(empty, info); }), ErrorCategory::bad_input);
    Mesh huge = make_tube(3, 3);
    huge.positions[4].z() = 1e39;  // beyond float32
    EXPECT_EQ(category_of([&] { assets::make_bake_writer(out)->begin(huge, info); }), ErrorCategory::bad_input);
    Mesh broken = make_tube(3, 3);
    broken.face_vertices[2] = 99;
    const std::string msg = message_of([&] { assets::make_bake_writer(out)->begin(broken, info); });
    EXPECT_NE(msg.find("vertex 99"), std::string::npos) << msg;
  }
  Mesh points;
  points.positions = {{0, 0, 0}, {1, 0, 0}};
  EXPECT_EQ(category_of([&] { assets::make_bake_writer(dir / "p.glb")->begin(points, info); }),
            ErrorCategory::unsupported);
  EXPECT_TRUE(list_dir(dir).empty());
}

}  // namespace
}  // namespace sweep::test
