#pragma once
/// \file registry.h
/// Finds plugin libraries, checks them, and creates configured instances.
#include <asf/errors.h>
#include <asf/plugin.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace asf::framework {

/// A loaded plugin library. Kept alive by every instance created from it.
struct PluginInfo {
  std::string file;  ///< canonical path of the .so
  const PluginDescriptor* descriptor = nullptr;
  std::shared_ptr<void> library;  ///< dlopen handle (closed when the last user goes)

  std::string name() const { return descriptor->name; }
  PluginKind kind() const { return descriptor->kind; }
  const KeySpec* findKey(const std::string& key) const;
};

/// An instance of a plugin together with the library that holds its code.
template <class T>
struct PluginHandle {
  std::shared_ptr<const PluginInfo> info;
  std::unique_ptr<T> instance;  ///< declared after `info`: destroyed before the library
  T* operator->() const { return instance.get(); }
  T& operator*() const { return *instance; }
  explicit operator bool() const { return static_cast<bool>(instance); }
};

class Registry {
 public:
  /// Loads one file. Throws PluginError naming the file: cannot be loaded (dlerror), not a
  /// plugin (no entry point), ABI mismatch (both versions), bad descriptor.
  static std::shared_ptr<const PluginInfo> loadFile(const std::string& path);

  /// Scans every *.so in `dir` (not recursive). Files that fail to load are recorded in
  /// problems(); a missing folder is skipped silently. Returns how many plugins were added.
  int scanDirectory(const std::string& dir);
  /// Adds one file; throws like loadFile, and PluginError when the name is already taken by
  /// another file (naming both). Loading the same file twice is a no-op.
  void addFile(const std::string& path);

  /// The default search folders, in order: `<exe>/../lib/asf/plugins` (build tree or install
  /// prefix of the running host), then every folder of $ASF_PLUGIN_PATH (':'-separated).
  static std::vector<std::string> defaultSearchPath();

  const std::vector<std::shared_ptr<const PluginInfo>>& plugins() const { return plugins_; }
  /// Problems met while scanning (one line each, naming the file).
  const std::vector<std::string>& problems() const { return problems_; }

  /// Throws PluginError: unknown name (listing the plugins of that kind), wrong kind,
  /// duplicated name (both files).
  std::shared_ptr<const PluginInfo> find(const std::string& name, PluginKind kind) const;
  std::shared_ptr<const PluginInfo> find(const std::string& name) const;
  std::vector<std::string> names(PluginKind kind) const;

  /// Creates an instance and checks its kind; throws PluginError if the factory throws
  /// (with its message) or the object is not of the descriptor's kind.
  static std::unique_ptr<Plugin> instantiate(const PluginInfo& info);

  template <class T>
  static PluginHandle<T> create(const std::shared_ptr<const PluginInfo>& info);

 private:
  std::vector<std::shared_ptr<const PluginInfo>> plugins_;
  std::map<std::string, std::vector<std::string>> duplicates_;  ///< name -> other files
  std::vector<std::string> problems_;
};

template <class T>
PluginHandle<T> Registry::create(const std::shared_ptr<const PluginInfo>& info) {
  if (info->kind() != T::kStaticKind)
    throw PluginError(info->file + ": plugin '" + info->name() + "' is a " +
                      kindName(info->kind()) + ", not a " + kindName(T::kStaticKind));
  PluginHandle<T> h;
  h.info = info;
  auto p = instantiate(*info);
  h.instance.reset(static_cast<T*>(p.release()));  // instantiate() checked the kind
  return h;
}

/// The plugin's log lines go to stderr as "[name] message", not to the console logger (for
/// commands whose stdout is their report).
void logPluginToStderr(Plugin& p, const std::string& name);

}  // namespace asf::framework
