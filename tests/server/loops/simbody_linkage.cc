#include "tests/server/loops/simbody_linkage.h"

#include <Simbody.h>
#include <gtest/gtest.h>

namespace mbstream {
namespace {

SimTK::Vec3 ToVec3(const Vector3d& v) { return SimTK::Vec3(v.x(), v.y(), v.z()); }

SimTK::Rotation ToRotation(const Matrix3d& R) {
  SimTK::Mat33 m;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) m(i, j) = R(i, j);
  }
  return SimTK::Rotation(m);
}

// A body of inertia `in` (about its frame's origin, as Simbody takes it).
SimTK::Body::Rigid RigidOf(const RigidInertia& in) {
  // Inertia about the body origin: I_cm + m (|c|^2 1 - c c^T).
  const Matrix3d I = in.inertia_com + in.mass * (in.com.squaredNorm() * Matrix3d::Identity() -
                                                 in.com * in.com.transpose());
  return SimTK::Body::Rigid(
      SimTK::MassProperties(in.mass, ToVec3(in.com),
                            SimTK::Inertia(SimTK::Mat33(I(0, 0), I(0, 1), I(0, 2), I(1, 0), I(1, 1),
                                                        I(1, 2), I(2, 0), I(2, 1), I(2, 2)))));
}

// A Simbody system with its matter and gravity (-9.81 m/s^2 along z), as both runs below use.
struct GravityWorld {
  SimTK::MultibodySystem system;
  SimTK::SimbodyMatterSubsystem matter{system};
  SimTK::GeneralForceSubsystem forces{system};
  SimTK::Force::UniformGravity gravity{forces, matter, SimTK::Vec3(0, 0, -9.81)};
};

// A rotation taking `to` (z for a pin, x for a slider) onto the joint's axis.
Matrix3d AxisFrame(const Vector3d& axis, const Vector3d& to) {
  return Eigen::Quaterniond::FromTwoVectors(to, axis).toRotationMatrix();
}

}  // namespace

std::vector<std::vector<double>> SimbodyTrajectories(const SdfImport& sdf,
                                                     const std::vector<double>& times,
                                                     const std::vector<double>& qd0) {
  using namespace SimTK;
  GravityWorld world;
  MultibodySystem& system = world.system;
  SimbodyMatterSubsystem& matter = world.matter;
  const Model& model = sdf.model;
  std::vector<MobilizedBody> bodies;
  for (const Body& body : model.bodies) {
    const SimTK::Body::Rigid info = RigidOf(body.inertia);
    const bool pin = body.joint.type == JointType::kRevolute;
    const Matrix3d R_JM = AxisFrame(body.joint.axis, pin ? Vector3d::UnitZ() : Vector3d::UnitX());
    const Transform X_PF(ToRotation(body.joint.X_PJ.R * R_JM), ToVec3(body.joint.X_PJ.p));
    const Transform X_BM(ToRotation(R_JM), Vec3(0));
    MobilizedBody& parent =
        body.parent == kBase ? matter.updGround() : bodies[static_cast<size_t>(body.parent)];
    if (pin) {
      bodies.push_back(MobilizedBody::Pin(parent, X_PF, info, X_BM));
    } else {
      bodies.push_back(MobilizedBody::Slider(parent, X_PF, info, X_BM));
    }
  }
  for (const LoopClosure& loop : sdf.loops) {
    EXPECT_EQ(loop.type, LoopJointType::kRevolute);  // planar: a ball holds it
    MobilizedBody& a = loop.body_a == kBase ? matter.updGround() : bodies[loop.body_a];
    MobilizedBody& b = loop.body_b == kBase ? matter.updGround() : bodies[loop.body_b];
    Constraint::Ball(a, ToVec3(loop.X_AJ.p), b, ToVec3(loop.X_BJ.p));
  }
  State state = system.realizeTopology();
  for (size_t i = 0; i < bodies.size(); ++i) bodies[i].setOneU(state, 0, qd0[i]);
  RungeKuttaMersonIntegrator integrator(system);
  integrator.setAccuracy(1e-12);
  integrator.setConstraintTolerance(1e-12);
  TimeStepper stepper(system, integrator);
  stepper.initialize(state);
  std::vector<std::vector<double>> q;
  for (double t : times) {
    if (t > 0.0) stepper.stepTo(t);
    const State& s = integrator.getState();
    std::vector<double> frame;
    for (const MobilizedBody& body : bodies) frame.push_back(body.getOneQ(s, 0));
    q.push_back(frame);
  }
  return q;
}

std::vector<Matrix3d> SimbodyBallOrientations(const Model& model, const Matrix3d& R0,
                                              const Vector3d& w0,
                                              const std::vector<double>& times) {
  using namespace SimTK;
  GravityWorld world;
  MultibodySystem& system = world.system;
  SimbodyMatterSubsystem& matter = world.matter;
  const SimTK::Body::Rigid info = RigidOf(model.bodies.back().inertia);
  const Pose& X_PJ = model.bodies.front().joint.X_PJ;
  const Transform X_PF(ToRotation(X_PJ.R), ToVec3(X_PJ.p));
  MobilizedBody::Ball ball(matter.updGround(), X_PF, info, Transform());
  State state = system.realizeTopology();
  system.realizeModel(state);  // a Ball mobilizer's quaternion coordinates exist from here
  ball.setQToFitRotation(state, ToRotation(R0));
  ball.setUToFitAngularVelocity(state, ToVec3(w0));
  RungeKuttaMersonIntegrator integrator(system);
  integrator.setAccuracy(1e-12);
  TimeStepper stepper(system, integrator);
  stepper.initialize(state);
  std::vector<Matrix3d> orientations;
  for (double t : times) {
    if (t > 0.0) stepper.stepTo(t);
    const Rotation& R = ball.getMobilizerTransform(integrator.getState()).R();
    Matrix3d out;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) out(i, j) = R.asMat33()(i, j);
    }
    orientations.push_back(out);
  }
  return orientations;
}

}  // namespace mbstream
