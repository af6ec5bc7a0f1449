// sweep-fit as a black box on each shape class a real part takes (curve_tubes.h): a curl of more
// than 270°, an elbow of 90° two radii from a body, a tube lying against the body along its
// length, a helix, a taper to a point, a tube leaving a broad body. Each is fitted from a tip clicked half a radius off
// its end (no root: the tool finds it), and the rig's key sections are checked against the generator's curve.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>

#include "curve_tubes.h"
#include "sweep/assets/mesh_io.h"
#include "sweep/io/rig_json.h"
#include "test_constants.h"
#include "tools/tool_runner.h"

namespace sweep::test {
namespace {

constexpr double kR = 0.1;  // the tube's radius
using ::sweep::test::kPi;

struct Shape {
  std::string name;
  CurveTube tube;
  double part_start = 0;   // arc length where the part begins (the body's end), 0: none
  double click_off = 0.5;  // how far beside the end the tip is clicked, in radii
};

// A point a person would click for the tip: `off` radii beside the end of the tube (half a radius
// by default: on its surface near the end).
Vec3 clicked_tip(const CurveTube& t, double off = 0.5) {
  const Vec3 tangent = t.tangent_at(t.length());
  const Vec3 side = (std::abs(tangent.z()) < 0.9 ? Vec3::UnitZ() : Vec3::UnitX()).cross(tangent).normalized();
  return t.axis_at(t.length()) + off * t.radius(t.length()) * side;
}

struct Checked {
  double worst_centre = 0;   // section centre to the curve, over kR
  double worst_degrees = 0;  // section axis to the curve's tangent there
  double first_s = 0, last_s = 0;
  double traced_over_surface = 0, rms = 0;
  int sections = 0;
  std::string table;  // per section, shown when a check fails
};

Checked fit_and_check(Shape& shape) {
  const fs::path dir = scratch_dir("shape-" + shape.name);
  const Mesh mesh = shape.tube.mesh();
  assets::write_obj(dir / "shape.obj", mesh);
  const ToolRun r =
      run_tool(SWEEP_FIT_EXE,
               quoted(dir / "shape.obj") + " -o " + quoted(dir / "rig.json") + " --name " + shape.name + " --tip " +
                   point_arg(clicked_tip(shape.tube, shape.click_off)) + " --report " + quoted(dir / "report.json"),
               dir);
  Checked c;
  EXPECT_EQ(r.code, 0) << shape.name << "\n" << r.out << r.err;
  if (r.code != 0) return c;
  const Rig rig = io::read_rig(dir / "rig.json");
  const nlohmann::json report = nlohmann::json::parse(slurp(dir / "report.json"));
  const auto& entry = report.at("sweeps").at(0);
  c.traced_over_surface = entry.at("traced_over_surface").get<double>();
  c.rms = entry.at("fit_rms_relative").get<double>();
  const SweepShape& rest = rig.sweeps.at(0).rest;
  c.sections = rest.section_count();
  for (int i = 0; i < rest.section_count(); ++i) {
    const Frame& f = rest.frames[static_cast<std::size_t>(i)];
    double s = 0;
    c.worst_centre = std::max(c.worst_centre, shape.tube.distance_to_axis(f.center, &s) / kR);
    const double cosine = std::clamp(f.axis().dot(shape.tube.tangent_at(s)), -1.0, 1.0);
    c.worst_degrees = std::max(c.worst_degrees, std::acos(cosine) * 180 / kPi);
    if (i == 0) c.first_s = s;
    c.last_s = s;
    char line[200];
    std::snprintf(line, sizeof line, "  section %2d at s=%.3f: %.2f%% of r off the curve, %.2f deg\n", i, s,
                  100 * shape.tube.distance_to_axis(f.center) / kR, std::acos(cosine) * 180 / kPi);
    c.table += line;
  }
  std::printf(
      "%-6s K=%d: centre off the curve <= %.2f%% of r, axis <= %.2f deg, sections from s=%.3f "
      "to %.3f of %.3f, traced/surface %.3f, rms %.2f%%\n",
      shape.name.c_str(), c.sections, 100 * c.worst_centre, c.worst_degrees, c.first_s, c.last_s, shape.tube.length(),
      c.traced_over_surface, 100 * c.rms);
  return c;
}

// What every shape must show: sections on the curve and along it, from where the part begins to
// near its end, the whole part traced, a tight fit.
void expect_follows(Shape& shape) {
  const Checked c = fit_and_check(shape);
  if (c.sections == 0) return;
  EXPECT_LT(c.worst_centre, 0.05) << shape.name << "\n" << c.table;  // within 5% of r
  EXPECT_LT(c.worst_degrees, 5.0) << shape.name << "\n" << c.table;
  EXPECT_NEAR(c.first_s, shape.part_start, 2 * kR) << shape.name;
  const double end = shape.tube.length();
  EXPECT_GT(c.last_s, end - 3 * std::max(shape.tube.radius(end), 0.2 * kR)) << shape.name;
  EXPECT_GE(c.traced_over_surface, 0.95) << shape.name;
  EXPECT_LE(c.rms, 0.02) << shape.name;
}

// A body of radius 4r over 10r of arc length, at the start of the curve.
constexpr double kBodyRadius = 4 * kR, kBodyLength = 10 * kR;

std::function<double(double)> constant_tube() {
  return [](double) { return kR; };
}

TEST(Shapes, CurlOfThreeHundredThirtyDegreesLeavingABody) {
  // Straight out of the body for 2r, then a spiral of 330° whose radius shrinks from 6r to 3.3r.
  const double lead = kBodyLength + 2 * kR, r0 = 6 * kR, turn = 330 * kPi / 180;
  const double spiral = 0.55 * r0 * turn;  // about its length, to share u fairly
  Shape s{"curl", {}, kBodyLength};
  s.tube.curve = [=](double u) {
    const double a = u * (lead + spiral);
    if (a <= lead) return Vec3(a, 0, 0);
    const double phi = (a - lead) / spiral * turn;
    const double radius = r0 * (1 - 0.45 * phi / turn);
    return Vec3(lead + radius * std::sin(phi), r0 - radius * std::cos(phi), 0);
  };
  s.tube.radius = with_body(kBodyRadius, kBodyLength, constant_tube());
  expect_follows(s);
}

TEST(Shapes, ElbowOfNinetyDegreesTwoRadiiFromTheBody) {
  const double lead = kBodyLength + 2 * kR, bend = 1.5 * kR, arc = bend * kPi / 2, after = 8 * kR;
  Shape s{"elbow", {}, kBodyLength};
  s.tube.curve = [=](double u) {
    const double a = u * (lead + arc + after);
    if (a <= lead) return Vec3(a, 0, 0);
    if (a <= lead + arc) {
      const double phi = (a - lead) / bend;
      return Vec3(lead + bend * std::sin(phi), bend * (1 - std::cos(phi)), 0);
    }
    return Vec3(lead + bend, bend + (a - lead - arc), 0);
  };
  s.tube.radius = with_body(kBodyRadius, kBodyLength, constant_tube());
  expect_follows(s);
}

TEST(Shapes, LyingAgainstTheBodyAlongItsLength) {
  // Out of the body's end for 2r, a U-turn of radius 2.75r, then 8r back along the body, its
  // surface half a radius from the body's: planes normal to the tube there cut the body too.
  const double lead = kBodyLength + 2 * kR, turn_radius = 2.75 * kR, arc = turn_radius * kPi, back = 8 * kR;
  Shape s{"along", {}, kBodyLength};
  s.tube.curve = [=](double u) {
    const double a = u * (lead + arc + back);
    if (a <= lead) return Vec3(a, 0, 0);
    if (a <= lead + arc) {
      const double phi = (a - lead) / turn_radius;
      return Vec3(lead + turn_radius * std::sin(phi), turn_radius * (1 - std::cos(phi)), 0);
    }
    return Vec3(lead - (a - lead - arc), 2 * turn_radius, 0);
  };
  s.tube.radius = with_body(kBodyRadius, kBodyLength, constant_tube());
  expect_follows(s);
}

TEST(Shapes, TipClickedThreeRadiiBesideTheEnd) {
  // The broad-body tube of the test below, its tip clicked in the air three radii beside its end.
  const double tube_length = 12 * kR;
  Shape s{"offtip", {}, kBodyLength, 3.0};
  s.tube.curve = [=](double u) { return Vec3(0, 0, u * (kBodyLength + tube_length)); };
  s.tube.radius = with_body(kBodyRadius, kBodyLength, constant_tube());
  expect_follows(s);
}

TEST(Shapes, HelixOfTwoTurns) {
  const double rh = 3 * kR, rise = 16 * kR;
  Shape s{"helix", {}, 0};
  s.tube.curve = [=](double u) { return Vec3(rh * std::cos(4 * kPi * u), rh * std::sin(4 * kPi * u), rise * u); };
  s.tube.radius = constant_tube();
  expect_follows(s);
}

TEST(Shapes, TaperToAPoint) {
  // 20r long, bending by 40°, from r to a twentieth of it.
  const double length = 20 * kR, bend = 40 * kPi / 180;
  Shape s{"taper", {}, 0};
  s.tube.curve = [=](double u) {
    const double k = bend / length, a = k * length * u;
    return Vec3((1 - std::cos(a)) / k, 0, std::sin(a) / k);
  };
  s.tube.radius = [=](double x) { return kR * (1 - 0.95 * std::clamp(x / length, 0.0, 1.0)); };
  expect_follows(s);
}

TEST(Shapes, TubeLeavingABroadBody) {
  // The body: an ellipsoid 4r wide and 10r long; the tube: 12r, bending by 40° in another plane.
  const double tube_length = 12 * kR, bend = 40 * kPi / 180;
  Shape s{"body", {}, kBodyLength};
  s.tube.curve = [=](double u) {
    const double a = u * (kBodyLength + tube_length);
    if (a <= kBodyLength) return Vec3(0, 0, a);
    const double k = bend / tube_length, phi = k * (a - kBodyLength);
    return Vec3(0, (1 - std::cos(phi)) / k, kBodyLength + std::sin(phi) / k);
  };
  s.tube.radius = with_body(kBodyRadius, kBodyLength, constant_tube());
  expect_follows(s);
}

}  // namespace
}  // namespace sweep::test
