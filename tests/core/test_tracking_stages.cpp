// The tracker's stages (core/src/tracking/) one by one, on hand-made pixel sets whose answer is
// known: the constant-turn-rate propagation against the closed-form arc, the box anchored at
// the end of an outline that the sensor sees and not at one the view cuts, association gating,
// and the background model with the claims of a carrying track.

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <random>
#include <set>
#include <utility>

#include "fmcw/core/motion_pipeline.hpp"
#include "fmcw/core/synthetic_scan.hpp"
#include "scenes.hpp"
#include "tracking/association.hpp"
#include "tracking/claims.hpp"
#include "tracking/ctrv.hpp"
#include "tracking/measurement.hpp"
#include "tracking/outline_axis.hpp"
#include "tracking/relabel.hpp"
#include "tracking/track_birth.hpp"
#include "tracking/track_box.hpp"

namespace fmcw::core::tracking {
namespace {

// A 5 x 20 scan of one head at the rig origin, every pixel invalid until set.
struct HandScan {
  Scan scan = Scan::make_empty(5, 20);
  void set(int r, int c, const Eigen::Vector3d& p, double doppler_mps) {
    const std::size_t i = scan.index(r, c);
    scan.x_m[i] = static_cast<float>(p.x());
    scan.y_m[i] = static_cast<float>(p.y());
    scan.z_m[i] = static_cast<float>(p.z());
    scan.range_m[i] = static_cast<float>(p.norm());
    scan.radial_velocity_mps[i] = static_cast<float>(doppler_mps);
    scan.intensity[i] = 1.0f;
    scan.valid[i] = 1;
  }
};

// The rig standing at the tracker's origin.
Frame standing_frame(const Scan& scan, const ScanBeams& beams) {
  return Frame{scan, beams, Eigen::Matrix2d::Identity(), Eigen::Vector2d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
}

// ---- CTRV filter --------------------------------------------------------------------------

TEST(TrackingCtrv, PropagationFollowsTheClosedFormArc) {
  // In complex numbers: p(t) = p0 + v0 (e^{i w t} - 1) / (i w), v(t) = v0 e^{i w t}.
  const std::complex<double> p0(1.0, 2.0), v0(8.0, -3.0);
  for (const double w : {0.4, -1.1, 1e-12, 0.0}) {
    for (const double dt : {0.1, 0.7, 2.0}) {
      Vec5 x;
      x << p0.real(), p0.imag(), v0.real(), v0.imag(), w;
      const Vec5 y = propagate(x, dt);
      const std::complex<double> turn = std::polar(1.0, w * dt);
      const std::complex<double> p = std::abs(w) > 1e-9 ? p0 + v0 * (turn - 1.0) / std::complex<double>(0.0, w) : p0 + v0 * dt;
      const std::complex<double> v = v0 * turn;
      EXPECT_NEAR(y(0), p.real(), 1e-9) << "w " << w << " dt " << dt;
      EXPECT_NEAR(y(1), p.imag(), 1e-9) << "w " << w << " dt " << dt;
      EXPECT_NEAR(y(2), v.real(), 1e-12);
      EXPECT_NEAR(y(3), v.imag(), 1e-12);
      EXPECT_EQ(y(4), w);
    }
  }
}

TEST(TrackingCtrv, PredictionTurnsTheBoxAndGrowsTheCovariance) {
  Track t;
  t.x << 0.0, 0.0, 10.0, 0.0, 0.5;
  t.P = Mat5::Identity() * 0.01;
  const Vec5 expected = propagate(t.x, 0.2);
  predict(t, 0.2, TrackerParams{}.motion);
  EXPECT_TRUE(t.x.isApprox(expected));
  EXPECT_NEAR(t.heading_rad, 0.1, 1e-12);
  EXPECT_TRUE(t.P.isApprox(t.P.transpose()));
  EXPECT_GT(t.P(0, 0), 0.01);  // position uncertainty grows with velocity and acceleration noise
  EXPECT_GT(t.P(4, 4), 0.01);
  // The position's variance along y picks up the yaw rate's: y moves by v dt^2 / 2 per rad/s.
  EXPECT_GT(t.P(1, 4), 0.0);
}

// A car-sized track at (20, 5) driving along x at `speed_mps`, turning at `yaw_rate_rps`.
Track car_track(double speed_mps, double yaw_rate_rps = 0.0) {
  Track t;
  t.x << 20.0, 5.0, speed_mps, 0.0, yaw_rate_rps;
  t.length_m = 4.5;
  t.width_m = 1.8;
  return t;
}

TEST(TrackingCtrv, TheNoiseScaleFollowsTheCorrectionsWithinItsBounds) {
  TrackerParams p;  // gains 0.5 up and 0.1 down
  p.motion.min_noise_scale = 0.03;
  Track t = car_track(10.0);
  // Corrections of none of what a consistent filter expects: s (1 + 0.1 (0 - 1)) = 0.9 s.
  adapt_noise(t, 0.0, 2.0, p);
  EXPECT_DOUBLE_EQ(t.noise_scale, 0.9);
  adapt_noise(t, 1.0, 2.0, p);  // half: s (1 - 0.05)
  EXPECT_DOUBLE_EQ(t.noise_scale, 0.9 * 0.95);
  for (int k = 0; k < 100; ++k) adapt_noise(t, 0.0, 2.0, p);
  EXPECT_DOUBLE_EQ(t.noise_scale, p.motion.min_noise_scale);
  // Three times what it expects (a manoeuvre begins): s (1 + 0.5 (3 - 1)) = 2 s, up to
  // max_noise_scale.
  adapt_noise(t, 6.0, 2.0, p);
  EXPECT_DOUBLE_EQ(t.noise_scale, 2.0 * p.motion.min_noise_scale);
  for (int k = 0; k < 10; ++k) adapt_noise(t, 6.0, 2.0, p);
  EXPECT_DOUBLE_EQ(t.noise_scale, p.motion.max_noise_scale);
  // A correction that says nothing (no expectation, not finite) leaves the scale as it is.
  t.noise_scale = 0.5;
  adapt_noise(t, 1.0, 0.0, p);
  adapt_noise(t, std::numeric_limits<double>::quiet_NaN(), 2.0, p);
  EXPECT_DOUBLE_EQ(t.noise_scale, 0.5);
  // Walkers, objects at a walker's pace and turning tracks go back to the full noise; turning
  // ones keep at least it.
  for (Track other : {car_track(2.0), car_track(10.0, 0.1)}) {
    other.noise_scale = 0.5;
    adapt_noise(other, 0.0, 2.0, p);
    EXPECT_EQ(other.noise_scale, 1.0);
  }
  Track walker = car_track(10.0);
  walker.length_m = walker.width_m = 0.6;
  walker.noise_scale = 0.5;
  adapt_noise(walker, 0.0, 2.0, p);
  EXPECT_EQ(walker.noise_scale, 1.0);
  // min_noise_scale = max_noise_scale = 1: the fixed noises.
  TrackerParams fixed;
  fixed.motion.max_noise_scale = 1.0;
  Track f = car_track(10.0);
  adapt_noise(f, 0.0, 2.0, fixed);
  adapt_noise(f, 6.0, 2.0, fixed);
  EXPECT_EQ(f.noise_scale, 1.0);
}

TEST(TrackingCtrv, AManoeuvreRaisesTheNoiseAboveTheFullNoiseAndAWalkerDoesNot) {
  const TrackerParams p;  // the defaults: never below the full noise, up to 4 times it
  ASSERT_EQ(p.motion.min_noise_scale, 1.0);
  ASSERT_EQ(p.motion.max_noise_scale, 4.0);
  // A car corrected by three times what its filter expects, update after update: 1, 2, 4, 4.
  Track car = car_track(10.0);
  adapt_noise(car, 6.0, 2.0, p);
  EXPECT_DOUBLE_EQ(car.noise_scale, 2.0);
  adapt_noise(car, 6.0, 2.0, p);
  EXPECT_DOUBLE_EQ(car.noise_scale, 4.0);
  adapt_noise(car, 6.0, 2.0, p);
  EXPECT_DOUBLE_EQ(car.noise_scale, 4.0);
  // The manoeuvre over (corrections of none of what it expects): down by a tenth an update, to
  // the full noise and no further.
  adapt_noise(car, 0.0, 2.0, p);
  EXPECT_DOUBLE_EQ(car.noise_scale, 3.6);
  for (int k = 0; k < 100; ++k) adapt_noise(car, 0.0, 2.0, p);
  EXPECT_DOUBLE_EQ(car.noise_scale, 1.0);
  // A turning car likewise; an object at a walker's pace and a small one keep the full noise.
  Track turning = car_track(10.0, 0.5);
  adapt_noise(turning, 6.0, 2.0, p);
  EXPECT_DOUBLE_EQ(turning.noise_scale, 2.0);
  Track slow = car_track(2.0);
  Track small = car_track(10.0);
  small.length_m = small.width_m = 0.6;
  for (Track* t : {&slow, &small}) {
    adapt_noise(*t, 6.0, 2.0, p);
    EXPECT_EQ(t->noise_scale, 1.0);
  }
}

// A linear case for the filter's consistency: a car track with a correlated prior, and a
// measurement of its position, its velocity along x and a Doppler-like row on the velocity
// along y and the yaw rate.
struct LinearCase {
  Track prior = car_track(10.0);
  Eigen::Matrix<double, 4, 5> H = Eigen::Matrix<double, 4, 5>::Zero();
  Eigen::Vector4d r_sigma{0.7, 0.7, 0.1, 0.1};
  Eigen::Matrix4d R_inv;
  Mat5 info;
  LinearCase() {
    Eigen::Matrix<double, 5, 5> A = Eigen::Matrix<double, 5, 5>::Identity();
    A(2, 4) = 0.3;
    A(0, 2) = 0.1;
    prior.P = A * Eigen::Matrix<double, 5, 1>(0.5, 0.4, 1.0, 0.8, 0.1).asDiagonal() * A.transpose();
    H(0, 0) = H(1, 1) = H(2, 2) = 1.0;
    H(3, 3) = 1.0;
    H(3, 4) = 5.0;
    R_inv = r_sigma.cwiseInverse().cwiseAbs2().asDiagonal();
    info = H.transpose() * R_inv * H;
    L = Eigen::LLT<Mat5>(prior.P).matrixL();
  }
  Mat5 L;  ///< Cholesky factor of the prior's covariance
  /// A truth drawn from N(x, scale P), measured with noise of scale R; `t` (the prior, with
  /// whatever sums it carries) updated by that measurement. Returns the truth.
  Vec5 draw_and_update(Track& t, double scale, std::mt19937_64& rng, std::normal_distribution<double>& n01,
                       const TrackerParams& p) const {
    Vec5 z5;
    for (int j = 0; j < 5; ++j) z5(j) = n01(rng);
    const Vec5 truth = prior.x + std::sqrt(scale) * (L * z5);
    Eigen::Vector4d y = H * truth;
    for (int j = 0; j < 4; ++j) y(j) += std::sqrt(scale) * r_sigma(j) * n01(rng);
    information_update(t, info, H.transpose() * R_inv * (y - H * prior.x), p);
    return truth;
  }
};

TEST(TrackingCtrv, TheCorrectionOfAConsistentFilterIsWhatItExpects) {
  // Monte Carlo cross-check of E[dx^T P^-1 dx] = 5 - tr(P^-1 P_updated): states drawn from the
  // prior N(x, P), a linear measurement of position and velocity (and a Doppler-like row on the
  // yaw rate) drawn with its noise; the information update's corrections, averaged, give the
  // expectation, and with the truth drawn from P / 4 (a filter too cautious) a quarter of it.
  const LinearCase lc;
  const Mat5 P_inv = lc.prior.P.inverse();
  const double expected = 5.0 - (P_inv * (P_inv + lc.info).inverse()).trace();
  std::mt19937_64 rng(7);
  std::normal_distribution<double> n01;
  for (const double truth_scale : {1.0, 0.25}) {
    double sum = 0.0;
    const int draws = 20000;
    for (int k = 0; k < draws; ++k) {
      Track t = lc.prior;
      lc.draw_and_update(t, truth_scale, rng, n01, TrackerParams{});  // fixed noise
      const Vec5 dx = t.x - lc.prior.x;
      sum += dx.dot(P_inv * dx);
    }
    EXPECT_NEAR(sum / draws / expected, truth_scale, 0.03) << "truth drawn from " << truth_scale << " P";
  }
}

TEST(TrackingCtrv, TheCovarianceScaleFollowsTheCorrectionsWithinItsBounds) {
  TrackerParams p;  // memory 0.9, prior_dof 1, min_scale 0.05
  Track t = car_track(10.0);
  EXPECT_DOUBLE_EQ(t.covariance_scale(p), 1.0);  // no update yet: the filter's covariance
  follow_corrections(t, 0.5, 2.0, p.calibration);
  follow_corrections(t, 0.25, 1.0, p.calibration);
  EXPECT_DOUBLE_EQ(t.corrections, 0.9 * 0.5 + 0.25);
  EXPECT_DOUBLE_EQ(t.expected_corrections, 0.9 * 2.0 + 1.0);
  EXPECT_DOUBLE_EQ(t.covariance_scale(p), (0.7 + 1.0) / (2.8 + 1.0));
  // A correction that is negative (rounding) or not finite, or an expectation that is not finite
  // and positive, says nothing.
  follow_corrections(t, -1e-17, 2.0, p.calibration);
  follow_corrections(t, std::numeric_limits<double>::quiet_NaN(), 2.0, p.calibration);
  follow_corrections(t, 1.0, 0.0, p.calibration);
  follow_corrections(t, 1.0, std::numeric_limits<double>::infinity(), p.calibration);
  EXPECT_DOUBLE_EQ(t.corrections, 0.7);
  // Within [min_scale, 1].
  for (int k = 0; k < 200; ++k) follow_corrections(t, 0.0, 3.0, p.calibration);
  EXPECT_DOUBLE_EQ(t.covariance_scale(p), p.calibration.min_scale);
  Track wild = car_track(10.0);
  follow_corrections(wild, 30.0, 3.0, p.calibration);
  EXPECT_DOUBLE_EQ(wild.covariance_scale(p), 1.0);
  // Unsteady tracks (turning, at a walker's pace, small) and the rule off: the filter's covariance.
  for (Track other : {car_track(10.0, 0.1), car_track(2.0)}) {
    other.corrections = 0.0;
    other.expected_corrections = 30.0;
    EXPECT_EQ(other.covariance_scale(p), 1.0);
  }
  Track walker = car_track(10.0);
  walker.length_m = walker.width_m = 0.6;
  walker.expected_corrections = 30.0;
  EXPECT_EQ(walker.covariance_scale(p), 1.0);
  // A car that has driven at a vehicle's pace and slowed to a walker's in a queue is neither a
  // walker nor a group of them: its covariance follows its updates. Turning, or small, it still
  // reports the filter's.
  Track queued = car_track(2.0);
  queued.vehicle_pace = true;
  queued.corrections = 1.0;
  queued.expected_corrections = 30.0;
  EXPECT_DOUBLE_EQ(queued.covariance_scale(p), 2.0 / 31.0);
  Track queued_turning = car_track(2.0, 0.1);
  queued_turning.vehicle_pace = true;
  queued_turning.expected_corrections = 30.0;
  EXPECT_EQ(queued_turning.covariance_scale(p), 1.0);
  Track queued_small = queued;
  queued_small.length_m = queued_small.width_m = 0.6;
  EXPECT_EQ(queued_small.covariance_scale(p), 1.0);
  TrackerParams off;
  off.calibration.enabled = false;
  EXPECT_EQ(t.covariance_scale(off), 1.0);
  Track unfed = car_track(10.0);
  follow_corrections(unfed, 0.5, 2.0, off.calibration);
  EXPECT_EQ(unfed.corrections, 0.0);
  EXPECT_EQ(unfed.expected_corrections, 0.0);
}

TEST(TrackingCtrv, AFilterTooCautiousReportsACovarianceItsErrorsFill) {
  // A filter whose noises are four times the truth's (the truth drawn from P / 4, the
  // measurements with a quarter of their variance): its own velocity covariance holds the
  // error inside the 95 % ellipse almost always; scaled as its corrections say, 95 % of the
  // time. Updates in sequence, the sums carried from one to the next (memory 0.99).
  TrackerParams p;
  p.calibration.memory = 0.99;
  p.turning.min_turn_rate_rps = 10.0;  // the yaw rates drawn here would make some tracks unsteady
  const LinearCase lc;
  std::mt19937_64 rng(11);
  std::normal_distribution<double> n01;
  double corrections = 0.0, expected = 0.0;
  int inside_filter = 0, inside_scaled = 0, counted = 0;
  const int draws = 20000;
  for (int k = 0; k < draws; ++k) {
    Track t = lc.prior;
    t.corrections = corrections;
    t.expected_corrections = expected;
    const Vec5 truth = lc.draw_and_update(t, 0.25, rng, n01, p);
    corrections = t.corrections;
    expected = t.expected_corrections;
    if (k < 500) continue;  // the sums settle
    const Eigen::Vector2d e = (truth - t.x).segment<2>(2);
    const Eigen::Matrix2d cov = t.P.block<2, 2>(2, 2);
    const double nees = e.dot(cov.inverse() * e);
    ++counted;
    inside_filter += nees <= 5.991464547107979 ? 1 : 0;
    inside_scaled += nees / t.covariance_scale(p) <= 5.991464547107979 ? 1 : 0;
  }
  EXPECT_NEAR(corrections / expected, 0.25, 0.05);
  EXPECT_GT(static_cast<double>(inside_filter) / counted, 0.999);
  EXPECT_NEAR(static_cast<double>(inside_scaled) / counted, 0.95, 0.01);
}

TEST(TrackingCtrv, ALostTracksMotionIsFusedAsAPriorByItsCovariance) {
  // A new track whose scan measured its velocity along x (2 m/s, sigma 0.1) and not along y
  // (0 +- 6 m/s), and a lost track's prediction (2, 8) m/s, sigma 1 each, yaw rate 0.3 +- 0.1
  // rad/s against the new track's 0 +- 0.4. Independent axes: each is the inverse-variance mean.
  Track born;
  born.x << 20.0, 5.0, 2.0, 0.0, 0.0;
  born.P = Mat5::Zero();
  born.P.diagonal() << 0.49, 0.49, 0.01, 36.0, 0.16;
  Track lost;
  lost.x << 19.0, 4.0, 2.0, 8.0, 0.3;
  lost.P = Mat5::Zero();
  lost.P.diagonal() << 4.0, 4.0, 1.0, 1.0, 0.01;
  Track t = born;
  fuse_motion_prior(t, lost);
  const auto mean = [](double a, double va, double b, double vb) {
    return (a / va + b / vb) / (1.0 / va + 1.0 / vb);
  };
  EXPECT_EQ(t.x(0), 20.0);  // the position is the new track's
  EXPECT_EQ(t.x(1), 5.0);
  EXPECT_NEAR(t.x(2), 2.0, 1e-12);
  EXPECT_NEAR(t.x(3), mean(0.0, 36.0, 8.0, 1.0), 1e-12);  // 7.78 m/s
  EXPECT_NEAR(t.x(4), mean(0.0, 0.16, 0.3, 0.01), 1e-12);
  EXPECT_NEAR(t.P(3, 3), 1.0 / (1.0 / 36.0 + 1.0), 1e-12);
  EXPECT_NEAR(t.P(4, 4), 1.0 / (1.0 / 0.16 + 1.0 / 0.01), 1e-12);
  EXPECT_EQ(t.P(0, 0), 0.49);
  // A prior without a covariance to weigh it by changes nothing.
  Track singular = lost;
  singular.P.block<3, 3>(2, 2).setZero();
  Track u = born;
  fuse_motion_prior(u, singular);
  EXPECT_EQ(u.x, born.x);
  EXPECT_EQ(u.P, born.P);
  Track nan_prior = lost;
  nan_prior.x(3) = std::numeric_limits<double>::quiet_NaN();
  fuse_motion_prior(u, nan_prior);
  EXPECT_EQ(u.x, born.x);
}

// ---- The Doppler rows -----------------------------------------------------------------------

// The rows of test_object_tracker's circling car (0.4 rad/s on a 15 m circle about (30, 0)) at
// time t, rendered without noise, and the least-squares fit of its velocity and yaw rate about
// its true centre on them: the normal matrix of the rows' velocity and yaw columns (row_jacobian
// at the true state), its solution, and the heads its rows come from.
struct RowsFit {
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Vector3d solution = Eigen::Vector3d::Zero();
  Vec5 truth = Vec5::Zero();
  std::set<std::pair<double, double>> origins;
  double worst_prediction = 0.0;  // largest |predicted(r, truth) - r.y| [m/s]
  std::size_t rows = 0;
};

RowsFit fit_circling_rows(double t) {
  const SyntheticBox b = fmcw::test::car_on_a_circle(30.0, 15.0, 0.4, t);
  SyntheticSceneParams sp;
  sp.actors.push_back(b);
  sp.range_noise_m = 0.0;
  sp.velocity_noise_mps = 0.0;
  const fmcw::core::Frame rendered = render_synthetic_scan(sp);
  const ScanBeams beams(rendered.scan);
  const Frame frame = standing_frame(rendered.scan, beams);
  RowsFit f;
  f.truth << b.center_m.x(), b.center_m.y(), b.velocity_mps.x(), b.velocity_mps.y(), b.yaw_rate_rps;
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < rendered.scan.size(); ++i) {
    if (!rendered.scan.valid[i] || rendered.truth->instance[i] != 1) continue;
    const Row r = frame.row_of(static_cast<std::uint32_t>(i));
    const Eigen::Vector3d h = row_jacobian(r, f.truth).tail<3>();
    f.normal += h * h.transpose();
    rhs += h * r.y;
    f.origins.insert({r.o.x(), r.o.y()});
    f.worst_prediction = std::max(f.worst_prediction, std::abs(predicted(r, f.truth) - r.y));
    ++f.rows;
  }
  f.solution = f.normal.ldlt().solve(rhs);
  return f;
}

TEST(TrackingRows, OneHeadsRowsReadOneVelocityTwoHeadsReadTheYawRate) {
  // A row predicts e . (v + omega z x (o - c)) with o its beam's origin: the rows of one head
  // read one vector, the body's velocity field at that head's origin, and tell of the yaw rate
  // apart from it only through another head's origin (docs/EVALUATION.md, "The circling car's
  // yaw rate read across two heads"). Without noise every row is what the true state predicts.
  // Across the seam of the right and the front head (0.49 m apart) the rows fix velocity and
  // yaw rate; in the front head alone their normal matrix is singular: any yaw rate, with the
  // velocity that keeps the field at the origin, fits them.
  const RowsFit seam = fit_circling_rows(1.2);  // frame 12
  ASSERT_GT(seam.rows, 100u);
  EXPECT_EQ(seam.origins.size(), 2u);
  EXPECT_LT(seam.worst_prediction, 1e-4);  // the scan stores its Doppler as float
  EXPECT_NEAR(seam.solution(2), 0.4, 1e-4);
  EXPECT_NEAR(seam.solution(0), seam.truth(2), 1e-3);
  EXPECT_NEAR(seam.solution(1), seam.truth(3), 1e-3);

  const RowsFit front = fit_circling_rows(3.0);  // frame 30
  ASSERT_GT(front.rows, 100u);
  EXPECT_EQ(front.origins.size(), 1u);
  EXPECT_LT(front.worst_prediction, 1e-4);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(front.normal);
  EXPECT_LT(eig.eigenvalues().minCoeff(), 1e-9 * eig.eigenvalues().maxCoeff());
  // The null direction: a yaw rate dw with the velocity -dw z x (o - c), the field at o unmoved.
  const Eigen::Vector2d o(front.origins.begin()->first, front.origins.begin()->second);
  const Eigen::Vector2d d = o - front.truth.head<2>();
  Eigen::Vector3d null(d.y(), -d.x(), 1.0);
  null.normalize();
  EXPECT_LT((front.normal * null).norm(), 1e-9 * eig.eigenvalues().maxCoeff());
}

// ---- The box: anchoring and view cuts -----------------------------------------------------

// A car track 1.8 m wide heading along +x at 5 m/s, centre (x, 15.9), `length` long.
Track track_along_x(double x, double length) {
  Track tr;
  tr.x << x, 15.9, 5.0, 0.0, 0.0;
  tr.length_m = length;
  tr.width_m = 1.8;
  tr.heading_rad = tr.extents_heading_rad = 0.0;
  return tr;
}

// A group of every valid pixel of the scan, found moving.
Group every_valid_pixel(const Scan& scan) {
  Group g;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (scan.valid[i]) g.found.push_back(static_cast<std::uint32_t>(i));
  }
  return g;
}

// A car 4.5 m long, heading along +x, of which the 2 m from x = 10 to 12 show at y = 15 (the
// rig at the origin sees its rear end, x = 10). With the rear pixel on the head's first column
// the view cuts that end, and the box cannot be anchored there.
Eigen::Vector2d measured_centre(bool rear_on_view_edge, double predicted_x) {
  HandScan h;
  for (int n = 0; n <= 8; ++n) {
    const int col = n == 0 && rear_on_view_edge ? 0 : 2 + n;
    h.set(2, col, Eigen::Vector3d(10.0 + 0.25 * n, 15.0, 0.5), 0.0);
  }
  const ScanBeams beams(h.scan);
  const Frame frame = standing_frame(h.scan, beams);
  Track tr = track_along_x(predicted_x, 4.5);
  const BoxMeasurement m =
      measure_box(tr, every_valid_pixel(h.scan), false, frame, ViewEdges(h.scan, TrackerParams{}.box.occlusion_gap_m), TrackerParams{});
  EXPECT_TRUE(m.seen);
  EXPECT_NEAR(tr.length_m, 4.5, 1e-9);  // the longest extent seen stays
  return m.centre;
}

TEST(TrackingBox, AnchoredAtTheEndTheSensorSees) {
  // The seen rear end at x = 10 holds: centre at 10 + 4.5 / 2; across, the near side at y = 15.
  const Eigen::Vector2d c = measured_centre(false, 11.0);
  EXPECT_NEAR(c.x(), 12.25, 1e-6);
  EXPECT_NEAR(c.y(), 15.9, 1e-6);
}

TEST(TrackingBox, NotAnchoredAtAnEndTheViewCuts) {
  // Cut at the rear: no end is the body's own along x; the predicted centre, brought into
  // [hi - 2.25, lo + 2.25] = [9.75, 12.25], stands for the measurement.
  EXPECT_NEAR(measured_centre(true, 11.0).x(), 11.0, 1e-6);
  EXPECT_NEAR(measured_centre(true, 14.0).x(), 12.25, 1e-6);
  EXPECT_NEAR(measured_centre(true, 8.0).x(), 9.75, 1e-6);
}

TEST(TrackingBox, ViewEdgesCutAtTheHeadsColumnsAndTheTopAndBottomRows) {
  HandScan h;
  h.set(2, 0, Eigen::Vector3d(10.0, 15.0, 0.5), 0.0);   // first column
  h.set(2, 9, Eigen::Vector3d(10.0, 1.0, 0.5), 0.0);    // inside
  h.set(4, 9, Eigen::Vector3d(10.0, 1.0, -0.5), 0.0);   // bottom row: cut towards the sensor
  const ScanBeams beams(h.scan);
  const Frame frame = standing_frame(h.scan, beams);
  const ViewEdges edges(h.scan, TrackerParams{}.box.occlusion_gap_m);
  std::vector<Cut> cuts;
  edges.add_cuts(frame, static_cast<std::uint32_t>(h.scan.index(2, 9)), Eigen::Vector2d(10.0, 1.0), cuts);
  EXPECT_TRUE(cuts.empty());
  edges.add_cuts(frame, static_cast<std::uint32_t>(h.scan.index(2, 0)), Eigen::Vector2d(10.0, 15.0), cuts);
  ASSERT_EQ(cuts.size(), 1u);
  EXPECT_LT(cuts[0].direction.x(), -0.5);  // away from the head's axis, out of its field of view
  EXPECT_GT(cuts[0].direction.y(), 0.0);
  cuts.clear();
  edges.add_cuts(frame, static_cast<std::uint32_t>(h.scan.index(4, 9)), Eigen::Vector2d(10.0, 1.0), cuts);
  ASSERT_EQ(cuts.size(), 1u);
  EXPECT_LT(cuts[0].direction.x(), -0.9);  // towards the sensor
}

TEST(TrackingBox, ANeighbourInFrontCutsTheOutlineOnItsSide) {
  // Row 2: an object 20 m ahead on columns 5 to 9, and on column 4 something at 10 m in front
  // of it. The object's pixel beside it is cut towards column 4 (the left: column 0 is the left
  // edge), across the beam; the one on column 9 has nothing beside it.
  HandScan h;
  for (int c = 5; c <= 9; ++c) h.set(2, c, Eigen::Vector3d(20.0, 0.1 * (7 - c), 0.5), 0.0);
  h.set(2, 4, Eigen::Vector3d(10.0, 0.15, 0.5), 0.0);
  const ScanBeams beams(h.scan);
  const Frame frame = standing_frame(h.scan, beams);
  std::vector<Cut> cuts;
  const ViewEdges edges(h.scan, 1.0);
  edges.add_cuts(frame, static_cast<std::uint32_t>(h.scan.index(2, 9)), Eigen::Vector2d(20.0, -0.2), cuts);
  EXPECT_TRUE(cuts.empty());
  edges.add_cuts(frame, static_cast<std::uint32_t>(h.scan.index(2, 5)), Eigen::Vector2d(20.0, 0.2), cuts);
  ASSERT_EQ(cuts.size(), 1u);
  EXPECT_GT(cuts[0].direction.y(), 0.99);  // to the left, across the beam along +x
  cuts.clear();
  ViewEdges(h.scan, 0.0).add_cuts(frame, static_cast<std::uint32_t>(h.scan.index(2, 5)), Eigen::Vector2d(20.0, 0.2), cuts);
  EXPECT_TRUE(cuts.empty());  // 0: no occluders
}

TEST(TrackingBox, AnExtentGrowingAtTheEndNotSeenMovesThePredictionNotTheMeasurement) {
  // A track 2 m long heading along +x, its rear (the end the rig at the origin sees) predicted
  // at x = 10, centre 11. Now 3 m show, from 10 to 13: more of it has come into view at its
  // front. Measured from the rear, the centre is 11.5, and the prediction moves with the box's
  // centre, by half the growth: no innovation, as the rear is where it was predicted.
  HandScan h;
  for (int n = 0; n <= 12; ++n) h.set(2, 2 + n, Eigen::Vector3d(10.0 + 0.25 * n, 15.0, 0.5), 0.0);
  const ScanBeams beams(h.scan);
  const Frame frame = standing_frame(h.scan, beams);
  Track tr = track_along_x(11.0, 2.0);
  const BoxMeasurement m = measure_box(tr, every_valid_pixel(h.scan), false, frame, ViewEdges(h.scan, 0.0), TrackerParams{});
  EXPECT_NEAR(tr.length_m, 3.0, 1e-6);
  EXPECT_NEAR(m.centre.x(), 11.5, 1e-6);
  EXPECT_NEAR(tr.x(0), 11.5, 1e-6);
  EXPECT_NEAR(tr.x(1), 15.9, 1e-12);  // across, nothing grew
}

TEST(TrackingBox, AVehiclesHeadingSwingKeepsTheLengthItsTurnedBoxBoundsSeenEndOn) {
  // A bus 12 x 2.5 m, centre (30, 0.5), its extents measured along +x; its velocity has swung
  // 0.3 rad (beyond heading_reset_rad, 0.25), and only its rear face shows, across the new
  // heading 6 m behind the centre. The box is measured afresh along the new heading, but the old
  // box turned by the swing bounds the body: at least 12 cos 0.3 - 2.5 sin 0.3 = 10.72 m long,
  // anchored at the face (the rig at the origin sees it), where the face's pixels lie. Measured
  // as the face alone it would be a sliver at the face, its centre 6 m from the old one.
  const double swing = 0.3;
  const Eigen::Vector2d u(std::cos(swing), std::sin(swing));
  const Eigen::Vector2d w(-u.y(), u.x());
  const Eigen::Vector2d centre(30.0, 0.5);
  const Eigen::Vector2d face = centre - 6.0 * u;
  HandScan h;
  for (int r = 1; r <= 3; ++r) {
    for (int c = 4; c <= 15; ++c) {
      const Eigen::Vector2d q = face + (1.2 - 2.4 * (c - 4) / 11.0) * w;  // column 0 is the left
      h.set(r, c, Eigen::Vector3d(q.x(), q.y(), 0.5 + 0.8 * (3 - r)), 0.0);
    }
  }
  const ScanBeams beams(h.scan);
  const Frame frame = standing_frame(h.scan, beams);
  const TrackerParams p;
  Track bus;
  bus.x << centre.x(), centre.y(), 5.0 * u.x(), 5.0 * u.y(), 0.0;
  bus.length_m = 12.0;
  bus.width_m = 2.5;
  bus.heading_rad = bus.extents_heading_rad = 0.0;
  const BoxMeasurement m =
      measure_box(bus, every_valid_pixel(h.scan), false, frame, ViewEdges(h.scan, 0.0), p);
  ASSERT_TRUE(m.seen);
  EXPECT_NEAR(bus.extents_heading_rad, swing, 1e-12);
  const double least = 12.0 * std::cos(swing) - 2.5 * std::sin(swing);
  EXPECT_NEAR(bus.length_m, least, 1e-4);
  EXPECT_NEAR(bus.width_m, 2.4, 1e-4);  // the face's
  EXPECT_NEAR((m.centre - (face + 0.5 * least * u)).norm(), 0.0, 1e-4);
  // A walker's box swinging as much is measured afresh: a walker is no rigid body.
  Track walker = bus;
  walker.length_m = walker.width_m = 0.6;
  walker.heading_rad = walker.extents_heading_rad = 0.0;
  walker.x.segment<2>(2) = 1.2 * u;
  measure_box(walker, every_valid_pixel(h.scan), false, frame, ViewEdges(h.scan, 0.0), p);
  EXPECT_LT(walker.length_m, 0.01);
}

// A walker's track heading along +x at 1.2 m/s, centre (15.5, 3.5), box 0.6 x 0.5 m, and an
// outline 1.2 m long: its own pixels from x = 15.3 to 15.75 and a second walker's from 14.55 to
// 14.95, 0.55-0.95 m behind its centre, in its cluster. Returns the track after its box is
// measured.
Track walker_followed_closely(const TrackerParams& p) {
  HandScan h;
  for (int n = 0; n <= 10; ++n) {
    const double x = n < 5 ? 14.55 + 0.1 * n : 15.3 + 0.09 * (n - 5);
    h.set(2, 2 + n, Eigen::Vector3d(x, 3.5, 0.5), 1.2);
  }
  const ScanBeams beams(h.scan);
  const Frame frame = standing_frame(h.scan, beams);
  Track tr;
  tr.x << 15.5, 3.5, 1.2, 0.0, 0.0;
  tr.length_m = 0.6;
  tr.width_m = 0.5;
  tr.heading_rad = tr.extents_heading_rad = 0.0;
  tr.walker = true;
  measure_box(tr, every_valid_pixel(h.scan), false, frame, ViewEdges(h.scan, 0.0), p);
  return tr;
}

TEST(TrackingBox, AWalkersBoxStopsShortOfTheWalkerBehindIt) {
  // Capped at walker_box_m (0.9 m), the box grown by claims.claim_margin_m (0.25 m) reaches
  // 0.7 m behind the centre: the second walker's centre, 0.75 m behind, is outside it, and its
  // pixels are split off as a companion's. Capped at small_object_m (1.2, before), the box
  // holds it.
  const TrackerParams p;
  const Track tr = walker_followed_closely(p);
  EXPECT_NEAR(tr.length_m, 0.9, 1e-12);
  const Eigen::Vector2d behind(14.75, 3.5);
  EXPECT_FALSE(box_of(tr).contains(behind, p.claims.claim_margin_m));
  EXPECT_TRUE(box_of(tr).contains(Eigen::Vector2d(15.1, 3.5), p.claims.claim_margin_m));
  TrackerParams wide;
  wide.small.walker_box_m = 1.2;
  const Track before = walker_followed_closely(wide);
  EXPECT_NEAR(before.length_m, 1.2, 1e-5);  // the outline's (float points)
  EXPECT_TRUE(box_of(before).contains(behind, wide.claims.claim_margin_m));
}

TEST(TrackingBox, AFewPixelsFarBesideAVehicleAreNoPartOfItsBox) {
  // A car's side, 60 pixels from x = 10 to 14.4 at y = 15, its track heading along +x at 5 m/s
  // with a box 1.8 m wide. One more pixel of its cluster lies 10 m beside it (a pole behind its
  // edge): the outline across would be 10 m wide, wider than any body, and that pixel lies beyond
  // a gap of more than stray_gap_m: a stray, and the box keeps its width. One 2.5 m beside it
  // (its far side seen under the body) is within a body's width and counts.
  const auto width_with = [](double extra_y, const TrackerParams& p, double speed) {
    HandScan h;
    for (int r = 0; r < 5; ++r) {
      for (int c = 0; c < 12; ++c) h.set(r, c, Eigen::Vector3d(10.0 + 0.4 * c, 15.0, 0.3 * r), 0.0);
    }
    h.set(2, 15, Eigen::Vector3d(12.0, extra_y, 0.6), 0.0);
    const ScanBeams beams(h.scan);
    const Frame frame = standing_frame(h.scan, beams);
    Track tr = track_along_x(12.2, 4.4);
    tr.x(2) = speed;
    measure_box(tr, every_valid_pixel(h.scan), false, frame, ViewEdges(h.scan, 0.0), p);
    EXPECT_NEAR(tr.length_m, 4.4, 1e-6);
    return tr.width_m;
  };
  const TrackerParams p;
  EXPECT_NEAR(width_with(25.0, p, 5.0), 1.8, 1e-9);  // the stray left out
  EXPECT_NEAR(width_with(17.5, p, 5.0), 2.5, 1e-6);  // within a body's width: counts
  TrackerParams off = p;
  off.box.stray_gap_m = 0.0;
  EXPECT_NEAR(width_with(25.0, off, 5.0), p.box.max_width_m, 1e-9);  // every pixel counts
  // A walker's pace: a group of walkers in a row has no strays.
  EXPECT_NEAR(width_with(25.0, p, 1.0), p.box.max_width_m, 1e-9);
}

// A bus's side, 75 pixels from x = 10 to 22 at y = 15 (the sensor at the origin sees it and its
// rear), its track heading along +x at 5 m/s with a box 12 x 2.5 m, settled for `settled`
// updates; and 6 pixels of a car following it, from x = follower_x to follower_x + 0.8
// at y = 15.3, in its cluster. Returns the track after its box is measured, and the centre.
std::pair<Track, Eigen::Vector2d> bus_followed(double follower_x, int settled,
                                               const TrackerParams& p) {
  HandScan h;
  for (int r = 0; r < 5; ++r) {
    for (int c = 1; c <= 15; ++c) {
      h.set(r, c, Eigen::Vector3d(10.0 + 12.0 * (c - 1) / 14.0, 15.0, 0.6 * r), 0.0);
    }
  }
  for (int r = 1; r <= 3; ++r) {
    for (int c = 17; c <= 18; ++c) {
      h.set(r, c, Eigen::Vector3d(follower_x + 0.8 * (c - 17), 15.3, 0.6 * r), 0.0);
    }
  }
  const ScanBeams beams(h.scan);
  const Frame frame = standing_frame(h.scan, beams);
  Track tr = track_along_x(16.0, 12.0);
  tr.x(1) = 16.25;
  tr.width_m = 2.5;
  tr.updates_settled = settled;
  const BoxMeasurement m =
      measure_box(tr, every_valid_pixel(h.scan), false, frame, ViewEdges(h.scan, 0.0), p);
  EXPECT_TRUE(m.seen);
  return {tr, m.centre};
}

TEST(TrackingBox, ACarFollowingASettledBoxIsNoPartOfIt) {
  // The car 3.2 m behind the bus's rear: the outline, 16 m long, is under any body's size but
  // longer than the bus's box by more than stray_gap_m, and the car's pixels (7 % of them) lie
  // beyond a gap of more than stray_gap_m: strays. The box keeps its length and its centre,
  // anchored at the rear the sensor sees, stays the bus's.
  const TrackerParams p;
  const auto [bus, centre] = bus_followed(6.0, 5, p);
  EXPECT_NEAR(bus.length_m, 12.0, 1e-9);
  EXPECT_NEAR(centre.x(), 16.0, 1e-5);
  EXPECT_NEAR(centre.y(), 16.25, 1e-5);
  // Searched against any body's size only, the car stretches the box to 16 m, and the centre
  // moves 2 m back.
  TrackerParams any_body = p;
  any_body.box.own_stray_share = 0.0;
  const auto [stretched, moved] = bus_followed(6.0, 5, any_body);
  EXPECT_NEAR(stretched.length_m, 16.0, 1e-5);
  EXPECT_NEAR(moved.x(), 14.0, 1e-5);
  // A box that grew within its last own_stray_settled_updates may still be showing more of its
  // body: its pixels beyond a gap count.
  EXPECT_NEAR(bus_followed(6.0, p.box.own_stray_settled_updates - 1, p).first.length_m, 16.0, 1e-5);
  // Within the box's length plus stray_gap_m, pixels behind a gap count: the bus's own far end.
  EXPECT_NEAR(bus_followed(8.5, 5, p).first.length_m, 13.5, 1e-5);
}

// ---- The outline's axis ------------------------------------------------------------------

// A scene on the paper rig, noise as in Table I, and the pixels of its actors (one box: instance 1).
struct AxisCase {
  fmcw::core::Frame rendered;
  std::vector<std::uint32_t> pixels;
};

// The scene rendered with Table I's noise (seed 7), and the pixels of all its actors.
AxisCase render_actors(SyntheticSceneParams p) {
  p.range_noise_m = 0.025;
  p.velocity_noise_mps = 0.031;
  p.seed = 7;
  AxisCase c{render_synthetic_scan(p), {}};
  for (std::size_t i = 0; i < c.rendered.scan.size(); ++i) {
    if (c.rendered.scan.valid[i] && c.rendered.truth->instance[i] >= 1)
      c.pixels.push_back(static_cast<std::uint32_t>(i));
  }
  return c;
}

AxisCase render_box(const Eigen::Vector2d& centre, double length, double width, double yaw,
                    double height = 1.5) {
  SyntheticSceneParams p;
  SyntheticBox b;
  b.center_m = Eigen::Vector3d(centre.x(), centre.y(), 0.05 + 0.5 * height);
  b.half_extent_m = Eigen::Vector3d(0.5 * length, 0.5 * width, 0.5 * height);
  b.yaw_rad = yaw;
  p.actors.push_back(b);
  return render_actors(p);
}

OutlineAxis axis_of(const AxisCase& c, const TrackerParams::Heading& p = {}) {
  const ScanBeams beams(c.rendered.scan);
  return outline_axis(c.pixels, standing_frame(c.rendered.scan, beams), p);
}

// The angle between two axes, sign and half-turns ignored [rad].
double axis_angle(const Eigen::Vector2d& a, double yaw) {
  return std::acos(std::min(1.0, std::abs(a.dot(Eigen::Vector2d(std::cos(yaw), std::sin(yaw))))));
}

TEST(TrackingOutlineAxis, ACarSeenAtAnAngleShowsItsAxis) {
  // A car 4.5 x 1.8 m, 15 m ahead and 5 m to the left, heading 30 degrees: its near side and its
  // rear show, an L whose long arm is the body's axis.
  const AxisCase c = render_box({15.0, 5.0}, 4.5, 1.8, 30.0 * M_PI / 180.0);
  ASSERT_GT(c.pixels.size(), 200u);
  const OutlineAxis a = axis_of(c);
  EXPECT_TRUE(a.informative);
  EXPECT_LT(axis_angle(a.axis, 30.0 * M_PI / 180.0), 1.0 * M_PI / 180.0);
  EXPECT_NEAR(a.length_m, 4.5, 0.35);  // the far end of the near side shows at a grazing angle
  EXPECT_NEAR(a.width_m, 1.8, 0.2);
  TrackerParams::Heading off;
  off.use_outline = false;
  EXPECT_FALSE(axis_of(c, off).informative);  // the switch
}

TEST(TrackingOutlineAxis, ASquareOutlineOrARearFaceGivesNoAxis) {
  // A square body 2.4 x 2.4 m at 40 degrees: its rectangle has no long side to tell.
  const OutlineAxis square = axis_of(render_box({15.0, 5.0}, 2.4, 2.4, 40.0 * M_PI / 180.0));
  EXPECT_FALSE(square.informative);
  EXPECT_NEAR(square.length_m, 2.4, 0.25);
  // A car straight ahead, driving away: only its rear shows, a line 1.8 m long across the body.
  // Its long side is the body's width, not its length: shorter than min_length_m, no axis.
  const OutlineAxis rear = axis_of(render_box({20.0, 0.0}, 4.5, 1.8, 0.0));
  EXPECT_FALSE(rear.informative);
  EXPECT_LT(rear.length_m, 2.0);
}

// A track at `centre` (the rig at the origin) whose prior holds the line one scan leaves open:
// v = v_app - omega z x (o - c), omega ~ N(0, s0^2), its velocity v_app = v + omega z x (o - c)
// (the body's v, turning at omega) and its yaw rate 0.
Track track_on_the_doppler_line(const Eigen::Vector2d& centre, const Eigen::Vector2d& v, double omega,
                                double s0, double length, double width) {
  const Eigen::Vector2d sv(centre.y(), -centre.x());  // z x (o - c), o at the origin
  Track tr;
  tr.length_m = length;
  tr.width_m = width;
  tr.x << centre.x(), centre.y(), (v + omega * sv).x(), (v + omega * sv).y(), 0.0;
  tr.P = Mat5::Zero();
  tr.P.topLeftCorner<2, 2>() = 0.01 * Eigen::Matrix2d::Identity();
  tr.P.block<2, 2>(2, 2) = 0.01 * Eigen::Matrix2d::Identity() + s0 * s0 * sv * sv.transpose();
  tr.P.block<2, 1>(2, 4) = -s0 * s0 * sv;
  tr.P.block<1, 2>(4, 2) = -s0 * s0 * sv.transpose();
  tr.P(4, 4) = s0 * s0;
  return tr;
}

// The track updated with the axis (or face) of the case's outline alone: whether it was
// measured, and the track after.
std::pair<bool, Track> axis_updated(Track t, const AxisCase& c, const Frame& frame,
                                    const TrackerParams& p) {
  Mat5 info = Mat5::Zero();
  Vec5 grad = Vec5::Zero();
  const bool used = axis_information(t, c.pixels, frame, p, info, grad);
  EXPECT_EQ(used, t.axis_seen);
  information_update(t, info, grad, p);
  return {used, t};
}

TEST(TrackingOutlineAxis, TheAxisFixesTheYawRateTheDopplerLeavesOpen) {
  // A track whose prior holds the line one scan leaves open: v = v_app - omega z x (o - c), omega
  // ~ N(0, 0.4^2). The car (20 m ahead, heading 30 degrees, 8 m/s, turning at 0.4 rad/s) shows
  // v_app = v + omega z x (o - c); with its axis measured, velocity and yaw rate are found.
  const double yaw = 30.0 * M_PI / 180.0;
  const AxisCase c = render_box({20.0, 6.0}, 4.5, 1.8, yaw);
  const ScanBeams beams(c.rendered.scan);
  const Frame frame = standing_frame(c.rendered.scan, beams);
  const Eigen::Vector2d centre(20.0, 6.0), v = 8.0 * Eigen::Vector2d(std::cos(yaw), std::sin(yaw));
  const double omega = 0.4;
  Track tr = track_on_the_doppler_line(centre, v, omega, 0.4, 4.5, 1.8);
  Mat5 info = Mat5::Zero();
  Vec5 grad = Vec5::Zero();
  ASSERT_TRUE(axis_information(tr, c.pixels, frame, TrackerParams{}, info, grad));
  EXPECT_TRUE(tr.axis_seen);
  information_update(tr, info, grad, TrackerParams{});
  EXPECT_NEAR(tr.yaw_rate(), omega, 0.06);
  EXPECT_LT((tr.velocity() - v).norm(), 1.0);
  EXPECT_LT(std::sqrt(tr.P(4, 4)), 0.1);  // and it knows it
  // Off: nothing is added, and the track keeps not knowing.
  TrackerParams off;
  off.heading.use_outline = false;
  Mat5 none = Mat5::Zero();
  Vec5 none_grad = Vec5::Zero();
  EXPECT_FALSE(axis_information(tr, c.pixels, frame, off, none, none_grad));
  EXPECT_TRUE(none.isZero());
}

TEST(TrackingCtrv, AnUpdateThatMovesTheYawRateFarIsLinearisedAgainAndExplainsItsDoppler) {
  // A van (5 x 2 m) 45 m away, turning at 0.5 rad/s at 4 m/s. One scan sees its velocity at the
  // sensor, v_app = v + omega z x (o - c): 18 m/s across the beam. Its track is born on that line
  // with yaw rate 0 (track_on_the_doppler_line), predicted 0.1 s and updated with the next scan,
  // whose centre says it hardly moved. Linearised at the prediction (relinearise off) the update
  // finds the turn but misplaces every row: its own pixels' Doppler is off by more than the
  // association's tolerance, so the next frame would not give it its cluster. Linearised again at
  // its result (measurement.relinearise_mps), the update explains its pixels and holds the van's
  // motion.
  const Eigen::Vector2d c0(44.0, 9.0), v0(0.0, 4.0);
  const double omega = 0.5, dt = 0.1, s0 = 0.4;
  Vec5 truth0;
  truth0 << c0.x(), c0.y(), v0.x(), v0.y(), omega;
  const Vec5 truth = propagate(truth0, dt);
  SyntheticSceneParams sp;
  SyntheticBox b;
  b.center_m = Eigen::Vector3d(truth(0), truth(1), 1.1);
  b.half_extent_m = Eigen::Vector3d(2.5, 1.0, 1.0);
  b.yaw_rad = std::atan2(truth(3), truth(2));
  b.velocity_mps = Eigen::Vector3d(truth(2), truth(3), 0.0);
  b.yaw_rate_rps = omega;
  sp.actors.push_back(b);
  sp.range_noise_m = 0.025;
  sp.velocity_noise_mps = 0.031;
  sp.seed = 11;
  const fmcw::core::Frame rendered = render_synthetic_scan(sp);
  Group g;
  for (std::size_t i = 0; i < rendered.scan.size(); ++i) {
    if (rendered.scan.valid[i] && rendered.truth->instance[i] == 1)
      g.found.push_back(static_cast<std::uint32_t>(i));
  }
  ASSERT_GT(g.found.size(), 30u);
  const ScanBeams beams(rendered.scan);
  const Frame frame = standing_frame(rendered.scan, beams);
  const ViewEdges edges(rendered.scan, TrackerParams{}.box.occlusion_gap_m);
  const auto updated = [&](const TrackerParams& p) {
    Track tr = track_on_the_doppler_line(c0, v0, omega, s0, 5.0, 2.0);
    EXPECT_GT(tr.velocity().norm(), 15.0);  // the line's point at omega = 0
    predict(tr, dt, p.motion);
    measure(tr, g, false, frame, edges, p);
    return tr;
  };
  TrackerParams off;
  off.measurement.relinearise_iterations = 0;
  const Track linear = updated(off);
  EXPECT_GT(doppler_deviation(frame, g.found, linear),
            off.association.doppler_tolerance_mps);  // 2.3 m/s
  const TrackerParams p;
  const Track again = updated(p);
  EXPECT_LT(doppler_deviation(frame, g.found, again), 0.1);
  EXPECT_NEAR(again.yaw_rate(), omega, 0.05);  // linearised once: 0.72
  EXPECT_LT((again.velocity() - truth.segment<2>(2)).norm(), 0.5);
  // Neither a track at a walker's pace nor one past its first update after birth is updated
  // again: bit for bit as linearised once.
  const auto same_as_once = [&](Track t) {
    Track once = t;
    predict(t, dt, p.motion);
    predict(once, dt, off.motion);
    measure(t, g, false, frame, edges, p);
    measure(once, g, false, frame, edges, off);
    return t.x == once.x && t.P == once.P;
  };
  Track slow = track_on_the_doppler_line(c0, Eigen::Vector2d::Zero(), 0.0, s0, 5.0, 2.0);
  slow.x.segment<2>(2) = Eigen::Vector2d(0.5, 0.5);
  EXPECT_TRUE(same_as_once(slow));
  Track older = track_on_the_doppler_line(c0, v0, omega, s0, 5.0, 2.0);
  older.hits = p.measurement.relinearise_max_hits + 1;
  EXPECT_TRUE(same_as_once(older));
  older.hits = p.measurement.relinearise_max_hits;
  EXPECT_FALSE(same_as_once(older));
}

TEST(TrackingOutlineAxis, ItsHeadingIsFinerBroadsideThanEndOnAndCoarsestAlongside) {
  // The noise the tracker states for the heading an axis measures (axis_heading_variance). A
  // car 30 m away seen broadside: its side's direction comes from its points' ranges, and the
  // noise is sigma_rad. The same car turned 25 degrees off the line of sight: from their lateral
  // offsets, which scatter by end_sigma_per_m of the range, over the length, times the cosine.
  // A bus alongside, nearer than two of its lengths: near_sigma_rad. Each measured axis is within
  // 1.96 of its stated noise of the known heading.
  const TrackerParams::Heading p;
  const double bearing = 10.0 * M_PI / 180.0;
  const Eigen::Vector2d at30 = 30.0 * Eigen::Vector2d(std::cos(bearing), std::sin(bearing));
  const auto sigma_of = [&](const AxisCase& c, double yaw) {
    const OutlineAxis a = axis_of(c);
    EXPECT_TRUE(a.informative);
    const double sigma = std::sqrt(axis_heading_variance(a, Eigen::Vector2d::Zero(), false, p));
    EXPECT_LT(axis_angle(a.axis, yaw), 1.96 * sigma);
    return std::make_pair(a, sigma);
  };
  const double broadside_yaw = bearing + 0.5 * M_PI;
  const auto [broadside, s_broadside] = sigma_of(render_box(at30, 4.5, 1.8, broadside_yaw), broadside_yaw);
  const double end_on_yaw = bearing + 25.0 * M_PI / 180.0;
  const auto [end_on, s_end_on] = sigma_of(render_box(at30, 4.5, 1.8, end_on_yaw), end_on_yaw);
  EXPECT_NEAR(s_broadside, p.sigma_rad, 0.1 * p.sigma_rad);
  const double expected_end = p.end_sigma_per_m * 30.0 / end_on.length_m * std::cos(25.0 * M_PI / 180.0);
  EXPECT_NEAR(s_end_on, std::hypot(p.sigma_rad, expected_end), 0.1 * expected_end);
  EXPECT_GT(s_end_on, 1.5 * s_broadside);
  const auto [bus, s_bus] = sigma_of(render_box({10.0, 8.0}, 12.0, 2.5, 0.0), 0.0);
  ASSERT_LT(bus.at.norm(), p.near_range_lengths * bus.length_m);
  EXPECT_GE(s_bus, p.near_sigma_rad);
  // Cut by the view or an occluder: cut_sigma_factor times as much.
  EXPECT_DOUBLE_EQ(axis_heading_variance(broadside, Eigen::Vector2d::Zero(), true, p),
                   p.cut_sigma_factor * p.cut_sigma_factor * s_broadside * s_broadside);
}

TEST(TrackingOutlineAxis, ItsNoiseAcrossTheBodyHoldsASlipThatGrowsWithTheSpeed) {
  // The noise axis_information states for the velocity across the body: the speed times the
  // heading's noise, plus a slip, the larger of slip_sigma_mps and the speed times
  // slip_sigma_rad (no turn here: no lateral term). A car 30 m away seen broadside, its track on
  // its axis, not turning: at 4 m/s the slip is its floor (0.1 m/s), at 25 m/s 0.25 m/s. The
  // innovation is within three of its standard deviations, so the information across the body
  // is one over that variance.
  const TrackerParams p;
  const double bearing = 10.0 * M_PI / 180.0;
  const double yaw = bearing + 0.5 * M_PI;
  const Eigen::Vector2d at30 = 30.0 * Eigen::Vector2d(std::cos(bearing), std::sin(bearing));
  const AxisCase c = render_box(at30, 4.5, 1.8, yaw);
  const ScanBeams beams(c.rendered.scan);
  const Frame frame = standing_frame(c.rendered.scan, beams);
  const OutlineAxis a = axis_of(c);
  ASSERT_TRUE(a.informative);
  const Eigen::Vector2d along(std::cos(yaw), std::sin(yaw));
  ASSERT_FALSE(is_face(a, frame.position, along, p.heading));
  const double heading_var = axis_heading_variance(a, frame.position, false, p.heading);
  const Eigen::Vector2d n(-a.axis.y(), a.axis.x());
  const auto slip_of = [&](double speed) {
    Track tr;
    tr.hits = 3;
    tr.length_m = 4.5;
    tr.width_m = 1.8;
    tr.x << at30.x(), at30.y(), speed * along.x(), speed * along.y(), 0.0;
    tr.P = Mat5::Identity() * 0.01;
    Mat5 info = Mat5::Zero();
    Vec5 grad = Vec5::Zero();
    EXPECT_TRUE(axis_information(tr, c.pixels, frame, p, info, grad));
    const double var = 1.0 / n.dot(info.block<2, 2>(2, 2) * n);
    return std::sqrt(var - speed * speed * heading_var);
  };
  EXPECT_NEAR(slip_of(4.0), p.heading.slip_sigma_mps, 1e-9);
  EXPECT_NEAR(slip_of(25.0), 25.0 * p.heading.slip_sigma_rad, 1e-9);
  EXPECT_DOUBLE_EQ(p.heading.slip_sigma_mps, 0.1);
  EXPECT_DOUBLE_EQ(25.0 * p.heading.slip_sigma_rad, 0.25);
}

// A track of a car 4.5 x 1.8 m at (20, 6), sure it drives along x at 8 m/s.
Track sure_along_x() {
  Track tr;
  tr.id = 1;
  tr.hits = 3;
  tr.length_m = 4.5;
  tr.width_m = 1.8;
  tr.x << 20.0, 6.0, 8.0, 0.0, 0.0;
  tr.P = Mat5::Identity() * 0.01;
  return tr;
}

TEST(TrackingOutlineAxis, AnAxisFarOffTheTracksHeadingIsNotMeasured) {
  // A track sure it drives along x at 8 m/s; the outline it takes is a car's at 30 degrees (a
  // far car's few columns read the wrong way, or another shape): beyond gate_sigmas of the
  // innovation's spread, the axis is not measured in this update. With the gate off it is,
  // Huber-weighted. An outline along the track's own heading is measured.
  const AxisCase skew = render_box({20.0, 6.0}, 4.5, 1.8, 30.0 * M_PI / 180.0);
  const AxisCase along = render_box({20.0, 6.0}, 4.5, 1.8, 0.0);
  const ScanBeams skew_beams(skew.rendered.scan), along_beams(along.rendered.scan);
  const Frame skew_frame = standing_frame(skew.rendered.scan, skew_beams);
  const Frame along_frame = standing_frame(along.rendered.scan, along_beams);
  const auto measured = [](Track tr, const AxisCase& c, const Frame& frame, const TrackerParams& p) {
    Mat5 info = Mat5::Zero();
    Vec5 grad = Vec5::Zero();
    const bool used = axis_information(tr, c.pixels, frame, p, info, grad);
    EXPECT_EQ(used, tr.axis_seen);
    EXPECT_EQ(used, !info.isZero());
    return used;
  };
  EXPECT_FALSE(measured(sure_along_x(), skew, skew_frame, TrackerParams{}));
  TrackerParams no_gate;
  no_gate.heading.gate_sigmas = 0.0;
  EXPECT_TRUE(measured(sure_along_x(), skew, skew_frame, no_gate));
  EXPECT_TRUE(measured(sure_along_x(), along, along_frame, TrackerParams{}));
}

TEST(TrackingOutlineAxis, AHeadingNoReadHoldsYieldsToReadsBeyondTheGateThatAgree) {
  // A track sure it drives along x at 8 m/s (a single wrong read set its heading at birth), no
  // axis of its window along it; the car's outline lies at 30 degrees. The first read is beyond
  // the gate and not measured; the next, 0.1 s on, agrees with it and is, Huber-weighted; read
  // every 0.1 s for 3.5 s (its covariance held where it was, each read moves it by at most 3
  // standard deviations), the track's velocity turns to within 2 degrees of the outline's axis.
  // Not with reopen_sigmas 0, nor where two axes of its window hold its heading, nor where the
  // reads are further apart than reopen_window_s (0.05 s here), nor where the second read
  // disagrees (-30 degrees).
  const double skew = 30.0 * M_PI / 180.0;
  const AxisCase up = render_box({20.0, 6.0}, 4.5, 1.8, skew);
  const AxisCase down = render_box({20.0, 6.0}, 4.5, 1.8, -skew);
  const AxisCase along = render_box({20.0, 6.0}, 4.5, 1.8, 0.0);
  const ScanBeams up_beams(up.rendered.scan), down_beams(down.rendered.scan),
      along_beams(along.rendered.scan);
  const Frame up_frame = standing_frame(up.rendered.scan, up_beams);
  const Frame down_frame = standing_frame(down.rendered.scan, down_beams);
  const Frame along_frame = standing_frame(along.rendered.scan, along_beams);
  // One read after dt s of prediction (the body where it was), measured into the state if used;
  // the covariance held where it was (the Doppler and the centre, not measured here, keep it).
  const auto read = [](Track& tr, const AxisCase& c, const Frame& frame, double dt,
                       const TrackerParams& p) {
    if (dt > 0.0) predict(tr, dt, p.motion);
    tr.x.head<2>() = Eigen::Vector2d(20.0, 6.0);
    tr.P = Mat5::Identity() * 0.01;
    Mat5 info = Mat5::Zero();
    Vec5 grad = Vec5::Zero();
    const bool used = axis_information(tr, c.pixels, frame, p, info, grad);
    if (used) information_update(tr, info, grad, p);
    return used;
  };
  const auto heading_deg = [](const Track& tr) {
    return std::atan2(tr.velocity().y(), tr.velocity().x()) * 180.0 / M_PI;
  };
  const TrackerParams p;
  {
    Track tr = sure_along_x();
    EXPECT_FALSE(read(tr, up, up_frame, 0.0, p));
    EXPECT_TRUE(read(tr, up, up_frame, 0.1, p));
    for (int k = 2; k <= 35; ++k) read(tr, up, up_frame, 0.1, p);
    EXPECT_NEAR(heading_deg(tr), 30.0, 2.0);
  }
  {
    TrackerParams never = p;
    never.heading.reopen_sigmas = 0.0;
    Track tr = sure_along_x();
    for (int k = 0; k <= 15; ++k) EXPECT_FALSE(read(tr, up, up_frame, k == 0 ? 0.0 : 0.1, never));
    EXPECT_NEAR(heading_deg(tr), 0.0, 1.0);
  }
  {
    // Two reads along x in its window hold the heading: the reads at 30 degrees stay out.
    Track tr = sure_along_x();
    EXPECT_TRUE(read(tr, along, along_frame, 0.0, p));
    EXPECT_TRUE(read(tr, along, along_frame, 0.1, p));
    ASSERT_EQ(tr.axes.size(), 2u);
    for (int k = 0; k < 5; ++k) EXPECT_FALSE(read(tr, up, up_frame, 0.1, p));
  }
  {
    TrackerParams brief = p;
    brief.heading.reopen_window_s = 0.05;
    Track tr = sure_along_x();
    EXPECT_FALSE(read(tr, up, up_frame, 0.0, brief));
    EXPECT_FALSE(read(tr, up, up_frame, 0.1, brief));
  }
  {
    Track tr = sure_along_x();
    EXPECT_FALSE(read(tr, up, up_frame, 0.0, p));
    EXPECT_FALSE(read(tr, down, down_frame, 0.1, p));
  }
}

// A van's height [m]: its roof lies above the rig's heads, unseen.
constexpr double kVanHeight = 2.6;

TEST(TrackingOutlineAxis, AFaceSeenEndOnGivesTheAxisAsItsNormal) {
  // A van 2.0 m wide, 30 m ahead, heading 3 degrees (its bearing): only its rear shows, a line
  // across the body (no long side). Square to the line of sight, in enough columns, and its
  // normal within face_max_angle_rad of the track's heading, it is a face: the axis is its
  // normal, within 1.96 of its stated noise of the known heading.
  const TrackerParams::Heading p;
  const double yaw = 3.0 * M_PI / 180.0;
  const Eigen::Vector2d heading(std::cos(yaw), std::sin(yaw));
  const AxisCase rear = render_box({30.0, 1.5}, 5.5, 2.0, yaw, kVanHeight);
  const OutlineAxis a = axis_of(rear);
  ASSERT_FALSE(a.informative);
  ASSERT_GE(a.columns, p.face_min_columns);
  EXPECT_TRUE(is_face(a, Eigen::Vector2d::Zero(), heading, p));
  const Eigen::Vector2d sensor = Eigen::Vector2d::Zero();
  const double sigma = std::sqrt(face_heading_variance(a, sensor, false, p));
  EXPECT_LT(axis_angle(Eigen::Vector2d(-a.side_axis.y(), a.side_axis.x()), yaw), 1.96 * sigma);
  // Its noise: the columns' share, and the obliquity's (|cos| of the angle between the face and
  // the line of sight; under 0.05 here, square to it within 3 degrees).
  const double cosine = std::abs(a.side_axis.dot((a.at - sensor).normalized()));
  EXPECT_LT(cosine, 0.05);
  const double base = p.sigma_rad * p.sigma_rad + p.face_sigma_rad * p.face_sigma_rad / a.columns;
  const double oblique = p.face_oblique_sigma_rad * cosine;
  EXPECT_NEAR(sigma * sigma, base + oblique * oblique, 1e-15);
  EXPECT_NEAR(face_heading_variance(a, sensor, true, p),
              p.cut_sigma_factor * p.cut_sigma_factor * base + oblique * oblique, 1e-15);
  // Seen from a sensor 7.5 m to the side (the face 11 degrees from square to the line of sight),
  // the obliquity's share is 0.2 times |cos|: 0.04 rad of noise, where the columns' is 0.01.
  const Eigen::Vector2d aside(0.0, -6.0);
  const double cos_aside = std::abs(a.side_axis.dot((a.at - aside).normalized()));
  EXPECT_GT(cos_aside, 0.15);
  EXPECT_NEAR(face_heading_variance(a, aside, false, p),
              base + std::pow(p.face_oblique_sigma_rad * cos_aside, 2), 1e-15);
  TrackerParams::Heading no_oblique = p;
  no_oblique.face_oblique_sigma_rad = 0.0;
  EXPECT_NEAR(face_heading_variance(a, aside, false, no_oblique), base, 1e-15);
  // Not a face: a track heading across it (a rider's or a van's side shows a line along its
  // way); seen from a sensor to whose line of sight the line is not square (a side at a grazing
  // angle); in fewer columns than face_min_columns; with face_min_length_m 0 (the switch).
  EXPECT_FALSE(is_face(a, Eigen::Vector2d::Zero(), Eigen::Vector2d(-heading.y(), heading.x()), p));
  EXPECT_FALSE(is_face(a, Eigen::Vector2d(30.0, -25.0), heading, p));
  TrackerParams::Heading more_columns = p;
  more_columns.face_min_columns = a.columns + 1;
  EXPECT_FALSE(is_face(a, Eigen::Vector2d::Zero(), heading, more_columns));
  TrackerParams::Heading off = p;
  off.face_min_length_m = 0.0;
  EXPECT_FALSE(is_face(a, Eigen::Vector2d::Zero(), heading, off));
  // A walker-wide outline is none: shorter than face_min_length_m.
  const OutlineAxis walker = axis_of(render_box({30.0, 1.5}, 0.4, 0.8, yaw));
  EXPECT_FALSE(is_face(walker, Eigen::Vector2d::Zero(), heading, p));
}

TEST(TrackingOutlineAxis, AFaceFixesTheVelocityOfAVanSeenEndOn) {
  // The van of the test above, at 14 m/s turning at 0.05 rad/s, its track holding the line one
  // scan leaves open (v = v_app - omega z x (o - c), omega ~ N(0, 0.1^2)). Its face measures the
  // direction of its velocity: velocity and yaw rate are found, where without it the track
  // keeps the Doppler's line, a velocity 1.5 m/s off.
  const double yaw = 3.0 * M_PI / 180.0;
  const Eigen::Vector2d centre(30.0, 1.5), v = 14.0 * Eigen::Vector2d(std::cos(yaw), std::sin(yaw));
  const AxisCase c = render_box(centre, 5.5, 2.0, yaw, kVanHeight);
  const ScanBeams beams(c.rendered.scan);
  const Frame frame = standing_frame(c.rendered.scan, beams);
  const double omega = 0.05;
  const Track tr = track_on_the_doppler_line(centre, v, omega, 0.1, 5.5, 2.0);
  ASSERT_GT((tr.velocity() - v).norm(), 1.4);
  const auto [used, with_face] = axis_updated(tr, c, frame, TrackerParams{});
  TrackerParams off;
  off.heading.face_min_length_m = 0.0;
  const auto [used_off, without] = axis_updated(tr, c, frame, off);
  EXPECT_TRUE(used);
  EXPECT_LT((with_face.velocity() - v).norm(), 0.25);
  EXPECT_NEAR(with_face.yaw_rate(), omega, 0.015);
  EXPECT_LT(std::sqrt(with_face.P(4, 4)), 0.02);  // and it knows it
  EXPECT_FALSE(used_off);
  EXPECT_GT((without.velocity() - v).norm(), 1.4);
}

TEST(TrackingOutlineAxis, ACarSeenEndOnShowsItsRoofBehindItsRearAndTheRearIsTheFace) {
  // A car 4.5 x 1.8 x 1.45 m, 20 m ahead, driving away at 13 m/s turning at 0.15 rad/s: the
  // heads see its rear and, from above it, its roof behind: the whole outline is deeper than
  // wide, no face. The side the sensor sees, its rear, is one: a face whose normal is its axis,
  // which fixes velocity and yaw rate where the Doppler leaves them open (the track on the
  // Doppler's line, 3 m/s off). With the face switched off, the track stays on that line.
  const TrackerParams p;
  const double yaw = 3.0 * M_PI / 180.0;
  const Eigen::Vector2d centre(20.0, 1.0), v = 13.0 * Eigen::Vector2d(std::cos(yaw), std::sin(yaw));
  const AxisCase c = render_box(centre, 4.5, 1.8, yaw, 1.45);
  const OutlineAxis a = axis_of(c);
  ASSERT_GE(a.columns, p.heading.face_min_columns);
  EXPECT_FALSE(a.informative);
  // The roof shows: the whole outline's long side runs along the line of sight, no face.
  EXPECT_GT(std::abs(a.axis.dot(centre.normalized())), p.heading.face_sight_cosine);
  EXPECT_NEAR(a.side_length_m, 1.8, 0.2);
  EXPECT_TRUE(is_face(a, Eigen::Vector2d::Zero(), v.normalized(), p.heading));
  const double sigma =
      std::sqrt(face_heading_variance(a, Eigen::Vector2d::Zero(), false, p.heading));
  EXPECT_LT(axis_angle(Eigen::Vector2d(-a.side_axis.y(), a.side_axis.x()), yaw), 1.96 * sigma);
  const ScanBeams beams(c.rendered.scan);
  const Frame frame = standing_frame(c.rendered.scan, beams);
  const double omega = 0.15;
  const Track tr = track_on_the_doppler_line(centre, v, omega, 0.2, 4.5, 1.8);
  ASSERT_GT((tr.velocity() - v).norm(), 2.0);
  const auto [used, with_face] = axis_updated(tr, c, frame, p);
  EXPECT_TRUE(used);
  EXPECT_LT((with_face.velocity() - v).norm(), 0.3);
  EXPECT_NEAR(with_face.yaw_rate(), omega, 0.02);
  TrackerParams off = p;
  off.heading.face_min_length_m = 0.0;
  const auto [used_off, without] = axis_updated(tr, c, frame, off);
  EXPECT_FALSE(used_off);
  EXPECT_GT((without.velocity() - v).norm(), 2.0);
}

// A van coming head-on, its axis along x, its front `front` m ahead and its right side `side` m
// to the left: its bonnet (its top 1.05 m up) `step` m ahead of its cab (2.25 m), both 2 m wide,
// 5 m long in all; a car standing 6 m ahead of it (static, 4.2 x 1.8 m, 1.25 m up), its centre
// `hide` m left of the van's right side: at 1.2 m it hides the bonnet's left part from the heads,
// at 3 m it stands beside it. The van's pixels (bonnet and cab) and the frame.
AxisCase van_head_on(double front, double side, double step, double hide = 2.0) {
  SyntheticSceneParams p;
  SyntheticBox bonnet, cab, car;
  bonnet.center_m = Eigen::Vector3d(front + 2.5, side + 1.0, 0.05 + 0.5);
  bonnet.half_extent_m = Eigen::Vector3d(2.5, 1.0, 0.5);
  cab.center_m = Eigen::Vector3d(front + step + 0.5 * (5.0 - step), side + 1.0, 0.05 + 1.1);
  cab.half_extent_m = Eigen::Vector3d(0.5 * (5.0 - step), 1.0, 1.1);
  bonnet.velocity_mps = cab.velocity_mps = Eigen::Vector3d(-10.0, 0.0, 0.0);
  car.center_m = Eigen::Vector3d(front - 6.0, side + hide, 0.05 + 0.6);
  car.half_extent_m = Eigen::Vector3d(2.1, 0.9, 0.6);
  p.static_boxes.push_back(car);
  p.actors = {bonnet, cab};
  return render_actors(p);
}

TEST(TrackingOutlineAxis, AnOutlineWhoseNearSideLiesOffItsRectangleIsNotRead) {
  // The van 50 m ahead, its right side 2.5 m to the left, the car hiding the bonnet's left part:
  // the near side is the cab's front on the left, the bonnet's 1.1 m nearer on the right, and a
  // column of its side behind. The rectangle whose edges those pixels lie closest to is a
  // diagonal over them, more than 30 degrees off the van's axis: with the rule off
  // (max_edge_distance_m 0) that is the axis read, and the track of the van driving straight at
  // 10 m/s, its velocity across the line of sight open, takes it, metres per second off. With the
  // rule its pixels lie farther than 0.15 m from the rectangle's edges on average: neither an
  // axis, a face nor a line is read, and the track is left as it was.
  const AxisCase c = van_head_on(50.0, 2.5, 1.1, 1.2);
  TrackerParams off;
  off.heading.max_edge_distance_m = 0.0;
  const OutlineAxis misread = axis_of(c, off.heading);
  ASSERT_TRUE(misread.informative);
  EXPECT_GT(axis_angle(misread.axis, 0.0), 30.0 * M_PI / 180.0);
  const TrackerParams p;
  const OutlineAxis a = axis_of(c, p.heading);
  EXPECT_FALSE(a.rectangle);
  EXPECT_FALSE(a.informative);
  EXPECT_FALSE(is_face(a, Eigen::Vector2d::Zero(), Eigen::Vector2d(-1.0, 0.0), p.heading));
  const ScanBeams beams(c.rendered.scan);
  const Frame frame = standing_frame(c.rendered.scan, beams);
  const Eigen::Vector2d centre(52.5, 3.5), v(-10.0, 0.0);
  const Track tr = track_on_the_doppler_line(centre, v, 0.0, 0.4, 5.0, 2.0);
  const auto [used_off, taken] = axis_updated(tr, c, frame, off);
  EXPECT_TRUE(used_off);
  EXPECT_GT((taken.velocity() - v).norm(), 3.0);
  const auto [used, kept] = axis_updated(tr, c, frame, p);
  EXPECT_FALSE(used);
  EXPECT_FALSE(kept.line_seen);
  EXPECT_EQ(kept.x, tr.x);
  // The same van with the bonnet's front whole (the car beside it, hiding none of it): a near
  // side on the rectangle's edges, its axis read along the van.
  const OutlineAxis whole = axis_of(van_head_on(50.0, 2.5, 1.1, 3.0), p.heading);
  EXPECT_TRUE(whole.rectangle);
  EXPECT_TRUE(whole.informative);
  EXPECT_LT(axis_angle(whole.axis, 0.0), 2.0 * M_PI / 180.0);
}

// ---- A turn released while its rate holds up -----------------------------------------------

// The one cluster of the case's pixels as the track's group reports it (relabel_estimate).
ClusterEstimate report_one(const AxisCase& c, const Frame& frame, const Track& tr, const Group& g,
                           const TrackerParams& p) {
  MotionEstimate est;
  est.labels.assign(c.rendered.scan.size(), 0);
  for (const std::uint32_t i : c.pixels) est.labels[i] = 1;
  ClusterEstimate ce;
  ce.id = 1;
  ce.num_pixels = static_cast<int>(c.pixels.size());
  ce.velocity.valid = true;
  est.clusters.push_back(ce);
  const std::vector<Group> groups{g};
  relabel_estimate(frame, {tr}, groups, group_of_labels(groups, 1), {}, p, est);
  EXPECT_EQ(est.clusters.size(), 1u);
  return est.clusters.front();
}

// A confirmed track of `hits` updates whose filter's state is the truth: its centre, velocity
// v and yaw rate w (sigma rad/s of it; 0.1 m and m/s elsewhere).
Track true_track(const Eigen::Vector2d& centre, const Eigen::Vector2d& v, double w, double sigma,
                 int hits, double length, double width) {
  Track tr;
  tr.id = 1;
  tr.hits = hits;
  tr.confirmed = true;
  tr.length_m = length;
  tr.width_m = width;
  tr.x << centre.x(), centre.y(), v.x(), v.y(), w;
  tr.P = Mat5::Identity() * 0.01;
  tr.P(4, 4) = sigma * sigma;
  return tr;
}

TEST(TrackingTurning, ATurnReleasedWhileItsRateHoldsUpIsHeldAndOneThatEndsIsNot) {
  // A cyclist's track turning at 0.2 rad/s, resolved at 0.05 rad/s of sigma; then its position
  // updates are down-weighted (its box cut by the view) and sigma grows to 0.12: below
  // turn_release_significance (2) sigma, the turn is released while the rate holds. Held as
  // long as the rate keeps its sign and at least hold_rate_fraction (0.8) of the last turning
  // one, for release_hold_updates (30) updates; a rate that falls (the turn ends, the filter
  // lagging) is not held.
  const TrackerParams p;
  Track tr;
  tr.hits = 10;
  tr.length_m = 1.8;
  tr.width_m = 0.6;
  tr.x(4) = 0.2;
  tr.P(4, 4) = 0.05 * 0.05;
  update_turning(tr, p);
  ASSERT_TRUE(tr.turning);
  EXPECT_EQ(tr.last_turn_rate_rps, 0.2);
  EXPECT_FALSE(turn_held(tr, p));  // turning: reported as a turn, not held
  tr.P(4, 4) = 0.12 * 0.12;
  update_turning(tr, p);
  ASSERT_FALSE(tr.turning);
  EXPECT_EQ(tr.updates_since_turn, 1);
  EXPECT_TRUE(turn_held(tr, p));
  const auto held_at = [&](double w) {
    Track t = tr;
    t.x(4) = w;
    return turn_held(t, p);
  };
  EXPECT_TRUE(held_at(0.161));   // 0.8 of 0.2 is 0.16
  EXPECT_FALSE(held_at(0.159));  // the rate falls: the turn ends
  EXPECT_FALSE(held_at(-0.2));   // the other way
  TrackerParams never = p;
  never.turning.hold_rate_fraction = 0.0;
  EXPECT_FALSE(turn_held(tr, never));
  for (int k = 1; k < p.turning.release_hold_updates; ++k) update_turning(tr, p);
  EXPECT_EQ(tr.updates_since_turn, p.turning.release_hold_updates);
  EXPECT_TRUE(turn_held(tr, p));
  update_turning(tr, p);
  EXPECT_FALSE(turn_held(tr, p));  // held no longer than the hold
  // A track that never turned is not held.
  Track straight;
  straight.hits = 10;
  straight.x(4) = 0.2;
  straight.P(4, 4) = 0.12 * 0.12;
  update_turning(straight, p);
  EXPECT_FALSE(straight.turning);
  EXPECT_FALSE(turn_held(straight, p));
}

TEST(TrackingTurning, AHeldTurnIsTakenOffTheReportedVelocity) {
  // The cyclist 6.5 m away, its filter's state the truth: centre velocity v, turning at 0.2
  // rad/s with 0.12 rad/s of sigma, just released. Its Doppler shows v + w z x (o - c), the
  // beams' origin o 5.2 m from its centre: 1.04 m/s off v across the line of sight. Held, the
  // report takes off w^3 / (w^2 + sigma^2) of the rate (0.147 rad/s) and is within 0.4 m/s of
  // v; not held (hold_rate_fraction 0) it reports the Doppler's velocity, the turn left in.
  const Eigen::Vector2d centre(6.0, -2.5);
  const double yaw = 0.5, w = 0.2, sigma = 0.12;
  const AxisCase c = render_box(centre, 1.8, 0.6, yaw);
  ASSERT_GT(c.pixels.size(), 20u);
  const ScanBeams beams(c.rendered.scan);
  const Frame frame = standing_frame(c.rendered.scan, beams);
  const Eigen::Vector2d v = 5.0 * Eigen::Vector2d(std::cos(yaw), std::sin(yaw));
  Track tr = true_track(centre, v, w, sigma, 20, 1.8, 0.6);
  tr.updates_since_turn = 1;
  tr.last_turn_rate_rps = 0.21;
  Group g;
  g.found = c.pixels;
  g.clusters = {1};
  const auto report = [&](const TrackerParams& p) { return report_one(c, frame, tr, g, p); };
  const TrackerParams held;
  ASSERT_TRUE(turn_held(tr, held));
  TrackerParams not_held;
  not_held.turning.hold_rate_fraction = 0.0;
  const ClusterEstimate a = report(held), b = report(not_held);
  const Eigen::Vector2d d = mean_origin(frame, g) - centre;
  const Eigen::Vector2d s(-d.y(), d.x());  // z x (o - c)
  const double taken = w * w * w / (w * w + sigma * sigma);
  EXPECT_NEAR(a.yaw_rate_rps, taken, 1e-12);
  EXPECT_LT((a.velocity.velocity_mps.head<2>() - (v + (w - taken) * s)).norm(), 1e-9);
  EXPECT_LT((a.velocity.velocity_mps.head<2>() - v).norm(), 0.4);
  EXPECT_EQ(b.yaw_rate_rps, 0.0);
  EXPECT_LT((b.velocity.velocity_mps.head<2>() - (v + w * s)).norm(), 1e-9);
  EXPECT_GT((b.velocity.velocity_mps.head<2>() - v).norm(), 1.0);
  // What is left of the rate is in the covariance: the error is within its 95 % ellipse.
  const Eigen::Vector2d e = a.velocity.velocity_mps.head<2>() - v;
  EXPECT_LT(e.dot(a.velocity.covariance.topLeftCorner<2, 2>().ldlt().solve(e)), 5.991);
}

TEST(TrackingTurning, TheLineAYoungCarsOutlineShowsTakesTheYawRateItLeftInOff) {
  // A small car (2.8 x 1.6 m: no axis, its long side under Heading::min_length_m) 12 m away,
  // seen at its corner, driving at 6 m/s along its axis and turning at 0.3 rad/s; its track is
  // young (3 updates: not settled, the rate 0.35 rad/s of sigma, neither resolved nor too large
  // to leave in), its filter's velocity the truth. The Doppler's velocity v + w z x (o - c) is
  // metres per second off v and off the car's axis; the line its outline shows lies along v.
  // The report takes the rate off in full: v, the rate's variance in the covariance. The same
  // track heading 20 degrees off the line, or with the rule off, reports the Doppler's velocity.
  const Eigen::Vector2d centre(10.0, 6.5);
  const double yaw = 70.0 * M_PI / 180.0, w = 0.3, sigma = 0.35;
  const AxisCase c = render_box(centre, 2.8, 1.6, yaw);
  const ScanBeams beams(c.rendered.scan);
  const Frame frame = standing_frame(c.rendered.scan, beams);
  const auto track_along = [&](double heading) {
    return true_track(centre, 6.0 * Eigen::Vector2d(std::cos(heading), std::sin(heading)), w, sigma,
                      3, 2.8, 1.6);
  };
  const TrackerParams p;
  Track tr = track_along(yaw);
  Mat5 info = Mat5::Zero();
  Vec5 grad = Vec5::Zero();
  EXPECT_FALSE(axis_information(tr, c.pixels, frame, p, info, grad));
  ASSERT_TRUE(tr.line_seen);
  EXPECT_FALSE(tr.axis_seen);
  EXPECT_LT(
      std::abs(std::remainder(std::atan2(tr.line_axis.y(), tr.line_axis.x()) - yaw, 0.5 * M_PI)),
      p.turning.line_max_angle_rad);
  Group g;
  g.found = c.pixels;
  g.clusters = {1};
  const Eigen::Vector2d v = tr.velocity();
  const Eigen::Vector2d d = mean_origin(frame, g) - centre;
  const Eigen::Vector2d s(-d.y(), d.x());  // z x (o - c)
  const ClusterEstimate a = report_one(c, frame, tr, g, p);
  EXPECT_EQ(a.yaw_rate_rps, w);
  EXPECT_LT((a.velocity.velocity_mps.head<2>() - v).norm(), 1e-9);
  const Eigen::Matrix2d cov = a.velocity.covariance.topLeftCorner<2, 2>();
  const Eigen::Vector2d ss = s.normalized();
  EXPECT_GT(ss.dot(cov * ss), sigma * sigma * s.squaredNorm());  // the rate's variance
  // Left in, the rate is metres per second of error.
  ASSERT_GT(w * s.norm(), 3.0);
  TrackerParams never = p;
  never.turning.line_max_angle_rad = 0.0;
  const ClusterEstimate b = report_one(c, frame, tr, g, never);
  EXPECT_EQ(b.yaw_rate_rps, 0.0);
  EXPECT_LT((b.velocity.velocity_mps.head<2>() - (v + w * s)).norm(), 1e-9);
  // The filter's velocity off the line: nothing says which is the body's.
  Track off = track_along(yaw + 20.0 * M_PI / 180.0);
  off.line_seen = true;
  off.line_axis = tr.line_axis;
  const ClusterEstimate e = report_one(c, frame, off, g, p);
  EXPECT_EQ(e.yaw_rate_rps, 0.0);
  EXPECT_LT((e.velocity.velocity_mps.head<2>() - (off.velocity() + w * s)).norm(), 1e-9);
  // Nor where the Doppler's velocity lies along the line too (a rate within the noise).
  Track slow = tr;
  slow.x(4) = 0.002;
  EXPECT_FALSE(line_says_turning(slow, slow.velocity() + slow.x(4) * s, p.turning));
  EXPECT_TRUE(line_says_turning(tr, v + w * s, p.turning));
  // Nor for a track old enough to have resolved a turn (Turning::min_turn_hits updates).
  Track old = tr;
  old.hits = p.turning.min_turn_hits;
  EXPECT_FALSE(line_says_turning(old, v + w * s, p.turning));
  EXPECT_EQ(report_one(c, frame, old, g, p).yaw_rate_rps, 0.0);
}

TEST(TrackingTurning, ATrackCoastingOverAClusterReportsTheDopplerAtThePixelsItLabels) {
  // A car 20 m ahead of a rig 155 m from the tracker's world origin, its track young (two
  // updates: its yaw rate of 0.1 rad/s neither resolved nor too large to leave in), reports the
  // velocity the Doppler measures, v + w z x (o - c). This frame it measured none of its pixels:
  // its one cluster was only absorbed (a track coasting over what it could not explain). o is
  // then the beam origin of the pixels it labels, so the report is the velocity whose Doppler
  // those pixels show; from the world's origin it would be w |c| = 15 m/s across.
  const Eigen::Vector2d centre(20.0, -3.0), rig(150.0, 40.0);
  const double yaw = 0.3, w = 0.1;
  const AxisCase c = render_box(centre, 4.5, 1.8, yaw);
  ASSERT_GT(c.pixels.size(), 20u);
  const ScanBeams beams(c.rendered.scan);
  Frame frame = standing_frame(c.rendered.scan, beams);
  frame.position = rig;
  const Eigen::Vector2d v = 10.0 * Eigen::Vector2d(std::cos(yaw), std::sin(yaw));
  Track tr;
  tr.id = 1;
  tr.hits = 2;
  tr.length_m = 4.5;
  tr.width_m = 1.8;
  tr.x << rig + centre, v, w;
  tr.P = Mat5::Identity() * 0.01;
  const TrackerParams p;
  Group g;
  g.absorbed = {1};
  ASSERT_TRUE(g.empty());
  const ClusterEstimate a = report_one(c, frame, tr, g, p);
  EXPECT_EQ(a.yaw_rate_rps, 0.0);  // left in
  const Eigen::Vector2d vel = a.velocity.velocity_mps.head<2>();
  // Each pixel's Doppler, as the track's state predicts it, is what the reported velocity shows.
  double worst = 0.0;
  for (const std::uint32_t i : c.pixels) {
    const Row r = frame.row_of(i);
    worst = std::max(worst, std::abs(predicted(r, tr.x) - r.e.dot(vel)));
  }
  EXPECT_LT(worst, 1e-9);
  EXPECT_GT((vel - v).norm(), 1.5);  // w |o - c|, about 2 m/s: the rate left in
  EXPECT_LT((vel - v).norm(), 2.5);
}

TEST(TrackingTurning, AStraightCarsFalseYawRateIsNotTakenOffWhereItsAxesSayStraight) {
  // A car 30 m ahead, driving straight along x at 15 m/s, its axis measured. Its filter holds a
  // false yaw rate of 0.015 rad/s (0.9 of its 0.017 rad/s sigma), and a centre velocity off by
  // -w z x (o - c) (the Doppler pins the velocity at the beams' origin, v + w z x (o - c), to
  // the truth). Its last 2 s of axes, 0.01 rad of noise each, lie on the x axis: their line's
  // slope is 0 within its 0.004 rad/s sigma, far tighter than the filter's, and the filter's
  // rate within one sigma of it. The body drives straight: the report is the Doppler's velocity,
  // the truth, with no yaw rate. Without the rule (straight_window_s 0), the shrinkage took
  // w^3 / (w^2 + sigma^2) of the false rate off: 0.2 m/s off across the line of sight.
  const Eigen::Vector2d centre(30.0, 1.5), v_true(15.0, 0.0);
  const double w = 0.015, sigma = 0.017;
  const AxisCase c = render_box(centre, 4.5, 1.8, 0.0, 1.45);
  ASSERT_GT(c.pixels.size(), 20u);
  const ScanBeams beams(c.rendered.scan);
  const Frame frame = standing_frame(c.rendered.scan, beams);
  Group g;
  g.found = c.pixels;
  g.clusters = {1};
  const Eigen::Vector2d d = mean_origin(frame, g) - centre;
  const Eigen::Vector2d s(-d.y(), d.x());  // z x (o - c)
  Track tr;
  tr.id = 1;
  tr.hits = 40;
  tr.confirmed = true;
  tr.vehicle_pace = true;
  tr.length_m = 4.5;
  tr.width_m = 1.8;
  tr.axis_seen = true;
  const Eigen::Vector2d v_filter = v_true - w * s;
  tr.x << centre.x(), centre.y(), v_filter.x(), v_filter.y(), w;
  tr.P = Mat5::Identity() * 0.01;
  tr.P(4, 4) = sigma * sigma;
  tr.clock_s = 4.0;
  const auto axes_turning_at = [&](double rate) {
    tr.axes.clear();
    for (int k = 0; k < 20; ++k) {
      const double t = tr.clock_s - 0.1 * (19 - k);
      tr.axes.push_back({t, rate * (t - tr.clock_s) + 0.01 * std::sin(1.7 * k), 1e-4});
    }
  };
  const auto report = [&](const TrackerParams& p) { return report_one(c, frame, tr, g, p); };
  const TrackerParams p;
  TrackerParams off = p;
  off.turning.straight_window_s = 0.0;
  axes_turning_at(0.0);
  double b = 1.0, var_b = 0.0;
  ASSERT_TRUE(straight_by_axes(tr, p.turning, b, var_b));
  EXPECT_LT(std::abs(b), 2.0 * std::sqrt(var_b));
  EXPECT_LT(std::sqrt(var_b), 0.5 * sigma);
  const ClusterEstimate straight = report(p), shrunk = report(off);
  EXPECT_EQ(straight.yaw_rate_rps, 0.0);
  EXPECT_LT((straight.velocity.velocity_mps.head<2>() - v_true).norm(), 1e-9);
  const double taken = w * w * w / (w * w + sigma * sigma);
  EXPECT_NEAR(shrunk.yaw_rate_rps, taken, 1e-12);
  EXPECT_GT((shrunk.velocity.velocity_mps.head<2>() - v_true).norm(), 0.15);
  // A gentle turn the axes show (0.03 rad/s over the 2 s, 0.06 rad) is no straight body: the
  // shrunk rate is taken off, as without the rule.
  axes_turning_at(0.03);
  EXPECT_FALSE(straight_by_axes(tr, p.turning, b, var_b));
  EXPECT_NEAR(report(p).yaw_rate_rps, taken, 1e-12);
  // Nor is a turn's onset the axes lag: the filter's rate 0.06 rad/s, over a sigma from the
  // straight line of axes.
  axes_turning_at(0.0);
  tr.x(4) = 0.06;
  EXPECT_FALSE(straight_by_axes(tr, p.turning, b, var_b));
  tr.x(4) = w;
  // Nor a window with too few axes (a track that has just begun to measure them).
  tr.axes.erase(tr.axes.begin(), tr.axes.begin() + 11);
  EXPECT_FALSE(straight_by_axes(tr, p.turning, b, var_b));
}

TEST(TrackingTurning, TheAxesATrackMeasuresAreKeptOrientedUnwrappedAndWithinTheWindow) {
  // A car 20 m ahead and 6 m to the side, driving along -x at 10 m/s (heading pi), its outline's
  // axis measured every 0.1 s for 3 s, its body turned by +-0.01 rad in turn (the outline's
  // angle steps by 0.25 degrees): the along-body direction's raw angle flips between +pi and -pi.
  // The track keeps each axis oriented with its velocity and unwrapped (consecutive angles about
  // 0.02 apart, not 2 pi), at the time its predictions have reached (0.1 s each), and only
  // those of the last 2 s (21 of 31). Their line is straight. With straight_window_s 0 none is
  // kept.
  const AxisCase left = render_box({20.0, 6.0}, 4.5, 1.8, M_PI - 0.01, 1.45);
  const AxisCase right = render_box({20.0, 6.0}, 4.5, 1.8, -M_PI + 0.01, 1.45);
  ASSERT_GT(left.pixels.size(), 20u);
  ASSERT_GT(right.pixels.size(), 20u);
  const ScanBeams beams_l(left.rendered.scan), beams_r(right.rendered.scan);
  const Frame frame_l = standing_frame(left.rendered.scan, beams_l);
  const Frame frame_r = standing_frame(right.rendered.scan, beams_r);
  const auto measure_for = [&](const TrackerParams& p) {
    Track tr;
    tr.id = 1;
    tr.hits = 10;
    tr.length_m = 4.5;
    tr.width_m = 1.8;
    tr.x << 20.0, 6.0, -10.0, 0.0, 0.0;
    tr.P = Mat5::Identity() * 0.01;
    for (int k = 0; k <= 30; ++k) {
      if (k > 0) predict(tr, 0.1, p.motion);
      tr.x.head<2>() = Eigen::Vector2d(20.0, 6.0);  // the same rendered body each time
      Mat5 info = Mat5::Zero();
      Vec5 grad = Vec5::Zero();
      const bool odd = k % 2 == 1;
      EXPECT_TRUE(axis_information(tr, odd ? right.pixels : left.pixels, odd ? frame_r : frame_l, p,
                                   info, grad));
    }
    return tr;
  };
  const TrackerParams p;
  const Track tr = measure_for(p);
  EXPECT_NEAR(tr.clock_s, 3.0, 1e-9);
  ASSERT_EQ(tr.axes.size(), 21u);
  EXPECT_NEAR(tr.axes.front().t_s, 1.0, 1e-9);
  EXPECT_NEAR(tr.axes.back().t_s, 3.0, 1e-9);
  for (std::size_t k = 0; k < tr.axes.size(); ++k) {
    // Along the velocity (-x), not against it: within 0.02 rad of pi, on one branch.
    EXPECT_NEAR(std::abs(tr.axes[k].angle_rad), M_PI, 0.02);
    if (k > 0) {
      EXPECT_LT(std::abs(tr.axes[k].angle_rad - tr.axes[k - 1].angle_rad), 0.05);
    }
    EXPECT_GT(tr.axes[k].var_rad2, 0.0);
  }
  double b = 1.0, var_b = 0.0;
  EXPECT_TRUE(straight_by_axes(tr, p.turning, b, var_b));
  EXPECT_LT(std::abs(b), 0.01);
  TrackerParams never = p;
  never.turning.straight_window_s = 0.0;
  EXPECT_TRUE(measure_for(never).axes.empty());
}

// ---- Association gating -------------------------------------------------------------------

// A track at (20, 0) moving at 5 m/s along x; three clusters of 10 pixels: one on it whose
// Doppler its motion explains, one on it whose Doppler it does not, one 10 m beside it.
// A cluster of 10 pixels in row `row` (columns 5..14), from `at` 0.1 m apart along x, moving
// at 5 m/s along x, its Doppler off that by extra_doppler.
void add_row_cluster(HandScan& h, MotionEstimate& est, int row, const Eigen::Vector2d& at, double extra_doppler = 0.0) {
  ClusterEstimate ce;
  ce.id = static_cast<std::int32_t>(est.clusters.size()) + 1;
  for (int n = 0; n < 10; ++n) {
    const Eigen::Vector3d p(at.x() + 0.1 * n, at.y(), 0.5);
    h.set(row, 5 + n, p, 5.0 * p.normalized().x() + extra_doppler);
    est.labels[h.scan.index(row, 5 + n)] = ce.id;
    ce.centroid_m += p / 10.0;
  }
  ce.num_pixels = 10;
  est.clusters.push_back(ce);
}

// A track at (20, 0) moving at 5 m/s along x, its position known to 1 cm, with a box of the
// given length and width.
Track track_at_20(double length_m, double width_m) {
  Track tr;
  tr.x << 20.0, 0.0, 5.0, 0.0, 0.0;
  tr.P = Mat5::Identity() * 1e-4;
  tr.length_m = length_m;
  tr.width_m = width_m;
  return tr;
}

TEST(TrackingAssociation, GatesByBoxAndDoppler) {
  HandScan h;
  MotionEstimate est;
  est.labels.assign(h.scan.size(), 0);
  add_row_cluster(h, est, 0, {19.5, 0.0}, 0.0);
  add_row_cluster(h, est, 1, {19.5, 0.3}, 3.0);
  add_row_cluster(h, est, 2, {19.5, 10.0}, 0.0);
  const ScanBeams beams(h.scan);
  const Frame frame = standing_frame(h.scan, beams);
  const Track tr = track_at_20(4.5, 1.8);
  const std::vector<Track> tracks{tr};
  const std::vector<Box> boxes{box_of(tr)};
  std::vector<Group> groups(1);
  const auto cluster_pixels = pixels_of_clusters(est);
  EXPECT_NEAR(doppler_deviation(frame, cluster_pixels[0], tr), 0.0, 1e-5);
  EXPECT_NEAR(doppler_deviation(frame, cluster_pixels[1], tr), 3.0, 1e-5);
  const Association a = associate(frame, cluster_pixels, est, tracks, boxes, TrackerParams{}, groups);
  EXPECT_EQ(a.owner[0], 0);   // on the box, Doppler explained
  EXPECT_EQ(a.owner[1], -1);  // on the box, Doppler 3 m/s off
  EXPECT_EQ(a.absorbed[1], 0);  // small, inside a vehicle's box: a wheel, absorbed
  EXPECT_EQ(a.owner[2], -1);  // 10 m away
  EXPECT_EQ(a.absorbed[2], -1);
  EXPECT_EQ(groups[0].found, cluster_pixels[0]);
  EXPECT_EQ(groups[0].absorbed, std::vector<std::int32_t>{2});
}

// A confirmed track of the given box that was at (18.5, 0), moving at 5 m/s along x, predicted
// over three frames it missed (0.1 s each) to (20, 0), and a cluster of 10 pixels on its box whose
// Doppler is off its motion by `off` (the object slowed while unseen). Whether the cluster joins
// the track, with the track's misses as given; sigma: the predicted Doppler's standard deviation
// at the cluster's middle pixel.
bool coasting_track_takes(double off, int misses, double length_m, const TrackerParams& p,
                          double* sigma = nullptr) {
  HandScan h;
  MotionEstimate est;
  est.labels.assign(h.scan.size(), 0);
  add_row_cluster(h, est, 0, {19.5, 0.0}, off);
  const ScanBeams beams(h.scan);
  const Frame frame = standing_frame(h.scan, beams);
  Track tr = track_at_20(length_m, 1.8);
  tr.x(0) = 18.5;
  for (int k = 0; k < 3; ++k) predict(tr, 0.1, p.motion);
  tr.hits = 10;
  tr.confirmed = true;
  tr.misses = misses;
  const auto cluster_pixels = pixels_of_clusters(est);
  if (sigma != nullptr) {
    const Vec5 j = row_jacobian(frame.row_of(cluster_pixels[0][5]), tr.x);
    *sigma = std::sqrt(j.dot(tr.P * j));
  }
  const std::vector<Track> tracks{tr};
  const std::vector<Box> boxes{box_of(tr)};
  std::vector<Group> groups(1);
  return associate(frame, cluster_pixels, est, tracks, boxes, p, groups).owner[0] == 0;
}

TEST(TrackingAssociation, AVehicleCoastingTakesItsClusterWithinItsPredictedDopplersSpread) {
  // Three frames unseen, the track's velocity is known to about 0.4 m/s (2.5 m/s^2 of
  // acceleration noise): a cluster 1.2 m/s off its Doppler is within three of its standard
  // deviations and the tolerance (0.6 m/s), in quadrature; 3 m/s off is not.
  const TrackerParams p;
  double sigma = 0.0;
  ASSERT_TRUE(coasting_track_takes(-1.2, 3, 4.5, p, &sigma));
  EXPECT_GT(std::hypot(p.association.doppler_tolerance_mps, 3.0 * sigma), 1.2);
  EXPECT_LT(std::hypot(p.association.doppler_tolerance_mps, 3.0 * sigma), 3.0);
  EXPECT_FALSE(coasting_track_takes(-3.0, 3, 4.5, p));
  // Measured last frame, the tolerance alone: 1.2 m/s off is not its Doppler.
  EXPECT_FALSE(coasting_track_takes(-1.2, 0, 4.5, p));
  EXPECT_TRUE(coasting_track_takes(-0.5, 0, 4.5, p));
  // Nor for a track shorter than a vehicle (walkers side by side), nor without the rule.
  EXPECT_FALSE(coasting_track_takes(-1.2, 3, 1.0, p));
  TrackerParams off = p;
  off.association.coasting_doppler_sigmas = 0.0;
  EXPECT_FALSE(coasting_track_takes(-1.2, 3, 4.5, off));
}

// A truck 9 m long seen whole as one cluster moving at 5 m/s along x: 20 pixels over its rear
// 4.6 m (15.7 to 20.3) and 5 over its front (20.9 to 24.1), their centroid at 18.9. Two vehicles'
// tracks explain its Doppler and hold the centroid in their boxes: one born on the whole truck
// (9 x 2.5 m, centred at 20) and one born on its rear (5 x 2.4 m, centred at 18, nearer the
// centroid). Returns the track the cluster joins: 0 the whole truck's, 1 the rear's.
int truck_cluster_joins(const TrackerParams& p) {
  HandScan h;
  MotionEstimate est;
  est.labels.assign(h.scan.size(), 0);
  ClusterEstimate ce;
  ce.id = 1;
  const auto add = [&](int row, int col, double x) {
    const Eigen::Vector3d q(x, 0.3, 0.5);
    h.set(row, col, q, 5.0 * q.normalized().x());
    est.labels[h.scan.index(row, col)] = 1;
    ce.centroid_m += q;
    ++ce.num_pixels;
  };
  for (int n = 0; n < 20; ++n) add(0, n, 15.7 + 0.24 * n);
  for (int n = 0; n < 5; ++n) add(1, n, 20.9 + 0.8 * n);
  ce.centroid_m /= static_cast<double>(ce.num_pixels);
  est.clusters.push_back(ce);
  const ScanBeams beams(h.scan);
  const Frame frame = standing_frame(h.scan, beams);
  Track whole = track_at_20(9.0, 2.5), rear = track_at_20(5.0, 2.4);
  rear.x(0) = 18.0;
  for (Track* t : {&whole, &rear}) {
    t->hits = 2;
    t->last_pixels = 25;
  }
  const std::vector<Track> tracks{whole, rear};
  const std::vector<Box> boxes{box_of(whole), box_of(rear)};
  std::vector<Group> groups(2);
  return associate(frame, pixels_of_clusters(est), est, tracks, boxes, p, groups).owner[0];
}

TEST(TrackingAssociation, AClusterInsideTwoVehiclesBoxesJoinsTheBoxHoldingMostOfIt) {
  // The whole truck's box holds all 25 pixels, the rear's the 20 of the rear (and none of the
  // front, 0.4 m and more beyond it): the whole truck's track takes the cluster, though the
  // rear's centre is nearer its centroid (0.9 m against 1.1).
  TrackerParams p;
  EXPECT_EQ(truck_cluster_joins(p), 0);
  p.association.most_held_vehicle = false;
  EXPECT_EQ(truck_cluster_joins(p), 1);  // the nearest centre
}

// A track at (20, 0) moving at 5 m/s along x, its box 2.8 x 0.7 m (shorter than a vehicle's),
// and two clusters that move with it: one on its box, one 1.6 m beyond its front (the part of a
// bus alongside that the next head shows). Returns the clusters that join the track.
std::vector<std::int32_t> joined_beyond_the_box(bool confirmed, bool cut, const TrackerParams& p = {}) {
  HandScan h;
  MotionEstimate est;
  est.labels.assign(h.scan.size(), 0);
  add_row_cluster(h, est, 0, {19.6, 0.2});
  add_row_cluster(h, est, 1, {22.5, 0.2});
  const ScanBeams beams(h.scan);
  const Frame frame = standing_frame(h.scan, beams);
  Track tr = track_at_20(2.8, 0.7);
  tr.hits = 10;
  tr.confirmed = confirmed;
  tr.outline_cut = cut;
  const std::vector<Track> tracks{tr};
  const std::vector<Box> boxes{box_of(tr)};
  std::vector<Group> groups(1);
  associate(frame, pixels_of_clusters(est), est, tracks, boxes, p, groups);
  return groups[0].clusters;
}

TEST(TrackingAssociation, ABoxCutByTheViewReachesForItsUnseenPartAsAVehiclesDoes) {
  const std::vector<std::int32_t> both{1, 2}, nearest{1};
  EXPECT_EQ(joined_beyond_the_box(true, true), both);
  // Not without the rule, nor for a box whose ends were seen, nor for a track not yet confirmed.
  TrackerParams off;
  off.association.cut_box_reach = false;
  EXPECT_EQ(joined_beyond_the_box(true, true, off), nearest);
  EXPECT_EQ(joined_beyond_the_box(true, false), nearest);
  EXPECT_EQ(joined_beyond_the_box(false, true), nearest);
}

// A confirmed track at (20, 0) moving at 5 m/s along x, and one cluster of 20 pixels in its box:
// 20 - n_other that move with it and n_other behind them, in the same box, at `other` (a car
// passing a cyclist); both parts span the cluster's 1.5 m across the beams.
// The cluster's single-scan fit leaves residual RMS `rms`. Returns the clusters after the split.
std::vector<std::vector<std::uint32_t>> doppler_split(const Eigen::Vector2d& other, double rms, MotionEstimate& est,
                                                      const TrackerParams& p = {}, double other_spread_mps = 0.0,
                                                      int n_other = 10) {
  HandScan h;
  est = MotionEstimate{};
  est.labels.assign(h.scan.size(), 0);
  ClusterEstimate ce;
  ce.id = 1;
  for (int n = 0; n < 20; ++n) {
    const bool mine = n % 2 == 0 || n / 2 >= n_other;
    const Eigen::Vector3d q(mine ? 19.8 : 20.3, -0.8 + 0.08 * n, 0.5);
    const Eigen::Vector2d v = mine ? Eigen::Vector2d(5.0, 0.0) : other;
    const double spread = mine ? 0.0 : other_spread_mps * ((n / 2) % 2 == 0 ? 1.0 : -1.0);
    h.set(mine ? 1 : 3, 5 + n, q, q.normalized().head<2>().dot(v) + spread);
    est.labels[h.scan.index(mine ? 1 : 3, 5 + n)] = 1;
    ce.centroid_m += q / 20.0;
  }
  ce.num_pixels = 20;
  ce.velocity.velocity_mps = Eigen::Vector3d(10.0, 0.0, 0.0);
  ce.velocity.residual_rms_mps = rms;
  ce.velocity.valid = true;
  est.clusters.push_back(ce);
  const ScanBeams beams(h.scan);
  const Frame frame = standing_frame(h.scan, beams);
  Track tr = track_along_x(20.0, 4.5);
  tr.x(1) = 0.0;
  tr.confirmed = true;
  tr.last_pixels = 10;
  const std::vector<Track> tracks{tr};
  const std::vector<Box> boxes{box_of(tr)};
  auto cluster_pixels = pixels_of_clusters(est);
  split_by_doppler(frame, est, cluster_pixels, tracks, boxes, p);
  EXPECT_EQ(cluster_pixels.size(), est.clusters.size());
  return cluster_pixels;
}

TEST(TrackingAssociation, AClusterOfTwoMotionsIsSplitByTheDoppler) {
  MotionEstimate est;
  // 15 m/s beside the track's 5: no one rigid motion explains the cluster (RMS 3 m/s).
  const auto parts = doppler_split({15.0, 0.0}, 3.0, est);
  ASSERT_EQ(parts.size(), 2u);
  EXPECT_EQ(parts[0].size(), 10u);  // the track's half keeps the label
  EXPECT_EQ(parts[1].size(), 10u);
  for (const std::uint32_t i : parts[1]) EXPECT_EQ(est.labels[i], 2);
  EXPECT_EQ(est.clusters[1].num_pixels, 10);
  // The other half's own fit: 15 m/s along x (the scan holds floats).
  EXPECT_NEAR(est.clusters[1].velocity.velocity_mps.x(), 15.0, 1e-4);
  EXPECT_NEAR(est.clusters[1].velocity.velocity_mps.y(), 0.0, 1e-3);
  EXPECT_LT(est.clusters[1].velocity.residual_rms_mps, 1e-3);
  // Not split: a cluster its own fit explains (RMS 0.5 m/s, under doppler_split_rms_mps); a rest
  // that is no one rigid motion either (its Doppler +-2 m/s about it); the rule off.
  EXPECT_EQ(doppler_split({15.0, 0.0}, 0.5, est).size(), 1u);
  EXPECT_EQ(doppler_split({15.0, 0.0}, 3.0, est, {}, 2.0).size(), 1u);
  TrackerParams off;
  off.association.doppler_split_rms_mps = 0.0;
  EXPECT_EQ(doppler_split({15.0, 0.0}, 3.0, est, off).size(), 1u);
  // Nor a cluster whose Doppler the track explains as a whole (12 of its 20 pixels: the median),
  // though the 8 others would make a cluster of their own.
  EXPECT_EQ(doppler_split({15.0, 0.0}, 3.0, est, {}, 0.0, 8).size(), 1u);
}

// One cluster of 12 pixels about 110 m ahead and two confirmed tracks seen last frame with 6
// pixels each, 1.5 m by 1.5 m, moving along x at 5 m/s: the first centred at (110, 0), the
// second `apart_m` further along x; 6 of the pixels at each track's centre. Returns the parts
// split_shared_clusters makes.
std::size_t parts_of_a_far_cluster(double apart_m) {
  HandScan h;
  MotionEstimate est;
  est.labels.assign(h.scan.size(), 0);
  ClusterEstimate ce;
  ce.id = 1;
  for (int n = 0; n < 12; ++n) {
    const Eigen::Vector3d q(110.0 + (n < 6 ? 0.0 : apart_m), -0.25 + 0.1 * (n % 6), 0.5);
    h.set(n < 6 ? 1 : 3, 5 + n, q, 5.0 * q.normalized().x());
    est.labels[h.scan.index(n < 6 ? 1 : 3, 5 + n)] = 1;
    ce.centroid_m += q / 12.0;
  }
  ce.num_pixels = 12;
  ce.velocity.valid = true;
  est.clusters.push_back(ce);
  const ScanBeams beams(h.scan);
  const Frame frame = standing_frame(h.scan, beams);
  std::vector<Track> tracks(2);
  for (std::size_t t = 0; t < 2; ++t) {
    tracks[t].x << 110.0 + (t == 0 ? 0.0 : apart_m), 0.0, 5.0, 0.0, 0.0;
    tracks[t].length_m = tracks[t].width_m = 1.5;
    tracks[t].confirmed = true;
    tracks[t].hits = 10;
    tracks[t].last_pixels = 6;
  }
  const std::vector<Box> boxes{box_of(tracks[0]), box_of(tracks[1])};
  auto cluster_pixels = pixels_of_clusters(est);
  split_shared_clusters(frame, est, cluster_pixels, tracks, boxes, TrackerParams{});
  EXPECT_EQ(cluster_pixels.size(), est.clusters.size());
  return est.clusters.size();
}

TEST(TrackingAssociation, AFarClusterIsSplitBetweenTwoTracksApartNotBetweenTwoOnOneObject) {
  // 6 pixels each: under min_cluster_pixels (8), but as many as a track 110 m away needs (3).
  EXPECT_EQ(parts_of_a_far_cluster(4.0), 2u);  // a car and a cyclist 4 m beyond it
  // 0.8 m apart, each centre in the other's box: one far car seen as two pieces, left whole.
  EXPECT_EQ(parts_of_a_far_cluster(0.8), 1u);
}

// A lost track, a car 4.5 m long at (20, 15.9) moving at 5 m/s along x, its position known to
// pos_sigma_m, and a track born this frame centred `offset` from it, from 10 pixels there whose
// Doppler is that of a motion `v_born`. Returns lost_track_of.
int lost_for(const Eigen::Vector2d& offset, const Eigen::Vector2d& v_born, double pos_sigma_m = 0.1) {
  HandScan h;
  std::vector<std::uint32_t> pixels;
  const Eigen::Vector2d c = Eigen::Vector2d(20.0, 15.9) + offset;
  for (int n = 0; n < 10; ++n) {
    const Eigen::Vector3d q(c.x() - 0.5 + 0.1 * n, c.y(), 0.5);
    h.set(2, 5 + n, q, q.normalized().head<2>().dot(v_born));
    pixels.push_back(static_cast<std::uint32_t>(h.scan.index(2, 5 + n)));
  }
  const ScanBeams beams(h.scan);
  const Frame frame = standing_frame(h.scan, beams);
  Track born = track_along_x(c.x(), 1.0);
  born.x(1) = c.y();
  std::vector<Track> lost{track_along_x(20.0, 4.5)};
  lost[0].P.topLeftCorner<2, 2>() = Eigen::Matrix2d::Identity() * pos_sigma_m * pos_sigma_m;
  return lost_track_of(frame, born, pixels, lost, TrackerParams{});
}

TEST(TrackingAssociation, ATrackBornWhereALostOneIsPredictedTakesItsIdIfItsMotionExplainsIt) {
  const Eigen::Vector2d along(5.0, 0.0);
  EXPECT_EQ(lost_for({1.0, 0.5}, along), 0);   // in its box, moving as it does
  EXPECT_EQ(lost_for({4.0, 0.0}, along), 0);   // 1.75 m beyond its box: within the gate, 2 + 3 x 0.1 m
  EXPECT_EQ(lost_for({6.0, 0.0}, along), -1);  // 3.75 m beyond: outside it
  EXPECT_EQ(lost_for({6.0, 0.0}, along, 1.0), 0);  // ... inside it when its position is known to 1 m (5 m)
  // Known to 5 m, the gate would be 17 m; it stops at 3 gate_m (6 m): 7.75 m beyond is refused.
  EXPECT_EQ(lost_for({10.0, 0.0}, along, 5.0), -1);
  EXPECT_EQ(lost_for({7.0, 0.0}, along, 5.0), 0);  // 4.75 m beyond
  EXPECT_EQ(lost_for({1.0, 0.5}, {2.0, 0.0}), -1);  // 3 m/s slower: another object
}

// Two confirmed tracks as old: the host, 10 m long at (20, 0) by default (a truck whose cab and
// load were born apart in one frame), and the part's, 0.4 times as long, its centre at 0.3
// times the host's length ahead and 0.05 times aside, inside the host's box; or, with `beside`,
// its centre that far beyond the side of the host's box. Both move along x at 5 m/s unless
// `speeds` says otherwise; the merge runs with the parameters p. Returns whether the part's track was merged into the host's.
struct Speeds {
  double host_mps = 5.0;
  double part_mps = 5.0;
};
bool part_merged(int part_last_pixels, double host_length_m = 10.0, int host_last_pixels = 3000, double beside_m = 0.0,
                 Speeds speeds = {}, const TrackerParams& p = {}) {
  std::vector<Track> tracks(2);
  for (Track& t : tracks) {
    t.hits = 4;
    t.confirmed = true;
    t.width_m = 2.5;
  }
  tracks[0].x << 20.0, 0.0, speeds.host_mps, 0.0, 0.0;
  tracks[0].length_m = host_length_m;
  tracks[0].last_pixels = host_last_pixels;
  tracks[0].width_m = std::min(2.5, 0.6 * host_length_m);
  const double aside = beside_m > 0.0 ? 0.5 * tracks[0].width_m + beside_m : 0.05 * host_length_m;
  tracks[1].x << 20.0 + 0.3 * host_length_m, aside, speeds.part_mps, 0.0, 0.0;
  tracks[1].length_m = 0.4 * host_length_m;
  tracks[1].last_pixels = part_last_pixels;
  const std::vector<Box> boxes{box_of(tracks[0]), box_of(tracks[1])};
  std::vector<Group> groups(2);
  groups[0].clusters = {1};
  groups[1].clusters = {2};
  Association a;
  a.owner = {0, 1};
  a.absorbed = {-1, -1};
  const Scan scan = Scan::make_empty(1, 1);
  const ScanBeams beams(scan);
  merge_nested_tracks(standing_frame(scan, beams), tracks, boxes, p, a, groups);
  const bool merged = groups[1].clusters.empty() && a.absorbed[1] == 0 && tracks[1].misses > p.lifecycle.max_misses;
  EXPECT_EQ(merged, groups[0].absorbed == std::vector<std::int32_t>{2});
  return merged;
}

TEST(TrackingAssociation, ATrackOnAPartOfAMuchLargerVehicleAsOldAsItEnds) {
  EXPECT_TRUE(part_merged(80));     // the truck's last update found 37 times its pixels
  EXPECT_FALSE(part_merged(2000));  // two vehicles of a size: left to the split
}

TEST(TrackingAssociation, ATrackOnAWalkersLimbEndsOnlyWhenTheWalkerShowsTenTimesItsPixels) {
  // The host a walker 1 m by 0.6 m (no vehicle) with 240 pixels, the other track's centre 0.3 m
  // ahead of its centre, inside its box: a limb of 15 pixels ends; a walker half hidden behind
  // it, of 80, does not.
  EXPECT_TRUE(part_merged(15, 1.0, 240));
  EXPECT_FALSE(part_merged(80, 1.0, 240));
}

TEST(TrackingAssociation, AHalfOfACarAsOldAsItsOtherHalfAndMovingWithItEnds) {
  // A car 4.5 m long first seen in two halves, both tracks as old (4 updates), the rear half's
  // box 1.8 m long with its centre inside the front half's box, 200 pixels against 240.
  EXPECT_TRUE(part_merged(200, 4.5, 240));
  EXPECT_FALSE(part_merged(200, 4.5, 240, 0.0, {5.0, 6.0}));  // 1 m/s apart
  EXPECT_FALSE(part_merged(200, 4.5, 240, 0.0, {2.0, 2.0}));  // at a walker's pace
}

TEST(TrackingAssociation, AFaceOfAVehicleBesideItsBoxMovingWithItEnds) {
  // A bus alongside shows its side (the host's box, as wide as the face seen) and its front
  // corner (a track of its own 0.6 m beside that box: past claim_margin_m, 0.25 m, within
  // same_motion_margin_m more, 0.5 m).
  EXPECT_TRUE(part_merged(80, 10.0, 3000, 0.6));
  EXPECT_FALSE(part_merged(80, 10.0, 3000, 0.6, {5.0, 6.0}));  // 1 m/s apart: another vehicle
  EXPECT_FALSE(part_merged(80, 10.0, 3000, 1.2));              // a lane beside it
  EXPECT_FALSE(part_merged(80, 10.0, 3000, 0.6, {2.0, 2.0}));  // a walker's pace: walkers side by side
  TrackerParams only_the_box;  // control: the same face, with only the box grown by claim_margin_m
  only_the_box.fragments.same_motion_margin_m = 0.0;
  EXPECT_FALSE(part_merged(80, 10.0, 3000, 0.6, {}, only_the_box));
}

// A confirmed car's track, 40 updates old, 4.5 m long at (20, 0) moving at 5 m/s along x (3,000
// pixels last), and inside its box a confirmed track `hits` updates old, 1.8 m long, whose
// 10 pixels move at 5 + extra_mps m/s along x. Returns whether that track was merged into the car's.
bool rider_merged(int hits, double extra_mps, const TrackerParams& p = {}) {
  HandScan h;
  MotionEstimate est;
  est.labels.assign(h.scan.size(), 0);
  add_row_cluster(h, est, 0, {19.6, 0.3}, extra_mps);
  const ScanBeams beams(h.scan);
  std::vector<Track> tracks{track_at_20(4.5, 1.8), track_at_20(1.8, 0.6)};
  tracks[0].hits = 40;
  tracks[0].last_pixels = 3000;
  tracks[1].x << 20.0, 0.3, 5.0 + extra_mps, 0.0, 0.0;
  tracks[1].hits = hits;
  tracks[1].last_pixels = 10;
  for (Track& t : tracks) t.confirmed = true;
  const std::vector<Box> boxes{box_of(tracks[0]), box_of(tracks[1])};
  std::vector<Group> groups(2);
  groups[1].clusters = {1};
  groups[1].found = pixels_of_clusters(est)[0];
  Association a;
  a.owner = {1};
  a.absorbed = {-1};
  merge_nested_tracks(standing_frame(h.scan, beams), tracks, boxes, p, a, groups);
  return tracks[1].merged;
}

TEST(TrackingAssociation, ARiderInsideACarsBoxMovingOtherwiseKeepsItsTrack) {
  // A cyclist at 2 m/s beside a car at 5 (a car turning past it: inside its box), tracked for 12
  // updates: an object of its own. A track as young as a wheel's, or one that moves with the
  // car, ends as a part; so does the cyclist without the rule.
  EXPECT_FALSE(rider_merged(12, -3.0));
  EXPECT_TRUE(rider_merged(5, -3.0));
  EXPECT_TRUE(rider_merged(12, 0.0));
  TrackerParams never;
  never.fragments.own_motion_hits = 0;
  EXPECT_TRUE(rider_merged(12, -3.0, never));
}

// A truck's track, 10 m long at (20, 0) moving at 5 m/s along x and turning at omega, and, as
// old (4 updates, both confirmed), the track of a piece of it whose centre lies in its box and
// whose own filter holds 8 m/s along x. The piece's 10 pixels (1-2 m ahead of the truck's
// centre, 0.3 m aside) have the Doppler of the truck's rigid motion plus extra_mps. Returns
// whether the piece's track was merged into the truck's.
bool piece_of_turning_truck_merged(double omega, double extra_mps, const TrackerParams& p = {}) {
  HandScan h;
  std::vector<Track> tracks{track_at_20(10.0, 2.5), track_at_20(1.8, 0.6)};
  tracks[0].x(4) = omega;
  tracks[0].last_pixels = 1000;
  tracks[1].x << 21.5, 0.3, 8.0, 0.0, 0.0;
  tracks[1].last_pixels = 800;
  for (Track& t : tracks) {
    t.hits = 4;
    t.confirmed = true;
  }
  std::vector<Group> groups(2);
  groups[0].clusters = {1};
  groups[1].clusters = {2};
  for (int n = 0; n < 10; ++n) {
    const Eigen::Vector3d q(21.0 + 0.1 * n, 0.3, 0.5);
    const Eigen::Vector2d d = q.head<2>() - tracks[0].centre();
    const Eigen::Vector2d v = tracks[0].velocity() + omega * Eigen::Vector2d(-d.y(), d.x());
    h.set(0, 5 + n, q, q.normalized().head<2>().dot(v) + extra_mps);
    groups[1].found.push_back(static_cast<std::uint32_t>(h.scan.index(0, 5 + n)));
  }
  const ScanBeams beams(h.scan);
  const std::vector<Box> boxes{box_of(tracks[0]), box_of(tracks[1])};
  Association a;
  a.owner = {0, 1};
  a.absorbed = {-1, -1};
  merge_nested_tracks(standing_frame(h.scan, beams), tracks, boxes, p, a, groups);
  return tracks[1].merged;
}

TEST(TrackingAssociation,
     APieceOfATurningTruckAsOldAsItEndsWhereTheTrucksMotionExplainsItsDoppler) {
  // Turning at 0.4 rad/s: the piece's own filter holds 3 m/s more than the truck's centre (no
  // twin by velocity: same_motion_mps 0.5), but its pixels' Doppler is the truck's rigid motion
  // (its velocity there 5.0 m/s along x and 0.4-0.8 across): a part of it, ended. 1 m/s off
  // that Doppler it is another body; with twin_by_doppler off (the control) it is left alone.
  EXPECT_TRUE(piece_of_turning_truck_merged(0.4, 0.0));
  EXPECT_FALSE(piece_of_turning_truck_merged(0.4, 1.0));
  TrackerParams by_velocity;
  by_velocity.fragments.twin_by_doppler = false;
  EXPECT_FALSE(piece_of_turning_truck_merged(0.4, 0.0, by_velocity));
}

// ---- Track birth -----------------------------------------------------------------------------

// A track born, the rig standing, on the pixels g of h whose single-scan fit gave velocity v
// with covariance cov and residual RMS rms.
Track born_of_fit(const HandScan& h, const Group& g, const Eigen::Vector2d& v,
                  const Eigen::Matrix3d& cov, double rms, const TrackerParams& p) {
  const ScanBeams beams(h.scan);
  const Frame frame = standing_frame(h.scan, beams);
  ClusterEstimate ce;
  ce.num_pixels = static_cast<int>(g.found.size());
  ce.velocity.velocity_mps = Eigen::Vector3d(v.x(), v.y(), 0.0);
  ce.velocity.covariance = cov;
  ce.velocity.residual_rms_mps = rms;
  ce.velocity.valid = true;
  return start_track(ce, g, 1, frame, ViewEdges(h.scan, p.box.occlusion_gap_m), p);
}

// A patch 0.3 m by 0.3 m (12 pixels) at (2, 1.5): the corner of a bus alongside the rig, or a
// walker close by. Its single-scan estimate is given: velocity v, a standard deviation sigma on
// both horizontal axes, residual RMS rms. Returns the velocity the track is born with, less the
// velocity expected: v itself (whole) or its part along the beam to the box centre.
enum class Expected { whole, radial };
double born_off(const Eigen::Vector2d& v, double sigma, double rms, Expected expected, const TrackerParams& p = {}) {
  HandScan h;
  Group g;
  for (int r = 1; r <= 3; ++r) {
    for (int c = 5; c <= 8; ++c) {
      const Eigen::Vector3d q(2.0 + 0.1 * (c - 5), 1.5 + 0.15 * (r - 1), 0.5);
      h.set(r, c, q, q.normalized().head<2>().dot(v));
      g.found.push_back(static_cast<std::uint32_t>(h.scan.index(r, c)));
    }
  }
  const Track tr = born_of_fit(h, g, v, Eigen::Matrix3d::Identity() * sigma * sigma, rms, p);
  EXPECT_TRUE(tr.small(p));
  EXPECT_FALSE(tr.outline_cut);
  const Eigen::Vector2d radial = tr.centre().normalized();  // the rig at the origin
  return (tr.velocity() - (expected == Expected::whole ? v : Eigen::Vector2d(v.dot(radial) * radial))).norm();
}

TEST(TrackingBirth, ASmallPatchWhoseScanResolvedAFastRigidMotionIsBornWithIt) {
  const Eigen::Vector2d v(4.5, 0.0);  // its part along the beam is 3.6 m/s: 2.7 m/s off
  // Resolved to 0.1 m/s, rigid (RMS 0.03 m/s, under the tracker's Doppler noise of 0.08), 4.5 m/s:
  // the scan's velocity.
  EXPECT_LT(born_off(v, 0.1, 0.03, Expected::whole), 1e-9);
  // Limbs swinging (RMS 0.2 m/s), or the velocity not resolved (0.5 m/s), or no faster than a
  // walker by three standard deviations (3.2 m/s): the radial part alone.
  EXPECT_LT(born_off(v, 0.1, 0.2, Expected::radial), 1e-9);
  EXPECT_LT(born_off(v, 0.5, 0.03, Expected::radial), 1e-9);
  EXPECT_LT(born_off({3.2, 0.0}, 0.1, 0.03, Expected::radial), 1e-9);
  // Control: with the rule off, the resolved patch too.
  TrackerParams off;
  off.small.rigid_patch_sigma_mps = 0.0;
  EXPECT_LT(born_off(v, 0.1, 0.03, Expected::radial, off), 1e-9);
}

// A patch 1.65 m long across the line of sight 20 m ahead (36 pixels, larger than a walker), its
// single-scan fit v = (2, 20) m/s: 0.05 m/s along the beam, sigma_across m/s across it. Returns
// the track's velocity at birth (the outline's axis not measured) and, in variance, the part of
// its covariance across the beam.
Eigen::Vector2d born_across(double sigma_across, const TrackerParams& params,
                            double& variance_across) {
  TrackerParams p = params;
  p.heading.use_outline = false;
  HandScan h;
  Group g;
  const Eigen::Vector2d v(2.0, 20.0);
  for (int r = 1; r <= 3; ++r) {
    for (int c = 4; c <= 15; ++c) {
      const Eigen::Vector3d q(20.0, -0.825 + 0.15 * (c - 4), 0.3 * r);
      h.set(r, c, q, q.normalized().head<2>().dot(v));
      g.found.push_back(static_cast<std::uint32_t>(h.scan.index(r, c)));
    }
  }
  const Eigen::Matrix3d cov =
      Eigen::Vector3d(0.05 * 0.05, sigma_across * sigma_across, 0.0).asDiagonal();
  const Track tr = born_of_fit(h, g, v, cov, 0.03, p);
  EXPECT_FALSE(tr.small(p));
  EXPECT_FALSE(tr.outline_cut);
  variance_across = tr.P(3, 3);
  return tr.velocity();
}

TEST(TrackingBirth, ADirectionTheScanResolvesNoBetterThanTheCapIsBornAtZero) {
  const TrackerParams p;
  const double cap = p.motion.max_initial_velocity_sigma_mps;  // 6 m/s
  double var = 0.0;
  // Resolved to 3 m/s across the beam: the fit's velocity, its variance as the fit gives it
  // (and the yaw rate's part).
  EXPECT_LT((born_across(3.0, p, var) - Eigen::Vector2d(2.0, 20.0)).norm(), 1e-9);
  const double resolved_var = var;
  EXPECT_GE(resolved_var, 9.0);
  // Resolved to 10 m/s, worse than the cap: the velocity along the beam alone, the variance
  // across it the cap's (6^2 = 27 more than 3^2), not the fit's (10^2).
  EXPECT_LT((born_across(10.0, p, var) - Eigen::Vector2d(2.0, 0.0)).norm(), 1e-9);
  EXPECT_NEAR(var - resolved_var, cap * cap - 9.0, 1e-6);
  // Control: with the cap at 12 m/s the same fit is resolved well enough.
  TrackerParams wide;
  wide.motion.max_initial_velocity_sigma_mps = 12.0;
  EXPECT_LT((born_across(10.0, wide, var) - Eigen::Vector2d(2.0, 20.0)).norm(), 1e-9);
  EXPECT_NEAR(var - resolved_var, 100.0 - 9.0, 1e-6);
}

// ---- Background model and claims ----------------------------------------------------------

TEST(TrackingBackground, ForegroundIsWhatComesIntoSpaceSeenEmpty) {
  HandScan h;
  for (int r = 0; r < 5; ++r) {
    for (int c = 0; c < 20; ++c) h.set(r, c, Eigen::Vector3d(20.0, 0.0, 0.0), 0.0);
  }
  BackgroundModel bg;
  const TrackerParams::Background p;
  bg.begin_frame(h.scan, true);
  for (int k = 0; k < p.min_frames; ++k) bg.add(h.scan);
  EXPECT_TRUE(bg.ready(p));
  h.set(2, 10, Eigen::Vector3d(10.0, 0.0, 0.0), 0.0);
  EXPECT_TRUE(bg.foreground(h.scan, h.scan.index(2, 10), p.margin_m));
  h.set(2, 10, Eigen::Vector3d(19.8, 0.0, 0.0), 0.0);  // within the margin
  EXPECT_FALSE(bg.foreground(h.scan, h.scan.index(2, 10), p.margin_m));
  bg.begin_frame(h.scan, false);  // the rig moves: start again
  EXPECT_EQ(bg.frames(), 0);
  EXPECT_FALSE(bg.ready(p));
}

// A confirmed track at (20, 0) moving at 5 m/s along x claims the static pixels inside its box
// whose Doppler its motion explains; not those outside it, below its ground clearance, or with
// other Doppler.
TEST(TrackingClaims, CarryingTrackClaimsPixelsThatMoveAsItDoes) {
  HandScan h;
  MotionEstimate est;
  est.labels.assign(h.scan.size(), Segmentation::kInvalid);
  const auto put = [&](int c, const Eigen::Vector3d& p, double extra) {
    h.set(1, c, p, 5.0 * p.normalized().x() + extra);
    est.labels[h.scan.index(1, c)] = 0;  // static
  };
  put(0, {20.0, 0.5, 0.8}, 0.0);   // claimed
  put(1, {21.0, -0.5, 1.2}, 0.0);  // claimed
  put(2, {20.0, 0.5, 0.8}, 1.0);   // other Doppler
  put(3, {30.0, 0.5, 0.8}, 0.0);   // outside the box
  put(4, {20.0, 0.5, 0.05}, 0.0);  // below the clearance: the ground under it
  const ScanBeams beams(h.scan);
  const Frame frame = standing_frame(h.scan, beams);
  Track tr;
  tr.x << 20.0, 0.0, 5.0, 0.0, 0.0;
  tr.length_m = 4.5;
  tr.width_m = 1.8;
  tr.z_min_m = 0.0;
  tr.z_max_m = 1.5;
  tr.confirmed = true;
  std::vector<Group> groups(1);
  const BackgroundModel background;
  claim_pixels(frame, est, {tr}, {box_of(tr)}, background, TrackerParams{}, groups);
  EXPECT_EQ(groups[0].claimed, (std::vector<std::uint32_t>{static_cast<std::uint32_t>(h.scan.index(1, 0)),
                                                           static_cast<std::uint32_t>(h.scan.index(1, 1))}));
  EXPECT_TRUE(groups[0].found.empty());
  // A track that does not carry (not confirmed) claims nothing.
  tr.confirmed = false;
  std::vector<Group> none(1);
  claim_pixels(frame, est, {tr}, {box_of(tr)}, background, TrackerParams{}, none);
  EXPECT_TRUE(none[0].claimed.empty());
}

}  // namespace
}  // namespace fmcw::core::tracking
