// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>
#include <vector>

#include <Eigen/Dense>

#include "dvi/boundary_value.hpp"
#include "dvi/boundary_value_mcp.hpp"
#include "dvi/convex_set.hpp"
#include "dvi/vector_samples.hpp"

namespace dvi {

/// Player ν of the linear-quadratic differential Nash game of [Seed]
/// Sect. 4.2 (time-invariant data), with state x^ν ∈ ℝ^{n_ν} and control
/// u^ν ∈ U^ν ⊆ ℝ^{m_ν}:
///   minimize  x^ν(T)ᵀ[c^ν + Σ_ν' W^{νν'} x^{ν'}(T)]
///             + ∫₀ᵀ x^νᵀ[p^ν + Σ_ν' (P^{νν'} x^{ν'} + Q^{νν'} u^{ν'})]
///                 + u^νᵀ[q^ν + Σ_ν' (R^{νν'} x^{ν'} + S^{νν'} u^{ν'})] dt
///   subject to  x^ν' = r^ν + G^ν x^ν + H^ν u^ν,  x^ν(0) = x0,  u^ν(t) ∈ U^ν.
/// The blocks P, Q, R, S, W are listed per rival ν' in player order
/// (P[ν'] = P^{νν'}); an empty list means all zero, as does an empty r, p,
/// q or c. Players are numbered from 0.
struct NashPlayer {
  Eigen::VectorXd x0;  ///< n_ν = x0.size() ≥ 1.
  Eigen::MatrixXd G;   ///< n_ν × n_ν.
  Eigen::MatrixXd H;   ///< n_ν × m_ν (m_ν = H.cols() ≥ 1).
  Eigen::VectorXd r;   ///< n_ν.
  std::vector<Eigen::MatrixXd> P;  ///< n_ν × n_ν'.
  std::vector<Eigen::MatrixXd> Q;  ///< n_ν × m_ν'.
  std::vector<Eigen::MatrixXd> R;  ///< m_ν × n_ν'.
  std::vector<Eigen::MatrixXd> S;  ///< m_ν × m_ν'.
  Eigen::VectorXd p;   ///< n_ν.
  Eigen::VectorXd q;   ///< m_ν.
  Eigen::VectorXd c;   ///< n_ν.
  std::vector<Eigen::MatrixXd> W;  ///< n_ν × n_ν'.
  ConvexSet U = ConvexSet::Whole(0);  ///< U^ν, of dimension m_ν: box, polyhedron, ball.

  int n() const { return static_cast<int>(x0.size()); }
  int m() const { return static_cast<int>(H.cols()); }
};

/// The game's first-order conditions as the boundary-value DAVI (4.5) in
/// z = (λ, x):  z' = d + A z + B u,  u ∈ SOL(U, q + C z + S ·),
/// x(0) = x0,  λ(T) = c + W x(T), with (4.3)–(4.4)
///   d = (−p, r),  A = [−diag(G^νᵀ), −[P^{νν'}] − diag(P^{ννᵀ}); 0, diag(G^ν)],
///   B = [−[Q^{νν'}] − diag(R^{ννᵀ}); diag(H^ν)],
///   C = [diag(H^νᵀ), [R^{νν'}] + diag(Q^{ννᵀ})],  S = [S^{νν'}] + diag(S^{ννᵀ}),
///   W = [W^{νν'}] + diag(W^{ννᵀ}).
/// The transposes make these the exact gradients of the players' costs; the
/// paper writes diag(P^{νν}), diag(S^{νν}), diag(W^{νν}), the same for the
/// symmetric blocks Prop. 10.1 assumes.
struct NashDavi {
  Eigen::VectorXd d;  ///< 2n.
  Eigen::MatrixXd A;  ///< 2n × 2n.
  Eigen::MatrixXd B;  ///< 2n × m.
  Eigen::VectorXd q;  ///< m.
  Eigen::MatrixXd C;  ///< m × 2n.
  Eigen::MatrixXd S;  ///< m × m.
  ConvexSet U = ConvexSet::Whole(0);  ///< Π_ν U^ν.
  Eigen::VectorXd x0; ///< n.
  Eigen::VectorXd c;  ///< n.
  Eigen::MatrixXd W;  ///< n × n.
};

/// The hypotheses of Prop. 10.1 (existence of a solution of the discrete
/// system (a)–(e) for all small h): each U^ν a nonempty compact polyhedron,
/// W^{νν} and Ξ^ν = [2P^{νν}, Q^{νν} + R^{ννᵀ}; Q^{ννᵀ} + R^{νν}, 2S^{νν}]
/// (10.2) symmetric positive semidefinite; and S psd, which Theorem 7.1 adds
/// for convergence as h ↓ 0. Where they fail, each player's discrete problem
/// (10.1) may be nonconvex: a solution of (a)–(e) is then a point of the
/// first-order conditions (4.5), not necessarily a Nash equilibrium.
struct NashHypotheses {
  struct Player {
    bool w_symmetric = true;
    double w_min_eigenvalue = 0;   ///< Of W^{νν}'s symmetric part.
    bool xi_symmetric = true;
    double xi_min_eigenvalue = 0;  ///< Of Ξ^ν's symmetric part.
    /// U^ν a box with finite bounds: a compact polyhedron. A polyhedron's
    /// boundedness is not checked (false); a ball is not a polyhedron.
    bool u_compact_polyhedron = false;
  };
  std::vector<Player> players;
  double s_min_eigenvalue = 0;  ///< Of S's symmetric part.
  bool hold = true;             ///< W^{νν}, Ξ^ν symmetric psd for every ν and S psd.
  std::string text;             ///< One sentence for people, naming what fails.
};

/// The LQ differential Nash game of Sect. 4.2 from its players' data.
struct LqNashGame {
  std::vector<NashPlayer> players;

  int n() const;  ///< Σ n_ν.
  int m() const;  ///< Σ m_ν.
  /// @throws InvalidInputError naming the block ("players[1].P[0]: 2x3,
  /// expected 2x2 (n_1 × n_0)"), a non-finite entry, a missing player list,
  /// or U^ν of the wrong dimension.
  void Validate() const;
  /// (4.3)–(4.5).
  NashDavi Davi() const;
  /// Prop. 10.1's hypotheses, checked and described (never thrown).
  NashHypotheses CheckHypotheses() const;
};

struct NashSolution {
  /// states x (n), multipliers u (m), as for a BVP: x̂ᴴ piecewise linear,
  /// ûᴴ piecewise constant; the diagnostics of (9.5) for the boundary
  /// conditions in z = (λ, x) (Sect. 10 notes that the game needs no (9.5)).
  BoundaryValueSolution solution;
  /// λ at the same times (x̂ᴴ-style interpolation of λ^{h,i}).
  VectorSamples adjoints;
  NashHypotheses hypotheses;
};

/// Solves the game by the time-stepping scheme (a)–(e) of Sect. 10 — x
/// implicit, λ^{h,i} explicit in (a) and in the VI (c), u^{h,i+1} ∈ U —
/// as one aggregate VI (boundary_value_mcp.hpp). Options as for
/// SolveBoundaryValue, except that the scheme is fixed: theta must be 0
/// and scheme kImplicit. The hypotheses of Prop. 10.1 are reported, not
/// required: where they fail the game is solved anyway (see NashHypotheses).
/// @throws InvalidInputError on an invalid game, horizon or options.
NashSolution SolveNashGame(const LqNashGame& game, double horizon,
                           const BoundaryValueOptions& options = {});

/// The aggregate VI of SolveNashGame on `steps` steps, for other back-ends.
BoundaryValueMcp AssembleNashGameMcp(const LqNashGame& game, double horizon, long steps);

}  // namespace dvi
