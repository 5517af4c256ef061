#include <asf/framework/registry.h>
#include <tclap/CmdLine.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.h"

namespace asf::app {

int cmdPlugins(int argc, char** argv) {
  TCLAP::CmdLine cmd(
      "Lists the plugins found in <asf>/../lib/asf/plugins, $ASF_PLUGIN_PATH and --plugin-path "
      "folders. Files that fail to load are reported on stderr and make the exit code 1.",
      ' ', ASF_VERSION_STRING);
  TCLAP::SwitchArg json_out("j", "json", "Print JSON (with each plugin's INI keys)", cmd);
  TCLAP::MultiArg<std::string> path("p", "plugin-path", "Extra plugin folder (repeatable)", false,
                                    "DIR", cmd);
  cmd.setExceptionHandling(false);
  cmd.parse(argc, argv);

  framework::Registry reg;
  for (const auto& d : framework::Registry::defaultSearchPath()) reg.scanDirectory(d);
  for (const auto& d : path.getValue()) reg.scanDirectory(d);
  auto plugins = reg.plugins();
  std::sort(plugins.begin(), plugins.end(), [](const auto& a, const auto& b) {
    return std::make_pair(a->kind(), a->name()) < std::make_pair(b->kind(), b->name());
  });

  if (json_out.getValue()) {
    nlohmann::json j = nlohmann::json::array();
    for (const auto& p : plugins) {
      const auto& d = *p->descriptor;
      nlohmann::json keys = nlohmann::json::array();
      for (std::size_t i = 0; i < d.num_keys; ++i) {
        const KeySpec& k = d.keys[i];
        nlohmann::json jk = {{"name", k.name},
                             {"type", keyTypeName(k.type)},
                             {"required", k.default_value == nullptr},
                             {"doc", k.doc}};
        if (k.default_value) jk["default"] = k.default_value;
        if (k.choices) jk["choices"] = k.choices;
        if (!std::isinf(k.min)) jk["min"] = k.min;
        if (!std::isinf(k.max)) jk["max"] = k.max;
        keys.push_back(jk);
      }
      j.push_back({{"name", d.name},
                   {"kind", kindName(d.kind)},
                   {"version", d.version},
                   {"abi", d.abi_version},
                   {"file", p->file},
                   {"description", d.description},
                   {"thread_safety", threadSafetyName(d.thread_safety)},
                   {"keys", keys}});
    }
    std::cout << j.dump(2) << "\n";
  } else {
    // The name column fits the longest name (two blanks after it), so columns stay aligned.
    std::size_t name_w = 4;
    for (const auto& p : plugins) name_w = std::max(name_w, std::strlen(p->descriptor->name));
    const int nw = static_cast<int>(name_w + 2);
    std::cout << std::left << std::setw(nw) << "NAME" << std::setw(11) << "KIND" << std::setw(9)
              << "VERSION" << std::setw(5) << "ABI"
              << "DESCRIPTION / FILE\n";
    for (const auto& p : plugins) {
      const auto& d = *p->descriptor;
      std::cout << std::left << std::setw(nw) << d.name << std::setw(11) << kindName(d.kind)
                << std::setw(9) << d.version << std::setw(5) << d.abi_version << d.description
                << "\n"
                << std::string(static_cast<std::size_t>(nw) + 25, ' ') << p->file << "\n";
    }
    if (plugins.empty()) std::cout << "(no plugins found)\n";
  }
  for (const auto& pr : reg.problems()) std::cerr << "problem: " << pr << "\n";
  return reg.problems().empty() ? kOk : kError;
}

}  // namespace asf::app
