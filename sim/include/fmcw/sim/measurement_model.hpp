#pragma once
// From the true range and radial velocity of a hit to what the sensor reports.

#include <algorithm>
#include <cmath>
#include <string>

#include "fmcw/core/random.hpp"

namespace fmcw::sim {

struct MeasurementParams {
  enum class Model {
    kGaussian,       ///< Table I: additive Gaussian error on range and radial velocity
    kBeatFrequency,  ///< Eq. 2-5: beat frequencies of a triangular chirp, quantised to FFT bins
  };
  Model model = Model::kGaussian;
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
    if (params_.model != MeasurementParams::Model::kGaussian) {
      return measure_beat_frequency(true_range_m, true_radial_velocity_mps, normals);
    }
    return {true_range_m + params_.range_sigma_m * normals[0],
            true_radial_velocity_mps + params_.velocity_sigma_mps * normals[1]};
  }

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
