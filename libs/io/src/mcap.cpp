// MCAP files (https://mcap.dev/spec, the default storage of rosbag2 since ROS 2 Iron), read by
// its specification: the records of the data section, chunks uncompressed, LZ4 (frame) or
// Zstandard; schemas, channels and messages; the summary section is not needed and skipped.
#include <asf/errors.h>
#include <lz4frame.h>
#include <zstd.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <map>

#include "asf/io/rosbag2.h"

namespace asf::io {

namespace {

constexpr std::uint8_t kMagic[8] = {0x89, 'M', 'C', 'A', 'P', 0x30, '\r', '\n'};
constexpr std::uint64_t kMaxRecord = std::uint64_t(1) << 32;  // 4 GiB: refused as damaged

enum Op : std::uint8_t {
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kFooter = 0x02,
  kDataEnd = 0x0F,
};

/// Little-endian fields of one record, bounds-checked.
class Fields {
 public:
  Fields(const std::uint8_t* p, std::size_t n, std::string where)
      : p_(p), n_(n), where_(std::move(where)) {}
  template <class T>
  T num() {
    T v;
    std::memcpy(&v, take(sizeof(T)), sizeof(T));  // MCAP is little-endian, as this machine
    return v;
  }
  std::string str() {
    const auto len = num<std::uint32_t>();
    return std::string(reinterpret_cast<const char*>(take(len)), len);
  }
  void skipBytes32() { take(num<std::uint32_t>()); }
  const std::uint8_t* take(std::uint64_t k) {
    if (k > n_ - pos_) throw InputError(where_ + ": a record ends inside a field (damaged?)");
    const std::uint8_t* q = p_ + pos_;
    pos_ += static_cast<std::size_t>(k);
    return q;
  }
  std::size_t left() const { return n_ - pos_; }
  const std::uint8_t* here() const { return p_ + pos_; }

 private:
  const std::uint8_t* p_;
  std::size_t n_, pos_ = 0;
  std::string where_;
};

std::vector<std::uint8_t> decompress(const std::string& how, const std::uint8_t* in, std::size_t n,
                                     std::uint64_t size, const std::string& where) {
  // Claimed sizes are checked before anything is allocated: a damaged header must not ask for
  // gigabytes. No sensor data compresses better than 1000:1 (zeros aside).
  if (size > kMaxRecord || size > 1000 * static_cast<std::uint64_t>(n) + (1u << 20))
    throw InputError(where + ": a chunk claims " + std::to_string(size) + " bytes from " +
                     std::to_string(n) + " compressed (damaged?)");
  std::vector<std::uint8_t> out(static_cast<std::size_t>(size));
  if (how.empty()) {
    if (n != size) throw InputError(where + ": an uncompressed chunk of the wrong size");
    std::copy(in, in + n, out.begin());
  } else if (how == "zstd") {
    const std::size_t got = ZSTD_decompress(out.data(), out.size(), in, n);
    if (ZSTD_isError(got) || got != size)
      throw InputError(where + ": a zstd chunk does not decompress (" +
                       (ZSTD_isError(got) ? ZSTD_getErrorName(got) : "wrong size") + ")");
  } else if (how == "lz4") {
    LZ4F_dctx* ctx = nullptr;
    if (LZ4F_isError(LZ4F_createDecompressionContext(&ctx, LZ4F_VERSION)))
      throw InputError(where + ": cannot start LZ4");
    std::size_t done = 0, used_total = 0, rc = 1;
    while (rc != 0 && used_total < n) {
      std::size_t dst = out.size() - done, src = n - used_total;
      rc = LZ4F_decompress(ctx, out.data() + done, &dst, in + used_total, &src, nullptr);
      if (LZ4F_isError(rc)) break;
      done += dst;
      used_total += src;
      if (dst == 0 && src == 0) break;
    }
    LZ4F_freeDecompressionContext(ctx);
    if (LZ4F_isError(rc) || done != size)
      throw InputError(where + ": an lz4 chunk does not decompress");
  } else {
    throw InputError(where + ": a chunk compressed with '" + how +
                     "', which is not supported (none, lz4, zstd)");
  }
  return out;
}

}  // namespace

struct McapReader::Impl {
  struct Channel {
    std::string topic, type, encoding;
  };
  std::vector<std::string> files;
  std::vector<BagTopic> topics;
  /// Called for every message (file order) of the data sections; schemas and channels kept.
  template <class F>
  void scan(F&& on_message);
  template <class F>
  void records(const std::uint8_t* p, std::size_t n, const std::string& where, F& on_message,
               bool in_chunk);
  std::map<std::uint16_t, std::string> schemas;
  std::map<std::uint16_t, Channel> channels;
  bool data_end = false;
};

template <class F>
void McapReader::Impl::records(const std::uint8_t* p, std::size_t n, const std::string& where,
                               F& on_message, bool in_chunk) {
  Fields all(p, n, where);
  while (all.left() > 0 && !data_end) {
    const auto op = all.num<std::uint8_t>();
    const auto len = all.num<std::uint64_t>();
    Fields r(all.take(len), static_cast<std::size_t>(len), where);
    switch (op) {
      case kSchema: {
        const auto id = r.num<std::uint16_t>();
        schemas[id] = r.str();  // the type's name; its encoding and text are not needed
        break;
      }
      case kChannel: {
        const auto id = r.num<std::uint16_t>();
        const auto schema = r.num<std::uint16_t>();
        Channel c;
        c.topic = r.str();
        c.encoding = r.str();
        auto s = schemas.find(schema);
        c.type = s == schemas.end() ? "" : s->second;
        channels[id] = c;
        break;
      }
      case kMessage: {
        const auto ch = r.num<std::uint16_t>();
        r.num<std::uint32_t>();  // sequence
        const auto log_time = r.num<std::uint64_t>();
        r.num<std::uint64_t>();  // publish time
        auto c = channels.find(ch);
        if (c == channels.end())
          throw InputError(where + ": a message on channel " + std::to_string(ch) +
                           " before its channel record");
        on_message(c->second.topic, log_time, r.here(), r.left());
        break;
      }
      case kChunk: {
        if (in_chunk) throw InputError(where + ": a chunk inside a chunk");
        r.num<std::uint64_t>();  // message start time
        r.num<std::uint64_t>();  // message end time
        const auto size = r.num<std::uint64_t>();
        r.num<std::uint32_t>();  // uncompressed CRC (0: not computed)
        const std::string how = r.str();
        const auto clen = r.num<std::uint64_t>();
        const std::uint8_t* c = r.take(clen);
        const auto raw = decompress(how, c, static_cast<std::size_t>(clen), size, where);
        records(raw.data(), raw.size(), where, on_message, true);
        break;
      }
      case kDataEnd:
      case kFooter:
        if (!in_chunk) data_end = true;
        break;
      default:
        break;  // header, indexes, attachments, metadata, statistics: not needed
    }
  }
}

template <class F>
void McapReader::Impl::scan(F&& on_message) {
  for (const auto& file : files) {
    std::ifstream f(file, std::ios::binary | std::ios::ate);
    if (!f) throw InputError(file + ": cannot open");
    const auto file_size = static_cast<std::uint64_t>(f.tellg());
    f.seekg(0);
    std::uint8_t magic[8];
    if (!f.read(reinterpret_cast<char*>(magic), 8) || std::memcmp(magic, kMagic, 8) != 0)
      throw InputError(file + ": not an MCAP file (no MCAP magic)");
    schemas.clear();
    channels.clear();
    data_end = false;
    // Record by record: an opcode, a length, the content (one chunk at a time in memory).
    std::vector<std::uint8_t> buf;
    for (std::uint64_t at = 8; !data_end;) {
      std::uint8_t head[9];
      if (!f.read(reinterpret_cast<char*>(head), 9)) break;  // the end without a footer
      std::uint64_t len;
      std::memcpy(&len, head + 1, 8);
      if (len > file_size - std::min(file_size, at + 9))
        throw InputError(file + ": the file ends inside the record at byte " + std::to_string(at) +
                         " (" + std::to_string(len) + " bytes long)");
      buf.resize(9 + static_cast<std::size_t>(len));
      std::memcpy(buf.data(), head, 9);
      if (!f.read(reinterpret_cast<char*>(buf.data() + 9), static_cast<std::streamsize>(len)))
        throw InputError(file + ": the file ends inside the record at byte " + std::to_string(at));
      records(buf.data(), buf.size(), file + " (record at byte " + std::to_string(at) + ")",
              on_message, false);
      at += 9 + len;
    }
  }
}

McapReader::McapReader(const std::vector<std::string>& files) : impl_(std::make_unique<Impl>()) {
  impl_->files = files;
  std::map<std::string, std::size_t> counts;
  impl_->scan([&](const std::string& topic, std::uint64_t, const std::uint8_t*, std::size_t) {
    ++counts[topic];
  });
  std::map<std::string, bool> seen;
  for (const auto& [id, c] : impl_->channels)
    if (!seen[c.topic]) {
      seen[c.topic] = true;
      impl_->topics.push_back({c.topic, c.type, c.encoding, counts[c.topic]});
    }
}

McapReader::~McapReader() = default;

const std::vector<BagTopic>& McapReader::topics() const { return impl_->topics; }

void McapReader::visit(const std::vector<std::string>& topics, Visitor v, void* ctx) const {
  struct Msg {
    std::uint64_t t;
    std::size_t topic;
    std::vector<std::uint8_t> data;
  };
  std::vector<Msg> msgs;
  impl_->scan([&](const std::string& topic, std::uint64_t t, const std::uint8_t* d, std::size_t n) {
    const auto it = std::find(topics.begin(), topics.end(), topic);
    if (it != topics.end())
      msgs.push_back({t, static_cast<std::size_t>(it - topics.begin()), {d, d + n}});
  });
  // The bag's time order (chunks may overlap in time), ties in file order.
  std::stable_sort(msgs.begin(), msgs.end(), [](const Msg& a, const Msg& b) { return a.t < b.t; });
  for (const auto& m : msgs)
    if (!v(ctx, topics[m.topic], static_cast<std::int64_t>(m.t), m.data.data(), m.data.size()))
      return;
}

}  // namespace asf::io
