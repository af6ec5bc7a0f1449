// Ends that are not tubes, clicked at their far end: a neck clicked on the muzzle of a head turned
// across it, an arm (root at the shoulder) clicked at a fingertip of a hand whose fingers fan out.
// Neither is refused: the sweep follows the neck or the arm (its sections on the generator's axis
// up to the head or the wrist), and what lies past its last section is carried rigidly.
#include <gtest/gtest.h>

#include "fit/creatures.h"
#include "sweep/fit/fit.h"

namespace sweep::test {
namespace {

TEST(FitEnds, ANeckClickedOnItsHeadIsFittedNotRefused) {
  const NeckAndHead n = make_neck_and_head();
  fit::FitOptions o;
  o.name = "neck";
  o.tip = n.muzzle;
  const fit::FitResult r = fit::fit_sweep(n.mesh, o);
  for (const std::string& p : r.problems) ADD_FAILURE() << p;
  int on_neck = 0;
  for (const Frame& f : r.sweep.rest.frames) {
    if (f.center.z() > NeckAndHead::kHeadZ - NeckAndHead::kHeadRadius) continue;  // in the head
    ++on_neck;
    EXPECT_LT(Vec3(f.center.x(), f.center.y(), 0).norm(), 0.1 * NeckAndHead::kR) << "on the neck's axis";
  }
  EXPECT_GE(on_neck, 12) << "most sections are the neck's";
  EXPECT_GT(r.error.beyond_ends_count, 0u) << "the head's far end is carried by the last section";
}

TEST(FitEnds, AnArmClickedAtAFingertipIsFittedNotRefused) {
  const ArmAndHand a = make_arm_and_hand();
  fit::FitOptions o;
  o.name = "arm";
  o.tip = a.fingertip;
  o.root = Vec3(0.35, 0, 0);
  const fit::FitResult r = fit::fit_sweep(a.mesh, o);
  for (const std::string& p : r.problems) ADD_FAILURE() << p;
  int on_arm = 0;
  for (const Frame& f : r.sweep.rest.frames) {
    if (f.center.x() > ArmAndHand::kWrist - ArmAndHand::kR) continue;  // in the hand
    ++on_arm;
    EXPECT_LT(Vec3(0, f.center.y(), f.center.z()).norm(), 0.1 * ArmAndHand::kR) << "on the arm's axis";
  }
  EXPECT_GE(on_arm, 10) << "the arm's sections";
  EXPECT_GT(r.error.beyond_ends_count, 0u) << "the fingertip's end is carried by the last section";
}

}  // namespace
}  // namespace sweep::test
