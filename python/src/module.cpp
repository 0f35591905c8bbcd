// The module coopdyn._coopdyn (re-exported by the package coopdyn, python/coopdyn/__init__.py):
// the library's exceptions and the checked conversions every binding uses (common.hpp).
#include "common.hpp"

#include <coopdyn/errors.hpp>

#include <sstream>

namespace coopdyn::python {

namespace {

// The Python exception types, created once at import and never freed (the module owns them too).
PyObject* error_type = nullptr;
PyObject* invalid_model_type = nullptr;
PyObject* invalid_argument_type = nullptr;

PyObject* new_exception(py::module_& module, const char* name, PyObject* base, const char* doc)
{
    const std::string qualified = std::string("coopdyn.") + name;
    PyObject* type = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, base, nullptr);
    if (type == nullptr) {
        throw py::error_already_set();
    }
    module.add_object(name, py::handle(type));  // a new reference for the module; ours stays
    return type;
}

/// Raises `type` with the message and the fields component, parameter, problem, arm (None for
/// no arm) of the C++ exception.
void raise_error(PyObject* type, const Error& error)
{
    const py::object instance = py::reinterpret_borrow<py::object>(type)(error.what());
    instance.attr("component") = error.component();
    instance.attr("parameter") = error.parameter();
    instance.attr("problem") = error.problem();
    instance.attr("arm") = error.has_arm() ? py::object(py::int_(error.arm())) : py::object(py::none());
    PyErr_SetObject(type, instance.ptr());
}

std::string shape_text(const py::array& array)
{
    std::ostringstream text;
    text << '(';
    for (py::ssize_t k = 0; k < array.ndim(); ++k) {
        text << (k > 0 ? ", " : "") << array.shape(k);
    }
    text << (array.ndim() == 1 ? ",)" : ")");
    return text.str();
}

using DoubleArray = py::array_t<double, py::array::forcecast>;

DoubleArray as_double_array(py::handle value, const char* function, const char* name, const char* expected)
{
    DoubleArray array = DoubleArray::ensure(value);
    if (!array) {
        fail_argument(function, name,
                      std::string("must be a real array of shape ") + expected + ", got a " +
                          std::string(py::str(py::type::handle_of(value).attr("__name__"))));
    }
    return array;
}

}  // namespace

void fail_argument(const char* function, const char* name, const std::string& problem)
{
    throw InvalidArgument(function, name, no_arm, problem);
}

Matrix to_matrix(py::handle value, const char* function, const char* name, Index rows, Index cols,
                 const char* expected)
{
    const DoubleArray array = as_double_array(value, function, name, expected);
    if (array.ndim() != 2 || (rows != any_size && array.shape(0) != rows) ||
        (cols != any_size && array.shape(1) != cols)) {
        fail_argument(function, name,
                      std::string("must be an array of shape ") + expected + ", got shape " + shape_text(array));
    }
    const auto view = array.unchecked<2>();  // honours any strides and memory order
    Matrix matrix(view.shape(0), view.shape(1));
    for (Index j = 0; j < matrix.cols(); ++j) {
        for (Index i = 0; i < matrix.rows(); ++i) {
            matrix(i, j) = view(i, j);
        }
    }
    return matrix;
}

Vector to_vector(py::handle value, const char* function, const char* name, Index size, const char* expected)
{
    const DoubleArray array = as_double_array(value, function, name, expected);
    if (array.ndim() != 1 || (size != any_size && array.shape(0) != size)) {
        fail_argument(function, name,
                      std::string("must be an array of shape ") + expected + ", got shape " + shape_text(array));
    }
    const auto view = array.unchecked<1>();
    Vector vector(view.shape(0));
    for (Index i = 0; i < vector.size(); ++i) {
        vector(i) = view(i);
    }
    return vector;
}

namespace {

void mark_read_only(py::array& array)
{
    py::detail::array_proxy(array.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
}

}  // namespace

py::array matrix_copy(const Eigen::Ref<const Matrix>& matrix, bool read_only)
{
    py::array_t<double> array({matrix.rows(), matrix.cols()});
    auto view = array.mutable_unchecked<2>();
    for (Index i = 0; i < matrix.rows(); ++i) {
        for (Index j = 0; j < matrix.cols(); ++j) {
            view(i, j) = matrix(i, j);
        }
    }
    if (read_only) {
        mark_read_only(array);
    }
    return std::move(array);
}

py::array vector_copy(const Eigen::Ref<const Vector>& vector, bool read_only)
{
    py::array_t<double> array(vector.size());
    auto view = array.mutable_unchecked<1>();
    for (Index i = 0; i < vector.size(); ++i) {
        view(i) = vector(i);
    }
    if (read_only) {
        mark_read_only(array);
    }
    return std::move(array);
}

Eigen::Quaterniond quaternion_from(py::handle value, const char* owner, const char* name)
{
    const Vector q = to_vector(value, owner, name, 4, "(4,) = [x, y, z, w]");
    return Eigen::Quaterniond(q(3), q(0), q(1), q(2));
}

py::array quaternion_array(const Eigen::Quaterniond& q, bool read_only)
{
    return vector_copy(q.coeffs(), read_only);
}

void bind_errors(py::module_& module)
{
    error_type = new_exception(module, "Error", PyExc_ValueError,
                               "Base of coopdyn's exceptions (a ValueError). Fields: component (what was being "
                               "built or called), parameter (the argument's name as spelled in the API), problem, "
                               "arm (the arm's or contact's index, or None). docs/conventions.md, \"Errors\".");
    invalid_model_type = new_exception(module, "InvalidModel", error_type,
                                       "A model parameter was refused when a model was built (C++ "
                                       "coopdyn::InvalidModel).");
    invalid_argument_type = new_exception(module, "InvalidArgument", error_type,
                                          "Any other refused input: an array of the wrong shape, a log, an option, "
                                          "a time step (C++ coopdyn::InvalidArgument).");
    py::register_exception_translator([](std::exception_ptr pointer) {
        try {
            if (pointer) {
                std::rethrow_exception(pointer);
            }
        } catch (const InvalidModel& error) {
            raise_error(invalid_model_type, error);
        } catch (const InvalidArgument& error) {
            raise_error(invalid_argument_type, error);
        } catch (const Error& error) {
            raise_error(error_type, error);
        }
    });
}

}  // namespace coopdyn::python

PYBIND11_MODULE(_coopdyn, module)
{
    module.doc() = "coopdyn's C++ bindings; import the package coopdyn instead (docs/python.md).";
    coopdyn::python::bind_errors(module);
    coopdyn::python::bind_numerics(module);
    coopdyn::python::bind_controller(module);
    coopdyn::python::bind_kernels(module);
    coopdyn::python::bind_spatial_model(module);
    coopdyn::python::bind_simulator(module);
    coopdyn::python::bind_model_analysis(module);  // after kernels and models: ApparentImpedance, SynthesisResult
    coopdyn::python::bind_analysis(module);  // after kernels: ApparentImpedance is bound there
    coopdyn::python::bind_identification(module);
}
