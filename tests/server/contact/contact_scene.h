// What the contact suites share: a scene of tests/data/contact/, a passive run of it with the
// suites' settings, a frame's coordinates (primitive_geometry.h: a bare geometry).
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "server/engine/engine.h"
#include "server/parse/sdf_import.h"
#include "server/sim/run_validation.h"

namespace mbstream::contact_testing {

// The SDFormat world tests/data/contact/NAME.
inline Model Scene(const std::string& name) {
  return ImportSdfFile(std::string(MBSTREAM_SOURCE_DIR) + "/tests/data/contact/" + name).model;
}

// The suites' run: joint formulation, rtol 1e-10, atol 1e-12, no torques, k = 1e5 N/m a
// surface (5e4 N/m the pair); the other contact settings the defaults.
inline RunConfig Config(double duration, double interval) {
  RunConfig config;
  config.formulation = Formulation::kJoint;
  config.duration = duration;
  config.output_interval = interval;
  config.rtol = 1e-10;
  config.atol = 1e-12;
  config.want_torques = false;
  config.contact.stiffness = 1e5;
  return config;
}

// `config` run on `model` with every coordinate passive; EXPECTs that it finished.
inline RunResult RunScene(const Model& model, RunConfig config) {
  config.formulation = Formulation::kJoint;
  config.want_torques = false;
  config.drives.resize(static_cast<size_t>(model.nv()));
  ValidateRun(model, config);
  RunResult result = Simulate(model, config);
  EXPECT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  return result;
}

// Position k and velocity k of output frame `frame`.
inline double Q(const RunResult& r, size_t frame, int k) {
  return r.q[frame * static_cast<size_t>(r.num_positions) + static_cast<size_t>(k)];
}
inline double Qd(const RunResult& r, size_t frame, int k) {
  return r.qd[frame * static_cast<size_t>(r.num_dofs) + static_cast<size_t>(k)];
}

// The total normal force of output frame `frame`'s contacts (N; every frame's records kept).
inline double NormalForce(const RunResult& r, size_t frame) {
  double force = 0.0;
  for (const ContactRecord& c : r.contacts.records) {
    if (c.t == r.t[frame]) force += c.normal_force;
  }
  return force;
}

}  // namespace mbstream::contact_testing
