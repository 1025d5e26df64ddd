#include "claims.hpp"

#include <cmath>

namespace fmcw::core::tracking {

namespace {
enum class Foreground { kUnknown, kNo, kYes };
}  // namespace

void claim_pixels(const Frame& frame, const MotionEstimate& est, const std::vector<Track>& tracks, const std::vector<Box>& boxes,
                  const BackgroundModel& background, const TrackerParams& p, std::vector<Group>& groups) {
  std::vector<std::size_t> carrying;
  for (std::size_t t = 0; t < tracks.size(); ++t) {
    if (tracks[t].carries(p)) carrying.push_back(t);
  }
  if (carrying.empty()) return;
  const bool background_ready = background.ready(p.background);
  const TrackerParams::Claims& pc = p.claims;
  // Each carrying box's reach, as half sides of an axis-aligned rectangle: a cheap first test.
  const double reach = std::max(pc.claim_margin_m, background_ready ? p.background.label_m : 0.0);
  std::vector<Eigen::Vector2d> half_sides;
  for (const std::size_t t : carrying) {
    const Box& b = boxes[t];
    const double l = b.half_l + reach;
    const double w = b.half_w + reach;
    half_sides.emplace_back(std::abs(b.u.x()) * l + std::abs(b.u.y()) * w, std::abs(b.u.y()) * l + std::abs(b.u.x()) * w);
  }
  for (std::size_t i = 0; i < est.labels.size(); ++i) {
    if (est.labels[i] != 0) continue;
    const Eigen::Vector3d q = frame.scan.position(i);
    const Eigen::Vector2d qw = frame.world_xy(q);
    Foreground fg = background_ready ? Foreground::kUnknown : Foreground::kNo;
    std::int32_t near_fg = -1;
    bool taken = false;
    for (std::size_t n = 0; n < carrying.size(); ++n) {
      const std::size_t t = carrying[n];
      const Eigen::Vector2d off = (qw - boxes[t].centre).cwiseAbs();
      if (off.x() > half_sides[n].x() || off.y() > half_sides[n].y()) continue;
      const Track& tr = tracks[t];
      if (q.z() < tr.z_min_m + pc.ground_clearance_m || q.z() > tr.z_max_m + pc.claim_margin_m) continue;
      if (fg != Foreground::kNo && near_fg < 0 && boxes[t].contains(qw, p.background.label_m)) {
        if (fg == Foreground::kUnknown)
          fg = background.foreground(frame.scan, i, p.background.margin_m) ? Foreground::kYes : Foreground::kNo;
        if (fg == Foreground::kYes) near_fg = static_cast<std::int32_t>(t);
      }
      if (!boxes[t].contains(qw, pc.claim_margin_m)) continue;
      const Row r = frame.row_of(static_cast<std::uint32_t>(i));
      if (std::abs(r.y - predicted(r, tr.x)) > pc.doppler_tolerance_mps) continue;
      groups[t].claimed.push_back(static_cast<std::uint32_t>(i));
      taken = true;
      break;
    }
    if (!taken && near_fg >= 0) groups[static_cast<std::size_t>(near_fg)].labelled.push_back(static_cast<std::uint32_t>(i));
  }
}

}  // namespace fmcw::core::tracking
