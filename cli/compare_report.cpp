#include "cli/compare_report.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
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

const char* const REPORT_STYLE = R"(
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
p.headline { font-size: 15px; max-width: 1100px; }
p.note { font-size: 12px; color: #444; margin: 2px 0 10px; max-width: 1100px; }
div.images { display: flex; flex-wrap: wrap; gap: 12px; }
figure { margin: 0; }
figure img { display: block; image-rendering: pixelated; border: 1px solid #888; }
figcaption { font-size: 13px; padding: 2px 0; }
)";

} // namespace

namespace {

std::string svgNumber(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f", v);
    return text;
}

std::string tickLabel(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", v);
    return text;
}

} // namespace

std::string chartSvg(const ReportChart& chart) {
    std::vector<ReportPoint> points;
    for (const ReportPoint& p : chart.points)
        if (p.ms > 0.0 && std::isfinite(p.ms) && std::isfinite(p.error) && p.error >= 0.0)
            points.push_back(p);
    if (points.empty()) return "";
    constexpr double W = 720, H = 400, left = 64, right = 170, top = 16, bottom = 48;
    const double plotW = W - left - right, plotH = H - top - bottom;
    double lo = 1e300, hi = 0.0, topError = 0.0;
    for (const ReportPoint& p : points) {
        lo = std::min(lo, p.ms);
        hi = std::max(hi, p.ms);
        topError = std::max(topError, p.error);
    }
    // Decades around the times; errors from 0 to a round value above the largest.
    const double x0 = std::floor(std::log10(lo)), x1 = std::max(std::ceil(std::log10(hi)), x0 + 1.0);
    const double step = std::pow(10.0, std::floor(std::log10(std::max(topError, 1e-6))));
    double y1 = std::ceil(std::max(topError, 1e-6) * 1.05 / step) * step;
    const auto X = [&](double ms) { return left + (std::log10(ms) - x0) / (x1 - x0) * plotW; };
    const auto Y = [&](double e) { return top + (1.0 - e / y1) * plotH; };
    std::ostringstream out;
    out << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H
        << "\" viewBox=\"0 0 " << W << " " << H << "\" font-family=\"sans-serif\" font-size=\"11\">\n";
    out << "<rect x=\"" << left << "\" y=\"" << top << "\" width=\"" << plotW << "\" height=\"" << plotH
        << "\" fill=\"none\" stroke=\"#888\"/>\n";
    // x ticks: 1, 2 and 5 of each decade.
    for (double d = x0; d <= x1; d += 1.0)
        for (const double m : {1.0, 2.0, 5.0}) {
            const double ms = m * std::pow(10.0, d);
            if (std::log10(ms) > x1 + 1e-9) break;
            const double x = X(ms);
            out << "<line x1=\"" << svgNumber(x) << "\" y1=\"" << top << "\" x2=\"" << svgNumber(x)
                << "\" y2=\"" << top + plotH << "\" stroke=\"" << (m == 1.0 ? "#ccc" : "#eee") << "\"/>\n";
            out << "<text x=\"" << svgNumber(x) << "\" y=\"" << top + plotH + 14
                << "\" text-anchor=\"middle\">" << tickLabel(ms) << "</text>\n";
        }
    const int yTicks = int(std::lround(y1 / step));
    const double yStep = yTicks > 6 ? 2.0 * step : yTicks < 3 ? 0.5 * step : step;
    for (double e = 0.0; e <= y1 + 1e-12; e += yStep) {
        const double y = Y(e);
        out << "<line x1=\"" << left << "\" y1=\"" << svgNumber(y) << "\" x2=\"" << left + plotW << "\" y2=\""
            << svgNumber(y) << "\" stroke=\"#eee\"/>\n";
        out << "<text x=\"" << left - 6 << "\" y=\"" << svgNumber(y + 4) << "\" text-anchor=\"end\">"
            << tickLabel(std::round(e / yStep * 1e6) / 1e6 * yStep) << "</text>\n";
    }
    out << "<text x=\"" << left + plotW / 2 << "\" y=\"" << H - 10
        << "\" text-anchor=\"middle\">frame time, ms (log scale)</text>\n";
    out << "<text transform=\"translate(14 " << top + plotH / 2 << ") rotate(-90)\" text-anchor=\"middle\">"
        << escapeHtml(chart.yLabel) << "</text>\n";
    const auto marker = [](const std::string& family, double x, double y) {
        std::ostringstream m;
        if (family == "object-based")
            m << "<circle cx=\"" << svgNumber(x) << "\" cy=\"" << svgNumber(y)
              << "\" r=\"5\" fill=\"#1f77b4\"/>";
        else if (family == "image-based")
            m << "<rect x=\"" << svgNumber(x - 4.5) << "\" y=\"" << svgNumber(y - 4.5)
              << "\" width=\"9\" height=\"9\" fill=\"#d62728\"/>";
        else
            m << "<path d=\"M" << svgNumber(x) << " " << svgNumber(y - 6)
              << " l6 6 l-6 6 l-6 -6 z\" fill=\"#555\"/>";
        return m.str();
    };
    for (const ReportPoint& p : points) {
        const double x = X(p.ms), y = Y(p.error);
        out << "<g data-method=\"" << escapeHtml(p.name) << "\" data-x=\"" << svgNumber(x) << "\" data-y=\""
            << svgNumber(y) << "\"><title>" << escapeHtml(p.name) << ": " << tickLabel(p.ms) << " ms, "
            << tickLabel(p.error) << "</title>" << marker(p.family, x, y) << "<text x=\"" << svgNumber(x + 7)
            << "\" y=\"" << svgNumber(y - 6) << "\">" << escapeHtml(p.name) << "</text></g>\n";
    }
    // Legend.
    double ly = top + 12;
    for (const char* family : {"object-based", "image-based", "ground truth"}) {
        out << marker(family, left + plotW + 20, ly) << "<text x=\"" << left + plotW + 32 << "\" y=\""
            << svgNumber(ly + 4) << "\">" << family << "</text>\n";
        ly += 20;
    }
    out << "</svg>\n";
    return out.str();
}

std::string reportHtml(const Report& r) {
    std::ostringstream out;
    out << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>"
        << escapeHtml(r.title) << "</title>\n<style>" << REPORT_STYLE << "</style>\n</head>\n<body>\n";
    out << "<h1>" << escapeHtml(r.title) << "</h1>\n";
    out << "<p>command: <code>" << escapeHtml(r.commandLine) << "</code></p>\n";
    out << "<table class=\"settings\">\n";
    for (const auto& [name, value] : r.settings)
        out << "<tr><th>" << escapeHtml(name) << "</th><td>" << escapeHtml(value) << "</td></tr>\n";
    out << "</table>\n";

    out << "<h2>Errors</h2>\n";
    if (!r.headline.empty()) out << "<p class=\"headline\">" << escapeHtml(r.headline) << "</p>\n";
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

    const std::string chart = chartSvg(r.chart);
    if (!chart.empty()) {
        out << "<h2>Error against time</h2>\n";
        if (!r.chart.caption.empty()) out << "<p class=\"note\">" << escapeHtml(r.chart.caption) << "</p>\n";
        out << chart;
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
