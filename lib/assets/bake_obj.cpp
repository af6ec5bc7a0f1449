// OBJ sequence: one Wavefront OBJ a frame (`out_0000.obj`, ...), `v` lines in vertex order and
// the mesh's polygons. Each frame's file is written and synced as a temporary when the frame
// arrives (no descriptor stays open); finish() renames them all into place (see bake.h).
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <memory>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "sweep/assets/bake.h"
#include "sweep/assets/bake_detail.h"
#include "sweep/assets/mesh_io_detail.h"
#include "sweep/core/error.h"
#include "sweep/io/atomic_file.h"

namespace sweep::assets {
namespace {

constexpr char kHeader[] = "# sweep bake 1: frame ";  // each frame's first line starts so

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
    header_tail_ = " of " + std::to_string(info().frame_count) + ", " + std::to_string(n) + " vertices, " +
                   std::to_string(mesh.face_count()) + " faces\n";
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
    // An upper bound, so that --max-output-size is never overrun: "v ", three floats in their
    // shortest form (at most 15 characters: a sign, 9 digits, the point and "e-38"), two spaces
    // and the newline for a vertex that moves; the rest pose's own lines for one that never does.
    constexpr std::uint64_t kMaxVertexLineBytes = 2 + 3 * 15 + 2 + 1;
    const std::uint64_t moving = all_animated() || info().body_moves ? n : animated().size();
    const std::uint64_t still_bytes = all_animated() || info().body_moves ? 0 : rest_lines_.size() - [&] {
      std::uint64_t b = 0;
      for (const std::uint32_t a : animated()) b += rest_line_start_[a + 1] - rest_line_start_[a];
      return b;
    }();
    const std::uint64_t header_bytes =
        sizeof kHeader - 1 + std::to_string(info().frame_count).size() + header_tail_.size();
    set_estimate(static_cast<std::uint64_t>(info().frame_count) *
                 (header_bytes + kMaxVertexLineBytes * moving + still_bytes + faces_.size()));
    // The files are made frame by frame; find out now, before any simulation, whether the folder
    // takes files at all (a nameless scratch file leaves nothing behind).
    io::TempFile probe(out(), /*scratch=*/true);
  }

  void write_frame(int index, std::span<const Eigen::Vector3f> body_positions) override {
    // World positions in the mesh's local space: with a moving body every vertex moves.
    const std::span<const Eigen::Vector3f> positions = stored_positions(body_positions);
    std::string& text = text_;
    text.clear();
    text += kHeader;
    text += std::to_string(index);
    text += header_tail_;
    if (all_animated() || info().body_moves) {
      for (const Eigen::Vector3f& p : positions) detail::append_vertex_line(text, "v ", p);
    } else {
      std::size_t next = 0;  // first vertex not yet written
      for (const std::uint32_t a : animated()) {
        text.append(rest_lines_, rest_line_start_[next], rest_line_start_[a] - rest_line_start_[next]);
        detail::append_vertex_line(text, "v ", positions[a]);
        next = std::size_t{a} + 1;
      }
      text.append(rest_lines_, rest_line_start_[next], std::string::npos);
    }
    text += faces_;
    auto file = std::make_unique<io::TempFile>(obj_sequence_path(out(), index, info().frame_count));
    file->write(text);
    file->seal();
    frames_.push_back(std::move(file));
  }

  // The frames go into place together (and with the run's other outputs): two runs publishing
  // the same sequence take turns, so frames never mix, and a frame of an earlier bake under the
  // same name is set aside and put back if the set cannot be completed (io::Publication).
  // The bake owns its sequence: frames of an earlier, longer bake under the same name (past this
  // one's end, or numbered with another width) go with the commit, so no stale frame stays beside
  // the new ones.
  void complete(io::Publication& outputs) override {
    std::set<std::filesystem::path> names;
    for (auto& frame : frames_) {
      names.insert(frame->target().filename());
      outputs.add(std::move(frame));
    }
    frames_.clear();
    for (const std::filesystem::path& stale : stale_frames(names)) outputs.remove(stale);
  }

  void abandon() noexcept override { frames_.clear(); }  // each io::TempFile removes its temporary

  // The files beside the sequence named as its frames are ("<stem>_<digits><ext>", at least four
  // digits) that this bake does not write, each an earlier bake's frame by its first line (this
  // writer's header), the mesh being baked excepted.
  std::vector<std::filesystem::path> stale_frames(const std::set<std::filesystem::path>& written) const {
    namespace fs = std::filesystem;
    const fs::path dir = out().has_parent_path() ? out().parent_path() : fs::path(".");
    const std::string prefix = out().stem().string() + "_", ext = out().extension().string();
    std::vector<fs::path> stale;
    std::error_code ec;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
      const std::string name = it->path().filename().string();
      if (name.size() < prefix.size() + 4 + ext.size() || name.rfind(prefix, 0) != 0 ||
          name.compare(name.size() - ext.size(), ext.size(), ext) != 0 || written.count(name)) {
        continue;
      }
      const std::string digits = name.substr(prefix.size(), name.size() - prefix.size() - ext.size());
      if (digits.find_first_not_of("0123456789") != std::string::npos) continue;
      std::error_code same;
      if (!info().source.path.empty() && fs::equivalent(it->path(), info().source.path, same)) continue;
      if (!it->is_regular_file(same) || it->is_symlink(same)) continue;
      std::ifstream in(it->path(), std::ios::binary);
      char head[sizeof kHeader - 1] = {};
      if (!in.read(head, sizeof head) || std::string_view(head, sizeof head) != kHeader) continue;
      stale.push_back(dir / name);
    }
    std::sort(stale.begin(), stale.end());
    return stale;
  }

 private:
  std::string faces_;        // the `f` lines, the same in every frame
  std::string header_tail_;  // the comment line after the frame number
  std::string rest_lines_;   // `v` lines of the rest pose, when some vertices never move
  std::vector<std::size_t> rest_line_start_;
  std::string text_;  // one frame's file, reused
  std::vector<std::unique_ptr<io::TempFile>> frames_;
};

}  // namespace

std::unique_ptr<BakeWriter> make_obj_bake_writer(const std::filesystem::path& out) {
  return std::make_unique<ObjSequenceWriter>(out);
}

}  // namespace sweep::assets
