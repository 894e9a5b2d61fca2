#include "export/report.h"

#include <cstdio>

#include "core/atomic_file.h"
#include "core/provenance.h"
#include "core/session_layout.h"

namespace mesocap {

void Report::Heading(const std::string& text) { blocks_.push_back({Block::kHeading, text, "", {}, {}}); }
void Report::Paragraph(const std::string& text) { blocks_.push_back({Block::kParagraph, text, "", {}, {}}); }
void Report::Table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows) {
  blocks_.push_back({Block::kTable, "", "", header, rows});
}
void Report::FoldedTable(const std::string& summary, const std::vector<std::string>& header,
                         const std::vector<std::vector<std::string>>& rows) {
  blocks_.push_back({Block::kTable, summary, "", header, rows});
}
void Report::Picture(const std::string& path, const std::string& caption) {
  blocks_.push_back({Block::kPicture, caption, path, {}, {}});
}
void Report::Html(const std::string& html, const std::string& markdown_note) {
  blocks_.push_back({Block::kHtml, markdown_note, html, {}, {}});
}

std::string HtmlEscape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '<') out += "&lt;";
    else if (c == '>') out += "&gt;";
    else if (c == '&') out += "&amp;";
    else if (c == '"') out += "&quot;";
    else out += c;
  }
  return out;
}

Status Report::Write(const std::filesystem::path& dir) const {
  std::string md = "# " + title_ + "\n\n";
  std::string html = "<!doctype html><html><head><meta charset=\"utf-8\"><title>" + HtmlEscape(title_) +
                     "</title><style>body{font-family:sans-serif;max-width:1100px;margin:2em auto;color:#222}"
                     "table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #ccc;padding:3px 8px;"
                     "text-align:right}th{background:#eee}img{max-width:100%;border:1px solid #ccc}"
                     "figcaption{color:#555;font-size:90%}</style></head><body><h1>" + HtmlEscape(title_) + "</h1>\n";
  for (const Block& b : blocks_) {
    switch (b.kind) {
      case Block::kHeading:
        md += "## " + b.text + "\n\n";
        html += "<h2>" + HtmlEscape(b.text) + "</h2>\n";
        break;
      case Block::kParagraph:
        md += b.text + "\n\n";
        html += "<p>" + HtmlEscape(b.text) + "</p>\n";
        break;
      case Block::kTable: {
        if (!b.text.empty()) {  // folded
          md += "<details><summary>" + HtmlEscape(b.text) + "</summary>\n\n";
          html += "<details><summary>" + HtmlEscape(b.text) + "</summary>\n";
        }
        std::string sep;
        md += "|";
        html += "<table><tr>";
        for (const auto& h : b.header) {
          md += " " + h + " |";
          sep += "---|";
          html += "<th>" + HtmlEscape(h) + "</th>";
        }
        md += "\n|" + sep + "\n";
        html += "</tr>\n";
        for (const auto& row : b.rows) {
          md += "|";
          html += "<tr>";
          for (const auto& cell : row) {
            md += " " + cell + " |";
            html += "<td>" + HtmlEscape(cell) + "</td>";
          }
          md += "\n";
          html += "</tr>\n";
        }
        md += "\n";
        html += "</table>\n";
        if (!b.text.empty()) md += "</details>\n\n", html += "</details>\n";
        break;
      }
      case Block::kPicture:
        md += "![" + b.text + "](" + b.path + ")\n\n*" + b.text + "*\n\n";
        html += "<figure><img src=\"" + HtmlEscape(b.path) + "\"><figcaption>" + HtmlEscape(b.text) + "</figcaption></figure>\n";
        break;
      case Block::kHtml:
        md += b.text + "\n\n";
        html += b.path + "\n";
        break;
    }
  }
  const std::string footer = "mesocap " + std::string(Version()) + ", " + UtcNowIso8601() + ": `" + CommandLine() + "`";
  md += "---\n" + footer + "\n";
  html += "<hr><p><small>" + HtmlEscape(footer) + "</small></p></body></html>\n";
  MESOCAP_RETURN_IF_ERROR(WriteTextAtomically(dir / ReportMarkdownName(), md));
  return WriteTextAtomically(dir / ReportHtmlName(), html);
}

}  // namespace mesocap
