// coopdyn._experiments: the example programs' experiments as functions (docs/python.md, "The
// experiments"), built only where MuJoCo and nlohmann-json are found (python/CMakeLists.txt): the
// library and the main module _coopdyn stay free of both. coopdyn/experiments.py wraps it.
#include "columns.hpp"

#include "common/files.hpp"
#include "common/json_reader.hpp"

#include <exception>

PYBIND11_MODULE(_experiments, module)
{
    namespace py = pybind11;
    module.doc() = "The dual-arm box and two-arm beam experiments; use coopdyn.experiments (docs/python.md).";
    // A scenario file the loader refuses is a ValueError; a file that cannot be read, an OSError:
    // the programs' exit codes 3 and 4 (examples/common/cli.hpp).
    py::register_local_exception_translator([](std::exception_ptr pointer) {
        try {
            if (pointer) {
                std::rethrow_exception(pointer);
            }
        } catch (const example_common::ScenarioError& error) {
            PyErr_SetString(PyExc_ValueError, (std::string("invalid scenario: ") + error.what()).c_str());
        } catch (const example_common::FileError& error) {
            PyErr_SetString(PyExc_OSError, error.what());
        }
    });
    coopdyn::python::experiments::bind_box(module);
    coopdyn::python::experiments::bind_beam(module);
}
