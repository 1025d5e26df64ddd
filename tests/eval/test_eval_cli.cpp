// `fmcw evaluate`, `fmcw run` and `fmcw study` as a user drives them: the report (every figure
// report.html names is a real PNG, metrics.json has every documented key), and bad input (one
// error line naming the file, exit code 1, no report written).

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "fmcw/core/motion_pipeline.hpp"
#include "support/cli.hpp"
#include "support/dataset_files.hpp"
#include "support/report_files.hpp"
#include "support/temp_dir.hpp"

namespace {

namespace fs = std::filesystem;

using fmcw::test::CliResult;
using fmcw::test::error_lines;
using fmcw::test::expect_report_figures;
using fmcw::test::slurp;

CliResult run(const std::string& args) { return fmcw::test::run_cli(args); }

class EvalCli : public fmcw::test::TempDirTest {
 protected:
  // A small dataset of the intersection scenario.
  std::string dataset(int frames = 3) {
    const std::string ds = path("ds");
    const CliResult r = run("simulate " + std::string(FMCW_SOURCE_DIR) + "/scenarios/intersection.yaml -o " + ds +
                            " --frames " + std::to_string(frames));
    EXPECT_EQ(r.code, 0) << r.output;
    return ds;
  }
  // Evaluating ds must fail as a bad file does, with one error line containing `names`, and
  // write no report: not even the report folder, which did not exist before.
  void expect_rejected(const std::string& ds, const std::string& names) {
    const std::string out = path("report");
    ASSERT_FALSE(fs::exists(out));
    const CliResult r = run("evaluate " + ds + " -o " + out);
    EXPECT_EQ(r.code, fmcw::test::kExitFile) << r.output;
    const std::vector<std::string> errors = error_lines(r.output);
    ASSERT_EQ(errors.size(), 1u) << r.output;
    EXPECT_EQ(errors[0].rfind("fmcw: error: ", 0), 0u) << errors[0];
    EXPECT_NE(errors[0].find(names), std::string::npos) << errors[0];
    for (const char* f : {"metrics.json", "frames.csv", "objects.csv", "report.html"}) {
      EXPECT_FALSE(fs::exists(fs::path(out) / f)) << f;
    }
    EXPECT_FALSE(fs::exists(out)) << "an empty report folder left behind";
  }
};

TEST_F(EvalCli, EvaluateWritesEveryDocumentedKeyAndFigure) {
  const std::string ds = dataset(3);
  const CliResult r = run("evaluate " + ds + " -o " + path("report"));
  ASSERT_EQ(r.code, 0) << r.output;
  const fs::path rep = path("report");
  const nlohmann::json m = nlohmann::json::parse(slurp(rep / "metrics.json"));
  EXPECT_EQ(m.at("scenario"), "intersection");
  EXPECT_EQ(m.at("frames"), 3);
  EXPECT_EQ(m.at("default_method"), fmcw::core::MotionPipelineParams::default_method());
  const std::vector<std::string> order = m.at("method_order");
  ASSERT_GE(order.size(), 2u);
  EXPECT_EQ(order.front(), "paper");  // the baseline, first
  EXPECT_TRUE(m.at("methods").contains("fast"));
  for (const std::string& method : order) {
    SCOPED_TRACE(method);
    const nlohmann::json& x = m.at("methods").at(method);
    for (const char* k : {"precision", "recall", "accuracy"}) EXPECT_TRUE(x.at("motion").contains(k)) << k;
    EXPECT_EQ(x.at("ego_velocity").at("rmse_mps").size(), 3u);
    EXPECT_EQ(x.at("ego_velocity").at("max_abs_mps").size(), 3u);
    for (const char* k : {"evaluated", "detected_fraction", "median_error_mps", "median_error_mps_ge200"}) {
      EXPECT_TRUE(x.at("objects").contains(k)) << k;
    }
    for (const char* k : {"centre_error_p90_mps_ge200", "centre_error_p95_mps_ge200", "centre_error_max_mps_ge200",
                          "centre_error_share_over_1mps_ge200", "centre_error_share_over_0p5mps_ge200", "by_class",
                          "by_distance", "by_track_age", "covariance_coverage_95", "mean_nees", "calibration",
                          "calibration_by_class", "calibration_by_track_age"}) {
      EXPECT_TRUE(x.at("objects").contains(k)) << k;
    }
    for (const char* k : {"mota", "motp_m", "id_switches", "fragmentations", "idf1", "hota", "deta", "assa", "loca",
                          "by_class", "vehicles"}) {
      EXPECT_TRUE(x.at("tracking").contains(k)) << k;
    }
    for (const char* k : {"clustering", "ego", "objects", "total"}) EXPECT_TRUE(x.at("timing_ms").contains(k)) << k;
    EXPECT_TRUE(x.at("motion").at("accuracy").is_number());
  }
  for (const char* k : {"scans", "motion_points", "duration_s", "ego_status"}) {
    EXPECT_TRUE(m.at("dataset").contains(k)) << k;
  }
  for (const auto& [key, file] : m.at("files").items()) EXPECT_TRUE(fs::is_regular_file(rep / file.get<std::string>())) << key;
  EXPECT_EQ(expect_report_figures(rep), 9);  // with the error CDF
  EXPECT_NE(slurp(rep / "report.html").find("HOTA (DetA / AssA / LocA)"), std::string::npos);
  // Per frame and method.
  std::istringstream frames(slurp(rep / "frames.csv"));
  std::string line;
  std::size_t rows = 0;
  while (std::getline(frames, line)) ++rows;
  EXPECT_EQ(rows, 1 + 3 * order.size());
}

TEST_F(EvalCli, RunSimulatesEvaluatesAndRefusesToMixDatasets) {
  const std::string scenario = std::string(FMCW_SOURCE_DIR) + "/scenarios/straight_road.yaml";
  const std::string out = path("run");
  CliResult r = run("run " + scenario + " -o " + out + " --frames 2 --no-figures --methods fast");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(fs::exists(fs::path(out) / "dataset" / "dataset.yaml"));
  const nlohmann::json m = nlohmann::json::parse(slurp(fs::path(out) / "metrics.json"));
  EXPECT_EQ(m.at("frames"), 2);
  EXPECT_TRUE(m.at("methods").contains("paper"));
  r = run("run " + scenario + " -o " + out + " --frames 1 --no-figures");
  EXPECT_EQ(r.code, fmcw::test::kExitUsage);
  EXPECT_NE(r.output.find("--overwrite"), std::string::npos) << r.output;
  r = run("run " + scenario + " -o " + out + " --frames 1 --no-figures --overwrite");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(nlohmann::json::parse(slurp(fs::path(out) / "metrics.json")).at("frames"), 1);
}

TEST_F(EvalCli, FolderWithoutDatasetYamlOrFrames) {
  fs::create_directories(path("empty"));
  expect_rejected(path("empty"), "empty/dataset.yaml");
  const std::string ds = dataset(2);
  fs::remove_all(fs::path(ds) / "frames");
  expect_rejected(ds, "ds/frames");
}

TEST_F(EvalCli, TruncatedFrameIsNamed) {
  const std::string ds = dataset(3);
  const fs::path frame = fs::path(ds) / "frames" / "000001.pcd";
  fs::resize_file(frame, fs::file_size(frame) / 2);
  expect_rejected(ds, "000001.pcd");
  // A report folder that was there before stays, with what was in it.
  const fs::path kept = path("kept");
  fs::create_directories(kept);
  std::ofstream(kept / "notes.txt") << "mine\n";
  EXPECT_EQ(run("evaluate " + ds + " -o " + kept.string()).code, fmcw::test::kExitFile);
  EXPECT_EQ(slurp(kept / "notes.txt"), "mine\n");
  fs::remove(kept / "notes.txt");
  EXPECT_EQ(run("evaluate " + ds + " -o " + kept.string()).code, fmcw::test::kExitFile);
  EXPECT_TRUE(fs::is_directory(kept)) << "an empty folder that was there before is kept";
}

TEST_F(EvalCli, TruthTablesThatDoNotMatchTheFrames) {
  const std::string ds = dataset(3);
  const fs::path ego = fs::path(ds) / "ego.csv";
  std::string text = slurp(ego);
  text.erase(text.rfind('\n', text.size() - 2) + 1);  // drop the last frame's row
  std::ofstream(ego, std::ios::binary) << text;
  expect_rejected(ds, "ego.csv");
}

// A frame of another rig whose stamp matches (both datasets run at 10 Hz from 0 s) would be
// evaluated against the wrong pixels; the shape and the heads of every frame must match the
// first frame's.
TEST_F(EvalCli, FrameOfAnotherRigIsNamedWithBothShapes) {
  const std::string ds = dataset(3);
  std::ofstream(path("small.yaml")) << fmcw::test::small_scenario_yaml(3);
  ASSERT_EQ(run("simulate " + path("small.yaml") + " -o " + path("small")).code, 0);
  const fs::path frame = fs::path(ds) / "frames" / "000001.pcd";
  const std::string original = slurp(frame);
  fs::copy_file(fs::path(path("small")) / "frames" / "000001.pcd", frame, fs::copy_options::overwrite_existing);
  expect_rejected(ds, frame.string() + ": 40 x 120 pixels (rows x cols) with head 'front' [0, 120) differs from " +
                          (fs::path(ds) / "frames" / "000000.pcd").string() +
                          ", the first frame: 150 x 600 pixels (rows x cols) with heads 'left' [0, 200), "
                          "'front' [200, 400), 'right' [400, 600); every frame must come from one rig");
  // The same shape with other heads: the first head no longer stitched to the next.
  std::string other = original;
  const std::size_t at = other.find("# fmcw_head left 0 200 1 ");
  ASSERT_NE(at, std::string::npos) << other.substr(0, 400);
  other[at + std::string("# fmcw_head left 0 200 ").size()] = '0';
  std::ofstream(frame, std::ios::binary) << other;
  expect_rejected(ds, frame.string() + ": head 'left' [0, 200) is not stitched to the next where the first frame's is");
}

TEST_F(EvalCli, ExtraFrameFileIsNamed) {
  const std::string ds = dataset(2);
  fs::copy_file(fs::path(ds) / "frames" / "000001.pcd", fs::path(ds) / "frames" / "000002.pcd");
  expect_rejected(ds, "dataset.yaml");
}

TEST_F(EvalCli, StudiesWriteTheirReports) {
  const std::string ds = dataset(2);
  CliResult r = run("study threshold " + ds + " -o " + path("th") + " --thresholds 0.1,0.17,0.3");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(nlohmann::json::parse(slurp(path("th") + "/metrics.json")).at("points").size(), 3u);
  EXPECT_EQ(expect_report_figures(path("th")), 1);
  r = run("study object-points " + ds + " -o " + path("op") + " --caps 50,200 --solvers closed_form");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(expect_report_figures(path("op")), 1);
  r = run("study blind-zone -o " + path("bz") + " --speeds 5 --distances 40 --no-small --phi-step 1 --refine 2 --methods fast");
  ASSERT_EQ(r.code, 0) << r.output;
  const nlohmann::json bz = nlohmann::json::parse(slurp(path("bz") + "/metrics.json"));
  EXPECT_EQ(bz.at("kind"), "blind_zone");
  EXPECT_FALSE(bz.at("bands").empty());
  EXPECT_EQ(expect_report_figures(path("bz")), 2);
}

}  // namespace
