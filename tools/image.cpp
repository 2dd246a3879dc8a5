// image.cpp - PNG read/write through libpng's simplified API.
#include "image.h"

#include <png.h>

#include "output.h"

bool write_png(const std::string& path, const Image& img, std::string& error) {
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  png.width = uint32_t(img.width);
  png.height = uint32_t(img.height);
  png.format = PNG_FORMAT_RGB;
  std::vector<uint8_t> rgb(size_t(img.width) * size_t(img.height) * 3);
  for (size_t i = 0; i < img.pixels.size(); ++i) {
    uint32_t p = img.pixels[i];
    rgb[3 * i + 0] = uint8_t(p >> 16);
    rgb[3 * i + 1] = uint8_t(p >> 8);
    rgb[3 * i + 2] = uint8_t(p);
  }
  OutputFile out;
  if (!out.open(path, error)) return false;
  // Through our own stream: libpng's write-to-file removes its path on error.
  if (!png_image_write_to_stdio(&png, out.stream(), 0, rgb.data(), 0, nullptr) && !out.failed()) {
    error = "cannot write PNG '" + path + "': " + png.message;
    return false; // `out` removes its temporary
  }
  return out.commit(error); // a failed write: the cause (errno) is reported here
}

bool read_png(const std::string& path, Image& img, std::string& error) {
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&png, path.c_str())) {
    error = "cannot read PNG '" + path + "': " + png.message;
    return false;
  }
  png.format = PNG_FORMAT_RGB;
  std::vector<uint8_t> rgb(PNG_IMAGE_SIZE(png));
  if (!png_image_finish_read(&png, nullptr, rgb.data(), 0, nullptr)) {
    error = "cannot decode PNG '" + path + "': " + png.message;
    return false;
  }
  img = Image(int(png.width), int(png.height));
  for (size_t i = 0; i < img.pixels.size(); ++i)
    img.pixels[i] = 0xff000000u | uint32_t(rgb[3 * i]) << 16 | uint32_t(rgb[3 * i + 1]) << 8 |
                    uint32_t(rgb[3 * i + 2]);
  return true;
}
