// Data safety and limits (the second reliability round): no command destroys its input, one
// writer per dataset, CSV cells that stay cells, resume that checks what it keeps, and inputs
// beyond what the simulator can do refused at load with the file and key, before any
// allocation and before any file is written.

#include <gtest/gtest.h>
#include <sys/resource.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include "support/child_process.hpp"
#include "support/cli.hpp"
#include "support/dataset_files.hpp"
#include "support/temp_dir.hpp"

namespace {

namespace fs = std::filesystem;
using fmcw::test::folder_bytes;
using fmcw::test::run_cli;
using fmcw::test::slurp;

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Peak resident memory [kB] of `fmcw ARGS` run in a fresh child (so that no earlier command of
// this test program counts), and its result.
std::pair<long, fmcw::test::CliResult> run_measured(const std::string& args, const fs::path& log) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    const fmcw::test::CliResult r = run_cli(args);
    rusage usage{};
    ::getrusage(RUSAGE_CHILDREN, &usage);
    std::ofstream(log, std::ios::binary) << usage.ru_maxrss << "\n" << r.code << "\n" << r.output;
    ::_exit(0);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  std::istringstream in(slurp(log));
  long kb = -1;
  fmcw::test::CliResult r;
  in >> kb >> r.code;
  r.output = std::string(std::istreambuf_iterator<char>(in), {});
  return {kb, r};
}

class DataSafety : public fmcw::test::TempDirTest {
 protected:
  void SetUp() override {
    TempDirTest::SetUp();
    scenario_ = write("small.yaml", fmcw::test::small_scenario_yaml(6));
  }
  void simulate(const std::string& extra) {
    const auto r = run_cli("simulate " + scenario_ + " " + extra);
    ASSERT_EQ(r.code, 0) << r.output;
  }
  // A scenario: the small one with its first line after `name: small` replaced by lines.
  std::string scenario_with(const std::string& name, const std::string& from, const std::string& to) {
    std::string yaml = fmcw::test::small_scenario_yaml(3);
    const std::size_t at = yaml.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    yaml.replace(at, from.size(), to);
    return write(name, yaml);
  }
  // Expects `fmcw simulate FILE -o OUT` to fail with the exit code of a bad file (or code) and a
  // message holding part, and to leave no output folder.
  void expect_refused(const std::string& file, const std::string& part, const std::string& extra = "",
                      int code = fmcw::test::kExitFile) {
    const auto r = run_cli("simulate " + file + " -o " + path("refused") + " " + extra);
    EXPECT_EQ(r.code, code) << r.output;
    EXPECT_TRUE(has(r.output, part)) << r.output;
    EXPECT_EQ(fmcw::test::error_lines(r.output).size(), 1u) << r.output;
    EXPECT_FALSE(fs::exists(path("refused"))) << r.output;
  }
  std::string scenario_;
};

// Case 1: merge A B -o A --overwrite deleted A's dataset.yaml and frames before it failed.
TEST_F(DataSafety, MergeNeverWritesOverOrInsideOneOfItsShards) {
  simulate("-o " + path("a") + " --shard 0/2");
  simulate("-o " + path("b") + " --shard 1/2");
  const auto a = folder_bytes(dir_ / "a");
  auto r = run_cli("merge " + path("a") + " " + path("b") + " -o " + path("a") + " --overwrite");
  EXPECT_EQ(r.code, fmcw::test::kExitUsage) << r.output;
  EXPECT_TRUE(has(r.output, "fmcw: error: output '" + path("a") + "' is the input '" + path("a") +
                                "': writing there could replace the input")) << r.output;
  r = run_cli("merge " + path("a") + " " + path("b") + " -o " + path("b") + "/merged");
  EXPECT_EQ(r.code, fmcw::test::kExitUsage) << r.output;
  EXPECT_TRUE(has(r.output, "lies inside the input '" + path("b") + "'")) << r.output;
  EXPECT_EQ(fmcw::test::first_difference(a, folder_bytes(dir_ / "a")), "");

  // --overwrite replaces a dataset, not a folder of other files.
  fs::create_directories(dir_ / "notes");
  std::ofstream(dir_ / "notes" / "keep.txt") << "mine";
  r = run_cli("merge " + path("a") + " " + path("b") + " -o " + path("notes") + " --overwrite");
  EXPECT_EQ(r.code, fmcw::test::kExitUsage) << r.output;
  EXPECT_TRUE(has(r.output, "holds no dataset.yaml or frames/: --overwrite replaces only a dataset (or what a stopped merge left)")) << r.output;
  EXPECT_EQ(slurp(dir_ / "notes" / "keep.txt"), "mine");
  r = run_cli("simulate " + scenario_ + " -o " + path("notes") + " --overwrite");
  EXPECT_EQ(r.code, fmcw::test::kExitUsage) << r.output;
  EXPECT_TRUE(has(r.output, "holds no dataset.yaml or frames/: --overwrite replaces only a dataset that fmcw writes"))
      << r.output;
  EXPECT_EQ(slurp(dir_ / "notes" / "keep.txt"), "mine");
  EXPECT_FALSE(fs::exists(dir_ / "notes" / "frames"));

  // The merge that is allowed still works, and leaves no lock behind.
  r = run_cli("merge " + path("a") + " " + path("b") + " -o " + path("merged"));
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_FALSE(fs::exists(dir_ / "merged" / ".fmcw.lock"));
}

// Case 5: export --to pcd into the input's own frames/ overwrote the inputs.
TEST_F(DataSafety, ExportAndProcessNeverWriteIntoTheirInput) {
  simulate("-o " + path("data"));
  const auto before = folder_bytes(dir_ / "data");
  auto r = run_cli("export " + path("data") + " -o " + path("data") + "/frames --to pcd");
  EXPECT_EQ(r.code, fmcw::test::kExitUsage) << r.output;
  EXPECT_TRUE(has(r.output, "output '" + path("data") + "/frames' lies inside the input '" + path("data") + "'"))
      << r.output;
  r = run_cli("export " + path("data") + "/frames/000001.pcd -o " + path("data") + "/frames --to pcd");
  EXPECT_EQ(r.code, fmcw::test::kExitUsage) << r.output;
  EXPECT_TRUE(has(r.output, "is the input file's folder")) << r.output;
  r = run_cli("process " + path("data") + " -o " + path("data"));
  EXPECT_EQ(r.code, fmcw::test::kExitUsage) << r.output;
  EXPECT_TRUE(has(r.output, "output '" + path("data") + "' is the input")) << r.output;
  EXPECT_EQ(fmcw::test::first_difference(before, folder_bytes(dir_ / "data")), "");
}

// Case 2: two writers into one folder both exited 0 and the frames were interleaved.
TEST_F(DataSafety, TwoWritersIntoOneFolderOneFailsAtOnceAndTheDatasetIsALoneRunsBytes) {
  const std::string long_run = write("long.yaml", fmcw::test::small_scenario_yaml(300));
  ASSERT_EQ(run_cli("simulate " + long_run + " -o " + path("lone") + " --threads 1").code, 0);
  fmcw::test::Child first =
      fmcw::test::start_cli({"simulate", long_run, "-o", path("shared"), "--threads", "1"}, path("first.log"));
  // The first holds the lock once its dataset.yaml is there (a bound, not a timing).
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(2);
  while (!fs::exists(dir_ / "shared" / "dataset.yaml") && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  const auto second = run_cli("simulate " + long_run + " -o " + path("shared") + " --overwrite --seed 9 --threads 1");
  fmcw::test::wait_for(first);
  EXPECT_EQ(first.code, 0) << slurp(dir_ / "first.log");
  EXPECT_EQ(second.code, 1) << second.output;
  EXPECT_TRUE(has(second.output, "fmcw: error: '" + path("shared") + "' is being written by another fmcw process (pid " +
                                     std::to_string(first.pid) + ")")) << second.output;
  EXPECT_EQ(fmcw::test::first_difference(folder_bytes(dir_ / "lone"), folder_bytes(dir_ / "shared")), "");
}

// Case 3: a class named with a comma gave a dataset that evaluate and export then rejected.
TEST_F(DataSafety, ClassNamesThatWouldBreakACsvCellAreRefusedAndPathsAreQuoted) {
  for (const auto& [name, what] : std::vector<std::pair<std::string, std::string>>{
           {"\"fork,lift\"", "holds a comma"}, {"'say \"hi\"'", "holds a double quote"}, {"\"fork\\nlift\"", "holds a control character"}}) {
    const std::string table = write("classes.yaml", "classes: {" + name + ": 300}\n");
    const std::string file = scenario_with("c.yaml", "name: small\n", "name: small\nclasses: " + table + "\n");
    expect_refused(file, what);
    expect_refused(file, table + ":1: classes.");
  }
  // A text cell the project writes from a path (process's ego.csv names each frame's file).
  simulate("-o " + path("data") + " --frames 1");
  fs::create_directories(dir_ / "in,put \"x\"");
  fs::copy_file(dir_ / "data" / "frames" / "000000.pcd", dir_ / "in,put \"x\"" / "000000.pcd");
  const auto r = run_cli("process '" + path("in,put \"x\"") + "/000000.pcd' -o " + path("out") + " --no-clouds");
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string ego = slurp(dir_ / "out" / "ego.csv");
  EXPECT_TRUE(has(ego, "\n0,\"" + path("in,put \"\"x\"\"") + "/000000.pcd\",")) << ego;  // RFC 4180
}

// Case 4: --resume trusted a counted frame cut to 1,000 bytes and called the dataset complete.
TEST_F(DataSafety, ResumeReadsEveryKeptFrameAndSimulatesABadOneAgain) {
  simulate("-o " + path("reference"));
  simulate("-o " + path("out"));
  fs::resize_file(dir_ / "out" / "frames" / "000002.pcd", 1000);
  const auto r = run_cli("simulate " + scenario_ + " -o " + path("out") + " --resume");
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "fmcw: note: " + path("out") + "/frames/000002.pcd: ")) << r.output;
  EXPECT_TRUE(has(r.output, "it and the 3 frames after it are simulated again")) << r.output;
  EXPECT_EQ(fmcw::test::first_difference(folder_bytes(dir_ / "reference"), folder_bytes(dir_ / "out")), "");
  // Another frame's file under this frame's name is caught by its stamp.
  fs::copy_file(dir_ / "out" / "frames" / "000001.pcd", dir_ / "out" / "frames" / "000004.pcd",
                fs::copy_options::overwrite_existing);
  const auto again = run_cli("simulate " + scenario_ + " -o " + path("out") + " --resume");
  EXPECT_EQ(again.code, 0) << again.output;
  EXPECT_TRUE(has(again.output, "000004.pcd: stamp 0.100000 s where frame time 0.400000 s was written")) << again.output;
  EXPECT_EQ(fmcw::test::first_difference(folder_bytes(dir_ / "reference"), folder_bytes(dir_ / "out")), "");
}

// Case 6: --threads 100000 crashed inside libgomp; 1000 printed libgomp's own failure.
TEST_F(DataSafety, ThreadCountsBeyondTheLimitAreOneError) {
  for (const char* n : {"100000", "65536", "1000"}) {
    expect_refused(scenario_, std::string("num_threads (--threads) must be in [0, 256] (0: all cores), got ") + n,
                   std::string("--threads ") + n, fmcw::test::kExitLimit);
  }
  simulate("-o " + path("data") + " --frames 1");
  // The pipeline's own check (core/src/motion_pipeline.cpp), a LimitError as the simulator's.
  const auto r = run_cli("process " + path("data") + " -o " + path("out") + " --threads 100000");
  EXPECT_EQ(r.code, fmcw::test::kExitLimit) << r.output;
  EXPECT_TRUE(has(r.output, "pipeline: num_threads (--threads) must be in [0, 256]")) << r.output;
}

// Case 7: far coordinates and times aborted inside Embree and left a partial dataset.
TEST_F(DataSafety, FarCoordinatesAndTimesAreRefusedAtLoadNamingTheKey) {
  expect_refused(scenario_with("rate.yaml", "rate_hz: 10", "rate_hz: 1e-308"), "rate.yaml:3: rate_hz: rate_hz must be in [0.001, 1e6] Hz");
  expect_refused(scenario_with("start.yaml", "rate_hz: 10", "rate_hz: 10\nstart_time_s: 1e300"),
                 "start_time_s: start_time_s must be within 1e9 s of 0");
  expect_refused(scenario_with("far.yaml", "pose: {x: 0}", "pose: {x: 1e39}"),
                 "far.yaml: ego.trajectory: at frame 0 (t = 0.000000 s) the body is at (1e+39, 0, 0), farther than 10000 m");
  // Driving away: inside the limit at first, out of it within the run.
  expect_refused(scenario_with("away.yaml", "pose: {x: 0}, velocity_mps: [8, 0, 0]", "pose: {x: 9999.5}, velocity_mps: [8, 0, 0]"),
                 "ego.trajectory: at frame 1 (t = 0.100000 s) the body is at (10000.3, 0, 0), farther than 10000 m");
}

// Case 11: absurd but finite motions ended in "scan: valid pixel ... holds a NaN".
TEST_F(DataSafety, AbsurdPhysicsIsRefusedWithFileAndKey) {
  expect_refused(scenario_with("speed.yaml", "speed_mps: 6", "speed_mps: 1e308"),
                 "speed.yaml: actors[0] (id 1) trajectory: at frame 0");
  expect_refused(scenario_with("speed.yaml", "speed_mps: 6", "speed_mps: 1e308"), "faster than 1000 m/s");
  expect_refused(scenario_with("vel.yaml", "velocity_mps: [8, 0, 0]", "velocity_mps: [1e308, 0, 0]"),
                 "vel.yaml: ego.trajectory: at frame 0 (t = 0.000000 s) the body moves at (1e+308, 0, 0) m/s, faster than 1000 m/s");
  expect_refused(scenario_with("yaw.yaml", "trajectory: {type: constant_velocity, pose: {x: 0}, velocity_mps: [8, 0, 0]}",
                               "trajectory: {type: constant_turn_rate, speed_mps: 5, yaw_rate_dps: 1e308}"),
                 "yaw.yaml: ego.trajectory: at frame 0 (t = 0.000000 s) the body turns at");
  expect_refused(scenario_with("noise.yaml", "range_sigma_m: 0.025", "range_sigma_m: 1e308"),
                 "range_sigma_m must be in [0, 10] m, got 1e+308");
}

// Case 12: ground.half_size_m: 1e20 removed the ground without a word.
TEST_F(DataSafety, AGroundTooLargeToTraceIsRefused) {
  expect_refused(scenario_with("ground.yaml", "half_size_m: 200", "half_size_m: 1e20"),
                 "ground.yaml:9: ground.half_size_m: must be in (0, 10000] m");
}

// Case 10: frames: 2 then frames: 3 gave 2 frames without a word.
TEST_F(DataSafety, AKeyGivenTwiceIsAnErrorNamingBothLines) {
  expect_refused(scenario_with("dup.yaml", "rate_hz: 10\n", "rate_hz: 10\nframes: 2\n"),
                 "dup.yaml:4: key 'frames' given twice in the top level (first at line 2); keep one");
  expect_refused(scenario_with("dup2.yaml", "pose: {x: 0}", "pose: {x: 0, x: 3}"),
                 "key 'x' given twice in ego.trajectory.pose");
}

// Case 13: --seed -1, 2^64 and 1e23 all became 18446744073709551615.
TEST_F(DataSafety, ASeedOutOfRangeIsRefusedNotWrapped) {
  for (const char* seed : {"-1", "18446744073709551616", "1e23", "0x10"}) {
    const auto r = run_cli("simulate " + scenario_ + " -o " + path("s") + " --seed " + seed);
    EXPECT_EQ(r.code, fmcw::test::kExitUsage) << r.output;
    EXPECT_EQ(fmcw::test::error_lines(r.output).size(), 1u) << r.output;
    EXPECT_TRUE(has(r.output, std::string("--seed: '") + seed + "' is not a seed: expected a whole number from 0 to "
                              "18446744073709551615")) << r.output;
    EXPECT_FALSE(fs::exists(path("s")));
  }
  simulate("-o " + path("max") + " --frames 1 --seed 18446744073709551615");
  EXPECT_TRUE(has(slurp(dir_ / "max" / "dataset.yaml"), "seed: 18446744073709551615"));
}

// Case 8: 100,000 repeats of a building took 5.5 GB and ended in bad_alloc; eight heads just
// under the per-head cap took 6.1 GB. Now both are refused from the estimate, before the copies
// or the pixels exist.
TEST_F(DataSafety, ScenariosOverTheMemoryBudgetFailFromTheEstimateWithLittleMemory) {
  const std::string repeat = scenario_with("repeat.yaml", "pose: {x: 40, y: 12}}", "pose: {x: 40, y: 12}, repeat: {count: 100000, dx: 0.01}}");
  std::string heads = "name: heads\nrig:\n  heads:\n";
  for (int i = 0; i < 8; ++i) {
    heads += "    - {name: h" + std::to_string(i) + ", mount: {yaw_deg: " + std::to_string(45 * i) +
             "}, fov_deg: [40, 30], resolution_deg: [0.0085, 0.0085]}\n";
  }
  const std::string eight = write("heads.yaml", heads);
  for (const auto& [file, part] : std::vector<std::pair<std::string, std::string>>{
           {repeat, "repeat.yaml:13: static[0]: 100000 copies of '"},
           {eight, "heads.yaml:4: rig.heads: the 8 heads' 132859792 pixels would take about 32436 MB"}}) {
    const auto [kb, r] = run_measured("simulate " + file + " -o " + path("big") + " --max-memory 4096", dir_ / "measure.log");
    EXPECT_EQ(r.code, fmcw::test::kExitLimit) << r.output;
    EXPECT_TRUE(has(r.output, part)) << r.output;
    EXPECT_TRUE(has(r.output, "over the memory budget of 4096 MB")) << r.output;
    EXPECT_GT(kb, 0);
    EXPECT_LT(kb, 200 * 1024) << r.output;
    EXPECT_FALSE(fs::exists(path("big")));
  }
  // Without --max-memory the budget is half of the machine's memory: the same files fail.
  const auto r = run_cli("simulate " + repeat + " -o " + path("big"));
  EXPECT_EQ(r.code, fmcw::test::kExitLimit) << r.output;
  EXPECT_TRUE(has(r.output, "(half of this machine's memory unless --max-memory says otherwise)")) << r.output;
}

// Case 16 (the simulator's part): what a path is, said as it is; a name that would garble the
// terminal refused.
TEST_F(DataSafety, MessagesSayWhatIsTrue) {
  fs::create_directories(dir_ / "mesh_dir.gltf");
  expect_refused(scenario_with("dir.yaml", std::string(FMCW_SOURCE_DIR) + "/assets/building_block.gltf", path("mesh_dir.gltf")),
                 "mesh file '" + path("mesh_dir.gltf") + "' is a directory");
  fs::create_symlink(dir_ / "loop.gltf", dir_ / "loop.gltf");
  expect_refused(scenario_with("loop.yaml", std::string(FMCW_SOURCE_DIR) + "/assets/building_block.gltf", path("loop.gltf")),
                 "is a broken or looping link");
  expect_refused(scenario_with("name.yaml", "name: small", "name: \"a\\e[2Jb\""),
                 "name: name must be 1 to 200 characters without control characters");
  expect_refused(scenario_with("long.yaml", "name: small", "name: " + std::string(5000, 'n')),
                 "(got 5000 characters)");
  // What a user wrote is echoed escaped and shortened.
  expect_refused(scenario_with("key.yaml", "seed: 5", "seed: 5\n\"\\e[2Jx\": 1"), "unknown key '\\x1b[2Jx' in the top level");
  expect_refused(scenario_with("num.yaml", "rate_hz: 10", "rate_hz: " + std::string(5000, 'a')),
                 "rate_hz: expected a finite number, got '" + std::string(80, 'a') + "... (5000 characters)'");
  expect_refused(write("deep.yaml", "name: deep\nrig: " + std::string(10000, '[') + std::string(10000, ']') + "\n"),
                 "deep.yaml:2:20006: malformed YAML: nested deeper than 499 levels");
}

}  // namespace
