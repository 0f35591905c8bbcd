// The generic part of the example programs' JSON scenario loaders (nlohmann-json): the error
// type, a reader that fetches fields by JSON path with type and value checks, and the file
// loading with parse-error wrapping. A program's own header describes its schema with these
// (examples/scenario.hpp for the two-arm beam).
//
// Every problem, whatever its origin, is a ScenarioError whose message names the file, the JSON
// path of the offending field and what is wrong:
//
//   beam.json: arms[1].end_effector.mass: expected a number, got string
//   beam.json: object.mass: not a finite number (number overflow parsing '1e400')
//   beam.json: name: must not contain a path separator (...), got "../escaped"
//   beam.json: (top level): not valid JSON: parse error at line 3, column 5: ...
//
// nlohmann-json's own exceptions never escape: parse_json() converts them (a number too large
// for a double, e.g. 1e400, is reported at its JSON path), the reader checks types before
// converting, and read_document() turns anything left into a ScenarioError at the path read
// last.
#pragma once

#include "files.hpp"
#include "output_names.hpp"
#include "ranges.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <nlohmann/json.hpp>

#include <cerrno>
#include <climits>
#include <cmath>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <stdexcept>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

namespace example_common {

using json = nlohmann::json;

/// A scenario file is malformed or describes an invalid set-up. what() is
/// "<source>: <json path>: <problem>" ("(top level)" for the empty path).
class ScenarioError : public std::runtime_error {
public:
    ScenarioError(const std::string& source, const std::string& path, const std::string& problem)
        : std::runtime_error(source + ": " + (path.empty() ? std::string("(top level)") : path) + ": " + problem),
          source_(source),
          path_(path),
          problem_(problem)
    {
    }
    /// The file name (or label) the document was read from.
    const std::string& source() const noexcept { return source_; }
    /// JSON path of the offending field, e.g. "arms[1].end_effector.mass"; empty: the document.
    const std::string& path() const noexcept { return path_; }
    /// What is wrong with it.
    const std::string& problem() const noexcept { return problem_; }

private:
    std::string source_;
    std::string path_;
    std::string problem_;
};

/// "number", "boolean", "null", "string", "array" or "object".
inline std::string type_name(const json& value)
{
    if (value.is_number()) {
        return "number";
    }
    if (value.is_boolean()) {
        return "boolean";
    }
    return value.type_name();
}

/// "a.b" (or "b" at the top level).
inline std::string join_path(const std::string& path, const std::string& key)
{
    return path.empty() ? key : path + "." + key;
}

/// "a[3]".
inline std::string index_path(const std::string& path, std::size_t index)
{
    return path + "[" + std::to_string(index) + "]";
}

/// A number for a message, 6 significant digits (3600, 0.5, 1e+300, nan).
inline std::string format_number(double value)
{
    std::ostringstream text;
    text << value;
    return text.str();
}

namespace detail {

/// nlohmann's message without its "[json.exception.<kind>.<id>] " prefix.
inline std::string without_nlohmann_prefix(const std::string& message)
{
    if (message.rfind("[json.exception.", 0) == 0) {
        const auto end = message.find("] ");
        if (end != std::string::npos) {
            return message.substr(end + 2);
        }
    }
    return message;
}

}  // namespace detail

/// Parses JSON text. `source` names it in error messages. Throws ScenarioError: syntax errors
/// at "(top level)" with nlohmann's line and column; a number that does not fit a double
/// (nlohmann refuses 1e400 as out of range) at the JSON path where it stands.
inline json parse_json(const std::string& text, const std::string& source)
{
    // Where the parser is, for the errors nlohmann reports without a path: one frame per open
    // object (the current key) or array (the current index).
    struct Frame {
        bool array = false;
        std::size_t index = 0;
        std::string key;
    };
    std::vector<Frame> frames;
    const auto current_path = [&frames] {
        std::string path;
        for (const Frame& frame : frames) {
            path = frame.array ? index_path(path, frame.index) : join_path(path, frame.key);
        }
        return path;
    };
    const auto next_element = [&frames] {
        if (!frames.empty() && frames.back().array) {
            ++frames.back().index;
        }
    };
    const json::parser_callback_t track = [&](int, json::parse_event_t event, json& parsed) {
        switch (event) {
        case json::parse_event_t::object_start: frames.push_back(Frame{false, 0, {}}); break;
        case json::parse_event_t::array_start: frames.push_back(Frame{true, 0, {}}); break;
        case json::parse_event_t::key:
            if (!frames.empty() && parsed.is_string()) {
                frames.back().key = parsed.get<std::string>();
            }
            break;
        case json::parse_event_t::value: next_element(); break;
        case json::parse_event_t::object_end:
        case json::parse_event_t::array_end:
            if (!frames.empty()) {
                frames.pop_back();
            }
            next_element();
            break;
        }
        return true;
    };
    try {
        return json::parse(text, track);
    } catch (const json::parse_error& error) {
        // "[json.exception.parse_error.101] parse error at line 3, column 5: ..."
        const std::string message = error.what();
        const auto start = message.find("parse error");
        throw ScenarioError(source, "",
                            "not valid JSON: " + (start == std::string::npos ? message : message.substr(start)));
    } catch (const json::out_of_range& error) {
        // 406: "number overflow parsing '1e400'" (the value would be +-inf).
        throw ScenarioError(source, current_path(),
                            "not a finite number (" + detail::without_nlohmann_prefix(error.what()) + ")");
    } catch (const json::exception& error) {
        throw ScenarioError(source, current_path(), detail::without_nlohmann_prefix(error.what()));
    }
}

/// The whole content of a file. Throws FileError ("cannot read <path>: <reason>", files.hpp) when
/// it cannot be read: a missing or unreadable file is no invalid scenario (exit_file, not
/// exit_scenario).
inline std::string read_text_file(const std::string& path)
{
    check_readable(path);
    errno = 0;
    std::ifstream file(path, std::ios::binary);
    if (!file) {
        throw FileError(FileError::Access::read, path, errno_reason(errno));
    }
    std::ostringstream text;
    text << file.rdbuf();
    if (file.bad()) {
        throw FileError(FileError::Access::read, path, "read error");
    }
    return text.str();
}

/// Walks a parsed document, naming every error by its JSON path. The accessors check the type
/// (and the value) before converting, so they throw ScenarioError only.
class JsonReader {
public:
    explicit JsonReader(std::string source) : source_(std::move(source)) {}

    const std::string& source() const noexcept { return source_; }
    /// The path of the field read last (where an unexpected error is reported).
    const std::string& last_path() const noexcept { return last_path_; }

    [[noreturn]] void fail(const std::string& path, const std::string& problem) const
    {
        throw ScenarioError(source_, path, problem);
    }

    void expect_object(const json& value, const std::string& path) const
    {
        visit(path);
        if (!value.is_object()) {
            fail(path, "expected an object, got " + type_name(value));
        }
    }

    /// Refuses keys outside `allowed` (a misspelt optional field would otherwise be ignored).
    void only_keys(const json& object, const std::string& path, std::initializer_list<const char*> allowed) const
    {
        expect_object(object, path);
        for (auto it = object.begin(); it != object.end(); ++it) {
            bool known = false;
            for (const char* key : allowed) {
                known = known || it.key() == key;
            }
            if (!known) {
                std::string list;
                for (const char* key : allowed) {
                    list += list.empty() ? key : std::string(", ") + key;
                }
                fail(join_path(path, it.key()), "unknown field (allowed here: " + list + ")");
            }
        }
    }

    /// The field `key` of `object` (at `path`); fails when it is missing.
    const json& required(const json& object, const std::string& path, const char* key) const
    {
        expect_object(object, path);
        const auto it = object.find(key);
        if (it == object.end()) {
            fail(join_path(path, key), "missing required field");
        }
        return *it;
    }

    /// The field `key` of `object`, or nullptr when it is absent (or `object` is no object).
    const json* optional(const json& object, const char* key) const
    {
        if (!object.is_object()) {
            return nullptr;
        }
        const auto it = object.find(key);
        return it == object.end() ? nullptr : &*it;
    }

    /// A finite number.
    double number(const json& value, const std::string& path) const
    {
        visit(path);
        if (!value.is_number()) {
            fail(path, "expected a number, got " + type_name(value));
        }
        const double result = value.get<double>();
        if (!std::isfinite(result)) {
            fail(path, "must be finite, got " + format_number(result));
        }
        return result;
    }

    /// A finite number > 0.
    double positive(const json& value, const std::string& path) const
    {
        const double result = number(value, path);
        if (!(result > 0.0)) {
            fail(path, "must be positive, got " + format_number(result));
        }
        return result;
    }

    /// A finite number >= 0.
    double non_negative(const json& value, const std::string& path) const
    {
        const double result = number(value, path);
        if (!(result >= 0.0)) {
            fail(path, "must be non-negative, got " + format_number(result));
        }
        return result;
    }

    /// A finite number in [low, high].
    double in_range(const json& value, const std::string& path, double low, double high) const
    {
        const double result = number(value, path);
        if (!(result >= low && result <= high)) {
            fail(path, "must be between " + format_number(low) + " and " + format_number(high) + ", got " +
                           format_number(result));
        }
        return result;
    }

    /// A finite number in `range` (examples/common/ranges.hpp: the range its command-line option
    /// has too).
    double in_range(const json& value, const std::string& path, const NumberRange& range) const
    {
        return in_range(value, path, range.low, range.high);
    }

    std::string string(const json& value, const std::string& path) const
    {
        visit(path);
        if (!value.is_string()) {
            fail(path, "expected a string, got " + type_name(value));
        }
        return value.get<std::string>();
    }

    /// A string that can prefix output file names (see name_problem()).
    std::string name(const json& value, const std::string& path) const
    {
        std::string result = string(value, path);
        const std::string problem = name_problem(result);
        if (!problem.empty()) {
            fail(path, problem);
        }
        return result;
    }

    /// A whole number written without a fraction or exponent, within long long.
    long long integer(const json& value, const std::string& path) const
    {
        visit(path);
        if (value.is_number_float()) {
            const double number = value.get<double>();
            fail(path, "expected an integer, got " +
                           (std::isfinite(number) && number == std::floor(number)
                                ? format_number(number) + " (write integers without a fraction or exponent)"
                                : std::string("a fractional number")));
        }
        if (!value.is_number_integer()) {
            fail(path, "expected an integer, got " + type_name(value));
        }
        if (value.is_number_unsigned() && value.get<unsigned long long>() > static_cast<unsigned long long>(LLONG_MAX)) {
            fail(path, "integer too large, got " + value.dump());
        }
        return value.get<long long>();
    }

    /// An array (of `size` entries when size > 0).
    const json& array(const json& value, const std::string& path, std::size_t size = 0) const
    {
        visit(path);
        if (!value.is_array()) {
            fail(path, "expected an array, got " + type_name(value));
        }
        if (size > 0 && value.size() != size) {
            fail(path, "expected " + std::to_string(size) + " entries, got " + std::to_string(value.size()));
        }
        return value;
    }

    /// An array of finite numbers (of `size` entries when size > 0).
    std::vector<double> numbers(const json& value, const std::string& path, std::size_t size = 0) const
    {
        array(value, path, size);
        std::vector<double> result;
        for (std::size_t i = 0; i < value.size(); ++i) {
            result.push_back(number(value[i], index_path(path, i)));
        }
        return result;
    }

    Eigen::Vector3d vector3(const json& value, const std::string& path) const
    {
        const std::vector<double> v = numbers(value, path, 3);
        return Eigen::Vector3d(v[0], v[1], v[2]);
    }

    /// A 3x3 matrix: [a, b, c] (the diagonal) or [[...], [...], [...]] (rows).
    Eigen::Matrix3d matrix3(const json& value, const std::string& path) const
    {
        array(value, path, 3);
        if (!value[0].is_array()) {
            return vector3(value, path).asDiagonal();
        }
        Eigen::Matrix3d result;
        for (std::size_t row = 0; row < 3; ++row) {
            result.row(static_cast<Eigen::Index>(row)) = vector3(value[row], index_path(path, row)).transpose();
        }
        return result;
    }

    /// A unit quaternion written [w, x, y, z] (norm 1 within 1e-9).
    Eigen::Quaterniond quaternion(const json& value, const std::string& path) const
    {
        const std::vector<double> q = numbers(value, path, 4);
        const Eigen::Quaterniond result(q[0], q[1], q[2], q[3]);
        if (std::abs(result.norm() - 1.0) > 1e-9) {
            std::ostringstream problem;
            problem.precision(12);
            problem << "must be a unit quaternion [w, x, y, z], has norm " << result.norm();
            fail(path, problem.str());
        }
        return result;
    }

private:
    void visit(const std::string& path) const { last_path_ = path; }

    std::string source_;
    mutable std::string last_path_;
};

/// Parses `text` (named `source` in messages) and hands the document to `schema(reader,
/// document)`, which builds the program's result with the JsonReader. Anything nlohmann-json
/// throws on the way becomes a ScenarioError at the path read last: only ScenarioError leaves.
template <typename Schema>
auto read_document(const std::string& text, const std::string& source, Schema&& schema)
    -> decltype(schema(std::declval<const JsonReader&>(), std::declval<const json&>()))
{
    const json document = parse_json(text, source);
    const JsonReader reader(source);
    try {
        return schema(reader, document);
    } catch (const json::exception& error) {
        reader.fail(reader.last_path(), detail::without_nlohmann_prefix(error.what()));
    }
}

}  // namespace example_common
