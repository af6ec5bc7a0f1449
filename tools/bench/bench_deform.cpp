// Deformation: the fast path at several stations per span and the exact path, against a plain
// 4-bone linear-blend-skinning loop and the memory-bandwidth floor, measured in the same run on the
// diplodocus (tail + neck) and on a dense generated tube of about 1,000,000 vertices.
//
// Error measure: the largest distance between a vertex from the fast path (float) and the same
// vertex from the exact per-vertex path (deform_point, double), in mesh units and relative to the
// sweep's length. Reference: deform_point on the same deformed shape and the same binding.
// Time: median wall time of a frame's deformation, per bound vertex; "loop" is the per-vertex loop
// alone, "total" adds the per-frame station table (tabulate).
#include <random>

#include "bench_common.h"
#include "sweep/bind/deform.h"
#include "sweep/bind/fast_deform.h"
#include "sweep/core/elastic_sweep.h"

namespace sweep::bench {
namespace {

using bind::FastDeformer;
using bind::Vec3f;

// A pose with bending, twisting and radial change along the whole sweep (the paper's Fig. 4 kinds).
void pose(ElasticSweep& s, double amount) {
  const int k = s.rest().section_count();
  const int n = s.rest().radial_count;
  const double len = s.rest().length();
  for (int i = 1; i < k; ++i) {
    s.set_section_pose(i, Vec3(0.002 * len * amount, 0, 0), Vec3(0.08 * amount, 0.04 * amount, 0.06 * amount));
    for (int j = 0; j < n; j += 3) s.set_radial_offset(i, j, 0.15 * amount * s.rest().radius_sample(i, j));
  }
}

struct Row {
  std::string mesh;
  std::size_t vertices = 0;
  std::string method;
  int threads = 1;
  double loop_ns = 0;   // per vertex, loop alone
  double total_ns = 0;  // per vertex, with the station table
  double tabulate_us = 0;
  double max_error = -1;      // mesh units; -1 = not applicable
  double max_error_rel = -1;  // over the sweep's length
  double floor_ns = 0;        // the floor measured with the same threads
};

// The memory-bandwidth floor for the fast loop's traffic: reads 24 bytes (u, w, a, b, z and a
// vertex index) and writes 12 bytes a vertex, in order, with no arithmetic to speak of.
struct Floor {
  std::vector<float> a, b, c, d, e;
  std::vector<std::uint32_t> idx;
  std::vector<float> out;
  explicit Floor(std::size_t n) : a(n, 1), b(n, 2), c(n, 3), d(n, 4), e(n, 5), idx(n, 6), out(3 * n) {}
  void run() {
    const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(a.size());
    float* o = out.data();
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t i = 0; i < n; ++i) {
      o[3 * i] = a[i] + b[i];
      o[3 * i + 1] = c[i] + d[i];
      o[3 * i + 2] = e[i] + static_cast<float>(idx[i]);
    }
  }
};

// Plain 4-bone linear blend skinning, float, structure of arrays: what a user would pick instead.
// Per vertex: 4 bone indices, 4 weights, the rest position; out = Σ w_k (B_k p).
struct Lbs {
  static constexpr int kBones = 64;
  std::vector<float> bones;  // 12 floats a bone (3×4 row-major)
  std::vector<std::uint16_t> i0, i1, i2, i3;
  std::vector<float> w0, w1, w2, w3, px, py, pz;
  std::vector<float> out;
  explicit Lbs(std::size_t n) : bones(12 * kBones), out(3 * n) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1, 1);
    for (float& b : bones) b = u(rng);
    for (auto* v : {&i0, &i1, &i2, &i3}) v->resize(n);
    for (auto* v : {&w0, &w1, &w2, &w3, &px, &py, &pz}) v->resize(n);
    for (std::size_t k = 0; k < n; ++k) {
      const int base = static_cast<int>(k * kBones / n);
      i0[k] = static_cast<std::uint16_t>(base);
      i1[k] = static_cast<std::uint16_t>(std::min(base + 1, kBones - 1));
      i2[k] = static_cast<std::uint16_t>(std::max(base - 1, 0));
      i3[k] = static_cast<std::uint16_t>(std::min(base + 2, kBones - 1));
      float w[4] = {std::abs(u(rng)) + 0.1f, std::abs(u(rng)), std::abs(u(rng)), std::abs(u(rng))};
      const float sum = w[0] + w[1] + w[2] + w[3];
      w0[k] = w[0] / sum;
      w1[k] = w[1] / sum;
      w2[k] = w[2] / sum;
      w3[k] = w[3] / sum;
      px[k] = u(rng);
      py[k] = u(rng);
      pz[k] = u(rng);
    }
  }
  void run() {
    const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(px.size());
    const float* B = bones.data();
    float* o = out.data();
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t k = 0; k < n; ++k) {
      const float* b0 = B + 12 * i0[k];
      const float* b1 = B + 12 * i1[k];
      const float* b2 = B + 12 * i2[k];
      const float* b3 = B + 12 * i3[k];
      float m[12];
      for (int c = 0; c < 12; ++c) m[c] = w0[k] * b0[c] + w1[k] * b1[c] + w2[k] * b2[c] + w3[k] * b3[c];
      const float x = px[k], y = py[k], z = pz[k];
      o[3 * k] = m[0] * x + m[1] * y + m[2] * z + m[3];
      o[3 * k + 1] = m[4] * x + m[5] * y + m[6] * z + m[7];
      o[3 * k + 2] = m[8] * x + m[9] * y + m[10] * z + m[11];
    }
  }
};

struct Case {
  std::string name;
  RealRig rig;
  std::vector<ElasticSweep> bodies;
};

void run_case(Case& c, const std::vector<int>& stations, const std::vector<int>& threads, int runs, int exact_runs,
              std::vector<Row>& rows) {
  const Mesh& mesh = c.rig.mesh;
  const std::size_t nv = mesh.vertex_count();
  std::size_t bound = 0;
  for (const auto& s : c.rig.binding.sweeps) bound += s.size();
  std::vector<Vec3f> rest(nv);
  for (std::size_t v = 0; v < nv; ++v) rest[v] = mesh.positions[v].cast<float>();
  std::vector<const SweepShape*> shapes;
  for (const auto& b : c.bodies) shapes.push_back(&b.deformed());

  // The reference: the exact path, in double.
  std::vector<Vec3> exact(nv);
  bind::deform_exact(c.rig.binding, shapes, mesh.positions, exact);
  double length = 0;
  for (const auto& b : c.bodies) length = std::max(length, b.rest().length());

  Floor floor(bound);
  Lbs lbs(bound);
  for (int th : threads) {
    omp_set_num_threads(th);
    const double floor_ns = 1e9 * median_seconds(runs, [&] { floor.run(); }) / bound;
    rows.push_back({c.name, bound, "floor (copy, 36 B/vertex)", th, floor_ns, floor_ns, 0, -1, -1, floor_ns});
    const double lbs_ns = 1e9 * median_seconds(runs, [&] { lbs.run(); }) / bound;
    rows.push_back({c.name, bound, "LBS 4 bones", th, lbs_ns, lbs_ns, 0, -1, -1, floor_ns});
    for (int st : stations) {
      std::vector<std::unique_ptr<FastDeformer>> fast;
      for (std::size_t i = 0; i < c.bodies.size(); ++i) {
        fast.push_back(std::make_unique<FastDeformer>(c.bodies[i].rest(), c.rig.binding.sweeps[i], rest, st));
      }
      std::vector<Vec3f> out = rest;
      for (std::size_t i = 0; i < fast.size(); ++i) fast[i]->tabulate(c.bodies[i].deformed());
      const double loop = median_seconds(runs, [&] {
        for (auto& f : fast) f->deform_vertices(out);
      });
      const double tab = median_seconds(runs, [&] {
        for (std::size_t i = 0; i < fast.size(); ++i) fast[i]->tabulate(c.bodies[i].deformed());
      });
      const double total = median_seconds(runs, [&] {
        for (std::size_t i = 0; i < fast.size(); ++i) fast[i]->deform(c.bodies[i].deformed(), out);
      });
      double err = 0;
      for (const auto& s : c.rig.binding.sweeps) {
        for (std::uint32_t v : s.vertices) err = std::max(err, (out[v].cast<double>() - exact[v]).norm());
      }
      rows.push_back({c.name, bound, fmt("fast %d stations/span", st), th, 1e9 * loop / bound, 1e9 * total / bound,
                      1e6 * tab, err, err / length, floor_ns});
    }
    std::vector<Vec3> out(nv);
    const double ex =
        median_seconds(exact_runs, [&] { bind::deform_exact(c.rig.binding, shapes, mesh.positions, out); });
    rows.push_back(
        {c.name, bound, "exact (deform_point, double)", th, 1e9 * ex / bound, 1e9 * ex / bound, 0, 0, 0, floor_ns});
  }
}

}  // namespace
}  // namespace sweep::bench

int main(int argc, char** argv) {
  using namespace sweep;
  using namespace sweep::bench;
  const Args args = parse_args(argc, argv);
  const int max_threads = omp_get_max_threads();
  std::vector<int> threads{1};
  if (max_threads >= 2) threads.push_back(2);
  std::vector<Row> rows;

  {
    Case dino{"diplodocus", diplodocus_rig(), {}};
    for (const auto& def : dino.rig.rig.sweeps) dino.bodies.emplace_back(def);
    for (auto& b : dino.bodies) pose(b, 1.0);
    run_case(dino, {1, 2, 4, 8, 16, 32}, threads, args.quick ? 101 : 401, args.quick ? 5 : 21, rows);
  }
  // The dense tube twice: in ring order (as generated; each block is written straight into the
  // mesh) and with its vertices numbered at random (no order to exploit: the worst case).
  omp_set_num_threads(max_threads);
  const RealRig ring_order = dense_tube_rig(1000000);
  for (const bool shuffle : {false, true}) {
    Case tube{shuffle ? "tube 1M random vertex order" : "tube 1M",
              shuffle ? shuffled_vertex_order(ring_order, 5) : ring_order,
              {}};
    for (const auto& def : tube.rig.rig.sweeps) tube.bodies.emplace_back(def);
    for (auto& b : tube.bodies) pose(b, 1.0);
    omp_set_num_threads(max_threads);
    run_case(tube, args.quick ? std::vector<int>{2, 8} : std::vector<int>{1, 2, 4, 8, 16}, threads, args.quick ? 9 : 21,
             shuffle ? 1 : 3, rows);
  }

  std::string csv =
      "mesh,bound_vertices,method,threads,loop_ns_per_vertex,total_ns_per_vertex,tabulate_us,max_"
      "error,"
      "max_error_over_length,floor_ns_per_vertex,loop_over_floor\n";
  std::string md =
      "| mesh | bound vertices | method | threads | loop ns/vertex | × floor | total ns/vertex "
      "(with table) | "
      "table µs | max error vs exact (mesh units) | max error / length "
      "|\n|---|---|---|---|---|---|---|---|---|---|\n";
  for (const Row& r : rows) {
    csv += fmt("%s,%zu,%s,%d,%.4g,%.4g,%.4g,%.4g,%.4g,%.4g,%.4g\n", r.mesh.c_str(), r.vertices, r.method.c_str(),
               r.threads, r.loop_ns, r.total_ns, r.tabulate_us, r.max_error, r.max_error_rel, r.floor_ns,
               r.loop_ns / r.floor_ns);
    const std::string e = r.max_error < 0 ? "—" : fmt("%.2e", r.max_error);
    const std::string er = r.max_error_rel < 0 ? "—" : fmt("%.2e", r.max_error_rel);
    md += fmt("| %s | %zu | %s | %d | %.3g | %.2f | %.3g | %.3g | %s | %s |\n", r.mesh.c_str(), r.vertices,
              r.method.c_str(), r.threads, r.loop_ns, r.loop_ns / r.floor_ns, r.total_ns, r.tabulate_us, e.c_str(),
              er.c_str());
  }
  write_text(args.out / "deform.csv", csv);
  write_text(args.out / "deform.md", md);
  std::fputs(md.c_str(), stdout);
  return 0;
}
