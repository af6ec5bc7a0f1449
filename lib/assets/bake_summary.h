#pragma once
// What sweep-sim tells of a finished bake: its JSON report (--report) and the summary it prints,
// both made from the BakeReport and the few settings they state beside it. No file I/O here.
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "sweep/assets/bake_run.h"

namespace sweep::assets {

// The settings a report and a summary name beside the bake's own figures.
struct BakeSummarySettings {
  std::filesystem::path rig;                   // the rig file, as given
  std::vector<std::filesystem::path> outputs;  // the outputs, as given (an .obj sequence by its pattern)
  std::filesystem::path report;                // the JSON report's file; empty: none
  bool exact = false;                          // deformed by the exact per-vertex path
  int joints = 0;                              // a skinned .glb's station joints a sweep
  int ring_joints = 1;                         // and ring joints a station (1: none)
  bool ring_fit = false;                       // the ring joints' keys fitted by least squares
  double load_seconds = 0;                     // wall time reading the inputs
  double total_seconds = 0;                    // wall time of the whole run
};

// The JSON report ("sweep-sim-report", version 1), indented by two, ending in a newline.
std::string bake_report_json(const BakeReport& report, const BakeSummarySettings& settings);

// The summary for a person: the timings; each sweep's steps, first sway frequencies, droop under
// the scene's gravity and largest bend of one span; the largest edge stretch; a skinned .glb's
// error against the bake; the teleports; a line an output.
void print_bake_summary(std::ostream& out, const BakeReport& report, const BakeSummarySettings& settings);

}  // namespace sweep::assets
