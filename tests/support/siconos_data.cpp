// SPDX-License-Identifier: Apache-2.0
#include "support/siconos_data.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string_view>

namespace dvi::test {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// No instance of the suite is larger than a few hundred; a bigger size is a
// corrupt header, not a problem to allocate for.
constexpr int kMaxDimension = 100000;

// Whitespace-separated tokens with the line each starts on, for messages
// "FILE:LINE: ...".
class TokenReader {
 public:
  explicit TokenReader(const std::string& path) : path_(path) {
    std::ifstream file(path, std::ios::binary);
    if (!file) throw std::runtime_error(path + ": cannot open the file");
    std::ostringstream contents;
    contents << file.rdbuf();
    text_ = contents.str();
  }

  bool AtEnd() {
    SkipSpace();
    return pos_ >= text_.size();
  }

  int ReadInt(const std::string& what) {
    const std::string token = Next(what);
    char* end = nullptr;
    errno = 0;
    const long value = std::strtol(token.c_str(), &end, 10);
    if (*end != '\0' || errno != 0 || value < std::numeric_limits<int>::min() ||
        value > std::numeric_limits<int>::max())
      Fail("expected an integer for " + what + ", got '" + token + "'");
    return static_cast<int>(value);
  }

  int ReadSize(const std::string& what) {
    const int value = ReadInt(what);
    if (value < 0 || value > kMaxDimension)
      Fail(what + " is " + std::to_string(value) + ", expected 0.." +
           std::to_string(kMaxDimension));
    return value;
  }

  double ReadDouble(const std::string& what) {
    const std::string token = Next(what);
    char* end = nullptr;
    const double value = std::strtod(token.c_str(), &end);
    if (*end != '\0' || token.empty()) Fail("expected a number for " + what + ", got '" + token + "'");
    return value;
  }

  /// The numbers left in the file (none when only whitespace is left).
  Eigen::VectorXd ReadRemainingNumbers(const std::string& what) {
    std::vector<double> values;
    while (!AtEnd()) values.push_back(ReadDouble(what + "[" + std::to_string(values.size()) + "]"));
    return Eigen::Map<const Eigen::VectorXd>(values.data(), static_cast<Eigen::Index>(values.size()));
  }

  [[noreturn]] void Fail(const std::string& message) const {
    throw std::runtime_error(path_ + ":" + std::to_string(token_line_) + ": " + message);
  }

 private:
  void SkipSpace() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
  }

  std::string Next(const std::string& what) {
    SkipSpace();
    // At the end of the file the message points at the last line with data.
    if (pos_ >= text_.size()) Fail("unexpected end of file while reading " + what);
    token_line_ = line_;
    const std::size_t start = pos_;
    while (pos_ < text_.size() && !std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
    return text_.substr(start, pos_ - start);
  }

  std::string path_;
  std::string text_;
  std::size_t pos_ = 0;
  int line_ = 1;
  int token_line_ = 1;
};

std::string Entry(const std::string& name, Eigen::Index i, Eigen::Index j) {
  return name + "(" + std::to_string(i) + "," + std::to_string(j) + ")";
}

std::string Entry(const std::string& name, Eigen::Index i) {
  return name + "[" + std::to_string(i) + "]";
}

// NM_new_from_file for storage 0: "storage size0 size1", the sizes again,
// then the size0·size1 entries in column-major order.
Eigen::MatrixXd ReadMatrixBlock(TokenReader& in, const std::string& name) {
  const int storage = in.ReadInt(name + " storage type");
  if (storage != 0)
    in.Fail(name + " has storage type " + std::to_string(storage) +
            " (sparse); only dense storage (0) is read, use the dense twin of this file");
  const int rows = in.ReadSize(name + " rows");
  const int cols = in.ReadSize(name + " columns");
  const int rows_again = in.ReadSize(name + " rows (repeated)");
  const int cols_again = in.ReadSize(name + " columns (repeated)");
  if (rows_again != rows || cols_again != cols)
    in.Fail(name + " is declared " + std::to_string(rows) + "x" + std::to_string(cols) +
            " and then " + std::to_string(rows_again) + "x" + std::to_string(cols_again));
  Eigen::MatrixXd M(rows, cols);
  for (int j = 0; j < cols; ++j)
    for (int i = 0; i < rows; ++i) M(i, j) = in.ReadDouble(Entry(name, i, j));
  return M;
}

Eigen::VectorXd ReadVector(TokenReader& in, const std::string& name, int size) {
  Eigen::VectorXd v(size);
  for (int i = 0; i < size; ++i) v(i) = in.ReadDouble(Entry(name, i));
  return v;
}

Eigen::MatrixXd ReadRowMajor(TokenReader& in, const std::string& name, int rows, int cols) {
  Eigen::MatrixXd A(rows, cols);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) A(i, j) = in.ReadDouble(Entry(name, i, j));
  return A;
}

// "n", then an n×n M and q: how the LCP and the relay files begin.
struct SquareSystem {
  int n;
  Eigen::MatrixXd M;
  Eigen::VectorXd q;
};

SquareSystem ReadSquareSystem(TokenReader& in) {
  const int n = in.ReadSize("n");
  Eigen::MatrixXd M = ReadMatrixBlock(in, "M");
  if (M.rows() != n || M.cols() != n)
    in.Fail("M is " + std::to_string(M.rows()) + "x" + std::to_string(M.cols()) +
            ", expected " + std::to_string(n) + "x" + std::to_string(n));
  Eigen::VectorXd q = ReadVector(in, "q", n);
  return {n, std::move(M), std::move(q)};
}

template <typename Derived>
void RequireFinite(const TokenReader& in, const Eigen::MatrixBase<Derived>& A,
                   const std::string& name) {
  for (Eigen::Index j = 0; j < A.cols(); ++j)
    for (Eigen::Index i = 0; i < A.rows(); ++i)
      if (!std::isfinite(A(i, j)))
        in.Fail((A.cols() == 1 ? Entry(name, i) : Entry(name, i, j)) + " is not finite");
}

// The row blocks of storage 1: first rows 0 = r₀ < r₁ < … < r_k = n + m (the
// list ends at the first value ≥ n + m), then k flags 1 = complementarity,
// 0 = equality. Returns the lower bound of each variable: 0 or −inf.
Eigen::VectorXd ReadBlocks(TokenReader& in, int size) {
  std::vector<int> first_rows{in.ReadInt("blocksRows[0]")};
  if (first_rows[0] != 0) in.Fail("blocksRows[0] is " + std::to_string(first_rows[0]) + ", expected 0");
  while (first_rows.back() < size) {
    const int next = in.ReadInt(Entry("blocksRows", static_cast<Eigen::Index>(first_rows.size())));
    if (next <= first_rows.back() || next > size)
      in.Fail("blocksRows must increase up to n + m = " + std::to_string(size) + ", got " +
              std::to_string(next) + " after " + std::to_string(first_rows.back()));
    first_rows.push_back(next);
  }
  Eigen::VectorXd lower(size);
  for (std::size_t k = 0; k + 1 < first_rows.size(); ++k) {
    const int flag = in.ReadInt(Entry("blocksIsComp", static_cast<Eigen::Index>(k)));
    if (flag != 0 && flag != 1)
      in.Fail("blocksIsComp[" + std::to_string(k) + "] is " + std::to_string(flag) +
              ", expected 0 (equality) or 1 (complementarity)");
    lower.segment(first_rows[k], first_rows[k + 1] - first_rows[k])
        .setConstant(flag == 1 ? 0.0 : -kInf);
  }
  return lower;
}

SiconosMcpInstance MakeInstance(const std::string& path, Eigen::MatrixXd M, Eigen::VectorXd q,
                                Eigen::VectorXd lower, Eigen::VectorXd upper) {
  SiconosMcpInstance instance;
  instance.name = SiconosInstanceName(path);
  instance.mcp = BoxMcp::Affine(M, q, std::move(lower), std::move(upper));
  instance.M = std::move(M);
  instance.q = std::move(q);
  return instance;
}

}  // namespace

std::string SiconosDataDirectory() { return std::string(DVI_TEST_DATA_DIR) + "/siconos-4.4.0"; }

std::vector<std::string> SiconosDataFiles(const std::string& subdirectory) {
  std::vector<std::string> files;
  for (const auto& entry :
       std::filesystem::directory_iterator(SiconosDataDirectory() + "/" + subdirectory))
    if (entry.is_regular_file() && entry.path().extension() == ".dat")
      files.push_back(entry.path().string());
  std::sort(files.begin(), files.end());
  return files;
}

std::string SiconosInstanceName(const std::string& path) {
  return std::filesystem::path(path).stem().string();
}

SiconosLcpInstance ReadSiconosLcp(const std::string& path) {
  TokenReader in(path);
  SquareSystem lcp = ReadSquareSystem(in);
  RequireFinite(in, lcp.M, "M");
  RequireFinite(in, lcp.q, "q");
  return SiconosLcpInstance{SiconosInstanceName(path), Lcp{std::move(lcp.M), std::move(lcp.q)}};
}

SiconosMcpInstance ReadSiconosMlcp(const std::string& path) {
  TokenReader in(path);
  const int has_m = in.ReadInt("st1 (M storage present)");
  const int has_abcd = in.ReadInt("st2 (A, B, C, D storage present)");
  if ((has_m != 0 && has_m != 1) || (has_abcd != 0 && has_abcd != 1) || has_m + has_abcd == 0)
    in.Fail("st1 and st2 must be 0 or 1 and not both 0");
  const int n = in.ReadSize("n");
  const int m = in.ReadSize("m");
  const int size = n + m;
  if (size == 0) in.Fail("n + m is 0");

  Eigen::VectorXd block_lower;
  Eigen::MatrixXd M;
  Eigen::VectorXd q;
  if (has_m == 1) {
    block_lower = ReadBlocks(in, size);
    M = ReadMatrixBlock(in, "M");
    // Siconos reads as many q entries as M has columns.
    q = ReadVector(in, "q", static_cast<int>(M.cols()));
  }
  const bool m_is_square = has_m == 1 && M.rows() == size && M.cols() == size;
  if (has_m == 1 && !m_is_square && has_abcd == 0)
    in.Fail("M is " + std::to_string(M.rows()) + "x" + std::to_string(M.cols()) +
            ", expected order n + m = " + std::to_string(size));

  if (has_abcd == 1) {
    const Eigen::MatrixXd A = ReadRowMajor(in, "A", n, n);
    const Eigen::MatrixXd B = ReadRowMajor(in, "B", m, m);
    const Eigen::MatrixXd C = ReadRowMajor(in, "C", n, m);
    const Eigen::MatrixXd D = ReadRowMajor(in, "D", m, n);
    const Eigen::VectorXd a = ReadVector(in, "a", n);
    const Eigen::VectorXd b = ReadVector(in, "b", m);
    Eigen::MatrixXd abcd(size, size);
    abcd << A, C, D, B;
    Eigen::VectorXd ab(size);
    ab << a, b;
    if (m_is_square) {
      // Both storages are printed from the same doubles with 24 digits, so
      // they agree exactly or the file is inconsistent.
      for (int j = 0; j < size; ++j)
        for (int i = 0; i < size; ++i)
          if (M(i, j) != abcd(i, j))
            in.Fail("M(" + std::to_string(i) + "," + std::to_string(j) + ") = " +
                    std::to_string(M(i, j)) + " disagrees with the A, B, C, D blocks (" +
                    std::to_string(abcd(i, j)) + ")");
      if (q != ab) in.Fail("q disagrees with a, b");
    } else {
      M = std::move(abcd);
      q = std::move(ab);
      block_lower.resize(size);
      block_lower.head(n).setConstant(-kInf);
      block_lower.tail(m).setZero();
    }
  }
  RequireFinite(in, M, "M");
  RequireFinite(in, q, "q");

  const Eigen::VectorXd stored = in.ReadRemainingNumbers("stored solution");
  if (stored.size() != 0 && stored.size() != n + 2 * m - 1)
    in.Fail("the stored solution has " + std::to_string(stored.size()) +
            " values, expected n + 2m - 1 = " + std::to_string(n + 2 * m - 1));

  SiconosMcpInstance instance = MakeInstance(path, std::move(M), std::move(q), block_lower,
                                             Eigen::VectorXd::Constant(size, kInf));
  instance.num_equalities = static_cast<int>((block_lower.array() == -kInf).count());
  if (stored.size() != 0) {
    instance.stored_z_tail = stored.head(size - 1);
    instance.stored_w_complementary = stored.tail(m);
  }
  return instance;
}

SiconosMcpInstance ReadSiconosRelay(const std::string& path) {
  TokenReader in(path);
  SquareSystem relay = ReadSquareSystem(in);
  const int n = relay.n;
  Eigen::VectorXd lb = ReadVector(in, "lb", n);
  Eigen::VectorXd ub = ReadVector(in, "ub", n);
  RequireFinite(in, relay.M, "M");
  RequireFinite(in, relay.q, "q");
  for (int i = 0; i < n; ++i)
    if (!(lb(i) <= ub(i))) in.Fail("lb[" + std::to_string(i) + "] > ub[" + std::to_string(i) + "]");
  if (!in.AtEnd()) in.Fail("unexpected data after ub");
  return MakeInstance(path, std::move(relay.M), std::move(relay.q), std::move(lb), std::move(ub));
}

}  // namespace dvi::test
