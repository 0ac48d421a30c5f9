#include "io/html.h"

#include <algorithm>
#include <cstdint>

#include "io/trajectory.h"

namespace splam::io {
namespace {

constexpr char kStyle[] =
    "body{font-family:sans-serif;margin:1.5em;max-width:1400px;color:#222}"
    "table{border-collapse:collapse;margin:0.5em 0 1.5em}"
    "th,td{border:1px solid #ccc;padding:2px 8px;text-align:left;font-size:13px}"
    "th{background:#eee}tr:nth-child(even) td{background:#fafafa}"
    "figure{margin:0.5em 0 1.5em}img{max-width:100%;border:1px solid #ddd}"
    "figcaption{font-size:13px;color:#555}pre{background:#f4f4f4;padding:0.6em;overflow:auto}";

}  // namespace

std::string HtmlEscape(std::string_view text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string Base64(std::string_view bytes) {
  static constexpr char kDigits[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
    std::uint32_t v = 0;
    for (std::size_t k = 0; k < 3; ++k)
      v = (v << 8) | (k < n ? static_cast<unsigned char>(bytes[i + k]) : 0u);
    for (std::size_t k = 0; k < 4; ++k) out += k <= n ? kDigits[(v >> (18 - 6 * k)) & 63u] : '=';
  }
  return out;
}

HtmlPage::HtmlPage(std::string title) : title_(std::move(title)) { Heading(title_, 1); }

void HtmlPage::Heading(const std::string& text, int level) {
  const std::string tag = "h" + std::to_string(level);
  body_ += "<" + tag + ">" + HtmlEscape(text) + "</" + tag + ">\n";
}

void HtmlPage::Paragraph(const std::string& text) { body_ += "<p>" + HtmlEscape(text) + "</p>\n"; }

void HtmlPage::Preformatted(const std::string& text) {
  body_ += "<pre>" + HtmlEscape(text) + "</pre>\n";
}

void HtmlPage::Table(const std::vector<std::string>& header,
                     const std::vector<std::vector<HtmlCell>>& rows) {
  body_ += "<table>\n<tr>";
  for (const std::string& h : header) body_ += "<th>" + HtmlEscape(h) + "</th>";
  body_ += "</tr>\n";
  for (const std::vector<HtmlCell>& row : rows) {
    body_ += "<tr>";
    for (const HtmlCell& c : row) {
      body_ += "<td>";
      body_ += c.href.empty()
                   ? HtmlEscape(c.text)
                   : "<a href=\"" + HtmlEscape(c.href) + "\">" + HtmlEscape(c.text) + "</a>";
      body_ += "</td>";
    }
    body_ += "</tr>\n";
  }
  body_ += "</table>\n";
}

void HtmlPage::List(const std::vector<std::string>& items) {
  body_ += "<ul>\n";
  for (const std::string& item : items) body_ += "<li>" + HtmlEscape(item) + "</li>\n";
  body_ += "</ul>\n";
}

void HtmlPage::Image(const std::string& src, const std::string& caption) {
  body_ += "<figure><a href=\"" + HtmlEscape(src) + "\"><img src=\"" + HtmlEscape(src) +
           "\" alt=\"" + HtmlEscape(caption) + "\"></a><figcaption>" + HtmlEscape(caption) +
           "</figcaption></figure>\n";
}

kernel::Status HtmlPage::EmbedImage(const std::string& path, const std::string& caption) {
  std::string bytes;
  if (kernel::Status read = ReadTextFile(path, &bytes); !read.ok()) return read;
  const std::string mime = path.ends_with(".svg") ? "image/svg+xml" : "image/png";
  body_ += "<figure><img src=\"data:" + mime + ";base64," + Base64(bytes) + "\" alt=\"" +
           HtmlEscape(caption) + "\"><figcaption>" + HtmlEscape(caption) +
           "</figcaption></figure>\n";
  return kernel::Status::Ok();
}

std::string HtmlPage::Html() const {
  return "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>" +
         HtmlEscape(title_) + "</title>\n<style>" + kStyle + "</style>\n</head>\n<body>\n" + body_ +
         "</body>\n</html>\n";
}

kernel::Status HtmlPage::Save(const std::string& path) const { return WriteTextFile(path, Html()); }

}  // namespace splam::io
