#ifndef SPLAM_IO_TEXT_H_
#define SPLAM_IO_TEXT_H_

#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "kernel/status.h"

namespace splam::io {

// Whitespace-separated tokens of a line.
std::vector<std::string_view> SplitTokens(std::string_view line);
// The whole token as a double (accepts "nan", "inf"), or nullopt.
std::optional<double> ParseDouble(std::string_view token);
std::optional<long> ParseInteger(std::string_view token);
// Where the text of a file starts: after a UTF-8 byte order mark, if it has one.
std::size_t TextStart(std::string_view text);
// Calls visit(line_number, tokens) for every line of `text` that is neither blank nor a '#'
// comment, counting lines from 1 (a leading UTF-8 byte order mark is skipped). Stops at the first
// failure `visit` returns and returns it; ok when every line was accepted.
kernel::Status ForEachDataLine(
    const std::string& text,
    const std::function<kernel::Status(int, const std::vector<std::string_view>&)>& visit);
// Every token as a finite number; on failure *values is unspecified and the message is
// "'token' is not a finite number".
kernel::Status ParseFiniteNumbers(const std::vector<std::string_view>& tokens,
                                  std::vector<double>* values);
// `token` in single quotes for an error message: control bytes (a NUL, an escape) written as
// \xNN, and cut to its first 40 bytes with "..." (binary junk must not reach the terminal).
std::string Quoted(std::string_view token);
// `text` as one line of a comment: control bytes (a line break, a carriage return, a NUL) written
// as \xNN, so that no text a user or a file chose (a topic name, a path) ends the comment and
// starts a line that a reader would take as data.
std::string OneLine(std::string_view text);
// Shortest text that reads back as exactly the same double ("inf", "-inf", "nan" for the rest).
std::string FormatDouble(double value);

}  // namespace splam::io

#endif  // SPLAM_IO_TEXT_H_
