#pragma once
// PLY export (binary little-endian, the form Open3D, CloudCompare and MeshLab read): one vertex
// per point with a return, every PCD field as a vertex property of the same type, optionally
// coloured (red green blue, uchar).

#include <string>
#include <vector>

#include "fmcw/io/pcd.hpp"
#include "fmcw/io/point_colors.hpp"

namespace fmcw::io {

/// Writes the points of the cloud whose x, y, z are finite, in cloud order, atomically. colors
/// is empty (no colour) or holds one entry per cloud point. The PCD's comment lines (head
/// layout, stamp) become PLY comments. Returns the number of vertices written.
/// std::invalid_argument for 8-byte integer fields (PLY has no such type) or a cloud that has
/// fields named red, green or blue already when colours are asked for.
std::size_t write_ply(const std::string& path, const PcdCloud& cloud, const std::vector<Rgb>& colors = {});

}  // namespace fmcw::io
