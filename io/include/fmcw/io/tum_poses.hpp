#pragma once
// Trajectories in the TUM format (one pose a line: "t x y z qx qy qz qw", '#' comments), as the
// public FMCW datasets ship their ego poses.

#include <string>

#include "fmcw/core/ego_motion.hpp"

namespace fmcw::io {

/// Reads a TUM trajectory. core::FileError naming the file and line for a line that is not
/// eight finite numbers, and (naming the file) for anything PoseSeries::validate refuses:
/// fewer than two poses, stamps that do not increase, a non-unit quaternion.
core::PoseSeries read_tum_poses(const std::string& path);

/// Writes poses in the TUM format atomically, 9 significant digits for positions and
/// quaternions and nanoseconds for stamps.
void write_tum_poses(const std::string& path, const core::PoseSeries& poses);

}  // namespace fmcw::io
