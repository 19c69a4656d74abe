// The gate: kRpcRoles names every RPC of the service, and each RPC refuses a token without
// its role (PERMISSION_DENIED) and lets one with it through, RPC by RPC.
#include "server/service/rpc_roles.h"

#include <gmock/gmock.h>
#include <google/protobuf/descriptor.h>

#include <fstream>
#include <functional>
#include <map>
#include <set>

#include "shared/common/check.h"
#include "tests/server/service/server_fixture.h"

namespace mbstream::testing {
namespace {

TEST(RpcRolesTest, EveryMethodOfTheServiceHasARole) {
  const google::protobuf::ServiceDescriptor* service =
      google::protobuf::DescriptorPool::generated_pool()->FindServiceByName(
          v1::Simulation::service_full_name());
  ASSERT_NE(service, nullptr);
  std::set<std::string> methods, listed;
  for (int i = 0; i < service->method_count(); ++i) methods.insert(service->method(i)->name());
  for (const RpcRole& entry : kRpcRoles) listed.insert(std::string(entry.method));
  EXPECT_EQ(methods, listed);
  EXPECT_THROW(RoleOf("NoSuchMethod"), InternalError);
}

// A token per role: "<role>-token-0123456789".
class RpcGateTest : public ServerTest {
 protected:
  void SetUp() override {
    const std::string file = (data_.path() / "tokens").string();
    std::ofstream(file) << "submit-token-0123456789 submit\nrun-token-0123456789 run\n"
                        << "view-token-0123456789 view\n";
    StartServer(ServerLimits(), file);
  }

  // Calls `method` with `token` and returns the status (streams: read to the end).
  grpc::Status Call(const std::string& method, const std::string& token) {
    grpc::ClientContext context;
    context.AddMetadata("authorization", "Bearer " + token);
    auto finish = [](auto reader, auto event) {
      while (reader->Read(&event)) {
      }
      return reader->Finish();
    };
    const std::map<std::string, std::function<grpc::Status()>> calls = {
        {"SubmitModel",
         [&] {
           v1::SubmitModelRequest request;
           *request.mutable_bundle() = IrbBundle();
           v1::ModelInfo info;
           return stub().SubmitModel(&context, request, &info);
         }},
        {"ListModels",
         [&] {
           v1::ListModelsResponse response;
           return stub().ListModels(&context, v1::ListModelsRequest(), &response);
         }},
        {"GetModel",
         [&] {
           v1::GetModelRequest request;
           request.set_model("irb1600");
           v1::GetModelResponse response;
           return stub().GetModel(&context, request, &response);
         }},
        {"StartRun",
         [&] {
           v1::StartRunRequest request;
           request.set_model("single_pendulum");
           v1::RunInfo info;
           return stub().StartRun(&context, request, &info);
         }},
        {"StartRuns",
         [&] {
           v1::StartRunsRequest request;
           request.set_model("single_pendulum");
           request.add_specs();
           v1::StartRunsResponse response;
           return stub().StartRuns(&context, request, &response);
         }},
        {"StartSweep",
         [&] {
           v1::StartSweepRequest request;
           request.set_model("single_pendulum");
           v1::SweepAxis& axis = *request.add_grid();
           axis.set_path("duration_s");
           axis.add_values("0.1");
           v1::StartSweepResponse response;
           return stub().StartSweep(&context, request, &response);
         }},
        {"CancelRun",
         [&] {
           v1::CancelRunRequest request;
           request.set_run_id("r-nosuch");
           v1::RunInfo info;
           return stub().CancelRun(&context, request, &info);
         }},
        {"GetRun",
         [&] {
           v1::GetRunRequest request;
           request.set_run_id("r-nosuch");
           v1::RunInfo info;
           return stub().GetRun(&context, request, &info);
         }},
        {"ListRuns",
         [&] {
           v1::ListRunsResponse response;
           return stub().ListRuns(&context, v1::ListRunsRequest(), &response);
         }},
        {"GetResult",
         [&] {
           v1::GetResultRequest request;
           request.set_run_id("r-nosuch");
           return finish(stub().GetResult(&context, request), v1::ResultChunk());
         }},
        {"GetResults",
         [&] {
           v1::GetResultsRequest request;
           request.add_run_ids("r-nosuch");
           return finish(stub().GetResults(&context, request), v1::ResultChunk());
         }},
        {"WatchRun",
         [&] {
           v1::WatchRunRequest request;
           request.set_run_id("r-nosuch");
           return finish(stub().WatchRun(&context, request), v1::WatchEvent());
         }},
        {"Subscribe",
         [&] {
           auto stream = stub().Subscribe(&context);
           v1::SubscribeRequest start;
           start.mutable_start()->set_run_id("r-nosuch");
           stream->Write(start);
           stream->WritesDone();
           return finish(std::move(stream), v1::SubscribeEvent());
         }},
        {"ListProbeSets",
         [&] {
           v1::ListProbeSetsRequest request;
           request.set_run_id("r-nosuch");
           v1::ListProbeSetsResponse response;
           return stub().ListProbeSets(&context, request, &response);
         }},
        {"ReplayRun",
         [&] {
           v1::ReplayRunRequest request;
           request.set_run_id("r-nosuch");
           v1::RunInfo info;
           return stub().ReplayRun(&context, request, &info);
         }},
        {"DeleteRuns",
         [&] {
           v1::DeleteRunsRequest request;
           request.add_run_ids("r-nosuch");
           v1::DeleteRunsResponse response;
           return stub().DeleteRuns(&context, request, &response);
         }},
        {"DeleteModel",
         [&] {
           v1::DeleteModelRequest request;
           request.set_model("m-nosuch");
           v1::DeleteModelResponse response;
           return stub().DeleteModel(&context, request, &response);
         }},
        {"SetKeep",
         [&] {
           v1::SetKeepRequest request;
           request.set_run_id("r-nosuch");
           v1::RunInfo info;
           return stub().SetKeep(&context, request, &info);
         }},
        {"RetentionPlan",
         [&] {
           v1::RetentionPlanResponse response;
           return stub().RetentionPlan(&context, v1::RetentionPlanRequest(), &response);
         }},
        {"ExportMcap",
         [&] {
           v1::ExportMcapRequest request;
           request.set_run_id("r-nosuch");
           return finish(stub().ExportMcap(&context, request), v1::McapFileChunk());
         }},
        {"GetSweep",
         [&] {
           v1::GetSweepRequest request;
           request.set_sweep_id("s-nosuch");
           v1::SweepProgress progress;
           return stub().GetSweep(&context, request, &progress);
         }},
        {"CancelSweep",
         [&] {
           v1::CancelSweepRequest request;
           request.set_sweep_id("s-nosuch");
           v1::SweepProgress progress;
           return stub().CancelSweep(&context, request, &progress);
         }},
        {"Control",
         [&] {
           auto stream = stub().Control(&context);
           v1::ControlRequest start;
           start.mutable_start();
           stream->Write(start);
           stream->WritesDone();
           return finish(std::move(stream), v1::ControlResponse());
         }},
        {"GetStorage",
         [&] {
           v1::GetStorageResponse response;
           return stub().GetStorage(&context, v1::GetStorageRequest(), &response);
         }},
        {"BackupStorage",
         [&] {
           v1::BackupStorageRequest request;
           request.set_dir((data_.path() / "backup").string());
           v1::BackupStorageResponse response;
           return stub().BackupStorage(&context, request, &response);
         }},
    };
    return calls.at(method)();
  }
};

TEST_F(RpcGateTest, EachRpcNeedsItsRoleAndNoOther) {
  const std::map<Role, std::string> token_of = {{Role::kSubmit, "submit-token-0123456789"},
                                                {Role::kRun, "run-token-0123456789"},
                                                {Role::kView, "view-token-0123456789"}};
  for (const RpcRole& entry : kRpcRoles) {
    const std::string method(entry.method);
    for (const auto& [role, token] : token_of) {
      const grpc::Status status = Call(method, token);
      if (role == entry.role) {
        EXPECT_NE(status.error_code(), grpc::StatusCode::PERMISSION_DENIED)
            << method << " with its role: " << status.error_message();
        EXPECT_NE(status.error_code(), grpc::StatusCode::UNAUTHENTICATED) << method;
      } else {
        EXPECT_EQ(status.error_code(), grpc::StatusCode::PERMISSION_DENIED)
            << method << " with the role " << RoleName(role);
        EXPECT_THAT(status.error_message(), ::testing::HasSubstr(RoleName(entry.role)));
      }
    }
    EXPECT_EQ(Call(method, "unknown-token-0123456789").error_code(),
              grpc::StatusCode::UNAUTHENTICATED)
        << method;
  }
}

}  // namespace
}  // namespace mbstream::testing
