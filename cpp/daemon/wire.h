// The decode step of every message mmae-daemon receives: bytes off the wire -> a message
// struct, or false. One function per message type, so the daemon (LcmNode) and the fuzz
// targets run the same code. A message decodes when LCM's generated decoder accepts it (its
// fingerprint matches and every declared length fits the payload) and it has no bytes left
// over. Allocation-free for the fixed-size frames (sensor, command); noexcept.
#pragma once

#include "f16mmae/lcmt_command_frame.hpp"
#include "f16mmae/lcmt_mmae_reset.hpp"
#include "f16mmae/lcmt_mmae_status.hpp"
#include "f16mmae/lcmt_sensor_frame.hpp"

#include <cstddef>
#include <limits>

namespace f16mmae::daemon {

template <class Message>
bool decode_message(const void* data, std::size_t size, Message& out) noexcept {
  if (data == nullptr || size > static_cast<std::size_t>(std::numeric_limits<int>::max())) return false;
  try {  // the generated decoders of messages with strings may allocate (reset, status)
    return out.decode(data, 0, static_cast<int>(size)) == static_cast<int>(size);
  } catch (...) {
    return false;
  }
}

}  // namespace f16mmae::daemon
