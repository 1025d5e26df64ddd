#include "fmcw/core/ego_motion.hpp"

#include <algorithm>
#include <cmath>

#include "fmcw/core/check.hpp"

namespace fmcw::core {

namespace {

// Index k of the interval [stamp[k], stamp[k+1]] holding t (t inside the stamps).
std::size_t interval_of(const std::vector<double>& stamp, double t) {
  const auto it = std::upper_bound(stamp.begin(), stamp.end(), t);
  const auto k = static_cast<std::size_t>(std::max<std::ptrdiff_t>(0, (it - stamp.begin()) - 1));
  return std::min(k, stamp.size() - 2);
}

// Calls f(i, origin, v_origin) for every valid pixel i of the scan, with its head's origin and
// that origin's velocity under the ego motion (rig frame).
template <class F>
void for_each_valid_beam(const Scan& scan, const EgoMotion& ego, F&& f) {
  for (const HeadInfo& head : scan.heads) {
    const Eigen::Vector3d o = head.origin_m();
    const Eigen::Vector3d v_origin = ego.point_velocity_mps(o);
    for (int r = 0; r < scan.rows; ++r) {
      for (int c = head.col_begin; c < head.col_end; ++c) {
        const std::size_t i = scan.index(r, c);
        if (scan.valid[i]) f(i, o, v_origin);
      }
    }
  }
}

// v_rig += sign * e . V_origin over the valid pixels.
void shift_by_ego(Scan& scan, const EgoMotion& ego, double sign) {
  scan.validate_layout();
  FMCW_CHECK_ARG(ego.velocity_mps.allFinite() && ego.angular_velocity_rps.allFinite(),
                 "ego motion: velocity and angular velocity must be finite");
  for_each_valid_beam(
      scan, ego, [&](std::size_t i, const Eigen::Vector3d& o, const Eigen::Vector3d& v_origin) {
        const Eigen::Vector3d d = scan.position(i) - o;
        const double norm = d.norm();
        if (!(norm > 0.0))
          return;  // a point on its origin has no beam direction; validate() refuses it
        scan.radial_velocity_mps[i] =
            static_cast<float>(scan.radial_velocity_mps[i] + sign * d.dot(v_origin) / norm);
      });
}

}  // namespace

void PoseSeries::validate() const {
  const std::size_t n = stamp_s.size();
  FMCW_CHECK_ARG(position_m.size() == n && orientation.size() == n, "poses: ", n, " stamps but ", position_m.size(),
                 " positions and ", orientation.size(), " orientations");
  FMCW_CHECK_ARG(n >= 2, "poses: need at least two poses to differentiate, got ", n);
  for (std::size_t k = 0; k < n; ++k) {
    FMCW_CHECK_ARG(std::isfinite(stamp_s[k]) && position_m[k].allFinite() && orientation[k].coeffs().allFinite(),
                   "poses: pose ", k, " (t = ", stamp_s[k], ") holds a NaN or Inf");
    FMCW_CHECK_ARG(k == 0 || stamp_s[k] > stamp_s[k - 1], "poses: pose ", k, " stamp ", stamp_s[k],
                   " is not after the previous one (", k == 0 ? 0.0 : stamp_s[k - 1], "): stamps must increase");
    const double norm = orientation[k].norm();
    FMCW_CHECK_ARG(std::abs(norm - 1.0) <= kUnitTolerance, "poses: pose ", k, " (t = ", stamp_s[k],
                   ") quaternion has norm ", norm, ", expected a unit quaternion");
  }
}

Eigen::Isometry3d PoseSeries::pose_at(double t) const {
  FMCW_CHECK_ARG(std::isfinite(t) && t >= stamp_s.front() && t <= stamp_s.back(), "poses: stamps [", stamp_s.front(),
                 ", ", stamp_s.back(), "] s do not cover t = ", t, " s");
  const std::size_t k = interval_of(stamp_s, t);
  const double a = (t - stamp_s[k]) / (stamp_s[k + 1] - stamp_s[k]);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = (1.0 - a) * position_m[k] + a * position_m[k + 1];
  T.linear() = orientation[k].normalized().slerp(a, orientation[k + 1].normalized()).toRotationMatrix();
  return T;
}

EgoMotion PoseSeries::ego_motion_at(double t) const {
  validate();
  FMCW_CHECK_ARG(std::isfinite(t) && t >= stamp_s.front() && t <= stamp_s.back(), "poses: stamps [", stamp_s.front(),
                 ", ", stamp_s.back(), "] s do not cover the scan stamp ", t, " s");
  // One pose interval on each side of t, clipped to the series.
  const std::size_t k = interval_of(stamp_s, t);
  const double step = stamp_s[k + 1] - stamp_s[k];
  const double ta = std::max(stamp_s.front(), t - step);
  const double tb = std::min(stamp_s.back(), t + step);
  const Eigen::Isometry3d A = pose_at(ta);
  const Eigen::Isometry3d B = pose_at(tb);
  const Eigen::Isometry3d T = pose_at(t);
  const Eigen::Vector3d v_world = (B.translation() - A.translation()) / (tb - ta);
  const Eigen::AngleAxisd turn(B.linear() * A.linear().transpose());  // world frame
  const Eigen::Vector3d w_world = turn.axis() * turn.angle() / (tb - ta);
  EgoMotion ego;
  ego.velocity_mps = T.linear().transpose() * v_world;
  ego.angular_velocity_rps = T.linear().transpose() * w_world;
  return ego;
}

void compensate_ego_velocity(Scan& scan, const EgoMotion& ego) {
  FMCW_CHECK_ARG(scan.velocity_frame == VelocityFrame::kSensor, "compensate_ego_velocity: the scan is already ego-compensated");
  shift_by_ego(scan, ego, +1.0);
  scan.velocity_frame = VelocityFrame::kEgoCompensated;
}

void uncompensate_ego_velocity(Scan& scan, const EgoMotion& ego) {
  FMCW_CHECK_ARG(scan.velocity_frame == VelocityFrame::kEgoCompensated,
                 "uncompensate_ego_velocity: the scan is not ego-compensated (its velocity is already the sensor's)");
  shift_by_ego(scan, ego, -1.0);
  scan.velocity_frame = VelocityFrame::kSensor;
}

void uncompensate_ego_velocity(Frame& frame, const EgoMotion& ego) {
  Scan& scan = frame.scan;
  uncompensate_ego_velocity(scan, ego);
  if (!frame.truth) return;
  std::vector<float>& truth_v = frame.truth->radial_velocity_mps;
  FMCW_CHECK_ARG(truth_v.size() == scan.valid.size(), "uncompensate_ego_velocity: the truth holds ",
                 truth_v.size(), " radial velocities for ", scan.valid.size(), " pixels");
  for_each_valid_beam(
      scan, ego, [&](std::size_t i, const Eigen::Vector3d& o, const Eigen::Vector3d& v_origin) {
        const Eigen::Vector3d e = (scan.position(i) - o).normalized();
        truth_v[i] = static_cast<float>(truth_v[i] - e.dot(v_origin));
      });
}

}  // namespace fmcw::core
