#include "fleetnav/core/map_image.hpp"

#include <png.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "fleetnav/core/occupancy_grid.hpp"

namespace fleetnav {
namespace {

constexpr unsigned char kPngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};

absl::Status CheckImageSize(const char* format, int64_t width, int64_t height) {
  if (width <= 0 || height <= 0) {
    return absl::InvalidArgumentError(
        absl::StrCat(format, ": width and height must be > 0, got ", width, " x ", height));
  }
  if (width > kMaxGridCells || height > kMaxGridCells || width * height > kMaxGridCells) {
    return absl::InvalidArgumentError(absl::StrCat(format, " of ", width, " x ", height,
                                                   " pixels exceeds the limit of ", kMaxGridCells,
                                                   " cells"));
  }
  return absl::OkStatus();
}

/// map_server's colour rule: the mean of red, green and blue.
uint8_t Average(uint32_t r, uint32_t g, uint32_t b) {
  return static_cast<uint8_t>((r + g + b + 1) / 3);
}

// ---------------------------------------------------------------------------------------------
// PNG, through libpng's simplified API (RGBA, 8 bits per channel).

absl::StatusOr<PgmImage> DecodePng(std::string_view bytes) {
  png_image png;
  std::memset(&png, 0, sizeof(png));
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_memory(&png, bytes.data(), bytes.size())) {
    return absl::InvalidArgumentError(absl::StrCat("PNG: ", png.message));
  }
  if (absl::Status s = CheckImageSize("PNG", png.width, png.height); !s.ok()) {
    png_image_free(&png);
    return s;
  }
  const bool has_alpha = (png.format & PNG_FORMAT_FLAG_ALPHA) != 0;
  png.format = PNG_FORMAT_RGBA;
  std::vector<uint8_t> rgba(PNG_IMAGE_SIZE(png));
  if (!png_image_finish_read(&png, /*background=*/nullptr, rgba.data(), /*row_stride=*/0,
                             /*colormap=*/nullptr)) {
    const std::string why = png.message;
    png_image_free(&png);
    return absl::InvalidArgumentError(absl::StrCat("PNG: ", why));
  }
  PgmImage image;
  image.width = static_cast<int>(png.width);
  image.height = static_cast<int>(png.height);
  const size_t count = static_cast<size_t>(image.width) * image.height;
  image.pixels.resize(count);
  if (has_alpha) image.alpha.resize(count);
  for (size_t i = 0; i < count; ++i) {
    const uint8_t* p = &rgba[4 * i];
    image.pixels[i] = Average(p[0], p[1], p[2]);
    if (has_alpha) image.alpha[i] = p[3];
  }
  return image;
}

// ---------------------------------------------------------------------------------------------
// BMP (Windows bitmap): BITMAPFILEHEADER, then a BITMAPINFOHEADER or a later version.

uint32_t U32(std::string_view b, size_t at) {
  return static_cast<uint32_t>(static_cast<unsigned char>(b[at])) |
         static_cast<uint32_t>(static_cast<unsigned char>(b[at + 1])) << 8 |
         static_cast<uint32_t>(static_cast<unsigned char>(b[at + 2])) << 16 |
         static_cast<uint32_t>(static_cast<unsigned char>(b[at + 3])) << 24;
}
uint16_t U16(std::string_view b, size_t at) {
  return static_cast<uint16_t>(static_cast<unsigned char>(b[at]) |
                               static_cast<unsigned char>(b[at + 1]) << 8);
}

absl::StatusOr<PgmImage> DecodeBmp(std::string_view b) {
  constexpr size_t kFileHeader = 14;
  if (b.size() < kFileHeader + 40) return absl::InvalidArgumentError("BMP: truncated header");
  const uint32_t pixel_offset = U32(b, 10);
  const uint32_t info_size = U32(b, kFileHeader);
  if (info_size < 40) {
    return absl::InvalidArgumentError(
        absl::StrCat("BMP: header of ", info_size, " bytes (only BITMAPINFOHEADER and later)"));
  }
  if (kFileHeader + static_cast<size_t>(info_size) > b.size()) {
    return absl::InvalidArgumentError(absl::StrCat("BMP: truncated header (", info_size,
                                                   " bytes announced, ", b.size() - kFileHeader,
                                                   " present)"));
  }
  const int64_t width = static_cast<int32_t>(U32(b, kFileHeader + 4));
  const int64_t raw_height = static_cast<int32_t>(U32(b, kFileHeader + 8));
  const uint16_t bits = U16(b, kFileHeader + 14);
  const uint32_t compression = U32(b, kFileHeader + 16);
  uint32_t palette_size = U32(b, kFileHeader + 32);
  const bool top_down = raw_height < 0;
  const int64_t height = top_down ? -raw_height : raw_height;
  if (absl::Status s = CheckImageSize("BMP", width, height); !s.ok()) return s;
  // BI_RGB, or BI_BITFIELDS with 32 bits (the usual B, G, R, A byte order is assumed).
  if (!(compression == 0 || (compression == 3 && bits == 32))) {
    return absl::InvalidArgumentError(absl::StrCat("BMP: compression ", compression,
                                                   " is not supported (uncompressed images only)"));
  }
  if (bits != 8 && bits != 24 && bits != 32) {
    return absl::InvalidArgumentError(
        absl::StrCat("BMP: ", bits, " bits per pixel is not supported (8, 24 or 32)"));
  }
  std::vector<uint8_t> palette_grey;
  if (bits == 8) {
    if (palette_size == 0) palette_size = 256;
    const size_t palette_at = kFileHeader + info_size;
    if (palette_size > 256 || palette_at + 4 * static_cast<size_t>(palette_size) > b.size()) {
      return absl::InvalidArgumentError("BMP: truncated or oversized palette");
    }
    for (uint32_t i = 0; i < palette_size; ++i) {
      const size_t at = palette_at + 4 * i;  // B, G, R, reserved
      palette_grey.push_back(Average(static_cast<unsigned char>(b[at + 2]),
                                     static_cast<unsigned char>(b[at + 1]),
                                     static_cast<unsigned char>(b[at])));
    }
  }
  const size_t bytes_per_pixel = bits / 8;
  const size_t row_bytes = (static_cast<size_t>(width) * bytes_per_pixel + 3) / 4 * 4;
  if (pixel_offset > b.size() || b.size() - pixel_offset < row_bytes * height) {
    return absl::InvalidArgumentError(
        absl::StrCat("BMP truncated: expected ", row_bytes * height, " bytes of pixel data"));
  }
  PgmImage image;
  image.width = static_cast<int>(width);
  image.height = static_cast<int>(height);
  image.pixels.resize(static_cast<size_t>(width) * height);
  const bool has_alpha = bits == 32 && info_size >= 56 && U32(b, kFileHeader + 52) != 0;
  if (has_alpha) image.alpha.resize(image.pixels.size());
  for (int64_t row = 0; row < height; ++row) {
    // Rows are stored bottom-up unless the height is negative.
    const int64_t file_row = top_down ? row : height - 1 - row;
    const size_t row_at = pixel_offset + static_cast<size_t>(file_row) * row_bytes;
    for (int64_t col = 0; col < width; ++col) {
      const size_t at = row_at + static_cast<size_t>(col) * bytes_per_pixel;
      const size_t i = static_cast<size_t>(row) * width + col;
      if (bits == 8) {
        const uint8_t index = static_cast<unsigned char>(b[at]);
        if (index >= palette_grey.size()) {
          return absl::InvalidArgumentError(absl::StrCat("BMP: pixel ", i, " uses palette entry ",
                                                         index, " of ", palette_grey.size()));
        }
        image.pixels[i] = palette_grey[index];
      } else {
        image.pixels[i] =
            Average(static_cast<unsigned char>(b[at + 2]), static_cast<unsigned char>(b[at + 1]),
                    static_cast<unsigned char>(b[at]));
        if (has_alpha) image.alpha[i] = static_cast<unsigned char>(b[at + 3]);
      }
    }
  }
  return image;
}

}  // namespace

absl::StatusOr<PgmImage> DecodeMapImage(std::string_view bytes) {
  if (bytes.size() >= sizeof(kPngSignature) &&
      std::memcmp(bytes.data(), kPngSignature, sizeof(kPngSignature)) == 0) {
    return DecodePng(bytes);
  }
  if (bytes.size() >= 2 && bytes[0] == 'B' && bytes[1] == 'M') return DecodeBmp(bytes);
  if (!bytes.empty() && bytes[0] == 'P') return DecodePgm(bytes);  // names a wrong magic
  return absl::InvalidArgumentError(
      "map image: not a PGM (P5/P2), PNG or BMP file (checked its first bytes)");
}

}  // namespace fleetnav
