// One of the two translation units that include CGAL (see slicer.h).
#include "fit/slicer.h"

#include "core/fp_environment.h"
#include "core/topology.h"

#include <CGAL/AABB_halfedge_graph_segment_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_slicer.h>
#include <CGAL/Surface_mesh.h>
#include <fenv.h>

#include <array>

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
    const auto face = sm.add_face(SurfaceMesh::Vertex_index(v[0]), SurfaceMesh::Vertex_index(v[1]),
                                  SurfaceMesh::Vertex_index(v[2]));
    if (face == SurfaceMesh::null_face()) rejected.push_back({v[0], v[1], v[2]});
  }
  if (!rejected.empty()) {
    // Rebuild from the whole soup: orienting it duplicates vertices at non-manifold places.
    impl_->repaired = rejected.size();
    std::vector<Point> points;
    points.reserve(positions.size());
    for (const Vec3& p : positions) points.push_back(to_point(p));
    std::vector<std::array<std::size_t, 3>> polygons;
    polygons.reserve(tris.size() / 3);
    for (std::size_t f = 0; f + 2 < tris.size(); f += 3) {
      if (tris[f] == tris[f + 1] || tris[f + 1] == tris[f + 2] || tris[f] == tris[f + 2]) continue;
      polygons.push_back({tris[f], tris[f + 1], tris[f + 2]});
    }
    CGAL::Polygon_mesh_processing::orient_polygon_soup(points, polygons);
    sm.clear();
    CGAL::Polygon_mesh_processing::polygon_soup_to_polygon_mesh(points, polygons, sm);
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
