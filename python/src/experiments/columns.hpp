// The experiments' logs as numpy columns (docs/python.md, "The experiments"): a sink with the CSV
// writer's number / text / optional / end_row (examples/common/csv_table.hpp), fed by the same
// emit functions that write the programs' CSV files (emit_box_log, emit_log, emit_summary), so
// that the columns and their order are defined once. Numbers keep every bit (the CSV prints 10
// significant digits); text columns (the status names) become numpy string arrays.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>  // std::optional arguments, lists of str

#include <algorithm>
#include <cstddef>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace coopdyn::python::experiments {

namespace py = pybind11;

class ColumnSink {
public:
    explicit ColumnSink(std::vector<std::string> names)
        : names_(std::move(names)), numbers_(names_.size()), texts_(names_.size()), is_text_(names_.size(), false)
    {
    }
    void number(double value)
    {
        next()->push_back(value);
    }
    void text(const std::string& value)
    {
        const std::size_t column = next_index();
        is_text_[column] = true;
        texts_[column].push_back(value);
        ++cell_;
    }
    /// An empty optional is NaN (the CSV's empty cell).
    void optional(const std::optional<double>& value)
    {
        number(value ? *value : std::numeric_limits<double>::quiet_NaN());
    }
    void end_row()
    {
        if (cell_ != names_.size()) {
            throw std::logic_error("ColumnSink: a row of " + std::to_string(cell_) + " cells, " +
                                   std::to_string(names_.size()) + " columns");
        }
        cell_ = 0;
    }

    /// {name: numpy array}: float64 for numbers, str for text; each array owns its memory.
    py::dict to_dict() const
    {
        py::dict columns;
        const py::object as_array = py::module_::import("numpy").attr("array");
        for (std::size_t k = 0; k < names_.size(); ++k) {
            if (is_text_[k]) {
                columns[py::str(names_[k])] = as_array(py::cast(texts_[k]), py::str("U"));
            } else {
                py::array_t<double> column(static_cast<py::ssize_t>(numbers_[k].size()));
                std::copy(numbers_[k].begin(), numbers_[k].end(), column.mutable_data());
                columns[py::str(names_[k])] = column;
            }
        }
        return columns;
    }

private:
    std::size_t next_index() const
    {
        if (cell_ >= names_.size()) {
            throw std::logic_error("ColumnSink: more cells than the " + std::to_string(names_.size()) + " columns");
        }
        return cell_;
    }
    std::vector<double>* next()
    {
        std::vector<double>* column = &numbers_[next_index()];
        ++cell_;
        return column;
    }

    std::vector<std::string> names_;
    std::vector<std::vector<double>> numbers_;
    std::vector<std::vector<std::string>> texts_;
    std::vector<bool> is_text_;
    std::size_t cell_ = 0;
};

/// The entry points of the extension's translation units (module.cpp calls them).
void bind_box(py::module_& module);
void bind_beam(py::module_& module);
void bind_loop(py::module_& module);

}  // namespace coopdyn::python::experiments
