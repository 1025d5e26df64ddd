// `fmcw evaluate FOLDER` over a folder of datasets, as a user drives it: one aggregate report
// whose rows, pooled metrics and target shares agree with `fmcw evaluate DATASET` of each
// dataset (known answers: pooled counts, pooled per-object errors from each objects.csv),
// deterministic output, and the errors: no dataset, an incomplete one, one failing part-way.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>

#include "fmcw/eval/scenario_manifest.hpp"
#include "fmcw/eval/statistics.hpp"
#include "support/cli.hpp"
#include "support/dataset_files.hpp"
#include "support/report_files.hpp"
#include "support/temp_dir.hpp"

namespace {

namespace fs = std::filesystem;
using fmcw::test::CliResult;
using fmcw::test::error_lines;
using fmcw::test::slurp;
using json = nlohmann::json;

CliResult run(const std::string& args) { return fmcw::test::run_cli(args); }

json read_json(const fs::path& p) { return json::parse(slurp(p)); }

// A CSV as a header and rows of cells (quotes as RFC 4180).
struct Csv {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::size_t col(const std::string& name) const {
    const auto it = std::find(header.begin(), header.end(), name);
    EXPECT_NE(it, header.end()) << name;
    return static_cast<std::size_t>(it - header.begin());
  }
};
Csv read_csv(const fs::path& p) {
  auto rows = fmcw::eval::parse_csv(slurp(p), p.string());
  Csv c;
  if (rows.empty()) return c;
  c.header = rows.front();
  c.rows.assign(rows.begin() + 1, rows.end());
  return c;
}

// The datasets: folder name -> committed scenario. Folder order differs from scenario order.
const std::vector<std::pair<std::string, std::string>> kDatasets = {
    {"a_straight", "straight_road"}, {"b_intersection", "intersection"}, {"c_crowd", "crowd"}};

class AggregateCli : public fmcw::test::TempDirTest {
 protected:
  // set/<folder> for each of kDatasets (the first `count`), 3 frames each.
  std::string make_set(std::size_t count = kDatasets.size()) {
    const fs::path set = path("set");
    for (std::size_t k = 0; k < count; ++k) {
      const CliResult r = run("simulate " + std::string(FMCW_SOURCE_DIR) + "/scenarios/" + kDatasets[k].second +
                              ".yaml -o " + (set / kDatasets[k].first).string() + " --frames 3");
      EXPECT_EQ(r.code, 0) << r.output;
    }
    return set.string();
  }
  // A manifest with one row per committed scenario of the set, an extra column with a comma.
  void write_manifest(const std::string& set, const std::string& extra_rows = "") {
    std::ofstream(fs::path(set) / "manifest.csv")
        << "name,layout,mean_speed_mps,actors_per_100m,seed,route\n"
           "straight_road,straight_road,12.5,2.0,1,\"lane 1, lane 2\"\n"
           "intersection,junction,8,4.5,2,left\n"
           "crowd,junction,1.4,20,3,none\n"
        << extra_rows;
  }
  // Expects the exit code of a bad file, one error line naming `names`, and no aggregate
  // report written.
  void expect_rejected(const std::string& folder, const std::string& names) {
    const std::string out = path("report");
    const CliResult r = run("evaluate " + folder + " -o " + out + " --no-figures");
    EXPECT_EQ(r.code, fmcw::test::kExitFile) << r.output;
    const std::vector<std::string> errors = error_lines(r.output);
    ASSERT_EQ(errors.size(), 1u) << r.output;
    EXPECT_EQ(errors[0].rfind("fmcw: error: ", 0), 0u) << errors[0];
    EXPECT_NE(errors[0].find(names), std::string::npos) << errors[0];
    EXPECT_FALSE(fs::exists(fs::path(out) / "metrics.json"));
    EXPECT_FALSE(fs::exists(fs::path(out) / "scenarios.csv"));
  }
};

TEST_F(AggregateCli, RowsPooledMetricsAndTargetSharesAgreeWithEachDatasetsOwnReport) {
  const std::string set = make_set();
  write_manifest(set);
  const fs::path agg = path("agg");
  const CliResult r = run("evaluate " + set + " -o " + agg.string() + " --no-figures");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(r.output.find("fmcw: note"), std::string::npos) << r.output;  // manifest and datasets match
  const json m = read_json(agg / "metrics.json");
  EXPECT_EQ(m.at("kind"), "aggregate");
  EXPECT_EQ(m.at("complete"), true);
  EXPECT_EQ(m.at("datasets"), 3);
  const std::vector<std::string> methods = m.at("method_order");
  ASSERT_GE(methods.size(), 2u);
  EXPECT_EQ(methods.front(), "paper");

  // Each dataset evaluated on its own, as a user would.
  std::map<std::string, json> single;
  for (const auto& [folder, scenario] : kDatasets) {
    const fs::path out = path("single_" + folder);
    const CliResult s = run("evaluate " + set + "/" + folder + " -o " + out.string() + " --no-figures");
    ASSERT_EQ(s.code, 0) << s.output;
    single[folder] = read_json(out / "metrics.json");
  }

  // One row per dataset and method, datasets sorted by folder, the manifest's columns carried.
  const Csv rows = read_csv(agg / "scenarios.csv");
  ASSERT_EQ(rows.rows.size(), kDatasets.size() * methods.size());
  for (std::size_t k = 0; k < rows.rows.size(); ++k) {
    const auto& row = rows.rows[k];
    const auto& [folder, scenario] = kDatasets[k / methods.size()];
    EXPECT_EQ(row[rows.col("dataset")], folder);
    EXPECT_EQ(row[rows.col("scenario")], scenario);
    EXPECT_EQ(row[rows.col("method")], methods[k % methods.size()]);
    EXPECT_EQ(row[rows.col("frames")], "3");
    const json& x = single[folder].at("methods").at(methods[k % methods.size()]);
    EXPECT_EQ(row[rows.col("tp")], std::to_string(x.at("motion").at("tp").get<std::uint64_t>()));
    EXPECT_EQ(row[rows.col("targets_met")], x.at("targets_met").get<bool>() ? "yes" : "no");
    for (const json& t : x.at("targets")) {
      EXPECT_EQ(row[rows.col("target_" + t.at("key").get<std::string>())], t.at("met").get<bool>() ? "yes" : "no");
    }
  }
  EXPECT_EQ(rows.rows[0][rows.col("layout")], "straight_road");
  EXPECT_EQ(rows.rows[0][rows.col("route")], "lane 1, lane 2");
  EXPECT_EQ(rows.rows[0][rows.col("manifest_seed")], "1");  // clashes with the dataset's seed column
  EXPECT_EQ(m.at("axes").at("speed").at("column"), "mean_speed_mps");
  EXPECT_EQ(m.at("axes").at("speed").at("source"), "manifest");

  for (const std::string& method : methods) {
    SCOPED_TRACE(method);
    const json& p = m.at("pooled").at(method);
    // Pooled accuracy from the summed confusion counts of the single reports.
    std::uint64_t tp = 0, fp = 0, tn = 0, fn = 0;
    for (const auto& [folder, report] : single) {
      const json& c = report.at("methods").at(method).at("motion");
      tp += c.at("tp").get<std::uint64_t>();
      fp += c.at("fp").get<std::uint64_t>();
      tn += c.at("tn").get<std::uint64_t>();
      fn += c.at("fn").get<std::uint64_t>();
    }
    EXPECT_EQ(p.at("motion").at("tp").get<std::uint64_t>(), tp);
    EXPECT_EQ(p.at("motion").at("fn").get<std::uint64_t>(), fn);
    EXPECT_DOUBLE_EQ(p.at("motion").at("accuracy").get<double>(),
                     static_cast<double>(tp + tn) / static_cast<double>(tp + fp + tn + fn));

    // Share of scenarios meeting each target, counted from the single reports.
    for (const json& t : p.at("targets")) {
      const std::string key = t.at("key");
      int checked = 0, met = 0;
      for (const auto& [folder, report] : single) {
        for (const json& c : report.at("methods").at(method).at("targets")) {
          if (c.at("key") != key) continue;
          ++checked;
          met += c.at("met").get<bool>() ? 1 : 0;
        }
      }
      EXPECT_EQ(t.at("scenarios_checked").get<int>(), checked) << key;
      EXPECT_EQ(t.at("scenarios_met").get<int>(), met) << key;
    }

    // Pooled centre-velocity errors of objects >= 200 points: the samples of every dataset's
    // objects.csv pooled (not their medians).
    std::vector<double> samples;
    for (const auto& [folder, scenario] : kDatasets) {
      const Csv o = read_csv(path("single_" + folder) + "/objects.csv");
      for (const auto& row : o.rows) {
        if (row[o.col("method")] == method && row[o.col("evaluated")] == "1" && row[o.col("estimate_valid")] == "1" &&
            std::stoi(row[o.col("pixels")]) >= 200) {
          samples.push_back(std::stod(row[o.col("ref_err_mps")]));
        }
      }
    }
    const json& e = p.at("objects").at("centre_error_mps_ge200");
    ASSERT_EQ(e.at("count").get<std::size_t>(), samples.size());
    if (!samples.empty()) {
      EXPECT_NEAR(e.at("median").get<double>(), fmcw::eval::median(samples), 1e-6);
      EXPECT_NEAR(e.at("max").get<double>(), *std::max_element(samples.begin(), samples.end()), 1e-6);
      EXPECT_NEAR(e.at("p95").get<double>(), fmcw::eval::quantile(samples, 0.95), 1e-6);
    }
    // Each scenario's per-dataset report in the aggregate is its own report.
    for (const auto& [folder, report] : single) {
      const json own = read_json(agg / "datasets" / folder / "metrics.json").at("methods").at(method);
      EXPECT_EQ(own.at("motion"), report.at("methods").at(method).at("motion")) << folder;
      EXPECT_EQ(own.at("targets"), report.at("methods").at(method).at("targets")) << folder;
    }
  }
}

// Removes what differs between two runs of the same input: the timing columns and keys, and the
// thread count the runs were told to use (config.num_threads).
std::string without_timing(const fs::path& p) {
  if (p.extension() == ".json") {
    json j = read_json(p);
    std::function<void(json&)> strip = [&](json& x) {
      if (x.is_object()) {
        for (const char* k : {"timing_ms", "timing_max_ms", "total_ms", "num_threads"}) x.erase(k);
        for (auto& [k, v] : x.items()) strip(v);
      } else if (x.is_array()) {
        for (auto& v : x) strip(v);
      }
    };
    strip(j);
    return j.dump();
  }
  Csv c = read_csv(p);
  c.rows.insert(c.rows.begin(), c.header);
  const auto it = std::find(c.header.begin(), c.header.end(), "total_ms");
  std::string out;
  for (auto row : c.rows) {
    if (it != c.header.end()) row.erase(row.begin() + (it - c.header.begin()));
    for (const auto& cell : row) out += cell + "|";
    out += "\n";
  }
  return out;
}

TEST_F(AggregateCli, TwoRunsGiveIdenticalFilesAsideFromTiming) {
  const std::string set = make_set(2);
  write_manifest(set);
  ASSERT_EQ(run("evaluate " + set + " -o " + path("one") + " --no-figures --threads 2").code, 0);
  ASSERT_EQ(run("evaluate " + set + " -o " + path("two") + " --no-figures --threads 1").code, 0);
  const auto one = fmcw::test::folder_bytes(path("one"));
  const auto two = fmcw::test::folder_bytes(path("two"));
  ASSERT_EQ(one.size(), two.size());
  EXPECT_EQ(one.size(), 5u + 2u);  // metrics.json, four tables, a metrics.json per dataset
  for (const auto& [name, bytes] : one) {
    SCOPED_TRACE(name);
    ASSERT_TRUE(two.count(name));
    EXPECT_EQ(without_timing(fs::path(path("one")) / name), without_timing(fs::path(path("two")) / name));
  }
}

TEST_F(AggregateCli, ReportWithFiguresWithoutManifestSaysWhatItPlots) {
  const std::string set = make_set(2);
  const fs::path agg = path("agg");
  const CliResult r = run("evaluate " + set + " -o " + agg.string() + " --methods fast");
  ASSERT_EQ(r.code, 0) << r.output;
  const json m = read_json(agg / "metrics.json");
  EXPECT_EQ(m.at("method_order"), json::array({"paper", "fast"}));
  EXPECT_TRUE(m.at("manifest").is_null());
  EXPECT_EQ(m.at("axes").at("speed").at("column"), "mean_ego_speed_mps");
  EXPECT_EQ(m.at("axes").at("density").at("source"), "datasets");
  EXPECT_EQ(fmcw::test::expect_report_figures(agg), 4);
  EXPECT_NE(slurp(agg / "report.html").find("from the datasets"), std::string::npos);
}

TEST_F(AggregateCli, ManifestRowsAndDatasetsThatDoNotMatchAreNotesOnce) {
  const std::string set = make_set(2);  // no crowd dataset: its manifest row has none
  write_manifest(set, "highway,highway,25,1,4,none\n");
  fs::create_directories(fs::path(set) / "scenarios");  // not a dataset: skipped, said
  std::string text = slurp(fs::path(set) / "manifest.csv");
  text.erase(text.find("intersection,junction"), text.find("crowd,") - text.find("intersection,junction"));
  std::ofstream(fs::path(set) / "manifest.csv") << text;  // intersection has no row now
  const CliResult r = run("evaluate " + set + " -o " + path("agg") + " --no-figures --methods fast");
  ASSERT_EQ(r.code, 0) << r.output;
  const auto count = [&](const std::string& s) {
    std::size_t n = 0;
    for (std::size_t at = r.output.find(s); at != std::string::npos; at = r.output.find(s, at + 1)) ++n;
    return n;
  };
  EXPECT_EQ(count("fmcw: note: "), 3u) << r.output;
  EXPECT_EQ(count("without a dataset: crowd, highway"), 1u) << r.output;
  EXPECT_EQ(count("no row for 1 scenario(s) of the datasets: intersection"), 1u) << r.output;
  EXPECT_EQ(count("without dataset.yaml skipped: scenarios"), 1u) << r.output;
  const json m = read_json(path("agg") + "/metrics.json");
  EXPECT_EQ(m.at("notes").size(), 3u);
  EXPECT_TRUE(m.at("scenarios").at(1).at("manifest").is_null());  // b_intersection
  EXPECT_EQ(m.at("scenarios").at(0).at("manifest").at("mean_speed_mps"), 12.5);
}

TEST_F(AggregateCli, FolderWithoutDatasetsIsAnError) {
  fs::create_directories(path("empty"));
  expect_rejected(path("empty"), "no subfolder holds a dataset.yaml");
  fs::create_directories(path("empty") + "/not_a_dataset/frames");
  expect_rejected(path("empty"), "empty/dataset.yaml");
}

TEST_F(AggregateCli, IncompleteDatasetIsNamedBeforeAnyIsEvaluated) {
  const std::string set = make_set(1);
  fs::copy(fs::path(set) / "a_straight", fs::path(set) / "b_stopped", fs::copy_options::recursive);
  const fs::path yaml = fs::path(set) / "b_stopped" / "dataset.yaml";
  std::string text = slurp(yaml);
  const auto at = text.find("complete: true");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 14, "complete: false");
  std::ofstream(yaml) << text;
  expect_rejected(set, "b_stopped/dataset.yaml");
  EXPECT_FALSE(fs::exists(path("report") + "/datasets/a_straight"));  // nothing evaluated
}

TEST_F(AggregateCli, DatasetFailingPartWayIsListedAndTheExitIsNonZero) {
  const std::string set = make_set(1);
  fs::copy(fs::path(set) / "a_straight", fs::path(set) / "b_truncated", fs::copy_options::recursive);
  const fs::path frame = fs::path(set) / "b_truncated" / "frames" / "000001.pcd";
  fs::resize_file(frame, fs::file_size(frame) / 2);
  const fs::path agg = path("agg");
  const CliResult r = run("evaluate " + set + " -o " + agg.string() + " --no-figures --methods fast");
  EXPECT_EQ(r.code, 1) << r.output;
  const std::vector<std::string> errors = error_lines(r.output);
  ASSERT_EQ(errors.size(), 1u) << r.output;
  EXPECT_NE(errors[0].find("dataset 'b_truncated'"), std::string::npos) << errors[0];
  EXPECT_NE(errors[0].find("000001.pcd"), std::string::npos) << errors[0];
  // The report of the others is written and lists the failure.
  const json m = read_json(agg / "metrics.json");
  EXPECT_EQ(m.at("complete"), false);
  EXPECT_EQ(m.at("datasets"), 2);
  EXPECT_EQ(m.at("datasets_evaluated"), 1);
  ASSERT_EQ(m.at("failures").size(), 1u);
  EXPECT_EQ(m.at("failures").at(0).at("dataset"), "b_truncated");
  EXPECT_EQ(read_csv(agg / "scenarios.csv").rows.size(), 2u);  // a_straight: paper and fast
}

}  // namespace
