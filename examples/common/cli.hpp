// Command-line helpers of the example programs (CLI11): validators that refuse NaN and
// infinities and print their limits readably, output folder and name checks, and the exit codes.
//
// CLI11's own number checks let NaN through (every comparison with NaN is false) and print a
// limit of DBL_MAX with all its ~300 digits; these validators run on the option's text before
// CLI11 converts it, so a bad value stops the program before anything runs, with a message like
//
//   --duration: must be a finite number in [1, 3600], got nan
//   --force: must be a non-negative finite number, got -1
//
// Exit codes (the same in every example program):
//
//   exit_success  0  success (also --help)
//   exit_failure  1  run-time failure: a simulation or identification that fails (the box
//                    dropped), gnuplot failing
//   exit_usage    2  bad command line: unknown option, invalid or out-of-range value, a value
//                    that contradicts the scenario (e.g. a low-pass above the Nyquist limit)
//   exit_scenario 3  invalid scenario file (a ScenarioError, examples/common/json_reader.hpp):
//                    malformed, a field missing, of the wrong type or out of its range
//   exit_file     4  a file that cannot be read (a missing scenario or --identify-log) or written
//                    (an unusable --output): "<program>: cannot read <path>: <reason>" or
//                    "<program>: cannot write <path>: <reason>" (a FileError, files.hpp)
//
// A number that is both an option and a scenario field (e.g. --duration and "duration") has one
// range, a NumberRange (ranges.hpp), that both the option's validator and the loader apply.
#pragma once

#include "output_names.hpp"
#include "ranges.hpp"

#include <CLI/CLI.hpp>

#include <cmath>
#include <sstream>
#include <string>

namespace example_common {

inline constexpr int exit_success = 0;
inline constexpr int exit_failure = 1;
inline constexpr int exit_usage = 2;
inline constexpr int exit_scenario = 3;
inline constexpr int exit_file = 4;

/// A limit for a message or --help: 6 significant digits (3600, 0.5, 1e+300).
inline std::string format_limit(double value)
{
    std::ostringstream text;
    text << value;
    return text.str();
}

namespace detail {

/// The option's text as CLI11 would convert it to a double; false when it is no number.
inline bool command_line_number(const std::string& text, double& value)
{
    return CLI::detail::lexical_cast(text, value);
}

/// A validator accepting finite numbers for which `accept(value)` holds; `requirement` completes
/// "must be a ..." in the error message.
template <typename Accept>
CLI::Validator finite_number_validator(const std::string& description, const std::string& requirement, Accept accept)
{
    return CLI::Validator(
        [requirement, accept](std::string& input) -> std::string {
            double value = 0.0;
            if (!command_line_number(input, value) || !std::isfinite(value) || !accept(value)) {
                return "must be a " + requirement + ", got " + input;
            }
            return {};
        },
        description);
}

}  // namespace detail

/// Any finite number (no nan, inf).
inline CLI::Validator finite_number()
{
    return detail::finite_number_validator("FINITE", "finite number", [](double) { return true; });
}

/// A finite number >= 0.
inline CLI::Validator non_negative_number()
{
    return detail::finite_number_validator("NONNEGATIVE", "non-negative finite number",
                                           [](double value) { return value >= 0.0; });
}

/// A finite number > 0.
inline CLI::Validator positive_number()
{
    return detail::finite_number_validator("POSITIVE", "positive finite number",
                                           [](double value) { return value > 0.0; });
}

/// A finite number in [low, high], e.g. "in [1, 3600]" in --help.
inline CLI::Validator number_in_range(double low, double high)
{
    const std::string range = "[" + format_limit(low) + ", " + format_limit(high) + "]";
    return detail::finite_number_validator("in " + range, "finite number in " + range,
                                           [low, high](double value) { return value >= low && value <= high; });
}

/// A finite number in `range`, the range its scenario field has too (ranges.hpp).
inline CLI::Validator number_in_range(const NumberRange& range) { return number_in_range(range.low, range.high); }

/// 0 (meaning "the scenario's value") or a finite number in `range`, the scenario field's range.
inline CLI::Validator zero_or_in_range(const NumberRange& range)
{
    const std::string limits = "[" + format_limit(range.low) + ", " + format_limit(range.high) + "]";
    return detail::finite_number_validator("0 or in " + limits, "finite number, 0 or in " + limits,
                                           [range](double value) { return value == 0.0 || range.contains(value); });
}

/// A positive decimal integer (1, 2, ...; no sign, no leading zeros), e.g. --log-every.
inline CLI::Validator decimal_positive()
{
    return CLI::Validator(
        [](std::string& input) -> std::string {
            bool digits = !input.empty() && input.front() != '0' && input.size() <= 9;
            for (const char c : input) {
                digits = digits && c >= '0' && c <= '9';
            }
            return digits ? std::string() : "must be a positive decimal integer (1 to 999999999), got " + input;
        },
        "");
}

/// A non-negative decimal integer (no sign, no leading zeros: CLI11 would read "-1" as 2^64 - 1
/// and "010" as octal 8), for unsigned options such as a seed.
inline CLI::Validator decimal_unsigned()
{
    return CLI::Validator(
        [](std::string& input) -> std::string {
            bool digits = !input.empty() && (input.size() == 1 || input.front() != '0');
            for (const char c : input) {
                digits = digits && c >= '0' && c <= '9';
            }
            return digits ? std::string() : "must be a non-negative decimal integer, got " + input;
        },
        "");
}

/// An output folder (see output_folder_problem()).
inline CLI::Validator output_folder()
{
    return CLI::Validator(
        [](std::string& input) { return output_folder_problem(input); }, "");
}

/// A name that prefixes output files (see name_problem()).
inline CLI::Validator output_name()
{
    return CLI::Validator([](std::string& input) { return name_problem(input); }, "NAME");
}

}  // namespace example_common
