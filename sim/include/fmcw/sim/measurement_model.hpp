#pragma once
// From the true range and radial velocity of a hit to what the sensor reports.

#include <algorithm>
#include <cmath>
#include <string>

#include "fmcw/core/random.hpp"
#include "fmcw/core/scan.hpp"

namespace fmcw::sim {

struct MeasurementParams {
  enum class Model {
    kGaussian,       ///< Table I: additive Gaussian error on range and radial velocity
    kBeatFrequency,  ///< Eq. 2-5: beat frequencies of a triangular chirp, quantised to FFT bins
    /// Signal-to-noise ratio from reflectivity, incidence and range; detection probability and
    /// the noise follow it (docs/SIMULATOR.md, "SNR model").
    kSnr,
  };
  Model model = Model::kGaussian;
  /// What the reported radial velocity is measured against: the sensor (Eq. 6, the paper's
  /// raw Doppler) or ego-compensated (v + e . V_origin, as the Aeva datasets ship it).
  core::VelocityFrame velocity_frame = core::VelocityFrame::kSensor;
  double range_sigma_m = 0.025;       ///< [m] Table I distance error
  double velocity_sigma_mps = 0.031;  ///< [m/s] Table I velocity error
  // Beat-frequency model (Section III-B): 1550 nm, 8-14 GHz sweep (B = 6 GHz), T = 50 us.
  double wavelength_m = 1550e-9;
  double bandwidth_hz = 6e9;
  double chirp_period_s = 50e-6;
  /// In the beat-frequency model, Gaussian jitter [Hz] added to each beat frequency before it is
  /// quantised (0: quantisation only).
  double beat_frequency_sigma_hz = 0.0;
  double speed_of_light_mps = 299792458.0;
  /// SNR model. SNR = reference SNR * (reflectivity / reference_reflectivity) * |cos incidence|
  /// * (reference_range / R)^2 (the lidar equation for a Lambertian target filling the beam).
  struct Snr {
    /// [dB] SNR of a 10 % Lambertian target at normal incidence at reference_range_m: chosen so
    /// that such a target is detected half the time at 150 m (Table I's maximum range).
    double reference_db = 34.7;
    double reference_range_m = 10.0;      ///< [m]
    double reference_reflectivity = 0.1;  ///< the datasheet convention: a 10 % target
    /// [dB] SNR at which Table I's sigmas hold; sigma scales as sqrt(10^(sigma_reference_db/10) / SNR).
    double sigma_reference_db = 20.0;
    /// [dB] SNR detected half the time, and the logistic width [dB]: a fit of Albersheim's
    /// equation for one coherent look at a false-alarm probability of 1e-6 (Pd 0.1 at 7.8 dB,
    /// 0.5 at 11.2 dB, 0.9 at 13.1 dB).
    double detection_threshold_db = 11.2;
    double detection_width_db = 1.2;
    /// [m/s] the velocity sigma never goes below this (phase noise and the chirp's linearity
    /// bound the precision of a strong return).
    double velocity_sigma_floor_mps = 0.005;
    /// [m] the same for range.
    double range_sigma_floor_m = 0.002;
  } snr;

  void validate() const;  ///< std::invalid_argument naming the bad field
};

std::string to_string(MeasurementParams::Model model);
MeasurementParams::Model measurement_model_from_string(const std::string& name);  ///< throws

/// Up- and down-ramp beat frequencies of a triangular chirp for range D and radial velocity v:
/// Eq. 2 and 4 give f_bd + f_bu = 8 B D / (c T) and f_bd - f_bu = 4 v / lambda.
struct BeatFrequencies {
  double up_hz = 0.0;
  double down_hz = 0.0;
};

class MeasurementModel {
 public:
  explicit MeasurementModel(const MeasurementParams& params);

  struct Reading {
    double range_m;
    double radial_velocity_mps;
  };
  /// The reported range and radial velocity of a return. Draws two standard normals from rng
  /// (Gaussian model: range, then velocity error; beat-frequency model: up-, then down-ramp
  /// jitter), so a seeded rng gives reproducible readings.
  Reading measure(double true_range_m, double true_radial_velocity_mps, core::Rng& rng) const {
    const double normals[2] = {rng.normal(), rng.normal()};
    return measure(true_range_m, true_radial_velocity_mps, normals);
  }
  /// The same from two standard normals drawn beforehand. Inline: it runs once per pixel.
  Reading measure(double true_range_m, double true_radial_velocity_mps, const double* normals) const {
    if (params_.model == MeasurementParams::Model::kBeatFrequency) {
      return measure_beat_frequency(true_range_m, true_radial_velocity_mps, normals);
    }
    return {true_range_m + params_.range_sigma_m * normals[0],
            true_radial_velocity_mps + params_.velocity_sigma_mps * normals[1]};
  }
  /// Standard normals each return draws: 2 (range, velocity), 3 with the SNR model (the third
  /// decides detection).
  int normals_per_return() const { return params_.model == MeasurementParams::Model::kSnr ? 3 : 2; }
  /// A return of a surface of this reflectivity at this incidence: false when the SNR model
  /// drops it; otherwise the reading in out. Other models: measure() and always true.
  bool measure_return(double true_range_m, double true_radial_velocity_mps, double reflectivity,
                      double cos_incidence, const double* normals, Reading& out) const {
    if (params_.model != MeasurementParams::Model::kSnr) {
      out = measure(true_range_m, true_radial_velocity_mps, normals);
      return true;
    }
    const double snr = snr_linear(true_range_m, reflectivity, cos_incidence);
    if (!(normal_cdf(normals[2]) < detection_probability(snr))) return false;
    const Sigmas s = sigmas(snr);
    out = {true_range_m + s.range_m * normals[0], true_radial_velocity_mps + s.velocity_mps * normals[1]};
    return true;
  }

  /// SNR model: the linear SNR of a return (0 for a surface seen edge-on or of zero reflectivity).
  double snr_linear(double range_m, double reflectivity, double cos_incidence) const;
  /// Logistic in dB around detection_threshold_db.
  double detection_probability(double snr_linear) const;
  struct Sigmas {
    double range_m;
    double velocity_mps;
  };
  /// Table I's sigmas scaled by sqrt(SNR_ref / SNR), floored.
  Sigmas sigmas(double snr_linear) const;
  static double normal_cdf(double z) { return 0.5 * std::erfc(-z * M_SQRT1_2); }

  BeatFrequencies beat_frequencies(double range_m, double radial_velocity_mps) const;
  Reading from_beat_frequencies(const BeatFrequencies& f) const;  ///< Eq. 2 and Eq. 4
  double fft_bin_hz() const;                ///< 2 / T: each ramp lasts T / 2
  double range_resolution_m() const;        ///< Eq. 3: c / (2 B)
  double velocity_resolution_mps() const;   ///< Eq. 5: lambda / T
  const MeasurementParams& params() const { return params_; }

 private:
  Reading measure_beat_frequency(double true_range_m, double true_radial_velocity_mps, const double* normals) const;
  MeasurementParams params_;
};

/// Return intensity: Lambertian reflectivity times the cosine of incidence, falling with the
/// square of range beyond a 10 m reference (a bright wall at 10 m gives its reflectivity).
inline float return_intensity(float reflectivity, double cos_incidence, double range_m) {
  constexpr double kReferenceRange = 10.0;
  constexpr double kReferenceSq = kReferenceRange * kReferenceRange;
  // 100 / max(r^2, 100): the same values as r > 10 ? 100 / r^2 : 1, without a branch.
  const double falloff = kReferenceSq / std::max(range_m * range_m, kReferenceSq);
  return static_cast<float>(reflectivity * std::abs(cos_incidence) * falloff);
}

}  // namespace fmcw::sim
