// SubmitModel, ListModels, GetModel through a real server on port 0.
#include <gmock/gmock.h>
#include <grpcpp/impl/client_unary_call.h>
#include <grpcpp/support/byte_buffer.h>

#include "tests/server/service/server_fixture.h"

namespace mbstream::testing {
namespace {

using ::testing::AllOf;
using ::testing::Contains;
using ::testing::HasSubstr;
using ::testing::Not;

// Calls grpc.health.v1.Health/Check for the whole server (empty request) as a blocking call
// on this thread (the generated stubs' own path), and returns the serialized response. Not
// the callback API: its completion runs on a thread of Debian's uninstrumented libgrpc++,
// where ThreadSanitizer sees only half of gRPC's synchronisation (docs/reliability.md).
std::string HealthCheck(const std::string& address) {
  const std::shared_ptr<grpc::Channel> channel =
      grpc::CreateChannel(address, grpc::InsecureChannelCredentials());
  const grpc::internal::RpcMethod method("/grpc.health.v1.Health/Check",
                                         grpc::internal::RpcMethod::NORMAL_RPC);
  grpc::ClientContext context;
  grpc::Slice empty;
  const grpc::ByteBuffer request(&empty, 1);
  grpc::ByteBuffer response;
  const grpc::Status status = grpc::internal::BlockingUnaryCall<grpc::ByteBuffer, grpc::ByteBuffer>(
      channel.get(), method, &context, request, &response);
  EXPECT_TRUE(status.ok()) << status.error_message();
  std::vector<grpc::Slice> slices;
  EXPECT_TRUE(response.Dump(&slices).ok());
  std::string bytes;
  for (const grpc::Slice& slice : slices) {
    bytes.append(reinterpret_cast<const char*>(slice.begin()), slice.size());
  }
  return bytes;
}

class ModelsServiceTest : public ServerTest {
 protected:
  void SetUp() override { StartServer(); }
};

TEST_F(ModelsServiceTest, SameBundleTwiceGivesTheSameId) {
  v1::ModelBundle bundle = IrbBundle();
  const v1::ModelInfo first = SubmitOk(bundle);
  bundle.set_name("another name");
  const v1::ModelInfo second = SubmitOk(bundle);
  EXPECT_EQ(first.id(), second.id());
  EXPECT_EQ(first.id().substr(0, 2), "m-");
  EXPECT_EQ(first.dofs(), 6);
  EXPECT_EQ(first.joints_size(), 6);
  EXPECT_EQ(first.tcp_frame(), "tcp");
  EXPECT_GT(first.total_mass_kg(), 0.0);
  ASSERT_EQ(first.formulations_size(), 2);
  EXPECT_EQ(first.formulations(1).formulation(), "joint");
  EXPECT_EQ(first.formulations(1).equations(), 12);
  EXPECT_EQ(first.formulations(1).jacobian_nnz(), 78);  // what a joint/bdf run reports
  // A different URDF text is a different model.
  bundle.set_urdf(bundle.urdf() + "\n<!-- changed -->\n");
  EXPECT_NE(SubmitOk(bundle).id(), first.id());
}

TEST_F(ModelsServiceTest, BadUrdfIsInvalidArgumentWithTheImportersMessage) {
  v1::ModelBundle bundle;
  bundle.set_urdf_file_name("broken.urdf");
  bundle.set_urdf(
      "<robot name='r'>\n  <link name='a'/>\n  <joint name='j' type='revolute'>\n"
      "    <parent link='a'/>\n    <child link='missing'/>\n  </joint>\n</robot>\n");
  v1::ModelInfo info;
  const grpc::Status status = Submit(bundle, &info);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(status.error_message(), HasSubstr("broken.urdf:"));
  EXPECT_THAT(status.error_message(), HasSubstr("missing"));
}

TEST_F(ModelsServiceTest, EmptyUrdfAndDuplicateAssetsAreRejected) {
  v1::ModelInfo info;
  EXPECT_EQ(Submit(v1::ModelBundle(), &info).error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  v1::ModelBundle bundle = IrbBundle();
  for (int i = 0; i < 2; ++i) {
    v1::Asset* asset = bundle.add_assets();
    asset->set_name("part.stl");
    asset->set_data("solid x\nendsolid x\n");
  }
  const grpc::Status status = Submit(bundle, &info);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(status.error_message(), HasSubstr("'part.stl' is given twice"));
}

TEST_F(ModelsServiceTest, BuiltinModelsAreListedAndFoundByName) {
  grpc::ClientContext context;
  v1::ListModelsResponse list;
  ASSERT_TRUE(stub().ListModels(&context, v1::ListModelsRequest(), &list).ok());
  bool found = false;
  for (const v1::ModelInfo& m : list.models()) found |= m.name() == "irb1600" && m.builtin();
  EXPECT_TRUE(found);

  grpc::ClientContext get_context;
  v1::GetModelRequest request;
  request.set_model("irb1600");
  request.set_include_bundle(true);
  v1::GetModelResponse model;
  ASSERT_TRUE(stub().GetModel(&get_context, request, &model).ok());
  EXPECT_EQ(model.info().name(), "irb1600");
  EXPECT_THAT(model.bundle().urdf(), HasSubstr("<robot"));
}

TEST_F(ModelsServiceTest, TakingABuiltinsNameIsWarned) {
  v1::ModelBundle mine = IrbBundle();
  mine.set_name("irb1600");
  mine.set_urdf(mine.urdf() + "<!-- my own copy -->\n");  // other content: another model
  v1::ModelInfo info;
  ASSERT_TRUE(Submit(mine, &info).ok());
  ASSERT_FALSE(info.builtin());
  EXPECT_THAT(info.warnings(),
              Contains(AllOf(HasSubstr("the name 'irb1600' was the built-in "
                                       "model"),
                             HasSubstr("stays reachable by its id"), HasSubstr("--name"))));
  // A name of its own is not warned.
  mine.set_name("my-irb");
  mine.set_urdf(mine.urdf() + "<!-- renamed -->\n");
  ASSERT_TRUE(Submit(mine, &info).ok());
  EXPECT_THAT(info.warnings(), Not(Contains(HasSubstr("built-in"))));
}

TEST_F(ModelsServiceTest, UnknownModelIsNotFoundAndNamesTheKnownOnes) {
  grpc::ClientContext context;
  v1::GetModelRequest request;
  request.set_model("nosuch");
  v1::GetModelResponse model;
  const grpc::Status status = stub().GetModel(&context, request, &model);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::NOT_FOUND);
  EXPECT_THAT(status.error_message(), HasSubstr("irb1600"));
}

TEST_F(ModelsServiceTest, OversizedModelIsResourceExhaustedAndTheServerStaysHealthy) {
  ServerLimits limits;
  limits.max_model_bytes = 1000;
  StartServer(limits);
  v1::ModelInfo info;
  const grpc::Status status = Submit(IrbBundle(), &info);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_THAT(status.error_message(), HasSubstr("--max-model-mb"));
  // Still serving.
  EXPECT_EQ(HealthCheck(host().address()), "\x08\x01");  // HealthCheckResponse{SERVING}
  grpc::ClientContext list_context;
  v1::ListModelsResponse list;
  EXPECT_TRUE(stub().ListModels(&list_context, v1::ListModelsRequest(), &list).ok());
}

TEST_F(ModelsServiceTest, BundleLimitsPerAssetAndAssetCountAreResourceExhausted) {
  ServerLimits limits;
  limits.max_asset_bytes = 100;
  limits.max_assets = 2;
  StartServer(limits);
  v1::ModelBundle big = IrbBundle();
  v1::Asset* asset = big.add_assets();
  asset->set_name("meshes/base.stl");
  asset->set_data(std::string(101, 'x'));
  v1::ModelInfo info;
  grpc::Status status = Submit(big, &info);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_THAT(status.error_message(), AllOf(HasSubstr("asset 'meshes/base.stl' has 101 bytes"),
                                            HasSubstr("--max-asset-mb")));

  v1::ModelBundle many = IrbBundle();
  for (const char* name : {"a.stl", "b.stl", "c.stl"}) {
    v1::Asset* small = many.add_assets();
    small->set_name(name);
    small->set_data("solid\nendsolid\n");
  }
  status = Submit(many, &info);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_THAT(status.error_message(), AllOf(HasSubstr("3 assets"), HasSubstr("--max-assets")));
  many.mutable_assets()->RemoveLast();  // two: within the limits (unreferenced, dropped)
  EXPECT_TRUE(Submit(many, &info).ok());
}

TEST_F(ModelsServiceTest, DefaultLimitsHoldAPr2SizedBundleWithItsCollisionMeshes) {
  // A PR2: about 46 MB of visual meshes in ~50 files, as much again for collisions.
  const ServerLimits defaults;
  EXPECT_GE(defaults.max_model_bytes, int64_t{2 * 46'000'000});
  EXPECT_GE(defaults.max_assets, 200);
  v1::ModelBundle pr2_sized = IrbBundle();
  for (int i = 0; i < 100; ++i) {
    v1::Asset* mesh = pr2_sized.add_assets();
    mesh->set_name("meshes/part" + std::to_string(i) + ".stl");
    mesh->set_data(std::string(920'000, 'x'));  // 92 MB in all
  }
  pr2_sized.mutable_assets(0)->set_data(std::string(8'000'000, 'x'));  // one large mesh
  v1::ModelInfo info;
  const grpc::Status status = Submit(pr2_sized, &info);
  EXPECT_TRUE(status.ok()) << status.error_message();
}

TEST_F(ModelsServiceTest, HealthServiceSaysServing) {
  EXPECT_EQ(HealthCheck(host().address()), "\x08\x01");
}

TEST_F(ModelsServiceTest, TooManyLinksIsResourceExhausted) {
  ServerLimits limits;
  limits.max_links = 3;
  StartServer(limits);
  v1::ModelInfo info;
  const grpc::Status status = Submit(IrbBundle(), &info);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_THAT(status.error_message(), HasSubstr("--max-links"));
}

}  // namespace
}  // namespace mbstream::testing
