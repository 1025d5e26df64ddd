// Output that cannot be written: a folder without write permission, a disk that fills up. One
// clear error, a non-zero exit, and nothing half-written that claims to be whole.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "support/cli.hpp"
#include "support/dataset_files.hpp"
#include "support/temp_dir.hpp"

namespace {

namespace fs = std::filesystem;
using fmcw::test::folder_bytes;
using fmcw::test::run_cli;
using fmcw::test::run_shell;
using fmcw::test::slurp;

class OutputFaults : public fmcw::test::TempDirTest {
 protected:
  void SetUp() override {
    TempDirTest::SetUp();
    scenario_ = write("small.yaml", fmcw::test::small_scenario_yaml(10));
  }
  std::string scenario_;
};

TEST_F(OutputFaults, FolderWithoutWritePermissionIsNamed) {
  // root passes every permission check, so as root the CLI runs as nobody for this test.
  std::string as_user;
  if (::geteuid() == 0) {
    if (run_shell("setpriv --reuid=65534 --regid=65534 --clear-groups true").code != 0) {
      GTEST_SKIP() << "running as root without setpriv: cannot drop privileges to test permissions";
    }
    as_user = "setpriv --reuid=65534 --regid=65534 --clear-groups ";
  }
  const fs::path locked = dir_ / "locked";
  fs::create_directories(locked);
  fs::permissions(locked, fs::perms::owner_read | fs::perms::owner_exec | fs::perms::group_read | fs::perms::group_exec |
                              fs::perms::others_read | fs::perms::others_exec);
  const std::string cli = as_user + FMCW_CLI_PATH;

  auto r = run_shell(cli + " simulate " + scenario_ + " -o " + (locked / "ds").string());
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(r.output, "fmcw: error: cannot create output folder '" + (locked / "ds").string() + "': Permission denied\n");

  ASSERT_EQ(run_cli("synth -o " + path("f.pcd") + " --objects 2").code, 0);
  r = run_shell(cli + " process " + path("f.pcd") + " -o " + (locked / "out").string());
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.output.find("fmcw: error: cannot create output folder '" + (locked / "out").string()), std::string::npos)
      << r.output;

  // A folder that exists but may not be written into.
  fs::permissions(locked, fs::perms::owner_all | fs::perms::group_all | fs::perms::others_all);
  fs::create_directories(locked / "ro" / "frames");
  fs::permissions(locked / "ro" / "frames", fs::perms::owner_read | fs::perms::owner_exec | fs::perms::others_read |
                                                fs::perms::others_exec);
  fs::permissions(locked / "ro", fs::perms::owner_read | fs::perms::owner_exec | fs::perms::others_read | fs::perms::others_exec);
  r = run_shell(cli + " simulate " + scenario_ + " -o " + (locked / "ro").string() + " --overwrite");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.output.find("output folder '" + (locked / "ro").string() + "' is not writable"), std::string::npos)
      << r.output;
  fs::permissions(locked / "ro", fs::perms::owner_all);
  fs::permissions(locked / "ro" / "frames", fs::perms::owner_all);
  EXPECT_TRUE(fs::is_empty(locked / "ro" / "frames"));

  // A file where the folder should be.
  std::ofstream(path("plain")) << "x";
  r = run_cli("simulate " + scenario_ + " -o " + path("plain"));
  EXPECT_EQ(r.code, fmcw::test::kExitUsage);
  EXPECT_NE(r.output.find("fmcw: error: output '" + path("plain") + "' exists and is not a folder"), std::string::npos)
      << r.output;
}

// A 1 MiB tmpfs, mounted in a private mount namespace (it vanishes with the shell), fills up
// after three or four frames of the small scenario.
TEST_F(OutputFaults, DiskThatFillsUpLeavesWholeFramesAndResumes) {
  if (::geteuid() != 0 || run_shell("unshare -m true").code != 0) {
    GTEST_SKIP() << "needs root and unshare -m to mount a small tmpfs";
  }
  ASSERT_EQ(run_cli("simulate " + scenario_ + " -o " + path("reference")).code, 0);
  const fs::path tiny = dir_ / "tiny";
  fs::create_directories(tiny);
  const std::string inside = "mount -t tmpfs -o size=1m tmpfs " + tiny.string() + " && { " + FMCW_CLI_PATH + " simulate " +
                             scenario_ + " -o " + (tiny / "ds").string() + "; echo \"exit=$?\"; cp -a " +
                             (tiny / "ds").string() + " " + path("after") + "; }";
  const auto r = run_shell("unshare -m sh -c '" + inside + "'");
  ASSERT_NE(r.output.find("exit=1"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("fmcw: error: cannot write '" + (tiny / "ds").string()), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("No space left on device"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("frames whole: fix the cause and continue with --resume"), std::string::npos) << r.output;

  // What the full disk holds: whole frames, as many as dataset.yaml says, and no temporary file.
  const auto after = folder_bytes(dir_ / "after");
  const auto reference = folder_bytes(dir_ / "reference");
  const std::string yaml = after.at("dataset.yaml");
  EXPECT_NE(yaml.find("complete: false"), std::string::npos);
  const int n = std::atoi(yaml.c_str() + yaml.find("frames_written: ") + 16);
  EXPECT_GE(n, 1);
  int frames = 0;
  for (const auto& [name, bytes] : after) {
    EXPECT_EQ(name.find(".tmp."), std::string::npos) << name;
    if (name.rfind("frames/", 0) == 0 && bytes == reference.at(name)) ++frames;
  }
  EXPECT_EQ(frames, n);

  // With space again, --resume finishes it into the bytes of an uninterrupted run.
  const auto resumed = run_cli("simulate " + scenario_ + " -o " + path("after") + " --resume");
  ASSERT_EQ(resumed.code, 0) << resumed.output;
  EXPECT_EQ(fmcw::test::first_difference(reference, folder_bytes(dir_ / "after")), "");
}

}  // namespace
