#pragma once
// Running the four programs as black boxes: scratch folders, a small rig/binding/scene made once by
// the tools themselves, stdout and stderr captured apart, folder listings to prove that a failed
// run left nothing behind, and the two permission tricks that also work as root.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "scratch_dir.h"

namespace sweep::test {

namespace fs = std::filesystem;

// A point as the tools' --root and --tip take it: "x,y,z", exact to a float's precision and more.
template <class Point>
std::string point_arg(const Point& p) {
  char s[128];
  std::snprintf(s, sizeof s, "%.9g,%.9g,%.9g", double(p.x()), double(p.y()), double(p.z()));
  return s;
}

struct ToolRun {
  int code = -1;
  std::string out, err;
  // stderr split into lines (without their newlines).
  std::vector<std::string> err_lines() const {
    std::vector<std::string> lines;
    std::istringstream in(err);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
  }
};

inline std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline void spit(const fs::path& p, const std::string& bytes) {
  std::ofstream(p, std::ios::binary | std::ios::trunc) << bytes;
}

inline std::string quoted(const fs::path& p) {
  return "'" + p.string() + "'";
}

// A fresh, empty folder under the build tree.
inline fs::path scratch_dir(const std::string& name) {
  return scratch_dir("tools", name);
}

// Runs `exe args` in the shell with `env` before it ("OMP_NUM_THREADS=1"); the captured streams go
// to `io_dir`, which must not be a folder whose listing the test checks.
inline ToolRun run_tool(const char* exe, const std::string& args, const fs::path& io_dir, const std::string& env = "") {
  const fs::path out = io_dir / "stdout.txt", err = io_dir / "stderr.txt";
  const std::string cmd = env + (env.empty() ? "" : " ") + "'" + exe + "' " + args + " >" + quoted(out) + " 2>" +
                          quoted(err) + " </dev/null";
  const int status = std::system(cmd.c_str());
  ToolRun r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(out);
  r.err = slurp(err);
  return r;
}

// Every path below `dir`, relative to it (files and folders; hidden temporaries included).
inline std::set<std::string> listing(const fs::path& dir) {
  std::set<std::string> names;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(dir, ec); it != fs::recursive_directory_iterator();
       it.increment(ec)) {
    if (ec) break;
    names.insert(fs::relative(it->path(), dir).generic_string());
  }
  return names;
}

// Makes `path` a file that the tools cannot read. chmod 000 does that for an ordinary user; root
// (the CI container) reads through any permission, so there a folder is put in its place, which
// no reader can read as a file either. Returns which of the two it did.
inline std::string make_unreadable(const fs::path& path, const std::string& content) {
  spit(path, content);
  fs::permissions(path, fs::perms::none);
  if (FILE* f = std::fopen(path.c_str(), "rb")) {  // still readable: we are root
    std::fclose(f);
    fs::permissions(path, fs::perms::owner_read | fs::perms::owner_write);
    fs::remove(path);
    fs::create_directory(path);
    return "folder";
  }
  return "chmod 000";
}

// Makes `dir` (existing) refuse new files and returns a path inside it for an output named `name`.
// chmod 555 does that for an ordinary user; root writes through it, so there the output is put
// below a regular file instead ("<dir>/not-a-folder/<name>"), which fails the same way for
// everyone (ENOTDIR).
inline fs::path read_only_output(const fs::path& dir, const std::string& name, std::string* how = nullptr) {
  fs::permissions(dir, fs::perms::owner_read | fs::perms::owner_exec | fs::perms::group_read | fs::perms::group_exec |
                           fs::perms::others_read | fs::perms::others_exec);
  const fs::path probe = dir / ".probe";
  if (FILE* f = std::fopen(probe.c_str(), "wb")) {  // still writable: we are root
    std::fclose(f);
    fs::remove(probe);
    fs::permissions(dir, fs::perms::owner_all, fs::perm_options::add);
    spit(dir / "not-a-folder", "a regular file\n");
    if (how) *how = "a regular file as the parent folder";
    return dir / "not-a-folder" / name;
  }
  if (how) *how = "chmod 555";
  return dir / name;
}

}  // namespace sweep::test
