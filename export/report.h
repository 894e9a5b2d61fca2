// A report a person can read at a glance: headings, short paragraphs, tables and pictures,
// written both as report.md and a self-contained-looking report.html beside its images.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "core/status.h"
#include "core/text_format.h"  // Format, for table cells

namespace mesocap {

// `s` as HTML text or a quoted attribute value: <, >, & and " escaped.
std::string HtmlEscape(const std::string& s);

class Report {
 public:
  explicit Report(std::string title) : title_(std::move(title)) {}

  void Heading(const std::string& text);
  void Paragraph(const std::string& text);
  void Table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows);
  // A table folded away under `summary` (HTML <details>; GitHub renders it in report.md too).
  void FoldedTable(const std::string& summary, const std::vector<std::string>& header,
                   const std::vector<std::vector<std::string>>& rows);
  // `relative_path` is relative to the report's folder.
  void Picture(const std::string& relative_path, const std::string& caption);
  // Markup placed as it is in report.html (trusted, made by mesocap: e.g. the interactive viewer);
  // report.md gets `markdown_note` instead.
  void Html(const std::string& html, const std::string& markdown_note);

  // Writes DIR/report.md and DIR/report.html atomically.
  Status Write(const std::filesystem::path& dir) const;

 private:
  struct Block {
    enum Kind { kHeading, kParagraph, kTable, kPicture, kHtml } kind;
    std::string text, path;
    std::vector<std::string> header;
    std::vector<std::vector<std::string>> rows;
  };
  std::string title_;
  std::vector<Block> blocks_;
};

}  // namespace mesocap
