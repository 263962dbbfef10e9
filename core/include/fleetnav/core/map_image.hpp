#pragma once

#include <string_view>

#include "absl/status/statusor.h"
#include "fleetnav/core/map_io.hpp"

namespace fleetnav {

/// Decodes the image of a map_server map, whatever format it comes in, told apart by its first
/// bytes: PGM (P5 binary or P2 ASCII, 8 or 16 bits per sample), PNG (grey, grey + alpha, RGB,
/// RGBA or palette, 8 or 16 bits; decoded by libpng) or BMP (uncompressed 8-bit palette, 24-bit
/// or 32-bit, bottom-up or top-down). Colour pixels become the average of their red, green and
/// blue values, as map_server does; an alpha channel is kept (map_server's scale mode reads a
/// transparent pixel as unknown). InvalidArgument naming the format and what is wrong (bytes
/// that are none of these, truncated or compressed data, sizes over the grid limit).
absl::StatusOr<PgmImage> DecodeMapImage(std::string_view bytes);

}  // namespace fleetnav
