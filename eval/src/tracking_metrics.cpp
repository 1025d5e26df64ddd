#include "fmcw/eval/tracking_metrics.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <set>

#include "fmcw/core/check.hpp"
#include "point_overlaps.hpp"

namespace fmcw::eval {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
double ratio(double a, double b) { return b > 0.0 ? a / b : kNaN; }
}  // namespace

double TrackingFrame::iou(const PointOverlap& o) const {
  const int uni = truths[static_cast<std::size_t>(o.truth)].pixels + tracks[static_cast<std::size_t>(o.track)].pixels - o.pixels;
  return uni > 0 ? static_cast<double>(o.pixels) / uni : 0.0;
}

void MotParams::validate() const {
  FMCW_CHECK_ARG(iou_threshold > 0.0 && iou_threshold <= 1.0, "tracking: iou_threshold must be in (0, 1], got ",
                 iou_threshold);
}

TrackingFrame tracking_frame(std::size_t frame_index, const core::PixelGroundTruth& gt,
                             const std::vector<std::uint8_t>& valid, const core::FrameTruth& truth,
                             const core::MotionEstimate& estimate, int min_moving_pixels) {
  const PointOverlaps po = point_overlaps(gt, valid, estimate.labels, "tracking_frame");
  const ActorIndex truth_of(truth, "tracking_frame");
  TrackingFrame f;
  std::map<std::uint32_t, int> truth_index;
  for (const auto& [id, counts] : po.actors) {
    const core::ActorTruth& a = truth_of[id];
    if (counts.moving < min_moving_pixels) continue;
    truth_index[id] = static_cast<int>(f.truths.size());
    f.truths.push_back({id, a.class_name, counts.pixels, a.box.center_m});
  }
  std::map<std::int32_t, int> track_index;
  for (const auto& [label, pixels] : po.clusters) {
    const auto k = static_cast<std::size_t>(label - 1);
    FMCW_CHECK_ARG(k < estimate.clusters.size() && estimate.clusters[k].id == label, "tracking_frame: label ", label,
                   " has no cluster in the estimate (", estimate.clusters.size(), " clusters)");
    const core::ClusterEstimate& c = estimate.clusters[k];
    TrackObservation t;
    // Untracked clusters: -(frame * 2^24 + label), unique over frames of any realistic run.
    t.track = c.track_id > 0 ? c.track_id : -(static_cast<std::int64_t>(frame_index) * (1 << 24) + label);
    t.pixels = pixels;
    t.centre_m = c.centre_m.allFinite() ? c.centre_m : c.centroid_m;
    track_index[label] = static_cast<int>(f.tracks.size());
    f.tracks.push_back(t);
  }
  // Class of each cluster: the actor holding most of its pixels, when they outnumber the
  // cluster's pixels on no actor (ties: the lower actor id).
  std::map<std::int32_t, std::pair<int, std::uint32_t>> best;  // label -> (pixels, actor)
  for (const auto& [key, pixels] : po.overlaps) {
    auto& b = best[key.second];
    if (pixels > b.first) b = {pixels, key.first};
    const auto ti = truth_index.find(key.first);
    if (ti != truth_index.end()) f.overlaps.push_back({ti->second, track_index.at(key.second), pixels});
  }
  for (const auto& [label, b] : best) {
    const int off_actor = po.clusters.at(label) - po.on_actors.at(label);
    if (b.first > off_actor) f.tracks[static_cast<std::size_t>(track_index.at(label))].class_name = truth_of[b.second].class_name;
  }
  return f;
}

std::vector<int> max_weight_assignment(const std::vector<std::vector<double>>& w) {
  const int rows = static_cast<int>(w.size());
  const int cols = rows == 0 ? 0 : static_cast<int>(w[0].size());
  std::vector<int> out(static_cast<std::size_t>(rows), -1);
  if (rows == 0 || cols == 0) return out;
  const bool transposed = rows > cols;
  const int n = transposed ? cols : rows, m = transposed ? rows : cols;
  const auto cost = [&](int i, int j) {  // 1-based, n <= m
    return -(transposed ? w[static_cast<std::size_t>(j - 1)][static_cast<std::size_t>(i - 1)]
                        : w[static_cast<std::size_t>(i - 1)][static_cast<std::size_t>(j - 1)]);
  };
  // The Hungarian method with potentials, O(n^2 m) (Kuhn 1955; Munkres 1957).
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> u(static_cast<std::size_t>(n) + 1, 0.0), v(static_cast<std::size_t>(m) + 1, 0.0);
  std::vector<int> p(static_cast<std::size_t>(m) + 1, 0), way(static_cast<std::size_t>(m) + 1, 0);
  for (int i = 1; i <= n; ++i) {
    p[0] = i;
    int j0 = 0;
    std::vector<double> minv(static_cast<std::size_t>(m) + 1, inf);
    std::vector<char> used(static_cast<std::size_t>(m) + 1, 0);
    do {
      used[static_cast<std::size_t>(j0)] = 1;
      const int i0 = p[static_cast<std::size_t>(j0)];
      double delta = inf;
      int j1 = 0;
      for (int j = 1; j <= m; ++j) {
        if (used[static_cast<std::size_t>(j)]) continue;
        const double cur = cost(i0, j) - u[static_cast<std::size_t>(i0)] - v[static_cast<std::size_t>(j)];
        if (cur < minv[static_cast<std::size_t>(j)]) {
          minv[static_cast<std::size_t>(j)] = cur;
          way[static_cast<std::size_t>(j)] = j0;
        }
        if (minv[static_cast<std::size_t>(j)] < delta) {
          delta = minv[static_cast<std::size_t>(j)];
          j1 = j;
        }
      }
      for (int j = 0; j <= m; ++j) {
        if (used[static_cast<std::size_t>(j)]) {
          u[static_cast<std::size_t>(p[static_cast<std::size_t>(j)])] += delta;
          v[static_cast<std::size_t>(j)] -= delta;
        } else {
          minv[static_cast<std::size_t>(j)] -= delta;
        }
      }
      j0 = j1;
    } while (p[static_cast<std::size_t>(j0)] != 0);
    do {
      const int j1 = way[static_cast<std::size_t>(j0)];
      p[static_cast<std::size_t>(j0)] = p[static_cast<std::size_t>(j1)];
      j0 = j1;
    } while (j0 != 0);
  }
  for (int j = 1; j <= m; ++j) {
    const int i = p[static_cast<std::size_t>(j)];
    if (i == 0 || cost(i, j) >= 0.0) continue;  // weight 0: no pair
    if (transposed) {
      out[static_cast<std::size_t>(j - 1)] = i - 1;
    } else {
      out[static_cast<std::size_t>(i - 1)] = j - 1;
    }
  }
  return out;
}

namespace {
// The identity true positives: the best one-to-one pairing of objects and tracks by the number
// of frames in which they may match, solved per connected component of the pairs.
int identity_true_positives(const std::map<std::pair<std::uint32_t, std::int64_t>, int>& together) {
  std::map<std::uint32_t, int> object_group;
  std::map<std::int64_t, int> track_group;
  std::vector<int> parent;
  const auto find = [&parent](int x) {
    while (parent[static_cast<std::size_t>(x)] != x) x = parent[static_cast<std::size_t>(x)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(x)])];
    return x;
  };
  const auto node = [&parent](auto& ids, auto id) {
    const auto [it, fresh] = ids.emplace(id, static_cast<int>(parent.size()));
    if (fresh) parent.push_back(it->second);
    return it->second;
  };
  for (const auto& [pair, n] : together) {
    const int a = find(node(object_group, pair.first)), b = find(node(track_group, pair.second));
    if (a != b) parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
  }
  std::map<int, std::vector<std::pair<std::pair<std::uint32_t, std::int64_t>, int>>> components;
  for (const auto& entry : together) components[find(object_group.at(entry.first.first))].push_back(entry);
  int idtp = 0;
  for (const auto& [root, pairs] : components) {
    std::map<std::uint32_t, std::size_t> row;
    std::map<std::int64_t, std::size_t> col;
    for (const auto& [pair, n] : pairs) {
      row.emplace(pair.first, row.size());
      col.emplace(pair.second, col.size());
    }
    std::vector<std::vector<double>> w(row.size(), std::vector<double>(col.size(), 0.0));
    for (const auto& [pair, n] : pairs) w[row.at(pair.first)][col.at(pair.second)] = n;
    const std::vector<int> a = max_weight_assignment(w);
    for (std::size_t r = 0; r < a.size(); ++r) {
      if (a[r] >= 0) idtp += static_cast<int>(w[r][static_cast<std::size_t>(a[r])]);
    }
  }
  return idtp;
}

// HOTA's counts and sums (Luiten et al. 2021, as TrackEval computes them). Each object o and
// hypothesis h get an alignment over the run: the sum over frames of their IoU / (the sum of o's
// row + the sum of h's column of the frame's IoU matrix - their IoU), divided by (the frames o
// is present in + the frames h is present in - that sum). Per frame the pairs are matched by the
// Hungarian method on alignment times IoU; a match counts at alpha where its IoU is at least
// alpha. A match's A: its pair's matches at alpha / (o's frames + h's frames - those matches).
void hota_sums(const std::vector<TrackingFrame>& frames, MotMetrics& s) {
  using Pair = std::pair<std::uint32_t, std::int64_t>;
  const auto pair_of = [](const TrackingFrame& f, const PointOverlap& o) {
    return Pair{f.truths[static_cast<std::size_t>(o.truth)].actor_id, f.tracks[static_cast<std::size_t>(o.track)].track};
  };
  std::map<std::uint32_t, int> object_frames;
  std::map<std::int64_t, int> track_frames;
  std::map<Pair, double> potential;
  for (const TrackingFrame& f : frames) {
    for (const TruthObservation& t : f.truths) ++object_frames[t.actor_id];
    for (const TrackObservation& h : f.tracks) ++track_frames[h.track];
    std::vector<double> row(f.truths.size(), 0.0), col(f.tracks.size(), 0.0);
    for (const PointOverlap& o : f.overlaps) {
      row[static_cast<std::size_t>(o.truth)] += f.iou(o);
      col[static_cast<std::size_t>(o.track)] += f.iou(o);
    }
    for (const PointOverlap& o : f.overlaps) {
      const double iou = f.iou(o);
      const double union_sum = row[static_cast<std::size_t>(o.truth)] + col[static_cast<std::size_t>(o.track)] - iou;
      if (union_sum > 0.0) potential[pair_of(f, o)] += iou / union_sum;
    }
  }
  const auto alignment = [&](const Pair& p) {
    const auto it = potential.find(p);
    if (it == potential.end()) return 0.0;
    return it->second / (object_frames.at(p.first) + track_frames.at(p.second) - it->second);
  };
  constexpr auto kAlphas = static_cast<std::size_t>(MotMetrics::kHotaAlphas);
  std::array<std::map<Pair, int>, kAlphas> together;
  for (const TrackingFrame& f : frames) {
    std::vector<std::vector<double>> w(f.truths.size(), std::vector<double>(f.tracks.size(), 0.0));
    for (const PointOverlap& o : f.overlaps) {
      w[static_cast<std::size_t>(o.truth)][static_cast<std::size_t>(o.track)] = alignment(pair_of(f, o)) * f.iou(o);
    }
    const std::vector<int> match = max_weight_assignment(w);
    std::vector<double> iou(f.truths.size(), 0.0);
    for (const PointOverlap& o : f.overlaps) {
      if (match[static_cast<std::size_t>(o.truth)] == o.track) iou[static_cast<std::size_t>(o.truth)] = f.iou(o);
    }
    for (std::size_t k = 0; k < kAlphas; ++k) {
      const double alpha = MotMetrics::hota_alpha(static_cast<int>(k)) - 1e-12;
      int tp = 0;
      for (std::size_t i = 0; i < f.truths.size(); ++i) {
        if (match[i] < 0 || iou[i] < alpha) continue;
        ++tp;
        s.hota_iou[k] += iou[i];
        ++together[k][{f.truths[i].actor_id, f.tracks[static_cast<std::size_t>(match[i])].track}];
      }
      s.hota_tp[k] += tp;
      s.hota_fn[k] += static_cast<int>(f.truths.size()) - tp;
      s.hota_fp[k] += static_cast<int>(f.tracks.size()) - tp;
    }
  }
  for (std::size_t k = 0; k < kAlphas; ++k) {
    for (const auto& [p, n] : together[k]) {
      s.hota_assoc[k] += n * static_cast<double>(n) / (object_frames.at(p.first) + track_frames.at(p.second) - n);
    }
  }
}

MotMetrics score(const std::vector<TrackingFrame>& frames, double threshold) {
  MotMetrics s;
  std::map<std::uint32_t, std::int64_t> last_track;  // object -> track it last matched
  std::map<std::uint32_t, bool> interrupted;         // matched before, then present and missed
  std::map<std::pair<std::uint32_t, std::int64_t>, int> together;
  double distance_sum = 0.0, iou_sum = 0.0;
  for (const TrackingFrame& f : frames) {
    s.objects += static_cast<int>(f.truths.size());
    s.hypotheses += static_cast<int>(f.tracks.size());
    std::vector<std::vector<double>> w(f.truths.size(), std::vector<double>(f.tracks.size(), 0.0));
    for (const PointOverlap& o : f.overlaps) {
      const double iou = f.iou(o);
      if (iou < threshold) continue;
      w[static_cast<std::size_t>(o.truth)][static_cast<std::size_t>(o.track)] = iou;
      ++together[{f.truths[static_cast<std::size_t>(o.truth)].actor_id, f.tracks[static_cast<std::size_t>(o.track)].track}];
    }
    // CLEAR MOT: a correspondence of the last frame that still may match is kept; the rest are
    // assigned by the Hungarian method on IoU.
    std::vector<int> match(f.truths.size(), -1);
    std::vector<char> track_taken(f.tracks.size(), 0);
    for (std::size_t i = 0; i < f.truths.size(); ++i) {
      const auto it = last_track.find(f.truths[i].actor_id);
      if (it == last_track.end()) continue;
      for (std::size_t j = 0; j < f.tracks.size(); ++j) {
        if (f.tracks[j].track == it->second && w[i][j] > 0.0 && !track_taken[j]) {
          match[i] = static_cast<int>(j);
          track_taken[j] = 1;
        }
      }
    }
    std::vector<std::vector<double>> rest = w;
    for (std::size_t i = 0; i < f.truths.size(); ++i) {
      for (std::size_t j = 0; j < f.tracks.size(); ++j) {
        if (match[i] >= 0 || track_taken[j]) rest[i][j] = 0.0;
      }
    }
    const std::vector<int> more = max_weight_assignment(rest);
    for (std::size_t i = 0; i < f.truths.size(); ++i) {
      if (match[i] < 0) match[i] = more[i];
      const std::uint32_t id = f.truths[i].actor_id;
      if (match[i] < 0) {
        ++s.misses;
        if (last_track.count(id) != 0) interrupted[id] = true;
        continue;
      }
      const TrackObservation& t = f.tracks[static_cast<std::size_t>(match[i])];
      ++s.matches;
      const auto it = last_track.find(id);
      if (it != last_track.end() && it->second != t.track) ++s.id_switches;
      if (interrupted[id]) ++s.fragmentations;
      interrupted[id] = false;
      last_track[id] = t.track;
      distance_sum += (t.centre_m - f.truths[i].centre_m).norm();
      iou_sum += w[i][static_cast<std::size_t>(match[i])];
    }
  }
  s.false_positives = s.hypotheses - s.matches;
  s.motp_m = distance_sum;
  s.motp_iou = iou_sum;
  s.idtp = identity_true_positives(together);
  hota_sums(frames, s);
  complete_mot(s);
  return s;
}

// The frames restricted to the objects and hypotheses of the given classes.
std::vector<TrackingFrame> of_classes(const std::vector<TrackingFrame>& frames, const std::set<std::string>& names) {
  std::vector<TrackingFrame> out;
  out.reserve(frames.size());
  for (const TrackingFrame& f : frames) {
    TrackingFrame g;
    std::vector<int> ti(f.truths.size(), -1), hi(f.tracks.size(), -1);
    for (std::size_t i = 0; i < f.truths.size(); ++i) {
      if (names.count(f.truths[i].class_name) == 0) continue;
      ti[i] = static_cast<int>(g.truths.size());
      g.truths.push_back(f.truths[i]);
    }
    for (std::size_t j = 0; j < f.tracks.size(); ++j) {
      if (names.count(f.tracks[j].class_name) == 0) continue;
      hi[j] = static_cast<int>(g.tracks.size());
      g.tracks.push_back(f.tracks[j]);
    }
    for (const PointOverlap& o : f.overlaps) {
      const int a = ti[static_cast<std::size_t>(o.truth)], b = hi[static_cast<std::size_t>(o.track)];
      if (a >= 0 && b >= 0) g.overlaps.push_back({a, b, o.pixels});
    }
    out.push_back(std::move(g));
  }
  return out;
}
}  // namespace

void complete_mot(MotMetrics& s) {
  s.mota = s.objects > 0 ? 1.0 - static_cast<double>(s.misses + s.false_positives + s.id_switches) / s.objects : kNaN;
  s.motp_m = ratio(s.motp_m, s.matches);
  s.motp_iou = ratio(s.motp_iou, s.matches);
  s.idf1 = ratio(2.0 * s.idtp, static_cast<double>(s.objects + s.hypotheses));
  s.idp = ratio(s.idtp, s.hypotheses);
  s.idr = ratio(s.idtp, s.objects);
  // HOTA: per alpha DetA = TP / (TP + FN + FP), AssA = the matches' mean A (0 without matches),
  // HOTA = sqrt(DetA AssA); each the mean over the alphas.
  if (s.objects + s.hypotheses == 0) {
    s.hota = s.deta = s.assa = s.loca = kNaN;
    return;
  }
  double hota = 0.0, deta = 0.0, assa = 0.0, loca = 0.0;
  int with_matches = 0;
  for (std::size_t k = 0; k < static_cast<std::size_t>(MotMetrics::kHotaAlphas); ++k) {
    const int tp = s.hota_tp[k];
    const double det = static_cast<double>(tp) / (tp + s.hota_fn[k] + s.hota_fp[k]);
    const double ass = tp > 0 ? s.hota_assoc[k] / tp : 0.0;
    deta += det;
    assa += ass;
    hota += std::sqrt(det * ass);
    if (tp > 0) {
      loca += s.hota_iou[k] / tp;
      ++with_matches;
    }
  }
  s.hota = hota / MotMetrics::kHotaAlphas;
  s.deta = deta / MotMetrics::kHotaAlphas;
  s.assa = assa / MotMetrics::kHotaAlphas;
  s.loca = with_matches > 0 ? loca / with_matches : kNaN;
}

void add_mot_counts(MotMetrics& sum, const MotMetrics& x) {
  sum.objects += x.objects;
  sum.hypotheses += x.hypotheses;
  sum.matches += x.matches;
  sum.misses += x.misses;
  sum.false_positives += x.false_positives;
  sum.id_switches += x.id_switches;
  sum.fragmentations += x.fragmentations;
  sum.idtp += x.idtp;
  for (std::size_t k = 0; k < static_cast<std::size_t>(MotMetrics::kHotaAlphas); ++k) {
    sum.hota_tp[k] += x.hota_tp[k];
    sum.hota_fn[k] += x.hota_fn[k];
    sum.hota_fp[k] += x.hota_fp[k];
    sum.hota_assoc[k] += x.hota_assoc[k];
    sum.hota_iou[k] += x.hota_iou[k];
  }
  if (x.matches > 0) {
    sum.motp_m += x.motp_m * x.matches;
    sum.motp_iou += x.motp_iou * x.matches;
  }
}

MotReport clear_mot(const std::vector<TrackingFrame>& frames, const MotParams& params) {
  params.validate();
  MotReport r;
  r.all = score(frames, params.iou_threshold);
  std::set<std::string> classes;
  for (const TrackingFrame& f : frames) {
    for (const TruthObservation& t : f.truths) classes.insert(t.class_name);
  }
  for (const std::string& c : classes) r.by_class[c] = score(of_classes(frames, {c}), params.iou_threshold);
  const std::set<std::string> vehicles(params.vehicle_classes.begin(), params.vehicle_classes.end());
  r.vehicles = score(of_classes(frames, vehicles), params.iou_threshold);
  return r;
}

}  // namespace fmcw::eval
