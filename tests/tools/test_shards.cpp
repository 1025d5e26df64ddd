// fmcw simulate --shard I/N and fmcw merge: parts made apart join into the bytes of one run.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "support/cli.hpp"
#include "support/dataset_files.hpp"
#include "support/temp_dir.hpp"

namespace {

namespace fs = std::filesystem;
using fmcw::test::folder_bytes;
using fmcw::test::run_cli;
using fmcw::test::slurp;

class Shards : public fmcw::test::TempDirTest {
 protected:
  void SetUp() override {
    TempDirTest::SetUp();
    // 10 frames in 4 shards: 2, 3, 2 and 3 frames.
    scenario_ = write("small.yaml", fmcw::test::small_scenario_yaml(10));
  }
  void simulate(const std::string& extra) {
    const auto r = run_cli("simulate " + scenario_ + " " + extra);
    ASSERT_EQ(r.code, 0) << r.output;
  }
  std::string scenario_;
};

TEST_F(Shards, FourShardsMergedAreByteIdenticalToOneRun) {
  simulate("-o " + path("single"));
  for (int i = 0; i < 4; ++i) simulate("-o " + path("part" + std::to_string(i)) + " --shard " + std::to_string(i) + "/4");
  // Shard 1 holds frames 2, 3 and 4 under their dataset-wide names.
  EXPECT_EQ(slurp(dir_ / "part1" / "frames" / "000003.pcd"), slurp(dir_ / "single" / "frames" / "000003.pcd"));
  EXPECT_FALSE(fs::exists(dir_ / "part1" / "frames" / "000000.pcd"));
  EXPECT_NE(slurp(dir_ / "part1" / "dataset.yaml").find("shard: {index: 1, count: 4, first_frame: 2, end_frame: 5}"),
            std::string::npos);

  // Any order on the command line.
  const auto r = run_cli("merge " + path("part2") + " " + path("part0") + " " + path("part3") + " " + path("part1") + " -o " +
                         path("merged"));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("merged 4 shards into " + path("merged") + ": 10 frames"), std::string::npos) << r.output;
  const auto single = folder_bytes(dir_ / "single");
  EXPECT_EQ(single.size(), 13u);
  EXPECT_EQ(fmcw::test::first_difference(single, folder_bytes(dir_ / "merged")), "");

  // The merged dataset is a dataset like any other.
  const auto ev = run_cli("evaluate " + path("merged") + " -o " + path("report") + " --no-figures --methods fast");
  EXPECT_EQ(ev.code, 0) << ev.output;
}

TEST_F(Shards, MergeNamesTheShardThatIsMissingIncompleteOrForeign) {
  for (int i = 0; i < 3; ++i) simulate("-o " + path("p" + std::to_string(i)) + " --shard " + std::to_string(i) + "/3");
  auto r = run_cli("merge " + path("p0") + " " + path("p2") + " -o " + path("m"));
  EXPECT_EQ(r.code, fmcw::test::kExitUsage);
  EXPECT_NE(r.output.find("p2/dataset.yaml: is shard 2 where shard 1 was expected"), std::string::npos) << r.output;

  r = run_cli("merge " + path("p0") + " " + path("p1") + " " + path("p1") + " " + path("p2") + " -o " + path("m"));
  EXPECT_EQ(r.code, fmcw::test::kExitUsage);
  EXPECT_NE(r.output.find("is shard 1 where shard 2 was expected"), std::string::npos) << r.output;

  simulate("-o " + path("seed7") + " --shard 1/3 --seed 7");
  r = run_cli("merge " + path("p0") + " " + path("seed7") + " " + path("p2") + " -o " + path("m"));
  EXPECT_EQ(r.code, fmcw::test::kExitFile);
  EXPECT_NE(r.output.find("seed7/dataset.yaml: shard 1 comes from another scenario, options or fmcw version"),
            std::string::npos)
      << r.output;

  std::string yaml = slurp(dir_ / "p1" / "dataset.yaml");
  yaml.replace(yaml.find("complete: true"), 14, "complete: false");
  std::ofstream(dir_ / "p1" / "dataset.yaml", std::ios::binary) << yaml;
  r = run_cli("merge " + path("p0") + " " + path("p1") + " " + path("p2") + " -o " + path("m"));
  EXPECT_EQ(r.code, fmcw::test::kExitFile);
  EXPECT_NE(r.output.find("p1/dataset.yaml: shard 1 is incomplete"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir_ / "m" / "dataset.yaml")) << "a failed merge leaves no dataset";

  r = run_cli("evaluate " + path("p0") + " -o " + path("report") + " --no-figures");
  EXPECT_EQ(r.code, fmcw::test::kExitFile);
  EXPECT_NE(r.output.find("this is one shard of a dataset: join all shards with `fmcw merge` first"), std::string::npos)
      << r.output;

  r = run_cli("simulate " + scenario_ + " -o " + path("bad") + " --shard 3/3");
  EXPECT_EQ(r.code, fmcw::test::kExitUsage);
  EXPECT_NE(r.output.find("--shard '3/3': expected I/N with 0 <= I < N"), std::string::npos) << r.output;
}

TEST_F(Shards, MoreShardsThanFramesLeavesSomeEmptyAndStillMerges) {
  simulate("-o " + path("single") + " --frames 2");
  for (int i = 0; i < 3; ++i) {
    simulate("-o " + path("p" + std::to_string(i)) + " --frames 2 --shard " + std::to_string(i) + "/3");
  }
  ASSERT_EQ(run_cli("merge " + path("p0") + " " + path("p1") + " " + path("p2") + " -o " + path("m")).code, 0);
  EXPECT_EQ(fmcw::test::first_difference(folder_bytes(dir_ / "single"), folder_bytes(dir_ / "m")), "");
}

}  // namespace
