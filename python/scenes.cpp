// SPDX-License-Identifier: Apache-2.0
// Scenes (docs/scenes.md) from a JSON file or a dict, run as `dvisim run`
// runs them: the same reader, overrides, limits and integration
// (src/dvisim's dvisim_scenes library), the same trajectory.csv and
// summary.json as text and dict. A malformed scene raises
// dvi.InvalidInputError with dvisim's message, which names the field.
#include <optional>
#include <string>
#include <utility>

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "dvi/trajectory.hpp"
#include "json_reading.hpp"
#include "run_command.hpp"
#include "scene_file.hpp"
#include "scene_limits.hpp"
#include "scene_run.hpp"

namespace dvi::python {
namespace {

using dvisim::BoundaryValueReport;
using dvisim::InputError;
using dvisim::Scene;

// dvisim's InputError (a field's mistake) as dvi.InvalidInputError.
template <typename Read>
auto NamingTheField(Read read) -> decltype(read()) {
  try {
    return read();
  } catch (const InputError& error) {
    throw InvalidInputError(error.what());
  }
}

// A scene run: the trajectory and what `dvisim run` writes of it.
struct SceneRun {
  Scene scene;
  Trajectory trajectory;
  std::optional<BoundaryValueReport> report;

  const BoundaryValueReport* Report() const { return report ? &*report : nullptr; }
};

// `dvisim run`'s overrides (--method, --h, ...), checked as there; the
// scene's limits; the run with the GIL released (a scene calls no Python).
SceneRun Run(const Scene& scene, const std::string& source, const dvisim::RunCommand& overrides) {
  SceneRun run{scene, {}, {}};
  NamingTheField([&] {
    dvisim::ApplyOverrides(overrides, run.scene);
    try {
      dvisim::CheckSceneLimits(run.scene);
    } catch (const InputError& error) {
      throw InputError(source + ": " + error.what());
    }
    py::gil_scoped_release released_here;
    run.trajectory = dvisim::RunSceneMethod(run.scene, source, run.report);
    return 0;
  });
  return run;
}

// nlohmann's JSON as Python objects, through the json module (the summary
// is small; its "inf"/"nan" strings stay strings, as in summary.json).
py::object ToPython(const nlohmann::ordered_json& value) {
  return py::module_::import("json").attr("loads")(value.dump());
}

}  // namespace

void BindScenes(py::module_& module) {
  // A scene keeps where it came from, to name it in messages as dvisim does.
  struct PyScene {
    Scene scene;
    std::string source;
  };
  py::class_<PyScene>(module, "Scene",
                      "A dvisim scene (docs/scenes.md), run with dvisim's integrators and options")
      .def_static(
          "from_json",
          [](const std::string& path) {
            return PyScene{NamingTheField([&] { return dvisim::ReadScene(path); }), path};
          },
          py::arg("path"), "Reads a scene file; InvalidInputError names the file and the field")
      .def_static(
          "from_dict",
          [](const py::dict& fields) {
            const std::string text = py::str(py::module_::import("json").attr("dumps")(fields));
            return PyScene{NamingTheField([&] { return dvisim::ParseScene(text); }), "scene"};
          },
          py::arg("fields"), "A scene from a dict of the file's fields")
      .def_property_readonly("name", [](const PyScene& s) { return s.scene.name; })
      .def_property_readonly("type", [](const PyScene& s) { return s.scene.type; })
      .def_property_readonly("n", [](const PyScene& s) { return s.scene.n; })
      .def_property_readonly("x0", [](const PyScene& s) { return s.scene.x0; })
      .def_property_readonly("horizon", [](const PyScene& s) { return s.scene.horizon; })
      .def_property_readonly("method",
                             [](const PyScene& s) { return std::string(ToString(s.scene.method)); })
      .def_property_readonly("output_times",
                             [](const PyScene& s) { return dvisim::OutputTimes(s.scene); })
      .def_property_readonly("has_exact",
                             [](const PyScene& s) { return s.scene.exact.has_value(); })
      .def(
          "exact",
          [](const PyScene& s, double t) {
            if (!s.scene.exact) throw InvalidInputError(s.source + ": the scene has no exact block");
            return s.scene.exact->State(t);
          },
          py::arg("t"), "x(t) of the scene's exact block")
      .def(
          "run",
          [](const PyScene& s, std::optional<std::string> method, std::optional<double> h,
             std::optional<double> theta, std::optional<double> gamma, std::optional<double> rtol,
             std::optional<double> atol, std::optional<double> h_max) {
            dvisim::RunCommand overrides;
            overrides.scene_path = s.source;
            overrides.method = std::move(method);
            overrides.h = h;
            overrides.theta = theta;
            overrides.gamma = gamma;
            overrides.rtol = rtol;
            overrides.atol = atol;
            overrides.h_max = h_max;
            return Run(s.scene, s.source, overrides);
          },
          py::kw_only(), py::arg("method") = py::none(), py::arg("h") = py::none(),
          py::arg("theta") = py::none(), py::arg("gamma") = py::none(),
          py::arg("rtol") = py::none(), py::arg("atol") = py::none(),
          py::arg("h_max") = py::none(),
          "Runs the scene as `dvisim run` does; the keywords are its --method, --h, --theta, "
          "--gamma, --rtol, --atol, --h-max (method.max_wall is not applied)");

  py::class_<SceneRun>(module, "SceneRun",
                       "A scene's run: its Trajectory and dvisim's trajectory.csv and summary.json")
      .def_readonly("trajectory", &SceneRun::trajectory)
      .def_property_readonly("multipliers",
                             [](const SceneRun& run) {
                               // trajectory.csv's u columns, one row per sample.
                               Eigen::MatrixXd rows(static_cast<Eigen::Index>(run.trajectory.multipliers.size()),
                                                    run.scene.output_multipliers);
                               for (std::size_t k = 0; k < run.trajectory.multipliers.size(); ++k)
                                 rows.row(static_cast<Eigen::Index>(k)) =
                                     dvisim::OutputMultiplier(run.scene,
                                                              run.trajectory.multipliers[k])
                                         .transpose();
                               return rows;
                             },
                             "The u columns of trajectory.csv (s for filippov, ν for pds)")
      .def_property_readonly("csv",
                             [](const SceneRun& run) {
                               return dvisim::TrajectoryCsv(run.scene, run.trajectory, run.Report());
                             },
                             "trajectory.csv as dvisim writes it")
      .def_property_readonly(
          "summary",
          [](const SceneRun& run) {
            return ToPython(dvisim::SummaryJson(run.scene, run.trajectory, run.Report()));
          },
          "summary.json as dvisim writes it, as a dict");
}

}  // namespace dvi::python
