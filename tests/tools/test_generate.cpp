// fmcw generate and fmcw simulate of a generated set: the same seed gives the same files, the
// output folder is only replaced when generate wrote it, a set is split into tasks.

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

class Generate : public fmcw::test::TempDirTest {};

TEST_F(Generate, SameSeedSameBytesAndAManifestRowPerScenario) {
  auto r = run_cli("generate --count 6 --seed 5 -o " + path("a"));
  ASSERT_EQ(r.code, 0) << r.output;
  r = run_cli("generate --count 6 --seed 5 -o " + path("b"));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(folder_bytes(dir_ / "a" / "scenarios"), folder_bytes(dir_ / "b" / "scenarios"));
  EXPECT_EQ(slurp(dir_ / "a" / "manifest.csv"), slurp(dir_ / "b" / "manifest.csv"));
  const std::string manifest = slurp(dir_ / "a" / "manifest.csv");
  EXPECT_EQ(std::count(manifest.begin(), manifest.end(), '\n'), 7);
  EXPECT_EQ(manifest.find("true\n") != std::string::npos, true);
  EXPECT_EQ(manifest.find(",false\n"), std::string::npos) << manifest;  // clearance_ok on every row
  // Another seed, other files; the first three of a 3-scenario set are the same files.
  ASSERT_EQ(run_cli("generate --count 3 --seed 6 -o " + path("c")).code, 0);
  EXPECT_NE(slurp(dir_ / "a" / "scenarios" / "gen_00001.yaml"), slurp(dir_ / "c" / "scenarios" / "gen_00001.yaml"));
  ASSERT_EQ(run_cli("generate --count 3 --seed 5 -o " + path("d")).code, 0);
  EXPECT_EQ(slurp(dir_ / "a" / "scenarios" / "gen_00002.yaml"), slurp(dir_ / "d" / "scenarios" / "gen_00002.yaml"));
}

TEST_F(Generate, OverwriteReplacesOnlyASetItWrote) {
  ASSERT_EQ(run_cli("generate --count 2 -o " + path("set")).code, 0);
  auto r = run_cli("generate --count 2 -o " + path("set"));
  EXPECT_EQ(r.code, fmcw::test::kExitUsage);
  EXPECT_NE(r.output.find("not empty"), std::string::npos) << r.output;
  EXPECT_EQ(run_cli("generate --count 1 -o " + path("set") + " --overwrite").code, 0);
  EXPECT_FALSE(fs::exists(dir_ / "set" / "scenarios" / "gen_00001.yaml"));  // the old set is gone
  fs::create_directories(dir_ / "mine");
  std::ofstream(dir_ / "mine" / "notes.txt") << "keep me";
  r = run_cli("generate --count 1 -o " + path("mine") + " --overwrite");
  EXPECT_EQ(r.code, fmcw::test::kExitUsage);
  EXPECT_NE(r.output.find("not"), std::string::npos) << r.output;
  EXPECT_EQ(slurp(dir_ / "mine" / "notes.txt"), "keep me");
}

TEST_F(Generate, MalformedConfigIsOneErrorWithFileLineAndKey) {
  const std::string cfg = write("gen.yaml", "rigs: {" + std::string(FMCW_SOURCE_DIR) + "/configs/paper_rig.yaml: 1}\n"
                                            "assets: " + FMCW_SOURCE_DIR + "/assets\n"
                                            "materials: " + FMCW_SOURCE_DIR + "/assets/materials.yaml\n"
                                            "classes: " + FMCW_SOURCE_DIR + "/configs/classes.yaml\n"
                                            "traffic:\n  stop_wait_s: [4, -1]\n");
  const auto r = run_cli("generate " + cfg + " --count 2 -o " + path("set"));
  EXPECT_EQ(r.code, fmcw::test::kExitFile);
  EXPECT_NE(r.output.find("gen.yaml:6"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("traffic.stop_wait_s"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir_ / "set" / "manifest.csv"));
}

TEST_F(Generate, ASetSimulatesTaskByTaskIntoOneFolderPerScenario) {
  ASSERT_EQ(run_cli("generate --count 4 --seed 2 -o " + path("set")).code, 0);
  auto r = run_cli("simulate " + path("set") + " -o " + path("out") + " --frames 2 --task 1/2 --threads 1");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir_ / "out" / "gen_00001" / "dataset.yaml"));
  EXPECT_TRUE(fs::exists(dir_ / "out" / "gen_00003" / "frames" / "000001.pcd"));
  EXPECT_FALSE(fs::exists(dir_ / "out" / "gen_00000"));
  EXPECT_EQ(slurp(dir_ / "out" / "manifest.csv"), slurp(dir_ / "set" / "manifest.csv"));
  EXPECT_NE(slurp(dir_ / "out" / "gen_00003" / "dataset.yaml").find("complete: true"), std::string::npos);
  // The same scenario simulated on its own gives the same dataset.
  r = run_cli("simulate " + path("set/scenarios/gen_00003.yaml") + " -o " + path("alone") + " --frames 2 --threads 2");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(folder_bytes(dir_ / "alone" / "frames"), folder_bytes(dir_ / "out" / "gen_00003" / "frames"));
  EXPECT_EQ(slurp(dir_ / "alone" / "objects.csv"), slurp(dir_ / "out" / "gen_00003" / "objects.csv"));
  // --task belongs to sets, --shard to one scenario.
  r = run_cli("simulate " + path("set") + " -o " + path("out2") + " --shard 0/2");
  EXPECT_EQ(r.code, fmcw::test::kExitUsage);
  EXPECT_NE(r.output.find("--task"), std::string::npos) << r.output;
  r = run_cli("simulate " + path("set") + " -o " + path("out3") + " --task 2/2");
  EXPECT_EQ(r.code, fmcw::test::kExitUsage);
  EXPECT_NE(r.output.find("--task '2/2'"), std::string::npos) << r.output;
  fs::remove(dir_ / "set" / "manifest.csv");
  r = run_cli("simulate " + path("set") + " -o " + path("out4"));
  EXPECT_EQ(r.code, fmcw::test::kExitFile);
  EXPECT_NE(r.output.find("manifest.csv: no manifest here"), std::string::npos) << r.output;
}

}  // namespace
