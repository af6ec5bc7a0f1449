#!/usr/bin/env bash
# The benchmark suite in one command: builds the Release preset, runs every benchmark,
# and writes BENCHMARKS.md at the top of the repository plus CSV files and PNG plots under
# tools/bench/results/.
#
#   tools/bench/run-benchmarks.sh            # full mode (several minutes)
#   tools/bench/run-benchmarks.sh --quick    # quick mode (under two minutes once built)
#
# Needs the Debian packages of tools/setup-deps.sh (gnuplot-nox for the plots; without gnuplot the
# tables are still written) and CGAL's sample meshes it unpacks into meshes/cgal/.
# Environment: SWEEP_BENCH_BUILD_DIR overrides the build folder (default: the release preset's);
# SWEEP_BENCH_JOBS the build parallelism (default 2).
set -euo pipefail
export LC_ALL=C

here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
mode=full
for a in "$@"; do
  case "$a" in
    --quick) mode=quick ;;
    -h|--help) sed -n '2,13p' "$0"; exit 0 ;;
    *) echo "error: unknown option $a (expected --quick)" >&2; exit 1 ;;
  esac
done
quick=()
[ "$mode" = quick ] && quick=(--quick)

cd "$here"
build=${SWEEP_BENCH_BUILD_DIR:-}
if [ -z "$build" ]; then
  cmake --preset release >/dev/null
  build="$here/build/release"
else
  cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
targets=(sweep-bench-beam sweep-bench-deform sweep-bench-fit sweep-bench-integrate sweep-bench-skip sweep-bench-stress
         sweep-bench-live)
cmake --build "$build" -j "${SWEEP_BENCH_JOBS:-2}" --target "${targets[@]}"

results="$here/tools/bench/results"
mkdir -p "$results"
# Clear only what this script writes: fit-evidence.{md,png} (tools/bench/fit-evidence.py) and
# glb_frames.md (tools/bench/glb-frames.sh) and skin_joints.md (tools/bench/skin-joints.sh) come
# from their own scripts and are kept, as is real-assets.md (recorded by hand).
for b in deform skip live integrate beam fit stress framerate follower; do rm -f "$results/$b".csv "$results/$b".md; done
rm -f "$results"/deform_*.png "$results"/fit_*.png "$results"/integrate.png
for kept in fit-evidence.md fit-evidence.png glb_frames.md skin_joints.md real-assets.md; do
  [ -s "$results/$kept" ] || { echo "error: $results/$kept is missing: run the script that writes it first (see BENCHMARKS.md)" >&2; exit 1; }
done
bin="$build/tools/bench"
start=$(date +%s)
for b in deform skip live integrate beam fit stress; do
  echo "bench: $b ($mode)" >&2
  "$bin/sweep-bench-$b" "${quick[@]}" --out "$results" >/dev/null
done
elapsed=$(( $(date +%s) - start ))

# ---- plots ---------------------------------------------------------------------------------------
if command -v gnuplot >/dev/null; then
  (
    cd "$results"
    # Deformation: time per vertex against the largest error, per mesh and thread count.
    awk -F, 'NR > 1 && $3 ~ /^fast/ {
      m = $1 ~ /random/ ? "tube_random" : ($1 ~ /tube/ ? "tube" : "dino")
      print $5, $9 > ("plot_deform_" m "_" $4 ".dat") }' deform.csv
    for m in dino tube tube_random; do
      plots=()
      for th in 1 2; do
        f="plot_deform_${m}_${th}.dat"
        [ -f "$f" ] && plots+=("'$f' using 1:2 with linespoints title '$th thread(s)'")
      done
      [ ${#plots[@]} -gt 0 ] || continue
      case $m in
        dino) title="diplodocus tail + neck" ;;
        tube) title="1M-vertex tube (ring order)" ;;
        *) title="1M-vertex tube (vertices numbered at random)" ;;
      esac
      gnuplot <<EOF
set terminal png size 800,560
set output 'deform_${m}.png'
set title "Fast path on the ${title}: loop time vs largest error against the exact path"
set xlabel 'ns per vertex (deform loop, median)'
set ylabel 'largest vertex error / part length'
set logscale y
set grid
plot $(IFS=,; echo "${plots[*]}")
EOF
    done
    # Fitting: fit_rms relative to the mean radius against K, one line per part and n.
    awk -F, 'NR > 1 { print $5, $4, $11, $6 > ("plot_fit_" $1 "_" $2 ".dat") }' fit.csv
    for f in plot_fit_*.dat; do
      [ -f "$f" ] || continue
      name=${f#plot_fit_}; name=${name%.dat}
      gnuplot <<EOF
set terminal png size 800,560
set output 'fit_${name}.png'
set title "Fit of ${name}: fit_rms / mean radius against fit time (each point a K, n)"
set xlabel 'fit time, ms (median)'
set ylabel 'fit_rms / mean radius'
set logscale xy
set grid
plot for [n in "4 8 16 32 64"] '$f' using (\$1 == n + 0 ? \$4 : 1/0):3 with linespoints title 'n = '.n
EOF
    done
    # Integration: error at T = 1 s against dt, per integrator.
    awk -F, 'NR > 1 && $4 >= 0 { print $2, $4 > ("plot_int_" $1 ".dat") }' integrate.csv
    gnuplot <<EOF
set terminal png size 800,560
set output 'integrate.png'
set title 'Damped oscillator, error at T = 1 s against the closed form'
set xlabel 'dt (s)'
set ylabel '|x - x*| / amplitude'
set logscale xy
set grid
set key left top
plot 'plot_int_exact.dat' using 1:(\$2 > 0 ? \$2 : 1e-17) with linespoints title 'exact (closed form)', \
     'plot_int_rk4.dat' using 1:2 with linespoints title 'RK4', \
     'plot_int_semi-implicit-euler.dat' using 1:2 with linespoints title 'semi-implicit Euler'
EOF
    rm -f plot_*.dat
  )
else
  echo "warning: gnuplot is not installed (tools/setup-deps.sh): no plots" >&2
fi

# ---- BENCHMARKS.md -------------------------------------------------------------------------------
cpu=$(lscpu | sed -n 's/^Model name: *//p' | head -1)
cores=$(nproc)
threads_per_core=$(lscpu | sed -n 's/^Thread(s) per core: *//p' | head -1)
compiler=$(c++ --version | head -1)
commit=$(git -C "$here" rev-parse --short HEAD 2>/dev/null || echo unknown)
load=$(cut -d' ' -f1-3 /proc/loadavg)
{
  cat <<EOF
# Benchmarks

Generated by \`tools/bench/run-benchmarks.sh${quick:+ --quick}\` ($mode mode, ${elapsed} s of benchmarks) on
$(date -u +%Y-%m-%d) — **${cpu}, ${cores} cores** (${threads_per_core} thread(s) per core, a shared VM),
${compiler}, Release build (\`-O3\`, no \`-march\`; the fast loop is compiled for baseline x86-64 and
AVX2 without FMA and picks one at load time — both give the same bits), commit ${commit}. Times are
wall-clock medians of several runs measured in the same run; other jobs share these cores, so read
the ratios (× floor, × LBS) rather than the absolute figures. Load average when the run ended:
${load} (on ${cores} cores). CSV files and plots are in \`tools/bench/results/\`.

**Reading the figures.** When other jobs keep the second core busy, a parallel loop waits for the
scheduler to give its second thread a time slice: every 2-thread figure then collapses to the same
multiple of a few milliseconds per frame (the copy loop and LBS included), which shows as "× floor ≈
1" and as thousands of ns per vertex on the small diplodocus. Those rows measure the machine's load,
not the loop. Even when idle, this shared VM has slow spells in which the same code runs ~1.5×
slower for seconds at a time (the unchanged simulator step went from 22 to 34 µs): the ratios
measured in one run stay meaningful, single absolute figures less so.

## Deformation: stations per span against error (and the exact path, LBS and the memory floor)

Error measure: the largest distance of any bound vertex from the fast path (float) to the same vertex
from the exact per-vertex path (\`deform_point\`, double) on the same posed sweeps; reference: the
exact path. "loop" is the per-vertex loop alone, "total" adds the per-frame station table. The
floor is a copy loop touching 36 bytes a vertex (24 read + 12 written, in order); the fast loop
reads 16 (20 where a block holds cap vertices) and writes 12, so it can come in under the floor
when its stores stream. LBS is a plain 4-bone linear-blend-skinning loop over the same number of
vertices. The meshes are posed with bending, twisting and radial change on every section (K = 16,
n = 16). The dense tube is measured twice: in ring order, as generated (each work block is one
contiguous range of the mesh, computed straight into it), and with its vertices numbered at random
(the same tube, faces and binding renumbered: no order to exploit, every store on a different cache
line — the worst case).

$(cat "$results/deform.md")

![diplodocus](tools/bench/results/deform_dino.png) ![tube](tools/bench/results/deform_tube.png)
![tube, random order](tools/bench/results/deform_tube_random.png)

### Layout and thread thresholds

Recorded by hand when the fast path's layout and the constants in \`lib/sim/fast_deform.h\` and
\`lib/bind/bind.h\` were chosen (\`tools/bench/sweep-bench-deform\`, \`sweep-bench-skip\`, callgrind and
timed binding runs; Release build, this 2-core VM); this script does not measure them again.

- **Mesh order** (\`FastDeformer::kMinMeanSegmentLength\`). The 1M-vertex tube, 8 stations a span,
  2 threads: sorted by angle cell, the ring-ordered tube wrote 17 rings' worth of scattered runs a
  span and took ~1.7× the copy floor; kept in mesh order with direct stores it takes ~0.8–1.2× the
  floor (it moves 28 bytes a vertex, the floor 36), with bit-identical output. The same tube
  numbered at random (no order to exploit) takes ~4 ns a vertex: every store lands on a different
  cache line.
- **Tiles** (\`FastDeformer::kTileVertices\` = 65,536). The 1M-vertex tube numbered at random,
  2 threads, loop ns/vertex with tiles of this size against none, same run: 16k 0.78×, 32k 0.66×,
  64k 0.63×, 128k 0.63×; ring order unchanged.
- **Whole vectors of radii** (\`kPad\` in \`fast_deform_detail.h\`): a short angle-cell segment costs no
  scalar remainder, −18 % instructions a vertex on the ring-ordered tube (callgrind).
- **One thread for small parts** (\`kParallelVertexThreshold\` = 40,000). Waking a thread team costs
  tens of µs on these machines, more than the loop saves below ~40k vertices at its
  4–6 ns a vertex on one thread.
- **A lone moving sweep is split** (\`kSplitLoneSweepVertices\` = 4,096). The threads are already
  awake from the simulator's and the last frame's work, so a split costs a few µs rather than tens
  ("4 sweeps, 1 driven" on 2 threads in the frame-cost table below).
- **Binding on one thread for small parts** (\`bind::kMinParallelVertices\` = 16,384). Waking an
  OpenMP team costs tens of µs on an idle VM and whole time slices on a busy one: the diplodocus
  bound in 24 ms on one thread and 68 ms on two while the other core was busy.

## Frame cost and skipping

One frame = \`Simulator::advance_frame\` (the default step, 1/480 s, exact integrator) + the fast path on every sweep
that moved (\`deform_sweeps\`), as sweep-sim runs it; sweeps that both have work run side by side on
the two threads (stepping and deforming). "× all driven" is the ratio to the four-sweeps-all-driven
frame with the same thread count. Four generated tubes of ~6,000 vertices each (K = 16, n = 16).
On two threads, driven sweeps run two at a time, and a lone moving sweep is split across both
cores. Every case is measured once a round, 9 rounds (3 in quick mode), and each figure is the
median over the rounds, so that a ratio compares cases measured in the same stretch of time; the
four sweeps together (~1.5 MB of working data) no longer fit one core's L2, so "4 driven" costs a
little more than four times "1 driven". Frames run back to back, as in a bake; the "1/60 s apart"
rows pace them like a 60 fps runtime, where between frames the caches cool and the worker threads
fall asleep (waking them is part of the cost). The two "step 1/480 s" rows compare material mode (issue
12: the coupled chain stepped by its modes, with gravity, real moments; E = 50 MPa, ρ = 1000 kg/m³,
25 m per unit, the demo's material) with the paper's independent springs, same forces, same clock,
measured in alternating rounds. The last row runs the same material frame on a body that walks
and turns all the way (a cubic path) in a gusty wind: inertia and drag against the still body's frame.
The "collider" rows run that walking material frame (without the wind) with the
demo's ground plane and leg capsules (rigs/diplodocus-walk.scene.json): first the ground and three
legs, then 16 colliders (the fourth leg and 11 spheres about the body), none of which the parts touch — what the
broad phase costs: a part's bounding sphere against each collider, then each span near one, then
each chord near one, with the tail passing within a radius and a half of a hind leg for much of
the walk —; then a floor raised into the tail's way, so that the tail lies on it while the body
walks (the contact solver's cost: some 30 contacts a step), and the same with the body still, where
the tail settles on the floor and sleeps.

$(cat "$results/skip.md")

### The live frame through libsweep (\`sweep-bench-live\`)

A game's frame: the diplodocus tail and neck in material mode with gravity (pre-loaded), a new
body pose every frame (a slow walk with a sway), frames 1/60 s apart, through the C interface
(\`sweep_set_body\` + \`sweep_advance\`: step and deform; \`sweep_positions\`, the world-space copy of
all vertices an engine uploads, apart), against the scene player's frame (\`advance_frame\` and the
fast path, what \`sweep-sim\` does per output frame) in the same run, at 30 fps (16 internal steps a
frame) and at 60 fps (8), and the live simulator in C++ with step and deform timed apart. The last
two rows: libsweep with frames back to back (warm caches, no sleeping threads), and with the
settings' \`step\` at 1/120 s (2 internal steps a frame instead of 8). Median over frames after the
first 10, median over rounds (5; 3 in quick mode) alternating cases and thread counts.

$(cat "$results/live.md")

## Integration: integrator × dt against the closed-form oscillator

Error measure: |x(T) − x*(T)| / |x0 − f/k| at T = 1 s; reference: the textbook closed form in long
double (m = 1 kg, f0 = 1.5 Hz, ζ = 0.1, x0 = 1, constant force 2 N). Cost: one step of one
oscillator in a flat bank of 4,096 (every integrator is the same affine map once set up), and the
one-off map setup per (parameters, dt).

$(cat "$results/integrate.md")

![integration](tools/bench/results/integrate.png)

### Frame-rate spread

The same scene (diplodocus: tail pushed sideways at its tip for 0.5 s, neck pushed down for 1/3 s,
chain moments, then free) baked at 24, 30 and 60 fps and compared with the same clock and
integrator at 144 fps, at every time all four share (every 1/6 s over 2 s). Error measure: the
largest distance of any bound vertex (exact path) from the 144 fps pose, over the part's length.
With a step of its own (scene \`step\`; the default when a scene gives neither \`step\` nor
\`substeps\`) the internal steps are the same at any frame rate and each frame is reached by an
exact partial step, so the poses agree to the bit (0 is an exact zero, not a rounding); the old
clock (\`substeps\` per frame, kept so that old scenes give their old frames) ties the step to the
frame rate.

$(cat "$results/framerate.md")

### Follower loads: step against error and cost

The diplodocus Fig. 4 scene (\`rigs/diplodocus-fig4.scene.json\`), exact integrator. Loads that
follow the moving surface are split again at the predicted mid-step pose, so halving the step
quarters the error. Error measure: the largest difference of any section's centre, radius or
rotation (angle × length) over every frame, over the part's length; reference: a step 64 times
finer than the default. Cost: stepping both parts for one simulated second (no deformation), median.

$(cat "$results/follower.md")

## Material mode against beam theory: K sections against error and cost

Generated straight tubes (\`tests/core/beam_tubes.h\`): 3.1 m long, 5 cm in radius, 32 radii,
E = 10 MPa, ν = 0.45, ρ = 1100 kg/m³, clamped at the root, K sections evenly spaced. Error measure:
model / theory − 1 for the tip deflection under a small tip load (F L³ / 3EI) and under its own
weight (w L⁴ / 8EI), the first three bending frequencies (Euler–Bernoulli clamped–free, βL =
1.8751, 4.6941, 7.8548), the first twist frequency (π/2 · √(GJ/ρJ_p) / L), and, for an elliptical
tube twice as wide as deep, the ratio of its tip deflections down and across against the ratio of
its polygon's second moments. Deflections and bending converge as K⁻², twist too. Cost: building
the model once per rig (section properties, the generalized eigenproblem of K and M) and one step
of the whole sweep under a chain force (median). The tests assert these bars at K = 32
(\`tests/core/beam_test.cpp\`).

$(cat "$results/beam.md")

## Fitting: K × n against fit time and fit error

Error measure: fit_rms / fit_max, the RMS and largest radial distance |ρ − r(θ,t)| of the part's
vertices from the fitted surface, in % of the part's mean radius; reference: the mesh's own
vertices. Time: median fit time with the slicer already built, without the error measurement.

$(cat "$results/fit.md")

## Fitting real parts from clicks

\`tools/bench/fit-evidence.py\` (Release build; Debian 12, 2-core AMD EPYC, while a fuzzing run used
the other core). Each part is fitted once at the defaults (K = 24, n = 24) from a tip clicked near
its end, the root found by the tool (one arm also given a root click); none of these meshes was used
by the project before. The clicks: the tip \`--list\` reports (or, for a part it does not name, the end
read off the preview) moved half a mean radius along (1,1,1) and rounded to the radius' leading
digit; no click was changed after seeing a fit. "fit RMS" and "90 % within" are the part's vertices'
distances to the fitted surface over the mean radius, "surface to part RMS" the other way (the
sweep's samples to the part's faces) and "surface 90 % within" its 90th percentile (over 20 %
the fit is refused: the sweep leaves the mesh between the part's vertices); "traced / surface" is the axis length over
the surface distance from the root ring to the tip (a foot, a paw or a head at the end lengthens
the surface path, not the axis); "axis end to tip" is in mean radii. Exit 2 is a fit the tool
refused (no rig written) with the numbers and what to try.

$(sed -n '1,/^$/p' "$results/fit-evidence.md")

![contact sheet: every part above, front, side and top](tools/bench/results/fit-evidence.png)

What it shows. With each section's radii fitted to the part's vertices by least squares (a slice
runs through the facets' chords, inside the vertices; fit/radii_fit.cpp), 17 parts from 11 meshes
fit at ≤ 2 % RMS with the root found and the clicks as the rule gives them: arms and legs leaving a
broad body (bear, homer, bull, refined_elephant, armadillo, ChineseDragon-10kv), tails lying against
the body on coarse meshes (camel, cow: 8–20 vertices round), arms bent 90° at the body (cactus),
parts tapering to a point (armadillo's tail and claw, bull's horn, man's finger), a flat ear
(bunny00). "fit RMS" is now what the fit minimises; "surface to part RMS", the sweep's samples to
the part's faces, is the independent check: ≤ 4.3 % on all of those. (It now counts the faces
across the root section: before, a sample at the root of a coarse part was measured a ring of
faces away, 23–29 % on man's finger and cow's tail, an artefact of the measure.) Short of the mark,
and why:
- **curled**: no real part of a full curl fits. refined_elephant's trunk and elephant's S-curved
  trunk touch the tusks where they leave the head. The part no longer floods through the contact
  into the head (the walk is bounded to 1.5 local radii of the axis, what lies beyond judged a
  bridge or a protrusion: 44,460 → 6,213 and 2,775 → 375 vertices; 90 % within 52.8 → 15.5 % and
  57.0 → 11.7 %), but the root is found where the tusks meet the trunk, half-way down, and the
  tusks' ends within the bound stay in the part: still refused (exit 2). bull's tail (half a turn) ends in a tuft that is no tube: 6.3 %,
  refused by the 90 % limit. The generated curl of 330° (tests/fit/shapes_test.cpp) fits.
- **L-shaped with a sharp elbow**: armadillo's raised arm (armour plates, a hand at the end) 2.5 %;
  dino's hind leg (knee and ankle bent, claws at the end) refused (14.1 % at 90 %, 68.6 % before
  the bound). The cactus's arms, bent 90°
  within three radii of the body, fit at 0.2 %.
- **lying against the body**: refined_elephant's tail (a tuft at the end) 2.7 %; man's fist is
  fused to his hip: bounded now, 18.1 % at 90 % (27.4 % before), still refused.
- flat parts: armadillo's ear 3.8 %; homer's legs touch at the thighs below the root found, so the
  right leg's part still takes some of the left (42.3 % at 90 %, was 95.5 %): refused.

\`--list\`, then \`--all\` (with \`--force\`, so that a refused part is still written and the rest can run),
\`sweep-bind\` and \`sweep-sim\` (a push at each part's tip) on eleven meshes; the suggested names assume
+Y up:

$(sed -n '/^$/,$p' "$results/fit-evidence.md" | sed 1d)

Speed (Release, same machine, median of 5 runs, wall time including reading the mesh):
\`sweep-fit diplodocus.off --list\` 0.47 s (6 parts); one fit of the diplodocus tail at K = 32,
n = 32, \`--root\` and \`--tip\` given, 0.15 s; the same with the root found, 0.15 s; \`--all\` (6 parts)
0.95 s (median of 3). The least-squares radii and the section checks cost, measured against the
build before them in one run on a busy machine (load 5.7: every time about 3× the quiet figures
above): the tail fit 0.59 s against 0.53 s (1.11×), with the root found 0.63 against 0.51 (1.24×),
\`--all\` 3.48 against 3.25 (1.07×), \`--list\` unchanged (it fits nothing).


## Parts found on models from other tools (\`--list\`)

$(cat "$results/real-assets.md")

## .glb size and memory against frames

\`tools/bench/glb-frames.sh\` (Release): the bent example tube (1,178 vertices, all moving) baked to
\`.glb\` at 60 fps. One morph target a frame, with POSITION and NORMAL deltas (the normals so that a
bent part is lit as bent), and the weights animation stored as a sparse accessor (one index and one
value a key over implied zeros): the file grows linearly, ~28 kB a frame here (14 kB before the
normal deltas; before the sparse weights, the dense one-hot weights added F² floats: 102 MB at
3,600 frames, and 2.5 GB more at 25,000). Vertex data streams through a scratch file; the memory
that grows (~9 kB a frame) is the JSON chunk, built whole by tinygltf, with two accessors and
views for each target.

$(cat "$results/glb_frames.md")

## Skinned .glb: joints against error and size (\`--joints N --ring-joints M\`)

\`tools/bench/skin-joints.sh build/release/tools\` (release build, \`cmake --preset release\`): CGAL's
diplodocus, tail and neck fitted and bound as the demo does (K = 24, n = 24, blend 0.02), the
Fig. 4 scene at 150 fps (its 4 s in 601 frames), baked with \`--exact\` so that the error is the
skin's alone. N station joints along each sweep, M ring joints around each station but the root
(M = 1: none, the station joint scales and shifts its whole section, the skin before ring joints);
"--ring-fit": the ring joints' keys by least squares instead of the sampled radius ratio. Error:
the writer's own figure (\`skin_error_max_relative\`, \`skin_error_rms_relative\`): every bound vertex
of every frame skinned from the floats the file holds, against the exact bake, over the length of
its part. Size: the \`.glb\`'s bytes, beside the morph-target \`.glb\` of the same bake (POSITION and
NORMAL deltas, one target a frame); ratios from one run (sizes are exact and repeatable). Write
time: the report's \`seconds.write\` (for the skin: keys, the error measurement and the file),
median of 3 runs. Machine: Debian 12, 2-core AMD EPYC (AVX2), shared — other agents were building
and testing on the same 2 cores during these runs, so the write times are noisy (e.g. the
morph-target bake's 1.0 s against 0.44 s on a quiet machine); the errors and sizes are exact.

$(cat "$results/skin_joints.md")

**Reading it.** The issue's target, at the default N × M — largest error ≤ 1 % of the length and
the file ≤ 1/20 of the morph-target bake — is met by **24 × 24, the default of \`--joints\` alone:
0.475 % and 1/29** (RMS 0.014 %). Section joints alone (M = 1) stop at 2.0 % from N = 8 on: the
scene's radial pushes dent a section over a few of its 24 radial handles (the largest at the
neck's tip, by the head, vertex 622, frame 57), which no whole-section scale and shift can follow.
Ring joints follow it once they sit where the handles are: a ring of 24 at the 24 handle angles
and stations on the 24 key sections (24 × 24: both coincide with the fit's sections and handles)
carry the dent exactly at the handles, and between them only the sweep's cubics (Catmull-Rom in
θ, Hermite in t) differ from the skin's hats. Fewer ring joints than handles interpolate a
one-handle dent linearly between joints 2–6 handles apart, so 8 × 8 is still 1.8 % and 16 × 12
1.2 %; M = 4 is worse than M = 1 (four uniform in-plane scales lose the per-axis scale and shift
of the section joint). The size stays small because a ring joint is keyed only when its radius
changes (12 bytes a frame, a scale), and in this scene few handles move: 1,153 joints cost 2.7 MB.
\`--ring-fit\` lowers the error further (24 × 24: 0.19 %) but keys every ring joint (10.8 MB,
1/7.3); it is off by default. Which ring motion: a ring joint that scales in-plane reproduces the
sweep better than one that translates along its radial direction (the one-handle dent on the test
tube, 6 × 8 joints: 0.61 % against 0.84 % of the length, RMS 0.052 % against 0.077 %; the scale
moves each vertex along its own direction and in proportion to its depth, as the sweep does), so
scale is what the writer keys. Engines with a cap on a skeleton's joints can take 12 × 24 (553 joints,
0.98 %, 1/35; measured with the dev build) — 16 × 24 is just over, 1.001 %.

## Stress

Random seeded forces (1 to 3 at a time, re-drawn every 50 steps, random components, section
targets and moment models, occasional impulses, up to 1,000 N) on the diplodocus tail, the first
half of each run forced and the second free. Checked after every step: all values finite, radii
positive, frames orthonormal (max |RᵀR − I| < 1e-6); in the free half, with damping, the energy
never grows (relative tolerance 1e-9) and, where the springs' decay predicts it within the run, the
sweep returns to rest. Fast versions of these runs are in \`tests/stress\`.

$(cat "$results/stress.md")
EOF
} > "$here/BENCHMARKS.md"
echo "bench: wrote $here/BENCHMARKS.md and $results/ (${elapsed} s)" >&2
