#pragma once
// The topics of a ROS 2 bag (all its files) by message type, and the choice of the topic that
// carries each type the importer reads.

#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "slamprep/eval/formats/byte_source.hpp"

namespace slamprep::eval {

struct BagTopic {
  std::string type;      ///< "pkg/Type" (schema names "pkg/msg/Type" and "pkg/Type" both map here)
  std::string encoding;  ///< message encoding, "cdr" for ROS 2
};
using BagTopics = std::map<std::string, BagTopic>;  ///< by topic name

/// "pkg/msg/Type" -> "pkg/Type".
std::string normalType(std::string_view name);

/// The topics of every file: from its summary's channels, or (a file without a summary, e.g. a
/// recording cut short) from a pass over its data section. Throws InputError when a topic has
/// different types in different files.
BagTopics listTopics(const std::vector<ByteSource*>& files);

/// The topic carrying `type`: `chosen` when given (it must exist with that type), else the only
/// one, else `preferred`; empty when the bag has none. Several candidates without `preferred`
/// among them are an InputError listing them and naming `flag`. The chosen topic must be CDR.
std::string chooseTopic(const BagTopics& topics, std::string_view type, const std::string& chosen,
                        const std::string& preferred, const std::string& bag, const char* flag);

}  // namespace slamprep::eval
