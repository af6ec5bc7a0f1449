#include "tools/common/path_checks.h"

#include <sys/stat.h>

#include <map>

#include "sweep/core/error.h"

namespace sweep::tools {
namespace fs = std::filesystem;

namespace {

bool valid_utf8(const std::string& s) {
  std::size_t i = 0;
  while (i < s.size()) {
    const auto c = static_cast<unsigned char>(s[i]);
    int more = 0;
    unsigned min = 0;
    unsigned cp = 0;
    if (c < 0x80) {
      ++i;
      continue;
    } else if ((c & 0xe0) == 0xc0) {
      more = 1, min = 0x80, cp = c & 0x1f;
    } else if ((c & 0xf0) == 0xe0) {
      more = 2, min = 0x800, cp = c & 0x0f;
    } else if ((c & 0xf8) == 0xf0) {
      more = 3, min = 0x10000, cp = c & 0x07;
    } else {
      return false;
    }
    if (i + static_cast<std::size_t>(more) >= s.size()) return false;  // cut short
    for (int k = 1; k <= more; ++k) {
      const auto d = static_cast<unsigned char>(s[i + k]);
      if ((d & 0xc0) != 0x80) return false;
      cp = (cp << 6) | (d & 0x3f);
    }
    // Overlong forms, UTF-16 surrogates and code points past U+10FFFF are not UTF-8.
    if (cp < min || cp > 0x10ffff || (cp >= 0xd800 && cp <= 0xdfff)) return false;
    i += more + 1;
  }
  return true;
}

// The file's identity: device and inode when it exists (hard links and symlinks meet there),
// else its weakly canonical absolute path (two outputs not yet written under one name).
std::string identity(const fs::path& p) {
  struct stat st {};
  if (::stat(p.c_str(), &st) == 0) {
    return "i:" + std::to_string(st.st_dev) + ":" + std::to_string(st.st_ino);
  }
  std::error_code ec;
  const fs::path canonical = fs::weakly_canonical(fs::absolute(p), ec);
  return "p:" + (ec ? fs::absolute(p).lexically_normal() : canonical).string();
}

}  // namespace

void check_utf8(const std::string& text, const std::string& what) {
  if (!valid_utf8(text)) {
    fail(ErrorCategory::usage, what + " is not valid UTF-8 (names are written into JSON files)");
  }
}

void check_paths(const std::vector<NamedPath>& inputs, const std::vector<NamedPath>& outputs) {
  std::map<std::string, const NamedPath*> seen;
  for (const NamedPath& in : inputs) {
    if (in.path.empty()) continue;
    check_utf8(in.path.string(), in.role + " file name");
    seen.emplace(identity(in.path), &in);
  }
  for (const NamedPath& out : outputs) {
    if (out.path.empty()) continue;
    check_utf8(out.path.string(), out.role + " file name");
    const auto [it, fresh] = seen.emplace(identity(out.path), &out);
    if (!fresh) {
      fail(ErrorCategory::usage, out.role + " " + out.path.string() + " is the same file as " + it->second->role + " " +
                                     it->second->path.string() + "; refusing to overwrite it (give another name)");
    }
  }
}

}  // namespace sweep::tools
