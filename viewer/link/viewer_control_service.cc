#include "viewer/link/viewer_control_service.h"

#include <filesystem>
#include <random>

#include "viewer/link/run_scene.h"
#include "viewer/scene/scene_error.h"

namespace mbstream::viewer {

grpc::Status ViewerControlService::GetStatus(grpc::ServerContext*, const v1::ViewerStatusRequest*,
                                             v1::ViewerStatus* response) {
  *response = status_->Get();
  return grpc::Status::OK;
}

grpc::Status ViewerControlService::Snapshot(grpc::ServerContext*, const v1::SnapshotRequest*,
                                            v1::SnapshotResponse* response) {
  bool shown = false;
  std::string error, no_window;
  slot_->RunOnRenderThread([&](Scene* scene) {
    if (!scene) return;
    try {
      response->set_png(scene->SnapshotPngBytes());
      const int* size = scene->render_window()->GetSize();
      response->set_width(size[0]);
      response->set_height(size[1]);
      shown = true;
    } catch (const SceneError& e) {  // no window: the X display is lost
      no_window = e.what();
    } catch (const std::exception& e) {
      error = e.what();
    }
  });
  if (!no_window.empty()) return grpc::Status(grpc::StatusCode::FAILED_PRECONDITION, no_window);
  if (!error.empty()) return grpc::Status(grpc::StatusCode::INTERNAL, error);
  if (!shown) {
    return grpc::Status(grpc::StatusCode::FAILED_PRECONDITION,
                        "no scene is shown yet: wait for a run or call LoadScene");
  }
  return grpc::Status::OK;
}

grpc::Status ViewerControlService::LoadScene(grpc::ServerContext*,
                                             const v1::LoadSceneRequest* request,
                                             v1::ViewerStatus* response) {
  v1::ModelBundle bundle;
  bundle.set_scene_script(request->scene_script());
  bundle.set_urdf(request->urdf());
  *bundle.mutable_assets() = request->assets();
  if (bundle.scene_script().empty() && bundle.urdf().empty()) {
    return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, "LoadScene: give scene_script or urdf");
  }
  const v1::ViewerStatus now = status_->Get();
  v1::ModelInfo model;
  model.set_id("loaded-" + std::to_string(std::random_device()()));
  model.set_name("loaded");
  RunSceneSource source;
  source.asset_root = std::filesystem::temp_directory_path() / "mbstream-viewer-assets";
  try {
    SceneDescription scene = SceneFromBundle(model, bundle, source);
    if (now.dofs() > 0) {  // a run is shown: the scene must fit its model
      model.set_dofs(now.dofs());
      try {
        CheckJointCount(scene, model);
      } catch (const std::runtime_error& e) {
        return grpc::Status(grpc::StatusCode::FAILED_PRECONDITION, e.what());
      }
    }
    const std::string error = slot_->Replace(std::move(scene));
    if (!error.empty()) return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, error);
  } catch (const std::exception& e) {
    return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, e.what());
  }
  *response = status_->Get();
  return grpc::Status::OK;
}

grpc::Status ViewerControlService::Control(grpc::ServerContext*, const v1::ReplayControl* request,
                                           v1::ViewerStatus* response) {
  if (!send_control_ || status_->Get().mode() != "replay") {
    return grpc::Status(grpc::StatusCode::FAILED_PRECONDITION,
                        "this viewer shows no replay: start it with --run of an ended run");
  }
  if (!send_control_(*request)) {
    return grpc::Status(grpc::StatusCode::UNAVAILABLE,
                        "the viewer's stream to the server is closed; try again when it shows "
                        "the replay");
  }
  *response = status_->Get();
  return grpc::Status::OK;
}

}  // namespace mbstream::viewer
