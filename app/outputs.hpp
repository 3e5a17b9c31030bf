#pragma once
// What a command may write (README, "Outputs"): only where an --out/--json style option says, an
// existing output only with --force, never an input or into one, never one output over another.
// Checked before any work starts by one OutputGuard per command; the write itself is atomic
// (core/atomic_file.hpp, eval::publishDirectoryAtomically), so a failed --force run leaves the old
// bytes in place, and an output given without --force is never replaced, even when it appears
// during the run.

#include <CLI/CLI.hpp>
#include <filesystem>
#include <string>
#include <vector>

#include "slamprep/eval/formats/dataset_io.hpp"

namespace slamprep::app {

/// The paths one command reads and writes, checked together. check() refuses an output
/// (InputError naming its option, the path and the cause) when it
///   - is empty, or has a name longer than 255 bytes;
///   - is an input, lies inside an input folder, or contains an input (--force would delete it);
///   - is another output of the command, or lies inside or contains one;
///   - exists and --force was not given, or exists and is not of the kind its writer may replace
///     (a dataset, a trajectories folder export wrote), even with --force;
///   - lies in a folder that cannot be written (or below a file).
/// Paths are compared resolved (core/paths.hpp: symlinks, `..`, trailing slashes). check() then
/// marks each output given without --force with refuseToReplace (core/atomic_file.hpp).
class OutputGuard {
 public:
  explicit OutputGuard(bool force) : force_(force) {}

  /// A file or folder the command reads (skipped when empty: an option not given).
  OutputGuard& input(const std::filesystem::path& path, const std::string& option);
  /// An output file.
  OutputGuard& file(const std::filesystem::path& path, const std::string& option);
  /// An output dataset folder: with --force it replaces an empty folder or one that holds a
  /// dataset.json, never anything else (a typo such as `--out ~` must never replace a home).
  OutputGuard& dataset(const std::filesystem::path& dir, const std::string& option);
  /// Another kind of output folder: `replaceable` says which existing ones --force may replace,
  /// `kind` names them in the message ("a trajectories folder export wrote").
  OutputGuard& directory(const std::filesystem::path& dir, const std::string& option,
                         eval::ReplaceableDirectory replaceable, std::string kind);

  /// Throws InputError for the first output refused; marks the outputs (see above).
  void check() const;

 private:
  struct Named {
    std::filesystem::path path;
    std::string option;
  };
  struct Output : Named {
    bool is_directory = false;
    eval::ReplaceableDirectory replaceable;
    std::string kind;
  };
  void checkRelations(const Output& out, std::size_t index) const;
  void checkExisting(const Output& out) const;

  bool force_;
  std::vector<Named> inputs_;
  std::vector<Output> outputs_;
};

/// A CLI11 check for an output option: refuses an empty path at parse time (`--json ""` would
/// otherwise read as "not given").
CLI::Validator outputPath();

/// An input that must exist: a dataset directory (with dataset.json) or a readable file.
void checkInputDataset(const std::filesystem::path& dir, const std::string& option);
void checkInputFile(const std::filesystem::path& file, const std::string& option);

}  // namespace slamprep::app
