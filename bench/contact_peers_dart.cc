#include "bench/contact_peers_dart.h"

#include <dart/collision/fcl/FCLCollisionDetector.hpp>
#include <dart/constraint/ConstraintSolver.hpp>
#include <dart/dynamics/BodyNode.hpp>
#include <dart/dynamics/BoxShape.hpp>
#include <dart/dynamics/CylinderShape.hpp>
#include <dart/dynamics/FreeJoint.hpp>
#include <dart/dynamics/ShapeNode.hpp>
#include <dart/dynamics/Skeleton.hpp>
#include <dart/dynamics/SphereShape.hpp>
#include <dart/dynamics/WeldJoint.hpp>
#include <dart/simulation/World.hpp>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

namespace mbstream::contact_peers {
namespace {

using dart::dynamics::BodyNode;
using dart::dynamics::CollisionAspect;
using dart::dynamics::DynamicsAspect;
using dart::dynamics::ShapePtr;

struct DartScene {
  dart::simulation::WorldPtr world;
  BodyNode* body = nullptr;
};

void AddShape(BodyNode* body, const ShapePtr& shape, double mu, double restitution) {
  auto* node = body->createShapeNodeWith<CollisionAspect, DynamicsAspect>(shape);
  node->getDynamicsAspect()->setFrictionCoeff(mu);
  node->getDynamicsAspect()->setRestitutionCoeff(restitution);
}

DartScene Build(const std::string& scene, const DartSetting& setting) {
  DartScene s;
  s.world = dart::simulation::World::create(scene);
  s.world->setTimeStep(setting.timestep);
  s.world->setGravity(SceneGravity(scene));
  if (setting.fcl_primitives) {  // one detector for every run: DART warns once, on the switch
    static const std::shared_ptr<dart::collision::FCLCollisionDetector> detector = [] {
      auto fcl = dart::collision::FCLCollisionDetector::create();
      fcl->setPrimitiveShapeType(dart::collision::FCLCollisionDetector::PRIMITIVE);
      return fcl;
    }();
    s.world->getConstraintSolver()->setCollisionDetector(detector);
  }
  const double mu = scene == "incline" ? 0.3 : scene == "rolling" ? 0.8 : 1.0;
  const double restitution = scene == "bounce" ? 1.0 : 0.0;

  auto ground = dart::dynamics::Skeleton::create("ground");
  auto [weld, floor] = ground->createJointAndBodyNodePair<dart::dynamics::WeldJoint>();
  Eigen::Isometry3d X_floor = Eigen::Isometry3d::Identity();
  X_floor.translation() = Eigen::Vector3d(0.0, 0.0, -0.1);
  weld->setTransformFromParentBodyNode(X_floor);
  AddShape(floor, std::make_shared<dart::dynamics::BoxShape>(Eigen::Vector3d(20.0, 20.0, 0.2)), mu,
           restitution);
  s.world->addSkeleton(ground);

  auto skeleton = dart::dynamics::Skeleton::create("body");
  auto [joint, body] = skeleton->createJointAndBodyNodePair<dart::dynamics::FreeJoint>();
  Eigen::Isometry3d X_body = Eigen::Isometry3d::Identity();
  if (scene == "incline") {
    AddShape(body, std::make_shared<dart::dynamics::BoxShape>(Eigen::Vector3d(0.2, 0.2, 0.2)), mu,
             restitution);
    body->setInertia(dart::dynamics::Inertia(2.0, Eigen::Vector3d::Zero(),
                                             Eigen::Matrix3d::Identity() * 0.013333333333333334));
    X_body.translation() = Eigen::Vector3d(0.0, 0.0, 0.1);
  } else if (scene == "rolling") {  // the axis (DART's cylinder: z) along y
    AddShape(body, std::make_shared<dart::dynamics::CylinderShape>(0.1, 0.2), mu, restitution);
    body->setInertia(dart::dynamics::Inertia(
        2.0, Eigen::Vector3d::Zero(),
        Eigen::Vector3d(0.011666666666666667, 0.011666666666666667, 0.010000000000000002)
            .asDiagonal()));
    X_body.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
    X_body.translation() = Eigen::Vector3d(0.0, 0.0, 0.1);
  } else {
    AddShape(body, std::make_shared<dart::dynamics::SphereShape>(0.1), mu, restitution);
    body->setInertia(
        dart::dynamics::Inertia(1.0, Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity() * 0.004));
    X_body.translation() = Eigen::Vector3d(0.0, 0.0, 1.0);
  }
  joint->setPositions(dart::dynamics::FreeJoint::convertToPositions(X_body));
  s.world->addSkeleton(skeleton);
  s.body = body;
  return s;
}

}  // namespace

Row RunDart(const std::string& scene, const DartSetting& setting, const std::string& label) {
  const double duration = Duration(scene);
  const long steps = std::lround(duration / setting.timestep);
  const long every = std::max(1L, std::lround(SampleInterval(scene) / setting.timestep));
  std::vector<double> samples, times;  // bounce: z; others: vx
  std::vector<double> cpu;
  for (int repeat = 0; repeat < 3; ++repeat) {
    DartScene s = Build(scene, setting);
    samples.clear();
    times.clear();
    samples.reserve(static_cast<size_t>(steps / every + 1));
    times.reserve(static_cast<size_t>(steps / every + 1));
    const double t0 = CpuSeconds();
    for (long k = 1; k <= steps; ++k) {
      s.world->step();
      if (k % every == 0) {
        samples.push_back(scene == "bounce" ? s.body->getTransform().translation().z()
                                            : s.body->getLinearVelocity().x());
        times.push_back(s.world->getTime());
      }
    }
    cpu.push_back(CpuSeconds() - t0);
  }
  std::sort(cpu.begin(), cpu.end());
  Row row{scene, "dart", label};
  row.cpu_per_sim_s = cpu[1] / duration;
  Measure(scene, times, samples, static_cast<double>(every) * setting.timestep, &row);
  return row;
}

}  // namespace mbstream::contact_peers
