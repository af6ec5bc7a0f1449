// The .glb bake writer: read back with tinygltf (rest mesh, every frame through its morph target,
// the weights animation), checked by the Khronos validator, and timed on a diplodocus-sized bake.
#include <tiny_gltf.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <limits>

#include "bake_test_util.h"
#include "sweep/core/error.h"

namespace sweep::test {
namespace {

namespace fs = std::filesystem;

tinygltf::Model load_glb(const fs::path& path) {
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string err, warn;
  const bool ok = loader.LoadBinaryFromFile(&model, &err, &warn, path.string());
  EXPECT_TRUE(ok) << err;
  EXPECT_EQ(warn, "");
  return model;
}

// Element i of a float or uint accessor, as stored (bufferView, stride), before any sparse part.
template <typename T, int N>
std::vector<std::array<T, N>> read_dense(const tinygltf::Model& m, const tinygltf::Accessor& a) {
  std::vector<std::array<T, N>> out(a.count, std::array<T, N>{});  // no bufferView: zeros
  if (a.bufferView < 0) return out;
  const tinygltf::BufferView& view = m.bufferViews[static_cast<std::size_t>(a.bufferView)];
  const std::size_t stride = view.byteStride ? view.byteStride : sizeof(T) * N;
  const unsigned char* base =
      m.buffers[static_cast<std::size_t>(view.buffer)].data.data() + view.byteOffset + a.byteOffset;
  EXPECT_LE(a.byteOffset + stride * (a.count - 1) + sizeof(T) * N, view.byteLength);
  for (std::size_t i = 0; i < a.count; ++i) std::memcpy(out[i].data(), base + i * stride, sizeof(T) * N);
  return out;
}

// Every element of an accessor: the dense part (zeros without a bufferView), then the sparse
// entries over it, their indices checked to ascend.
template <typename T, int N>
std::vector<std::array<T, N>> read_accessor(const tinygltf::Model& m, const tinygltf::Accessor& a) {
  std::vector<std::array<T, N>> out = read_dense<T, N>(m, a);
  if (!a.sparse.isSparse) return out;
  EXPECT_EQ(a.sparse.indices.componentType, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT);
  tinygltf::Accessor idx;
  idx.bufferView = a.sparse.indices.bufferView;
  idx.byteOffset = static_cast<std::size_t>(a.sparse.indices.byteOffset);
  idx.count = static_cast<std::size_t>(a.sparse.count);
  tinygltf::Accessor val;
  val.bufferView = a.sparse.values.bufferView;
  val.byteOffset = static_cast<std::size_t>(a.sparse.values.byteOffset);
  val.count = static_cast<std::size_t>(a.sparse.count);
  const auto indices = read_dense<std::uint32_t, 1>(m, idx);
  const auto values = read_dense<T, N>(m, val);
  for (std::size_t i = 0; i < indices.size(); ++i) {
    if (i > 0) {
      EXPECT_LT(indices[i - 1][0], indices[i][0]) << "sparse indices must ascend";
    }
    out.at(indices[i][0]) = values[i];
  }
  return out;
}

std::vector<Eigen::Vector3f> read_vec3(const tinygltf::Model& m, int index) {
  const tinygltf::Accessor& a = m.accessors[static_cast<std::size_t>(index)];
  EXPECT_EQ(a.componentType, TINYGLTF_COMPONENT_TYPE_FLOAT);
  EXPECT_EQ(a.type, TINYGLTF_TYPE_VEC3);
  std::vector<Eigen::Vector3f> out;
  for (const auto& e : read_accessor<float, 3>(m, a)) out.emplace_back(e[0], e[1], e[2]);
  return out;
}

std::vector<float> read_floats(const tinygltf::Model& m, int index) {
  const tinygltf::Accessor& a = m.accessors[static_cast<std::size_t>(index)];
  EXPECT_EQ(a.componentType, TINYGLTF_COMPONENT_TYPE_FLOAT);
  EXPECT_EQ(a.type, TINYGLTF_TYPE_SCALAR);
  std::vector<float> out;
  for (const auto& e : read_accessor<float, 1>(m, a)) out.push_back(e[0]);
  return out;
}

void expect_min_max(const tinygltf::Accessor& a, const std::vector<Eigen::Vector3f>& values) {
  ASSERT_EQ(a.minValues.size(), 3u);
  ASSERT_EQ(a.maxValues.size(), 3u);
  for (int c = 0; c < 3; ++c) {
    float lo = values[0][c], hi = values[0][c];
    for (const auto& v : values) {
      lo = std::min(lo, v[c]);
      hi = std::max(hi, v[c]);
    }
    EXPECT_EQ(a.minValues[static_cast<std::size_t>(c)], double{lo});
    EXPECT_EQ(a.maxValues[static_cast<std::size_t>(c)], double{hi});
  }
}

// Reads `path` and checks it holds exactly `bake`: returns whether its targets were sparse.
bool check_glb_matches(const fs::path& path, const TestBake& bake) {
  const tinygltf::Model m = load_glb(path);
  const std::size_t n = bake.mesh.vertex_count();
  const int frames = bake.info.frame_count;
  EXPECT_EQ(m.asset.version, "2.0");
  EXPECT_EQ(m.buffers.size(), 1u);
  EXPECT_EQ(m.meshes.size(), 1u);
  EXPECT_EQ(m.nodes.size(), 1u);
  EXPECT_EQ(m.nodes[0].mesh, 0);
  const tinygltf::Mesh& mesh = m.meshes[0];
  EXPECT_EQ(mesh.primitives.size(), 1u);
  const tinygltf::Primitive& prim = mesh.primitives[0];
  EXPECT_EQ(prim.mode, TINYGLTF_MODE_TRIANGLES);

  // Rest mesh: count, order and values exact; triangles are the fanned polygons.
  const std::vector<Eigen::Vector3f> rest = read_vec3(m, prim.attributes.at("POSITION"));
  EXPECT_EQ(rest, rest_floats(bake.mesh));
  expect_min_max(m.accessors[static_cast<std::size_t>(prim.attributes.at("POSITION"))], rest);
  const std::vector<Eigen::Vector3f> normals = read_vec3(m, prim.attributes.at("NORMAL"));
  EXPECT_EQ(normals.size(), n);
  for (const auto& nrm : normals) EXPECT_NEAR(nrm.norm(), 1.0f, 1e-6f);
  {
    const auto& a = m.accessors[static_cast<std::size_t>(prim.indices)];
    EXPECT_EQ(a.componentType, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT);
    std::vector<std::uint32_t> tris;
    for (const auto& e : read_dense<std::uint32_t, 1>(m, a)) tris.push_back(e[0]);
    EXPECT_EQ(tris, bake.mesh.triangles());
  }

  // One target per frame; rest + delta is the frame's positions, float for float.
  EXPECT_EQ(prim.targets.size(), static_cast<std::size_t>(frames));
  EXPECT_EQ(mesh.weights, std::vector<double>(static_cast<std::size_t>(frames), 0.0));
  const auto& names = mesh.extras.Get("targetNames");
  EXPECT_TRUE(names.IsArray());
  EXPECT_EQ(names.ArrayLen(), static_cast<std::size_t>(frames));
  bool sparse = false;
  for (int k = 0; k < frames && k < static_cast<int>(prim.targets.size()); ++k) {
    char expected_name[32];
    std::snprintf(expected_name, sizeof expected_name, "frame_%04d", k);
    EXPECT_EQ(names.Get(k).Get<std::string>(), expected_name);
    const int accessor = prim.targets[static_cast<std::size_t>(k)].at("POSITION");
    sparse = m.accessors[static_cast<std::size_t>(accessor)].sparse.isSparse;
    const std::vector<Eigen::Vector3f> delta = read_vec3(m, accessor);
    EXPECT_EQ(delta.size(), n);
    expect_min_max(m.accessors[static_cast<std::size_t>(accessor)], delta);
    const auto& given = bake.frames[static_cast<std::size_t>(k)];
    std::size_t wrong = 0;
    for (std::size_t v = 0; v < n; ++v) {
      const Eigen::Vector3f sum = rest[v] + delta[v];  // what a viewer computes at weight 1
      if (sum != given[v]) {
        if (wrong++ < 5) ADD_FAILURE() << "frame " << k << " vertex " << v;
      }
    }
    EXPECT_EQ(wrong, 0u) << "frame " << k;
    // Lighting follows the bend: the rest normal plus the target's NORMAL delta is the frame's
    // own smooth normal (area-weighted face normals of its positions, computed here), within
    // float rounding (a hundredth of a degree).
    const auto target = prim.targets[static_cast<std::size_t>(k)];
    EXPECT_EQ(target.count("NORMAL"), 1u) << "frame " << k;
    if (target.count("NORMAL") == 0) continue;
    const std::vector<Eigen::Vector3f> normal_delta = read_vec3(m, target.at("NORMAL"));
    EXPECT_EQ(normal_delta.size(), n);
    if (normal_delta.size() != n) continue;
    std::vector<Eigen::Vector3d> sum(n, Eigen::Vector3d::Zero());
    const std::vector<std::uint32_t> tris = bake.mesh.triangles();
    for (std::size_t t = 0; t + 2 < tris.size(); t += 3) {
      const Eigen::Vector3d a = given[tris[t]].cast<double>(), b = given[tris[t + 1]].cast<double>(),
                            c = given[tris[t + 2]].cast<double>();
      for (int j = 0; j < 3; ++j) sum[tris[t + static_cast<std::size_t>(j)]] += (b - a).cross(c - a);
    }
    double worst_degrees = 0;
    for (std::size_t v = 0; v < n; ++v) {
      if (!(sum[v].norm() > 0)) continue;
      const Eigen::Vector3d lit = (normals[v] + normal_delta[v]).cast<double>();
      const double cosine = std::clamp(lit.normalized().dot(sum[v].normalized()), -1.0, 1.0);
      worst_degrees = std::max(worst_degrees, std::acos(cosine) * 180 / 3.14159265358979);
    }
    EXPECT_LT(worst_degrees, 0.01) << "frame " << k;
  }

  // The animation: keys at k / fps, weights one-hot, LINEAR, on the node's weights.
  EXPECT_EQ(m.animations.size(), 1u);
  const tinygltf::Animation& anim = m.animations[0];
  EXPECT_EQ(anim.channels.size(), 1u);
  EXPECT_EQ(anim.channels[0].target_node, 0);
  EXPECT_EQ(anim.channels[0].target_path, "weights");
  const tinygltf::AnimationSampler& sampler = anim.samplers.at(static_cast<std::size_t>(anim.channels[0].sampler));
  EXPECT_EQ(sampler.interpolation, "LINEAR");
  const std::vector<float> times = read_floats(m, sampler.input);
  if (times.size() != static_cast<std::size_t>(frames)) {
    ADD_FAILURE() << "animation has " << times.size() << " keys";
    return sparse;
  }
  for (int k = 0; k < frames; ++k) {
    EXPECT_EQ(times[static_cast<std::size_t>(k)], static_cast<float>(k / bake.info.fps)) << k;
  }
  // Stored sparse: one entry a key, so the file grows with frames, not frames squared.
  const tinygltf::Accessor& output = m.accessors[static_cast<std::size_t>(sampler.output)];
  EXPECT_TRUE(output.sparse.isSparse);
  EXPECT_EQ(output.sparse.count, frames);
  EXPECT_LT(output.bufferView, 0) << "zeros under the sparse entries are implied, not stored";
  const std::vector<float> weights = read_floats(m, sampler.output);
  if (weights.size() != static_cast<std::size_t>(frames) * static_cast<std::size_t>(frames)) {
    ADD_FAILURE() << "animation has " << weights.size() << " weights";
    return sparse;
  }
  for (int key = 0; key < frames; ++key) {
    for (int t = 0; t < frames; ++t) {
      EXPECT_EQ(weights[static_cast<std::size_t>(key * frames + t)], key == t ? 1.0f : 0.0f);
    }
  }
  return sparse;
}

TEST(BakeGltf, SparseBakeReadsBackExactly) {
  const TestBake bake = make_test_bake();
  const fs::path out = fresh_dir("") / "tube.glb";
  write_bake(out, bake);
  EXPECT_TRUE(check_glb_matches(out, bake)) << "a partly moving mesh gets sparse targets";
  EXPECT_EQ(list_dir(out.parent_path()), std::vector<std::string>{"tube.glb"});
}

TEST(BakeGltf, DenseBakeReadsBackExactly) {
  const TestBake bake = make_test_bake(12, 8, 4, 0.3, /*list_animated=*/false);
  const fs::path out = fresh_dir("") / "tube.glb";
  write_bake(out, bake);
  EXPECT_FALSE(check_glb_matches(out, bake)) << "with no animated list every target is dense";
}

TEST(BakeGltf, NothingMovesStillGivesAValidTargetPerFrame) {
  TestBake bake = make_test_bake(6, 5, 3, 0.0);
  bake.info.animated_vertices = std::vector<std::uint32_t>{};
  const fs::path out = fresh_dir("") / "still.glb";
  write_bake(out, bake);
  EXPECT_TRUE(check_glb_matches(out, bake));
}

TEST(BakeGltf, MoreFramesThanTheWeightsCanIndexAreRefusedAtTheStart) {
  // 65,536² one-hot weights overflow a uint32 sparse index: refused before any frame, no file.
  TestBake bake = make_test_bake(3, 3, 1, 0.3);
  bake.info.frame_count = 65536;
  const fs::path out = fresh_dir("") / "long.glb";
  auto writer = assets::make_bake_writer(out);
  try {
    writer->begin(bake.mesh, bake.info);
    ADD_FAILURE() << "65,536 frames were accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.category(), ErrorCategory::unsupported);
    EXPECT_NE(std::string(e.what()).find("more morph targets than a .glb's weights can index"), std::string::npos)
        << e.what();
  }
  writer.reset();
  EXPECT_FALSE(fs::exists(out));
}

TEST(BakeGltf, DeltaPrecisionWhenAVertexMovesFarRelativeToItsCoordinates) {
  // A vertex moving from 0.1 to -0.2 needs a delta whose float grid is coarser than the baked
  // coordinate's: rest + delta is then within half an ulp of the delta (plus the sum's rounding),
  // and no float delta can do better. Small moves, as in the other tests, are exact.
  Mesh mesh;
  mesh.positions = {{0.1, 0.2, 0.3}, {1.9, -0.2, 3.0}, {-0.2, 1e-3, 7.0}, {5.0, 6.0, 7.0}};
  mesh.add_face({0, 1, 2});
  mesh.add_face({0, 2, 3});
  TestBake bake;
  bake.mesh = mesh;
  bake.info.frame_count = 2;
  bake.info.fps = 30;
  bake.frames = {rest_floats(mesh), rest_floats(mesh)};
  for (int v = 0; v < 4; ++v) {
    bake.frames[1][static_cast<std::size_t>(v)] =
        Eigen::Vector3f(-0.2f + 2.1f * static_cast<float>(v), 1.9f - 0.7f * static_cast<float>(v),
                        0.3f + 1.37f * static_cast<float>(v));
  }
  const fs::path out = fresh_dir("") / "far.glb";
  write_bake(out, bake);
  const tinygltf::Model m = load_glb(out);
  const auto& prim = m.meshes.at(0).primitives.at(0);
  const auto rest = read_vec3(m, prim.attributes.at("POSITION"));
  const auto delta = read_vec3(m, prim.targets.at(1).at("POSITION"));
  auto ulp = [](float x) { return std::nextafter(std::abs(x), std::numeric_limits<float>::infinity()) - std::abs(x); };
  int inexact = 0;
  for (std::size_t v = 0; v < 4; ++v) {
    for (int c = 0; c < 3; ++c) {
      const float p = bake.frames[1][v][c], d = delta[v][c], sum = rest[v][c] + d;
      EXPECT_EQ(d, p - rest[v][c]) << "the delta is the correctly rounded difference";
      EXPECT_LE(std::abs(sum - p), 0.5f * ulp(d) + 0.5f * ulp(p)) << v << " " << c;
      if (std::abs(d) <= std::abs(p)) {
        EXPECT_EQ(sum, p) << v << " " << c;
      }
      inexact += sum != p;
    }
  }
  EXPECT_GT(inexact, 0) << "the case this test is about did not occur";
}

// --- The Khronos glTF validator -------------------------------------------------------------

struct Validation {
  int exit_code = -1;
  std::string report;
};

Validation run_validator(const fs::path& glb) {
  const fs::path script = fs::path(SWEEP_SOURCE_DIR) / "tests/gltf-validator/validate.js";
  const std::string command = "node '" + script.string() + "' '" + glb.string() + "' 2>&1";
  Validation v;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return v;
  char buf[4096];
  std::size_t got;
  while ((got = std::fread(buf, 1, sizeof buf, pipe)) > 0) v.report.append(buf, got);
  const int status = ::pclose(pipe);
  v.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return v;
}

void require_validator() {
  const fs::path package = fs::path(SWEEP_SOURCE_DIR) / "tests/gltf-validator/node_modules/gltf-validator";
  ASSERT_EQ(std::system("node --version > /dev/null 2>&1"), 0)
      << "node is not installed: run tools/setup-deps.sh (Debian packages nodejs and npm)";
  ASSERT_TRUE(fs::exists(package / "package.json"))
      << "the Khronos glTF validator is not installed in " << package.parent_path() << ": run tools/setup-deps.sh";
}

void expect_valid(const fs::path& glb) {
  const Validation v = run_validator(glb);
  EXPECT_EQ(v.exit_code, 0) << glb << ":\n" << v.report;
  EXPECT_NE(v.report.find("\"numErrors\": 0"), std::string::npos) << v.report;
  // Not required, but a clean file has no warnings either.
  EXPECT_NE(v.report.find("\"numWarnings\": 0"), std::string::npos) << v.report;
}

TEST(BakeGltfValidator, SparseDenseStillAndSingleFrameBakesPassWithNoErrors) {
  require_validator();
  if (HasFatalFailure()) return;
  const fs::path dir = fresh_dir("");
  write_bake(dir / "sparse.glb", make_test_bake(16, 10, 6, 0.3));
  write_bake(dir / "dense.glb", make_test_bake(8, 6, 3, 0.5, /*list_animated=*/false));
  TestBake still = make_test_bake(4, 5, 2, 0.0);
  still.info.animated_vertices = std::vector<std::uint32_t>{};
  write_bake(dir / "still.glb", still);
  write_bake(dir / "single.glb", make_test_bake(4, 4, 1, 0.5));
  for (const char* name : {"sparse.glb", "dense.glb", "still.glb", "single.glb"}) {
    expect_valid(dir / name);
  }
}

TEST(BakeGltfValidator, ReportsErrorsInABrokenFile) {
  // The validator really looks: a .glb whose JSON chunk is cut short must fail.
  require_validator();
  if (HasFatalFailure()) return;
  const fs::path dir = fresh_dir("");
  write_bake(dir / "good.glb", make_test_bake(4, 4, 2));
  std::string bytes = slurp(dir / "good.glb");
  bytes[20] = '#';  // the JSON text's opening brace
  std::ofstream(dir / "bad.glb", std::ios::binary) << bytes;
  const Validation v = run_validator(dir / "bad.glb");
  EXPECT_NE(v.exit_code, 0) << v.report;
}

// --- Speed ------------------------------------------------------------------------------------

TEST(BakeGltfSpeed, SixHundredFramesOf24000VerticesWith30PercentMoving) {
  // A diplodocus-sized bake (200 rings × 120 = 24,000 vertices; the last 60 rings, 7,200 vertices,
  // move). Times only the writer; frame positions are made outside the timed calls. Median of 3.
  constexpr int kRings = 200, kSegments = 120, kFirstMoving = 140;
#if defined(NDEBUG) && !defined(SWEEP_SANITIZED)
  constexpr int kFrames = 600, kRuns = 3;
#elif defined(SWEEP_SANITIZED)  // the writer's memory use checked on 12 frames, untimed (16 s for 60)
  constexpr int kFrames = 12, kRuns = 1;
#else                           // unoptimized: a tenth of the bake, once, untimed (it takes minutes otherwise)
  constexpr int kFrames = 60, kRuns = 1;
#endif
  const Mesh mesh = make_tube(kRings, kSegments);
  assets::BakeInfo info;
  info.frame_count = kFrames;
  info.fps = 30;
  std::vector<std::uint32_t> animated;
  for (std::uint32_t v = kFirstMoving * kSegments; v < kRings * kSegments; ++v) animated.push_back(v);
  info.animated_vertices = animated;
  const fs::path out = fresh_dir("") / "big.glb";
  std::vector<Eigen::Vector3f> positions;
  std::vector<double> seconds;
  for (int run = 0; run < kRuns; ++run) {
    using Clock = std::chrono::steady_clock;
    Clock::duration spent{};
    auto writer = assets::make_bake_writer(out);
    auto t0 = Clock::now();
    writer->begin(mesh, info);
    spent += Clock::now() - t0;
    for (int k = 0; k < kFrames; ++k) {
      bend_frame(mesh, kSegments, kFirstMoving, k, positions);
      t0 = Clock::now();
      writer->frame(k, positions);
      spent += Clock::now() - t0;
    }
    t0 = Clock::now();
    writer->finish();
    spent += Clock::now() - t0;
    seconds.push_back(std::chrono::duration<double>(spent).count());
  }
  std::sort(seconds.begin(), seconds.end());
  const double median = seconds[seconds.size() / 2];
  std::cout << "[ timing   ] " << kFrames << " frames, 24,000 vertices (7,200 moving) to .glb ("
            << fs::file_size(out) / 1e6 << " MB): median " << median << " s of " << kRuns << " (" << seconds.front()
            << " .. " << seconds.back() << ")\n";
  RecordProperty("median_seconds", std::to_string(median));
#if defined(NDEBUG) && !defined(SWEEP_SANITIZED)
  EXPECT_LT(median, 3.0);
#endif
  fs::remove(out);
}

}  // namespace
}  // namespace sweep::test
