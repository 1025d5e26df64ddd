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
}

std::string to_string(MeasurementParams::Model model) {
  return model == MeasurementParams::Model::kGaussian ? "gaussian" : "beat_frequency";
}

MeasurementParams::Model measurement_model_from_string(const std::string& name) {
  if (name == "gaussian") return MeasurementParams::Model::kGaussian;
  if (name == "beat_frequency") return MeasurementParams::Model::kBeatFrequency;
  throw core::InputError("measurement: unknown model '" + name + "' (known: gaussian, beat_frequency)");
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
