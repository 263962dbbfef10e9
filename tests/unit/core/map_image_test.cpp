// Map images as users have them (ROS map_server reads PGM, PNG and BMP): every format decodes
// to the same grey values and alpha, and gives the same grid as the PGM of those values.
#include "fleetnav/core/map_image.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <png.h>

#include <cstring>
#include <string>
#include <vector>

namespace fleetnav {
namespace {

using ::testing::HasSubstr;

/// A 4 x 3 test card: free, occupied, unknown and in-between greys, top row first.
const std::vector<uint8_t> kGrey = {254, 0, 205, 128, 0, 254, 254, 60, 205, 254, 0, 230};

std::string Png(const std::vector<uint8_t>& samples, uint32_t format, int width, int height) {
  png_image png;
  std::memset(&png, 0, sizeof(png));
  png.version = PNG_IMAGE_VERSION;
  png.width = width;
  png.height = height;
  png.format = format;
  png_alloc_size_t size = 0;
  EXPECT_TRUE(png_image_write_to_memory(&png, nullptr, &size, 0, samples.data(), 0, nullptr));
  std::string bytes(size, '\0');
  EXPECT_TRUE(png_image_write_to_memory(&png, bytes.data(), &size, 0, samples.data(), 0, nullptr))
      << png.message;
  bytes.resize(size);
  return bytes;
}

void PutU32(std::string& b, size_t at, uint32_t v) {
  for (int i = 0; i < 4; ++i) b[at + i] = static_cast<char>((v >> (8 * i)) & 0xff);
}

/// A BMP of `bits` (8: a grey palette; 24: B, G, R) with rows bottom-up or top-down.
std::string Bmp(const std::vector<uint8_t>& grey, int width, int height, int bits, bool top_down) {
  const int bytes_per_pixel = bits / 8;
  const int row_bytes = (width * bytes_per_pixel + 3) / 4 * 4;
  const int palette = bits == 8 ? 256 * 4 : 0;
  const int offset = 14 + 40 + palette;
  std::string b(offset + row_bytes * height, '\0');
  b[0] = 'B';
  b[1] = 'M';
  PutU32(b, 2, b.size());
  PutU32(b, 10, offset);
  PutU32(b, 14, 40);
  PutU32(b, 18, width);
  PutU32(b, 22, top_down ? static_cast<uint32_t>(-height) : height);
  b[26] = 1;
  b[28] = static_cast<char>(bits);
  for (int i = 0; i < 256 && bits == 8; ++i) {
    for (int c = 0; c < 3; ++c) b[54 + 4 * i + c] = static_cast<char>(i);
  }
  for (int row = 0; row < height; ++row) {
    const int file_row = top_down ? row : height - 1 - row;
    for (int col = 0; col < width; ++col) {
      const uint8_t v = grey[row * width + col];
      const size_t at = offset + file_row * row_bytes + col * bytes_per_pixel;
      for (int c = 0; c < bytes_per_pixel; ++c) b[at + c] = static_cast<char>(v);
    }
  }
  return b;
}

std::string Pgm(const std::vector<uint8_t>& grey, int width, int height) {
  PgmImage image;
  image.width = width;
  image.height = height;
  image.pixels = grey;
  return EncodePgm(image);
}

constexpr char kScaleYaml[] = "image: x\nresolution: 0.1\norigin: [0, 0, 0]\nmode: scale\n";

TEST(MapImageTest, EveryFormatGivesThePgmsGreysAndGrid) {
  const std::string pgm = Pgm(kGrey, 4, 3);
  std::vector<uint8_t> rgb;
  for (uint8_t v : kGrey) rgb.insert(rgb.end(), {v, v, v});
  const std::vector<std::pair<std::string, std::string>> images = {
      {"PNG grey", Png(kGrey, PNG_FORMAT_GRAY, 4, 3)},
      {"PNG RGB", Png(rgb, PNG_FORMAT_RGB, 4, 3)},
      {"BMP 8-bit bottom-up", Bmp(kGrey, 4, 3, 8, false)},
      {"BMP 24-bit top-down", Bmp(kGrey, 4, 3, 24, true)},
      {"BMP 24-bit bottom-up", Bmp(kGrey, 4, 3, 24, false)},
  };
  const absl::StatusOr<OccupancyGrid> from_pgm = GridFromMapServerBytes(kScaleYaml, pgm);
  ASSERT_TRUE(from_pgm.ok()) << from_pgm.status();
  for (const auto& [name, bytes] : images) {
    absl::StatusOr<PgmImage> image = DecodeMapImage(bytes);
    ASSERT_TRUE(image.ok()) << name << ": " << image.status();
    EXPECT_EQ(image->width, 4) << name;
    EXPECT_EQ(image->height, 3) << name;
    EXPECT_EQ(image->pixels, kGrey) << name;
    EXPECT_TRUE(image->alpha.empty()) << name;
    absl::StatusOr<OccupancyGrid> grid = GridFromMapServerBytes(kScaleYaml, bytes);
    ASSERT_TRUE(grid.ok()) << name << ": " << grid.status();
    EXPECT_TRUE(*grid == *from_pgm) << name;
  }
}

// map_server: colour is the mean of red, green and blue; in scale mode a transparent pixel
// between the thresholds is unknown, an opaque one a value.
TEST(MapImageTest, ColourIsAveragedAndTransparencyIsUnknownInScaleMode) {
  const std::vector<uint8_t> rgba = {30,  60,  90,  255, 128, 128, 128, 0,
                                     128, 128, 128, 255, 0,   0,   0,   0};
  absl::StatusOr<PgmImage> image = DecodeMapImage(Png(rgba, PNG_FORMAT_RGBA, 4, 1));
  ASSERT_TRUE(image.ok()) << image.status();
  EXPECT_EQ(image->pixels, (std::vector<uint8_t>{60, 128, 128, 0}));
  EXPECT_EQ(image->alpha, (std::vector<uint8_t>{255, 0, 255, 0}));
  absl::StatusOr<OccupancyGrid> grid =
      GridFromMapServerBytes(kScaleYaml, Png(rgba, PNG_FORMAT_RGBA, 4, 1));
  ASSERT_TRUE(grid.ok()) << grid.status();
  EXPECT_EQ(grid->Value({1, 0}), OccupancyGrid::kUnknownValue);  // transparent mid-grey
  EXPECT_GT(grid->Value({2, 0}), 0);                             // opaque mid-grey: a value
  EXPECT_LT(grid->Value({2, 0}), 100);
  EXPECT_EQ(grid->Value({3, 0}), OccupancyGrid::kOccupiedValue);  // black is black
}

TEST(MapImageTest, BadImagesAreRefusedNamingTheProblem) {
  const auto expect = [](std::string_view bytes, const std::string& needle) {
    absl::StatusOr<PgmImage> image = DecodeMapImage(bytes);
    ASSERT_FALSE(image.ok()) << needle;
    EXPECT_EQ(image.status().code(), absl::StatusCode::kInvalidArgument);
    EXPECT_THAT(std::string(image.status().message()), HasSubstr(needle));
  };
  expect("GIF89a....", "not a PGM (P5/P2), PNG or BMP");
  expect("", "not a PGM");
  expect("P6\n1 1\n255\n\x01\x02\x03", "wrong magic 'P6'");
  const std::string png = Png(kGrey, PNG_FORMAT_GRAY, 4, 3);
  expect(png.substr(0, png.size() / 2), "PNG");
  std::string not_png = png;
  not_png[20] ^= 0x55;  // a corrupt header chunk
  expect(not_png, "PNG");
  std::string bmp = Bmp(kGrey, 4, 3, 24, false);
  expect(bmp.substr(0, bmp.size() - 5), "BMP truncated");
  std::string rle = bmp;
  rle[30] = 1;  // BI_RLE8
  expect(rle, "compression 1 is not supported");
  std::string bits16 = bmp;
  bits16[28] = 16;
  expect(bits16, "16 bits per pixel is not supported");
  std::string huge = bmp;
  PutU32(huge, 18, 200000);
  PutU32(huge, 22, 200000);
  expect(huge, "exceeds the limit");
  // A 32-bit BMP whose header says it is a 59-byte BITMAPV3INFOHEADER (alpha mask at byte 52)
  // in a file that ends before it (found by fuzz_map_image: it read past the buffer).
  std::string short_v3 = Bmp(kGrey, 1, 1, 32, false).substr(0, 60);
  PutU32(short_v3, 14, 59);
  expect(short_v3, "BMP: truncated header (59 bytes announced, 44 present)");
}

}  // namespace
}  // namespace fleetnav
