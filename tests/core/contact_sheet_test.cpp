// Image composition: text from stb_easy_font's quads, scaled pasting, the contact-sheet layout.
#include "core/contact_sheet.h"

#include <gtest/gtest.h>

namespace stsv {
namespace {

Image8 blank(int w, int h, Rgb8 colour = {0, 0, 0}) {
    Image8 image;
    image.width = w;
    image.height = h;
    image.channels = 3;
    image.pixels.resize(std::size_t(w) * std::size_t(h) * 3);
    fillRect(image, 0, 0, w, h, colour);
    return image;
}

int countColour(const Image8& image, Rgb8 colour, int x0 = 0, int y0 = 0, int x1 = -1, int y1 = -1) {
    x1 = x1 < 0 ? image.width : x1;
    y1 = y1 < 0 ? image.height : y1;
    int n = 0;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x)
            n += image.at(x, y, 0) == colour[0] && image.at(x, y, 1) == colour[1] &&
                 image.at(x, y, 2) == colour[2];
    return n;
}

TEST(ContactSheet, TextMetricsFollowStbEasyFont) {
    EXPECT_EQ(textLineHeight(1), 12);
    EXPECT_EQ(textLineHeight(2), 24);
    EXPECT_EQ(textWidth("", 2), 0);
    // Digits and the space advance 6 font units in stb_easy_font.
    EXPECT_EQ(textWidth("0123 ", 1), 30);
    EXPECT_EQ(textWidth("0123 ", 3), 90);
}

TEST(ContactSheet, TextIsDrawnInsideItsBoxAndClipped) {
    const Rgb8 white{255, 255, 255};
    Image8 image = blank(200, 40);
    drawText(image, 10, 5, "stsv/cpu", 2, white);
    const int inked = countColour(image, white);
    EXPECT_GT(inked, 50) << "the label left no pixels";
    // Every inked pixel lies in the text's box: x in [10, 10 + width), y in [5, 5 + line height).
    EXPECT_EQ(countColour(image, white, 10, 5, 10 + textWidth("stsv/cpu", 2), 5 + textLineHeight(2)), inked);
    // Drawn at scale 2, each font unit is a 2x2 block: the inked count is a multiple of 4.
    EXPECT_EQ(inked % 4, 0);

    Image8 clipped = blank(200, 40);
    drawText(clipped, 10, 5, "stsv/cpu", 2, white, 30);
    EXPECT_EQ(countColour(clipped, white, 30, 0), 0) << "ink right of clipRight";
    EXPECT_GT(countColour(clipped, white), 0);
    Image8 edge = blank(20, 10);
    drawText(edge, 15, 5, "\x01wide text \xff", 2, white); // off the image and non-ASCII: no crash
    EXPECT_GT(countColour(edge, white), 0);
}

TEST(ContactSheet, PasteScaledMakesBlocksAndGrayFromOneChannel) {
    Image8 gray;
    gray.width = 2;
    gray.height = 1;
    gray.channels = 1;
    gray.pixels = {10, 200};
    Image8 target = blank(7, 4, {1, 2, 3});
    pasteScaled(target, gray, 1, 1, 3);
    EXPECT_EQ(countColour(target, {10, 10, 10}), 9);
    EXPECT_EQ(countColour(target, {200, 200, 200}), 9);
    EXPECT_EQ(target.at(1, 1, 0), 10);
    EXPECT_EQ(target.at(4, 3, 1), 200);
    EXPECT_EQ(target.at(0, 0, 2), 3);
}

TEST(ContactSheet, LayoutSizesAndLabelledRows) {
    EXPECT_EQ(tileScaleFor(32, 24), 8);
    EXPECT_EQ(tileScaleFor(48, 48), 5);
    EXPECT_EQ(tileScaleFor(1024, 512), 1);
    const SheetLayout layout = sheetLayout(32, 24, 3, 2);
    EXPECT_EQ(layout.tileWidth, 256);
    EXPECT_EQ(layout.tileHeight, 192);
    // 3 tiles and 4 paddings wide; padding, the title band, then per row a band, a tile, padding.
    EXPECT_EQ(layout.width(), 3 * 256 + 4 * 8);
    EXPECT_EQ(layout.height(), 8 + 32 + 2 * (32 + 192 + 8));

    Image8 red = blank(32, 24, {255, 0, 0});
    Image8 green = blank(32, 24, {0, 255, 0});
    const Image8 sheet = contactSheet(layout, {"lit", "visibility", "heat"},
                                      {{"first", {red, green, Image8{}}}, {"second", {green, red, red}}});
    ASSERT_EQ(sheet.width, layout.width());
    ASSERT_EQ(sheet.height, layout.height());
    EXPECT_EQ(countColour(sheet, {255, 0, 0}), 3 * 256 * 192);
    EXPECT_EQ(countColour(sheet, {0, 255, 0}), 2 * 256 * 192);
    EXPECT_EQ(countColour(sheet, {255, 0, 0}, layout.tileX(0), layout.tileY(0), layout.tileX(0) + 256,
                          layout.tileY(0) + 192),
              256 * 192);
    for (int row = 0; row < 2; ++row)
        EXPECT_GT(countColour(sheet, SHEET_TEXT, 0, layout.labelY(row), sheet.width, layout.tileY(row)), 50)
            << "row " << row;
    EXPECT_GT(countColour(sheet, SHEET_TEXT, 0, 0, sheet.width, layout.labelY(0)), 50) << "column titles";
    // The empty cell stays background.
    EXPECT_EQ(countColour(sheet, SHEET_BACKGROUND, layout.tileX(2), layout.tileY(0), layout.tileX(2) + 256,
                          layout.tileY(0) + 192),
              256 * 192);
}

} // namespace
} // namespace stsv
