// A fixed-width 5 x 9 bitmap font for plot text: printable ASCII (32..126)
// plus a few characters common in axis labels (degree sign, micro sign,
// capital Delta).  Rows 0..6 hold capitals and digits (row 6 is the baseline
// row); rows 7..8 hold descenders (g, j, p, q, y, comma, underscore).
#pragma once

#include <array>
#include <cstdint>
#include <string>

namespace rcfd::plot::font {

inline constexpr int kGlyphWidth = 5;
inline constexpr int kGlyphHeight = 9;
/// Height of capitals and digits, rows 0..kCapHeight-1.
inline constexpr int kCapHeight = 7;
/// Horizontal distance from one glyph's left edge to the next one's.
inline constexpr int kAdvance = 6;

/// One row per entry, top to bottom; bit 4 is the leftmost column.
using Glyph = std::array<std::uint8_t, kGlyphHeight>;

/// The glyph of code point c; characters the font lacks get a hollow box.
const Glyph &glyph(char32_t c);

/// True when the font has a glyph of its own for c.
bool hasGlyph(char32_t c);

/// The code points of UTF-8 text; malformed bytes become U+FFFD each.
std::u32string decodeUtf8(const std::string &text);

/// UTF-8 text of code points (the inverse of decodeUtf8 on valid input).
std::string encodeUtf8(const std::u32string &codes);

/// Width in font pixels of a run of n glyphs (no trailing spacing).
inline constexpr int runWidth(int n) { return n > 0 ? n * kAdvance - (kAdvance - kGlyphWidth) : 0; }

} // namespace rcfd::plot::font
