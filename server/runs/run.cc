#include "server/runs/run.h"

#include <algorithm>

#include "shared/common/check.h"

namespace mbstream {

Run::Run(const v1::RunInfo& info, const RunConfig& config,
         std::shared_ptr<const CompiledModel> model, const RunClock& clock,
         ProbeRecorder::Options probe_options)
    : id_(info.id()),
      model_(std::move(model)),
      config_(config),
      realtime_(info.spec().realtime()),
      info_(info),
      spool_(info.id(), info.expected_frames()),
      probes_("run " + info.id(), clock, probe_options) {
  MBSTREAM_CHECK(model_ != nullptr);
  const auto external = std::count_if(config_.drives.begin(), config_.drives.end(), [](auto& d) {
    return d.kind == DriveConfig::Kind::kExternal;
  });
  if (external > 0) {
    const v1::RunSpec& spec = info.spec();
    control_ = std::make_shared<ControlChannel>(
        static_cast<int>(external),
        std::chrono::duration<double>(spec.has_control_timeout_s() ? spec.control_timeout_s()
                                                                   : kDefaultControlTimeoutS),
        spec.hold_last_command(), &cancel);
  }
}

v1::RunInfo Run::Info() const {
  std::lock_guard<std::mutex> lock(mutex_);
  v1::RunInfo info = info_;
  info.set_subscribers(static_cast<int>(subscribers_.size()));
  info.set_probe_reports(probes_.accepted());
  return info;
}

void Run::Attach(const std::shared_ptr<Subscription>& subscriber, bool send_started) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (std::find(subscribers_.begin(), subscribers_.end(), subscriber) != subscribers_.end()) {
    return;
  }
  if (send_started) {  // a viewer (Subscribe): it will answer with probe reports
    subscriber->Push({StreamEvent::Kind::kRunStarted, id_, nullptr});
    ++viewers_;
  }
  if (ended_) {
    subscriber->Push({StreamEvent::Kind::kRunEnded, id_, nullptr});
    return;
  }
  if (published_ > 0) {
    subscriber->Push(
        {StreamEvent::Kind::kFrame, id_, std::make_shared<const v1::Frame>(latest_frame_)});
  }
  subscribers_.push_back(subscriber);
}

void Run::Publish(v1::Frame* frame) {
  std::lock_guard<std::mutex> lock(mutex_);
  latest_frame_.Swap(frame);  // both on the heap: the fields' storage is exchanged, not copied
  info_.set_frames(++published_);
  info_.set_t_s(latest_frame_.t_s());
  // Detach subscribers whose streams have gone, then fan out.
  subscribers_.erase(std::remove_if(subscribers_.begin(), subscribers_.end(),
                                    [](const auto& s) { return s->cancelled(); }),
                     subscribers_.end());
  if (subscribers_.empty()) return;
  const auto shared = std::make_shared<const v1::Frame>(latest_frame_);
  for (const auto& subscriber : subscribers_) {
    subscriber->Push({StreamEvent::Kind::kFrame, id_, shared});
  }
}

void Run::End() {
  std::lock_guard<std::mutex> lock(mutex_);
  ended_ = true;
  for (const auto& subscriber : subscribers_) {
    subscriber->Push({StreamEvent::Kind::kRunEnded, id_, nullptr});
  }
  subscribers_.clear();
}

std::shared_ptr<const v1::Frame> Run::latest_frame() const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (published_ == 0) return nullptr;
  return std::make_shared<const v1::Frame>(latest_frame_);
}

v1::RunState Run::state() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return info_.state();
}

bool Run::ended() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return ended_;
}

int Run::subscriber_count() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return static_cast<int>(subscribers_.size());
}

void Run::WaitForProbes(int64_t seq, std::chrono::duration<double> timeout) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (viewers_ == 0 && probes_.accepted() == 0) return;
  }
  probes_.WaitFor(seq, timeout);
}

}  // namespace mbstream
