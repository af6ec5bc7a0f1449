// The binding file: round trip, deterministic bytes (twice, and with 1 and 2 threads), and every
// way a binding can be stale or broken refused with a clear message, through the loader API and
// through the sweep-bind program (--check) with its exit code.
#include <omp.h>

#include <cstring>
#include <nlohmann/json.hpp>

#include "support.h"
#include "sweep/io/binding_file.h"
#include "sweep/io/read_file.h"
#include "sweep/io/rig_json.h"

namespace sweep::test {
namespace {

using bind::Binding;

// A tube mesh and rig on disk (rig.json next to tube.obj), as a user would have them.
struct OnDisk {
  fs::path dir, rig_path, mesh_path;
  Rig rig;
  Mesh mesh;
};

OnDisk write_tube_rig(const std::string& name) {
  OnDisk d;
  d.dir = scratch_dir(name);
  d.mesh_path = d.dir / "tube.obj";
  d.rig_path = d.dir / "tube.json";
  d.mesh = tube::make_tube(straight_tube_params());
  assets::write_mesh(d.mesh_path, d.mesh);
  d.mesh = assets::read_mesh(d.mesh_path);  // exactly what the tool will read
  d.rig = rig_of({straight_sweep("tail")}, "tube.obj");
  io::write_rig(d.rig_path, d.rig);
  d.rig = io::read_rig(d.rig_path);
  return d;
}

TEST(BindingFile, RoundTripKeepsEveryValueAndTheLayoutIsAsDocumented) {
  const Mesh mesh = tube::make_tube(straight_tube_params());
  const Rig rig = rig_of({straight_sweep("a"), straight_sweep("b", true, 0.2)});
  bind::BindOptions o;
  o.blend = 0.05;
  const Binding b = bind::bind_rig(rig, mesh, o);
  const std::string bytes = io::binding_bytes(b);
  // 48-byte header, per sweep 4 + name + 8 + 24 per vertex, 8-byte checksum.
  std::size_t expected = 48 + 8;
  for (const auto& s : b.sweeps) expected += 4 + s.name.size() + 8 + 24 * s.size();
  EXPECT_EQ(bytes.size(), expected);
  EXPECT_EQ(bytes.substr(0, 8), std::string("SWPBIND\0", 8));
  EXPECT_EQ(bytes[8], 2);  // version 2, little-endian
  const Binding back = io::parse_binding(bytes, "mem.bind");
  EXPECT_EQ(back.vertex_count, b.vertex_count);
  EXPECT_EQ(back.mesh_hash, b.mesh_hash);
  EXPECT_EQ(back.rig_hash, b.rig_hash);
  ASSERT_EQ(back.sweeps.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(back.sweeps[i].name, b.sweeps[i].name);
    EXPECT_EQ(back.sweeps[i].vertices, b.sweeps[i].vertices);
    EXPECT_EQ(back.sweeps[i].t, b.sweeps[i].t);
    EXPECT_EQ(back.sweeps[i].theta, b.sweeps[i].theta);
    EXPECT_EQ(back.sweeps[i].s, b.sweeps[i].s);
    EXPECT_EQ(back.sweeps[i].z, b.sweeps[i].z);
    EXPECT_EQ(back.sweeps[i].weight, b.sweeps[i].weight);
  }
  EXPECT_EQ(io::binding_bytes(back), bytes);
  EXPECT_NO_THROW(io::check_binding(back, mesh, rig, "mem.bind"));
}

TEST(BindingFile, SameInputsGiveTheSameBytesWhateverTheThreadCount) {
  const Mesh mesh = tube::make_tube(straight_tube_params());
  // A dense tube (38,402 vertices): large enough that the loops really run on two threads.
  tube::TubeParams dense_params = straight_tube_params();
  dense_params.rings = 401;
  dense_params.segments = 96;
  const Mesh dense = tube::make_tube(dense_params);
  ASSERT_GE(static_cast<std::ptrdiff_t>(dense.vertex_count()), 2 * bind::kMinParallelVertices);
  std::vector<const Mesh*> meshes{&mesh, &dense};
  std::vector<Rig> rigs{rig_of({straight_sweep("a"), straight_sweep("b", false, 0.12)}),
                        rig_of({straight_sweep("a", false), straight_sweep("b", true, 0.12)})};
  if (const Diplodocus* d = diplodocus()) {
    meshes.push_back(&d->mesh);
    rigs.push_back(d->rig);
  }
  const int saved = omp_get_max_threads();
  for (std::size_t c = 0; c < meshes.size(); ++c) {
    bind::BindOptions o;
    o.blend = 0.02;
    omp_set_num_threads(1);
    const std::string one = io::binding_bytes(bind::bind_rig(rigs[c], *meshes[c], o));
    const std::string again = io::binding_bytes(bind::bind_rig(rigs[c], *meshes[c], o));
    omp_set_num_threads(2);
    const std::string two = io::binding_bytes(bind::bind_rig(rigs[c], *meshes[c], o));
    omp_set_num_threads(saved);
    EXPECT_EQ(one, again) << "case " << c;
    EXPECT_EQ(one, two) << "case " << c;
  }
}

TEST(BindingFile, HashesFollowPositionsAndSweepGeometryButNotSpringsOrMeshPath) {
  const Mesh mesh = tube::make_tube(straight_tube_params());
  Mesh moved = mesh;
  moved.positions[500].x() = std::nextafter(moved.positions[500].x(), 1.0);  // one ulp
  EXPECT_NE(bind::hash_positions(mesh.positions), bind::hash_positions(moved.positions));
  const Rig rig = rig_of({straight_sweep()}, "a.obj");
  Rig other_path = rig;
  other_path.mesh = "elsewhere/b.obj";
  EXPECT_EQ(bind::hash_sweeps(rig), bind::hash_sweeps(other_path));
  Rig stiffer = rig;
  stiffer.sweeps[0].springs[2].bend.frequency_hz *= 2;
  stiffer.sweeps[0].rotational_scale = 3;
  EXPECT_EQ(bind::hash_sweeps(rig), bind::hash_sweeps(stiffer));
  Rig reshaped = rig;
  reshaped.sweeps[0].rest.radii[5] *= 1.01;
  EXPECT_NE(bind::hash_sweeps(rig), bind::hash_sweeps(reshaped));
  Rig renamed = rig;
  renamed.sweeps[0].name = "other";
  EXPECT_NE(bind::hash_sweeps(rig), bind::hash_sweeps(renamed));
  Rig reseeded = rig;
  reseeded.sweeps[0].part->tip.z() = 0.9;
  EXPECT_NE(bind::hash_sweeps(rig), bind::hash_sweeps(reseeded));
  Rig cut = rig;  // a tip-side cut selects other vertices: a binding made without it is stale
  cut.sweeps[0].part->tip_cut = true;
  EXPECT_NE(bind::hash_sweeps(rig), bind::hash_sweeps(cut));
}

// The rig hash is of the documented byte layout (bind.h), built here independently of bind.cpp:
// the binding depends on the sweep's numbers, not on how any file prints them. A material, a
// one-ulp change of a radius, a sweep without seeds and one with a tip-side cut are all covered.
TEST(BindingFile, RigHashIsFnvOfTheDocumentedByteLayout) {
  Rig rig = rig_of({straight_sweep("tail"), straight_sweep("neck", false), straight_sweep("hose")}, "a.obj");
  rig.sweeps[2].part->tip_cut = true;
  rig.sweeps[0].rest.radii[3] = std::nextafter(rig.sweeps[0].rest.radii[3], 1.0);
  rig.sweeps[1].material = Material{};
  std::string bytes(bind::kSweepHashTag);
  auto u32 = [&](std::uint64_t v) {
    for (int b = 0; b < 4; ++b) bytes += static_cast<char>((v >> (8 * b)) & 0xff);
  };
  auto f64 = [&](double x) {
    std::uint64_t v;
    std::memcpy(&v, &x, 8);
    for (int b = 0; b < 8; ++b) bytes += static_cast<char>((v >> (8 * b)) & 0xff);
  };
  u32(rig.sweeps.size());
  for (const SweepDef& d : rig.sweeps) {
    u32(d.name.size());
    bytes += d.name;
    u32(d.rest.section_count());
    u32(d.rest.radial_count);
    for (int i = 0; i < d.rest.section_count(); ++i) {
      const Frame& f = d.rest.frames[i];
      f64(d.rest.t[i]);
      for (double x : {f.rotation.w(), f.rotation.x(), f.rotation.y(), f.rotation.z()}) f64(x);
      for (int a = 0; a < 3; ++a) f64(f.center[a]);
      for (int j = 0; j < d.rest.radial_count; ++j) f64(d.rest.radius_sample(i, j));
    }
    bytes += static_cast<char>(d.part ? (d.part->tip_cut ? 2 : 1) : 0);
    if (d.part) {
      for (int a = 0; a < 3; ++a) f64(d.part->root[a]);
      for (int a = 0; a < 3; ++a) f64(d.part->tip[a]);
    }
  }
  std::uint64_t h = 14695981039346656037ull;  // FNV-1a 64, written out
  for (unsigned char c : bytes) h = (h ^ c) * 1099511628211ull;
  EXPECT_EQ(bind::hash_sweeps(rig), h);
}

TEST(BindingFile, StaleAndBrokenBindingsAreRefusedByTheLoader) {
  const OnDisk d = write_tube_rig("loader");
  const fs::path path = d.dir / "tube.bind";
  io::write_binding(path, bind::bind_rig(d.rig, d.mesh));
  EXPECT_NO_THROW(io::load_binding(path, d.mesh, d.rig));
  const std::string src = path.string();
  const std::string good = io::read_file(path);

  // Another mesh: fewer vertices, then the same count with one vertex moved.
  Mesh smaller = tube::make_tube([] {
    auto p = straight_tube_params();
    p.rings = 4;
    return p;
  }());
  expect_refused([&] { io::load_binding(path, smaller, d.rig); }, ErrorCategory::bad_input,
                 {src.c_str(), "made for a mesh with 986 vertices, this mesh has 98", "run sweep-bind again"});
  Mesh edited = d.mesh;
  edited.positions[100] += Vec3(0, 0, 1e-9);
  expect_refused([&] { io::load_binding(path, edited, d.rig); }, ErrorCategory::bad_input,
                 {src.c_str(), "other vertex positions", "run sweep-bind again"});

  // Another version of the rig: a radius changed, a sweep renamed, a sweep added.
  Rig reshaped = d.rig;
  reshaped.sweeps[0].rest.radii[0] = 0.11;
  Rig renamed = d.rig;
  renamed.sweeps[0].name = "neck";
  Rig added = d.rig;
  added.sweeps.push_back(straight_sweep("neck"));
  for (const Rig* r : {&reshaped, &renamed, &added}) {
    expect_refused([&] { io::load_binding(path, d.mesh, *r); }, ErrorCategory::bad_input,
                   {src.c_str(), "another version of the rig (sweeps changed since binding)", "run sweep-bind again"});
  }

  // Truncated: anywhere in the header, in the payload, just before the checksum; and empty.
  for (std::size_t keep :
       {std::size_t{0}, std::size_t{20}, std::size_t{47}, std::size_t{100}, good.size() / 2, good.size() - 1}) {
    expect_refused([&] { io::parse_binding(good.substr(0, keep), src); }, ErrorCategory::bad_input,
                   {src.c_str(), "truncated"});
  }
  // Trailing garbage.
  expect_refused([&] { io::parse_binding(good + "xx", src); }, ErrorCategory::bad_input, {src.c_str(), "corrupt"});
  // A flipped byte anywhere is refused: magic, version, counts, hashes, names, indices, floats,
  // the checksum itself.
  for (std::size_t at = 0; at < good.size(); at += 7) {
    std::string bad = good;
    bad[at] = static_cast<char>(bad[at] ^ 0x5a);
    try {
      io::parse_binding(bad, src);
      ADD_FAILURE() << "flipped byte " << at << " accepted";
    } catch (const Error& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind(src + ": ", 0), 0u) << what;
      if (at < 8) {
        EXPECT_NE(what.find("not a sweep binding file"), std::string::npos) << what;
      } else if (at < 12) {
        EXPECT_NE(what.find("version"), std::string::npos) << what;
      } else if (at >= 40 && at < 48) {
        EXPECT_TRUE(what.find("truncated") != std::string::npos || what.find("corrupt") != std::string::npos) << what;
      } else {
        EXPECT_NE(what.find("corrupt binding: checksum mismatch"), std::string::npos) << what;
      }
    }
  }
  // A newer format version is "unsupported", not "corrupt".
  std::string newer = good;
  newer[8] = 3;
  expect_refused([&] { io::parse_binding(newer, src); }, ErrorCategory::unsupported,
                 {"binding format version 3 is not supported"});
  // Format 1 hashed the rig's JSON text: refused with what to do, whatever else it holds.
  std::string older = good;
  older[8] = 1;
  expect_refused([&] { io::parse_binding(older, src); }, ErrorCategory::bad_input,
                 {src.c_str(), "binding format 1", "run sweep-bind again"});
  // A missing file.
  expect_refused([&] { io::read_binding(d.dir / "missing.bind"); }, ErrorCategory::bad_input, {"missing.bind"});
}

TEST(BindingFile, TableConsistencyIsCheckedEvenWhenTheChecksumHolds) {
  const Mesh mesh = tube::make_tube(straight_tube_params());
  const Rig rig = rig_of({straight_sweep("a"), straight_sweep("b")});
  Binding b = bind::bind_rig(rig, mesh);
  b.sweeps[1].vertices = {3};  // also bound by "a"
  for (auto* c : {&b.sweeps[1].t, &b.sweeps[1].theta, &b.sweeps[1].s, &b.sweeps[1].z, &b.sweeps[1].weight}) {
    *c = {0.5f};
  }
  expect_refused([&] { io::parse_binding(io::binding_bytes(b), "x.bind"); }, ErrorCategory::bad_input,
                 {"x.bind: corrupt binding: vertex 3 is bound by more"});
  Binding c = bind::bind_rig(rig, mesh);
  c.sweeps[0].vertices[10] = 5000;
  expect_refused([&] { io::parse_binding(io::binding_bytes(c), "x.bind"); }, ErrorCategory::bad_input,
                 {"sweep 0 ('a'), entry 10", "out of range"});
  Binding w = bind::bind_rig(rig, mesh);
  w.sweeps[0].weight[7] = 1.5f;
  expect_refused([&] { io::parse_binding(io::binding_bytes(w), "x.bind"); }, ErrorCategory::bad_input,
                 {"entry 7", "weight must be in [0, 1]"});
}

// The program, as a black box.
TEST(BindTool, WritesTheBindingBesideTheRigAndAReport) {
  const OnDisk d = write_tube_rig("tool");
  const fs::path report = d.dir / "report.json";
  const ToolRun r = run_bind_tool(quoted(d.rig_path) + " --report " + quoted(report), d.dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  EXPECT_NE(r.out.find("tail: 986 vertices bound"), std::string::npos) << r.out;
  const fs::path bind_path = d.dir / "tube.bind";
  ASSERT_TRUE(fs::exists(bind_path));
  const Binding b = io::load_binding(bind_path, d.mesh, d.rig);
  EXPECT_EQ(io::binding_bytes(b), io::binding_bytes(bind::bind_rig(d.rig, d.mesh)));
  const auto doc = nlohmann::json::parse(io::read_file(report));
  EXPECT_EQ(doc["format"], "sweep-bind-report");
  ASSERT_EQ(doc["sweeps"].size(), 1u);
  EXPECT_EQ(doc["sweeps"][0]["name"], "tail");
  EXPECT_EQ(doc["sweeps"][0]["bound_vertex_count"], 986);
  EXPECT_LT(doc["sweeps"][0]["rest_max_error"].get<double>(), 1e-5);
  EXPECT_GE(doc["seconds"]["bind"].get<double>(), 0);
  // -o, and the same bytes again.
  const ToolRun again = run_bind_tool(quoted(d.rig_path) + " -q -o " + quoted(d.dir / "b2.bind"), d.dir);
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(again.out, "");
  EXPECT_EQ(io::read_file(d.dir / "b2.bind"), io::read_file(bind_path));
  // --check accepts the matching binding.
  const ToolRun check = run_bind_tool(quoted(d.rig_path) + " --check " + quoted(bind_path), d.dir);
  EXPECT_EQ(check.exit_code, 0) << check.err;
  EXPECT_NE(check.out.find("matches"), std::string::npos) << check.out;
  // --version and a usage error.
  const ToolRun version = run_bind_tool("--version", d.dir);
  EXPECT_EQ(version.exit_code, 0);
  EXPECT_NE(version.out.find("sweep-bind"), std::string::npos);
  EXPECT_NE(version.out.find("binding format 2"), std::string::npos);
  const ToolRun usage = run_bind_tool(quoted(d.rig_path) + " --blend -3", d.dir);
  EXPECT_EQ(usage.exit_code, 1);
  EXPECT_NE(usage.err.find("error: "), std::string::npos);
  EXPECT_NE(usage.err.find("--blend"), std::string::npos) << usage.err;
}

TEST(BindTool, RefusesStaleAndBrokenBindingsWithExitCode2) {
  const OnDisk d = write_tube_rig("tool-stale");
  const fs::path bind_path = d.dir / "tube.bind";
  ASSERT_EQ(run_bind_tool(quoted(d.rig_path) + " -q", d.dir).exit_code, 0);
  const std::string good = io::read_file(bind_path);
  const std::string mesh_text = io::read_file(d.mesh_path);
  const std::string rig_text = io::read_file(d.rig_path);
  auto check = [&](const std::string& expect) {
    const ToolRun r = run_bind_tool(quoted(d.rig_path) + " --check " + quoted(bind_path), d.dir);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(r.err.rfind("error: " + bind_path.string() + ": ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find(expect), std::string::npos) << r.err << "\nexpected: " << expect;
    EXPECT_EQ(r.out, "");
  };

  // The mesh edited: one vertex moved, then vertices removed.
  Mesh edited = d.mesh;
  edited.positions[7].x() += 0.001;
  assets::write_mesh(d.mesh_path, edited);
  check(
      "made for a mesh with other vertex positions (the mesh changed since binding); run "
      "sweep-bind again");
  assets::write_mesh(d.mesh_path, tube::make_tube([] {
                       auto p = straight_tube_params();
                       p.rings = 4;
                       return p;
                     }()));
  check("made for a mesh with 986 vertices, this mesh has 98; run sweep-bind again");
  io::write_file_atomically(d.mesh_path, mesh_text);

  // The rig edited: a radius.
  Rig edited_rig = d.rig;
  edited_rig.sweeps[0].rest.radii[9] = 0.105;
  io::write_rig(d.rig_path, edited_rig);
  check(
      "was made for another version of the rig (sweeps changed since binding); run sweep-bind "
      "again");
  io::write_file_atomically(d.rig_path, rig_text);

  // The binding truncated, then one byte flipped in the payload, then its magic.
  io::write_file_atomically(bind_path, good.substr(0, good.size() - 100));
  check("truncated binding");
  std::string flipped = good;
  flipped[good.size() / 2] = static_cast<char>(flipped[good.size() / 2] ^ 1);
  io::write_file_atomically(bind_path, flipped);
  check("corrupt binding: checksum mismatch");
  std::string not_ours = good;
  not_ours[0] = 'X';
  io::write_file_atomically(bind_path, not_ours);
  check("not a sweep binding file");

  // And the original is accepted again.
  io::write_file_atomically(bind_path, good);
  EXPECT_EQ(run_bind_tool(quoted(d.rig_path) + " --check " + quoted(bind_path), d.dir).exit_code, 0);
}

TEST(BindTool, MissingRigOrMeshIsBadInputAndWritesNothing) {
  const OnDisk d = write_tube_rig("tool-missing");
  const ToolRun no_rig = run_bind_tool(quoted(d.dir / "nope.json"), d.dir);
  EXPECT_EQ(no_rig.exit_code, 2);
  EXPECT_NE(no_rig.err.find("nope.json"), std::string::npos) << no_rig.err;
  fs::remove(d.mesh_path);
  const ToolRun no_mesh = run_bind_tool(quoted(d.rig_path), d.dir);
  EXPECT_EQ(no_mesh.exit_code, 2);
  EXPECT_NE(no_mesh.err.find("tube.obj"), std::string::npos) << no_mesh.err;
  EXPECT_FALSE(fs::exists(d.dir / "tube.bind"));
}

}  // namespace
}  // namespace sweep::test
