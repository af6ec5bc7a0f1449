#include "sweep/fit/discover.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <string_view>

#include "sweep/core/text.h"
#include "sweep/fit/geodesic.h"

namespace sweep::fit {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// Names: a part pointing down this much that reaches this near the lowest point is a leg.
constexpr double kDownCos = 0.5;
constexpr double kGroundShare = 0.05;
// ... or that points steeply down and reaches this near it (a lifted foot of a walking pose).
constexpr double kSteepCos = 0.8;
constexpr double kLiftedShare = 0.15;
// Pointing up this much: a neck (along the body) or a top (ears, horns, a head).
constexpr double kRisingCos = 0.3;
constexpr double kTopCos = 0.7;
// A body this much taller than long stands upright (a biped): its side parts are arms.
constexpr double kUprightRatio = 1.2;
// What lies beyond this share of a part's reach, as near its line, hangs on the part's end (a hand,
// a head): no body for the names' body axes.
constexpr double kEndShare = 0.5;
// Two parts whose lengths, roots and tips agree to this share of their length across a plane are
// a mirrored pair.
constexpr double kMirrorTolerance = 0.1;
// A part shorter than this share of the longest, rooted in the upper part of the mesh (above this
// share of its height) and not hanging, is a horn (pointing up or along the body) or an ear (sideways).
constexpr double kSmallPartShare = 0.4;
constexpr double kHeadHeightShare = 0.6;
// (Hanging down more than this, it is a tail.)
constexpr double kHangingCos = 0.3;
// Rings that never grow past this many median radii from the tip to the far end: one tube.
constexpr double kWholeTubeWidening = 2;
// ... and that are this many median radii long: a thick blob (a fist, a pebble) is not a tube.
constexpr double kLoneTubeAspect = 8;
// A tube is traced over at least this many closed rings between its tip's cap and the junction.
// An open ring runs into a hole of the mesh: its area, hence its radius, measures nothing, and
// one or two rings past the tip of a flat face or a hole's rim are no tube (mech-holes-shark's
// "parts" of 2 vertices, 0.002 wide, before this).
constexpr int kMinTubeRings = 3;
// A part holds at least this many vertices: fewer (a spike of 4 or 5 on a low-polygon figure) bend
// as a stick, whatever the rings say (two rings of three round a tube and its tip are 7).
constexpr std::size_t kMinPartVertices = 8;
// A part's last ring before the body is as wide as the tube. Rings that shrink to this share of
// the tube's median radius before the jump closed round another end of the surface: they ran
// from one end of a foot (the heel) to the other (the toes) across the leg that meets it in the
// middle, and the jump is the leg; that is no part, and a fit from there leaks into the body.
constexpr double kClosedOffShare = 0.25;

// The average surface distance from `samples` sources spread by farthest-point sampling; NaN
// where no source reaches.
std::vector<double> average_distance(const Mesh& mesh, const Topology& topology, int samples) {
  const std::size_t n = mesh.vertex_count();
  std::vector<double> sum(n, 0.0), nearest(n, kInfinity);
  std::vector<int> count(n, 0);
  // Start at the point farthest from the first vertex a face uses: an extremity, not the middle
  // of the body.
  std::uint32_t source = topology.weld[0];
  for (std::uint32_t v = 0; v < n; ++v) {
    if (!topology.adjacency.of(v).empty()) {
      source = v;
      break;
    }
  }
  {
    const std::vector<double> d = surface_distances(mesh, topology, std::span(&source, 1));
    for (std::uint32_t v = 0; v < n; ++v) {
      if (std::isfinite(d[v]) && d[v] > d[source]) source = v;
    }
  }
  for (int k = 0; k < samples; ++k) {
    const std::vector<double> d = surface_distances(mesh, topology, std::span(&source, 1));
    for (std::size_t v = 0; v < n; ++v) {
      if (!std::isfinite(d[v])) continue;
      sum[v] += d[v];
      ++count[v];
      nearest[v] = std::min(nearest[v], d[v]);
    }
    // The next source: the vertex farthest from every source so far (another piece first). A
    // vertex no face uses (a file may list them; a hole cut from a mesh leaves them) is no piece:
    // each would take a source of its own, and a cut of 23 such left the part one source only.
    std::uint32_t next = source;
    for (std::uint32_t v = 0; v < n; ++v) {
      if (topology.weld[v] == v && nearest[v] > nearest[next] && !topology.adjacency.of(v).empty()) next = v;
    }
    if (!(nearest[next] > 0)) break;
    source = next;
  }
  std::vector<double> average(n, std::numeric_limits<double>::quiet_NaN());
  for (std::size_t v = 0; v < n; ++v) {
    if (count[v] > 0) average[v] = sum[v] / count[v];
  }
  return average;
}

// Vertices (weld representatives) where `field` is largest among their neighbours, highest
// first; ties go to the lower index so that a flat top gives one candidate.
std::vector<std::uint32_t> local_maxima(const Topology& topology, const std::vector<double>& field) {
  std::vector<std::uint32_t> out;
  for (std::uint32_t v = 0; v < field.size(); ++v) {
    if (topology.weld[v] != v || !std::isfinite(field[v])) continue;
    bool top = true;
    for (const std::uint32_t w : topology.adjacency.of(v)) {
      if (field[w] > field[v] || (field[w] == field[v] && w < v)) {
        top = false;
        break;
      }
    }
    if (top) out.push_back(v);
  }
  std::sort(out.begin(), out.end(),
            [&](std::uint32_t a, std::uint32_t b) { return field[a] != field[b] ? field[a] > field[b] : a < b; });
  return out;
}

// Where `p` lies between the mesh's lowest and highest points along `up`: 0 at the bottom, 1 at the top.
double height_share(const Vec3& p, const Vec3& up, double low, double high) {
  return (p.dot(up) - low) / std::max(high - low, 1e-300);
}

// Two parts that are each other's mirror image across a vertical plane between their roots are a
// pair — of limbs, of horns — and named alike: a pair that does not rise, named a tail or nothing,
// is a pair of arms (a body has one tail, along its middle; a stocky or wide figure is not upright by
// its proportions, and its arms, hanging out to the sides along its widest direction, read as
// tails); a pair that rises from the head's height, named a neck or a top, a pair of horns.
void name_mirrored_pairs(std::vector<FoundPart>& parts, const Vec3& up, double low, double high) {
  const auto pair_name = [&](const FoundPart& p) -> std::string_view {  // "": no pair's name
    const double rise = (p.tip - p.root).normalized().dot(up);
    if ((p.name == "tail" || p.name == "part") && rise <= kRisingCos) return "arm";
    const bool head_high = height_share(p.root, up, low, high) >= kHeadHeightShare;
    if ((p.name == "neck" || p.name == "top" || p.name == "part") && rise > kRisingCos && head_high) return "horn";
    return {};
  };
  for (std::size_t a = 0; a < parts.size(); ++a) {
    for (std::size_t b = a + 1; b < parts.size(); ++b) {
      FoundPart &p = parts[a], &q = parts[b];
      const std::string_view name = pair_name(p);
      if (name.empty() || pair_name(q) != name) continue;
      const double length = std::max(p.length, q.length);
      Vec3 normal = p.root - q.root;
      normal -= normal.dot(up) * up;  // the plane is vertical
      if (normal.norm() < kMirrorTolerance * length) continue;
      normal.normalize();
      const Vec3 middle = 0.5 * (p.root + q.root);
      const auto mirrored = [&](const Vec3& x) { return Vec3(x - 2 * (x - middle).dot(normal) * normal); };
      if (std::abs(p.length - q.length) <= kMirrorTolerance * length &&
          (mirrored(p.root) - q.root).norm() <= kMirrorTolerance * length &&
          (mirrored(p.tip) - q.tip).norm() <= kMirrorTolerance * length) {
        p.name = q.name = std::string(name);
      }
    }
  }
}

// Suggested names from where each part points (see find_parts).
void name_parts(const Mesh& mesh, const std::vector<char>& in_part, const Vec3& up_in, std::vector<FoundPart>& parts) {
  const Vec3 up = up_in.normalized();
  double low = kInfinity, high = -kInfinity;
  for (const Vec3& p : mesh.positions) {
    low = std::min(low, p.dot(up));
    high = std::max(high, p.dot(up));
  }
  // The body: the vertices of no part, less what hangs past a part's end — a hand beyond an arm,
  // a head beyond a neck, a tuft beyond a tail — which a part carries, not the body: left in, a
  // T-posed figure's hands made its body wider than tall and its arms "tails". Past an end: beyond
  // the middle of the part's reach (root to tip) and within half that reach of its line. Its long
  // axis is its widest horizontal direction.
  std::vector<char> in_body(mesh.vertex_count());
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) in_body[v] = !in_part[v];
  for (const FoundPart& p : parts) {
    const double reach = (p.tip - p.root).norm();
    if (reach <= 0) continue;
    const Vec3 dir = (p.tip - p.root) / reach;
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
      const Vec3 d = mesh.positions[v] - p.root;
      const double along_part = d.dot(dir);
      if (along_part >= kEndShare * reach && (d - along_part * dir).norm() <= kEndShare * reach) in_body[v] = 0;
    }
  }
  if (std::find(in_body.begin(), in_body.end(), 1) == in_body.end()) {  // all past some end: judge them all
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) in_body[v] = !in_part[v];
  }
  Vec3 centre = Vec3::Zero();
  std::size_t count = 0;
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    if (in_body[v]) {
      centre += mesh.positions[v];
      ++count;
    }
  }
  if (count == 0) return;
  centre /= static_cast<double>(count);
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  double body_low = kInfinity, body_high = -kInfinity;
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    if (!in_body[v]) continue;
    const Vec3 d = mesh.positions[v] - centre;
    const Vec3 flat = d - d.dot(up) * up;
    cov += flat * flat.transpose();
    body_low = std::min(body_low, d.dot(up));
    body_high = std::max(body_high, d.dot(up));
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  const Vec3 along = eig.eigenvectors().col(2);
  const Vec3 side = up.cross(along).normalized();
  double long_low = kInfinity, long_high = -kInfinity;
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    if (!in_body[v]) continue;
    const double x = (mesh.positions[v] - centre).dot(along);
    long_low = std::min(long_low, x);
    long_high = std::max(long_high, x);
  }
  const bool upright = body_high - body_low > kUprightRatio * (long_high - long_low);
  double longest = 0;
  for (const FoundPart& p : parts) longest = std::max(longest, p.length);
  std::map<std::string, int> total, used;
  for (FoundPart& p : parts) {
    const Vec3 dir = (p.tip - p.root).normalized();
    const double rise = dir.dot(up);
    const bool along_body = std::abs(dir.dot(along)) >= std::abs(dir.dot(side));
    const double above_ground = (p.bottom - low) / std::max(high - low, 1e-300);
    const bool small_and_high =
        p.length < kSmallPartShare * longest && height_share(p.root, up, low, high) >= kHeadHeightShare;
    if ((rise < -kDownCos && above_ground <= kGroundShare) || (rise < -kSteepCos && above_ground <= kLiftedShare)) {
      p.name = "leg";
    } else if (small_and_high && rise > -kHangingCos) {
      p.name = rise > kTopCos || along_body ? "horn" : "ear";
    } else if (rise > kTopCos && (upright || !along_body)) {
      p.name = "top";
    } else if (along_body && !upright) {
      p.name = rise > kRisingCos ? "neck" : "tail";
    } else if (rise >= -kDownCos || (upright && !small_and_high)) {
      // (On an upright body a part hanging down short of the ground is an arm too, unless it is a
      // small one at head height: a tusk, a beard.)
      p.name = "arm";
    } else {
      p.name = "part";
    }
  }
  name_mirrored_pairs(parts, up, low, high);
  for (const FoundPart& p : parts) ++total[p.name];
  for (FoundPart& p : parts) {
    if (total[p.name] > 1) p.name += std::to_string(++used[p.name]);
  }
}

// The mesh's shells (pieces connected by edges, over weld representatives): shell[v] for every
// vertex (a non-representative takes its representative's); -1 for a vertex no face uses.
std::vector<int> shells_of(const Topology& topology, int& count) {
  const std::size_t n = topology.weld.size();
  std::vector<int> shell(n, -1);
  count = 0;
  std::vector<std::uint32_t> stack;
  for (std::uint32_t v = 0; v < n; ++v) {
    if (topology.weld[v] != v || shell[v] >= 0 || topology.adjacency.of(v).empty()) continue;
    shell[v] = count;
    stack.assign(1, v);
    while (!stack.empty()) {
      const std::uint32_t u = stack.back();
      stack.pop_back();
      for (const std::uint32_t w : topology.adjacency.of(u)) {
        if (shell[w] < 0) {
          shell[w] = count;
          stack.push_back(w);
        }
      }
    }
    ++count;
  }
  for (std::uint32_t v = 0; v < n; ++v) shell[v] = shell[topology.weld[v]];
  return shell;
}

// Separate shells around a body (a spider's legs, a doll's arms): each is traced from its end
// away from the body only. The body is the shells of at least kBodyShellShare of the largest
// shell's area; a smaller shell's attachment is its vertex nearest to them, its end the vertex
// farthest over its surface from there. Candidates of such a shell nearer over its surface to
// the attachment than half that are its body end, never a tip (traced from there, a leg's rings
// run from its hip to its foot, and the part comes out root at the foot).
constexpr double kBodyShellShare = 0.25;
// A shell this many of the body shells' sample points or fewer is compared with all of them.
constexpr std::size_t kBodySamples = 4096;
// A separate shell whose part is at least this share of the body's radius (√(area / 4π) of the
// largest shell) across is a piece of the body's core (an abdomen beside a thorax), not a part.
constexpr double kCoreRadiusShare = 0.5;
// ... as is the whole of a body shell (this share of its area), traced from one end to the other.
constexpr double kWholeShellShare = 0.9;

struct Shells {
  std::vector<int> of;                  // shell of each vertex, -1 for none
  std::vector<char> body;               // per shell: one of the body's
  std::vector<std::uint32_t> end;       // per shell: its end away from the body (body shells: unused)
  std::vector<double> reach;            // per shell: surface distance from its attachment to its end
  std::vector<double> area;             // per shell
  std::vector<double> from_attachment;  // per vertex of a non-body shell: that distance
  double body_radius = 0;               // √(area / 4π) of the largest shell
  int largest = -1;
  int count = 0;
  bool several() const { return count > 1; }
  // A body with separate pieces that may be parts: some shell is not one of the body's (two
  // tubes of one size, a link of two rings, are two bodies: each may be a part).
  bool with_parts() const { return several() && std::find(body.begin(), body.end(), 0) != body.end(); }
};

Shells find_shells(const Mesh& mesh, const Topology& topology, const std::vector<double>& vertex_area) {
  Shells s;
  s.of = shells_of(topology, s.count);
  if (s.count < 2) return s;
  const std::size_t n = mesh.vertex_count();
  std::vector<double> area(static_cast<std::size_t>(s.count), 0.0);
  for (std::size_t v = 0; v < n; ++v) {
    if (s.of[v] >= 0) area[static_cast<std::size_t>(s.of[v])] += vertex_area[v];
  }
  s.area = area;
  s.largest = static_cast<int>(std::max_element(area.begin(), area.end()) - area.begin());
  const double largest = area[static_cast<std::size_t>(s.largest)];
  s.body_radius = std::sqrt(largest / (4 * std::numbers::pi));
  s.body.assign(area.size(), 0);
  for (std::size_t c = 0; c < area.size(); ++c) s.body[c] = area[c] >= kBodyShellShare * largest;
  std::vector<std::uint32_t> body_points;
  for (std::uint32_t v = 0; v < n; ++v) {
    if (topology.weld[v] == v && s.of[v] >= 0 && s.body[static_cast<std::size_t>(s.of[v])]) body_points.push_back(v);
  }
  const std::size_t stride = std::max<std::size_t>(1, body_points.size() / kBodySamples);
  std::vector<double> gap(area.size(), kInfinity);
  std::vector<std::uint32_t> attachment(area.size(), 0);
  for (std::uint32_t v = 0; v < n; ++v) {
    const int c = s.of[v];
    if (topology.weld[v] != v || c < 0 || s.body[static_cast<std::size_t>(c)]) continue;
    double nearest = kInfinity;
    for (std::size_t k = 0; k < body_points.size(); k += stride)
      nearest = std::min(nearest, (mesh.positions[body_points[k]] - mesh.positions[v]).squaredNorm());
    if (nearest < gap[static_cast<std::size_t>(c)]) {
      gap[static_cast<std::size_t>(c)] = nearest;
      attachment[static_cast<std::size_t>(c)] = v;
    }
  }
  s.end.assign(area.size(), 0);
  s.reach.assign(area.size(), 0);
  s.from_attachment.assign(n, kInfinity);
  for (std::size_t c = 0; c < area.size(); ++c) {
    if (s.body[c] || !std::isfinite(gap[c])) continue;
    const std::vector<double> d = surface_distances(mesh, topology, std::span(&attachment[c], 1));
    for (std::uint32_t v = 0; v < n; ++v) {
      if (s.of[v] != static_cast<int>(c) || !std::isfinite(d[topology.weld[v]])) continue;
      s.from_attachment[v] = d[topology.weld[v]];
      if (topology.weld[v] == v && d[v] > s.reach[c]) {
        s.reach[c] = d[v];
        s.end[c] = v;
      }
    }
  }
  return s;
}

// The candidates in the order they are traced: the local maxima of the average distance, highest
// first, but on a separate shell only those on its far half, and its end always.
std::vector<std::uint32_t> candidates(const Topology& topology, const std::vector<double>& average,
                                      const Shells& shells) {
  std::vector<std::uint32_t> out = local_maxima(topology, average);
  if (!shells.several()) return out;
  const auto near_body_end = [&](std::uint32_t v) {
    const int c = shells.of[v];
    return c >= 0 && !shells.body[static_cast<std::size_t>(c)] &&
           !(shells.from_attachment[v] >= 0.5 * shells.reach[static_cast<std::size_t>(c)]);
  };
  out.erase(std::remove_if(out.begin(), out.end(), near_body_end), out.end());
  for (std::size_t c = 0; c < shells.body.size(); ++c) {
    if (shells.body[c] || !(shells.reach[c] > 0)) continue;
    if (std::find(out.begin(), out.end(), shells.end[c]) == out.end()) out.push_back(shells.end[c]);
  }
  std::stable_sort(out.begin(), out.end(), [&](std::uint32_t a, std::uint32_t b) {
    const double fa = std::isfinite(average[a]) ? average[a] : -kInfinity;
    const double fb = std::isfinite(average[b]) ? average[b] : -kInfinity;
    return fa != fb ? fa > fb : a < b;
  });
  return out;
}

}  // namespace

std::vector<FoundPart> find_parts(const Mesh& mesh, const Topology& topology, const DiscoverOptions& o,
                                  std::vector<std::string>* passed_over) {
  std::vector<FoundPart> parts;
  const std::size_t n = mesh.vertex_count();
  if (n == 0) return parts;
  const std::vector<double> average = average_distance(mesh, topology, std::max(o.samples, 1));
  // Each vertex's share of the surface: a third of its triangles' areas.
  std::vector<double> vertex_area(n, 0.0);
  double total_area = 0;
  {
    const std::vector<std::uint32_t> tris = mesh.triangles();
    for (std::size_t t = 0; t + 2 < tris.size(); t += 3) {
      const Vec3& a = mesh.positions[tris[t]];
      const double third = (mesh.positions[tris[t + 1]] - a).cross(mesh.positions[tris[t + 2]] - a).norm() / 6;
      for (int k = 0; k < 3; ++k) vertex_area[tris[t + static_cast<std::size_t>(k)]] += third;
      total_area += 3 * third;
    }
  }
  const Shells shells = find_shells(mesh, topology, vertex_area);
  // The figure's size, which a part must not be tiny against.
  Vec3 box_low = mesh.positions.front(), box_high = box_low;
  for (const Vec3& p : mesh.positions) {
    box_low = box_low.cwiseMin(p);
    box_high = box_high.cwiseMax(p);
  }
  const double size = (box_high - box_low).norm();
  std::vector<char> covered(n, 0), in_part(n, 0);
  int traced = 0;
  std::optional<FoundPart> lone_tube;
  for (const std::uint32_t tip : candidates(topology, average, shells)) {
    if (covered[tip]) continue;
    if (traced++ >= o.max_candidates) break;
    const std::vector<double> d = surface_distances(mesh, topology, std::span(&tip, 1));
    const RingTrace rings = trace_rings(mesh, topology, d, tip, kInfinity, true, o.rings);
    const auto cover = [&](double up_to) {
      for (std::size_t v = 0; v < n; ++v) covered[v] |= d[topology.weld[v]] <= up_to;
    };
    if (rings.rings.size() < 2 || rings.junction < 1) {
      cover(0);
      continue;
    }
    const Ring& junction = rings.rings[static_cast<std::size_t>(rings.junction)];
    // The tube between the tip's cap and the junction: its median ring radius.
    int cap = 0;
    while (cap < rings.junction && rings.rings[static_cast<std::size_t>(cap)].growth >= o.rings.settled_growth) {
      ++cap;
    }
    std::vector<double> radii;
    bool open_ring = false;
    for (int i = cap; i <= rings.junction; ++i) {
      const Ring& ring = rings.rings[static_cast<std::size_t>(i)];
      if (ring.closed) radii.push_back(ring.radius);
      open_ring |= !ring.closed;
    }
    if (static_cast<int>(radii.size()) < kMinTubeRings) {
      if (passed_over) {
        passed_over->push_back("vertex " + std::to_string(tip) + " at " + format_point(mesh.positions[tip]) + ": " +
                               std::to_string(radii.size()) + " closed ring" + (radii.size() == 1 ? "" : "s") +
                               " before " + rings.junction_reason + "; a tube has at least " +
                               std::to_string(kMinTubeRings) +
                               (open_ring ? " (an open ring runs into a hole of the mesh)" : ""));
      }
      cover(junction.distance);
      continue;
    }
    std::nth_element(radii.begin(), radii.begin() + static_cast<std::ptrdiff_t>(radii.size() / 2), radii.end());
    const double radius = radii[radii.size() / 2];
    if (junction.closed && junction.radius < kClosedOffShare * radius &&
        rings.junction + 1 < static_cast<int>(rings.rings.size())) {
      if (passed_over) {
        passed_over->push_back("vertex " + std::to_string(tip) + " at " + format_point(mesh.positions[tip]) +
                               ": its rings close round another end (" + format_number(junction.radius) +
                               " across against the tube's " + format_number(radius) +
                               ") before they meet the body: an end traced across, as a foot from its heel");
      }
      cover(2 * rings.rings[static_cast<std::size_t>(cap)].radius);
      continue;
    }
    std::size_t count = 0;
    double area = 0;
    for (std::size_t v = 0; v < n; ++v) {
      if (d[topology.weld[v]] > junction.distance) continue;
      ++count;
      area += vertex_area[v];
    }
    // No junction and no ring much wider than the tube: the whole mesh is one tube (a part
    // without a body). Rings that reach the far end after widening crossed the body instead.
    double widest = 0;
    for (int i = cap; i <= rings.junction; ++i) {
      const Ring& ring = rings.rings[static_cast<std::size_t>(i)];
      if (ring.closed) widest = std::max(widest, ring.radius);
    }
    const bool whole_mesh =
        rings.junction + 1 == static_cast<int>(rings.rings.size()) && widest <= kWholeTubeWidening * radius;
    // (A flat piece, a lone triangle or an open sheet, has rings that enclose nothing: no tube.)
    const bool long_enough = radius > 0 && junction.distance >= o.min_aspect * radius;
    const bool not_the_body = area <= o.max_area_share * total_area;
    if (whole_mesh && radius > 0 && junction.distance >= kLoneTubeAspect * radius && !not_the_body && !lone_tube) {
      // Perhaps the mesh is one tube; only if no part is found (else these rings crossed a body).
      lone_tube = FoundPart{};
      lone_tube->tip_vertex = tip;
      lone_tube->tip = mesh.positions[tip];
      lone_tube->root = junction.centroid;
      lone_tube->length = junction.distance;
      lone_tube->mean_radius = radius;
      lone_tube->vertex_count = count;
      lone_tube->junction_reason = rings.junction_reason;
    }
    if ((!long_enough || !not_the_body) && passed_over) {
      passed_over->push_back("vertex " + std::to_string(tip) + " at " + format_point(mesh.positions[tip]) + ": " +
                             (long_enough
                                  ? "its rings hold " + format_percent(area / total_area) + " of the surface (the body)"
                              : !(radius > 0) ? std::string("flat: its rings enclose no area")
                                              : "a bump, " + format_number(junction.distance / radius) +
                                                    " radii long (" + rings.junction_reason + ")"));
    }
    if (!long_enough || !not_the_body) {
      // A bump (cover it) or the body itself (cover only the tip's cap, so that the parts
      // around it are still found).
      cover(long_enough ? 2 * rings.rings[static_cast<std::size_t>(cap)].radius : junction.distance);
      continue;
    }
    // On a body with separate parts: a part of a separate shell found twice (from two tips of
    // one end: most of its region is a part already), and the body's core pieces.
    const int shell = shells.with_parts() ? shells.of[tip] : -1;
    std::size_t shared = 0;
    if (shell >= 0) {
      for (std::size_t v = 0; v < n; ++v) shared += in_part[v] && d[topology.weld[v]] <= junction.distance;
    }
    // (A body shell's rings that cover it whole run from one end of the body to the other.)
    const bool core = shell >= 0 && ((shell != shells.largest && radius >= kCoreRadiusShare * shells.body_radius) ||
                                     (shells.body[static_cast<std::size_t>(shell)] &&
                                      area >= kWholeShellShare * shells.area[static_cast<std::size_t>(shell)]));
    if (2 * shared > count || core) {
      if (passed_over) {
        passed_over->push_back("vertex " + std::to_string(tip) + " at " + format_point(mesh.positions[tip]) + ": " +
                               (core ? "a piece of the body's core (" + format_percent(radius / shells.body_radius) +
                                           " of the body's radius across, " +
                                           format_percent(area / shells.area[static_cast<std::size_t>(shell)]) +
                                           " of its shell)"
                                     : std::string("the same part as one found before")));
      }
      cover(junction.distance);
      continue;
    }
    // Tiny against the figure: no part a person counts.
    const bool short_part = junction.distance < o.min_length_share * size;
    if (short_part || count < kMinPartVertices) {
      if (passed_over) {
        passed_over->push_back(
            "vertex " + std::to_string(tip) + " at " + format_point(mesh.positions[tip]) + ": small, " +
            (short_part
                 ? format_number(junction.distance) + " long against the mesh's " + format_number(size) +
                       " (its bounding box's diagonal; a part is at least " + format_percent(o.min_length_share) +
                       " of it)"
                 : std::to_string(count) + " vertices (a part has at least " + std::to_string(kMinPartVertices) + ")"));
      }
      cover(junction.distance);
      continue;
    }
    FoundPart p;
    p.tip_vertex = tip;
    p.tip = mesh.positions[tip];
    p.root = junction.centroid;
    p.length = junction.distance;
    p.mean_radius = radius;
    p.vertex_count = count;
    p.junction_reason = rings.junction_reason;
    cover(junction.distance);
    if (o.refuse) {
      if (const std::string why = o.refuse(p); !why.empty()) {
        if (passed_over) {
          passed_over->push_back("vertex " + std::to_string(tip) + " at " + format_point(mesh.positions[tip]) + ": " +
                                 why);
        }
        continue;
      }
    }
    p.bottom = std::numeric_limits<double>::infinity();
    for (std::size_t v = 0; v < n; ++v) {
      if (d[topology.weld[v]] > junction.distance) continue;
      in_part[v] = 1;
      p.bottom = std::min(p.bottom, mesh.positions[v].dot(o.up.normalized()));
    }
    parts.push_back(p);
  }
  if (parts.empty() && lone_tube) {
    parts.push_back(*lone_tube);
    in_part.assign(n, 0);  // no body to name it by
  }
  std::stable_sort(parts.begin(), parts.end(),
                   [](const FoundPart& a, const FoundPart& b) { return a.length > b.length; });
  name_parts(mesh, in_part, o.up, parts);
  return parts;
}

}  // namespace sweep::fit
