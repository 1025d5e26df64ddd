#include "fmcw/eval/aggregate_report.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <stdexcept>

#include "fmcw/core/errors.hpp"
#include "fmcw/eval/table_writer.hpp"
#include "fmcw/io/atomic_file.hpp"
#include "report_json.hpp"

namespace fmcw::eval {

namespace fs = std::filesystem;
using json = report_json::json;
using report_json::error_json;
using report_json::number;

bool is_dataset_folder(const std::string& dir) {
  std::error_code ec;
  return fs::is_regular_file(fs::path(dir) / "dataset.yaml", ec);
}

std::vector<DatasetFolder> find_datasets(const std::string& folder, std::vector<std::string>* notes) {
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) throw core::FileError("'" + folder + "': not a folder");
  std::vector<DatasetFolder> found;
  std::vector<std::string> ignored;
  for (const auto& e : fs::directory_iterator(folder, ec)) {
    const std::string name = e.path().filename().string();
    if (name.empty() || name[0] == '.' || !e.is_directory()) continue;
    if (is_dataset_folder(e.path().string())) {
      found.push_back({name, e.path().string()});
    } else {
      ignored.push_back(name);
    }
  }
  if (ec) throw core::FileError("'" + folder + "': cannot list: " + ec.message());
  if (found.empty()) {
    throw core::FileError((fs::path(folder) / "dataset.yaml").string() +
                          ": missing, and no subfolder holds a dataset.yaml: '" + folder +
                          "' is neither a dataset nor a folder of datasets written by `fmcw simulate`");
  }
  std::sort(found.begin(), found.end(), [](const DatasetFolder& a, const DatasetFolder& b) { return a.name < b.name; });
  std::sort(ignored.begin(), ignored.end());
  if (notes != nullptr && !ignored.empty()) {
    std::string list;
    for (const std::string& n : ignored) list += (list.empty() ? "" : ", ") + n;
    notes->push_back(std::to_string(ignored.size()) + " subfolder(s) of '" + folder +
                     "' without dataset.yaml skipped: " + list);
  }
  return found;
}

namespace {
std::string join_names(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

// Notes for manifest rows without a dataset and datasets without a manifest row.
void manifest_notes(const ScenarioManifest& manifest, const std::vector<std::string>& scenarios,
                    std::vector<std::string>& notes) {
  const std::set<std::string> have(scenarios.begin(), scenarios.end());
  std::vector<std::string> rows_without, datasets_without;
  for (const auto& row : manifest.rows) {
    if (have.count(row[manifest.name_column]) == 0) rows_without.push_back(row[manifest.name_column]);
  }
  for (const std::string& s : have) {
    if (manifest.find(s) == nullptr) datasets_without.push_back(s);
  }
  if (!rows_without.empty()) {
    notes.push_back(manifest.path + ": " + std::to_string(rows_without.size()) +
                    " scenario(s) without a dataset: " + join_names(rows_without));
  }
  if (!datasets_without.empty()) {
    notes.push_back(manifest.path + ": no row for " + std::to_string(datasets_without.size()) +
                    " scenario(s) of the datasets: " + join_names(datasets_without));
  }
}
}  // namespace

AggregateResult evaluate_folder(const std::string& folder, int max_frames, const EvaluationParams& params,
                                const AggregateCallbacks& callbacks) {
  params.validate();
  AggregateResult r;
  r.folder = folder;
  r.max_frames = max_frames;
  r.params = params;
  r.methods = params.resolved_methods();
  const std::vector<DatasetFolder> datasets = find_datasets(folder, &r.notes);
  // Every dataset is checked before any is evaluated: a stopped or broken one is found in
  // seconds, not after hours of evaluating the others.
  std::vector<std::string> scenarios;
  for (const DatasetFolder& d : datasets) scenarios.push_back(DatasetSource(d.path, max_frames).info().scenario);
  const fs::path manifest_file = fs::path(folder) / AggregateFiles::kManifest;
  std::error_code ec;
  if (fs::is_regular_file(manifest_file, ec)) {
    r.manifest = read_scenario_manifest(manifest_file.string());
    manifest_notes(*r.manifest, scenarios, r.notes);
  }
  if (callbacks.notes) callbacks.notes(r.notes);
  for (std::size_t k = 0; k < datasets.size(); ++k) {
    if (callbacks.dataset_started) callbacks.dataset_started(k, datasets.size(), datasets[k].name);
    EvaluationResult result;
    try {
      DatasetSource source(datasets[k].path, max_frames);
      result = evaluate(source, params, callbacks.frame_progress);
    } catch (const std::exception& e) {
      // A bad frame found part-way: the other datasets still count, the failure is listed.
      r.failures.push_back({datasets[k].name, e.what()});
      continue;
    }
    r.digests.push_back(digest(result, datasets[k].name));
    if (callbacks.dataset_done) callbacks.dataset_done(result, datasets[k].name);
  }
  if (!r.digests.empty()) {
    for (const std::string& m : r.methods) r.pooled.push_back(pool(r.digests, m, params.targets));
  }
  return r;
}

namespace {
json named_values(const std::vector<NamedValue>& values) {
  json out = json::object();
  for (const NamedValue& v : values) {
    out[v.key] = v.integer && std::isfinite(v.value) ? json(static_cast<std::int64_t>(v.value)) : number(v.value);
  }
  return out;
}

// A manifest cell in JSON: a number when the whole cell is one, else the text.
json manifest_cell(const std::string& s) {
  if (s.empty()) return s;
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (end == s.c_str() + s.size() && std::isfinite(v)) return v;
  return s;
}

const char* yes_no(bool b) { return b ? "yes" : "no"; }

// What a target says on one scenario: "yes", "no", or "n/a" when it was not held there.
std::string target_cell(const std::vector<TargetCheck>& checks, const std::string& key) {
  for (const TargetCheck& c : checks) {
    if (c.key == key) return yes_no(c.met);
  }
  return "n/a";
}

bool all_met(const std::vector<TargetCheck>& checks) {
  return std::all_of(checks.begin(), checks.end(), [](const TargetCheck& c) { return c.met; });
}

// The dataset columns of a per-scenario row, before the method's metrics.
std::vector<NamedValue> dataset_values(const DatasetDigest& d) {
  return {{"frames", static_cast<double>(d.dataset.frames), true, false},
          {"seed", static_cast<double>(d.source.seed), true, false},
          {"duration_s", d.dataset.duration_s, false, false},
          {"mean_ego_speed_mps", d.dataset.mean_ego_speed_mps, false, false},
          {"max_ego_speed_mps", d.dataset.max_ego_speed_mps, false, false},
          {"actors_seen", static_cast<double>(d.dataset.actors_seen), true, false},
          {"motion_points", static_cast<double>(d.dataset.motion_points), true, false}};
}

void add_value(CsvTable& t, const NamedValue& v) {
  if (v.integer && std::isfinite(v.value)) {
    t.add(static_cast<std::int64_t>(v.value));
  } else {
    t.add(v.value);
  }
}

// Manifest columns carried into scenarios.csv: all but "name", renamed manifest_<col> when the
// table already has a column of that name.
struct CarriedColumn {
  std::size_t index;
  std::string name;
};
std::vector<CarriedColumn> carried_columns(const ScenarioManifest& m, const std::vector<std::string>& taken) {
  std::vector<CarriedColumn> out;
  for (std::size_t k = 0; k < m.columns.size(); ++k) {
    if (k == m.name_column) continue;
    const bool clash = std::find(taken.begin(), taken.end(), m.columns[k]) != taken.end();
    out.push_back({k, clash ? "manifest_" + m.columns[k] : m.columns[k]});
  }
  return out;
}

std::vector<std::string> scenario_columns(const std::vector<std::string>& target_keys) {
  std::vector<std::string> cols = {"dataset", "scenario", "method"};
  for (const NamedValue& v : dataset_values(DatasetDigest{})) cols.push_back(v.key);
  for (const NamedValue& v : scenario_metrics(MethodDigest{})) cols.push_back(v.key);
  for (const std::string& k : target_keys) cols.push_back("target_" + k);
  cols.push_back("targets_met");
  cols.push_back("total_ms");
  return cols;
}

std::vector<std::string> target_keys(const AggregateResult& r) {
  std::vector<std::string> keys;
  for (const TargetCheck& c : all_target_checks(r.params.targets)) keys.push_back(c.key);
  return keys;
}

void write_scenarios(const std::string& path, const AggregateResult& r) {
  const std::vector<std::string> keys = target_keys(r);
  std::vector<std::string> cols = scenario_columns(keys);
  std::vector<CarriedColumn> carried;
  if (r.manifest) carried = carried_columns(*r.manifest, cols);
  for (const CarriedColumn& c : carried) cols.push_back(c.name);
  CsvTable t(cols);
  for (const DatasetDigest& d : r.digests) {
    const std::vector<std::string>* row = r.manifest ? r.manifest->find(d.source.scenario) : nullptr;
    for (std::size_t m = 0; m < d.methods.size(); ++m) {
      const MethodDigest& md = d.per_method[m];
      t.add_quoted(d.folder).add_quoted(d.source.scenario).add(d.methods[m]);
      for (const NamedValue& v : dataset_values(d)) add_value(t, v);
      for (const NamedValue& v : scenario_metrics(md)) add_value(t, v);
      for (const std::string& k : keys) t.add(target_cell(md.checks, k));
      t.add(yes_no(all_met(md.checks))).add(md.summary.mean_timing_ms.total_ms);
      for (const CarriedColumn& c : carried) t.add_quoted(row != nullptr ? (*row)[c.index] : "");
      t.end_row();
    }
  }
  t.write(path);
}

void write_pooled(const std::string& path, const AggregateResult& r) {
  std::vector<std::string> cols = {"method", "scenarios", "frames"};
  for (const NamedValue& v : scenario_metrics(MethodDigest{})) cols.push_back(v.key);
  cols.push_back("scenarios_all_targets_met");
  cols.push_back("total_ms");
  CsvTable t(cols);
  for (const PooledMethod& p : r.pooled) {
    t.add(p.method).add(p.scenarios).add(p.pooled.frames);
    for (const NamedValue& v : p.metrics) add_value(t, v);
    t.add(p.all_targets_met).add(p.pooled.mean_timing_ms.total_ms);
    t.end_row();
  }
  t.write(path);
}

double pooled_value(const PooledMethod& p, const std::string& key) {
  for (const NamedValue& v : p.metrics) {
    if (v.key == key) return v.value;
  }
  return std::nan("");
}

void write_spread(const std::string& path, const AggregateResult& r) {
  CsvTable t({"method", "metric", "pooled", "median", "p10", "p90", "min", "max", "scenarios"});
  for (const PooledMethod& p : r.pooled) {
    for (const Spread& s : p.spread) {
      t.add(p.method).add(s.key).add(pooled_value(p, s.key)).add(s.median).add(s.p10).add(s.p90).add(s.min).add(s.max);
      t.add(s.scenarios).end_row();
    }
  }
  t.write(path);
}

void write_targets(const std::string& path, const AggregateResult& r) {
  CsvTable t({"method", "target", "relation", "limit", "scenarios_checked", "scenarios_met", "share_met"});
  for (const PooledMethod& p : r.pooled) {
    for (const TargetShare& s : p.targets) {
      t.add(p.method).add(s.key).add(s.relation).add(s.limit).add(s.checked).add(s.met).add(s.share).end_row();
    }
    const double share = p.scenarios > 0 ? static_cast<double>(p.all_targets_met) / p.scenarios : std::nan("");
    t.add(p.method).add("all").add("").add(std::nan("")).add(p.scenarios).add(p.all_targets_met).add(share).end_row();
  }
  t.write(path);
}

// What the figures plot against: a manifest column when the manifest has it, else a column
// the datasets give.
json axis(const AggregateResult& r, const std::vector<CarriedColumn>& carried, const std::string& wanted,
          const std::string& fallback, const std::string& meaning) {
  if (r.manifest) {
    for (const CarriedColumn& c : carried) {
      if (r.manifest->columns[c.index] == wanted) return {{"column", c.name}, {"source", "manifest"}, {"meaning", meaning}};
    }
  }
  return {{"column", fallback}, {"source", "datasets"}, {"meaning", meaning}};
}
}  // namespace

std::string aggregate_metrics_json(const AggregateResult& r, const std::string& tool_version) {
  const std::vector<std::string> keys = target_keys(r);
  std::vector<CarriedColumn> carried;
  if (r.manifest) carried = carried_columns(*r.manifest, scenario_columns(keys));
  json scenarios = json::array();
  for (const DatasetDigest& d : r.digests) {
    json methods = json::object();
    for (std::size_t m = 0; m < d.methods.size(); ++m) {
      const MethodDigest& md = d.per_method[m];
      json x = named_values(scenario_metrics(md));
      json targets = json::object();
      for (const TargetCheck& c : md.checks) targets[c.key] = c.met;
      x["targets"] = targets;
      x["targets_met"] = all_met(md.checks);
      x["total_ms"] = number(md.summary.mean_timing_ms.total_ms);
      methods[d.methods[m]] = x;
    }
    json manifest = nullptr;
    if (r.manifest) {
      if (const std::vector<std::string>* row = r.manifest->find(d.source.scenario)) {
        manifest = json::object();
        for (const CarriedColumn& c : carried) manifest[r.manifest->columns[c.index]] = manifest_cell((*row)[c.index]);
      }
    }
    json entry = {{"dataset", d.folder}, {"path", d.source.path}, {"scenario", d.source.scenario}};
    entry.update(named_values(dataset_values(d)));
    entry["manifest"] = manifest;
    entry["methods"] = methods;
    entry["report"] = std::string(AggregateFiles::kDatasets) + "/" + d.folder + "/metrics.json";
    scenarios.push_back(entry);
  }
  json pooled = json::object();
  for (const PooledMethod& p : r.pooled) {
    const MethodSummary& s = p.pooled;
    json spread = json::object();
    for (const Spread& x : p.spread) {
      spread[x.key] = {{"median", number(x.median)}, {"p10", number(x.p10)}, {"p90", number(x.p90)},
                       {"min", number(x.min)},       {"max", number(x.max)}, {"scenarios", x.scenarios}};
    }
    json targets = json::array();
    for (const TargetShare& t : p.targets) {
      targets.push_back({{"key", t.key},
                         {"relation", t.relation},
                         {"limit", t.limit},
                         {"scenarios_checked", t.checked},
                         {"scenarios_met", t.met},
                         {"share_met", number(t.share)}});
    }
    pooled[p.method] = {
        {"scenarios", p.scenarios},
        {"frames", s.frames},
        {"frames_not_ok", s.frames_not_ok},
        {"motion", report_json::motion(s.motion)},
        {"ego_velocity",
         {{"rmse_mps", report_json::vec(s.ego_rmse_mps)},
          {"frames", s.ego_frames},
          {"yaw_rate_rmse_dps", number(s.yaw_rate_rmse_dps)},
          {"yaw_frames", s.yaw_frames}}},
        {"objects",
         {{"evaluated", s.objects_evaluated},
          {"detected", s.objects_detected},
          {"estimated", s.objects_estimated},
          {"large", s.objects_large},
          {"detected_fraction", number(s.detected_fraction)},
          {"centre_error_mps", error_json(p.centre)},
          {"centre_error_mps_ge200", error_json(p.centre_large)},
          {"instance_precision", number(s.instance_precision)},
          {"instance_recall", number(s.instance_recall)}}},
        {"blind_zone",
         {{"band_pixels", s.blind_band_pixels},
          {"band_pixels_detected", s.blind_band_detected},
          {"recall_tracked", number(s.blind_recall_tracked)}}},
        {"timing_ms", {{"total", number(s.mean_timing_ms.total_ms)}}},
        {"spread", spread},
        {"targets", targets},
        {"all_targets_met",
         {{"scenarios_met", p.all_targets_met},
          {"share_met", p.scenarios > 0 ? json(static_cast<double>(p.all_targets_met) / p.scenarios) : json(nullptr)}}},
    };
  }
  json failures = json::array();
  for (const FailedDataset& f : r.failures) failures.push_back({{"dataset", f.folder}, {"error", f.error}});
  json manifest = nullptr;
  if (r.manifest) {
    json columns = json::array();
    for (const CarriedColumn& c : carried) columns.push_back(c.name);
    manifest = {{"path", r.manifest->path}, {"rows", r.manifest->rows.size()}, {"columns", columns}};
  }
  json out = {
      {"kind", "aggregate"},
      {"format_version", 1},
      {"tool_version", tool_version},
      {"folder", r.folder},
      {"datasets", r.digests.size() + r.failures.size()},
      {"datasets_evaluated", r.digests.size()},
      {"complete", r.failures.empty()},
      {"failures", failures},
      {"default_method", r.params.default_method},
      {"method_order", r.methods},
      {"target_keys", keys},
      {"scenarios", scenarios},
      {"pooled", pooled},
      {"manifest", manifest},
      {"axes",
       {{"layout", axis(r, carried, "layout", "scenario", "layout")},
        {"speed", axis(r, carried, "mean_speed_mps", "mean_ego_speed_mps", "speed [m/s]")},
        {"density", axis(r, carried, "actors_per_100m", "actors_seen", "density")}}},
      {"notes", r.notes},
      {"targets", report_json::held_targets(r.params)},
      {"config", {{"method_seed", r.params.seed}, {"num_threads", r.params.num_threads}, {"max_frames", r.max_frames}}},
      {"files",
       {{"scenarios", AggregateFiles::kScenarios},
        {"pooled", AggregateFiles::kPooled},
        {"spread", AggregateFiles::kSpread},
        {"targets", AggregateFiles::kTargets},
        {"datasets", AggregateFiles::kDatasets}}},
  };
  return out.dump(2) + "\n";
}

void write_aggregate_report(const std::string& dir, const AggregateResult& r, const std::string& tool_version) {
  io::ensure_writable_directory(dir);
  const fs::path d(dir);
  write_scenarios((d / AggregateFiles::kScenarios).string(), r);
  write_pooled((d / AggregateFiles::kPooled).string(), r);
  write_spread((d / AggregateFiles::kSpread).string(), r);
  write_targets((d / AggregateFiles::kTargets).string(), r);
  write_text_atomically((d / AggregateFiles::kMetrics).string(), aggregate_metrics_json(r, tool_version));
}

std::string aggregate_summary_text(const AggregateResult& r) {
  std::ostringstream out;
  out << r.digests.size() << " datasets evaluated";
  if (!r.failures.empty()) out << ", " << r.failures.size() << " failed";
  out << "\n";
  for (const PooledMethod& p : r.pooled) {
    const MethodSummary& s = p.pooled;
    out << "  " << std::left << std::setw(8) << p.method << std::right << std::fixed << std::setprecision(4)
        << " pooled accuracy " << s.motion.accuracy() << "  centre velocity >=200 px off by median "
        << std::setprecision(3) << p.centre_large.median << " / p95 " << p.centre_large.p95 << " m/s ("
        << p.centre_large.count << " object-frames)  all targets met in " << p.all_targets_met << " of "
        << p.scenarios << " scenarios\n";
    std::string shares;
    for (const TargetShare& t : p.targets) {
      if (t.checked == 0) continue;
      shares += (shares.empty() ? "" : ", ") + t.key + " " + std::to_string(t.met) + "/" + std::to_string(t.checked);
    }
    out << "           targets met: " << shares << "\n";
  }
  return out.str();
}

AggregateResult evaluate_folder_to_report(const std::string& folder, int max_frames, const EvaluationParams& params,
                                          const ReportOptions& options, const AggregateCallbacks& callbacks,
                                          std::ostream* summary) {
  io::ensure_writable_directory(options.dir);
  AggregateCallbacks cb = callbacks;
  cb.dataset_done = [&](const EvaluationResult& result, const std::string& name) {
    // Each dataset's own metrics.json, for looking into one scenario; its tables are not
    // written (objects.csv and the snapshot of fifty scenarios would be hundreds of MB).
    const fs::path dir = fs::path(options.dir) / AggregateFiles::kDatasets / name;
    io::ensure_writable_directory(dir.string());
    json m = json::parse(metrics_json(result, options.tool_version));
    m.erase("files");
    write_text_atomically((dir / EvaluationFiles::kMetrics).string(), m.dump(2) + "\n");
    if (callbacks.dataset_done) callbacks.dataset_done(result, name);
  };
  AggregateResult r = evaluate_folder(folder, max_frames, params, cb);
  std::string failed;
  for (const FailedDataset& f : r.failures) {
    failed += (failed.empty() ? "dataset '" : "; dataset '") + f.folder + "': " + f.error;
  }
  if (r.digests.empty()) {
    throw std::runtime_error("every dataset of '" + folder + "' failed, no report written: " + failed);
  }
  write_aggregate_report(options.dir, r, options.tool_version);
  if (summary != nullptr) *summary << aggregate_summary_text(r) << std::flush;
  if (options.figures) run_report_script(options.script, options.dir);
  if (!r.failures.empty()) {
    throw std::runtime_error(std::to_string(r.failures.size()) + " of " +
                             std::to_string(r.failures.size() + r.digests.size()) + " datasets failed (listed in " +
                             options.dir + "/metrics.json; the report covers the others): " + failed);
  }
  return r;
}

}  // namespace fmcw::eval
