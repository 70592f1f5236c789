#pragma once
// Reads a PNG back for the tests, with libpng's simplified API.

#include <png.h>

#include <string>
#include <vector>

namespace tb::client::testing {

struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgba;
  const std::uint8_t* at(int x, int y) const {
    return &rgba[(static_cast<std::size_t>(y) * width + x) * 4];
  }
};

inline bool read_png(const std::string& path, Image& out) {
  png_image img{};
  img.version = PNG_IMAGE_VERSION;
  if (png_image_begin_read_from_file(&img, path.c_str()) == 0)
    return false;
  img.format = PNG_FORMAT_RGBA;
  out.width = static_cast<int>(img.width);
  out.height = static_cast<int>(img.height);
  out.rgba.resize(PNG_IMAGE_SIZE(img));
  if (png_image_finish_read(&img, nullptr, out.rgba.data(), 0, nullptr) == 0) {
    png_image_free(&img);
    return false;
  }
  return true;
}

// Pixels within `radius` of (cx, cy) whose colour is within `tol` of `c` per channel.
inline int count_near(const Image& im, int cx, int cy, int radius, std::uint8_t r, std::uint8_t g,
                      std::uint8_t b, int tol = 8) {
  int n = 0;
  for (int y = std::max(cy - radius, 0); y < std::min(cy + radius, im.height); ++y) {
    for (int x = std::max(cx - radius, 0); x < std::min(cx + radius, im.width); ++x) {
      const auto* p = im.at(x, y);
      if (std::abs(p[0] - r) <= tol && std::abs(p[1] - g) <= tol && std::abs(p[2] - b) <= tol)
        ++n;
    }
  }
  return n;
}

inline int distinct_colours(const Image& im) {
  std::vector<std::uint32_t> seen;
  for (int i = 0; i < im.width * im.height; i += 7) {
    const auto* p = &im.rgba[static_cast<std::size_t>(i) * 4];
    const std::uint32_t v = p[0] << 16 | p[1] << 8 | p[2];
    if (std::find(seen.begin(), seen.end(), v) == seen.end())
      seen.push_back(v);
    if (seen.size() > 64)
      break;
  }
  return static_cast<int>(seen.size());
}

}  // namespace tb::client::testing
