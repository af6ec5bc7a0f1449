// sweep-fit as a black box on a leg that ends in a foot: a round leg with a bulge halfway down (a
// knee, a hock), an ankle that turns forward, and a foot that spreads sideways to 2.5 radii and
// flattens to 0.4 (camel's legs, whose feet broke the error limit at 9-12 % RMS, refused). The
// tip is clicked at a toe, the foot's front corner, as a person clicks a leg's end. What matters:
// the fit is accepted and tight where it is measured; the sweep either follows the foot or ends
// where the tube ends, says so, and carries the foot whole (its vertices in the part, past the
// last section), never a silently bad fit. (Before sweep-fit cut ends that are not tubes, this
// shape fitted through its foot at 2.1 % RMS, the foot's last span 5.8 % off; now its last span
// is carried, 1.9 %.)
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <vector>

#include "sweep/assets/mesh_io.h"
#include "sweep/io/rig_json.h"
#include "test_constants.h"
#include "tools/tool_runner.h"

namespace sweep::test {
namespace {

constexpr double kLegR = 0.1;  // the leg's radius
using ::sweep::test::kPi;
constexpr double kLeg = 12 * kLegR;    // the leg, straight down (-y)
constexpr double kBend = 1.2 * kLegR;  // the ankle: a quarter turn of this radius, towards +z
constexpr double kFoot = 3 * kLegR;    // the foot, forward (+z)

struct Station {
  Vec3 centre, tangent;
  double side, height;  // semi-axes: sideways (x) and in the plane of the turn
};

Station station(double s) {
  const double bend_end = kLeg + kBend * kPi / 2;
  // A bulge halfway down the leg (a knee): 30 % wider over about a radius.
  const double bulge = 1 + 0.3 * std::exp(-std::pow((s - 0.5 * kLeg) / kLegR, 2));
  if (s <= kLeg) return {Vec3(0, -s, 0), Vec3(0, -1, 0), kLegR * bulge, kLegR * bulge};
  // From the ankle on, the section spreads sideways and flattens, over the turn and a radius.
  const double u = std::clamp((s - kLeg) / (bend_end - kLeg + kLegR), 0.0, 1.0);
  const double w = u * u * (3 - 2 * u);
  const double side = kLegR * (1 + 1.5 * w), height = kLegR * (1 - 0.6 * w);
  if (s <= bend_end) {
    const double phi = (s - kLeg) / kBend;
    return {Vec3(0, -kLeg - kBend * std::sin(phi), kBend * (1 - std::cos(phi))), Vec3(0, -std::cos(phi), std::sin(phi)),
            side, height};
  }
  return {Vec3(0, -kLeg - kBend, kBend + (s - bend_end)), Vec3(0, 0, 1), side, height};
}

double total_length() {
  return kLeg + kBend * kPi / 2 + kFoot;
}

// Rings every quarter radius (the foot's sole closer), 32 around; flat fans close both ends.
Mesh leg_with_foot() {
  Mesh m;
  const int segments = 32;
  std::vector<double> along;
  for (double s = 0; s < total_length(); s += 0.25 * kLegR) along.push_back(s);
  along.push_back(total_length());
  for (const double s : along) {
    const Station st = station(s);
    const Vec3 x = Vec3::UnitX(), n = st.tangent.cross(x).normalized();
    for (int j = 0; j < segments; ++j) {
      const double th = 2 * kPi * j / segments;
      m.positions.push_back(st.centre + st.side * std::cos(th) * x + st.height * std::sin(th) * n);
    }
  }
  const int rings = static_cast<int>(along.size());
  const auto id = [&](int i, int j) { return static_cast<std::uint32_t>(i * segments + (j % segments)); };
  const auto top = static_cast<std::uint32_t>(m.positions.size());
  m.positions.push_back(station(0).centre);
  m.positions.push_back(station(total_length()).centre);
  for (int i = 0; i + 1 < rings; ++i) {
    for (int j = 0; j < segments; ++j) m.add_face({id(i, j), id(i, j + 1), id(i + 1, j + 1), id(i + 1, j)});
  }
  for (int j = 0; j < segments; ++j) {
    m.add_face({top, id(0, j + 1), id(0, j)});
    m.add_face({top + 1, id(rings - 1, j), id(rings - 1, j + 1)});
  }
  return m;
}

TEST(Foot, LegWithAKneeAndAFootSpreadingSidewaysIsAcceptedAndHonest) {
  const fs::path dir = scratch_dir("leg-with-foot");
  const Mesh mesh = leg_with_foot();
  assets::write_obj(dir / "leg.obj", mesh);
  // The toe: the foot's front corner, half a radius in from its side.
  const Station end = station(total_length());
  const Vec3 toe = end.centre + (end.side - 0.5 * kLegR) * Vec3::UnitX();
  const Vec3 root(0, -1.5 * kLegR, 0);
  const ToolRun r =
      run_tool(SWEEP_FIT_EXE,
               quoted(dir / "leg.obj") + " -o " + quoted(dir / "rig.json") + " --name leg --tip " + point_arg(toe) +
                   " --root " + point_arg(root) + " --report " + quoted(dir / "report.json"),
               dir);
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  const nlohmann::json report = nlohmann::json::parse(slurp(dir / "report.json"));
  const auto& e = report.at("sweeps").at(0);
  std::printf(
      "leg with a foot: rms %.2f%%, 90%% within %.2f%%, traced/surface %.3f, end cut %d, "
      "%zu of %zu part vertices measured\n",
      100 * e.at("fit_rms_relative").get<double>(), 100 * e.at("fit_p90_relative").get<double>(),
      e.at("traced_over_surface").get<double>(), e.at("end_cut").get<bool>() ? 1 : 0,
      e.at("measured_vertex_count").get<std::size_t>(), e.at("part_vertex_count").get<std::size_t>());
  EXPECT_LE(e.at("fit_rms_relative").get<double>(), 0.02) << r.out;
  EXPECT_LE(e.at("fit_p90_relative").get<double>(), 0.1) << r.out;
  EXPECT_GE(e.at("traced_over_surface").get<double>(), 0.8) << r.out;
  // The part is the whole leg below the root section, foot and all: nothing lost, nothing added.
  std::size_t below_root = 0;
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) below_root += mesh.positions[v].y() < root.y();
  const auto part = e.at("part_vertex_count").get<std::size_t>();
  EXPECT_NEAR(static_cast<double>(part), static_cast<double>(below_root), 32.0);  // a ring
  // Every part vertex is measured, or declared: past an end section (carried) or a protrusion.
  EXPECT_EQ(e.at("measured_vertex_count").get<std::size_t>() + e.at("beyond_ends_vertex_count").get<std::size_t>() +
                e.at("protrusion_vertex_count").get<std::size_t>(),
            part);
  const Rig rig = io::read_rig(dir / "rig.json");
  const SweepShape& rest = rig.sweeps.at(0).rest;
  const Vec3 last = rest.frames.back().center;
  if (e.at("end_cut").get<bool>()) {
    // Ended before the foot's end: said so, and the foot past the last section carried whole.
    EXPECT_NE(e.at("end_cut_reason").get<std::string>().find("not a tube"), std::string::npos);
    EXPECT_GT(e.at("beyond_ends_vertex_count").get<std::size_t>(), 0U);
    EXPECT_EQ(e.at("beyond_root_vertex_count").get<std::size_t>(), 0U);
  } else {
    // Followed into the foot: the sweep reaches its second half.
    EXPECT_GT(last.z(), kBend + 0.5 * kFoot);
  }
  // Either way the sweep reaches the ankle: the leg, knee and all, is a sweep.
  EXPECT_LT(last.y(), -kLeg + kLegR);
}

}  // namespace
}  // namespace sweep::test
