// The turbulence-bank-set file (bankfile/turbulence_set_file.h) and the executive running its
// set (Executive(set_file), TurbulenceSetBank): the file round-trips (members, levels,
// references, selector, tempering, adaptation gains, the selector's rule; content hash = SHA-256
// of the payload), reads versions 1 to 3, and
// refuses damage and invalid sets naming the field; the file's tempering is flown unless one is
// given; the executive equals the core TurbulenceBankSet stepped directly over
// the same members, bit for bit, across handovers, with the set's hash, its member in force and
// that member's rho in its status; its
// per-frame path allocates nothing, handovers included.
#include "executive/executive.h"
#include "allocation_counter.h"
#include "test_executive_bank.h"

#include "bankfile/sha256.h"
#include "bankfile/turbulence_set_file.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

using namespace f16mmae;
using namespace f16mmae::executive;

namespace {

using Bank = F16GustThrottleHierarchicalBank;

// Two 19-state 6-input members: the synthetic bank, and the same with every residual
// covariance 9 times larger (a design for rougher air: its rho reads about 1/9 of the first's).
TurbulenceSetFile two_member_set() {
  TurbulenceSetFile f;
  const ModelBank calm = test_support::synthetic_bank(19, 6);
  ModelBank rough = calm;
  for (auto& h : rough.hypotheses) h.a *= 9.0;
  rough.content_hash = "synthetic-rough";
  f.members = {calm, rough};
  f.levels = {"none", "severe"};
  f.adapt_reference = {1.0, 0.5};
  f.trim_time_constant_s = {0.0, 0.0};
  f.selector.bounds = {0.05,   // the calm member's rho between its level and the rough one's
                       0.15};  // the rough member's
  f.selector.typical = {0.1, 0.01};
  f.selector.hold_s = 0.1;
  f.selector.warm_up_s = 0.1;
  f.selector.warm_down_s = 0.1;
  f.selector.settle_s = 0.2;
  f.selector.start = 0;
  f.selector.start_standby = -1;
  f.maneuver_tempering_g = 0.05;   // a load factor the synthetic signals reach: the tempering acts
  f.adapt_gain = {20.0, 35.0};
  return f;
}

// Absolute signals near trim: a residual that grows (the calm member reads rougher air after
// a second), then shrinks (the rough member reads calm air).
Eigen::Matrix<double, 7, 1> z_at(const ModelBank& b, long long i) {
  const double amplitude = i < 64 ? 0.01 : i < 192 ? 0.4 : 0.002;
  Eigen::Matrix<double, 7, 1> z = b.z_trim;
  for (int j = 0; j < 7; ++j) z(j) += amplitude * std::sin(1.7 * i + 2.3 * j);
  return z;
}
Eigen::Matrix<double, 6, 1> u_at(const ModelBank& b, long long i) {
  Eigen::Matrix<double, 6, 1> u = b.u_trim;
  for (int j = 0; j < 6; ++j) u(j) += 0.01 * std::cos(0.2 * i + j);
  return u;
}
lcmt_sensor_frame sensor(long long i, const Eigen::Matrix<double, 7, 1>& z) {
  lcmt_sensor_frame f{};
  f.frame = i;
  f.mach = 0.4;
  f.pressure_altitude_ft = 20000.0;
  for (int j = 0; j < 7; ++j) f.z[j] = z(j), f.valid[j] = 1;
  return f;
}
lcmt_command_frame command(long long i, const Eigen::Matrix<double, 6, 1>& u) {
  lcmt_command_frame f{};
  f.frame = i;
  for (int j = 0; j < 5; ++j) f.u_rad[j] = u(j);
  f.throttle = u(5);
  return f;
}

}  // namespace

TEST(TurbulenceSetFile, RoundTripsAndHashesItsPayload) {
  const TurbulenceSetFile f = two_member_set();
  const std::vector<std::uint8_t> image = turbulence_set_file_bytes(f);
  ASSERT_TRUE(is_turbulence_set_file(image.data(), image.size()));
  const TurbulenceSetFile g = parse_turbulence_set_file(image.data(), image.size(), "memory");
  EXPECT_EQ(g.levels, f.levels);
  EXPECT_EQ(g.adapt_reference, f.adapt_reference);
  EXPECT_EQ(g.trim_time_constant_s, f.trim_time_constant_s);
  EXPECT_EQ(g.selector.bounds, f.selector.bounds);
  EXPECT_EQ(g.selector.typical, f.selector.typical);
  EXPECT_EQ(g.selector.hold_s, 0.1);
  EXPECT_EQ(g.selector.settle_s, 0.2);
  EXPECT_EQ(g.selector.start, 0);
  EXPECT_EQ(g.selector.start_standby, -1);
  EXPECT_EQ(g.maneuver_tempering_g, 0.05);
  EXPECT_EQ(g.adapt_gain, (std::vector<double>{20.0, 35.0}));
  ASSERT_EQ(g.size(), 2);
  EXPECT_EQ(g.members[1].hypotheses[0].a, f.members[1].hypotheses[0].a);
  EXPECT_EQ(g.members[0].content_hash, bank_content_hash(f.members[0]));
  EXPECT_EQ(g.content_hash, to_hex(sha256(image.data() + kBankFileHeaderSize, image.size() - kBankFileHeaderSize)));
  EXPECT_EQ(turbulence_set_file_bytes(g), image);  // deterministic
  EXPECT_FALSE(is_turbulence_set_file(bank_file_bytes(f.members[0]).data(), 60));
}

// Versions 1 (before the tempering), 2 (before the gains) and 3 (before the selector's rule):
// the same payload without its last fields, read with the tempering off, the core's default
// gain (20) in every member and the rule off; a payload without a field its version has is
// truncated; version 5 is refused naming the versions this build reads.
TEST(TurbulenceSetFile, ReadsVersionsOneToFourWithoutTheLaterFields) {
  TurbulenceSetFile with_rule = two_member_set();
  with_rule.selector.calmer_own_rho = true;
  const std::vector<std::uint8_t> image = turbulence_set_file_bytes(with_rule);
  // version 5 without the floor by rho: floor_rho 0.0 (8 bytes), floor_p_min none (a 4-byte count)
  const std::vector<std::uint8_t> v5_payload(image.begin() + kBankFileHeaderSize, image.end());
  const std::vector<std::uint8_t> v4_payload(v5_payload.begin(), v5_payload.end() - (8 + 4));
  EXPECT_TRUE(parse_turbulence_set_file(image.data(), image.size(), "v5").selector.calmer_own_rho);
  const std::vector<std::uint8_t> without_rule = turbulence_set_file_bytes(two_member_set());
  EXPECT_FALSE(parse_turbulence_set_file(without_rule.data(), without_rule.size(), "v5").selector.calmer_own_rho);
  const std::vector<std::uint8_t> v4 = hashed_file_image(kTurbulenceSetFileMagic, 4, v4_payload);
  const TurbulenceSetFile r = parse_turbulence_set_file(v4.data(), v4.size(), "v4");
  EXPECT_TRUE(r.selector.calmer_own_rho);
  EXPECT_EQ(r.selector.floor_rho, 0.0) << "a version-4 file flies without the floor by rho";
  EXPECT_TRUE(r.selector.floor_p_min.empty());
  // the floor by rho round trip
  TurbulenceSetFile with_floor = with_rule;
  with_floor.selector.floor_rho = 2.68;
  with_floor.selector.floor_p_min = {0.0, 1e-6};
  const std::vector<std::uint8_t> floored = turbulence_set_file_bytes(with_floor);
  EXPECT_EQ(floored.size(), image.size() + 2 * 8);
  const TurbulenceSetFile back = parse_turbulence_set_file(floored.data(), floored.size(), "v5");
  EXPECT_EQ(back.selector.floor_rho, 2.68);
  EXPECT_EQ(back.selector.floor_p_min, (std::vector<double>{0.0, 1e-6}));
  const std::vector<std::uint8_t> v3_payload(v4_payload.begin(), v4_payload.end() - 4);
  const std::vector<std::uint8_t> v3 = hashed_file_image(kTurbulenceSetFileMagic, 3, v3_payload);
  const TurbulenceSetFile k = parse_turbulence_set_file(v3.data(), v3.size(), "v3");
  EXPECT_FALSE(k.selector.calmer_own_rho) << "a version-3 file flies the rule it was designed for";
  EXPECT_EQ(k.adapt_gain, (std::vector<double>{20.0, 35.0}));
  const std::vector<std::uint8_t> v2_payload(v3_payload.begin(), v3_payload.end() - (4 + 2 * 8));
  const std::vector<std::uint8_t> v1_payload(v2_payload.begin(), v2_payload.end() - 8);
  const std::vector<std::uint8_t> v1 = hashed_file_image(kTurbulenceSetFileMagic, 1, v1_payload);
  const TurbulenceSetFile g = parse_turbulence_set_file(v1.data(), v1.size(), "v1");
  EXPECT_EQ(g.maneuver_tempering_g, 0.0);
  EXPECT_EQ(g.adapt_gain, (std::vector<double>{20.0, 20.0}));
  EXPECT_EQ(g.selector.bounds, two_member_set().selector.bounds);
  const std::vector<std::uint8_t> v2 = hashed_file_image(kTurbulenceSetFileMagic, 2, v2_payload);
  const TurbulenceSetFile h = parse_turbulence_set_file(v2.data(), v2.size(), "v2");
  EXPECT_EQ(h.maneuver_tempering_g, 0.05);
  EXPECT_EQ(h.adapt_gain, (std::vector<double>{20.0, 20.0}));
  const std::vector<std::uint8_t> short_v2 = hashed_file_image(kTurbulenceSetFileMagic, 2, v1_payload);
  EXPECT_THROW(parse_turbulence_set_file(short_v2.data(), short_v2.size(), "v2"), BankFileFormatError);
  const std::vector<std::uint8_t> short_v3 = hashed_file_image(kTurbulenceSetFileMagic, 3, v2_payload);
  EXPECT_THROW(parse_turbulence_set_file(short_v3.data(), short_v3.size(), "v3"), BankFileFormatError);
  const auto refused = [&](std::uint32_t version, const std::vector<std::uint8_t>& payload, const std::string& expected) {
    const std::vector<std::uint8_t> file = hashed_file_image(kTurbulenceSetFileMagic, version, payload);
    try {
      parse_turbulence_set_file(file.data(), file.size(), "'v'");
      ADD_FAILURE() << "version " << version << " accepted";
    } catch (const BankFileFormatError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  };
  refused(1, v2_payload, "8 bytes after start_standby");
  refused(2, v3_payload, "20 bytes after maneuver_tempering_g");
  refused(3, v4_payload, "4 bytes after adapt_gain");
  const std::vector<std::uint8_t> short_v4 = hashed_file_image(kTurbulenceSetFileMagic, 4, v3_payload);
  EXPECT_THROW(parse_turbulence_set_file(short_v4.data(), short_v4.size(), "v4"), BankFileFormatError);
  std::vector<std::uint8_t> bad_rule = v4_payload;
  bad_rule.back() = 2;
  refused(4, bad_rule, "payload field calmer_own_rho = 2 is not 0 or 1");
  refused(4, v5_payload, "12 bytes after calmer_own_rho");
  const std::vector<std::uint8_t> short_v5 = hashed_file_image(kTurbulenceSetFileMagic, 5, v4_payload);
  EXPECT_THROW(parse_turbulence_set_file(short_v5.data(), short_v5.size(), "v5"), BankFileFormatError);
  // floor_p_min with one value for two members: refused by the selector's check, naming it
  std::vector<std::uint8_t> one_floor(floored.begin() + kBankFileHeaderSize, floored.end() - 8);
  one_floor[one_floor.size() - 8 - 1] = 1;   // the count's last byte: 2 -> 1
  const std::vector<std::uint8_t> one = hashed_file_image(kTurbulenceSetFileMagic, 5, one_floor);
  try {
    parse_turbulence_set_file(one.data(), one.size(), "'v'");
    ADD_FAILURE() << "one floor for two members accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("floor_p_min must be empty or have 2 values (one per member), got 1"),
              std::string::npos) << e.what();
  }
  refused(6, v5_payload, "unsupported format version 6 (this build reads 1 to 5)");
}

TEST(TurbulenceSetFile, RefusesDamageAndInvalidSetsNamingTheField) {
  const auto refused = [](const auto& make, const std::string& expected) {
    try {
      make();
      ADD_FAILURE() << "accepted; expected: " << expected;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  };
  std::vector<std::uint8_t> image = turbulence_set_file_bytes(two_member_set());
  image[image.size() - 3] ^= 1;
  refused([&] { parse_turbulence_set_file(image.data(), image.size(), "'x.f16set'"); },
          "turbulence bank set file 'x.f16set': content hash mismatch");
  const std::vector<std::uint8_t> bank = bank_file_bytes(test_support::synthetic_bank(19, 6));
  refused([&] { parse_turbulence_set_file(bank.data(), bank.size(), "'b'"); }, "not a turbulence bank set file");
  TurbulenceSetFile f = two_member_set();
  f.levels[1] = "none";
  refused([&] { turbulence_set_file_bytes(f); }, "member 1 ('none'): its level must be a new, non-empty name");
  f = two_member_set();
  f.members[1] = test_support::synthetic_bank(13, 6);
  refused([&] { turbulence_set_file_bytes(f); }, "member 1 ('severe') has (nx, nu, nz) = (13, 6, 7)");
  f = two_member_set();
  f.selector.bounds = {0.05};
  refused([&] { turbulence_set_file_bytes(f); }, "bounds must have n x (n-1) = 2 values");
  f = two_member_set();
  f.adapt_reference[0] = -1.0;
  refused([&] { turbulence_set_file_bytes(f); }, "adapt_reference must be in [0, 100]");
  f = two_member_set();
  f.trim_time_constant_s[1] = -1.0;
  refused([&] { turbulence_set_file_bytes(f); }, "trim_time_constant_s must be in [0, 1e6] s");
  f = two_member_set();
  f.maneuver_tempering_g = -0.5;
  refused([&] { turbulence_set_file_bytes(f); }, "maneuver_tempering_g must be in [0, 100] g (0: off), got -0.5");
  f = two_member_set();
  f.adapt_gain[1] = 0.0;
  refused([&] { turbulence_set_file_bytes(f); }, "member 1 ('severe'): adapt_gain must be in (0, 1000], got 0");
  f = two_member_set();
  f.adapt_gain = {20.0};
  refused([&] { turbulence_set_file_bytes(f); }, "trim_time_constant_s and adapt_gain need one value per member (2)");
  f = two_member_set();
  f.selector.floor_p_min = {0.0, 0.5};
  refused([&] { turbulence_set_file_bytes(f); }, "floor_p_min must be in [0, 1e-3] (0: the member's own), got 0.5");
  f = two_member_set();
  f.selector.floor_rho = -1.0;
  refused([&] { turbulence_set_file_bytes(f); }, "floor_rho must be in [0, 1e6] (0: off), got -1");
  f = two_member_set();
  for (auto& m : f.members) m = test_support::synthetic_bank(19, 5);
  refused([&] { Executive ex(f); }, "turbulence bank set of (nx, nu, nz) = (19, 6, 7) members");
}

namespace {

// The core set over the file's members, each with its reference, trim tracking, adaptation gain
// and the load-factor tempering `tempering_g`, over `o`.
struct DirectSet {
  DirectSet(const TurbulenceSetFile& f, const HierarchicalOptions& o, double tempering_g) {
    std::vector<Bank*> members;
    for (int i = 0; i < f.size(); ++i) {
      HierarchicalOptions m = o;
      m.bank.adaptation.enabled = true;
      m.bank.adaptation.reference = f.adapt_reference[i];
      m.bank.adaptation.gain = f.adapt_gain[i];
      m.trim.time_constant_s = f.trim_time_constant_s[i];
      m.maneuver.tempering_g = tempering_g;
      owned.push_back(std::make_unique<Bank>(f.members[i], m));
      members.push_back(owned.back().get());
    }
    set = std::make_unique<TurbulenceBankSet<Bank>>(members, f.selector);
  }
  std::vector<std::unique_ptr<Bank>> owned;
  std::unique_ptr<TurbulenceBankSet<Bank>> set;
};

// The largest difference of the probabilities between an executive's set and a direct set over
// `frames` frames of the test's signals.
double largest_difference(Executive& ex, TurbulenceBankSet<Bank>& direct, const TurbulenceSetFile& f, long long frames) {
  double most = 0.0;
  for (long long i = 0; i < frames; ++i) {
    const auto z = z_at(f.members[0], i);
    const auto u = u_at(f.members[0], i);
    ex.on_sensor(sensor(i, z));
    ex.on_command(command(i, u));
    direct.schedule(AirData{0.4, 20000.0});
    direct.update(z);
    direct.propagate(u);
    for (int k = 0; k < 13; ++k)
      most = std::max(most, std::abs(ex.status().probabilities[k] - direct.running().probabilities()(k)));
  }
  return most;
}

}  // namespace

// The set file's load-factor tempering is the members' unless the options temper themselves
// (then theirs in every member), and it changes the probabilities (so the comparison can fail).
TEST(Executive, ATurbulenceBankSetFliesItsFilesTemperingUnlessGivenOne) {
  const TurbulenceSetFile f = two_member_set();
  HierarchicalOptions o;
  o.bank.p_min = 1e-9;
  {
    Executive ex(f, o);
    DirectSet file(f, o, f.maneuver_tempering_g);
    EXPECT_EQ(largest_difference(ex, *file.set, f, 256), 0.0);
  }
  {
    Executive ex(f, o);
    DirectSet untempered(f, o, 0.0);
    EXPECT_GT(largest_difference(ex, *untempered.set, f, 256), 1e-6) << "the tempering acts on these signals";
  }
  HierarchicalOptions given = o;
  given.maneuver.tempering_g = 0.2;
  Executive ex(f, given);
  DirectSet flag(f, o, 0.2);
  EXPECT_EQ(largest_difference(ex, *flag.set, f, 256), 0.0);
}

// The executive's set is the core set over the same members (each with its reference, trim
// tracking and tempering of the file), stepped directly, bit for bit; the selector hands over
// up and back down; no frame allocates.
TEST(Executive, ATurbulenceBankSetRunsAsTheCoreSetAndAllocatesNothing) {
  TurbulenceSetFile f = two_member_set();
  f.trim_time_constant_s = {30.0, 0.0};   // the calm member tracks the trim, the rough one does not
  f.content_hash = "the-set";
  HierarchicalOptions o;
  o.bank.p_min = 1e-9;
  Executive ex(f, o);
  EXPECT_EQ(ex.estimator().members(), 2);
  EXPECT_EQ(ex.estimator().states(), "2 members of 19 states, 6 inputs");
  EXPECT_EQ(ex.status().bank_hash, "the-set");

  DirectSet direct_set(f, o, f.maneuver_tempering_g);
  TurbulenceBankSet<Bank>& direct = *direct_set.set;

  long long allocations = 0;
  std::vector<int> active;
  for (long long i = 0; i < 448; ++i) {
    const auto z = z_at(f.members[0], i);
    const auto u = u_at(f.members[0], i);
    const lcmt_sensor_frame s = sensor(i, z);
    const lcmt_command_frame c = command(i, u);
    const long long before = f16mmae::testing::allocation_count();
    ASSERT_EQ(ex.on_sensor(s), Fate::used);
    ASSERT_EQ(ex.on_command(c), Fate::used);
    allocations += f16mmae::testing::allocation_count() - before;
    direct.schedule(AirData{0.4, 20000.0});
    direct.update(z);
    // the status carries the member in force after the update and its rho (the adaptive dither's input)
    ASSERT_EQ(ex.status().turbulence_member, direct.active()) << "frame " << i;
    ASSERT_EQ(ex.status().turbulence_power_ratio, direct.power_ratio()) << "frame " << i;
    direct.propagate(u);
    const auto* set = ex.estimator().turbulence_set();
    ASSERT_NE(set, nullptr);
    ASSERT_EQ(set->active(), direct.active()) << "frame " << i;
    for (int k = 0; k < 13; ++k)
      ASSERT_EQ(ex.status().probabilities[k], direct.running().probabilities()(k)) << "frame " << i;
    const auto z_hat = direct.running().z_hat();
    for (int j = 0; j < 7; ++j) ASSERT_EQ(ex.status().z_hat[j], z_hat(j)) << "frame " << i;
    if (active.empty() || active.back() != direct.active()) active.push_back(direct.active());
  }
  EXPECT_EQ(allocations, 0);
  EXPECT_EQ(active, (std::vector<int>{0, 1, 0})) << "up in the rough segment, back down after it";
  ex.on_reset();
  EXPECT_EQ(ex.estimator().turbulence_set()->active(), 0);
  EXPECT_EQ(ex.estimator().turbulence_set()->switches(), 0);
}
