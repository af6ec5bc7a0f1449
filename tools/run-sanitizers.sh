#!/usr/bin/env bash
# The whole test suite under AddressSanitizer + UndefinedBehaviorSanitizer (the asan preset: Debug,
# SWEEP_SANITIZE=ON, warnings as errors): builds build/asan and runs every CTest test in it. Tests
# that only time things skip themselves under the sanitizers. Any sanitizer report fails its test
# (ASan aborts; UBSan is built with -fno-sanitize-recover) and so the script.
#   tools/run-sanitizers.sh [--all] [extra ctest arguments, e.g. -R BadInput]
# The libraries are built at -O1 here (lib/CMakeLists.txt), the tests and tools at -O0.
# By default (the CI budget) the tests that only repeat already-sanitized code paths on CGAL's real
# meshes or at stress-test length are left out: with everything unoptimized under ASan they took
# ~20 of the ~25 minutes (the diplodocus fits alone ~8). --all runs every test.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
jobs=${SWEEP_JOBS:-$(nproc)}
# Leak checking stays on (the default on Linux); halt at the first UBSan report with a stack.
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}
# (BodyProxy.ATailKicked… simulates the diplodocus's tail at 24 and 144 fps against the body's
# spheres: 8 s optimised, over 15 minutes unoptimised under ASan; the contact and sphere code it
# runs is sanitized by the Contact.* and the other BodyProxy.* tests, the sphere fit on a small
# body with a tail. Tool.AllFits… and Tool.RootOnTheTails… fit the diplodocus, 140 s and 50 s
# there; --all's code runs sanitized in Tool.AllNames… and Tool.AnOpenMesh….
# The ContactFriction.* tests slide or hold a tube for seconds at steps down to 1/960 s (2 to 20 s
# each optimised; unoptimised Eigen under ASan runs the hold's per-step solve ~200× slower: the
# frame-rate test alone took 318 s, the stuck tip over 11 minutes); the position hold runs
# sanitized in Contact.FrictionDrags… and Contact.APartLaidOnTheGround… (friction 0.5), its
# momentum bound with it; Contact.ASoftTubeLyingOnAFrictionalSlope… (two 1 s runs of the
# 32-section rubber tube held along a slope) took 120 s under ASan, the longest test there;
# Contact.ATubeLyingOnAFrictionalSlope… (six 1.5 s runs, 16 s optimised) and
# Contact.ACoarseStepIsCut… (four 1 s runs, 7 s) are left out with it: the patches' hold and the
# cut step run sanitized in Contact.ContactsNeverAddEnergy and Contact.ACoarseStepFarFrom….)
# The exact chain step's dynamics tests (ChainDynamics.*: seconds of a 32-joint chain at steps down
# to 1/3840 s, a dense Newton solve each) took 220 s under ASan together; its construction, mass
# matrix and inverse dynamics run sanitized in ChainDynamics.MassMatrixAtRest…. The fused-tube fit
# (FusedTubes.ACurledTubeWithATusk…, 77 s) repeats fit code the other FusedTubes and Shapes tests
# sanitize; Contact.ATubeLyingAlongASlopeOrASoftOne… (63 s) the lying-tube contact that
# Contact.ATubeLyingAlongTheFloorFromItsRootStaysOnIt runs sanitized. Left out for the CI budget
# too (seconds under ASan, measured on a fresh clone): Tool.AllNames… (20 s and 17 s; --all runs
# sanitized in Tool.AnOpenMesh…), BodyProxy.SpheresLieInsideABodyAndFillIt (22 s; the sphere fit
# runs in BodyProxy.NoSphereCutsATailsRestSurface), Contact.AFastSwingNeverEndsAFrameThroughAThinPlate
# (17 s; the swept contact runs in Contact.AFastBodyCannotCarryAPartThroughAWorldCollider) and
# Shapes.TaperToAPoint (11 s; the other Shapes.* tests run the same fit). LargeRotation.StabilityMatrix…
# (16 runs of the exact chain, 1.2 s optimised) repeats the exact step that
# LargeRotation.ASoftTubeReleasedLevel… and ChainDynamics.MassMatrixAtRest… run sanitized.
# Tests named *_long (seconds of the exact chain or of a stress run optimised: minutes under
# ASan; each says in its comment which sanitized test runs its code).
# Blender.* (11 s: Blender playing files the sanitized tools baked in other tests) and the format
# check (sources, not code). `--list` fits every part it offers: the tool tests that list and fit a
# whole real mesh through the sanitized sweep-fit — Tool.PartsWhoseFitIsRefused… (elk, 33 s),
# Tool.APartThatCannotBeFitted… (knot2, 29 s), FileUp.ListNames… (Z-up FBX and Collada, 19 s) and
# FileUp.AZUpFormats… (Z-up .smd and .3ds: four lists, about as long) — are
# left out: the offered-parts search and its fits run sanitized in OfferedParts.* and Tool.AnOpenMesh….
# FitEnds.* (an arm clicked at a fingertip, a neck on its head: 26 and 13 s, level-set meshes made
# by unoptimised test code) carry an end past the tube as Foot.* and TipCut.* do sanitized. Two contact
# tests run one case of two there (Contact.FrictionDrags… one friction, Contact.ATubeLyingAlongTheFloor…
# one stiffness: 26 and 22 s saved).
# LargeRotation.ByDefaultA{Straight,Bent}SoftPartOnABodyTurning… (the exact chain through a quarter
# turn: 2.3 and 0.9 s optimised, 225 and 80 s sanitized); the switch and the exact chain's step run
# sanitized in AutoChain.* and the other LargeRotation.ByDefault* tests.
# HeldRest.TheAsModelledRestOfASoftPartNudged… (a tube nudged and rolling over with three dynamics:
# 3.1 s optimised, 193 s sanitized) and HeldRest.TheVerdictFlips… (6 s of the exact chain twice,
# 40 s sanitized); the held-rest check runs sanitized in HeldRest.HeldLevel… and GravityStart.*,
# the exact chain started from a held rest and kicked in LargeRotation.ByDefaultATipImpulse….
# Also seconds of motion that repeat a sanitized path (seconds under ASan on a fresh clone):
# AutoChain.TheModesStray… (17 s; modes and exact chain side by side in AutoChain.TheSwitchIsOneWay…),
# TruncatedModes.UnderAWalkingBody… (11 s; the truncated step in the other TruncatedModes.*) and
# OfferedParts.PartsTiny… (22 s; the offered-parts search in the other OfferedParts.*).
exclude='Diplodocus|CgalMeshes|OtherMeshes|^Stress\.|BindingFile\.SameInputsGiveTheSameBytesWhateverTheThreadCount|BindAdjacency\.RowsAreSortedUniqueAndSymmetric|BodyProxy\.ATailKickedIntoTheBody|Tool\.AllFitsEveryPartIntoOneRigUnderTheNamesGiven|Tool\.RootOnTheTailsUpperSurfaceFitsTheWholeTail|^ContactFriction\.|Contact\.ASoftTubeLyingOnAFrictionalSlopeStaysOnIt|Contact\.ATubeLyingOnAFrictionalSlope|Contact\.ACoarseStepIsCutIntoContactSteps|ChainDynamics\.(AnUndamped|AReleased|AWhipped|ASoftPart|ASwing|SettledShapes)|FusedTubes\.ACurledTubeWithATusk|Contact\.ATubeLyingAlongASlopeOrASoftOne|Tool\.AllNames|BodyProxy\.SpheresLieInsideABodyAndFillIt|Contact\.AFastSwingNeverEndsAFrameThroughAThinPlate|Shapes\.TaperToAPoint|^Blender\.|^House\.SourcesAreFormatted|LargeRotation\.StabilityMatrix|Tool\.PartsWhoseFitIsRefused|Tool\.APartThatCannotBeFitted|FileUp\.ListNames|FileUp\.AZUpFormats|LargeRotation\.ByDefaultA(Straight|Bent)SoftPartOnABodyTurning|HeldRest\.(TheAsModelledRestOfASoftPartNudged|TheVerdictFlips)|AutoChain\.TheModesStray|TruncatedModes\.UnderAWalkingBody|OfferedParts\.PartsTiny|^FitEnds\.|_long$'
filter=(-E "$exclude")
if [ "${1:-}" = "--all" ]; then
  filter=()
  shift
fi
cmake --preset asan >/dev/null
cmake --build --preset asan -j "$jobs"
ctest --preset asan -j "$jobs" "${filter[@]}" "$@"
