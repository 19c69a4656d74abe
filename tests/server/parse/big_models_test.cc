// The big benchmark models (models/big/) import as generated, and their dynamics agree with
// themselves: ABA inverts RNEA, M qdd + C = tau with M from CRBA, so the benchmarks on them
// time correct algorithms, not only fast ones.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <random>
#include <string>

#include "server/dynamics/aba.h"
#include "server/dynamics/crba.h"
#include "server/dynamics/rnea.h"
#include "server/kinematics/joint_spatial_transform.h"
#include "server/parse/urdf_import.h"

namespace mbstream {
namespace {

struct BigModel {
  const char* file;  // under models/big/
  int joints;
};

class BigModelTest : public ::testing::TestWithParam<BigModel> {
 protected:
  BigModelTest()
      : imported_(
            ImportUrdfFile(std::string(MBSTREAM_SOURCE_DIR) + "/models/big/" + GetParam().file)),
        model_(imported_.model),
        data_(model_) {}

  Eigen::VectorXd Random(double scale) {
    std::uniform_real_distribution<double> dist(-scale, scale);
    Eigen::VectorXd v(model_.num_dofs());
    for (int i = 0; i < v.size(); ++i) v(i) = dist(rng_);
    return v;
  }

  UrdfImport imported_;
  const Model& model_;
  Data data_;
  std::mt19937 rng_{7};
};

TEST_P(BigModelTest, ImportsWithoutWarningsAndEveryJointShape) {
  EXPECT_EQ(model_.num_dofs(), GetParam().joints);
  EXPECT_TRUE(imported_.warnings.empty()) << imported_.warnings.front();
  // The generator mixes the fast paths with general joints (rotated origins, skew axes).
  bool general = false, fast = false;
  for (const Body& body : model_.bodies) {
    (JointShape(body.joint) == kGeneralJoint ? general : fast) = true;
  }
  EXPECT_TRUE(general);
  EXPECT_TRUE(fast);
}

TEST_P(BigModelTest, AbaAndRneaRoundTrip) {
  for (int k = 0; k < 20; ++k) {
    const Eigen::VectorXd q = Random(3.0), qd = Random(2.0), tau = Random(50.0);
    const Eigen::VectorXd qdd = Aba(model_, data_, q, qd, tau);
    const Eigen::VectorXd back = Rnea(model_, data_, q, qd, qdd);
    EXPECT_LT((back - tau).norm(), 1e-9 * tau.norm()) << "state " << k;
  }
}

TEST_P(BigModelTest, MassMatrixTimesAbaPlusBiasIsTau) {
  for (int k = 0; k < 10; ++k) {
    const Eigen::VectorXd q = Random(3.0), qd = Random(2.0), tau = Random(50.0);
    const Eigen::VectorXd c = NonlinearEffects(model_, data_, q, qd);
    const Eigen::MatrixXd M = Crba(model_, data_, q);
    const Eigen::VectorXd qdd = Aba(model_, data_, q, qd, tau);
    EXPECT_LT((M * qdd + c - tau).norm(), 1e-9 * tau.norm()) << "state " << k;
    EXPECT_LT((qdd - M.llt().solve(tau - c)).norm(), 1e-8 * (1.0 + qdd.norm())) << "state " << k;
  }
}

INSTANTIATE_TEST_SUITE_P(Models, BigModelTest,
                         ::testing::Values(BigModel{"tree38.urdf", 38},
                                           BigModel{"chain100.urdf", 100}),
                         [](const auto& info) { return info.index == 0 ? "Tree38" : "Chain100"; });

}  // namespace
}  // namespace mbstream
