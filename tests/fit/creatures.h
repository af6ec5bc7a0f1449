#pragma once
// Small creatures whose parts are known, for the part search and the loose pieces: a body with
// legs that are separate shells (feet at their ends), built in any up direction; a tail with a
// tuft of loose quads beyond its tip. Each generator says where its parts are.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "fit/curve_tubes.h"
#include "fit/fused_tubes.h"
#include "sweep/core/mesh.h"

namespace sweep::test {

// Appends `from` to `to` as a separate piece (its own vertices).
inline void append(Mesh& to, const Mesh& from) {
  const auto base = static_cast<std::uint32_t>(to.positions.size());
  to.positions.insert(to.positions.end(), from.positions.begin(), from.positions.end());
  for (std::size_t f = 0; f + 1 < from.face_offsets.size(); ++f) {
    const std::uint32_t a = from.face_offsets[f], b = from.face_offsets[f + 1];
    for (std::uint32_t k = a; k < b; ++k) to.face_vertices.push_back(from.face_vertices[k] + base);
    to.face_offsets.push_back(static_cast<std::uint32_t>(to.face_vertices.size()));
  }
}

// A closed ellipsoid of semi-axes `axes` about `centre`, `lat` × `lon` quads (poles fanned).
inline Mesh ellipsoid(const Vec3& centre, const Vec3& axes, int lat = 16, int lon = 24) {
  Mesh m;
  m.positions.push_back(centre - Vec3(0, axes.y(), 0));
  for (int i = 1; i < lat; ++i) {
    const double phi = std::numbers::pi * i / lat - std::numbers::pi / 2;
    for (int j = 0; j < lon; ++j) {
      const double th = 2 * std::numbers::pi * j / lon;
      m.positions.push_back(centre + Vec3(axes.x() * std::cos(phi) * std::cos(th), axes.y() * std::sin(phi),
                                          axes.z() * std::cos(phi) * std::sin(th)));
    }
  }
  m.positions.push_back(centre + Vec3(0, axes.y(), 0));
  const auto id = [&](int i, int j) { return static_cast<std::uint32_t>(1 + (i - 1) * lon + (j % lon)); };
  const auto top = static_cast<std::uint32_t>(m.positions.size() - 1);
  for (int j = 0; j < lon; ++j) {
    m.add_face({0, id(1, j), id(1, j + 1)});
    m.add_face({top, id(lat - 1, j + 1), id(lat - 1, j)});
    for (int i = 1; i + 1 < lat; ++i) m.add_face({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
  }
  return m;
}

// A walker: a body 2 long at height 0.8 (Y up), with `legs_per_side` × 2 legs, each a separate
// closed tube of radius kLegRadius from its hip (on the body's side) up over a knee and down to a
// ball foot that touches the ground; with `abdomen`, a second, smaller body shell behind (a core
// piece of the body, no part). `rotate` takes the Y-up model to the file's axes.
struct Walker {
  static constexpr double kLegRadius = 0.05;
  static constexpr double kFootRadius = 0.1;
  std::vector<Vec3> hips, feet;  // per leg, Y up before `rotate`: the curve's ends
  Mesh mesh;
};

inline Walker make_walker(int legs_per_side, bool abdomen,
                          const Eigen::Matrix3d& rotate = Eigen::Matrix3d::Identity()) {
  Walker w;
  append(w.mesh, ellipsoid(Vec3(0, 0.8, 0), Vec3(1.0, 0.3, 0.35)));
  if (abdomen) append(w.mesh, ellipsoid(Vec3(-1.55, 0.85, 0), Vec3(0.6, 0.3, 0.3)));
  for (int side : {-1, 1}) {
    for (int k = 0; k < legs_per_side; ++k) {
      const double x = legs_per_side == 1 ? 0.0 : -0.6 + 1.2 * k / (legs_per_side - 1);
      const Vec3 hip(x, 0.8, side * 0.3), knee(x, 1.25, side * 0.9), foot(x, Walker::kFootRadius, side * 1.05);
      CurveTube t;
      t.curve = [=](double u) { return Vec3((1 - u) * (1 - u) * hip + 2 * u * (1 - u) * knee + u * u * foot); };
      // The leg, widening into a ball foot over its last two foot radii.
      t.samples = 400;
      t.segments = 16;
      t.ring_spacing = 0.03;
      t.resample();
      const double len = t.length();
      t.radius = [=](double s) {
        const double x_end = (s - (len - Walker::kFootRadius)) / Walker::kFootRadius;
        const double ball = std::abs(x_end) < 1 ? Walker::kFootRadius * std::sqrt(1 - x_end * x_end) : 0.0;
        return std::max(Walker::kLegRadius, ball);
      };
      append(w.mesh, t.mesh());
      w.hips.push_back(hip);
      w.feet.push_back(t.points.back() + Walker::kLegRadius * t.tangents.back());
    }
  }
  for (Vec3& p : w.mesh.positions) p = rotate * p;
  for (Vec3& p : w.hips) p = rotate * p;
  for (Vec3& p : w.feet) p = rotate * p;
  return w;
}

// A figure standing in a T-pose (Y up): a torso 1.3 tall and 0.5 wide, arms straight out to the
// sides as separate closed tubes of radius kArmRadius from inside the shoulders to the wrists at
// x = ±kWrist, and a fist beyond each wrist as a separate shell (a ball) reaching x = ±kHandEnd:
// the fists make the whole figure wider than tall, its body without them is taller than wide.
struct TPosedFigure {
  static constexpr double kArmRadius = 0.05, kShoulderY = 1.5, kWrist = 0.9, kHandEnd = 1.1;
  Mesh mesh;
};

// A straight closed tube of radius r from `from` to `to` (capped), rings 0.03 apart.
inline Mesh straight_tube(const Vec3& from, const Vec3& to, double r) {
  CurveTube t;
  t.curve = [from, to](double u) { return Vec3(from + u * (to - from)); };
  t.radius = [r](double) { return r; };
  t.samples = 200;
  t.segments = 16;
  t.ring_spacing = 0.03;
  t.resample();
  return t.mesh();
}

inline TPosedFigure make_t_posed_figure() {
  TPosedFigure f;
  using T = TPosedFigure;
  append(f.mesh, ellipsoid(Vec3(0, 1.15, 0), Vec3(0.25, 0.65, 0.15)));
  for (const double side : {-1.0, 1.0}) {
    append(f.mesh,
           straight_tube(Vec3(side * 0.15, T::kShoulderY, 0), Vec3(side * T::kWrist, T::kShoulderY, 0), T::kArmRadius));
    const double half = (T::kHandEnd - T::kWrist) / 2;
    append(f.mesh, ellipsoid(Vec3(side * (T::kWrist + half), T::kShoulderY, 0), Vec3(half, half, half), 8, 12));
  }
  return f;
}

// A stocky figure (Y up), wider than tall, so not upright by its proportions: a body 1.2 wide and 0.9
// tall, arms hanging out and down to the sides (separate tubes, `hands` their ends) and two horns
// rising from its top (`horn_tips`), each pair the other's mirror image across x = 0.
struct StockyFigure {
  std::vector<Vec3> hands, horn_tips;
  Mesh mesh;
};

inline StockyFigure make_stocky_figure() {
  StockyFigure f;
  append(f.mesh, ellipsoid(Vec3(0, 1, 0), Vec3(0.6, 0.45, 0.3)));
  for (const double side : {-1.0, 1.0}) {
    f.hands.emplace_back(side * 1.0, 0.75, 0);
    append(f.mesh, straight_tube(Vec3(side * 0.45, 1.2, 0), f.hands.back(), 0.05));
    f.horn_tips.emplace_back(side * 0.4, 1.85, 0);
    append(f.mesh, straight_tube(Vec3(side * 0.15, 1.42, 0), f.horn_tips.back(), 0.04));
  }
  return f;
}

inline double capsule_distance(const Vec3& p, const Vec3& from, const Vec3& to, double r) {
  return distance_to_polyline({from, to}, p) - r;
}
// A signed distance (near enough: exact on the axes) to an ellipsoid of semi-axes `axes`.
inline double ellipsoid_distance(const Vec3& p, const Vec3& centre, const Vec3& axes) {
  return ((p - centre).cwiseQuotient(axes).norm() - 1) * axes.minCoeff();
}

// A neck ending in a head turned across it (a camel's, a horse's), one closed surface
// (mesh_level_set): a body ball, a neck of radius kR up +Z from the body's centre to z = kNeckTop,
// and a head, an ellipsoid long along +X, whose front is `muzzle`.
struct NeckAndHead {
  static constexpr double kR = 0.1, kNeckTop = 1.0;
  static constexpr double kHeadX = 0.15, kHeadZ = 1.1, kHeadLength = 0.3, kHeadRadius = 0.18;
  static constexpr double kMuzzleX = 0.42, kMuzzleZ = 0.98, kMuzzleRadius = 0.12;
  Vec3 muzzle = Vec3(kMuzzleX + kMuzzleRadius, 0, kMuzzleZ);
  Mesh mesh;
};

inline NeckAndHead make_neck_and_head() {
  NeckAndHead n;
  const auto f = [](const Vec3& p) {
    double v = p.norm() - 0.35;
    v = std::min(v, capsule_distance(p, Vec3::Zero(), Vec3(0, 0, NeckAndHead::kNeckTop), NeckAndHead::kR));
    v = std::min(v,
                 Vec3(p - Vec3(NeckAndHead::kMuzzleX, 0, NeckAndHead::kMuzzleZ)).norm() - NeckAndHead::kMuzzleRadius);
    return std::min(
        v, ellipsoid_distance(p, Vec3(NeckAndHead::kHeadX, 0, NeckAndHead::kHeadZ),
                              Vec3(NeckAndHead::kHeadLength, NeckAndHead::kHeadRadius, NeckAndHead::kHeadRadius)));
  };
  n.mesh = mesh_level_set(f, Vec3(-0.4, -0.4, -0.4), Vec3(0.6, 0.4, 1.35), 0.03);
  return n;
}

// An arm ending in a hand, one closed surface: a body ball, an arm of radius kR along +X from the
// body's centre to the wrist, a flat palm wider than the arm and four fingers fanning out from it
// (at −45°, −15°, 15° and 45° to the arm, in its plane); `fingertip` is the end of the 15° one.
struct ArmAndHand {
  static constexpr double kR = 0.1, kWrist = 1.0, kFingerRadius = 0.045, kFingerLength = 0.4;
  static constexpr double kFingerBase = 1.2;
  Vec3 fingertip;
  Mesh mesh;
};

inline Vec3 finger_direction(double degrees) {
  const double a = degrees * std::numbers::pi / 180;
  return Vec3(std::cos(a), std::sin(a), 0);
}

inline ArmAndHand make_arm_and_hand() {
  ArmAndHand a;
  const auto f = [](const Vec3& p) {
    double v = p.norm() - 0.3;
    v = std::min(v, capsule_distance(p, Vec3::Zero(), Vec3(ArmAndHand::kWrist, 0, 0), ArmAndHand::kR));
    v = std::min(v, ellipsoid_distance(p, Vec3(1.12, 0, 0), Vec3(0.16, 0.18, 0.06)));
    for (const double degrees : {-45.0, -15.0, 15.0, 45.0}) {
      const Vec3 base(ArmAndHand::kFingerBase, 0, 0);
      v = std::min(v, capsule_distance(p, base, base + ArmAndHand::kFingerLength * finger_direction(degrees),
                                       ArmAndHand::kFingerRadius));
    }
    return v;
  };
  a.fingertip = Vec3(ArmAndHand::kFingerBase, 0, 0) +
                (ArmAndHand::kFingerLength + ArmAndHand::kFingerRadius) * finger_direction(15);
  a.mesh = mesh_level_set(f, Vec3(-0.35, -0.45, -0.35), Vec3(1.7, 0.45, 0.35), 0.03);
  return a;
}

// A biped's lower half standing on the ground (Y up), one closed surface: a hip ball, two legs of
// radius kR down to the ankles, and feet that are capsules along +X from the heel (`heel` behind the
// ankle) to the toes (`toes` in front). Traced from the heel, rings run along the foot to the toes
// (closing there) before they ever reach the leg's junction with the hips: the heel is no part's tip.
struct LegsWithFeet {
  static constexpr double kR = 0.08, kHipY = 1.1, kAnkleY = 0.09, kFootR = 0.07;
  static constexpr double kLegZ = 0.22;
  std::vector<Vec3> hips, ankles, heels, toes;
  Mesh mesh;
};

inline LegsWithFeet make_legs_with_feet(double heel, double toes) {
  LegsWithFeet l;
  using L = LegsWithFeet;
  for (const double side : {-1.0, 1.0}) {
    l.hips.emplace_back(0, L::kHipY, side * L::kLegZ);
    l.ankles.emplace_back(0, L::kAnkleY, side * L::kLegZ);
    l.heels.emplace_back(-heel - L::kFootR, L::kFootR, side * L::kLegZ);
    l.toes.emplace_back(toes + L::kFootR, L::kFootR, side * L::kLegZ);
  }
  const auto f = [&l, heel, toes](const Vec3& p) {
    double v = ellipsoid_distance(p, Vec3(0, L::kHipY + 0.1, 0), Vec3(0.3, 0.3, 0.4));
    for (std::size_t k = 0; k < 2; ++k) {
      v = std::min(v, capsule_distance(p, l.hips[k], l.ankles[k], L::kR));
      const Vec3 foot(0, L::kFootR, l.hips[k].z());
      v = std::min(v, capsule_distance(p, foot - Vec3(heel, 0, 0), foot + Vec3(toes, 0, 0), L::kFootR));
    }
    return v;
  };
  l.mesh = mesh_level_set(f, Vec3(-heel - 0.2, -0.05, -0.45), Vec3(toes + 0.2, 1.55, 0.45), 0.04);
  return l;
}

// A figure's lower half whose thighs widen into the hips as a person's do (Y up), one closed
// surface (mesh_level_set): a pelvis and a torso, two legs tapering from kThighR at the hip to
// kAnkleR at the ankle, blended smoothly (a soft minimum over kBlend) into the pelvis and into each
// other, and flat feet along +X. Traced from the toes, the rings round a thigh spread slowly over
// the hips (growing by under 0.4 of their distance, no jump) and then split round the other leg
// and the torso; the legs part from each other below the pelvis, at about kPartY.
struct StandingHips {
  static constexpr double kHipY = 0.98, kAnkleY = 0.1, kLegZ = 0.1, kThighR = 0.1, kAnkleR = 0.045;
  static constexpr double kBlend = 0.12, kPartY = 0.55;
  std::vector<Vec3> toes;
  Mesh mesh;
};

inline StandingHips make_standing_hips() {
  using S = StandingHips;
  StandingHips s;
  for (const double side : {-1.0, 1.0}) s.toes.emplace_back(0.18, 0.05, side * (S::kLegZ + 0.01));
  const auto soft_min = [](double a, double b) {
    const double h = std::max(S::kBlend - std::abs(a - b), 0.0) / S::kBlend;
    return std::min(a, b) - h * h * S::kBlend / 4;
  };
  const auto f = [&soft_min](const Vec3& p) {
    double v = std::min(ellipsoid_distance(p, Vec3(0, 1.0, 0), Vec3(0.16, 0.14, 0.22)),
                        ellipsoid_distance(p, Vec3(0, 1.4, 0), Vec3(0.15, 0.35, 0.22)));
    for (const double side : {-1.0, 1.0}) {
      const Vec3 hip(0, S::kHipY, side * S::kLegZ), ankle(0, S::kAnkleY, side * (S::kLegZ + 0.01));
      const double t = std::clamp((p - hip).dot(ankle - hip) / (ankle - hip).squaredNorm(), 0.0, 1.0);
      const double leg = std::min((p - (hip + t * (ankle - hip))).norm() - (S::kThighR + (S::kAnkleR - S::kThighR) * t),
                                  ellipsoid_distance(p, Vec3(0.05, 0.05, ankle.z()), Vec3(0.13, 0.05, 0.065)));
      v = soft_min(v, leg);
    }
    return v;
  };
  s.mesh = mesh_level_set(f, Vec3(-0.3, -0.05, -0.4), Vec3(0.35, 1.85, 0.4), 0.025);
  return s;
}

}  // namespace sweep::test
