// asf plan (being written).
#include "commands.h"

#include <iostream>

namespace asf::app {
int cmdPlan(int, char**) {
  std::cerr << "asf plan: not built yet\n";
  return kError;
}
}  // namespace asf::app
