// image.h - the Linux tool's framebuffer and PNG output (libpng).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

struct Image {
  int width = 0, height = 0;
  std::vector<uint32_t> pixels;  // 0xAARRGGBB, row-major, top row first
  Image() = default;
  Image(int w, int h) : width(w), height(h), pixels(size_t(w) * size_t(h), 0xff000000u) {}
  uint32_t& at(int x, int y) { return pixels[size_t(y) * size_t(width) + size_t(x)]; }
  uint32_t at(int x, int y) const { return pixels[size_t(y) * size_t(width) + size_t(x)]; }
};

// Writes an 8-bit RGB PNG whole or not at all (output.h). On failure returns
// false and sets `error` (one line).
bool write_png(const std::string& path, const Image& img, std::string& error);
// Reads an 8-bit RGB or RGBA PNG (any format libpng can expand to RGB8).
bool read_png(const std::string& path, Image& img, std::string& error);
