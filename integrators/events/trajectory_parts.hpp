// SPDX-License-Identifier: Apache-2.0
#pragma once

#include "dvi/trajectory.hpp"

namespace dvi::internal {

/// Appends a part of a run that starts where `whole` ends: samples (a
/// junction sample at the same time is replaced by the part's, whose u is
/// the right limit), dense output (and u between samples, each part by its
/// own rule: JoinedMultipliers), the certificate, events, step records and
/// statistics; the status and message become the part's. Intervals are the
/// caller's to merge.
void AppendPart(Trajectory& whole, Trajectory&& part);

/// Adds the work counters of `part` (steps, rejections, evaluations, VI
/// solves, iterations) to `sum`: a run repeated at a finer step (the
/// automatic driver's window check) reports the work of every attempt.
void AddWork(const IntegrationStats& part, IntegrationStats& sum);

}  // namespace dvi::internal
