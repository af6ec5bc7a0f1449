// Every committed fuzz seed (tests/fuzz/corpus/<target>/) and every input that ever crashed a fuzz
// target (tests/fuzz/regressions/<target>/) run through the same target code as the fuzzers
// (tests/fuzz/targets.cpp), in the regular suite: no clang needed, and under the asan preset the
// sanitizers watch them as libFuzzer did.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "fp_guard.h"
#include "fuzz/targets.h"

namespace sweep::fuzz {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> inputs(const char* kind, const char* target) {
  std::vector<fs::path> files;
  const fs::path dir = fs::path(SWEEP_SOURCE_DIR) / "tests" / "fuzz" / kind / target;
  if (!fs::exists(dir)) return files;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.is_regular_file() && e.path().filename() != "README.md") files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::string bytes_of(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

class Replay : public testing::TestWithParam<Target> {};

void replay(const Target& t, const char* kind, std::size_t at_least) {
  const std::vector<fs::path> files = inputs(kind, t.name);
  EXPECT_GE(files.size(), at_least) << kind << "/" << t.name;
  for (const fs::path& f : files) {
    SCOPED_TRACE(f.string());
    // The parsers meet NaN and overflowing numbers in these inputs on purpose (libFuzzer runs them
    // without floating-point traps too); what is checked is that only sweep::Error comes out.
    const test::FpTrapsOff no_traps;
    EXPECT_NO_THROW(t.run(bytes_of(f)));
  }
}

TEST_P(Replay, SeedCorpus) {
  replay(GetParam(), "corpus", 3);
}
TEST_P(Replay, Regressions) {
  replay(GetParam(), "regressions", 0);
}

std::string target_name(const testing::TestParamInfo<Target>& param) {
  return param.param.name;
}

INSTANTIATE_TEST_SUITE_P(Fuzz, Replay, testing::ValuesIn(targets()), target_name);

}  // namespace
}  // namespace sweep::fuzz
