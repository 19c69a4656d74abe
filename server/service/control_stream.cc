// Simulation.Control (proto/mbstream/v1/control.proto): a controller in the loop of a run,
// lockstep; each stream a reactor (control_call.h).
#include "server/service/control_call.h"
#include "server/service/simulation_service.h"

namespace mbstream {

grpc::ServerBidiReactor<v1::ControlRequest, v1::ControlResponse>* SimulationService::Control(
    grpc::CallbackServerContext* context) {
  return ControlCall::Open(
      context, StreamDeps{runs_, models_, authorizer_, peers_, &stopping_, &pump_, &live_});
}

}  // namespace mbstream
