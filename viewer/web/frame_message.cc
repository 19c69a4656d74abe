#include "viewer/web/frame_message.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <iterator>

namespace mbstream::viewer {

namespace {

void AppendMatrices(std::string* out, std::span<const Eigen::Isometry3d> frames) {
  auto it = std::back_inserter(*out);
  *out += '[';
  bool first = true;
  for (const Eigen::Isometry3d& frame : frames) {
    const Eigen::Matrix4d& m = frame.matrix();
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 4; ++c) {
        if (!first) *out += ',';
        first = false;
        fmt::format_to(it, "{:.9g}", m(r, c) == 0.0 ? 0.0 : m(r, c));
      }
    }
  }
  *out += ']';
}

// A JSON string literal (the run id and the names come from the server and the model).
std::string Quoted(const std::string& text) { return nlohmann::json(text).dump(); }

}  // namespace

std::string FrameMessageJson(const FrameMessage& frame, const v1::ViewerStatus& s) {
  std::string out;
  out.reserve(256 + 120 * frame.frames.size() + 100 * frame.probes.size());
  auto it = std::back_inserter(out);
  fmt::format_to(it,
                 "{{\"type\":\"frame\",\"scene\":{},\"n\":{},\"posed_ms\":{:.3f},\"run\":{},"
                 "\"state\":{},\"mode\":{},\"seq\":{},\"t\":{:.9g},\"frames\":{},\"missed\":{},"
                 "\"render_fps\":{:.3g},\"paused\":{},\"speed\":{:.6g},\"run_frames\":{},"
                 "\"compare\":{},\"tcp_distance\":{:.9g},\"tcp_distance_max\":{:.9g},"
                 "\"tcp_distance_max_t\":{:.9g},\"m\":",
                 frame.scene_version, frame.number, frame.posed_unix_ms, Quoted(s.run_id()),
                 Quoted(s.state()), Quoted(s.mode()), s.seq(), s.t_s(), s.frames(),
                 s.missed_frames(), s.render_fps(), s.paused() ? "true" : "false", s.speed(),
                 s.run_frames(), Quoted(s.compare_run_id()), s.tcp_distance_m(),
                 s.tcp_distance_max_m(), s.tcp_distance_max_t_s());
  AppendMatrices(&out, frame.frames);
  out += ",\"g\":";
  AppendMatrices(&out, frame.ghost_frames);
  out += ",\"probes\":[";
  for (std::size_t i = 0; i < frame.probes.size(); ++i) {
    const ProbeReport& p = frame.probes[i];
    fmt::format_to(it, "{}{{\"name\":{},\"frame\":{},\"x\":{:.9g},\"y\":{:.9g},\"z\":{:.9g}}}",
                   i ? "," : "", Quoted(p.name), Quoted(p.frame), p.position_m.x(),
                   p.position_m.y(), p.position_m.z());
  }
  out += ']';
  if (frame.contacts) {
    fmt::format_to(it, ",\"contact_scale\":{:.9g},\"c\":[", frame.contact_scale);
    for (std::size_t i = 0; i < frame.contact_marks.size(); ++i) {
      const ContactMark& c = frame.contact_marks[i];
      fmt::format_to(it, "{}[{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g}]", i ? "," : "", c.point.x(),
                     c.point.y(), c.point.z(), c.force.x(), c.force.y(), c.force.z());
    }
    out += ']';
  }
  out += '}';
  return out;
}

}  // namespace mbstream::viewer
