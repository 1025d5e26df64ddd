#include "fmcw/sim/measurement_model.hpp"

#include <cmath>

#include "fmcw/core/check.hpp"

namespace fmcw::sim {

void MeasurementParams::validate() const {
  // Beyond 10 m (m/s) the noise is no longer a measurement error: ranges and Doppler turn into
  // noise alone, and squares of it overflow.
  FMCW_CHECK_ARG(std::isfinite(range_sigma_m) && range_sigma_m >= 0.0 && range_sigma_m <= 10.0,
                 "measurement: range_sigma_m must be in [0, 10] m, got ", range_sigma_m);
  FMCW_CHECK_ARG(std::isfinite(velocity_sigma_mps) && velocity_sigma_mps >= 0.0 && velocity_sigma_mps <= 10.0,
                 "measurement: velocity_sigma_mps must be in [0, 10] m/s, got ", velocity_sigma_mps);
  FMCW_CHECK_ARG(wavelength_m > 0.0 && bandwidth_hz > 0.0 && chirp_period_s > 0.0 && speed_of_light_mps > 0.0,
                 "measurement: wavelength_m, bandwidth_hz and chirp_period_s must be > 0");
  FMCW_CHECK_ARG(std::isfinite(beat_frequency_sigma_hz) && beat_frequency_sigma_hz >= 0.0,
                 "measurement: beat_frequency_sigma_hz must be >= 0, got ", beat_frequency_sigma_hz);
  FMCW_CHECK_ARG(std::isfinite(snr.reference_db) && std::abs(snr.reference_db) <= 200.0,
                 "measurement: snr.reference_db must be in [-200, 200] dB, got ", snr.reference_db);
  FMCW_CHECK_ARG(std::isfinite(snr.sigma_reference_db) && std::abs(snr.sigma_reference_db) <= 200.0,
                 "measurement: snr.sigma_reference_db must be in [-200, 200] dB, got ", snr.sigma_reference_db);
  FMCW_CHECK_ARG(std::isfinite(snr.detection_threshold_db) && std::abs(snr.detection_threshold_db) <= 200.0,
                 "measurement: snr.detection_threshold_db must be in [-200, 200] dB, got ", snr.detection_threshold_db);
  FMCW_CHECK_ARG(std::isfinite(snr.reference_range_m) && snr.reference_range_m > 0.0,
                 "measurement: snr.reference_range_m must be > 0, got ", snr.reference_range_m);
  FMCW_CHECK_ARG(std::isfinite(snr.reference_reflectivity) && snr.reference_reflectivity > 0.0,
                 "measurement: snr.reference_reflectivity must be > 0, got ", snr.reference_reflectivity);
  FMCW_CHECK_ARG(std::isfinite(snr.detection_width_db) && snr.detection_width_db > 0.0,
                 "measurement: snr.detection_width_db must be > 0, got ", snr.detection_width_db);
  FMCW_CHECK_ARG(std::isfinite(snr.velocity_sigma_floor_mps) && snr.velocity_sigma_floor_mps >= 0.0 &&
                     snr.velocity_sigma_floor_mps <= 10.0,
                 "measurement: snr.velocity_sigma_floor_mps must be in [0, 10] m/s, got ", snr.velocity_sigma_floor_mps);
  FMCW_CHECK_ARG(std::isfinite(snr.range_sigma_floor_m) && snr.range_sigma_floor_m >= 0.0 && snr.range_sigma_floor_m <= 10.0,
                 "measurement: snr.range_sigma_floor_m must be in [0, 10] m, got ", snr.range_sigma_floor_m);
}

std::string to_string(MeasurementParams::Model model) {
  switch (model) {
    case MeasurementParams::Model::kGaussian:
      return "gaussian";
    case MeasurementParams::Model::kBeatFrequency:
      return "beat_frequency";
    case MeasurementParams::Model::kSnr:
      return "snr";
  }
  return "unknown";
}

MeasurementParams::Model measurement_model_from_string(const std::string& name) {
  if (name == "gaussian") return MeasurementParams::Model::kGaussian;
  if (name == "beat_frequency") return MeasurementParams::Model::kBeatFrequency;
  if (name == "snr") return MeasurementParams::Model::kSnr;
  throw core::InputError("measurement: unknown model '" + name + "' (known: gaussian, beat_frequency, snr)");
}

double MeasurementModel::snr_linear(double range_m, double reflectivity, double cos_incidence) const {
  const MeasurementParams::Snr& p = params_.snr;
  const double r = std::max(range_m, 1e-3);
  const double ratio = p.reference_range_m / r;
  return std::pow(10.0, p.reference_db / 10.0) * (std::max(0.0, reflectivity) / p.reference_reflectivity) *
         std::abs(cos_incidence) * ratio * ratio;
}

double MeasurementModel::detection_probability(double snr) const {
  if (!(snr > 0.0)) return 0.0;
  const double snr_db = 10.0 * std::log10(snr);
  return 1.0 / (1.0 + std::exp(-(snr_db - params_.snr.detection_threshold_db) / params_.snr.detection_width_db));
}

MeasurementModel::Sigmas MeasurementModel::sigmas(double snr) const {
  const MeasurementParams::Snr& p = params_.snr;
  // sigma ~ 1 / sqrt(SNR) (Cramer-Rao bound of a frequency estimate), from Table I's values at
  // sigma_reference_db.
  const double scale = std::sqrt(std::pow(10.0, p.sigma_reference_db / 10.0) / std::max(snr, 1e-30));
  return {std::max(p.range_sigma_floor_m, params_.range_sigma_m * scale),
          std::max(p.velocity_sigma_floor_mps, params_.velocity_sigma_mps * scale)};
}

MeasurementModel::MeasurementModel(const MeasurementParams& params) : params_(params) { params_.validate(); }

double MeasurementModel::fft_bin_hz() const { return 2.0 / params_.chirp_period_s; }
double MeasurementModel::range_resolution_m() const { return params_.speed_of_light_mps / (2.0 * params_.bandwidth_hz); }
double MeasurementModel::velocity_resolution_mps() const { return params_.wavelength_m / params_.chirp_period_s; }

BeatFrequencies MeasurementModel::beat_frequencies(double range_m, double v_mps) const {
  const double c = params_.speed_of_light_mps;
  const double sum = 8.0 * params_.bandwidth_hz * range_m / (c * params_.chirp_period_s);  // Eq. 2
  const double diff = 4.0 * v_mps / params_.wavelength_m;                                  // Eq. 4
  return {0.5 * (sum - diff), 0.5 * (sum + diff)};
}

MeasurementModel::Reading MeasurementModel::from_beat_frequencies(const BeatFrequencies& f) const {
  const double c = params_.speed_of_light_mps;
  return {c * params_.chirp_period_s / (8.0 * params_.bandwidth_hz) * (f.down_hz + f.up_hz),  // Eq. 2
          params_.wavelength_m / 4.0 * (f.down_hz - f.up_hz)};                              // Eq. 4
}

MeasurementModel::Reading MeasurementModel::measure_beat_frequency(double range_m, double v_mps,
                                                                  const double* normals) const {
  BeatFrequencies f = beat_frequencies(range_m, v_mps);
  const double jitter_up = params_.beat_frequency_sigma_hz * normals[0];
  const double jitter_down = params_.beat_frequency_sigma_hz * normals[1];
  // The peak of each ramp's spectrum lands in the nearest FFT bin of width 2 / T.
  const double bin = fft_bin_hz();
  f.up_hz = std::round((f.up_hz + jitter_up) / bin) * bin;
  f.down_hz = std::round((f.down_hz + jitter_down) / bin) * bin;
  return from_beat_frequencies(f);
}

}  // namespace fmcw::sim
