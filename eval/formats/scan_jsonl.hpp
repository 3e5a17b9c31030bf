#pragma once
// scans.jsonl: one scan per line as a JSON object in the laser_data format of CSM (the Canonical
// Scan Matcher) plus slamprep's exact fields (docs/dataset.md, "scans.jsonl").

#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "slamprep/core/dataset.hpp"
#include "slamprep/eval/formats/text_io.hpp"

namespace slamprep::eval {

/// Appends one scan as a single JSON line (with its '\n'). Throws InputError at `where` (the
/// line it would occupy) for values that could not be read back: NaN/Inf in stamps, angles,
/// poses or points, range_min not finite, p_ref_true or p_ref not empty and not one entry per
/// beam, and for scans readers refuse: no beams, range_min < 0, range_max <= range_min,
/// time_increment < 0, scan_time < 0.
/// Non-finite ranges (REP 117 +inf/-inf/NaN) are all written as null and read back as +inf.
void appendScanLine(std::string& out, const ScanRecord& record, const TextLocation& where);

/// Parses one line. Throws InputError naming `where` and the field for bad JSON, missing keys,
/// wrong types, length mismatches with nrays, non-finite numbers, and the scans appendScanLine
/// refuses (no beams, negative range_min, ...).
ScanRecord parseScanLine(std::string_view line, const TextLocation& where);

std::string formatScans(const std::vector<ScanRecord>& scans, const std::string& file);
/// The same text written to `path` a few scans at a time (scans.jsonl of a long run is about
/// 1 GB per 30 min), with writeTextFile's durability; `file` names it in errors.
void writeScans(const std::filesystem::path& path, const std::vector<ScanRecord>& scans,
                const std::string& file);
/// The same from a source that hands out one scan at a time (false after the last), so the
/// scans need never all be in memory.
using ScanSource = std::function<bool(ScanRecord&)>;
void writeScans(const std::filesystem::path& path, const ScanSource& next, const std::string& file);
/// Every non-blank line is a scan; stamps must increase strictly. `line_numbers`, when given,
/// receives the 1-based line of every scan (for messages about a scan found later).
std::vector<ScanRecord> parseScans(std::string_view text, const std::string& file,
                                   std::vector<std::size_t>* line_numbers = nullptr);

}  // namespace slamprep::eval
