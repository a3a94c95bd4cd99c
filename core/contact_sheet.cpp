#include "core/contact_sheet.h"

#include "core/error.h"

#include <stb/stb_easy_font.h>

#include <algorithm>

namespace stsv {

namespace {

/// stb_easy_font indexes its glyph table by (c − 32) and reads c + 1: only ' ' … '~' are valid.
std::string easyFontText(const std::string& text) {
    std::string out = text;
    for (char& c : out)
        if (c < ' ' || c > '~') c = '?';
    return out;
}

void checkColourImage(const Image8& image, const char* what) {
    if (image.channels != 3 && image.channels != 4)
        throw Error(std::string(what) + ": needs an RGB or RGBA image, not " +
                    std::to_string(image.channels) + " channel(s)");
}

} // namespace

int textWidth(const std::string& text, int scale) {
    std::string line = easyFontText(text);
    return scale * stb_easy_font_width(line.data());
}

int textLineHeight(int scale) {
    return 12 * scale;
}

void fillRect(Image8& image, int x, int y, int width, int height, Rgb8 colour) {
    checkColourImage(image, "fillRect");
    const int x0 = std::max(x, 0), x1 = std::min(x + width, image.width);
    const int y0 = std::max(y, 0), y1 = std::min(y + height, image.height);
    for (int py = y0; py < y1; ++py)
        for (int px = x0; px < x1; ++px)
            for (int c = 0; c < 3; ++c) image.at(px, py, c) = colour[std::size_t(c)];
}

void drawText(Image8& image, int x, int y, const std::string& text, int scale, Rgb8 colour, int clipRight) {
    checkColourImage(image, "drawText");
    std::string line = easyFontText(text);
    line.erase(std::find(line.begin(), line.end(), '\n'), line.end());
    // stb_easy_font emits 4 vertices of 16 bytes (x, y, z floats, RGBA8) per quad, about 270 bytes
    // per character; the quads are axis-aligned with integer corners in font units.
    std::vector<char> vertices(line.size() * 400 + 64);
    const int quads =
        stb_easy_font_print(0.0f, 0.0f, line.data(), nullptr, vertices.data(), int(vertices.size()));
    const int right = clipRight < 0 ? image.width : std::min(clipRight, image.width);
    for (int q = 0; q < quads; ++q) {
        const float* v0 = reinterpret_cast<const float*>(vertices.data() + std::size_t(q) * 64);
        const float* v2 = reinterpret_cast<const float*>(vertices.data() + std::size_t(q) * 64 + 32);
        const int qx0 = x + scale * int(v0[0]), qy0 = y + scale * int(v0[1]);
        const int qx1 = x + scale * int(v2[0]), qy1 = y + scale * int(v2[1]);
        fillRect(image, qx0, qy0, std::min(qx1, right) - qx0, qy1 - qy0, colour);
    }
}

void pasteScaled(Image8& target, const Image8& source, int x, int y, int scale) {
    checkColourImage(target, "pasteScaled");
    for (int sy = 0; sy < source.height; ++sy)
        for (int sx = 0; sx < source.width; ++sx) {
            Rgb8 colour;
            for (int c = 0; c < 3; ++c)
                colour[std::size_t(c)] = source.at(sx, sy, source.channels >= 3 ? c : 0);
            fillRect(target, x + sx * scale, y + sy * scale, scale, scale, colour);
        }
}

int tileScaleFor(int sourceWidth, int sourceHeight, int targetSide) {
    const int side = std::max({sourceWidth, sourceHeight, 1});
    return std::max(1, targetSide / side);
}

SheetLayout sheetLayout(int sourceWidth, int sourceHeight, int columns, int rows) {
    SheetLayout layout;
    layout.tileScale = tileScaleFor(sourceWidth, sourceHeight);
    layout.tileWidth = sourceWidth * layout.tileScale;
    layout.tileHeight = sourceHeight * layout.tileScale;
    layout.columns = columns;
    layout.rows = rows;
    return layout;
}

Image8 contactSheet(const SheetLayout& layout, const std::vector<std::string>& columnTitles,
                    const std::vector<SheetRow>& rows) {
    Image8 sheet;
    sheet.width = layout.width();
    sheet.height = layout.height();
    sheet.channels = 3;
    sheet.pixels.resize(std::size_t(sheet.width) * std::size_t(sheet.height) * 3);
    fillRect(sheet, 0, 0, sheet.width, sheet.height, SHEET_BACKGROUND);
    const int textInset = layout.padding / 2; // the text's top within its band
    for (int c = 0; c < layout.columns && c < int(columnTitles.size()); ++c)
        drawText(sheet, layout.tileX(c), layout.padding + textInset, columnTitles[std::size_t(c)],
                 layout.textScale, SHEET_TEXT, layout.tileX(c) + layout.tileWidth);
    for (int r = 0; r < layout.rows && r < int(rows.size()); ++r) {
        const SheetRow& row = rows[std::size_t(r)];
        drawText(sheet, layout.tileX(0), layout.labelY(r) + textInset, row.label, layout.textScale,
                 SHEET_TEXT);
        for (int c = 0; c < layout.columns && c < int(row.tiles.size()); ++c) {
            const Image8& tile = row.tiles[std::size_t(c)];
            if (tile.width == 0) continue;
            // Clip a tile larger than its cell by pasting through a cell-sized window.
            Image8 cell;
            cell.width = std::min(tile.width * layout.tileScale, layout.tileWidth);
            cell.height = std::min(tile.height * layout.tileScale, layout.tileHeight);
            cell.channels = 3;
            cell.pixels.assign(std::size_t(cell.width) * std::size_t(cell.height) * 3, 0);
            pasteScaled(cell, tile, 0, 0, layout.tileScale);
            pasteScaled(sheet, cell, layout.tileX(c), layout.tileY(r), 1);
        }
    }
    return sheet;
}

} // namespace stsv
