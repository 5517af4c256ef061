// Robust kernels of the sparse_lm back-end (declared in sparse_se2.h; README.md, "Robust
// kernels").
#include <algorithm>
#include <cmath>

#include "sparse_se2.h"

namespace asf::sparse_lm {

double robustCost(Kernel k, double delta, double s) {
  const double d2 = delta * delta;
  switch (k) {
    case Kernel::None:
      return s;
    case Kernel::Huber:
      return s <= d2 ? s : 2 * delta * std::sqrt(s) - d2;
    case Kernel::Cauchy:
      return d2 * std::log1p(s / d2);
    case Kernel::Dcs:
      return s <= d2 ? s : d2 * (3 * s - d2) / (d2 + s);
  }
  return s;
}

double robustWeight(Kernel k, double delta, double s) {
  const double d2 = delta * delta;
  switch (k) {
    case Kernel::None:
      return 1;
    case Kernel::Huber:
      return s <= d2 ? 1 : delta / std::sqrt(s);
    case Kernel::Cauchy:
      return 1 / (1 + s / d2);
    case Kernel::Dcs: {
      const double scale = std::min(1.0, 2 * d2 / (d2 + s));
      return scale * scale;
    }
  }
  return 1;
}

}  // namespace asf::sparse_lm
