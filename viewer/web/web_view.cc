#include "viewer/web/web_view.h"

#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <memory>
#include <utility>

#include "viewer/web/frame_message.h"
#include "viewer/web/scene_export.h"

namespace mbstream::viewer {

namespace {

double UnixMs() {
  return std::chrono::duration<double, std::milli>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// What changes on the pages without a new pose.
std::string StateKey(const v1::ViewerStatus& s) {
  return s.run_id() + "|" + s.state() + "|" + s.mode() + "|" + (s.paused() ? "p" : "r") + "|" +
         std::to_string(s.speed()) + "|" + std::to_string(s.run_frames());
}

}  // namespace

WebView::WebView(WebOptions options, const LinkStatus* status, SendControl send_control)
    : status_(status),
      send_control_(std::move(send_control)),
      server_(std::move(options), [this](const std::string& json) {
        v1::ReplayControl control;
        if (!ParseControl(json, &control)) return false;
        if (!send_control_) {
          spdlog::info("web: a page sent a replay control, but this is not a replay (--run ID)");
          return false;
        }
        return send_control_(control);
      }) {}

bool WebView::ParseControl(const std::string& json, v1::ReplayControl* control) {
  const nlohmann::json message = nlohmann::json::parse(json, nullptr, /*allow_exceptions=*/false);
  if (!message.is_object() || message.size() != 1) return false;
  const auto& [key, value] = *message.items().begin();
  if (key == "pause" && value.is_boolean()) {
    control->set_pause(true);
  } else if (key == "resume" && value.is_boolean()) {
    control->set_resume(true);
  } else if (key == "seek_seq" && value.is_number_integer() && value.get<std::int64_t>() >= 0) {
    control->set_seek_seq(value.get<std::int64_t>());
  } else if (key == "step" && value.is_number_integer() && value.get<std::int64_t>() != 0 &&
             std::abs(value.get<std::int64_t>()) < 1'000'000) {
    control->set_step(static_cast<std::int32_t>(value.get<std::int64_t>()));
  } else if (key == "speed" && value.is_number() && value.get<double>() >= 0.0 &&
             value.get<double>() <= 1000.0) {
    control->set_speed(value.get<double>());
  } else {
    return false;
  }
  return true;
}

void WebView::OnScene(Scene* scene) {
  std::lock_guard<std::mutex> lock(mutex_);
  scene_ = scene;
  if (!scene) return;
  ++version_;
  const auto begin = std::chrono::steady_clock::now();
  auto json = std::make_shared<std::string>(ExportSceneJson(*scene, version_));
  spdlog::info(
      "web: scene '{}' exported for the pages: {} parts, {} bytes in {:.1f} ms",
      scene->description().title, scene->part_actors().size(), json->size(),
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - begin).count());
  // Sent from the web thread, so that it comes after the frames of the scene before it.
  server_.Post([this, json] { server_.SetScene(std::move(*json)); });
  scene->Frames(&frames_);
  if (scene->ghost()) {
    ghost_frames_ = scene->ghost()->Frames();
  } else {
    ghost_frames_.clear();
  }
  scene->ProbeReports(&probes_);
  posed_unix_ms_ = UnixMs();
  status_->GetSeq(&seq_, &t_s_);
  RequestLocked(true);
}

void WebView::OnPosed(Scene& scene, std::span<const ProbeReport> probes) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (&scene != scene_) return;  // not exported yet: OnScene sends its pose
  scene.Frames(&frames_);
  if (scene.ghost()) ghost_frames_ = scene.ghost()->Frames();
  contacts_on_ = scene.contacts() != nullptr;
  if (contacts_on_) {
    scene.contacts()->Marks(&contacts_);
    contact_scale_ = scene.contacts()->scale();
  }
  probes_.assign(probes.begin(), probes.end());
  posed_unix_ms_ = UnixMs();
  status_->GetSeq(&seq_, &t_s_);  // the batch's (the link set it before posing us)
  RequestLocked(true);
}

void WebView::OnTick() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (scene_) RequestLocked(false);
}

void WebView::RequestLocked(bool posed) {
  posed_ = posed_ || posed;
  if (requested_) return;
  requested_ = true;
  server_.Post([this] { Publish(); });
}

void WebView::Publish() {
  status_->Get(&status_copy_);
  const std::string state = StateKey(status_copy_);
  FrameMessage frame;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    requested_ = false;
    if (!scene_) return;
    const bool posed = std::exchange(posed_, false);
    if (!posed && state == published_state_) return;
    sent_frames_.assign(frames_.begin(), frames_.end());
    sent_ghost_frames_.assign(ghost_frames_.begin(), ghost_frames_.end());
    sent_probes_.assign(probes_.begin(), probes_.end());
    sent_contacts_.assign(contacts_.begin(), contacts_.end());
    frame.contacts = contacts_on_;
    frame.contact_scale = contact_scale_;
    frame.scene_version = version_;
    frame.posed_unix_ms = posed ? posed_unix_ms_ : UnixMs();
    status_copy_.set_seq(seq_);  // the pose's, not a newer batch's
    status_copy_.set_t_s(t_s_);
  }
  published_state_ = state;
  frame.number = ++number_;
  frame.frames = sent_frames_;
  frame.ghost_frames = sent_ghost_frames_;
  frame.probes = sent_probes_;
  frame.contact_marks = sent_contacts_;
  server_.PublishFrame(FrameMessageJson(frame, status_copy_));
}

}  // namespace mbstream::viewer
