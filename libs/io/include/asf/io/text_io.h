#pragma once
/// \file text_io.h
/// Building blocks of the log converters: line reading from plain, gzip or bzip2 files,
/// bzip2 writing, exact field parsing, timestamps, and an observation-only rawlog writer.
#include <mrpt/core/Clock.h>

#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace mrpt::serialization {
class CSerializable;
}

namespace asf::io {

/// Reads the lines of a text file; a name ending in ".gz" is gunzipped, ".bz2" bunzipped
/// (also concatenated bzip2 streams, as pbzip2 writes them). Errors are asf::InputError
/// naming the file (and the line for corrupt compressed data).
class LineReader {
 public:
  explicit LineReader(const std::string& path);
  ~LineReader();
  LineReader(const LineReader&) = delete;
  LineReader& operator=(const LineReader&) = delete;

  /// The next line without its end-of-line ("\n" or "\r\n"); false at the end of the file.
  bool next(std::string& line);
  /// 1-based number of the last line returned by next().
  std::size_t lineNumber() const;
  const std::string& path() const;
  /// Share of the (compressed) file read so far in [0, 1].
  double progress() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Writes a bzip2-compressed file. close() finishes it (the destructor closes silently).
class Bz2Writer {
 public:
  explicit Bz2Writer(const std::string& path);  ///< throws asf::InputError
  ~Bz2Writer();
  Bz2Writer(const Bz2Writer&) = delete;
  Bz2Writer& operator=(const Bz2Writer&) = delete;
  void write(std::string_view data);
  void close();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Writes `data` to `path`, bzip2-compressed when the name ends in ".bz2".
void writeTextFile(const std::string& path, std::string_view data);

/// Fields separated by `sep`, spaces and tabs around each field removed. A blank line gives
/// no fields.
std::vector<std::string_view> splitFields(std::string_view line, char sep);
/// Fields separated by runs of spaces and tabs.
std::vector<std::string_view> splitWhitespace(std::string_view line);

/// The whole field as a finite double (locale-independent); nullopt otherwise.
std::optional<double> parseDouble(std::string_view s);
/// The whole field as a double, also "inf"/"nan" (for range readings); nullopt if not a number.
std::optional<double> parseNumber(std::string_view s);
/// The whole field as an integer.
std::optional<long long> parseInt(std::string_view s);

/// A non-negative timestamp in seconds, held exactly to the microsecond (the resolution of
/// the Rawseeds and CARMEN logs; a double loses it near 1e9 s).
struct Stamp {
  std::int64_t sec = 0;
  std::int32_t usec = 0;  ///< [0, 999999]

  double seconds() const { return static_cast<double>(sec) + usec * 1e-6; }
  mrpt::Clock::time_point toClock() const;
  /// "sec.uuuuuu"
  std::string str() const;
  Stamp plusMicroseconds(std::int64_t us) const;
  static Stamp fromSeconds(double t);  ///< rounded to the microsecond; t >= 0
};
bool operator<(const Stamp& a, const Stamp& b);
bool operator==(const Stamp& a, const Stamp& b);
inline bool operator<=(const Stamp& a, const Stamp& b) { return !(b < a); }

/// Timestamps are below this many seconds (year 5138; MRPT's clock and the microsecond
/// arithmetic both hold there, 1e15 s overflowed it: found by fuzzing).
constexpr double kMaxStampSeconds = 1e11;

/// "seconds[.fraction]" (fraction rounded to the microsecond) or any non-negative decimal
/// number below kMaxStampSeconds; nullopt for anything else.
std::optional<Stamp> parseStamp(std::string_view s);

/// Writes an observation-only MRPT rawlog: one serialized object per record, gz-compressed
/// when the name ends in ".gz". Written as asf::AtomicOutput writes (atomic_file.h): into
/// "<path>.tmp", renamed to `path` by close(), so an interrupted or failed conversion never
/// leaves a file that looks complete nor loses the one that was there; a device (/dev/stdout)
/// is written in place. Every failed write, also the last buffer's, throws.
class ObsRawlogWriter {
 public:
  explicit ObsRawlogWriter(const std::string& path);  ///< throws asf::InputError
  ~ObsRawlogWriter();  ///< without close(): removes the partial file
  ObsRawlogWriter(const ObsRawlogWriter&) = delete;
  ObsRawlogWriter& operator=(const ObsRawlogWriter&) = delete;
  void write(const mrpt::serialization::CSerializable& obj);
  void close();
  std::size_t records() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Prints one progress line to `os` at most every `interval_s` seconds of wall time.
class Progress {
 public:
  Progress(std::ostream* os, double interval_s = 2.0);
  /// True when a line is due; the caller then prints it.
  bool due();
  std::ostream* stream() const { return os_; }

 private:
  std::ostream* os_;
  double interval_s_;
  double last_ = 0;
};

/// Number formatting for the text outputs: fixed, `decimals` digits, "-0.000000" as "0.000000".
std::string fixed(double v, int decimals = 6);

}  // namespace asf::io
