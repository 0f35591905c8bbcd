// Names that end up in output file names, and output folders (shared by the example programs;
// no dependencies). A scenario's `name` prefixes every file a program writes
// (<output>/<name>_x.csv, ...), so it must be a plain file name: the loaders check it with
// name_problem() when they read the file, and the programs build every output path with
// confined_path(), which refuses anything that could leave the output folder.
#pragma once

#include <cstddef>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <system_error>

namespace example_common {

/// Longest accepted name (it is only a prefix of the file names).
inline constexpr std::size_t max_name_length = 64;

/// `text` for a message: in double quotes, control and non-ASCII bytes as \xNN.
inline std::string quoted_for_message(const std::string& text)
{
    std::string result = "\"";
    for (const char c : text) {
        const auto byte = static_cast<unsigned char>(c);
        if (byte < 0x20 || byte >= 0x7f || c == '"' || c == '\\') {
            char buffer[8];
            std::snprintf(buffer, sizeof buffer, "\\x%02x", static_cast<unsigned>(byte));
            result += buffer;
        } else {
            result += c;
        }
    }
    return result + "\"";
}

namespace detail {

inline bool plain_file_character(char c)
{
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' ||
           c == '.';
}

/// Why `name` is not a plain file name of at most `max_length` characters, or "".
inline std::string plain_name_problem(const std::string& name, std::size_t max_length)
{
    const std::string rule = "letters, digits, '_', '-' and '.' only, not starting with a dot, 1 to " +
                             std::to_string(max_length) + " characters";
    if (name.empty()) {
        return "must not be empty (" + rule + ")";
    }
    if (name.size() > max_length) {
        return "is too long, " + std::to_string(name.size()) + " characters (" + rule + ")";
    }
    for (const char c : name) {
        if (c == '/' || c == '\\') {
            return "must not contain a path separator (" + rule + "), got " + quoted_for_message(name);
        }
        if (!plain_file_character(c)) {
            return "must be a plain file name (" + rule + "), got " + quoted_for_message(name);
        }
    }
    if (name.front() == '.') {
        return "must not start with a dot (" + rule + "), got " + quoted_for_message(name);
    }
    return {};
}

}  // namespace detail

/// Why `name` cannot prefix output file names, or "" when it can: 1 to 64 characters, letters,
/// digits, '_', '-' and '.' only, no leading dot (so no "..", no hidden files, no path
/// separators).
inline std::string name_problem(const std::string& name) { return detail::plain_name_problem(name, max_name_length); }

/// `folder / file_name`, after checking that `file_name` is a plain file name (the rules of
/// name_problem(), up to 255 characters): the result always lies directly in `folder`.
/// Throws std::runtime_error otherwise.
inline std::filesystem::path confined_path(const std::filesystem::path& folder, const std::string& file_name)
{
    const std::string problem = detail::plain_name_problem(file_name, 255);
    if (!problem.empty()) {
        throw std::runtime_error("refusing to write outside the output folder " + folder.string() +
                                 ": the file name " + problem);
    }
    return folder / file_name;
}

/// Why `folder` cannot be an output folder, or "": it must not be empty, must not contain
/// control characters, and must be a directory if it exists (it is created otherwise).
inline std::string output_folder_problem(const std::string& folder)
{
    if (folder.empty()) {
        return "must not be empty (use . for the current directory)";
    }
    for (const char c : folder) {
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
            return "must not contain control characters, got " + quoted_for_message(folder);
        }
    }
    std::error_code error;
    const auto status = std::filesystem::status(folder, error);
    if (!error && std::filesystem::exists(status) && !std::filesystem::is_directory(status)) {
        return "'" + folder + "' exists and is not a directory";
    }
    return {};
}

}  // namespace example_common
