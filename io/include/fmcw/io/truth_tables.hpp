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
/// std::invalid_argument naming file and line on a malformed table.
std::vector<core::FrameTruth> read_truth_tables(const std::string& ego_csv, const std::string& objects_csv);

}  // namespace fmcw::io
