// A dataset on disk, read and evaluated with fmcw::eval alone: this executable links no simulator
// (the CTest eval.links_without_simulator checks that neither Embree nor assimp is in it). The
// dataset is written here as `fmcw simulate` writes one, by fmcw::io: dataset.yaml from
// DatasetHeader, frames/NNNNNN.pcd, ego.csv and objects.csv.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "fmcw/core/ego_motion.hpp"
#include "fmcw/core/errors.hpp"
#include "fmcw/eval/evaluator.hpp"
#include "fmcw/io/dataset_header.hpp"
#include "fmcw/io/pcd.hpp"
#include "fmcw/io/truth_tables.hpp"
#include "support/synthetic_source.hpp"
#include "support/temp_dir.hpp"

namespace fmcw::eval {
namespace {

namespace fs = std::filesystem;

class DatasetOnDisk : public test::TempDirTest {
 protected:
  // Frames 0..n-1 of test::synthetic_frame as the dataset DIR/ds; returns DIR/ds.
  // compensated: its velocities ego-compensated, as a dataset of measurement.velocity_frame:
  // ego_compensated holds them (the truth's radial velocity too).
  std::string write_dataset(int n, const io::DatasetHeader& header, bool compensated = false,
                            const std::string& name = "ds") const {
    const fs::path ds = dir_ / name;
    fs::create_directories(ds / "frames");
    std::string ego = io::kEgoCsvHeader, objects = io::kObjectsCsvHeader;
    for (int k = 0; k < n; ++k) {
      core::Frame f = test::synthetic_frame(static_cast<std::size_t>(k));
      f.scan.stamp_s = f.frame_truth->stamp_s;
      if (compensated) compensate(f);
      io::write_frame((ds / "frames" / io::frame_file_name(k)).string(), f);
      ego += io::ego_csv_row(static_cast<std::size_t>(k), *f.frame_truth);
      objects += io::objects_csv_rows(static_cast<std::size_t>(k), *f.frame_truth);
    }
    std::ofstream(ds / "ego.csv", std::ios::binary) << ego;
    std::ofstream(ds / "objects.csv", std::ios::binary) << objects;
    std::ofstream(ds / "dataset.yaml", std::ios::binary) << header.to_yaml();
    return ds.string();
  }
  static void compensate(core::Frame& f) {
    const core::EgoMotion ego{f.frame_truth->ego.velocity_mps,
                              f.frame_truth->ego.angular_velocity_rps};
    core::compensate_ego_velocity(f.scan, ego);
    for (const core::HeadInfo& head : f.scan.heads) {
      const Eigen::Vector3d v_origin = ego.point_velocity_mps(head.origin_m());
      for (int r = 0; r < f.scan.rows; ++r) {
        for (int c = head.col_begin; c < head.col_end; ++c) {
          const std::size_t i = f.scan.index(r, c);
          if (!f.scan.valid[i]) continue;
          const Eigen::Vector3d e = (f.scan.position(i) - head.origin_m()).normalized();
          f.truth->radial_velocity_mps[i] =
              static_cast<float>(f.truth->radial_velocity_mps[i] + e.dot(v_origin));
        }
      }
    }
  }
  static io::DatasetHeader complete_header(int frames) {
    io::DatasetHeader h;
    h.tool_version = "test";
    h.complete = true;
    h.frames_written = frames;
    h.scenario_yaml = "name: synthetic\nrate_hz: 10\nseed: 7\n";
    return h;
  }
  // The message of the error DatasetSource(dir) throws, or "" when it throws none.
  static std::string open_error(const std::string& dir) {
    try {
      DatasetSource source(dir);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "";
  }
};

TEST_F(DatasetOnDisk, IsReadAndEvaluatedExactly) {
  const std::string ds = write_dataset(3, complete_header(3));
  DatasetSource source(ds);
  ASSERT_EQ(source.size(), 3u);
  EXPECT_EQ(source.info().scenario, "synthetic");
  EXPECT_EQ(source.info().rate_hz, 10.0);
  EXPECT_EQ(source.info().seed, 7u);
  EXPECT_EQ(source.info().config_yaml, "name: synthetic\nrate_hz: 10\nseed: 7");
  EXPECT_EQ(source.describe(2), (fs::path(ds) / "frames" / "000002.pcd").string());

  EvaluationParams params;
  params.methods = {"fast"};
  const EvaluationResult r = evaluate(source, params);
  ASSERT_EQ(r.methods, (std::vector<std::string>{"paper", "fast"}));
  EXPECT_EQ(r.dataset.frames, 3);
  EXPECT_EQ(r.dataset.actors_seen, 1);
  for (const MethodSummary& s : r.summaries) {
    EXPECT_DOUBLE_EQ(s.motion.accuracy(), 1.0);
    EXPECT_LT(s.ego_max_abs_mps.maxCoeff(), 1e-4);
    EXPECT_EQ(s.objects_evaluated, 3);
    EXPECT_LT(s.median_error_mps, 1e-3);
  }
}

TEST_F(DatasetOnDisk, HeaderThatDoesNotMatchTheFolderIsNamed) {
  io::DatasetHeader h = complete_header(2);
  h.complete = false;
  std::string ds = write_dataset(2, h);
  EXPECT_NE(open_error(ds).find(ds + "/dataset.yaml: complete: false: the dataset is incomplete"), std::string::npos)
      << open_error(ds);

  h = complete_header(3);
  fs::remove_all(ds);
  ds = write_dataset(2, h);
  EXPECT_NE(open_error(ds).find(ds + "/dataset.yaml: frames_written: says 3 frames, but " + ds + "/frames holds 2"),
            std::string::npos)
      << open_error(ds);

  h.shard = io::ShardInfo::of(1, 2, 4);
  h.frames_written = 2;
  fs::remove_all(ds);
  ds = write_dataset(2, h);
  EXPECT_NE(open_error(ds).find("this is one shard of a dataset: join all shards with `fmcw merge` first"), std::string::npos)
      << open_error(ds);

  fs::remove_all(ds);
  ds = write_dataset(3, complete_header(3));
  fs::remove(fs::path(ds) / "frames" / "000001.pcd");
  EXPECT_NE(open_error(ds).find(ds + "/frames/000001.pcd: missing (found '000002.pcd'"), std::string::npos)
      << open_error(ds);
}

TEST_F(DatasetOnDisk, EgoCompensatedFramesAreEvaluatedBackInTheSensorFrame) {
  // As a real dataset with its poses is (AevaScenesSource): the dataset's own ego motion undoes
  // the compensation, so that the ego velocity is measured and tracks are carried with the rig.
  const std::string raw_ds = write_dataset(4, complete_header(4), false, "raw");
  const std::string comp_ds = write_dataset(4, complete_header(4), true, "comp");
  DatasetSource raw(raw_ds), comp(comp_ds);
  for (std::size_t k = 0; k < 4; ++k) {
    const core::Frame r = raw.frame(k), c = comp.frame(k);
    EXPECT_EQ(c.scan.velocity_frame, core::VelocityFrame::kSensor);
    double worst = 0.0, worst_truth = 0.0;
    std::size_t moving_static = 0;
    for (std::size_t i = 0; i < r.scan.size(); ++i) {
      if (!r.scan.valid[i]) continue;
      worst = std::max(worst, static_cast<double>(std::abs(c.scan.radial_velocity_mps[i] -
                                                           r.scan.radial_velocity_mps[i])));
      worst_truth =
          std::max(worst_truth, static_cast<double>(std::abs(c.truth->radial_velocity_mps[i] -
                                                             r.truth->radial_velocity_mps[i])));
      moving_static +=
          r.truth->instance[i] == 0 && std::abs(r.scan.radial_velocity_mps[i]) > 1.0 ? 1 : 0;
    }
    EXPECT_GT(moving_static,
              1000u);  // the raw static world reads the ego's 8 m/s: no test of 0 against 0
    EXPECT_LT(worst, 1e-4) << "frame " << k;
    EXPECT_LT(worst_truth, 1e-4) << "frame " << k;
  }
  EvaluationParams params;
  params.methods = {"tracked"};
  const EvaluationResult er = evaluate(raw, params), ec = evaluate(comp, params);
  ASSERT_EQ(er.summaries.size(), ec.summaries.size());
  for (std::size_t m = 0; m < er.summaries.size(); ++m) {
    const MethodSummary &a = er.summaries[m], &b = ec.summaries[m];
    EXPECT_LT(b.ego_max_abs_mps.maxCoeff(), 1e-3) << m;
    EXPECT_EQ(a.objects_evaluated, b.objects_evaluated) << m;
    EXPECT_NEAR(a.motion.accuracy(), b.motion.accuracy(), 1e-9) << m;
    EXPECT_NEAR(a.median_error_mps, b.median_error_mps, 1e-3) << m;
  }
  // An ego velocity that is not finite cannot undo the compensation: named, file and frame.
  const fs::path ego_csv = fs::path(comp_ds) / "ego.csv";
  std::ifstream in(ego_csv, std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  const std::size_t row = text.find("\n2,");
  ASSERT_NE(row, std::string::npos);
  const std::size_t end = text.find('\n', row + 1);
  std::vector<std::string> fields;
  std::stringstream line(text.substr(row + 1, end - row - 1));
  for (std::string field; std::getline(line, field, ',');) fields.push_back(field);
  ASSERT_GT(fields.size(), 9u);
  fields[9] = "nan";  // vx_mps
  std::string joined;
  for (std::size_t n = 0; n < fields.size(); ++n) joined += (n ? "," : "") + fields[n];
  text.replace(row + 1, end - row - 1, joined);
  std::ofstream(ego_csv, std::ios::binary) << text;
  try {
    DatasetSource bad(comp_ds);
    bad.frame(2);
    FAIL() << "a NaN ego velocity undid the compensation";
  } catch (const core::FileError& e) {
    EXPECT_NE(
        std::string(e.what()).find(ego_csv.string() + ": frame 2: the ego velocity is not finite"),
        std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace fmcw::eval
