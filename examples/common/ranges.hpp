// The ranges of the example programs' numbers, defined once and applied both to a command-line
// option (cli.hpp: number_in_range) and to the scenario field it stands for (json_reader.hpp:
// JsonReader::in_range), so that a value the command line refuses is refused in a scenario file
// too, with the same limits in both messages. No dependencies.
#pragma once

namespace example_common {

/// A closed range [low, high] of finite numbers.
struct NumberRange {
    double low;
    double high;
    constexpr bool contains(double value) const { return value >= low && value <= high; }
};

/// Simulated seconds of one experiment, in both programs (--duration, the box scenarios'
/// "duration"). The common rule: at least 1 s, at most an hour. 1 s is what each program needs to
/// say anything: the beam's identification fits three parameters per axis to a multisine whose
/// lines are odd harmonics of 1 / duration in 0.1-5 Hz (at 1 s: 1, 3 and 5 Hz, three lines; below
/// it fewer, and fewer than the 100 samples the fit needs at coarse time steps), and the box's
/// table averages the squeeze "at rest" over its first 0.8 s (box_report.hpp, rest_window).
inline constexpr NumberRange experiment_duration_range{1.0, 3600.0};

}  // namespace example_common
