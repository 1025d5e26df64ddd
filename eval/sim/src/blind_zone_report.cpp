#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "fmcw/eval/blind_zone_study.hpp"
#include "fmcw/eval/table_writer.hpp"
#include "fmcw/io/atomic_file.hpp"

namespace fmcw::eval {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

namespace {
json number(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json band_json(const BlindZoneBand& b) {
  return {{"target", b.target},
          {"speed_mps", b.speed_mps},
          {"distance_m", b.distance_m},
          {"method", b.method},
          {"noise", b.noise ? "table1" : "none"},
          {"found", b.measured.found},
          {"measured_lower_deg", b.measured.found ? number(b.measured.lower_deg) : json(nullptr)},
          {"measured_upper_deg", b.measured.found ? number(b.measured.upper_deg) : json(nullptr)},
          {"theory_lower_deg", number(b.theory.lower_deg)},
          {"theory_upper_deg", number(b.theory.upper_deg)},
          {"silhouette_lower_deg", b.silhouette.found ? number(b.silhouette.lower_deg) : json(nullptr)},
          {"silhouette_upper_deg", b.silhouette.found ? number(b.silhouette.upper_deg) : json(nullptr)},
          {"lower_minus_theory_deg", b.measured.found ? number(b.measured.lower_deg - b.theory.lower_deg) : json(nullptr)},
          {"upper_minus_theory_deg", b.measured.found ? number(b.measured.upper_deg - b.theory.upper_deg) : json(nullptr)}};
}
}  // namespace

void write_blind_zone_report(const std::string& dir, const BlindZoneStudyResult& r, const std::string& tool_version) {
  io::ensure_writable_directory(dir);
  const fs::path d(dir);
  std::vector<std::string> columns = {"target", "speed_mps", "distance_m", "phi_deg", "object_pixels",
                                      "silhouette_min_doppler_mps"};
  for (const std::string& m : r.methods) columns.push_back("recall_" + m);
  if (r.params.noise_free_too) {
    for (const std::string& m : r.methods) columns.push_back("recall_noise_free_" + m);
  }
  CsvTable samples(columns);
  for (const BlindZoneSample& s : r.samples) {
    samples.add(s.target).add(s.speed_mps).add(s.distance_m).add(s.phi_deg).add(s.object_pixels).add(s.silhouette_min_doppler_mps);
    for (const double v : s.recall) samples.add(v);
    for (const double v : s.recall_noise_free) samples.add(v);
    samples.end_row();
  }
  samples.write((d / "blind_zone_samples.csv").string());

  CsvTable bands({"target", "speed_mps", "distance_m", "method", "noise", "found", "measured_lower_deg", "measured_upper_deg",
                  "theory_lower_deg", "theory_upper_deg", "silhouette_lower_deg", "silhouette_upper_deg"});
  json bands_json = json::array();
  for (const BlindZoneBand& b : r.bands) {
    const double nan = std::nan("");
    bands.add(b.target).add(b.speed_mps).add(b.distance_m).add(b.method).add(b.noise ? "table1" : "none").add(b.measured.found);
    bands.add(b.measured.found ? b.measured.lower_deg : nan).add(b.measured.found ? b.measured.upper_deg : nan);
    bands.add(b.theory.lower_deg).add(b.theory.upper_deg);
    bands.add(b.silhouette.found ? b.silhouette.lower_deg : nan).add(b.silhouette.found ? b.silhouette.upper_deg : nan);
    bands.end_row();
    bands_json.push_back(band_json(b));
  }
  bands.write((d / "blind_zone_bands.csv").string());

  const BlindZoneStudyParams& p = r.params;
  const BlindZoneSceneParams& sc = p.scene;
  const BandEdges example = theoretical_blind_band(5.0, p.velocity_threshold_mps);
  json targets = json::array();
  for (const BlindZoneTarget& t : p.targets) {
    targets.push_back({{"name", t.name},
                       {"box_size_m", {t.box_size_m.x(), t.box_size_m.y(), t.box_size_m.z()}},
                       {"distances_m", t.distances_m},
                       {"mesh", t.mesh}});
  }
  const json out = {
      {"kind", "blind_zone"},
      {"format_version", 1},
      {"tool_version", tool_version},
      {"methods", r.methods},
      {"params",
       {{"speeds_mps", p.speeds_mps},
        {"targets", targets},
        {"phi_step_deg", p.phi_step_deg},
        {"phi_range_deg", {p.phi_min_deg, p.phi_max_deg}},
        {"fine_step_deg", p.fine_step_deg},
        {"fine_margin_deg", p.fine_margin_deg},
        {"refine_iterations", p.refine_iterations},
        {"recall_level", p.recall_level},
        {"velocity_threshold_mps", p.velocity_threshold_mps},
        {"noise_free_too", p.noise_free_too},
        {"ground_clearance_m", sc.ground_clearance_m},
        {"wall_gap_m", sc.wall_gap_m},
        {"sensor_height_m", sc.sensor_height_m},
        {"range_sigma_m", sc.measurement.range_sigma_m},
        {"velocity_sigma_mps", sc.measurement.velocity_sigma_mps},
        {"seed", sc.seed}}},
      {"samples", r.samples.size()},
      {"seconds", r.seconds},
      {"paper_example",
       {{"speed_mps", 5.0},
        {"paper_band_deg", {88.0, 92.0}},
        {"theory_band_deg", {example.lower_deg, example.upper_deg}}}},
      {"bands", bands_json},
      {"files", {{"samples", "blind_zone_samples.csv"}, {"bands", "blind_zone_bands.csv"}}},
  };
  write_text_atomically((d / "metrics.json").string(), out.dump(2) + "\n");
}

}  // namespace fmcw::eval
