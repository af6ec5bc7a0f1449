#pragma once
// Checks the tools make on their file names before any work (sweep::Error, usage, exit 1):
//  - no output is the same file as an input or as another output (compared by identity: device
//    and inode where the file exists, else the weakly canonical path), so that no run overwrites
//    what it reads (`--report` onto the rig, `sweep-bind r.rig.json -o r.rig.json`, an .obj frame
//    named like the mesh);
//  - no output name is empty (`--report ""`);
//  - every name is valid UTF-8: names are written into JSON (rigs, reports), which holds only
//    UTF-8 text.
// Whether an output may be written at all (folder, permissions, not a FIFO or device) is
// TempFile's check (io/atomic_file.h, exit 4).
#include <filesystem>
#include <string>
#include <vector>

namespace sweep::tools {

struct NamedPath {
  std::string role;            // for messages: "--report", "the rig", "the mesh", ...
  std::filesystem::path path;  // empty: an optional file not given, skipped (tools refuse an
                               // empty name on the command line: tools/common/cli_checks.h)
};

void check_paths(const std::vector<NamedPath>& inputs, const std::vector<NamedPath>& outputs);

// Throws Error(usage) "<what> is not valid UTF-8" unless `text` is.
void check_utf8(const std::string& text, const std::string& what);

}  // namespace sweep::tools
