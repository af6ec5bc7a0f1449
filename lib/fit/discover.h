#pragma once
// Finding a mesh's tubular parts without being told where they are (`sweep-fit --list`).
//
// Extremities are where the average surface distance to the rest of the mesh is locally largest
// (the tips of tails, legs, fingers, ears). The average is estimated from a few
// sources spread over the surface by farthest-point sampling. Each extremity, highest first, is
// then traced by rings of surface distance (fit/rings.h): where the rings keep a steady size for
// a few radii and then widen into the body, it is the tip of a part (where they only widen slowly
// and then split, as from a person's thigh into the hips, the part ends there if the first jump
// would leave it holding the body: fit/rings.h); the part's region is the surface nearer to the tip
// than that junction, and no later candidate inside it is traced again.
// On a body with separate shells (legs modelled apart and pushed into it), a smaller shell is
// traced from its end away from the body only, and a shell that is part of the body's core (an
// abdomen beside a thorax, the body shell itself traced end to end) is no part (discover.cpp).
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "sweep/core/topology.h"
#include "sweep/fit/rings.h"

namespace sweep::fit {

struct FoundPart;

struct DiscoverOptions {
  int samples = 24;         // farthest-point sources for the average distance
  int max_candidates = 48;  // extremities traced at most (highest average distance first)
  // A part is at least this many of its median radii long (tip to junction): a bump or a
  // nose is shorter.
  double min_aspect = 3;
  // ... and holds at most this share of the mesh's surface area (else it is the body itself;
  // area, not vertices, so that a finely meshed part is not taken for the body).
  double max_area_share = 0.5;
  // ... and is at least this share of the mesh's size (its bounding box's diagonal) long: a part
  // tiny against the figure (a finger of a whole figure, a low-polygon spike) is none a person
  // counts, nor one whose motion shows.
  double min_length_share = 0.05;
  // The up direction of the names (glTF and most tools: +Y); names only, never the geometry.
  Vec3 up = Vec3::UnitY();
  RingOptions rings;
  // When given, a part is offered only if this returns no reason against it (sweep-fit fits it, so
  // that no part is offered whose fit is then refused: fit/offered_parts.h); a part refused is
  // passed over with the reason, and its region is not searched again.
  std::function<std::string(const FoundPart&)> refuse;
};

struct FoundPart {
  std::string name;              // suggested: leg1, neck, tail, arm2, top1, part3 (see below)
  std::uint32_t tip_vertex = 0;  // the extremity: where the rings start
  Vec3 tip = Vec3::Zero();
  Vec3 root = Vec3::Zero();      // centroid of the junction ring: where the part meets the body
  double length = 0;             // surface distance from the tip to the junction ring
  double mean_radius = 0;        // median ring radius between the tip's cap and the junction
  std::size_t vertex_count = 0;  // vertices nearer to the tip than the junction ring
  std::string junction_reason;   // what ended the part
  double bottom = 0;             // the lowest height (along `up`) of its vertices: legs stand
};

// The mesh's tubular parts, longest first. Names are suggestions from where each part points
// (with `up`): down, reaching the lowest twentieth of the mesh (or steeply down, its lowest
// sixth), "leg"; rising, "neck"; across the body's long axis, or hanging on an upright body,
// "arm"; along it, "tail"; otherwise "part"; the body judged without what hangs past a part's end
// (a hand, a head); two parts that mirror each other across a vertical plane are a pair, of arms
// (not tails: a body has one) or, rising from the head, of horns; numbered when a name repeats
// (leg1 … leg4).
// Candidates traced and passed over are described in `passed_over` when given.
std::vector<FoundPart> find_parts(const Mesh& mesh, const Topology& topology, const DiscoverOptions& options = {},
                                  std::vector<std::string>* passed_over = nullptr);

}  // namespace sweep::fit
