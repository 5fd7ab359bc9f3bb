#pragma once

#include <cstddef>
#include <fstream>
#include <istream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace tgw::sensor {

/// Reads a line-based configuration file (a rate trace, a link quality table) field by field: `#` starts a comment
/// to the end of the line, lines without a field are skipped, fields are separated by blanks (so CRLF line ends
/// are allowed). Errors are base::ConfigError naming the file and line.
class ConfigLineReader {
  public:
    ConfigLineReader(std::istream& in, std::string file_name) : in_(in), file_name_(std::move(file_name)) {}

    /// Moves to the next line with a field; false at the end. Throws base::ConfigError "FILE: read error after
    /// line N" if the stream failed.
    bool next();

    /// The fields of the current line; they stay valid until the next call of next().
    const std::vector<std::string_view>& fields() const { return fields_; }

    std::size_t line_number() const { return line_number_; }

    /// Throws base::ConfigError "FILE:LINE: what", for the current line.
    [[noreturn]] void fail(const std::string& what) const;

    /// Throws base::ConfigError "FILE: what", for the file as a whole.
    [[noreturn]] void fail_file(const std::string& what) const;

  private:
    std::istream& in_;
    std::string file_name_;
    std::string line_;
    std::vector<std::string_view> fields_;
    std::size_t line_number_ = 0;
};

/// Opens `path` for reading; throws base::ConfigError "PATH: cannot open: REASON" if it cannot.
std::ifstream open_config_file(const std::string& path);

}  // namespace tgw::sensor
