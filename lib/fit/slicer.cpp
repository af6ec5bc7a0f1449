// One of the two translation units that include CGAL (see slicer.h).
#include "sweep/fit/slicer.h"

#include <CGAL/AABB_halfedge_graph_segment_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_slicer.h>
#include <CGAL/Surface_mesh.h>
#include <fenv.h>

#include <array>
#include <cassert>

#include "sweep/core/fp_environment.h"
#include "sweep/core/topology.h"

namespace sweep::fit {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
using EdgePrimitive = CGAL::AABB_halfedge_graph_segment_primitive<SurfaceMesh>;
using EdgeTree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, EdgePrimitive>>;
using Slicer = CGAL::Polygon_mesh_slicer<SurfaceMesh, Kernel>;

Point to_point(const Vec3& v) {
  return {v.x(), v.y(), v.z()};
}

}  // namespace

struct MeshSlicer::Impl {
  SurfaceMesh mesh;
  std::unique_ptr<EdgeTree> tree;  // refers to `mesh`, which must not move after it is built
  std::size_t repaired = 0;
};

MeshSlicer::MeshSlicer(const Mesh& mesh) : MeshSlicer(mesh.positions, build_topology(mesh).triangles) {}

MeshSlicer::MeshSlicer(const std::vector<Vec3>& positions, const std::vector<std::uint32_t>& tris)
    : impl_(std::make_unique<Impl>()) {
  QuietFpEnvironment quiet;
  SurfaceMesh& sm = impl_->mesh;
  sm.reserve(static_cast<SurfaceMesh::size_type>(positions.size()),
             static_cast<SurfaceMesh::size_type>(tris.size() / 2 * 3),
             static_cast<SurfaceMesh::size_type>(tris.size() / 3));
  // Every vertex, so that indices stay the caller's: a welded-away copy is an isolated vertex,
  // which no edge and so no slice touches.
  for (const Vec3& p : positions) sm.add_vertex(to_point(p));
  std::vector<std::array<std::size_t, 3>> rejected;
  for (std::size_t f = 0; f + 2 < tris.size(); f += 3) {
    const std::array<std::uint32_t, 3> v{tris[f], tris[f + 1], tris[f + 2]};
    if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) continue;  // degenerate: cuts nothing
    const auto face =
        sm.add_face(SurfaceMesh::Vertex_index(v[0]), SurfaceMesh::Vertex_index(v[1]), SurfaceMesh::Vertex_index(v[2]));
    if (face == SurfaceMesh::null_face()) rejected.push_back({v[0], v[1], v[2]});
  }
  // Each face add_face refused (it would leave an edge with three faces or a vertex with two fans,
  // or it is turned against its neighbour) goes in again turned over, or with copies of as few of
  // its corners as take it (a copy at its vertex's place, appended after the caller's indices): a
  // slice through it runs on as before but where the copy parts it from its neighbours. Local and
  // linear, where orienting the whole soup again (CGAL's orient_polygon_soup) took a fifth of a
  // fit of the diplodocus for its 6 such faces.
  impl_->repaired = rejected.size();
  for (const std::array<std::size_t, 3>& v : rejected) {
    std::array<SurfaceMesh::Vertex_index, 3> copy{SurfaceMesh::null_vertex(), SurfaceMesh::null_vertex(),
                                                  SurfaceMesh::null_vertex()};
    bool added = false;
    for (const int copied : {0, 1, 2, 4, 3, 5, 6, 7}) {  // a bit per corner, fewest copies first
      std::array<SurfaceMesh::Vertex_index, 3> c{};
      for (int i = 0; i < 3; ++i) {
        if (copied & (1 << i)) {
          if (copy[i] == SurfaceMesh::null_vertex()) {
            const Point at = sm.point(SurfaceMesh::Vertex_index(v[i]));  // a copy: adding may move the points
            copy[i] = sm.add_vertex(at);
          }
          c[i] = copy[i];
        } else {
          c[i] = SurfaceMesh::Vertex_index(v[i]);
        }
      }
      added = sm.add_face(c[0], c[1], c[2]) != SurfaceMesh::null_face() ||
              sm.add_face(c[0], c[2], c[1]) != SurfaceMesh::null_face();
      if (added) break;
    }
    assert(added);  // three fresh copies always take it
  }
  impl_->tree = std::make_unique<EdgeTree>(edges(sm).first, edges(sm).second, sm);
  impl_->tree->build();
}

MeshSlicer::~MeshSlicer() = default;
MeshSlicer::MeshSlicer(MeshSlicer&&) noexcept = default;
MeshSlicer& MeshSlicer::operator=(MeshSlicer&&) noexcept = default;

std::size_t MeshSlicer::repaired_face_count() const {
  return impl_->repaired;
}

std::vector<SlicePolyline> MeshSlicer::slice(const Vec3& point, const Vec3& normal) const {
  QuietFpEnvironment quiet;
  std::vector<std::vector<Point>> lines;
  {
    Slicer slicer(impl_->mesh, *impl_->tree);
    slicer(Kernel::Plane_3(to_point(point), Kernel::Vector_3(normal.x(), normal.y(), normal.z())),
           std::back_inserter(lines));
  }
  std::vector<SlicePolyline> out;
  out.reserve(lines.size());
  for (const std::vector<Point>& line : lines) {
    if (line.empty()) continue;
    SlicePolyline pl;
    pl.closed = line.size() > 2 && line.front() == line.back();
    const std::size_t count = pl.closed ? line.size() - 1 : line.size();
    pl.points.reserve(count);
    for (std::size_t i = 0; i < count; ++i) {
      pl.points.emplace_back(line[i].x(), line[i].y(), line[i].z());
    }
    out.push_back(std::move(pl));
  }
  return out;
}

}  // namespace sweep::fit
