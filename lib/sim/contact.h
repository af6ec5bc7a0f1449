#pragma once
// Contact between one sweep and the scene's colliders, resolved after every step of the
// springs and continuously in time: a part cannot step over a thin collider, however fast it moves.
//
// The part's surface is taken as its axis, cut into chords (`stations_per_span` per span between
// key sections, not sample points: a thin collider between two stations is still met by the
// chord), each end carrying its section's reach toward the collider (section_support, below). At
// the start of a step, each chord near a collider gets the plane that separates it from the
// collider there: the tangent plane at the collider's point nearest the chord (or, for a chord
// already inside, out through the nearest face). A convex collider lies wholly on one side of that
// plane, so a chord whose two ends end the step on the free side, by their reach and the margin,
// cannot have crossed the collider on its way (the speculative contacts of game physics). What is
// held is the chords' ends; between them the curve may sag toward a collider by its bend over a
// chord (the tests measure the true surface: at most 1e-3 of the length, 0 in the fast swing into
// a plate). The contacts of a step are solved together, as the complementarity problem they are
// (a push ≥ 0 only where the gap closes; projected Gauss–Seidel on the couplings of the contact
// rows, core/contact_rows_detail.h), so that pushes do not fight and lift the part off elsewhere:
// first the ends are moved back onto their planes through the springs (as the step would have moved
// them with the force in it, each spring or mode by 1/(m/dt² + c/dt + k): by its inertia over a
// short step, its compliance over a long one; the speeds by the same move over dt; the true curve
// re-measured and the solve repeated, up to 16 times), then the approach speeds are taken out by
// impulses (by the masses: inelastic), then the sliding speeds by friction (Coulomb, all contacts
// together: projected Gauss–Seidel over two rows across each normal, each contact's impulse held in
// its cone |λ| ≤ μ N·dt, each update lowering the kinetic energy relative to the colliders, so
// friction never adds any). N·dt is read two ways, each contact taking the larger: the impulses
// that would change the points' normal speeds as the move and the kicks did (a hit, a soft part
// falling each step), and the force that holds the springs off where the loads alone would hold
// them (a stiff part resting), times dt. The friction acts at the section's centre (no roll), on
// positions first (contact_stick.cpp: a station held at an anchor on its collider while the
// springs' force across the normal stays within μN — neighbouring stations on one collider
// sharing their cones —, slid to where it is μN if not — a steady slide drags by μN at any step,
// tests/sim/friction_test.cpp), then on the speeds with what is left of
// each cone (the first step of a contact, and the directions the springs barely move). Where
// nothing touches, nothing is done: the springs keep their exact integration.
//
// What it costs: a sweep far from every collider (its bounding sphere clear of the collider at the
// step's two ends and on its way between them) costs two distances per collider; then each span, then each chord near a
// collider one more; contacts are solved only when a chord end comes within its reach of a plane.
// Friction held on positions adds, for the pairs held, J C Jᵀ over their rows and the normal ones
// and an eigensolve of its 2m × 2m tangential block (~1.1× the frame of a tail lying on a floor).
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "sweep/core/elastic_sweep.h"
#include "sweep/core/rig.h"
#include "sweep/sim/collider.h"

namespace sweep::sim {

// A collider placed in the sweep's (the mesh's) coordinates at one time: local → mesh.
struct PlacedCollider {
  const Collider* collider = nullptr;
  Frame to_mesh;
};

// How far the section at t reaches in the unit direction `direction` from its centre: the largest
// of its radius samples' projections and of the radius toward that direction (exact for a round
// section), times the share of `direction` across the axis.
// `scratch` holds the radii there and the samples' cos θ_j, sin θ_j (filled once per sample count).
struct SupportScratch {
  std::vector<double> radii, cos, sin;
};
double section_support(const SweepShape& shape, double t, const Vec3& direction, SupportScratch& scratch);

// Signed clearance of the sweep's surface from a collider over the axis stations (negative: a
// penetration), with the station parameter of the worst one (the tests' and warnings' measure).
struct Clearance {
  double gap = 0;
  double t = 0;
};
Clearance clearance(const SweepShape& shape, const PlacedCollider& placed, int stations_per_span);

// Colliders that cut a part's surface in its rest pose at time 0 (the part is pushed out on its
// first step: rarely what a user meant), one message each naming both and how deep.
std::vector<std::string> rest_pose_overlaps(const Rig& rig, const std::vector<Collider>& colliders,
                                            const Frame& body_at_start, int stations_per_span);

// How far a point (mesh coordinates) lies outside every part's rest surface, less `margin`
// (negative inside one; infinity for a rig of no part): the largest sphere about it that the rest
// pose leaves clear, by the same measure as rest_pose_overlaps (the body proxy fills the body with
// such spheres, assets/body_proxy.h).
double rest_room(const Rig& rig, const Vec3& point, double margin, int stations_per_span);

class ContactSolver {
 public:
  // The stick anchors (contact_stick.cpp) are state carried from step to step. A throwaway step —
  // the frame view's partial step, from the body's state — runs between save_anchors and
  // restore_anchors, so that the output frame rate does not move them; a teleport forgets them
  // (the part is put to rest in the new place, not dragged back towards its old contacts).
  struct Anchor {
    Vec3 local = Vec3::Zero();  // the station's centre, collider coordinates
    long step = -2;             // the last step (step_) the contact touched
  };
  struct AnchorMemo {
    long step = 0;
    std::vector<Anchor> anchors;
  };
  void save_anchors(AnchorMemo& memo) const {
    memo.step = step_;
    memo.anchors.assign(anchors_.begin(), anchors_.end());  // no allocation once sized
  }
  void restore_anchors(const AnchorMemo& memo) {
    step_ = memo.step;
    anchors_.assign(memo.anchors.begin(), memo.anchors.end());
  }
  void forget_anchors() { anchors_.clear(); }
  static constexpr int kDefaultStationsPerSpan = 2;  // = Scene::contact_stations by default
  ContactSolver(const SweepShape& rest, int stations_per_span = kDefaultStationsPerSpan);
  ContactSolver(ContactSolver&&) noexcept;
  ContactSolver& operator=(ContactSolver&&) noexcept;
  ~ContactSolver();

  // Whether a collider at `from` or `to` (its places at two times, in the part's coordinates) may
  // reach the part in `shape` in between: a sleeping part a world collider comes at must wake.
  bool may_reach(const SweepShape& shape, std::span<const PlacedCollider> from,
                 std::span<const PlacedCollider> to) const;

  // Whether a collider at `from` or `to` is within the part's reach — where its springs could take
  // it from its root (Simulator cuts a long step into pieces of Scene::contact_step there).
  bool within_reach(const ElasticSweep& sweep, std::span<const PlacedCollider> from,
                    std::span<const PlacedCollider> to) const;
  // Into how many pieces a step within reach must be cut for no collider to move against the part
  // farther than its thinnest section's reach in one (a body keyed to move very fast: Simulator
  // cuts the step into at least the ceiling of this).
  double pieces_for_move(const ElasticSweep& sweep, std::span<const PlacedCollider> from,
                         std::span<const PlacedCollider> to) const;

  // Before a step: where the axis is, and where each collider is at the step's start.
  void begin_step(const ElasticSweep& sweep, std::span<const PlacedCollider> colliders);
  // After the step (`dt` s long), colliders where they are at its end: pushes the part out and
  // takes out its approach and sliding speeds. Returns whether any part of it touches.
  bool resolve(ElasticSweep& sweep, std::span<const PlacedCollider> colliders, double dt);

 private:
  struct Plane {  // in the collider's local coordinates
    int station = 0;
    std::size_t collider = 0;
    Vec3 normal, point;
    double margin = 0;
  };
  double gap(const ElasticSweep& sweep, const Plane& plane, const PlacedCollider& placed);
  // The speed (mesh coordinates) of collider c's point now at `here`, over the step.
  Vec3 collider_velocity(std::size_t c, const PlacedCollider& placed, const Vec3& here, double dt) const;
  // Projected Gauss–Seidel for amounts a ≥ 0 with r + W a ≥ 0, a·(r + W a) = 0, starting from and
  // keeping `total` + a ≥ 0 (a may take back part of what earlier solves pushed).
  void solve(const Eigen::MatrixXd& w, const std::vector<double>& r, const std::vector<double>& total,
             std::vector<double>& a);

  struct Bound {
    Vec3 centre = Vec3::Zero();
    double radius = 0;
  };
  Bound bound(const SweepShape& shape) const;
  static bool near(const Bound& b, const PlacedCollider& placed);
  // Whether the bound, carried straight (in the collider's frame) from `before` in the collider
  // at `start` to `after` in `placed`, comes within reach of it on the way: the step's broad
  // phase, which the ends alone are not (a part moving farther than its size in one step).
  static bool passes_near(const Bound& before, const Frame& start, const Bound& after, const PlacedCollider& placed);
  // Whether any collider, at `from` or `to`, comes within the bound, grown by how far the collider
  // moves in between (moved_only: only those that move at all).
  static bool meets(const Bound& b, std::span<const PlacedCollider> from, std::span<const PlacedCollider> to,
                    bool moved_only);

  int per_span_ = 1;
  std::vector<double> stations_;   // axis parameters of the chords' ends
  SweepShape start_shape_;         // the part at the step's start
  double longest_span_ = 0;        // between two key sections
  double smallest_reach_ = 0;      // the thinnest rest section's largest radius
  std::vector<Vec3> start_, end_;  // their points at the step's start and end (mesh coordinates)
  std::vector<Frame> start_pose_;  // each collider's local → mesh at the step's start
  std::vector<Plane> planes_;
  // The contact rows (core/contact_rows_detail.h) and their couplings, behind a pointer: the rows
  // are the solver's own business, not the installed headers' (sim/contact_detail.h).
  struct RowWork;
  std::unique_ptr<RowWork> work_;
  std::vector<double> move_speed_;  // the move's change of each row's speed
  std::vector<double> residual_, amount_, total_, coupled_;
  std::vector<double> pressed_, held_, none_;  // normal impulses; forces; zeros
  SupportScratch support_;
  std::vector<char> evaluated_;     // whether start_/end_ hold station s this step
  std::vector<double> span_reach_;  // each span's largest radius over the step
  // Friction: the slip speeds of the two rows across each pressed contact's normal (RowWork::slide),
  // each contact's cone radius μN, the impulses.
  std::vector<double> slip_, cone_, friction_, friction_w_;
  void solve_friction(const ElasticSweep& sweep, std::size_t contacts);
  // resolve()'s stages, in order: the broad phase; each span's reach over the step; the planes
  // separating each chord near a collider from it at the step's start; whether any station may
  // touch its plane (gaps measured into residual_; `length` the part's at the step's end, before
  // the push); the contact rows and their couplings; the
  // push back onto the planes; the approach speeds taken out (false: nothing touches); the normal
  // impulses N·dt friction is bounded by; the sliding speeds' friction.
  bool any_passes_near(const Bound& before, const Bound& after, std::span<const PlacedCollider> colliders) const;
  void measure_span_reach(const SweepShape& shape);
  void collect_planes(const SweepShape& shape, std::span<const PlacedCollider> colliders, const Bound& before,
                      const Bound& after);
  bool may_touch(const ElasticSweep& sweep, std::span<const PlacedCollider> colliders, double length);
  void build_rows(ElasticSweep& sweep, std::span<const PlacedCollider> colliders, double dt);
  void push_out(ElasticSweep& sweep, std::span<const PlacedCollider> colliders, double dt);
  bool stop_approach(ElasticSweep& sweep, std::span<const PlacedCollider> colliders, double dt, double length);
  void measure_normal_impulses(const ElasticSweep& sweep, double dt);
  void slide(ElasticSweep& sweep, std::span<const PlacedCollider> colliders, double dt);
  // The move's rounds: the ends back onto their planes through the springs, `total` the forces so
  // far (residual_ already holding the gaps when `measured`).
  void move_out(ElasticSweep& sweep, std::span<const PlacedCollider> colliders, double dt, std::vector<double>& total,
                bool measured);

  // Static friction on positions (contact_stick.cpp): each pressed contact's station is held at
  // its anchor — where it last started touching or last slid to, in its collider's coordinates —
  // while the springs' force across the normal stays within μN, slid to where it is μN if not.
  void hold(ElasticSweep& sweep, std::span<const PlacedCollider> colliders, double dt);
  struct Held {
    std::size_t plane = 0;  // the first pressed plane of the station and collider
    std::size_t anchor = 0;
    double cone = 0;  // μN, N summed over the pair's pressed planes, N
  };
  long step_ = 0;
  std::vector<Anchor> anchors_;  // collider · stations + station
  std::vector<Held> held_pairs_;
  std::vector<double> spent_;  // per plane: the friction impulse (N·s) the hold took of its cone
  std::vector<double> stick_amount_, repush_;
};

}  // namespace sweep::sim
