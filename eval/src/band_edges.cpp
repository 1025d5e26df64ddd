#include "fmcw/eval/band_edges.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "fmcw/core/check.hpp"

namespace fmcw::eval {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kDeg = M_PI / 180.0;

// Angle where the straight line through (a, ra) and (b, rb) crosses level.
double crossing(double a, double ra, double b, double rb, double level) {
  if (ra == rb) return 0.5 * (a + b);
  return a + (level - ra) * (b - a) / (rb - ra);
}
}  // namespace

BandEdges find_blind_band(const std::vector<double>& phi_deg, const std::vector<double>& recall, double level,
                          double centre_deg) {
  FMCW_CHECK_ARG(phi_deg.size() == recall.size(), "find_blind_band: ", phi_deg.size(), " angles but ", recall.size(),
                 " recall values");
  for (std::size_t k = 0; k < phi_deg.size(); ++k) {
    FMCW_CHECK_ARG(std::isfinite(phi_deg[k]) && std::isfinite(recall[k]), "find_blind_band: sample ", k,
                   " is not finite (phi ", phi_deg[k], ", recall ", recall[k], ")");
  }
  std::vector<std::size_t> order(phi_deg.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return phi_deg[a] < phi_deg[b]; });
  std::vector<double> phi, r;
  for (const std::size_t k : order) {
    phi.push_back(phi_deg[k]);
    r.push_back(recall[k]);
  }
  // Runs of consecutive samples below the level; pick the one holding, or nearest to, the centre.
  BandEdges out;
  double best_distance = std::numeric_limits<double>::infinity();
  std::size_t best_begin = 0, best_end = 0;
  for (std::size_t k = 0; k < r.size();) {
    if (r[k] >= level) {
      ++k;
      continue;
    }
    std::size_t e = k;
    while (e < r.size() && r[e] < level) ++e;
    const double distance = centre_deg < phi[k] ? phi[k] - centre_deg : (centre_deg > phi[e - 1] ? centre_deg - phi[e - 1] : 0.0);
    if (distance < best_distance) {
      best_distance = distance;
      best_begin = k;
      best_end = e;
    }
    k = e;
  }
  if (!std::isfinite(best_distance)) return out;
  out.found = true;
  out.lower_deg = best_begin == 0 ? kNaN : crossing(phi[best_begin - 1], r[best_begin - 1], phi[best_begin], r[best_begin], level);
  out.upper_deg = best_end == r.size() ? kNaN : crossing(phi[best_end - 1], r[best_end - 1], phi[best_end], r[best_end], level);
  return out;
}

BandEdges theoretical_blind_band(double speed_mps, double velocity_threshold_mps) {
  FMCW_CHECK_ARG(speed_mps >= 0.0 && velocity_threshold_mps > 0.0, "theoretical_blind_band: speed (", speed_mps,
                 ") must be >= 0 and v_th (", velocity_threshold_mps, ") > 0");
  BandEdges out;
  out.found = true;
  if (speed_mps <= velocity_threshold_mps) {
    out.lower_deg = 0.0;
    out.upper_deg = 180.0;
    return out;
  }
  out.lower_deg = std::acos(velocity_threshold_mps / speed_mps) / kDeg;
  out.upper_deg = 180.0 - out.lower_deg;
  return out;
}

}  // namespace fmcw::eval
