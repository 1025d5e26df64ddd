#pragma once
// Multi-object tracking metrics: CLEAR MOT (MOTA, MOTP, identity switches, fragmentations), IDF1
// and HOTA, with tracks matched to actors per frame by the IoU of their point sets.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "fmcw/core/ground_truth.hpp"
#include "fmcw/core/motion_pipeline.hpp"

namespace fmcw::eval {

/// One ground-truth object of a frame: an actor with at least min_moving_pixels truly moving
/// valid pixels (ObjectMatch::evaluated).
struct TruthObservation {
  std::uint32_t actor_id = 0;
  std::string class_name;
  int pixels = 0;                                       ///< valid pixels of the actor
  Eigen::Vector3d centre_m = Eigen::Vector3d::Zero();   ///< its box centre, rig frame
};

/// One hypothesis of a frame: a moving cluster (label >= 1) with at least one valid pixel.
struct TrackObservation {
  /// The cluster's track id when the method tracks (ClusterEstimate::track_id > 0); otherwise
  /// an id of its own, negative and never reused: one track per cluster per frame.
  std::int64_t track = 0;
  int pixels = 0;  ///< valid pixels of the cluster
  Eigen::Vector3d centre_m = Eigen::Vector3d::Zero();  ///< the track's box centre, else the cluster centroid
  /// Class of the actor (any actor, moving or not) holding most of the cluster's pixels;
  /// empty when most of them are on no actor.
  std::string class_name;
};

struct PointOverlap {
  int truth = 0;   ///< index into TrackingFrame::truths
  int track = 0;   ///< index into TrackingFrame::tracks
  int pixels = 0;  ///< valid pixels in both
};

struct TrackingFrame {
  std::vector<TruthObservation> truths;  ///< increasing actor id
  std::vector<TrackObservation> tracks;  ///< increasing label
  std::vector<PointOverlap> overlaps;    ///< pairs with a common pixel

  double iou(const PointOverlap& o) const;
};

/// Builds the frame's objects and hypotheses. Throws std::invalid_argument when sizes disagree,
/// a pixel's actor is missing from truth or a label has no cluster.
TrackingFrame tracking_frame(std::size_t frame_index, const core::PixelGroundTruth& gt,
                             const std::vector<std::uint8_t>& valid, const core::FrameTruth& truth,
                             const core::MotionEstimate& estimate, int min_moving_pixels);

struct MotParams {
  /// A track and an object may match in a frame when the IoU of their point sets is at least
  /// this (the literature uses 0.5; DopplerTrack uses 0.4).
  double iou_threshold = 0.5;
  /// The classes scored together as MotReport::vehicles.
  std::vector<std::string> vehicle_classes = {"car", "van", "truck", "bus"};
  void validate() const;
};

struct MotMetrics {
  int objects = 0;          ///< ground-truth object-frames (GT)
  int hypotheses = 0;       ///< track observations
  int matches = 0;          ///< TP
  int misses = 0;           ///< FN
  int false_positives = 0;  ///< FP
  int id_switches = 0;
  int fragmentations = 0;
  double mota = 0.0;        ///< 1 - (FN + FP + IDSW) / GT; NaN without objects
  double motp_m = 0.0;      ///< mean centre distance over matches [m]; NaN without matches
  double motp_iou = 0.0;    ///< mean point IoU over matches
  int idtp = 0;             ///< identity true positives (the best one-to-one track/object pairing)
  double idf1 = 0.0;        ///< 2 IDTP / (GT + hypotheses); NaN when both are 0
  double idp = 0.0;         ///< IDTP / hypotheses
  double idr = 0.0;         ///< IDTP / GT

  /// HOTA (Luiten et al. 2021) at the 19 localisation thresholds alpha = hota_alpha(k) = (k + 1)
  /// / 20, k = 0..18: per alpha the counts and sums that pool over runs (docs/EVALUATION.md,
  /// "Tracking (CLEAR MOT, IDF1, HOTA)").
  static constexpr int kHotaAlphas = 19;
  static double hota_alpha(int k) { return (k + 1) / 20.0; }
  std::array<int, kHotaAlphas> hota_tp{};           ///< matches at alpha
  std::array<int, kHotaAlphas> hota_fn{};           ///< objects unmatched at alpha
  std::array<int, kHotaAlphas> hota_fp{};           ///< hypotheses unmatched at alpha
  std::array<double, kHotaAlphas> hota_assoc{};     ///< sum over the matches of their pair's A
  std::array<double, kHotaAlphas> hota_iou{};       ///< sum over the matches of their IoU
  double hota = 0.0;  ///< mean over alpha of sqrt(DetA AssA); NaN without objects and hypotheses
  double deta = 0.0;  ///< mean over alpha of TP / (TP + FN + FP)
  double assa = 0.0;  ///< mean over alpha of the matches' mean A (0 at an alpha without matches)
  double loca = 0.0;  ///< mean IoU of the matches, over the alphas with matches; NaN without
};

struct MotReport {
  MotMetrics all;
  /// Per class: the class's objects, and the hypotheses whose class (TrackObservation::
  /// class_name) is that class. Hypotheses on no actor count in `all` only.
  std::map<std::string, MotMetrics> by_class;
  /// The objects of the vehicle classes (MotParams::vehicle_classes) and the hypotheses of those
  /// classes, scored together: a track that swaps a car for a van is one identity switch here.
  MotMetrics vehicles;
};

/// Fills mota, motp_m, motp_iou, idf1, idp, idr, hota, deta, assa and loca from the counts. On
/// entry motp_m and motp_iou hold their sums over the matches (so runs pool by adding counts and
/// sums).
void complete_mot(MotMetrics& m);

/// Pools a completed run's metrics into `sum`: CLEAR MOT's, IDF1's and HOTA's counts and sums
/// add over runs (an actor of one run is never one of another), MOTP's means back into sums.
/// complete_mot(sum) after the last run gives the pooled metrics.
void add_mot_counts(MotMetrics& sum, const MotMetrics& x);

/// Frames in order. See docs/EVALUATION.md ("Tracking") for the exact procedure.
MotReport clear_mot(const std::vector<TrackingFrame>& frames, const MotParams& params = {});

/// Maximum-weight one-to-one assignment (Hungarian method). weights[r][c] >= 0; a pair of
/// weight 0 is never returned. Returns, per row, the assigned column or -1.
std::vector<int> max_weight_assignment(const std::vector<std::vector<double>>& weights);

}  // namespace fmcw::eval
