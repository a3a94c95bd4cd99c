// The report model of `stsv compare`: HTML escaping, the shell-quoted command line, aligned
// text tables and the page's structure.
#include "cli/compare_report.h"

#include <gtest/gtest.h>

namespace stsv {
namespace {

TEST(CompareReport, EscapesEveryHtmlSpecialCharacter) {
    EXPECT_EQ(escapeHtml("a&b <c> \"d\" 'e'"), "a&amp;b &lt;c&gt; &quot;d&quot; &#39;e&#39;");
    EXPECT_EQ(escapeHtml("plain/text_1.png"), "plain/text_1.png");
    EXPECT_EQ(escapeHtml("&amp;"), "&amp;amp;") << "escaping is not idempotent, it is applied once";
}

TEST(CompareReport, CommandLineIsQuotedForAShell) {
    EXPECT_EQ(
        shellCommandLine({"stsv", "compare", "fence", "--size", "32x32", "--methods", "stsv,dcs+stsv/cpu"}),
        "stsv compare fence --size 32x32 --methods stsv,dcs+stsv/cpu");
    EXPECT_EQ(shellCommandLine({"stsv", "a b", "it's", "", "$HOME"}), "stsv 'a b' 'it'\\''s' '' '$HOME'");
}

TEST(CompareReport, TextTableAlignsColumns) {
    ReportTable t;
    t.caption = "caption:";
    t.header = {"method", "rmse"};
    t.rows = {{"a", "0.5"}, {"longer name", "12.25"}};
    t.note = "(note)";
    EXPECT_EQ(formatTextTable(t), "caption:\n"
                                  "method        rmse\n"
                                  "a              0.5\n"
                                  "longer name  12.25\n"
                                  "(note)\n");
}

TEST(CompareReport, PageHasTablesImagesAndNoScript) {
    Report r;
    r.title = "stsv compare: <scene>";
    r.commandLine = "stsv compare '<scene>'";
    r.settings = {{"size", "32x32"}};
    ReportTable t;
    t.header = {"method", "vis RMSE"};
    t.rows = {{"stsv/cpu", "0.1"}};
    r.tables = {t};
    r.imageRows = {{"dcs+stsv/cpu", "", {{"dcs+stsv/cpu: lit", "dcs+stsv_cpu_lit.png", 64, 48}}}};
    const std::string html = reportHtml(r);
    EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
    EXPECT_NE(html.find("<title>stsv compare: &lt;scene&gt;</title>"), std::string::npos) << html;
    EXPECT_NE(html.find("<code>stsv compare &#39;&lt;scene&gt;&#39;</code>"), std::string::npos) << html;
    EXPECT_NE(html.find("<td>stsv/cpu</td><td>0.1</td>"), std::string::npos) << html;
    EXPECT_NE(html.find("<img src=\"dcs%2Bstsv_cpu_lit.png\" width=\"64\" height=\"48\""), std::string::npos)
        << html;
    EXPECT_NE(html.find("<figcaption>dcs+stsv/cpu: lit</figcaption>"), std::string::npos) << html;
    EXPECT_EQ(html.find("<script"), std::string::npos);
    EXPECT_EQ(html.find("<scene>"), std::string::npos);
}

/// The data-x / data-y of the chart's group for `name` (−1 when absent).
std::pair<double, double> chartPoint(const std::string& svg, const std::string& name) {
    const std::string key = "data-method=\"" + name + "\" data-x=\"";
    const auto at = svg.find(key);
    if (at == std::string::npos) return {-1.0, -1.0};
    const double x = std::stod(svg.substr(at + key.size()));
    const auto y = svg.find("data-y=\"", at);
    return {x, std::stod(svg.substr(y + 8))};
}

TEST(CompareReport, ChartPlacesEachMethodByTimeAndErrorWithItsFamilysMarker) {
    ReportChart c;
    c.yLabel = "visibility RMSE";
    c.points = {{"reference/cpu", "ground truth", 2000.0, 0.0146},
                {"stsv/vulkan", "object-based", 200.0, 0.0146},
                {"pcf/vulkan", "image-based", 700.0, 0.04},
                {"<odd>", "image-based", 20.0, 0.09}};
    const std::string svg = chartSvg(c);
    ASSERT_EQ(svg.rfind("<svg", 0), 0u) << svg;
    EXPECT_EQ(svg.find("<script"), std::string::npos);
    const auto ref = chartPoint(svg, "reference/cpu"), stsv = chartPoint(svg, "stsv/vulkan"),
               pcf = chartPoint(svg, "pcf/vulkan"), odd = chartPoint(svg, "&lt;odd&gt;");
    ASSERT_GE(odd.first, 0.0) << "names are escaped";
    // Time on a log axis: 20 < 200 < 700 < 2000 ms left to right, 10× apart → equal steps.
    EXPECT_LT(odd.first, stsv.first);
    EXPECT_LT(stsv.first, pcf.first);
    EXPECT_LT(pcf.first, ref.first);
    EXPECT_NEAR(stsv.first - odd.first, ref.first - stsv.first, 0.2);
    // Error upwards: equal errors on one line, larger ones higher (smaller SVG y).
    EXPECT_DOUBLE_EQ(ref.second, stsv.second);
    EXPECT_LT(pcf.second, stsv.second);
    EXPECT_LT(odd.second, pcf.second);
    // One marker per family: circle, square, diamond (plus the legend's three).
    auto count = [&](const std::string& what) {
        std::size_t n = 0;
        for (auto at = svg.find(what); at != std::string::npos; at = svg.find(what, at + 1)) ++n;
        return n;
    };
    EXPECT_EQ(count("<circle"), 2u);
    EXPECT_EQ(count("<rect x="), 1u + 2u + 1u); // the frame, two image-based points, the legend's square
    EXPECT_EQ(count("<path"), 2u);
    // No points, no chart; a page with points carries it.
    EXPECT_EQ(chartSvg(ReportChart{}), "");
    Report r;
    r.chart = c;
    EXPECT_NE(reportHtml(r).find("<h2>Error against time</h2>"), std::string::npos);
    EXPECT_EQ(reportHtml(Report{}).find("<h2>Error against time</h2>"), std::string::npos);
}

} // namespace
} // namespace stsv
