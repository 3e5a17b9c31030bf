#pragma once
// Stamps of a constant-rate sensor put back on their grid. Encoders, IMUs and lidars sample at a
// fixed rate on their own clock; the host stamps them when the data arrives, which adds jitter
// (docs/faults.md, stamp_jitter). Fitting the grid t_k = t_0 + k T (T slowly varying: clock
// drift) to the stamps removes that jitter; missing samples (dropouts) are gaps of whole periods.

#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace slamprep::algo {

struct StampGridParams {
  /// Residual RMS to the grid below which the stamps are left as they are: they are regular
  /// already (a clean simulation's are exact to rounding; hardware stamping is ~ 1 us).
  double min_rms_s = 5e-5;
  /// Residual RMS, as a fraction of the period, above which the stream is not taken for a
  /// constant-rate one and is left alone: stamps with no grid at all scatter uniformly over a
  /// period (RMS 0.29 T); 1 ms of jitter on a 200 Hz IMU is 0.2 T.
  double max_rms_fraction = 0.25;
  /// Samples in each local line fit: the grid's period may drift with the sensor's clock.
  std::size_t window = 201;
  /// A stream whose own evidence (stamp_checks.hpp) puts its stamps' error below this fraction
  /// of their irregularity keeps them (regularizeStamps): it was sampled irregularly and stamped
  /// right, and its grid would move each sample by about its irregularity.
  double right_fraction = 1.0 / 3.0;
};

/// What fitStampGrid found and did.
struct StampGrid {
  std::vector<double> stamps;  ///< the regularised stamps when applied, else the input
  bool applied = false;
  std::string reason;               ///< why not applied ("" when applied)
  double period_s = 0.0;            ///< fitted mean period
  double residual_rms_s = 0.0;      ///< input stamps against the fitted grid
  double residual_max_s = 0.0;      ///< largest |input - grid|
  std::size_t missing_samples = 0;  ///< grid points without a sample (gaps bridged)
};

/// Fits the constant-rate grid to strictly increasing stamps and returns the grid's stamps when
/// the input is measurably but plausibly irregular (min_rms_s < RMS < max_rms_fraction * T).
/// The output keeps the input's order and count and increases strictly.
StampGrid fitStampGrid(std::span<const double> stamps, const StampGridParams& params = {});

/// A stream's sampling period: the fitted grid's where the stamps have one (jittered, or with an
/// alternating step: an RPLIDAR driver stamps its scans 0.123 and 0.135 s apart in turn, about a
/// 0.1296 s period, whose median step is 0.1348 s), else the median step; 0 when undefined.
double streamPeriod(std::span<const double> stamps, const StampGridParams& params = {});

}  // namespace slamprep::algo
