#include <asf/config.h>
#include <asf/errors.h>
#include <asf/text.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace asf {

namespace fs = std::filesystem;

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

/// MRPT exceptions carry a long backtrace; keep the message lines only.
std::string mrptMessage(const std::exception& e) {
  std::istringstream is(e.what());
  std::string line, out;
  bool in_msg = false;
  while (std::getline(is, line)) {
    if (line.rfind("Message:", 0) == 0) {
      in_msg = true;
      line = trim(line.substr(8));
    } else if (line.rfind("Location:", 0) == 0 || line.rfind("Call stack", 0) == 0) {
      in_msg = false;
    }
    if (in_msg && !trim(line).empty()) out += (out.empty() ? "" : " ") + trim(line);
  }
  return out.empty() ? std::string(e.what()) : out;
}

std::size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j)
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] != b[j - 1])});
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

}  // namespace

std::string didYouMean(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t best_d = std::max<std::size_t>(2, word.size() / 3) + 1;
  for (const auto& c : candidates) {
    const std::size_t d = editDistance(lower(word), lower(c));
    if (d < best_d) best_d = d, best = c;
  }
  return best;
}

IniConfig IniConfig::fromFile(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw ConfigError(path + ": cannot open the configuration file");
  // Read at most kMaxBytes + 1: a device or a huge file is refused without reading it all.
  std::string text(kMaxBytes + 1, '\0');
  f.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<std::size_t>(f.gcount()));
  if (text.size() > kMaxBytes)
    throw ConfigError(path + ": larger than " + std::to_string(kMaxBytes >> 20) +
                      " MiB: not a configuration file");
  IniConfig c = fromText(text, path);
  c.base_dir_ = fs::absolute(fs::path(path)).parent_path().string();
  return c;
}

namespace {

/// Where each section and key first appears, for messages (MRPT does the real parsing); the
/// mistakes MRPT would pass over silently are errors naming the line.
struct SourceLines {
  std::map<std::string, int> section;
  std::map<std::pair<std::string, std::string>, int> key;
};

SourceLines scanIniLines(const std::string& text, const std::string& name) {
  SourceLines lines;
  std::istringstream is(text);
  std::string line, section;
  int n = 0;
  while (std::getline(is, line)) {
    ++n;
    const std::string t = trim(line);
    if (t.empty() || t[0] == ';' || t[0] == '#' || t.rfind("//", 0) == 0) continue;
    if (t[0] == '@') {  // MRPT's one directive; any other would be ignored silently
      const std::string word = t.substr(0, t.find_first_of(" \t"));
      if (word != "@define")
        throw ConfigError(name + ":" + std::to_string(n) + ": unknown directive '" + word +
                          "' (MRPT INI files know @define only)");
      continue;
    }
    if (t[0] == '[') {
      const auto close = t.find(']');
      if (close == std::string::npos)
        throw ConfigError(name + ":" + std::to_string(n) + ": unterminated section header '" + t +
                          "'");
      section = lower(trim(t.substr(1, close - 1)));
      lines.section.emplace(section, n);
      continue;
    }
    const auto eq = t.find('=');
    if (eq == std::string::npos)
      throw ConfigError(name + ":" + std::to_string(n) + ": expected 'key = value', got '" + t +
                        "'");
    const std::string key = lower(trim(t.substr(0, eq)));
    if (section.empty())
      throw ConfigError(name + ":" + std::to_string(n) + ": key '" + key +
                        "' before any [section]");
    const auto [it, fresh] = lines.key.emplace(std::make_pair(section, key), n);
    if (!fresh)
      throw ConfigError(name + ":" + std::to_string(n) + ": key '" + key + "' of [" + section +
                        "] is already set at line " + std::to_string(it->second) +
                        " (only one value would count)");
  }
  return lines;
}

}  // namespace

IniConfig IniConfig::fromText(const std::string& text, const std::string& name) {
  // A UTF-8 byte order mark (editors on Windows write one) is not part of the first line.
  if (text.rfind("\xEF\xBB\xBF", 0) == 0) return fromText(text.substr(3), name);
  IniConfig c;
  c.name_ = name;

  // MRPT's parser stops at a NUL byte: everything after it would silently be the default.
  if (const auto nul = text.find('\0'); nul != std::string::npos)
    throw ConfigError(name + ":" +
                      std::to_string(1 + std::count(text.begin(), text.begin() + nul, '\n')) +
                      ": a NUL byte: not a text INI file (everything after it would be lost)");

  const SourceLines lines = scanIniLines(text, name);
  const auto& section_line = lines.section;
  const auto& key_line = lines.key;

  std::unique_ptr<mrpt::config::CConfigFileMemory> mem;
  try {
    mem = std::make_unique<mrpt::config::CConfigFileMemory>(text);
  } catch (const std::exception& e) {
    throw ConfigError(name + ": " + mrptMessage(e));
  }
  std::vector<std::string> sections;
  mem->getAllSections(sections);
  for (const auto& s : sections) {
    const std::string ls = lower(s);
    auto& sec = c.sections_[ls];
    auto sl = section_line.find(ls);
    sec.origin = sl == section_line.end() ? name : name + ":" + std::to_string(sl->second);
    std::vector<std::string> keys;
    mem->getAllKeys(s, keys);
    for (const auto& k : keys) {
      const std::string lk = lower(k);
      Entry e;
      e.value = trim(mem->read_string(s, k, ""));
      auto kl = key_line.find({ls, lk});
      e.origin = kl == key_line.end() ? name : name + ":" + std::to_string(kl->second);
      sec.entries[lk] = e;
    }
  }
  // Sections with no keys are not reported by MRPT; keep them so they are validated too.
  for (const auto& [s, line] : section_line)
    if (!c.sections_.count(s)) c.sections_[s].origin = name + ":" + std::to_string(line);
  return c;
}

void IniConfig::set(const std::string& section, const std::string& key, const std::string& value,
                    const std::string& origin) {
  auto& sec = sections_[lower(section)];
  if (sec.origin.empty()) sec.origin = origin;
  sec.entries[lower(key)] = Entry{value, origin};
}

void IniConfig::applyOverride(const std::string& assignment) {
  const auto eq = assignment.find('=');
  const std::string lhs = eq == std::string::npos ? assignment : assignment.substr(0, eq);
  const auto dot = lhs.find('.');
  if (eq == std::string::npos || dot == std::string::npos || dot == 0 || dot + 1 == lhs.size())
    throw ConfigError("--set '" + assignment + "': expected section.key=value");
  set(trim(lhs.substr(0, dot)), trim(lhs.substr(dot + 1)), trim(assignment.substr(eq + 1)),
      "--set " + trim(lhs));
}

std::vector<std::string> IniConfig::sections() const {
  std::vector<std::string> v;
  for (const auto& [s, _] : sections_) v.push_back(s);
  return v;
}

bool IniConfig::hasSection(const std::string& section) const {
  return sections_.count(lower(section)) != 0;
}

std::vector<std::string> IniConfig::keys(const std::string& section) const {
  std::vector<std::string> v;
  auto it = sections_.find(lower(section));
  if (it != sections_.end())
    for (const auto& [k, _] : it->second.entries) v.push_back(k);
  return v;
}

bool IniConfig::has(const std::string& section, const std::string& key) const {
  auto it = sections_.find(lower(section));
  return it != sections_.end() && it->second.entries.count(lower(key));
}

std::string IniConfig::get(const std::string& section, const std::string& key) const {
  auto it = sections_.find(lower(section));
  if (it == sections_.end()) return {};
  auto k = it->second.entries.find(lower(key));
  return k == it->second.entries.end() ? std::string() : k->second.value;
}

std::string IniConfig::where(const std::string& section, const std::string& key) const {
  auto it = sections_.find(lower(section));
  if (it == sections_.end()) return name_;
  if (key.empty()) return it->second.origin;
  auto k = it->second.entries.find(lower(key));
  return k == it->second.entries.end() ? it->second.origin : k->second.origin;
}

std::string IniConfig::unknownSection(const std::string& section,
                                      const std::vector<std::string>& known,
                                      const std::string& expected) const {
  std::string msg = where(section) + ": unknown section [" + section + "]";
  const std::string hint = didYouMean(section, known);
  if (!hint.empty()) msg += " (did you mean [" + hint + "]?)";
  return msg + "; " + expected;
}

Params IniConfig::resolve(const std::string& section_in, const KeySpec* keys, std::size_t n) const {
  const std::string section = lower(section_in);
  Params p(section);
  std::vector<std::string> errors;
  std::vector<std::string> known;
  for (std::size_t i = 0; i < n; ++i) known.push_back(keys[i].name);

  auto sit = sections_.find(section);
  if (sit != sections_.end()) {
    for (const auto& [k, e] : sit->second.entries) {
      if (std::find(known.begin(), known.end(), k) != known.end()) continue;
      std::string msg = e.origin + ": [" + section + "] unknown key '" + k + "'";
      const std::string hint = didYouMean(k, known);
      if (!hint.empty()) msg += " (did you mean '" + hint + "'?)";
      errors.push_back(msg);
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    const KeySpec& spec = keys[i];
    Params::Value v;
    v.type = spec.type;
    const Entry* e = nullptr;
    if (sit != sections_.end()) {
      auto it = sit->second.entries.find(spec.name);
      if (it != sit->second.entries.end()) e = &it->second;
    }
    if (e) {
      v.text = e->value;
      v.is_default = false;
      v.origin = e->origin;
    } else if (spec.default_value) {
      v.text = spec.default_value;
      v.origin = "default";
    } else {
      errors.push_back((sit != sections_.end() ? sit->second.origin : name_) + ": [" + section +
                       "] missing required key '" + spec.name + "' (" + spec.doc + ")");
      continue;
    }
    if (auto why = validateValue(spec, v.text); !why.empty()) {
      errors.push_back(v.origin + ": [" + section + "] " + spec.name + " = '" + v.text +
                       "': " + why);
      continue;
    }
    if (spec.type == KeyType::Path && !v.text.empty() && !v.is_default && !base_dir_.empty() &&
        fs::path(v.text).is_relative())
      v.text = (fs::path(base_dir_) / v.text).lexically_normal().string();
    p.set(spec.name, v);
  }
  if (!errors.empty()) {
    std::string msg;
    for (const auto& e : errors) msg += (msg.empty() ? "" : "\n") + e;
    throw ConfigError(msg);
  }
  return p;
}

}  // namespace asf
