#include "sweep/fit/rings.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "sweep/core/text.h"

namespace sweep::fit {
namespace {

// Loops shorter than this fraction of the followed ring are specks of a jagged level set, not the
// ring's continuation.
constexpr double kSpeckFraction = 0.25;
constexpr double kNearRadii = 3;
constexpr double kMaxLevels = 4096;
// The junction: the last ring no more than this share wider than the tube over the few radii
// (kTubeWindowRadii) before the knee.
constexpr double kFlareShare = 0.1;
constexpr double kTubeWindowRadii = 3;

// The loop of this level that continues the previous ring: the one with the nearest centroid among
// loops that are not specks; the longest one on the first level.
const LevelLoop* continuing(const std::vector<LevelLoop>& loops, const Ring* previous, double previous_length) {
  if (loops.empty()) return nullptr;
  if (!previous) return &loops[0];
  const LevelLoop* best = nullptr;
  double best_d = std::numeric_limits<double>::infinity();
  for (const LevelLoop& l : loops) {
    if (l.length < kSpeckFraction * previous_length && &l != &loops[0]) continue;
    // Near loops (within a few radii) compete by length: where a level set holds the part's ring
    // and a branch's (a second toe, a horn), the part's own ring is the longer.
    const double d = (l.centroid - previous->centroid).norm();
    const double reach = kNearRadii * previous->radius;
    if (best && d <= reach && best_d <= reach) {
      if (l.length > best->length) best = &l, best_d = d;
      continue;
    }
    if (d < best_d) {
      best_d = d;
      best = &l;
    }
  }
  return best;
}

// Each ring's share of the mesh's surface nearer to the tip than its level (a vertex holds a third
// of each of its triangles' area).
void fill_area_shares(const Mesh& mesh, const Topology& topology, const std::vector<double>& distance,
                      std::vector<Ring>& rings) {
  std::vector<double> area(mesh.vertex_count(), 0.0);
  double total = 0;
  const std::vector<std::uint32_t> tris = mesh.triangles();
  for (std::size_t t = 0; t + 2 < tris.size(); t += 3) {
    const Vec3& a = mesh.positions[tris[t]];
    const double third = (mesh.positions[tris[t + 1]] - a).cross(mesh.positions[tris[t + 2]] - a).norm() / 6;
    for (std::size_t k = 0; k < 3; ++k) area[tris[t + k]] += third;
    total += 3 * third;
  }
  if (!(total > 0)) return;
  std::vector<std::pair<double, double>> by_distance;  // (distance from the tip, area)
  by_distance.reserve(area.size());
  for (std::size_t v = 0; v < area.size(); ++v) {
    const double d = distance[topology.weld[v]];
    if (std::isfinite(d) && area[v] > 0) by_distance.emplace_back(d, area[v]);
  }
  std::sort(by_distance.begin(), by_distance.end());
  std::size_t next = 0;
  double within = 0;
  for (Ring& ring : rings) {  // levels in increasing distance
    while (next < by_distance.size() && by_distance[next].first <= ring.distance) within += by_distance[next++].second;
    ring.area_share = within / total;
  }
}

}  // namespace

double median_edge_length(const Mesh& mesh, const Topology& topology) {
  std::vector<double> lengths;
  lengths.reserve(topology.adjacency.neighbours.size() / 2);
  for (std::uint32_t v = 0; v + 1 < topology.adjacency.offsets.size(); ++v) {
    for (const std::uint32_t w : topology.adjacency.of(v)) {
      if (w > v) lengths.push_back((mesh.positions[w] - mesh.positions[v]).norm());
    }
  }
  if (lengths.empty()) return 0;
  auto mid = lengths.begin() + static_cast<std::ptrdiff_t>(lengths.size() / 2);
  std::nth_element(lengths.begin(), mid, lengths.end());
  return *mid;
}

std::uint32_t climb(const Topology& topology, const std::vector<double>& field, std::uint32_t start) {
  std::uint32_t v = topology.weld[start];
  for (;;) {
    std::uint32_t best = v;
    for (const std::uint32_t w : topology.adjacency.of(v)) {
      if (std::isfinite(field[w]) && field[w] > field[best]) best = w;
    }
    if (best == v) return v;
    v = best;
  }
}

RingTrace trace_rings(const Mesh& mesh, const Topology& topology, const std::vector<double>& distance,
                      std::uint32_t tip_vertex, double stop_distance, bool find_junction, const RingOptions& o) {
  RingTrace trace;
  trace.tip_vertex = topology.weld[tip_vertex];
  double farthest = 0;
  for (const double x : distance) {
    if (std::isfinite(x)) farthest = std::max(farthest, x);
  }
  const double reach = std::min(farthest, stop_distance);
  // At most kMaxLevels rings: a stray vertex far from the rest (bad data) would otherwise ask
  // for millions of levels at the edges' spacing (fit_off fuzz find, kept).
  const double spacing = std::max(o.spacing_edges * median_edge_length(mesh, topology), reach / kMaxLevels);
  if (!(spacing > 0) || !(farthest > 0)) return trace;
  const LevelSets levels(mesh, topology, distance, spacing, reach);

  double previous_length = 0;
  for (int k = 0; k < levels.level_count(); ++k) {
    const std::vector<LevelLoop> loops = levels.loops(k);
    const Ring* previous = trace.rings.empty() ? nullptr : &trace.rings.back();
    const LevelLoop* loop = continuing(loops, previous, previous_length);
    if (!loop) break;
    Ring ring{levels.level(k), loop->centroid, loop->radius(), 0, loop->closed};
    for (const LevelLoop& other : loops) {
      ring.split |= &other != loop && other.length >= kSpeckFraction * loop->length;
    }
    // Growth over the last local radius of distance (from the tip itself, radius 0, at first).
    const double window = std::max(ring.radius, 2 * spacing);
    double back_distance = 0, back_radius = 0;
    for (auto it = trace.rings.rbegin(); it != trace.rings.rend(); ++it) {
      if (ring.distance - it->distance >= window) {
        back_distance = it->distance;
        back_radius = it->radius;
        break;
      }
    }
    ring.growth = (ring.radius - back_radius) / (ring.distance - back_distance);
    previous_length = loop->length;
    trace.rings.push_back(ring);
  }
  if (trace.rings.empty()) return trace;
  trace.junction = static_cast<int>(trace.rings.size()) - 1;
  trace.junction_reason = "the rings reached the far end of the surface";
  if (find_junction) {
    fill_area_shares(mesh, topology, distance, trace.rings);
    locate_junction(trace, o);
  }
  return trace;
}

void locate_junction(RingTrace& trace, const RingOptions& o) {
  const std::vector<Ring>& rings = trace.rings;
  const int n = static_cast<int>(rings.size());
  const auto at = [&](int i) -> const Ring& { return rings[static_cast<std::size_t>(i)]; };
  int k = 0, gentle = -1;  // (the first gentle rise into a split that would be the body)
  std::string gentle_reason;
  while (k < n && at(k).growth >= o.settled_growth) ++k;  // the tip's cap
  while (k < n) {
    if (at(k).growth <= o.settled_growth) {
      ++k;
      continue;
    }
    // A rise (steep from its first ring past junction_growth, if any): it began at the last ring
    // that grew by at most knee_growth, and peaks where the rings stop growing.
    int steep = -1;
    for (int i = k; i < n && at(i).growth > 0 && steep < 0; ++i) {
      if (at(i).growth > o.junction_growth) steep = i;
    }
    const int start = steep >= 0 ? steep : k;
    int knee = start;
    while (knee > 0 && at(knee).growth > o.knee_growth) --knee;
    int peak = start;
    for (int i = start; i < n && at(i).growth > 0; ++i) {  // windowed growth: smoother than radii
      if (at(i).radius > at(peak).radius) peak = i;
    }
    // A blob at the end (a head, a hoof, a hand) narrows again into the part beyond it; the
    // body does not: look for rings back near the knee's size within a few peak radii.
    bool narrows = false;
    if (at(knee).distance <= o.blob_reach * at(knee).radius)
      for (int i = peak + 1; i < n && at(i).distance - at(peak).distance <= o.blob_radii * at(peak).radius; ++i) {
        if (at(i).split) break;  // branching into other parts: the body
        if (at(i).radius <= o.blob_narrowing * at(peak).radius) {
          narrows = true;
          break;
        }
      }
    // Where the level set first splits (into the body's other parts), up to a few peak radii on.
    int split = -1;
    for (int i = start; i < n && at(i).distance - at(peak).distance <= o.blob_radii * at(peak).radius; ++i) {
      if (at(i).split) {
        split = i;
        break;
      }
    }
    // Growth is measured over a radius of distance, so the knee lags into the flare: back to
    // the last ring still within kFlareShare of the tube's own size just before it.
    std::vector<double> before;
    for (int i = knee; i >= 0 && at(knee).distance - at(i).distance <= kTubeWindowRadii * at(knee).radius; --i) {
      if (at(knee).distance - at(i).distance >= at(knee).radius) before.push_back(at(i).radius);
    }
    double tube = at(knee).radius;
    if (!before.empty()) {
      std::nth_element(before.begin(), before.begin() + static_cast<std::ptrdiff_t>(before.size() / 2), before.end());
      tube = before[before.size() / 2];
      while (knee > 0 && at(knee).radius > (1 + kFlareShare) * tube) --knee;
    }
    // A gentle rise is where the part meets the body only where the rings widen far before the
    // level set splits into the body's other parts, after a part long against that width (the body
    // comes after a long part); kept aside (the first one), the trace goes on: it is the junction
    // only if the part up to the next jump would hold the body (below).
    if (steep < 0) {
      const int widest = split - 1;
      if (gentle < 0 && split > start && at(widest).radius >= o.gentle_widening * tube &&
          at(knee).distance > o.blob_reach * at(widest).radius) {
        gentle = knee;
        gentle_reason = "the ring size widens from " + format_number(at(knee).radius) + " to " +
                        format_number(at(widest).radius) + " from distance " + format_number(at(start).distance) +
                        " from the tip, then the rings split (the body)";
      }
    } else if (!narrows) {
      trace.junction = knee;
      trace.junction_reason = "the ring size jumps from " + format_number(at(knee).radius) + " to " +
                              format_number(at(peak).radius) + " at distance " + format_number(at(start).distance) +
                              " from the tip (the body)";
      break;
    }
    k = peak + 1;
  }
  if (gentle >= 0 && trace.junction >= 0 && at(trace.junction).area_share > o.body_area_share) {
    trace.junction = gentle;
    trace.junction_reason = gentle_reason;
  }
}

}  // namespace sweep::fit
