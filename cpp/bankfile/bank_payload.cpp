// ModelBank <-> f16mmae::lcmt_model_bank (the LCM payload of a bank file); see bank_file.h.
// Matrices travel row-major with their dimensions: data[i][j] = M(i, j).
#include <cstring>
#include <limits>
#include <sstream>

#include "bankfile/bank_file.h"
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

Eigen::MatrixXd from_lcm(const lcmt_bank_matrix& m) {
  if (m.rows < 0 || m.cols < 0)
    throw BankFileFormatError("payload declares a " + std::to_string(m.rows) + "x" + std::to_string(m.cols) + " matrix");
  Eigen::MatrixXd out(m.rows, m.cols);
  for (int i = 0; i < m.rows; ++i)
    for (int j = 0; j < m.cols; ++j) out(i, j) = m.data[i][j];
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
    msg.hypotheses.push_back(std::move(out));
  }
  const int size = msg.getEncodedSize();
  std::vector<std::uint8_t> payload(static_cast<std::size_t>(size));
  if (msg.encode(payload.data(), 0, size) != size)
    throw std::invalid_argument("model bank: LCM encoding failed (inconsistent sizes)");
  return payload;
}

ModelBank decode_bank_payload(const std::uint8_t* data, std::size_t size) {
  auto fail = [](const std::string& what) { throw BankFileFormatError(what); };
  if (size < 8) fail("payload of " + std::to_string(size) + " bytes is too short for an LCM message");
  if (size > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    fail("payload of " + std::to_string(size) + " bytes exceeds the LCM limit of 2 GiB");
  std::int64_t fingerprint = 0;
  __int64_t_decode_array(data, 0, 8, &fingerprint, 1);
  if (fingerprint != lcmt_model_bank::getHash()) {
    std::ostringstream s;
    s << "payload type fingerprint 0x" << std::hex << static_cast<std::uint64_t>(fingerprint)
      << " is not that of f16mmae.lcmt_model_bank (0x" << static_cast<std::uint64_t>(lcmt_model_bank::getHash())
      << "): written by an incompatible version, or not a model bank";
    fail(s.str());
  }
  lcmt_model_bank msg;
  int used = -1;
  try {
    used = msg.decode(data, 0, static_cast<int>(size));
  } catch (const std::exception& e) {  // a huge declared size that cannot be allocated
    fail(std::string("payload does not decode as f16mmae.lcmt_model_bank (") + e.what() + ")");
  }
  if (used < 0) fail("payload does not decode as f16mmae.lcmt_model_bank (declared sizes exceed the data)");
  if (static_cast<std::size_t>(used) != size)
    fail("payload has " + std::to_string(size - used) + " bytes after the f16mmae.lcmt_model_bank message");

  ModelBank bank;
  bank.state_names = msg.state_names;
  bank.input_names = msg.input_names;
  bank.measurement_names = msg.measurement_names;
  bank.u_trim = Eigen::Map<const Eigen::VectorXd>(msg.u_trim.data(), msg.u_trim_size);
  bank.z_trim = Eigen::Map<const Eigen::VectorXd>(msg.z_trim.data(), msg.z_trim_size);
  bank.h_output = from_lcm(msg.h_output);
  bank.frame_rate_hz = msg.frame_rate_hz;
  bank.mach = msg.mach;
  bank.alt_ft = msg.alt_ft;
  bank.tuning = msg.tuning;
  bank.metadata = msg.metadata;
  bank.hypotheses.reserve(msg.hypotheses.size());
  for (const lcmt_bank_hypothesis& h : msg.hypotheses)
    bank.hypotheses.push_back({h.name, from_lcm(h.phi), from_lcm(h.bd), from_lcm(h.h), from_lcm(h.k), from_lcm(h.a)});
  bank.content_hash = to_hex(sha256(data, size));
  return bank;
}

std::string bank_content_hash(const ModelBank& bank) {
  const std::vector<std::uint8_t> payload = encode_bank_payload(bank);
  return to_hex(sha256(payload.data(), payload.size()));
}

}  // namespace f16mmae
