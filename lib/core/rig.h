#pragma once
// The rig: one mesh and the sweeps fitted to its deformable parts. Plain data, as read from and
// written to the rig file (lib/io/rig_json.h); the runtime is ElasticSweep (core/elastic_sweep.h).
#include <optional>
#include <string>
#include <vector>

#include "sweep/core/material.h"
#include "sweep/core/springs.h"
#include "sweep/core/sweep_shape.h"
#include "sweep/core/topology.h"

namespace sweep {

// How the part a sweep drives was picked out of the mesh (sweep-fit writes it, sweep-bind uses it
// to select the same vertices): the region on the tip side of section 0's plane that is reached
// from the tip point without crossing that plane (the paper's §III). A stretch of a tube that goes on
// past the tip (a hose, a knot, a torus: tip_cut) is bounded on the tip side too, by the last key
// section's plane and disc (tip_disc_radius); nothing beyond it is part of the part.
struct PartSeeds {
  Vec3 root = Vec3::Zero();  // where the part leaves the body, near its axis
  Vec3 tip = Vec3::Zero();   // at or near the part's end
  bool tip_cut = false;      // the surface goes on past the last key section: cut it there too
};

struct SweepDef {
  std::string name;                        // unique within the rig, e.g. "tail"
  SweepShape rest;                         // key sections in the rest pose (world space)
  std::vector<std::string> section_names;  // K entries; "" where a section has no name
  SectionSprings default_springs;          // the sweep's springs ...
  std::vector<SectionSprings> springs;     // ... resolved per section (K entries, overrides applied)
  // Force scale factors of the paper (§2.3): torque = rotational_scale · |f| (N·m per N, i.e. a
  // lever arm in mesh units); radial handle force = radial_scale · (inward part of f).
  double rotational_scale = 1.0;
  double radial_scale = 1.0;
  std::optional<PartSeeds> part;  // absent for rigs written by hand with no mesh part
  // Material mode: when set, the sections are one coupled chain whose bending and
  // twisting stiffness, masses and inertias follow from this material and each section's polygon
  // (core/chain_model.h); `springs` then only sets the radial handles. Empty = the paper's
  // independent springs.
  std::optional<Material> material;
  std::vector<Material> section_materials;  // K entries when `material` is set (overrides applied)

  int section_index(const std::string& section_name) const;  // -1 when there is none
};

struct Rig {
  // Version 1: every rig without a tip cut or a mesh name (written as version 1, byte for byte as
  // before). Version 2 adds part.tip_cut; version 3 mesh_name. A rig is written with the lowest
  // version that holds what it has.
  static constexpr int kFormatVersion = 1;
  static constexpr int kTipCutFormatVersion = 2;
  static constexpr int kMeshNameFormatVersion = 3;
  int format_version() const;  // the version format_rig writes for this rig
  std::string mesh;            // mesh path as written in the file (relative to the rig file)
  // The mesh of that file the rig belongs to: its node's name (assets/mesh_io.h, read_scene_mesh);
  // "" = the whole file, every mesh in it (rigs before version 3, and files of one nameless mesh).
  std::string mesh_name;
  std::vector<SweepDef> sweeps;
  // The file's "scene" member as compact JSON text ("" when it has none): not the rig's business,
  // but kept so that rewriting the rig (sweep-fit adding a sweep) does not drop it.
  std::string scene_json;

  const SweepDef* find(const std::string& sweep_name) const;
};

// A sweep with K sections and n radii, all springs at their defaults: the way tools and tests make
// one before filling in the geometry.
SweepDef make_sweep(std::string name, SweepShape rest);

// The root section a part may not be crossed through, as select_part (core/topology.h) takes it:
// section 0's plane, and a disc of kRootDiscRadii times its largest radius (the slice loop's
// crossings lie within its largest ray; the margin takes edges that cross the plane just outside).
inline constexpr double kRootDiscRadii = 1.5;
double root_disc_radius(const SweepShape& rest);
// The tip-side cut of a part with PartSeeds::tip_cut: the last key section's plane, and a disc of
// kRootDiscRadii times that section's largest radius.
double tip_disc_radius(const SweepShape& rest);

// The part `seeds` pick out of the mesh for a sweep of shape `rest` (what sweep-fit and sweep-bind
// both select): select_part from the tip bounded by the root disc, or with seeds.tip_cut
// select_part_between the root and tip discs; either way only through vertices near the sweep:
// between its end sections, at most kPartReachRadii local radii from the axis (before the root
// section, as far behind it too; past the tip section, anything: a foot, a head, a tuft). The
// surface of a part that touches another mid-length (a trunk against a tusk) then stops a few
// radii into the other instead of flooding through it into the body.
inline constexpr double kPartReachRadii = 1.5;
// What lies beyond that bound is the part's own protrusion (a claw, a spike, a fin: carried along,
// not measured) when it stays within kProtrusionReachRadii local radii of where it leaves the
// bound; a region that reaches farther (a tusk into the head, a hand the arm lies against, a
// shoulder) is something else the part touches, and stays out.
inline constexpr double kProtrusionReachRadii = 3;
// Where such a bridge is fused to the part (a tusk against the trunk, along a seam), its foot
// lies inside the bound: part vertices farther than kBridgeFootRadii local radii off the sweep's
// surface, reached from a bridge through such vertices, go with the bridge. (Only from a bridge:
// a part the sweep misses elsewhere must still show in the fit error, not be cut away.)
inline constexpr double kBridgeFootRadii = 0.25;
// Outwards, "off the surface" is measured against the radii without their narrow lobes
// (without_narrow_lobes): a tusk fused alongside the trunk makes a lobe of the sections towards
// it, which radii fitted to a part that still holds the tusk's foot follow.
// A section's radii with each sample that has an outward turn of the section's outline (a reflex
// corner, turning out by more than asin kLobeBaseTurn ≈ 3°) within kLobeWindowDegrees of it
// lowered to the median of the samples in that window (never raised): a lobe at most half that
// wide, pinched at its base, is cut off (at n = 24, 30°: two samples either side, a lobe of up to
// two samples). A convex section — a circle, an ellipse or a strip however flat, at any sample
// count — is kept whole (the median alone cut the tips of a 2:1 ellipse at 12 samples; the
// measured choice is in docs/findings.md, "Fitting real parts").
inline constexpr double kLobeWindowDegrees = 30;
inline constexpr double kLobeBaseTurn = 0.05;
SweepShape without_narrow_lobes(const SweepShape& rest);
std::vector<std::uint32_t> select_sweep_part(const Mesh& mesh, const Topology& topology, const SweepShape& rest,
                                             const PartSeeds& seeds);

}  // namespace sweep
