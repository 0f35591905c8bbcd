// CSV files of the example programs (a header row, then rows of numbers or text): CsvTable
// reads them (`two_arm_beam --identify-log`, the tests that check the programs' output),
// CsvWriter writes them (numbers with 10 significant digits, NaN as "nan").
#pragma once

#include "files.hpp"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace example_common {

/// Columns of a CSV file by header name. Cells are kept as text; number() parses them.
class CsvTable {
public:
    /// Reads `path`. Throws FileError ("cannot read <path>: <reason>") when the file cannot be
    /// read, std::runtime_error (naming the file and the line) when it is empty or a row has a
    /// different number of cells than the header.
    explicit CsvTable(const std::string& path) : path_(path)
    {
        check_readable(path);
        errno = 0;
        std::ifstream file(path, std::ios::binary);
        if (!file) {
            throw FileError(FileError::Access::read, path, errno_reason(errno));
        }
        std::string line;
        std::size_t line_number = 0;
        while (std::getline(file, line)) {
            ++line_number;
            if (!line.empty() && line.back() == '\r') {
                line.pop_back();
            }
            if (line.empty()) {
                continue;
            }
            std::vector<std::string> cells = split(line);
            if (header_.empty()) {
                header_ = cells;
                for (std::size_t i = 0; i < header_.size(); ++i) {
                    index_[header_[i]] = i;
                }
                continue;
            }
            if (cells.size() != header_.size()) {
                throw std::runtime_error(path + ":" + std::to_string(line_number) + ": " +
                                         std::to_string(cells.size()) + " cells, but the header has " +
                                         std::to_string(header_.size()));
            }
            rows_.push_back(std::move(cells));
        }
        if (header_.empty()) {
            throw std::runtime_error(path + ": empty file (no header row)");
        }
    }

    const std::vector<std::string>& header() const { return header_; }
    std::size_t rows() const { return rows_.size(); }
    bool has(const std::string& column) const { return index_.count(column) > 0; }

    const std::string& text(std::size_t row, const std::string& column) const { return rows_.at(row).at(at(column)); }

    /// The cell as a number: "nan" and "" give NaN. Throws on text that is not a number.
    double number(std::size_t row, const std::string& column) const
    {
        const std::string& cell = text(row, column);
        if (cell.empty()) {
            return std::numeric_limits<double>::quiet_NaN();
        }
        char* end = nullptr;
        errno = 0;
        const double value = std::strtod(cell.c_str(), &end);
        if (end == cell.c_str() || *end != '\0') {
            throw std::runtime_error(path_ + ": row " + std::to_string(row + 1) + ", column '" + column +
                                     "': not a number: '" + cell + "'");
        }
        return value;
    }

    /// A whole column as numbers.
    std::vector<double> numbers(const std::string& column) const
    {
        std::vector<double> result(rows_.size());
        for (std::size_t row = 0; row < rows_.size(); ++row) {
            result[row] = number(row, column);
        }
        return result;
    }

private:
    std::size_t at(const std::string& column) const
    {
        const auto it = index_.find(column);
        if (it == index_.end()) {
            throw std::runtime_error(path_ + ": no column '" + column + "'");
        }
        return it->second;
    }

    static std::vector<std::string> split(const std::string& line)
    {
        std::vector<std::string> cells;
        std::string cell;
        for (const char c : line) {
            if (c == ',') {
                cells.push_back(cell);
                cell.clear();
            } else {
                cell += c;
            }
        }
        cells.push_back(cell);
        return cells;
    }

    std::string path_;
    std::vector<std::string> header_;
    std::map<std::string, std::size_t> index_;
    std::vector<std::vector<std::string>> rows_;
};

/// Writes a CSV file row by row. Throws FileError ("cannot write <path>: <reason>") when it cannot
/// be opened or written.
class CsvWriter {
public:
    explicit CsvWriter(const std::filesystem::path& path) : path_(path)
    {
        errno = 0;
        file_.open(path, std::ios::binary);
        if (!file_) {
            throw FileError(FileError::Access::write, path.string(), errno_reason(errno));
        }
    }
    void text(const std::string& value)
    {
        separate();
        line_ += value;
    }
    void number(double value)
    {
        separate();
        if (std::isnan(value)) {
            line_ += "nan";
            return;
        }
        char buffer[32];
        const auto written = std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::general, 10);
        line_.append(buffer, written.ptr);
    }
    /// The number, or an empty cell.
    void optional(const std::optional<double>& value)
    {
        if (value) {
            number(*value);
        } else {
            text("");
        }
    }
    void end_row()
    {
        line_ += '\n';
        file_ << line_;
        line_.clear();
        first_ = true;
    }
    void close()
    {
        errno = 0;
        file_.close();
        if (!file_) {
            throw FileError(FileError::Access::write, path_.string(), errno_reason(errno));
        }
    }

private:
    void separate()
    {
        if (!first_) {
            line_ += ',';
        }
        first_ = false;
    }
    std::filesystem::path path_;
    std::ofstream file_;
    std::string line_;
    bool first_ = true;
};

}  // namespace example_common
