#include <asf/segmentation.h>

#include <cmath>

namespace asf {

RegionId LabelImage::atPoint(double x, double y) const {
  if (resolution <= 0) return 0;
  const int cx = static_cast<int>(std::floor((x - origin_x) / resolution));
  const int cy = static_cast<int>(std::floor((y - origin_y) / resolution));
  if (cx < 0 || cy < 0 || cx >= width || cy >= height) return 0;
  return at(cx, cy);
}

const Region* Segmentation::find(RegionId id) const {
  for (const auto& r : regions)
    if (r.id == id) return &r;
  return nullptr;
}

}  // namespace asf
