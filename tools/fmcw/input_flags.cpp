#include "input_flags.hpp"

#include <sstream>

namespace fmcw::cli {

io::InputOptions InputFlags::resolve() const {
  io::InputOptions o;
  o.format = io::parse_input_format(format);
  o.aeva_layout = io::parse_aeva_layout(aeva_record);
  o.negate_velocity = negate_velocity;
  if (!velocity_frame.empty()) o.velocity_frame = core::velocity_frame_from_string(velocity_frame);
  o.grid.fov_horizontal_deg = fov_horizontal_deg;
  o.grid.resolution_horizontal_deg = resolution_horizontal_deg;
  o.grid.fov_vertical_deg = fov_vertical_deg;
  o.grid.resolution_vertical_deg = resolution_vertical_deg;
  o.grid.lines = lines;
  o.mcap.topic = mcap_topic;
  o.mcap.doppler_field = doppler_field;
  o.grid.validate();
  return o;
}

void add_input_flags(CLI::App* cmd, InputFlags& f) {
  cmd->add_option("input", f.path, "A frame file, or a folder: a dataset (frames/*.pcd) or *.pcd / *.bin files")
      ->required();
  cmd->add_option("--format", f.format,
                  "Input: pcd (organized frames), points (any PCD with x y z v, projected onto a grid), "
                  "aeva (Aeva Aeries II .bin scans), mcap (PointCloud2 messages of --topic)")
      ->check(CLI::IsMember(io::input_format_names()));
  cmd->add_option("--aeva-record", f.aeva_record, "Aeva record size: auto, 25 or 29 bytes")
      ->check(CLI::IsMember({"auto", "25", "29"}));
  cmd->add_option("--aeva-lines", f.lines, "Aeva scan lines (rows); a larger line index is an error; 0 = from the file")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--fov-h", f.fov_horizontal_deg, "points, aeva: azimuth span of the grid [deg]");
  cmd->add_option("--res-h", f.resolution_horizontal_deg, "points, aeva: azimuth bin [deg]");
  cmd->add_option("--fov-v", f.fov_vertical_deg, "points: elevation span of the grid [deg]");
  cmd->add_option("--res-v", f.resolution_vertical_deg, "points: elevation bin [deg]");
  cmd->add_option("--velocity-frame", f.velocity_frame,
                  "What the velocities are measured against: raw (the sensor's Doppler) or compensated "
                  "(ego-motion compensated, the static world at 0). Default: pcd, points and mcap as the file "
                  "says (else raw), aeva compensated (the public datasets' convention)")
      ->check(CLI::IsMember({"raw", "compensated"}));
  cmd->add_flag("--negate-velocity", f.negate_velocity,
                "points, aeva, mcap: flip the Doppler sign to the project's (+ away)");
  cmd->add_option("--topic", f.mcap_topic, "mcap: the PointCloud2 topic to read");
  cmd->add_option("--doppler-field", f.doppler_field, "mcap: the Doppler field (auto tries v, velocity, doppler, radial_vel)")
      ->check(CLI::IsMember({"auto", "v", "velocity", "doppler", "radial_vel"}));
}

std::string velocity_frame_note(const io::InputFrame& in, const InputFlags& flags) {
  const core::VelocityFrame used = in.frame.scan.velocity_frame;
  const std::string name = used == core::VelocityFrame::kSensor ? "raw (sensor frame)" : "ego-compensated";
  if (!flags.velocity_frame.empty()) {
    if (used == in.file_velocity_frame) return "";
    return "velocity frame: " + name + " from --velocity-frame, overriding " + in.velocity_frame_source + " (" +
           core::to_string(in.file_velocity_frame) + ")";
  }
  if (used == core::VelocityFrame::kSensor && in.velocity_frame_source == "the default") return "";
  std::string note = "velocity frame: " + name + " assumed, from " + in.velocity_frame_source;
  if (used == core::VelocityFrame::kEgoCompensated) {
    note += " (--velocity-frame raw if the velocities are the raw Doppler)";
  }
  return note;
}

std::string projection_summary(const io::InputFrame& frame) {
  if (!frame.projected) return "";
  const core::GridProjectionStats& s = frame.stats;
  std::ostringstream out;
  out << "placed " << s.placed << " of " << s.points << " points (" << s.collisions << " collisions, " << s.outside_fov
      << " outside the field of view) on " << frame.frame.scan.rows << " x " << frame.frame.scan.cols
      << (s.rows_by_line ? " by line and azimuth" : " by elevation and azimuth");
  return out.str();
}

}  // namespace fmcw::cli
