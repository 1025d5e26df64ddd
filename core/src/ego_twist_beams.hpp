#pragma once
// Internal to core: estimate_ego_twist on beams already computed for the scan.

#include <cstdint>
#include <vector>

#include "fmcw/core/ego_twist.hpp"
#include "scan_beams.hpp"

namespace fmcw::core {

constexpr int kCellCols = 24;  // the twist's coverage grid over the image
constexpr int kCellRows = 6;

// The valid points as rows of the twist problem, a = [e, (r x e)_z], target -v, stored by
// component so that the passes over them run two points per instruction.
struct TwistRows {
  std::vector<double> ex, ey, ez, ew;  // ew: the yaw-rate term
  std::vector<double> v;
  std::vector<std::uint16_t> cell;

  std::size_t size() const { return v.size(); }
  void clear() {
    for (auto* c : {&ex, &ey, &ez, &ew, &v}) c->clear();
    cell.clear();
  }
  void resize(std::size_t n) {
    for (auto* c : {&ex, &ey, &ez, &ew, &v}) c->resize(n);
    cell.resize(n);
  }
  void set(std::size_t k, double x, double y, double z, double w, double target, std::uint16_t c) {
    ex[k] = x;
    ey[k] = y;
    ez[k] = z;
    ew[k] = w;
    v[k] = target;
    cell[k] = c;
  }
  void push_back(double x, double y, double z, double w, double target, std::uint16_t c) {
    ex.push_back(x);
    ey.push_back(y);
    ez.push_back(z);
    ew.push_back(w);
    v.push_back(target);
    cell.push_back(c);
  }
  Eigen::Vector4d a(std::size_t k) const { return {ex[k], ey[k], ez[k], ew[k]}; }
};

/// Buffers estimate_ego_twist fills anew each frame: kept by the caller so that a sequence of
/// frames does not allocate (and fault in) megabytes per frame.
struct EgoTwistWorkspace {
  TwistRows rows;    ///< every valid point
  TwistRows sub;     ///< MSAC's seeded subset
  std::vector<double> r2;
};

/// Every valid pixel's row, in image order (ego_twist_rows.cpp).
void gather_rows(const Scan& scan, const ScanBeams& beams, TwistRows& rows);

EgoTwistEstimate estimate_ego_twist(const Scan& scan, const ScanBeams& beams, const EgoTwistParams& params,
                                    std::uint64_t seed, const TwistPrior* prior, EgoTwistWorkspace& ws);

}  // namespace fmcw::core
