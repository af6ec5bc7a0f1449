#include "sweep/assets/bake_summary.h"

#include <nlohmann/json.hpp>
#include <numbers>

#include "sweep/core/elastic_sweep.h"
#include "sweep/core/text.h"

namespace sweep::assets {
namespace {

// A frame number, or null for −1 (never).
nlohmann::ordered_json frame_or_null(int frame) {
  return frame >= 0 ? nlohmann::ordered_json(frame) : nlohmann::ordered_json();
}

}  // namespace

std::string bake_report_json(const BakeReport& r, const BakeSummarySettings& s) {
  nlohmann::ordered_json doc;
  doc["format"] = "sweep-sim-report";
  doc["version"] = 1;
  doc["rig"] = s.rig.string();
  doc["frames"] = r.frames;
  doc["fps"] = r.fps;
  doc["step_seconds"] = r.step_seconds;
  doc["deformation"] = s.exact ? "exact" : "fast";
  nlohmann::ordered_json sweeps = nlohmann::ordered_json::array();
  for (const auto& st : r.sweeps) {
    sweeps.push_back(
        {{"name", st.name},
         {"driven", st.driven},
         {"steps", st.steps},
         {"frames_deformed", st.frames_deformed},
         {"bound_vertex_count", st.bound_vertex_count},
         {"work_blocks", st.work_blocks},
         {"blocks_in_place", st.blocks_in_place},
         {"sway_frequencies_hz", st.sway.frequencies_hz},
         {"feels_gravity", st.sway.feels_gravity},
         {"droop", st.sway.droop},
         {"largest_span_bend_degrees", st.largest_bend * 180 / std::numbers::pi},
         {"largest_bend_span", st.bend_span},
         {"largest_bend_frame", st.bend_frame},
         {"fold_frame", frame_or_null(st.fold_frame)},
         {"fold_span", st.fold_frame >= 0 ? nlohmann::ordered_json(st.fold_span) : nlohmann::ordered_json()},
         {"self_cross_frame", frame_or_null(st.cross_frame)},
         {"self_cross_sections",
          st.cross_frame >= 0 ? nlohmann::ordered_json::array({st.cross_a, st.cross_b}) : nlohmann::ordered_json()},
         {"largest_rotation_degrees", st.largest_rotation * 180 / std::numbers::pi},
         {"exact_chain_from",
          st.exact_chain_time >= 0 || st.exact_chain_angle > 0
              ? nlohmann::ordered_json{{"time", st.exact_chain_time},
                                       {"rotation_degrees", st.exact_chain_angle * 180 / std::numbers::pi}}
              : nlohmann::ordered_json()}});
    // Material mode under gravity, unless the scene starts it unloaded: its as-modelled rest's check.
    nlohmann::ordered_json held;
    if (st.held_rest) {
      held = {{"holds", st.held_rest->holds()},
              {"load_factor", st.held_rest->load_factor},
              {"beta", st.held_rest->beta},
              {"growth_rate", st.held_rest->growth_rate},
              {"started_from_it", st.as_modelled}};
    }
    sweeps.back()["as_modelled_rest"] = std::move(held);
  }
  doc["sweeps"] = std::move(sweeps);
  nlohmann::ordered_json frames = nlohmann::ordered_json::array();
  for (const auto& f : r.per_frame) {
    frames.push_back({{"time", f.time},
                      {"max_displacement", f.max_displacement},
                      {"awake_sweeps", f.awake_sweeps},
                      {"edge_stretch", f.edge_stretch}});
  }
  doc["per_frame"] = std::move(frames);
  // The bake's quality figure: the largest deformed / rest length of any edge in any frame.
  const EdgeStretch& worst = r.max_stretch;
  doc["max_edge_stretch"] = {
      {"ratio", worst.ratio},
      {"edge", worst.found ? nlohmann::ordered_json::array({worst.a, worst.b}) : nlohmann::ordered_json()},
      {"frame", r.max_stretch_frame},
      {"time", r.max_stretch_frame / r.fps},
      {"edges_measured", r.stretch_edge_count},
      {"seconds", r.stretch_seconds}};
  // Times at which the body jumped (a cut, a respawn) and the parts were put to rest there.
  doc["teleports"] = r.teleport_times;
  doc["seconds"] = {{"load", s.load_seconds},
                    {"simulate", r.simulate_seconds},
                    {"deform", r.deform_seconds},
                    {"write", r.write_seconds},
                    {"total", s.total_seconds}};
  nlohmann::ordered_json files = nlohmann::ordered_json::array();
  for (const auto& f : r.files) files.push_back(f.string());
  doc["files"] = std::move(files);
  if (r.skin_joints > 0) {
    // The skinned .glb against the bake's positions, as fractions of the part's length.
    doc["joints_per_sweep"] = s.joints;
    doc["ring_joints"] = s.ring_joints;
    doc["ring_fit"] = s.ring_fit;
    doc["skin_joints"] = r.skin_joints;
    if (r.skin_in_character) doc["skin_joints_in_character"] = true;  // added to the character's skeleton
    doc["skin_error_max_relative"] = r.skin_error.max_relative;
    doc["skin_error_rms_relative"] = r.skin_error.rms_relative;
    doc["skin_error_max_frame"] = r.skin_error.max_frame;
    doc["skin_error_max_vertex"] = r.skin_error.max_vertex;
  }
  return doc.dump(2) + "\n";
}

void print_bake_summary(std::ostream& out, const BakeReport& report, const BakeSummarySettings& s) {
  out << "baked " << report.frames << " frames (" << format_number((report.frames - 1) / report.fps, 3) << " s at "
      << format_number(report.fps) << " fps, step " << format_number(report.step_seconds, 3) << " s) in "
      << format_number(s.total_seconds, 3) << " s: simulate " << format_number(report.simulate_seconds * 1e3, 3)
      << " ms, deform " << format_number(report.deform_seconds * 1e3, 3) << " ms, write "
      << format_number(report.write_seconds * 1e3, 3) << " ms\n";
  for (const auto& st : report.sweeps) {
    out << "  " << st.name << std::string(st.name.size() < 12 ? 12 - st.name.size() : 0, ' ') << " "
        << (st.driven ? "driven" : "no force reaches it: skipped") << ", " << st.steps << " steps, deformed in "
        << st.frames_deformed << " frames, " << st.bound_vertex_count << " vertices\n";
    out << "    sways at";
    for (std::size_t m = 0; m < st.sway.frequencies_hz.size(); ++m)
      out << (m ? ", " : " ") << format_number(st.sway.frequencies_hz[m], 3);
    out << " Hz, "
        << (st.sway.feels_gravity ? "droops " + format_number(st.sway.droop * 100, 3) + " % of its length"
                                  : std::string("feels no gravity (the paper's springs)"));
    if (st.driven) {
      out << "; largest bend of a span " << format_number(st.largest_bend * 180 / std::numbers::pi, 3) << "° (sections "
          << st.bend_span - 1 << "-" << st.bend_span << ", frame " << st.bend_frame << ")";
      if (st.sway.feels_gravity) {
        out << "; turned at most " << format_number(st.largest_rotation * 180 / std::numbers::pi, 3)
            << "° from its rest";
      }
    }
    out << "\n";
    if (st.held_rest && !st.held_rest->holds()) {
      out << "    cannot hold its modelled pose under gravity (beta " << format_number(st.held_rest->beta, 3)
          << ", stiffness " << format_number(st.held_rest->load_factor, 3)
          << "x too low): " << (st.as_modelled ? "started from it: a nudge topples it" : "started unloaded") << "\n";
    }
    if (st.exact_chain_time >= 0 || st.exact_chain_angle > 0) {
      out << "    large motion: the exact chain from t = " << format_number(st.exact_chain_time, 4)
          << " s (a section turned " << format_number(st.exact_chain_angle * 180 / std::numbers::pi, 3)
          << "° from its rest, past the modes' "
          << format_number(ElasticSweep::kSwitchAngle * 180 / std::numbers::pi, 3) << "°)\n";
    }
  }
  out << "largest edge stretch " << format_number(report.max_stretch.ratio, 4) << "x";
  if (report.max_stretch.found) {
    out << " (edge " << report.max_stretch.a << "-" << report.max_stretch.b << ", frame " << report.max_stretch_frame
        << " at t = " << format_number(report.max_stretch_frame / report.fps, 3) << " s)";
  }
  out << " over " << report.stretch_edge_count << " edges, measured in "
      << format_number(report.stretch_seconds * 1e3, 3) << " ms\n";
  if (report.skin_joints > 0 && report.skin_in_character) {
    out << "skinned .glb: " << report.skin_joints << " joints added to the character's skeleton (" << s.joints
        << " a part";
    if (s.ring_joints > 1) out << ", " << s.ring_joints << " around each station but the root";
    out << "); against the bake: max " << format_number(report.skin_error.max_relative * 100, 3)
        << " % of the part's length (frame " << report.skin_error.max_frame << ", vertex "
        << report.skin_error.max_vertex << "), RMS " << format_number(report.skin_error.rms_relative * 100, 3)
        << " %\n";
  } else if (report.skin_joints > 0) {
    out << "skinned .glb: " << report.skin_joints << " joints (" << s.joints << " a sweep";
    if (s.ring_joints > 1) out << ", " << s.ring_joints << " around each but the root";
    out << ", and the body); against the bake: max " << format_number(report.skin_error.max_relative * 100, 3)
        << " % of the part's length (frame " << report.skin_error.max_frame << ", vertex "
        << report.skin_error.max_vertex << "), RMS " << format_number(report.skin_error.rms_relative * 100, 3)
        << " %\n";
  }
  for (const double t : report.teleport_times) {
    out << "  the body jumped at t = " << format_number(t)
        << " s (a cut or respawn): the parts were put to rest there\n";
  }
  // One line an output: an .obj sequence as its pattern and count, not a line a frame.
  for (const std::filesystem::path& output : s.outputs) {
    const std::vector<std::filesystem::path> files = bake_files(output, report.frames);
    if (files.size() == 1) {
      out << "wrote " << files[0].string() << "\n";
    } else {
      out << "wrote " << files.size() << " files " << files.front().string() << " ... "
          << files.back().filename().string() << " (" << output.stem().string() << "_"
          << std::string(files.front().stem().string().size() - output.stem().string().size() - 1, '#')
          << output.extension().string() << ", one a frame)\n";
    }
  }
  if (!s.report.empty()) out << "report " << s.report.string() << "\n";
}

}  // namespace sweep::assets
