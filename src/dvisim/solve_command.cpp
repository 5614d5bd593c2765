// SPDX-License-Identifier: Apache-2.0
#include "solve_command.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <system_error>

#include "dvi/error.hpp"
#include "dvi/solve.hpp"

namespace dvi::dvisim {
namespace {

nlohmann::ordered_json IndicesToJson(const std::vector<int>& indices) {
  nlohmann::ordered_json array = nlohmann::ordered_json::array();
  for (const int i : indices) array.push_back(i);
  return array;
}

}  // namespace

SolveResult SolveProblemFile(const ProblemFile& file, const SolverOptions& options) {
  switch (file.type) {
    case ProblemType::kLcp:
      if (file.M.is_sparse) return Solve(SparseLcp{file.M.sparse, file.q}, options);
      return Solve(Lcp{file.M.dense, file.q}, options);
    case ProblemType::kMcp:
      if (file.M.is_sparse)
        return Solve(BoxMcp::Affine(file.M.sparse, file.q, file.lower, file.upper), options);
      return Solve(BoxMcp::Affine(file.M.dense, file.q, file.lower, file.upper), options);
    case ProblemType::kAvi:
      return Solve(Vi::Affine(file.M.ToDense(), file.q, file.set), options);
  }
  throw InvalidInputError("problem.type: unknown problem type");
}

nlohmann::ordered_json AnswerJson(const ProblemFile& file, const SolveResult& result) {
  nlohmann::ordered_json answer;
  if (!file.name.empty()) answer["name"] = file.name;
  answer["problem"] = ToString(file.type);
  answer["status"] = std::string(ToString(result.status));
  answer["message"] = result.message;
  answer["method"] = std::string(ToString(result.method));
  answer["residual"] = NumberToJson(result.residual);
  answer["iterations"] = result.iterations;
  answer["seconds"] = result.seconds;
  answer["z"] = VectorToJson(result.z);
  answer["w"] = VectorToJson(result.w);
  if (result.has_index_sets) {
    answer["alpha"] = IndicesToJson(result.index_sets.alpha);
    answer["beta"] = IndicesToJson(result.index_sets.beta);
    answer["gamma"] = IndicesToJson(result.index_sets.gamma);
  }
  if (result.status == SolveStatus::kInfeasible && result.certificate.size() > 0)
    answer["certificate"] = VectorToJson(result.certificate);
  return answer;
}

void WriteFileAtomically(const std::string& path, const std::string& contents) {
  const std::string temporary = path + ".tmp-" + std::to_string(::getpid());
  {
    std::ofstream stream(temporary, std::ios::binary | std::ios::trunc);
    if (!stream) throw InputError("--out " + path + ": cannot create (" + std::strerror(errno) + ")");
    stream << contents;
    stream.close();
    if (!stream) {
      std::error_code ignored;
      std::filesystem::remove(temporary, ignored);
      throw InputError("--out " + path + ": cannot write");
    }
  }
  std::error_code error;
  std::filesystem::rename(temporary, path, error);
  if (error) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw InputError("--out " + path + ": cannot replace (" + error.message() + ")");
  }
}

int RunSolve(const SolveCommand& command, std::ostream& out, std::ostream& err) {
  try {
    std::error_code ignored;
    if (!command.out_path.empty() &&
        std::filesystem::equivalent(command.out_path, command.problem_path, ignored))
      throw InputError("--out " + command.out_path +
                       ": is the problem file itself; the answer would replace the problem "
                       "(write it elsewhere)");
    const ProblemFile file = ReadProblemFile(command.problem_path);
    SolverOptions options;
    if (file.solver) options.method = *file.solver;
    if (file.tolerance) options.tolerance = *file.tolerance;
    if (command.solver) options.method = ReadSolver(*command.solver, "--solver");
    if (command.tolerance) options.tolerance = ReadTolerance(*command.tolerance, "--tol");
    const SolveResult result = SolveProblemFile(file, options);
    const std::string text = AnswerJson(file, result).dump(2) + "\n";
    if (command.out_path.empty()) {
      out << text << std::flush;
    } else {
      WriteFileAtomically(command.out_path, text);
    }
    return result.solved() ? kExitSolved : kExitNumericalFailure;
  } catch (const InputError& error) {
    err << "dvisim: " << error.what() << "\n";
  } catch (const InvalidInputError& error) {
    err << "dvisim: " << command.problem_path << ": " << error.what() << "\n";
  } catch (const std::exception& error) {
    // As in RunScene: a message, not std::terminate, should one get here.
    err << "dvisim: " << command.problem_path << ": the solve failed: " << error.what()
        << " (an internal error: please report it with the problem)\n";
    return kExitNumericalFailure;
  }
  return kExitBadInput;
}

}  // namespace dvi::dvisim
