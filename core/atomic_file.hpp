#pragma once
// Output files that are never seen half-written: write a temporary sibling, then rename.

#include <filesystem>
#include <string>

namespace slamprep {

/// Writes `text` to `file` atomically (temporary sibling + rename). Creates parent folders.
/// Throws InputError naming the file when it cannot be written.
void writeFileAtomic(const std::filesystem::path& file, const std::string& text);

/// Reads a whole file; throws InputError naming the file when it cannot be read or is not a
/// regular file.
std::string readFile(const std::filesystem::path& file);

}  // namespace slamprep
