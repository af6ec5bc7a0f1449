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
# glb_frames.md (tools/bench/glb-frames.sh), skin_joints.md (tools/bench/skin-joints.sh),
# step_accuracy.md (tools/bench/step-accuracy.py) and asset-evidence.md (tools/bench/asset-evidence.py)
# come from their own scripts and are kept.
for b in deform skip live integrate beam fit stress framerate follower; do rm -f "$results/$b".csv "$results/$b".md; done
rm -f "$results"/deform_*.png "$results"/fit_*.png "$results"/integrate.png
for kept in fit-evidence.md fit-evidence.png glb_frames.md skin_joints.md step_accuracy.md asset-evidence.md; do
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
{
  echo "mode=$mode"
  echo "elapsed=$elapsed"
  echo "date=$(date -u +%Y-%m-%d)"
  echo "cpu=$(lscpu | sed -n 's/^Model name: *//p' | head -1)"
  echo "cores=$(nproc)"
  echo "threads_per_core=$(lscpu | sed -n 's/^Thread(s) per core: *//p' | head -1)"
  echo "compiler=$(c++ --version | head -1)"
  echo "commit=$(git -C "$here" rev-parse --short HEAD 2>/dev/null || echo unknown)"
  echo "load=$(cut -d' ' -f1-3 /proc/loadavg)"
} > "$results/run-info.txt"
"$here/tools/bench/render-benchmarks.sh" "$results" > "$here/BENCHMARKS.md.tmp"
mv "$here/BENCHMARKS.md.tmp" "$here/BENCHMARKS.md"
echo "bench: wrote $here/BENCHMARKS.md and $results/ (${elapsed} s)" >&2
