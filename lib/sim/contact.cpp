#include "sweep/sim/contact.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "sweep/core/sweep_shape.h"
#include "sweep/sim/contact_detail.h"

namespace sweep::sim {
namespace {

// Gauss–Seidel passes over a step's contacts, and the gap (× the part's length) they must reach.
constexpr int kPasses = 64;
// A projected Gauss–Seidel solve stops when a pass changes no residual by more than this share of
// the largest residual it started from.
constexpr double kSolveTolerance = 1e-6;
// Solves per step: each moves the part by the linear model, then the true curve is re-measured.
constexpr int kRounds = 16;
constexpr double kGapTolerance = 1e-7;
// A contact whose gap is within this (× the length) after the pushes is touching: its approach
// speed is taken out even if this step's motion did not push it.
constexpr double kTouchSlack = 1e-7;
// A friction block (a contact's two rows across its normal) is solved as a 2 × 2 system when its
// determinant is above this share of its trace²; else row by row (a point one row cannot move).
constexpr double kBlockConditioning = 1e-12;
// Pieces of a step shorter than this (s) move nothing worth a speed: no collider speed, no friction.
constexpr double kShortestPiece = 1e-9;

// The point of segment [a, b] nearest the convex collider (its signed distance is convex along
// the segment: golden-section search to a 1e-9 of the segment).
Vec3 nearest_on_segment(const Collider& c, const Vec3& a, const Vec3& b) {
  Vec3 out;
  if (c.shape == ColliderShape::plane) return c.local_distance(a, &out) <= c.local_distance(b, &out) ? a : b;
  constexpr double kInvPhi = 0.6180339887498949;
  double lo = 0, hi = 1;
  double x1 = hi - kInvPhi * (hi - lo), x2 = lo + kInvPhi * (hi - lo);
  double f1 = c.local_distance(a + x1 * (b - a), &out), f2 = c.local_distance(a + x2 * (b - a), &out);
  for (int it = 0; it < 44 && hi - lo > 1e-9; ++it) {
    if (f1 <= f2) {
      hi = x2, x2 = x1, f2 = f1;
      x1 = hi - kInvPhi * (hi - lo);
      f1 = c.local_distance(a + x1 * (b - a), &out);
    } else {
      lo = x1, x1 = x2, f1 = f2;
      x2 = lo + kInvPhi * (hi - lo);
      f2 = c.local_distance(a + x2 * (b - a), &out);
    }
  }
  const double s = 0.5 * (lo + hi);
  // The ends too: a minimum at an end is reached only to the bracket's width otherwise.
  const double fa = c.local_distance(a, &out), fb = c.local_distance(b, &out),
               fs = c.local_distance(a + s * (b - a), &out);
  if (fa <= fs && fa <= fb) return a;
  if (fb <= fs) return b;
  return a + s * (b - a);
}

// The smallest sphere about the mean of the points that holds them all, grown by `grow`: whether
// it stays clear of the collider (its signed distance is 1-Lipschitz).
bool clear_of(const Collider& c, std::span<const Vec3> points, double grow) {
  Vec3 centre = Vec3::Zero();
  for (const Vec3& p : points) centre += p;
  centre /= static_cast<double>(points.size());
  double radius = 0;
  for (const Vec3& p : points) radius = std::max(radius, (p - centre).norm());
  Vec3 out;
  return c.local_distance(centre, &out) > radius + grow;
}

double largest_radius(const SweepShape& shape) {
  return shape.radii.empty() ? 0.0 : *std::max_element(shape.radii.begin(), shape.radii.end());
}

}  // namespace

double section_support(const SweepShape& shape, double t, const Vec3& direction, SupportScratch& scratch) {
  const Vec3 local = rotation_at(shape, t).conjugate() * direction;
  const double across = std::hypot(local.x(), local.y());
  if (!(across > 0)) return 0;
  const int n = shape.radial_count;
  const std::size_t count = static_cast<std::size_t>(n);
  if (scratch.cos.size() != count) {
    scratch.cos.resize(count);
    scratch.sin.resize(count);
    for (int j = 0; j < n; ++j) {
      scratch.cos[j] = std::cos(shape.sample_angle(j));
      scratch.sin[j] = std::sin(shape.sample_angle(j));
    }
  }
  scratch.radii.resize(count);
  radii_at_samples(shape, t, scratch.radii);
  double reach = radius_at(shape, std::atan2(local.y(), local.x()), t) * across;
  for (std::size_t j = 0; j < count; ++j) {
    reach = std::max(reach, scratch.radii[j] * (scratch.cos[j] * local.x() + scratch.sin[j] * local.y()));
  }
  return reach;
}

Clearance clearance(const SweepShape& shape, const PlacedCollider& placed, int stations_per_span) {
  const std::vector<double> t = station_parameters(shape, stations_per_span);
  SupportScratch scratch;
  Clearance worst{std::numeric_limits<double>::infinity(), 0};
  const Collider& c = *placed.collider;
  for (std::size_t s = 0; s + 1 < t.size(); ++s) {
    const Vec3 a = placed.to_mesh.to_local(center_at(shape, t[s]));
    const Vec3 b = placed.to_mesh.to_local(center_at(shape, t[s + 1]));
    const Vec3 x = nearest_on_segment(c, a, b);
    Vec3 out;
    const double d = c.local_distance(x, &out);
    const double u = (b - a).squaredNorm() > 0 ? std::clamp((x - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0) : 0.0;
    const double ts = t[s] + u * (t[s + 1] - t[s]);
    const double gap = d - section_support(shape, ts, -(placed.to_mesh.rotation * out), scratch) - c.margin;
    if (gap < worst.gap) worst = {gap, ts};
  }
  return worst;
}

std::vector<std::string> rest_pose_overlaps(const Rig& rig, const std::vector<Collider>& colliders,
                                            const Frame& body_at_start, int stations_per_span) {
  std::vector<std::string> out;
  const Frame world_to_mesh = body_at_start.inverse();
  for (const SweepDef& def : rig.sweeps) {
    for (const Collider& c : colliders) {
      const PlacedCollider placed{&c, c.carried ? c.pose : world_to_mesh * c.pose};
      const Clearance cl = clearance(def.rest, placed, stations_per_span);
      if (cl.gap >= 0) continue;
      std::ostringstream msg;
      msg << "collider \"" << c.name << "\" (a " << shape_name(c.shape) << ") cuts sweep \"" << def.name
          << "\" in its rest pose, " << -cl.gap << " deep at " << cl.t / def.rest.length()
          << " of its length (margin included): the part is pushed out when it is first stepped";
      out.push_back(msg.str());
    }
  }
  return out;
}

double rest_room(const Rig& rig, const Vec3& point, double margin, int stations_per_span) {
  // A sphere's clearance is its centre's less its radius wherever the nearest station is, so a
  // unit sphere's clearance + 1 is the centre's own.
  Collider probe = Collider::sphere(point, 1.0);
  probe.margin = margin;
  const PlacedCollider placed{&probe, probe.pose};
  double room = std::numeric_limits<double>::infinity();
  for (const SweepDef& def : rig.sweeps)
    room = std::min(room, 1.0 + clearance(def.rest, placed, stations_per_span).gap);
  return room;
}

ContactSolver::ContactSolver(const SweepShape& rest, int stations_per_span)
    : per_span_(stations_per_span), stations_(station_parameters(rest, stations_per_span)), start_shape_(rest) {
  start_.resize(stations_.size());
  end_.resize(stations_.size());
  evaluated_.resize(stations_.size());
  for (int i = 0; i + 1 < rest.section_count(); ++i) longest_span_ = std::max(longest_span_, rest.t[i + 1] - rest.t[i]);
  smallest_reach_ = std::numeric_limits<double>::infinity();
  for (int i = 0; i < rest.section_count(); ++i) {
    double r = 0;
    for (const double x : rest.section_radii(i)) r = std::max(r, x);
    smallest_reach_ = std::min(smallest_reach_, r);
  }
  work_ = std::make_unique<RowWork>();
}
ContactSolver::ContactSolver(ContactSolver&&) noexcept = default;
ContactSolver& ContactSolver::operator=(ContactSolver&&) noexcept = default;
ContactSolver::~ContactSolver() = default;

// A sphere that holds the whole surface: about the mean of the key sections' centres, out to the
// farthest of them, plus a third of the longest span (each span's Hermite curve lies within its
// Bézier hull: within h/3 of its chord) and half again the largest radius sample (the
// interpolated radius may swell past its samples a little).
ContactSolver::Bound ContactSolver::bound(const SweepShape& shape) const {
  Bound b;
  for (const Frame& f : shape.frames) b.centre += f.center;
  b.centre /= static_cast<double>(shape.frames.size());
  for (const Frame& f : shape.frames) b.radius = std::max(b.radius, (f.center - b.centre).norm());
  b.radius += longest_span_ / 3 + 1.5 * largest_radius(shape);
  return b;
}

bool ContactSolver::near(const Bound& b, const PlacedCollider& placed) {
  Vec3 out;
  return placed.collider->local_distance(placed.to_mesh.to_local(b.centre), &out) <= b.radius + placed.collider->margin;
}

bool ContactSolver::passes_near(const Bound& before, const Frame& start, const Bound& after,
                                const PlacedCollider& placed) {
  const Collider& c = *placed.collider;
  const Vec3 a = start.to_local(before.centre), b = placed.to_mesh.to_local(after.centre);
  // Every point of the part, moving straight from its place in the first sphere to its place in
  // the second (as the chords below take it), stays within the larger radius of the segment
  // between the centres.
  const double reach = std::max(before.radius, after.radius) + c.margin;
  Vec3 out;
  const double da = c.local_distance(a, &out), db = c.local_distance(b, &out);
  if (da <= reach || db <= reach) return true;
  // The signed distance is 1-Lipschitz: nowhere on the segment below (da + db − |ab|) / 2. A
  // step's move shorter than the gaps (every step but a very fast one) is settled here.
  if (0.5 * (da + db - (b - a).norm()) > reach) return false;
  return c.local_distance(nearest_on_segment(c, a, b), &out) <= reach;
}

bool ContactSolver::may_reach(const SweepShape& shape, std::span<const PlacedCollider> from,
                              std::span<const PlacedCollider> to) const {
  // One that has not moved against the part cannot come nearer than it was (a part asleep on the
  // ground while the body stands still stays asleep).
  return meets(bound(shape), from, to, true);
}

bool ContactSolver::within_reach(const ElasticSweep& sweep, std::span<const PlacedCollider> from,
                                 std::span<const PlacedCollider> to) const {
  // Wherever its springs take it, a part's axis stays within twice its rest length of its root
  // (it does not stretch to twice its length); its surface within its sections' reach of the axis,
  // as they are now (the paper's radial springs swell a kicked section past its rest radius: 1.9
  // against 0.3 in a review's probe, which the second length covered).
  const Bound reach{sweep.deformed().frames.front().center,
                    2 * sweep.rest().length() + 1.5 * largest_radius(sweep.deformed())};
  return meets(reach, from, to, false);
}

double ContactSolver::pieces_for_move(const ElasticSweep& sweep, std::span<const PlacedCollider> from,
                                      std::span<const PlacedCollider> to) const {
  const Bound reach{sweep.deformed().frames.front().center,
                    2 * sweep.rest().length() + 1.5 * largest_radius(sweep.deformed())};
  double most = 0;
  for (std::size_t c = 0; c < from.size() && c < to.size(); ++c) {
    const double turn = from[c].to_mesh.rotation.angularDistance(to[c].to_mesh.rotation);
    const double size = std::isfinite(from[c].collider->bounding_radius())
                            ? from[c].collider->bounding_radius()
                            : (reach.centre - from[c].to_mesh.center).norm() + reach.radius;
    most = std::max(most, (to[c].to_mesh.center - from[c].to_mesh.center).norm() + turn * size);
  }
  // No farther than the part's thinnest rest section's reach a piece (at least a thousandth of its
  // length): the separating planes, taken at a piece's start, then hold only what the collider
  // really comes to (over a longer move they would hold points the collider passes beside).
  const double piece = std::max(smallest_reach_, 1e-3 * sweep.rest().length());
  return most / piece;
}

bool ContactSolver::meets(const Bound& b, std::span<const PlacedCollider> from, std::span<const PlacedCollider> to,
                          bool moved_only) {
  for (std::size_t c = 0; c < from.size() && c < to.size(); ++c) {
    const bool still = from[c].to_mesh.center == to[c].to_mesh.center &&
                       from[c].to_mesh.rotation.coeffs() == to[c].to_mesh.rotation.coeffs();
    if (still && moved_only) continue;
    // Grown by how far any of its points may travel: its origin's move, and its turn (an angle)
    // times its size (a plane: times how far the part is from its point).
    Bound swept = b;
    const double turn = from[c].to_mesh.rotation.angularDistance(to[c].to_mesh.rotation);
    const double size = std::isfinite(from[c].collider->bounding_radius())
                            ? from[c].collider->bounding_radius()
                            : (b.centre - from[c].to_mesh.center).norm() + b.radius;
    swept.radius += (to[c].to_mesh.center - from[c].to_mesh.center).norm() + turn * size;
    if (near(swept, from[c]) || near(swept, to[c])) return true;
  }
  return false;
}

void ContactSolver::begin_step(const ElasticSweep& sweep, std::span<const PlacedCollider> colliders) {
  // Only what the end of the step may need: the start's shape (copied, not evaluated) and where
  // the colliders were.
  const SweepShape& shape = sweep.deformed();
  std::copy(shape.frames.begin(), shape.frames.end(), start_shape_.frames.begin());
  std::copy(shape.radii.begin(), shape.radii.end(), start_shape_.radii.begin());
  start_pose_.resize(colliders.size());
  for (std::size_t c = 0; c < colliders.size(); ++c) start_pose_[c] = colliders[c].to_mesh;
}

Vec3 ContactSolver::collider_velocity(std::size_t c, const PlacedCollider& placed, const Vec3& here, double dt) const {
  // Where the collider's point now at `here` was at the step's start. Equal poses (a collider the
  // body carries, a body at rest) are exactly still; and over a sliver of a step (a switching time
  // a hair off the step grid) a rounding of `here` over dt would be a speed of nothing real.
  const Frame& before = start_pose_[c];
  if (dt < kShortestPiece ||
      (before.center == placed.to_mesh.center && before.rotation.coeffs() == placed.to_mesh.rotation.coeffs()))
    return Vec3::Zero();
  return (here - before.to_world(placed.to_mesh.to_local(here))) / dt;
}

double ContactSolver::gap(const ElasticSweep& sweep, const Plane& plane, const PlacedCollider& placed) {
  const SweepShape& shape = sweep.deformed();
  const double t = stations_[plane.station];
  const Vec3 local = placed.to_mesh.to_local(center_at(shape, t));
  return plane.normal.dot(local - plane.point) -
         section_support(shape, t, -(placed.to_mesh.rotation * plane.normal), support_) - plane.margin;
}

void ContactSolver::solve(const Eigen::MatrixXd& w, const std::vector<double>& r, const std::vector<double>& total,
                          std::vector<double>& a) {
  const std::size_t n = r.size();
  a.assign(n, 0.0);
  std::vector<double>& w_a = coupled_;  // W a, kept up to date
  w_a.assign(n, 0.0);
  // Converged once no pass changes any residual by more than this share of the largest one.
  double scale = 0;
  for (const double x : r) {
    if (std::isfinite(x)) scale = std::max(scale, std::abs(x));
  }
  for (int pass = 0; pass < kPasses; ++pass) {
    double change = 0;
    for (std::size_t p = 0; p < n; ++p) {
      const double wpp = w(static_cast<Eigen::Index>(p), static_cast<Eigen::Index>(p));
      if (!(wpp > 0) || !std::isfinite(r[p])) continue;  // the root, or a contact left out
      const double next = std::max(a[p] - (r[p] + w_a[p]) / wpp, -total[p]);
      const double delta = next - a[p];
      if (delta == 0) continue;
      a[p] = next;
      for (std::size_t q = 0; q < n; ++q)
        w_a[q] += w(static_cast<Eigen::Index>(q), static_cast<Eigen::Index>(p)) * delta;
      change = std::max(change, std::abs(delta) * wpp);
    }
    if (change <= kSolveTolerance * scale) break;
  }
}

void ContactSolver::solve_friction(const ElasticSweep& sweep, std::size_t contacts) {
  // Projected Gauss–Seidel over the contacts, one 2 × 2 block each: the impulse that stops the
  // block's slip given the others' (W_bb⁻¹ of it), projected onto the cone, then taken only as far
  // along the way as lowers f(λ) = ½ λᵀWλ + λᵀu (the change of the kinetic energy relative to the
  // colliders): each update lowers f from f(0) = 0, so friction never adds energy in the colliders'
  // frames, and where the cone does not bind the block ends stopped (stick).
  const std::size_t m = 2 * contacts;
  work_->ops.row_couplings(sweep, {work_->slide.data(), m}, work_->slide_by_mass, work_->slide_by_compliance);
  const Eigen::MatrixXd& w = work_->slide_by_mass;
  friction_.assign(m, 0.0);
  friction_w_.assign(m, 0.0);  // W λ, kept up to date
  double scale = 0;
  for (std::size_t r = 0; r < m; ++r) scale = std::max(scale, std::abs(slip_[r]));
  if (!(scale > 0)) return;
  const auto at = [&](std::size_t a, std::size_t b) {
    return w(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b));
  };
  for (int pass = 0; pass < kPasses; ++pass) {
    double change = 0;
    for (std::size_t c = 0; c < contacts; ++c) {
      const std::size_t a = 2 * c, b = a + 1;
      const Eigen::Vector2d u(slip_[a] + friction_w_[a], slip_[b] + friction_w_[b]);
      Eigen::Matrix2d block;
      block << at(a, a), at(a, b), at(b, a), at(b, b);
      const double det = block.determinant();
      Eigen::Vector2d step;
      if (det > kBlockConditioning * block.trace() * block.trace()) {
        step = -block.inverse() * u;
      } else {  // one row (or none) moves the point: each by its own mobility
        step.x() = block(0, 0) > 0 ? -u.x() / block(0, 0) : 0.0;
        step.y() = block(1, 1) > 0 ? -u.y() / block(1, 1) : 0.0;
      }
      Eigen::Vector2d next = Eigen::Vector2d(friction_[a], friction_[b]) + step;
      if (next.norm() > cone_[c]) next *= cone_[c] / next.norm();
      Eigen::Vector2d delta = next - Eigen::Vector2d(friction_[a], friction_[b]);
      // f along the segment to `next` (inside the cone, convex): its least point in [0, 1].
      const double curve = delta.dot(block * delta);
      if (!(curve > 0)) continue;
      delta *= std::clamp(-delta.dot(u) / curve, 0.0, 1.0);
      if (delta.x() == 0 && delta.y() == 0) continue;
      friction_[a] += delta.x();
      friction_[b] += delta.y();
      for (std::size_t q = 0; q < m; ++q) friction_w_[q] += at(q, a) * delta.x() + at(q, b) * delta.y();
      change = std::max(change, (block * delta).norm());  // the block's own change of speed
    }
    if (change <= kSolveTolerance * scale) break;
  }
}

void ContactSolver::move_out(ElasticSweep& sweep, std::span<const PlacedCollider> colliders, double dt,
                             std::vector<double>& total, bool measured) {
  const double length = sweep.deformed().length();
  const std::size_t n = planes_.size();
  for (int round = 0; round < kRounds; ++round) {
    double worst = 0;
    for (std::size_t p = 0; p < n; ++p) {
      if (round > 0 || !measured) residual_[p] = gap(sweep, planes_[p], colliders[planes_[p].collider]);
      // A point no spring can move (the root, and in material mode the first span, which only the
      // stiff stretch and shear springs carry) cannot be pushed: it is not waited for.
      const Eigen::Index i = static_cast<Eigen::Index>(p);
      if (work_->by_move(i, i) > 0) worst = std::min(worst, residual_[p]);
    }
    if (worst >= -kGapTolerance * length) break;
    // The move is the step's own answer to a force held over it (ContactRows::move_rows): through
    // the springs' inertia over the step as much as their compliance, and the speeds by the same
    // move over dt (as in position-based dynamics: else a part lying on the ground keeps its fall
    // in its speeds, falls through each step, is pushed back, and never comes to rest).
    solve(work_->by_move, residual_, total, amount_);
    work_->ops.move_rows(sweep, work_->normal, amount_, dt);
    for (std::size_t p = 0; p < n; ++p) total[p] += amount_[p];
  }
}

bool ContactSolver::resolve(ElasticSweep& sweep, std::span<const PlacedCollider> colliders, double dt) {
  ++step_;  // a stick anchor lasts while its contact touches at every step (contact_stick.cpp)
  const SweepShape& shape = sweep.deformed();
  const double length = shape.length();  // before the push moves it
  const Bound before = bound(start_shape_), after = bound(shape);
  if (!any_passes_near(before, after, colliders)) return false;
  measure_span_reach(shape);
  collect_planes(shape, colliders, before, after);
  if (planes_.empty() || !may_touch(sweep, colliders, length)) return false;
  build_rows(sweep, colliders, dt);
  push_out(sweep, colliders, dt);
  if (!stop_approach(sweep, colliders, dt, length)) return false;
  if (dt < kShortestPiece) {
    // A sliver of a step (a force or a path corner just off the step grid) holds nothing, but the
    // contacts that touched the step before still do: their anchors carry on.
    for (Anchor& a : anchors_) a.step += a.step == step_ - 1;
    return true;
  }
  measure_normal_impulses(sweep, dt);
  // Static friction on positions first (contact_stick.cpp): what of each cone it spends, the
  // speeds below may not.
  hold(sweep, colliders, dt);
  slide(sweep, colliders, dt);
  return true;
}

bool ContactSolver::any_passes_near(const Bound& before, const Bound& after,
                                    std::span<const PlacedCollider> colliders) const {
  // Broad phase: a collider clear of the part's bounding sphere at both ends of the step and on
  // its way between them (in the collider's own frame) cannot have been reached; with none left,
  // nothing more is computed.
  for (std::size_t c = 0; c < colliders.size(); ++c) {
    if (passes_near(before, start_pose_[c], after, colliders[c])) return true;
  }
  return false;
}

void ContactSolver::measure_span_reach(const SweepShape& shape) {
  // How far the surface may reach from a chord: 1.5× the radius, as in bound(), and the curve's
  // own bulge between two stations (half a chord's parameter length bounds it, loosely: the
  // Hermite curve's speed stays under 1.5 over a span and its Bézier hull within a third).
  // Per span j: the largest radius sample of the sections its interpolation reads (j − 1 … j + 2),
  // at either end of the step.
  const int sections = shape.section_count();
  span_reach_.assign(static_cast<std::size_t>(sections - 1), 0.0);
  for (int i = 0; i < sections; ++i) {
    double r = 0;
    for (const SweepShape* sh : {static_cast<const SweepShape*>(&start_shape_), &shape}) {
      for (const double x : sh->section_radii(i)) r = std::max(r, x);
    }
    for (int j = std::max(i - 2, 0); j <= std::min(i + 1, sections - 2); ++j) {
      span_reach_[static_cast<std::size_t>(j)] = std::max(span_reach_[static_cast<std::size_t>(j)], r);
    }
  }
}

void ContactSolver::collect_planes(const SweepShape& shape, std::span<const PlacedCollider> colliders,
                                   const Bound& before, const Bound& after) {
  const double bulge = 0.5 * longest_span_ / per_span_;
  // Stations are evaluated only on spans some collider comes near (a span's curve lies within a
  // third of its length of its chord: a sphere about the two sections' centres holds it).
  const int spans = start_shape_.section_count() - 1;
  std::fill(evaluated_.begin(), evaluated_.end(), 0);
  const auto station_points = [&](std::size_t s) {
    if (!evaluated_[s]) {
      start_[s] = center_at(start_shape_, stations_[s]);
      end_[s] = center_at(shape, stations_[s]);
      evaluated_[s] = 1;
    }
  };

  // The planes that separated each chord near a collider from it at the step's start.
  planes_.clear();
  for (std::size_t c = 0; c < colliders.size(); ++c) {
    const Collider& col = *colliders[c].collider;
    if (!passes_near(before, start_pose_[c], after, colliders[c])) continue;
    for (int j = 0; j < spans; ++j) {
      const double grow = 1.5 * span_reach_[static_cast<std::size_t>(j)] + bulge + col.margin;
      const Vec3 ends[4] = {start_pose_[c].to_local(start_shape_.frames[j].center),
                            start_pose_[c].to_local(start_shape_.frames[j + 1].center),
                            colliders[c].to_mesh.to_local(shape.frames[j].center),
                            colliders[c].to_mesh.to_local(shape.frames[j + 1].center)};
      if (clear_of(col, ends, grow + (start_shape_.t[j + 1] - start_shape_.t[j]) / 3)) continue;
      for (int k = 0; k < per_span_; ++k) {
        const std::size_t s = static_cast<std::size_t>(j * per_span_ + k);
        station_points(s);
        station_points(s + 1);
        const Vec3 a0 = start_pose_[c].to_local(start_[s]), b0 = start_pose_[c].to_local(start_[s + 1]);
        const Vec3 chord[4] = {a0, b0, colliders[c].to_mesh.to_local(end_[s]),
                               colliders[c].to_mesh.to_local(end_[s + 1])};
        if (clear_of(col, chord, grow)) continue;
        const Vec3 x = nearest_on_segment(col, a0, b0);
        Vec3 outward;
        const double d = col.local_distance(x, &outward);
        const Vec3 surface = x - d * outward;
        for (std::size_t e : {s, s + 1}) {
          // The chord before this one may have left the same plane on this end (a flat collider).
          const bool again = !planes_.empty() && planes_.back().station == static_cast<int>(e) &&
                             planes_.back().collider == c && planes_.back().normal == outward &&
                             planes_.back().point == surface;
          if (!again) planes_.push_back({static_cast<int>(e), c, outward, surface, col.margin});
        }
      }
    }
  }
}

bool ContactSolver::may_touch(const ElasticSweep& sweep, std::span<const PlacedCollider> colliders, double length) {
  const std::size_t n = planes_.size();
  // Most steps near a collider end clear of it: then nothing touches and nothing is built. A
  // station whose centre is farther from its plane than 1.5× its span's radius is clear without
  // measuring its section's reach.
  bool near_plane = false;
  for (std::size_t p = 0; p < n && !near_plane; ++p) {
    const Plane& pl = planes_[p];
    const PlacedCollider& placed = colliders[pl.collider];
    const double centre = pl.normal.dot(placed.to_mesh.to_local(end_[static_cast<std::size_t>(pl.station)]) - pl.point);
    const std::size_t span = std::min(static_cast<std::size_t>(pl.station / per_span_), span_reach_.size() - 1);
    near_plane = centre - 1.5 * span_reach_[span] - pl.margin <= kTouchSlack * length;
  }
  if (!near_plane) return false;
  residual_.resize(n);
  double closest = std::numeric_limits<double>::infinity();
  for (std::size_t p = 0; p < n; ++p) {
    residual_[p] = gap(sweep, planes_[p], colliders[planes_[p].collider]);
    closest = std::min(closest, residual_[p]);
  }
  return closest <= kTouchSlack * length;
}

void ContactSolver::build_rows(ElasticSweep& sweep, std::span<const PlacedCollider> colliders, double dt) {
  const std::size_t n = planes_.size();
  // The contact rows along each plane's normal, on the pose the springs reached, and their
  // couplings: the linear model the solves below use.
  work_->normal.resize(n);
  for (std::size_t p = 0; p < n; ++p) {
    const Vec3 normal = colliders[planes_[p].collider].to_mesh.rotation * planes_[p].normal;
    ContactRows::contact_row(sweep, stations_[planes_[p].station], normal, work_->normal[p]);
  }
  work_->ops.row_couplings(sweep, work_->normal, work_->by_mass, work_->by_compliance);
  work_->ops.row_move_couplings(sweep, work_->normal, dt, work_->by_move);
}

void ContactSolver::push_out(ElasticSweep& sweep, std::span<const PlacedCollider> colliders, double dt) {
  const std::size_t n = planes_.size();
  // Move the ends back onto their planes; the true curve is re-measured after each solve.
  total_.assign(n, 0.0);
  // The move's change of each row's speed, for N below.
  move_speed_.resize(n);
  for (std::size_t p = 0; p < n; ++p) move_speed_[p] = -ContactRows::row_speed(sweep, work_->normal[p]);
  move_out(sweep, colliders, dt, total_, true);
  for (std::size_t p = 0; p < n; ++p) move_speed_[p] += ContactRows::row_speed(sweep, work_->normal[p]);
}

bool ContactSolver::stop_approach(ElasticSweep& sweep, std::span<const PlacedCollider> colliders, double dt,
                                  double length) {
  const std::size_t n = planes_.size();
  // Touching: pushed, or resting on the plane. Their approach speeds out, all together.
  bool touching = false;
  for (std::size_t p = 0; p < n; ++p) {
    const PlacedCollider& placed = colliders[planes_[p].collider];
    const bool touches = total_[p] > 0 || gap(sweep, planes_[p], placed) <= kTouchSlack * length;
    touching = touching || touches;
    residual_[p] = std::numeric_limits<double>::infinity();  // not in contact: free to leave
    if (!touches) continue;
    // The collider's own speed there, relative to the body (a world collider on a moving body).
    const Vec3 here = center_at(sweep.deformed(), stations_[planes_[p].station]);
    const Vec3 normal = placed.to_mesh.rotation * planes_[p].normal;
    residual_[p] = ContactRows::row_speed(sweep, work_->normal[p]) -
                   normal.dot(collider_velocity(planes_[p].collider, placed, here, dt));
  }
  if (!touching) return false;
  // A contact the step pushed back is held on its plane for the step (its speed along the normal
  // made zero, a pull allowed): the push already took it out, and letting the velocity solve
  // leave it a speed off the plane sets a resting part jittering. One only resting there is
  // free to leave.
  for (std::size_t p = 0; p < n; ++p) total_[p] = total_[p] > 0 ? std::numeric_limits<double>::infinity() : 0.0;
  solve(work_->by_mass, residual_, total_, amount_);
  work_->ops.apply_rows(sweep, work_->normal, amount_, true);
  return true;
}

void ContactSolver::measure_normal_impulses(const ElasticSweep& sweep, double dt) {
  const std::size_t n = planes_.size();
  // The normal impulse N·dt each touching contact took over the step, which its friction is
  // bounded by: the move's change of the points' speeds along their normals (Δq/dt, measured as
  // the move made it: move_speed_, the step's fall it took back) and the kicks' (J M⁻¹ Jᵀ
  // amount), read back as the impulses ≥ 0 that would make that change together (one solve over
  // the contacts: two rows at one point, or neighbours on one chain, share it rather than each
  // counting it whole). A part resting on the ground gets its weight times dt, however long the
  // step.
  for (std::size_t p = 0; p < n; ++p) {
    if (!std::isfinite(residual_[p]) ||
        !(work_->by_mass(static_cast<Eigen::Index>(p), static_cast<Eigen::Index>(p)) > 0)) {
      residual_[p] = std::numeric_limits<double>::infinity();  // not touching, or held by the root
      continue;
    }
    const Eigen::Index i = static_cast<Eigen::Index>(p);
    double change = 0;
    for (std::size_t q = 0; q < n; ++q) {
      const Eigen::Index j = static_cast<Eigen::Index>(q);
      change += work_->by_mass(i, j) * amount_[q];
    }
    change += move_speed_[p];
    residual_[p] = -change;
  }
  none_.assign(n, 0.0);
  solve(work_->by_mass, residual_, none_, pressed_);
  // The same force read quasi-statically: what holds the springs off where the step's loads alone
  // would hold them (J C Jᵀ N = J (q − C f), N ≥ 0, over the touching contacts). A stiff part resting
  // on the ground is held by its springs' strain, its steps' falls and kicks next to nothing; a hit
  // is all kicks. Each contact takes the larger reading, N·dt.
  for (std::size_t p = 0; p < n; ++p) {
    if (std::isfinite(residual_[p])) residual_[p] = -ContactRows::row_strain(sweep, work_->normal[p]);
  }
  solve(work_->by_compliance, residual_, none_, held_);
  for (std::size_t p = 0; p < n; ++p) pressed_[p] = std::max(pressed_[p], held_[p] * dt);
}

void ContactSolver::slide(ElasticSweep& sweep, std::span<const PlacedCollider> colliders, double dt) {
  const std::size_t n = planes_.size();
  // Sliding speeds, all contacts together: each contact's friction impulse lies in its cone
  // (|λ| ≤ μN), stops its slip if that is enough (stick) and is μN against the slip if not
  // (kinetic). Two rows per contact, across its normal at its section's centre (no roll).
  std::size_t k = 0;
  for (std::size_t p = 0; p < n; ++p) {
    const PlacedCollider& placed = colliders[planes_[p].collider];
    const double mu = placed.collider->friction;
    if (!(pressed_[p] > 0) || !(mu > 0) || !(mu * pressed_[p] > spent_[p])) continue;
    const double t = stations_[planes_[p].station];
    const Vec3 normal = placed.to_mesh.rotation * planes_[p].normal;
    const Vec3 here = center_at(sweep.deformed(), t);
    Vec3 v = -collider_velocity(planes_[p].collider, placed, here, dt);
    for (int c = 0; c < 3; ++c) {
      ContactRows::contact_row(sweep, t, Vec3::Unit(c), work_->probe, false);
      v[c] += ContactRows::row_speed(sweep, work_->probe);
    }
    const Vec3 slide = v - normal.dot(v) * normal;
    const double speed = slide.norm();
    // The first row along the slip (any direction across the normal when there is none).
    const Vec3 first = speed > 0 ? Vec3(slide / speed) : normal.unitOrthogonal();
    if (work_->slide.size() < 2 * (k + 1)) work_->slide.resize(2 * (k + 1));
    if (slip_.size() < 2 * (k + 1)) slip_.resize(2 * (k + 1)), cone_.resize(k + 1);
    ContactRows::contact_row(sweep, t, first, work_->slide[2 * k]);
    ContactRows::contact_row(sweep, t, normal.cross(first), work_->slide[2 * k + 1]);
    slip_[2 * k] = speed;
    slip_[2 * k + 1] = 0;
    cone_[k] = mu * pressed_[p] - spent_[p];
    ++k;
  }
  if (k == 0) return;
  solve_friction(sweep, k);
  work_->ops.apply_rows(sweep, {work_->slide.data(), 2 * k}, {friction_.data(), 2 * k}, true);
}

}  // namespace sweep::sim
