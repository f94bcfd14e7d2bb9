// Model-bank file (cpp/bankfile): SHA-256 against the FIPS 180-4 vectors, round trip,
// deterministic bytes, and refusal of every kind of bad file with a message naming it.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "bankfile/bank_file.h"
#include "bankfile/sha256.h"

namespace f16mmae {
namespace {

using Bytes = std::vector<std::uint8_t>;

std::string hex_of(const std::string& text) { return to_hex(sha256(text.data(), text.size())); }

TEST(Sha256, FipsVectors) {
  EXPECT_EQ(hex_of(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(hex_of("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(hex_of("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  EXPECT_EQ(hex_of("abcdefghbcdefghicdefghijdefghijkefghijklfghijklmghijklmnhijklmnoijklmnopjklmnopqklmnopqr"
                   "lmnopqrsmnopqrstnopqrstu"),
            "cf5b16a778af8380036ce59e7b0492370b249b11e8f07a51afac45037afee9d1");
}

TEST(Sha256, MillionAInUnevenPieces) {
  Sha256 hasher;
  const std::string chunk(997, 'a');  // pieces that straddle the 64-byte blocks
  std::size_t left = 1000000;
  while (left > 0) {
    const std::size_t n = std::min(left, chunk.size());
    hasher.update(chunk.data(), n);
    left -= n;
  }
  EXPECT_EQ(to_hex(hasher.finish()), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
  EXPECT_EQ(to_hex(hasher.finish()), hex_of(""));  // finish() resets
}

// Steady-state filter of a random stable system by iterating the Riccati recursion
// P+ = (I - K H) P-,  P-' = Phi P+ Phi^T + Q,  K = P- H^T A^-1,  A = H P- H^T + R.
HypothesisModel random_hypothesis(const std::string& name, int nx, int nu, int nz, std::mt19937& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  auto rnd = [&](int r, int c) { return Eigen::MatrixXd::NullaryExpr(r, c, [&]() { return g(rng); }); };
  HypothesisModel m;
  m.name = name;
  m.phi = rnd(nx, nx);
  m.phi *= 0.95 / spectral_radius(m.phi);
  m.bd = rnd(nx, nu);
  m.h = rnd(nz, nx);
  const Eigen::MatrixXd q = 0.1 * Eigen::MatrixXd::Identity(nx, nx);
  const Eigen::MatrixXd r = 0.01 * Eigen::MatrixXd::Identity(nz, nz);
  Eigen::MatrixXd p = Eigen::MatrixXd::Identity(nx, nx);
  for (int i = 0; i < 500; ++i) {
    m.a = m.h * p * m.h.transpose() + r;
    m.k = p * m.h.transpose() * m.a.inverse();
    p = m.phi * (Eigen::MatrixXd::Identity(nx, nx) - m.k * m.h) * p * m.phi.transpose() + q;
    p = 0.5 * (p + p.transpose());
  }
  m.a = 0.5 * (m.a + m.a.transpose());
  return m;
}

ModelBank random_bank(int n_hyp, int nx, int nu, int nz, unsigned seed) {
  std::mt19937 rng(seed);
  ModelBank bank;
  for (int i = 0; i < nx; ++i) bank.state_names.push_back("x" + std::to_string(i));
  for (int i = 0; i < nu; ++i) bank.input_names.push_back("u" + std::to_string(i));
  for (int i = 0; i < nz; ++i) bank.measurement_names.push_back("z" + std::to_string(i));
  for (int k = 0; k < n_hyp; ++k)
    bank.hypotheses.push_back(random_hypothesis(k == 0 ? "NONE" : "H" + std::to_string(k), nx, nu, nz, rng));
  bank.u_trim = Eigen::VectorXd::LinSpaced(nu, -0.1, 0.1);
  bank.z_trim = Eigen::VectorXd::LinSpaced(nz, 1.0, 400.0);
  bank.h_output = bank.hypotheses[0].h;
  bank.frame_rate_hz = 64.0;
  bank.mach = 0.4;
  bank.alt_ft = 20000.0;
  bank.tuning = "untuned";
  bank.metadata = R"({"generator": "test_bank_file"})";
  return bank;
}

class TempDir : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("f16mmae_test_bank_file_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  static Bytes read(const std::string& p) {
    std::ifstream in(p, std::ios::binary);
    return Bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
  static void write(const std::string& p, const Bytes& b) {
    std::ofstream out(p, std::ios::binary);
    out.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
  }
  // A file image built here from the documented layout, independently of bank_file_bytes.
  static Bytes image_of(const Bytes& payload, std::uint32_t version = ModelBank::kFormatVersion) {
    Bytes out(kBankFileMagic, kBankFileMagic + 8);
    for (int i = 3; i >= 0; --i) out.push_back(static_cast<std::uint8_t>(version >> (8 * i)));
    for (int i = 7; i >= 0; --i) out.push_back(static_cast<std::uint8_t>(std::uint64_t{payload.size()} >> (8 * i)));
    const Sha256Digest d = sha256(payload.data(), payload.size());
    out.insert(out.end(), d.begin(), d.end());
    out.insert(out.end(), payload.begin(), payload.end());
    return out;
  }
  // Loading `bytes` throws E with a message containing `needle`.
  template <class E>
  void expect_refused(const Bytes& bytes, const std::string& needle) {
    const std::string p = path("bad.bank");
    write(p, bytes);
    try {
      load_bank(p);
      ADD_FAILURE() << "accepted a bad file, expected: " << needle;
    } catch (const E& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << "message does not name the file: " << e.what();
    }
  }
  std::filesystem::path dir_;
};

void expect_equal(const ModelBank& a, const ModelBank& b) {
  EXPECT_EQ(a.state_names, b.state_names);
  EXPECT_EQ(a.input_names, b.input_names);
  EXPECT_EQ(a.measurement_names, b.measurement_names);
  EXPECT_EQ(a.u_trim, b.u_trim);
  EXPECT_EQ(a.z_trim, b.z_trim);
  EXPECT_EQ(a.h_output, b.h_output);
  EXPECT_EQ(a.frame_rate_hz, b.frame_rate_hz);
  EXPECT_EQ(a.mach, b.mach);
  EXPECT_EQ(a.alt_ft, b.alt_ft);
  EXPECT_EQ(a.tuning, b.tuning);
  EXPECT_EQ(a.estimator.p_min, b.estimator.p_min);
  EXPECT_EQ(a.estimator.threshold, b.estimator.threshold);
  EXPECT_EQ(a.estimator.dwell_s, b.estimator.dwell_s);
  EXPECT_EQ(a.metadata, b.metadata);
  ASSERT_EQ(a.hypotheses.size(), b.hypotheses.size());
  for (std::size_t i = 0; i < a.hypotheses.size(); ++i) {
    EXPECT_EQ(a.hypotheses[i].name, b.hypotheses[i].name);
    EXPECT_EQ(a.hypotheses[i].phi, b.hypotheses[i].phi);  // bit-exact
    EXPECT_EQ(a.hypotheses[i].bd, b.hypotheses[i].bd);
    EXPECT_EQ(a.hypotheses[i].h, b.hypotheses[i].h);
    EXPECT_EQ(a.hypotheses[i].k, b.hypotheses[i].k);
    EXPECT_EQ(a.hypotheses[i].a, b.hypotheses[i].a);
    EXPECT_EQ(a.hypotheses[i].uninformative_width, b.hypotheses[i].uninformative_width);
  }
}

using BankFile = TempDir;

TEST_F(BankFile, RoundTripIsExactAndHashed) {
  const ModelBank bank = random_bank(5, 4, 2, 3, 1);
  bank.validate();
  const std::string p = path("small.bank");
  const std::string hash = save_bank(bank, p);
  const ModelBank loaded = load_bank(p);
  expect_equal(bank, loaded);
  EXPECT_EQ(loaded.content_hash, hash);
  EXPECT_EQ(hash.size(), 64u);
  const Bytes file = read(p);
  EXPECT_EQ(file, bank_file_bytes(bank));
  const Bytes payload(file.begin() + kBankFileHeaderSize, file.end());
  EXPECT_EQ(payload, encode_bank_payload(bank));
  EXPECT_EQ(file, image_of(payload));  // the documented layout, byte for byte
  EXPECT_EQ(hash, to_hex(sha256(payload.data(), payload.size())));
  EXPECT_EQ(hash, bank_content_hash(loaded));
}

TEST_F(BankFile, SameBankSameBytesDifferentBankDifferentHash) {
  const ModelBank bank = random_bank(3, 4, 2, 3, 7);
  save_bank(bank, path("a.bank"));
  save_bank(random_bank(3, 4, 2, 3, 7), path("b.bank"));
  EXPECT_EQ(read(path("a.bank")), read(path("b.bank")));
  ModelBank other = bank;
  other.hypotheses[1].k(0, 0) = std::nextafter(other.hypotheses[1].k(0, 0), 1e300);  // one ulp
  EXPECT_NE(bank_content_hash(bank), bank_content_hash(other));
}

TEST_F(BankFile, F16SizedBankOf79Hypotheses) {
  const ModelBank bank = random_bank(79, 13, 5, 7, 3);
  const std::string p = path("f16.bank");
  save_bank(bank, p);
  const ModelBank loaded = load_bank(p);
  expect_equal(bank, loaded);
  // 79 x (169 + 65 + 91 + 91 + 49) doubles dominate the size.
  const std::size_t doubles = 79 * (13 * 13 + 13 * 5 + 7 * 13 + 13 * 7 + 7 * 7) + 7 * 13 + 5 + 7;
  EXPECT_GT(std::filesystem::file_size(p), doubles * 8);
  EXPECT_LT(std::filesystem::file_size(p), doubles * 8 + 8 * 1024);
}

TEST_F(BankFile, SaveReplacesAtomicallyAndLeavesNoTemporary) {
  const std::string p = path("x.bank");
  save_bank(random_bank(2, 3, 1, 2, 1), p);
  save_bank(random_bank(2, 3, 1, 2, 2), p);
  expect_equal(load_bank(p), random_bank(2, 3, 1, 2, 2));
  int files = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir_)) files += e.is_regular_file();
  EXPECT_EQ(files, 1);
}

TEST_F(BankFile, SaveRefusesABadBankAndKeepsTheOldFile) {
  const std::string p = path("keep.bank");
  save_bank(random_bank(2, 3, 1, 2, 1), p);
  const Bytes before = read(p);
  ModelBank bad = random_bank(2, 3, 1, 2, 1);
  bad.hypotheses[1].a(0, 0) = -1.0;
  EXPECT_THROW(save_bank(bad, p), std::invalid_argument);
  EXPECT_EQ(read(p), before);
  EXPECT_THROW(save_bank(bad, path("new.bank")), std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(path("new.bank")));
}

TEST_F(BankFile, SaveIntoAMissingFolderIsAnIoError) {
  EXPECT_THROW(save_bank(random_bank(2, 3, 1, 2, 1), path("no/such/folder/x.bank")), BankFileIoError);
}

TEST_F(BankFile, MissingFileAndFolder) {
  EXPECT_THROW(load_bank(path("absent.bank")), BankFileNotFound);
  EXPECT_THROW(load_bank(dir_.string()), BankFileIoError);
}

TEST_F(BankFile, RefusesTruncation) {
  const Bytes good = bank_file_bytes(random_bank(3, 4, 2, 3, 5));
  expect_refused<BankFileFormatError>({}, "empty");
  for (std::size_t n : {std::size_t{5}, std::size_t{8}, std::size_t{30}, kBankFileHeaderSize})
    expect_refused<BankFileFormatError>(Bytes(good.begin(), good.begin() + n), "truncated");
  expect_refused<BankFileFormatError>(Bytes(good.begin(), good.end() - 1), "truncated: the payload has");
  Bytes longer = good;
  longer.push_back(0);
  expect_refused<BankFileFormatError>(longer, "1 unexpected bytes after");
}

TEST_F(BankFile, RefusesCorruptionWrongMagicAndWrongVersion) {
  const Bytes good = bank_file_bytes(random_bank(3, 4, 2, 3, 5));
  for (std::size_t at : {kBankFileHeaderSize + 3, good.size() / 2, good.size() - 1, std::size_t{20}}) {
    Bytes bad = good;
    bad[at] ^= 0x10;
    expect_refused<BankFileFormatError>(bad, "content hash mismatch");
  }
  Bytes magic = good;
  magic[0] = 'X';
  expect_refused<BankFileFormatError>(magic, "wrong magic bytes 'X16MMAEB'");
  expect_refused<BankFileFormatError>(Bytes{'P', 'K', 3, 4}, "wrong magic");
  const Bytes payload(good.begin() + kBankFileHeaderSize, good.end());
  expect_refused<BankFileFormatError>(image_of(payload, 5), "unsupported format version 5");
  for (const std::uint32_t old : {1u, 2u, 3u})
    expect_refused<BankFileFormatError>(image_of(payload, old), "format version " + std::to_string(old) +
                                                                    " is no longer read: this build reads version 4");
}

TEST_F(BankFile, RefusesPayloadsThatAreNotABank) {
  Bytes payload = encode_bank_payload(random_bank(3, 4, 2, 3, 5));
  Bytes foreign = payload;
  foreign[0] ^= 0xff;  // another type's fingerprint, correctly hashed
  expect_refused<BankFileFormatError>(image_of(foreign), "fingerprint");
  Bytes cut(payload.begin(), payload.end() - 21);  // past dwell_nats and the empty width vector, into a
  expect_refused<BankFileFormatError>(image_of(cut), "payload field hypotheses[2].a (byte");
  Bytes padded = payload;
  padded.insert(padded.end(), {1, 2, 3});
  expect_refused<BankFileFormatError>(image_of(padded), "3 bytes after the f16mmae.lcmt_model_bank message");
  Bytes huge = payload;  // num_states = 1,000,000: more names declared than there are bytes
  huge[8] = 0x00;
  huge[9] = 0x0f;
  huge[10] = 0x42;
  huge[11] = 0x40;
  expect_refused<BankFileFormatError>(image_of(huge), "payload field num_states (byte 8) = 1000000 exceeds the limit of 256");
}

// Issue 16: u_trim_size = 2^28 with the hash recomputed made LCM's decoder compute
// int total_size = 8 * 2^28 (overflow), pass its length check and read past the buffer.
TEST_F(BankFile, RefusesHugeDeclaredSizesBeforeAllocating) {
  const ModelBank bank = random_bank(3, 4, 2, 3, 5);
  const Bytes payload = encode_bank_payload(bank);
  // fingerprint, then (count, names) x 3: "x0".."x3", "u0" "u1", "z0".."z2" (7 bytes each)
  const std::size_t u_trim_size_at = 8 + (4 + 4 * 7) + (4 + 2 * 7) + (4 + 3 * 7);
  ASSERT_EQ(payload[u_trim_size_at + 3], 2);  // nu
  for (const std::uint32_t declared : {0x10000000u, 0x7fffffffu, 0xffffffffu}) {
    Bytes bad = payload;
    for (int i = 0; i < 4; ++i) bad[u_trim_size_at + i] = static_cast<std::uint8_t>(declared >> (24 - 8 * i));
    expect_refused<BankFileFormatError>(image_of(bad), "payload field u_trim_size (byte 83) = ");
  }
}

TEST_F(BankFile, ReadsOnlyRegularFiles) {
  try {
    load_bank("/dev/zero");
    ADD_FAILURE();
  } catch (const BankFileIoError& e) {
    EXPECT_STREQ(e.what(), "bank file '/dev/zero': is a character device; it must be a regular file");
  }
  const std::string fifo = path("bank.fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_THROW(load_bank(fifo), BankFileIoError);  // at once: no writer is waited for
}

// A well-formed, correctly hashed file whose content ModelBank::validate() rejects.
TEST_F(BankFile, RefusesBanksThatFailValidation) {
  struct Case {
    const char* needle;
    void (*spoil)(ModelBank&);
  };
  const Case cases[] = {
      {"'H1': phi is 4x3, expected 4x4", [](ModelBank& b) { b.hypotheses[1].phi.conservativeResize(4, 3); }},
      {"u_trim has size 3, expected 2", [](ModelBank& b) { b.u_trim.setOnes(3); }},
      {"h_output is 3x2, expected 3x4", [](ModelBank& b) { b.h_output.conservativeResize(3, 2); }},
      {"'H2': k has a non-finite entry", [](ModelBank& b) { b.hypotheses[2].k(1, 1) = NAN; }},
      {"'H1': residual covariance A is not positive definite",
       [](ModelBank& b) { b.hypotheses[1].a = -b.hypotheses[1].a; }},
      {"'H1': residual covariance A is not symmetric", [](ModelBank& b) { b.hypotheses[1].a(0, 1) += 1.0; }},
      {"'NONE': error dynamics Phi (I - K H) is unstable",
       [](ModelBank& b) { b.hypotheses[0].phi *= 50.0; }},
      {"hypothesis 0 must be NONE", [](ModelBank& b) { b.hypotheses[0].name = "LS"; }},
      {"duplicate name", [](ModelBank& b) { b.hypotheses[2].name = "H1"; }},
      {"frame_rate_hz must be finite, > 0 and <= 10000, got 0", [](ModelBank& b) { b.frame_rate_hz = 0.0; }},
      {"mach must be finite, >= 0 and <= 10, got nan", [](ModelBank& b) { b.mach = NAN; }},
      {"alt_ft must be finite, >= 0 and <= 1e+06, got -1", [](ModelBank& b) { b.alt_ft = -1.0; }},
      {"state_names[2] 'x0' duplicates state_names[0]", [](ModelBank& b) { b.state_names[2] = "x0"; }},
      {"input_names[1] is empty", [](ModelBank& b) { b.input_names[1].clear(); }},
      {"measurement_names[0] is not valid UTF-8 at byte 1", [](ModelBank& b) { b.measurement_names[0] = "z\xff"; }},
      {"estimator: dwell_s must be in [0, 60] s, got 3.4e+07", [](ModelBank& b) { b.estimator.dwell_s = 3.4e7; }},
      {"estimator: threshold must be in (0.5, 1), got 0.5", [](ModelBank& b) { b.estimator.threshold = 0.5; }},
      {"estimator: p_min must be in [0, 1/K) with K = 3 hypotheses, got 0.4",
       [](ModelBank& b) { b.estimator.p_min = 0.4; }},
  };
  for (const Case& c : cases) {
    ModelBank bank = random_bank(3, 4, 2, 3, 11);
    c.spoil(bank);
    EXPECT_THROW(bank_file_bytes(bank), std::invalid_argument) << c.needle;
    expect_refused<std::invalid_argument>(image_of(encode_bank_payload(bank)), c.needle);
  }
}

TEST(BankPayload, RefusesNulInNames) {
  ModelBank bank = random_bank(2, 3, 1, 2, 1);
  bank.tuning = std::string("a\0b", 3);
  EXPECT_THROW(encode_bank_payload(bank), std::invalid_argument);
}

}  // namespace
}  // namespace f16mmae
