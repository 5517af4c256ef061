// asf segment / asf segment-eval (being written).
#include "commands.h"

#include <iostream>

namespace asf::app {
int cmdSegment(int, char**) {
  std::cerr << "asf segment: not built yet\n";
  return kError;
}
int cmdSegmentEval(int, char**) {
  std::cerr << "asf segment-eval: not built yet\n";
  return kError;
}
}  // namespace asf::app
