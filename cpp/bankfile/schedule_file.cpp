// Scheduled-bank file: payload encoding, checks and I/O; see schedule_file.h for the layout.
#include "bankfile/schedule_file.h"

#include <cstring>
#include <memory>

#include "bankfile/payload_reader.h"
#include "bankfile/sha256.h"

namespace f16mmae {
namespace {

class Writer {
 public:
  void i32(std::int64_t v) { be(static_cast<std::uint64_t>(v), 4); }
  void i64(std::int64_t v) { be(static_cast<std::uint64_t>(v), 8); }
  void f64(double v) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    be(bits, 8);
  }
  void text(const std::string& s) {
    i32(static_cast<std::int64_t>(s.size()) + 1);
    out.insert(out.end(), s.begin(), s.end());
    out.push_back(0);
  }
  void axis(const std::vector<double>& a) {
    i32(static_cast<std::int64_t>(a.size()));
    for (double v : a) f64(v);
  }
  std::vector<std::uint8_t> out;

 private:
  void be(std::uint64_t v, int bytes) {
    for (int i = bytes - 1; i >= 0; --i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  }
};

std::vector<double> read_axis(PayloadReader& r, const std::string& field) {
  const std::size_t n = r.count(field + " size", kMaxScheduleAxis, 8);
  std::vector<double> out(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = r.f64(field + "[" + std::to_string(i) + "]");
  return out;
}

}  // namespace

std::uint32_t schedule_file_version(const BankSchedule& schedule) {
  return schedule.has_reference_scale() ? 5 : schedule.has_calm_reference() ? 4 : schedule.start_up_s != 0.0 ? 3 : 2;
}

bool is_schedule_file(const std::uint8_t* data, std::size_t size) {
  return size >= sizeof kScheduleFileMagic && std::memcmp(data, kScheduleFileMagic, sizeof kScheduleFileMagic) == 0;
}

std::vector<std::uint8_t> schedule_file_bytes(const BankSchedule& schedule) {
  schedule.validate();
  Writer w;
  w.axis(schedule.mach);
  w.axis(schedule.alt_ft);
  w.i32(schedule.primary);
  w.text(schedule.metadata);
  w.i32(schedule.switch_state);
  w.axis(schedule.switch_thresholds);
  const std::uint32_t version = schedule_file_version(schedule);
  if (version >= 3) w.f64(schedule.start_up_s);
  w.i32(static_cast<std::int64_t>(schedule.nodes.size()));
  for (const ScheduleNode& node : schedule.nodes) {
    w.i32(node.i_mach);
    w.i32(node.i_alt);
    w.i32(node.layer);
    w.i32(node.x_trim.size());
    for (Eigen::Index i = 0; i < node.x_trim.size(); ++i) w.f64(node.x_trim(i));
    w.f64(node.adapt_reference);
    if (version >= 4) w.f64(node.calm_reference);
    if (version >= 5) w.f64(node.reference_scale);
    const std::vector<std::uint8_t> bank = bank_file_bytes(node.bank);
    w.i64(static_cast<std::int64_t>(bank.size()));
    w.out.insert(w.out.end(), bank.begin(), bank.end());
  }
  return hashed_file_image(kScheduleFileMagic, version, w.out);
}

ModelBank decode_schedule_payload(const std::uint8_t* payload, std::size_t size, std::uint32_t version) {
  if (version < 1 || version > BankSchedule::kFormatVersion)
    throw BankFileFormatError("unsupported format version " + std::to_string(version) + " (this build reads 1 to " +
                              std::to_string(BankSchedule::kFormatVersion) + ")");
  auto schedule = std::make_shared<BankSchedule>();
  PayloadReader r(payload, size);
  schedule->mach = read_axis(r, "mach");
  schedule->alt_ft = read_axis(r, "alt_ft");
  schedule->primary = r.i32("primary");
  schedule->metadata = r.text("metadata", kMaxBankTextBytes);
  if (version >= 2) {
    schedule->switch_state = r.i32("switch_state");
    schedule->switch_thresholds = read_axis(r, "switch_thresholds");
  }
  if (version >= 3) schedule->start_up_s = r.f64("start_up_s");   // versions 1 and 2: 0, none
  const std::size_t per_node = (version >= 5 ? 40 : version >= 4 ? 32 : version >= 2 ? 24 : 12) + 8 + kBankFileHeaderSize;
  const std::size_t n = r.count("nodes size", kMaxScheduleNodes, per_node);
  schedule->nodes.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const std::string node = "nodes[" + std::to_string(k) + "]";
    ScheduleNode& sn = schedule->nodes[k];
    sn.i_mach = r.i32(node + ".i_mach");
    sn.i_alt = r.i32(node + ".i_alt");
    if (version >= 2) sn.layer = r.i32(node + ".layer");
    const std::size_t nx = r.count(node + ".x_trim size", kMaxBankDimension, 8);
    sn.x_trim.resize(static_cast<Eigen::Index>(nx));
    for (std::size_t i = 0; i < nx; ++i) sn.x_trim(static_cast<Eigen::Index>(i)) = r.f64(node + ".x_trim");
    if (version >= 2) sn.adapt_reference = r.f64(node + ".adapt_reference");
    if (version >= 4) sn.calm_reference = r.f64(node + ".calm_reference");
    if (version >= 5) sn.reference_scale = r.f64(node + ".reference_scale");
    const std::int64_t bytes = r.i64(node + ".bank size");
    if (bytes < 0 || static_cast<std::uint64_t>(bytes) > kMaxBankFileBytes)
      throw BankFileFormatError("payload field " + node + ".bank size = " + std::to_string(bytes) +
                                " is outside [0, " + std::to_string(kMaxBankFileBytes) + "]");
    const std::uint8_t* image = r.bytes(node + ".bank", static_cast<std::uint64_t>(bytes));
    sn.bank = parse_bank_file(image, static_cast<std::size_t>(bytes), node);
  }
  if (r.remaining() != 0)
    throw BankFileFormatError("payload has " + std::to_string(r.remaining()) + " bytes after the last node");
  schedule->validate();
  ModelBank bank = schedule->nodes[static_cast<std::size_t>(schedule->primary)].bank;
  bank.estimator.start_up_s = schedule->start_up_s;   // the schedule's recommendation
  bank.content_hash = to_hex(sha256(payload, size));
  bank.schedule = std::move(schedule);
  return bank;
}

ModelBank parse_schedule_file(const std::uint8_t* data, std::size_t size, const std::string& source) {
  const std::string who = "scheduled-bank file " + source + ": ";
  const std::uint32_t version = hashed_file_version(data, size, kScheduleFileMagic, who, "scheduled-bank");
  if (version < 1 || version > BankSchedule::kFormatVersion)
    throw BankFileFormatError(who + "unsupported format version " + std::to_string(version) +
                              " (this build reads versions 1 to " + std::to_string(BankSchedule::kFormatVersion) + ")");
  const std::uint8_t* payload = hashed_file_payload(data, size, who);
  try {
    return decode_schedule_payload(payload, size - kBankFileHeaderSize, version);
  } catch (const BankFileFormatError& e) {
    throw BankFileFormatError(who + e.what());
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(who + e.what());
  }
}

std::string save_schedule(const BankSchedule& schedule, const std::string& path) {
  const std::vector<std::uint8_t> image = schedule_file_bytes(schedule);
  write_file_atomically(image, path, "scheduled-bank file");
  return to_hex(sha256(image.data() + kBankFileHeaderSize, image.size() - kBankFileHeaderSize));
}

}  // namespace f16mmae
