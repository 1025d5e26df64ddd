// fmcw simulate stopped mid-run (SIGINT, SIGTERM, SIGKILL) and resumed gives the bytes of an
// uninterrupted run; what a stopped run leaves is whole frames and a dataset.yaml that counts them.

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include "fmcw/io/dataset_header.hpp"
#include "support/child_process.hpp"
#include "support/cli.hpp"
#include "support/dataset_files.hpp"
#include "support/temp_dir.hpp"

namespace {

namespace fs = std::filesystem;
using fmcw::test::Child;
using fmcw::test::folder_bytes;
using fmcw::test::wait_for;
using fmcw::test::run_cli;
using fmcw::test::slurp;

constexpr int kFrames = 60;

// frames_written in DIR/dataset.yaml, or -1 while there is none.
int frames_written(const fs::path& dir) {
  const std::string yaml = slurp(dir / "dataset.yaml");
  const std::size_t at = yaml.find("frames_written: ");
  return at == std::string::npos ? -1 : std::atoi(yaml.c_str() + at + 16);
}

class Resume : public fmcw::test::TempDirTest {
 protected:
  void SetUp() override {
    TempDirTest::SetUp();
    scenario_ = write("small.yaml", fmcw::test::small_scenario_yaml(kFrames));
  }
  std::vector<std::string> simulate_args(const std::string& out) const {
    return {"simulate", scenario_, "-o", path(out), "--threads", "2"};
  }
  // The uninterrupted run every stopped run is compared with.
  std::map<std::string, std::string> reference() {
    const auto r = run_cli("simulate " + scenario_ + " -o " + path("reference"));
    EXPECT_EQ(r.code, 0) << r.output;
    return folder_bytes(dir_ / "reference");
  }
  // Runs the simulator and sends sig once dataset.yaml counts at least 3 frames.
  Child run_and_stop(const std::string& out, int sig) {
    Child c = fmcw::test::start_cli(simulate_args(out), path(out + ".log"));
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(5);  // a bound, not a timing
    while (frames_written(dir_ / out) < 3 && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    ::kill(c.pid, sig);
    wait_for(c);
    return c;
  }
  std::string resume(const std::string& out) {
    std::string cmd;
    for (const auto& a : simulate_args(out)) cmd += a + " ";
    const auto r = run_cli(cmd + "--resume");
    EXPECT_EQ(r.code, 0) << r.output;
    return r.output;
  }
  std::string scenario_;
};

TEST_F(Resume, SigintLeavesWholeFramesCountedAndResumeGivesTheUninterruptedBytes) {
  const auto expected = reference();
  const Child c = run_and_stop("out", SIGINT);
  const std::string log = slurp(dir_ / "out.log");
  ASSERT_EQ(c.code, 128 + SIGINT) << log;
  EXPECT_NE(log.find("fmcw: interrupted by SIGINT: " + path("out") + " holds "), std::string::npos) << log;
  EXPECT_NE(log.find("continue with the same command and --resume"), std::string::npos) << log;

  // Only whole frames, exactly as many as dataset.yaml says, each the reference's bytes.
  const int n = frames_written(dir_ / "out");
  ASSERT_GE(n, 3);
  ASSERT_LT(n, kFrames);
  EXPECT_NE(slurp(dir_ / "out" / "dataset.yaml").find("complete: false"), std::string::npos);
  const auto partial = folder_bytes(dir_ / "out");
  int frame_files = 0;
  for (const auto& [name, bytes] : partial) {
    if (name.rfind("frames/", 0) != 0) continue;
    ++frame_files;
    EXPECT_EQ(bytes, expected.at(name)) << name;
  }
  EXPECT_EQ(frame_files, n);
  EXPECT_EQ(partial.size(), static_cast<std::size_t>(n) + 3) << "frames, ego.csv, objects.csv, dataset.yaml; no temporary";

  const std::string out = resume("out");
  EXPECT_NE(out.find("after the " + std::to_string(n) + " found there"), std::string::npos) << out;
  EXPECT_EQ(fmcw::test::first_difference(expected, folder_bytes(dir_ / "out")), "");
}

TEST_F(Resume, SigkillAtAnyPointIsRepairedByResume) {
  const auto expected = reference();
  const Child c = run_and_stop("out", SIGKILL);
  ASSERT_EQ(c.code, 128 + SIGKILL);
  const int n = frames_written(dir_ / "out");
  ASSERT_GE(n, 3);
  ASSERT_LT(n, kFrames);
  // Every frame dataset.yaml counts is whole; a frame or temporary file beyond them may be there.
  for (int k = 0; k < n; ++k) {
    const std::string name = "frames/" + fmcw::io::frame_file_name(k);
    EXPECT_EQ(slurp(dir_ / "out" / name), expected.at(name)) << name;
  }
  resume("out");
  EXPECT_EQ(fmcw::test::first_difference(expected, folder_bytes(dir_ / "out")), "");
}

TEST_F(Resume, SigtermStopsLikeSigint) {
  const Child c = run_and_stop("out", SIGTERM);
  ASSERT_EQ(c.code, 128 + SIGTERM) << slurp(dir_ / "out.log");
  EXPECT_NE(slurp(dir_ / "out.log").find("interrupted by SIGTERM"), std::string::npos);
}

TEST_F(Resume, ResumeRefusesOtherOptionsAndKnowsWhenItIsDone) {
  ASSERT_EQ(run_cli("simulate " + scenario_ + " -o " + path("out") + " --frames 4").code, 0);
  auto r = run_cli("simulate " + scenario_ + " -o " + path("out") + " --frames 4 --resume");
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("is complete already (4 frames)"), std::string::npos) << r.output;

  r = run_cli("simulate " + scenario_ + " -o " + path("out") + " --frames 4 --seed 6 --resume");
  EXPECT_EQ(r.code, fmcw::test::kExitUsage);
  EXPECT_NE(r.output.find("dataset.yaml: the dataset was started with another scenario or options, first difference at "
                          "scenario line"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("'seed: 5' in the dataset, 'seed: 6' now"), std::string::npos) << r.output;

  fs::create_directories(dir_ / "other");
  std::ofstream(dir_ / "other" / "notes.txt") << "x";
  r = run_cli("simulate " + scenario_ + " -o " + path("other") + " --resume");
  EXPECT_EQ(r.code, fmcw::test::kExitUsage);
  EXPECT_NE(r.output.find("cannot resume: '" + path("other") + "' holds no dataset.yaml"), std::string::npos) << r.output;

  // An incomplete dataset is refused by evaluation, with the way out.
  std::string yaml = slurp(dir_ / "out" / "dataset.yaml");
  yaml.replace(yaml.find("complete: true"), 14, "complete: false");
  std::ofstream(dir_ / "out" / "dataset.yaml", std::ios::binary) << yaml;
  r = run_cli("evaluate " + path("out") + " -o " + path("report") + " --no-figures");
  EXPECT_EQ(r.code, fmcw::test::kExitFile);
  EXPECT_NE(r.output.find("the dataset is incomplete (its writer stopped early): finish it with `fmcw simulate ... --resume`"),
            std::string::npos)
      << r.output;
}

}  // namespace
