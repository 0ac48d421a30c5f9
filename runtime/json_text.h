#ifndef SPLAM_RUNTIME_JSON_TEXT_H_
#define SPLAM_RUNTIME_JSON_TEXT_H_

#include <istream>
#include <nlohmann/json.hpp>
#include <string>

namespace splam::runtime {

// The JSON text of `json` (indented by `indent` spaces, -1: one line). Strings that are not
// UTF-8 (a Latin-1 file name, a log's binary junk quoted in an error, a world's name) are written
// with U+FFFD for each invalid byte instead of throwing (nlohmann's type_error.316, which aborted
// a finished run and left its file empty). Every JSON splam writes goes through here.
// `Json`: nlohmann::json or nlohmann::ordered_json (whose key order is kept).
template <class Json>
std::string JsonText(const Json& json, int indent = -1) {
  return json.dump(indent, ' ', false, Json::error_handler_t::replace);
}

// Values nested deeper than this in a JSON file splam reads back are left out.
inline constexpr int kMaxJsonDepth = 64;

// The JSON document in `in` (a cell's summary.json or cell.json, an experiment's report.json:
// files splam wrote, which a user or a full disk may have changed), discarded (is_discarded())
// when it is not JSON. Values nested deeper than kMaxJsonDepth are left out: a document nested
// 10^6 deep segfaulted `sweep merge` walking it.
inline nlohmann::json ReadJson(std::istream& in) {
  return nlohmann::json::parse(
      in,
      [](int depth, nlohmann::json::parse_event_t, nlohmann::json&) {
        return depth <= kMaxJsonDepth;
      },
      /*allow_exceptions=*/false);
}

}  // namespace splam::runtime

#endif  // SPLAM_RUNTIME_JSON_TEXT_H_
