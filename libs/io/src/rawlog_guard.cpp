#include <asf/io/rawlog_guard.h>

#include <mrpt/obs/CAction.h>
#include <mrpt/obs/CObservation.h>
#include <mrpt/poses/CPosePDF.h>
#include <mrpt/rtti/CObject.h>

#include <algorithm>
#include <cstring>

namespace asf::io {

namespace {

constexpr std::uint8_t kNewFormat = 0x80;  ///< MRPT: class-name length byte of the new format
constexpr std::uint8_t kEndFlag = 0x88;    ///< MRPT: written after every object

/// The class MRPT makes of a class-name read: the bytes up to the first NUL (MRPT reads a C
/// string), resolved as MRPT resolves it (by the part after the last "::": a damaged
/// "mrp::CActionCollection" is still a collection). Null for "nullptr" or an unknown name.
const mrpt::rtti::TRuntimeClassId* resolve(const std::string& read, bool& null) {
  const std::string name(read.c_str());
  null = name == "nullptr";
  return null ? nullptr : mrpt::rtti::findRegisteredClass(name);
}

bool is(const mrpt::rtti::TRuntimeClassId* cls, const char* name) {
  return cls && std::strcmp(cls->className, name) == 0;
}

}  // namespace

// MRPT reads each value in one call and checks only that something was read: a value cut by
// the end of the file would be taken whole, its missing bytes uninitialized (a cut ray count
// became a 5 GB scan). So a read gives all it was asked for or nothing.
size_t RawlogGuard::readAhead(void* buffer, size_t count) {
  auto* out = static_cast<std::uint8_t*>(buffer);
  std::size_t have = std::min(count, ahead_.size());
  if (have > 0) {  // memcpy from an empty vector's null data() is undefined (UBSan)
    std::memcpy(out, ahead_.data(), have);
    ahead_.erase(ahead_.begin(), ahead_.begin() + static_cast<std::ptrdiff_t>(have));
  }
  while (have < count) {
    const std::size_t got = in_.Read(out + have, count - have);
    if (got == 0 || got > count - have) break;  // the end (MRPT's gz stream says -1 there)
    have += got;
  }
  return have == count ? count : 0;
}

size_t RawlogGuard::Read(void* buffer, size_t count) {
  const std::size_t n = readAhead(buffer, count);
  before_last_ = std::move(last_read_);
  // Class names are up to 127 bytes (the length byte's low 7 bits); longer reads are data.
  last_read_.assign(n <= 127 ? static_cast<const char*>(buffer) : "", n <= 127 ? n : 0);
  if (header_ != Kind::None) {
    const Kind kind = header_;
    header_ = Kind::None;
    if (n == 1) onVersion(kind, static_cast<std::uint8_t>(last_read_[0]));
    return n;
  }
  if (before_last_.size() == 1 && !last_read_.empty() &&
      static_cast<std::uint8_t>(before_last_[0]) == (kNewFormat | last_read_.size())) {
    onHeader(last_read_);
  } else if (n == 1 && static_cast<std::uint8_t>(last_read_[0]) == kEndFlag && !open_.empty()) {
    onEndFlag();
  }
  return n;
}

void RawlogGuard::onHeader(const std::string& name) {
  bool null = false;  // what MRPT writes for a null pointer (no version follows)
  const mrpt::rtti::TRuntimeClassId* cls = resolve(name, null);
  if (!null && !cls) return;  // not an object header, or a class MRPT refuses itself
  const Kind kind = is(cls, "mrpt::obs::CObservation2DRangeScan")  ? Kind::Scan
                    : is(cls, "mrpt::obs::CObservation3DRangeScan") ? Kind::Scan3D
                    : is(cls, "mrpt::obs::CObservationOdometry")   ? Kind::Odometry
                    : is(cls, "mrpt::obs::CSensoryFrame")          ? Kind::SensoryFrame
                    : is(cls, "mrpt::obs::CActionCollection")      ? Kind::ActionCollection
                    : is(cls, "mrpt::obs::CActionRobotMovement2D") ? Kind::Movement2D
                    : is(cls, "mrpt::obs::CActionRobotMovement3D") ? Kind::Movement3D
                                                                   : Kind::Other;
  if (!open_.empty()) {
    Open& parent = open_.back();
    ++parent.children;
    // An abstract class (no constructor) is read as a null pointer too.
    const bool none = null || !cls->ptrCreateObject;
    const std::string what = null   ? "a null object"
                             : none ? std::string("an abstract ") + cls->className
                                    : std::string(cls->className);
    if (parent.kind == Kind::ActionCollection) {
      if (parent.children > parent.expected)
        refuse("an action collection holds more objects than the " +
               std::to_string(parent.expected) + " it claims (its bytes do not parse)");
      if (none || !cls->derivedFrom(CLASS_ID(mrpt::obs::CAction)))
        refuse("an action collection holds " + what + ", not an action");
    } else if (parent.kind == Kind::SensoryFrame &&
               (none || !cls->derivedFrom(CLASS_ID(mrpt::obs::CObservation)))) {
      refuse("a version-0 sensory frame holds " + what + ", not an observation");
    } else if (parent.kind == Kind::Movement2D && parent.children == 1 && parent.pdf_first &&
               (none || !cls->derivedFrom(CLASS_ID(mrpt::poses::CPosePDF)))) {
      refuse("an odometry action's pose change is " + what + ", not a pose PDF");
    }
    open_.push_back({kind});
  } else if (kind == Kind::ActionCollection || kind == Kind::Movement2D ||
             kind == Kind::SensoryFrame) {
    open_.push_back({kind});  // watched: what sits directly inside matters
  }
  if (!null) header_ = kind;
}

void RawlogGuard::onVersion(Kind kind, std::uint8_t version) {
  if (kind == Kind::Scan) checkScan(version);
  if (kind == Kind::Scan3D) checkScan3D(version);
  if (kind == Kind::Odometry) checkOdometry(version);
  if (kind == Kind::Movement2D) checkMovement2D(version);
  if (kind == Kind::Movement3D) checkMovement3D(version);
  if (kind == Kind::SensoryFrame || kind == Kind::ActionCollection) checkCount(kind, version);
  if (open_.empty()) return;
  Open& self = open_.back();  // the object whose header this version ends
  // A sensory frame of version 0 sets each observation's timestamp after reading it: a null
  // one (an object of another class) is dereferenced. Later versions do not: the reader
  // checks their observations; no need to follow the frame.
  if (kind == Kind::SensoryFrame && version != 0 && open_.size() == 1) {
    open_.pop_back();
    return;
  }
  // CActionCollection version 0: the number of actions (uint32) follows.
  if (kind == Kind::ActionCollection && version == 0 && peek(4)) self.expected = u32At(0);
  // CActionRobotMovement2D (MRPT 2.5's serializeFrom): versions 0 and 1 start with the pose
  // PDF; versions 2 to 7 with the estimation method (int32), and a method other than odometry
  // (0) is followed by the PDF, odometry by a CPose2D that MRPT checks itself.
  if (kind == Kind::Movement2D)
    self.pdf_first = version <= 1 || (version <= 7 && peek(4) && u32At(0) != 0);
}

// CActionRobotMovement2D versions 4 to 7 estimated by odometry (method 0): the raw increment
// (a nested CPose2D version 1: three doubles), the motion model (int32; not 0 = Thrun's
// particles), its Gaussian parameters (six floats), then the number of particles (int32) MRPT
// draws when it rebuilds the PDF on reading: a damaged count of 996459400 took 24 GB.
void RawlogGuard::checkMovement2D(std::uint8_t version) {
  // after the estimation method (int32, 0 = odometry)
  if (version < 4 || version > 7 || !peek(4) || u32At(0) != 0) return;
  const std::size_t at = nestedPose2DEnd(4);
  if (at == 0 || !peek(at + 4 + 6 * 4 + 4)) return;
  const std::uint32_t model = u32At(at), particles = u32At(at + 4 + 6 * 4);
  if (model != 0 && particles > kMaxParticles)
    refuse("an odometry action's motion model claims " + std::to_string(particles) +
           " particles (more than " + std::to_string(kMaxParticles) + ": a damaged count)");
}

// CActionRobotMovement3D version 1 (MRPT 2.5): the estimation method (int32), the pose
// change as a nested
// CPose3DPDFGaussian version 1 (a nested CPose3D, 21 doubles of covariance, end flag), then
// two vectors read as a count (uint32) and its elements: bytes, then floats (6 of each).
// MRPT resizes each to its count first.
void RawlogGuard::checkMovement3D(std::uint8_t version) {
  if (version != 1) return;
  std::size_t at = nestedHeaderEnd(4, "mrpt::poses::CPose3DPDFGaussian", 1);
  if (at == 0 || !peek(at + 1)) return;
  const std::size_t after_pose = nestedPose3DEnd(at);
  if (after_pose == 0) return;
  at = after_pose + 21 * sizeof(double);
  if (!peek(at + 1 + 4) || ahead_[at] != kEndFlag) return;
  at += 1;
  const std::uint32_t bytes = u32At(at);
  if (bytes <= kMaxVector && peek(at + 4 + bytes + 4)) {
    const std::uint32_t floats = u32At(at + 4 + bytes);
    if (floats > kMaxVector)
      refuse("a 3D odometry action claims " + std::to_string(floats) + " velocities (more than " +
             std::to_string(kMaxVector) + ": a damaged count)");
  }
  if (bytes > kMaxVector)
    refuse("a 3D odometry action claims " + std::to_string(bytes) + " velocity flags (more than " +
           std::to_string(kMaxVector) + ": a damaged count)");
}

// A nested object's header (header byte, a name MRPT resolves to `cls`, the version) at
// look-ahead offset `at`: the offset after it, or 0 if it is not that.
std::size_t RawlogGuard::nestedHeaderEnd(std::size_t at, const char* cls, std::uint8_t version) {
  if (!peek(at + 1) || !(ahead_[at] & kNewFormat)) return 0;
  const std::size_t name_len = ahead_[at] & 0x7f;
  if (!peek(at + 1 + name_len + 1)) return 0;
  bool null = false;
  const auto* found =
      resolve(std::string(ahead_.begin() + static_cast<std::ptrdiff_t>(at + 1),
                          ahead_.begin() + static_cast<std::ptrdiff_t>(at + 1 + name_len)),
              null);
  at += 1 + name_len;
  return is(found, cls) && ahead_[at] == version ? at + 1 : 0;
}

// A nested CPose3D of version 2 (x y z and a quaternion) or 3 (x y z and the rotation
// matrix, what MRPT 2.5 writes) at `at`: the offset after its end flag, or 0.
std::size_t RawlogGuard::nestedPose3DEnd(std::size_t at) {
  std::size_t end = nestedHeaderEnd(at, "mrpt::poses::CPose3D", 3);
  std::size_t doubles = 12;
  if (end == 0) {
    end = nestedHeaderEnd(at, "mrpt::poses::CPose3D", 2);
    doubles = 7;
  }
  if (end == 0) return 0;
  end += doubles * sizeof(double);
  if (!peek(end + 1) || ahead_[end] != kEndFlag) return 0;
  return end + 1;
}

// A nested CPose2D version 1 (header byte, a name MRPT resolves to mrpt::poses::CPose2D,
// version, three doubles, end flag) at look-ahead offset `at`: the offset after it, or 0.
std::size_t RawlogGuard::nestedPose2DEnd(std::size_t at) {
  std::size_t end = nestedHeaderEnd(at, "mrpt::poses::CPose2D", 1);
  if (end == 0) return 0;
  end += 3 * sizeof(double);
  if (!peek(end + 1) || ahead_[end] != kEndFlag) return 0;
  return end + 1;
}

void RawlogGuard::onEndFlag() {
  const Open done = open_.back();
  open_.pop_back();
  if (done.kind == Kind::ActionCollection && done.expected != UINT32_MAX &&
      done.children != done.expected)
    refuse("an action collection claims " + std::to_string(done.expected) +
           " objects but ends after " + std::to_string(done.children) +
           " (its bytes do not parse)");
}

void RawlogGuard::refuse(std::string why) {
  refusal_ = std::move(why);
  open_.clear();
  throw RawlogRefusal(refusal_);
}

std::uint32_t RawlogGuard::u32At(std::size_t i) const {  // MRPT writes little endian
  return static_cast<std::uint32_t>(ahead_[i]) | static_cast<std::uint32_t>(ahead_[i + 1]) << 8 |
         static_cast<std::uint32_t>(ahead_[i + 2]) << 16 |
         static_cast<std::uint32_t>(ahead_[i + 3]) << 24;
}

bool RawlogGuard::peek(std::size_t n) {
  std::uint8_t chunk[65536];  // a 3D scan's points are looked past: megabytes
  while (ahead_.size() < n) {
    const std::size_t want = std::min(sizeof chunk, n - ahead_.size());
    std::size_t got = 0;
    try {
      got = in_.Read(chunk, want);
    } catch (const std::exception&) {
      return false;  // the end of the file: MRPT reports the cut itself
    }
    // MRPT's gz stream returns gzread's -1 (as a size_t) past the end of a cut file.
    if (got == 0 || got > want) return false;
    ahead_.insert(ahead_.end(), chunk, chunk + got);
  }
  return true;
}

void RawlogGuard::checkCount(Kind kind, std::uint8_t version) {
  // CActionCollection version 0: the number of actions (uint32) right after the version.
  // CSensoryFrame versions 0 to 2: after an ID (uint32, versions 0 and 1) and a timestamp
  // (uint64, version 0). MRPT resizes a container to the count.
  const bool frame = kind == Kind::SensoryFrame;
  const std::size_t at = !frame ? 0 : version == 2 ? 0 : version == 1 ? 4 : 12;
  if ((frame ? version > 2 : version != 0) || !peek(at + 4)) return;
  const std::uint32_t n = u32At(at);
  if (n > kMaxObjects)
    refuse(std::string(frame ? "a sensory frame claims " : "an action collection claims ") +
           std::to_string(n) + " objects (more than " + std::to_string(kMaxObjects) +
           ": a damaged count)");
}

// The layout of CObservation2DRangeScan versions 6 to 8 up to the ray count (MRPT 2.5's
// serializeFrom): aperture (float), rightToLeft (bool, one byte), maxRange (float), the
// sensor pose as a nested object (class-name header, "mrpt::poses::CPose3D", version, its
// doubles, end flag), then the count (uint32, little endian). Older versions carry a
// covariance matrix before the count: not checked.
void RawlogGuard::checkScan(std::uint8_t version) {
  if (version < 6 || version > 8) return;
  const std::size_t at = nestedPose3DEnd(9);  // after aperture, rightToLeft, maxRange
  if (at == 0 || !peek(at + 4)) return;
  const std::uint32_t rays = u32At(at);
  if (rays > kMaxScanRays)
    refuse("a 2D scan claims " + std::to_string(rays) + " rays (more than " +
           std::to_string(kMaxScanRays) + ": a damaged count)");
  // Then the ranges (float each), the validity bytes, stdError (float), the timestamp
  // (uint64), beamAperture (float) and the sensor label (uint32 length, its bytes).
  checkLabel(at + 4 + 5 * std::size_t{rays} + 4 + 8 + 4, "a 2D scan's");
}

// CObservation3DRangeScan versions 9 and 10 (MRPT 2.5's serializeFrom): maxRange (float), the
// sensor pose as a nested CPose3D, hasPoints3D (bool); with points their count N (uint32) and
// N floats x, y, z and N uint16 pixel columns and rows; hasRangeImage (bool), rangeUnits
// (float); with an image its rows and columns (uint32 each), which MRPT allocates at once.
void RawlogGuard::checkScan3D(std::uint8_t version) {
  if (version < 9 || version > 10) return;
  std::size_t at = nestedPose3DEnd(4);
  if (at == 0 || !peek(at + 1)) return;
  const bool has_points = ahead_[at++] != 0;
  if (has_points) {
    if (!peek(at + 4)) return;
    const std::uint32_t n = u32At(at);
    if (n > kMaxPixels)
      refuse("a 3D range scan claims " + std::to_string(n) + " points (more than " +
             std::to_string(kMaxPixels) + ": a damaged count)");
    at += 4 + std::size_t{n} * (3 * sizeof(float) + 2 * sizeof(std::uint16_t));
  }
  if (!peek(at + 1 + 4 + 8) || ahead_[at] == 0) return;  // no range image
  const std::uint64_t rows = u32At(at + 5), cols = u32At(at + 9);
  if (rows * cols > kMaxPixels)
    refuse("a 3D range scan claims a range image of " + std::to_string(rows) + " x " +
           std::to_string(cols) + " pixels (more than " + std::to_string(kMaxPixels) +
           ": a damaged size)");
}

// CObservationOdometry version 2 (MRPT 2.5): the odometry as a nested CPose2D, then the
// sensor label.
void RawlogGuard::checkOdometry(std::uint8_t version) {
  const std::size_t at = version == 2 ? nestedPose2DEnd(0) : 0;
  if (at > 0) checkLabel(at, "an odometry reading's");
}

// MRPT reads a string as its length and then resizes the string to it: a damaged length of
// 4294967295 asks for 4 GB and fills it with zeros before finding the bytes missing.
void RawlogGuard::checkLabel(std::size_t at, const char* whose) {
  if (!peek(at + 4)) return;
  const std::uint32_t n = u32At(at);
  if (n > kMaxLabel)
    refuse(std::string(whose) + " sensor label claims " + std::to_string(n) + " bytes (more than " +
           std::to_string(kMaxLabel) + ": a damaged length)");
}

size_t RawlogGuard::Write(const void*, size_t) {
  throw std::logic_error("RawlogGuard: read-only stream");
}

uint64_t RawlogGuard::Seek(int64_t, mrpt::io::CStream::TSeekOrigin) {
  throw std::logic_error("RawlogGuard: no seeking");
}

}  // namespace asf::io
