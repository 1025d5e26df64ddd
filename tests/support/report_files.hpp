#pragma once
// Checks on a report folder: every figure report.html names is a real PNG, nothing half-written
// is left behind.

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <regex>
#include <string>

#include "support/cli.hpp"

namespace fmcw::test {

// A PNG starts with its 8-byte signature and an IHDR chunk holding width and height.
inline void expect_png(const std::filesystem::path& p) {
  const std::string bytes = slurp(p);
  ASSERT_GE(bytes.size(), 33u) << p;
  EXPECT_EQ(bytes.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8)) << p;
  EXPECT_EQ(bytes.substr(12, 4), "IHDR") << p;
  const auto be32 = [&](std::size_t at) {
    return (static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[at])) << 24) |
           (static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[at + 1])) << 16) |
           (static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[at + 2])) << 8) |
           static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[at + 3]));
  };
  EXPECT_GE(be32(16), 400u) << p << " width";
  EXPECT_LE(be32(16), 5000u) << p << " width";
  EXPECT_GE(be32(20), 200u) << p << " height";
  EXPECT_LE(be32(20), 5000u) << p << " height";
}

// Every image report.html names exists and is a PNG; returns how many.
inline int expect_report_figures(const std::filesystem::path& dir) {
  const std::string html = slurp(dir / "report.html");
  EXPECT_NE(html.find("</html>"), std::string::npos);
  const std::regex img("<img src=\"([^\"]+)\"");
  int count = 0;
  for (auto it = std::sregex_iterator(html.begin(), html.end(), img); it != std::sregex_iterator(); ++it) {
    const std::filesystem::path png = dir / (*it)[1].str();
    EXPECT_TRUE(std::filesystem::is_regular_file(png)) << png;
    if (std::filesystem::is_regular_file(png)) expect_png(png);
    ++count;
  }
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    EXPECT_NE(e.path().filename().string().rfind(".tmp.", 0), 0u) << "left behind: " << e.path();
  }
  return count;
}

}  // namespace fmcw::test
