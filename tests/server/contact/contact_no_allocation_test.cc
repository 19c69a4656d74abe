// A contact run's time steps allocate nothing on the heap (tests/common/allocation_counter.h
// counts malloc too): the joint-space ODE's right-hand side with box-plane, box-box and
// sphere-box contacts (FCL's broad phase and primitive routines), and CVODE BDF and ARKODE
// ERK stepping through the bounces, after a first call has grown the buffers; the same for
// body-baumgarte's ODE (body_contact.h).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <memory>
#include <string>

#include "server/body/body_baumgarte_ode.h"
#include "server/body/body_model.h"
#include "server/body/consistent_init.h"
#include "server/drives/drive_set.h"
#include "server/integrate/integrator.h"
#include "server/parse/sdf_import.h"
#include "server/sim/joint_integration.h"
#include "server/sim/joint_space_ode.h"
#include "tests/common/allocation_counter.h"

namespace mbstream {
namespace {

Model Scene(const std::string& name) {
  return ImportSdfFile(std::string(MBSTREAM_SOURCE_DIR) + "/tests/data/contact/" + name).model;
}

Eigen::VectorXd InitialState(const Model& model) {
  Eigen::VectorXd y = Eigen::VectorXd::Zero(model.nq() + model.nv());
  NeutralPositions(model, y.data());
  return y;
}

TEST(ContactNoAllocationTest, RightHandSideWithContactsAllocatesNothing) {
  const Model model = Scene("stacked_boxes.sdf");
  ASSERT_EQ(model.collisions.size(), 4u);
  const DriveSet drives(model, std::vector<DriveConfig>(static_cast<size_t>(model.nv())));
  ContactSettings settings;
  ContactForces contact(model, settings);
  ASSERT_TRUE(contact.active());
  JointSpaceOde ode(model, drives, /*track_work=*/true, &contact);
  Eigen::VectorXd y = InitialState(model);
  double sink = 0.0;  // each body 0.1 mm into the one below
  for (const int b : model.free_bodies) y(model.bodies[b].q_index + 2) -= (sink += 1e-4);
  Eigen::VectorXd ydot(y.size());
  std::array<double, 2> work{};  // J: the work; the contacts' dissipated work
  ASSERT_EQ(ode.RhsAndQuadrature(0.0, y.data(), ydot.data(), work.data()), 0);  // grows the buffers
  ASSERT_GE(contact.contacts().size(), 9u);  // 4 box-plane, 4 box-box, 1 sphere-box
  const long before = testing::AllocationCount();
  for (int k = 0; k < 20; ++k) {
    y(model.nq()) = 1e-3 * k;  // a sliding speed
    ode.RhsAndQuadrature(0.01 * k, y.data(), ydot.data(), work.data());
  }
  EXPECT_EQ(testing::AllocationCount() - before, 0);
  EXPECT_TRUE(ydot.allFinite());
}

// Mesh hulls (docs/contact.md, "Meshes") against a plane, a box, a hull and a sphere: closed
// forms, nothing on the heap either.
TEST(ContactNoAllocationTest, HullContactsAllocateNothing) {
  for (const char* scene : {"box_mesh_on_plane.sdf", "mesh_box_on_table.sdf",
                            "mesh_box_on_mesh_table.sdf", "ball_on_l_shape.sdf"}) {
    const Model model = Scene(scene);
    const DriveSet drives(model, std::vector<DriveConfig>(static_cast<size_t>(model.nv())));
    ContactSettings settings;
    ContactForces contact(model, settings);
    ASSERT_TRUE(contact.active()) << scene;
    JointSpaceOde ode(model, drives, /*track_work=*/true, &contact);
    Eigen::VectorXd y = InitialState(model);
    const int b = model.free_bodies.front();
    const bool ball = std::string(scene) == "ball_on_l_shape.sdf";
    // into the surface below by 0.1 mm (the ball: from 0.15 m onto the hull face at 0.0354)
    y(model.bodies[b].q_index + 2) = ball ? 0.05 / std::sqrt(2.0) + 0.05 - 1e-4 : 0.1 - 1e-4;
    Eigen::VectorXd ydot(y.size());
    std::array<double, 2> work{};
    ASSERT_EQ(ode.RhsAndQuadrature(0.0, y.data(), ydot.data(), work.data()), 0);
    ASSERT_EQ(contact.contacts().size(), ball ? 1u : 4u) << scene;
    const long before = testing::AllocationCount();
    for (int k = 0; k < 20; ++k) {
      y(model.nq()) = 1e-3 * k;
      ode.RhsAndQuadrature(0.01 * k, y.data(), ydot.data(), work.data());
    }
    EXPECT_EQ(testing::AllocationCount() - before, 0) << scene;
    EXPECT_TRUE(ydot.allFinite()) << scene;
  }
}

TEST(ContactNoAllocationTest, StepsThroughBouncesAllocateNothing) {
  const Model model = Scene("ball_on_plane.sdf");
  for (const Method method : {Method::kBdf, Method::kErk}) {
    RunConfig config;
    config.method = method;
    config.drives.resize(static_cast<size_t>(model.nv()));
    config.contact.dissipation = 0.5;
    IntegratorOptions options;
    options.method = method;
    options.rtol = 1e-8;
    options.atol = 1e-10;
    options.t_final = 3.0;
    options.max_step = ContactPeriod(model, config.contact) / kContactStepsPerPeriod;
    JointIntegration live(model, config, /*track_work=*/false, options);
    ASSERT_NE(live.contact, nullptr);
    Eigen::VectorXd& y = live.y;
    ASSERT_EQ(live.integrator->AdvanceTo(0.1, y.data()).status, IntegratorStatus::kOk);
    const long before = testing::AllocationCount();
    bool ok = true;
    for (int k = 2; k <= 30; ++k) {  // through the first bounce (t = 0.43 s) and beyond
      ok = ok && live.integrator->AdvanceTo(0.1 * k, y.data()).status == IntegratorStatus::kOk;
    }
    EXPECT_TRUE(ok) << MethodName(method);
    EXPECT_EQ(testing::AllocationCount() - before, 0) << MethodName(method);
    EXPECT_GT(y(2), 0.0);  // above the plane
  }
}

// body-baumgarte: the right-hand side with the box 0.1 mm into the plane, its root functions,
// and CVODE BDF stepping through the landing.
TEST(ContactNoAllocationTest, TheBodyBaumgarteOdeWithContactAllocatesNothing) {
  const Model model = Scene("box_on_slider.sdf");
  const DriveSet drives(model, std::vector<DriveConfig>(static_cast<size_t>(model.nv())));
  ContactSettings settings;
  settings.dissipation = 20.0;
  ContactForces contact(model, settings);
  ASSERT_TRUE(contact.active());
  const Eigen::VectorXd q0 = Eigen::VectorXd::Zero(model.nv());
  const BodyModel bm = MakeBodyModel(model, drives, q0);
  BodyBaumgarteOde ode(bm, drives, BaumgarteParameters{}, /*track_work=*/true, &contact);
  ASSERT_EQ(ode.num_roots(), 1);
  ASSERT_EQ(ode.num_quadratures(), 2);
  BodyInitialState init;
  ASSERT_TRUE(ConsistentInitialState(model, bm, ode.mechanics(), 0.0, q0, q0, &init));
  Eigen::VectorXd y = init.y.head(bm.ode_size());
  Eigen::VectorXd sunk = y;
  sunk(BodyModel::position(1) + 2) -= 0.05 + 1e-4;  // the box's centre of mass: 0.1 mm in
  Eigen::VectorXd ydot(y.size());
  std::array<double, 2> work{};
  double g = 0.0;
  ASSERT_EQ(ode.RhsAndQuadrature(0.0, sunk.data(), ydot.data(), work.data()), 0);
  ASSERT_EQ(ode.contact()->contacts().size(), 4u);
  const long before = testing::AllocationCount();
  for (int k = 0; k < 20; ++k) {
    sunk(bm.velocity(0)) = 1e-3 * k;  // a sliding speed
    ode.RhsAndQuadrature(0.01 * k, sunk.data(), ydot.data(), work.data());
    ode.Roots(0.01 * k, sunk.data(), &g);
  }
  EXPECT_EQ(testing::AllocationCount() - before, 0);
  EXPECT_TRUE(ydot.allFinite());
  EXPECT_NEAR(g, -1e-4, 1e-12);
  IntegratorOptions options;
  options.rtol = 1e-8;
  options.atol = 1e-10;
  options.t_final = 1.0;
  options.max_step = ContactPeriod(model, settings) / kContactStepsPerPeriod;
  std::unique_ptr<Integrator> integrator = MakeIntegrator(ode, 0.0, y.data(), options);
  ASSERT_EQ(integrator->AdvanceTo(0.05, y.data()).status, IntegratorStatus::kOk);
  const long stepping = testing::AllocationCount();
  bool ok = true;
  for (int k = 2; k <= 10; ++k) {  // through the landing (t = 0.1 s)
    ok = ok && integrator->AdvanceTo(0.05 * k, y.data()).status == IntegratorStatus::kOk;
  }
  EXPECT_TRUE(ok);
  EXPECT_EQ(testing::AllocationCount() - stepping, 0);
  EXPECT_GT(integrator->stats().roots_found, 0);
}

}  // namespace
}  // namespace mbstream
