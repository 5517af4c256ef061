#include <asf/errors.h>
#include <asf/framework/registry.h>
#include <dlfcn.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <regex>
#include <sstream>

namespace asf::framework {

namespace fs = std::filesystem;

const KeySpec* PluginInfo::findKey(const std::string& key) const {
  for (std::size_t i = 0; i < descriptor->num_keys; ++i)
    if (key == descriptor->keys[i].name) return &descriptor->keys[i];
  return nullptr;
}

namespace {

std::string canonical(const std::string& path) {
  std::error_code ec;
  auto p = fs::canonical(path, ec);
  return ec ? fs::absolute(path).lexically_normal().string() : p.string();
}

bool validName(const char* s) {
  static const std::regex re("[a-z][a-z0-9_]*");
  return s && std::regex_match(s, re);
}

/// Checks the descriptor beyond the ABI version; returns why it is unusable, or "".
std::string descriptorProblem(const PluginDescriptor& d) {
  if (!validName(d.name)) return "plugin name must be lower_snake_case";
  if (static_cast<std::uint32_t>(d.kind) >= static_cast<std::uint32_t>(kNumPluginKinds))
    return "unknown plugin kind " + std::to_string(static_cast<std::uint32_t>(d.kind));
  if (!d.version || !*d.version) return "empty plugin version";
  if (!d.description || !*d.description) return "empty description";
  if (!d.create) return "no factory";
  if (d.num_keys && !d.keys) return "key table missing";
  for (std::size_t i = 0; i < d.num_keys; ++i) {
    if (!validName(d.keys[i].name)) return "key #" + std::to_string(i) + " has a bad name";
    for (std::size_t j = 0; j < i; ++j)
      if (std::string(d.keys[i].name) == d.keys[j].name)
        return std::string("key '") + d.keys[i].name + "' declared twice";
  }
  return {};
}

}  // namespace

std::shared_ptr<const PluginInfo> Registry::loadFile(const std::string& path) {
  if (!fs::exists(path)) throw PluginError(path + ": no such plugin file");
  const std::string file = canonical(path);
  // RTLD_LOCAL: plugins may carry private copies of helpers without clashing.
  void* h = dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!h) {
    const char* err = dlerror();
    throw PluginError(file + ": cannot load: " + (err ? err : "unknown dlopen error"));
  }
  std::shared_ptr<void> lib(h, [](void* p) { dlclose(p); });
  dlerror();
  void* sym = dlsym(h, ASF_PLUGIN_ENTRY_SYMBOL);
  if (!sym)
    throw PluginError(file + ": not an asf plugin (no '" ASF_PLUGIN_ENTRY_SYMBOL "' entry point)");
  using EntryFn = const PluginDescriptor* (*)();
  const PluginDescriptor* d = nullptr;
  try {
    d = reinterpret_cast<EntryFn>(sym)();
  } catch (const std::exception& e) {
    throw PluginError(file + ": entry point threw: " + e.what());
  }
  if (!d) throw PluginError(file + ": entry point returned no descriptor");
  if (d->abi_version != ASF_ABI_VERSION)
    throw PluginError(file + ": ABI mismatch: plugin built for asf ABI " +
                      std::to_string(d->abi_version) + ", this host has ABI " +
                      std::to_string(ASF_ABI_VERSION) + " (rebuild the plugin)");
  if (d->descriptor_size != sizeof(PluginDescriptor))
    throw PluginError(file + ": descriptor size " + std::to_string(d->descriptor_size) +
                      " differs from the host's " + std::to_string(sizeof(PluginDescriptor)) +
                      " (rebuild the plugin)");
  if (auto why = descriptorProblem(*d); !why.empty())
    throw PluginError(file + ": bad descriptor: " + why);
  auto info = std::make_shared<PluginInfo>();
  info->file = file;
  info->descriptor = d;
  info->library = std::move(lib);
  return info;
}

void Registry::addFile(const std::string& path) {
  const std::string file = canonical(path);
  for (const auto& p : plugins_)
    if (p->file == file) return;
  auto info = loadFile(file);
  for (const auto& p : plugins_)
    if (p->name() == info->name()) {
      duplicates_[info->name()].push_back(file);
      throw PluginError("two plugins named '" + info->name() + "': " + p->file + " and " + file);
    }
  plugins_.push_back(std::move(info));
}

int Registry::scanDirectory(const std::string& dir) {
  std::error_code ec;
  if (dir.empty() || !fs::is_directory(dir, ec)) return 0;
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.path().extension() == ".so" && (e.is_regular_file() || e.is_symlink()))
      files.push_back(e.path().string());
  std::sort(files.begin(), files.end());  // deterministic: first file wins a duplicate
  int added = 0;
  for (const auto& f : files) {
    const std::size_t before = plugins_.size();
    try {
      addFile(f);
    } catch (const PluginError& e) {
      problems_.push_back(e.what());
    }
    added += static_cast<int>(plugins_.size() - before);
  }
  return added;
}

std::vector<std::string> Registry::defaultSearchPath() {
  std::vector<std::string> dirs;
  char exe[4096];
  const ssize_t n = readlink("/proc/self/exe", exe, sizeof(exe) - 1);
  if (n > 0) {
    exe[n] = '\0';
    dirs.push_back((fs::path(exe).parent_path().parent_path() / "lib" / "asf" / "plugins")
                       .lexically_normal()
                       .string());
  }
  if (const char* env = std::getenv("ASF_PLUGIN_PATH")) {
    std::stringstream ss(env);
    std::string d;
    while (std::getline(ss, d, ':'))
      if (!d.empty()) dirs.push_back(d);
  }
  return dirs;
}

std::vector<std::string> Registry::names(PluginKind kind) const {
  std::vector<std::string> v;
  for (const auto& p : plugins_)
    if (p->kind() == kind) v.push_back(p->name());
  std::sort(v.begin(), v.end());
  return v;
}

std::shared_ptr<const PluginInfo> Registry::find(const std::string& name) const {
  auto dup = duplicates_.find(name);
  for (const auto& p : plugins_)
    if (p->name() == name) {
      if (dup != duplicates_.end()) {
        std::string files = p->file;
        for (const auto& f : dup->second) files += " and " + f;
        throw PluginError("two plugins named '" + name + "': " + files +
                          " (remove one or fix the plugin path)");
      }
      return p;
    }
  return nullptr;
}

std::shared_ptr<const PluginInfo> Registry::find(const std::string& name, PluginKind kind) const {
  auto p = find(name);
  if (p && p->kind() == kind) return p;
  std::string msg;
  if (p)
    msg = "plugin '" + name + "' (" + p->file + ") is a " + kindName(p->kind()) + ", not a " +
          kindName(kind);
  else
    msg = "unknown " + std::string(kindName(kind)) + " plugin '" + name + "'";
  const auto avail = names(kind);
  msg += "; available " + std::string(kindName(kind)) + " plugins: ";
  if (avail.empty()) msg += "(none)";
  for (std::size_t i = 0; i < avail.size(); ++i) msg += (i ? ", " : "") + avail[i];
  if (!problems_.empty())
    msg += "\n(" + std::to_string(problems_.size()) +
           " plugin file(s) failed to load; `asf plugins` lists them)";
  throw PluginError(msg);
}

std::unique_ptr<Plugin> Registry::instantiate(const PluginInfo& info) {
  std::unique_ptr<Plugin> p;
  try {
    p = info.descriptor->create();
  } catch (const std::exception& e) {
    throw PluginError(info.file + ": plugin '" + info.name() + "': factory threw: " + e.what());
  } catch (...) {
    throw PluginError(info.file + ": plugin '" + info.name() +
                      "': factory threw a non-std exception");
  }
  if (!p) throw PluginError(info.file + ": plugin '" + info.name() + "': factory returned null");
  if (p->kind() != info.kind())
    throw PluginError(info.file + ": plugin '" + info.name() + "' declares kind " +
                      kindName(info.kind()) + " but its object is a " + kindName(p->kind()));
  p->setLoggerName(info.name());
  return p;
}

void logPluginToStderr(Plugin& p, const std::string& name) {
  p.logging_enable_console_output = false;
  p.logRegisterCallback([](std::string_view msg, mrpt::system::VerbosityLevel,
                           std::string_view logger, const mrpt::Clock::time_point&) {
    std::cerr << "[" << logger << "] " << msg;
    if (msg.empty() || msg.back() != '\n') std::cerr << "\n";
  });
  p.setLoggerName(name);
}

}  // namespace asf::framework
