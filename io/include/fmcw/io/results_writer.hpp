#pragma once
// Per-frame motion results as tables: ego.csv, objects.csv, timing.csv and results.json.
// Timings live only in timing.csv, so that the
// other files are byte-identical across runs of the same input, method and seed.

#include <fstream>
#include <string>

#include "fmcw/core/motion_pipeline.hpp"

namespace fmcw::io {

class ResultsWriter {
 public:
  /// Opens the tables under dir (created if missing). Files are written under temporary names
  /// and renamed into place by finish(), so an interrupted run leaves no partial table.
  explicit ResultsWriter(const std::string& dir);
  ~ResultsWriter();
  ResultsWriter(const ResultsWriter&) = delete;
  ResultsWriter& operator=(const ResultsWriter&) = delete;

  void add(std::size_t frame_index, const std::string& source, const core::MotionEstimate& estimate);
  void finish();

 private:
  struct Table {
    std::string path;
    std::string tmp;
    std::ofstream out;
  };
  void open(Table& table, const std::string& name, const std::string& header);
  void close(Table& table);

  std::string dir_;
  Table ego_, objects_, timing_, json_;
  bool first_json_ = true;
  bool finished_ = false;
};

/// Labelled cloud: x y z range v intensity label (I4: -1 invalid, 0 static, k cluster), with the
/// scan's head comments, written atomically.
void write_labelled_pcd(const std::string& path, const core::Scan& scan, const core::MotionEstimate& estimate);

}  // namespace fmcw::io
