#pragma once
// Private to the framework: writing an OpenCV image with asf's errors (image_io.cpp).
#include <opencv2/core.hpp>
#include <string>

namespace asf::detail {

/// cv::imwrite with the file named in asf::Error when it fails (or throws).
void writeImage(const std::string& path, const cv::Mat& m);

}  // namespace asf::detail
