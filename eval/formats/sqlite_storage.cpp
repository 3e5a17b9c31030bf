// BagStorage over a rosbag2 sqlite3 file (.db3), through the system's libsqlite3.
#include <sqlite3.h>

#include <cctype>
#include <map>

#include "slamprep/core/error.hpp"
#include "slamprep/eval/formats/bag_storage.hpp"

namespace slamprep::eval {
namespace {

/// `file` as an SQLite URI path: every byte but the unreserved ones and '/' percent-encoded.
std::string uriPath(const std::filesystem::path& file) {
  static const char* hex = "0123456789ABCDEF";
  std::string out;
  for (const unsigned char c : std::filesystem::absolute(file).string()) {
    if (std::isalnum(c) || c == '/' || c == '-' || c == '_' || c == '.' || c == '~') {
      out += static_cast<char>(c);
    } else {
      out += '%';
      out += hex[c >> 4];
      out += hex[c & 15];
    }
  }
  return out;
}

using Statement = std::unique_ptr<sqlite3_stmt, decltype(&sqlite3_finalize)>;
using Database = std::unique_ptr<sqlite3, decltype(&sqlite3_close)>;

class SqliteStorage final : public BagStorage {
 public:
  SqliteStorage(const std::filesystem::path& file, bool immutable, const std::string& name)
      : name_(name.empty() ? file.string() : name) {
    const std::string uri = "file:" + uriPath(file) + (immutable ? "?immutable=1" : "");
    const int flags = SQLITE_OPEN_URI | (immutable ? SQLITE_OPEN_READONLY : SQLITE_OPEN_READWRITE);
    sqlite3* opened = nullptr;
    const int rc = sqlite3_open_v2(uri.c_str(), &opened, flags, nullptr);
    // Owned before anything can throw: a failed open or a corrupt topics table still closes it.
    db_.reset(opened);
    if (rc != SQLITE_OK) {
      const std::string why = opened ? sqlite3_errmsg(opened) : sqlite3_errstr(rc);
      throw InputError(name_, "cannot open as an SQLite database: " + why);
    }
    readTopics();
  }

  const std::string& name() const override { return name_; }

  BagTopics topics() override {
    BagTopics out;
    for (const auto& [id, t] : topics_) out.emplace(t.name, BagTopic{t.type, t.encoding});
    return out;
  }

  const StorageTopic& topic(std::uint32_t id) const override { return topics_.at(id); }

  void select(const std::set<std::string>& names) override {
    std::string ids;
    for (const auto& [id, t] : topics_)
      if (names.count(t.name)) {
        if (!ids.empty()) ids += ',';
        ids += std::to_string(id);
      }
    // rosbag2 indexes messages by timestamp; (timestamp, id) is that index's order.
    rows_ = prepare("SELECT id, topic_id, timestamp, data FROM messages WHERE topic_id IN (" + ids +
                    ") ORDER BY timestamp, id");
  }

  bool next(BagMessage& m) override {
    if (!rows_) select({});
    const int rc = sqlite3_step(rows_.get());
    if (rc == SQLITE_DONE) return false;
    if (rc != SQLITE_ROW)
      throw InputError(name_, "messages after row " + std::to_string(last_row_) + ": " +
                                  sqlite3_errmsg(db_.get()) + " (a corrupt or truncated .db3)");
    const sqlite3_int64 row = sqlite3_column_int64(rows_.get(), 0);
    const sqlite3_int64 topic = sqlite3_column_int64(rows_.get(), 1);
    const sqlite3_int64 stamp = sqlite3_column_int64(rows_.get(), 2);
    last_row_ = row;
    const std::string where = name_ + ": " + positionText(static_cast<std::uint64_t>(row));
    if (!topics_.count(topic))
      throw InputError(where, "topic_id " + std::to_string(topic) + " is not in the topics table");
    if (stamp < 0) throw InputError(where, "timestamp " + std::to_string(stamp) + " is negative");
    const auto* blob = static_cast<const char*>(sqlite3_column_blob(rows_.get(), 3));
    const int bytes = sqlite3_column_bytes(rows_.get(), 3);
    m.topic_id = static_cast<std::uint32_t>(topic);
    m.log_time_ns = static_cast<std::uint64_t>(stamp);
    m.position = static_cast<std::uint64_t>(row);
    m.sequence = sequences_[m.topic_id]++;
    m.data.assign(blob ? blob : "", static_cast<std::size_t>(bytes));
    return true;
  }

  std::string positionText(std::uint64_t position) const override {
    return "messages row " + std::to_string(position);
  }

 private:
  Statement prepare(const std::string& sql) {
    sqlite3_stmt* s = nullptr;
    if (sqlite3_prepare_v2(db_.get(), sql.c_str(), -1, &s, nullptr) != SQLITE_OK) {
      sqlite3_finalize(s);
      throw InputError(name_,
                       std::string("not a rosbag2 sqlite3 file: ") + sqlite3_errmsg(db_.get()));
    }
    return Statement(s, &sqlite3_finalize);
  }

  void readTopics() {
    const Statement s = prepare("SELECT id, name, type, serialization_format FROM topics");
    int rc;
    while ((rc = sqlite3_step(s.get())) == SQLITE_ROW) {
      const sqlite3_int64 id = sqlite3_column_int64(s.get(), 0);
      if (id < 0 || id > 0xffffffffLL)
        throw InputError(name_, "topics: id " + std::to_string(id) + " out of range");
      auto text = [&](int column) {
        const auto* t = sqlite3_column_text(s.get(), column);
        return t ? std::string(reinterpret_cast<const char*>(t)) : std::string();
      };
      topics_[static_cast<std::uint32_t>(id)] = {text(1), normalType(text(2)), text(3)};
    }
    if (rc != SQLITE_DONE)
      throw InputError(name_, std::string("topics: ") + sqlite3_errmsg(db_.get()) +
                                  " (a corrupt or truncated .db3)");
  }

  std::string name_;
  Database db_{nullptr, &sqlite3_close};  // declared before the statements: closed after them
  std::map<std::uint32_t, StorageTopic> topics_;
  std::map<std::uint32_t, std::uint32_t> sequences_;
  Statement rows_{nullptr, &sqlite3_finalize};
  sqlite3_int64 last_row_ = 0;
};

}  // namespace

std::unique_ptr<BagStorage> openSqliteStorage(const std::filesystem::path& file, bool immutable,
                                              const std::string& name) {
  return std::make_unique<SqliteStorage>(file, immutable, name);
}

}  // namespace slamprep::eval
