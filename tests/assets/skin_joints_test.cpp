// A glTF skin's joint indices (JOINTS_0) are unsigned shorts: a skeleton of more than 65535 joints
// would wrap them. check_skin_joints counts the skin's joints before anything is baked: one body
// joint, and a sweep's N station joints with M ring joints at each station but the root,
// N + (N − 1)·M a sweep.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/sample_sweeps.h"
#include "sweep/assets/bake_skin.h"
#include "sweep/core/error.h"
#include "sweep/core/rig.h"

namespace sweep::test {
namespace {

// 14 sweeps of 16 key sections (121 stations at 8 a span): with N = 118 and M = 39 the skin has
// 1 + 14·(118 + 117·39) = 65535 joints exactly.
constexpr int kSweeps = 14, kSpan = 8;

std::string refusal(int stations, int ring) {
  const SweepShape rest = straight_shape(16, 8);
  std::vector<assets::SkinSweep> sweeps;
  for (int i = 0; i < kSweeps; ++i) sweeps.push_back({"part" + std::to_string(i), &rest, nullptr});
  try {
    assets::check_skin_joints({.stations = stations, .ring = ring}, sweeps, kSpan);
  } catch (const Error& e) {
    EXPECT_EQ(e.category(), ErrorCategory::usage);
    return e.what();
  }
  return "";
}

TEST(SkinJoints, ASkeletonOfMoreThan65535JointsIsRefusedAndOneOfExactlyThatManyIsNot) {
  EXPECT_EQ(refusal(118, 39), "");
  const std::string one_more_ring = refusal(118, 40);
  EXPECT_NE(one_more_ring.find("67173 joints, more than a glTF skin's 65535"), std::string::npos) << one_more_ring;
  const std::string one_more_station = refusal(119, 39);
  EXPECT_NE(one_more_station.find("66095 joints"), std::string::npos) << one_more_station;
}

TEST(SkinJoints, JointsAloneTakeTheDefaultOrTheFewestStationsOfAnySweep) {
  // A sweep of K key sections has (K − 1)·stations_per_span + 1 stations, at most a joint each.
  const std::vector<SweepDef> long_only = {make_sweep("long", straight_shape(9, 6))};  // 65 stations at 8
  const assets::DefaultSkinJoints alone = assets::default_skin_joints(long_only, 8);
  EXPECT_EQ(alone.joints, assets::kDefaultSkinJoints);
  EXPECT_EQ(alone.fewest, nullptr);
  const std::vector<SweepDef> mixed = {long_only[0], make_sweep("short", straight_shape(3, 6)),
                                       make_sweep("shorter", straight_shape(2, 6)),
                                       make_sweep("mid", straight_shape(3, 6))};
  const assets::DefaultSkinJoints fewest = assets::default_skin_joints(mixed, 8);
  EXPECT_EQ(fewest.joints, 9);  // "shorter": 1·8 + 1, below "short"'s 17 and the default 24
  EXPECT_EQ(fewest.fewest, &mixed[2]);
  // One station a span: 2 stations, the fewest joints a sweep may have.
  const assets::DefaultSkinJoints least = assets::default_skin_joints(mixed, 1);
  EXPECT_EQ(least.joints, assets::kMinSkinJoints);
  EXPECT_EQ(least.fewest, &mixed[2]);
}

}  // namespace
}  // namespace sweep::test
