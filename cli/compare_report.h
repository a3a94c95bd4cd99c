// Tables and the static HTML page of `stsv compare`: one model of the report, printed as
// aligned text on the terminal and written as HTML (inline CSS, no scripts, images by relative
// path).
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace stsv {

/// A table of cells, the first column names the row.
struct ReportTable {
    std::string caption;
    std::vector<std::string> header;
    std::vector<std::vector<std::string>> rows;
    std::string note; ///< printed below the table
};

/// Columns right-aligned to their widest cell (the first left-aligned), two spaces apart; the
/// caption above, the note below.
std::string formatTextTable(const ReportTable& table);

struct ReportImage {
    std::string title; ///< e.g. "stsv/cpu: lit"
    std::string file;  ///< path relative to the page
    int width = 0;     ///< displayed CSS pixels (an integer multiple of the PNG's, drawn pixelated)
    int height = 0;
};

struct ReportImageRow {
    std::string name; ///< the method, or "converged reference"
    std::string note; ///< one line under the heading (may be empty)
    std::vector<ReportImage> images;
};

/// One method's point of the error-versus-time chart.
struct ReportPoint {
    std::string name;   ///< e.g. "stsv/vulkan"
    std::string family; ///< "object-based", "image-based" or "ground truth": the marker
    double ms = 0.0;    ///< frame time
    double error = 0.0; ///< visibility RMSE (compare: over the light-facing pixels)
};

struct ReportChart {
    std::string caption;
    std::string yLabel;
    std::vector<ReportPoint> points;
};

/// The chart as an inline SVG element (no scripts): frame time on a logarithmic x axis, error on
/// a linear y axis from 0, a marker per family (circle object-based, square image-based, diamond
/// ground truth) and each point labelled with its name. Empty for a chart without points.
std::string chartSvg(const ReportChart& chart);

struct Report {
    std::string title;
    std::string commandLine;
    std::vector<std::pair<std::string, std::string>> settings; ///< name, value
    std::string headline; ///< what the compare found, in a sentence or two, above the tables (may be empty)
    std::vector<ReportTable> tables;
    ReportChart chart;      ///< error against time, after the tables (none without points)
    std::string imagesNote; ///< what the heat maps show
    ReportImage heatScale;  ///< the heat maps' colour scale with its numbers (no file: none)
    std::vector<ReportImageRow> imageRows;
};

/// `text` with &, <, >, " and ' replaced by character references (safe in text and attributes).
std::string escapeHtml(const std::string& text);

/// The command line as one could paste it into a POSIX shell: arguments with characters other
/// than letters, digits and _-./=,:+@% single-quoted.
std::string shellCommandLine(const std::vector<std::string>& argv);

/// The whole page.
std::string reportHtml(const Report& report);

} // namespace stsv
