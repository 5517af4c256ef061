// libFuzzer entry: the target is chosen by the environment variable ASF_FUZZ_TARGET (a name
// of fuzz_targets.h; scripts/fuzz.sh sets it), so one instrumented executable serves all.
#include <cstdio>
#include <cstdlib>

#include "fuzz_targets.h"

namespace {
const asf::fuzz::Target* chosen = nullptr;
}

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  const char* name = std::getenv("ASF_FUZZ_TARGET");
  chosen = name ? asf::fuzz::findTarget(name) : nullptr;
  if (!chosen) {
    std::fprintf(stderr, "asf_fuzz: set ASF_FUZZ_TARGET to one of:");
    for (const auto& t : asf::fuzz::targets()) std::fprintf(stderr, " %s", t.name);
    std::fprintf(stderr, "\n");
    std::exit(2);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const unsigned char* data, std::size_t size) {
  chosen->run(data, size);
  return 0;
}
