// Pooling over scenarios with known answers (hand-built digests), the error statistics, and the
// manifest reader.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "fmcw/core/errors.hpp"
#include "fmcw/eval/aggregate.hpp"
#include "fmcw/eval/scenario_manifest.hpp"
#include "fmcw/eval/table_writer.hpp"
#include "support/temp_dir.hpp"

namespace {

using namespace fmcw::eval;

TEST(ErrorStats, OrderStatisticsAndShareOverOneMetrePerSecond) {
  const double nan = std::nan("");
  const ErrorStats e = error_stats({0.5, 1.5, 0.2, 3.0, nan});
  EXPECT_EQ(e.count, 4);  // NaN skipped
  EXPECT_DOUBLE_EQ(e.median, 1.0);
  EXPECT_DOUBLE_EQ(e.max, 3.0);
  EXPECT_NEAR(e.p90, 1.5 + 0.7 * 1.5, 1e-12);  // numpy's linear: position 0.9 * 3 = 2.7
  EXPECT_DOUBLE_EQ(e.share_over_1mps, 0.5);
  const ErrorStats none = error_stats({});
  EXPECT_EQ(none.count, 0);
  EXPECT_TRUE(std::isnan(none.median));
  EXPECT_TRUE(std::isnan(none.share_over_1mps));
}

// One method on one dataset with the given counts, ego RMSE over frames, samples and checks.
DatasetDigest make_digest(const std::string& folder, MotionConfusion motion, double ego_rmse_x, int ego_frames,
                          std::vector<double> errors, std::vector<double> large, std::uint64_t band_pixels,
                          std::uint64_t band_detected) {
  DatasetDigest d;
  d.folder = folder;
  d.methods = {"paper"};
  MethodDigest m;
  m.summary.method = "paper";
  m.summary.frames = ego_frames;
  m.summary.motion = motion;
  m.summary.ego_frames = ego_frames;
  m.summary.ego_rmse_mps = {ego_rmse_x, 0.0, 0.0};
  m.summary.objects_evaluated = static_cast<int>(errors.size()) + 1;
  m.summary.objects_detected = static_cast<int>(errors.size());
  m.summary.objects_estimated = static_cast<int>(errors.size());
  m.summary.blind_band_pixels = band_pixels;
  m.summary.blind_band_detected = band_detected;
  m.summary.blind_recall_tracked = band_pixels > 0 ? double(band_detected) / double(band_pixels) : std::nan("");
  m.summary.yaw_rate_rmse_dps = std::nan("");
  m.centre_errors_mps = std::move(errors);
  m.centre_errors_large_mps = std::move(large);
  m.checks = check_targets(m.summary);
  d.per_method.push_back(m);
  return d;
}

TEST(Pool, CountsAreSummedAndSamplesPooledNotTheirMedians) {
  // a: 90 of 100 right; b: 990 of 1000 right. Pooled accuracy 1080 / 1100, not the mean 0.945.
  const DatasetDigest a = make_digest("a", {5, 5, 85, 5}, 0.1, 1, {0.1, 0.2, 2.0}, {0.1}, 0, 0);
  const DatasetDigest b = make_digest("b", {10, 5, 980, 5}, 0.2, 3, {0.3}, {0.3, 0.4}, 10, 9);
  const PooledMethod p = pool({a, b}, "paper", Targets{});
  EXPECT_EQ(p.scenarios, 2);
  EXPECT_EQ(p.pooled.motion.tp, 15u);
  EXPECT_EQ(p.pooled.motion.tn, 1065u);
  EXPECT_DOUBLE_EQ(p.pooled.motion.accuracy(), 1080.0 / 1100.0);
  // RMSE pooled from the squared errors: sqrt((1 * 0.01 + 3 * 0.04) / 4).
  EXPECT_DOUBLE_EQ(p.pooled.ego_rmse_mps.x(), std::sqrt((0.01 + 3 * 0.04) / 4.0));
  // Samples {0.1, 0.2, 2.0, 0.3}: median 0.25, max 2.0, one of four over 1 m/s.
  EXPECT_EQ(p.centre.count, 4);
  EXPECT_DOUBLE_EQ(p.centre.median, 0.25);
  EXPECT_DOUBLE_EQ(p.centre.max, 2.0);
  EXPECT_DOUBLE_EQ(p.centre.share_over_1mps, 0.25);
  EXPECT_DOUBLE_EQ(p.centre_large.median, 0.3);  // {0.1, 0.3, 0.4}
  EXPECT_DOUBLE_EQ(p.pooled.detected_fraction, 4.0 / 6.0);
  EXPECT_DOUBLE_EQ(p.pooled.blind_recall_tracked, 0.9);
  // Spread of the per-scenario accuracy: two values, 0.9 and 0.99.
  const auto acc = std::find_if(p.spread.begin(), p.spread.end(), [](const Spread& s) { return s.key == "accuracy"; });
  ASSERT_NE(acc, p.spread.end());
  EXPECT_EQ(acc->scenarios, 2);
  EXPECT_DOUBLE_EQ(acc->min, 0.9);
  EXPECT_DOUBLE_EQ(acc->max, 0.99);
  EXPECT_DOUBLE_EQ(acc->median, 0.945);
  EXPECT_NEAR(acc->p10, 0.9 + 0.1 * 0.09, 1e-12);
  // Targets: accuracy met on neither (0.9, 0.99 < 0.995); the blind band held only on b; the
  // vehicles' targets on neither (no vehicle is evaluated).
  for (const TargetShare& t : p.targets) {
    SCOPED_TRACE(t.key);
    if (t.key == "blind_zone_recall_tracked") {
      EXPECT_EQ(t.checked, 1);
      EXPECT_EQ(t.met, 1);
    } else if (t.key == "tracking_mota_vehicles" || t.key == "tracking_idf1_vehicles") {
      EXPECT_EQ(t.checked, 0);
    } else {
      EXPECT_EQ(t.checked, 2);
    }
    if (t.key == "accuracy") {
      EXPECT_EQ(t.met, 0);
    }
  }
  EXPECT_EQ(p.all_targets_met, 0);
  // The pooled row carries the per-scenario keys.
  ASSERT_EQ(p.metrics.size(), scenario_metrics(a.per_method[0]).size());
  EXPECT_EQ(p.metrics[1].key, "accuracy");
  EXPECT_DOUBLE_EQ(p.metrics[1].value, 1080.0 / 1100.0);
}

TEST(Pool, MethodMissingFromADatasetIsAnError) {
  const DatasetDigest a = make_digest("a", {1, 0, 1, 0}, 0.0, 1, {}, {}, 0, 0);
  EXPECT_THROW(pool({a}, "robust", Targets{}), std::invalid_argument);
}

TEST(AllTargetChecks, ListsTheBlindBandAndVehicleTargetsToo) {
  const std::vector<TargetCheck> all = all_target_checks(Targets{});
  EXPECT_EQ(all.front().key, "accuracy");
  ASSERT_EQ(all.size(), check_targets(MethodSummary{}).size() + 3);
  EXPECT_EQ(all[all.size() - 3].key, "blind_zone_recall_tracked");
  EXPECT_EQ(all[all.size() - 2].key, "tracking_mota_vehicles");
  EXPECT_EQ(all.back().key, "tracking_idf1_vehicles");
}

class Manifest : public fmcw::test::TempDirTest {};

TEST_F(Manifest, QuotedCellsCrlfAndLookupByName) {
  const std::string file = write("manifest.csv",
                                 "name,layout,mean_speed_mps,route\r\n"
                                 "s1,junction,7.5,\"a, b\"\r\n"
                                 "\r\n"
                                 "s2,roundabout,3,\"say \"\"hi\"\"\nthere\"\r\n");
  const ScenarioManifest m = read_scenario_manifest(file);
  ASSERT_EQ(m.columns.size(), 4u);
  EXPECT_EQ(m.name_column, 0u);
  ASSERT_EQ(m.rows.size(), 2u);
  ASSERT_NE(m.find("s1"), nullptr);
  EXPECT_EQ((*m.find("s1"))[3], "a, b");
  EXPECT_EQ((*m.find("s2"))[3], "say \"hi\"\nthere");
  EXPECT_EQ(m.find("s3"), nullptr);
  EXPECT_EQ(m.column("mean_speed_mps"), 2);
  EXPECT_EQ(m.column("nope"), -1);
}

TEST_F(Manifest, ErrorsNameTheFileAndLine) {
  const auto message = [&](const std::string& text) {
    try {
      read_scenario_manifest(write("m.csv", text));
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("layout,speed\njunction,3\n").find("m.csv:1: no 'name' column"), std::string::npos);
  EXPECT_NE(message("name,layout\ns1,junction\ns2\n").find("m.csv:3: 1 cells, the header has 2"), std::string::npos);
  EXPECT_NE(message("name,layout\ns1,a\ns1,b\n").find("m.csv:3: name 's1' repeats line 2"), std::string::npos);
  EXPECT_NE(message("name,layout\ns1,\"open\n").find("m.csv:2: unterminated"), std::string::npos);
  EXPECT_NE(message("").find("m.csv:1: empty"), std::string::npos);
  EXPECT_THROW(read_scenario_manifest(path("missing.csv")), fmcw::core::FileError);  // a missing file is the file's fault
}

TEST(CsvTable, QuotedTextReadsBackAsWritten) {
  CsvTable t({"a", "b", "c"});
  t.add_quoted("plain").add_quoted("x, y").add_quoted("say \"hi\"").end_row();
  EXPECT_EQ(t.text(), "a,b,c\nplain,\"x, y\",\"say \"\"hi\"\"\"\n");
  const auto rows = parse_csv(t.text(), "t");
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[1], (std::vector<std::string>{"plain", "x, y", "say \"hi\""}));
}

}  // namespace
