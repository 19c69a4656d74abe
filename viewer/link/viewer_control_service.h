// The viewer's control service (proto/mbstream/v1/viewer_service.proto) on --listen.
#pragma once

#include "mbstream/v1/viewer_service.grpc.pb.h"
#include "viewer/link/link_status.h"
#include "viewer/link/scene_slot.h"

namespace mbstream::viewer {

class ViewerControlService final : public v1::Viewer::Service {
 public:
  // Neither is owned.
  ViewerControlService(SceneSlot* slot, LinkStatus* status) : slot_(slot), status_(status) {}

  grpc::Status GetStatus(grpc::ServerContext*, const v1::ViewerStatusRequest*,
                         v1::ViewerStatus* response) override;
  grpc::Status Snapshot(grpc::ServerContext*, const v1::SnapshotRequest*,
                        v1::SnapshotResponse* response) override;
  grpc::Status LoadScene(grpc::ServerContext*, const v1::LoadSceneRequest* request,
                         v1::ViewerStatus* response) override;

 private:
  SceneSlot* slot_;
  LinkStatus* status_;
};

}  // namespace mbstream::viewer
