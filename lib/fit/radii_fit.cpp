// Radius samples fitted to the part's vertices by least squares (fit.h, fit_radii).
//
// The slices give each key section the radii of one plane's polygon: on a faceted mesh that
// polygon runs through the facets' chords, inside the vertices, and between the sections the
// surface follows only what the interpolation makes of them (a bump, an armour plate, a bend
// between two planes is missed). The sweep's radius r(θ, t) is linear in its samples
// (Catmull-Rom in θ, Hermite with finite-difference slopes in t), and a vertex's sweep coordinates
// (t, θ, its distance ρ from the axis) do not depend on them, so the samples that best match the
// vertices' distances solve a linear least-squares problem:
//     min Σ_v w_v (r(θ_v, t_v) − ρ_v)² + λ Σ_q (r_q − r_q⁰)²,
// where the small pull to the slice radii r⁰ keeps samples no vertex reaches where the slices put
// them. Two passes: the second down-weights vertices far off the first fit (a toe or a tuft that
// no tube follows), so they do not drag the rest of the section out.
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <vector>

#include "sweep/core/locate.h"
#include "sweep/fit/fit.h"

namespace sweep::fit {
namespace {

// The pull to the slice radii, per sample, as a share of the mean weight a sample gets from the
// vertices: enough to pin a sample no vertex reaches, too little to hold one that many do.
constexpr double kPullShare = 0.05;
// Smoothness, per second difference, as a share of the same mean weight.
constexpr double kBendShare = 0.01;
// Second pass: weights 1 / (1 + (residual / (kRobustScale · rms))²).
constexpr double kRobustScale = 2;
// A fitted sample stays within this factor of its slice radius either way (a safeguard against
// an ill-posed sample; the fit moves radii by a few percent).
constexpr double kMaxChange = 2;

struct Row {
  std::vector<std::pair<int, double>> weights;  // (sample index q = i·n + j, coefficient)
  double rho = 0;                               // the vertex's distance from the axis
};

}  // namespace

int fit_radii(SweepShape& shape, const Mesh& mesh, const std::vector<std::uint32_t>& vertices) {
  const int n = shape.radial_count;
  const int k = shape.section_count();
  const int unknowns = k * n;
  const SweepLocator locator(shape);
  // Coefficients by linearity: with every sample 1, r ≡ 1; raising sample q by 1 raises r(θ, t)
  // by its coefficient. Only the 4 × 4 samples around (θ, t) can have one.
  SweepShape unit = shape;
  std::fill(unit.radii.begin(), unit.radii.end(), 1.0);
  std::vector<Row> rows;
  rows.reserve(vertices.size());
  for (const std::uint32_t v : vertices) {
    const SweepCoords c = locator.locate(mesh.positions[v]);
    if (c.z != 0 || !std::isfinite(c.s)) continue;  // beyond the end sections
    Row row;
    row.rho = c.s * radius_at(shape, c.theta, c.t);
    const SpanCoord sc = locate_span(shape, c.t);
    const AngleCoord ac = locate_angle(n, c.theta);
    for (int i = std::max(sc.span - 1, 0); i <= std::min(sc.span + 2, k - 1); ++i) {
      for (int dj = -1; dj <= 2; ++dj) {
        const int j = ((ac.j + dj) % n + n) % n;
        const std::size_t q = static_cast<std::size_t>(i) * n + static_cast<std::size_t>(j);
        unit.radii[q] = 2.0;
        const double w = radius_at(unit, c.theta, c.t) - 1.0;
        unit.radii[q] = 1.0;
        if (w != 0) row.weights.emplace_back(static_cast<int>(q), w);
      }
    }
    if (!row.weights.empty() && std::isfinite(row.rho)) rows.push_back(std::move(row));
  }
  if (rows.empty()) return 0;

  std::vector<double> weight(rows.size(), 1.0);
  Eigen::VectorXd prior(unknowns);
  for (int q = 0; q < unknowns; ++q) prior[q] = shape.radii[static_cast<std::size_t>(q)];
  Eigen::VectorXd solution = prior;
  for (int pass = 0; pass < 2; ++pass) {
    // The normal matrix is banded: a sample couples with samples of at most 3 sections and 3
    // angles either way (a row's 4 × 4, the second differences), so each column is reserved
    // that many entries and summed in place (no list of a row's 16² products per vertex).
    Eigen::SparseMatrix<double> normal(unknowns, unknowns);
    normal.reserve(Eigen::VectorXi::Constant(unknowns, 7 * 7));
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(unknowns);
    std::vector<double> reach(static_cast<std::size_t>(unknowns), 0.0);
    for (std::size_t r = 0; r < rows.size(); ++r) {
      const Row& row = rows[r];
      for (const auto& [a, wa] : row.weights) {
        rhs[a] += weight[r] * wa * row.rho;
        reach[static_cast<std::size_t>(a)] += weight[r] * wa * wa;
        for (const auto& [b, wb] : row.weights) normal.coeffRef(a, b) += weight[r] * wa * wb;
      }
    }
    double mean_reach = 0;
    for (const double x : reach) mean_reach += x;
    mean_reach /= unknowns;
    const double pull = kPullShare * std::max(mean_reach, 1e-300);
    for (int q = 0; q < unknowns; ++q) {
      normal.coeffRef(q, q) += pull;
      rhs[q] += pull * prior[q];
    }
    // Smoothness: second differences around each section (periodic) and along the sweep, so
    // that a sample follows its neighbours where few vertices decide it.
    const double bend = kBendShare * std::max(mean_reach, 1e-300);
    const auto add_second_difference = [&](int a, int b, int c) {
      const int idx[3] = {a, b, c};
      const double coef[3] = {1, -2, 1};
      for (int x = 0; x < 3; ++x)
        for (int y = 0; y < 3; ++y) normal.coeffRef(idx[x], idx[y]) += bend * coef[x] * coef[y];
    };
    for (int i = 0; i < k; ++i) {
      for (int j = 0; j < n; ++j) {
        add_second_difference(i * n + (j + n - 1) % n, i * n + j, i * n + (j + 1) % n);
        if (i > 0 && i + 1 < k) add_second_difference((i - 1) * n + j, i * n + j, (i + 1) * n + j);
      }
    }
    normal.makeCompressed();
    const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(normal);
    if (solver.info() != Eigen::Success) return 0;
    const Eigen::VectorXd x = solver.solve(rhs);
    if (solver.info() != Eigen::Success || !is_finite(x)) return 0;
    solution = x;
    // Residuals of this pass: the weights of the next.
    double sum2 = 0;
    std::vector<double> residual(rows.size());
    for (std::size_t r = 0; r < rows.size(); ++r) {
      double fitted = 0;
      for (const auto& [a, wa] : rows[r].weights) fitted += wa * x[a];
      residual[r] = fitted - rows[r].rho;
      sum2 += residual[r] * residual[r];
    }
    const double scale = kRobustScale * std::sqrt(sum2 / static_cast<double>(rows.size()));
    for (std::size_t r = 0; r < rows.size(); ++r) {
      const double u = scale > 0 ? residual[r] / scale : 0;
      weight[r] = 1 / (1 + u * u);
    }
  }
  for (int q = 0; q < unknowns; ++q) {
    const double r0 = prior[q];
    shape.radii[static_cast<std::size_t>(q)] = std::clamp(solution[q], r0 / kMaxChange, r0 * kMaxChange);
  }
  return static_cast<int>(rows.size());
}

}  // namespace sweep::fit
