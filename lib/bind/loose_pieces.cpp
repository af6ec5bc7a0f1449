#include "sweep/bind/loose_pieces.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "sweep/core/frame.h"
#include "sweep/core/text.h"

namespace sweep::bind {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The pieces of the mesh: piece[v] for every vertex (welded copies with their representative;
// a vertex no face uses is a piece of its own).
std::vector<std::uint32_t> pieces_of(const Topology& topology, std::uint32_t& count) {
  const auto n = static_cast<std::uint32_t>(topology.weld.size());
  constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> piece(n, kNone);
  std::vector<std::uint32_t> stack;
  count = 0;
  for (std::uint32_t v = 0; v < n; ++v) {
    if (topology.weld[v] != v || piece[v] != kNone) continue;
    piece[v] = count;
    stack.assign(1, v);
    while (!stack.empty()) {
      const std::uint32_t u = stack.back();
      stack.pop_back();
      for (const std::uint32_t w : topology.adjacency.of(u)) {
        if (piece[w] == kNone) {
          piece[w] = count;
          stack.push_back(w);
        }
      }
    }
    ++count;
  }
  for (std::uint32_t v = 0; v < n; ++v) piece[v] = piece[topology.weld[v]];
  return piece;
}

// Points in cubic cells of one size: the nearest within a cell's width, by the 27 cells around.
class PointGrid {
 public:
  PointGrid(const Mesh& mesh, const std::vector<std::uint32_t>& points, double cell) : mesh_(mesh), cell_(cell) {
    for (const std::uint32_t v : points) cells_[key(cell_of(mesh.positions[v]))].push_back(v);
  }
  // The distance from p to the nearest point, if one lies within a cell's width; else infinity.
  double nearest(const Vec3& p) const {
    const Eigen::Vector3i c = cell_of(p);
    double best = kInf;
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = cells_.find(key(c + Eigen::Vector3i(dx, dy, dz)));
          if (it == cells_.end()) continue;
          for (const std::uint32_t v : it->second) best = std::min(best, (mesh_.positions[v] - p).norm());
        }
      }
    }
    return best <= cell_ ? best : kInf;
  }

 private:
  Eigen::Vector3i cell_of(const Vec3& p) const {
    // (Clamped: a mesh a million cells across still hashes, if coarsely.)
    const Vec3 c = (p / cell_).array().floor().cwiseMax(-1e6).cwiseMin(1e6);
    return c.cast<int>();
  }
  static std::int64_t key(const Eigen::Vector3i& c) {
    return (static_cast<std::int64_t>(c.x()) * 2097152 + c.y()) * 2097152 + c.z();
  }
  const Mesh& mesh_;
  double cell_;
  std::unordered_map<std::int64_t, std::vector<std::uint32_t>> cells_;
};

double mean_radius(const SweepShape& shape) {
  double sum = 0;
  for (const double r : shape.radii) sum += r;
  return shape.radii.empty() ? 0.0 : sum / static_cast<double>(shape.radii.size());
}

}  // namespace

std::vector<LoosePiece> find_loose_pieces(const Rig& rig, const Mesh& mesh, const Topology& topology,
                                          const std::vector<std::vector<std::uint32_t>>& parts) {
  std::vector<LoosePiece> out;
  std::uint32_t count = 0;
  const std::vector<std::uint32_t> piece = pieces_of(topology, count);
  if (count < 2) return out;
  std::vector<char> attached(count, 0);
  for (const std::vector<std::uint32_t>& part : parts) {
    for (const std::uint32_t v : part) attached[piece[v]] = 1;
  }
  // The pieces no part holds, as vertex lists, and their size across.
  std::vector<std::vector<std::uint32_t>> members(count);
  for (std::uint32_t v = 0; v < piece.size(); ++v) {
    if (!attached[piece[v]]) members[piece[v]].push_back(v);
  }
  std::vector<double> across(count, 0.0);
  for (std::uint32_t c = 0; c < count; ++c) {
    if (members[c].empty()) continue;
    Vec3 lo = mesh.positions[members[c][0]], hi = lo;
    for (const std::uint32_t v : members[c]) {
      lo = lo.cwiseMin(mesh.positions[v]);
      hi = hi.cwiseMax(mesh.positions[v]);
    }
    across[c] = (hi - lo).norm();
  }
  std::vector<double> gap(count, kInf), gap_radii(count, kInf);  // mesh units; in mean radii
  std::vector<int> nearest_sweep(count, -1);
  for (std::size_t i = 0; i < rig.sweeps.size() && i < parts.size(); ++i) {
    const SweepDef& def = rig.sweeps[i];
    if (!def.part || parts[i].empty()) continue;
    const double radius = mean_radius(def.rest), length = def.rest.length();
    if (!(radius > 0)) continue;
    const PointGrid grid(mesh, parts[i], kLooseNearRadii * radius);
    for (std::uint32_t c = 0; c < count; ++c) {
      if (members[c].empty() || across[c] > length) continue;
      double g = kInf;
      for (const std::uint32_t v : members[c]) g = std::min(g, grid.nearest(mesh.positions[v]));
      // In mean radii, so that a thin part and a thick one are judged alike.
      if (g / radius < gap_radii[c]) {
        gap[c] = g;
        gap_radii[c] = g / radius;
        nearest_sweep[c] = static_cast<int>(i);
      }
    }
  }
  for (std::uint32_t c = 0; c < count; ++c) {
    if (nearest_sweep[c] < 0) continue;
    const SweepDef& def = rig.sweeps[static_cast<std::size_t>(nearest_sweep[c])];
    LoosePiece p;
    p.vertices = members[c];
    p.near = nearest_sweep[c];
    p.gap = gap[c];
    const Frame& root = def.rest.frames[0];
    const bool behind_root = std::any_of(p.vertices.begin(), p.vertices.end(), [&](std::uint32_t v) {
      return (mesh.positions[v] - root.center).dot(root.axis()) < 0;
    });
    const double radius = mean_radius(def.rest);
    if (p.gap > kLooseReachRadii * radius) {
      p.why_unbound = format_number(p.gap / radius) + " mean radii from the part (a piece within " +
                      format_number(kLooseReachRadii) + " goes with it)";
    } else if (behind_root) {
      p.why_unbound = "it reaches behind the part's root section, into the body";
    } else {
      p.sweep = p.near;
    }
    out.push_back(std::move(p));
  }
  return out;
}

std::string describe_piece(const LoosePiece& piece, const Mesh& mesh) {
  const std::uint32_t first = piece.vertices.front();
  return "a loose piece of " + std::to_string(piece.vertices.size()) +
         (piece.vertices.size() == 1 ? " vertex" : " vertices") + " (vertex " + std::to_string(first) + " at " +
         format_point(mesh.positions[first], 4) + ")";
}

}  // namespace sweep::bind
