#pragma once
// Input options shared by the commands that read frames (process, export): the format and, for
// point lists and Aeva scans, the grid they are projected onto.

#include <CLI/CLI.hpp>
#include <string>

#include "fmcw/io/frame_input.hpp"

namespace fmcw::cli {

struct InputFlags {
  std::string path;  ///< the positional input: a frame file or a folder of frames
  std::string format = "pcd";
  std::string aeva_record = "auto";
  int lines = 0;
  double fov_horizontal_deg = 120.0;
  double resolution_horizontal_deg = 0.2;
  double fov_vertical_deg = 30.0;
  double resolution_vertical_deg = 0.2;
  bool negate_velocity = false;
  std::string velocity_frame;  ///< "", "raw" or "compensated"
  std::string mcap_topic = "/points";
  std::string doppler_field = "auto";

  /// Checks the values (std::invalid_argument naming the option) and returns them as options.
  io::InputOptions resolve() const;
};

/// Registers the positional input and the format and grid options.
void add_input_flags(CLI::App* cmd, InputFlags& flags);

/// The stderr line that says which velocity frame a run's frames are taken in and why, once
/// per run (the first frame's): "" when the input says nothing worth saying (a sensor-frame
/// dataset read as such).
std::string velocity_frame_note(const io::InputFrame& frame, const InputFlags& flags);

/// "placed P of N points (C collisions, O outside the field of view) on R x C" for a projected
/// frame, "" otherwise.
std::string projection_summary(const io::InputFrame& frame);

}  // namespace fmcw::cli
