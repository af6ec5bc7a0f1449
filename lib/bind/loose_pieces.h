#pragma once
// Loose pieces: shells of the mesh (pieces connected by edges, or vertices no face uses) that no
// part reaches over the surface but that lie against a part: a tuft of separate quads at a
// tail's tip, a claw modelled apart from its toe, a few foot vertices the file never welded. A
// part walked over the surface from its tip (select_sweep_part) leaves them behind, and they
// would hang in the air as the part moves; bind() gives each to the part it lies against, where
// sweep coordinates carry it: within the sweep it moves with the sweep, past the tip section
// rigidly with that section (z > 0), as the part's own cap does.
#include <cstdint>
#include <string>
#include <vector>

#include "sweep/core/mesh.h"
#include "sweep/core/rig.h"
#include "sweep/core/topology.h"

namespace sweep::bind {

// A piece goes with a part when its nearest vertex lies within this many of the sweep's mean
// radii of the part's nearest vertex, it lies wholly on the tip side of the root section's plane,
// and it is no larger across than the sweep is long (larger, it is the body, or something the
// part merely touches).
inline constexpr double kLooseReachRadii = 1;
// A piece within this many mean radii of a part, no larger than it, and not taken is named in a
// warning: it will not move with the part.
inline constexpr double kLooseNearRadii = 3;

struct LoosePiece {
  std::vector<std::uint32_t> vertices;  // ascending
  int sweep = -1;                       // the rig sweep it goes with; -1: left unbound (it is only next to `near`)
  int near = -1;                        // the sweep it lies nearest to
  double gap = 0;                       // from its nearest vertex to that part's nearest vertex, mesh units
  std::string why_unbound;              // for a piece left unbound
};

// The loose pieces next to the seeded sweeps' parts. `parts[i]` is sweep i's selected part
// (ascending; empty for a sweep without seeds, which has no loose pieces: it binds by geometry).
// A piece that holds a vertex of any part is not loose. Pieces come in the order of their lowest
// vertex.
std::vector<LoosePiece> find_loose_pieces(const Rig& rig, const Mesh& mesh, const Topology& topology,
                                          const std::vector<std::vector<std::uint32_t>>& parts);

// "a loose piece of 4 vertices (vertex 1021 at (0.1, 2, 0.3))", for messages.
std::string describe_piece(const LoosePiece& piece, const Mesh& mesh);

}  // namespace sweep::bind
