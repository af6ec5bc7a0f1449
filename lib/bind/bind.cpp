#include "sweep/bind/bind.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <iterator>
#include <limits>
#include <optional>
#include <sstream>

#include "sweep/bind/deform.h"
#include "sweep/bind/loose_pieces.h"
#include "sweep/core/error.h"
#include "sweep/core/frame.h"
#include "sweep/core/hash.h"
#include "sweep/core/locate.h"
#include "sweep/core/text.h"
#include "sweep/core/topology.h"

namespace sweep::bind {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

double smoothstep01(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * (3 - 2 * x);
}

// One sweep's candidates before ownership: mesh indices (ascending), coordinates, and the
// distance used to settle overlaps.
struct Candidates {
  std::vector<std::uint32_t> vertices;
  std::vector<SweepCoords> coords;
  std::vector<double> surface_distance;  // |s − 1|·r(θ,t) + |z|, mesh units
  std::vector<char> keep;                // seedless filter result (1 = bind)
};

std::string sweep_label(const SweepDef& def, std::size_t index) {
  std::ostringstream s;
  s << "sweep " << index << " ('" << def.name << "')";
  return s.str();
}

void check_inputs(const Rig& rig, const Mesh& mesh, const BindOptions& o) {
  if (!(o.blend >= 0) || !std::isfinite(o.blend)) {
    fail(ErrorCategory::usage, "BindOptions::blend must be a finite distance >= 0, got " + format_exact(o.blend));
  }
  if (!(o.seedless_radius_factor >= 1) || !std::isfinite(o.seedless_radius_factor)) {
    fail(ErrorCategory::usage,
         "BindOptions::seedless_radius_factor must be finite and >= 1, got " + format_exact(o.seedless_radius_factor));
  }
  if (o.stations_per_span < 1)
    fail(ErrorCategory::usage,
         "BindOptions::stations_per_span must be >= 1, got " + std::to_string(o.stations_per_span));
  if (mesh.vertex_count() == 0) fail(ErrorCategory::bad_input, "the mesh has no vertices");
  if (mesh.vertex_count() > std::numeric_limits<std::uint32_t>::max()) {
    fail(ErrorCategory::unsupported, "meshes of more than 2^32 - 1 vertices are not supported");
  }
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    if (!is_finite(mesh.positions[v])) {
      fail(ErrorCategory::bad_input, "vertex " + std::to_string(v) + " is not finite");
    }
  }
  if (rig.sweeps.empty()) fail(ErrorCategory::bad_input, "the rig has no sweeps");
  for (std::size_t i = 0; i < rig.sweeps.size(); ++i) {
    const std::string why = check_shape(rig.sweeps[i].rest);
    if (!why.empty()) fail(ErrorCategory::bad_input, sweep_label(rig.sweeps[i], i) + ": " + why);
  }
}

// The candidates of one sweep: `selected` (its part and loose pieces, ascending) for a sweep with
// seeds, else every vertex on the tip side of its root plane, filtered by `keep` below.
Candidates locate_part(const SweepDef& def, const Mesh& mesh, std::vector<std::uint32_t> selected,
                       const BindOptions& o) {
  const SweepShape& rest = def.rest;
  const Frame& root = rest.frames[0];
  Candidates c;
  if (def.part) {
    c.vertices = std::move(selected);
  } else {
    const Vec3 normal = root.axis();
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
      if ((mesh.positions[v] - root.center).dot(normal) >= 0) {
        c.vertices.push_back(static_cast<std::uint32_t>(v));
      }
    }
  }
  const std::size_t m = c.vertices.size();
  c.coords.resize(m);
  c.surface_distance.resize(m);
  c.keep.assign(m, 1);
  const SweepLocator locator(rest, o.stations_per_span);
  const double length = rest.length();
  const int last = rest.section_count() - 1;
  double tip_radius = 0;
  for (double r : rest.section_radii(last)) tip_radius = std::max(tip_radius, r);
  const double factor = o.seedless_radius_factor;
  const bool seedless = !def.part;
  const auto count = static_cast<std::ptrdiff_t>(m);
#pragma omp parallel for schedule(dynamic, 256) if (count >= kMinParallelVertices)
  for (std::ptrdiff_t k = 0; k < count; ++k) {
    const SweepCoords sc = locator.locate(mesh.positions[c.vertices[k]]);
    c.coords[k] = sc;
    const double r = radius_at(rest, sc.theta, sc.t);
    c.surface_distance[k] = std::abs(sc.s - 1) * r + std::abs(sc.z);
    if (seedless) {
      const bool inside = sc.s <= factor;
      const bool in_span = sc.z == 0;
      const bool tip_cap = sc.t == length && sc.z > 0 && sc.z <= factor * tip_radius;
      c.keep[k] = inside && (in_span || tip_cap) ? 1 : 0;
    }
  }
  return c;
}

}  // namespace

std::size_t Binding::bound_count() const {
  std::size_t n = 0;
  for (const SweepBinding& s : sweeps) n += s.size();
  return n;
}

std::uint64_t hash_positions(const std::vector<Vec3>& positions) {
  std::uint64_t h = kFnvOffset;
  for (const Vec3& p : positions) {
    for (int a = 0; a < 3; ++a) h = fnv1a_double(h, p[a]);
  }
  return h;
}

std::uint64_t hash_sweeps(const Rig& rig) {
  // The byte layout of bind.h, fed to FNV-1a as it goes; integers and doubles little-endian.
  std::uint64_t h = fnv1a(kFnvOffset, kSweepHashTag);
  h = fnv1a_le(h, rig.sweeps.size(), 4);
  for (const SweepDef& def : rig.sweeps) {
    const SweepShape& rest = def.rest;
    h = fnv1a_le(h, def.name.size(), 4);
    h = fnv1a(h, def.name);
    h = fnv1a_le(h, static_cast<std::uint64_t>(rest.section_count()), 4);
    h = fnv1a_le(h, static_cast<std::uint64_t>(rest.radial_count), 4);
    for (int i = 0; i < rest.section_count(); ++i) {
      const Frame& f = rest.frames[i];
      h = fnv1a_double(h, rest.t[i]);
      for (double x : {f.rotation.w(), f.rotation.x(), f.rotation.y(), f.rotation.z()}) h = fnv1a_double(h, x);
      for (int a = 0; a < 3; ++a) h = fnv1a_double(h, f.center[a]);
      for (double r : rest.section_radii(i)) h = fnv1a_double(h, r);
    }
    h = fnv1a_le(h, def.part ? (def.part->tip_cut ? 2 : 1) : 0, 1);
    if (def.part) {
      for (int a = 0; a < 3; ++a) h = fnv1a_double(h, def.part->root[a]);
      for (int a = 0; a < 3; ++a) h = fnv1a_double(h, def.part->tip[a]);
    }
  }
  return h;
}

BindResult bind(const Rig& rig, const Mesh& mesh, const BindOptions& options) {
  const Clock::time_point start = Clock::now();
  check_inputs(rig, mesh, options);
  BindResult result;
  Binding& b = result.binding;
  b.vertex_count = mesh.vertex_count();
  b.mesh_hash = hash_positions(mesh.positions);
  b.rig_hash = hash_sweeps(rig);

  const bool any_seeds = std::any_of(rig.sweeps.begin(), rig.sweeps.end(), [](const SweepDef& d) { return d.part; });
  std::optional<Topology> topology;
  if (any_seeds) topology = build_topology(mesh);

  // Candidates of every sweep, then ownership: strictly nearer surface wins, so ties stay with
  // the earlier sweep (sweeps are visited in rig order).
  const std::size_t sweep_count = rig.sweeps.size();
  std::vector<Candidates> candidates(sweep_count);
  result.sweeps.resize(sweep_count);
  std::vector<int> owner(mesh.vertex_count(), -1);
  std::vector<double> owner_distance(mesh.vertex_count(), std::numeric_limits<double>::infinity());
  // The seeded parts walked over the surface, then the loose pieces against them.
  std::vector<std::vector<std::uint32_t>> selected(sweep_count);
  std::vector<double> select_seconds(sweep_count, 0.0);
  for (std::size_t i = 0; i < sweep_count; ++i) {
    const SweepDef& def = rig.sweeps[i];
    if (!def.part) continue;
    const Clock::time_point sweep_start = Clock::now();
    try {
      selected[i] = select_sweep_part(mesh, *topology, def.rest, *def.part);
    } catch (const Error& e) {
      throw Error(e.category(), sweep_label(def, i) + ": " + e.what());
    }
    select_seconds[i] = seconds_since(sweep_start);
  }
  if (any_seeds) {
    for (const LoosePiece& piece : find_loose_pieces(rig, mesh, *topology, selected)) {
      if (piece.sweep < 0) {
        result.warnings.push_back(describe_piece(piece, mesh) + " lies " + format_number(piece.gap) + " from part '" +
                                  rig.sweeps[static_cast<std::size_t>(piece.near)].name + "' but is not bound (" +
                                  piece.why_unbound + "): it will not move with the part");
        continue;
      }
      const auto i = static_cast<std::size_t>(piece.sweep);
      std::vector<std::uint32_t> merged;
      merged.reserve(selected[i].size() + piece.vertices.size());
      std::merge(selected[i].begin(), selected[i].end(), piece.vertices.begin(), piece.vertices.end(),
                 std::back_inserter(merged));
      selected[i] = std::move(merged);
      ++result.sweeps[i].loose_piece_count;
      result.sweeps[i].loose_vertex_count += piece.vertices.size();
    }
  }
  for (std::size_t i = 0; i < sweep_count; ++i) {
    const Clock::time_point sweep_start = Clock::now();
    const SweepDef& def = rig.sweeps[i];
    try {
      candidates[i] = locate_part(def, mesh, std::move(selected[i]), options);
    } catch (const Error& e) {
      throw Error(e.category(), sweep_label(def, i) + ": " + e.what());
    }
    const Candidates& c = candidates[i];
    SweepBindStats& st = result.sweeps[i];
    st.name = def.name;
    st.length = def.rest.length();
    for (std::size_t k = 0; k < c.vertices.size(); ++k) {
      if (!c.keep[k]) continue;
      ++st.part_vertex_count;
      const std::uint32_t v = c.vertices[k];
      if (c.surface_distance[k] < owner_distance[v]) {
        owner_distance[v] = c.surface_distance[k];
        owner[v] = static_cast<int>(i);
      }
    }
    st.seconds = select_seconds[i] + seconds_since(sweep_start);
  }

  // The tables: owned candidates in ascending vertex order, coordinates rounded to float32.
  b.sweeps.resize(sweep_count);
  for (std::size_t i = 0; i < sweep_count; ++i) {
    const Clock::time_point sweep_start = Clock::now();
    const SweepDef& def = rig.sweeps[i];
    const Candidates& c = candidates[i];
    SweepBinding& sb = b.sweeps[i];
    sb.name = def.name;
    const Frame& root = def.rest.frames[0];
    const Vec3 normal = root.axis();
    // A part cut on the tip side blends out towards that cut as well (nothing beyond it moves).
    const bool tip_cut = def.part && def.part->tip_cut;
    const Frame& tip = def.rest.frames.back();
    const Vec3 tip_normal = tip.axis();
    for (std::size_t k = 0; k < c.vertices.size(); ++k) {
      const std::uint32_t v = c.vertices[k];
      if (!c.keep[k] || owner[v] != static_cast<int>(i)) continue;
      const SweepCoords& sc = c.coords[k];
      double w = 1;
      if (options.blend > 0) {
        w = smoothstep01((mesh.positions[v] - root.center).dot(normal) / options.blend);
        if (tip_cut) w *= smoothstep01((tip.center - mesh.positions[v]).dot(tip_normal) / options.blend);
      }
      sb.vertices.push_back(v);
      sb.t.push_back(static_cast<float>(sc.t));
      sb.theta.push_back(static_cast<float>(sc.theta));
      sb.s.push_back(static_cast<float>(sc.s));
      sb.z.push_back(static_cast<float>(sc.z));
      sb.weight.push_back(static_cast<float>(w));
    }
    SweepBindStats& st = result.sweeps[i];
    st.bound_vertex_count = sb.size();
    st.blended_vertex_count =
        static_cast<std::size_t>(std::count_if(sb.weight.begin(), sb.weight.end(), [](float w) { return w < 1; }));
    // The rest pose rebuilt from exactly what the file will hold.
    st.rest_max_error = max_rebuild_error(sb, def.rest, mesh.positions);
    st.seconds += seconds_since(sweep_start);
  }
  result.unbound_vertex_count = mesh.vertex_count() - b.bound_count();
  result.seconds = seconds_since(start);
  return result;
}

}  // namespace sweep::bind
