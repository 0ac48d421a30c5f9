#ifndef SPLAM_IO_TEXT_H_
#define SPLAM_IO_TEXT_H_

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace splam::io {

// Whitespace-separated tokens of a line.
std::vector<std::string_view> SplitTokens(std::string_view line);
// The whole token as a double (accepts "nan", "inf"), or nullopt.
std::optional<double> ParseDouble(std::string_view token);
std::optional<long> ParseInteger(std::string_view token);
// Shortest text that reads back as exactly the same double ("inf", "-inf", "nan" for the rest).
std::string FormatDouble(double value);

}  // namespace splam::io

#endif  // SPLAM_IO_TEXT_H_
