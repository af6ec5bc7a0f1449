#include "sweep/fit/tube_end.h"

#include <algorithm>
#include <cmath>

namespace sweep::fit {

// The value a tenth of the distances exceed (nth_element: linear, reorders the copy it is given).
double percentile_90(std::vector<double> distances) {
  if (distances.empty()) return 0;
  const auto p90 = distances.begin() + static_cast<std::ptrdiff_t>(distances.size() * 9 / 10);
  std::nth_element(distances.begin(), p90, distances.end());
  return *p90;
}

std::optional<TubeEnd> find_tube_end(const SweepShape& shape, std::span<const std::pair<double, double>> along,
                                     double limit, double mean_radius) {
  const int k = shape.section_count();
  if (k < 3 || along.empty()) return std::nullopt;
  std::vector<double> sum2(static_cast<std::size_t>(k - 1), 0.0);
  std::vector<std::size_t> count(static_cast<std::size_t>(k - 1), 0);
  const auto span_of = [&](double t) {
    const auto i = std::upper_bound(shape.t.begin(), shape.t.end(), t) - shape.t.begin() - 1;
    return static_cast<std::size_t>(std::clamp<std::ptrdiff_t>(i, 0, k - 2));
  };
  for (const auto& [t, dist] : along) {
    sum2[span_of(t)] += dist * dist;
    ++count[span_of(t)];
  }
  const auto off_tube = [&](int i) {
    const auto u = static_cast<std::size_t>(i);
    return count[u] > 0 && std::sqrt(sum2[u] / static_cast<double>(count[u])) > kEndCutSpanShare * limit;
  };
  // From the tip end back: the run goes on over spans with no vertex measured (neither on nor
  // off) and over fitting stretches shorter than kMaxEndGapRadii mean radii (a toe's gap); by
  // length, not by span, so that it is the same run at any section count.
  int end_first = k - 1;  // the run's first section (k − 1: no run)
  double gap = 0;         // fitting length since the run's last span off the tube (or the tip)
  for (int i = k - 2; i >= 0; --i) {
    if (count[static_cast<std::size_t>(i)] == 0) continue;
    if (off_tube(i)) {
      end_first = i;
      gap = 0;
      continue;
    }
    gap += shape.t[static_cast<std::size_t>(i) + 1] - shape.t[static_cast<std::size_t>(i)];
    if (gap > kMaxEndGapRadii * mean_radius) break;
  }
  TubeEnd end;
  end.first_section = end_first;
  end.t = shape.t[static_cast<std::size_t>(end_first)];
  std::vector<double> before;
  double end2 = 0, before2 = 0;
  for (const auto& [t, dist] : along) {
    if (t < end.t) {
      before.push_back(dist);
      before2 += dist * dist;
    } else {
      end2 += dist * dist;
    }
  }
  const double length = shape.length();
  if (end_first <= 0 || end_first >= k - 1 || end.t < (1 - kMaxEndCutShare) * length ||
      length > kMaxEndCutSpacingRadii * mean_radius * (k - 1) || before.empty() || percentile_90(before) > limit)
    return std::nullopt;
  end.end_count = along.size() - before.size();
  end.end_rms = std::sqrt(end2 / static_cast<double>(std::max<std::size_t>(end.end_count, 1)));
  end.before_rms = std::sqrt(before2 / static_cast<double>(before.size()));
  end.share = 1 - end.t / length;
  return end;
}

std::vector<TubeEnd> wide_end_cuts(const SweepShape& shape, std::span<const std::pair<double, double>> along,
                                   double limit) {
  std::vector<TubeEnd> out;
  const int k = shape.section_count();
  if (k < 3 || along.empty()) return out;
  std::vector<double> sum2(static_cast<std::size_t>(k - 1), 0.0);
  std::vector<std::size_t> count(static_cast<std::size_t>(k - 1), 0);
  for (const auto& [t, dist] : along) {
    const auto i = std::upper_bound(shape.t.begin(), shape.t.end(), t) - shape.t.begin() - 1;
    const auto span = static_cast<std::size_t>(std::clamp<std::ptrdiff_t>(i, 0, k - 2));
    sum2[span] += dist * dist;
    ++count[span];
  }
  int first = -1;
  for (int i = 0; i < k - 1 && first < 0; ++i) {
    const auto u = static_cast<std::size_t>(i);
    if (count[u] > 0 && std::sqrt(sum2[u] / static_cast<double>(count[u])) > kEndCutSpanShare * limit) first = i;
  }
  const double length = shape.length();
  for (int cut = first; cut >= std::max(1, first - kMaxWideEndSteps); --cut) {
    TubeEnd end;
    end.first_section = cut;
    end.t = shape.t[static_cast<std::size_t>(cut)];
    end.share = 1 - end.t / length;
    double end2 = 0, before2 = 0;
    std::size_t before = 0;
    for (const auto& [t, dist] : along) {
      if (t < end.t) {
        before2 += dist * dist;
        ++before;
      } else {
        end2 += dist * dist;
      }
    }
    if (before == 0) continue;
    end.end_count = along.size() - before;
    end.end_rms = std::sqrt(end2 / static_cast<double>(std::max<std::size_t>(end.end_count, 1)));
    end.before_rms = std::sqrt(before2 / static_cast<double>(before));
    out.push_back(end);
  }
  return out;
}

}  // namespace sweep::fit
