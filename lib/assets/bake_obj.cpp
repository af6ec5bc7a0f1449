// OBJ sequence: one Wavefront OBJ a frame (`out_0000.obj`, ...), `v` lines in vertex order and
// the mesh's polygons. Each frame's file is written and synced as a temporary when the frame
// arrives (no descriptor stays open); finish() renames them all into place (see bake.h).
#include <unistd.h>

#include <cstdio>
#include <memory>
#include <string>

#include "assets/bake.h"
#include "assets/bake_detail.h"
#include "assets/mesh_io_detail.h"
#include "core/error.h"
#include "io/atomic_file.h"

namespace sweep::io {
namespace {

class ObjSequenceWriter final : public detail::BakeWriterBase {
 public:
  explicit ObjSequenceWriter(std::filesystem::path out) : BakeWriterBase(std::move(out)) {}

  std::vector<std::filesystem::path> files() const override {
    std::vector<std::filesystem::path> paths;
    for (int k = 0; k < info().frame_count; ++k) {
      paths.push_back(obj_sequence_path(out(), k, info().frame_count));
    }
    return paths;
  }

 protected:
  void start(const Mesh& mesh) override {
    const std::size_t n = rest().size();
    faces_.clear();
    detail::append_obj_faces(faces_, mesh);
    header_tail_ = " of " + std::to_string(info().frame_count) + ", " + std::to_string(n) +
                   " vertices, " + std::to_string(mesh.face_count()) + " faces\n";
    // Vertices that never move are formatted once: their lines are copied from here each frame.
    if (!all_animated() && !info().body_moves) {
      rest_lines_.clear();
      rest_line_start_.resize(n + 1);
      for (std::size_t v = 0; v < n; ++v) {
        rest_line_start_[v] = rest_lines_.size();
        detail::append_vertex_line(rest_lines_, "v ", stored_rest()[v]);
      }
      rest_line_start_[n] = rest_lines_.size();
    }
    frames_.reserve(static_cast<std::size_t>(info().frame_count));
    constexpr std::uint64_t kVertexLineBytes = 36;  // "v " and three shortest floats: typical
    set_estimate(static_cast<std::uint64_t>(info().frame_count) *
                 (64 + kVertexLineBytes * n + faces_.size()));
    // The files are made frame by frame; find out now, before any simulation, whether the folder
    // takes files at all (a nameless scratch file leaves nothing behind).
    TempFile probe(out(), /*scratch=*/true);
  }

  void write_frame(int index, std::span<const Eigen::Vector3f> body_positions) override {
    // World positions in the mesh's local space: with a moving body every vertex moves.
    const std::span<const Eigen::Vector3f> positions = stored_positions(body_positions);
    std::string& text = text_;
    text.clear();
    text += "# sweep bake 1: frame ";
    text += std::to_string(index);
    text += header_tail_;
    if (all_animated() || info().body_moves) {
      for (const Eigen::Vector3f& p : positions) detail::append_vertex_line(text, "v ", p);
    } else {
      std::size_t next = 0;  // first vertex not yet written
      for (const std::uint32_t a : animated()) {
        text.append(rest_lines_, rest_line_start_[next],
                    rest_line_start_[a] - rest_line_start_[next]);
        detail::append_vertex_line(text, "v ", positions[a]);
        next = std::size_t{a} + 1;
      }
      text.append(rest_lines_, rest_line_start_[next], std::string::npos);
    }
    text += faces_;
    auto file =
        std::make_unique<TempFile>(obj_sequence_path(out(), index, info().frame_count));
    file->write(text);
    file->seal();
    frames_.push_back(std::move(file));
  }

  // The frames go into place together (and with the run's other outputs): two runs publishing
  // the same sequence take turns, so frames never mix, and a frame of an earlier bake under the
  // same name is set aside and put back if the set cannot be completed (Publication).
  void complete(Publication& outputs) override {
    for (auto& frame : frames_) outputs.add(std::move(frame));
    frames_.clear();
  }

  void abandon() noexcept override { frames_.clear(); }  // each TempFile removes its temporary

 private:
  std::string faces_;        // the `f` lines, the same in every frame
  std::string header_tail_;  // the comment line after the frame number
  std::string rest_lines_;   // `v` lines of the rest pose, when some vertices never move
  std::vector<std::size_t> rest_line_start_;
  std::string text_;  // one frame's file, reused
  std::vector<std::unique_ptr<TempFile>> frames_;
};

}  // namespace

std::unique_ptr<BakeWriter> make_obj_bake_writer(const std::filesystem::path& out) {
  return std::make_unique<ObjSequenceWriter>(out);
}

}  // namespace sweep::io
