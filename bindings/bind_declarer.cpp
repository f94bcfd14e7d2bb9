// f16mmae.core.Declarer: hypothesis declaration by threshold and dwell (cpp/f16mmae/declarer.h).
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "core_convert.h"
#include "f16mmae/declarer.h"

namespace py = pybind11;

namespace f16mmae::bindings {

void bind_declarer(py::module_& m) {
  m.def("read_dwell_nats_table", &read_dwell_nats_table, py::arg("path"),
        "The evidence dwell per hypothesis of a table file, {name: N} (cpp/f16mmae/declarer.h: one\n"
        "'NAME N' a line, '#' a comment; N in [0, 1e6] nats). ValueError naming the file and the line.");
  m.def("dwell_nats_table_argument", &dwell_nats_table_argument, py::arg("argument"),
        "The evidence dwell per hypothesis an argument names, {name: N} (cpp/f16mmae/declarer.h): inline\n"
        "'NAME=N[,NAME=N...]' when it holds an '=', else the table file of that path. ValueError naming\n"
        "the entry, or the file and the line.");
  m.def("parse_dwell_s_per_hypothesis", &parse_dwell_s_per_hypothesis, py::arg("text"),
        "The least dwell per hypothesis of 'NAME=S[,NAME=S...]', {name: S} (cpp/f16mmae/declarer.h;\n"
        "S in [0, 60] s). ValueError naming the entry.");
  py::class_<Declarer>(m, "Declarer", R"doc(
Declares hypothesis k when p_k > threshold on round(dwell_s * frame_rate_hz) consecutive
frames (at least one) and k is not already the current hypothesis.

    Declarer(threshold=0.9, dwell_s=0.25, frame_rate_hz=64.0, presumed=0, dwell_nats=0.0)

With dwell_nats > 0 the candidate is also declared once its log-odds above the threshold's,
ln(p/(1-p)) - ln(T/(1-T)), summed over the consecutive frames it has been above, reach
dwell_nats (the evidence dwell; 0: off).

Defaults: 0.9 asks for a clear winner (the floor lets a hypothesis reach 1 - 12 * 0.001 with
13 filters), 0.25 s (16 frames at 64 Hz) rejects single-frame spikes while spending only a
quarter of a 1-s latency budget. Raises ValueError for threshold outside (0.5, 1), a negative
dwell or dwell_nats, or a non-positive frame rate.)doc")
      .def(py::init([](double threshold, double dwell_s, double frame_rate_hz, int presumed, double dwell_nats) {
             DeclarerOptions o;
             o.dwell_nats = dwell_nats;
             o.threshold = threshold;
             o.dwell_s = dwell_s;
             o.frame_rate_hz = frame_rate_hz;
             return Declarer(o, presumed);
           }),
           py::kw_only(), py::arg("threshold") = 0.9, py::arg("dwell_s") = 0.25, py::arg("frame_rate_hz") = 64.0,
           py::arg("presumed") = 0, py::arg("dwell_nats") = 0.0)
      .def(
          "update",
          [](Declarer& d, py::handle p) -> py::object {
            const Eigen::VectorXd v = convert::to_vector(p, -1, "probabilities");
            const int k = d.update(v);
            return k < 0 ? py::object(py::none()) : py::object(py::int_(k));
          },
          py::arg("probabilities"),
          "Feed one frame's probabilities (K,); returns the index declared on this frame, or None.")
      .def("reset", &Declarer::reset, py::arg("presumed") = 0,
           "Start again with hypothesis `presumed` current and no dwell under way.")
      .def_property_readonly("current", &Declarer::current, "index of the presumed or last declared hypothesis")
      .def_property_readonly("candidate", &Declarer::candidate, "index above the threshold now, or -1")
      .def_property_readonly("dwell_count", &Declarer::dwell_count, "consecutive frames above so far")
      .def_property_readonly("dwell_frames", &Declarer::dwell_frames, "frames needed for a declaration")
      .def_property_readonly("dwell_evidence_nats", &Declarer::dwell_evidence_nats,
                             "the candidate's log-odds above the threshold's, summed over its frames so far")
      .def_property_readonly("dwell_nats", [](const Declarer& d) { return d.options().dwell_nats; })
      .def_property_readonly("threshold", [](const Declarer& d) { return d.options().threshold; })
      .def_property_readonly("dwell_s", [](const Declarer& d) { return d.options().dwell_s; })
      .def_property_readonly("frame_rate_hz", [](const Declarer& d) { return d.options().frame_rate_hz; });
}

}  // namespace f16mmae::bindings
