#include "sweep/core/held_rest.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <memory>
#include <vector>

#include "sweep/core/chain_dynamics.h"
#include "sweep/core/section_properties.h"

namespace sweep {
namespace {

// The central differences' step, radians: the residual's rounding (1e-16 of the pre-load) over it
// is 1e-10 of the stiffness, its truncation (the third derivative) 1e-12.
constexpr double kTurn = 1e-6;

double beta_of(const SweepDef& def, const ChainModel& model, const Vec3& gravity) {
  const SweepShape& rest = def.rest;
  double mass = 0;
  for (const double m : model.node_mass) mass += m;
  const double length = model.metres_per_unit * rest.length();
  std::vector<double> radii(static_cast<std::size_t>(rest.radial_count));
  for (int j = 0; j < rest.radial_count; ++j) radii[j] = model.metres_per_unit * rest.radius_sample(1, j);
  const SectionProperties p = section_properties(radii);
  const double ei = def.section_materials[1].youngs_modulus * std::min(p.i_xx, p.i_yy);
  return mass * gravity.norm() * length * length / ei;
}

}  // namespace

HeldRest held_rest(const SweepDef& def, const ChainModel& model, const Vec3& gravity) {
  HeldRest out;
  const Eigen::Index dim = 3 * model.joints;
  ChainDynamics chain(std::make_shared<const ChainModel>(model), def.rest);
  ChainDynamics::Body body;
  body.gravity = gravity;
  // The pre-load that holds the rest pose, as ElasticSweep::set_gravity gives it.
  const Eigen::VectorXd still = Eigen::VectorXd::Zero(dim);
  Eigen::VectorXd load(dim);
  chain.inverse_dynamics(still, still, body, load);
  load = -load;
  chain.set_rest_load(std::span<const double>(load.data(), static_cast<std::size_t>(dim)));
  // K + G, column by column (at φ = 0 a turn applied on the joint's left is φ itself).
  Eigen::MatrixXd tangent(dim, dim);
  Eigen::VectorXd phi = still, plus(dim), minus(dim);
  for (Eigen::Index c = 0; c < dim; ++c) {
    phi[c] = kTurn;
    chain.static_residual(phi, body, plus);
    phi[c] = -kTurn;
    chain.static_residual(phi, body, minus);
    phi[c] = 0;
    tangent.col(c) = (plus - minus) / (2 * kTurn);
  }
  // Symmetric at an equilibrium (the residual is an energy's gradient there); the differences'
  // asymmetry is their rounding.
  tangent = (0.5 * (tangent + tangent.transpose())).eval();
  // −G v = f K v with K diagonal (and positive): as K^{-½} (−G) K^{-½} u = f u.
  const Eigen::VectorXd k = model.stiffness.diagonal();
  const Eigen::VectorXd scale = k.cwiseSqrt().cwiseInverse();
  Eigen::MatrixXd geometric = tangent;
  geometric.diagonal() -= k;
  const Eigen::MatrixXd scaled = -(scale.asDiagonal() * geometric * scale.asDiagonal());
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> loads(scaled, Eigen::EigenvaluesOnly);
  out.load_factor = loads.eigenvalues()[dim - 1];
  // The slowest motion about the pose, and, unstable, how fast a nudge grows.
  // (The unstable mode's shape only where there is one: its damping gives the growth rate.)
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> sway(
      tangent, chain.mass_matrix(), out.load_factor < 1 ? Eigen::EigenvaluesOnly : Eigen::ComputeEigenvectors);
  out.lowest = sway.eigenvalues()[0];
  if (out.lowest < 0 && out.load_factor >= 1) {
    const Eigen::VectorXd mode = sway.eigenvectors().col(0);  // M-normalised
    const double c = mode.dot(chain.damping() * mode);
    out.growth_rate = 0.5 * (std::sqrt(c * c - 4 * out.lowest) - c);
  }
  out.beta = beta_of(def, model, gravity);
  return out;
}

HeldRest stiffen_to_hold(SweepDef& def, const Vec3& gravity, double largest_load_factor) {
  assert(def.material && def.material->shear_modulus <= 0);
  const HeldRest given = held_rest(def, build_chain_model(def.rest, def.section_materials), gravity);
  if (given.load_factor <= largest_load_factor) return given;
  def.material->youngs_modulus *= given.load_factor / largest_load_factor;
  for (Material& m : def.section_materials) m.youngs_modulus = def.material->youngs_modulus;
  return given;
}

}  // namespace sweep
