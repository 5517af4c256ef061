// A rosbag2 bag with MCAP storage (bag_writer.h), written by the MCAP specification
// (https://mcap.dev/spec): records of an opcode, a little-endian u64 length and the content.
#include <asf/ros2/bag_writer.h>
#include <asf/ros2/cdr.h>

#include <cstring>
#include <filesystem>
#include <sstream>
#include <stdexcept>

namespace asf::ros2 {

namespace {

constexpr char kMagic[8] = {'\x89', 'M', 'C', 'A', 'P', '0', '\r', '\n'};
enum Op : std::uint8_t {
  kHeader = 0x01, kFooter = 0x02, kSchema = 0x03, kChannel = 0x04, kMessage = 0x05, kDataEnd = 0x0F
};

template <class T>
void put(std::string& b, T v) {
  b.append(reinterpret_cast<const char*>(&v), sizeof(T));  // this machine is little endian
}
void putStr(std::string& b, const std::string& s) {
  put<std::uint32_t>(b, static_cast<std::uint32_t>(s.size()));
  b += s;
}

}  // namespace

BagWriter::BagWriter(const std::string& folder) : folder_(folder) {
  namespace fs = std::filesystem;
  if (fs::exists(fs::path(folder) / "metadata.yaml"))
    throw std::runtime_error(folder + ": holds a bag already (metadata.yaml)");
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec) throw std::runtime_error(folder + ": cannot create the bag folder: " + ec.message());
  out_.open((fs::path(folder) / "data.mcap").string(), std::ios::binary | std::ios::trunc);
  if (!out_) throw std::runtime_error(folder + "/data.mcap: cannot create");
  out_.write(kMagic, 8);
  std::string h;
  putStr(h, "ros2");
  putStr(h, "asf");
  record(kHeader, h);
}

BagWriter::~BagWriter() {
  try {
    close();
  } catch (...) {
    // the destructor must not throw; close() reports its errors when called
  }
}

void BagWriter::record(std::uint8_t op, const std::string& body) {
  out_.put(static_cast<char>(op));
  const std::uint64_t n = body.size();
  out_.write(reinterpret_cast<const char*>(&n), 8);
  out_.write(body.data(), static_cast<std::streamsize>(body.size()));
}

int BagWriter::topic(const std::string& name, const std::string& type, const std::string& qos_yaml) {
  const std::string definition = messageDefinition(type);  // throws for a type it cannot write
  std::lock_guard<std::mutex> lock(mu_);
  const auto id = static_cast<std::uint16_t>(topics_.size() + 1);
  std::string s;
  put<std::uint16_t>(s, id);  // one schema per channel, with the same id
  putStr(s, type);
  putStr(s, "ros2msg");
  putStr(s, definition);
  record(kSchema, s);
  std::string c;
  put<std::uint16_t>(c, id);
  put<std::uint16_t>(c, id);
  putStr(c, name);
  putStr(c, "cdr");
  std::string meta;  // map<string, string>: its byte length, then key/value pairs
  putStr(meta, "offered_qos_profiles");
  putStr(meta, qos_yaml);
  put<std::uint32_t>(c, static_cast<std::uint32_t>(meta.size()));
  c += meta;
  record(kChannel, c);
  topics_.push_back({name, type, qos_yaml, 0});
  return id;
}

void BagWriter::write(int channel, std::int64_t time_ns, const std::vector<std::uint8_t>& cdr) {
  std::lock_guard<std::mutex> lock(mu_);
  if (closed_ || channel < 1 || channel > static_cast<int>(topics_.size())) return;
  std::string m;
  put<std::uint16_t>(m, static_cast<std::uint16_t>(channel));
  put<std::uint32_t>(m, static_cast<std::uint32_t>(topics_[channel - 1].count));
  put<std::uint64_t>(m, static_cast<std::uint64_t>(time_ns));  // log time
  put<std::uint64_t>(m, static_cast<std::uint64_t>(time_ns));  // publish time
  m.append(reinterpret_cast<const char*>(cdr.data()), cdr.size());
  record(kMessage, m);
  ++topics_[channel - 1].count;
  if (messages_ == 0 || time_ns < first_ns_) first_ns_ = time_ns;
  if (messages_ == 0 || time_ns > last_ns_) last_ns_ = time_ns;
  ++messages_;
}

std::uint64_t BagWriter::messages() const {
  std::lock_guard<std::mutex> lock(mu_);
  return messages_;
}

void BagWriter::close() {
  std::lock_guard<std::mutex> lock(mu_);
  if (closed_) return;
  closed_ = true;
  std::string d;
  put<std::uint32_t>(d, 0);  // no data section CRC
  record(kDataEnd, d);
  std::string f;
  put<std::uint64_t>(f, 0);  // no summary section
  put<std::uint64_t>(f, 0);
  put<std::uint32_t>(f, 0);
  record(kFooter, f);
  out_.write(kMagic, 8);
  out_.close();
  if (!out_) throw std::runtime_error(folder_ + "/data.mcap: write failed (disk full?)");
  std::ostringstream y;
  y << "rosbag2_bagfile_information:\n  version: 5\n  storage_identifier: mcap\n"
    << "  duration:\n    nanoseconds: " << (last_ns_ - first_ns_) << "\n"
    << "  starting_time:\n    nanoseconds_since_epoch: " << first_ns_ << "\n"
    << "  message_count: " << messages_ << "\n  topics_with_message_count:\n";
  for (const Topic& t : topics_)
    y << "    - topic_metadata:\n        name: " << t.name << "\n        type: " << t.type
      << "\n        serialization_format: cdr\n        offered_qos_profiles: \"\"\n"
      << "      message_count: " << t.count << "\n";
  y << "  compression_format: \"\"\n  compression_mode: \"\"\n"
    << "  relative_file_paths:\n    - data.mcap\n  files:\n    - path: data.mcap\n"
    << "      starting_time:\n        nanoseconds_since_epoch: " << first_ns_ << "\n"
    << "      duration:\n        nanoseconds: " << (last_ns_ - first_ns_) << "\n"
    << "      message_count: " << messages_ << "\n";
  std::ofstream meta(folder_ + "/metadata.yaml");
  meta << y.str();
  if (!meta) throw std::runtime_error(folder_ + "/metadata.yaml: cannot write");
}

}  // namespace asf::ros2
