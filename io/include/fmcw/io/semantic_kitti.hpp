#pragma once
// SemanticKITTI-style export: a scan as NAME.bin (float32 x y z remission per point,
// little-endian) and its labels as NAME.label (uint32 per point: semantic class in the lower 16
// bits, instance id in the upper 16), the same points in the same order. Only points with a
// return are written, in row-major order of the organized cloud.

#include <string>

#include "fmcw/io/pcd.hpp"
#include "fmcw/io/point_labels.hpp"

namespace fmcw::io {

/// Remission is the cloud's `intensity` (0 when it has none). Both files are written
/// atomically. Returns the number of points written. std::invalid_argument naming where for a
/// point with a return whose intensity is not finite.
std::size_t write_semantic_kitti(const std::string& bin_path, const std::string& label_path, const PcdCloud& cloud,
                                 const PointLabels& labels, const std::string& where);

}  // namespace fmcw::io
