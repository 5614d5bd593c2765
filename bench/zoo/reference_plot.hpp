// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <filesystem>
#include <string>

#include "support/zoo/zoo_model.hpp"

namespace dvi::zoo {

/// Draws the exact solution with gnuplot (Debian gnuplot-nox, as dvisim's
/// plots): dir/<key>_reference.png, one panel per state, from 2001 samples
/// and both sides of every switch (kept in dir/<key>_reference.csv). For
/// every model, also where no method of dvisim runs.
void PlotReference(const ZooModel& model, const PiecewiseLinearReference& reference,
                   const std::filesystem::path& dir, const std::string& gnuplot);

}  // namespace dvi::zoo
