#include "io/text.h"

#include <charconv>
#include <cmath>

#include "io/result.h"

namespace splam::io {

kernel::Status FileError(const std::string& path, int line, const std::string& message) {
  if (line <= 0) return kernel::Status::Error(path + ": " + message);
  return kernel::Status::Error(path + ":" + std::to_string(line) + ": " + message);
}

std::vector<std::string_view> SplitTokens(std::string_view line) {
  std::vector<std::string_view> tokens;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
    if (i > start) tokens.push_back(line.substr(start, i - start));
  }
  return tokens;
}

std::optional<double> ParseDouble(std::string_view token) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  double value = 0.0;
  const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (ec != std::errc() || ptr != token.data() + token.size()) return std::nullopt;
  return value;
}

std::optional<long> ParseInteger(std::string_view token) {
  long value = 0;
  const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (ec != std::errc() || ptr != token.data() + token.size()) return std::nullopt;
  return value;
}

std::size_t TextStart(std::string_view text) {
  constexpr std::string_view kByteOrderMark = "\xEF\xBB\xBF";
  return text.starts_with(kByteOrderMark) ? kByteOrderMark.size() : 0;
}

kernel::Status ForEachDataLine(
    const std::string& text,
    const std::function<kernel::Status(int, const std::vector<std::string_view>&)>& visit) {
  std::size_t pos = TextStart(text);
  int line_number = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    const std::vector<std::string_view> tokens =
        SplitTokens(std::string_view(text).substr(pos, end - pos));
    pos = end + 1;
    ++line_number;
    if (tokens.empty() || tokens[0].front() == '#') continue;
    if (kernel::Status status = visit(line_number, tokens); !status.ok()) return status;
  }
  return {};
}

kernel::Status ParseFiniteNumbers(const std::vector<std::string_view>& tokens,
                                  std::vector<double>* values) {
  values->clear();
  for (std::string_view token : tokens) {
    const std::optional<double> value = ParseDouble(token);
    if (!value || !std::isfinite(*value)) {
      return kernel::Status::Error(Quoted(token) + " is not a finite number");
    }
    values->push_back(*value);
  }
  return {};
}

std::string OneLine(std::string_view text) {
  std::string line;
  line.reserve(text.size());
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20 || byte == 0x7f) {
      constexpr char kHex[] = "0123456789abcdef";
      line += {'\\', 'x', kHex[byte >> 4], kHex[byte & 0xf]};
    } else {
      line += c;
    }
  }
  return line;
}

std::string Quoted(std::string_view token) {
  constexpr std::size_t kMaxShown = 40;
  return "'" + OneLine(token.substr(0, kMaxShown)) + (token.size() > kMaxShown ? "..." : "") + "'";
}

std::string FormatDouble(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char buffer[64];
  const auto [ptr, ec] = std::to_chars(buffer, buffer + sizeof(buffer), value);
  return std::string(buffer, ptr);
}

}  // namespace splam::io
