// Running gnuplot for the example programs: find it on PATH, write a script, run it in the
// output folder, or say how to run it later when it is missing. The scripts themselves (what is
// plotted) belong to each program.
#pragma once

#include "files.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

namespace example_common {

/// Absolute path of the executable `name` on PATH (a regular file executable by others), or
/// empty.
inline std::filesystem::path find_on_path(const std::string& name)
{
    const char* path = std::getenv("PATH");
    if (path == nullptr) {
        return {};
    }
    const std::string list = path;
    std::size_t start = 0;
    while (start <= list.size()) {
        const std::size_t end = std::min(list.find(':', start), list.size());
        const std::filesystem::path candidate =
            std::filesystem::path(end > start ? list.substr(start, end - start) : ".") / name;
        std::error_code error;
        const auto status = std::filesystem::status(candidate, error);
        if (!error && std::filesystem::is_regular_file(status) &&
            (status.permissions() & std::filesystem::perms::others_exec) != std::filesystem::perms::none) {
            return candidate;
        }
        start = end + 1;
    }
    return {};
}

/// gnuplot on PATH, or empty.
inline std::filesystem::path find_gnuplot() { return find_on_path("gnuplot"); }

/// Single-quoted for /bin/sh.
inline std::string shell_quote(const std::string& text)
{
    std::string result = "'";
    for (const char c : text) {
        result += c == '\'' ? std::string("'\\''") : std::string(1, c);
    }
    return result + "'";
}

/// Writes `text` to `path`; throws FileError ("cannot write <path>: <reason>") on failure.
inline void write_text_file(const std::filesystem::path& path, const std::string& text)
{
    errno = 0;
    std::ofstream file(path, std::ios::binary);
    if (!file) {
        throw FileError(FileError::Access::write, path.string(), errno_reason(errno));
    }
    file << text;
    file.close();
    if (!file) {
        throw FileError(FileError::Access::write, path.string(), errno_reason(errno));
    }
}

/// A gnuplot script and the image it draws (both in the same folder).
struct Plot {
    std::filesystem::path script;
    std::filesystem::path image;
};

/// Runs gnuplot on each script from the script's folder (the scripts name their data and image
/// files relative to it) and lists the images on stdout. Without gnuplot on PATH it prints how to
/// make the plots later and succeeds. Returns false, after a message on stderr prefixed with
/// `program`, when gnuplot fails.
inline bool render_plots(const std::string& program, const std::vector<Plot>& plots)
{
    if (plots.empty()) {
        return true;
    }
    const std::filesystem::path folder = plots.front().script.parent_path();
    const std::string cd = "cd " + shell_quote(folder.empty() ? std::string(".") : folder.string());
    const std::filesystem::path gnuplot = find_gnuplot();
    if (gnuplot.empty()) {
        std::printf("plots: skipped, gnuplot was not found on PATH (install the Debian package gnuplot-nox);\n"
                    "  the scripts are written: %s && gnuplot %s\n",
                    cd.c_str(), plots.front().script.filename().string().c_str());
        return true;
    }
    std::printf("plots (gnuplot, PNG):\n");
    for (const Plot& plot : plots) {
        const std::filesystem::path here = plot.script.parent_path();
        const std::string command = "cd " + shell_quote(here.empty() ? std::string(".") : here.string()) + " && " +
                                    shell_quote(gnuplot.string()) + " " + shell_quote(plot.script.filename().string());
        const int status = std::system(command.c_str());
        if (status != 0) {
            std::fprintf(stderr, "%s: gnuplot failed on %s (status %d)\n", program.c_str(), plot.script.string().c_str(),
                         status);
            return false;
        }
        std::printf("  %s\n", plot.image.string().c_str());
    }
    return true;
}

}  // namespace example_common
