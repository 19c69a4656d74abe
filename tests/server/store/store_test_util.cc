#include "tests/server/store/store_test_util.h"

#include <atomic>
#include <chrono>
#include <system_error>

#include <unistd.h>

#include "server/store/store_location.h"
#include "tests/common/postgres_cluster.h"

namespace mbstream::testing {

TempDirectory::TempDirectory() {
  static std::atomic<int> counter{0};
  const auto ticks = std::chrono::steady_clock::now().time_since_epoch().count();
  path_ = std::filesystem::temp_directory_path() /
          ("mbstream-store-test-" + std::to_string(::getpid()) + "-" + std::to_string(ticks) + "-" +
           std::to_string(counter++));
}

TempDirectory::~TempDirectory() {
  std::error_code ignored;
  std::filesystem::remove_all(path_, ignored);
}

void StoreBackendTest::SetUp() {
  if (backend() != Backend::kPostgres) return;
  if (const std::string why = PostgresCluster::Unavailable(); !why.empty()) {
    GTEST_SKIP() << "PostgreSQL variant skipped: " << why;
  }
  static std::atomic<int> databases{0};
  uri_ = SharedPostgresCluster().CreateDatabase("store_test_" + std::to_string(databases++));
}

std::unique_ptr<Store> StoreBackendTest::Open() {
  if (backend() == Backend::kSqlite) return Store::Open(temp_.str());
  return OpenStore(ParseStoreLocation(uri_));
}

std::string BackendName(const ::testing::TestParamInfo<Backend>& info) {
  return info.param == Backend::kSqlite ? "sqlite" : "postgres";
}

v1::ModelInfo MakeModelInfo(const std::string& id, int64_t created_unix_ms) {
  v1::ModelInfo info;
  info.set_id(id);
  info.set_name("arm " + id);
  info.set_dofs(2);
  for (int i = 0; i < 2; ++i) {
    v1::JointInfo* joint = info.add_joints();
    joint->set_name("joint" + std::to_string(i + 1));
    joint->set_type("revolute");
    joint->set_lower(-1.5);
    joint->set_upper(1.5);
  }
  info.set_tcp_frame("tool0");
  info.set_links(4);
  info.set_total_mass_kg(12.5);
  info.add_warnings("link 'x' has no inertia");
  info.set_created_unix_ms(created_unix_ms);
  return info;
}

v1::ModelBundle MakeBundle(const std::string& name, int num_assets) {
  v1::ModelBundle bundle;
  bundle.set_name(name);
  bundle.set_urdf("<robot name=\"" + name + "\"/>");
  bundle.set_scene_script("Device arm\n");
  bundle.set_urdf_file_name(name + ".urdf");
  for (int i = 0; i < num_assets; ++i) {
    v1::Asset* asset = bundle.add_assets();
    asset->set_name("meshes/part" + std::to_string(i) + ".stl");
    std::string data(1000 + i, '\0');  // binary, with NUL bytes
    for (std::size_t k = 0; k < data.size(); ++k) data[k] = static_cast<char>((k * 7 + i) & 0xff);
    asset->set_data(data);
  }
  return bundle;
}

void StoreWholeRun(Store& store, const std::string& id, int64_t frames,
                   const std::string& model_id) {
  v1::RunInfo info = MakeRun(id, v1::RUNNING, 1);
  info.set_model_id(model_id);
  store.PutRun(info);
  info.set_state(v1::FINISHED);
  store.FinishRun(info, MakeFrames(frames, 2));
  store.AddProbes({MakeProbe(id, 0, "tcp"), MakeProbe(id, 1, "tcp")});
  v1::ProbeSet set;
  set.set_id("ps-" + id);
  set.set_run_id(id);
  store.CreateProbeSet(set);
  store.AddProbeSetReports(set.id(), {MakeProbe(id, 3, "tcp")});
}

v1::RunInfo MakeRun(const std::string& id, v1::RunState state, int64_t created_unix_ms) {
  v1::RunInfo info;
  info.set_id(id);
  info.set_model_id("m-abc");
  info.set_model_name("arm");
  info.mutable_spec()->set_duration_s(2.0);
  info.mutable_spec()->set_method("bdf");
  info.set_state(state);
  info.set_created_unix_ms(created_unix_ms);
  info.set_started_unix_ms(created_unix_ms + 5);
  info.set_num_dofs(6);
  info.add_joint_names("joint1");
  info.mutable_stats()->set_steps(123);
  info.set_mbstream_version("0.1.0");
  return info;
}

std::vector<v1::Frame> MakeFrames(int64_t count, int dofs) {
  std::vector<v1::Frame> frames(static_cast<std::size_t>(count));
  for (int64_t k = 0; k < count; ++k) {
    v1::Frame& frame = frames[static_cast<std::size_t>(k)];
    frame.set_seq(k);
    frame.set_t_s(0.001 * static_cast<double>(k));
    for (int j = 0; j < dofs; ++j) {
      frame.add_q(0.1 * j + 1e-6 * static_cast<double>(k));
      frame.add_qd(-0.2 * j + 3e-7 * static_cast<double>(k));
      frame.add_tau(10.0 * j - 1e-5 * static_cast<double>(k));
    }
    frame.mutable_tcp_m()->set_x(0.5 + 1e-7 * static_cast<double>(k));
    frame.mutable_tcp_m()->set_y(-0.25);
    frame.mutable_tcp_m()->set_z(1.125);
    frame.set_kinetic_j(0.3 * static_cast<double>(k));
    frame.set_potential_j(-9.81);
  }
  return frames;
}

v1::ProbeReport MakeProbe(const std::string& run_id, int64_t seq, const std::string& probe) {
  v1::ProbeReport report;
  report.set_run_id(run_id);
  report.set_seq(seq);
  report.set_t_s(0.05 * static_cast<double>(seq));
  report.set_probe(probe);
  report.mutable_position_m()->set_x(1.0 + static_cast<double>(seq));
  report.mutable_position_m()->set_y(2.0);
  report.mutable_position_m()->set_z(3.0);
  report.set_frame("World");
  report.set_latency_us(250 + seq);
  return report;
}

}  // namespace mbstream::testing
