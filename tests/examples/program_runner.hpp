// Runs an example program as a user would (through /bin/sh, in a directory of its own) for the
// examples' end-to-end tests, and captures its exit code and output.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace example_tests {

namespace fs = std::filesystem;

struct ProgramRun {
    int exit_code = -1;
    std::string output;  // stdout and stderr
};

/// Single-quoted for /bin/sh.
inline std::string quote(const std::string& text)
{
    std::string result = "'";
    for (const char c : text) {
        result += c == '\'' ? std::string("'\\''") : std::string(1, c);
    }
    return result + "'";
}

/// A fresh, empty directory `root / name`.
inline fs::path fresh_directory(const fs::path& root, const std::string& name)
{
    const fs::path directory = root / name;
    fs::remove_all(directory);
    fs::create_directories(directory);
    return directory;
}

/// Runs `program` with `arguments` in `directory`; `environment` is prefixed (e.g. "PATH=/x").
inline ProgramRun run_program(const std::string& program, const fs::path& directory, const std::string& arguments,
                              const std::string& environment = "")
{
    const fs::path log = directory / "program_output.txt";
    const std::string command = "cd " + quote(directory.string()) + " && " + environment + " " + quote(program) + " " +
                                arguments + " > " + quote(log.string()) + " 2>&1";
    const int status = std::system(command.c_str());
    ProgramRun result;
    result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::ifstream file(log);
    std::ostringstream text;
    text << file.rdbuf();
    result.output = text.str();
    return result;
}

inline bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

/// The whole output is `line` and a newline: one message, no empty line before or after it.
inline bool is_one_line(const std::string& output, const std::string& line) { return output == line + "\n"; }

/// `text` (e.g. a shipped scenario) with `from` (found once) replaced by `to`, written to `file`.
inline bool write_edited(const std::string& text, const std::string& from, const std::string& to, const fs::path& file)
{
    std::string edited = text;
    const auto at = edited.find(from);
    if (at == std::string::npos) {
        return false;
    }
    edited.replace(at, from.size(), to);
    std::ofstream(file) << edited;
    return true;
}

/// The content of a text file.
inline std::string read_file(const fs::path& file)
{
    std::ifstream in(file);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

}  // namespace example_tests
