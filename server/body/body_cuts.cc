#include "server/body/body_cuts.h"

#include <utility>

#include <Eigen/QR>

#include "server/body/body_mechanics.h"
#include "server/body/consistent_init.h"
#include "server/kinematics/loop_solver.h"
#include "shared/common/check.h"

namespace mbstream {

void CheckBodyFormulationCloses(const std::vector<LoopClosure>& loops) {
  for (const LoopClosure& loop : loops) {
    if (loop.type == LoopJointType::kFixed) {
      throw InputError(loop.where + ": joint '" + loop.name +
                       "' (fixed) closes a loop, and the body formulations close loops with "
                       "revolute, prismatic and ball joints only: use formulation joint");
    }
    if (loop.type == LoopJointType::kMimic) {
      throw InputError(loop.where + ": joint '" + loop.name +
                       "' follows another joint (<mimic>), a relation of joint coordinates "
                       "that the body formulations do not have: use formulation joint");
    }
  }
}

void AddCutJoints(const std::vector<LoopClosure>& loops, BodyModel* bm) {
  CheckBodyFormulationCloses(loops);
  int row = 0;
  for (const LoopClosure& loop : loops) {
    // The child side must be a body (the base has no velocity columns): swap the sides
    // when it is the base; the constraints are the same.
    int a = loop.body_a, b = loop.body_b;
    Pose X_AJ = loop.X_AJ, X_BJ = loop.X_BJ;
    if (b == kBase) {
      std::swap(a, b);
      std::swap(X_AJ, X_BJ);
    }
    MBSTREAM_CHECK(b != kBase && a != b);
    BodyJoint j;
    j.sides_swapped = a != loop.body_a;
    j.type = loop.type == LoopJointType::kPrismatic ? JointType::kPrismatic : JointType::kRevolute;
    j.ball = loop.type == LoopJointType::kBall;
    j.parent = a;
    j.child = b;
    j.d_P = X_AJ.p - (a == kBase ? Vector3d::Zero() : bm->com[a]);
    j.d_B = X_BJ.p - bm->com[b];
    j.a = X_BJ.R * loop.axis.normalized();
    j.a_P = X_AJ.R * loop.axis.normalized();
    j.u1 = Perpendicular(j.a);
    j.u2 = j.a.cross(j.u1);
    j.R_PJ = X_AJ.R;
    j.R_BJ = X_BJ.R;
    j.rows = j.ball ? 3 : 5;
    j.row = row;
    row += j.rows;
    bm->cuts.push_back(j);
  }
  bm->cut_rows_all = row;
  bm->cut_rows.clear();
  for (int c = 0; c < static_cast<int>(bm->cuts.size()); ++c) {
    for (int k = 0; k < bm->cuts[c].rows; ++k) bm->cut_rows.push_back({c, k});
  }
  bm->m = bm->m_tree + row;
}

int SelectCutRows(const Model& model, const DriveSet& drives, const Eigen::VectorXd& q0,
                  BodyModel* bm) {
  if (bm->cuts.empty()) return 0;
  MBSTREAM_CHECK(static_cast<int>(bm->cut_rows.size()) == bm->cut_rows_all);
  const Eigen::VectorXd y = BodyStateFromJoints(model, *bm, q0, Eigen::VectorXd::Zero(q0.size()));
  BodyMechanics mechanics(*bm, drives);
  mechanics.Load(0.0, y.data());
  mechanics.EvaluateConstraints(/*acceleration_terms=*/false);
  const Eigen::MatrixXd& G = mechanics.G();
  const Eigen::Index n6 = G.cols(), tree = bm->m_tree;
  // The tree's motions: an orthonormal basis N of the null space of the tree's rows (they
  // are independent), from the QR of their transpose; the cut rows act on them as G_cut N.
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(G.topRows(tree).transpose());
  const Eigen::MatrixXd Q = qr.householderQ();
  const Eigen::MatrixXd N = Q.rightCols(n6 - tree);
  const LoopRank rank = RankOf(G.bottomRows(bm->cut_rows_all) * N);
  std::vector<BodyModel::CutRow> kept;
  for (int i : rank.independent) kept.push_back(bm->cut_rows[i]);
  bm->cut_rows = std::move(kept);
  bm->m = bm->m_tree + static_cast<int>(bm->cut_rows.size());
  return bm->cut_rows_all - static_cast<int>(bm->cut_rows.size());
}

bool IsPointRow(const BodyJoint& joint, int k) {
  return joint.type == JointType::kPrismatic ? k >= 3 : k < 3;
}

}  // namespace mbstream
