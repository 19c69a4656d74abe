// One frame as the browser page gets it: the run's state (as the VTK window's HUD shows it),
// the probes the viewer computed (the readout), and every frame's pose in World (the page
// poses its meshes and computes its own probe markers from them), with the ghost's frames
// under --compare. Numbered, so that a page counts the frames it did not get.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "mbstream/v1/viewer_service.pb.h"
#include "viewer/scene/contact_layer.h"
#include "viewer/scene/probe_report.h"

namespace mbstream::viewer {

struct FrameMessage {
  std::uint64_t scene_version = 0;  // ExportSceneJson's version of the scene posed
  std::uint64_t number = 0;         // increases by one per message sent to the pages
  double posed_unix_ms = 0;         // when the viewer posed it (wall clock, for latency)
  std::span<const Eigen::Isometry3d> frames;
  std::span<const Eigen::Isometry3d> ghost_frames;  // empty without --compare
  std::span<const ProbeReport> probes;
  // --contacts: the frame's contacts (point, force on the pair's first body, World) and the
  // arrows' scale in m/N (0: the largest force so far is ContactLayer::kAutoLength long).
  bool contacts = false;
  std::span<const ContactMark> contact_marks;
  double contact_scale = 0.0;
};

// JSON text; frame matrices as the 12 numbers of their top 3 rows, row by row (9 digits);
// with contacts, "c": [[px, py, pz, fx, fy, fz], ...] (m, N) and "contact_scale".
std::string FrameMessageJson(const FrameMessage& frame, const v1::ViewerStatus& status);

}  // namespace mbstream::viewer
