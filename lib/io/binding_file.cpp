#include "sweep/io/binding_file.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <numbers>
#include <sstream>

#include "sweep/core/error.h"
#include "sweep/core/hash.h"
#include "sweep/core/limits.h"
#include "sweep/io/atomic_file.h"
#include "sweep/io/read_file.h"

using sweep::bind::hash_positions;
using sweep::bind::hash_sweeps;

namespace sweep::io {
namespace {

constexpr char kMagic[8] = {'S', 'W', 'P', 'B', 'I', 'N', 'D', '\0'};
constexpr std::size_t kHeaderSize = 48;
constexpr std::size_t kTrailerSize = 8;
// θ is stored as float32 of a double in [0, 2π): the rounding may land on float(2π).
constexpr float kThetaMax = static_cast<float>(2 * std::numbers::pi);

// Little-endian writer into a string.
class Writer {
 public:
  void u32(std::uint32_t v) { put(v, 4); }
  void u64(std::uint64_t v) { put(v, 8); }
  void f32(float v) { put(std::bit_cast<std::uint32_t>(v), 4); }
  void bytes(std::string_view b) { out_.append(b); }
  std::string& str() { return out_; }

 private:
  void put(std::uint64_t v, int n) {
    for (int b = 0; b < n; ++b) out_.push_back(static_cast<char>((v >> (8 * b)) & 0xffu));
  }
  std::string out_;
};

// Little-endian reader with bounds checks; running past the end is a corrupt table.
class Reader {
 public:
  Reader(std::string_view data, std::size_t pos, std::size_t end, const std::string& source)
      : data_(data), pos_(pos), end_(end), source_(source) {}
  std::uint32_t u32(const char* what) { return static_cast<std::uint32_t>(get(4, what)); }
  std::uint64_t u64(const char* what) { return get(8, what); }
  float f32(const char* what) { return std::bit_cast<float>(u32(what)); }
  std::string_view bytes(std::size_t n, const char* what) {
    need(n, what);
    const std::string_view v = data_.substr(pos_, n);
    pos_ += n;
    return v;
  }
  std::size_t remaining() const { return end_ - pos_; }
  std::size_t pos() const { return pos_; }

 private:
  void need(std::size_t n, const char* what) const {
    if (n > end_ - pos_) {
      std::ostringstream s;
      s << source_ << ": corrupt binding: " << what << " at byte " << pos_ << " runs past the end of the payload";
      fail(ErrorCategory::bad_input, s.str());
    }
  }
  std::uint64_t get(int n, const char* what) {
    need(static_cast<std::size_t>(n), what);
    std::uint64_t v = 0;
    for (int b = 0; b < n; ++b) {
      v |= static_cast<std::uint64_t>(static_cast<unsigned char>(data_[pos_ + b])) << (8 * b);
    }
    pos_ += static_cast<std::size_t>(n);
    return v;
  }
  std::string_view data_;
  std::size_t pos_, end_;
  const std::string& source_;
};

[[noreturn]] void refuse(const std::string& source, const std::string& what) {
  fail(ErrorCategory::bad_input, source + ": " + what);
}

void read_floats(Reader& in, std::vector<float>& out, std::size_t m, const char* what) {
  out.resize(m);
  for (std::size_t k = 0; k < m; ++k) out[k] = in.f32(what);
}

// The tables' own consistency (a checksum only proves the bytes are the ones written).
void check_table(const bind::SweepBinding& sb, std::size_t index, std::uint64_t vertex_count,
                 const std::string& source) {
  auto bad = [&](std::size_t k, const std::string& what) {
    std::ostringstream s;
    s << "corrupt binding: sweep " << index << " ('" << sb.name << "'), entry " << k << " (vertex " << sb.vertices[k]
      << "): " << what;
    refuse(source, s.str());
  };
  for (std::size_t k = 0; k < sb.size(); ++k) {
    if (sb.vertices[k] >= vertex_count) bad(k, "vertex index out of range");
    if (k > 0 && sb.vertices[k] <= sb.vertices[k - 1]) bad(k, "vertex indices not increasing");
    // Lengths within the rig's limit (core/limits.h), so a binding never carries an inf.
    if (!(sb.t[k] >= 0 && sb.t[k] <= limits::kMaxLength)) bad(k, "t must be in [0, 1e9]");
    if (!(sb.theta[k] >= 0 && sb.theta[k] <= kThetaMax)) bad(k, "theta must be in [0, 2 pi]");
    if (!(sb.s[k] >= 0 && sb.s[k] <= limits::kMaxLength)) bad(k, "s must be in [0, 1e9]");
    if (!(std::abs(sb.z[k]) <= limits::kMaxLength)) bad(k, "z must be in [-1e9, 1e9]");
    if (!(sb.weight[k] >= 0 && sb.weight[k] <= 1)) bad(k, "weight must be in [0, 1]");
  }
}

}  // namespace

std::string binding_bytes(const bind::Binding& binding) {
  Writer payload;
  for (const bind::SweepBinding& sb : binding.sweeps) {
    payload.u32(static_cast<std::uint32_t>(sb.name.size()));
    payload.bytes(sb.name);
    payload.u64(sb.size());
    for (std::uint32_t v : sb.vertices) payload.u32(v);
    for (const std::vector<float>* column : {&sb.t, &sb.theta, &sb.s, &sb.z, &sb.weight}) {
      for (float x : *column) payload.f32(x);
    }
  }
  Writer out;
  out.bytes(std::string_view(kMagic, sizeof kMagic));
  out.u32(kBindingFormatVersion);
  out.u32(static_cast<std::uint32_t>(binding.sweeps.size()));
  out.u64(binding.vertex_count);
  out.u64(binding.mesh_hash);
  out.u64(binding.rig_hash);
  out.u64(payload.str().size());
  out.bytes(payload.str());
  out.u64(fnv1a(out.str()));
  return std::move(out.str());
}

void write_binding(const std::filesystem::path& path, const bind::Binding& binding) {
  io::write_file_atomically(path, binding_bytes(binding));
}

bind::Binding parse_binding(std::string_view bytes, const std::string& source) {
  if (bytes.size() >= sizeof kMagic && std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0) {
    refuse(source, "not a sweep binding file (wrong magic bytes)");
  }
  if (bytes.size() < kHeaderSize + kTrailerSize) {
    std::ostringstream s;
    s << "truncated binding: " << bytes.size() << " bytes, less than the " << kHeaderSize + kTrailerSize
      << "-byte header and checksum";
    refuse(source, s.str());
  }
  Reader header(bytes, sizeof kMagic, kHeaderSize, source);
  const std::uint32_t version = header.u32("version");
  if (version == 1) {
    // Format 1 hashed the rig's JSON text, so its rig hash cannot be checked any more.
    refuse(source, "binding format 1 (written by an older sweep-bind) is no longer read; run sweep-bind again");
  }
  if (version != kBindingFormatVersion) {
    std::ostringstream s;
    s << source << ": binding format version " << version << " is not supported (this program reads "
      << kBindingFormatVersion << ")";
    fail(version > kBindingFormatVersion ? ErrorCategory::unsupported : ErrorCategory::bad_input, s.str());
  }
  bind::Binding b;
  const std::uint32_t sweep_count = header.u32("sweep count");
  b.vertex_count = header.u64("vertex count");
  b.mesh_hash = header.u64("mesh hash");
  b.rig_hash = header.u64("rig hash");
  const std::uint64_t payload_size = header.u64("payload size");
  const std::uint64_t available = bytes.size() - kHeaderSize - kTrailerSize;
  if (payload_size != available) {
    std::ostringstream s;
    if (payload_size > available) {
      s << "truncated binding: the header announces " << kHeaderSize + payload_size + kTrailerSize
        << " bytes, the file has " << bytes.size();
    } else {
      s << "corrupt binding: " << available - payload_size
        << " unexpected bytes after the payload the header announces";
    }
    refuse(source, s.str());
  }
  const std::size_t end = bytes.size() - kTrailerSize;
  Reader trailer(bytes, end, bytes.size(), source);
  const std::uint64_t stored = trailer.u64("checksum");
  const std::uint64_t actual = fnv1a(bytes.substr(0, end));
  if (stored != actual) {
    refuse(source, "corrupt binding: checksum mismatch (the file was damaged or edited after writing)");
  }
  // After the checksum: a damaged count is reported as the damage it is.
  if (b.vertex_count > limits::kMaxVertices) {
    refuse(source, "corrupt binding: a vertex count of " + std::to_string(b.vertex_count) + " is beyond the limit of " +
                       std::to_string(limits::kMaxVertices));
  }
  Reader in(bytes, kHeaderSize, end, source);
  for (std::uint32_t i = 0; i < sweep_count; ++i) {
    bind::SweepBinding sb;
    const std::uint32_t name_length = in.u32("sweep name length");
    sb.name = std::string(in.bytes(name_length, "sweep name"));
    const std::uint64_t m = in.u64("bound vertex count");
    // Each entry takes 24 bytes: refuse a count the payload cannot hold before allocating.
    if (m > in.remaining() / 24) {
      std::ostringstream s;
      s << "corrupt binding: sweep " << i << " ('" << sb.name << "') claims " << m
        << " vertices, more than the payload holds";
      refuse(source, s.str());
    }
    sb.vertices.resize(m);
    for (auto& v : sb.vertices) v = in.u32("vertex index");
    read_floats(in, sb.t, m, "t");
    read_floats(in, sb.theta, m, "theta");
    read_floats(in, sb.s, m, "s");
    read_floats(in, sb.z, m, "z");
    read_floats(in, sb.weight, m, "weight");
    check_table(sb, i, b.vertex_count, source);
    b.sweeps.push_back(std::move(sb));
  }
  if (in.remaining() != 0) {
    std::ostringstream s;
    s << "corrupt binding: " << in.remaining() << " unexpected bytes after the last sweep table";
    refuse(source, s.str());
  }
  // A vertex belongs to at most one sweep (each table is increasing; merge them all and look for
  // neighbours that repeat; memory follows the file size, not the claimed vertex count).
  std::vector<std::uint32_t> all;
  for (const bind::SweepBinding& sb : b.sweeps) all.insert(all.end(), sb.vertices.begin(), sb.vertices.end());
  std::sort(all.begin(), all.end());
  const auto repeat = std::adjacent_find(all.begin(), all.end());
  if (repeat != all.end()) {
    std::ostringstream s;
    s << "corrupt binding: vertex " << *repeat << " is bound by more than one sweep";
    refuse(source, s.str());
  }
  return b;
}

bind::Binding read_binding(const std::filesystem::path& path) {
  return parse_binding(io::read_file(path), path.string());
}

void check_binding(const bind::Binding& binding, const Mesh& mesh, const Rig& rig, const std::string& source) {
  const std::string again = "; run sweep-bind again";
  if (binding.vertex_count != mesh.vertex_count()) {
    std::ostringstream s;
    s << "made for a mesh with " << binding.vertex_count << " vertices, this mesh has " << mesh.vertex_count() << again;
    refuse(source, s.str());
  }
  if (binding.mesh_hash != hash_positions(mesh.positions)) {
    refuse(source, "made for a mesh with other vertex positions (the mesh changed since binding)" + again);
  }
  bool same_sweeps = binding.sweeps.size() == rig.sweeps.size();
  for (std::size_t i = 0; same_sweeps && i < rig.sweeps.size(); ++i) {
    same_sweeps = binding.sweeps[i].name == rig.sweeps[i].name;
  }
  if (!same_sweeps || binding.rig_hash != hash_sweeps(rig)) {
    refuse(source, "was made for another version of the rig (sweeps changed since binding)" + again);
  }
}

bind::Binding load_binding(const std::filesystem::path& path, const Mesh& mesh, const Rig& rig) {
  bind::Binding b = read_binding(path);
  check_binding(b, mesh, rig, path.string());
  return b;
}

}  // namespace sweep::io
