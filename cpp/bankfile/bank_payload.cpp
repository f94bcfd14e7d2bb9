// ModelBank <-> f16mmae::lcmt_model_bank (the LCM payload of a bank file); see bank_file.h.
// Matrices travel row-major with their dimensions: data[i][j] = M(i, j).
// Encoding uses the lcm-gen type; decoding uses PayloadReader (payload_reader.h), which
// checks every declared size in 64 bits before allocating, and names the field it refuses.
#include <cstring>
#include <limits>
#include <sstream>

#include "bankfile/bank_file.h"
#include "bankfile/payload_reader.h"
#include "bankfile/sha256.h"
#include "f16mmae/lcmt_model_bank.hpp"

namespace f16mmae {
namespace {

std::int32_t checked_size(Eigen::Index n, const char* what) {
  if (n > std::numeric_limits<std::int32_t>::max())
    throw std::invalid_argument(std::string("model bank: ") + what + " is too large for the bank file");
  return static_cast<std::int32_t>(n);
}

const std::string& checked_string(const std::string& s, const char* what) {
  if (s.find('\0') != std::string::npos)
    throw std::invalid_argument(std::string("model bank: ") + what + " holds a NUL character");
  return s;
}

lcmt_bank_matrix to_lcm(const Eigen::MatrixXd& m, const char* what) {
  lcmt_bank_matrix out;
  out.rows = checked_size(m.rows(), what);
  out.cols = checked_size(m.cols(), what);
  out.data.assign(out.rows, std::vector<double>(out.cols));
  for (Eigen::Index i = 0; i < m.rows(); ++i)
    for (Eigen::Index j = 0; j < m.cols(); ++j) out.data[i][j] = m(i, j);
  return out;
}


std::vector<std::string> checked_names(const std::vector<std::string>& names, const char* what) {
  for (const auto& n : names) checked_string(n, what);
  return names;
}

}  // namespace

std::vector<std::uint8_t> encode_bank_payload(const ModelBank& bank) {
  lcmt_model_bank msg;
  msg.num_states = checked_size(bank.state_names.size(), "state_names");
  msg.state_names = checked_names(bank.state_names, "a state name");
  msg.num_inputs = checked_size(bank.input_names.size(), "input_names");
  msg.input_names = checked_names(bank.input_names, "an input name");
  msg.num_measurements = checked_size(bank.measurement_names.size(), "measurement_names");
  msg.measurement_names = checked_names(bank.measurement_names, "a measurement name");
  msg.u_trim_size = checked_size(bank.u_trim.size(), "u_trim");
  msg.u_trim.assign(bank.u_trim.data(), bank.u_trim.data() + bank.u_trim.size());
  msg.z_trim_size = checked_size(bank.z_trim.size(), "z_trim");
  msg.z_trim.assign(bank.z_trim.data(), bank.z_trim.data() + bank.z_trim.size());
  msg.h_output = to_lcm(bank.h_output, "h_output");
  msg.frame_rate_hz = bank.frame_rate_hz;
  msg.mach = bank.mach;
  msg.alt_ft = bank.alt_ft;
  msg.tuning = checked_string(bank.tuning, "tuning");
  msg.p_min = bank.estimator.p_min;
  msg.threshold = bank.estimator.threshold;
  msg.dwell_s = bank.estimator.dwell_s;
  msg.metadata = checked_string(bank.metadata, "metadata");
  msg.num_hypotheses = checked_size(bank.hypotheses.size(), "hypotheses");
  msg.hypotheses.reserve(bank.hypotheses.size());
  for (const HypothesisModel& h : bank.hypotheses) {
    lcmt_bank_hypothesis out;
    out.name = checked_string(h.name, "a hypothesis name");
    out.phi = to_lcm(h.phi, "phi");
    out.bd = to_lcm(h.bd, "bd");
    out.h = to_lcm(h.h, "h");
    out.k = to_lcm(h.k, "k");
    out.a = to_lcm(h.a, "a");
    // the two vectors share one size in the file: a bank with widths and no weights stores zeros
    out.width_size = checked_size(h.uninformative_width.size(), "uninformative_width");
    if (h.uninformative_level_q.size() != 0 && h.uninformative_level_q.size() != h.uninformative_width.size())
      throw std::invalid_argument("model bank: hypothesis '" + h.name +
                                  "': uninformative_level_q needs the size of uninformative_width");
    out.uninformative_width.assign(h.uninformative_width.data(),
                                   h.uninformative_width.data() + h.uninformative_width.size());
    out.uninformative_level_q.assign(static_cast<std::size_t>(out.width_size), 0.0);
    for (Eigen::Index j = 0; j < h.uninformative_level_q.size(); ++j)
      out.uninformative_level_q[static_cast<std::size_t>(j)] = h.uninformative_level_q(j);
    out.dwell_nats = h.dwell_nats;
    msg.hypotheses.push_back(std::move(out));
  }
  const int size = msg.getEncodedSize();
  std::vector<std::uint8_t> payload(static_cast<std::size_t>(size));
  if (msg.encode(payload.data(), 0, size) != size)
    throw std::invalid_argument("model bank: LCM encoding failed (inconsistent sizes)");
  return payload;
}

ModelBank decode_bank_payload(const std::uint8_t* data, std::size_t size) {
  PayloadReader in(data, size);
  const std::int64_t fingerprint = in.i64("fingerprint");
  if (fingerprint != lcmt_model_bank::getHash()) {
    std::ostringstream s;
    s << "payload type fingerprint 0x" << std::hex << static_cast<std::uint64_t>(fingerprint)
      << " is not that of f16mmae.lcmt_model_bank (0x" << static_cast<std::uint64_t>(lcmt_model_bank::getHash())
      << "): written by an incompatible version, or not a model bank";
    throw BankFileFormatError(s.str());
  }
  ModelBank bank;
  bank.state_names = in.names("state_names", "num_states");
  bank.input_names = in.names("input_names", "num_inputs");
  bank.measurement_names = in.names("measurement_names", "num_measurements");
  bank.u_trim = in.vector("u_trim", "u_trim_size");
  bank.z_trim = in.vector("z_trim", "z_trim_size");
  bank.h_output = in.matrix("h_output");
  bank.frame_rate_hz = in.f64("frame_rate_hz");
  bank.mach = in.f64("mach");
  bank.alt_ft = in.f64("alt_ft");
  bank.tuning = in.text("tuning", kMaxBankTextBytes);
  bank.estimator.p_min = in.f64("p_min");
  bank.estimator.threshold = in.f64("threshold");
  bank.estimator.dwell_s = in.f64("dwell_s");
  bank.metadata = in.text("metadata", kMaxBankTextBytes);
  // each hypothesis takes at least a name (5 bytes), five empty matrices (8 bytes each), an
  // empty width vector (4 bytes) and its dwell_nats (8 bytes)
  const std::size_t n = in.count("num_hypotheses", kMaxBankHypotheses, 57);
  bank.hypotheses.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::string who = "hypotheses[" + std::to_string(i) + "]";
    HypothesisModel& h = bank.hypotheses[i];
    h.name = in.text(who + ".name", kMaxBankNameBytes);
    h.phi = in.matrix(who + ".phi");
    h.bd = in.matrix(who + ".bd");
    h.h = in.matrix(who + ".h");
    h.k = in.matrix(who + ".k");
    h.a = in.matrix(who + ".a");
    h.uninformative_width = in.vector(who + ".uninformative_width", who + ".width_size");
    h.uninformative_level_q = in.doubles(who + ".uninformative_level_q", h.uninformative_width.size());
    h.dwell_nats = in.f64(who + ".dwell_nats");
  }
  in.finish();
  bank.content_hash = to_hex(sha256(data, size));
  return bank;
}

std::string bank_content_hash(const ModelBank& bank) {
  const std::vector<std::uint8_t> payload = encode_bank_payload(bank);
  return to_hex(sha256(payload.data(), payload.size()));
}

}  // namespace f16mmae
