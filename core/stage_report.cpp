#include "slamprep/core/stage_report.hpp"

#include <sstream>

namespace slamprep {
namespace {

StageSink& currentSink() {
  static StageSink sink;
  return sink;
}

void report(const StageEvent& event) {
  if (const StageSink& sink = currentSink()) sink(event);
}

}  // namespace

ScopedStageSink::ScopedStageSink(StageSink sink) : previous_(std::move(currentSink())) {
  currentSink() = std::move(sink);
}

ScopedStageSink::~ScopedStageSink() {
  currentSink() = std::move(previous_);
}

StageReporter::StageReporter(std::string task, int count) : task_(std::move(task)), count_(count) {}

StageReporter::~StageReporter() {
  end();
}

void StageReporter::begin(const std::string& stage) {
  end();
  stage_ = stage;
  ++index_;
  open_ = true;
  report({task_, stage_, index_, count_, StageEvent::kStart, 0.0});
}

void StageReporter::update(double fraction) const {
  if (open_) report({task_, stage_, index_, count_, StageEvent::kUpdate, fraction});
}

void StageReporter::end() {
  if (!open_) return;
  open_ = false;
  report({task_, stage_, index_, count_, StageEvent::kFinish, 1.0});
}

std::string encodeStageEvent(const StageEvent& e) {
  std::ostringstream line;
  line << e.task << '\t' << e.stage << '\t' << e.index << '\t' << e.count << '\t'
       << static_cast<int>(e.kind) << '\t' << e.fraction << '\n';
  return line.str();
}

bool decodeStageEvent(const std::string& line, StageEvent& e) {
  std::istringstream in(line);
  int kind = 0;
  if (!std::getline(in, e.task, '\t') || !std::getline(in, e.stage, '\t')) return false;
  if (!(in >> e.index >> e.count >> kind >> e.fraction)) return false;
  if (kind < StageEvent::kStart || kind > StageEvent::kFinish) return false;
  e.kind = static_cast<StageEvent::Kind>(kind);
  return true;
}

}  // namespace slamprep
