#include "layouts.hpp"

#include <algorithm>
#include <cmath>

#include "fmcw/core/check.hpp"

namespace fmcw::sim::gen {

namespace {

constexpr double kStep_m = 1.0;  // spacing of the dense centre lines

Vec2 dir(double a) { return {std::cos(a), std::sin(a)}; }
Vec2 left_of(const Vec2& u) { return {-u.y(), u.x()}; }
double heading(const Vec2& v) { return std::atan2(v.y(), v.x()); }
double deg(double d) { return d * M_PI / 180.0; }

void add_point(std::vector<Vec2>& out, const Vec2& p) {
  if (out.empty() || (out.back() - p).norm() > 1e-6) out.push_back(p);
}

void add_line(std::vector<Vec2>& out, const Vec2& a, const Vec2& b) {
  const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / kStep_m)));
  for (int k = 0; k <= n; ++k) add_point(out, a + (b - a) * (static_cast<double>(k) / n));
}

// Arc about c of radius r from angle a0 sweeping by `sweep` (positive: counter-clockwise).
void add_arc(std::vector<Vec2>& out, const Vec2& c, double r, double a0, double sweep) {
  const int n = std::max(2, static_cast<int>(std::ceil(std::abs(sweep) * r / kStep_m)));
  for (int k = 0; k <= n; ++k) add_point(out, c + r * dir(a0 + sweep * k / n));
}

// Cubic Hermite from p0 to p1 with unit tangents t0, t1 scaled by the chord.
void add_hermite(std::vector<Vec2>& out, const Vec2& p0, const Vec2& t0, const Vec2& p1, const Vec2& t1) {
  const double len = (p1 - p0).norm();
  const int n = std::max(4, static_cast<int>(std::ceil(2.0 * len / kStep_m)));
  Vec2 last = p0;
  for (int k = 0; k <= n; ++k) {
    const double t = static_cast<double>(k) / n, t2 = t * t, t3 = t2 * t;
    const Vec2 p = (2 * t3 - 3 * t2 + 1) * p0 + (t3 - 2 * t2 + t) * len * t0 + (-2 * t3 + 3 * t2) * p1 +
                   (t3 - t2) * len * t1;
    if (k == n || (p - last).norm() >= 0.5 * kStep_m) {
      add_point(out, p);
      last = p;
    }
  }
}

// Line from `from` heading h_in, a circular fillet of radius r, then heading h_out to `to`
// (which lies on the outgoing line).
void add_fillet(std::vector<Vec2>& out, const Vec2& from, const Vec2& h_in, const Vec2& to, const Vec2& h_out, double r) {
  // Intersection of from + a h_in and to - b h_out.
  const double det = h_in.x() * (-h_out.y()) - h_in.y() * (-h_out.x());
  FMCW_CHECK_ARG(std::abs(det) > 1e-9, "generator: a fillet between parallel lines");
  const Vec2 d = to - from;
  const double a = (d.x() * (-h_out.y()) - d.y() * (-h_out.x())) / det;
  const Vec2 x = from + a * h_in;
  const double turn = std::atan2(h_in.x() * h_out.y() - h_in.y() * h_out.x(), h_in.dot(h_out));
  const double t = r * std::tan(0.5 * std::abs(turn));
  const Vec2 start = x - t * h_in, end = x + t * h_out;
  const Vec2 n = turn > 0 ? left_of(h_in) : Vec2(-left_of(h_in));
  const Vec2 c = start + r * n;
  add_line(out, from, start);
  add_arc(out, c, r, heading(start - c), turn);
  add_line(out, end, to);
}

// One road arm leaving the origin at angle phi: distance d along it, lateral offset to its left.
struct Arm {
  double phi = 0.0;
  double d0 = 0.0;       // where its own lanes begin (the junction's edge)
  double d_cross = 0.0;  // its crossing; < 0: none
  double d_stop = 0.0;   // its stop line
  Vec2 u, v;
  Vec2 at(double d, double lateral) const { return d * u + lateral * v; }
};

Arm make_arm(double phi, double d0, double d_cross, double d_stop) {
  Arm a;
  a.phi = phi;
  a.d0 = d0;
  a.d_cross = d_cross;
  a.d_stop = d_stop;
  a.u = dir(phi);
  a.v = left_of(a.u);
  return a;
}

double lane_lateral(int i) { return (i + 0.5) * kLaneWidth_m; }

// Route in along arm a's lane i (from distance `length`), then out along arm b's lane j.
Route arm_route(const Arm& a, int i, const Arm& b, int j, double length, double turn_at, const std::string& kind) {
  Route r;
  r.kind = kind;
  const Vec2 from = a.at(length, lane_lateral(i)), h_in = -a.u;
  const Vec2 to = b.at(length, -lane_lateral(j)), h_out = b.u;
  if (kind == "straight") {
    add_line(r.pts, from, to);
  } else {
    // Radius so that the turn begins at turn_at along arm a.
    const double det = h_in.x() * (-h_out.y()) - h_in.y() * (-h_out.x());
    const Vec2 d = to - from;
    const double s = (d.x() * (-h_out.y()) - d.y() * (-h_out.x())) / det;
    const Vec2 x = from + s * h_in;
    const double radius = std::max(3.0, turn_at - x.dot(a.u));
    add_fillet(r.pts, from, h_in, to, h_out, radius);
  }
  r.stop_s = a.d_stop >= 0.0 ? length - a.d_stop : -1.0;
  return r;
}

// Straight along arm a's lane i, moving from lane i to lane k between distances d1 > d2.
Route lane_change_route(const Arm& a, int i, int k, const Arm& b, double length, double d1, double d2) {
  Route r;
  r.kind = "lane_change";
  add_line(r.pts, a.at(length, lane_lateral(i)), a.at(d1, lane_lateral(i)));
  add_hermite(r.pts, a.at(d1, lane_lateral(i)), -a.u, a.at(d2, lane_lateral(k)), -a.u);
  add_line(r.pts, a.at(d2, lane_lateral(k)), b.at(length, -lane_lateral(k)));
  r.stop_s = a.d_stop >= 0.0 ? length - a.d_stop : -1.0;
  return r;
}

double yaw_of(const Vec2& v) { return heading(v); }

// A straight route through, and on the outer lane a cyclists' route at its right edge.
void add_straight(Layout& out, const Route& r, const Arm& a, const Arm& b, int i, double length) {
  out.routes.push_back(r);
  if (!r.outermost) return;
  Route bike;
  bike.kind = "straight";
  add_line(bike.pts, a.at(length, lane_lateral(i) + 0.9), b.at(length, -lane_lateral(i) - 0.9));
  bike.stop_s = r.stop_s;
  out.bike_routes.push_back(bike);
}

// Walkways, crossings, parking, and static slots along one arm whose lanes reach `edge` (the
// curb: driving lanes plus parking) and that runs from d_begin to d_end.
void dress_arm(Layout& out, const Arm& a, int lanes, bool parking, double d_begin, double d_end, bool incoming_sign,
               std::mt19937_64& rng) {
  const double edge = lanes * kLaneWidth_m + (parking ? kParkingWidth_m : 0.0);
  for (double side : {1.0, -1.0}) {
    for (double off : {1.7, 3.0}) {
      out.walkways.push_back({a.at(d_begin + 1.0, side * (edge + off)), a.at(d_end, side * (edge + off))});
    }
    out.sidewalk_length_m += d_end - d_begin - 1.0;
    // Parking bays beside the outer lane, heading with its traffic.
    if (parking) {
      const double lat = side * (lanes * kLaneWidth_m + 0.5 * kParkingWidth_m);
      const double yaw = yaw_of(side > 0 ? Vec2(-a.u) : a.u);
      for (double d = d_begin + 12.0; d < d_end - 10.0; d += 6.5) out.parking.push_back({a.at(d, lat), yaw});
    }
    // Poles at the curb, their arm over the road; trees behind the sidewalk; buildings set back.
    const double pole_yaw = yaw_of(side > 0 ? Vec2(-a.v) : a.v);
    const double pole_step = uniform(rng, 25.0, 40.0);
    for (double d = d_begin + uniform(rng, 6.0, 15.0); d < d_end; d += pole_step) {
      if (a.d_cross >= 0.0 && std::abs(d - a.d_cross) < 4.0) continue;
      out.poles.push_back({a.at(d, side * (edge + 0.6)), pole_yaw});
    }
    const double tree_step = uniform(rng, 8.0, 15.0);
    for (double d = d_begin + uniform(rng, 3.0, 9.0); d < d_end; d += tree_step) {
      if (uniform(rng, 0.0, 1.0) < 0.75) out.trees.push_back({a.at(d, side * (edge + kSidewalkWidth_m + 2.0)), 0.0});
    }
    for (double d = d_begin + uniform(rng, 8.0, 14.0); d < d_end - 5.0;) {
      const double half = uniform(rng, 0.0, 1.0) < 0.7 ? 5.0 : 7.5;  // block or tower
      const double setback = uniform(rng, 5.0, 12.0);
      out.buildings.push_back({a.at(d + half, side * (edge + kSidewalkWidth_m + setback + half)), a.phi});
      d += 2.0 * half + uniform(rng, 3.0, 15.0);
    }
  }
  // A sign facing the incoming traffic before its stop line.
  if (incoming_sign && a.d_stop >= 0.0) out.signs.push_back({a.at(a.d_stop + 4.0, edge + 0.6), yaw_of(-a.v)});
}

Layout junction_layout(const std::string& name, std::vector<double> arm_deg, int lanes, bool parking, std::mt19937_64& rng) {
  Layout out;
  out.name = name;
  out.lanes_per_direction = lanes;
  const double length = 200.0;
  const double edge = lanes * kLaneWidth_m + (parking ? kParkingWidth_m : 0.0);
  const double d0 = edge + kSidewalkWidth_m;
  const double d_cross = edge + 2.0;
  const double d_stop = d_cross + 2.5;
  std::vector<Arm> arms;
  for (double a : arm_deg) arms.push_back(make_arm(deg(a), d0, d_cross, d_stop));
  for (const Arm& a : arms) {
    for (const Arm& b : arms) {
      const double turn = std::remainder(b.phi - a.phi, 2.0 * M_PI);
      for (int i = 0; i < lanes; ++i) {
        if (std::abs(std::abs(turn) - M_PI) < 1e-6) {
          Route r = arm_route(a, i, b, i, length, d_stop, "straight");
          r.outermost = i == lanes - 1;
          add_straight(out, r, a, b, i, length);
          if (lanes >= 2) {
            const int k = i == 0 ? 1 : i - 1;
            const double d1 = uniform(rng, d_stop + 60.0, length - 30.0);
            out.routes.push_back(lane_change_route(a, i, k, b, length, d1, d1 - uniform(rng, 30.0, 45.0)));
          }
        } else if (std::abs(turn - M_PI / 2) < 1e-6 && i == lanes - 1) {
          // b is 90 degrees counter-clockwise of a: coming in along a, that is a right turn.
          Route r = arm_route(a, i, b, i, length, d_stop, "right");
          r.outermost = true;
          out.routes.push_back(r);
        } else if (std::abs(turn + M_PI / 2) < 1e-6 && i == 0) {
          out.routes.push_back(arm_route(a, i, b, i, length, d_stop, "left"));
        }
      }
    }
    dress_arm(out, a, lanes, parking, d0, length, true, rng);
    out.crossings.push_back({a.at(d_cross, -(edge + 0.5)), a.at(d_cross, edge + 1.0)});
    out.crossings.push_back({a.at(d_cross, edge + 0.5), a.at(d_cross, -(edge + 1.0))});
  }
  out.lane_length_m = arms.size() * 2.0 * lanes * (length - d0);
  out.extent_m = length + 10.0;
  return out;
}

Layout straight_layout(int lanes, bool parking, std::mt19937_64& rng) {
  Layout out;
  out.name = "straight_road";
  out.lanes_per_direction = lanes;
  const double length = 200.0;
  const double edge = lanes * kLaneWidth_m + (parking ? kParkingWidth_m : 0.0);
  // A mid-block crossing ahead of the origin, with stop lines 3 m before it both ways.
  const double x_cross = uniform(rng, 15.0, 45.0);
  const Arm east = make_arm(0.0, 0.0, -1.0, -1.0), west = make_arm(M_PI, 0.0, -1.0, -1.0);
  for (int i = 0; i < lanes; ++i) {
    for (int dirn = 0; dirn < 2; ++dirn) {
      const Arm& a = dirn == 0 ? west : east;  // coming in along a (from its far end)
      const Arm& b = dirn == 0 ? east : west;
      Route r = arm_route(a, i, b, i, length, 0.0, "straight");
      // The crossing is at x_cross: arc length from the start at -length (eastbound) or +length.
      r.stop_s = dirn == 0 ? length + x_cross - 3.0 : length - x_cross - 3.0;
      r.outermost = i == lanes - 1;
      add_straight(out, r, a, b, i, length);
      if (lanes >= 2) {
        const int k = i == 0 ? 1 : i - 1;
        const double d1 = uniform(rng, 40.0, length - 20.0);
        Route lc = lane_change_route(a, i, k, b, length, d1, d1 - uniform(rng, 30.0, 45.0));
        lc.stop_s = r.stop_s;
        out.routes.push_back(lc);
      }
    }
  }
  dress_arm(out, east, lanes, parking, 0.0, length, false, rng);
  dress_arm(out, west, lanes, parking, 0.0, length, false, rng);
  out.crossings.push_back({Vec2(x_cross, -(edge + 0.5)), Vec2(x_cross, edge + 1.0)});
  out.crossings.push_back({Vec2(x_cross, edge + 0.5), Vec2(x_cross, -(edge + 1.0))});
  out.signs.push_back({Vec2(x_cross - 6.0, -(edge + 0.6)), M_PI / 2});
  out.signs.push_back({Vec2(x_cross + 6.0, edge + 0.6), -M_PI / 2});
  out.lane_length_m = 2.0 * lanes * 2.0 * length;
  out.extent_m = length + 10.0;
  return out;
}

Layout roundabout_layout(std::mt19937_64& rng) {
  Layout out;
  out.name = "roundabout";
  out.lanes_per_direction = 1;
  const double length = 200.0;
  const double island = uniform(rng, 7.0, 11.0);
  const double ring = island + 2.2;   // circulating lane centre
  const double outer = ring + 2.0;    // outer edge of the ring
  const double edge = kLaneWidth_m;
  const double d_cross = outer + 10.0, d_yield = outer + 7.0, d_join = outer + 5.0;
  const double alpha = deg(28.0);
  std::vector<Arm> arms;
  for (double a : {0.0, 90.0, 180.0, 270.0}) arms.push_back(make_arm(deg(a), outer + 4.0, d_cross, d_yield));
  for (std::size_t ai = 0; ai < arms.size(); ++ai) {
    const Arm& a = arms[ai];
    for (int exit = 1; exit <= 3; ++exit) {
      const Arm& b = arms[(ai + static_cast<std::size_t>(exit)) % arms.size()];
      Route r;
      r.kind = "exit_" + std::to_string(exit);
      const double t_in = a.phi + alpha, t_out = a.phi + exit * M_PI / 2 - alpha;
      add_line(r.pts, a.at(length, lane_lateral(0)), a.at(d_join, lane_lateral(0)));
      add_hermite(r.pts, a.at(d_join, lane_lateral(0)), -a.u, ring * dir(t_in), left_of(dir(t_in)));
      add_arc(r.pts, Vec2::Zero(), ring, t_in, t_out - t_in);
      add_hermite(r.pts, ring * dir(t_out), left_of(dir(t_out)), b.at(d_join, -lane_lateral(0)), b.u);
      add_line(r.pts, b.at(d_join, -lane_lateral(0)), b.at(length, -lane_lateral(0)));
      r.stop_s = length - d_yield;
      r.outermost = true;
      out.routes.push_back(r);
    }
    dress_arm(out, a, 1, false, outer + 4.0, length, true, rng);
    out.crossings.push_back({a.at(d_cross, -(edge + 0.5)), a.at(d_cross, edge + 1.0)});
    out.crossings.push_back({a.at(d_cross, edge + 0.5), a.at(d_cross, -(edge + 1.0))});
  }
  // Trees on the island.
  const double r_trees = island - 3.5;
  const int n_trees = std::max(1, static_cast<int>(2.0 * M_PI * r_trees / 5.0));
  for (int k = 0; k < n_trees; ++k) out.trees.push_back({r_trees * dir(2.0 * M_PI * k / n_trees), 0.0});
  out.lane_length_m = 4 * 2.0 * (length - outer) + 2.0 * M_PI * ring;
  out.extent_m = length + 10.0;
  return out;
}

Layout highway_layout(std::mt19937_64& rng) {
  Layout out;
  out.name = "highway";
  out.urban = false;
  const int lanes = uniform_int(rng, 2, 3);
  out.lanes_per_direction = lanes;
  const double length = 450.0, median = 0.75;
  const auto lat = [&](int i) { return median + lane_lateral(i); };
  for (int i = 0; i < lanes; ++i) {
    for (double s : {1.0, -1.0}) {  // s = 1: eastbound (south side, y < 0)
      Route r;
      r.kind = "straight";
      add_line(r.pts, Vec2(-s * length, -s * lat(i)), Vec2(s * length, -s * lat(i)));
      r.outermost = i == lanes - 1;
      out.routes.push_back(r);
      const int k = i == 0 ? 1 : i - 1;
      const double x1 = uniform(rng, -length + 50.0, length - 150.0), x2 = x1 + uniform(rng, 50.0, 90.0);
      Route lc;
      lc.kind = "lane_change";
      add_line(lc.pts, Vec2(-s * length, -s * lat(i)), Vec2(s * x1, -s * lat(i)));
      add_hermite(lc.pts, Vec2(s * x1, -s * lat(i)), Vec2(s, 0.0), Vec2(s * x2, -s * lat(k)), Vec2(s, 0.0));
      add_line(lc.pts, Vec2(s * x2, -s * lat(k)), Vec2(s * length, -s * lat(k)));
      out.routes.push_back(lc);
    }
  }
  // An on-ramp each way: a curve onto an acceleration lane, then a merge into the outer lane.
  const double road_edge = median + lanes * kLaneWidth_m;
  for (double s : {1.0, -1.0}) {
    const double xm = uniform(rng, -60.0, 100.0);
    const double y_acc = -s * lat(lanes);
    Route r;
    r.kind = "ramp";
    const Vec2 start(s * (xm - 260.0), y_acc - s * 45.0), join(s * (xm - 80.0), y_acc);
    add_hermite(r.pts, start, Vec2(s, 0.0), join, Vec2(s, 0.0));
    add_line(r.pts, join, Vec2(s * (xm + 60.0), y_acc));
    add_hermite(r.pts, Vec2(s * (xm + 60.0), y_acc), Vec2(s, 0.0), Vec2(s * (xm + 140.0), -s * lat(lanes - 1)), Vec2(s, 0.0));
    add_line(r.pts, Vec2(s * (xm + 140.0), -s * lat(lanes - 1)), Vec2(s * length, -s * lat(lanes - 1)));
    r.outermost = true;
    out.routes.push_back(r);
    out.signs.push_back({Vec2(s * (xm - 100.0), -s * (road_edge + kLaneWidth_m + 3.0)), s > 0 ? M_PI / 2 : -M_PI / 2});
    out.lane_length_m += 400.0;
  }
  // Barrier rows along the median and both edges: 10 m segments 0.6 m apart, so that each keeps
  // the clearance every static object keeps (the generator leaves out those in a ramp's way and
  // may leave out all).
  for (double y : {0.0, road_edge + 2.5, -(road_edge + 2.5)}) {
    for (double x = -length + 5.0; x < length - 5.0; x += 10.6) out.barriers.push_back({Vec2(x, y), 0.0});
  }
  // Lights along both edges, trees and a few buildings further out.
  for (double s : {1.0, -1.0}) {
    const double step = uniform(rng, 40.0, 60.0);
    for (double x = -length + uniform(rng, 0.0, step); x < length; x += step) {
      out.poles.push_back({Vec2(x, -s * (road_edge + kLaneWidth_m + 3.5)), s > 0 ? M_PI / 2 : -M_PI / 2});
    }
    for (double x = -length + uniform(rng, 0.0, 20.0); x < length; x += uniform(rng, 10.0, 30.0)) {
      out.trees.push_back({Vec2(x, -s * (road_edge + uniform(rng, 14.0, 30.0))), 0.0});
    }
    for (double x = -length + uniform(rng, 0.0, 80.0); x < length; x += uniform(rng, 60.0, 140.0)) {
      out.buildings.push_back({Vec2(x, -s * (road_edge + uniform(rng, 45.0, 70.0))), 0.0});
    }
  }
  out.lane_length_m += 2.0 * lanes * 2.0 * length;
  out.extent_m = length + 10.0;
  return out;
}

}  // namespace

double uniform(std::mt19937_64& rng, double lo, double hi) {
  const double u = static_cast<double>(rng() >> 11) * 0x1.0p-53;
  return lo + (hi - lo) * u;
}

int uniform_int(std::mt19937_64& rng, int lo, int hi) {
  const auto span = static_cast<std::uint64_t>(hi - lo + 1);
  return lo + static_cast<int>(rng() % span);
}

const std::vector<std::string>& layout_names() {
  static const std::vector<std::string> names = {"straight_road", "junction", "t_junction", "roundabout", "highway"};
  return names;
}

Layout make_layout(const std::string& name, int straight_lanes, bool parking, std::mt19937_64& rng) {
  if (name == "straight_road") return straight_layout(straight_lanes, parking, rng);
  if (name == "junction") return junction_layout(name, {0.0, 90.0, 180.0, 270.0}, uniform_int(rng, 1, 2), parking, rng);
  if (name == "t_junction") return junction_layout(name, {0.0, 90.0, 180.0}, 1, parking, rng);
  if (name == "roundabout") return roundabout_layout(rng);
  if (name == "highway") return highway_layout(rng);
  FMCW_CHECK_ARG(false, "generator: unknown layout '", name, "'");
  return {};
}

std::vector<double> arc_lengths(const std::vector<Vec2>& pts) {
  std::vector<double> s(pts.size(), 0.0);
  for (std::size_t k = 1; k < pts.size(); ++k) s[k] = s[k - 1] + (pts[k] - pts[k - 1]).norm();
  return s;
}

std::vector<double> curvatures(const std::vector<Vec2>& pts, const std::vector<double>& s) {
  std::vector<double> out(pts.size(), 0.0);
  std::size_t lo = 0, hi = 0;
  for (std::size_t k = 0; k < pts.size(); ++k) {
    while (lo < k && s[k] - s[lo + 1] >= 2.0) ++lo;
    hi = std::max(hi, k);
    while (hi + 1 < pts.size() && s[hi] - s[k] < 2.0) ++hi;
    if (lo == k || hi == k) continue;
    // Curvature of the circle through three points: 4 area / (product of the sides).
    const Vec2 a = pts[lo], b = pts[k], c = pts[hi];
    const double area2 = std::abs((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x());
    const double denom = (b - a).norm() * (c - b).norm() * (c - a).norm();
    out[k] = denom > 0.0 ? 2.0 * area2 / denom : 0.0;
  }
  return out;
}

Vec2 point_at(const std::vector<Vec2>& pts, const std::vector<double>& s, double at) {
  if (at <= 0.0) return pts.front();
  if (at >= s.back()) return pts.back();
  const auto it = std::upper_bound(s.begin(), s.end(), at);
  const auto k = static_cast<std::size_t>(it - s.begin());
  const double f = (at - s[k - 1]) / (s[k] - s[k - 1]);
  return pts[k - 1] + f * (pts[k] - pts[k - 1]);
}

}  // namespace fmcw::sim::gen
