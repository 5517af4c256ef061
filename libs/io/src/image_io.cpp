#include <asf/errors.h>
#include <asf/io/image_io.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <utility>
#include <vector>


namespace asf::io {

namespace fs = std::filesystem;

namespace {

/// The format of an image file by its first bytes, or nullptr for one asf does not decode:
/// OpenCV would hand anything to whichever decoder claims it, and some of those abort the
/// process on a malformed file (fuzzing: GDCM, the DICOM reader, asserts).
const char* imageFormat(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  unsigned char b[8] = {0};
  f.read(reinterpret_cast<char*>(b), sizeof b);
  const auto n = f.gcount();
  const auto starts = [&](std::initializer_list<int> sig) {
    if (n < static_cast<std::streamsize>(sig.size())) return false;
    std::size_t i = 0;
    for (int c : sig)
      if (b[i++] != c) return false;
    return true;
  };
  if (starts({0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'})) return "PNG";
  if (n >= 2 && b[0] == 'P' && b[1] >= '1' && b[1] <= '6') return "PNM";
  if (starts({'B', 'M'})) return "BMP";
  if (starts({0xff, 0xd8, 0xff})) return "JPEG";
  if (starts({'I', 'I', '*', 0}) || starts({'M', 'M', 0, '*'})) return "TIFF";
  return nullptr;
}

cv::Mat readImage(const std::string& path, int flags) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) throw InputError(path + ": no such file");
  if (!imageFormat(path))
    throw InputError(path +
                     ": cannot be read as an image (not PNG, PGM/PPM/PBM, BMP, JPEG or TIFF)");
  cv::Mat m;
  try {
    m = cv::imread(path, flags);
  } catch (const cv::Exception& e) {  // some decoders throw (fuzzing: a PBM 33333333 rows high)
    throw InputError(path + ": cannot be read as an image (" + e.err + ")");
  }
  if (m.empty()) throw InputError(path + ": cannot be read as an image (malformed or unsupported)");
  return m;
}

/// cv::imwrite with the file named in asf::Error when it fails (or throws).
void writeImage(const std::string& path, const cv::Mat& m) {
  bool ok = false;
  try {
    ok = cv::imwrite(path, m);
  } catch (const cv::Exception& e) {
    throw Error(path + ": cannot write (" + e.what() + ")");
  }
  if (!ok) throw Error(path + ": cannot write");
}

}  // namespace

void writeBgrImage(const std::string& path, int width, int height, const std::uint8_t* bgr) {
  if (width <= 0 || height <= 0) throw Error(path + ": cannot write an empty image");
  // The Mat wraps the caller's pixels without copying; imwrite only reads them.
  writeImage(path, cv::Mat(height, width, CV_8UC3, const_cast<std::uint8_t*>(bgr)));
}

GrayImage readGrayImage(const std::string& path) {
  const cv::Mat m = readImage(path, cv::IMREAD_GRAYSCALE);
  GrayImage g;
  g.width = m.cols;
  g.height = m.rows;
  g.pixels.resize(static_cast<std::size_t>(m.cols) * m.rows);
  for (int r = 0; r < m.rows; ++r)
    std::copy(m.ptr<std::uint8_t>(r), m.ptr<std::uint8_t>(r) + m.cols,
              g.pixels.begin() + static_cast<std::ptrdiff_t>(r) * m.cols);
  return g;
}

void writeGrayImage(const std::string& path, const GrayImage& image) {
  if (image.pixels.size() != static_cast<std::size_t>(image.width) * image.height)
    throw Error(path + ": image size does not match its pixels");
  cv::Mat m(image.height, image.width, CV_8U, const_cast<std::uint8_t*>(image.pixels.data()));
  writeImage(path, m);
}

LabelRaster readLabelImage(const std::string& path) {
  const cv::Mat m = readImage(path, cv::IMREAD_UNCHANGED);
  if (m.channels() != 1 || (m.depth() != CV_16U && m.depth() != CV_8U))
    throw InputError(path + ": not a single-channel 8- or 16-bit label image");
  cv::Mat m32;
  m.convertTo(m32, CV_32S);
  LabelRaster L;
  L.width = m.cols;
  L.height = m.rows;
  L.labels.resize(static_cast<std::size_t>(m.cols) * m.rows);
  for (int r = 0; r < m.rows; ++r)
    std::copy(m32.ptr<std::int32_t>(r), m32.ptr<std::int32_t>(r) + m.cols,
              L.labels.begin() + static_cast<std::ptrdiff_t>(r) * m.cols);
  return L;
}

LabelRaster readColourRegions(const std::string& path) {
  const cv::Mat m = readImage(path, cv::IMREAD_COLOR);
  LabelRaster L;
  L.width = m.cols;
  L.height = m.rows;
  L.labels.assign(static_cast<std::size_t>(m.cols) * m.rows, 0);
  const auto colour = [&](int c, int r) {
    const cv::Vec3b& p = m.at<cv::Vec3b>(r, c);
    return p[0] | (p[1] << 8) | (p[2] << 16);
  };
  std::vector<std::pair<int, int>> stack;
  std::int32_t next = 0;
  for (int r = 0; r < m.rows; ++r)
    for (int c = 0; c < m.cols; ++c) {
      const int k = colour(c, r);
      if (k == 0 || L.labels[static_cast<std::size_t>(r) * m.cols + c] != 0) continue;
      // One region: the 8-connected pixels of this colour.
      L.labels[static_cast<std::size_t>(r) * m.cols + c] = ++next;
      stack.assign(1, {c, r});
      while (!stack.empty()) {
        const auto [x, y] = stack.back();
        stack.pop_back();
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int nx = x + dx, ny = y + dy;
            if (nx < 0 || ny < 0 || nx >= m.cols || ny >= m.rows) continue;
            std::int32_t& l = L.labels[static_cast<std::size_t>(ny) * m.cols + nx];
            if (l != 0 || colour(nx, ny) != k) continue;
            l = next;
            stack.push_back({nx, ny});
          }
      }
    }
  return L;
}

void writeLabelImage(const std::string& path, const LabelRaster& labels) {
  if (labels.labels.size() != static_cast<std::size_t>(labels.width) * labels.height)
    throw Error(path + ": label image size does not match its labels");
  cv::Mat m(labels.height, labels.width, CV_16U);
  for (int r = 0; r < labels.height; ++r)
    for (int c = 0; c < labels.width; ++c) {
      const std::int32_t v = labels.at(c, r);
      if (v < 0 || v > 65535)
        throw Error(path + ": label " + std::to_string(v) +
                    " does not fit a 16-bit label image (0..65535)");
      m.at<std::uint16_t>(r, c) = static_cast<std::uint16_t>(v);
    }
  writeImage(path, m);
}

}  // namespace asf::io
