#pragma once
// A generator of tube meshes with a known answer, for tests, examples and demos: the exact axis,
// frame and radius of every generated surface are available as functions, so a fitted sweep can be
// compared against the truth.
//
// Parametrisation (s = arc length along the axis, 0 <= s <= L = length; theta = polar angle):
//  - Axis: a circular arc in the x-z plane starting at the origin heading +z, turning by the total
//    angle `bend` (radians) towards +x (towards -x when bend < 0). With kappa = bend / L and
//    a = kappa * s:
//        axis(s)    = (2 sin^2(a/2) / kappa, 0, sin(a) / kappa)      ( = (0, 0, s) when bend = 0 )
//        tangent(s) = (sin a, 0, cos a)
//  - Frame (the rotation about +y by a, applied to x, y, z): u(s) = (cos a, 0, -sin a),
//    v(s) = (0, 1, 0), tangent = u x v. At s = 0 it is (x, y, z).
//  - Cross section: surface(theta, s) = axis(s) + radius(theta, s) (cos(theta) u + sin(theta) v).
//  - radius(theta, s) = root_radius * (1 + (taper - 1) s / L) * shape(theta), where shape is
//        circle:  1
//        ellipse: q / sqrt(q^2 cos^2(theta) + sin^2(theta))   (q = ellipse_ratio: the ellipse
//                 with semi-axis 1 along u and q along v, in polar form)
//        lobed:   1 + amplitude * cos(lobes * theta)
//
// Mesh layout (the vertex order tests rely on):
//  - ring i = 0 .. rings-1 at s_i = L i / (rings - 1); segment j = 0 .. segments-1 at
//    theta_j = 2 pi j / segments; vertex i * segments + j = surface(theta_j, s_i).
//  - with caps: vertex rings * segments = axis(0) (root centre), rings * segments + 1 = axis(L).
//  - vertex count = rings * segments + (caps ? 2 : 0).
//  - faces: the side quads (i,j) (i,j+1) (i+1,j+1) (i+1,j) for each i < rings-1 and j (j+1 taken
//    mod segments), ring by ring; then, with caps, the root fan (centre, (0,j+1), (0,j)) for each
//    j and the tip fan (centre, (rings-1,j), (rings-1,j+1)). All faces are oriented outwards.
//    face count = (rings - 1) * segments * (triangulate ? 2 : 1) + (caps ? 2 * segments : 0);
//    with triangulate each quad (a b c d) becomes (a b c) and (a c d).
#include <cstddef>

#include "sweep/core/mesh.h"

namespace sweep::tube {

enum class CrossSection { circle, ellipse, lobed };

struct TubeParams {
  double length = 1.0;  // arc length L of the axis, mesh units; > 0
  double radius = 0.1;  // cross-section scale at the root (s = 0), mesh units; > 0
  double taper = 1.0;   // tip scale / root scale, > 0; the scale is linear in s
  double bend = 0.0;    // total turning angle of the axis, radians; |bend| <= 2 pi
  CrossSection shape = CrossSection::circle;
  double ellipse_ratio = 0.6;   // ellipse: semi-axis along v / semi-axis along u, > 0
  int lobes = 5;                // lobed: number of lobes, >= 1
  double lobe_amplitude = 0.2;  // lobed: relative depth of the lobes, 0 <= amplitude < 1
  int rings = 33;               // cross sections along the axis, >= 2
  int segments = 24;            // vertices around each ring, >= 3
  bool caps = true;             // close both ends with a triangle fan to a centre vertex
  bool triangulate = false;     // split each side quad into two triangles
};

// Throws Error(usage) naming the sweep-tube option at fault (e.g. "--rings must be at least 2").
// Also rejects a bend so tight that the inner side of the tube would fold through the axis.
void check_params(const TubeParams& params);

struct AxisFrame {
  Vec3 point;    // axis(s)
  Vec3 tangent;  // unit tangent at s
  Vec3 u;        // unit, theta = 0 direction of the cross section
  Vec3 v;        // unit, theta = pi/2 direction; (u, v, tangent) is right-handed
};

Vec3 tube_axis_point(const TubeParams& params, double s);
Vec3 tube_axis_tangent(const TubeParams& params, double s);
AxisFrame tube_frame(const TubeParams& params, double s);
// Distance from axis(s) to the surface at polar angle theta in the cross-section plane.
double tube_radius(const TubeParams& params, double theta, double s);
Vec3 tube_surface_point(const TubeParams& params, double theta, double s);

double tube_ring_s(const TubeParams& params, int ring);            // s_i
double tube_segment_theta(const TubeParams& params, int segment);  // theta_j

std::size_t tube_vertex_count(const TubeParams& params);
std::size_t tube_face_count(const TubeParams& params);

// The mesh described above. Calls check_params first.
Mesh make_tube(const TubeParams& params);

}  // namespace sweep::tube
