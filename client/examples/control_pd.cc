// Your controller in the loop, from C++ (issue 45): a PD controller at 1 kHz holding a sine on
// every joint of the IRB 1600 through Simulation.Control (proto/mbstream/v1/control.proto),
// against the server at MBSTREAM_SERVER (or the first argument; default 127.0.0.1:50051).
//   control_pd [ADDRESS [PERIOD_S [DURATION_S]]]     defaults: 1e-3 s (1 kHz), 1 s
// (bench/control_delay.py runs it across a delayed link, period against rate).
// At each control instant the server sends the state and waits for this program's command
// for the period after it. Prints the run's final state and the last tracking error; exits 1
// when the run did not finish.
#include <grpcpp/grpcpp.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "mbstream/v1/simulation_service.grpc.pb.h"

int main(int argc, char** argv) {
  const char* env = std::getenv("MBSTREAM_SERVER");
  const std::string address = argc > 1 ? argv[1] : env != nullptr ? env : "127.0.0.1:50051";
  auto stub = mbstream::v1::Simulation::NewStub(
      grpc::CreateChannel(address, grpc::InsecureChannelCredentials()));

  const double kH = argc > 2 ? std::atof(argv[2]) : 1e-3;       // s: 1 kHz by default
  const double duration = argc > 3 ? std::atof(argv[3]) : 1.0;  // s of simulated time
  if (!(kH > 0.0) || !(duration > 0.0)) {
    std::fprintf(stderr, "usage: control_pd [ADDRESS [PERIOD_S [DURATION_S]]]\n");
    return 2;
  }
  const auto wall0 = std::chrono::steady_clock::now();
  const double kp[6] = {400, 400, 400, 400, 400, 40};  // N*m/rad
  const double kd[6] = {40, 40, 40, 40, 40, 2};        // N*m*s/rad
  mbstream::v1::ControlRequest request;
  mbstream::v1::ControlStart& start = *request.mutable_start();
  start.set_model("irb1600");
  mbstream::v1::RunSpec& spec = *start.mutable_spec();
  spec.set_duration_s(duration);
  spec.set_output_interval_s(0.01);
  spec.set_formulation("joint");
  spec.set_method("rk4");  // one RK4 step per control period
  spec.set_fixed_step_s(kH);
  for (int i = 0; i < 6; ++i) {
    mbstream::v1::Drive::External& external = *spec.add_drives()->mutable_external();
    external.set_command("effort");
    external.set_period_s(kH);
  }

  grpc::ClientContext context;
  auto stream = stub->Control(&context);
  stream->Write(request);
  mbstream::v1::ControlResponse response;
  double error = 0.0;
  while (stream->Read(&response)) {
    if (response.has_started()) {
      std::printf("controlling run %s\n", response.started().run().id().c_str());
    } else if (response.has_state()) {
      const mbstream::v1::ControlState& state = response.state();
      const double q_ref = 0.5 * std::sin(M_PI * state.t_s());
      const double qd_ref = 0.5 * M_PI * std::cos(M_PI * state.t_s());
      error = std::abs(q_ref - state.q(0));
      if (state.final()) continue;  // the run's end: no command
      mbstream::v1::ControlRequest command;
      command.mutable_command()->set_step(state.step());
      for (int i = 0; i < 6; ++i) {
        command.mutable_command()->add_values(kp[i] * (q_ref - state.q(i)) +
                                              kd[i] * (qd_ref - state.qd(i)));
      }
      stream->Write(command);
    } else if (response.has_ended()) {
      const mbstream::v1::RunInfo& info = response.ended();
      std::printf("run %s %s%s%s; joint1's tracking error at the end %.3g rad\n", info.id().c_str(),
                  mbstream::v1::RunState_Name(info.state()).c_str(),
                  info.message().empty() ? "" : ": ", info.message().c_str(), error);
      stream->WritesDone();
    }
  }
  const grpc::Status status = stream->Finish();
  if (!status.ok()) {
    std::fprintf(stderr, "Control: %s\n", status.error_message().c_str());
    return 1;
  }
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  std::printf("period %g s: %g s simulated in %.3f s of wall time, %.2f x real time\n", kH,
              duration, wall, duration / wall);
  return response.ended().state() == mbstream::v1::FINISHED ? 0 : 1;
}
