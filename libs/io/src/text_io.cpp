#include <asf/errors.h>
#include <asf/io/text_io.h>
#include <asf/atomic_file.h>
#include <bzlib.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/serialization/CSerializable.h>
#include <zlib.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <ostream>

#include "checked_output.h"

namespace asf::io {

namespace {

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::string bzErrorName(int code) {
  switch (code) {
    case BZ_DATA_ERROR:
      return "corrupt bzip2 data";
    case BZ_DATA_ERROR_MAGIC:
      return "not bzip2 data";
    case BZ_UNEXPECTED_EOF:
      return "bzip2 data ends early (truncated file)";
    case BZ_IO_ERROR:
      return "read/write error";
    case BZ_MEM_ERROR:
      return "out of memory";
    default:
      return "bzip2 error " + std::to_string(code);
  }
}

// A byte source: plain file, gzip (MRPT's zlib stream) or bzip2.
struct Source {
  virtual ~Source() = default;
  virtual std::size_t read(char* buf, std::size_t n) = 0;
  virtual double progress() const = 0;
};

struct PlainSource : Source {
  FILE* f = nullptr;
  double size = 0;
  ~PlainSource() override {
    if (f) std::fclose(f);
  }
  std::size_t read(char* buf, std::size_t n) override { return std::fread(buf, 1, n, f); }
  double progress() const override {
    return size > 0 ? static_cast<double>(std::ftell(f)) / size : 1.0;
  }
};

// zlib directly, not MRPT's gz stream: that one reports a truncated file as a clean end.
struct GzSource : Source {
  std::string path;
  gzFile f = nullptr;
  ~GzSource() override {
    if (f) gzclose(f);
  }
  std::size_t read(char* buf, std::size_t n) override {
    const int got = gzread(f, buf, static_cast<unsigned>(std::min<std::size_t>(n, 1u << 30)));
    if (got <= 0) {
      // zlib returns 0 both at the end and on a truncated file; gzerror tells them apart.
      int code = Z_OK;
      const char* msg = gzerror(f, &code);
      if (got < 0 || code != Z_OK) {
        std::string why = msg && *msg ? msg : "read error";
        if (why.rfind(path + ": ", 0) == 0) why.erase(0, path.size() + 2);  // zlib names it too
        throw InputError(path + ": gzip data: " + why +
                         (code == Z_BUF_ERROR ? " (truncated file)" : ""));
      }
    }
    return static_cast<std::size_t>(got);
  }
  double progress() const override { return size > 0 ? gzoffset(f) / size : -1; }
  double size = 0;
};

struct Bz2Source : Source {
  std::string path;
  FILE* f = nullptr;
  BZFILE* bz = nullptr;
  bool eof = false;
  double size = 0;
  ~Bz2Source() override {
    int err;
    if (bz) BZ2_bzReadClose(&err, bz);
    if (f) std::fclose(f);
  }
  std::size_t read(char* buf, std::size_t n) override {
    while (!eof) {
      int err = BZ_OK;
      const int got = BZ2_bzRead(&err, bz, buf, static_cast<int>(n));
      if (err == BZ_OK) {
        if (got > 0) return static_cast<std::size_t>(got);
        continue;
      }
      if (err != BZ_STREAM_END) throw InputError(path + ": " + bzErrorName(err));
      // End of one bzip2 stream: parallel compressors (pbzip2) concatenate several, so go on
      // with the bytes bzlib read past its end, if any, or with the rest of the file.
      void* unused = nullptr;
      int n_unused = 0;
      BZ2_bzReadGetUnused(&err, bz, &unused, &n_unused);
      std::vector<char> keep(static_cast<char*>(unused), static_cast<char*>(unused) + n_unused);
      BZ2_bzReadClose(&err, bz);
      bz = nullptr;
      bool more = n_unused > 0;
      if (!more) {
        const int c = std::fgetc(f);
        if (c != EOF) {
          std::ungetc(c, f);
          more = true;
        }
      }
      if (!more) {
        eof = true;
      } else {
        bz = BZ2_bzReadOpen(&err, f, 0, 0, keep.empty() ? nullptr : keep.data(), n_unused);
        if (err != BZ_OK) throw InputError(path + ": " + bzErrorName(err));
      }
      if (got > 0) return static_cast<std::size_t>(got);
    }
    return 0;
  }
  double progress() const override {
    return size > 0 ? static_cast<double>(std::ftell(f)) / size : 1.0;
  }
};

FILE* openFile(const std::string& path, const char* mode) {
  FILE* f = std::fopen(path.c_str(), mode);
  if (!f)
    throw InputError(path + ": cannot open " + (mode[0] == 'r' ? "for reading" : "for writing") +
                     " (" + std::strerror(errno) + ")");
  return f;
}

double fileSize(const std::string& path) {
  std::error_code ec;
  const auto s = std::filesystem::file_size(path, ec);
  return ec ? 0.0 : static_cast<double>(s);
}

}  // namespace

// ------------------------------------------------------------------------------ LineReader

struct LineReader::Impl {
  std::string path;
  std::unique_ptr<Source> src;
  std::vector<char> buf = std::vector<char>(1 << 20);
  std::size_t pos = 0, len = 0;
  bool eof = false;
  std::size_t line = 0;
};

LineReader::LineReader(const std::string& path) : impl_(std::make_unique<Impl>()) {
  impl_->path = path;
  if (!std::filesystem::is_regular_file(path)) throw InputError(path + ": no such file");
  if (endsWith(path, ".bz2")) {
    auto s = std::make_unique<Bz2Source>();
    s->path = path;
    s->f = openFile(path, "rb");
    s->size = fileSize(path);
    int err = BZ_OK;
    s->bz = BZ2_bzReadOpen(&err, s->f, 0, 0, nullptr, 0);
    if (err != BZ_OK) throw InputError(path + ": " + bzErrorName(err));
    impl_->src = std::move(s);
  } else if (endsWith(path, ".gz")) {
    auto s = std::make_unique<GzSource>();
    s->path = path;
    s->size = fileSize(path);
    s->f = gzopen(path.c_str(), "rb");
    if (!s->f) throw InputError(path + ": cannot open for reading");
    gzbuffer(s->f, 1 << 17);
    impl_->src = std::move(s);
  } else {
    auto s = std::make_unique<PlainSource>();
    s->f = openFile(path, "rb");
    s->size = fileSize(path);
    impl_->src = std::move(s);
  }
}

LineReader::~LineReader() = default;

bool LineReader::next(std::string& out) {
  Impl& d = *impl_;
  out.clear();
  bool any = false;
  for (;;) {
    if (d.pos == d.len) {
      if (d.eof) break;
      d.len = d.src->read(d.buf.data(), d.buf.size());
      d.pos = 0;
      if (d.len == 0) {
        d.eof = true;
        break;
      }
    }
    any = true;
    const char* begin = d.buf.data() + d.pos;
    const char* nl = static_cast<const char*>(std::memchr(begin, '\n', d.len - d.pos));
    if (nl) {
      out.append(begin, nl);
      d.pos += static_cast<std::size_t>(nl - begin) + 1;
      if (!out.empty() && out.back() == '\r') out.pop_back();
      ++d.line;
      return true;
    }
    out.append(begin, d.len - d.pos);
    d.pos = d.len;
  }
  if (!any) return false;
  if (!out.empty() && out.back() == '\r') out.pop_back();
  ++d.line;  // last line without a newline
  return true;
}

std::size_t LineReader::lineNumber() const { return impl_->line; }
const std::string& LineReader::path() const { return impl_->path; }
double LineReader::progress() const { return impl_->src->progress(); }

// ------------------------------------------------------------------------------- Bz2Writer

struct Bz2Writer::Impl {
  std::string path;
  FILE* f = nullptr;
  BZFILE* bz = nullptr;
};

Bz2Writer::Bz2Writer(const std::string& path) : impl_(std::make_unique<Impl>()) {
  impl_->path = path;
  impl_->f = openFile(path, "wb");
  int err = BZ_OK;
  impl_->bz = BZ2_bzWriteOpen(&err, impl_->f, 9, 0, 0);
  if (err != BZ_OK) {
    std::fclose(impl_->f);
    throw InputError(path + ": " + bzErrorName(err));
  }
}

Bz2Writer::~Bz2Writer() {
  if (!impl_->f) return;
  int err;
  BZ2_bzWriteClose(&err, impl_->bz, 1, nullptr, nullptr);
  std::fclose(impl_->f);
}

void Bz2Writer::write(std::string_view data) {
  if (!impl_->bz) throw InputError(impl_->path + ": write after close");
  while (!data.empty()) {
    const int n = static_cast<int>(std::min<std::size_t>(data.size(), 1 << 30));
    int err = BZ_OK;
    BZ2_bzWrite(&err, impl_->bz, const_cast<char*>(data.data()), n);
    if (err != BZ_OK) throw InputError(impl_->path + ": " + bzErrorName(err));
    data.remove_prefix(static_cast<std::size_t>(n));
  }
}

void Bz2Writer::close() {
  if (!impl_->f) return;
  int err = BZ_OK;
  BZ2_bzWriteClose(&err, impl_->bz, 0, nullptr, nullptr);
  impl_->bz = nullptr;
  const bool ok = std::fclose(impl_->f) == 0;
  impl_->f = nullptr;
  if (err != BZ_OK) throw InputError(impl_->path + ": " + bzErrorName(err));
  if (!ok) throw InputError(impl_->path + ": write error on close");
}

void writeTextFile(const std::string& path, std::string_view data) {
  if (endsWith(path, ".bz2")) {
    Bz2Writer w(path);
    w.write(data);
    w.close();
    return;
  }
  FILE* f = openFile(path, "wb");
  const bool ok = std::fwrite(data.data(), 1, data.size(), f) == data.size();
  if ((std::fclose(f) != 0) || !ok) throw InputError(path + ": write error");
}

// --------------------------------------------------------------------------------- parsing

namespace {
std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}
}  // namespace

std::vector<std::string_view> splitFields(std::string_view line, char sep) {
  std::vector<std::string_view> out;
  if (trim(line).empty()) return out;
  std::size_t start = 0;
  for (;;) {
    const std::size_t p = line.find(sep, start);
    if (p == std::string_view::npos) {
      out.push_back(trim(line.substr(start)));
      return out;
    }
    out.push_back(trim(line.substr(start, p - start)));
    start = p + 1;
  }
}

std::vector<std::string_view> splitWhitespace(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  const std::size_t n = line.size();
  while (i < n) {
    while (i < n && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    const std::size_t b = i;
    while (i < n && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
    if (i > b) out.push_back(line.substr(b, i - b));
  }
  return out;
}

std::optional<double> parseNumber(std::string_view s) {
  if (s.empty()) return std::nullopt;
  if (s.front() == '+') s.remove_prefix(1);  // from_chars refuses a leading '+'
  double v = 0;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  if (r.ec != std::errc() || r.ptr != s.data() + s.size()) return std::nullopt;
  return v;
}

std::optional<double> parseDouble(std::string_view s) {
  const auto v = parseNumber(s);
  if (!v || !std::isfinite(*v)) return std::nullopt;
  return v;
}

std::optional<long long> parseInt(std::string_view s) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  long long v = 0;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || r.ec != std::errc() || r.ptr != s.data() + s.size()) return std::nullopt;
  return v;
}

// ---------------------------------------------------------------------------------- Stamp

mrpt::Clock::time_point Stamp::toClock() const {
  // Whole seconds through fromDouble (exact for integers), microseconds added exactly.
  return mrpt::Clock::fromDouble(static_cast<double>(sec)) + std::chrono::microseconds(usec);
}

std::string Stamp::str() const {
  char b[40];
  std::snprintf(b, sizeof b, "%lld.%06d", static_cast<long long>(sec), static_cast<int>(usec));
  return b;
}

Stamp Stamp::plusMicroseconds(std::int64_t us) const {
  const std::int64_t total = sec * 1000000 + usec + us;
  return Stamp{total / 1000000, static_cast<std::int32_t>(total % 1000000)};
}

Stamp Stamp::fromSeconds(double t) {
  const auto us = static_cast<std::int64_t>(std::llround(t * 1e6));
  return Stamp{us / 1000000, static_cast<std::int32_t>(us % 1000000)};
}

bool operator<(const Stamp& a, const Stamp& b) {
  return a.sec < b.sec || (a.sec == b.sec && a.usec < b.usec);
}
bool operator==(const Stamp& a, const Stamp& b) { return a.sec == b.sec && a.usec == b.usec; }

std::optional<Stamp> parseStamp(std::string_view s) {
  const std::size_t dot = s.find('.');
  const std::string_view ip = s.substr(0, dot);
  const std::string_view fp =
      dot == std::string_view::npos ? std::string_view() : s.substr(dot + 1);
  const auto digits = [](std::string_view v) {
    return std::all_of(v.begin(), v.end(), [](char c) { return c >= '0' && c <= '9'; });
  };
  if (!ip.empty() && ip.size() <= 15 && digits(ip) && digits(fp) &&
      !(dot != std::string_view::npos && fp.empty() && ip.empty())) {
    Stamp st;
    st.sec = *parseInt(ip);
    if (st.sec >= static_cast<std::int64_t>(kMaxStampSeconds)) return std::nullopt;
    std::int64_t us = 0;
    for (std::size_t i = 0; i < 6; ++i) us = us * 10 + (i < fp.size() ? fp[i] - '0' : 0);
    if (fp.size() > 6 && fp[6] >= '5') ++us;  // round half up
    return st.plusMicroseconds(us);
  }
  // Other spellings (exponents, a leading '+'): through a double, to the microsecond.
  const auto v = parseDouble(s);
  if (!v || !(*v >= 0 && *v < kMaxStampSeconds)) return std::nullopt;
  return Stamp::fromSeconds(*v);
}

// ------------------------------------------------------------------------- ObsRawlogWriter

struct ObsRawlogWriter::Impl {
  explicit Impl(const std::string& path)
      : target(path, "rawlog"), out(target.file(), endsWith(path, ".gz"), path) {}
  AtomicOutput target;
  CheckedFileOutput out;
  std::unique_ptr<mrpt::serialization::CArchive> arch;
  std::size_t records = 0;
  bool closed = false;
};

ObsRawlogWriter::ObsRawlogWriter(const std::string& path) : impl_(std::make_unique<Impl>(path)) {
  impl_->arch = mrpt::serialization::archiveUniquePtrFrom(impl_->out);
}

// Without close(): Impl's members close the file and remove the temporary one.
ObsRawlogWriter::~ObsRawlogWriter() = default;

void ObsRawlogWriter::write(const mrpt::serialization::CSerializable& obj) {
  try {
    impl_->arch->WriteObject(&obj);
  } catch (const std::exception&) {
    throw InputError(impl_->target.path() + ": write failed (disk full or not writable?)");
  }
  ++impl_->records;
}

void ObsRawlogWriter::close() {
  Impl& d = *impl_;
  if (d.closed) return;
  d.arch.reset();
  d.out.close();  // throws when the last buffer or the close failed
  d.target.commit();
  d.closed = true;
}

std::size_t ObsRawlogWriter::records() const { return impl_->records; }

// ------------------------------------------------------------------------------- Progress

namespace {
double wallSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace

Progress::Progress(std::ostream* os, double interval_s)
    : os_(os), interval_s_(interval_s), last_(wallSeconds()) {}

bool Progress::due() {
  if (!os_) return false;
  const double now = wallSeconds();
  if (now - last_ < interval_s_) return false;
  last_ = now;
  return true;
}

std::string fixed(double v, int decimals) {
  char b[64];
  std::snprintf(b, sizeof b, "%.*f", decimals, v);
  std::string s = b;
  if (s[0] == '-' && s.find_first_not_of("-0.") == std::string::npos) s.erase(0, 1);
  return s;
}

}  // namespace asf::io
