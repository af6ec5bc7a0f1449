#pragma once
// An external force at a surface point, split as the paper does (§III, Figs. 2–3) into loads on the
// key sections' springs: a rotational part (torque about normalize(a × f)), a radial part (the
// inward push in the cross-sectional plane, spread bilinearly over the four nearest radial
// handles), and an optional positional part (spread over the two sections around the point).
#include <array>
#include <cstdint>
#include <vector>

#include "sweep/core/sweep_shape.h"

namespace sweep {

enum ForceComponent : std::uint8_t {
  kRotational = 1 << 0,
  kRadial = 1 << 1,
  kPositional = 1 << 2,
};
inline constexpr std::uint8_t kPaperComponents = kRotational | kRadial;  // the paper's pair

// Which sections take the rotational part.
enum class RotationTarget {
  nearest,  // the key section nearest the point in t (never the fixed root section 0)
  section,  // one named section
  chain,    // every section between the root and the point: a push at the tip bends the whole part
};

// How big the torque is.
enum class MomentModel {
  scaled,    // the paper: C_rot·|f| about normalize(a × f)
  physical,  // the bending moment a beam feels: a × f itself (C_rot is not used)
};

// The axes the force vector is given in.
enum class VectorFrame {
  world,    // world axes
  surface,  // at the point: (outward in the cross-section plane, tangential towards growing θ,
            // along the axis towards the tip) — [-1,0,0] squeezes, [0,1,0] twists, whatever the pose
};

struct ForceSpec {
  // Where: at sweep parameters (t, θ) on the surface, or at a world point projected to the surface
  // when the force is added (it then keeps those parameters and follows the surface).
  bool at_world_point = false;
  Vec3 point = Vec3::Zero();
  double t = 0;
  double theta = 0;

  Vec3 vector = Vec3::Zero();  // the force (N), in `frame`'s axes
  VectorFrame frame = VectorFrame::world;
  std::uint8_t components = kPaperComponents;
  RotationTarget target = RotationTarget::nearest;
  int target_section = -1;  // with RotationTarget::section
  MomentModel moment = MomentModel::scaled;
};

// Loads on one sweep's springs, in world space, as the force sources produce them. Converting to
// each section's spring frame is the runtime's job (ElasticSweep).
struct SectionLoads {
  std::vector<Vec3> force;     // K: on each section's positional spring
  std::vector<Vec3> torque;    // K: on each section's rotational spring
  std::vector<double> radial;  // K·n: on each radial handle, positive = outward (radius grows)

  void resize(int sections, int radial_count);
  void clear();
};

// --- The pieces of the split, each testable by hand --------------------------------------------

// Torque of the rotational part about the section centre `center`: C_rot·|f|·normalize(a × f) with
// a = p − center (scaled model) or a × f (physical model). Zero when a × f vanishes.
Vec3 rotational_torque(const Vec3& p, const Vec3& center, const Vec3& f, double c_rot, MomentModel model);

// The paper's f_rad = C_rad·⟨op, p̂p⟩/|op| for the cross-sectional plane through p with origin o and
// unit normal `normal`; p̂ is p moved by f's projection onto that plane. Positive = pushing inward.
double radial_force(const Vec3& p, const Vec3& o, const Vec3& normal, const Vec3& f, double c_rad);

// Bilinear weights of the four handles around a point at span coordinate u and angle coordinate w:
// {(i, j), (i, j+1), (i+1, j), (i+1, j+1)}. Each corner gets the area of the opposite sub-rectangle.
std::array<double, 4> bilinear_weights(double u, double w);

// Adds the loads of one force, acting at parameters (t, θ) of the current shape, to `loads`.
// Section 0 is the root, fixed to the body: it takes no load.
void accumulate_force(const SweepShape& shape, const ForceSpec& force, double t, double theta, double c_rot,
                      double c_rad, SectionLoads& loads);

}  // namespace sweep
