#include "asf/io/rosbag2.h"

#include <asf/errors.h>
#include <asf/text.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <sqlite3.h>
#include <unistd.h>
#include <zstd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <ostream>
#include <set>
#include <sstream>

#include "asf/io/text_io.h"

namespace asf::io {

namespace fs = std::filesystem;

// ------------------------------------------------------------------------------- CDR -----

CdrReader::CdrReader(const std::uint8_t* data, std::size_t size, std::string where, Wire wire)
    : data_(data), size_(size), wire_(wire), where_(std::move(where)) {
  if (wire == Wire::Ros1) {  // no header, little-endian
    pos_ = 0;
    const std::uint16_t probe = 1;
    std::uint8_t first;
    std::memcpy(&first, &probe, 1);
    swap_ = first != 1;
    return;
  }
  if (size < 4) throw InputError(where_ + ": a CDR message shorter than its 4-byte header");
  // Encapsulation kind (big-endian short): 0 CDR_BE, 1 CDR_LE; the parameter-list and XCDR2
  // kinds are not what ROS 2 writes for these messages.
  if (data[0] != 0 || data[1] > 1)
    throw InputError(where_ + ": CDR encapsulation " + std::to_string(data[0] * 256 + data[1]) +
                     " is not plain CDR (0 big-endian, 1 little-endian)");
  const bool le = data[1] == 1;
  const std::uint16_t probe = 1;
  std::uint8_t first;
  std::memcpy(&first, &probe, 1);
  swap_ = (first == 1) != le;
}

void CdrReader::align(std::size_t n) {
  if (wire_ == Wire::Ros1) return;   // packed
  const std::size_t rel = pos_ - 4;  // alignment counts from the end of the header
  pos_ = 4 + (rel + n - 1) / n * n;
}

const std::uint8_t* CdrReader::need(std::size_t n) {
  if (pos_ > size_ || size_ - pos_ < n)
    throw InputError(where_ + ": the message ends at byte " + std::to_string(size_) +
                     ", inside a field at byte " + std::to_string(pos_) + " (truncated?)");
  const std::uint8_t* p = data_ + pos_;
  pos_ += n;
  return p;
}

namespace {
template <class T>
T readSwapped(const std::uint8_t* p, bool swap) {
  std::uint8_t b[sizeof(T)];
  std::memcpy(b, p, sizeof(T));
  if (swap) std::reverse(b, b + sizeof(T));
  T v;
  std::memcpy(&v, b, sizeof(T));
  return v;
}
}  // namespace

std::uint8_t CdrReader::u8() { return *need(1); }
std::int32_t CdrReader::i32() {
  align(4);
  return readSwapped<std::int32_t>(need(4), swap_);
}
std::uint32_t CdrReader::u32() {
  align(4);
  return readSwapped<std::uint32_t>(need(4), swap_);
}
float CdrReader::f32() {
  align(4);
  return readSwapped<float>(need(4), swap_);
}
double CdrReader::f64() {
  align(8);
  return readSwapped<double>(need(8), swap_);
}
std::string CdrReader::str() {
  const std::uint32_t n = u32();
  if (n == 0) return {};  // some writers send an empty string as length 0
  const std::uint8_t* p = need(n);
  if (wire_ == Wire::Ros1) return std::string(reinterpret_cast<const char*>(p), n);
  if (p[n - 1] != 0) throw InputError(where_ + ": a string without its terminating NUL");
  return std::string(reinterpret_cast<const char*>(p), n - 1);
}
std::vector<float> CdrReader::f32seq() {
  const std::uint32_t n = u32();
  if (n > (size_ - std::min(size_, pos_)) / 4)
    throw InputError(where_ + ": a sequence of " + std::to_string(n) +
                     " floats is longer than the message");
  std::vector<float> v(n);
  for (auto& x : v) x = f32();
  return v;
}

namespace {

void header(CdrReader& c, RosTime& stamp, std::string& frame_id, Wire wire) {
  if (wire == Wire::Ros1) c.u32();  // seq
  stamp.sec = c.i32();
  stamp.nanosec = c.u32();
  frame_id = c.str();
}

/// geometry_msgs/Pose: position, then orientation (x, y, z, w).
template <class M>
void pose(CdrReader& c, M& m) {
  m.x = c.f64();
  m.y = c.f64();
  m.z = c.f64();
  m.qx = c.f64();
  m.qy = c.f64();
  m.qz = c.f64();
  m.qw = c.f64();
}

}  // namespace

LaserScanMsg decodeLaserScan(const std::uint8_t* data, std::size_t size, const std::string& where,
                             Wire wire) {
  CdrReader c(data, size, where, wire);
  LaserScanMsg m;
  header(c, m.stamp, m.frame_id, wire);
  m.angle_min = c.f32();
  m.angle_max = c.f32();
  m.angle_increment = c.f32();
  m.time_increment = c.f32();
  m.scan_time = c.f32();
  m.range_min = c.f32();
  m.range_max = c.f32();
  m.ranges = c.f32seq();
  m.intensities = c.f32seq();
  return m;
}

OdometryMsg decodeOdometry(const std::uint8_t* data, std::size_t size, const std::string& where,
                           Wire wire) {
  CdrReader c(data, size, where, wire);
  OdometryMsg m;
  header(c, m.stamp, m.frame_id, wire);
  m.child_frame_id = c.str();
  pose(c, m);
  for (int k = 0; k < 36; ++k) c.f64();  // the pose covariance: the message must hold it
  return m;
}

OdometryMsg decodePoseStamped(const std::uint8_t* data, std::size_t size, const std::string& where,
                              Wire wire) {
  CdrReader c(data, size, where, wire);
  OdometryMsg m;
  header(c, m.stamp, m.frame_id, wire);
  pose(c, m);
  return m;
}

std::vector<TransformMsg> decodeTfMessage(const std::uint8_t* data, std::size_t size,
                                          const std::string& where, Wire wire) {
  CdrReader c(data, size, where, wire);
  const std::uint32_t n = c.u32();
  if (n > size / 60) throw InputError(where + ": " + std::to_string(n) + " transforms cannot fit");
  std::vector<TransformMsg> v(n);
  for (auto& t : v) {
    header(c, t.stamp, t.frame_id, wire);
    t.child_frame_id = c.str();
    pose(c, t);
  }
  return v;
}

// --------------------------------------------------------------------------- the bag -----

namespace {

struct Db {
  sqlite3* db = nullptr;
  ~Db() {
    if (db) sqlite3_close(db);
  }
};

struct Stmt {
  sqlite3_stmt* s = nullptr;
  Stmt(sqlite3* db, const std::string& sql, const std::string& file) {
    if (sqlite3_prepare_v2(db, sql.c_str(), -1, &s, nullptr) != SQLITE_OK)
      throw InputError(file + ": not a rosbag2 sqlite3 file (" + sqlite3_errmsg(db) + ")");
  }
  ~Stmt() { sqlite3_finalize(s); }
  std::string text(int col) const {
    const unsigned char* t = sqlite3_column_text(s, col);
    return t ? reinterpret_cast<const char*>(t) : "";
  }
};

/// The value of `key: value` on its own line (quotes removed), or "".
std::string yamlValue(const std::string& text, const std::string& key) {
  std::istringstream is(text);
  std::string line;
  while (std::getline(is, line)) {
    const std::string t = trim(line);
    if (t.rfind(key + ":", 0) != 0) continue;
    std::string v = trim(t.substr(key.size() + 1));
    if (v.size() >= 2 && (v.front() == '"' || v.front() == '\'')) v = v.substr(1, v.size() - 2);
    return v;
  }
  return "";
}

/// The items of the block list under `key:` ("- item" lines).
std::vector<std::string> yamlList(const std::string& text, const std::string& key) {
  std::istringstream is(text);
  std::string line;
  std::vector<std::string> out;
  bool in = false;
  while (std::getline(is, line)) {
    const std::string t = trim(line);
    if (!in) {
      in = t == key + ":";
      continue;
    }
    if (t.rfind("- ", 0) != 0) break;
    std::string v = trim(t.substr(2));
    if (v.size() >= 2 && (v.front() == '"' || v.front() == '\'')) v = v.substr(1, v.size() - 2);
    out.push_back(v);
  }
  return out;
}

}  // namespace

struct Rosbag2Reader::Impl {
  std::vector<std::string> files;  ///< what SQLite opens
  std::vector<std::string> names;  ///< what errors name: the bag's file, never a temporary
  std::vector<std::unique_ptr<Db>> dbs;
  std::vector<BagTopic> topics;
  bool zstd_messages = false;        ///< compression_mode MESSAGE: every blob a zstd frame
  std::vector<std::string> scratch;  ///< files decompressed for compression_mode FILE
  ~Impl() {
    dbs.clear();
    for (const auto& f : scratch) std::remove(f.c_str());
  }
};

namespace {

/// A rosbag2 folder's metadata.yaml: storage, files, rosbag2's own compression.
struct Folder {
  std::string storage, compression, mode;
  std::vector<std::string> files;
};

Folder readFolder(const std::string& path) {
  const fs::path meta = fs::path(path) / "metadata.yaml";
  std::ifstream f(meta);
  if (!f) throw InputError(path + ": a folder without metadata.yaml is not a rosbag2 bag");
  const std::string text((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  Folder out;
  out.storage = yamlValue(text, "storage_identifier");
  out.compression = yamlValue(text, "compression_format");
  out.mode = yamlValue(text, "compression_mode");
  if (!out.compression.empty() &&
      (out.compression != "zstd" || (out.mode != "FILE" && out.mode != "MESSAGE") ||
       out.storage != "sqlite3"))
    throw InputError(meta.string() + ": compressed with '" + out.compression + "' (" + out.mode +
                     " mode, " + out.storage +
                     " storage), which is not supported (zstd FILE or MESSAGE mode of sqlite3 "
                     "bags is); decompress with `ros2 bag decompress` or `ros2 bag convert`");
  for (const auto& r : yamlList(text, "relative_file_paths"))
    out.files.push_back((fs::path(path) / r).string());
  if (out.files.empty()) throw InputError(meta.string() + ": no relative_file_paths");
  return out;
}

// A recorder's zstd expands a few times; more than this (past the floor) is refused before it
// fills the memory or the disk.
constexpr std::uint64_t kMaxExpansion = 1000, kExpansionFloor = std::uint64_t{64} << 20;

using ZstdStream = std::unique_ptr<ZSTD_DStream, std::size_t (*)(ZSTD_DStream*)>;

/// `n` bytes of zstd frames decompressed (the frame's size when it says it, else streamed).
std::vector<std::uint8_t> unzstd(const std::uint8_t* in, std::size_t n, const std::string& where) {
  ZstdStream ds(ZSTD_createDStream(), &ZSTD_freeDStream);
  std::vector<std::uint8_t> out;
  std::vector<std::uint8_t> buf(ZSTD_DStreamOutSize());
  ZSTD_inBuffer ib{in, n, 0};
  std::size_t rc = 0;
  for (;;) {
    ZSTD_outBuffer ob{buf.data(), buf.size(), 0};
    rc = ZSTD_decompressStream(ds.get(), &ob, &ib);
    if (ZSTD_isError(rc)) break;
    out.insert(out.end(), buf.data(), buf.data() + ob.pos);
    if (out.size() > std::max<std::size_t>(kMaxExpansion * n, kExpansionFloor))
      throw InputError(where + ": expands more than " + std::to_string(kMaxExpansion) +
                       "-fold: not what a recorder writes");
    // All input read and room left in the output: done (rc != 0: the frame is cut short).
    if (ib.pos == ib.size && ob.pos < ob.size) break;
  }
  if (ZSTD_isError(rc) || rc != 0)
    throw InputError(where + ": not a whole zstd frame (" +
                     (ZSTD_isError(rc) ? ZSTD_getErrorName(rc) : "truncated") + ")");
  return out;
}

/// compression_mode FILE: the zstd stream `file` decompressed into `tmp`, one buffer at a time.
/// Bounded as unzstd is.
void unzstdFile(const std::string& file, const std::string& tmp) {
  std::error_code ec;
  const std::uint64_t size = fs::file_size(file, ec);
  if (ec) throw InputError(file + ": cannot open (" + ec.message() + ")");
  const std::uint64_t limit = std::max(kMaxExpansion * size, kExpansionFloor);
  std::ifstream in(file, std::ios::binary);
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> out(std::fopen(tmp.c_str(), "wb"), &std::fclose);
  if (!in || !out) throw InputError(file + ": cannot " + (in ? "create " + tmp : "open"));
  ZstdStream ds(ZSTD_createDStream(), &ZSTD_freeDStream);
  std::vector<char> ibuf(ZSTD_DStreamInSize()), obuf(ZSTD_DStreamOutSize());
  std::uint64_t written = 0;
  std::size_t rc = 0;
  while (in.read(ibuf.data(), static_cast<std::streamsize>(ibuf.size())) || in.gcount() > 0) {
    ZSTD_inBuffer ib{ibuf.data(), static_cast<std::size_t>(in.gcount()), 0};
    while (ib.pos < ib.size || rc > 0) {
      ZSTD_outBuffer ob{obuf.data(), obuf.size(), 0};
      rc = ZSTD_decompressStream(ds.get(), &ob, &ib);
      if (ZSTD_isError(rc))
        throw InputError(file + ": not a whole zstd frame (" + ZSTD_getErrorName(rc) + ")");
      if ((written += ob.pos) > limit)
        throw InputError(file + ": expands more than " + std::to_string(kMaxExpansion) +
                         "-fold (past " + std::to_string(limit >> 20) + " MiB from " +
                         std::to_string(size) + " bytes): not a bag a recorder writes");
      if (std::fwrite(obuf.data(), 1, ob.pos, out.get()) != ob.pos)
        throw InputError(file + ": decompressing it into " + tmp + " failed: " +
                         std::strerror(errno));
      if (ob.pos < ob.size && ib.pos == ib.size) break;  // this input is used up
    }
  }
  if (rc != 0) throw InputError(file + ": not a whole zstd frame (truncated)");
  if (std::fclose(out.release()) != 0)
    throw InputError(file + ": decompressing it into " + tmp + " failed: " + std::strerror(errno));
}

}  // namespace

Rosbag2Reader::Rosbag2Reader(const std::string& path) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  std::error_code ec;
  if (fs::is_directory(path, ec)) {
    const Folder folder = readFolder(path);
    if (folder.storage != "sqlite3")
      throw InputError(
          path + ": storage '" + folder.storage +
          "' is not supported (sqlite3 and mcap are; convert with `ros2 bag convert`)");
    m.zstd_messages = folder.mode == "MESSAGE";
    for (const auto& file : folder.files) {
      if (folder.mode != "FILE") {
        m.files.push_back(file);
        m.names.push_back(file);
        continue;
      }
      // FILE mode: each storage file is one zstd stream; SQLite needs it on disk, whole.
      const fs::path tmp =
          fs::temp_directory_path() /
          ("asf_rosbag2_" + std::to_string(::getpid()) + "_" + std::to_string(m.scratch.size()) +
           "_" + std::to_string(reinterpret_cast<std::uintptr_t>(this)) + ".db3");
      m.scratch.push_back(tmp.string());  // removed by ~Impl, also when this throws
      unzstdFile(file, tmp.string());
      m.files.push_back(tmp.string());
      m.names.push_back(file);
    }
  } else if (fs::exists(path, ec)) {
    m.files.push_back(path);
    m.names.push_back(path);
  } else {
    throw InputError(path + ": no such bag (a rosbag2 folder or a .db3 file)");
  }
  std::map<std::string, std::size_t> by_name;
  for (std::size_t k = 0; k < m.files.size(); ++k) {
    const std::string& file = m.files[k];
    const std::string& name = m.names[k];
    auto db = std::make_unique<Db>();
    if (sqlite3_open_v2(file.c_str(), &db->db, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK)
      throw InputError(name + ": cannot open (" + sqlite3_errmsg(db->db) + ")");
    Stmt t(db->db,
           "SELECT t.name, t.type, t.serialization_format, COUNT(m.id) FROM topics t "
           "LEFT JOIN messages m ON m.topic_id = t.id GROUP BY t.id ORDER BY t.id",
           name);
    while (sqlite3_step(t.s) == SQLITE_ROW) {
      const std::string topic = t.text(0);
      auto it = by_name.find(topic);
      if (it == by_name.end()) {
        it = by_name.emplace(topic, m.topics.size()).first;
        m.topics.push_back({topic, t.text(1), t.text(2), 0});
      }
      m.topics[it->second].messages += static_cast<std::uint64_t>(sqlite3_column_int64(t.s, 3));
    }
    m.dbs.push_back(std::move(db));
    // A decompressed copy leaves the folder once open: SQLite reads it through its open file,
    // and the space comes back on any exit, a kill -9 included.
    if (file != name) std::remove(file.c_str());
  }
}

Rosbag2Reader::~Rosbag2Reader() = default;

const std::vector<BagTopic>& Rosbag2Reader::topics() const { return impl_->topics; }

const BagTopic* BagReader::topic(const std::string& name) const {
  for (const auto& t : topics())
    if (t.name == name) return &t;
  return nullptr;
}

std::unique_ptr<BagReader> openBag(const std::string& path) {
  const std::string ext = fs::path(path).extension().string();
  if (ext == ".bag") return std::make_unique<Ros1BagReader>(path);
  if (ext == ".mcap") {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) throw InputError(path + ": no such MCAP file");
    return std::make_unique<McapReader>(std::vector<std::string>{path});
  }
  std::error_code ec;
  if (fs::is_directory(path, ec)) {
    const Folder folder = readFolder(path);
    if (folder.storage == "mcap") return std::make_unique<McapReader>(folder.files);
  }
  return std::make_unique<Rosbag2Reader>(path);
}

void Rosbag2Reader::visit(const std::vector<std::string>& topics, Visitor v, void* ctx) const {
  for (std::size_t k = 0; k < impl_->dbs.size(); ++k) {
    sqlite3* db = impl_->dbs[k]->db;
    const std::string& file = impl_->names[k];
    std::string in;
    for (const auto& t : topics) {
      char* q = sqlite3_mprintf("%Q", t.c_str());
      in += (in.empty() ? "" : ", ") + std::string(q);
      sqlite3_free(q);
    }
    Stmt s(db,
           "SELECT t.name, m.timestamp, m.data FROM messages m JOIN topics t ON t.id = m.topic_id "
           "WHERE t.name IN (" +
               in + ") ORDER BY m.timestamp, m.id",
           file);
    int rc;
    while ((rc = sqlite3_step(s.s)) == SQLITE_ROW) {
      const auto* d = static_cast<const std::uint8_t*>(sqlite3_column_blob(s.s, 2));
      const auto n = static_cast<std::size_t>(sqlite3_column_bytes(s.s, 2));
      if (impl_->zstd_messages) {  // MESSAGE mode: each message a zstd frame
        const auto raw = unzstd(d, n, file + ": a message of " + s.text(0));
        if (!v(ctx, s.text(0), sqlite3_column_int64(s.s, 1), raw.data(), raw.size())) return;
      } else {
        if (!v(ctx, s.text(0), sqlite3_column_int64(s.s, 1), d, n)) return;
      }
    }
    if (rc != SQLITE_DONE) throw InputError(file + ": " + sqlite3_errmsg(db));
  }
}

}  // namespace asf::io
