#include "track_box.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "fmcw/core/median.hpp"

namespace fmcw::core::tracking {

double Box::distance(const Eigen::Vector2d& q) const {
  const Eigen::Vector2d d = q - centre;
  const double a = std::max(0.0, std::abs(d.dot(u)) - half_l);
  const double b = std::max(0.0, std::abs(-d.x() * u.y() + d.y() * u.x()) - half_w);
  return std::hypot(a, b);
}

Box box_of(const Track& t) {
  Box b;
  b.centre = t.centre();
  b.u = Eigen::Vector2d(std::cos(t.heading_rad), std::sin(t.heading_rad));
  b.half_l = 0.5 * std::max(t.length_m, 0.4);
  b.half_w = 0.5 * std::max(t.width_m, 0.4);
  return b;
}

ViewEdges::ViewEdges(const Scan& scan, double occlusion_gap_m)
    : occlusion_gap_m_(occlusion_gap_m), edge_head_(static_cast<std::size_t>(scan.cols), -1) {
  for (std::size_t h = 0; h < scan.heads.size(); ++h) {
    edge_head_[static_cast<std::size_t>(scan.heads[h].col_begin)] = static_cast<int>(h);
    edge_head_[static_cast<std::size_t>(scan.heads[h].col_end - 1)] = static_cast<int>(h);
  }
}

void ViewEdges::add_cuts(const Frame& frame, std::uint32_t i, const Eigen::Vector2d& at, std::vector<Cut>& cuts) const {
  const Scan& scan = frame.scan;
  const int c = static_cast<int>(i % static_cast<std::uint32_t>(scan.cols));
  const int r = static_cast<int>(i / static_cast<std::uint32_t>(scan.cols));
  const int head = edge_head_[static_cast<std::size_t>(c)];
  const Eigen::Vector3d& origin = frame.beams.origin[static_cast<std::size_t>(c)];
  const Eigen::Vector3d ray = scan.position(i) - origin;
  const Eigen::Vector2d d = (frame.R * ray.head<2>()).normalized();
  const Eigen::Vector2d left(-d.y(), d.x());  // towards the lower columns (column 0 is the left edge)
  if (occlusion_gap_m_ > 0.0) {
    // A neighbour in the row, in the same head, nearer by the gap: something in front hides
    // what lies beyond this pixel on that side.
    const double range = ray.norm();
    const auto occludes = [&](int nc) {
      if (nc < 0 || nc >= scan.cols) return false;
      const std::size_t j = scan.index(r, nc);
      return scan.valid[j] && frame.beams.origin[static_cast<std::size_t>(nc)] == origin &&
             (scan.position(j) - origin).norm() < range - occlusion_gap_m_;
    };
    if (occludes(c - 1)) cuts.push_back({left, at});
    if (occludes(c + 1)) cuts.push_back({-left, at});
  }
  if (head < 0 && r != 0 && r != scan.rows - 1) return;
  if (head >= 0) {
    const Eigen::Vector2d axis = frame.R * scan.heads[static_cast<std::size_t>(head)].T_rig_head.linear().col(0).head<2>();
    cuts.push_back({left.dot(axis) > 0.0 ? Eigen::Vector2d(-left) : left, at});
  }
  if (r == scan.rows - 1) cuts.push_back({-d, at, false});
  if (r == 0) cuts.push_back({d, at, false});
}

namespace {

// The box's heading from the velocity once the object moves. Extents measured along a heading
// that has since swung, beyond what the yaw rate turned the body (a poor first velocity,
// corrected over a few frames), say nothing about the box along the new one: returns whether
// they are to be measured afresh, with the swing (the heading's, from the extents' axis) [rad].
bool update_heading(Track& tr, bool born, const TrackerParams::Box& p, double& swing) {
  const Eigen::Vector2d v = tr.velocity();
  bool resize = born;
  swing = 0.0;
  if (v.norm() > 1.0) {
    const double heading = std::atan2(v.y(), v.x());
    swing = std::abs(std::remainder(heading - tr.extents_heading_rad, 2.0 * M_PI));
    resize = resize || swing > p.heading_reset_rad;
    tr.heading_rad = heading;
  }
  if (resize) tr.extents_heading_rad = tr.heading_rad;
  return resize;
}

// The outline's points in the world plane, relative to their mean, with its extents along the
// box axes, its heights and the view's cuts.
struct Outline {
  Eigen::Vector2d ref = Eigen::Vector2d::Zero();
  std::vector<Eigen::Vector2d> pts;
  std::vector<Cut> cuts;
  double a0 = 0.0, a1 = 0.0, b0 = 0.0, b1 = 0.0;  // extents along u and across it, about ref
  double zmin = std::numeric_limits<double>::infinity();
  double zmax = -std::numeric_limits<double>::infinity();
};

constexpr double kInf = std::numeric_limits<double>::infinity();

// Of the values, the lowest that is no stray: of the m + 1 lowest, the one after the last gap
// wider than gap_m among them (none: -inf). Reorders v.
double lowest_kept(std::vector<double>& v, std::size_t m, double gap_m) {
  const auto k = static_cast<std::ptrdiff_t>(m + 1);
  std::nth_element(v.begin(), v.begin() + k - 1, v.end());
  std::sort(v.begin(), v.begin() + k);
  double lo = -kInf;
  for (std::ptrdiff_t j = 0; j + 1 < k; ++j) {
    if (v[j + 1] - v[j] > gap_m) lo = v[j + 1];
  }
  return lo;
}

// Where stray pixels may lie along one axis: below `lo` or above `hi`. Of the share of the values
// nearest each end (the two ends' shares apart), those beyond the last gap wider than gap_m
// there (none: -inf or +inf).
std::pair<double, double> stray_bounds(std::vector<double> v, double gap_m, double share) {
  const auto m = static_cast<std::size_t>(share * static_cast<double>(v.size()));
  if (gap_m <= 0.0 || m == 0 || 2 * (m + 1) > v.size()) return {-kInf, kInf};
  const double lo = lowest_kept(v, m, gap_m);
  for (double& x : v) x = -x;  // the highest end, as the lowest of the negated values
  return {lo, -lowest_kept(v, m, gap_m)};
}

// Where an outline is searched for a vehicle's stray pixels (TrackerParams::Box): along an axis
// where it is longer than these, among the share of its pixels nearest each end.
struct StraySearch {
  double length_m = kInf;
  double width_m = kInf;
  double share = 0.0;
};

// Any vehicle's outline is searched where it is longer than any body; a settled box's also where
// it is longer than the box itself (Box::own_stray_share).
StraySearch stray_search(const Track& tr, bool born, bool resize, const TrackerParams::Box& p) {
  StraySearch s{p.max_length_m, p.max_width_m, p.stray_share};
  if (p.own_stray_share > 0.0 && !born && !resize && !tr.walker &&
      tr.updates_settled >= p.own_stray_settled_updates) {
    s.length_m =
        std::min(s.length_m, std::max(tr.length_m + p.stray_gap_m, p.own_stray_min_length_m));
    s.width_m = std::min(s.width_m, tr.width_m + p.stray_gap_m);
    s.share = std::max(s.share, p.own_stray_share);
  }
  return s;
}

// The outline of the pixels; strays: leave out a vehicle's stray pixels (TrackerParams::Box)
// where search finds them.
Outline outline_of(const std::vector<std::uint32_t>& pixels, const Frame& frame,
                   const ViewEdges& edges, const Eigen::Vector2d& u, const Eigen::Vector2d& wv,
                   const TrackerParams::Box& p, bool strays, const StraySearch& search) {
  Outline o;
  o.pts.reserve(pixels.size());
  for (const std::uint32_t i : pixels) {
    const Eigen::Vector3d q = frame.scan.position(i);
    o.pts.push_back(frame.world_xy(q));
    edges.add_cuts(frame, i, o.pts.back(), o.cuts);
    o.ref += o.pts.back();
    o.zmin = std::min(o.zmin, q.z());
    o.zmax = std::max(o.zmax, q.z());
  }
  o.ref /= static_cast<double>(std::max<std::size_t>(pixels.size(), 1));
  const auto extents = [&](double a_lo, double a_hi, double b_lo, double b_hi) {
    o.a0 = o.a1 = o.b0 = o.b1 = 0.0;
    for (const Eigen::Vector2d& q : o.pts) {
      const double a = (q - o.ref).dot(u);
      const double b = (q - o.ref).dot(wv);
      if (a < a_lo || a > a_hi || b < b_lo || b > b_hi) continue;
      o.a0 = std::min(o.a0, a);
      o.a1 = std::max(o.a1, a);
      o.b0 = std::min(o.b0, b);
      o.b1 = std::max(o.b1, b);
    }
  };
  extents(-kInf, kInf, -kInf, kInf);
  // Stray pixels: beyond a gap at an end of an axis, stretching the extent along it past what
  // any body measures (Box: max_length_m, max_width_m), or past a settled box's own size.
  const bool long_a = o.a1 - o.a0 > search.length_m, long_b = o.b1 - o.b0 > search.width_m;
  if (!strays || !(long_a || long_b)) return o;
  std::vector<double> along(o.pts.size()), across(o.pts.size());
  for (std::size_t k = 0; k < o.pts.size(); ++k) {
    along[k] = (o.pts[k] - o.ref).dot(u);
    across[k] = (o.pts[k] - o.ref).dot(wv);
  }
  const std::pair<double, double> none{-kInf, kInf};
  const auto [a_lo, a_hi] = long_a ? stray_bounds(along, p.stray_gap_m, search.share) : none;
  const auto [b_lo, b_hi] = long_b ? stray_bounds(across, p.stray_gap_m, search.share) : none;
  extents(a_lo, a_hi, b_lo, b_hi);
  return o;
}

// Where the centre is measured along one box axis: the middle of the outline, or one end of it
// (the other end is not seen, and what grows the extent appears there).
struct Anchor {
  double centre = 0.0;  ///< along the axis, relative to the outline's ref [m]
  int end = 0;          ///< -1: at lo, +1: at hi, 0: the middle or the predicted centre
  bool cut = false;     ///< an end is cut sideways: by a head's column edge or an occluder
};

// Less than the whole size seen along an axis: the centre lies in [hi - size/2, lo + size/2].
// An end of the outline is the body's own where the sensor sees that face or the silhouette,
// unless the view cuts it there (a car beside the ego, its rear beyond a head's edge). Anchored
// at such an end; with none, the predicted centre (pc, relative to ref), brought into the
// interval, stands for the measurement. s: the sensor relative to ref.
// Which ends of the outline along an axis (lo, hi: relative to its ref) the view or an occluder
// cuts: a cut counts at the end its pixel lies at, within near_end of it, pointing out of that
// end (a seam between stitched heads runs through an object that spans it, away from its ends).
// sideways: a cut at either end is sideways; with sideways_only, only sideways cuts count.
struct EndCuts {
  bool lo = false, hi = false, sideways = false;
};

EndCuts end_cuts(const Outline& o, const Eigen::Vector2d& axis, double lo, double hi,
                 double near_end, double cosine, bool sideways_only) {
  EndCuts e;
  for (const Cut& cut : o.cuts) {
    if (sideways_only && !cut.sideways) continue;
    const double along = (cut.at - o.ref).dot(axis);
    const bool lo_here = cut.direction.dot(axis) < -cosine && along <= lo + near_end;
    const bool hi_here = cut.direction.dot(axis) > cosine && along >= hi - near_end;
    e.lo = e.lo || lo_here;
    e.hi = e.hi || hi_here;
    e.sideways = e.sideways || (cut.sideways && (lo_here || hi_here));
  }
  return e;
}

Anchor anchor(const Outline& o, const Eigen::Vector2d& axis, double lo, double hi, double size,
              const Eigen::Vector2d& s, const Eigen::Vector2d& pc, bool born,
              const TrackerParams::Box& p) {
  const EndCuts cuts =
      end_cuts(o, axis, lo, hi, p.view_cut_end_m + 0.05 * (hi - lo), p.view_cut_cosine, false);
  const bool cut_lo = cuts.lo, cut_hi = cuts.hi, sideways = cuts.sideways;
  const double sensor = s.dot(axis);
  const bool lo_own = !cut_lo && sensor <= hi;
  const bool hi_own = !cut_hi && sensor >= lo;
  // The whole size seen: the middle, but an end the body does not own may still hide more of it
  // (a car entering the view grows at its cut end: the extent seen is then the largest yet).
  if (lo_own && hi_own) return {0.5 * (lo + hi), 0, sideways};
  if (lo_own) return {lo + 0.5 * std::max(size, hi - lo), -1, sideways};
  if (hi_own) return {hi - 0.5 * std::max(size, hi - lo), 1, sideways};
  if (born || hi - lo >= size) return {0.5 * (lo + hi), 0, sideways};
  return {std::clamp(pc.dot(axis), hi - 0.5 * size, lo + 0.5 * size), 0, sideways};
}

// A small, slow track that is not yet a walker, across the line of sight: where one edge of its
// outline is cut sideways (an occluder beside it, a head's edge) and the other is not, the uncut
// edge is its silhouette and the centre lies half its width inward from it. Its width: the widest
// its outline has shown across the sight (Track::across_extent_m, under small_object_m). Its
// edges leave out a few pixels beyond a gap (Small::silhouette_stray_gap_m): a neighbour's hand
// chained into its cluster is not its silhouette. A walker coming into a head's view at its
// edge, or out from behind something nearer, shows a sliver that grows: its middle lies off the
// body's by half of what is still hidden, and moves slower than the body while it grows. A width
// that grew grew at the cut edge: the prediction moves with half the growth, as a vehicle's does
// (at the first update after birth that measures it, the whole width counts as grown).
void centre_from_silhouette(Track& tr, const Outline& o, bool born, const Frame& frame,
                            const TrackerParams& p, Eigen::Vector2d& centre) {
  const Eigen::Vector2d d = (o.ref - frame.position).normalized();
  const Eigen::Vector2d t(-d.y(), d.x());  // across the line of sight
  std::vector<double> across;
  across.reserve(o.pts.size());
  for (const Eigen::Vector2d& q : o.pts) across.push_back((q - o.ref).dot(t));
  // The edges, a neighbour's stray pixels left out (Small::silhouette_stray_gap_m).
  const auto [lo, hi] =
      stray_bounds(across, p.small.silhouette_stray_gap_m, p.small.silhouette_stray_share);
  double t0 = kInf, t1 = -kInf;
  for (const double v : across) {
    if (v < lo || v > hi) continue;
    t0 = std::min(t0, v);
    t1 = std::max(t1, v);
  }
  const EndCuts cuts = end_cuts(o, t, t0, t1, 0.05 + 0.1 * (t1 - t0), p.box.view_cut_cosine, true);
  const bool cut0 = cuts.lo, cut1 = cuts.hi;
  const double before = born ? 0.0 : tr.across_extent_m;
  tr.across_extent_m =
      std::min(std::max(before, t1 - t0), std::nextafter(p.small.small_object_m, 0.0));
  if (cut0 == cut1) return;
  const double w = std::max(tr.across_extent_m, t1 - t0);
  const double centre_t = cut0 ? t1 - 0.5 * w : t0 + 0.5 * w;
  centre += (centre_t - (centre - o.ref).dot(t)) * t;
  if (!born) {
    const double side = cut0 ? -1.0 : 1.0;  // the cut edge
    tr.x.head<2>() += 0.5 * std::max(0.0, tr.across_extent_m - before) * side * t;
  }
}

}  // namespace

BoxMeasurement measure_box(Track& tr, const Group& g, bool born, const Frame& frame, const ViewEdges& edges,
                           const TrackerParams& p) {
  double swing = 0.0;
  const bool resize = update_heading(tr, born, p.box, swing);
  const Eigen::Vector2d u(std::cos(tr.heading_rad), std::sin(tr.heading_rad));
  const Eigen::Vector2d wv(-u.y(), u.x());
  // The box is measured on the pixels one scan found moving. When the track claimed more than
  // one scan found moving, what moved is a Doppler slice of the object (the rest is in the blind
  // band), not its visible outline: the box is then left as predicted. A small object wholly
  // inside the band (a walker crossing the beams) is found by its claims alone; they lie in its
  // predicted box, which is tight, and give its centre (not its size).
  const bool small_track = tr.small(p);
  BoxMeasurement m;
  m.centre_from_claims = !born && g.found.empty() && !g.claimed.empty() && small_track;
  static const std::vector<std::uint32_t> kNone;
  const std::vector<std::uint32_t>& pixels = m.centre_from_claims                    ? g.claimed
                                             : born || g.claimed.size() <= g.found.size() ? g.found
                                                                                          : kNone;
  m.centre = tr.centre();
  m.seen = !pixels.empty();
  tr.seen_extent_m = std::max(tr.length_m, tr.width_m);
  if (!m.seen) return m;
  // Strays are left out of a vehicle's box, not out of a walker's or a group of walkers' (a
  // walker at the end of a row is no stray).
  const bool strays = tr.velocity().norm() > p.small.walker_max_speed_mps;
  const Outline o =
      outline_of(pixels, frame, edges, u, wv, p.box, strays, stray_search(tr, born, resize, p.box));
  const double length_before = tr.length_m;
  const double width_before = tr.width_m;
  if (!m.centre_from_claims) {
    // A walker stays small (at most walker_box_m, under small_object_m: the limbs reach out of
    // its box).
    const double walker_cap =
        std::min(p.small.walker_box_m, std::nextafter(p.small.small_object_m, 0.0));
    const double cap_l = tr.walker ? walker_cap : p.box.max_length_m;
    const double cap_w = tr.walker ? walker_cap : p.box.max_width_m;
    tr.seen_extent_m = std::max(o.a1 - o.a0, o.b1 - o.b0);
    // A heading swing re-measures the box along the new axis, but a vehicle does not change
    // size: the extents it had, a box around its body turned by the swing, bound its length and
    // width from below (l >= L cos(swing) - W sin(swing), and so the width). A bus seen end-on
    // as its heading swings would otherwise shrink to the face it shows, its box a sliver left
    // at its old centre, metres from its pixels.
    double lo_l = 0.0;
    double lo_w = 0.0;
    if (resize && !born && swing < 0.25 * M_PI && !tr.walker && tr.vehicle(p) &&
        tr.velocity().norm() > p.small.walker_max_speed_mps) {
      lo_l = length_before * std::cos(swing) - width_before * std::sin(swing);
      lo_w = width_before * std::cos(swing) - length_before * std::sin(swing);
    }
    tr.length_m =
        std::min(resize ? std::max(o.a1 - o.a0, lo_l) : std::max(tr.length_m, o.a1 - o.a0), cap_l);
    tr.width_m =
        std::min(resize ? std::max(o.b1 - o.b0, lo_w) : std::max(tr.width_m, o.b1 - o.b0), cap_w);
    tr.z_min_m = o.zmin;  // this frame's: the ground under an object changes at curbs
    // A walker inside the band shows only its swinging limbs: its top stays where it was.
    tr.z_max_m = small_track && !born ? std::max(o.zmax, tr.z_max_m) : o.zmax;
  }
  if (tr.walker) {
    std::vector<double> cu, cw;
    cu.reserve(o.pts.size());
    cw.reserve(o.pts.size());
    for (const Eigen::Vector2d& q : o.pts) {
      cu.push_back((q - o.ref).dot(u));
      cw.push_back((q - o.ref).dot(wv));
    }
    m.centre = o.ref + upper_median(cu) * u + upper_median(cw) * wv;
  } else {
    const Eigen::Vector2d s = frame.position - o.ref;  // the sensor, relative to ref
    const Eigen::Vector2d pc = tr.centre() - o.ref;
    const Anchor along = anchor(o, u, o.a0, o.a1, tr.length_m, s, pc, born, p.box);
    const Anchor across = anchor(o, wv, o.b0, o.b1, tr.width_m, s, pc, born, p.box);
    m.centre = o.ref + along.centre * u + across.centre * wv;
    tr.outline_cut = along.cut || across.cut;
    // Measured from one end, an extent that grew grew at the other end: the box's centre, what
    // the track's position stands for, moves by half the growth away from the anchored end. The
    // prediction moves with it, so the growth is no innovation (a car entering the view would
    // otherwise seem to slow down and, seen from the side, to turn). Not at a walker's speed: a
    // group of walkers grows and shrinks as they part and meet, and its centre is measured.
    if (!resize && tr.velocity().norm() > p.small.walker_max_speed_mps) {
      tr.x.head<2>() -= 0.5 * ((tr.length_m - length_before) * along.end * u + (tr.width_m - width_before) * across.end * wv);
    }
    if (p.small.centre_from_silhouette && !m.centre_from_claims && small_track &&
        tr.velocity().norm() <= p.small.walker_max_speed_mps) {
      centre_from_silhouette(tr, o, born, frame, p, m.centre);
    }
  }
  return m;
}

}  // namespace fmcw::core::tracking
