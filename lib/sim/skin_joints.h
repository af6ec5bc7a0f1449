#pragma once
// The joints of the skinned export (sweep-sim --joints: the skeleton the .glb's skin holds, in its
// order) posed live from the simulated sweeps, for an engine that skins on the GPU: it loads the
// exported mesh, weights and inverse bind matrices once, and each frame reads these joints' world
// matrices instead of the deformed positions.
//
// The skeleton, as the export lays it out: joint 0 the body; per sweep, N station joints at
// t_j = L·j/(N−1) carrying the deformed sweep's frame there (centre C'(t_j), rotation R'(t_j));
// with a ring (M ≥ 2), M ring joints around every station but the root, at φ_m = 2πm/M, children
// of their station joint, each an in-plane scale (ρ, ρ, 1) by the ratio of the deformed radius at
// (φ_m, t_j) to the rest one; without a ring (M = 1) the station joint carries the section's change
// itself, an in-plane scale per axis and a shift fitted by least squares to its radii. The poses are
// the export's, computed in double (the export writes them as float keys). The export's --ring-fit
// (ring joints fitted to the baked vertices) is not reproduced: a live frame has no bake to fit to;
// its ring joints are the sampled ones.
//
// Cost: a part whose radii never moved (no radial load has reached it) keeps its ring joints at
// their rest scale and only its N frames are evaluated. Allocation-free after construction.
#include <span>
#include <vector>

#include "sweep/core/frame.h"
#include "sweep/core/sweep_shape.h"

namespace sweep::sim {

struct SkinJointLayout {
  int stations = 24;  // joints along each sweep, ≥ 2 (--joints)
  int ring = 24;      // joints around each station but the root; 1 = none (--ring-joints)
};

class SkinJoints {
 public:
  // One rest shape per sweep, in the rig's order. Throws Error(usage) for a layout out of the
  // export's ranges (stations 2 … 255, ring 1 … 64).
  SkinJoints(std::span<const SweepShape* const> rests, const SkinJointLayout& layout);

  int joint_count() const { return joint_count_; }
  const SkinJointLayout& layout() const { return layout_; }

  // Poses sweep s's joints from its deformed shape (the body's frame). `radii_moved` false: its
  // radii are the rest ones (ElasticSweep::radial_active() false), and its ring joints' work is
  // skipped.
  void pose(int sweep, const SweepShape& shape, bool radii_moved);
  // Every joint's world matrix (world = body · joint, column-major, 16 floats a joint) into `out`
  // (16·joint_count() floats).
  void world_matrices(const Frame& body, std::span<float> out) const;

 private:
  struct Station {
    double t = 0;
    int span = 0;  // of the rest shape's key sections (as radius_at locates it)
    double u = 0;
    double h00 = 0, h10 = 0, h01 = 0, h11 = 0;  // HermiteBasis(u)
  };
  struct Ring {  // a ring angle φ_m in the sweep's angle cells
    int cell = 0;
    double w = 0;
  };
  struct Sweep {
    double length = 0;
    std::vector<Station> stations;
    std::vector<Ring> rings;                     // M
    std::vector<double> rest_ring;               // (N − 1)·M: radius at (φ_m, t_j) at rest
    std::vector<double> rest_radii;              // N·n: without a ring, the rest radii at each station
    std::vector<Frame> frames;                   // N: this frame's station frames
    std::vector<double> in_plane;                // N·4: without a ring, a, b, c_x, c_y
    std::vector<double> ring_scale;              // (N − 1)·M: this frame's ρ
    std::vector<double> cell_value, cell_floor;  // scratch: K·M cell values at each φ_m, their floors
    std::vector<double> radii;                   // scratch: n
    std::vector<double> cos_sample, sin_sample;  // n: of the sample angles θ_j
  };
  SkinJointLayout layout_;
  int joint_count_ = 1;
  std::vector<const SweepShape*> rests_;
  std::vector<Sweep> sweeps_;
};

}  // namespace sweep::sim
