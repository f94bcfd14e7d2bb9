// Turbulence-bank-set file: payload encoding, checks and I/O; see turbulence_set_file.h.
#include "bankfile/turbulence_set_file.h"

#include <cmath>
#include <cstring>
#include <set>
#include <stdexcept>

#include "bankfile/payload_reader.h"
#include "bankfile/sha256.h"

namespace f16mmae {
namespace {

// Big-endian appends of the payload's fields.
void put(std::vector<std::uint8_t>& out, std::uint64_t v, int bytes) {
  for (int i = bytes - 1; i >= 0; --i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}
void put_f64(std::vector<std::uint8_t>& out, double v) {
  std::uint64_t bits;
  std::memcpy(&bits, &v, sizeof bits);
  put(out, bits, 8);
}
void put_doubles(std::vector<std::uint8_t>& out, const std::vector<double>& v) {
  put(out, v.size(), 4);
  for (double x : v) put_f64(out, x);
}

std::vector<double> read_doubles(PayloadReader& r, const std::string& field, std::int64_t limit) {
  const std::size_t n = r.count(field + " size", limit, 8);
  std::vector<double> out(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = r.f64(field + "[" + std::to_string(i) + "]");
  return out;
}

}  // namespace

void TurbulenceSetFile::validate() const {
  const auto refuse = [](const std::string& what) { throw std::invalid_argument("turbulence bank set: " + what); };
  const int n = size();
  if (n < 2 || n > kMaxTurbulenceSetMembers)
    refuse("needs 2 to " + std::to_string(kMaxTurbulenceSetMembers) + " member banks, got " + std::to_string(n));
  if (levels.size() != members.size() || adapt_reference.size() != members.size() ||
      trim_time_constant_s.size() != members.size() || adapt_gain.size() != members.size())
    refuse("levels, adapt_reference, trim_time_constant_s and adapt_gain need one value per member (" +
           std::to_string(n) + "), got " + std::to_string(levels.size()) + ", " + std::to_string(adapt_reference.size()) +
           ", " + std::to_string(trim_time_constant_s.size()) + " and " + std::to_string(adapt_gain.size()));
  std::set<std::string> seen;
  for (int i = 0; i < n; ++i) {
    const std::string who = "member " + std::to_string(i) + " ('" + levels[i] + "')";
    if (levels[i].empty() || !seen.insert(levels[i]).second) refuse(who + ": its level must be a new, non-empty name");
    const ModelBank& b = members[i];
    const ModelBank& b0 = members[0];
    if (b.schedule) refuse(who + " is a scheduled bank (not supported)");
    if (b.nx() != b0.nx() || b.nu() != b0.nu() || b.nz() != b0.nz())
      refuse(who + " has (nx, nu, nz) = (" + std::to_string(b.nx()) + ", " + std::to_string(b.nu()) + ", " +
             std::to_string(b.nz()) + "), member 0 (" + std::to_string(b0.nx()) + ", " + std::to_string(b0.nu()) +
             ", " + std::to_string(b0.nz()) + ")");
    if (b.frame_rate_hz != b0.frame_rate_hz)
      refuse(who + " has frame rate " + format_value(b.frame_rate_hz) + " Hz, member 0 " +
             format_value(b0.frame_rate_hz));
    if (b.hypotheses.size() != b0.hypotheses.size())
      refuse(who + " has " + std::to_string(b.hypotheses.size()) + " hypotheses, member 0 " +
             std::to_string(b0.hypotheses.size()));
    for (std::size_t h = 0; h < b.hypotheses.size(); ++h)
      if (b.hypotheses[h].name != b0.hypotheses[h].name)
        refuse(who + "'s hypothesis " + std::to_string(h) + " is '" + b.hypotheses[h].name + "', member 0's '" +
               b0.hypotheses[h].name + "'");
    if (!(adapt_reference[i] >= 0.0 && adapt_reference[i] <= 100.0))
      refuse(who + ": adapt_reference must be in [0, 100], got " + format_value(adapt_reference[i]));
    if (!(trim_time_constant_s[i] >= 0.0 && trim_time_constant_s[i] <= 1e6))
      refuse(who + ": trim_time_constant_s must be in [0, 1e6] s (0: off), got " + format_value(trim_time_constant_s[i]));
    if (!(adapt_gain[i] > 0.0 && adapt_gain[i] <= 1000.0))
      refuse(who + ": adapt_gain must be in (0, 1000], got " + format_value(adapt_gain[i]));
  }
  check_turbulence_set_selector(selector, n);
  if (!(maneuver_tempering_g >= 0.0 && maneuver_tempering_g <= 100.0))
    refuse("maneuver_tempering_g must be in [0, 100] g (0: off), got " + format_value(maneuver_tempering_g));
}

bool is_turbulence_set_file(const std::uint8_t* data, std::size_t size) {
  return size >= sizeof kTurbulenceSetFileMagic &&
         std::memcmp(data, kTurbulenceSetFileMagic, sizeof kTurbulenceSetFileMagic) == 0;
}

std::vector<std::uint8_t> turbulence_set_file_bytes(const TurbulenceSetFile& set) {
  set.validate();
  std::vector<std::uint8_t> out;
  put(out, static_cast<std::uint64_t>(set.size()), 4);
  for (int i = 0; i < set.size(); ++i) {
    put(out, set.levels[i].size() + 1, 4);
    out.insert(out.end(), set.levels[i].begin(), set.levels[i].end());
    out.push_back(0);
    put_f64(out, set.adapt_reference[i]);
    put_f64(out, set.trim_time_constant_s[i]);
    const std::vector<std::uint8_t> bank = bank_file_bytes(set.members[i]);
    put(out, bank.size(), 8);
    out.insert(out.end(), bank.begin(), bank.end());
  }
  const TurbulenceBankSetOptions& s = set.selector;
  put_doubles(out, s.bounds);
  put_doubles(out, s.typical);
  for (double v : {s.hold_s, s.warm_up_s, s.warm_down_s, s.settle_s, s.freeze_probability}) put_f64(out, v);
  put(out, static_cast<std::uint32_t>(s.start), 4);
  put(out, static_cast<std::uint32_t>(s.start_standby), 4);
  put_f64(out, set.maneuver_tempering_g);
  put_doubles(out, set.adapt_gain);
  put(out, s.calmer_own_rho ? 1u : 0u, 4);
  put_f64(out, s.floor_rho);
  put_doubles(out, s.floor_p_min);
  return hashed_file_image(kTurbulenceSetFileMagic, TurbulenceSetFile::kFormatVersion, out);
}

TurbulenceSetFile parse_turbulence_set_file(const std::uint8_t* data, std::size_t size, const std::string& source) {
  const std::string who = "turbulence bank set file " + source + ": ";
  const std::uint32_t version = hashed_file_version(data, size, kTurbulenceSetFileMagic, who, "turbulence bank set");
  if (version < 1 || version > TurbulenceSetFile::kFormatVersion)
    throw BankFileFormatError(who + "unsupported format version " + std::to_string(version) + " (this build reads 1 to " +
                              std::to_string(TurbulenceSetFile::kFormatVersion) + ")");
  const std::uint8_t* payload = hashed_file_payload(data, size, who);
  const std::size_t payload_size = size - kBankFileHeaderSize;
  TurbulenceSetFile set;
  try {
    PayloadReader r(payload, payload_size);
    const std::size_t n = r.count("members size", kMaxTurbulenceSetMembers, 4 + 1 + 8 + 8 + 8 + kBankFileHeaderSize);
    for (std::size_t i = 0; i < n; ++i) {
      const std::string member = "members[" + std::to_string(i) + "]";
      set.levels.push_back(r.text(member + ".level", kMaxBankNameBytes));
      set.adapt_reference.push_back(r.f64(member + ".adapt_reference"));
      set.trim_time_constant_s.push_back(r.f64(member + ".trim_time_constant_s"));
      const std::int64_t bytes = r.i64(member + ".bank size");
      if (bytes < 0 || static_cast<std::uint64_t>(bytes) > kMaxBankFileBytes)
        throw BankFileFormatError("payload field " + member + ".bank size = " + std::to_string(bytes) +
                                  " is outside [0, " + std::to_string(kMaxBankFileBytes) + "]");
      const std::uint8_t* image = r.bytes(member + ".bank", static_cast<std::uint64_t>(bytes));
      set.members.push_back(parse_bank_file(image, static_cast<std::size_t>(bytes), member));
    }
    const std::int64_t pairs = static_cast<std::int64_t>(n) * (static_cast<std::int64_t>(n) - 1);
    set.selector.bounds = read_doubles(r, "bounds", pairs > 0 ? pairs : 0);
    set.selector.typical = read_doubles(r, "typical", static_cast<std::int64_t>(n));
    set.selector.hold_s = r.f64("hold_s");
    set.selector.warm_up_s = r.f64("warm_up_s");
    set.selector.warm_down_s = r.f64("warm_down_s");
    set.selector.settle_s = r.f64("settle_s");
    set.selector.freeze_probability = r.f64("freeze_probability");
    set.selector.start = r.i32("start");
    set.selector.start_standby = r.i32("start_standby");
    if (version >= 2) set.maneuver_tempering_g = r.f64("maneuver_tempering_g");
    if (version >= 3)
      set.adapt_gain = read_doubles(r, "adapt_gain", static_cast<std::int64_t>(n));
    else
      set.adapt_gain.assign(n, TurbulenceAdaptationOptions{}.gain);
    if (version >= 4) {
      const std::int32_t rule = r.i32("calmer_own_rho");
      if (rule != 0 && rule != 1)
        throw BankFileFormatError("payload field calmer_own_rho = " + std::to_string(rule) + " is not 0 or 1");
      set.selector.calmer_own_rho = rule == 1;
    }
    if (version >= 5) {
      set.selector.floor_rho = r.f64("floor_rho");
      set.selector.floor_p_min = read_doubles(r, "floor_p_min", static_cast<std::int64_t>(n));   // 0 or n: validate()
    }
    if (r.remaining() != 0)
      throw BankFileFormatError("payload has " + std::to_string(r.remaining()) + " bytes after " +
                                (version >= 5   ? "floor_p_min"
                                 : version >= 4 ? "calmer_own_rho"
                                 : version >= 3 ? "adapt_gain"
                                 : version >= 2 ? "maneuver_tempering_g"
                                                : "start_standby"));
    set.validate();
  } catch (const BankFileFormatError& e) {
    throw BankFileFormatError(who + e.what());
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(who + e.what());
  }
  set.content_hash = to_hex(sha256(payload, payload_size));
  return set;
}

TurbulenceSetFile load_turbulence_set(const std::string& path) {
  const std::vector<std::uint8_t> bytes = read_regular_file(path, kMaxTurbulenceSetFileBytes, "turbulence bank set file");
  return parse_turbulence_set_file(bytes.data(), bytes.size(), "'" + path + "'");
}

std::string save_turbulence_set(const TurbulenceSetFile& set, const std::string& path) {
  const std::vector<std::uint8_t> image = turbulence_set_file_bytes(set);
  write_file_atomically(image, path, "turbulence bank set file");
  return to_hex(sha256(image.data() + kBankFileHeaderSize, image.size() - kBankFileHeaderSize));
}

}  // namespace f16mmae
