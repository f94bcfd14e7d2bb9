// TurbulenceAdaptation — on-line adaptation of the MMAE's likelihoods to the turbulence
// intensity, which the estimator is never told (issue 14, option (b): residual covariance
// scaling common to all hypotheses). Eigen and std only.
//
// The bank's filters are designed for one gust intensity (the shipped bank: light). In
// stronger gusts every filter's residual is larger than its A_k says, the log-likelihood
// differences grow with the residual power, and gust-shaped residuals are read as failures;
// in calmer air the opposite. The adaptation models the residual covariance of every filter
// on line as s·A_k, with one scale s common to all hypotheses, estimated on line:
//
//   per accepted update, with q_k = r_kᵀ A_k⁻¹ r_k the bank's quadratic forms:
//     ρ ← ρ + α (min(min_k q_k / m, ρ_clip) − ρ),   α = 1 − exp(−1 / (τ f))  (f: frame rate,
//                                                                          m: measurements)
//     s = clamp(1 + κ (ρ − ρ_0),  s_min, s_max)
//   and the bank's log-likelihood of that frame (eq. 2) uses the s of the frames BEFORE it:
//     l_k = −q_k / (2 s)            (leading term stripped, the default)
//     l_k = −q_k / (2 s) − (m/2) ln 2π − (1/2) ln|A_k|   (kept: ln|s A_k| adds −(m/2) ln s to
//                                    every l_k alike, which the normalisation of eq. 1 removes)
//
// Why these choices:
//   - E[q_k] = m when filter k's model is right and its residual covariance is A_k, so q_k / m
//     measures the ratio of the actual residual power to the design's.
//   - The MINIMUM over the hypotheses on line, frame by frame: after a failure the no-failure
//     filter's residuals grow but the matching hypothesis's do not, so the failure does not
//     raise ρ (the adaptation does not absorb the failure); gusts, which no hypothesis models,
//     raise every q_k. Taken per frame, not as the minimum of per-hypothesis averages: a
//     hypothesis that did not fit before the failure would carry its large average for τ
//     after it, and the no-failure filter's growing one would set ρ: the failure itself would
//     drive s towards its bound.
//   - ρ_0, the reference: the minimum of 13 quadratic forms sits below m even when every
//     model is right, so ρ reads less than the power ratio (docs/results/
//     turbulence_adaptation.md gives ρ by turbulence level). Tempering starts above ρ_0.
//   - κ, the gain on the EXCESS ρ − ρ_0: κ = 1, ρ_0 = 0 would be the matched scale s = ρ
//     (covariance matching). It is not enough: gust residuals are coloured and shaped like
//     the flaperon and AOA signatures, so the likelihood-ratio excursions they cause outgrow
//     the matched scale; κ > 1 tempers in proportion to the excess. κ, ρ_0, τ and s_max are
//     chosen on tuning seeds (tools/turbulence_tuning.py; docs/results/
//     turbulence_adaptation.md gives the figures).
//   - s_min (default 1): the bank's own A_k are the floor, so in calmer air than the design
//     the bank is exactly the one designed (no sharpening below the design).
//   - ρ_clip = 10 s_max keeps one wild frame (a sensor spike) from moving ρ by more than
//     α ρ_clip.
//   - ρ carries over the hierarchical switches (it does not depend on which filters are on
//     line); at the start and at reset() ρ = ρ_0: s = clamp(1, s_min, s_max), the bank as
//     designed until the residuals say otherwise. ρ_0 is the one in force when the first
//     residuals arrive: a reference set before any update is averaged (a scheduled bank's
//     per-node reference at its first air data, set_reference) moves ρ with it, so a flight
//     starts at its own flight condition's ρ_0, not at the one of the node in force before
//     air data.
//   - Running start (running_start, default off): from the start or reset() ρ is the plain mean
//     of the x's until the average's length, as ρ̄ is below,
//         ρ ← ρ + a_i (min(x, ρ_clip) − ρ),   a_i = max(1 / i, α)
//     (ρ_j likewise, i counted per channel), so s is the air's within a second instead of rising
//     from 1 over τ. Why: with ρ starting at ρ_0, s at 3 s is about half its settled value in
//     the design's own turbulence (light air at Mach 0.42, 17,400 ft: s 1.7 over the first 5 s,
//     3.2-3.8 from 15 s on; docs/results/envelope_scheduled.md, round 20), so the estimator a
//     failure meets, and the false-alarm bound that calibrates ρ_0 (design/calibrate.py), depend
//     on how long it has flown. set_power_ratio ends the running start (the average goes on from
//     the ρ it is given).
//
// Lull floor (floor_time_constant_s τ_L >= τ; 0, the default, is off: bit for bit without): a
// second, longer average of the same minimum, and the scale reads the larger of the two once
// that average has run for τ_L / 2,
//     ρ_L ← ρ_L + a_i (min(x, ρ_clip) − ρ_L),   a_i = max(1 / i, α_L),   α_L = 1 − exp(−1 / (τ_L f))
//     s = clamp(1 + κ (max(ρ, ρ_L)/σ − ρ_0),  s_min, s_max)   from i >= τ_L f / 2 on (ρ alone before)
//   (i the updates averaged since the start or reset(): a plain mean first, as ρ̄ below;
//   set_power_ratio sets ρ_L with ρ and puts the floor in force). Why: the turbulence's
//   intensity is the air mass's and changes over minutes, while the gusts' power over τ has
//   lulls (the Dryden gusts' low bandwidth; κ turns a small dip of ρ into a large one of s): in
//   moderate air at the nominal point s spends a few per cent of its frames at 1 against a
//   median of 2-4, and a burst that follows a lull meets the design's untempered A_k until ρ has
//   risen over τ. The false flaperon and roll-gyro declarations of 40 h of moderate-air soaks at
//   the nominal point began at s 1-1.55 against flight medians of 2-4 (docs/results/
//   turbulence_adaptation.md, round 44). The floor holds the air's tempering through a lull and
//   leaves s alone wherever ρ is above it, and a failure, which by the minimum does not raise ρ,
//   does not raise ρ_L either. Why not a slower fall of ρ itself (the last burst's tempering
//   held): it holds s near its peaks, and the flaperon failures in moderate air, whose evidence
//   is the dither's against the gusts', are then missed (round 44: 7 of 20 found). Why in force
//   only after τ_L / 2: in force from the start, the first seconds' mean tempers a failure 3 s
//   into a flight in rough air by the air's full scale where ρ is still rising (the severe
//   single-failure runs lost 4 of 120); started at the reference instead, it stays below the
//   air's level for the flight's first minute (a false RF at 65 s in moderate air, s 1.13 at its
//   onset against the flight's median 4.67).
//   Only s (and through it the per-channel and per-hypothesis forms); scale_at() and ρ̄ read ρ.
//   Held (hold_floor; the hierarchical bank holds it in a flight phase, climbing or maneuvering:
//   hierarchical_bank.h): ρ_L and i keep their values and s reads ρ alone. Why: a climb's or a
//   turn's onset lifts every residual the models do not carry, which is no gust, and a floor
//   that took it in held s at the onset's 7-8 for a minute after it (a flaperon failing 4 s into
//   a climb in light air, found 3-7 s after it without the floor, was then missed in 7 of 10 runs).
//
// Power scale σ (set_power_scale, default 1; a scheduled bank's node reference scale,
// bank_schedule.h): the bank's power ratio in the units of another bank's, ρ/σ, is what the
// scale reads,
//     s = clamp(1 + κ (ρ/σ − ρ_0),  s_min, s_max)      (s'_j likewise with ρ_j/σ)
// and ρ and ρ_j start and reset at σ ρ_0 (s = 1), the spare rule reads ρ̄/σ against ρ_s. Why: a
// bank whose hypotheses cover more than the model its references and gain were chosen on (a
// failed sensor's reading at an unknown level over its range, hypotheses.py) fits no-failure
// gusts better, so its minimum q_k / m runs lower in the same air (σ 0.80-0.88 of the
// constant-VEL-and-roll-gyro bank's over the scheduled grid, design/schedule.py); reading ρ/σ
// tempers it as that bank would be tempered (κ/σ on the excess over σ ρ_0), where scaling ρ_0
// alone would leave s − 1 at σ of it (severe air at the nominal point: s 58 against 71, and the
// stabilators declared falsely 1.3 times an hour against 0.2).
//
// Per channel (channel_weight γ in (0, 1]; 0, the default, is off): the same recursion per
// measurement j, with the channel's share of the best-fitting filter's quadratic form in
// place of min_k q_k / m:
//     k* = argmin_k q_k,   c_j = r_k*,j (A_k*⁻¹ r_k*)_j      (Σ_j c_j = q_k*;  E[c_j] = 1 when
//                                                             filter k*'s model is right)
//     ρ_j ← ρ_j + α (min(c_j, ρ_clip) − ρ_j),   s'_j = clamp(1 + κ (ρ_j − ρ_0), s_min, s_max)
//     s_j = s^(1−γ) s'_j^γ        (γ = 1: the channel's own scale; γ → 0: the common s)
//   (a channel that k* leaves out, A_k*⁻¹ row j zero: a failed sensor's uninformative
//   reading, is not observed that frame), and the likelihood models filter k's residual
//   covariance as S^½ A_k S^½, S = diag(s_j), of the frames before:
//     l_k = −(D r_k)ᵀ A_k⁻¹ (D r_k) / 2,   D = diag(s_j^−½)
//   The mean of the ρ_j over the channels is ρ (up to the clip), and with every s_j = s this is
//   −q_k / (2 s): the common scale (so it is with one channel). Why: the gusts drive the channels unequally (in severe
//   turbulence pitch rate and angle of attack far more than normal acceleration and yaw
//   rate), so one common s, set by the strongest, tempers the evidence a flaperon failure
//   gives in the quieter channels as much as the gusts in the loudest. ρ_j start and reset at
//   ρ_0 and follow set_power_ratio like ρ; s (scale()) and ρ̄ stay the common ones.
//
// Own channels (own_channels, default off): a hypothesis with uninformative channels (a failed
// sensor's reading an unknown level, filter_bank.h) leaves them out of q_k, so q_k sums
// m_k = m − (its uninformative channels) terms, E[q_k] = m_k: its q_k / m reads low by
// (m − m_k)/m, and in gusts by more (the gusts' share in the channel it leaves out), and wins
// the minimum, so ρ reads the air calmer than it is. With own_channels every filter's form
// counts per channel it reads: x = min_k q_k / m_k in place of min_k q_k / m (the filter bank
// passes q_k m / m_k to observe()); a bank without uninformative channels is unchanged.
// Counted channels (counted_channels, a bit per measurement channel j, default none): an
// uninformative channel whose bit is set still counts in m_k,
//     m_k = m − |{ j uninformative in filter k, bit j of counted_channels clear }|,
// so the hypotheses that leave out only such channels count their form over m, as without
// own_channels (their share of the plain minimum), the others over the channels they read.
// Why per channel: a failed sensor's level that follows the failed reading slowly (a failed
// airspeed sensor's jump to its stuck value) leaves the matching hypothesis's q_k above m_k for
// seconds after the failure; read per channel it wins the minimum with ρ up to m / m_k higher,
// s rises and tempers that hypothesis's own evidence (docs/results/envelope_tuning.md).
// Excluded channels (excluded_channels, a bit per measurement channel j, default none): a
// hypothesis that reads an excluded channel as a free level (uninformative there: a `constant`
// or `cover` level for that sensor) while the presumed hypothesis p (filter 0 at level 0; at
// level 1 the declared failure) does not, leaves the minimum:
//     E = { k : some j with bit j of excluded_channels set, j uninformative in k, not in p },
//     x = min_{k on line, k ∉ E} q'_k / m    (q'_k = q_k, or q_k m / m_k with own_channels)
//   in place of the minimum over every hypothesis on line; x feeds ρ, ρ̄ and x̃ alike. The
//   hypotheses in E still get s (their l_k as every other's). The per-channel form's k* and the
//   per-hypothesis form's b are chosen as without it. Why: a level the design reads as free
//   absorbs that channel's gust power (the level fits whatever the reading does), so in gusts
//   its q_k is the least more often than its fit deserves and ρ reads the air calmer than the
//   references were calibrated for; s then falls to its floor and other hypotheses peak in
//   gusts (a constant AOA level: docs/results/envelope_tuning.md, round 16). Excluding is
//   what own_channels' per-channel count cannot do: the level's q_k / m_k is still low.
//   A channel the presumed hypothesis reads as a free level excludes nobody (at level 1 after
//   that sensor's failure every hypothesis reads it so, and the minimum would be empty).
//
// Per hypothesis (hypothesis_weight w in (0, 1]; 1, the default, is off): the gusts lift some
// hypotheses' likelihoods against the no-failure filter's far more than others' (in severe
// turbulence the stabilators', whose columns of B act in pitch as the gusts do, most), so one s
// set by the most lifted tempers the others' evidence more than their own gust excursions need.
// With w < 1, on each frame the best-fitting failure hypothesis b = argmin_{k>0, on line} q_k,
// unless it is one of the fully tempered ones (bit b of full_tempering set), has its evidence
// against filter 0 tempered by
//     s_b = 1 + w (s − 1)          (the tempering's excess over the design, shared by w)
// in place of s:
//     l_b = −(q_0 + (q_b − q_0) s / s_b) / (2 s)     i.e.  l_b − l_0 = −(q_b − q_0) / (2 s_b),
// every other l_k as above (the load-factor tempering s_e, when on, divides every l_k alike
// and u_k is added after, as without it). Why the best-fitting one only: a failure lifts every
// hypothesis that explains part of its signature (a failed stabilator lifts the pitch-rate and
// angle-of-attack sensor hypotheses with it), and a weight on each of them would let a lightly
// tempered partial fit outrun the fully tempered right one; the hypothesis that fits best
// this frame is the one whose evidence is spared. Which ones keep s is the caller's
// (full_tempering): with a turbulence bank set the stabilators and flaperons; with a bank's own
// adaptation (a scheduled bank's default, W 0.25) also AZ, AOA and VEL, whose signatures the gusts
// mimic in light air, so that the gyros', the lateral accelerometer's and the rudder's evidence is
// not held back by the scale the flaperons need (docs/results/envelope_scheduled.md, round 20).
// At s = 1 (air no rougher than the design)
// s_b = 1: the bank as without it. q_k, ρ and ρ̄ are the raw forms, untouched.
// Only while the scale has caught up with the air, ρ >= ρ̄ / 2: ρ starts at ρ_0 (the start,
// reset()) and rises over τ, ρ̄ is right within a second, so in rough air s understates the
// gusts for the first seconds, and a spared hypothesis would take their excursions at a
// fraction of an s already too small. Only a first failure's evidence is spared: while
// a hypothesis other than 0 is presumed (FilterBank::presume; a hierarchical bank's level 1
// presumes its declared failure, whose duals are then the hypotheses) every l_k keeps s.
// full_tempering: bit k set keeps hypothesis k's s (the caller names them: the turbulence
// bank set's stabilators and flaperons, design/turbulence_banks.py). Scalar tempering only: with
// channel_weight > 0 it is refused.
// Refinements of the per-hypothesis form, each off by default:
//   spare_rho ρ_s (> 0): the sparing only while ρ̄ >= ρ_s (the measured ρ̄ below, the frames
//     before). ρ̄ is the turbulence bank set's measure of the air (turbulence_bank_set.h), so ρ_s
//     between a member's ρ̄ in moderate and in severe turbulence spares in severe air only:
//     wherever ρ̄ < ρ_s every l_k is the one without the per-hypothesis form, frame for frame.
//     ρ̄ averages over τ, so a burst of gusts from calmer air is tempered by s alone until ρ̄ has
//     risen past ρ_s (a few seconds), when ρ has too.
//   spare_margin: the spared evidence is b's margin over the best-fitting of filter 0 and the
//     fully tempered hypotheses F (bits of full_tempering, on line), not over filter 0 alone:
//       q_r = min(q_0, min_{f∈F} q_f),   l_b = −(q_r + (q_b − q_r) s / s_b) / (2 s)
//     i.e. l_b − l_r = −(q_b − q_r) / (2 s_b) with l_r = −q_r / (2 s) the reference's likelihood
//     (with q_r = q_0 this is the form above). Why: the sparing tempers b's evidence against
//     filter 0 by s_b < s, which also lifts b against every other hypothesis by
//     (q_0 − q_b)(1/s_b − 1/s)/2 per frame. A hypothesis that fits a failure's signature in
//     part (a failed stabilator's lifts the pitch-rate and angle-of-attack sensor hypotheses
//     with it) is then the least q_k on a few frames of the onset, where its q_b is a little
//     below the failed stabilator's own q_f and far below q_0, and on each such frame takes the
//     whole lift (q_0 − q_b) over the fully tempered right hypothesis, which gets no sparing:
//     a few such frames can carry it past a stabilator already at p = 0.9. With the
//     margin, b gains over f only (q_f − q_b)(1/s_b − 1/s)/2 on such a frame: the spared lift is
//     what b fits better than every hypothesis kept at s. Where a fully tempered hypothesis fits
//     the gusts better than filter 0 (their columns of B act as the gusts do) the spared lift is
//     smaller too. b is chosen as above (argmin over every failure hypothesis on line, fully
//     tempered ones included: a fully tempered least q_k spares none), so q_r >= q_b whenever
//     q_b <= q_0.
//   spare_margin_over (bits; with spare_margin): the reference set F of the margin is these
//     hypotheses (on line) in place of full_tempering's:
//       q_r = min(q_0, min_{f∈F'} q_f),   F' = {f : bit f of spare_margin_over set}
//     0 (the default): F' = F. Why a subset: in severe air the flaperons, whose columns of B act
//     in roll as the gusts do, fit the gusts better than filter 0 on many frames where no failure
//     is on; measured against them, every spared hypothesis's lift is smaller there, a latency
//     cost on every sensor failure, while the confusions the margin removes were with the
//     stabilators only (docs/results/turbulence_banks.md, rounds 17-18). F' = the stabilators
//     keeps the margin where a stabilator's onset is fitted in part by a sensor hypothesis and
//     measures every other frame's lift against filter 0 and the stabilators only. Bits outside
//     F are allowed (a hypothesis spared on a frame is still b's rival at s there).
//   rough_tempering (bits) with rough_rho ρ_r and rough_weight w_r: while the air's power
//     ratio reads rough, ρ_a >= σ ρ_r (air_power_ratio() below: ρ̄, or the lull floor's ρ_L
//     once in force, the frames before), these hypotheses' share of s − 1 is w_r in place of w:
//     when one of them is b,
//       s_b = 1 + w_r (s − 1)
//     in the spared form above. w_r = 1 (the default) keeps them at the full s: they join the
//     fully tempered ones,
//       F(ρ_a) = full_tempering ∪ (rough_tempering if ρ_a >= σ ρ_r),
//     in the choice of b (a fully tempered least q_k spares none) and in the margin's reference.
//     Why: a hypothesis whose likelihood the gusts lift little in moderate air, so that sparing
//     it keeps its failure's latency, can be lifted past a declaration in severe air, where its
//     spared evidence takes the gusts' excursions at s_b << s (a scheduled bank's rudder and
//     lateral accelerometer above 29,000 ft: docs/results/envelope_scheduled.md, round 51). ρ_r
//     between the air's ρ̄ in moderate and in severe turbulence keeps the sparing in moderate air
//     and shares less of it in severe. With rough_tempering 0 (the default) nothing changes.
//   So the sparing is in force on a frame iff w < 1, s > 1, ρ >= ρ̄ / 2 and ρ̄ >= ρ_s.
//
// The bound's knee (scale_max_from ρ_c > 0; 0, the default, is off): from ρ/σ = ρ_c on the
// bound s_max rises with the air at the adaptation's own gain,
//     s = clamp(1 + κ (ρ/σ − ρ_0),  s_min,  s_max + κ max(ρ/σ − ρ_c, 0))
//   (s'_j and scale_at() likewise; the ρ in force: ρ or the lull floor's ρ_L). With ρ_c above
//   ρ_0 + (s_max − 1)/κ, where the line meets s_max, s is held at s_max between that ratio and ρ_c
//   and runs parallel to the line beyond, κ (ρ_c − ρ_0) + 1 − s_max below it. Why: s_max keeps a
//   failure's evidence from being tempered away in severe air, but a gust's likelihood excursion
//   grows with ρ/s, and where the air is rougher still the bound holds s while the excursions
//   grow: a scheduled bank's severe air reads 6-10 at 23,000-32,000 ft and 11.7-15.5 above, where
//   s sat at s_max 100 on every frame and all but two (low-altitude rudders) of the false
//   declarations of 40 h of severe air over the envelope happened (tuning seed;
//   docs/results/envelope_scheduled.md, round 52). Lifting the bound there alone keeps the failures
//   found between, which a larger s_max tempers away.
//
// The measured ρ̄ (measured_power_ratio(); the turbulence bank set's selector classifies the
// air by it, turbulence_bank_set.h): the same per-update x = min_k q_k / m, unclipped,
// averaged from the start or reset() on as
//     ρ̄ ← ρ̄ + a_i (x − ρ̄),   a_i = max(1 / i, α)   (i: updates averaged since the reset)
// i.e. a plain mean over the first τ f updates, then ρ's average over τ: right within a second
// of a start, where ρ starts at ρ_0 and only the likelihoods' tempering wants that. 0 before
// the first update. It leaves s and the likelihoods alone.
// Off (enabled = false, the default) the bank computes exactly what it did without it
// (l_k = −q_k/2): bit-identical results.
//
// Cost per frame: a minimum over K, two multiply-adds, a division, a clamp, K multiplies; no
// allocation (per channel: one A⁻¹ r product, m recursions and m square roots, and in the
// bank one extra m×m quadratic form per filter; m logarithms and exponentials). (ρ̄'s 1 / i is divided only over its first τ f updates: running_mean.h.)
// Throws: configure() throws std::invalid_argument naming the option and its valid range.
#pragma once

#include "f16mmae/estimator_settings.h"
#include "f16mmae/running_mean.h"

#include <Eigen/Dense>

#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

namespace f16mmae {

// alignas(16), 128 bytes: it sits inside FilterBankOptions, the first member of the banks, and
// a shift of the banks' Eigen members by other than a multiple of 16 bytes changes Eigen's
// alignment peeling, hence the rounding of the blend: "off" would not be bit-identical.
struct alignas(16) TurbulenceAdaptationOptions {
  bool enabled = false;          // off: the bank as designed (bit-identical)
  bool own_channels = false;     // ρ from min_k q_k / m_k, m_k the channels filter k reads (header)
  bool running_start = false;    // ρ (and ρ_j) the running mean of x until the average's length (header)
  bool level_scale = false;      // at level 1: l_k += (n / 2) ln s, n the presumed failure's level channels k reads (filter_bank.h)
  std::uint32_t counted_channels = 0;   // own_channels: uninformative channels still counted in m_k (bit j: z_j)
  double channel_weight = 0.0;   // γ: a scale s_j per measurement channel (header); 0: one s
  double time_constant_s = 5.0;  // τ of the residual-power average (tuned with κ, s_max)
  double scale_min = 1.0;        // s_min: the design's A_k are the floor
  double scale_max = 100.0;      // s_max
  double gain = 20.0;            // κ, gain on the excess residual power
  double reference = 0.6;        // ρ_0, the power ratio above which tempering starts
  double frame_rate_hz = 64.0;   // f (the hierarchical bank sets its ModelBank's)
  double hypothesis_weight = 1.0;        // w: the best-fitting failure hypothesis' share of s − 1 (header); 1: off
  std::uint32_t full_tempering = 0;      // bit k: hypothesis k keeps the full s under hypothesis_weight
  bool spare_margin = false;             // the spared evidence over min(q_0, q_f: f fully tempered) (header)
  std::uint32_t spare_margin_over = 0;   // with spare_margin, bit k: q_k in q_r's min (header); 0: full_tempering's
  std::uint32_t excluded_channels = 0;  // hypotheses reading these channels as a free level leave the minimum (bit j: z_j)
  std::uint32_t level_scale_channels = 0;  // at every level: l_k += (n / 2) ln max(s / s_0, 1), n of these level channels k reads (filter_bank.h)
  double spare_rho = 0.0;                // ρ_s: the sparing only while ρ̄ >= ρ_s (header); 0: at any ρ̄
  double level_scale_from = 1.0;         // s_0 of level_scale_channels (filter_bank.h); 1: (n / 2) ln s
  double floor_time_constant_s = 0.0;    // τ_L of the lull floor's long average ρ_L (header); 0: off
  double rough_rho = 0.0;                // ρ_r: the air reads rough while ρ_a >= σ ρ_r (header)
  double rough_weight = 1.0;             // w_r: rough_tempering's share of s − 1 in rough air (header); 1: the full s
  std::uint32_t rough_tempering = 0;     // bit k: hypothesis k's share is w_r in rough air (header); 0: none
  double scale_max_from = 0.0;           // ρ_c: from ρ/σ = ρ_c on, s_max rises at κ (header); 0: off
};

// Throws std::invalid_argument "<who>: <option> must be <range>, got <value>".
static_assert(sizeof(TurbulenceAdaptationOptions) % 16 == 0, "see the comment on TurbulenceAdaptationOptions");

inline void check_adaptation(const TurbulenceAdaptationOptions& o, const std::string& who) {
  const auto refuse = [&](const char* what, const std::string& range, double v) {
    throw std::invalid_argument(who + ": " + what + " must be " + range + ", got " + format_value(v));
  };
  if (!(o.time_constant_s > 0.0 && o.time_constant_s <= 3600.0))
    refuse("adapt_time_constant_s", "in (0, 3600] s", o.time_constant_s);
  if (!(o.scale_min > 0.0 && std::isfinite(o.scale_min))) refuse("adapt_scale_min", "positive and finite", o.scale_min);
  if (!(o.scale_max >= o.scale_min && std::isfinite(o.scale_max)))
    refuse("adapt_scale_max", "finite and >= adapt_scale_min = " + format_value(o.scale_min), o.scale_max);
  if (!(o.gain > 0.0 && o.gain <= 1000.0)) refuse("adapt_gain", "in (0, 1000]", o.gain);
  if (!(o.reference >= 0.0 && o.reference <= 100.0)) refuse("adapt_reference", "in [0, 100]", o.reference);
  if (!(o.channel_weight >= 0.0 && o.channel_weight <= 1.0)) refuse("adapt_channel_weight", "in [0, 1]", o.channel_weight);
  if (!(o.hypothesis_weight > 0.0 && o.hypothesis_weight <= 1.0))
    refuse("adapt_hypothesis_weight", "in (0, 1]", o.hypothesis_weight);
  if (!(o.spare_rho >= 0.0 && o.spare_rho <= 100.0)) refuse("adapt_spare_rho", "in [0, 100]", o.spare_rho);
  if (!(o.rough_rho >= 0.0 && o.rough_rho <= 100.0)) refuse("adapt_rough_rho", "in [0, 100]", o.rough_rho);
  if (!(o.rough_weight > 0.0 && o.rough_weight <= 1.0)) refuse("adapt_rough_weight", "in (0, 1]", o.rough_weight);
  if (!(o.scale_max_from >= 0.0 && o.scale_max_from <= 100.0))
    refuse("adapt_scale_max_from", "in [0, 100] (0: off)", o.scale_max_from);
  if (!(o.level_scale_from >= 1.0 && o.level_scale_from <= 1000.0))
    refuse("adapt_level_scale_from", "in [1, 1000]", o.level_scale_from);
  if (!(o.floor_time_constant_s == 0.0 ||
        (o.floor_time_constant_s >= o.time_constant_s && o.floor_time_constant_s <= 3600.0)))
    refuse("adapt_floor_time_constant_s", "0 (off) or in [adapt_time_constant_s = " + format_value(o.time_constant_s) +
           ", 3600] s", o.floor_time_constant_s);
  if (o.hypothesis_weight < 1.0 && o.channel_weight > 0.0)
    throw std::invalid_argument(who + ": adapt_hypothesis_weight below 1 needs the common scale (adapt_channel_weight 0), got " +
                                format_value(o.channel_weight));
  check_frame_rate(o.frame_rate_hz, who);
}

// The scale estimator of the header's equations for a bank of K hypotheses and NZ
// measurements (Eigen::Dynamic or fixed; K types the quadratic forms observed, NZ the
// channels' scales).
template <int K, int NZ = Eigen::Dynamic>
class ResidualScale {
 public:
  using PVector = Eigen::Matrix<double, K, 1>;
  using ZVector = Eigen::Matrix<double, NZ, 1>;
  using AMatrix = Eigen::Matrix<double, NZ, NZ>;

  // Validates and sets the options for nz measurements; resets.
  void configure(const TurbulenceAdaptationOptions& o, int nz, const std::string& who) {
    check_adaptation(o, who);
    options_ = o;
    nz_ = static_cast<double>(nz);
    alpha_ = 1.0 - std::exp(-1.0 / (o.time_constant_s * o.frame_rate_hz));
    alpha_floor_ = o.floor_time_constant_s > 0.0 ? 1.0 - std::exp(-1.0 / (o.floor_time_constant_s * o.frame_rate_hz)) : 0.0;
    long_length_ = alpha_floor_ > 0.0 ? running_mean_length(alpha_floor_) : 0;
    long_min_ = static_cast<std::int64_t>(std::lround(0.5 * o.floor_time_constant_s * o.frame_rate_hz));
    rho_clip_ = 10.0 * o.scale_max;
    mean_length_ = running_mean_length(alpha_);
    channel_rho_.setZero(nz);
    channel_updates_.setZero(nz);
    channel_inv_sqrt_s_.setOnes(nz);
    reset();
  }
  bool enabled() const noexcept { return options_.enabled; }
  bool per_channel() const noexcept { return options_.enabled && options_.channel_weight > 0.0; }
  bool per_hypothesis() const noexcept { return options_.enabled && options_.hypothesis_weight < 1.0; }
  // The per-hypothesis tempering in force for the next frame (header): on, s > 1, ρ >= ρ̄ / 2
  // and ρ̄ >= ρ_s.
  bool spares() const noexcept {
    return per_hypothesis() && s_ > 1.0 && rho_ >= 0.5 * measured_ && measured_ >= power_scale_ * options_.spare_rho;
  }
  // F(ρ_a) of the header's per-hypothesis form: the bits of the hypotheses kept at the full s
  // this frame (full_tempering, with rough_tempering's while ρ_a >= σ ρ_r).
  std::uint32_t fully_tempered() const noexcept {
    return options_.full_tempering | (options_.rough_weight >= 1.0 ? rough_in_force() : 0u);
  }
  // The rough-air hypotheses spared by w_r < 1 in place of w this frame (header; 0 with w_r = 1).
  std::uint32_t rough_spared() const noexcept { return options_.rough_weight < 1.0 ? rough_in_force() : 0u; }
  // rough_tempering's bits while ρ_a >= σ ρ_r, else 0.
  std::uint32_t rough_in_force() const noexcept {
    return options_.rough_tempering != 0u && air_power_ratio() >= power_scale_ * options_.rough_rho
               ? options_.rough_tempering : 0u;
  }
  // s / (1 + w_r (s − 1)): the rough-air share's ratio (1 when off).
  double rough_scale_ratio() const noexcept {
    return per_hypothesis() ? s_ / (1.0 + options_.rough_weight * (s_ - 1.0)) : 1.0;
  }
  // s_b = 1 + w (s − 1) of the header's per-hypothesis form, as the ratio s / s_b (1 when off).
  double hypothesis_scale_ratio() const noexcept {
    return per_hypothesis() ? s_ / (1.0 + options_.hypothesis_weight * (s_ - 1.0)) : 1.0;
  }
  // ρ_j and s_j^−½ of the header's per-channel form (ρ_0 and 1 when it is off).
  const ZVector& channel_power_ratios() const noexcept { return channel_rho_; }
  const ZVector& channel_inverse_sqrt_scales() const noexcept { return channel_inv_sqrt_s_; }
  const TurbulenceAdaptationOptions& options() const noexcept { return options_; }
  // s, the scale in force for the next frame's likelihoods (1 when disabled).
  double scale() const noexcept { return options_.enabled ? s_ : 1.0; }
  double inverse_scale() const noexcept { return options_.enabled ? inv_s_ : 1.0; }
  // s at another reference: clamp(1 + κ (ρ/σ − reference), s_min, s_max, raised past the knee) with
  // the ρ in force (1 when disabled); the air-data gates' gust scale (hierarchical_bank.h) reads it
  // at the base reference.
  double scale_at(double reference) const noexcept {
    return options_.enabled ? clamped_scale(rho_, reference) : 1.0;
  }
  // ρ, the averaged residual power ratio (ρ_0 at the start and when disabled).
  double power_ratio() const noexcept { return rho_; }
  // ρ̄, the measured residual power ratio (header; 0 before the first update and when disabled).
  double measured_power_ratio() const noexcept { return measured_; }
  // The air's power ratio: ρ̄, or the larger of ρ̄ and the lull floor's ρ_L once that is in force
  // (τ_L / 2 after the start; held or not): the rough-air floor's measure (rough_air_floor.h).
  double air_power_ratio() const noexcept {
    return alpha_floor_ > 0.0 && long_updates_ >= long_min_ && rho_long_ > measured_ ? rho_long_ : measured_;
  }

  // One accepted update's quadratic forms (non-finite ones are skipped; a frame with none
  // finite leaves ρ as it was).
  void observe(const PVector& q) noexcept {
    if (!options_.enabled) return;
    double lo = std::numeric_limits<double>::infinity();
    for (int i = 0; i < q.size(); ++i)
      if (q(i) < lo) lo = q(i);   // NaN compares false: skipped
    if (!(lo < std::numeric_limits<double>::infinity())) return;
    at_start_ = false;
    const double x = lo / nz_;
    // a_i = max(1 / i, alpha): 1 / i for i <= mean_length_, alpha from there on (running_mean.h)
    const double a = measured_updates_ < mean_length_ ? 1.0 / static_cast<double>(++measured_updates_) : alpha_;
    const double target = x < rho_clip_ ? x : rho_clip_;
    rho_ += (rho_running_ ? a : alpha_) * (target - rho_);
    if (alpha_floor_ > 0.0 && !floor_held_)   // the lull floor's ρ_L (header): a plain mean first, then α_L
      rho_long_ += (long_updates_ < long_length_ ? 1.0 / static_cast<double>(++long_updates_) : alpha_floor_) *
                   (target - rho_long_);
    measured_ += a * (x - measured_);
    set_scale();
  }
  // Per channel (per_channel()): the best-fitting filter's residual r and A⁻¹ (header: k*);
  // channels whose A⁻¹ diagonal is zero are left as they were. Call after observe(q).
  template <class R>
  void observe_channels(const Eigen::MatrixBase<R>& r, const AMatrix& a_inv) noexcept {
    if (!per_channel()) return;
    for (Eigen::Index j = 0; j < channel_rho_.size(); ++j) {
      if (a_inv(j, j) == 0.0) continue;
      const double c = r(j) * a_inv.row(j).dot(r);
      if (!(c == c)) continue;   // NaN: skipped
      double a = alpha_;   // the running start's a_i, counted per channel (a channel k* leaves out is not observed)
      if (rho_running_ && channel_updates_(j) < static_cast<double>(mean_length_)) a = 1.0 / ++channel_updates_(j);
      channel_rho_(j) += a * ((c < rho_clip_ ? c : rho_clip_) - channel_rho_(j));
    }
    set_channel_scales();
  }
  // A new reference ρ_0 (a scheduled bank's per-node reference, bank_schedule.h; in
  // [0, 100], checked where it is read), ρ kept: s follows at once. Before the first update
  // since the start or reset() (and before set_power_ratio) ρ and ρ_j move to σ times it (header).
  void set_reference(double reference) noexcept {
    options_.reference = reference;
    if (at_start_) {
      rho_ = power_scale_ * reference;
      channel_rho_.setConstant(rho_);
    }
    set_scale();
    set_channel_scales();
  }
  // ρ set to a given value (a bank taking over in known turbulence: turbulence_bank_set.h); s
  // follows at once, ρ̄ is left alone. Non-finite or negative values are ignored.
  void set_power_ratio(double rho) noexcept {
    if (!(rho >= 0.0 && rho < std::numeric_limits<double>::infinity())) return;
    rho_ = rho;
    rho_long_ = rho;
    long_updates_ = long_length_;   // a known ρ: the floor in force, its average going on from it
    rho_running_ = false;   // a known ρ: the average goes on from it
    at_start_ = false;
    channel_rho_.setConstant(rho);
    set_scale();
    set_channel_scales();
  }
  // The power scale σ (header; > 0, checked where it is read), ρ kept: s follows at once. Before
  // the first update since the start or reset() (and before set_power_ratio) ρ and ρ_j move to
  // σ ρ_0.
  void set_power_scale(double sigma) noexcept {
    power_scale_ = sigma;
    if (at_start_) {
      rho_ = sigma * options_.reference;
      channel_rho_.setConstant(rho_);
    }
    set_scale();
    set_channel_scales();
  }
  double power_scale() const noexcept { return power_scale_; }
  // The lull floor held (header): while held, ρ_L keeps its value and s reads ρ alone; s follows
  // at once. Released by the caller, and by reset().
  void hold_floor(bool held) noexcept {
    if (held == floor_held_) return;
    floor_held_ = held;
    set_scale();
    set_channel_scales();
  }
  bool floor_held() const noexcept { return floor_held_; }
  // Back to the start: ρ = σ ρ_0, s = clamp(1, s_min, s_max); ρ̄ restarts (0, no update averaged).
  void reset() noexcept {
    rho_ = power_scale_ * options_.reference;
    long_updates_ = 0;   // ρ_L: its first update replaces whatever it held
    floor_held_ = false;
    rho_running_ = options_.running_start;
    at_start_ = true;
    measured_ = 0.0;
    measured_updates_ = 0;
    channel_rho_.setConstant(rho_);
    channel_updates_.setZero();
    set_scale();
    set_channel_scales();
  }

 private:
  double clamped_scale(double rho) const noexcept { return clamped_scale(rho, options_.reference); }
  double clamped_scale(double rho, double reference) const noexcept {
    const double x = rho / power_scale_, s = 1.0 + options_.gain * (x - reference);
    const double knee = options_.scale_max_from, top = options_.scale_max +
        (knee > 0.0 && x > knee ? options_.gain * (x - knee) : 0.0);   // the bound's knee (header)
    return s < options_.scale_min ? options_.scale_min : (s > top ? top : s);
  }
  void set_scale() noexcept {
    const bool floored = alpha_floor_ > 0.0 && !floor_held_ && long_updates_ >= long_min_ && rho_long_ > rho_;
    s_ = clamped_scale(floored ? rho_long_ : rho_);   // the lull floor (header)
    inv_s_ = 1.0 / s_;
  }
  void set_channel_scales() noexcept {
    if (!per_channel()) return;
    const double g = options_.channel_weight, common = (1.0 - g) * std::log(s_);
    for (Eigen::Index j = 0; j < channel_rho_.size(); ++j)   // (s^(1−γ) s'_j^γ)^−½
      channel_inv_sqrt_s_(j) = std::exp(-0.5 * (common + g * std::log(clamped_scale(channel_rho_(j)))));
  }

  TurbulenceAdaptationOptions options_{};
  double alpha_floor_ = 0.0, rho_long_ = 1.0;   // the lull floor's α_L and ρ_L (header)
  bool floor_held_ = false;                      // hold_floor (header)
  std::int64_t long_updates_ = 0, long_length_ = 0, long_min_ = 0;   // ρ_L's i, its mean's length, τ_L f / 2
  double nz_ = 1.0, alpha_ = 0.0, rho_clip_ = 0.0, rho_ = 1.0, s_ = 1.0, inv_s_ = 1.0, measured_ = 0.0;
  double power_scale_ = 1.0;            // σ (header)
  std::int64_t measured_updates_ = 0;   // i of the header's ρ̄, counted up to mean_length_
  std::int64_t mean_length_ = 1;        // running_mean_length(alpha_) (running_mean.h)
  bool rho_running_ = false;            // running_start and ρ not set since the start (set_power_ratio)
  bool at_start_ = true;                // no update averaged and ρ not set since the start: set_reference moves ρ
  ZVector channel_rho_ = ZVector::Constant(NZ == Eigen::Dynamic ? 0 : NZ, 1.0);          // ρ_j
  ZVector channel_inv_sqrt_s_ = ZVector::Constant(NZ == Eigen::Dynamic ? 0 : NZ, 1.0);   // s_j^−½
  ZVector channel_updates_ = ZVector::Zero(NZ == Eigen::Dynamic ? 0 : NZ);              // the running start's i per channel
};

}  // namespace f16mmae
