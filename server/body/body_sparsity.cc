// The known sparsity of the body DAE's iteration matrix, block by block.
#include <algorithm>
#include <set>

#include "server/body/body_dae.h"

namespace mbstream {

namespace {

class Pattern {
 public:
  explicit Pattern(int size) : columns_(size) {}
  void Add(int row, int col) { columns_[col].insert(row); }
  // Every (row0 + i, col0 + k), i < rows, k < cols.
  void Dense(int row0, int rows, int col0, int cols) {
    for (int i = 0; i < rows; ++i) {
      for (int k = 0; k < cols; ++k) Add(row0 + i, col0 + k);
    }
  }
  void Diagonal(int row0, int col0, int count) {
    for (int i = 0; i < count; ++i) Add(row0 + i, col0 + i);
  }
  void Write(std::vector<int>* starts, std::vector<int>* rows) const {
    starts->assign(1, 0);
    rows->clear();
    for (const std::set<int>& column : columns_) {
      rows->insert(rows->end(), column.begin(), column.end());
      starts->push_back(static_cast<int>(rows->size()));
    }
  }

 private:
  std::vector<std::set<int>> columns_;
};

}  // namespace

void BodyDaePattern(const BodyModel& bm, ConstraintLevel level, std::vector<int>* column_starts,
                    std::vector<int>* row_indices) {
  Pattern p(bm.dae_size());
  for (int b = 0; b < bm.n; ++b) {
    const int x = BodyModel::position(b), e = BodyModel::quaternion(b);
    const int v = bm.velocity(b), w = bm.omega(b);
    // dx/dt - v: x (cj), v.
    p.Diagonal(x, x, 3);
    p.Diagonal(x, v, 3);
    // de/dt - rate(e, w): e, w.
    p.Dense(e, 4, e, 4);
    p.Dense(e, 4, w, 3);
    // Newton: m dv/dt (cj). Euler: w (inertia, gyroscopic), e (constraint torques in body
    // axes).
    p.Diagonal(v, v, 3);
    p.Dense(w, 3, w, 3);
    p.Dense(w, 3, e, 4);
  }
  for (const BodyJoint& joint : bm.joints) {
    const int b = joint.child, par = joint.parent;
    const bool has_parent = par != kBase;
    const int lambda = bm.multiplier(joint.row);
    // The bodies' columns: x, e (positions, 7) and v, w (velocities, 6) of child and parent.
    const int bodies[2] = {b, has_parent ? par : -1};
    if (joint.type == JointType::kPrismatic) {
      // The constraint forces and joint forces of a prismatic joint act at lever arms that
      // depend on both bodies' positions: every force row of both bodies depends on every
      // state of both and on all the joint's multipliers.
      for (int rb : bodies) {
        if (rb < 0) continue;
        for (int cb : bodies) {
          if (cb < 0) continue;
          p.Dense(bm.velocity(rb), 6, BodyModel::position(cb), 7);
          p.Dense(bm.velocity(rb), 6, bm.velocity(cb), 6);
        }
        p.Dense(bm.velocity(rb), 6, lambda, joint.rows);
      }
      for (int cb : bodies) {
        if (cb < 0) continue;
        p.Dense(lambda, joint.rows, BodyModel::position(cb), 7);
        if (level == ConstraintLevel::kVelocity) p.Dense(lambda, joint.rows, bm.velocity(cb), 6);
      }
      continue;
    }
    // Revolute. Newton rows: the joint-point multipliers (+- identity). Euler rows: all the
    // joint's multipliers, and the other body's e and w (constraint directions, joint rate,
    // armature).
    p.Diagonal(bm.velocity(b), lambda, 3);
    p.Dense(bm.omega(b), 3, lambda, joint.rows);
    if (has_parent) {
      p.Diagonal(bm.velocity(par), lambda, 3);
      p.Dense(bm.omega(par), 3, lambda, joint.rows);
      p.Dense(bm.omega(b), 3, BodyModel::quaternion(par), 4);
      p.Dense(bm.omega(b), 3, bm.omega(par), 3);
      p.Dense(bm.omega(par), 3, BodyModel::quaternion(b), 4);
      p.Dense(bm.omega(par), 3, bm.omega(b), 3);
    }
    // Constraint rows: both orientations; the point rows also the positions (index 3) or
    // the velocities (index 2); at index 2 every row also the angular velocities.
    p.Dense(lambda, joint.rows, BodyModel::quaternion(b), 4);
    if (has_parent) p.Dense(lambda, joint.rows, BodyModel::quaternion(par), 4);
    if (level == ConstraintLevel::kPosition) {
      p.Diagonal(lambda, BodyModel::position(b), 3);
      if (has_parent) p.Diagonal(lambda, BodyModel::position(par), 3);
    } else {
      p.Diagonal(lambda, bm.velocity(b), 3);
      p.Dense(lambda, joint.rows, bm.omega(b), 3);
      if (has_parent) {
        p.Diagonal(lambda, bm.velocity(par), 3);
        p.Dense(lambda, joint.rows, bm.omega(par), 3);
      }
    }
  }
  // The kept cut rows: dense in both bodies' states, and both bodies' force rows in the
  // row's multiplier and in both bodies' positions (lever arms and directions).
  for (size_t i = 0; i < bm.cut_rows.size(); ++i) {
    const BodyJoint& cut = bm.cuts[bm.cut_rows[i].cut];
    const int lambda = bm.multiplier(bm.m_tree + static_cast<int>(i));
    const int bodies[2] = {cut.child, cut.parent};
    for (int rb : bodies) {
      if (rb == kBase) continue;
      p.Dense(lambda, 1, BodyModel::position(rb), 7);
      if (level == ConstraintLevel::kVelocity) p.Dense(lambda, 1, bm.velocity(rb), 6);
      p.Dense(bm.velocity(rb), 6, lambda, 1);
      for (int cb : bodies) {
        if (cb != kBase) p.Dense(bm.velocity(rb), 6, BodyModel::position(cb), 7);
      }
    }
  }
  p.Write(column_starts, row_indices);
}

}  // namespace mbstream
