// The Python module's shared helpers (docs/python.md): checked conversions of Python arguments to
// Eigen matrices (any memory order, any strides, exact shapes), copies of results into numpy
// arrays, and the entry points of the module's translation units.
//
// Every argument goes through to_matrix / to_vector: pybind11's own Eigen caster accepts any shape
// for a dynamic matrix, and the library's per-tick functions check sizes only with debug
// assertions, so a wrong shape would read out of bounds. Here it raises coopdyn.InvalidArgument (a
// ValueError) naming the function, the argument and the expected shape.
#pragma once

#include <coopdyn/config.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <string>

namespace coopdyn::python {

namespace py = pybind11;

using Matrix = Eigen::MatrixXd;
using Vector = Eigen::VectorXd;

/// An array argument as it arrives from Python (any object numpy can convert), converted and
/// checked by to_matrix / to_vector. Its own type only so that signatures read
/// "r: numpy.typing.ArrayLike" in help() instead of "r: handle".
struct ArrayLike {
    py::handle value;
    operator py::handle() const noexcept { return value; }  // NOLINT: implicit on purpose
};

/// A dimension that may take any size (N, K, Q read from the argument itself).
inline constexpr Index any_size = -1;

/// Throws coopdyn::InvalidArgument (component `function`, parameter `name`): Python sees
/// coopdyn.InvalidArgument, a ValueError.
[[noreturn]] void fail_argument(const char* function, const char* name, const std::string& problem);

/// `value` (a numpy array of any dtype convertible to float, memory order and strides, or a nested
/// sequence) as a rows x cols matrix; any_size accepts any extent. `expected` spells the shape for
/// the message, e.g. "(3, N)". A 2-D array only.
Matrix to_matrix(py::handle value, const char* function, const char* name, Index rows, Index cols,
                 const char* expected);
/// `value` as a vector of `size` entries (any_size: any); a 1-D array only.
Vector to_vector(py::handle value, const char* function, const char* name, Index size, const char* expected);

/// A new numpy array (C order) holding a copy of `matrix` (2-D) or `vector` (1-D). read_only marks
/// it not writeable: a field of a coopdyn object returned as a copy, so that writing into it raises
/// instead of changing a copy nobody sees (docs/python.md, "Arrays").
py::array matrix_copy(const Eigen::Ref<const Matrix>& matrix, bool read_only = false);
py::array vector_copy(const Eigen::Ref<const Vector>& vector, bool read_only = false);

/// Raises InvalidArgument (function, name) when an argument (a Data, Setpoints, ...) was made for
/// another number of arms than the model's.
inline void require_arms(Index arms, Index expected, const char* function, const char* name)
{
    if (arms != expected) {
        fail_argument(function, name,
                      "was made for N = " + std::to_string(arms) + " arms, the model has N = " + std::to_string(expected));
    }
}

// ---- templates shared by the bindings of classes -------------------------------------------

inline std::string dims(Index rows, Index cols) { return "(" + std::to_string(rows) + ", " + std::to_string(cols) + ")"; }
inline std::string dims(Index size) { return "(" + std::to_string(size) + ",)"; }

/// A copy of an Eigen member as a numpy array: 1-D for a vector, 2-D otherwise.
template <typename Derived> py::array copy_of(const Eigen::MatrixBase<Derived>& value, bool read_only)
{
    if constexpr (Derived::ColsAtCompileTime == 1) {
        return vector_copy(value, read_only);
    } else {
        return matrix_copy(value, read_only);
    }
}

/// Assigns `value` to an Eigen member, checked against the member's current shape (`symbol`, e.g.
/// "(Q, Q)", names it in the message) or, with resizable, against its fixed extents only.
template <typename Derived>
void assign(Eigen::MatrixBase<Derived>& target, py::handle value, const char* owner, const char* name,
            const char* symbol, bool resizable = false)
{
    const std::string expected = resizable ? std::string(symbol)
                                           : std::string(symbol) + " = " +
                                                 (Derived::ColsAtCompileTime == 1 ? dims(target.size())
                                                                                  : dims(target.rows(), target.cols()));
    if constexpr (Derived::ColsAtCompileTime == 1) {
        target.derived() = to_vector(value, owner, name, resizable ? any_size : target.size(), expected.c_str());
    } else {
        target.derived() = to_matrix(value, owner, name, target.rows(), target.cols(), expected.c_str());
    }
}

/// A read-write array property: the getter returns a read-only copy (assign the whole array to
/// change it), the setter checks the shape.
template <typename Class, typename Field, typename... Options>
void def_array(py::class_<Class, Options...>& cls, const char* owner, const char* name, Field Class::*field,
               const char* symbol, const char* doc, bool resizable = false)
{
    cls.def_property(
        name, [field](const Class& self) { return copy_of(self.*field, true); },
        [field, owner, name, symbol, resizable](Class& self, ArrayLike value) {
            assign(self.*field, value, owner, name, symbol, resizable);
        },
        doc);
}

/// A read-only array property (an output): a read-only copy.
template <typename Class, typename Field, typename... Options>
void def_output(py::class_<Class, Options...>& cls, const char* name, Field Class::*field, const char* doc)
{
    cls.def_property_readonly(name, [field](const Class& self) { return copy_of(self.*field, true); }, doc);
}

Eigen::Quaterniond quaternion_from(py::handle value, const char* owner, const char* name);
py::array quaternion_array(const Eigen::Quaterniond& q, bool read_only);

/// The entry points, one per translation unit (module.cpp calls them in this order).
void bind_errors(py::module_& module);
void bind_numerics(py::module_& module);
void bind_controller(py::module_& module);
void bind_control_kernels(py::module_& module);  ///< called by bind_controller
void bind_kernels(py::module_& module);
void bind_spatial_model(py::module_& module);
void bind_simulator(py::module_& module);      ///< after bind_spatial_model (its models)
void bind_model_analysis(py::module_& module);  ///< after bind_kernels and bind_spatial_model
void bind_analysis(py::module_& module);
void bind_identification(py::module_& module);

}  // namespace coopdyn::python

namespace pybind11::detail {

/// Accepts any object (the conversion and its checks happen in to_matrix / to_vector).
template <> struct type_caster<coopdyn::python::ArrayLike> {
    PYBIND11_TYPE_CASTER(coopdyn::python::ArrayLike, const_name("numpy.typing.ArrayLike"));
    bool load(handle source, bool)
    {
        value.value = source;
        return static_cast<bool>(source);
    }
    static handle cast(const coopdyn::python::ArrayLike& source, return_value_policy, handle)
    {
        return source.value.inc_ref();
    }
};

}  // namespace pybind11::detail
