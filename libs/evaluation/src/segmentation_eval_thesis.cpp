// The thesis' own scoring of the room segmentation benchmark (segmentation_eval.h,
// scoreThesisProtocol): what Table 4.1 of the thesis reports, reproduced to compare with it.
#include <asf/errors.h>
#include <asf/evaluation/segmentation_eval.h>

#include <map>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <string>

namespace asf::evaluation {

ThesisProtocolScore scoreThesisProtocol(const io::LabelRaster& segmentation,
                                        const io::GrayImage& gt) {
  if (segmentation.width != gt.width || segmentation.height != gt.height ||
      segmentation.labels.size() != static_cast<std::size_t>(gt.width) * gt.height)
    throw Error("scoreThesisProtocol: the segmentation is " + std::to_string(segmentation.width) +
                " x " + std::to_string(segmentation.height) + ", the ground truth " +
                std::to_string(gt.width) + " x " + std::to_string(gt.height));
  ThesisProtocolScore out;
  if (gt.width == 0 || gt.height == 0) return out;
  cv::Mat free(gt.height, gt.width, CV_8U, cv::Scalar(0));
  for (int r = 0; r < gt.height; ++r)
    for (int c = 0; c < gt.width; ++c) free.at<std::uint8_t>(r, c) = gt.at(c, r) > 250 ? 255 : 0;
  const cv::Mat k3 = cv::Mat::ones(3, 3, CV_8U);
  // Outside the image counts as obstacle for the erosion (the author's BORDER_CONSTANT).
  cv::erode(free, free, k3, cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  cv::Mat rooms;
  cv::connectedComponents(free, rooms, 8, CV_32S);
  rooms.convertTo(rooms, CV_32F);  // dilate has no 32-bit integer version; labels < 2^24
  cv::dilate(rooms, rooms, k3, cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  rooms.convertTo(rooms, CV_32S);

  std::map<int, std::map<int, long>> by_room, by_segment;  // room -> segment -> pixels
  for (int r = 0; r < gt.height; ++r)
    for (int c = 0; c < gt.width; ++c) {
      const int room = rooms.at<int>(r, c), seg = segmentation.at(c, r);
      if (room <= 0 || seg <= 0) continue;
      ++by_room[room][seg];
      ++by_segment[seg][room];
    }
  auto meanBest = [](const std::map<int, std::map<int, long>>& m) {
    double sum = 0;
    for (const auto& [k, row] : m) {
      long total = 0, best = 0;
      for (const auto& [o, n] : row) total += n, best = std::max(best, n);
      // Whole percent, truncated: the author's code divides integers (100 * best / total).
      sum += static_cast<double>(100 * best / total) / 100.0;
    }
    return m.empty() ? 0.0 : sum / static_cast<double>(m.size());
  };
  out.precision = meanBest(by_room);
  out.recall = meanBest(by_segment);
  out.rooms = static_cast<int>(by_room.size());
  out.segments = static_cast<int>(by_segment.size());
  return out;
}

}  // namespace asf::evaluation
