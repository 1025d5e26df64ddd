// The fmcw CLI as a user drives it: exit codes, messages, files written.

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "support/cli.hpp"
#include "support/temp_dir.hpp"

namespace {

namespace fs = std::filesystem;

using fmcw::test::CliResult;
using fmcw::test::kExitFile;
using fmcw::test::kExitLimit;
using fmcw::test::kExitOther;
using fmcw::test::kExitUsage;
using fmcw::test::slurp;

CliResult run(const std::string& args) { return fmcw::test::run_cli(args); }

class Cli : public fmcw::test::TempDirTest {
 protected:
  std::string p(const std::string& name) const { return path(name); }
};

TEST_F(Cli, SynthThenProcessRecoversEgoAndWritesTables) {
  ASSERT_EQ(run("synth -o " + p("f.pcd") + " --objects 6 --noise-free").code, 0);
  for (const std::string method : {"fast", "paper"}) {
    const CliResult r = run("process " + p("f.pcd") + " -o " + p(method) + " --method " + method);
    ASSERT_EQ(r.code, 0) << r.output;
    for (const char* f : {"ego.csv", "objects.csv", "timing.csv", "results.json", "labels/f.pcd"}) {
      EXPECT_TRUE(fs::exists(dir_ / method / f)) << f;
    }
    // frame,source,method,status,static_pixels,clusters,vx,vy,vz,...
    const std::vector<std::string> cells = fmcw::test::csv_row(dir_ / method / "ego.csv");
    ASSERT_GE(cells.size(), 9u) << slurp(dir_ / method / "ego.csv");
    EXPECT_EQ(cells[2], method);
    EXPECT_EQ(cells[3], "ok");
    EXPECT_NEAR(std::stod(cells[6]), 10.0, 1e-5);
    EXPECT_NEAR(std::stod(cells[7]), 0.0, 1e-5);
    EXPECT_NEAR(std::stod(cells[8]), 0.0, 1e-5);
  }
}

TEST_F(Cli, SameInputGivesByteIdenticalTablesWithOneOrTwoThreads) {
  ASSERT_EQ(run("synth -o " + p("f.pcd") + " --objects 12").code, 0);
  ASSERT_EQ(run("process " + p("f.pcd") + " -o " + p("a") + " --method paper --threads 1").code, 0);
  ASSERT_EQ(run("process " + p("f.pcd") + " -o " + p("b") + " --method paper --threads 2").code, 0);
  for (const char* f : {"ego.csv", "objects.csv", "results.json", "labels/f.pcd"}) {
    EXPECT_EQ(slurp(dir_ / "a" / f), slurp(dir_ / "b" / f)) << f;
  }
}

TEST_F(Cli, DatasetFolderIsProcessedFrameByFrame) {
  fs::create_directories(dir_ / "ds" / "frames");
  ASSERT_EQ(run("synth -o " + p("ds/frames/000000.pcd") + " --objects 3 --seed 1").code, 0);
  ASSERT_EQ(run("synth -o " + p("ds/frames/000001.pcd") + " --objects 3 --seed 2").code, 0);
  const CliResult r = run("process " + p("ds") + " -o " + p("out"));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("[2/2]"), std::string::npos);
  std::istringstream ego(slurp(dir_ / "out" / "ego.csv"));
  int lines = 0;
  for (std::string l; std::getline(ego, l);) ++lines;
  EXPECT_EQ(lines, 3);
}

// The exit code says what kind of error stopped the command (README, "Exit codes"), and the
// error is one line on stderr, whatever its kind: 2 usage or bad input, 3 a bad file, 4 a
// resource limit, 1 anything else.
TEST_F(Cli, ExitCodeSaysWhatKindOfError) {
  const std::string scenario = std::string(FMCW_SOURCE_DIR) + "/scenarios/straight_road.yaml";
  const auto expect = [&](const std::string& args, int code, const std::string& message) {
    const CliResult r = run(args);
    EXPECT_EQ(r.code, code) << args << "\n" << r.output;
    EXPECT_EQ(fmcw::test::error_lines(r.output).size(), 1u) << args << "\n" << r.output;
    EXPECT_EQ(r.output.rfind("fmcw: error: ", 0), 0u) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(message), std::string::npos) << args << "\n" << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << args << "\n" << r.output;
  };
  // 2: what the command line parser refuses, and values the program refuses.
  expect("process " + p("f.pcd"), kExitUsage, "fmcw: error: --output is required (see fmcw process --help)");
  expect("process " + p("f.pcd") + " -o " + p("o") + " --no-such-option", kExitUsage, "--no-such-option");
  expect("", kExitUsage, "A subcommand is required (see fmcw --help)");
  expect("simulate " + scenario + " -o " + p("s") + " --shard 4/4", kExitUsage, "--shard '4/4': expected I/N with 0 <= I < N");
  // 3: a file that is missing, or holds what it may not.
  expect("process " + p("nope.pcd") + " -o " + p("o"), kExitFile, "input '" + p("nope.pcd") + "' does not exist");
  std::ofstream(p("bad.yaml")) << "name: x\nframes: 2\nrig:\n  heads:\n    - {name: a, rate_hz: -10}\n";
  expect("simulate " + p("bad.yaml") + " -o " + p("s"), kExitFile, "bad.yaml:5: rig.heads[0]: head 'a': rate must be > 0 Hz");
  // 4: a resource limit.
  expect("simulate " + scenario + " -o " + p("s") + " --max-memory 1", kExitLimit, "over the memory budget of 1 MB");
  expect("simulate " + scenario + " -o " + p("s") + " --threads 1000", kExitLimit, "num_threads (--threads) must be in [0, 256]");
  // 1: anything else, here a frame the method cannot estimate.
  std::ofstream(p("empty.pcd")) << "VERSION 0.7\nFIELDS x y z v\nSIZE 4 4 4 4\nTYPE F F F F\nWIDTH 2\nHEIGHT 2\n"
                                << "POINTS 4\nDATA ascii\nnan nan nan nan\nnan nan nan nan\nnan nan nan nan\nnan nan nan nan\n";
  expect("process " + p("empty.pcd") + " -o " + p("o"), kExitOther, "empty.pcd: scan has no valid pixels");
  EXPECT_FALSE(fs::exists(dir_ / "s" / "dataset.yaml"));
  EXPECT_FALSE(fs::exists(dir_ / "o" / "ego.csv"));
  // --help lists the codes and succeeds.
  const CliResult help = run("--help");
  EXPECT_EQ(help.code, 0) << help.output;
  EXPECT_NE(help.output.find("Exit codes: 0 success; 1 any other failure"), std::string::npos) << help.output;
  EXPECT_EQ(run("process --help").code, 0);
}

TEST_F(Cli, BadInputGivesOneClearLineAndNonZeroExit) {
  CliResult r = run("process " + p("nope.pcd") + " -o " + p("out"));
  EXPECT_EQ(r.code, kExitFile);
  EXPECT_EQ(r.output, "fmcw: error: input '" + p("nope.pcd") + "' does not exist\n");

  std::ofstream(p("trunc.pcd"), std::ios::binary)
      << "VERSION 0.7\nFIELDS x y z v\nSIZE 4 4 4 4\nTYPE F F F F\nWIDTH 4\nHEIGHT 2\nPOINTS 8\nDATA binary\n"
      << std::string(10, '\0');
  r = run("process " + p("trunc.pcd") + " -o " + p("out"));
  EXPECT_EQ(r.code, kExitFile);
  EXPECT_NE(r.output.find("trunc.pcd: truncated PCD"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir_ / "out" / "ego.csv")) << "no half-written tables";

  // A scan with returns but all of them far apart in Doppler: no static region of 3 points.
  std::ofstream(p("nostatic.pcd"))
      << "VERSION 0.7\nFIELDS x y z v\nSIZE 4 4 4 4\nTYPE F F F F\nWIDTH 2\nHEIGHT 2\nPOINTS 4\nDATA ascii\n"
      << "5 0 0 1\n5 1 0 3\n5 0 1 5\n5 1 1 7\n";
  r = run("process " + p("nostatic.pcd") + " -o " + p("out2"));
  EXPECT_EQ(r.code, kExitOther);
  EXPECT_NE(r.output.find("nostatic.pcd: ego velocity not estimable:"), std::string::npos) << r.output;
  r = run("process " + p("nostatic.pcd") + " -o " + p("out2b") + " --method fast");
  EXPECT_EQ(r.code, kExitOther);
  EXPECT_NE(r.output.find("nostatic.pcd: ego velocity not estimable: 1 static points"), std::string::npos) << r.output;

  std::ofstream(p("empty.pcd")) << "VERSION 0.7\nFIELDS x y z v\nSIZE 4 4 4 4\nTYPE F F F F\nWIDTH 2\nHEIGHT 2\n"
                                << "POINTS 4\nDATA ascii\nnan nan nan nan\nnan nan nan nan\nnan nan nan nan\nnan nan nan nan\n";
  r = run("process " + p("empty.pcd") + " -o " + p("out3"));
  EXPECT_EQ(r.code, kExitOther);
  EXPECT_NE(r.output.find("empty.pcd: scan has no valid pixels"), std::string::npos) << r.output;

  r = run("process " + p("empty.pcd") + " -o " + p("out4") + " --method magic");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.output.find("magic"), std::string::npos) << r.output;
}

TEST_F(Cli, AFrameThatFailsLeavesNoOutputBehind) {
  // A dataset folder whose second frame has no valid pixel: the run stops there with its error,
  // and the first frame's labelled cloud, written before, is gone with the folders made for it.
  fs::create_directories(dir_ / "ds" / "frames");
  ASSERT_EQ(run("synth -o " + p("ds/frames/000000.pcd") + " --objects 3 --seed 1").code, 0);
  {
    // The first frame's rig (its head comments, 600 x 150) without a return.
    std::ofstream second(p("ds/frames/000001.pcd"));
    std::istringstream first(slurp(dir_ / "ds" / "frames" / "000000.pcd"));
    for (std::string line; std::getline(first, line) && line.rfind("VERSION", 0) != 0;) {
      if (line.rfind("# fmcw_", 0) == 0) second << line << "\n";
    }
    second << "VERSION 0.7\nFIELDS x y z v\nSIZE 4 4 4 4\nTYPE F F F F\nWIDTH 600\nHEIGHT 150\nPOINTS 90000\n"
           << "DATA ascii\n";
    for (int i = 0; i < 90000; ++i) second << "nan nan nan nan\n";
  }
  CliResult r = run("process " + p("ds") + " -o " + p("out"));
  EXPECT_EQ(r.code, kExitOther);
  EXPECT_NE(r.output.find("000001.pcd: scan has no valid pixels"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir_ / "out")) << "the folder the run made is removed";
  // Into a folder that holds other files already: those stay, nothing of the run does.
  fs::create_directories(dir_ / "mine");
  std::ofstream(p("mine/notes.txt")) << "keep\n";
  r = run("process " + p("ds") + " -o " + p("mine"));
  EXPECT_EQ(r.code, kExitOther);
  EXPECT_EQ(slurp(dir_ / "mine" / "notes.txt"), "keep\n");
  std::vector<std::string> left;
  for (const auto& e : fs::recursive_directory_iterator(dir_ / "mine")) left.push_back(e.path().filename().string());
  EXPECT_EQ(left, std::vector<std::string>{"notes.txt"});
  // Control: the first frame alone goes through and leaves its labelled cloud.
  fs::remove(dir_ / "ds" / "frames" / "000001.pcd");
  r = run("process " + p("ds") + " -o " + p("out"));
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir_ / "out" / "labels" / "000000.pcd"));
}

TEST_F(Cli, BenchJsonNamesBothMethodsWithPointsPerSecond) {
  const CliResult r = run("bench --json --objects 4 --repeats 2");
  ASSERT_EQ(r.code, 0) << r.output;
  for (const char* key : {"\"fast\"", "\"paper\"", "\"robust\"", "\"points_per_s\"", "\"ms_per_frame\"", "\"rays_per_s\""}) {
    EXPECT_NE(r.output.find(key), std::string::npos) << key;
  }
}

TEST_F(Cli, SimulateWritesACompleteDatasetIdenticalForAnyThreadCount) {
  const std::string scenario = std::string(FMCW_SOURCE_DIR) + "/scenarios/intersection.yaml";
  CliResult a = run("simulate " + scenario + " -o " + p("one") + " --frames 3 --threads 1 --seed 9");
  ASSERT_EQ(a.code, 0) << a.output;
  CliResult b = run("simulate " + scenario + " -o " + p("two") + " --frames 3 --threads 2 --seed 9");
  ASSERT_EQ(b.code, 0) << b.output;
  for (const char* f : {"dataset.yaml", "ego.csv", "objects.csv", "frames/000000.pcd", "frames/000002.pcd"}) {
    ASSERT_TRUE(fs::exists(dir_ / "one" / f)) << f;
    EXPECT_EQ(slurp(dir_ / "one" / f), slurp(dir_ / "two" / f)) << f;
  }
  EXPECT_FALSE(fs::exists(dir_ / "one" / "frames" / "000003.pcd"));
  const std::string yaml = slurp(dir_ / "one" / "dataset.yaml");
  EXPECT_NE(yaml.find("frames_written: 3"), std::string::npos);
  EXPECT_NE(yaml.find("seed: 9"), std::string::npos);
  // Another seed changes the noise.
  ASSERT_EQ(run("simulate " + scenario + " -o " + p("other") + " --frames 1 --seed 10").code, 0);
  EXPECT_NE(slurp(dir_ / "one" / "frames/000000.pcd"), slurp(dir_ / "other" / "frames/000000.pcd"));
  // The dataset feeds straight into process.
  CliResult r = run("process " + p("one") + " -o " + p("processed"));
  EXPECT_EQ(r.code, 0) << r.output;
}

TEST_F(Cli, SimulateRejectsBadScenariosAndOccupiedFolders) {
  std::ofstream(p("bad.yaml")) << "name: x\nframes: 2\nrig:\n  heads:\n    - {name: a, rate_hz: -10}\n";
  CliResult r = run("simulate " + p("bad.yaml") + " -o " + p("out"));
  EXPECT_EQ(r.code, kExitFile);
  EXPECT_NE(r.output.find("bad.yaml:5: rig.heads[0]: head 'a': rate must be > 0 Hz, got -10"), std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(dir_ / "out")) << "nothing is written for a bad scenario";

  std::ofstream(p("typo.yaml")) << "name: x\nframs: 2\n";
  r = run("simulate " + p("typo.yaml") + " -o " + p("out"));
  EXPECT_EQ(r.code, kExitFile);
  EXPECT_NE(r.output.find("typo.yaml:2: unknown key 'frams'"), std::string::npos) << r.output;

  fs::create_directories(dir_ / "full");
  std::ofstream(dir_ / "full" / "keep.txt") << "x";
  std::ofstream(p("ok.yaml")) << "frames: 1\n";
  r = run("simulate " + p("ok.yaml") + " -o " + p("full"));
  EXPECT_EQ(r.code, kExitUsage);
  EXPECT_NE(r.output.find("exists and is not empty"), std::string::npos) << r.output;
}

TEST_F(Cli, ClipsThatDoNotPlayAreSaidOnceAndABadClipStopsTheRun) {
  // Two statues of the skinned walker (animate: false) and one walking: one note for the file.
  const std::string walker = std::string(FMCW_SOURCE_DIR) + "/assets/walker_skinned.gltf";
  std::ofstream(p("s.yaml")) << "frames: 1\nactors:\n"
                             << "  - {id: 1, class: pedestrian, mesh: " << walker << ", animate: false, trajectory: {type: static, pose: {x: 8}}}\n"
                             << "  - {id: 2, class: pedestrian, mesh: " << walker << ", animate: false, trajectory: {type: static, pose: {x: 9}}}\n"
                             << "  - {id: 3, class: pedestrian, mesh: " << walker << ", trajectory: {type: static, pose: {x: 10}}}\n";
  CliResult r = run("simulate " + p("s.yaml") + " -o " + p("out"));
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string note = "fmcw: note: " + p("s.yaml") + ":3: actors[0]: mesh '" + walker +
                           "' has clip(s) 'walk', 'idle', not played: the actor has animate: false";
  EXPECT_NE(r.output.find(note), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("fmcw: note:"), r.output.rfind("fmcw: note:")) << "said once: " << r.output;
  // The dataset records what plays.
  EXPECT_NE(slurp(dir_ / "out" / "dataset.yaml").find("animation: {clip: walk, speed: 1, loop: true"), std::string::npos);
  // An unknown clip: one line naming the file, the key and the clips there are; nothing written.
  std::ofstream(p("bad.yaml")) << "frames: 1\nactors:\n  - {id: 1, class: pedestrian, mesh: " << walker
                               << ", animation: {clip: run}, trajectory: {type: static}}\n";
  r = run("simulate " + p("bad.yaml") + " -o " + p("bad"));
  EXPECT_EQ(r.code, kExitFile);
  EXPECT_NE(r.output.find("bad.yaml:3: actors[0]: animation.clip: mesh '" + walker + "' has no clip 'run'; its clips: 'walk', 'idle'"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(dir_ / "bad"));
}

}  // namespace
