// A dataset on disk, read and evaluated with fmcw::eval alone: this executable links no simulator
// (the CTest eval.links_without_simulator checks that neither Embree nor assimp is in it). The
// dataset is written here as `fmcw simulate` writes one, by fmcw::io: dataset.yaml from
// DatasetHeader, frames/NNNNNN.pcd, ego.csv and objects.csv.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>

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
  std::string write_dataset(int n, const io::DatasetHeader& header) const {
    const fs::path ds = dir_ / "ds";
    fs::create_directories(ds / "frames");
    std::string ego = io::kEgoCsvHeader, objects = io::kObjectsCsvHeader;
    for (int k = 0; k < n; ++k) {
      core::Frame f = test::synthetic_frame(static_cast<std::size_t>(k));
      f.scan.stamp_s = f.frame_truth->stamp_s;
      io::write_frame((ds / "frames" / io::frame_file_name(k)).string(), f);
      ego += io::ego_csv_row(static_cast<std::size_t>(k), *f.frame_truth);
      objects += io::objects_csv_rows(static_cast<std::size_t>(k), *f.frame_truth);
    }
    std::ofstream(ds / "ego.csv", std::ios::binary) << ego;
    std::ofstream(ds / "objects.csv", std::ios::binary) << objects;
    std::ofstream(ds / "dataset.yaml", std::ios::binary) << header.to_yaml();
    return ds.string();
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

}  // namespace
}  // namespace fmcw::eval
