#pragma once
// Reading what the tools write, for tests: a .glb's JSON and BIN chunks, its float accessors (dense
// or sparse) and uint32 index lists, the Khronos validator's verdict on it, and a .pc2 frame.
#include <sys/wait.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "tool_runner.h"

namespace sweep::test {

// A .glb's two chunks.
struct Glb {
  nlohmann::json json;
  std::string bin;
};

inline Glb read_glb(const fs::path& p) {
  const std::string b = slurp(p);
  Glb g;
  if (b.size() < 20 || b.compare(0, 4, "glTF") != 0) return g;
  std::uint32_t json_length = 0, bin_length = 0;
  std::memcpy(&json_length, b.data() + 12, 4);
  g.json = nlohmann::json::parse(b.substr(20, json_length));
  const std::size_t at = 20 + json_length;
  if (at + 8 <= b.size()) {
    std::memcpy(&bin_length, b.data() + at, 4);
    g.bin = b.substr(at + 8, bin_length);
  }
  return g;
}

// A float accessor's values (dense or sparse, uint32 sparse indices), `width` a element.
inline std::vector<float> floats(const nlohmann::json& doc, const std::string& bin, std::size_t index, int width) {
  const nlohmann::json& a = doc["accessors"][index];
  EXPECT_EQ(a["componentType"], 5126);
  const std::size_t count = a["count"];
  std::vector<float> out(count * width, 0.0f);
  auto view_at = [&](std::size_t view) {
    const nlohmann::json& v = doc["bufferViews"][view];
    return static_cast<std::size_t>(v.value("byteOffset", 0));
  };
  if (a.contains("bufferView")) {
    const nlohmann::json& v = doc["bufferViews"][a["bufferView"].get<std::size_t>()];
    const std::size_t stride = v.value("byteStride", 4 * width);
    const std::size_t begin = view_at(a["bufferView"]) + a.value("byteOffset", 0);
    for (std::size_t i = 0; i < count; ++i) std::memcpy(&out[i * width], bin.data() + begin + i * stride, 4 * width);
  }
  if (a.contains("sparse")) {
    const nlohmann::json& s = a["sparse"];
    EXPECT_EQ(s["indices"]["componentType"], 5125);
    const std::size_t n = s["count"];
    const std::size_t ib = view_at(s["indices"]["bufferView"]) + s["indices"].value("byteOffset", 0);
    const std::size_t vb = view_at(s["values"]["bufferView"]) + s["values"].value("byteOffset", 0);
    for (std::size_t k = 0; k < n; ++k) {
      std::uint32_t i = 0;
      std::memcpy(&i, bin.data() + ib + 4 * k, 4);
      std::memcpy(&out[i * width], bin.data() + vb + 4 * width * k, 4 * width);
    }
  }
  return out;
}

// The bytes of a buffer view.
inline std::string view_bytes(const nlohmann::json& doc, const std::string& bin, std::size_t view) {
  const nlohmann::json& v = doc["bufferViews"][view];
  return bin.substr(v.value("byteOffset", 0), v["byteLength"].get<std::size_t>());
}

// The Khronos validator's JSON report on `glb`; `code` is its exit code (0: no errors).
inline std::string validate(const fs::path& glb, int* code) {
  const fs::path script = fs::path(SWEEP_SOURCE_DIR) / "tests/gltf-validator/validate.js";
  const std::string cmd = "node '" + script.string() + "' '" + glb.string() + "' 2>&1";
  std::string report;
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (!pipe) return report;
  char buf[4096];
  for (std::size_t got; (got = std::fread(buf, 1, sizeof buf, pipe)) > 0;) report.append(buf, got);
  const int status = ::pclose(pipe);
  *code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return report;
}

// Frame `frame` of a .pc2 file's bytes, 3 floats a point; `points` is its point count.
inline std::vector<float> pc2_frame(const std::string& pc2, int frame, int* points) {
  std::int32_t n = 0;
  std::memcpy(&n, pc2.data() + 16, 4);
  *points = n;
  std::vector<float> out(3 * static_cast<std::size_t>(n));
  std::memcpy(out.data(), pc2.data() + 32 + 12 * static_cast<std::size_t>(frame) * n, out.size() * 4);
  return out;
}

// A uint32 accessor's values (an index list).
inline std::vector<std::uint32_t> uints(const nlohmann::json& doc, const std::string& bin, std::size_t index) {
  const nlohmann::json& a = doc["accessors"][index];
  std::vector<std::uint32_t> out(a["count"].get<std::size_t>());
  const nlohmann::json& v = doc["bufferViews"][a["bufferView"].get<std::size_t>()];
  std::memcpy(out.data(), bin.data() + v.value("byteOffset", 0) + a.value("byteOffset", 0), 4 * out.size());
  return out;
}

}  // namespace sweep::test
