// Composition of 8-bit images: integer upscaling, pasting, text labels (stb_easy_font's quads
// rasterised into the image) and a contact sheet of labelled rows of tiles.
#pragma once

#include "core/image.h"

#include <array>
#include <string>
#include <vector>

namespace stsv {

using Rgb8 = std::array<std::uint8_t, 3>;

/// Width in pixels of `text` drawn at `scale` pixels per font unit (stb_easy_font's advances).
int textWidth(const std::string& text, int scale);
/// Height in pixels of one line of text at `scale` (12 font units: capitals, descenders, gap).
int textLineHeight(int scale);

/// Draws one line of `text` with its top-left corner at (x, y), `scale` pixels per font unit, in
/// `colour`, clipped to the image and to columns below `clipRight` (−1: the image's width).
/// Characters outside printable ASCII are drawn as '?'. `image` must have 3 or 4 channels.
void drawText(Image8& image, int x, int y, const std::string& text, int scale, Rgb8 colour,
              int clipRight = -1);

/// Fills the rectangle [x, x + width) × [y, y + height), clipped to the image.
void fillRect(Image8& image, int x, int y, int width, int height, Rgb8 colour);

/// Pastes `source` with its top-left pixel at (x, y), each pixel as a scale × scale block, clipped
/// to `target`. One-channel sources become gray, a fourth channel is dropped (no blending).
void pasteScaled(Image8& target, const Image8& source, int x, int y, int scale);

/// One row of a contact sheet: a label and its tiles, left to right; a tile with no pixels
/// (width 0) leaves its cell empty.
struct SheetRow {
    std::string label;
    std::vector<Image8> tiles;
};

/// Geometry of a contact sheet, in pixels. From the top: `padding`, the band of column titles,
/// then per row a label band and the row's tiles; `padding` between and around the tiles. A band
/// is one text line plus `padding`.
struct SheetLayout {
    int tileWidth = 0;  ///< a tile's width on the sheet (source width · tileScale)
    int tileHeight = 0; ///< a tile's height on the sheet
    int tileScale = 1;  ///< sheet pixels per source pixel
    int textScale = 2;  ///< pixels per stb_easy_font unit
    int padding = 8;
    int columns = 0;
    int rows = 0;

    int bandHeight() const { return textLineHeight(textScale) + padding; }
    int width() const { return columns * tileWidth + (columns + 1) * padding; }
    int height() const { return padding + bandHeight() + rows * (bandHeight() + tileHeight + padding); }
    int tileX(int column) const { return padding + column * (tileWidth + padding); }
    int labelY(int row) const { return padding + bandHeight() + row * (bandHeight() + tileHeight + padding); }
    int tileY(int row) const { return labelY(row) + bandHeight(); }
};

/// Sheet (and report) pixels per source pixel for a sourceWidth × sourceHeight image: the largest
/// integer that keeps the longer side within `targetSide`, at least 1, so small frames stay legible.
int tileScaleFor(int sourceWidth, int sourceHeight, int targetSide = 256);

/// Layout for `rows` rows of `columns` tiles of sourceWidth × sourceHeight pixels scaled by
/// tileScaleFor; text at 2 pixels per font unit.
SheetLayout sheetLayout(int sourceWidth, int sourceHeight, int columns, int rows);

/// Colours of the sheet: text on a dark background, so the labels stand out from light tiles.
inline constexpr Rgb8 SHEET_BACKGROUND{32, 32, 32};
inline constexpr Rgb8 SHEET_TEXT{255, 255, 255};

/// The sheet as an RGB image of layout.width() × layout.height(): the column titles in the top
/// band, each row's label above its tiles. Tiles larger than the layout's cell are clipped.
Image8 contactSheet(const SheetLayout& layout, const std::vector<std::string>& columnTitles,
                    const std::vector<SheetRow>& rows);

} // namespace stsv
