// HierarchicalBank on synthetic model banks built like the design (B column / H row
// removed, Riccati gains) and flown against a linear truth with failures injected:
// level-0 declaration, level-1 dual declaration, back-out, switch initialisation, trim
// handling, lookup errors, the 19-state and 6-input instantiations against the dynamic bank,
// and no heap allocation in the fixed-size F-16 step (switches
// included; global operator new is counted in this executable).
#include "f16mmae/hierarchical_bank.h"

#include "allocation_counter.h"
#include "synthetic_models.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>


using namespace f16mmae;

namespace {

const std::vector<std::string> kAct{"U1", "U2"};
const std::vector<std::string> kSen{"Z1", "Z2", "Z3"};

struct Flight {
  std::vector<Eigen::VectorXd> z, u;  // absolute
};

// failures: (component, first frame, last frame exclusive)
struct Failure {
  std::string name;
  int from, to;
};

Flight fly(const test::Plant& plant, const std::vector<std::string>& act, const std::vector<std::string>& sen,
           const ModelBank& bank, const std::vector<Failure>& failures, int frames, unsigned seed) {
  test::Truth truth(plant, act, sen, seed);
  Flight f;
  for (int i = 0; i < frames; ++i) {
    std::vector<std::string> failed;
    for (const auto& x : failures)
      if (i >= x.from && i < x.to) failed.push_back(x.name);
    f.z.push_back(truth.measure(failed) + bank.z_trim);
    const Eigen::VectorXd u = test::dither(static_cast<int>(act.size()), i, bank.frame_rate_hz);
    f.u.push_back(u + bank.u_trim);
    truth.advance(u, failed);
  }
  return f;
}

template <class HB>
std::vector<std::string> declared_names(const HB& hb) {
  std::vector<std::string> out;
  for (const auto& d : hb.declarations()) out.push_back(hb.name(d.hypothesis));
  return out;
}

const std::vector<std::string> kF16Act{"LS", "RS", "LF", "RF", "RUD"};
const std::vector<std::string> kF16Sen{"VEL", "AOA", "PIT", "AZ", "ROL", "YAW", "AY"};

// An F-16-sized bank (5 inputs, 7 measurements, 79 hypotheses) of the plant, at a trim.
ModelBank f16_sized_bank(const test::Plant& plant) {
  Eigen::VectorXd u_trim = Eigen::VectorXd::Constant(5, -0.03), z_trim(7);
  z_trim << 414.8, 0.14, 0.0, 1.0, 0.0, 0.0, 0.0;
  return test::make_bank(plant, kF16Act, kF16Sen, u_trim, z_trim);
}

// Flies `f` through the fixed-size bank HB and the dynamic bank on the same model bank:
// their probabilities agree to 1e-9 on every frame, their declarations are the same and no
// frame of HB allocates. Returns the names declared.
template <class HB>
std::vector<std::string> fixed_equals_dynamic(const ModelBank& bank, const Flight& f) {
  HB hb(bank);
  DynamicHierarchicalBank reference(bank);
  const std::vector<typename HB::ZVector> z(f.z.begin(), f.z.end());
  const std::vector<typename HB::UVector> u(f.u.begin(), f.u.end());
  double worst = 0.0;
  for (std::size_t i = 0; i < z.size(); ++i) {
    const long long before = f16mmae::testing::allocation_count();
    hb.step(z[i], u[i]);
    EXPECT_EQ(f16mmae::testing::allocation_count() - before, 0) << "frame " << i;
    reference.step(f.z[i], f.u[i]);
    worst = std::max(worst, (hb.probabilities() - reference.probabilities()).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst, 1e-9);
  EXPECT_EQ(declared_names(hb), declared_names(reference));
  return declared_names(hb);
}

struct Small {
  test::Plant plant = test::random_plant(3, 2, 3, 21u);
  ModelBank bank = test::make_bank(plant, kAct, kSen, Eigen::Vector2d(0.1, -0.2), Eigen::Vector3d(10.0, 1.0, -3.0));
};

// The small bank's options with the turbulence adaptation reading s > 1 in its noise, its rho
// catching up with rho-bar within a few frames (before the flights' failures).
HierarchicalOptions adapted(const Small& s) {
  HierarchicalOptions o;
  o.bank.p_min = 1e-6;
  o.bank.adaptation.enabled = true;
  o.bank.adaptation.reference = 0.05;
  o.bank.adaptation.time_constant_s = 4.0 / s.bank.frame_rate_hz;
  return o;
}

}  // namespace

TEST(HierarchicalBank, StartsAtLevelZeroWithTheSinglesByName) {
  Small s;
  DynamicHierarchicalBank hb(s.bank);
  EXPECT_EQ(hb.level(), 0);
  EXPECT_EQ(hb.size(), 6);
  EXPECT_EQ(hb.online_names(), (std::vector<std::string>{"NONE", "U1", "U2", "Z1", "Z2", "Z3"}));
  EXPECT_EQ(hb.name(hb.current_hypothesis()), "NONE");
  EXPECT_EQ(hb.hypothesis_count(), 16);
}

TEST(HierarchicalBank, SubtractsTheTrimLikeAPlainBankOnPerturbations) {
  Small s;
  DynamicHierarchicalBank hb(s.bank);
  std::vector<DynamicFilterModel> models;
  for (int i : hb.online()) {
    const auto& h = s.bank.hypotheses[i];
    models.push_back(DynamicFilterModel::from_matrices(h.phi, h.bd, h.h, h.k, h.a));
  }
  DynamicFilterBank plain(models);
  plain.set_h_output(s.bank.h_output);
  const Flight f = fly(s.plant, kAct, kSen, s.bank, {}, 100, 1u);
  for (int i = 0; i < 100; ++i) {
    hb.step(f.z[i], f.u[i]);
    plain.step(f.z[i] - s.bank.z_trim, f.u[i] - s.bank.u_trim);
    ASSERT_LT((hb.probabilities() - plain.probabilities()).cwiseAbs().maxCoeff(), 1e-12);
    ASSERT_LT((hb.z_hat() - (plain.z_hat() + s.bank.z_trim)).cwiseAbs().maxCoeff(), 1e-12);
    ASSERT_LT((hb.z_hat_perturbation() - plain.z_hat()).cwiseAbs().maxCoeff(), 1e-12);
  }
  EXPECT_TRUE(hb.declarations().empty());
}

TEST(HierarchicalBank, UnscheduledBankKeepsTheLastUsableAirDataAndCountsTheRest) {
  Small s;
  s.bank.mach = 0.4;
  s.bank.alt_ft = 20000.0;
  DynamicHierarchicalBank hb(s.bank);
  DynamicHierarchicalBank reference(s.bank);
  EXPECT_EQ(hb.air_data().mach, 0.4);
  EXPECT_EQ(hb.air_data().pressure_altitude_ft, 20000.0);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const Flight f = fly(s.plant, kAct, kSen, s.bank, {{"Z2", 40, 100}}, 100, 3u);
  for (int i = 0; i < 100; ++i) {
    if (i == 10) hb.schedule(AirData{0.55, 12000.0});
    if (i == 20) hb.schedule(AirData{nan, 15000.0});
    if (i == 30) hb.schedule(AirData{0.6, inf});
    hb.step(f.z[i], f.u[i]);
    reference.step(f.z[i], f.u[i]);
    // An unscheduled bank's filters do not depend on the air data.
    ASSERT_EQ(hb.probabilities(), reference.probabilities());
  }
  EXPECT_EQ(hb.air_data().mach, 0.55);
  EXPECT_EQ(hb.air_data().pressure_altitude_ft, 12000.0);
  EXPECT_EQ(hb.air_data_rejected(), 2);
  hb.reset();
  EXPECT_EQ(hb.air_data().mach, 0.4);
  EXPECT_EQ(hb.air_data_rejected(), 0);
}

TEST(HierarchicalBank, SingleThenDualFailureIsDeclaredAndStays) {
  Small s;
  DynamicHierarchicalBank hb(s.bank);
  const Flight f = fly(s.plant, kAct, kSen, s.bank, {{"U1", 64, 1 << 30}, {"Z3", 320, 1 << 30}}, 640, 2u);
  bool checked_switch = false;
  for (int i = 0; i < 640; ++i) {
    const int d = hb.update(f.z[i]);
    if (d >= 0 && hb.name(d) == "U1") {
      // switch initialisation: every filter starts from the declared filter's x⁺ and the
      // declared hypothesis is presumed
      const Eigen::MatrixXd x = hb.bank().state_estimates();
      for (int k = 1; k < x.rows(); ++k) EXPECT_LT((x.row(k) - x.row(0)).cwiseAbs().maxCoeff(), 1e-15);
      EXPECT_NEAR(hb.probabilities()(1), 1.0 - 5 * 0.001, 1e-15);
      EXPECT_EQ(hb.level(), 1);
      checked_switch = true;
    }
    hb.propagate(f.u[i]);
  }
  EXPECT_TRUE(checked_switch);
  ASSERT_EQ(declared_names(hb), (std::vector<std::string>{"U1", "U1+Z3"}));
  EXPECT_EQ(hb.declarations()[0].level, 0);
  EXPECT_EQ(hb.declarations()[1].level, 1);
  EXPECT_GE(hb.declarations()[0].frame, 64 + 15);
  EXPECT_LT(hb.declarations()[0].frame, 64 + 64);
  EXPECT_DOUBLE_EQ(hb.declarations()[0].time_s, hb.declarations()[0].frame / 64.0);
  EXPECT_GE(hb.declarations()[1].frame, 320 + 15);
  EXPECT_LT(hb.declarations()[1].frame, 320 + 64);
  EXPECT_EQ(hb.level(), 1);
  EXPECT_EQ(hb.name(hb.level1_failure()), "U1");
  EXPECT_EQ(hb.online_names(), (std::vector<std::string>{"NONE", "U1", "U1+U2", "U1+Z1", "U1+Z2", "U1+Z3"}));
  EXPECT_EQ(hb.name(hb.current_hypothesis()), "U1+Z3");
}

TEST(HierarchicalBank, BacksOutWhenNoneWinsAtLevelOne) {
  Small s;
  DynamicHierarchicalBank hb(s.bank);
  const Flight f = fly(s.plant, kAct, kSen, s.bank, {{"Z2", 64, 256}}, 512, 3u);
  for (int i = 0; i < 512; ++i) hb.step(f.z[i], f.u[i]);
  ASSERT_EQ(declared_names(hb), (std::vector<std::string>{"Z2", "NONE"}));
  EXPECT_EQ(hb.declarations()[1].level, 1);
  EXPECT_GE(hb.declarations()[1].frame, 256 + 15);
  EXPECT_EQ(hb.level(), 0);
  EXPECT_EQ(hb.online_names(), (std::vector<std::string>{"NONE", "U1", "U2", "Z1", "Z2", "Z3"}));
  hb.reset();
  EXPECT_TRUE(hb.declarations().empty());
  EXPECT_EQ(hb.frames(), 0);
}

TEST(HierarchicalBank, LevelOneFloorHoldsWhileLevelOneIsOnLineOnly) {
  // the single-then-back-out flight of the test above, with a level-1 floor of its own: at
  // the switch the duals sit on f1, NONE on the level-0 floor p_min and the presumed single
  // carries the rest; at the back-out (and after reset) p_min is every floor again; 0 leaves
  // the bank as it was
  Small s;
  HierarchicalOptions o;
  o.bank.p_min = 1e-6;
  o.level1_p_min = 1e-3;
  DynamicHierarchicalBank hb(s.bank, o);
  const Flight f = fly(s.plant, kAct, kSen, s.bank, {{"Z2", 64, 256}}, 512, 3u);
  int switches = 0;
  for (int i = 0; i < 512; ++i) {
    const int d = hb.update(f.z[i]);
    if (d >= 0 && hb.name(d) == "Z2") {
      ++switches;
      EXPECT_EQ(hb.level(), 1);
      EXPECT_DOUBLE_EQ(hb.bank().options().p_min, 1e-3);
      EXPECT_NEAR(hb.probabilities()(1), 1.0 - 4 * 1e-3 - 1e-6, 1e-15);
      EXPECT_DOUBLE_EQ(hb.probabilities()(0), 1e-6);
      for (int k : {2, 3, 4, 5}) EXPECT_DOUBLE_EQ(hb.probabilities()(k), 1e-3);
    }
    if (hb.level() == 1) {
      EXPECT_GE(hb.probabilities()(0), 1e-6 * (1 - 1e-12));
      EXPECT_GE(hb.probabilities().tail(4).minCoeff(), 1e-3 * (1 - 1e-12));
    }
    if (d >= 0 && hb.name(d) == "NONE") {
      EXPECT_EQ(hb.level(), 0);
      EXPECT_DOUBLE_EQ(hb.bank().options().p_min, 1e-6);
      EXPECT_NEAR(hb.probabilities()(0), 1.0 - 5 * 1e-6, 1e-15);
    }
    hb.propagate(f.u[i]);
  }
  EXPECT_EQ(switches, 1);
  ASSERT_EQ(declared_names(hb), (std::vector<std::string>{"Z2", "NONE"}));
  hb.reset();
  EXPECT_DOUBLE_EQ(hb.bank().options().p_min, 1e-6);
  EXPECT_NEAR(hb.probabilities()(0), 1.0 - 5 * 1e-6, 1e-15);

  o.level1_p_min = 0.0;   // the default: the level-0 floor at level 1 too, bit for bit
  DynamicHierarchicalBank same(s.bank, o);
  HierarchicalOptions plain;
  plain.bank.p_min = 1e-6;
  DynamicHierarchicalBank reference(s.bank, plain);
  for (int i = 0; i < 512; ++i) {
    same.step(f.z[i], f.u[i]);
    reference.step(f.z[i], f.u[i]);
    ASSERT_EQ(same.probabilities(), reference.probabilities()) << "frame " << i;
  }
  o.level1_p_min = 0.02;   // K = 6, threshold 0.9: must be below (1 - 0.9) / 5 = 0.02
  EXPECT_THROW(DynamicHierarchicalBank(s.bank, o), std::invalid_argument);
  o.level1_p_min = 0.019;
  EXPECT_NO_THROW(DynamicHierarchicalBank(s.bank, o));
  o.declarer.threshold = 0.6;   // (1 - 0.6) / 5 = 0.08
  o.level1_p_min = 0.079;
  EXPECT_NO_THROW(DynamicHierarchicalBank(s.bank, o));
  o.level1_p_min = 0.08;
  EXPECT_THROW(DynamicHierarchicalBank(s.bank, o), std::invalid_argument);
  o.level1_p_min = -1e-3;
  EXPECT_THROW(DynamicHierarchicalBank(s.bank, o), std::invalid_argument);
}

TEST(HierarchicalBank, AFlightPhaseDwellTurnsTheEvidenceDwellOff) {
  // with a climb or maneuver dwell configured the declarers' evidence dwell is 0 in force
  // (header); the table's names are kept (still checked against the bank), each at 0; with
  // evidence_dwell_in_phases it stays as configured
  Small s;
  HierarchicalOptions o;
  o.declarer.dwell_nats = 48.0;
  o.declarer.dwell_nats_per_hypothesis = {{"U1", 32.0}};
  EXPECT_EQ(DynamicHierarchicalBank(s.bank, o).options().declarer.dwell_nats, 48.0);
  EXPECT_EQ(DynamicHierarchicalBank(s.bank, o).declarer().dwell_nats_of(1), 32.0);
  HierarchicalOptions p = o;   // the climb's dwell (the maneuver dwell's needs an AZ this bank lacks)
  p.bank.adaptation.enabled = true;
  p.climb_reference.reference = 0.6;
  p.climb_reference.dwell_s = 1.0;
  DynamicHierarchicalBank hb(s.bank, p);
  EXPECT_EQ(hb.options().declarer.dwell_nats, 0.0);
  EXPECT_EQ(hb.options().declarer.dwell_nats_per_hypothesis.at("U1"), 0.0);
  EXPECT_EQ(hb.declarer().dwell_nats_of(1), 0.0);
  HierarchicalOptions q = p;   // kept through the phases: the evidence dwell as configured
  q.evidence_dwell_in_phases = true;
  DynamicHierarchicalBank kept(s.bank, q);
  EXPECT_EQ(kept.options().declarer.dwell_nats, 48.0);
  EXPECT_EQ(kept.options().declarer.dwell_nats_per_hypothesis.at("U1"), 32.0);
  EXPECT_EQ(kept.declarer().dwell_nats_of(1), 32.0);
  p.declarer.dwell_nats_per_hypothesis = {{"NOT_A_HYPOTHESIS", 32.0}};
  EXPECT_THROW(DynamicHierarchicalBank(s.bank, p), std::invalid_argument);
}

TEST(HierarchicalBank, TheRoughDwellReadsTheAdaptationsScale) {
  // the declarer is handed the adaptation's scale on every accepted frame (header, step 6; s_b,
  // here the scale itself: no flight-phase reference): its rough-air table is in force exactly
  // while s >= rough_scale. With the scale above rough_scale
  // throughout, the rough table declares on the frames the same table as a plain least dwell
  // does; with rough_scale out of reach, on the frames of the bank without either
  Small s;
  const HierarchicalOptions plain = adapted(s);
  HierarchicalOptions rough = plain, table = plain, unreached = plain;
  rough.declarer.rough_dwell_s_per_hypothesis = {{"Z2", 1.0}};
  rough.declarer.rough_scale = 1.0 + 1e-9;
  table.declarer.dwell_s_per_hypothesis = {{"Z2", 1.0}};
  unreached.declarer.rough_dwell_s_per_hypothesis = {{"Z2", 1.0}};
  unreached.declarer.rough_scale = kMaxRoughScale;
  DynamicHierarchicalBank hb(s.bank, rough), with_table(s.bank, table), far(s.bank, unreached),
      reference(s.bank, plain);
  const Flight f = fly(s.plant, kAct, kSen, s.bank, {{"Z2", 64, 512}}, 512, 3u);
  int rough_frames = 0;
  for (int i = 0; i < 512; ++i) {
    hb.update(f.z[i]);
    if (hb.level() == 0 && i >= 8) {
      EXPECT_EQ(hb.declarer().rough(), hb.turbulence_scale() >= rough.declarer.rough_scale) << i;
      rough_frames += hb.declarer().rough();
    }
    hb.propagate(f.u[i]);
    with_table.step(f.z[i], f.u[i]);
    far.step(f.z[i], f.u[i]);
    reference.step(f.z[i], f.u[i]);
    EXPECT_FALSE(far.declarer().rough()) << i;
  }
  EXPECT_GT(rough_frames, 0);
  auto same = [](const auto& a, const auto& b) {
    ASSERT_FALSE(a.declarations().empty());
    ASSERT_EQ(a.declarations().size(), b.declarations().size());
    for (std::size_t j = 0; j < a.declarations().size(); ++j) {
      EXPECT_EQ(a.declarations()[j].frame, b.declarations()[j].frame) << j;
      EXPECT_EQ(a.declarations()[j].hypothesis, b.declarations()[j].hypothesis) << j;
    }
  };
  same(hb, with_table);
  same(far, reference);
  EXPECT_GT(hb.declarations().at(0).frame, reference.declarations().at(0).frame);   // Z2 waited its second
  HierarchicalOptions bad = rough;
  bad.bank.adaptation.enabled = false;   // no scale to read
  try {
    DynamicHierarchicalBank refused(s.bank, bad);
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("rough_dwell_s_per_hypothesis"), std::string::npos) << e.what();
  }
}

TEST(HierarchicalBank, LevelOneDwellHoldsWhileLevelOneIsOnLineOnly) {
  // the single-then-back-out flight with a level-1 dwell of 0.75 s (48 frames at 64 Hz): Z2 is
  // declared at level 0 on the reference's frame (its dwell, 16 frames), and NONE's back-out at
  // level 1 on the first frame that completes 48 consecutive frames above the threshold,
  // counted here from the bank's own probabilities; later than the reference's back-out
  Small s;
  HierarchicalOptions plain;
  plain.bank.p_min = 1e-6;
  HierarchicalOptions o = plain;
  o.level1_dwell_s = 0.75;
  DynamicHierarchicalBank hb(s.bank, o), reference(s.bank, plain);
  const Flight f = fly(s.plant, kAct, kSen, s.bank, {{"Z2", 64, 256}}, 512, 3u);
  const int d1 = static_cast<int>(std::lround(0.75 * hb.frame_rate_hz()));
  std::int64_t ref_z2 = -1, ref_none = -1, z2 = -1, none = -1, expected_none = -1;
  int run = 0;
  for (int i = 0; i < 512; ++i) {
    const int r = reference.update(f.z[i]);
    if (r >= 0) (reference.name(r) == "Z2" ? ref_z2 : ref_none) = i;
    const bool at_level1 = hb.level() == 1;
    const int d = hb.update(f.z[i]);
    if (at_level1 && expected_none < 0) {
      run = hb.probabilities()(0) > o.declarer.threshold ? run + 1 : 0;
      if (run == d1) expected_none = i;
    }
    if (d >= 0) (hb.name(d) == "Z2" ? z2 : none) = i;
    if (hb.level() == 1) EXPECT_EQ(hb.declarer().dwell_frames(), d1);
    else EXPECT_EQ(hb.declarer().dwell_frames(), reference.declarer().dwell_frames());
    reference.propagate(f.u[i]);
    hb.propagate(f.u[i]);
  }
  ASSERT_EQ(declared_names(hb), (std::vector<std::string>{"Z2", "NONE"}));
  EXPECT_EQ(z2, ref_z2);
  EXPECT_EQ(none, expected_none);
  EXPECT_GT(none, ref_none);
  EXPECT_GE(none - ref_none, d1 - reference.declarer().dwell_frames());
  o.level1_dwell_s = -0.1;
  EXPECT_THROW(DynamicHierarchicalBank(s.bank, o), std::invalid_argument);
}

TEST(HierarchicalBank, SpareDwellHoldsWhileTheTemperingSpares) {
  // with spare_dwell_s the level-0 dwell in force is its frames on the frames where the
  // per-hypothesis tempering spares (ResidualScale::spares()), the declarer's elsewhere. The
  // bank without it (the reference, declaring later) has the same probabilities and sparing
  // frame for frame until then: the first declaration falls on the frame the declarer's rule
  // (declarer.h: the count restarts with the candidate and is capped at the dwell in force)
  // gives on the reference's probabilities and sparing
  Small s;
  HierarchicalOptions plain = adapted(s);
  plain.bank.adaptation.hypothesis_weight = 0.5;
  HierarchicalOptions o = plain;
  o.spare_dwell_s = 4.0 / s.bank.frame_rate_hz;
  DynamicHierarchicalBank hb(s.bank, o), reference(s.bank, plain);
  const int d = reference.declarer().dwell_frames(), d_spare = 4;
  ASSERT_GT(d, d_spare);
  const Flight f = fly(s.plant, kAct, kSen, s.bank, {{"Z2", 64, 512}}, 512, 3u);
  std::int64_t first = -1, ref_first = -1, expected = -1;
  int count = 0, candidate = -1, spared_frames = 0;
  for (int i = 0; i < 512 && (first < 0 || ref_first < 0); ++i) {
    const int r = reference.update(f.z[i]);
    if (r >= 0 && ref_first < 0) ref_first = i;
    const int k = hb.update(f.z[i]);
    if (k >= 0 && first < 0) first = i;
    if (ref_first < 0 && expected < 0) {   // the rule on the reference's frames
      const bool spares = reference.bank().adaptation().spares();
      spared_frames += spares;
      const int dwell = spares ? d_spare : d;
      int above = -1;
      for (int j = 0; j < reference.probabilities().size() && above < 0; ++j)
        if (reference.probabilities()(j) > o.declarer.threshold) above = j;
      if (above != candidate) count = 0;
      candidate = above;
      if (above >= 0 && count < dwell) ++count;
      if (above > 0 && count >= dwell) expected = i;
    }
    if (first < 0) ASSERT_EQ(hb.probabilities(), reference.probabilities()) << i;
    reference.propagate(f.u[i]);
    hb.propagate(f.u[i]);
  }
  ASSERT_GE(first, 0);
  EXPECT_GT(spared_frames, 0);
  EXPECT_EQ(first, expected);
  EXPECT_LT(first, ref_first);   // the short dwell in force at the onset
  EXPECT_EQ(hb.name(hb.declarations().at(0).hypothesis), "Z2");
  // where the tempering never spares (its gate on the measured rho out of reach) the dwell is the
  // declarer's: the same declarations on the same frames as without spare_dwell_s
  HierarchicalOptions never = o, never_plain = plain;
  never.bank.adaptation.spare_rho = never_plain.bank.adaptation.spare_rho = 100.0;
  DynamicHierarchicalBank held(s.bank, never), held_plain(s.bank, never_plain);
  for (int i = 0; i < 512; ++i) {
    held.step(f.z[i], f.u[i]);
    held_plain.step(f.z[i], f.u[i]);
    ASSERT_FALSE(held.bank().adaptation().spares());
  }
  ASSERT_FALSE(held_plain.declarations().empty());
  ASSERT_EQ(held.declarations().size(), held_plain.declarations().size());
  for (std::size_t j = 0; j < held.declarations().size(); ++j) {
    EXPECT_EQ(held.declarations()[j].frame, held_plain.declarations()[j].frame);
    EXPECT_EQ(held.declarations()[j].hypothesis, held_plain.declarations()[j].hypothesis);
  }
  HierarchicalOptions bad = o;
  bad.spare_dwell_s = 0.5 / s.bank.frame_rate_hz;   // under a frame
  EXPECT_THROW(DynamicHierarchicalBank(s.bank, bad), std::invalid_argument);
  bad.spare_dwell_s = kMaxDwellS + 1.0;
  EXPECT_THROW(DynamicHierarchicalBank(s.bank, bad), std::invalid_argument);
  bad = o;
  bad.bank.adaptation.hypothesis_weight = 1.0;   // no per-hypothesis tempering: nothing to hold it to
  EXPECT_THROW(DynamicHierarchicalBank(s.bank, bad), std::invalid_argument);
}

// The departure hold (hierarchical_bank.h): a bank whose sensors carry the names the hold reads
// (AOA, PIT, ROL; no YAW: not checked). U1 fails, then PIT: without the hold U1 then U1+PIT.
//  - bounds no reading reaches: the same declarations on the same frames, nothing held;
//  - a rate bound every rate reading exceeds: U1 only, every level-1 frame held, and the
//    probabilities are the unheld bank's until it switches (the hold touches only declarations);
//  - a hold of H frames after sprinkled excursions: the dual is declared on the first frame that
//    ends 16 frames above the threshold, none of them within H frames of an excursion,
//    computed here from the bank's own probabilities and readings;
//  - AOA failed first: its own channel is left out, so an AOA bound it exceeds changes nothing.
TEST(HierarchicalBank, DepartureHoldKeepsLevelOneFromDeclaringOutsideTheLinearization) {
  const std::vector<std::string> sen{"AOA", "PIT", "ROL"};
  const test::Plant plant = test::random_plant(3, 2, 3, 21u);
  const Eigen::Vector3d z_trim(0.14, 0.0, 0.0);
  const ModelBank bank = test::make_bank(plant, kAct, sen, Eigen::Vector2d(0.1, -0.2), z_trim);
  const Flight f = fly(plant, kAct, sen, bank, {{"U1", 64, 1 << 30}, {"PIT", 320, 1 << 30}}, 640, 2u);
  HierarchicalOptions off;
  off.departure.enabled = false;
  auto run = [&](const HierarchicalOptions& o, const Flight& fl) {
    DynamicHierarchicalBank hb(bank, o);
    std::vector<std::pair<std::string, std::int64_t>> out;
    for (int i = 0; i < static_cast<int>(fl.z.size()); ++i) {
      const int d = hb.step(fl.z[i], fl.u[i]);
      if (d >= 0) out.emplace_back(hb.name(d), i);
    }
    return std::make_pair(out, hb.departure_frames());
  };
  const auto plain = run(off, f);
  ASSERT_EQ(plain.first.size(), 2u);
  EXPECT_EQ(plain.first[1].first, "U1+PIT");
  HierarchicalOptions wide;
  wide.departure.aoa_rad = wide.departure.rate_rad_s = 1e6;
  const auto w = run(wide, f);
  EXPECT_EQ(w.first, plain.first);
  EXPECT_EQ(w.second, 0);

  HierarchicalOptions tight;
  tight.departure.rate_rad_s = 1e-12;
  DynamicHierarchicalBank held(bank, tight), ref(bank, off);
  for (int i = 0; i < 640; ++i) {
    held.update(f.z[i]);
    ref.update(f.z[i]);
    if (i < plain.first[1].second) {
      EXPECT_LT((held.probabilities() - ref.probabilities()).cwiseAbs().maxCoeff(), 1e-15) << i;
    }
    held.propagate(f.u[i]);
    ref.propagate(f.u[i]);
  }
  ASSERT_EQ(declared_names(held), (std::vector<std::string>{"U1"}));
  EXPECT_EQ(held.declarations()[0].frame, plain.first[0].second);
  EXPECT_EQ(held.departure_frames(), 640 - 1 - plain.first[0].second);

  // sprinkled excursions: the ROL readings above their 80th percentile (of |z - trim|)
  std::vector<double> rol;
  for (const auto& z : f.z) rol.push_back(std::abs(z(2) - z_trim(2)));
  std::vector<double> sorted = rol;
  std::sort(sorted.begin(), sorted.end());
  HierarchicalOptions sprinkled;
  sprinkled.departure.aoa_rad = 1e6;
  sprinkled.departure.rate_rad_s = sorted[sorted.size() * 8 / 10];
  sprinkled.departure.hold_s = 3.0 / 64.0;
  DynamicHierarchicalBank hb(bank, sprinkled);
  std::int64_t last_outside = -1000, expected = -1, declared = -1;
  int above = 0;
  for (int i = 0; i < 640; ++i) {
    const bool at_level1 = hb.level() == 1;
    const int d = hb.update(f.z[i]);
    if (at_level1) {
      if (rol[i] > sprinkled.departure.rate_rad_s) last_outside = i;
      const bool free = i - last_outside > 3;
      const auto on = hb.online_names();
      const auto j = std::find(on.begin(), on.end(), "U1+PIT") - on.begin();
      above = free && hb.probabilities()(j) > 0.9 ? above + 1 : 0;
      if (above == 16 && expected < 0) expected = i;
    }
    if (d >= 0 && hb.name(d) == "U1+PIT") declared = i;
    hb.propagate(f.u[i]);
  }
  ASSERT_GE(expected, 0);
  EXPECT_EQ(declared, expected);
  EXPECT_GT(declared, plain.first[1].second);
  EXPECT_GT(hb.departure_frames(), 0);

  // AOA failed first: its own (trim-reading) channel is not checked
  const Flight fa = fly(plant, kAct, sen, bank, {{"AOA", 64, 1 << 30}, {"U2", 320, 1 << 30}}, 640, 6u);
  HierarchicalOptions aoa;
  aoa.departure.aoa_rad = 1e-12;
  aoa.departure.rate_rad_s = 1e6;
  const auto a_off = run(off, fa), a_on = run(aoa, fa);
  ASSERT_GE(a_off.first.size(), 2u);
  EXPECT_EQ(a_off.first[0].first, "AOA");
  EXPECT_EQ(a_on.first, a_off.first);
  EXPECT_EQ(a_on.second, 0);

  HierarchicalOptions bad;
  bad.departure.rate_rad_s = 0.0;
  EXPECT_THROW(DynamicHierarchicalBank(bank, bad), std::invalid_argument);
  bad = HierarchicalOptions{};
  bad.departure.hold_s = -1.0;
  EXPECT_THROW(DynamicHierarchicalBank(bank, bad), std::invalid_argument);
}

TEST(HierarchicalBank, NoFailureDeclaresNothing) {
  Small s;
  DynamicHierarchicalBank hb(s.bank);
  const Flight f = fly(s.plant, kAct, kSen, s.bank, {}, 640, 4u);
  for (int i = 0; i < 640; ++i) hb.step(f.z[i], f.u[i]);
  EXPECT_TRUE(hb.declarations().empty());
  EXPECT_GT(hb.probabilities()(0), 0.9);
}

TEST(HierarchicalBank, MissingDualOrWrongSizesAreRefusedByName) {
  Small s;
  ModelBank b = s.bank;
  b.hypotheses.erase(b.hypotheses.begin() + b.find("U2+Z1"));
  try {
    DynamicHierarchicalBank hb(b);
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("U2+Z1"), std::string::npos) << e.what();
  }
  EXPECT_THROW(F16HierarchicalBank{s.bank}, std::invalid_argument);
  b = s.bank;
  b.hypotheses[3].a(0, 0) = -5.0;
  EXPECT_THROW(DynamicHierarchicalBank{b}, std::invalid_argument);
}

TEST(HierarchicalBank, F16SizedBankDeclaresAndSwitchesWithoutAllocating) {
  const test::Plant plant = test::random_plant(13, 5, 7, 31u, 1e-3, 1e-3);
  const ModelBank bank = f16_sized_bank(plant);
  ASSERT_EQ(bank.hypotheses.size(), 79u);
  HierarchicalOptions tracking;  // with trim tracking on, too: tracker and trim in force included
  tracking.trim.time_constant_s = 30.0;
  F16HierarchicalBank hb(bank), tracked(bank, tracking);
  const Flight f = fly(plant, kF16Act, kF16Sen, bank, {{"PIT", 64, 1 << 30}}, 320, 5u);
  std::vector<Eigen::Matrix<double, 7, 1>> z(f.z.begin(), f.z.end());
  std::vector<Eigen::Matrix<double, 5, 1>> u(f.u.begin(), f.u.end());
  const long long before = f16mmae::testing::allocation_count();
  for (std::size_t i = 0; i < z.size(); ++i) {
    hb.step(z[i], u[i]);
    tracked.schedule(AirData{0.4, 20000.0});
    tracked.step(z[i], u[i]);
  }
  const long long after = f16mmae::testing::allocation_count();
  EXPECT_EQ(after - before, 0);
  EXPECT_GT(tracked.trim_tracker().frozen_frames(), 0);
  ASSERT_EQ(declared_names(hb), (std::vector<std::string>{"PIT"}));
  EXPECT_EQ(hb.online_names(), (std::vector<std::string>{"NONE", "PIT", "LS+PIT", "RS+PIT", "LF+PIT", "RF+PIT",
                                                         "RUD+PIT", "VEL+PIT", "AOA+PIT", "PIT+AZ", "PIT+ROL",
                                                         "PIT+YAW", "PIT+AY"}));
}

// The 19-state instantiation (the filters with six Dryden gust states, design/gust_states.py)
// runs the same arithmetic as the dynamic bank on the same model bank, and its frames
// allocate nothing.
TEST(HierarchicalBank, GustSizedBankEqualsTheDynamicBankWithoutAllocating) {
  const test::Plant plant = test::random_plant(19, 5, 7, 37u, 1e-3, 1e-3);
  const ModelBank bank = f16_sized_bank(plant);
  ASSERT_EQ(bank.nx(), 19);
  EXPECT_THROW(F16HierarchicalBank{bank}, std::invalid_argument);
  const Flight f = fly(plant, kF16Act, kF16Sen, bank, {{"LF", 64, 1 << 30}}, 320, 9u);
  const std::vector<std::string> declared = fixed_equals_dynamic<F16GustHierarchicalBank>(bank, f);
  ASSERT_FALSE(declared.empty());
  EXPECT_EQ(declared.front(), "LF");
}

// The 6-input instantiation (the throttle command as the sixth input, `f16mmae design
// --throttle-input`: an input of every hypothesis, never a failure) runs the same arithmetic
// as the dynamic bank on the same model bank, and its frames allocate nothing.
TEST(HierarchicalBank, ThrottleSizedBankEqualsTheDynamicBankWithoutAllocating) {
  const test::Plant plant = test::random_plant(13, 6, 7, 41u, 1e-3, 1e-3);
  Eigen::VectorXd u_trim = Eigen::VectorXd::Constant(6, -0.03), z_trim(7);
  u_trim(5) = 0.25;
  z_trim << 414.8, 0.14, 0.0, 1.0, 0.0, 0.0, 0.0;
  ModelBank bank = test::make_bank(plant, kF16Act, kF16Sen, u_trim, z_trim);
  bank.input_names.push_back("THR");
  ASSERT_EQ(bank.nu(), 6);
  ASSERT_EQ(bank.hypotheses.size(), 79u);
  EXPECT_THROW(F16HierarchicalBank{bank}, std::invalid_argument);
  std::vector<std::string> inputs = kF16Act;
  inputs.push_back("THR");
  const Flight f = fly(plant, inputs, kF16Sen, bank, {{"AZ", 64, 1 << 30}}, 320, 13u);
  const std::vector<std::string> declared = fixed_equals_dynamic<F16ThrottleHierarchicalBank>(bank, f);
  ASSERT_FALSE(declared.empty());
  EXPECT_EQ(declared.front(), "AZ");
}
