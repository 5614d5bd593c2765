// SPDX-License-Identifier: Apache-2.0
#pragma once

/// Umbrella header of dvi: everything a user of the library needs.
#include "dvi/complementarity_problem.hpp"
#include "dvi/convex_set.hpp"
#include "dvi/dvi_problem.hpp"
#include "dvi/error.hpp"
#include "dvi/event_driven.hpp"
#include "dvi/filippov.hpp"
#include "dvi/lcs.hpp"
#include "dvi/lemke.hpp"
#include "dvi/matrix_classes.hpp"
#include "dvi/polyhedral_vi.hpp"
#include "dvi/projected_dynamics.hpp"
#include "dvi/projected_gauss_seidel.hpp"
#include "dvi/projection_method.hpp"
#include "dvi/semismooth_newton.hpp"
#include "dvi/solution_diagnostics.hpp"
#include "dvi/solve.hpp"
#include "dvi/solve_result.hpp"
#include "dvi/solver_options.hpp"
#include "dvi/time_stepping.hpp"
#include "dvi/trajectory.hpp"
