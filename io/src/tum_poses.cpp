#include "fmcw/io/tum_poses.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "fmcw/core/check.hpp"
#include "fmcw/io/atomic_file.hpp"
#include "fmcw/io/input_file.hpp"

namespace fmcw::io {

using core::concat;

core::PoseSeries read_tum_poses(const std::string& path) {
  regular_file_size(path, "poses file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw core::FileError(concat(path, ": cannot open poses file: ", std::strerror(errno)));
  core::PoseSeries poses;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::size_t first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream words(line);
    std::string word;
    double v[8];
    int count = 0;
    while (words >> word) {
      if (count == 8) {
        throw core::FileError(concat(path, ":", number, ": more than eight values (expected t x y z qx qy qz qw)"));
      }
      char* end = nullptr;
      v[count] = std::strtod(word.c_str(), &end);
      if (end == word.c_str() || *end != '\0' || !std::isfinite(v[count])) {
        throw core::FileError(concat(path, ":", number, ": value ", count + 1, " '", word,
                                     "' is not a finite number (expected t x y z qx qy qz qw)"));
      }
      ++count;
    }
    if (count != 8) {
      throw core::FileError(concat(path, ":", number, ": ", count, " values, expected 8 (t x y z qx qy qz qw)"));
    }
    poses.stamp_s.push_back(v[0]);
    poses.position_m.emplace_back(v[1], v[2], v[3]);
    poses.orientation.emplace_back(v[7], v[4], v[5], v[6]);  // Eigen: (w, x, y, z)
  }
  try {
    poses.validate();
  } catch (const std::exception&) {
    core::rethrow_as_file_error(path + ": ");
  }
  return poses;
}

void write_tum_poses(const std::string& path, const core::PoseSeries& poses) {
  poses.validate();
  std::ostringstream out;
  out << "# t x y z qx qy qz qw (TUM): rig pose in the world, stamps [s]\n";
  for (std::size_t k = 0; k < poses.size(); ++k) {
    const Eigen::Vector3d& p = poses.position_m[k];
    const Eigen::Quaterniond& q = poses.orientation[k];
    out << std::fixed << std::setprecision(9) << poses.stamp_s[k] << std::defaultfloat << std::setprecision(9) << ' '
        << p.x() << ' ' << p.y() << ' ' << p.z() << ' ' << q.x() << ' ' << q.y() << ' ' << q.z() << ' ' << q.w()
        << '\n';
  }
  const std::string text = out.str();
  write_file_atomically(path, [&](std::ostream& o) { o.write(text.data(), static_cast<std::streamsize>(text.size())); });
}

}  // namespace fmcw::io
