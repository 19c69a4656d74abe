// Closed kinematic loops in body coordinates: each cut joint (server/model/loop_closure.h) is
// one more joint between two free bodies, with the constraint rows of its type (revolute,
// prismatic: 5; ball: 3), and the rows that are dependent on the others (a planar loop
// described with spatial revolutes) are dropped at the initial pose.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "server/body/body_model.h"
#include "server/drives/drive_set.h"
#include "server/model/loop_closure.h"
#include "server/model/model.h"

namespace mbstream {

// Throws InputError for a cut joint the body formulations do not model (fixed, or a joint
// coupling: a URDF <mimic>), naming it with FILE:LINE and saying what to use instead. A run's
// validation calls it up front.
void CheckBodyFormulationCloses(const std::vector<LoopClosure>& loops);

// Adds the cut joints of `loops` to `bm`, every row kept (SelectCutRows then keeps the
// independent ones). Throws InputError as CheckBodyFormulationCloses.
void AddCutJoints(const std::vector<LoopClosure>& loops, BodyModel* bm);

// Keeps the cut rows that are independent of the tree joints' rows and of each other at the
// joint pose q0 (the rank of the cut rows' Jacobian restricted to the tree's motions, by the
// column-pivoted QR of loop_solver.h's RankOf), and sets bm->m. Returns the rows dropped.
// Allocates (once, before a run).
int SelectCutRows(const Model& model, const DriveSet& drives, const Eigen::VectorXd& q0,
                  BodyModel* bm);

// Whether row k of `joint` is a position row (m; else an orientation row, rad): the joint
// point's rows of a revolute or ball joint, the axis-line rows of a prismatic one.
bool IsPointRow(const BodyJoint& joint, int k);

}  // namespace mbstream
