// What the readers do with files that are not what they claim: a 2 GB file is refused from its
// header or its size without being read (peak memory stays small), and a directory, a FIFO or a
// device is refused before it is opened for reading (a FIFO would block, /dev/zero never ends).

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>

#include "fmcw/io/aeva.hpp"
#include "fmcw/io/frame_input.hpp"
#include "fmcw/io/pcd.hpp"
#include "support/temp_dir.hpp"

namespace fmcw::io {
namespace {

namespace fs = std::filesystem;

constexpr off_t kTwoGiB = off_t{1} << 31;
// Far below the 2 GiB the files hold: reading one whole would show.
constexpr long kMaxPeakRssKiB = 200 * 1024;

long peak_rss_kib() {
  rusage usage{};
  ::getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss;
}

class InputFiles : public fmcw::test::TempDirTest {
 protected:
  // A sparse file of `size` bytes that starts with `prefix`: no disk space, no page of memory.
  std::string sparse(const std::string& name, const std::string& prefix, off_t size) const {
    const std::string p = write(name, prefix);
    EXPECT_EQ(::truncate(p.c_str(), size), 0) << p;
    return p;
  }
  // f() must throw std::invalid_argument holding every fragment.
  static void expect_error(const std::function<void()>& f, const std::vector<std::string>& fragments) {
    try {
      f();
      ADD_FAILURE() << "expected an error with '" << fragments.front() << "'";
    } catch (const std::invalid_argument& e) {
      for (const auto& s : fragments) EXPECT_NE(std::string(e.what()).find(s), std::string::npos) << e.what();
    }
  }
};

TEST_F(InputFiles, PcdWithoutNewlineIsRefusedFromItsFirstLine) {
  const std::string big = sparse("nonl.pcd", "VERSION", kTwoGiB);
  expect_error([&] { read_frame(big); }, {"nonl.pcd:1: header line too long"});
  expect_error([&] { read_pcd(big); }, {"nonl.pcd:1: header line too long"});
  fs::remove(big);
  EXPECT_LT(peak_rss_kib(), kMaxPeakRssKiB);
}

TEST_F(InputFiles, AsciiPcdLineWithoutEndIsRefusedWithoutReadingIt) {
  const std::string header =
      "VERSION 0.7\nFIELDS x y z v\nSIZE 4 4 4 4\nTYPE F F F F\nWIDTH 2\nHEIGHT 2\nPOINTS 4\nDATA ascii\n1 2 3 4";
  const std::string big = sparse("line.pcd", header, kTwoGiB);
  expect_error([&] { read_frame(big); }, {"line.pcd:9: point 0: line longer than", "bytes"});
  fs::remove(big);
  EXPECT_LT(peak_rss_kib(), kMaxPeakRssKiB);
}

TEST_F(InputFiles, AevaSizeMismatchIsRefusedFromTheFileSizeAlone) {
  // 2^31 bytes: 23 bytes over a multiple of 25, 8 over a multiple of 29.
  const std::string big = sparse("big.bin", "", kTwoGiB);
  expect_error([&] { read_aeva(big); }, {"big.bin: size 2147483648 bytes is not a whole number of Aeva records"});
  expect_error([&] { read_aeva(big, AevaLayout::k25); },
               {"big.bin: size 2147483648 bytes is not a multiple of the 25-byte Aeva record"});
  expect_error([&] { read_aeva_scan(big); }, {"big.bin: size 2147483648 bytes"});
  fs::remove(big);
  EXPECT_LT(peak_rss_kib(), kMaxPeakRssKiB);
}

TEST_F(InputFiles, DirectoriesFifosAndDevicesAreRefusedBeforeTheyAreRead) {
  const std::string fifo = path("pipe.pcd");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  fs::create_directories(path("folder.pcd"));
  InputOptions points;
  points.format = InputFormat::kPoints;
  InputOptions aeva;
  aeva.format = InputFormat::kAeva;
  for (const std::string& file : {fifo, std::string("/dev/zero")}) {
    expect_error([&] { read_frame(file); }, {file + ": is not a regular file"});
    expect_error([&] { read_input_frame(file, points); }, {file + ": is not a regular file"});
    expect_error([&] { read_aeva(file); }, {file + ": is not a regular file"});
    expect_error([&] { read_input_frame(file, aeva); }, {file + ": is not a regular file"});
  }
  expect_error([&] { read_frame(path("folder.pcd")); }, {"folder.pcd: is a directory"});
  expect_error([&] { read_aeva(path("folder.pcd")); }, {"folder.pcd: is a directory"});
  EXPECT_LT(peak_rss_kib(), kMaxPeakRssKiB);
}

}  // namespace
}  // namespace fmcw::io
