#include "scan_count_guard.h"

#include <algorithm>
#include <cstring>

namespace asf {

namespace {

constexpr std::uint8_t kNewFormat = 0x80;  ///< MRPT: class-name length byte of the new format
constexpr std::uint8_t kEndFlag = 0x88;    ///< MRPT: written after every object

bool isClass(const std::string& name, const char* cls) {
  const std::size_t n = std::strlen(cls);
  return name == cls || (name.size() > n + 2 &&
                         name.compare(name.size() - n - 2, n + 2, std::string("::") + cls) == 0);
}

}  // namespace

size_t ScanCountGuard::readAhead(void* buffer, size_t count) {
  const std::size_t from_ahead = std::min(count, ahead_.size());
  if (from_ahead > 0) {  // memcpy from an empty vector's null data() is undefined (UBSan)
    std::memcpy(buffer, ahead_.data(), from_ahead);
    ahead_.erase(ahead_.begin(), ahead_.begin() + static_cast<std::ptrdiff_t>(from_ahead));
  }
  if (from_ahead == count) return count;
  return from_ahead + in_.Read(static_cast<std::uint8_t*>(buffer) + from_ahead, count - from_ahead);
}

size_t ScanCountGuard::Read(void* buffer, size_t count) {
  const std::size_t n = readAhead(buffer, count);
  before_last_ = std::move(last_read_);
  // Only short reads can be a length byte, a class name or a version.
  last_read_.assign(n <= 64 ? static_cast<const char*>(buffer) : "", n <= 64 ? n : 0);
  if (header_ != Header::None) {
    const Header h = header_;
    header_ = Header::None;
    if (n == 1) check(h, static_cast<std::uint8_t>(last_read_[0]));
    return n;
  }
  if (before_last_.size() == 1 && !last_read_.empty() &&
      static_cast<std::uint8_t>(before_last_[0]) == (kNewFormat | last_read_.size())) {
    if (isClass(last_read_, "CObservation2DRangeScan")) header_ = Header::Scan;
    if (isClass(last_read_, "CSensoryFrame")) header_ = Header::SensoryFrame;
    if (isClass(last_read_, "CActionCollection")) header_ = Header::ActionCollection;
  }
  return n;
}

std::uint32_t ScanCountGuard::u32At(std::size_t i) const {  // MRPT writes little endian
  return static_cast<std::uint32_t>(ahead_[i]) | static_cast<std::uint32_t>(ahead_[i + 1]) << 8 |
         static_cast<std::uint32_t>(ahead_[i + 2]) << 16 |
         static_cast<std::uint32_t>(ahead_[i + 3]) << 24;
}

bool ScanCountGuard::peek(std::size_t n) {
  while (ahead_.size() < n) {
    std::uint8_t chunk[128];
    const std::size_t want = std::min(sizeof chunk, n - ahead_.size());
    std::size_t got = 0;
    try {
      got = in_.Read(chunk, want);
    } catch (const std::exception&) {
      return false;  // the end of the file: MRPT reports the cut itself
    }
    if (got == 0) return false;
    ahead_.insert(ahead_.end(), chunk, chunk + got);
  }
  return true;
}

void ScanCountGuard::check(Header h, std::uint8_t version) {
  if (h == Header::Scan) return checkScan(version);
  // CSensoryFrame version 2 and CActionCollection version 0 (what MRPT 2.5 writes): the
  // number of objects (uint32) right after the version; MRPT resizes a container to it.
  const bool frame = h == Header::SensoryFrame;
  if (version != (frame ? 2 : 0) || !peek(4)) return;
  const std::uint32_t n = u32At(0);
  if (n > kMaxObjects) {
    refusal_ = std::string(frame ? "a sensory frame claims " : "an action collection claims ") +
               std::to_string(n) + " objects (more than " + std::to_string(kMaxObjects) +
               ": a damaged count)";
    throw ScanCountError(refusal_);
  }
}

// The layout of CObservation2DRangeScan versions 6 to 8 up to the ray count (MRPT 2.5's
// serializeFrom): aperture (float), rightToLeft (bool, one byte), maxRange (float), the
// sensor pose as a nested object (class-name header, "mrpt::poses::CPose3D", version, its
// doubles, end flag), then the count (uint32, little endian). Older versions carry a
// covariance matrix before the count: not checked.
void ScanCountGuard::checkScan(std::uint8_t version) {
  if (version < 6 || version > 8) return;
  std::size_t at = 9;  // after aperture, rightToLeft, maxRange
  if (!peek(at + 1)) return;
  const std::uint8_t header = ahead_[at];
  if (!(header & kNewFormat)) return;
  const std::size_t name_len = header & 0x7f;
  if (!peek(at + 1 + name_len + 1)) return;
  const std::string name(ahead_.begin() + static_cast<std::ptrdiff_t>(at + 1),
                         ahead_.begin() + static_cast<std::ptrdiff_t>(at + 1 + name_len));
  at += 1 + name_len;
  // CPose3D version 2: the pose as x y z and a quaternion; 3 (MRPT 2.5 writes it): x y z
  // and the rotation matrix.
  const std::size_t pose_doubles = ahead_[at] == 2 ? 7 : ahead_[at] == 3 ? 12 : 0;
  if (!isClass(name, "CPose3D") || pose_doubles == 0) return;
  at += 1 + pose_doubles * sizeof(double);
  if (!peek(at + 1 + 4) || ahead_[at] != kEndFlag) return;
  at += 1;
  const std::uint32_t rays = u32At(at);
  if (rays > kMaxScanRays) {
    refusal_ = "a 2D scan claims " + std::to_string(rays) + " rays (more than " +
               std::to_string(kMaxScanRays) + ": a damaged count)";
    throw ScanCountError(refusal_);
  }
}

size_t ScanCountGuard::Write(const void*, size_t) {
  throw std::logic_error("ScanCountGuard: read-only stream");
}

uint64_t ScanCountGuard::Seek(int64_t, mrpt::io::CStream::TSeekOrigin) {
  throw std::logic_error("ScanCountGuard: no seeking");
}

}  // namespace asf
