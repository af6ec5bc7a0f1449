// libFuzzer entry point of the material target (tests/fuzz/targets.h says what it checks).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "targets.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  sweep::fuzz::material(std::string_view(reinterpret_cast<const char*>(data), size));
  return 0;
}
