// f16mmae.core.FrameAuth: the daemon's message authentication (cpp/daemon/frame_auth.h) for
// the Python ends of the link (`f16mmae hil`, `f16mmae replay`): the same HMAC-SHA256 tag and
// sequence rule, one implementation. The binding keeps the last accepted sequence per channel.
#include <pybind11/pybind11.h>

#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>

#include "daemon/frame_auth.h"

namespace py = pybind11;

namespace f16mmae::bindings {
namespace {

using daemon::FrameAuth;

class PyFrameAuth {
 public:
  explicit PyFrameAuth(FrameAuth auth) : auth_(std::move(auth)) {}

  py::bytes sign(const std::string& channel, const py::bytes& data) {
    std::string buf = data;
    if (!auth_.sign(channel.c_str(), reinterpret_cast<std::uint8_t*>(buf.data()), buf.size()))
      throw py::value_error("a message to sign is at least 48 bytes (its auth trailer is 40), got " +
                            std::to_string(buf.size()));
    return py::bytes(buf);
  }

  std::string check(const std::string& channel, const py::bytes& data) {
    const std::string buf = data;
    std::int64_t& last = last_[channel];
    switch (auth_.check(channel.c_str(), reinterpret_cast<const std::uint8_t*>(buf.data()), buf.size(), last)) {
      case FrameAuth::Check::ok: return "ok";
      case FrameAuth::Check::unauthenticated: return "unauthenticated";
      case FrameAuth::Check::replayed: return "replayed";
    }
    return "unauthenticated";
  }

 private:
  FrameAuth auth_;
  std::map<std::string, std::int64_t> last_;
};

}  // namespace

void bind_frame_auth(py::module_& m) {
  py::class_<PyFrameAuth>(m, "FrameAuth", R"doc(
Authentication of the executive's LCM messages with a pre-shared key (16 to 64 bytes): the
last 40 bytes of every encoded message are its sequence and HMAC-SHA256 tag over the channel
name and the bytes before the tag (cpp/daemon/frame_auth.h).

FrameAuth.from_key_file(path) or FrameAuth(key: bytes); ValueError naming the file or size.
sign(channel, data) -> the message numbered and signed; check(channel, data) -> "ok",
"unauthenticated" (no valid tag) or "replayed" (a sequence not above the last one accepted on
that channel by this object).)doc")
      .def(py::init([](const py::bytes& key) {
             const std::string k = key;
             return new PyFrameAuth(FrameAuth(reinterpret_cast<const std::uint8_t*>(k.data()), k.size()));
           }),
           py::arg("key"))
      .def_static(
          "from_key_file", [](const std::string& path) { return new PyFrameAuth(FrameAuth::from_key_file(path)); },
          py::arg("path"))
      .def("sign", &PyFrameAuth::sign, py::arg("channel"), py::arg("data"))
      .def("check", &PyFrameAuth::check, py::arg("channel"), py::arg("data"));
}

}  // namespace f16mmae::bindings
