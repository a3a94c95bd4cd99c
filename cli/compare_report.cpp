#include "cli/compare_report.h"

#include <algorithm>
#include <cctype>
#include <sstream>

namespace stsv {

std::string formatTextTable(const ReportTable& table) {
    std::vector<std::size_t> widths(table.header.size(), 0);
    auto widen = [&](const std::vector<std::string>& cells) {
        if (widths.size() < cells.size()) widths.resize(cells.size(), 0);
        for (std::size_t c = 0; c < cells.size(); ++c) widths[c] = std::max(widths[c], cells[c].size());
    };
    widen(table.header);
    for (const auto& row : table.rows) widen(row);
    std::ostringstream out;
    auto line = [&](const std::vector<std::string>& cells) {
        std::string text;
        for (std::size_t c = 0; c < cells.size(); ++c) {
            const std::string pad(widths[c] - cells[c].size(), ' ');
            text += c == 0 ? cells[c] + pad : "  " + pad + cells[c];
        }
        out << text << '\n';
    };
    if (!table.caption.empty()) out << table.caption << '\n';
    line(table.header);
    for (const auto& row : table.rows) line(row);
    if (!table.note.empty()) out << table.note << '\n';
    return out.str();
}

std::string escapeHtml(const std::string& text) {
    std::string out;
    out.reserve(text.size());
    for (char c : text) switch (c) {
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
    return out;
}

std::string shellCommandLine(const std::vector<std::string>& argv) {
    std::string out;
    for (const std::string& a : argv) {
        const bool plain = !a.empty() && std::all_of(a.begin(), a.end(), [](unsigned char c) {
            return std::isalnum(c) || std::string("_-./=,:+@%").find(char(c)) != std::string::npos;
        });
        std::string quoted = "'";
        for (char c : a) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
        quoted += "'";
        out += (out.empty() ? "" : " ") + (plain ? a : quoted);
    }
    return out;
}

namespace {

/// A relative path as a URL path: unreserved characters and '/' kept, the rest percent-encoded.
std::string urlPath(const std::string& path) {
    static const char* const digits = "0123456789ABCDEF";
    std::string out;
    for (unsigned char c : path) {
        if (std::isalnum(c) || c == '/' || c == '.' || c == '-' || c == '_' || c == '~') {
            out += char(c);
        } else {
            out += '%';
            out += digits[c >> 4];
            out += digits[c & 15];
        }
    }
    return out;
}

const char* const kStyle = R"(
body { font-family: sans-serif; margin: 16px 24px; color: #111; background: #fff; }
h1 { font-size: 22px; margin: 0 0 8px; }
h2 { font-size: 18px; margin: 20px 0 6px; }
h3 { font-size: 15px; margin: 14px 0 4px; }
code { background: #f2f2f2; padding: 2px 4px; word-break: break-all; }
table { border-collapse: collapse; margin: 4px 0; }
th, td { border: 1px solid #bbb; padding: 2px 8px; font-family: monospace; font-size: 13px; text-align: right; }
th:first-child, td:first-child { text-align: left; }
caption { text-align: left; font-weight: bold; padding: 4px 0; }
table.settings td { text-align: left; }
p.note { font-size: 12px; color: #444; margin: 2px 0 10px; max-width: 1100px; }
div.images { display: flex; flex-wrap: wrap; gap: 12px; }
figure { margin: 0; }
figure img { display: block; image-rendering: pixelated; border: 1px solid #888; }
figcaption { font-size: 13px; padding: 2px 0; }
)";

} // namespace

std::string reportHtml(const Report& r) {
    std::ostringstream out;
    out << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>"
        << escapeHtml(r.title) << "</title>\n<style>" << kStyle << "</style>\n</head>\n<body>\n";
    out << "<h1>" << escapeHtml(r.title) << "</h1>\n";
    out << "<p>command: <code>" << escapeHtml(r.commandLine) << "</code></p>\n";
    out << "<table class=\"settings\">\n";
    for (const auto& [name, value] : r.settings)
        out << "<tr><th>" << escapeHtml(name) << "</th><td>" << escapeHtml(value) << "</td></tr>\n";
    out << "</table>\n";

    out << "<h2>Errors</h2>\n";
    for (const ReportTable& t : r.tables) {
        out << "<table>\n";
        if (!t.caption.empty()) out << "<caption>" << escapeHtml(t.caption) << "</caption>\n";
        out << "<tr>";
        for (const std::string& h : t.header) out << "<th>" << escapeHtml(h) << "</th>";
        out << "</tr>\n";
        for (const auto& row : t.rows) {
            out << "<tr>";
            for (const std::string& cell : row) out << "<td>" << escapeHtml(cell) << "</td>";
            out << "</tr>\n";
        }
        out << "</table>\n";
        if (!t.note.empty()) out << "<p class=\"note\">" << escapeHtml(t.note) << "</p>\n";
    }

    out << "<h2>Images</h2>\n";
    if (!r.imagesNote.empty()) out << "<p class=\"note\">" << escapeHtml(r.imagesNote) << "</p>\n";
    if (!r.heatScale.file.empty())
        out << "<p><img src=\"" << escapeHtml(urlPath(r.heatScale.file)) << "\" width=\"" << r.heatScale.width
            << "\" height=\"" << r.heatScale.height << "\" alt=\"" << escapeHtml(r.heatScale.title)
            << "\"></p>\n";
    for (const ReportImageRow& row : r.imageRows) {
        out << "<h3>" << escapeHtml(row.name) << "</h3>\n";
        if (!row.note.empty()) out << "<p class=\"note\">" << escapeHtml(row.note) << "</p>\n";
        out << "<div class=\"images\">\n";
        for (const ReportImage& image : row.images)
            out << "<figure><img src=\"" << escapeHtml(urlPath(image.file)) << "\" width=\"" << image.width
                << "\" height=\"" << image.height << "\" alt=\"" << escapeHtml(image.title)
                << "\"><figcaption>" << escapeHtml(image.title) << "</figcaption></figure>\n";
        out << "</div>\n";
    }
    out << "</body>\n</html>\n";
    return out.str();
}

} // namespace stsv
