// Stored models: unreferenced assets dropped, count and size caps, compiled on first use.
#include <gmock/gmock.h>

#include <set>

#include "server/runs/model_registry.h"
#include "server/runs/run_manager.h"
#include "tests/server/service/server_fixture.h"

namespace mbstream::testing {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;

// One moving link drawn with a mesh, as package:// (supplied by its base name).
constexpr const char* kMeshUrdf = R"(<robot name="meshy">
  <link name="base"/>
  <joint name="j1" type="revolute">
    <parent link="base"/><child link="arm"/>
    <axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="10" velocity="1"/>
  </joint>
  <link name="arm">
    <inertial><mass value="1"/>
      <inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial>
    <visual><geometry><mesh filename="package://demo/meshes/arm.stl"/></geometry></visual>
  </link>
</robot>
)";

v1::ModelBundle MeshBundle(const std::string& mesh_bytes) {
  v1::ModelBundle bundle;
  bundle.set_urdf(kMeshUrdf);
  bundle.set_urdf_file_name("meshy.urdf");
  v1::Asset* asset = bundle.add_assets();
  asset->set_name("arm.stl");
  asset->set_data(mesh_bytes);
  return bundle;
}

void AddAsset(v1::ModelBundle& bundle, const std::string& name, const std::string& data) {
  v1::Asset* asset = bundle.add_assets();
  asset->set_name(name);
  asset->set_data(data);
}

class ModelStorageTest : public ServerTest {
 protected:
  v1::GetModelResponse GetModel(const std::string& model) {
    grpc::ClientContext context;
    v1::GetModelRequest request;
    request.set_model(model);
    request.set_include_bundle(true);
    v1::GetModelResponse response;
    const grpc::Status status = stub().GetModel(&context, request, &response);
    EXPECT_TRUE(status.ok()) << status.error_message();
    return response;
  }
  const ModelRegistry& registry() { return host().runs().models(); }
};

TEST_F(ModelStorageTest, AssetsNothingReferencesAreDroppedWithAWarning) {
  StartServer();
  v1::ModelBundle bundle = MeshBundle("solid arm\nendsolid arm\n");
  bundle.set_scene_script("! a part of the scene\nPart gripper;\n$ Part ghost; $\n");
  AddAsset(bundle, "gripper.stl", "solid g\nendsolid g\n");  // the scene's Part
  AddAsset(bundle, "unused.stl", std::string(5000, 'x'));
  AddAsset(bundle, "ghost.stl", "solid h\nendsolid h\n");  // only in a comment
  const v1::ModelInfo info = SubmitOk(bundle);
  EXPECT_EQ(info.num_assets(), 2);
  std::string warnings;
  for (const std::string& warning : info.warnings()) warnings += warning + "\n";
  EXPECT_THAT(warnings, HasSubstr("asset 'unused.stl' is referenced by neither"));
  EXPECT_THAT(warnings, HasSubstr("asset 'ghost.stl'"));
  EXPECT_THAT(warnings, ::testing::Not(HasSubstr("'gripper.stl'")));

  const v1::GetModelResponse stored = GetModel(info.id());
  std::vector<std::string> names;
  for (const v1::Asset& asset : stored.bundle().assets()) names.push_back(asset.name());
  EXPECT_THAT(names, ElementsAre("arm.stl", "gripper.stl"));
  EXPECT_EQ(stored.bundle().assets(0).data(), "solid arm\nendsolid arm\n");

  // The same model without the spare files is the same model.
  v1::ModelBundle clean = MeshBundle("solid arm\nendsolid arm\n");
  clean.set_scene_script(bundle.scene_script());
  AddAsset(clean, "gripper.stl", "solid g\nendsolid g\n");
  EXPECT_EQ(SubmitOk(clean).id(), info.id());
}

TEST_F(ModelStorageTest, TheNumberOfStoredModelsIsCapped) {
  ServerLimits limits;
  limits.max_models = 2;
  StartServer(limits);  // the built-in models do not count
  const v1::ModelInfo first = SubmitOk(MeshBundle("solid 1\nendsolid 1\n"));
  SubmitOk(MeshBundle("solid 2\nendsolid 2\n"));
  v1::ModelInfo info;
  const grpc::Status status = Submit(MeshBundle("solid 3\nendsolid 3\n"), &info);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_THAT(status.error_message(), HasSubstr("already stores 2 models"));
  EXPECT_THAT(status.error_message(), HasSubstr("--max-models"));
  EXPECT_EQ(SubmitOk(MeshBundle("solid 1\nendsolid 1\n")).id(), first.id());  // known: fine

  StartServer(limits);  // the count survives a restart
  EXPECT_EQ(Submit(MeshBundle("solid 3\nendsolid 3\n"), &info).error_code(),
            grpc::StatusCode::RESOURCE_EXHAUSTED);
}

TEST_F(ModelStorageTest, TheTotalSizeOfStoredModelsIsCapped) {
  ServerLimits limits;
  limits.max_total_model_bytes = 100 << 10;
  StartServer(limits);
  SubmitOk(MeshBundle(std::string(60 << 10, 'a')));
  v1::ModelInfo info;
  const grpc::Status status = Submit(MeshBundle(std::string(60 << 10, 'b')), &info);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_THAT(status.error_message(), HasSubstr("--max-models-mb"));
  SubmitOk(MeshBundle(std::string(20 << 10, 'c')));  // what still fits is taken

  StartServer(limits);  // sizes are read back from the store
  EXPECT_EQ(Submit(MeshBundle(std::string(30 << 10, 'd')), &info).error_code(),
            grpc::StatusCode::RESOURCE_EXHAUSTED);
}

TEST_F(ModelStorageTest, StoredModelsAreCompiledOnFirstUseOnly) {
  StartServer();
  const std::string mesh(200 << 10, 'm');
  const v1::ModelInfo info = SubmitOk(MeshBundle(mesh));
  EXPECT_GE(registry().compiled_count(), 1);

  StartServer();  // a restart lists the stored models without compiling any
  EXPECT_EQ(registry().compiled_count(), 0);
  grpc::ClientContext context;
  v1::ListModelsResponse list;
  ASSERT_TRUE(stub().ListModels(&context, v1::ListModelsRequest(), &list).ok());
  std::set<std::string> ids;
  for (const v1::ModelInfo& model : list.models()) ids.insert(model.id());
  EXPECT_EQ(ids.count(info.id()), 1u);
  const v1::GetModelResponse stored = GetModel(info.id());  // the bundle from the store
  ASSERT_EQ(stored.bundle().assets_size(), 1);
  EXPECT_EQ(stored.bundle().assets(0).data(), mesh);
  EXPECT_EQ(stored.info().dofs(), 1);
  EXPECT_EQ(registry().compiled_count(), 0);

  v1::RunSpec spec;
  spec.set_duration_s(0.1);
  spec.set_output_interval_s(0.05);
  const v1::RunInfo ended = WaitForEnd(StartRunOk(info.id(), spec).id());
  EXPECT_EQ(ended.state(), v1::FINISHED) << ended.message();
  EXPECT_EQ(ended.frames(), 3);
  EXPECT_EQ(registry().compiled_count(), 1);
}

TEST_F(ModelStorageTest, TheCacheOfCompiledModelsIsBounded) {
  ServerLimits limits;
  limits.compiled_models_cached = 1;
  StartServer(limits);
  const v1::ModelInfo a = SubmitOk(MeshBundle("solid a\nendsolid a\n"));
  const v1::ModelInfo b = SubmitOk(MeshBundle("solid b\nendsolid b\n"));
  EXPECT_EQ(registry().compiled_count(), 1);
  EXPECT_EQ(registry().Find(a.id())->info.id(), a.id());  // compiled again on demand
  EXPECT_EQ(registry().Find(b.id())->model.num_dofs(), 1);
  EXPECT_EQ(registry().compiled_count(), 1);
}

}  // namespace
}  // namespace mbstream::testing
