#include "server/sim/singular_pose.h"

#include "shared/common/format.h"

namespace mbstream {

std::string PoseText(const Model& model, const Eigen::VectorXd& q) {
  std::string text;
  for (int i = 0; i < model.num_bodies(); ++i) {
    const Body& body = model.bodies[i];
    const Joint& joint = body.joint;
    if (!text.empty()) text += ", ";
    const int k = body.q_index;
    if (body.free()) {  // x y z qw qx qy qz
      text +=
          FormatString("%s = (%.6g, %.6g, %.6g) m, (%.6g, %.6g, %.6g, %.6g)", joint.name.c_str(),
                       q(k), q(k + 1), q(k + 2), q(k + 3), q(k + 4), q(k + 5), q(k + 6));
    } else if (body.ball()) {  // qw qx qy qz
      text += FormatString("%s = (%.6g, %.6g, %.6g, %.6g)", joint.name.c_str(), q(k), q(k + 1),
                           q(k + 2), q(k + 3));
    } else {
      text += FormatString("%s = %.6g %s", joint.name.c_str(), q(k),
                           joint.type == JointType::kRevolute ? "rad" : "m");
    }
  }
  return text;
}

SingularPoseWatch::SingularPoseWatch(const Model& model, Eigen::Index rows)
    : model_(model),
      square_(rows == model.num_dofs()),
      conditioning_(rows, model.num_dofs()),
      last_q_(model.nq()) {}

std::optional<std::string> SingularPoseWatch::Check(double t, const Eigen::VectorXd& q,
                                                    const Eigen::MatrixXd& A) {
  const double conditioning = conditioning_.Of(A);
  if (conditioning < kSingularPoseConditioning) {
    return FormatString(
        "the driven mechanism reached a singular pose at t = %.6g s (%s; the constraint rows' "
        "conditioning %.2g): there the prescribed joints no longer determine the others (a "
        "dead centre, or a change point where the bars line up) and past it the loops' branch "
        "would be the solver's choice, not the drives'; prescribe a joint that keeps the "
        "mechanism determined through this pose (a crank rather than a slider), or keep the "
        "motion clear of it",
        t, PoseText(model_, q).c_str(), conditioning);
  }
  const int sign = square_ ? conditioning_.DeterminantSign(A) : 0;
  if (last_sign_ != 0 && sign != 0 && sign != last_sign_) {
    return FormatString(
        "the driven mechanism went through a singular pose between t = %.6g s (%s) and t = "
        "%.6g s (the determinant of the constraint rows changed sign): there the prescribed "
        "joints no longer determine the others (a dead centre, or a change point where the "
        "bars line up) and past it the loops' branch would be the solver's choice, not the "
        "drives'; the run stops at the frame before it. Prescribe a joint that keeps the "
        "mechanism determined through this pose (a crank rather than a slider), or keep the "
        "motion clear of it",
        last_t_, PoseText(model_, last_q_).c_str(), t);
  }
  last_sign_ = sign;
  last_t_ = t;
  last_q_ = q;
  return std::nullopt;
}

}  // namespace mbstream
