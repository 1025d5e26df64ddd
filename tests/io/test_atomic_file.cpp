#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "fmcw/io/atomic_file.hpp"

namespace fmcw::io {
namespace {

namespace fs = std::filesystem;

TEST(AtomicFile, FailedWriteLeavesTheOldFileAndNoTemporary) {
  const fs::path dir = fs::temp_directory_path() / ("fmcw_atomic_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string target = (dir / "out.txt").string();
  write_file_atomically(target, [](std::ostream& out) { out << "first"; });
  EXPECT_THROW(write_file_atomically(target,
                                     [](std::ostream& out) {
                                       out << "partial";
                                       throw std::runtime_error("interrupted");
                                     }),
               std::runtime_error);
  std::ifstream in(target);
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), "first");
  int files = 0;
  for (const auto& e : fs::directory_iterator(dir)) files += e.is_regular_file() ? 1 : 0;
  EXPECT_EQ(files, 1);
  fs::remove_all(dir);
}

TEST(AtomicFile, UnwritablePlacesGiveAClearError) {
  const fs::path dir = fs::temp_directory_path() / ("fmcw_atomic_bad_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "plain_file") << "x";
  try {
    write_file_atomically((dir / "plain_file" / "out.pcd").string(), [](std::ostream&) {});
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot write '"), std::string::npos) << e.what();
  }
  try {
    ensure_writable_directory((dir / "plain_file" / "sub").string());
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot create output folder"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace fmcw::io
