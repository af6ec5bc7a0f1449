#pragma once
// Shared pieces of the benchmark programs (tools/bench/run-benchmarks.sh runs them all): wall-clock
// timing and medians, the machine stamp, CSV and Markdown output in the C locale, and the two real
// rigs every curve uses — CGAL's diplodocus, tail and neck fitted and bound here, and a dense
// generated tube (tools/sweep-tube) with a hand-built sweep bound by the locator.
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "diplodocus_seeds.h"
#include "sweep/assets/mesh_io.h"
#include "sweep/bind/bind.h"
#include "sweep/core/locate.h"
#include "sweep/core/rig.h"
#include "sweep/fit/fit.h"
#include "tube.h"

namespace sweep::bench {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

inline double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

// Median wall time of `runs` calls of f, seconds (one untimed warm-up call first).
template <class F>
double median_seconds(int runs, F&& f) {
  f();
  std::vector<double> t;
  t.reserve(runs);
  for (int r = 0; r < runs; ++r) {
    const auto t0 = Clock::now();
    f();
    t.push_back(seconds_since(t0));
  }
  return median(t);
}

// Command line shared by every benchmark: --quick, --out DIR (CSV and Markdown fragments).
struct Args {
  bool quick = false;
  fs::path out = "tools/bench/results";
};
inline Args parse_args(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    const std::string s = argv[i];
    if (s == "--quick") {
      a.quick = true;
    } else if (s == "--out" && i + 1 < argc) {
      a.out = argv[++i];
    } else {
      std::fprintf(stderr, "usage: %s [--quick] [--out DIR]\n", argv[0]);
      std::exit(1);
    }
  }
  fs::create_directories(a.out);
  return a;
}

// printf into a std::string (the C locale is the default of a C++ program that never sets one).
template <class... T>
std::string fmt(const char* f, T... args) {
  const int n = std::snprintf(nullptr, 0, f, args...);
  std::string s(static_cast<std::size_t>(n), '\0');
  std::snprintf(s.data(), s.size() + 1, f, args...);
  return s;
}

inline void write_text(const fs::path& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary);
  f << text;
  if (!f) throw std::runtime_error("cannot write " + path.string());
}

// ---- the diplodocus ----------------------------------------------------------------------------

inline fs::path source_dir() {
  return fs::path(SWEEP_SOURCE_DIR);
}
inline fs::path diplodocus_path() {
  return source_dir() / "meshes/cgal/diplodocus.off";
}

using test::Seeds;  // and test::kDiplodocusTail, test::kDiplodocusNeck (diplodocus_seeds.h)

struct RealRig {
  Mesh mesh;
  Rig rig;
  bind::Binding binding;
};

inline RealRig diplodocus_rig(int sections = 16, int radial = 16) {
  if (!fs::exists(diplodocus_path())) {
    throw std::runtime_error(diplodocus_path().string() + " is absent: run tools/setup-deps.sh");
  }
  RealRig r;
  r.mesh = assets::read_mesh(diplodocus_path());
  const fit::SweepFitter fitter(r.mesh);
  for (const Seeds& s : {test::kDiplodocusTail, test::kDiplodocusNeck}) {
    fit::FitOptions o;
    o.name = s.name;
    o.root = s.root;
    o.tip = s.tip;
    o.sections = sections;
    o.radial = radial;
    o.measure_error = false;
    r.rig.sweeps.push_back(fitter.fit(o).sweep);
  }
  r.binding = bind::bind_rig(r.rig, r.mesh);
  return r;
}

// ---- a dense generated tube --------------------------------------------------------------------

// The sweep of a sweep-tube surface from its exact parametrisation: K sections evenly spaced in arc
// length, frames (u, v, tangent), n radii at θ_j.
inline SweepShape tube_sweep(const tube::TubeParams& p, int sections, int radial) {
  SweepShape s;
  s.radial_count = radial;
  for (int i = 0; i < sections; ++i) {
    const double t = p.length * i / (sections - 1);
    const tube::AxisFrame f = tube::tube_frame(p, t);
    Mat3 m;
    m << f.u, f.v, f.tangent;
    s.t.push_back(t);
    s.frames.push_back({Quat(m).normalized(), f.point});
    for (int j = 0; j < radial; ++j) s.radii.push_back(tube::tube_radius(p, 2 * std::numbers::pi * j / radial, t));
  }
  return s;
}

// Every vertex of `mesh` bound to `shape` by the locator (as sweep-bind does for a seedless rig,
// without its part selection: the whole mesh is the tube), in parallel.
inline bind::SweepBinding locate_all(const SweepShape& shape, const Mesh& mesh) {
  const std::size_t nv = mesh.vertex_count();
  bind::SweepBinding b;
  b.name = "tube";
  b.vertices.resize(nv);
  b.t.resize(nv);
  b.theta.resize(nv);
  b.s.resize(nv);
  b.z.resize(nv);
  b.weight.assign(nv, 1.0f);
  const SweepLocator locator(shape);
#pragma omp parallel for schedule(dynamic, 1024)
  for (std::ptrdiff_t v = 0; v < static_cast<std::ptrdiff_t>(nv); ++v) {
    const SweepCoords c = locator.locate(mesh.positions[v]);
    b.vertices[v] = static_cast<std::uint32_t>(v);
    b.t[v] = static_cast<float>(c.t);
    b.theta[v] = static_cast<float>(c.theta);
    b.s[v] = static_cast<float>(c.s);
    b.z[v] = static_cast<float>(c.z);
  }
  return b;
}

// A bent, tapered, lobed tube of about `vertices` vertices (rings × 500 segments, capped), its
// K = 16, n = 16 sweep, and the binding of every vertex.
// The same rig in material mode: every part given the diplodocus's flesh (tests/diplodocus_seeds.h).
inline RealRig in_material(RealRig rig) {
  for (SweepDef& d : rig.rig.sweeps) {
    d.material = test::diplodocus_flesh();
    d.section_materials.assign(d.rest.section_count(), *d.material);
  }
  return rig;
}

inline RealRig dense_tube_rig(std::size_t vertices) {
  tube::TubeParams p;
  p.length = 1.0;
  p.radius = 0.08;
  p.taper = 0.4;
  p.bend = 1.2;
  p.shape = tube::CrossSection::lobed;
  p.lobes = 5;
  p.lobe_amplitude = 0.15;
  p.segments = 500;
  p.rings = static_cast<int>(std::max<std::size_t>(2, vertices / p.segments));
  RealRig r;
  r.mesh = tube::make_tube(p);
  SweepDef def = make_sweep("tube", tube_sweep(p, 16, 16));
  r.rig.sweeps.push_back(def);
  r.binding.vertex_count = r.mesh.vertex_count();
  r.binding.sweeps.push_back(locate_all(def.rest, r.mesh));
  return r;
}

// The same rig with the mesh's vertices numbered at random (faces and binding follow): the
// vertex order of a mesh that keeps no ring order, the fast path's worst case for memory.
inline RealRig shuffled_vertex_order(const RealRig& in, unsigned seed) {
  const std::size_t nv = in.mesh.vertex_count();
  std::vector<std::uint32_t> number(nv);
  for (std::size_t v = 0; v < nv; ++v) number[v] = static_cast<std::uint32_t>(v);
  std::shuffle(number.begin(), number.end(), std::mt19937(seed));
  RealRig r;
  r.rig = in.rig;
  r.mesh = in.mesh;
  for (std::size_t v = 0; v < nv; ++v) r.mesh.positions[number[v]] = in.mesh.positions[v];
  for (std::uint32_t& f : r.mesh.face_vertices) f = number[f];
  r.binding.vertex_count = nv;
  for (const SweepDef& def : r.rig.sweeps) r.binding.sweeps.push_back(locate_all(def.rest, r.mesh));
  return r;
}

// ---- the machine -------------------------------------------------------------------------------

inline std::string cpu_model() {
  std::ifstream f("/proc/cpuinfo");
  std::string line;
  while (std::getline(f, line)) {
    if (line.rfind("model name", 0) == 0) {
      const auto c = line.find(':');
      if (c != std::string::npos) return line.substr(line.find_first_not_of(' ', c + 1));
    }
  }
  return "unknown CPU";
}

}  // namespace sweep::bench
