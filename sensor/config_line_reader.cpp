#include "sensor/config_line_reader.hpp"

#include <cerrno>
#include <cstring>

#include "base/config_error.hpp"

namespace tgw::sensor {

namespace {

bool is_space(char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

std::vector<std::string_view> split_fields(std::string_view line) {
    std::vector<std::string_view> fields;
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && is_space(line[i]))
            ++i;
        const std::size_t start = i;
        while (i < line.size() && !is_space(line[i]))
            ++i;
        if (i > start)
            fields.push_back(line.substr(start, i - start));
    }
    return fields;
}

}  // namespace

bool ConfigLineReader::next() {
    while (std::getline(in_, line_)) {
        ++line_number_;
        std::string_view content(line_);
        if (const auto hash = content.find('#'); hash != std::string_view::npos)
            content = content.substr(0, hash);
        fields_ = split_fields(content);
        if (!fields_.empty())
            return true;
    }
    fields_.clear();
    if (in_.bad())
        fail_file("read error after line " + std::to_string(line_number_));
    return false;
}

void ConfigLineReader::fail(const std::string& what) const {
    throw base::ConfigError(file_name_ + ":" + std::to_string(line_number_) + ": " + what);
}

void ConfigLineReader::fail_file(const std::string& what) const {
    throw base::ConfigError(file_name_ + ": " + what);
}

std::ifstream open_config_file(const std::string& path) {
    std::ifstream in(path);
    if (!in)
        throw base::ConfigError(path + ": cannot open: " + std::strerror(errno));
    return in;
}

}  // namespace tgw::sensor
