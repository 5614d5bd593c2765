// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstddef>
#include <functional>

namespace dvi::dvisim {

/// Runs job(0) … job(count − 1) on up to `workers` threads (in this thread
/// when workers ≤ 1), each index once, and calls done() after each job, one
/// call at a time. A job writes only its own result slot, so the results do
/// not depend on the number of workers. The first exception a job throws is
/// rethrown here once every thread has stopped; the jobs not yet started
/// are then skipped.
void RunJobs(std::size_t count, int workers, const std::function<void(std::size_t)>& job,
             const std::function<void()>& done);

}  // namespace dvi::dvisim
