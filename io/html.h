#ifndef SPLAM_IO_HTML_H_
#define SPLAM_IO_HTML_H_

#include <string>
#include <string_view>
#include <vector>

#include "kernel/status.h"

// Self-contained HTML pages for run and sweep reports: one file with its style inline, no script
// and nothing loaded from the network; pictures either embedded (data: URLs) or linked by a path
// relative to the page.
namespace splam::io {

std::string HtmlEscape(std::string_view text);
std::string Base64(std::string_view bytes);

// A table cell: text, a link when `href` is set.
struct HtmlCell {
  std::string text;
  std::string href;
  HtmlCell(std::string t) : text(std::move(t)) {}  // NOLINT: a plain string is a text cell
  HtmlCell(const char* t) : text(t) {}             // NOLINT
  HtmlCell(std::string t, std::string link) : text(std::move(t)), href(std::move(link)) {}
};

class HtmlPage {
 public:
  explicit HtmlPage(std::string title);
  void Heading(const std::string& text, int level = 2);
  void Paragraph(const std::string& text);
  void Preformatted(const std::string& text);
  // A bulleted list, one item per string.
  void List(const std::vector<std::string>& items);
  void Table(const std::vector<std::string>& header,
             const std::vector<std::vector<HtmlCell>>& rows);
  // A picture linked by its path relative to the page, as wide as the page at most.
  void Image(const std::string& src, const std::string& caption);
  // A picture file embedded in the page (PNG or SVG by its extension); an error when unreadable.
  kernel::Status EmbedImage(const std::string& path, const std::string& caption);
  std::string Html() const;
  kernel::Status Save(const std::string& path) const;

 private:
  std::string title_, body_;
};

}  // namespace splam::io

#endif  // SPLAM_IO_HTML_H_
