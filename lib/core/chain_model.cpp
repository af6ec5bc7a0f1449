#include "sweep/core/chain_model.h"

#include <cassert>
#include <cmath>
#include <numbers>

#include "sweep/core/section_properties.h"

namespace sweep {
ChainModel build_chain_model(const SweepShape& rest, const std::vector<Material>& materials) {
  const int k = rest.section_count();
  const int n = rest.radial_count;
  assert(k >= 2 && static_cast<int>(materials.size()) == k);
  ChainModel m;
  m.joints = k - 1;
  const double s = materials[0].metres_per_unit;
  m.metres_per_unit = s;
  const int dim = 3 * m.joints;

  // Lengths each section stands for (metres): for its mass, half of each span beside it; for its
  // joint's stiffness the same, plus the first span's root half for joint 1.
  std::vector<double> mass_len(k, 0.0), stiff_len(k, 0.0);
  for (int i = 1; i < k; ++i) {
    const double h = s * (rest.t[i] - rest.t[i - 1]);
    mass_len[i] += 0.5 * h;
    mass_len[i - 1] += 0.5 * h;
    stiff_len[i] += 0.5 * h;
    stiff_len[i - 1] += 0.5 * h;
  }
  const std::vector<double> patch_len = mass_len;  // the root's radial handles stand for a half span too
  m.section_length = patch_len;
  mass_len[0] = 0;
  stiff_len[1] += stiff_len[0];
  stiff_len[0] = 0;

  std::vector<SectionProperties> props(k);
  std::vector<double> scaled(n);
  for (int i = 0; i < k; ++i) {
    for (int j = 0; j < n; ++j) scaled[j] = s * rest.radius_sample(i, j);
    props[i] = section_properties(scaled);
  }

  m.mass = Eigen::MatrixXd::Zero(dim, dim);
  m.stiffness = Eigen::MatrixXd::Zero(dim, dim);
  m.node_mass.assign(k, 0.0);
  m.node_inertia.assign(k, Vec3::Zero());
  Eigen::MatrixXd jl = Eigen::MatrixXd::Zero(3, dim), ja = Eigen::MatrixXd::Zero(3, dim);
  for (int i = 1; i < k; ++i) {
    const Material& mat = materials[i];
    const SectionProperties& p = props[i];
    const double rho_l = mat.density * mass_len[i];
    m.node_mass[i] = rho_l * p.area;
    m.node_inertia[i] = Vec3(rho_l * p.i_xx, rho_l * p.i_yy, rho_l * p.polar);
    const Eigen::Matrix3d r = rest.frames[i].rotation.toRotationMatrix();
    const Eigen::Matrix3d inertia = r * m.node_inertia[i].asDiagonal() * r.transpose();
    // Node i at rest: joint j turns it about c_j (j < i) and turns its own frame (j ≤ i).
    jl.setZero();
    ja.setZero();
    const Vec3 ci = s * rest.frames[i].center;
    for (int j = 1; j <= i; ++j) {
      const Eigen::Matrix3d rj = rest.frames[j].rotation.toRotationMatrix();
      jl.middleCols<3>(3 * (j - 1)) = -skew(ci - s * rest.frames[j].center) * rj;
      ja.middleCols<3>(3 * (j - 1)) = rj;
    }
    m.mass.noalias() += m.node_mass[i] * jl.transpose() * jl + ja.transpose() * inertia * ja;
    // Bending: the joint's compliance is that of the half spans around it (a midpoint rule for the
    // deflection, whose lever arms start at the joint). Twist has no lever arm: the angle at
    // section i is the sum of the twists of the spans before it, so joint i stands for its span.
    const double l = stiff_len[i], span = s * (rest.t[i] - rest.t[i - 1]);
    m.stiffness.block<3, 3>(3 * (i - 1), 3 * (i - 1)) =
        Eigen::Vector3d(mat.youngs_modulus * p.i_xx / l, mat.youngs_modulus * p.i_yy / l,
                        mat.shear() * p.torsion / span)
            .asDiagonal();
  }

  m.compliance = m.stiffness.diagonal().cwiseInverse();

  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(m.stiffness, m.mass);
  m.modes = eig.eigenvectors();
  m.omega2 = eig.eigenvalues();
  // A mode's damping ratio: the material's at the joint that moves most in it (M-weighted).
  m.damping_ratio.assign(dim, materials[0].damping_ratio);
  for (int c = 0; c < dim; ++c) {
    Eigen::Index joint = 0;
    m.modes.col(c).cwiseAbs().maxCoeff(&joint);
    m.damping_ratio[c] = materials[1 + joint / 3].damping_ratio;
  }

  // Positional springs: each carries the mass beyond it (a shift moves everything beyond).
  m.positional.assign(static_cast<std::size_t>(3) * k, OscillatorParams{});
  double beyond = 0;
  for (int i = k - 1; i >= 1; --i) {
    beyond += m.node_mass[i];
    const Material& mat = materials[i];
    const double a = props[i].area, l = stiff_len[i];
    const double ks[3] = {kShearCoefficient * mat.shear() * a / l, kShearCoefficient * mat.shear() * a / l,
                          mat.youngs_modulus * a / l};
    for (int c = 0; c < 3; ++c) {
      // m ẍ + c ẋ + k x = f in metres is (m s) ẍ_u + (c s) ẋ_u + (k s) x_u = f in mesh units.
      const double damping = 2 * mat.damping_ratio * std::sqrt(ks[c] * beyond);
      m.positional[3 * i + c] = {beyond * s, damping * s, ks[c] * s};
    }
  }

  // Radial handles: handle j of section i moves the wedge of the section around it (angle 2π/n,
  // radius r) over the length the section stands for, h. A radial field growing linearly from the
  // axis, u = δ ρ/r, strains the wedge uniformly by δ/r: its energy ½ E (δ/r)² V with V = π r² h/n
  // gives k = E π h / n, and its kinetic energy the moving mass ρ V / 2. So ω = √(2E/ρ) / r: the
  // surface of a thin part is stiffer than a thick one's, as it should be.
  m.radial.assign(static_cast<std::size_t>(k) * n, OscillatorParams{});
  for (int i = 0; i < k; ++i) {
    const Material& mat = materials[i];
    const double h = patch_len[i];
    for (int j = 0; j < n; ++j) {
      const double r = s * rest.radius_sample(i, j);
      const double mass = mat.density * std::numbers::pi * r * r * h / (2.0 * n);
      const double stiffness = mat.youngs_modulus * std::numbers::pi * h / n;
      const double damping = 2 * mat.damping_ratio * std::sqrt(stiffness * mass);
      m.radial[static_cast<std::size_t>(i) * n + j] = {mass * s, damping * s, stiffness * s};
    }
  }
  return m;
}

}  // namespace sweep
