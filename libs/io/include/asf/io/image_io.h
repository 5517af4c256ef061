#pragma once
/// \file image_io.h
/// Image files as asf reads and writes them: 8-bit grayscale maps and 16-bit label images
/// (PNG; also PGM/PPM/PBM, BMP, JPEG and TIFF when read). Row 0 is the top row. Only formats
/// recognised by their first bytes are decoded (a malformed file of another format never
/// reaches a decoder that could abort the process).
#include <cstdint>
#include <string>
#include <vector>

namespace asf::io {

/// 8-bit grayscale image, row-major, row 0 = top.
struct GrayImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> pixels;
  std::uint8_t at(int col, int row) const {
    return pixels[static_cast<std::size_t>(row) * width + col];
  }
};

/// Label image in image orientation (row 0 = top), 0 = no region.
struct LabelRaster {
  int width = 0, height = 0;
  std::vector<std::int32_t> labels;
  std::int32_t at(int col, int row) const {
    return labels[static_cast<std::size_t>(row) * width + col];
  }
};

/// Reads any PNG/image as 8-bit grayscale (alpha dropped). Throws InputError naming the file
/// when it is missing or cannot be decoded.
GrayImage readGrayImage(const std::string& path);
/// Writes an 8-bit grayscale PNG. Throws Error naming the file.
void writeGrayImage(const std::string& path, const GrayImage& image);
/// Reads a label PNG (16-bit or 8-bit, single channel, values are labels). Throws InputError.
LabelRaster readLabelImage(const std::string& path);
/// Reads a picture whose regions are each drawn in one colour (the reference DuDe's published
/// outputs): black is no region; every 8-connected piece of one colour becomes a label 1, 2,
/// ... in the order of its first pixel, row by row from the top. Throws InputError.
LabelRaster readColourRegions(const std::string& path);
/// Writes a 16-bit single-channel PNG; throws Error when a label is < 0 or > 65535.
void writeLabelImage(const std::string& path, const LabelRaster& labels);

/// Writes an 8-bit three-channel picture (blue, green, red per pixel; row-major, row 0 the top)
/// in the format of the path's extension (.png, .jpg, ...). Throws Error naming the file.
void writeBgrImage(const std::string& path, int width, int height, const std::uint8_t* bgr);

}  // namespace asf::io
