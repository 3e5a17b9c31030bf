#include "slamprep/eval/formats/bag_topics.hpp"

#include "slamprep/core/error.hpp"
#include "slamprep/eval/formats/mcap.hpp"

namespace slamprep::eval {
namespace {

void addTopics(const std::map<std::uint16_t, McapSchema>& schemas,
               const std::map<std::uint16_t, McapChannel>& channels, const std::string& file,
               BagTopics& topics) {
  for (const auto& [id, ch] : channels) {
    const auto s = schemas.find(ch.schema_id);
    BagTopic t{s == schemas.end() ? "" : normalType(s->second.name), ch.message_encoding};
    const auto [it, inserted] = topics.emplace(ch.topic, t);
    if (!inserted && it->second.type != t.type)
      throw InputError(file, "topic " + ch.topic + " has type " + t.type + " here but " +
                                 it->second.type + " in an earlier file of the bag");
  }
}

}  // namespace

std::string normalType(std::string_view name) {
  std::string type(name);
  if (const auto p = type.find("/msg/"); p != std::string::npos) type.erase(p, 4);
  return type;
}

BagTopics listTopics(const std::vector<ByteSource*>& files) {
  BagTopics topics;
  for (ByteSource* file : files) {
    McapReader reader(*file);
    if (const auto summary = reader.summary()) {
      addTopics(summary->schemas, summary->channels, file->name(), topics);
      continue;
    }
    McapMessage m;
    while (reader.next(m)) {
    }
    addTopics(reader.schemas(), reader.channels(), file->name(), topics);
  }
  return topics;
}

std::string chooseTopic(const BagTopics& topics, std::string_view type, const std::string& chosen,
                        const std::string& preferred, const std::string& bag, const char* flag) {
  const std::string want = normalType(type);
  std::vector<std::string> found;
  for (const auto& [topic, t] : topics)
    if (t.type == want && (chosen.empty() || topic == chosen)) found.push_back(topic);
  if (!chosen.empty() && found.empty()) {
    const auto it = topics.find(chosen);
    throw InputError(bag, std::string(flag) + " " + chosen + ": " +
                              (it == topics.end() ? "no such topic in the bag"
                                                  : "its type is " + it->second.type + ", not " +
                                                        std::string(type)));
  }
  std::string topic;
  if (found.size() == 1) topic = found[0];
  for (const auto& t : found)
    if (found.size() > 1 && t == preferred) topic = t;
  if (found.size() > 1 && topic.empty()) {
    std::string list;
    for (const auto& t : found) list += " " + t;
    throw InputError(bag,
                     std::string(type) + " on several topics (" + list + " ): choose with " + flag);
  }
  if (!topic.empty() && topics.at(topic).encoding != "cdr")
    throw InputError(bag, "topic " + topic + ": message encoding \"" + topics.at(topic).encoding +
                              "\" is not supported (only cdr, the ROS 2 encoding)");
  return topic;
}

}  // namespace slamprep::eval
