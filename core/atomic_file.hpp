#pragma once
// Output files that are never seen half-written: write a temporary sibling, then rename. The
// rename is where an output given without --force is protected (refuseToReplace).

#include <filesystem>
#include <string>

namespace slamprep {

/// Writes `text` to `file` atomically (temporary sibling + renameIntoPlace). Creates parent
/// folders. Throws InputError naming the file when it cannot be written.
void writeFileAtomic(const std::filesystem::path& file, const std::string& text);

/// Reads a whole file; throws InputError naming the file when it cannot be read or is not a
/// regular file.
std::string readFile(const std::filesystem::path& file);

/// `<folder>/<name>.<tag>-<pid>`: the sibling a file or folder is written into before it is
/// renamed onto `target` (tag "partial"), or the old one is moved to ("old"). `name` is
/// shortened so that the sibling's name fits in 255 bytes whenever the target's does.
std::filesystem::path partialSibling(const std::filesystem::path& target,
                                     const std::string& tag = "partial");

/// Marks `target` as an output this process creates but must not replace (`option` names it in
/// messages, e.g. "--out"): the commands mark every output given without --force
/// (app/outputs.hpp), so one that appears while they work is refused at the final rename.
void refuseToReplace(const std::filesystem::path& target, const std::string& option);

/// Whether renameIntoPlace may replace an existing `target` (not marked by refuseToReplace).
bool mayReplace(const std::filesystem::path& target);

/// Renames `from` (a file or folder) onto `to` only if nothing is at `to`: false, with `from`
/// left in place, when something is (renameat2(RENAME_NOREPLACE), or link(2) for a file where the
/// filesystem lacks it). Throws InputError naming `to` on any other failure.
bool renameIfAbsent(const std::filesystem::path& from, const std::filesystem::path& to);

/// Renames the finished `from` (a file or folder) onto `to`, replacing an existing `to` unless
/// refuseToReplace marked it: then nothing is replaced and InputError names the option, `to`
/// and that it appeared during the run. Throws InputError naming `to` on any failure; `from` is
/// the caller's to remove.
void renameIntoPlace(const std::filesystem::path& from, const std::filesystem::path& to);

}  // namespace slamprep
