// A progress line on stderr for the example programs' long runs: "<label>  42.0 %", shown after
// the first two seconds, refreshed at most four times a second, erased by finish(); only when
// stderr is a terminal (a log file or a pipe gets no carriage-return clutter).
#pragma once

#include <chrono>
#include <cstdio>
#include <string>

#include <unistd.h>

namespace example_common {

class Progress {
public:
    explicit Progress(bool enabled)
        : enabled_(enabled && isatty(fileno(stderr)) != 0), start_(Clock::now()), last_(start_)
    {
    }
    /// Erases a line still shown, e.g. when an error ends the run: its message starts a clean line.
    ~Progress() { finish(); }
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;
    void update(const std::string& label, double fraction)
    {
        if (!enabled_) {
            return;
        }
        const auto now = Clock::now();
        if (seconds(start_, now) < 2.0 || (shown_ && seconds(last_, now) < 0.25)) {
            return;
        }
        std::fprintf(stderr, "\r%-40s %5.1f %%   ", label.c_str(), 100.0 * fraction);
        std::fflush(stderr);
        last_ = now;
        shown_ = true;
    }
    void finish()
    {
        if (shown_) {
            std::fprintf(stderr, "\r%-52s\r", "");
            std::fflush(stderr);
            shown_ = false;
        }
    }

private:
    using Clock = std::chrono::steady_clock;
    static double seconds(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }
    bool enabled_;
    bool shown_ = false;
    Clock::time_point start_, last_;
};

}  // namespace example_common
