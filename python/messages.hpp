// SPDX-License-Identifier: Apache-2.0
#pragma once

// dvi's messages in the module's names. The library's InvalidInputError
// names C++ things (AdvanceTo, AutoOptions.event.rtol, SolverOptions::
// tolerance, x0(0)) for C++ callers; a Python caller gets the keyword, the
// method and the index it wrote (advance_to, rtol, solver_tolerance,
// x0[0]), and the function it called. The C++ messages stay as they are.
#include <initializer_list>
#include <string>
#include <string_view>
#include <utility>

#include "dvi/error.hpp"

namespace dvi::python {

/// message with each C++ name replaced by its Python one (module.cpp's
/// translation of every InvalidInputError).
std::string PythonMessage(std::string message);

/// Names of one function's own, replaced before PythonMessage's.
using Renames = std::initializer_list<std::pair<std::string_view, std::string_view>>;

/// message with `renames` applied, prefixed with "function: " unless it
/// starts so already.
std::string NamingFunction(std::string_view function, std::string message, Renames renames = {});

/// call(); an InvalidInputError from it is thrown again naming `function`
/// (integrate_event, EventDrivenIntegrator ...), the Python function the
/// caller called, with `renames` applied.
template <typename Call>
decltype(auto) CallNaming(const char* function, Call&& call, Renames renames = {}) {
  try {
    return call();
  } catch (const InvalidInputError& error) {
    throw InvalidInputError(NamingFunction(function, error.what(), renames));
  }
}

}  // namespace dvi::python
