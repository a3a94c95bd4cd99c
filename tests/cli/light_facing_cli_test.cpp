// compare's light-facing visibility error: the figure over the pixels that face a light (the
// headline and the ranking), its arithmetic on hand-made images, and the command's tables, JSON
// and report on small scenes with the cpu backend.
#include "cli/cli_util.h"
#include "core/error.h"
#include "sampling/light_sampling.h"
#include "tests/cli/cli_test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <regex>
#include <sstream>

namespace stsv {
namespace {

using test::CliResult;
using test::readJson;
using test::readText;
using test::runStsv;
using test::ScratchDir;

/// A rectangle facing down (normal −y) at height 1 over the origin.
Light rectangleAbove() {
    Light l{};
    l.type = LIGHT_RECTANGLE;
    l.position = vec3(0, 1, 0);
    l.axisU = vec3(0.5f, 0, 0);
    l.axisV = vec3(0, 0, 0.5f);
    l.normal = vec3(0, -1, 0);
    l.radius = length(l.axisU + l.axisV);
    l.radiance = vec3(1.0f);
    return l;
}

/// A one-row G-buffer: per pixel 'F' a point at the origin turned up to the light (faces it),
/// 'A' one turned down (faces away), '.' background.
GBuffer rowOf(const std::string& kinds) {
    GBuffer g(int(kinds.size()), 1);
    for (std::size_t x = 0; x < kinds.size(); ++x) {
        if (kinds[x] == '.') continue;
        g.position[x] = vec3(0.0f);
        g.normal[x] = kinds[x] == 'F' ? vec3(0, 1, 0) : vec3(0, -1, 0);
        g.triangle[x] = 0;
    }
    return g;
}

ImageF visibilityRow(const std::vector<float>& values) {
    ImageF image(int(values.size()), 1, 1);
    image.pixels = values;
    return image;
}

TEST(LightFacingError, ErrorsOnlyOnPixelsFacingAwayLeaveTheFacingFigureZero) {
    const LightFacingMask mask = lightFacingMask(rowOf("FAF.A"), {rectangleAbove()}, 1000.0f, 5, 1);
    EXPECT_EQ(mask.selected, (std::vector<std::uint8_t>{1, 0, 1, 0, 0}));
    EXPECT_EQ(mask.facing, 2u);
    EXPECT_EQ(mask.away, 2u);
    EXPECT_EQ(mask.background, 1u);
    const ImageF reference = visibilityRow({0.25f, 0.0f, 1.0f, 1.0f, 0.5f});
    const ImageF method = visibilityRow({0.25f, 1.0f, 1.0f, 1.0f, 0.0f}); // off on the 'A' pixels only
    const RegionError facing = compareImagesWhere(method, reference, mask.selected);
    EXPECT_EQ(facing.rmse, 0.0);
    EXPECT_EQ(facing.bias, 0.0);
    EXPECT_EQ(facing.maxAbs, 0.0);
    EXPECT_EQ(facing.pixels, 2u);
    EXPECT_GT(compareImages(method, reference).rmse, 0.0); // the whole-image figure sees them
}

TEST(LightFacingError, ErrorsOnFacingPixelsGiveTheHandComputedFigures) {
    // Four facing pixels off by +0.5, −0.25, 0 and 0; the pixel facing away off by 1 (not
    // counted), the background pixel equal.
    //   RMSE = √((0.5² + 0.25² + 0 + 0) / 4) = √(0.3125 / 4) = √0.078125 = 0.27950849718747373
    //   bias = (0.5 − 0.25 + 0 + 0) / 4 = 0.0625,  max = 0.5,  pixels = 4
    const LightFacingMask mask = lightFacingMask(rowOf("FFAFF."), {rectangleAbove()}, 1000.0f, 6, 1);
    const ImageF reference = visibilityRow({0.25f, 0.5f, 0.0f, 1.0f, 0.125f, 1.0f});
    const ImageF method = visibilityRow({0.75f, 0.25f, 1.0f, 1.0f, 0.125f, 1.0f});
    const RegionError e = compareImagesWhere(method, reference, mask.selected);
    EXPECT_EQ(e.pixels, 4u);
    // Every value and difference is exact in float and double; the sums and the square root
    // round once or twice in double: 1e-15 is a few ulp of these magnitudes.
    EXPECT_NEAR(e.rmse, 0.27950849718747373, 1e-15);
    EXPECT_NEAR(e.bias, 0.0625, 1e-15);
    EXPECT_EQ(e.maxAbs, 0.5);
    // No pixel selected: nothing to measure, every figure 0.
    const RegionError none = compareImagesWhere(method, reference, std::vector<std::uint8_t>(6, 0));
    EXPECT_EQ(none.pixels, 0u);
    EXPECT_EQ(none.rmse, 0.0);
    // A mask of another size, images of different sizes.
    EXPECT_THROW(compareImagesWhere(method, reference, std::vector<std::uint8_t>(5, 1)), UsageError);
    EXPECT_THROW(compareImagesWhere(method, visibilityRow({1.0f}), std::vector<std::uint8_t>(6, 1)),
                 UsageError);
}

/// The lines of the ranking table that compare prints: rank, method, then the figures.
std::vector<std::vector<std::string>> rankingLines(const std::string& out) {
    std::vector<std::vector<std::string>> lines;
    const std::size_t start = out.find("ranking by visibility RMSE over the light-facing pixels");
    if (start == std::string::npos) return lines;
    std::istringstream in(out.substr(start));
    std::string line;
    std::getline(in, line); // caption
    std::getline(in, line); // header
    while (std::getline(in, line) && !line.empty() && line[0] != '(') {
        std::istringstream words(line);
        std::vector<std::string> cells;
        for (std::string w; words >> w;) cells.push_back(w);
        lines.push_back(cells);
    }
    return lines;
}

std::string fixed5(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.5f", v);
    return text;
}

/// data-y of the chart's point for `name` in the report (−1 when absent).
double chartY(const std::string& html, const std::string& name) {
    std::smatch m;
    if (!std::regex_search(
            html, m, std::regex("data-method=\"" + name + "\" data-x=\"[0-9.]+\" data-y=\"([0-9.]+)\"")))
        return -1.0;
    return std::stod(m[1]);
}

TEST(LightFacingCli, RankingFollowsTheLightFacingFigureWhereTheWholeImageOrderDiffers) {
    // On the knot at 48×48 and 16 samples, pw's visibility is closer to the reference's over the
    // whole image (0.035 against 0.036) and PCSS's over the pixels that face the light (0.032
    // against 0.038: PCSS errs most where the knot faces away): the two orders differ, and the ranking must
    // follow the light-facing one. A renderer change that makes them agree leaves this test without its
    // point: pick another case.
    ScratchDir dir;
    const std::vector<std::string> args = {
        "compare", "knot",   "--methods",        "pw/cpu,pcss/cpu", "--size",           "48x48", "--samples",
        "16",      "--json", dir.file("c.json"), "--report",        dir.file("report"), "-q"};
    const CliResult r = runStsv(args);
    ASSERT_EQ(r.code, 0) << test::describe(args, r);
    const nlohmann::json j = readJson(dir.file("c.json"));
    ASSERT_EQ(j["rows"].size(), 3u);
    const nlohmann::json &reference = j["rows"][0], &pw = j["rows"][1], &pcss = j["rows"][2];
    ASSERT_EQ(pw["method"], "pw");
    ASSERT_EQ(pcss["method"], "pcss");
    // The mask: every pixel is of one kind; some face away, most face the light; every row
    // counts the same pixels.
    const nlohmann::json& mask = j["light_facing"];
    const std::size_t facing = mask["facing_pixels"], away = mask["away_pixels"],
                      background = mask["background_pixels"];
    EXPECT_EQ(facing + away + background, 48u * 48u);
    EXPECT_GT(away, 0u);
    EXPECT_GT(facing, away);
    for (const nlohmann::json& row : j["rows"]) EXPECT_EQ(row["visibility_facing"]["pixels"], facing);
    EXPECT_EQ(reference["visibility_facing"]["rmse"], 0.0);
    EXPECT_TRUE(reference["rank"].is_null());
    // The case: the orders differ.
    const double pwAll = pw["visibility"]["rmse"], pcssAll = pcss["visibility"]["rmse"];
    const double pwFacing = pw["visibility_facing"]["rmse"], pcssFacing = pcss["visibility_facing"]["rmse"];
    ASSERT_LT(pwAll, pcssAll) << "whole image";
    ASSERT_LT(pcssFacing, pwFacing) << "light-facing pixels";
    // The facing pixels are a subset: their squared error is at most the whole image's.
    EXPECT_LE(pwFacing * pwFacing * double(facing), pwAll * pwAll * 48.0 * 48.0 * (1.0 + 1e-9));
    // The JSON's ranking and ranks follow the facing figure.
    EXPECT_EQ(j["ranking"]["by"], "visibility_facing.rmse");
    EXPECT_EQ(j["ranking"]["methods"], nlohmann::json({"pcss/cpu", "pw/cpu"}));
    EXPECT_EQ(pcss["rank"], 1);
    EXPECT_EQ(pw["rank"], 2);
    // The printed ranking: pcss first, with the JSON's figures, and the rule said in a sentence.
    const auto lines = rankingLines(r.out);
    ASSERT_EQ(lines.size(), 2u) << r.out;
    EXPECT_EQ(lines[0][0], "1");
    EXPECT_EQ(lines[0][1], "pcss/cpu");
    EXPECT_EQ(lines[0][2], fixed5(pcssFacing));
    EXPECT_EQ(lines[1][0], "2");
    EXPECT_EQ(lines[1][1], "pw/cpu");
    EXPECT_EQ(lines[1][2], fixed5(pwFacing));
    // The whole-image figure and the lit image's RMSE beside it.
    EXPECT_EQ(lines[1][5], fixed5(pwAll));
    EXPECT_EQ(lines[1][6], fixed5(pw["lit"]["rmse"].get<double>()));
    EXPECT_NE(r.out.find("ranked by the visibility error over the light-facing pixels"), std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find(std::to_string(facing) + " of the " + std::to_string(facing + away) +
                         " pixels with a surface"),
              std::string::npos)
        << r.out;
    // The report: the headline sentence names the rule and the order; the chart plots the facing
    // figure (pcss's smaller error lower on the chart, at a larger y).
    const std::string html = readText(dir.file("report/index.html"));
    const std::size_t headline = html.find("Ranked by visibility RMSE over the light-facing pixels");
    ASSERT_NE(headline, std::string::npos) << html.substr(0, 3000);
    const std::size_t first = html.find("1. pcss/cpu " + fixed5(pcssFacing), headline);
    const std::size_t second = html.find("2. pw/cpu " + fixed5(pwFacing), headline);
    EXPECT_NE(first, std::string::npos) << html.substr(headline, 600);
    EXPECT_NE(second, std::string::npos) << html.substr(headline, 600);
    EXPECT_NE(html.find("light-facing visibility RMSE vs reference"), std::string::npos);
    const double pcssY = chartY(html, "pcss/cpu"), pwY = chartY(html, "pw/cpu");
    ASSERT_GT(pcssY, 0.0);
    ASSERT_GT(pwY, 0.0);
    EXPECT_GT(pcssY, pwY);
}

TEST(LightFacingCli, ConvergedReferenceGivesTheFacingFigureAndRanksByIt) {
    // With K = 1 the converged reference is the equal-sample one: the converged facing figures
    // equal the equal-sample ones, the noise floor's is 0, and the ranking says it uses the
    // converged figure.
    ScratchDir dir;
    const std::vector<std::string> args = {
        "compare",          "fence", "--methods",  "pcf/cpu,pcss/cpu,stsv/cpu",
        "--size",           "32x24", "--samples",  "16",
        "--converged",      "1",     "--no-cache", "--json",
        dir.file("c.json"), "-q"};
    const CliResult r = runStsv(args);
    ASSERT_EQ(r.code, 0) << test::describe(args, r);
    const nlohmann::json j = readJson(dir.file("c.json"));
    EXPECT_EQ(j["ranking"]["by"], "converged.visibility_facing.rmse");
    EXPECT_EQ(j["noise_floor"]["visibility_facing"]["rmse"], 0.0);
    std::vector<std::pair<double, std::string>> figures;
    for (std::size_t i = 1; i < j["rows"].size(); ++i) {
        const nlohmann::json& row = j["rows"][i];
        EXPECT_EQ(row["converged"]["visibility_facing"], row["visibility_facing"]) << row.dump();
        figures.push_back({row["converged"]["visibility_facing"]["rmse"].get<double>(),
                           row["method"].get<std::string>() + "/" + row["backend"].get<std::string>()});
    }
    std::stable_sort(figures.begin(), figures.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    nlohmann::json order = nlohmann::json::array();
    for (const auto& f : figures) order.push_back(f.second);
    EXPECT_EQ(j["ranking"]["methods"], order);
    // pcf and pcss differ from the reference on facing pixels: a ranking with something to rank.
    EXPECT_GT(figures.back().first, 0.0);
    const auto lines = rankingLines(r.out);
    ASSERT_EQ(lines.size(), 4u) << r.out; // the noise floor, then the three methods
    EXPECT_EQ(lines[0][0], "-");
    EXPECT_EQ(lines[0][1], "noise");
    for (std::size_t k = 0; k < 3; ++k) {
        EXPECT_EQ(lines[k + 1][0], std::to_string(k + 1)) << r.out;
        EXPECT_EQ(lines[k + 1][1], order[k].get<std::string>()) << r.out;
    }
    EXPECT_NE(r.out.find("against the converged reference ("), std::string::npos) << r.out;
}

TEST(LightFacingCli, TwoVisibilityFilesSayTheyHaveNoFacingFigure) {
    ScratchDir dir;
    for (const char* method : {"stsv", "pcf"}) {
        const CliResult r =
            runStsv({"render", "fence", "--backend", "cpu", "--method", method, "--size", "24x16",
                     "--samples", "16", "--visibility", dir.file(std::string(method) + ".exr"), "-q"});
        ASSERT_EQ(r.code, 0) << r.err;
    }
    const CliResult r = runStsv({"compare", dir.file("stsv.exr"), dir.file("pcf.exr")});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("no light-facing figure: visibility files hold no normals"), std::string::npos)
        << r.out;
}

} // namespace
} // namespace stsv
