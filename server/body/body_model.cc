#include "server/body/body_model.h"

#include <cmath>

#include "shared/common/check.h"

namespace mbstream {

Vector3d Perpendicular(const Vector3d& a) {
  const Vector3d trial = std::abs(a.x()) < 0.9 ? Vector3d::UnitX() : Vector3d::UnitY();
  return (trial - a * a.dot(trial)).normalized();
}

void CheckBodyFormulationHandles(const Model& model) {
  for (const Body& body : model.bodies) {
    if (body.ball()) {
      throw InputError("ball joint '" + body.joint.name + "' (link '" + body.name +
                       "'): the body-coordinate formulations do not simulate ball joints yet; "
                       "use formulation joint (or auto)");
    }
    if (!(body.inertia.mass > 0.0)) {
      throw InputError("link '" + body.name +
                       "' has no mass: a free body needs mass and inertia in the body-coordinate "
                       "formulations; use formulation joint (or auto)");
    }
  }
}

BodyModel MakeBodyModel(const Model& model, const DriveSet& drives, const Eigen::VectorXd& q0) {
  CheckBodyFormulationHandles(model);
  BodyModel bm;
  bm.n = model.num_dofs();
  bm.gravity = model.gravity;
  bm.children.resize(bm.n);
  for (int i = 0; i < bm.n; ++i) {
    const Body& body = model.bodies[i];
    bm.mass.push_back(body.inertia.mass);
    bm.inertia.push_back(body.inertia.inertia_com);
    bm.com.push_back(body.inertia.com);
  }
  int row = 0;
  for (int i = 0; i < bm.n; ++i) {
    const Body& body = model.bodies[i];
    BodyJoint j;
    j.type = body.joint.type;
    j.parent = body.parent;
    j.child = i;
    const Vector3d parent_com = body.parent == kBase ? Vector3d::Zero() : bm.com[body.parent];
    j.d_P = body.joint.X_PJ.p - parent_com;
    j.d_B = -bm.com[i];
    j.a = body.joint.axis.normalized();
    j.a_P = body.joint.X_PJ.R * j.a;
    j.u1 = Perpendicular(j.a);
    j.u2 = j.a.cross(j.u1);
    j.R_PJ = body.joint.X_PJ.R;
    j.prescribed = drives.prescribed(i);
    j.rows = j.prescribed ? 6 : 5;
    j.row = row;
    row += j.rows;
    if (drives.velocity_source(i) && q0.size() == bm.n) {
      j.q_offset = q0(i) - drives.Reference(i, 0.0).q;
    }
    j.damping = drives.damping(i);
    j.armature = body.joint.armature;
    bm.any_armature = bm.any_armature || j.armature != 0.0;
    if (body.parent != kBase) bm.children[body.parent].push_back(i);
    bm.joints.push_back(j);
  }
  bm.m = bm.m_tree = row;
  if (model.tcp_frame >= 0) {
    const Frame& frame = model.frames[model.tcp_frame];
    bm.tcp_body = frame.body;
    if (frame.body == kBase) {
      bm.tcp_fixed = frame.X_BF.p;
    } else {
      bm.tcp_from_com = frame.X_BF.p - bm.com[frame.body];
    }
  }
  return bm;
}

}  // namespace mbstream
