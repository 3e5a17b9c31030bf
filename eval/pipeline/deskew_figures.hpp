#pragma once
// A method's de-skew of a dataset in numbers: the point error against the truth, split by its
// cause, and the repacked scans' error. What `slamprep deskew --json` and a bench trial's
// "deskew/<method>" write (deskew_json.hpp), each figure under one key.

#include <array>
#include <cstddef>
#include <optional>

#include "slamprep/core/enum_names.hpp"
#include "slamprep/eval/pipeline/dataset_deskew.hpp"

namespace slamprep::eval {

/// The figures of DeskewFigures, by their JSON key, in the order they are written.
enum class DeskewFigure {
  kMean,
  kRms,
  kP95,
  kMax,
  kRotationMean,
  kRotationP95,
  kTranslationMean,
  kTranslationP95,
  kSplitResidualMax,
  kRepackedMean,
  kRepackedP95,
  kRepackedLostBeams,
  kBeams
};

inline constexpr auto kDeskewFigureKeys = std::to_array<EnumName<DeskewFigure>>(
    {{DeskewFigure::kMean, "mean_m"},
     {DeskewFigure::kRms, "rms_m"},
     {DeskewFigure::kP95, "p95_m"},
     {DeskewFigure::kMax, "max_m"},
     {DeskewFigure::kRotationMean, "rotation_mean_m"},
     {DeskewFigure::kRotationP95, "rotation_p95_m"},
     {DeskewFigure::kTranslationMean, "translation_mean_m"},
     {DeskewFigure::kTranslationP95, "translation_p95_m"},
     {DeskewFigure::kSplitResidualMax, "split_residual_max_m"},
     {DeskewFigure::kRepackedMean, "repacked_mean_m"},
     {DeskewFigure::kRepackedP95, "repacked_p95_m"},
     {DeskewFigure::kRepackedLostBeams, "repacked_lost_beams"},
     {DeskewFigure::kBeams, "beams"}});

/// nullopt: the dataset cannot give the figure (no truth, scans not repacked).
struct DeskewFigures {
  std::optional<double> mean_m;                    ///< point error against the truth, mean
  std::optional<double> rms_m;                     ///< ... RMS
  std::optional<double> p95_m;                     ///< ... 95th percentile
  std::optional<double> max_m;                     ///< ... max
  std::optional<double> rotation_mean_m;           ///< the part the rotation error explains
  std::optional<double> rotation_p95_m;            ///< ... its 95th percentile
  std::optional<double> translation_mean_m;        ///< the part the translation error explains
  std::optional<double> translation_p95_m;         ///< ... its 95th percentile
  std::optional<double> split_residual_max_m;      ///< what the split leaves unexplained, max
  std::optional<double> repacked_mean_m;           ///< repacked scans against the truth, mean
  std::optional<double> repacked_p95_m;            ///< ... 95th percentile
  std::optional<std::size_t> repacked_lost_beams;  ///< grid rays the repacking lost
  std::optional<std::size_t> beams;                ///< beams measured

  bool operator==(const DeskewFigures&) const = default;
};

/// The figures of `deskewed`; the split by cause only when every measured scan had both parts.
DeskewFigures deskewFigures(const DatasetDeskew& deskewed);

}  // namespace slamprep::eval
