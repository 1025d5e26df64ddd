#include "fmcw/io/mcap_frames.hpp"

#include <algorithm>
#include <cstdio>
#include <iostream>

#include "fmcw/core/check.hpp"
#include "fmcw/io/ros2_messages.hpp"

namespace fmcw::io {

using core::concat;

const std::vector<std::string>& doppler_field_names() {
  static const std::vector<std::string> names = {"v", "velocity", "doppler", "radial_vel"};
  return names;
}

McapFrames::McapFrames(const std::string& path, const McapInputOptions& options)
    : reader_(std::make_unique<McapReader>(path, options.topic)), options_(options) {
  const std::vector<std::string>& names = doppler_field_names();
  FMCW_CHECK_ARG(options.doppler_field == "auto" ||
                     std::find(names.begin(), names.end(), options.doppler_field) != names.end(),
                 "--doppler-field must be auto, v, velocity, doppler or radial_vel, got '", options.doppler_field, "'");
  const McapChannel* ch = reader_->topic_channel();
  if (ch == nullptr) {
    std::string topics;
    for (const McapChannel& c : reader_->channels()) {
      topics += concat(topics.empty() ? "" : ", ", c.topic, " (", c.schema_name.empty() ? "no schema" : c.schema_name, ")");
    }
    throw core::FileError(concat(path, ": no channel on topic '", options.topic, "'; the file has: ",
                                 topics.empty() ? "no channels" : topics));
  }
  const std::string where = concat(path, ": record at offset ", ch->record_offset, " (Channel '", ch->topic, "')");
  const bool cloud_schema = ch->schema_name == "sensor_msgs/msg/PointCloud2" || ch->schema_name == "sensor_msgs/PointCloud2";
  FMCW_CHECK_FILE(cloud_schema && ch->schema_encoding == "ros2msg" && ch->message_encoding == "cdr", where,
                  ": unknown schema '", ch->schema_name, "' (encoding '", ch->schema_encoding, "', messages '",
                  ch->message_encoding, "'); only sensor_msgs/msg/PointCloud2 in ros2msg schema and cdr is read");
  FMCW_CHECK_FILE(reader_->size() > 0, where, ": no message on the topic");
  const auto meta = reader_->metadata().find("fmcw");
  if (meta != reader_->metadata().end()) {
    for (const auto& [key, value] : meta->second) {
      if (value.rfind("fmcw_head ", 0) == 0) head_comments_.push_back(value);
    }
  }
}

McapFrames::~McapFrames() = default;

std::size_t McapFrames::size() const { return reader_->size(); }

std::string McapFrames::source(std::size_t k) const { return concat(reader_->path(), "#", k); }

PcdCloud McapFrames::cloud(std::size_t k) {
  const McapMessage m = reader_->message(k);
  const ros2::PointCloud2 msg = ros2::decode_point_cloud2(m.data.data(), m.data.size(), m.where);
  PcdCloud cloud = ros2::pcd_from_point_cloud2(msg, m.where);
  // The Doppler field: the one asked for, or the first of the known names.
  std::string doppler = options_.doppler_field;
  if (doppler == "auto") {
    doppler.clear();
    for (const std::string& name : doppler_field_names()) {
      if (cloud.find(name)) {
        doppler = name;
        break;
      }
    }
  }
  std::string fields;
  for (const PcdField& f : cloud.fields) fields += " " + f.name;
  if (doppler.empty() || cloud.find(doppler) == nullptr) {
    throw core::FileError(concat(m.where, ": missing field: no Doppler field ",
                                 doppler.empty() ? "(tried v velocity doppler radial_vel)" : "'" + doppler + "'",
                                 "; the cloud has:", fields));
  }
  if (!told_doppler_) {
    std::cerr << reader_->path() << ": Doppler from field '" << doppler << "' of " << options_.topic << "\n";
    told_doppler_ = true;
  }
  // The chosen field becomes `v`; another field named `v` would clash with it and goes.
  const std::vector<std::string>& known = known_frame_fields();
  std::vector<PcdField> kept;
  std::string dropped;
  for (PcdField& f : cloud.fields) {
    if (f.name == doppler) {
      f.name = "v";
    } else if (f.name == "v" || std::find(known.begin(), known.end(), f.name) == known.end()) {
      dropped += " " + f.name;
      continue;
    }
    kept.push_back(std::move(f));
  }
  cloud.fields = std::move(kept);
  if (!dropped.empty() && !told_fields_) {
    std::cerr << "fmcw: note: " << reader_->path() << ": fields not read:" << dropped << "\n";
    told_fields_ = true;
  }
  char stamp[40];
  std::snprintf(stamp, sizeof stamp, "fmcw_stamp %.17g", msg.stamp.seconds());  // exact through strtod
  cloud.comments.push_back(stamp);
  cloud.comments.insert(cloud.comments.end(), head_comments_.begin(), head_comments_.end());
  return cloud;
}

}  // namespace fmcw::io
