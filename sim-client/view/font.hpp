#pragma once
/// @file A tiny built-in 5×7 bitmap font for the view's labels and HUD, so that the client
/// needs no font files (SDL_ttf) to run anywhere.

#include <array>
#include <cstdint>
#include <string_view>

namespace tb::client::font {

inline constexpr int kGlyphWidth = 5;
inline constexpr int kGlyphHeight = 7;
inline constexpr int kAdvance = 6;  ///< glyph width plus one column of space

/// Rows top to bottom, bit 4 = leftmost column. Lower-case letters use the capitals; unknown
/// characters draw as a hollow box.
std::array<std::uint8_t, kGlyphHeight> glyph(char c);

/// Width in pixels of @p text at @p scale.
inline int text_width(std::string_view text, int scale) {
  return text.empty() ? 0 : static_cast<int>(text.size()) * kAdvance * scale - scale;
}

}  // namespace tb::client::font
