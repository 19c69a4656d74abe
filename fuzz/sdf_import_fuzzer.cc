// Fuzzes the SDFormat import (server/parse/sdf_import.h: libsdformat's reading, the spanning
// tree, ball joints as three axes, cut joints as loop closures), with a link limit
// (64): any text either imports or throws InputError (or LimitError) with a message. What
// imports must be whole: every body's joint frame, axis and inertia finite (the axis a unit
// vector), and every loop closure between bodies of the model (or the world), with finite
// frames and a unit axis.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "server/parse/sdf_import.h"
#include "shared/common/check.h"

namespace {

bool Finite(const mbstream::Pose& pose) { return pose.R.allFinite() && pose.p.allFinite(); }

bool UnitAxis(const mbstream::Vector3d& axis) {
  return axis.allFinite() && std::abs(axis.norm() - 1.0) < 1e-9;
}

void CheckImport(const mbstream::SdfImport& imported) {
  // Bodies, not coordinates: a free body has 7 position and 6 velocity coordinates.
  const int bodies = imported.model.num_bodies();
  for (int i = 0; i < bodies; ++i) {
    const mbstream::Body& body = imported.model.bodies[static_cast<size_t>(i)];
    if (body.parent < mbstream::kBase || body.parent >= i) std::abort();  // topological order
    if (!Finite(body.joint.X_PJ)) std::abort();
    if (body.joint.type == mbstream::JointType::kFree) {  // no axis; a root with a finite pose
      if (body.parent != mbstream::kBase || !Finite(body.X_W0)) std::abort();
    } else if (!UnitAxis(body.joint.axis)) {
      std::abort();
    }
    const mbstream::RigidInertia& inertia = body.inertia;
    if (!std::isfinite(inertia.mass) || inertia.mass < 0.0) std::abort();
    if (!inertia.com.allFinite() || !inertia.inertia_com.allFinite()) std::abort();
  }
  for (const mbstream::LoopClosure& loop : imported.loops) {
    if (loop.name.empty() || loop.where.empty()) std::abort();
    if (loop.body_a < mbstream::kBase || loop.body_a >= bodies) std::abort();
    if (loop.body_b < mbstream::kBase || loop.body_b >= bodies) std::abort();
    if (!Finite(loop.X_AJ) || !Finite(loop.X_BJ)) std::abort();
    if (loop.type != mbstream::LoopJointType::kBall &&
        loop.type != mbstream::LoopJointType::kFixed && !UnitAxis(loop.axis)) {
      std::abort();
    }
  }
  for (const std::string& warning : imported.warnings) {
    if (warning.empty()) std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  // One import a text (libsdformat's reading is slow: tens of ms); the link limit is checked
  // before it and throws LimitError for the larger texts.
  try {
    CheckImport(mbstream::ImportSdf(text, "fuzz.sdf", {.max_links = 64}));
  } catch (const mbstream::InputError& error) {  // LimitError is one too
    if (std::string(error.what()).empty()) std::abort();
  }
  return 0;
}
