#pragma once
// Tracking moving objects across frames: what one scan cannot see (tangential velocity, yaw
// rate, objects inside the Doppler blind band), several scans can.

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "fmcw/core/scan.hpp"

namespace fmcw::core {

struct MotionEstimate;

/// The tracker's parameters, by stage (core/src/tracking/, docs/METHODS.md).
struct TrackerParams {
  /// The measurement update: each pixel's Doppler a row, the box centre a position.
  struct Measurement {
    /// Per-row standard deviation of an object's Doppler rows: sensor noise plus what a rigid
    /// model does not explain (body panels at grazing angles, residual limb motion) [m/s].
    double doppler_sigma_mps = 0.08;
    /// Rows of one object count as at most this many independent rows: neighbouring pixels of
    /// one body share their model error, so thousands of rows are not thousands of measurements.
    int max_effective_rows = 150;
    /// Rows whose residual against the track's prediction exceeds this many robust standard
    /// deviations (and outlier_floor_mps) are left out: wheels, swinging limbs [m/s].
    double outlier_sigmas = 3.0;
    double outlier_floor_mps = 0.15;
    double position_sigma_m = 0.7;  ///< box-centre measurement noise [m]
    /// A small object wholly inside the blind band is seen only through the pixels its track
    /// claims; their centre is a weak measurement of its position (they may include whatever
    /// stands close by) [m].
    double claim_position_sigma_m = 0.75;
    /// The prediction and the Doppler rows are linearised at the predicted state, and both are
    /// bilinear in the yaw rate and the rest (the velocity turns by omega dt; a row reads omega
    /// e . (z x (o - c))). The first update after a track's birth meets the line its prior
    /// leaves open (velocity against yaw rate, start_track): where its step bounds their
    /// linearisation error, |d omega| (|d c| + dt |d v|), above relinearise_mps (a row's noise),
    /// it is made again with both linearised at its result, at most relinearise_iterations
    /// times (0: never), for a track faster than a walker with at most relinearise_max_hits
    /// updates (its birth counts one): an iterated smoother over the one step [m/s].
    double relinearise_mps = 0.08;
    int relinearise_iterations = 3;
    int relinearise_max_hits = 1;
  } measurement;

  /// Small objects and walkers.
  struct Small {
    /// Objects whose box is shorter than this on both axes (walkers, a cyclist seen head-on)
    /// span a few degrees: their Doppler rows fix the radial velocity but hardly the tangential
    /// one, and swinging limbs bias what little they say about it. Such an object is measured by
    /// its mean Doppler along its mean beam, and its tangential velocity comes from its path [m].
    double small_object_m = 1.2;
    double position_sigma_m = 0.15;              ///< box-centre noise of a small object [m]
    double doppler_floor_mps = 0.05;             ///< floor of its mean-Doppler noise (gait) [m/s]
    double initial_tangential_sigma_mps = 1.5;   ///< its tangential velocity at birth [m/s]
    /// A track small for walker_hits consecutive updates and slower than walker_max_speed_mps
    /// is a walker, and stays one while it stays that slow. Small: its box, or the outline its
    /// update measured, under small_object_m (a box only grows: one born over two walkers side
    /// by side keeps their width after they part). Walkers side by side at one speed make one
    /// cluster, and a box grown over two of them would turn the walker into a rigid body with a
    /// yaw rate. A walker's own pixels are those inside its predicted box (grown by
    /// claims.claim_margin_m), its box is at most walker_box_m on each axis, and its centre is
    /// the median of its pixels along the box axes (the torso: the limbs swing about it, and an
    /// end of the outline is a foot or a hand).
    int walker_hits = 3;
    double walker_max_speed_mps = 3.0;
    /// The largest a walker's box grows on either axis (under small_object_m). Its box holds the
    /// largest extents its outline has shown, a stride's swing included; a box as long as
    /// small_object_m also held a walker following 0.6-0.8 m behind, whose pixels then moved the
    /// median centre back and forth between the two [m].
    double walker_box_m = 0.9;
    /// A box at a walker's pace larger than small_object_m may be several walkers side by side:
    /// walkers crossing the line of sight together make one cluster whichever way each one
    /// walks (their Doppler is near zero alike), and the track's velocity is then the group's.
    /// Each walker's differs from it by up to a walker's pace, so such a track reports its
    /// covariance with group_sigma_mps squared added on both horizontal axes (0: never). A
    /// track that has been faster than walker_max_speed_mps for vehicle_pace_updates
    /// consecutive updates is a vehicle's and never a group (a car slowing for a light).
    double group_sigma_mps = 1.0;  ///< [m/s]
    int vehicle_pace_updates = 5;
    /// A small patch whose single scan resolved its whole velocity (the larger standard
    /// deviation of the fit's two horizontal axes at most this), as one rigid motion (residual
    /// RMS at most measurement.doppler_sigma_mps: no swinging limbs), faster than
    /// walker_max_speed_mps by three of those standard deviations, is part of a body that moves
    /// as a vehicle does: the corner of a bus alongside the rig, seen at close range across a
    /// wide angle. It is born with the scan's velocity, as a larger object is, not with the
    /// radial part alone. 0: never [m/s].
    double rigid_patch_sigma_mps = 0.25;
    /// Walkers side by side at one pace make one cluster, and the track of one of them held
    /// both: its box, its velocity and its covariance a walker's, the other's not. The pixels
    /// of a confirmed walker's cluster outside its predicted box (grown by
    /// claims.claim_margin_m), enough to start a track at their range and more than a
    /// fragments.small_host_ratio-th of those inside (a walker beside it, not a limb), become a
    /// cluster of their own, with their own single-scan fit; a small track born from them takes
    /// the walker's tangential velocity as its prior (companions walk at about one pace), the
    /// walker's variance plus companion_sigma_mps squared, where their radial velocities agree
    /// within three standard deviations.
    bool split_companions = true;
    double companion_sigma_mps = 0.5;  ///< [m/s]
    /// A small track at a walker's pace, not yet a walker: where one edge of its outline across
    /// the line of sight is cut sideways (an occluder beside it, a head's edge) and the other is
    /// not, its centre is measured half its width (the widest it has shown across the line of
    /// sight, Track::across_extent_m) in from the uncut edge, not from the middle of what shows.
    /// A walker coming into a head's view at its edge, or out from behind something nearer,
    /// shows a growing sliver, whose middle lies off its body and moves slower than it.
    bool centre_from_silhouette = true;
    /// The silhouette's edges leave out a neighbour's stray pixels: of the
    /// silhouette_stray_share of the outline's pixels nearest an edge across the line of sight,
    /// those beyond the last gap wider than silhouette_stray_gap_m count neither for the edge
    /// nor for the width. A walker beside another makes one cluster with the other's hand or
    /// foot, and an edge on it put the centre half a metre off (docs/EVALUATION.md, "A
    /// silhouette without a neighbour's hand"). 0: every pixel counts.
    double silhouette_stray_gap_m = 0.3;  ///< [m]
    double silhouette_stray_share = 0.05;
  } small;

  /// The constant-turn-rate filter.
  struct Motion {
    double accel_sigma_mps2 = 2.5;        ///< acceleration noise [m/s^2]
    double yaw_accel_sigma_rps2 = 0.8;    ///< yaw acceleration noise [rad/s^2]
    double initial_yaw_rate_sigma_rps = 0.4;      ///< yaw rate at birth [rad/s]
    /// A track's velocity prior at birth is its cluster's single-scan fit, the fit's standard
    /// deviation capped at this; along a direction the fit resolves no better than this, the
    /// prior's velocity is 0 (the fit's value there is no measurement) [m/s].
    double max_initial_velocity_sigma_mps = 6.0;
    /// Bound of a track's yaw rate [rad/s]: a car turning a corner at 6 m/s on a 3 m radius
    /// turns at 2 rad/s.
    double max_yaw_rate_rps = 2.0;
    /// Noise matched to the innovations. Each update measures r = dx^T P^-1 dx / E[dx^T P^-1 dx]
    /// (dx the update's correction, P the predicted covariance; E[...] = 5 - tr(P^-1 P_updated)
    /// for a consistent filter) and moves the track's noise scale s to
    /// s (1 + gain (r - 1)) within [min_noise_scale, max_noise_scale], gain noise_gain_up when
    /// r > 1 and noise_gain_down otherwise. Small tracks and tracks at a walker's pace
    /// (small.walker_max_speed_mps: a gait, or walkers side by side, is no manoeuvre) keep the
    /// full noise (s = 1); turning ones (|omega| > turning.min_turn_rate_rps) at least the full
    /// noise.
    ///
    /// Above 1 (max_noise_scale > 1, the default), on the yaw acceleration's noise alone: a turn
    /// sharper than it (a car swinging into a side street at 2 rad/s, its yaw rate building up
    /// and falling back by 4 rad/s^2) is corrected by every update more than the filter
    /// expects, and its noise rises within a few updates; the filter then follows the turn
    /// instead of lagging it and overshooting after it (docs/EVALUATION.md, "A manoeuvre's
    /// noise"). The acceleration's noise stays: raised with it, the velocity was further off
    /// after the turn than with the fixed noises. 1: never above.
    ///
    /// Below 1 (min_noise_scale < 1; off by default: docs/EVALUATION.md, "A noise that follows
    /// the track"), on both noises: the noises above are those of a manoeuvring object; a
    /// vehicle driving straight is corrected by its updates less than its covariance expects,
    /// and its noise variances are scaled down, to min_noise_scale of them at the least. A turn
    /// that builds up slowly stays under the turning bound and is followed late: on generated
    /// traffic the tails of objects of 200 points and more grew. 1: never below.
    double min_noise_scale = 1.0;
    double max_noise_scale = 4.0;
    double noise_gain_up = 0.5;
    double noise_gain_down = 0.1;
  } motion;

  /// The reported covariance matched to the track's own updates (docs/METHODS.md, "A
  /// covariance that follows the track's updates"). The noises of `motion` and `measurement`
  /// are those of a manoeuvring object seen by a noisy sensor; a vehicle driving steadily under
  /// a good sensor is corrected by its updates far less than its covariance expects, and the
  /// covariance it reports is that much too wide. Each update's correction dx is scored against
  /// what a consistent filter expects of it, E[dx^T P^-1 dx] = 5 - tr(P^-1 P_updated), and the
  /// track keeps both sums, each previous one weighted by `memory` per update. Scaling every
  /// noise of a linear filter (process, measurement and initial) by c leaves its gain and its
  /// estimate as they are and scales its covariance by c; the corrections, c times what the
  /// filter expects, say which c (for this filter, linearised, with Huber weights and outlier
  /// gates, approximately). The reported covariance from the filter's (its yaw rate's share
  /// included; not the yaw rate the report leaves in the velocity) is multiplied by
  /// (corrections + prior_dof) / (expected + prior_dof), within [min_scale, 1]: a track with
  /// few updates reports the filter's covariance. Tracks whose next motion their past updates
  /// do not tell (Track::unsteady: small objects, objects at a walker's pace that have not driven
  /// at a vehicle's, turning ones) report the filter's covariance. Estimates are not changed,
  /// only the covariance reported.
  struct Calibration {
    bool enabled = true;
    double memory = 0.9;     ///< weight of the sums so far at each update, in [0, 1)
    double prior_dof = 1.0;  ///< the filter's own covariance, as this many expected degrees of freedom
    double min_scale = 0.05;
  } calibration;

  /// The outline's axis as a measurement of a vehicle's heading: a vehicle drives along its body
  /// axis, so the velocity across the axis of its outline (the long side of the rectangle
  /// whose edges the footprint's near side lies on) is zero. One scan's Doppler fixes velocity and
  /// yaw rate only along a line; with the direction of the velocity known, it fixes both. Measured
  /// where the long side is at least min_length_m (longer than any vehicle is wide: it is the
  /// body's length) and min_aspect times the short side (a square-ish outline says nothing). The
  /// noise of the velocity across the axis: the speed times the heading's noise, a slip (the
  /// larger of slip_sigma_mps and the speed times slip_sigma_rad: a body drifts across its axis
  /// by a small angle, more metres per second the faster it goes), and the lateral velocity of
  /// the box's centre in a turn (a car turns about its rear axle: |omega| times
  /// centre_offset_fraction of its length). The heading's noise, from the axis's measured errors
  /// (docs/METHODS.md, "The outline's axis"): sigma_rad (near_sigma_rad where the range is less
  /// than near_range_lengths times the length: a long body alongside, its outline spanning a
  /// wide angle), and the scatter of the outline's ends (end_sigma_per_m of the range) over its
  /// length, times |cos| of the angle between the axis and the line of sight (a side seen
  /// end-on shows its direction through the lateral offsets of its points, which scatter by
  /// about that much; seen broadside, through their ranges, far finer); all times
  /// cut_sigma_factor where the view or an occluder cuts the outline. An axis whose innovation
  /// exceeds gate_sigmas standard deviations (the track's own and the measurement's) is not
  /// measured in that update (0: never dropped). Unless the heading it disagrees with is no
  /// heading the track's reads hold: the gate opens to a read beyond it where the track's last
  /// read beyond it, within reopen_window_s, agrees with this one within reopen_sigmas standard
  /// deviations (the two reads' own, the track's yaw rate turning the older one on), and fewer
  /// than reopen_support of the axes the track keeps (those of turning.straight_window_s before
  /// the last one it measured: a read the gate drops is not kept) lie within reopen_sigmas of
  /// their own standard deviation of its heading (turned back by its yaw rate to when each was
  /// read). A heading a single wrong read set at birth (a far van's few
  /// columns read 51 degrees off) then yields to the reads that agree on the body's axis
  /// (measured: docs/EVALUATION.md, "A heading no read holds"). 0: never.
  ///
  /// A face across the body (a vehicle seen end-on shows its rear or its front, a line as long
  /// as the body is wide) gives the axis as its normal: measured where no long side shows, the
  /// side the sensor sees (the nearest pixel of each column: a car's roof behind its rear is no
  /// part of it) is at least face_min_length_m long (wider than a walker or a rider) and
  /// min_aspect times its short side, seen in face_min_columns columns or more, square to the
  /// line of sight within face_sight_cosine (|cos| of the angle between the face and the line of
  /// sight: a side seen at a grazing angle is not square to it), and its normal within
  /// face_max_angle_rad of the track's velocity (a face along the body, a rider's or a van's
  /// side, lies square to it). Its heading's noise: sigma_rad and face_sigma_rad over the root
  /// of the columns the face spans (measured: docs/METHODS.md), times cut_sigma_factor where the
  /// view or an occluder cuts the outline; plus face_oblique_sigma_rad times |cos| of the angle
  /// between the face and the line of sight (a face seen obliquely brings its corner and the
  /// start of the side into its nearest pixels, and reads turned toward the side: measured,
  /// docs/EVALUATION.md, "A face seen obliquely").
  struct Heading {
    bool use_outline = true;            ///< false: the outline's axis is not measured
    double min_length_m = 3.0;          ///< [m]
    double min_aspect = 1.5;
    double sigma_rad = 0.006;           ///< [rad]
    double end_sigma_per_m = 0.002;     ///< [m per m of range]
    double near_sigma_rad = 0.015;      ///< [rad]
    double near_range_lengths = 2.0;
    double cut_sigma_factor = 1.5;
    double slip_sigma_mps = 0.1;   ///< [m/s], at least
    double slip_sigma_rad = 0.01;  ///< [rad], times the speed
    double centre_offset_fraction = 0.25;
    double gate_sigmas = 4.0;
    double reopen_sigmas = 3.0;     ///< (0: never)
    double reopen_window_s = 0.35;  ///< [s]
    int reopen_support = 2;
    double face_min_length_m = 1.2;     ///< [m] (0: no face measured)
    int face_min_columns = 8;
    double face_sight_cosine = 0.3;
    double face_max_angle_rad = 0.35;   ///< [rad]
    double face_sigma_rad = 0.052;      ///< [rad], over the root of the face's columns
    double face_oblique_sigma_rad = 0.2;  ///< [rad] per unit of |cos| (0: none)
    /// An outline with a long side (min_length_m, min_aspect) whose near side lies farther than
    /// this from its rectangle's edges, on average over its columns, shows no side of a box:
    /// nothing of it is read, no axis, face or line (0: always read).
    /// Reads lie 0.02 m from their edges at the median, 0.14 m at the 99th percentile (841 reads
    /// on eight runs: docs/EVALUATION.md, "A rectangle the near side does not lie on") [m].
    double max_edge_distance_m = 0.15;
  } heading;

  /// A track starts turning (its velocity reported at its centre with the yaw rate) when
  /// |omega| exceeds min_turn_rate_rps and turn_significance standard deviations after at least
  /// min_turn_hits updates (a young track's yaw rate follows its box as more of the object comes
  /// into view), and stops when |omega| falls below min_turn_rate_rps or
  /// turn_release_significance standard deviations. Otherwise the velocity reported is the one
  /// its Doppler field shows, with yaw rate 0, but for a track whose outline's axis was measured
  /// in the update (Heading) or whose box has settled (shrink_settled): its yaw rate is known as
  /// well as its variance says, and the velocity reported is the Doppler's less the yaw rate
  /// shrunk by its significance times z x (o - c).
  struct Turning {
    double min_turn_rate_rps = 0.05;  ///< [rad/s]
    double turn_significance = 3.0;
    double turn_release_significance = 2.0;
    int min_turn_hits = 5;
    /// A track whose outline's axis was measured in the update: the yaw rate taken off the
    /// Doppler's velocity is omega^3 / (omega^2 + k^2 sigma^2), k = axis_shrink_sigmas.
    double axis_shrink_sigmas = 1.0;
    /// A track whose box has settled reports its yaw rate shrunk the same way without its axis:
    /// the yaw rate comes from the path of the box's centre against the Doppler's velocity, and
    /// is the body's once that path is the body's. Settled: its last box not cut (see
    /// Track::outline_cut), at least min_turn_hits updates, length plus width grown by no more
    /// than settle_growth_m over the last settle_updates updates (a box growing as more of the
    /// object comes into view moves its centre), and not turning within the last
    /// release_hold_updates updates (the filter's yaw rate lags the end of a turn). Otherwise
    /// (and with shrink_settled false) the yaw rate is not taken off.
    bool shrink_settled = true;
    int settle_updates = 5;
    double settle_growth_m = 0.2;  ///< [m]
    int release_hold_updates = 30;
    /// A turn released while its rate holds up: within release_hold_updates updates of its last
    /// turning update, a track whose yaw rate still has that update's sign and at least
    /// hold_rate_fraction of its size was released because the rate's variance grew (the box
    /// of a near cyclist cut by the view), not because the turn ended (the filter's rate then
    /// falls, lagging the body's). It reports its yaw rate shrunk by its significance, as a
    /// settled track does, not 0. 0: never.
    double hold_rate_fraction = 0.8;
    /// A yaw rate too large to leave in: where the yaw rate of a track that is not small, left
    /// in, would move the velocity reported by more than max_left_in_mps (|omega| |o - c|) and
    /// stands max_left_in_significance standard deviations from zero, it is taken off shrunk by
    /// its significance, as a settled track's is, at any age (a young car turning out of a side
    /// street, or a far track whose few columns the Doppler reads across a wide lever). Below
    /// turn_significance: the shrinking already takes little of a rate within its noise, and a
    /// rate one or two standard deviations from zero, left in across a lever of 50 m, puts
    /// metres per second into the velocity. 0 (max_left_in_mps): never.
    double max_left_in_mps = 3.0;  ///< [m/s]
    double max_left_in_significance = 1.0;
    /// Straight by its axes: where the yaw rate would be taken off (the axis measured, the box
    /// settled or the turn held; not a yaw rate too large to leave in), the outline's axes the
    /// track measured over the last straight_window_s (at least straight_min_axes of them,
    /// spanning half the window) are fitted with a line, angle against time, weighted by their
    /// variances; its slope b is a yaw rate with variance var_b (the fit's, times its reduced
    /// chi-square where above 1). Where |b| is within straight_sigmas of var_b's standard
    /// deviation, that deviation is at most straight_max_sigma_ratio of the filter's yaw-rate
    /// sigma (the axes know the rate better than the filter) and the filter's yaw rate lies within
    /// straight_consistency_sigmas of b (a turn's onset, which the window lags, is not
    /// straight), the body drives straight: the Doppler's velocity is reported with no yaw rate
    /// taken off, and its covariance carries (b^2 + var_b) s s^T for the yaw rate instead of the
    /// filter's (scaled with the rest as Calibration says). A straight car's filter holds yaw
    /// rates of up to a degree a second within its noise, and the shrinkage took a share of them
    /// off: a few tenths of a metre per second at 30 m (docs/EVALUATION.md, "Straight by its
    /// axes"). 0: never.
    double straight_window_s = 2.0;  ///< [s]
    int straight_min_axes = 10;
    double straight_sigmas = 2.0;
    double straight_consistency_sigmas = 1.0;
    double straight_max_sigma_ratio = 0.5;
    /// The line an outline shows: where none of the above says a young track's yaw rate is
    /// known (fewer than min_turn_hits updates; no axis measured, not settled, not held, not too
    /// large to leave in), but the side the sensor sees is at least line_min_length_m long over
    /// at least line_min_columns columns (a face seen obliquely, an L too short for an axis:
    /// Track::line_seen), a vehicle drives along one of that rectangle's directions. If the
    /// filter's velocity lies within line_max_angle_rad of one of them (mod 90 degrees) and the
    /// Doppler's velocity, the rate left in, more than line_doppler_angle_rad off every one, the
    /// rate is the Doppler's error: it is taken off in full, its variance in the covariance.
    /// Only the report; the filter is as it was. A young car turning into view, its front face
    /// seen first at 40 degrees to the line of sight, reports 2-3 m/s off otherwise
    /// (docs/EVALUATION.md, "The line an outline shows"). An older track whose rate is still
    /// unresolved has had the updates to resolve a turn. 0 (line_max_angle_rad): never.
    double line_min_length_m = 1.2;  ///< [m]
    int line_min_columns = 16;
    double line_max_angle_rad = 3.0 * M_PI / 180.0;      ///< [rad]
    double line_doppler_angle_rad = 6.0 * M_PI / 180.0;  ///< [rad]
  } turning;

  /// Association of clusters to tracks.
  struct Association {
    double gate_m = 2.0;  ///< cluster centroid within the predicted box grown by this [m]
    /// Smaller clusters neither start nor update tracks: min_cluster_pixels within
    /// full_pixels_range_m of the rig, fewer beyond (min_pixels_at), as few as
    /// min_far_cluster_pixels: a car's rear 120 m away shows 4-6 pixels, a fragment of a near
    /// walker as many.
    int min_cluster_pixels = 8;
    double full_pixels_range_m = 40.0;  ///< [m]
    int min_far_cluster_pixels = 3;
    /// max(min_far_cluster_pixels, min_cluster_pixels (full_pixels_range_m / range)^2, rounded up):
    /// the pixels of a given area fall with the square of the range.
    int min_pixels_at(double range_m) const;
    /// A cluster joins a track only when the track's predicted motion explains its Doppler to
    /// within this (median over its pixels) [m/s].
    double doppler_tolerance_mps = 0.6;
    /// A vehicle's track that missed its last update (coasting through an occlusion) predicts
    /// the Doppler less well than the tolerance assumes: a truck braking behind a bus for three
    /// frames comes back a metre per second slower. Its cluster joins it within the tolerance
    /// and this many standard deviations of the Doppler its predicted state gives at the
    /// cluster's middle pixel, added in quadrature. 0: the tolerance alone.
    double coasting_doppler_sigmas = 3.0;
    /// Tracks at least this long are vehicles: a second cluster joins one up to the gate from
    /// its box (its far end may not have been seen yet), and small clusters inside its box whose
    /// Doppler it does not explain (wheels) take its label without being measured [m].
    double vehicle_length_m = 3.0;
    /// A confirmed track that is not small, faster than a walker, whose last box was cut by the
    /// view or an occluder, takes a second cluster up to the gate from its box too: its far end
    /// has not been seen (a bus alongside fills one head, its front shows in the next).
    bool cut_box_reach = true;
    int absorb_max_pixels = 60;  ///< size bound of such a wheel cluster [pixels]
    /// A cluster whose centroid lies inside the boxes of two or more vehicles' tracks that
    /// explain its Doppler joins the one whose box (grown by claims.claim_margin_m) holds the
    /// most of its pixels, not the one whose centre is nearest: a track born on a piece of a
    /// truck beside the one born on the whole truck took the whole truck's cluster once its
    /// pieces joined, its box half the truck's, and the whole truck's track ended.
    bool most_held_vehicle = true;
    /// A cluster is split between two or more tracks when each one's predicted box holds at
    /// least this share of the pixels that track had last frame, and at least min_pixels_at its
    /// range (two cars nose to tail at one speed make one cluster; so do a far car and a
    /// cyclist beside it).
    double split_min_share = 0.5;
    /// A cluster that no one rigid motion explains (its single-scan fit leaves a residual RMS
    /// above this) is split by the Doppler where a track explains a part of it
    /// (split_by_doppler in core/src/tracking/association.hpp). 0: never [m/s].
    double doppler_split_rms_mps = 1.0;
  } association;

  /// Pieces of a tracked object seen apart in the range image (wheels, mirrors, limbs with a
  /// Doppler of their own): a cluster no track took, of at most max_pixels pixels, within
  /// reach_px pixels in the image of the pixels of a group (a track's this frame, or one born
  /// before it: the largest clusters are born first; not a small one: walkers side by side are
  /// as near each other in the image as a body and its wheel) that holds at least host_ratio times its
  /// pixels, at a range within max(range_gap_m, range_gap_fraction * range) of them, goes under
  /// that group's label, unmeasured, and starts no track. max_pixels = 0: never.
  struct Fragments {
    int max_pixels = 60;             ///< [pixels]
    int reach_px = 2;                ///< [pixels]
    double range_gap_m = 1.0;        ///< [m]
    double range_gap_fraction = 0.03;
    double host_ratio = 3.0;
    /// A track whose centre lies in the box of a confirmed track that is no vehicle (a walker),
    /// as old, whose last update found small_host_ratio times its pixels, follows a part of it
    /// (a limb split off when the walker was first seen in two halves) and ends. Stricter than
    /// host_ratio: a walker half hidden behind another shows a good share of its pixels. So a
    /// cluster of at most max_pixels that no track took, whose centroid lies in the box (grown by
    /// claims.claim_margin_m) of a confirmed walker (a small track taken for a walker, or one no
    /// faster than small.walker_max_speed_mps) whose update this frame found small_host_ratio
    /// times its pixels, is a limb swung off it (the slow knee or elbow between them left out of
    /// the moving pixels): it goes under the walker's label, unmeasured, and starts no track.
    /// 0: never.
    double small_host_ratio = 10.0;
    /// A track whose centre lies up to same_motion_margin_m beyond the box of a confirmed vehicle
    /// faster than small.walker_max_speed_mps (past claims.claim_margin_m), and whose velocity
    /// is within same_motion_mps of the vehicle's, counts as inside that box (the rules above
    /// then apply): one face of a large body seen beside another, as a bus alongside the rig
    /// shows its side and its front corner. 0: only the box [m, m/s].
    double same_motion_margin_m = 0.5;
    double same_motion_mps = 0.5;
    /// A track as old as the vehicle whose box holds its centre (as above), whose pixels' Doppler
    /// the vehicle's motion explains (within association.doppler_tolerance_mps, the median over
    /// its pixels), is a part of it even where its own velocity differs by more than
    /// same_motion_mps: a turning truck first seen in two pieces, the second piece's young filter
    /// holding a velocity of its own while one rigid body's Doppler is one field. false: only by
    /// velocity.
    bool twin_by_doppler = true;
    /// A confirmed track of at least own_motion_hits updates, inside a vehicle's box (as above),
    /// whose pixels' Doppler the vehicle's motion does not explain (beyond
    /// association.doppler_tolerance_mps), moves on its own (a cyclist riding beside a turning
    /// car, inside its box): it is left alone. A piece's track (a wheel) ends younger. 0: never.
    int own_motion_hits = 10;
  } fragments;

  /// A track's life.
  struct Lifecycle {
    int confirm_hits = 3;              ///< hysteresis: updates before a track may carry labels
    int max_misses = 5;                ///< frames a track survives without a cluster
    /// A confirmed track missed for more than max_misses frames is remembered, its motion
    /// predicted on, for this many frames more: a track born where the association would have
    /// given it the cluster (its predicted box grown by the gate, at most 3 gate_m, the
    /// cluster's Doppler explained by its motion) takes its id. A walker or a cyclist hidden behind
    /// a crossing van for longer than max_misses comes back as the object it was. The new track's
    /// state is its own but for reid_motion. 0: never.
    int reid_frames = 15;
    /// A lost track that is a vehicle's (Track::vehicle, and not maybe a group of walkers)
    /// gives the track that takes its id its predicted velocity and yaw rate too, with their
    /// covariance, as a prior fused into the new track's (information form): one scan sees
    /// only the radial part of a vehicle's velocity, and the new track's first frames would
    /// be as far off as a newborn's (a van seen again after six frames unseen: 10.5 m/s off).
    bool reid_motion = true;
    double carry_min_speed_mps = 0.8;  ///< a confirmed track carries "moving" while faster than this [m/s]
    int release_slow_frames = 3;       ///< ... and stops after this many frames below it
    double max_gap_s = 0.5;            ///< frames further apart (or going back in time) reset the tracker [s]
  } lifecycle;

  /// Carrying tracks claim static pixels inside their predicted box that move as they do.
  struct Claims {
    double claim_margin_m = 0.25;            ///< the predicted box grows by this when claiming pixels [m]
    double ground_clearance_m = 0.12;        ///< claimed pixels lie this far above the track's lowest point [m]
    double doppler_tolerance_mps = 0.25;     ///< claimed pixels' Doppler agrees with the track's motion [m/s]
  } claims;

  /// While the rig stands (the zero-velocity test holds), the tracker keeps per pixel the
  /// farthest range seen since it stopped. A static pixel nearer than anything its 3 x 3
  /// neighbourhood has seen, by margin_m, is something that has come into space the beams saw
  /// empty; within label_m of a carrying track's box (and at its heights) it takes that track's
  /// label without being measured: walkers crossing the beams in a group, whose Doppler is zero
  /// whichever way they walk, beside the one whose track claims them. Used once the background
  /// holds min_frames frames (0: never).
  struct Background {
    int min_frames = 5;
    double margin_m = 0.3;  ///< [m]
    double label_m = 2.0;   ///< [m]
  } background;

  /// Growth into the blind band: from a moving object's pixels, static neighbours in the range
  /// image (8-connected, not across a head seam) join it, unmeasured, when they continue its
  /// surface (range step below max(range_gap_m, range_gap_fraction * range)), lie at its heights
  /// (from its lowest pixel, plus claims.ground_clearance_m for a small object whose feet stand
  /// on the ground, to claims.claim_margin_m over its top), within reach_m of it, and have the
  /// Doppler its motion gives there (claims.doppler_tolerance_mps). An object crossing the beams
  /// is cut by the band where its Doppler changes sign; the part inside the band reads as
  /// static, but it is the same surface and moves as the rest does. Each cluster grows by its
  /// single-scan velocity, each carrying track that found pixels this scan by its updated state
  /// (from its claimed pixels too). reach_m = 0: no growth.
  struct Growth {
    double reach_m = 3.0;             ///< [m]
    double range_gap_m = 0.5;         ///< [m]
    double range_gap_fraction = 0.01;
  } growth;

  /// The track's box.
  struct Box {
    double max_length_m = 20.0;       ///< size caps [m]
    double max_width_m = 4.0;
    double heading_reset_rad = 0.25;  ///< a heading swing beyond this (not turned by the yaw rate) re-measures the box [rad]
    /// An end of a box axis is cut by the view where an edge pixel lies within view_cut_end_m
    /// (plus 5 % of the visible extent) of that end and its cut direction (away from the view,
    /// in the ground plane) has a cosine beyond view_cut_cosine with the axis.
    double view_cut_cosine = 0.5;
    double view_cut_end_m = 0.25;     ///< [m]
    /// An outline's pixel whose neighbour in the row (same head) is nearer by this is cut there
    /// by an occluder, as by the view's edge: a car coming out from behind another [m]. 0: never.
    double occlusion_gap_m = 1.0;
    /// A vehicle's box leaves out stray pixels: where the outline along an axis is longer than
    /// any body (max_length_m along, max_width_m across), the pixels at an end beyond the last
    /// gap wider than stray_gap_m among the stray_share of the outline's pixels nearest that end.
    /// A pole behind a vehicle's edge, its Doppler close to the edge's (a rigid body's Doppler is
    /// the same all along each ray), is chained into the vehicle's cluster and would otherwise
    /// stretch its box, and move its centre, by metres; a vehicle's own far end seen under its
    /// body or past a gap lies within those sizes and counts. Not for walkers or groups of them
    /// (a walker at the end of a row is no stray) [m]. 0: every pixel counts.
    double stray_gap_m = 2.0;
    double stray_share = 0.02;
    /// A settled vehicle's box (its length plus width grown by no more than
    /// Turning::settle_growth_m over its last own_stray_settled_updates updates, at least that
    /// many since its birth, and not re-measured by a heading swing) is searched the same way where
    /// the outline is longer than the box itself by stray_gap_m (along the axis, and longer than
    /// own_stray_min_length_m), among the own_stray_share of the pixels nearest each end. A car
    /// following a bus, a pole behind a truck, their Doppler within the threshold of the body's
    /// edge, join its cluster under any body's size but beyond its own: they stretched a box by
    /// metres, which the centre, anchored at the end the sensor sees, followed by half, and the
    /// track absorbed the follower. A box still growing as more of the body comes into view (a
    /// bus's side seen at a grazing angle, its pixels metres apart at range) is not searched,
    /// nor along an outline under own_stray_min_length_m (a truck's cab, its trailer seen behind
    /// a gap). own_stray_share 0: only any body's size counts.
    double own_stray_share = 0.1;
    double own_stray_min_length_m = 8.0;  ///< [m]
    int own_stray_settled_updates = 1;
  } box;

  /// Throws std::invalid_argument naming the field that failed (tracking.<stage>.<field>).
  void validate() const;
};

/// One tracked object in the tracker's world frame (the rig's frame at the first frame after a
/// reset, carried forward by the estimated ego twist).
struct Track {
  std::int32_t id = 0;
  /// State: centre x, y [m], velocity x, y [m/s], yaw rate [rad/s], all in the tracker's world.
  Eigen::Matrix<double, 5, 1> x = Eigen::Matrix<double, 5, 1>::Zero();
  Eigen::Matrix<double, 5, 5> P = Eigen::Matrix<double, 5, 5>::Identity();
  /// The state and covariance before the last prediction, the time it spanned and the noise it
  /// added (dt 0: not predicted yet): the update may linearise the prediction again
  /// (TrackerParams::Measurement::relinearise_mps).
  Eigen::Matrix<double, 5, 1> x_before = Eigen::Matrix<double, 5, 1>::Zero();
  Eigen::Matrix<double, 5, 5> P_before = Eigen::Matrix<double, 5, 5>::Identity();
  Eigen::Matrix<double, 5, 5> Q_before = Eigen::Matrix<double, 5, 5>::Zero();
  double dt_before = 0.0;
  double heading_rad = 0.0;  ///< box axis; follows the velocity once the object moves
  double extents_heading_rad = 0.0;  ///< the axis the extents were measured along, turned with the body
  double length_m = 0.0;     ///< largest extent seen along the heading [m]
  double width_m = 0.0;      ///< largest extent seen across it [m]
  double z_min_m = 0.0;      ///< lowest and highest point of the last box measurement (rig height) [m]
  double z_max_m = 0.0;
  int hits = 0;              ///< frames with a cluster
  int last_pixels = 0;       ///< pixels one scan found moving in its last update
  int misses = 0;            ///< consecutive frames without one
  int slow_frames = 0;       ///< consecutive frames slower than carry_min_speed_mps
  bool confirmed = false;    ///< hits >= confirm_hits at some point
  bool merged = false;       ///< ended this frame as a part of another track (merge_nested_tracks)
  bool turning = false;      ///< yaw rate resolved (TrackerParams::Turning; not while the axis is measured)
  /// Updates since it was last turning; kNever if it has not turned.
  int updates_since_turn = kNever;
  static constexpr int kNever = std::numeric_limits<int>::max();
  /// The yaw rate at its last turning update [rad/s] (TrackerParams::Turning::hold_rate_fraction).
  double last_turn_rate_rps = 0.0;
  /// Length plus width when the box last grew by more than Turning::settle_growth_m (or
  /// shrank), and the updates since (TrackerParams::Turning::shrink_settled).
  double settled_extent_m = 0.0;
  int updates_settled = 0;
  int small_hits = 0;        ///< consecutive updates small (TrackerParams::Small::walker_hits)
  /// The larger side of the outline the last update measured (its box, where it was not measured).
  double seen_extent_m = 0.0;
  bool walker = false;       ///< see TrackerParams::walker_hits
  /// Consecutive updates faster than TrackerParams::Small::walker_max_speed_mps, and whether
  /// they have reached vehicle_pace_updates (it stays so).
  int fast_updates = 0;
  bool vehicle_pace = false;
  /// The widest its outline has shown across the line of sight (small tracks at a walker's pace,
  /// TrackerParams::Small::centre_from_silhouette) [m].
  double across_extent_m = 0.0;
  /// The last box measured had an end cut sideways, by a head's column edge or an occluder: what
  /// shows may be the corner of a larger body (a car coming into view is born as a small patch).
  bool outline_cut = false;
  /// The last update measured the outline's axis (TrackerParams::Heading).
  bool axis_seen = false;
  /// The last update's outline showed a line or an L too short for an axis, no face
  /// (TrackerParams::Turning::line_max_angle_rad), and the direction of its rectangle.
  bool line_seen = false;
  Eigen::Vector2d line_axis = Eigen::Vector2d::UnitX();
  /// Scale of the motion noise variances (TrackerParams::Motion::min_noise_scale and
  /// max_noise_scale).
  double noise_scale = 1.0;
  /// The updates' corrections dx^T P^-1 dx and what a consistent filter expects of them,
  /// summed with TrackerParams::Calibration::memory.
  double corrections = 0.0;
  double expected_corrections = 0.0;
  /// The time the track has been predicted through [s], and the outline's axes it measured
  /// within the last TrackerParams::Turning::straight_window_s: the along-body direction,
  /// oriented with the velocity and unwrapped, at that time, and its variance.
  struct AxisSample {
    double t_s = 0.0;
    double angle_rad = 0.0;
    double var_rad2 = 0.0;
  };
  double clock_s = 0.0;
  std::vector<AxisSample> axes;
  /// The last outline's axis beyond TrackerParams::Heading::gate_sigmas (oriented with the
  /// velocity; at t_s -infinity before any).
  AxisSample beyond_gate{-std::numeric_limits<double>::infinity(), 0.0, 0.0};

  Eigen::Vector2d centre() const { return x.head<2>(); }
  Eigen::Vector2d velocity() const { return x.segment<2>(2); }
  double yaw_rate() const { return x(4); }
  /// The standard deviation of the yaw rate, from its variance [rad/s].
  double yaw_rate_sigma() const { return std::sqrt(std::max(0.0, P(4, 4))); }
  /// A walker, or a box under small_object_m on both axes: see TrackerParams::small_object_m.
  bool small(const TrackerParams& p) const {
    return walker || std::max(length_m, width_m) < p.small.small_object_m;
  }
  /// At a walker's pace and never at a vehicle's (vehicle_pace): a walker or walkers side by
  /// side, not a car slowed to a walker's pace in a queue.
  bool at_walkers_pace(const TrackerParams& p) const {
    return !vehicle_pace && velocity().norm() <= p.small.walker_max_speed_mps;
  }
  /// Larger than a walker at a walker's pace, never at a vehicle's: maybe a group of walkers
  /// (TrackerParams::Small::group_sigma_mps).
  bool may_be_group(const TrackerParams& p) const { return !small(p) && at_walkers_pace(p); }
  /// Its next motion is not what its past updates say: a small object (a walker's gait), one
  /// at_walkers_pace (walkers side by side make one box) or a turning one (|yaw rate| above
  /// turning.min_turn_rate_rps). Keeps at least the full noise (Motion::min_noise_scale; a
  /// turning one may have more, Motion::max_noise_scale) and reports the filter's covariance
  /// (Calibration).
  bool unsteady(const TrackerParams& p) const {
    return small(p) || at_walkers_pace(p) || std::abs(yaw_rate()) > p.turning.min_turn_rate_rps;
  }
  /// The factor on the filter's covariance it reports (TrackerParams::Calibration).
  double covariance_scale(const TrackerParams& p) const;
  /// At least vehicle_length_m long: see TrackerParams::vehicle_length_m.
  bool vehicle(const TrackerParams& p) const { return length_m >= p.association.vehicle_length_m; }
  /// Confirmed, recently seen and moving: its pixels stay "moving" inside the blind band.
  bool carries(const TrackerParams& p) const {
    return confirmed && slow_frames < p.lifecycle.release_slow_frames && misses <= p.lifecycle.max_misses;
  }
};

/// What the tracker knows of the static world while the rig stands: per pixel the farthest
/// range seen since the rig stopped (infinite where a beam returned nothing), and over how many
/// frames (TrackerParams::Background).
class BackgroundModel {
 public:
  void reset();
  /// At the start of a frame: starts again when the rig moves or the scan's shape changes.
  void begin_frame(const Scan& scan, bool standing);
  /// The background holds enough frames to be used.
  bool ready(const TrackerParams::Background& p) const { return p.min_frames > 0 && frames_ >= p.min_frames; }
  /// Pixel i is nearer, by margin_m, than the farthest range its 3 x 3 neighbourhood has seen:
  /// something has come into space the beams saw empty. The neighbourhood's least such range
  /// keeps the edge of a static body (its pixels see it in one frame and what lies behind in
  /// the next) out of it.
  bool foreground(const Scan& scan, std::size_t i, double margin_m) const;
  /// At the end of a frame in which the rig stands: the scan joins the background.
  void add(const Scan& scan);
  int frames() const { return frames_; }

 private:
  std::vector<float> range_m_;
  int frames_ = 0;
};

struct ScanBeams;  // internal to core: the scan's unit beam directions

/// A Kalman filter per object with a constant-turn-rate model. Each update uses every Doppler
/// row of the object's pixels directly, v_i = e_i . (v + omega z x (o_i - c)) (the rotation
/// term reduces to the beam origin o_i, since e_i is parallel to p_i - o_i), and the centre of
/// its box. Frames must come in time order; the tracker resets on a gap or a step back.
/// The stages live in core/src/tracking/ (docs/ARCHITECTURE.md).
class ObjectTracker {
 public:
  explicit ObjectTracker(const TrackerParams& params = {});

  void reset();

  /// Updates the tracks with one frame's estimate, then rewrites the estimate: pixels that a
  /// carrying track claims inside its predicted box become moving (joining its cluster, or a
  /// new one), clusters of one track are merged, and each tracked cluster's velocity becomes
  /// the track's velocity at its centre (rig axes). The estimate must come from `scan`.
  void update(const Scan& scan, MotionEstimate& estimate);
  /// The same with the scan's beams already computed (the pipeline's path).
  void update(const Scan& scan, const ScanBeams& beams, MotionEstimate& estimate);

  const std::vector<Track>& tracks() const { return tracks_; }
  const TrackerParams& params() const { return params_; }

 private:
  /// Dead reckoning of the rig by the mean of two frames' twists, and prediction of every
  /// track to this frame; resets on a gap. Returns false when the estimate has no ego.
  bool advance(const Scan& scan, const MotionEstimate& est);

  TrackerParams params_;
  std::vector<Track> tracks_;
  /// Confirmed tracks missed too long, kept for Lifecycle::reid_frames frames to give their id
  /// to a track born where they are predicted.
  std::vector<Track> lost_;
  std::int32_t next_id_ = 1;
  bool has_pose_ = false;
  double last_stamp_s_ = 0.0;
  double yaw_ = 0.0;                                       ///< rig heading in the tracker's world
  Eigen::Vector2d position_ = Eigen::Vector2d::Zero();     ///< rig origin in the tracker's world
  Eigen::Vector3d last_ego_velocity_ = Eigen::Vector3d::Zero();
  double last_ego_yaw_rate_ = 0.0;
  BackgroundModel background_;
};

}  // namespace fmcw::core
