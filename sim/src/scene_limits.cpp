#include "scene_limits.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "fmcw/core/errors.hpp"

namespace fmcw::sim {

namespace {

std::string vec_text(const Eigen::Vector3d& v) {
  std::ostringstream out;
  out << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return out.str();
}

// Checks one body at the times of every frame (and the end of the last frame's sweep).
void check_body(const Scenario& s, const TrajectorySpec& spec, const std::string& key) {
  const std::string where = s.source_file + ": " + key + ": ";
  std::unique_ptr<Trajectory> trajectory;
  try {
    trajectory = spec.make();
  } catch (const std::invalid_argument&) {
    core::rethrow_as_file_error(where);
  }
  const int last = spec.type == "static" ? 0 : s.frames;  // a static body is where it was
  for (int k = 0; k <= last; ++k) {
    const double t = s.frame_time_s(static_cast<std::uint64_t>(k));
    if (!std::isfinite(t)) {
      throw core::FileError(s.source_file + ": frame " + std::to_string(k) + " has no finite time (start_time_s " +
                            std::to_string(s.start_time_s) + ", rate_hz " + std::to_string(s.rate_hz) + ")");
    }
    MotionState m;
    try {
      m = trajectory->state(t);
    } catch (const std::invalid_argument&) {
      core::rethrow_as_file_error(where + "at t = " + std::to_string(t) + " s: ");
    }
    const Eigen::Vector3d p = m.T_world_body.translation();
    const std::string at = "at frame " + std::to_string(k) + " (t = " + std::to_string(t) + " s) ";
    if (!p.allFinite() || p.norm() > kMaxSceneExtent_m) {
      throw core::FileError(where + at + "the body is at " + vec_text(p) + ", farther than " +
                            std::to_string(static_cast<int>(kMaxSceneExtent_m)) +
                            " m from the origin, where single-precision ray tracing loses millimetres; "
                            "move the scene nearer the origin or shorten it");
    }
    if (!m.twist.linear_mps.allFinite() || m.twist.linear_mps.norm() > kMaxSpeed_mps) {
      throw core::FileError(where + at + "the body moves at " + vec_text(m.twist.linear_mps) +
                            " m/s, faster than " + std::to_string(static_cast<int>(kMaxSpeed_mps)) + " m/s");
    }
    if (!m.twist.angular_rps.allFinite() || m.twist.angular_rps.norm() > kMaxTurnRate_rps) {
      throw core::FileError(where + at + "the body turns at " + vec_text(m.twist.angular_rps) +
                            " rad/s, faster than 10 turns a second");
    }
  }
}

}  // namespace

void check_scene_limits(const Scenario& s) {
  check_body(s, s.ego, "ego.trajectory");
  for (std::size_t k = 0; k < s.statics.size(); ++k) {
    check_body(s, s.statics[k].trajectory, "static[" + std::to_string(k) + "] ('" + s.statics[k].name + "')");
  }
  for (std::size_t k = 0; k < s.actors.size(); ++k) {
    check_body(s, s.actors[k].trajectory,
               "actors[" + std::to_string(k) + "] (id " + std::to_string(s.actors[k].id) + ") trajectory");
  }
}

}  // namespace fmcw::sim
