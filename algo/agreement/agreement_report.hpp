#pragma once
// SensorAgreement as the `sensor_agreement` JSON object of import, match and calibrate, and as
// the lines those commands print (docs/matching.md "Sensor agreement").

#include <nlohmann/json.hpp>
#include <string>

#include "slamprep/algo/agreement/sensor_agreement.hpp"

namespace slamprep::algo {

/// docs/matching.md "sensor_agreement": sources, pairs with their disagreeing spans, findings.
/// Angles in degrees, as every JSON output a person reads.
nlohmann::ordered_json agreementJson(const SensorAgreement& agreement,
                                     const std::string& wheels_from);

/// A few lines for the terminal: each source's turning, each pair's scale and disagreements.
std::string agreementText(const SensorAgreement& agreement);

/// One line per disagreeing span of the wheels against the gyro: why calibrate refuses.
std::string wheelsGyroConflictText(const SensorAgreement& agreement);

/// " +t0..+t1 s from the start (cause);" for each disagreeing span of `pair`.
std::string spansText(const SensorAgreement& agreement, const PairAgreement& pair);

}  // namespace slamprep::algo
