// f16mmae.core.ResidualMonitor: the Sec. VII voters on each scalar residual of one filter
// (cpp/f16mmae/residual_monitor.h).
#include <pybind11/pybind11.h>

#include "core_convert.h"
#include "f16mmae/residual_monitor.h"

namespace py = pybind11;

namespace f16mmae::bindings {
namespace {

template <class F>
py::array_t<double> per_channel(const ResidualMonitor& m, F f) {
  Eigen::VectorXd v(m.channels());
  for (int j = 0; j < m.channels(); ++j) v(j) = f(m.channel(j));
  return convert::to_numpy(v);
}

template <class F>
py::array per_channel_flag(const ResidualMonitor& m, F f) {
  py::array_t<bool> out(m.channels());
  for (int j = 0; j < m.channels(); ++j) out.mutable_at(j) = f(m.channel(j));
  return out;
}

}  // namespace

void bind_monitor(py::module_& m) {
  using S = ResidualChannelStatistics;
  py::class_<ResidualMonitor>(m, "ResidualMonitor", R"doc(
Residual monitoring voters (paper Sec. VII) on each scalar residual r_j of one filter, over a
sliding window of the last n <= window_frames frames:

  mean_z            = mean(r) / sqrt(A_jj / n)                 zero-mean test   (N(0,1) if white)
  zero_crossing_z   = (c - (n-1)/2) / sqrt((n-1)/4)             whiteness, c = sign changes
  variance_z        = (mean(r^2)/A_jj - 1) / sqrt(2/n)          variance test against A_jj
  tone_ratio        = |Goertzel X(dither_hz)|^2 / (n A_jj)      dither tone (about Exp(1) if white)

    ResidualMonitor(a_diag, window_frames=64, frame_rate_hz=64.0, dither_hz=0.0,
                    mean_threshold=5.0, zero_crossing_threshold=5.0, variance_threshold=5.0,
                    tone_threshold=14.0)

a_diag (m,): the diagonal of the filter's residual covariance A. A voter votes when
|statistic| exceeds its threshold (tone: tone_ratio > tone_threshold), only once the window is
full; dither_hz = 0 switches the tone test off. update(r (m,)) returns True if any channel
votes; a residual with a non-finite entry is skipped and counted.)doc")
      .def(py::init([](py::handle a_diag, int window_frames, double frame_rate_hz, double dither_hz,
                       double mean_threshold, double zero_crossing_threshold, double variance_threshold,
                       double tone_threshold) {
             ResidualMonitorOptions o;
             o.window_frames = window_frames;
             o.frame_rate_hz = frame_rate_hz;
             o.dither_hz = dither_hz;
             o.mean_threshold = mean_threshold;
             o.zero_crossing_threshold = zero_crossing_threshold;
             o.variance_threshold = variance_threshold;
             o.tone_threshold = tone_threshold;
             return ResidualMonitor(convert::to_vector(a_diag, -1, "a_diag"), o);
           }),
           py::arg("a_diag"), py::kw_only(), py::arg("window_frames") = 64, py::arg("frame_rate_hz") = 64.0,
           py::arg("dither_hz") = 0.0, py::arg("mean_threshold") = 5.0, py::arg("zero_crossing_threshold") = 5.0,
           py::arg("variance_threshold") = 5.0, py::arg("tone_threshold") = 14.0)
      .def(
          "update",
          [](ResidualMonitor& mon, py::handle r) {
            return mon.update(convert::to_vector(r, mon.channels(), "r"));
          },
          py::arg("r"), "Feed one residual vector (m,); returns True if any channel votes.")
      .def("reset", &ResidualMonitor::reset, "Empty the window and zero the counters.")
      .def_property_readonly("mean", [](const ResidualMonitor& m) { return per_channel(m, [](const S& s) { return s.mean; }); })
      .def_property_readonly("mean_z", [](const ResidualMonitor& m) { return per_channel(m, [](const S& s) { return s.mean_z; }); })
      .def_property_readonly("zero_crossing_rate", [](const ResidualMonitor& m) {
        return per_channel(m, [](const S& s) { return s.zero_crossing_rate; });
      })
      .def_property_readonly("zero_crossing_z", [](const ResidualMonitor& m) {
        return per_channel(m, [](const S& s) { return s.zero_crossing_z; });
      })
      .def_property_readonly("variance_ratio", [](const ResidualMonitor& m) {
        return per_channel(m, [](const S& s) { return s.variance_ratio; });
      })
      .def_property_readonly("variance_z", [](const ResidualMonitor& m) {
        return per_channel(m, [](const S& s) { return s.variance_z; });
      })
      .def_property_readonly("tone_ratio", [](const ResidualMonitor& m) {
        return per_channel(m, [](const S& s) { return s.tone_ratio; });
      })
      .def_property_readonly(
          "votes",
          [](const ResidualMonitor& m) {
            py::dict d;
            d["mean"] = per_channel_flag(m, [](const S& s) { return s.mean_vote; });
            d["zero_crossing"] = per_channel_flag(m, [](const S& s) { return s.zero_crossing_vote; });
            d["variance"] = per_channel_flag(m, [](const S& s) { return s.variance_vote; });
            d["tone"] = per_channel_flag(m, [](const S& s) { return s.tone_vote; });
            return d;
          },
          "{'mean', 'zero_crossing', 'variance', 'tone'}: (m,) bool arrays")
      .def_property_readonly("any_vote", &ResidualMonitor::any_vote)
      .def_property_readonly("ready", &ResidualMonitor::ready, "True once the window is full")
      .def_property_readonly("samples", &ResidualMonitor::samples, "samples in the window")
      .def_property_readonly("channels", &ResidualMonitor::channels)
      .def_property_readonly("window_frames", &ResidualMonitor::window)
      .def_property_readonly("frames", &ResidualMonitor::frames)
      .def_property_readonly("skipped_frames", &ResidualMonitor::skipped_frames);
}

}  // namespace f16mmae::bindings
