#pragma once
/// \file statistics.h
/// The two summaries asf reports everywhere (scores, latencies, update times), defined once.
#include <vector>

namespace asf {

/// Mean and population standard deviation.
struct MeanStd {
  double mean = 0, std = 0;
};
/// Of `values`; zeros for none.
MeanStd meanStd(const std::vector<double>& values);

/// Nearest-rank percentile (p in [0, 100], clamped) of unsorted values; 0 for none.
double percentile(std::vector<double> values, double p);

}  // namespace asf
