// .pc2 point cache: a 32-byte header, then float32 x y z per vertex per frame, little-endian,
// streamed frame by frame into a temporary beside the output (see bake.h).
#include <bit>
#include <cstdint>
#include <cstring>
#include <memory>

#include "sweep/assets/bake.h"
#include "sweep/assets/bake_detail.h"
#include "sweep/core/error.h"

namespace sweep::assets {
namespace {

static_assert(sizeof(float) == 4 && sizeof(Eigen::Vector3f) == 12,
              "frames are written straight from a span of Vector3f");

void put_u32(char* at, std::uint32_t value) {
  for (int b = 0; b < 4; ++b) at[b] = static_cast<char>((value >> (8 * b)) & 0xffu);
}

class Pc2Writer final : public detail::BakeWriterBase {
 public:
  explicit Pc2Writer(std::filesystem::path out) : BakeWriterBase(std::move(out)) {}

  std::vector<std::filesystem::path> files() const override { return {out()}; }

 protected:
  void start(const Mesh&) override {
    file_ = std::make_unique<io::TempFile>(out());
    char header[32];
    std::memcpy(header, "POINTCACHE2\0", 12);
    put_u32(header + 12, 1);                                               // version
    put_u32(header + 16, static_cast<std::uint32_t>(rest().size()));       // points
    put_u32(header + 20, std::bit_cast<std::uint32_t>(0.0f));              // start frame
    put_u32(header + 24, std::bit_cast<std::uint32_t>(1.0f));              // sample rate
    put_u32(header + 28, static_cast<std::uint32_t>(info().frame_count));  // samples
    file_->write(header, sizeof header);
    set_estimate(sizeof header + 12 * std::uint64_t{rest().size()} * static_cast<std::uint64_t>(info().frame_count));
    if constexpr (std::endian::native != std::endian::little) scratch_.resize(rest().size() * 12);
  }

  void write_frame(int, std::span<const Eigen::Vector3f> body_positions) override {
    const std::span<const Eigen::Vector3f> positions = stored_positions(body_positions);
    if constexpr (std::endian::native == std::endian::little) {
      file_->write(positions.data(), positions.size_bytes());
    } else {
      char* at = scratch_.data();
      for (const Eigen::Vector3f& p : positions) {
        for (int c = 0; c < 3; ++c, at += 4) put_u32(at, std::bit_cast<std::uint32_t>(p[c]));
      }
      file_->write(scratch_.data(), scratch_.size());
    }
  }

  void complete(io::Publication& outputs) override {
    file_->seal();
    outputs.add(std::move(file_));
  }
  void abandon() noexcept override {
    if (file_) file_->discard();
  }

 private:
  std::unique_ptr<io::TempFile> file_;
  std::vector<char> scratch_;  // big-endian hosts only
};

}  // namespace

std::unique_ptr<BakeWriter> make_pc2_bake_writer(const std::filesystem::path& out) {
  return std::make_unique<Pc2Writer>(out);
}

}  // namespace sweep::assets
