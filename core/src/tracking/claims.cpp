#include "claims.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "../vector_clones.hpp"

namespace fmcw::core::tracking {

namespace {

enum class Foreground { kUnknown, kNo, kYes };

// The carrying boxes' reach rectangles (centre +- half sides, world axes) by cell of a world
// grid: a point needs testing only against the boxes listed at its cell, in carrying order. A
// box is listed at every cell its rectangle, padded by a millimetre, overlaps, so a box whose
// rectangle holds the point is always listed at the point's cell: the same boxes pass the
// rectangle test as when every box is tested.
class BoxGrid {
 public:
  BoxGrid(const std::vector<Eigen::Vector2d>& centre, const std::vector<Eigen::Vector2d>& half) {
    constexpr double kPad = 1e-3;
    lo_ = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
    Eigen::Vector2d hi = -lo_;
    for (std::size_t n = 0; n < centre.size(); ++n) {
      lo_ = lo_.cwiseMin(centre[n] - half[n]);
      hi = hi.cwiseMax(centre[n] + half[n]);
    }
    lo_ -= Eigen::Vector2d::Constant(kPad);
    hi += Eigen::Vector2d::Constant(kPad);
    const Eigen::Vector2d extent = hi - lo_;
    cell_ = std::max(1.0, extent.maxCoeff() / 128.0);  // at most 129 x 129 cells
    nx_ = static_cast<int>(extent.x() / cell_) + 1;
    ny_ = static_cast<int>(extent.y() / cell_) + 1;
    cells_.assign(static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_), {});
    for (std::size_t n = 0; n < centre.size(); ++n) {
      const Eigen::Vector2d a = centre[n] - half[n] - Eigen::Vector2d::Constant(kPad);
      const Eigen::Vector2d b = centre[n] + half[n] + Eigen::Vector2d::Constant(kPad);
      for (int y = cell_y(a.y()); y <= cell_y(b.y()); ++y) {
        for (int x = cell_x(a.x()); x <= cell_x(b.x()); ++x) cells_[index(x, y)].push_back(static_cast<std::uint32_t>(n));
      }
    }
  }
  /// Per pixel i of the scan: the cell of its world point (R p + t) where it is static (label
  /// 0) and inside the grid, -1 elsewhere. A filter only: the cell is found with the
  /// reciprocal of the cell size, which may put a point a rounding away from a cell border in
  /// the neighbouring cell; every box is listed a millimetre beyond its rectangle, so the
  /// boxes whose rectangle holds the point are listed there too.
  void mark_candidates(const Scan& scan, const std::vector<std::int32_t>& labels, const Eigen::Matrix2d& R,
                       const Eigen::Vector2d& t, std::vector<std::int32_t>& out) const {
    out.resize(labels.size());
    const double m[6] = {R(0, 0), R(0, 1), R(1, 0), R(1, 1), t.x() - lo_.x(), t.y() - lo_.y()};
    cells_of(labels.size(), labels.data(), scan.x_m.data(), scan.y_m.data(), m, 1.0 / cell_, nx_, ny_, out.data());
  }
  /// The boxes listed at a cell mark_candidates gave.
  const std::vector<std::uint32_t>& listed_at(std::int32_t cell) const { return cells_[static_cast<std::size_t>(cell)]; }

 private:
  int cell_x(double x) const { return std::clamp(static_cast<int>(std::floor((x - lo_.x()) / cell_)), 0, nx_ - 1); }
  int cell_y(double y) const { return std::clamp(static_cast<int>(std::floor((y - lo_.y()) / cell_)), 0, ny_ - 1); }
  std::size_t index(int x, int y) const { return static_cast<std::size_t>(y) * static_cast<std::size_t>(nx_) + static_cast<std::size_t>(x); }

  Eigen::Vector2d lo_;
  double cell_ = 1.0;
  int nx_ = 1, ny_ = 1;
  std::vector<std::vector<std::uint32_t>> cells_;

  FMCW_VECTOR_CLONES static void cells_of(std::size_t n, const std::int32_t* labels, const float* x, const float* y,
                                          const double (&m)[6], double inv_cell, int nx, int ny, std::int32_t* out) {
    const double m0 = m[0], m1 = m[1], m2 = m[2], m3 = m[3], m4 = m[4], m5 = m[5];
    const double nxd = nx, nyd = ny;
    for (std::size_t i = 0; i < n; ++i) {
      const double qx = x[i], qy = y[i];
      const double fx = (m0 * qx + m1 * qy + m4) * inv_cell, fy = (m2 * qx + m3 * qy + m5) * inv_cell;
      const bool inside = (labels[i] == 0) & (fx >= 0.0) & (fy >= 0.0) & (fx < nxd) & (fy < nyd);  // false for NaN
      const double cx = inside ? fx : 0.0, cy = inside ? fy : 0.0;  // no conversion of NaN or far values
      const std::int32_t cell = static_cast<std::int32_t>(cy) * nx + static_cast<std::int32_t>(cx);
      out[i] = inside ? cell : -1;
    }
  }
};

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
  std::vector<Eigen::Vector2d> half_sides, centres;
  for (const std::size_t t : carrying) {
    const Box& b = boxes[t];
    const double l = b.half_l + reach;
    const double w = b.half_w + reach;
    half_sides.emplace_back(std::abs(b.u.x()) * l + std::abs(b.u.y()) * w, std::abs(b.u.y()) * l + std::abs(b.u.x()) * w);
    centres.push_back(b.centre);
  }
  const BoxGrid grid(centres, half_sides);
  std::vector<std::int32_t> candidate;
  grid.mark_candidates(frame.scan, est.labels, frame.R, frame.position, candidate);
  for (std::size_t i = 0; i < est.labels.size(); ++i) {
    if (candidate[i] < 0 || grid.listed_at(candidate[i]).empty()) continue;
    const Eigen::Vector3d q = frame.scan.position(i);
    const Eigen::Vector2d qw = frame.world_xy(q);
    Foreground fg = background_ready ? Foreground::kUnknown : Foreground::kNo;
    std::int32_t near_fg = -1;
    bool taken = false;
    for (const std::uint32_t n : grid.listed_at(candidate[i])) {
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
