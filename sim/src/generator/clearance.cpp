// Clearance between footprints: rectangles moved by trajectories, checked at frame times.

#include "clearance_index.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "fmcw/core/check.hpp"
#include "fmcw/sim/mesh_asset.hpp"
#include "fmcw/sim/scenario.hpp"

namespace fmcw::sim {

namespace {

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

// Distance from p to the segment ab.
double point_segment(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double len_sq = ab.squaredNorm();
  const double t = len_sq > 0.0 ? std::clamp((p - a).dot(ab) / len_sq, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

// True if the convex quadrilateral q (either winding) contains p.
bool contains(const std::array<Eigen::Vector2d, 4>& q, const Eigen::Vector2d& p) {
  bool pos = false, neg = false;
  for (int i = 0; i < 4; ++i) {
    const double c = cross(q[(i + 1) % 4] - q[i], p - q[i]);
    pos = pos || c > 0.0;
    neg = neg || c < 0.0;
  }
  return !(pos && neg);
}

bool segments_cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                    const Eigen::Vector2d& d) {
  const double d1 = cross(b - a, c - a), d2 = cross(b - a, d - a);
  const double d3 = cross(d - c, a - c), d4 = cross(d - c, b - c);
  return ((d1 > 0.0) != (d2 > 0.0)) && ((d3 > 0.0) != (d4 > 0.0));
}

}  // namespace

double rectangle_gap(const std::array<Eigen::Vector2d, 4>& a, const std::array<Eigen::Vector2d, 4>& b) {
  if (contains(a, b[0]) || contains(b, a[0])) return 0.0;
  double gap = 1e300;
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      if (segments_cross(a[i], a[(i + 1) % 4], b[j], b[(j + 1) % 4])) return 0.0;
    }
  }
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      gap = std::min({gap, point_segment(a[i], b[j], b[(j + 1) % 4]), point_segment(b[j], a[i], a[(i + 1) % 4])});
    }
  }
  return gap;
}

ClearanceIndex::ClearanceIndex(std::vector<double> times_s) : times_s_(std::move(times_s)) {
  FMCW_CHECK_ARG(!times_s_.empty(), "clearance: no times to check");
}

ClearanceIndex::Placed ClearanceIndex::place(const Footprint& body, double t_s) {
  FMCW_CHECK_ARG(!body.box.isEmpty(), "clearance: ", body.what, " has an empty footprint");
  const Eigen::Isometry3d T = body.motion ? body.motion->state(t_s).T_world_body : body.T_world_body;
  const Eigen::Vector2d lo = body.box.min(), hi = body.box.max();
  const std::array<Eigen::Vector2d, 4> local = {lo, Eigen::Vector2d(hi.x(), lo.y()), hi, Eigen::Vector2d(lo.x(), hi.y())};
  Placed out;
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector3d w = T * Eigen::Vector3d(local[i].x(), local[i].y(), 0.0);
    out.corners[i] = w.head<2>();
  }
  out.centre = 0.25 * (out.corners[0] + out.corners[1] + out.corners[2] + out.corners[3]);
  out.radius = 0.5 * (hi - lo).norm();
  return out;
}

void ClearanceIndex::add_fixed(const Footprint& body) {
  fixed_.push_back(place(body, times_s_.front()));
  fixed_bounds_.push_back(bounds({fixed_.back()}));
  fixed_names_.push_back(body.what);
}

std::vector<ClearanceIndex::Placed> ClearanceIndex::sweep(const Footprint& body) const {
  std::vector<Placed> out;
  out.reserve(times_s_.size());
  for (double t : times_s_) out.push_back(place(body, t));
  return out;
}

ClearanceResult ClearanceIndex::probe(const std::vector<Placed>& path, const std::string& what, double stop_below) const {
  ClearanceResult r;
  const auto consider = [&](const Placed& a, const Placed& b, const std::string& other, std::size_t k) {
    // The gap is at least the centres' distance less both circumscribed radii.
    if ((a.centre - b.centre).norm() - a.radius - b.radius >= r.min_clearance_m) return;
    const double gap = rectangle_gap(a.corners, b.corners);
    if (gap < r.min_clearance_m) {
      r.min_clearance_m = gap;
      r.first = what;
      r.second = other;
      r.time_s = times_s_[k];
    }
  };
  // Bodies whose boxes around all their positions are at least the smallest gap so far apart
  // cannot come closer: skipping them leaves the result exact.
  const Eigen::AlignedBox2d reach = bounds(path);
  std::vector<std::size_t> near_fixed, near_moving;
  for (std::size_t f = 0; f < fixed_.size(); ++f) {
    if (box_gap(reach, fixed_bounds_[f]) < r.min_clearance_m) near_fixed.push_back(f);
  }
  for (std::size_t m = 0; m < moving_.size(); ++m) {
    if (box_gap(reach, moving_bounds_[m]) < r.min_clearance_m) near_moving.push_back(m);
  }
  for (std::size_t k = 0; k < times_s_.size(); ++k) {
    for (std::size_t f : near_fixed) consider(path[k], fixed_[f], fixed_names_[f], k);
    for (std::size_t m : near_moving) consider(path[k], moving_[m][k], moving_names_[m], k);
    if (r.min_clearance_m < stop_below) return r;
  }
  return r;
}

Eigen::AlignedBox2d ClearanceIndex::bounds(const std::vector<Placed>& path) {
  Eigen::AlignedBox2d box;
  for (const Placed& p : path) {
    for (const Eigen::Vector2d& c : p.corners) box.extend(c);
  }
  return box;
}

double ClearanceIndex::box_gap(const Eigen::AlignedBox2d& a, const Eigen::AlignedBox2d& b) {
  const Eigen::Vector2d d = (a.min() - b.max()).cwiseMax(b.min() - a.max()).cwiseMax(0.0);
  return d.norm();
}

double ClearanceIndex::gap_to_fixed(const Footprint& body) const {
  const Placed a = place(body, times_s_.front());
  double gap = 1e300;
  for (const Placed& b : fixed_) {
    if ((a.centre - b.centre).norm() - a.radius - b.radius >= gap) continue;
    gap = std::min(gap, rectangle_gap(a.corners, b.corners));
  }
  return gap;
}

void ClearanceIndex::add_moving(std::vector<Placed> path, const std::string& what) {
  moving_bounds_.push_back(bounds(path));
  moving_.push_back(std::move(path));
  moving_names_.push_back(what);
}

ClearanceResult check_clearance(const std::vector<Footprint>& moving, const std::vector<Footprint>& fixed,
                                const std::vector<double>& times_s) {
  ClearanceIndex index(times_s);
  for (const Footprint& f : fixed) index.add_fixed(f);
  ClearanceResult worst;
  for (const Footprint& m : moving) {
    std::vector<ClearanceIndex::Placed> path = index.sweep(m);
    const ClearanceResult r = index.probe(path, m.what, -1.0);
    if (r.min_clearance_m < worst.min_clearance_m) worst = r;
    index.add_moving(std::move(path), m.what);
  }
  return worst;
}

Eigen::AlignedBox2d footprint_below(const MeshAsset& asset, const Eigen::Affine3d& T_body_asset, double max_z_m) {
  Eigen::AlignedBox2d box;
  const std::vector<Eigen::Affine3d> T = asset.rest_transforms();
  for (std::size_t k = 0; k < asset.parts.size(); ++k) {
    for (const Eigen::Vector3f& v : asset.rest_vertices(k, T)) {
      const Eigen::Vector3d p = T_body_asset * v.cast<double>();
      if (p.z() < max_z_m) box.extend(p.head<2>());
    }
  }
  return box;
}

ScenarioFootprints scenario_footprints(const LoadedScenario& loaded) {
  const Scenario& s = loaded.scenario;
  ScenarioFootprints out;
  Footprint ego;
  ego.what = "ego";
  ego.motion = s.ego.make();
  ego.box = Eigen::AlignedBox2d(Eigen::Vector2d(-0.5 * kEgoLength_m, -0.5 * kEgoWidth_m),
                                Eigen::Vector2d(0.5 * kEgoLength_m, 0.5 * kEgoWidth_m));
  out.moving.push_back(std::move(ego));
  for (std::size_t k = 0; k < s.actors.size(); ++k) {
    const ObjectSpec& a = s.actors[k];
    Footprint f;
    f.what = "actor " + std::to_string(a.id) + " (" + a.class_name + ")";
    f.motion = a.trajectory.make();
    f.box = footprint_below(*loaded.actor_meshes[k], a.T_body_asset, 1e300);
    out.moving.push_back(std::move(f));
  }
  for (std::size_t k = 0; k < s.statics.size(); ++k) {
    const ObjectSpec& o = s.statics[k];
    Footprint f;
    f.what = "static " + std::to_string(k) + " (" + o.mesh + ")";
    f.T_world_body = o.trajectory.pose;
    f.box = footprint_below(*loaded.static_meshes[k], o.T_body_asset, kFootprintHeight_m);
    if (f.box.isEmpty()) continue;  // nothing below the height: nothing to touch
    out.fixed.push_back(std::move(f));
  }
  return out;
}

}  // namespace fmcw::sim
