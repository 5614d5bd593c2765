// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>
#include <vector>

#include <Eigen/Dense>

#include "dvi/complementarity_problem.hpp"

namespace dvi::test {

/// Readers for the instances of Siconos 4.4.0's numerics test suite in
/// tests/data/siconos-4.4.0/ (formats in its README.md). They read what
/// Siconos' own readers read (linearComplementarity_newFromFile,
/// mixedLinearComplementarity_newFromFile, relay_newFromFile with
/// NM_new_from_file for the matrices): whitespace-separated tokens, dense
/// matrices stored column-major, the A, B, C, D blocks of an MLCP row-major.
/// Every reader throws std::runtime_error("FILE:LINE: what was expected") on
/// a malformed file.

/// tests/data/siconos-4.4.0.
std::string SiconosDataDirectory();
/// The *.dat files of SiconosDataDirectory()/subdirectory ("lcp", "mlcp",
/// "relay"), sorted by name.
std::vector<std::string> SiconosDataFiles(const std::string& subdirectory);
/// The file name without its directory and ".dat" ("lcp_CPS_1").
std::string SiconosInstanceName(const std::string& path);

struct SiconosLcpInstance {
  std::string name;
  Lcp lcp;
};

/// An lcp/*.dat file: n, then the matrix block (storage 0 = dense only; the
/// *_block files in sparse-block storage are rejected), then q. Text after q
/// is a comment.
SiconosLcpInstance ReadSiconosLcp(const std::string& path);

/// An MLCP or relay problem as the box MCP z ∈ [lower, upper], w = M z + q
/// (mcp holds BoxMcp::Affine of the same data).
struct SiconosMcpInstance {
  std::string name;
  Eigen::MatrixXd M;
  Eigen::VectorXd q;
  BoxMcp mcp;
  /// MLCP: the number n of free variables with equality rows (z_i free,
  /// w_i = 0); the other m are complementary (0 ≤ z_i ⊥ w_i ≥ 0). Relay: 0.
  int num_equalities = 0;
  /// MLCP files that append a solution hold n + 2m − 1 values printed with
  /// six decimals: z without its first entry, then the m complementary
  /// entries of w (Siconos' test driver reads n + 2m and so runs past the
  /// data). Empty when the file has none.
  Eigen::VectorXd stored_z_tail;
  Eigen::VectorXd stored_w_complementary;
};

/// An mlcp/*.dat file: "st1 st2 n m"; when st1 = 1 the row blocks (their
/// first rows up to n + m, then 1 = complementarity / 0 = equality per
/// block), the matrix M and q; when st2 = 1 the blocks A (n×n), B (m×m),
/// C (n×m), D (m×n), a, b of [[A, C], [D, B]] z + (a; b); then an optional
/// stored solution. When both are present they must agree exactly (they are
/// printed from the same numbers). A file whose M block is not of order
/// n + m (Rectangular_mlcp: 3×2 for n = m = 1) is read from A, B, C, D.
SiconosMcpInstance ReadSiconosMlcp(const std::string& path);

/// A relay/*.dat file: n, the matrix block, q, lb, ub; the box MCP on
/// [lb, ub] (−(M z + q) ∈ N_[lb,ub](z)).
SiconosMcpInstance ReadSiconosRelay(const std::string& path);

}  // namespace dvi::test
