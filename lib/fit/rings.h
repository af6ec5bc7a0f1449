#pragma once
// A part's axis from rings of equal surface distance from its tip. Level sets of the
// distance from the tip's vertex run around the part whatever its curl or elbow; their centroids
// are axis points, and their size, which changes slowly along a tube, jumps where the part meets
// the body: that is the root when the user gives none.
#include <cstdint>
#include <string>
#include <vector>

#include "sweep/fit/geodesic.h"

namespace sweep::fit {

struct RingOptions {
  // Level spacing as a fraction of the mesh's median edge length: finer gives more rings per
  // radius (smoother size curve), coarser fewer loops to chain.
  double spacing_edges = 0.5;
  // The ring size's growth over the last local radius of distance, d(radius)/d(distance): a tube
  // tapers slowly (a tail: < 0.15); a ring spreading over the body grows at 0.5 to 1. The trace
  // counts the part as begun once growth falls below `settled_growth` (past the tip's cap, where
  // rings grow fast too), finds the body where growth next exceeds `junction_growth`, and puts
  // the junction back where that rise began: the last ring that grew by at most `knee_growth`.
  double settled_growth = 0.3;
  double junction_growth = 0.4;
  double knee_growth = 0.2;
  // A rise that begins within `blob_reach` radii of the tip and narrows again to
  // `blob_narrowing` times its peak within `blob_radii` peak radii, without the level set
  // splitting on the way, is a blob at the end of the part (a hoof's pad past a toe), not the
  // body: the body comes after a long part, and its level sets split into the other parts as
  // they pass it; a head or a hand, the tip's own cap, is passed before the trace settles.
  double blob_reach = 4;
  double blob_narrowing = 0.8;
  double blob_radii = 2;
  // A gentler rise (growth past settled_growth, never past junction_growth) where the rings widen
  // to this many times the tube's size before the level set splits (within blob_radii peak radii)
  // into other parts, after a part blob_reach of those widest radii long, is where the part meets
  // the body when the first jump past it would leave the part holding more than body_area_share of
  // the surface (the body itself): a person's leg, whose thigh widens slowly into the hips and
  // whose rings part there round the other leg and the torso, and jump nowhere before the far
  // side of the body. (Elsewhere such a rise is no body: a foot's tube meeting its leg.)
  double gentle_widening = 1.5;
  double body_area_share = 0.5;
};

struct Ring {
  double distance = 0;           // the level: surface distance from the tip vertex, mesh units
  Vec3 centroid = Vec3::Zero();  // length-weighted centroid of the loop
  double radius = 0;             // √(area/π) of the loop, mesh units
  double growth = 0;             // d(radius)/d(distance) over the last local radius
  bool closed = true;            // false: the loop runs into a hole of the mesh
  bool split = false;            // the level also holds another loop of comparable length
  double area_share = 0;         // the share of the mesh's surface nearer to the tip than this level
};

struct RingTrace {
  std::uint32_t tip_vertex = 0;
  std::vector<Ring> rings;  // from the tip outwards, one per level
  // Index of the last ring of the part proper: the ring before the size jump or split, or the
  // last ring there is (the whole mesh is one tube). -1 when no ring was found.
  int junction = -1;
  std::string junction_reason;  // what ended the part ("the ring size jumps ...", ...)
};

// Rings from `tip_vertex` up to `stop_distance` (mesh units) or the end of the surface; with
// `find_junction`, `junction` is then placed by locate_junction.
RingTrace trace_rings(const Mesh& mesh, const Topology& topology, const std::vector<double>& distance_from_tip,
                      std::uint32_t tip_vertex, double stop_distance, bool find_junction,
                      const RingOptions& options = {});

// Where the part meets the body along rings from its tip: the first rise of the ring size past
// the tip's cap (growth above junction_growth) that does not narrow again; the junction is the
// ring where that rise began. Without one, the last ring. Where the part up to there would hold the
// body, a gentler rise into a split before it (RingOptions::gentle_widening).
void locate_junction(RingTrace& trace, const RingOptions& options = {});

// The vertex where `field` is locally largest, reached from `start` by steepest ascent over the
// mesh's edges (representatives of the weld). Used to move a tip clicked near a part's end to
// the end itself: the surface distance from the body is largest there.
std::uint32_t climb(const Topology& topology, const std::vector<double>& field, std::uint32_t start);

// Median edge length of the mesh (over welded edges), mesh units; 0 for a mesh without edges.
double median_edge_length(const Mesh& mesh, const Topology& topology);

}  // namespace sweep::fit
