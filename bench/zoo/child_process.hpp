// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>
#include <vector>

namespace dvi::zoo {

struct ChildExit {
  int exit_code = -1;  ///< 128 + signal when a signal ended it.
  bool timed_out = false;
};

/// Runs argv[0] (a path) with stdout to /dev/null and stderr to
/// stderr_path; kills the child, by its pid, after timeout seconds.
ChildExit RunChild(const std::vector<std::string>& argv, const std::string& stderr_path,
                   double timeout);

}  // namespace dvi::zoo
