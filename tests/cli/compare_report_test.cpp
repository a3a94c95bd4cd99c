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

} // namespace
} // namespace stsv
