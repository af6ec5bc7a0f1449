#pragma once
// The bad-input matrix's case and its one test (tests/tools/bad_input_test.cpp): a tool run on a
// prepared workspace must give the documented exit code, the message's phrases on stderr (one
// "error: " line), nothing on stdout, and leave the folder exactly as it was (no output, no
// temporary, no input touched); a case expected to succeed names the files it must write. Other
// files instantiate the same test with their own cases.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pipeline.h"

namespace sweep::test {

using nlohmann::json;

struct Case {
  std::string name;
  const char* tool;
  // Prepares the workspace and returns the tool's arguments.
  std::function<std::string(const Workspace&)> setup;
  int code;
  std::vector<std::string> expect = {};   // substrings of stderr
  std::vector<std::string> creates = {};  // exit 0 only: files the run must write
  bool one_line = true;                   // stderr is exactly one "error: " line
};

// A named pipe at `p` (an input or output that is not a regular file).
inline void make_fifo(const fs::path& p) {
  fs::remove(p);
  ASSERT_EQ(::mkfifo(p.c_str(), 0644), 0);
}

// Test names, not bytes, in gtest's messages.
inline void PrintTo(const Case& c, std::ostream* os) {
  *os << c.name;
}

inline void edit_json(const fs::path& p, const std::function<void(json&)>& change) {
  json j = json::parse(slurp(p));
  change(j);
  spit(p, j.dump(2));
}

// Every file below `dir` with its bytes.
inline std::map<std::string, std::string> snapshot(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const std::string& name : listing(dir)) {
    const fs::path p = dir / name;
    std::error_code ec;
    files[name] = fs::is_regular_file(p, ec) ? slurp(p) : std::string("<not a file>");
  }
  return files;
}

inline std::string names(const std::map<std::string, std::string>& files) {
  std::string s;
  for (const auto& [name, bytes] : files) s += " " + name;
  return s;
}

// The test (bad_input_test.cpp); INSTANTIATE_TEST_SUITE_P(..., BadInput, ...) runs it on cases.
class BadInput : public testing::TestWithParam<Case> {};

inline std::string case_name(const testing::TestParamInfo<Case>& info) {
  return info.param.name;
}

}  // namespace sweep::test
