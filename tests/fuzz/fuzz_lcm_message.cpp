// libFuzzer target: one LCM channel of mmae-daemon, through the daemon's own code. The bytes
// are published on an in-process memq:// LCM, and the daemon's LcmNode decodes them and hands
// them to its Executive (shipped tuned bank), exactly as in mmae-daemon; statuses the
// executive publishes are decoded again with the generated lcmt_mmae_status decoder and must
// re-encode to the same bytes. Compiled once per channel (FUZZ_CHANNEL):
//   0 sensor frame   the fuzzed F16_SENSORS message after a valid frame 0
//   1 command frame  the fuzzed F16_COMMANDS message after a valid frame 0, then frame 1
//   2 reset          the fuzzed MMAE_RESET message, then a valid frame 0
//   3 status         the input read as up to 64 sensor frames (7 doubles of z, a byte of
//                    valid flags, a byte of frame step), so hostile values (NaN, Inf, 1e308)
//                    and gaps drive the estimator; every status it publishes must decode to
//                    itself and hold probabilities that are finite, >= p_min and sum to 1
// Each input starts from a reset executive, so every finding reproduces from its input alone.
// A finding is a crash, an AddressSanitizer report, a hang (-timeout), or a status that does
// not decode to itself.
#include <lcm/lcm.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "bankfile/bank_file.h"
#include "daemon/lcm_node.h"
#include "f16mmae/lcmt_command_frame.hpp"
#include "f16mmae/lcmt_mmae_status.hpp"
#include "f16mmae/lcmt_sensor_frame.hpp"

#ifndef FUZZ_CHANNEL
#error "compile with -DFUZZ_CHANNEL=0..3"
#endif

namespace {

using namespace f16mmae;

struct Rig {
  ModelBank bank = load_bank(F16MMAE_SOURCE_DIR "/python/harness/f16mmae/data/nominal_tuned.f16bank");
  executive::Executive exec{bank};
  daemon::Channels channels = daemon::Channels::with_prefix("");
  lcm_t* lcm = lcm_create("memq://");
  daemon::LcmNode node{lcm, channels, exec};
  lcm_subscription_t* status_sub =
      lcm_subscribe(lcm, channels.status.c_str(), &Rig::on_status, this);

  static void on_status(const lcm_recv_buf_t* rbuf, const char*, void* self) {
    lcmt_mmae_status status;
    const int size = static_cast<int>(rbuf->data_size);
    if (status.decode(rbuf->data, 0, size) != size) std::abort();  // the executive's own status
    std::vector<std::uint8_t> again(static_cast<std::size_t>(status.getEncodedSize()));
    if (status.encode(again.data(), 0, static_cast<int>(again.size())) != size ||
        std::memcmp(again.data(), rbuf->data, again.size()) != 0)
      std::abort();
    const double p_min = static_cast<Rig*>(self)->bank.estimator.p_min;
    double sum = 0.0;
    for (double p : status.probabilities) {
      if (!std::isfinite(p) || p < p_min * (1.0 - 1e-9)) std::abort();
      sum += p;
    }
    if (std::abs(sum - 1.0) > 1e-9) std::abort();
  }

  void drain() {
    while (lcm_handle_timeout(lcm, 0) > 0) {
    }
  }
  void publish(const std::string& channel, const void* data, std::size_t size) {
    lcm_publish(lcm, channel.c_str(), data, static_cast<unsigned int>(size));
    drain();
  }
  template <class Msg>
  void publish(const std::string& channel, const Msg& msg) {
    std::vector<std::uint8_t> buf(static_cast<std::size_t>(msg.getEncodedSize()));
    msg.encode(buf.data(), 0, static_cast<int>(buf.size()));
    publish(channel, buf.data(), buf.size());
  }
  void sensor_frame(std::int64_t i) {
    lcmt_sensor_frame f{};
    f.utime = i * 15625;
    f.frame = i;
    for (int k = 0; k < 7; ++k) {
      f.z[k] = bank.z_trim(k);
      f.valid[k] = true;
    }
    publish(channels.sensors, f);
  }
};

Rig& rig() {
  static Rig* r = new Rig;  // never destroyed: libFuzzer exits without unwinding
  return *r;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Rig& r = rig();
  r.exec.on_reset();
  switch (FUZZ_CHANNEL) {
    case 0:
      r.sensor_frame(0);
      r.publish(r.channels.sensors, data, size);
      break;
    case 1:
      r.sensor_frame(0);
      r.publish(r.channels.commands, data, size);
      r.sensor_frame(1);
      break;
    case 2:
      r.publish(r.channels.reset, data, size);
      r.sensor_frame(0);
      break;
    case 3: {
      constexpr std::size_t kRecord = 7 * sizeof(double) + 2;
      lcmt_sensor_frame f{};
      lcmt_command_frame c{};
      for (std::size_t at = 0; at + kRecord <= size && at < 64 * kRecord; at += kRecord) {
        std::memcpy(f.z, data + at, 7 * sizeof(double));
        for (int k = 0; k < 7; ++k) f.valid[k] = (data[at + 56] >> k) & 1;
        f.frame += 1 + data[at + 57] % 4;  // consecutive, or up to 3 frames lost
        f.utime = f.frame * 15625;
        r.publish(r.channels.sensors, f);
        c.frame = f.frame;
        c.utime = f.utime;
        for (int k = 0; k < 5; ++k) c.u_rad[k] = r.bank.u_trim(k);
        r.publish(r.channels.commands, c);
      }
      break;
    }
  }
  return 0;
}
