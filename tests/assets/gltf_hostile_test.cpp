// What the gltf fuzz target (tests/fuzz/) found in the project's own glTF reading, each refused
// with the file and the JSON pointer (or the vertex) as a bad input, on the very inputs the target
// found (tests/fuzz/regressions/gltf/, replayed there as well):
//  - a member that must be a string and is not (a node's name, a sampler's interpolation):
//    nlohmann's value() threw its own type_error, which no tool catches as bad input (exit 6);
//  - a bufferView at byte 2^64 - 4: its offset plus its length wrapped to 4, within the buffer,
//    and the key times were read from 2^64 - 4 bytes past the buffer's start;
//  - a FLOAT JOINTS_0 holding -1: converted to an unsigned short (undefined behaviour), where it
//    names no joint.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "sweep/assets/gltf_motion.h"
#include "sweep/assets/gltf_skin.h"
#include "sweep/core/error.h"

namespace sweep::test {
namespace {

namespace fs = std::filesystem;

fs::path regression(const std::string& name) {
  return fs::path(SWEEP_SOURCE_DIR) / "tests" / "fuzz" / "regressions" / "gltf" / name;
}

template <class F>
std::string bad_input_message(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    EXPECT_EQ(e.category(), ErrorCategory::bad_input) << e.what();
    return e.what();
  }
  ADD_FAILURE() << "accepted";
  return "";
}

TEST(GltfHostile, ANodeNameThatIsNotAStringIsBadInputWithItsPointer) {
  const fs::path file = regression("type-error-node-name-not-a-string.gltf");
  const std::string skin = bad_input_message([&] { assets::read_gltf_skin(file, {}, Eigen::Affine3d::Identity()); });
  EXPECT_EQ(skin, file.string() + ": /nodes/0/name: must be a string, got 7");
  const std::string body = bad_input_message([&] { assets::read_gltf_body_path(file, "Body"); });
  EXPECT_EQ(body, file.string() + ": /nodes/0/name: must be a string, got 7");
}

TEST(GltfHostile, AnInterpolationThatIsNotAStringIsBadInputWithItsPointer) {
  const fs::path file = regression("type-error-interpolation-not-a-string.gltf");
  const std::string m = bad_input_message([&] { assets::read_gltf_body_path(file, "Body"); });
  EXPECT_EQ(m, file.string() + ": /animations/0/samplers/0/interpolation: must be a string, got 1");
}

TEST(GltfHostile, ABufferViewWhoseOffsetWrapsIsNotRead) {
  const fs::path file = regression("crash-view-offset-wraps.gltf");
  const std::string m = bad_input_message([&] { assets::read_gltf_body_path(file, "Body"); });
  EXPECT_EQ(m, file.string() +
                   ": animation 'Walk': the translation keys of node 'Body' cannot be read "
                   "(float times and values of matching count expected)");
}

TEST(GltfHostile, ANegativeJointIsNoJoint) {
  const fs::path file = regression("ub-joint-negative-float.gltf");
  const std::string m = bad_input_message([&] { assets::read_gltf_skin(file, {}, Eigen::Affine3d::Identity()); });
  EXPECT_EQ(m, file.string() +
                   ": mesh 'Creature', vertex 3: joint -1 in JOINTS_0 is not a joint index (a whole "
                   "number from 0)");
}

}  // namespace
}  // namespace sweep::test
