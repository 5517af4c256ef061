// asf: the host's launcher. It answers --version itself and loads the commands (libasf_host.so,
// host_main.cpp) only when one runs: that library needs about 300 others (MRPT, OpenCV, CGAL,
// ...) whose loading and relocation take most of a short command's time
// (docs/benchmarks/performance.md).
#include <asf/abi.h>
#include <dlfcn.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace {

/// Directory of this executable, or "" if /proc/self/exe cannot be read.
std::string exeDir() {
  std::vector<char> buf(4096);
  const ssize_t n = readlink("/proc/self/exe", buf.data(), buf.size() - 1);
  if (n <= 0) return "";
  std::string path(buf.data(), static_cast<std::size_t>(n));
  return path.substr(0, path.find_last_of('/'));
}

}  // namespace

int main(int argc, char** argv) {
  // The only place --version is answered (words after it are ignored, as before).
  if (argc >= 2 && std::strcmp(argv[1], "--version") == 0) {
    std::printf("asf " ASF_VERSION_STRING " (plugin ABI %u)\n", ASF_ABI_VERSION);
    return 0;
  }
  const std::string dir = exeDir();
  // `asf sim-robot` lives in its own module (apps/sim_robot): it links Fast DDS, which the
  // host does not, and it is built only with the optional ROS 2 component.
  const bool sim_robot = argc >= 2 && std::strcmp(argv[1], "sim-robot") == 0;
  const char* module = sim_robot ? "libasf_sim_robot.so" : "libasf_host.so";
  const char* entry = sim_robot ? "asf_sim_robot_main" : "asf_host_main";
  // The build tree and an install with lib/ as its library directory: <exe>/../lib/asf, where
  // the plugins' directory is too; else the configured install library directory.
  const std::string candidates[] = {dir + "/../lib/asf/" + module,
                                    dir + "/../" ASF_HOST_INSTALL_DIR "/" + module};
  std::string errors;
  for (const std::string& lib : candidates) {
    if (access(lib.c_str(), F_OK) != 0) continue;
    void* handle = dlopen(lib.c_str(), RTLD_LAZY | RTLD_GLOBAL);
    if (!handle) {
      errors += std::string("\n  ") + dlerror();
      continue;
    }
    using HostMain = int (*)(int, char**);
    const auto host_main = reinterpret_cast<HostMain>(dlsym(handle, entry));
    if (!host_main) {
      std::fprintf(stderr, "asf: error: %s has no %s\n", lib.c_str(), entry);
      return 1;
    }
    return host_main(argc, argv);
  }
  if (sim_robot && errors.empty()) {
    std::fprintf(stderr,
                 "asf: error: asf sim-robot is part of the optional ROS 2 component, not built "
                 "here: install its packages (scripts/install-deps.sh --ros2) and build again\n");
    return 1;
  }
  std::fprintf(stderr, "asf: error: cannot load the host library (looked for %s and %s)%s\n",
               candidates[0].c_str(), candidates[1].c_str(), errors.c_str());
  return 1;
}
