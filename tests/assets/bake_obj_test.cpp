// The OBJ sequence bake writer: file names, `v` lines read back exactly, faces as in the mesh.
#include <charconv>
#include <sstream>

#include "bake_test_util.h"

namespace sweep::test {
namespace {

namespace fs = std::filesystem;

struct ObjFile {
  std::vector<Eigen::Vector3f> v;
  std::vector<std::vector<std::uint32_t>> faces;  // 0-based
};

ObjFile parse_obj(const std::string& text) {
  ObjFile obj;
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> words;
    std::istringstream ws(line);
    for (std::string w; ws >> w;) words.push_back(w);
    if (words[0] == "v") {
      EXPECT_EQ(words.size(), 4u) << line;
      Eigen::Vector3f p;
      for (int c = 0; c < 3; ++c) {
        const std::string& w = words[static_cast<std::size_t>(c) + 1];
        const auto [end, ec] = std::from_chars(w.data(), w.data() + w.size(), p[c]);
        EXPECT_TRUE(ec == std::errc() && end == w.data() + w.size()) << line;
      }
      obj.v.push_back(p);
    } else if (words[0] == "f") {
      std::vector<std::uint32_t> face;
      for (std::size_t i = 1; i < words.size(); ++i) {
        face.push_back(static_cast<std::uint32_t>(std::stoul(words[i]) - 1));
      }
      obj.faces.push_back(face);
    } else {
      ADD_FAILURE() << "unexpected line: " << line;
    }
  }
  return obj;
}

std::vector<std::vector<std::uint32_t>> faces_of(const Mesh& mesh) {
  std::vector<std::vector<std::uint32_t>> faces;
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    faces.emplace_back(mesh.face_vertices.begin() + mesh.face_offsets[f],
                       mesh.face_vertices.begin() + mesh.face_offsets[f + 1]);
  }
  return faces;
}

TEST(BakeObj, SequenceNamesVerticesAndFacesReadBackExactly) {
  const TestBake bake = make_test_bake(9, 6, 4, 0.3);
  const fs::path dir = fresh_dir("");
  write_bake(dir / "tube.obj", bake);
  EXPECT_EQ(list_dir(dir),
            (std::vector<std::string>{"tube_0000.obj", "tube_0001.obj", "tube_0002.obj", "tube_0003.obj"}));
  const auto faces = faces_of(bake.mesh);
  ASSERT_EQ(faces.front().size(), 6u) << "the cap polygon stays one face";
  for (std::size_t k = 0; k < bake.frames.size(); ++k) {
    const fs::path file = dir / ("tube_000" + std::to_string(k) + ".obj");
    const ObjFile obj = parse_obj(slurp(file));
    EXPECT_EQ(obj.v, bake.frames[k]) << file;
    EXPECT_EQ(obj.faces, faces) << file;
  }
}

TEST(BakeObj, EveryVertexMovingGivesTheSameNumbers) {
  // Without an animated list every vertex is formatted each frame (no cached rest lines).
  const TestBake bake = make_test_bake(5, 4, 2, 0.6, /*list_animated=*/false);
  const fs::path dir = fresh_dir("");
  write_bake(dir / "all.obj", bake);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(parse_obj(slurp(dir / ("all_000" + std::to_string(k) + ".obj"))).v, bake.frames[k]);
  }
}

TEST(BakeObj, NumbersWidenPastTenThousandFrames) {
  EXPECT_EQ(assets::obj_sequence_path("a/b.obj", 7, 10), fs::path("a/b_0007.obj"));
  EXPECT_EQ(assets::obj_sequence_path("b.obj", 9999, 10000), fs::path("b_9999.obj"));
  EXPECT_EQ(assets::obj_sequence_path("b.obj", 7, 10001), fs::path("b_00007.obj"));
  EXPECT_EQ(assets::obj_sequence_path("b.obj", 10000, 10001), fs::path("b_10000.obj"));
  EXPECT_EQ(assets::obj_sequence_path("x.y/b.OBJ", 3, 5), fs::path("x.y/b_0003.OBJ"));
}

}  // namespace
}  // namespace sweep::test
