// A fresh, empty folder under the build tree for one test's files: every test support header of
// the suite makes its folders here, so that a folder a test left read-only, or half-written by a
// killed run, is handled the same way everywhere.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <system_error>

namespace sweep::test {

// test-scratch/<area>/<name> under the build tree, emptied. A folder a test made read-only (the
// bad-input tests do) is made writable first so that it can be removed.
inline std::filesystem::path scratch_dir(const std::string& area, const std::string& name) {
  const std::filesystem::path dir = std::filesystem::path(SWEEP_BINARY_DIR) / "test-scratch" / area / name;
  std::error_code ec;
  std::filesystem::permissions(dir, std::filesystem::perms::owner_all, std::filesystem::perm_options::add, ec);
  std::filesystem::remove_all(dir, ec);
  std::filesystem::create_directories(dir);
  return dir;
}

// The same, named after the running test: <area>/<suite>.<test>[.<suffix>].
inline std::filesystem::path scratch_dir_of_this_test(const std::string& area, const std::string& suffix = "") {
  const testing::TestInfo* info = testing::UnitTest::GetInstance()->current_test_info();
  return scratch_dir(area,
                     std::string(info->test_suite_name()) + "." + info->name() + (suffix.empty() ? "" : "." + suffix));
}

}  // namespace sweep::test
