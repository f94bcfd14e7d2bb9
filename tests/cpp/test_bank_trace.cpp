// Golden trace of the banks: FilterBank (fixed size on the packed kernel and on the Eigen
// path, dynamic size) and HierarchicalBank (both paths, with level switches and back-outs)
// flown over a few hundred frames that take every branch of the frame (huge residuals,
// rejected frames, q overflowing to +inf, presume, set_probabilities, set_h_output, reset).
// After every frame the bank's outputs (probabilities, log-probabilities, log-likelihoods,
// quadratic forms, z_hat, blended state, residuals, posterior and prior states, counters,
// and for the hierarchical bank its declarations and on-line hypotheses) are hashed bit
// by bit (FNV-1a over the bytes of each double, one running hash per output group); every
// 20th frame the running hashes are one line of the trace. The trace must equal
// tests/cpp/data/bank_trace.txt exactly: the stored trace was recorded from the code before
// the bank's state was stored once, so the numbers of every path are bit-identical to it.
// On a mismatch the test writes the trace it computed to bank_trace.actual.txt in the
// directory named by F16MMAE_TEST_OUTPUT_DIR (ctest sets it to build/cpp/test_output), else
// in the system's temporary directory, and names the file, the first line and the output
// group that differ.
// The fixture holds the results of the x86-64 build (AVX2/FMA kernel and Eigen's SSE2 path);
// the test fails, by name, on a CPU without AVX2 and FMA rather than comparing other numbers.
#include "f16mmae/filter_bank.h"
#include "f16mmae/hierarchical_bank.h"

#include "synthetic_models.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

using namespace f16mmae;

namespace {

const std::vector<std::string>& kAct = test::kF16Actuators;
const std::vector<std::string>& kSen = test::kF16Sensors;
constexpr int kEvery = 20;  // frames per line of the trace

// One running FNV-1a hash per output group.
class Hashes {
 public:
  static constexpr int kGroups = 6;
  static constexpr const char* kNames[kGroups] = {"probabilities", "blend", "residuals",
                                                  "posteriors", "priors", "counters"};
  template <class M>
  void add(int group, const M& m) {
    for (Eigen::Index j = 0; j < m.cols(); ++j)
      for (Eigen::Index i = 0; i < m.rows(); ++i) add(group, static_cast<double>(m(i, j)));
  }
  void add(int group, double v) {
    unsigned char b[sizeof(double)];
    std::memcpy(b, &v, sizeof(double));
    for (unsigned char c : b) h_[group] = (h_[group] ^ c) * 1099511628211ull;
  }
  std::string line(const std::string& label, int frame) const {
    std::ostringstream s;
    s << label << ' ' << frame;
    char hex[20];
    for (std::uint64_t h : h_) {
      std::snprintf(hex, sizeof(hex), " %016llx", static_cast<unsigned long long>(h));
      s << hex;
    }
    return s.str();
  }

 private:
  std::uint64_t h_[kGroups] = {14695981039346656037ull, 14695981039346656037ull, 14695981039346656037ull,
                               14695981039346656037ull, 14695981039346656037ull, 14695981039346656037ull};
};

template <class Bank>
void hash_bank(Hashes& h, const Bank& b, bool ok) {
  h.add(0, b.probabilities());
  h.add(0, b.log_probabilities());
  h.add(0, b.log_likelihoods());
  h.add(0, b.quadratic_forms());
  h.add(1, b.z_hat());
  h.add(1, b.blended_state());
  h.add(2, b.residuals());
  h.add(3, b.state_estimates());
  h.add(4, b.prior_states());
  h.add(5, ok ? 1.0 : 0.0);
  h.add(5, static_cast<double>(b.rejected_frames()));
  h.add(5, static_cast<double>(b.accepted_updates()));
}

// A FilterBank flown through every branch of its frame; one line per kEvery frames.
template <class Bank, class Z, class U>
std::vector<std::string> bank_trace(const std::string& label, Bank& bank) {
  std::mt19937 g(7);
  std::normal_distribution<double> n01(0.0, 1.0);
  Hashes h;
  std::vector<std::string> out;
  for (int i = 0; i < 400; ++i) {
    Z z(7);
    for (int j = 0; j < 7; ++j) z(j) = 0.3 * n01(g);
    Eigen::VectorXd u_dyn = test::dither(5, i, 64.0);
    U u = u_dyn;
    if (i == 60) z(2) = 1e150;                                          // huge residuals
    if (i == 90) z(4) = std::numeric_limits<double>::quiet_NaN();       // rejected update
    if (i == 91) u(1) = std::numeric_limits<double>::infinity();        // rejected propagation
    if (i == 150) z.setConstant(1e308);                                 // every q overflows
    if (i == 200) bank.presume(4);
    if (i == 230) {
      Eigen::VectorXd p = Eigen::VectorXd::Constant(13, 0.5 / 12.0);
      p(7) = 0.5;
      bank.set_probabilities(p);
    }
    if (i == 260) bank.set_h_output(Eigen::MatrixXd::Constant(7, 13, 0.25));
    if (i == 320) bank.reset();
    const bool ok = bank.step(z, u);
    hash_bank(h, bank, ok);
    if ((i + 1) % kEvery == 0) out.push_back(h.line(label, i + 1));
  }
  return out;
}

template <class Bank>
std::vector<std::string> filter_bank_trace(const std::string& label, const ModelBank& mb, bool kernel) {
  using Model = typename Bank::Model;
  std::vector<Model> models;
  for (int i = 0; i < 13; ++i) {  // NONE and the 12 singles
    const auto& m = mb.hypotheses[i];
    models.push_back(Model::from_matrices(m.phi, m.bd, m.h, m.k, m.a));
  }
  FilterBankOptions o;
  o.vectorized_kernel = kernel;
  Bank bank(models, o);
  return bank_trace<Bank, typename Bank::ZVector, typename Bank::UVector>(label, bank);
}

// A HierarchicalBank flown against a linear truth with a sensor failure that heals (level 1,
// then back-out) and then an actuator and a second failure (level 1, dual). The departure
// hold is off: the synthetic plant's readings are no physical angles and rates (the hold's
// bounds would hold its level 1 throughout), and the trace records the banks' arithmetic;
// the hold has its own tests (test_hierarchical_bank.cpp).
std::vector<std::string> hierarchical_trace(const std::string& label, const ModelBank& mb, bool kernel,
                                            std::vector<std::string>& declared) {
  HierarchicalOptions o;
  o.bank.vectorized_kernel = kernel;
  o.departure.enabled = false;
  F16HierarchicalBank hb(mb, o);
  test::Truth truth(test::random_plant(13, 5, 7, 41u, 1e-3, 1e-3), kAct, kSen, 9u);
  Hashes h;
  std::vector<std::string> out;
  for (int i = 0; i < 900; ++i) {
    std::vector<std::string> failed;
    if (i >= 64 && i < 300) failed.push_back("AOA");
    if (i >= 500) failed.push_back("LF");
    if (i >= 700) failed.push_back("YAW");
    const Eigen::Matrix<double, 7, 1> z = truth.measure(failed) + mb.z_trim;
    const Eigen::VectorXd u = test::dither(5, i, mb.frame_rate_hz);
    truth.advance(u, failed);
    const Eigen::Matrix<double, 5, 1> u_abs = u + mb.u_trim;
    const int d = hb.update(z);
    if (d >= 0) declared.push_back(hb.name(d));
    hash_bank(h, hb.bank(), d >= 0);
    hb.propagate(u_abs);
    hash_bank(h, hb.bank(), true);
    h.add(5, static_cast<double>(hb.level()));
    for (int k : hb.online()) h.add(5, static_cast<double>(k));
    h.add(1, hb.z_hat());
    if ((i + 1) % kEvery == 0) out.push_back(h.line(label, i + 1));
  }
  for (const auto& d : hb.declarations()) {
    h.add(5, static_cast<double>(d.hypothesis));
    h.add(5, static_cast<double>(d.frame));
    h.add(5, d.time_s);
  }
  out.push_back(h.line(label + "-declarations", 900));
  return out;
}

std::vector<std::string> read_lines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> out;
  for (std::string line; std::getline(in, line);)
    if (!line.empty() && line[0] != '#') out.push_back(line);
  return out;
}

// Where a failing run leaves its trace: $F16MMAE_TEST_OUTPUT_DIR, else the temporary directory;
// never the working directory, which may be the source tree.
std::filesystem::path test_output_dir() {
  const char* env = std::getenv("F16MMAE_TEST_OUTPUT_DIR");
  std::filesystem::path dir =
      env != nullptr && env[0] != '\0' ? std::filesystem::path(env) : std::filesystem::temp_directory_path();
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace

TEST(BankTrace, EveryPathIsBitIdenticalToTheRecordedTrace) {
  ASSERT_TRUE(packed::cpu_has_avx2_fma())
      << "the recorded trace holds the AVX2/FMA kernel's numbers; this CPU has no AVX2 and FMA";
  const ModelBank mb = test::f16_model_bank(41u);
  std::vector<std::string> trace, declared_kernel, declared_eigen;
  auto append = [&](const std::vector<std::string>& t) { trace.insert(trace.end(), t.begin(), t.end()); };
  append(filter_bank_trace<F16FilterBank>("fixed-kernel", mb, true));
  append(filter_bank_trace<F16FilterBank>("fixed-eigen", mb, false));
  append(filter_bank_trace<DynamicFilterBank>("dynamic", mb, true));
  append(hierarchical_trace("hierarchical-kernel", mb, true, declared_kernel));
  append(hierarchical_trace("hierarchical-eigen", mb, false, declared_eigen));
  // the flight exercises what it is meant to: a switch, a back-out, a dual declaration
  EXPECT_EQ(declared_kernel, declared_eigen);
  std::string names;
  for (const auto& d : declared_kernel) names += d + " ";
  EXPECT_GE(declared_kernel.size(), 3u) << names;

  const std::string path = std::string(F16MMAE_SOURCE_DIR) + "/tests/cpp/data/bank_trace.txt";
  const std::vector<std::string> expected = read_lines(path);
  std::string actual_path = "(not written: the trace matches)";
  if (trace != expected) {
    actual_path = (test_output_dir() / "bank_trace.actual.txt").string();
    std::ofstream actual(actual_path);
    actual << "# declared: " << names << "\n";
    for (const auto& line : trace) actual << line << "\n";
  }
  ASSERT_EQ(trace.size(), expected.size()) << "lines in " << path << " (this run's trace: " << actual_path << ")";
  for (std::size_t i = 0; i < trace.size(); ++i) {
    if (trace[i] == expected[i]) continue;
    std::istringstream a(trace[i]), e(expected[i]);
    std::string ta, te;
    int field = 0;
    while (a >> ta && e >> te && ta == te) ++field;
    const std::string group = field >= 2 ? Hashes::kNames[field - 2] : "label/frame";
    FAIL() << "line " << i + 1 << " of " << path << " differs first in " << group << ":\n  expected "
           << expected[i] << "\n  got      " << trace[i] << "\n(this run's trace: " << actual_path << ")";
  }
}
