// The CLI with MCAP: a dataset exported with `fmcw export --to mcap` and processed with
// `fmcw process --format mcap` gives the results of processing its PCD frames; a process output
// exports with its labels and clusters; bad files end in one error line and exit code 3.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "fmcw/io/mcap_frames.hpp"
#include "fmcw/io/mcap_reader.hpp"
#include "support/cli.hpp"
#include "support/temp_dir.hpp"

namespace {

namespace fs = std::filesystem;
using fmcw::test::run_cli;

class CliMcap : public fmcw::test::TempDirTest {
 protected:
  // A three-frame dataset of a committed scenario.
  std::string dataset() {
    const std::string out = path("data");
    const auto r = run_cli("simulate " + std::string(FMCW_SOURCE_DIR) + "/scenarios/intersection.yaml -o " + out +
                           " --frames 3 --seed 2");
    EXPECT_EQ(r.code, 0) << r.output;
    return out;
  }
  // ego.csv without its source column (the second): what the method estimated, frame by frame.
  static std::vector<std::string> estimates(const fs::path& ego_csv) {
    std::ifstream in(ego_csv);
    std::vector<std::string> rows;
    for (std::string line; std::getline(in, line);) {
      const std::size_t a = line.find(','), b = line.find(',', a + 1);
      rows.push_back(line.substr(0, a) + line.substr(b));
    }
    return rows;
  }
};

TEST_F(CliMcap, ProcessingTheExportEqualsProcessingThePcdFrames) {
  const std::string data = dataset();
  const std::string file = path("seq.mcap");
  auto r = run_cli("export " + data + " -o " + file + " --to mcap");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("wrote " + file + ": 3 frames"), std::string::npos) << r.output;
  r = run_cli("process " + data + " -o " + path("from_pcd"));
  ASSERT_EQ(r.code, 0) << r.output;
  r = run_cli("process --format mcap " + file + " --topic /points -o " + path("from_mcap"));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("Doppler from field 'v' of /points"), std::string::npos) << r.output;
  const auto a = estimates(path("from_pcd") + "/ego.csv"), b = estimates(path("from_mcap") + "/ego.csv");
  ASSERT_EQ(a.size(), 4u);
  EXPECT_EQ(a, b);
  EXPECT_TRUE(fs::exists(path("from_mcap") + "/labels/seq_000002.pcd"));

  // The process output exports too: labels in the clouds, the clusters as markers.
  r = run_cli("export " + path("from_pcd") + " -o " + path("processed.mcap") + " --to mcap --compression none");
  ASSERT_EQ(r.code, 0) << r.output;
  fmcw::io::McapReader reader(path("processed.mcap"), "/markers/estimated");
  EXPECT_EQ(reader.size(), 3u);
  fmcw::io::McapFrames frames(path("processed.mcap"), fmcw::io::McapInputOptions{});
  ASSERT_EQ(frames.size(), 3u);
  EXPECT_NE(frames.cloud(0).find("label"), nullptr);
}

TEST_F(CliMcap, BadFilesEndInOneErrorLine) {
  const std::string data = dataset();
  const std::string file = path("seq.mcap");
  ASSERT_EQ(run_cli("export " + data + " -o " + file + " --to mcap").code, 0);
  const std::string bytes = fmcw::test::slurp(file);
  std::ofstream(path("cut.mcap"), std::ios::binary) << bytes.substr(0, bytes.size() - 100);
  auto r = run_cli("process --format mcap " + path("cut.mcap") + " -o " + path("out"));
  EXPECT_EQ(r.code, fmcw::test::kExitFile) << r.output;
  EXPECT_NE(r.output.find(path("cut.mcap") + ": offset "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("truncated"), std::string::npos) << r.output;
  EXPECT_EQ(fmcw::test::error_lines(r.output).size(), 1u) << r.output;
  EXPECT_FALSE(fs::exists(path("out")));
  r = run_cli("process --format mcap " + file + " --topic /lidar -o " + path("out"));
  EXPECT_EQ(r.code, fmcw::test::kExitFile) << r.output;
  EXPECT_NE(r.output.find("no channel on topic '/lidar'"), std::string::npos) << r.output;
  r = run_cli("process --format mcap " + file + " --doppler-field radial_vel -o " + path("out"));
  EXPECT_EQ(r.code, fmcw::test::kExitFile) << r.output;
  EXPECT_NE(r.output.find("missing field: no Doppler field 'radial_vel'"), std::string::npos) << r.output;
  r = run_cli("process --format mcap " + file + " --doppler-field speed -o " + path("out"));
  EXPECT_EQ(r.code, fmcw::test::kExitUsage) << r.output;
}

}  // namespace
