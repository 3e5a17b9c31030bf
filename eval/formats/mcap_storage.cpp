// BagStorage over McapReader: channels become topics as they appear.
#include "slamprep/core/error.hpp"
#include "slamprep/eval/formats/bag_storage.hpp"

namespace slamprep::eval {
namespace {

class McapStorage final : public BagStorage {
 public:
  explicit McapStorage(ByteSource& source) : source_(source), reader_(source) {}

  const std::string& name() const override { return source_.name(); }

  BagTopics topics() override { return listTopics({&source_}); }

  const StorageTopic& topic(std::uint32_t id) const override {
    const auto it = topics_.find(id);
    if (it != topics_.end()) return it->second;
    const McapChannel& ch = reader_.channels().at(static_cast<std::uint16_t>(id));
    const auto schema = reader_.schemas().find(ch.schema_id);
    StorageTopic t{ch.topic,
                   schema == reader_.schemas().end() ? "" : normalType(schema->second.name),
                   ch.message_encoding};
    return topics_.emplace(id, std::move(t)).first->second;
  }

  void select(const std::set<std::string>&) override {}

  bool next(BagMessage& m) override {
    if (!reader_.next(message_)) return false;
    m.topic_id = message_.channel_id;
    m.log_time_ns = message_.log_time_ns;
    m.position = message_.file_offset;
    m.sequence = message_.sequence;
    m.data.swap(message_.data);  // the reader reuses whichever string it gets back
    return true;
  }

  std::string positionText(std::uint64_t position) const override {
    return "offset " + std::to_string(position);
  }

  std::vector<McapMetadata> metadata() const override { return reader_.metadata(); }

 private:
  ByteSource& source_;
  McapReader reader_;
  McapMessage message_;
  mutable std::map<std::uint32_t, StorageTopic> topics_;
};

}  // namespace

std::unique_ptr<BagStorage> openMcapStorage(ByteSource& source) {
  return std::make_unique<McapStorage>(source);
}

}  // namespace slamprep::eval
