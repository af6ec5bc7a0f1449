// sweep-tube: writes a tube mesh with a known axis and radius (see tube.h for the exact
// parametrisation). Exit codes as in core/error.h: 1 usage, 4 output.
#include <CLI/CLI.hpp>
#include <filesystem>
#include <iostream>
#include <string>

#include "sweep/assets/mesh_io.h"
#include "tools/common/tool_main.h"
#include "tube.h"

namespace {

struct Settings {
  sweep::tube::TubeParams tube;
  std::filesystem::path output;
  bool quiet = false;
};

int run(const Settings& settings) {
  if (!sweep::assets::is_writable_mesh_extension(settings.output)) {
    sweep::fail(sweep::ErrorCategory::usage,
                "--output " + settings.output.string() + ": the extension must be .obj, .off or .ply");
  }
  const sweep::Mesh mesh = sweep::tube::make_tube(settings.tube);
  sweep::assets::write_mesh(settings.output, mesh);
  if (!settings.quiet) {
    std::cout << settings.output.string() << ": " << mesh.vertex_count() << " vertices, " << mesh.face_count()
              << " faces\n";
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return sweep::tools::guarded_main([&] {
    Settings s;
    sweep::tube::TubeParams& t = s.tube;
    CLI::App app{"Write a tube mesh with a known axis and radius (parametrisation: tube.h)", "sweep-tube"};
    app.add_option("-o,--output", s.output, "Output mesh (.obj, .off or .ply)")->required();
    app.add_option("--length", t.length, "Arc length of the axis (mesh units)")->capture_default_str();
    app.add_option("--radius", t.radius, "Cross-section radius at the root (mesh units)")->capture_default_str();
    app.add_option("--taper", t.taper, "Tip radius / root radius (linear along the axis)")->capture_default_str();
    app.add_option("--bend", t.bend,
                   "Total turning angle of the axis in radians, in the x-z plane towards +x "
                   "(0 = straight along +z)")
        ->capture_default_str();
    std::string shape = "circle";
    app.add_option("--shape", shape, "Cross section: circle, ellipse or lobed")
        ->check(CLI::IsMember({"circle", "ellipse", "lobed"}))
        ->capture_default_str();
    app.add_option("--ellipse-ratio", t.ellipse_ratio, "Ellipse: minor / major semi-axis")->capture_default_str();
    app.add_option("--lobes", t.lobes, "Lobed: number of lobes")->capture_default_str();
    app.add_option("--lobe-amplitude", t.lobe_amplitude, "Lobed: relative lobe depth, in [0, 1)")
        ->capture_default_str();
    app.add_option("--rings", t.rings, "Cross sections along the axis (>= 2)")->capture_default_str();
    app.add_option("--segments", t.segments, "Vertices around each ring (>= 3)")->capture_default_str();
    app.add_flag("--caps,!--no-caps", t.caps, "Close the ends with triangle fans (default on)");
    app.add_flag("--triangulate", t.triangulate, "Split the side quads into triangles");
    app.add_flag("-q,--quiet", s.quiet, "Print nothing on success");
    if (const auto stop = sweep::tools::parse_command_line(app, argc, argv)) return *stop;
    t.shape = shape == "ellipse" ? sweep::tube::CrossSection::ellipse
              : shape == "lobed" ? sweep::tube::CrossSection::lobed
                                 : sweep::tube::CrossSection::circle;
    return run(s);
  });
}
