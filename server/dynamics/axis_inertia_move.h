// The articulated-body algorithm's costliest step, for a revolute joint about coordinate axis
// K with an unrotated origin (axis_joint_steps.h): moving the projected articulated inertia
// Ia = IA - U U^T / D of the child to its parent, IA_parent += X^T Ia X (Featherstone,
// RBDA 7.3), with every product by a known zero left out at compile time:
//
// - only upper triangles are read and written (IA is symmetric: entries (r, q) with r <= q of
//   the 6x6 matrix, i.e. the two 3x3 diagonal blocks' upper triangles and the top-right
//   block, 21 of 36); the lower triangle of IA is not kept up to date (see aba_passes.h);
// - kFold (the joint's armature is 0, so D = U_K): Ia's row and column K are zero (Ia e_K =
//   U - U U_K / D = 0), which a rotation about K keeps: the angular block has 3 entries left,
//   the top-right block 6;
// - the shift by the joint's offset p uses [p]x's structure for p's offset shape L
//   (axis_joint::OffsetMayBeNonzero): p on one coordinate axis (most joints) has two nonzero
//   entries in [p]x instead of six, and p = 0 none (no shift at all).
//
// The values are the general path's but for rounding (kFold's zeros are exact where the
// general path leaves rounding residues; tests/server/parse/axis_kernels_test.cc holds them
// to 1e-12 relative). Internal to server/dynamics; allocates nothing.
#pragma once

#include <utility>

#include "server/dynamics/axis_joint_steps.h"

namespace mbstream::axis_joint {

// Calls f(std::integral_constant<int, 0>{}), ..., f(std::integral_constant<int, N - 1>{}), so
// that f's body can select terms with `if constexpr` on its index.
template <int N, typename F>
[[gnu::always_inline]] inline void Unroll(F&& f) {
  [&]<int... I>(std::integer_sequence<int, I...>) { (f(std::integral_constant<int, I>{}), ...); }
  (std::make_integer_sequence<int, N>{});
}

// Which entries of the move's intermediate 3x3 blocks may be nonzero (see the header comment).
template <int K, int L, bool kFold>
struct MoveStructure {
  // [p]x (r, k) = +-p_(3 - r - k) for r != k.
  static constexpr bool P(int r, int k) { return r != k && OffsetMayBeNonzero(L, 3 - r - k); }
  // The projected, rotated angular block A and top-right block B (C is full).
  static constexpr bool A(int r, int q) { return !(kFold && (r == K || q == K)); }
  static constexpr bool B(int r, int /*q*/) { return !(kFold && r == K); }
  // Q = [p]x C, T = [p]x B^T, W = Q [p]x^T.
  static constexpr bool Q(int r, int /*l*/) {
    for (int k = 0; k < 3; ++k) {
      if (P(r, k)) return true;
    }
    return false;
  }
  static constexpr bool T(int r, int q) {
    for (int k = 0; k < 3; ++k) {
      if (P(r, k) && B(q, k)) return true;
    }
    return false;
  }
  static constexpr bool W(int r, int q) {
    for (int l = 0; l < 3; ++l) {
      if (Q(r, l) && P(q, l)) return true;
    }
    return false;
  }
};

// sum += [p]x (r, k) * x, for [p]x (r, k) structurally nonzero.
template <int r, int k>
[[gnu::always_inline]] inline void AddSkewTerm(const double* p, double x, double& sum) {
  constexpr int m = 3 - r - k;
  if constexpr ((k - r + 3) % 3 == 2) {
    sum += p[m] * x;
  } else {
    sum -= p[m] * x;
  }
}

// IA_parent += X^T (IA - U U^T inv_D) X for X = (rotation r about K, offset p of shape L);
// reads IA's upper triangle, adds to IA_parent's upper triangle. kFold requires the joint's
// armature to be 0 (then D = U_K, inv_D = 1 / D). Also writes the bias force that goes with it,
// pa = pA + Ia c + U u / D, in the child's frame (c_K = c_(3 + K) = 0).
template <int K, int L, bool kFold>
[[gnu::always_inline]] inline void AddProjectedInertiaToParent(AxisRotation rot, const double* p,
                                                               const Matrix6d& IA, const double* U,
                                                               double inv_D, const double* pA,
                                                               const double* c_vel, double u,
                                                               double* pa, Matrix6d* IA_parent) {
  using S = MoveStructure<K, L, kFold>;
  constexpr int i = (K + 1) % 3, j = (K + 2) % 3;
  const double c = rot.c, s = rot.s;
  // Ia's blocks [A B; B^T C] in the child's frame (A, C symmetric, both halves filled).
  double w[6];
  Unroll<6>([&](auto e) { w[e] = U[e] * inv_D; });
  const double* ia = IA.data();  // column-major: (r, q) at r + 6 q
  double A[3][3], B[3][3], C[3][3];
  Unroll<3>([&](auto r) {
    Unroll<3>([&](auto q) {
      if constexpr (r <= q && S::A(r, q)) {
        A[r][q] = ia[r + 6 * q] - w[r] * U[q];
        if constexpr (r != q) A[q][r] = A[r][q];
      }
      if constexpr (S::B(r, q)) B[r][q] = ia[r + 6 * (3 + q)] - w[r] * U[3 + q];
      if constexpr (r <= q) {
        C[r][q] = ia[3 + r + 6 * (3 + q)] - w[3 + r] * U[3 + q];
        if constexpr (r != q) C[q][r] = C[r][q];
      }
    });
  });
  // pa = pA + Ia c + U (u / D), Ia read from its blocks (zero where kFold made it so).
  {
    constexpr int cols[4] = {i, j, 3 + i, 3 + j};
    const double uD = u * inv_D;
    Unroll<6>([&](auto e) {
      double sum = -0.0;  // x + -0.0 folds to x
      Unroll<4>([&](auto n) {
        constexpr int col = cols[n];
        if constexpr (e < 3 && col < 3) {
          if constexpr (S::A(e, col)) sum += A[e][col] * c_vel[col];
        } else if constexpr (e < 3) {
          if constexpr (S::B(e, 0)) sum += B[e][col - 3] * c_vel[col];
        } else if constexpr (col < 3) {
          sum += B[col][e - 3] * c_vel[col];  // col is i or j: never a zero row
        } else {
          sum += C[e - 3][col - 3] * c_vel[col];
        }
      });
      pa[e] = (pA[e] + U[e] * uD) + sum;
    });
  }
  // Rotated into the parent's orientation: X R X^T for the symmetric blocks (kFold: A's row
  // and column K are zero and stay so), R B R^T for B.
  const double cs = c * s, c2 = c * c, s2 = s * s;
  auto rotate_symmetric = [&]<bool kKEntries>(double(&x)[3][3]) {
    const double ii = x[i][i], jj = x[j][j], ij = x[i][j];
    if constexpr (kKEntries) {
      const double ki = x[K][i], kj = x[K][j];
      x[K][i] = x[i][K] = c * ki - s * kj;
      x[K][j] = x[j][K] = s * ki + c * kj;
    }
    x[i][i] = c2 * ii - 2.0 * cs * ij + s2 * jj;
    x[j][j] = s2 * ii + 2.0 * cs * ij + c2 * jj;
    x[i][j] = x[j][i] = cs * (ii - jj) + (c2 - s2) * ij;
  };
  rotate_symmetric.template operator()<!kFold>(A);
  rotate_symmetric.template operator()<true>(C);
  Unroll<3>([&](auto q) {
    const double bi = B[i][q], bj = B[j][q];
    B[i][q] = c * bi - s * bj;
    B[j][q] = s * bi + c * bj;
  });
  Unroll<3>([&](auto r) {
    if constexpr (S::B(r, 0)) {
      const double bi = B[r][i], bj = B[r][j];
      B[r][i] = c * bi - s * bj;
      B[r][j] = s * bi + c * bj;
    }
  });
  // Shifted from the child's origin to the parent's by p (see AddInertiaToParent):
  //   TL += A + T + T^T + W, TR += B + Q, BR += C.
  double Q[3][3], T[3][3];
  Unroll<3>([&](auto r) {
    Unroll<3>([&](auto q) {
      double q_sum = -0.0, t_sum = -0.0;  // x + -0.0 folds to x
      Unroll<3>([&](auto k) {
        if constexpr (S::P(r, k)) {
          AddSkewTerm<r, k>(p, C[k][q], q_sum);
          if constexpr (S::B(q, k)) AddSkewTerm<r, k>(p, B[q][k], t_sum);
        }
      });
      Q[r][q] = q_sum;
      T[r][q] = t_sum;
    });
  });
  double* out = IA_parent->data();
  Unroll<3>([&](auto r) {
    Unroll<3>([&](auto q) {
      if constexpr (r <= q && (S::A(r, q) || S::T(r, q) || S::T(q, r) || S::W(r, q))) {
        double tl = -0.0;
        if constexpr (S::A(r, q)) tl = A[r][q];
        if constexpr (S::T(r, q)) tl += T[r][q];
        if constexpr (S::T(q, r)) tl += T[q][r];
        if constexpr (S::W(r, q)) {
          double w_sum = -0.0;
          Unroll<3>([&](auto l) {
            if constexpr (S::Q(r, l) && S::P(q, l)) AddSkewTerm<q, l>(p, Q[r][l], w_sum);
          });
          tl += w_sum;
        }
        out[r + 6 * q] += tl;
      }
      if constexpr (S::B(r, q) || S::Q(r, q)) {
        double tr = -0.0;
        if constexpr (S::B(r, q)) tr = B[r][q];
        if constexpr (S::Q(r, q)) tr += Q[r][q];
        out[r + 6 * (3 + q)] += tr;
      }
      if constexpr (r <= q) out[3 + r + 6 * (3 + q)] += C[r][q];
    });
  });
}

}  // namespace mbstream::axis_joint
