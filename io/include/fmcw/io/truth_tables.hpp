#pragma once
// Per-frame ground truth of a dataset as CSV: ego.csv (one row per frame) and objects.csv (one
// row per frame and actor). Poses are world frame; velocities are rig axes, as the estimators
// report them.

#include <string>
#include <vector>

#include "fmcw/core/ground_truth.hpp"

namespace fmcw::io {

extern const char* const kEgoCsvHeader;
extern const char* const kObjectsCsvHeader;

/// One ego.csv row (with newline).
std::string ego_csv_row(std::size_t frame, const core::FrameTruth& truth);
/// The objects.csv rows of one frame (with newlines).
std::string objects_csv_rows(std::size_t frame, const core::FrameTruth& truth);

/// Reads ego.csv and objects.csv back into one FrameTruth per frame (frames 0..n-1 in order).
/// std::invalid_argument naming file and line on a malformed table. The boxes of an objects.csv
/// written before boxes were are left at zero (objects_csv_has_boxes tells).
std::vector<core::FrameTruth> read_truth_tables(const std::string& ego_csv, const std::string& objects_csv);

/// Whether objects.csv has the box columns (box_x_m ... box_world_yaw_rad), from its header.
/// std::invalid_argument naming the file when it cannot be opened or its header is neither form.
bool objects_csv_has_boxes(const std::string& objects_csv);

}  // namespace fmcw::io
