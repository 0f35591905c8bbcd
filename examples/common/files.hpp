// Files the example programs read or write: one error type, FileError, for every file that cannot
// be read (a scenario, an --identify-log) or written (the output folder, a CSV log, a gnuplot
// script), with one message style, "cannot read <path>: <reason>" / "cannot write <path>:
// <reason>", and one exit code, exit_file (cli.hpp). No dependencies beyond the standard library.
#pragma once

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <system_error>

#include <unistd.h>

namespace example_common {

/// A file or folder cannot be read or written. what() is "cannot read <path>: <reason>" or
/// "cannot write <path>: <reason>".
class FileError : public std::runtime_error {
public:
    enum class Access { read, write };
    FileError(Access access, const std::string& path, const std::string& reason)
        : std::runtime_error(std::string(access == Access::read ? "cannot read " : "cannot write ") + path + ": " +
                             reason),
          access_(access),
          path_(path),
          reason_(reason)
    {
    }
    Access access() const noexcept { return access_; }
    const std::string& path() const noexcept { return path_; }
    const std::string& reason() const noexcept { return reason_; }

private:
    Access access_;
    std::string path_;
    std::string reason_;
};

/// The reason of the last failed system call (errno), e.g. "No such file or directory"; a
/// generic text when errno was not set.
inline std::string errno_reason(int error_number)
{
    return error_number != 0 ? std::string(std::strerror(error_number)) : std::string("input/output error");
}

/// Throws FileError(read) unless `path` is a file that can be opened for reading: it is checked
/// before opening so that a missing file or a folder gets its own reason.
inline void check_readable(const std::string& path)
{
    std::error_code error;
    const auto status = std::filesystem::status(path, error);
    if (error || !std::filesystem::exists(status)) {
        throw FileError(FileError::Access::read, path,
                        error && error != std::errc::no_such_file_or_directory ? error.message()
                                                                               : "No such file or directory");
    }
    if (std::filesystem::is_directory(status)) {
        throw FileError(FileError::Access::read, path, "is a directory, not a file");
    }
}

/// Creates the output folder `folder` (and its parents) if missing and checks that files can be
/// created in it; throws FileError(write) naming it otherwise. Called before anything runs, so
/// that an unusable --output fails at once, not after a long simulation.
inline void prepare_output_folder(const std::filesystem::path& folder)
{
    std::error_code error;
    std::filesystem::create_directories(folder, error);
    if (error) {
        throw FileError(FileError::Access::write, folder.string(), error.message());
    }
    if (!std::filesystem::is_directory(folder, error)) {
        throw FileError(FileError::Access::write, folder.string(), "not a directory");
    }
    if (::access(folder.c_str(), W_OK | X_OK) != 0) {
        throw FileError(FileError::Access::write, folder.string(), errno_reason(errno));
    }
}

}  // namespace example_common
