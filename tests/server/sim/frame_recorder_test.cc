// The output frames' kinematics and energies: one pass of body kinematics shared by the
// TCP and both energies gives the values of the separate ForwardKinematics and
// KineticEnergy calls, bit for bit, and recording a frame allocates nothing.
#include "server/sim/frame_recorder.h"

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <random>

#include "server/dynamics/energy.h"
#include "server/kinematics/forward_kinematics.h"
#include "server/sim/run_config.h"
#include "tests/common/allocation_counter.h"
#include "tests/common/test_models.h"

namespace mbstream {
namespace {

std::uint64_t Bits(double x) { return std::bit_cast<std::uint64_t>(x); }

void ExpectSameBits(const Vector3d& a, const Vector3d& b) {
  for (int k = 0; k < 3; ++k) EXPECT_EQ(Bits(a(k)), Bits(b(k))) << "component " << k;
}

TEST(FrameRecorderTest, ReusedKinematicsGiveTheSeparateCallsValues) {
  for (const Model& model : {testing::Irb1600Model(), testing::BranchingModel()}) {
    const int n = model.num_dofs();
    Data reuse(model), separate(model);
    std::mt19937 rng(3);
    for (int sample = 0; sample < 20; ++sample) {
      const Eigen::VectorXd q = testing::RandomVector(rng, n, 2.0);
      const Eigen::VectorXd qd = testing::RandomVector(rng, n, 3.0);
      // The old path: ForwardKinematics, then KineticEnergy recomputing the joint transforms.
      ForwardKinematics(model, separate, q);
      const double potential = PotentialEnergy(model, separate);
      const double kinetic = KineticEnergy(model, separate, q, qd);
      // The recorder's path: body poses once, reused.
      BodyKinematics(model, reuse, q);
      EXPECT_EQ(Bits(PotentialEnergy(model, reuse)), Bits(potential));
      EXPECT_EQ(Bits(KineticEnergyAfterKinematics(model, reuse, qd)), Bits(kinetic));
      for (int i = 0; i < n; ++i) {
        ExpectSameBits(reuse.X_world[i].p, separate.X_world[i].p);
        for (int k = 0; k < 3; ++k)
          ExpectSameBits(reuse.X_world[i].R.col(k), separate.X_world[i].R.col(k));
      }
      for (size_t f = 0; f < model.frames.size(); ++f) {
        ExpectSameBits(FramePositionFromBodies(model, reuse, static_cast<int>(f)),
                       FramePosition(separate, static_cast<int>(f)));
      }
    }
  }
}

TEST(FrameRecorderTest, RecordsTheSeparateCallsTcpAndEnergiesWithoutAllocating) {
  const Model model = testing::BranchingModel();
  const int n = model.num_dofs();
  RunConfig config;
  config.drives.resize(n);
  const DriveSet drives(model, config.drives);
  RunResult result;
  result.num_dofs = n;
  result.has_torques = true;
  result.has_energy = true;
  const int frames = 10;
  FrameRecorder recorder(model, drives, result, frames, /*track_tcp_error=*/false);
  Data data(model);
  std::mt19937 rng(5);
  for (int k = 0; k < frames; ++k) {
    const Eigen::VectorXd q = testing::RandomVector(rng, n, 2.0);
    const Eigen::VectorXd qd = testing::RandomVector(rng, n, 3.0);
    const Eigen::VectorXd effort = testing::RandomVector(rng, n, 10.0);
    const long before = testing::AllocationCount();
    ASSERT_TRUE(recorder.Record(0.1 * k, q, qd, &effort));
    EXPECT_EQ(testing::AllocationCount() - before, 0) << "frame " << k;
    ForwardKinematics(model, data, q);
    ExpectSameBits(Vector3d(result.tcp.data() + 3 * k), FramePosition(data, model.tcp_frame));
    EXPECT_EQ(Bits(result.potential[k]), Bits(PotentialEnergy(model, data)));
    EXPECT_EQ(Bits(result.kinetic[k]), Bits(KineticEnergy(model, data, q, qd)));
  }
}

}  // namespace
}  // namespace mbstream
