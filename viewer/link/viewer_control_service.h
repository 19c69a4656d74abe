// The viewer's control service (proto/mbstream/v1/viewer_service.proto) on --listen.
#pragma once

#include <functional>

#include "mbstream/v1/viewer_service.grpc.pb.h"
#include "viewer/link/link_status.h"
#include "viewer/link/scene_slot.h"

namespace mbstream::viewer {

class ViewerControlService final : public v1::Viewer::Service {
 public:
  using SendControl = std::function<bool(const v1::ReplayControl&)>;
  // Neither is owned. `send_control` sends a replay's time control on the link's stream.
  ViewerControlService(SceneSlot* slot, LinkStatus* status, SendControl send_control = nullptr)
      : slot_(slot), status_(status), send_control_(std::move(send_control)) {}

  grpc::Status GetStatus(grpc::ServerContext*, const v1::ViewerStatusRequest*,
                         v1::ViewerStatus* response) override;
  grpc::Status Snapshot(grpc::ServerContext*, const v1::SnapshotRequest*,
                        v1::SnapshotResponse* response) override;
  grpc::Status LoadScene(grpc::ServerContext*, const v1::LoadSceneRequest* request,
                         v1::ViewerStatus* response) override;
  grpc::Status Control(grpc::ServerContext*, const v1::ReplayControl* request,
                       v1::ViewerStatus* response) override;

 private:
  SceneSlot* slot_;
  LinkStatus* status_;
  const SendControl send_control_;
};

}  // namespace mbstream::viewer
