#pragma once
// FNV-1a 64, the one hash of the project: binding files (their checksum, the mesh and rig hashes
// they are checked against), temporary names and hash tables keyed by bits. Not cryptographic:
// it tells a stale or damaged file from the right one, it does not stand up to an adversary.
#include <bit>
#include <cstdint>
#include <string_view>

namespace sweep {

inline constexpr std::uint64_t kFnvOffset = 14695981039346656037ull;
inline constexpr std::uint64_t kFnvPrime = 1099511628211ull;

// Feeds bytes into a running hash (start from kFnvOffset).
inline std::uint64_t fnv1a(std::uint64_t h, std::string_view bytes) {
  for (unsigned char c : bytes) {
    h ^= c;
    h *= kFnvPrime;
  }
  return h;
}
inline std::uint64_t fnv1a(std::string_view bytes) {
  return fnv1a(kFnvOffset, bytes);
}

// Feeds the low `bytes` bytes of `word`, least significant first (little-endian, whatever the host).
inline std::uint64_t fnv1a_le(std::uint64_t h, std::uint64_t word, int bytes) {
  for (int b = 0; b < bytes; ++b) {
    h ^= (word >> (8 * b)) & 0xffu;
    h *= kFnvPrime;
  }
  return h;
}
inline std::uint64_t fnv1a_double(std::uint64_t h, double x) {
  return fnv1a_le(h, std::bit_cast<std::uint64_t>(x), 8);
}

}  // namespace sweep
