// f16mmae.core.ModelBank, HypothesisModel, load_bank, save_bank: the model bank and its
// file (cpp/f16mmae/model_bank.h, cpp/bankfile/bank_file.h). Inputs are checked here and
// refused with ValueError naming the argument and the expected shape; file errors become
// FileNotFoundError / OSError, bad file content ValueError. A Python ModelBank is
// immutable: arrays come back as read-only copies, and content_hash (hex SHA-256 of the
// bank's file payload) is computed once, at construction, so it always names the content.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bankfile/bank_file.h"
#include "bankfile/bank_signature.h"
#include "bankfile/schedule_file.h"
#include "f16mmae/bank_schedule.h"
#include "f16mmae/filter_bank.h"
#include "f16mmae/model_bank.h"

namespace py = pybind11;

namespace f16mmae::bindings {
namespace {

using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

std::string shape_of(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

// obj as a C-contiguous float64 array; ValueError unless it holds real numbers.
py::array_t<double> as_float_array(py::handle obj, const std::string& what) {
  const py::array raw = py::array::ensure(obj);
  const char kind = raw ? raw.dtype().kind() : 'O';
  if (kind != 'f' && kind != 'i' && kind != 'u' && kind != 'b')
    throw py::value_error(what + " must be an array of real numbers, got " +
                          (raw ? "dtype " + std::string(py::str(raw.dtype()))
                               : std::string(py::str(py::type::handle_of(obj).attr("__name__")))));
  return py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(raw);
}

Eigen::MatrixXd to_matrix(py::handle obj, const std::string& what) {
  const py::array_t<double> arr = as_float_array(obj, what);
  if (arr.ndim() != 2) throw py::value_error(what + " must be a 2-D array, got shape " + shape_of(arr));
  return Eigen::Map<const RowMajor>(arr.data(), arr.shape(0), arr.shape(1));
}

Eigen::VectorXd to_vector(py::handle obj, const std::string& what) {
  const py::array_t<double> arr = as_float_array(obj, what);
  if (arr.ndim() != 1) throw py::value_error(what + " must be a 1-D array, got shape " + shape_of(arr));
  return Eigen::Map<const Eigen::VectorXd>(arr.data(), arr.shape(0));
}

// A read-only numpy copy: writing to it raises instead of silently changing nothing.
py::array readonly(const Eigen::MatrixXd& m) {
  py::array_t<double> out({m.rows(), m.cols()});
  Eigen::Map<RowMajor>(out.mutable_data(), m.rows(), m.cols()) = m;
  out.attr("flags").attr("writeable") = false;
  return out;
}
py::array readonly(const Eigen::VectorXd& v) {
  py::array_t<double> out(v.size());
  std::copy(v.data(), v.data() + v.size(), out.mutable_data());
  out.attr("flags").attr("writeable") = false;
  return out;
}

std::string fspath(py::handle path) { return py::str(py::module_::import("os").attr("fspath")(path)); }

constexpr const char* kMatrixKeys[] = {"phi", "bd", "h", "k", "a"};

// One hypothesis from a HypothesisModel, or a (name, model) pair whose model is a mapping
// with keys phi, bd, h, k, a or an object with those attributes (e.g. core.FilterModel).
HypothesisModel hypothesis_from(py::handle item, std::size_t index) {
  if (py::isinstance<HypothesisModel>(item)) return item.cast<HypothesisModel>();
  const std::string where = "hypotheses[" + std::to_string(index) + "]";
  if (!(py::isinstance<py::tuple>(item) || py::isinstance<py::list>(item)) || py::len(item) != 2)
    throw py::value_error(where + " must be a core.HypothesisModel or a (name, model) pair, got " +
                          std::string(py::str(py::repr(item))).substr(0, 80));
  const py::sequence pair = py::reinterpret_borrow<py::sequence>(item);
  if (!py::isinstance<py::str>(pair[0])) throw py::value_error(where + ": the name must be a str");
  HypothesisModel h;
  h.name = pair[0].cast<std::string>();
  const py::object model = pair[1];
  const bool mapping = py::hasattr(model, "keys");
  Eigen::MatrixXd* targets[] = {&h.phi, &h.bd, &h.h, &h.k, &h.a};
  for (int i = 0; i < 5; ++i) {
    const char* key = kMatrixKeys[i];
    const bool has = mapping ? model.contains(key) : py::hasattr(model, key);
    if (!has)
      throw py::value_error("hypothesis '" + h.name + "': the model has no '" + key +
                            "' (a model needs phi, bd, h, k, a)");
    const py::object value = mapping ? py::object(model[key]) : py::object(model.attr(key));
    *targets[i] = to_matrix(value, "hypothesis '" + h.name + "': " + key);
  }
  for (const char* wkey : {"uninformative_width", "uninformative_level_q"}) {  // optional
    if (!(mapping ? model.contains(wkey) : py::hasattr(model, wkey))) continue;
    const py::object w = mapping ? py::object(model[wkey]) : py::object(model.attr(wkey));
    if (w.is_none()) continue;
    (std::string(wkey) == "uninformative_width" ? h.uninformative_width : h.uninformative_level_q) =
        to_vector(w, "hypothesis '" + h.name + "': " + wkey);
  }
  return h;
}

// Sets each named hypothesis' recommended evidence dwell N_k from `table` (a mapping name ->
// nats; None: leaves them) after clearing every other one to 0 (the frame dwell alone); a
// name the bank does not hold or an N_k outside [0, kMaxDwellNats] is a ValueError.
void set_dwell_nats(ModelBank& bank, py::handle table) {
  if (table.is_none()) return;
  if (!py::hasattr(table, "items"))
    throw py::value_error("dwell_nats_per_hypothesis must be a mapping name -> nats, got " +
                          std::string(py::str(py::repr(table))).substr(0, 80));
  for (HypothesisModel& h : bank.hypotheses) h.dwell_nats = 0.0;
  for (const auto item : table.attr("items")()) {
    const py::tuple kv = py::reinterpret_borrow<py::tuple>(item);
    if (!py::isinstance<py::str>(kv[0]))
      throw py::value_error("dwell_nats_per_hypothesis: a name must be a str, got " + std::string(py::repr(kv[0])));
    const std::string name = kv[0].cast<std::string>();
    auto it = std::find_if(bank.hypotheses.begin(), bank.hypotheses.end(),
                           [&](const HypothesisModel& h) { return h.name == name; });
    if (it == bank.hypotheses.end())
      throw py::value_error("dwell_nats_per_hypothesis names '" + name + "', not a hypothesis of the bank");
    const double n = kv[1].cast<double>();
    check_dwell_nats(n, "dwell_nats_per_hypothesis '" + name + "'", "N_k");
    it->dwell_nats = n;
  }
}

// The bank's recommended N_k by name, the hypotheses with N_k > 0 only (declarer.h's table).
py::dict dwell_nats_table(const ModelBank& bank) {
  py::dict d;
  for (const HypothesisModel& h : bank.hypotheses)
    if (h.dwell_nats > 0.0) d[py::str(h.name)] = h.dwell_nats;
  return d;
}

std::vector<std::string> names_from(py::handle obj, const char* what) {
  if (py::isinstance<py::str>(obj)) throw py::value_error(std::string(what) + " must be a sequence of str, got a str");
  std::vector<std::string> out;
  for (py::handle n : py::iter(obj)) {
    if (!py::isinstance<py::str>(n))
      throw py::value_error(std::string(what) + " must be a sequence of str, got an entry " +
                            std::string(py::repr(n)));
    out.push_back(n.cast<std::string>());
  }
  return out;
}

ModelBank make_bank(py::handle hypotheses, py::handle state_names, py::handle input_names,
                    py::handle measurement_names, double frame_rate_hz, py::handle u_trim, py::handle z_trim,
                    py::handle h_output, double mach, double alt_ft, const std::string& tuning,
                    double p_min, double threshold, double dwell_s, py::handle dwell_nats_per_hypothesis,
                    py::handle metadata, bool validate) {
  ModelBank bank;
  bank.state_names = names_from(state_names, "state_names");
  bank.input_names = names_from(input_names, "input_names");
  bank.measurement_names = names_from(measurement_names, "measurement_names");
  py::object items = py::reinterpret_borrow<py::object>(hypotheses);
  if (py::isinstance<py::dict>(items)) items = items.attr("items")();
  std::size_t index = 0;
  for (py::handle item : py::iter(items)) bank.hypotheses.push_back(hypothesis_from(item, index++));
  bank.u_trim = u_trim.is_none() ? Eigen::VectorXd::Zero(bank.nu()) : to_vector(u_trim, "u_trim");
  bank.z_trim = z_trim.is_none() ? Eigen::VectorXd::Zero(bank.nz()) : to_vector(z_trim, "z_trim");
  if (!h_output.is_none()) {
    bank.h_output = to_matrix(h_output, "h_output");
  } else if (!bank.hypotheses.empty()) {
    bank.h_output = bank.hypotheses[0].h;  // the unfailed H
  }
  bank.frame_rate_hz = frame_rate_hz;
  bank.mach = mach;
  bank.alt_ft = alt_ft;
  bank.tuning = tuning;
  bank.estimator = EstimatorSettings{p_min, threshold, dwell_s};
  set_dwell_nats(bank, dwell_nats_per_hypothesis);
  if (py::isinstance<py::str>(metadata)) {
    bank.metadata = metadata.cast<std::string>();
  } else {  // a dict: canonical JSON, so equal metadata gives equal bytes and hash
    bank.metadata = py::str(py::module_::import("json").attr("dumps")(metadata, py::arg("sort_keys") = true));
  }
  if (validate) bank.validate();
  bank.content_hash = bank_content_hash(bank);
  return bank;
}

ModelBank bank_from_file_bytes(const py::bytes& data, const std::string& source) {
  const std::string_view view = data;
  return parse_any_bank_file(reinterpret_cast<const std::uint8_t*>(view.data()), view.size(), source);
}

// A BankSchedule from Python: nodes = [(i_mach, i_alt, ModelBank, x_trim[, adapt_reference[, layer[,
// calm_reference[, reference_scale]]]]), ...] (a reference or scale None: not carried).
BankSchedule make_schedule(const std::vector<double>& mach, const std::vector<double>& alt_ft, const py::list& nodes,
                           int primary, const std::string& metadata, int switch_state,
                           const std::vector<double>& switch_thresholds, double start_up_s) {
  BankSchedule s;
  s.start_up_s = start_up_s;
  s.switch_state = switch_state;
  s.switch_thresholds = switch_thresholds;
  s.mach = mach;
  s.alt_ft = alt_ft;
  s.primary = primary;
  s.metadata = metadata;
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    const py::tuple t = nodes[n].cast<py::tuple>();
    if (t.size() < 4 || t.size() > 8)
      throw py::value_error("schedule nodes[" + std::to_string(n) +
                            "] must be (i_mach, i_alt, ModelBank, x_trim[, adapt_reference[, layer[, "
                            "calm_reference[, reference_scale]]]]), got " + std::to_string(t.size()) + " items");
    ScheduleNode node;
    node.i_mach = t[0].cast<int>();
    node.i_alt = t[1].cast<int>();
    node.bank = t[2].cast<ModelBank>();
    node.bank.schedule.reset();
    node.x_trim = to_vector(t[3], "schedule nodes[" + std::to_string(n) + "].x_trim");
    if (t.size() >= 5 && !t[4].is_none()) node.adapt_reference = t[4].cast<double>();
    if (t.size() >= 6) node.layer = t[5].cast<int>();
    if (t.size() >= 7 && !t[6].is_none()) node.calm_reference = t[6].cast<double>();
    if (t.size() == 8 && !t[7].is_none()) node.reference_scale = t[7].cast<double>();
    s.nodes.push_back(std::move(node));
  }
  s.validate();
  return s;
}

// The schedule of a scheduled bank as Python data, or None.
py::object schedule_info(const ModelBank& b) {
  if (!b.schedule) return py::none();
  const BankSchedule& s = *b.schedule;
  py::dict d;
  d["mach"] = py::tuple(py::cast(s.mach));
  d["alt_ft"] = py::tuple(py::cast(s.alt_ft));
  py::list nodes;
  for (const ScheduleNode& n : s.nodes) {
    py::dict e;
    e["i_mach"] = n.i_mach;
    e["i_alt"] = n.i_alt;
    e["mach"] = s.mach[n.i_mach];
    e["alt_ft"] = s.alt_ft[n.i_alt];
    e["bank"] = n.bank;
    e["x_trim"] = readonly(n.x_trim);
    e["layer"] = n.layer;
    e["adapt_reference"] = std::isnan(n.adapt_reference) ? py::object(py::none()) : py::object(py::float_(n.adapt_reference));
    e["calm_reference"] =
        std::isnan(n.calm_reference) ? py::object(py::none()) : py::object(py::float_(n.calm_reference));
    e["reference_scale"] =
        std::isnan(n.reference_scale) ? py::object(py::none()) : py::object(py::float_(n.reference_scale));
    nodes.append(e);
  }
  d["nodes"] = nodes;
  d["primary"] = s.primary;
  d["metadata"] = s.metadata;
  d["switch_state"] = s.switch_state;
  d["switch_thresholds"] = py::tuple(py::cast(s.switch_thresholds));
  d["start_up_s"] = s.start_up_s;
  return d;
}

int index_of(const ModelBank& bank, const std::string& name) {
  const int i = bank.find(name);
  if (i < 0) {
    std::string valid;
    for (const auto& h : bank.hypotheses) valid += (valid.empty() ? "" : ", ") + h.name;
    throw py::key_error("no hypothesis '" + name + "' in the bank; it holds: " + valid);
  }
  return i;
}

// Seconds per frame of F16FilterBank::step over the frames z (N,7), u (N,5), built from the
// bank's first 13 hypotheses and timed in C++ (std::chrono::steady_clock): the frames are
// replayed from a reset bank, pass after pass, for at least min_time_s and 3 passes; the
// result is the fastest pass's time over N (the machine's least-disturbed pass). With
// adapt_turbulence the bank runs its turbulence adaptation (turbulence_adaptation.h, default
// settings, the bank's frame rate). For f16mmae.bench.
double bench_filter_bank_loop(const ModelBank& bank, py::handle z_frames, py::handle u_frames, double min_time_s,
                              bool adapt_turbulence) {
  constexpr int kBank = 13;
  if (bank.hypotheses.size() < kBank || bank.nx() != 13 || bank.nu() != 5 || bank.nz() != 7)
    throw py::value_error("the C++ loop needs an F-16-size bank (>= 13 hypotheses, nx=13, nu=5, nz=7), got " +
                          std::to_string(bank.hypotheses.size()) + " hypotheses, nx=" + std::to_string(bank.nx()) +
                          ", nu=" + std::to_string(bank.nu()) + ", nz=" + std::to_string(bank.nz()));
  const Eigen::MatrixXd z = to_matrix(z_frames, "z"), u = to_matrix(u_frames, "u");
  if (z.cols() != 7 || u.cols() != 5 || z.rows() != u.rows() || z.rows() == 0)
    throw py::value_error("z must be (N, 7) and u (N, 5) with N >= 1, got z " + std::to_string(z.rows()) + "x" +
                          std::to_string(z.cols()) + " and u " + std::to_string(u.rows()) + "x" +
                          std::to_string(u.cols()));
  std::vector<F16FilterModel> models;
  for (int k = 0; k < kBank; ++k) {
    const HypothesisModel& h = bank.hypotheses[k];
    models.push_back(F16FilterModel::from_matrices(h.phi, h.bd, h.h, h.k, h.a, h.uninformative_width,
                                                   h.uninformative_level_q, "hypothesis '" + h.name + "'"));
  }
  FilterBankOptions options;
  options.adaptation.enabled = adapt_turbulence;
  options.adaptation.frame_rate_hz = bank.frame_rate_hz;
  const auto filters = std::make_unique<F16FilterBank>(models, options);
  filters->set_h_output(bank.h_output);
  std::vector<F16FilterBank::ZVector> zs(z.rows());
  std::vector<F16FilterBank::UVector> us(u.rows());
  for (Eigen::Index i = 0; i < z.rows(); ++i) {
    zs[i] = z.row(i).transpose();
    us[i] = u.row(i).transpose();
  }
  py::gil_scoped_release release;
  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  double best_s = std::numeric_limits<double>::infinity(), sink = 0.0;
  for (int pass = 0; pass < 3 || std::chrono::duration<double>(Clock::now() - start).count() < min_time_s; ++pass) {
    filters->reset();
    const Clock::time_point t0 = Clock::now();
    for (std::size_t i = 0; i < zs.size(); ++i) filters->step(zs[i], us[i]);
    const double pass_s = std::chrono::duration<double>(Clock::now() - t0).count();
    best_s = std::min(best_s, pass_s);
    sink += filters->z_hat()(0);
  }
  volatile double keep = sink;  // the work is observable, so it cannot be optimised away
  (void)keep;
  return best_s / static_cast<double>(zs.size());
}

}  // namespace

void bind_model_bank(py::module_& m) {
  py::register_local_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const BankFileNotFound& e) {
      PyErr_SetString(PyExc_FileNotFoundError, e.what());
    } catch (const BankFileIoError& e) {
      PyErr_SetString(PyExc_OSError, e.what());
    }
  });

  py::class_<HypothesisModel>(m, "HypothesisModel", R"doc(
One hypothesis filter of a model bank: a steady-state discrete Kalman filter (paper eqs. 3-5)
  x(t_{i+1}) = phi x(t_i) + bd u(t_i) + w,   z(t_i) = h x(t_i) + v,
with steady-state gain k and residual covariance a = H P- H^T + R.
Shapes: phi (nx,nx), bd (nx,nu), h (nz,nx), k (nx,nz), a (nz,nz); checked by ModelBank.
uninformative_width (nz,) or None: W_j > 0 marks channel j's reading as uninformative under
the hypothesis: an unknown level anywhere in a range of width W_j, a random walk of
uninformative_level_q_j (nz,) or None (zeros: no memory) per frame (its H row must be zero; the likelihood is
derived in cpp/f16mmae/steady_state_filter.h); None means every channel informative.
dwell_nats: the evidence dwell N_k the design recommends for the hypothesis (nats, [0, 1e6];
cpp/f16mmae/declarer.h; 0, the default: the frame dwell alone).
Immutable; the matrices come back as read-only numpy copies.)doc")
      .def(py::init([](const std::string& name, py::handle phi, py::handle bd, py::handle h, py::handle k,
                       py::handle a, py::handle width, py::handle level_q, double dwell_nats) {
             const std::string who = "hypothesis '" + name + "': ";
             HypothesisModel m{name, to_matrix(phi, who + "phi"), to_matrix(bd, who + "bd"),
                               to_matrix(h, who + "h"), to_matrix(k, who + "k"), to_matrix(a, who + "a"), {}};
             if (!width.is_none()) m.uninformative_width = to_vector(width, who + "uninformative_width");
             if (!level_q.is_none())
               m.uninformative_level_q = to_vector(level_q, who + "uninformative_level_q");
             check_dwell_nats(dwell_nats, "hypothesis '" + name + "'");
             m.dwell_nats = dwell_nats;
             return m;
           }),
           py::kw_only(), py::arg("name"), py::arg("phi"), py::arg("bd"), py::arg("h"), py::arg("k"), py::arg("a"),
           py::arg("uninformative_width") = py::none(), py::arg("uninformative_level_q") = py::none(),
           py::arg("dwell_nats") = 0.0)
      .def_property_readonly("name", [](const HypothesisModel& h) { return h.name; })
      .def_property_readonly("dwell_nats", [](const HypothesisModel& h) { return h.dwell_nats; },
                             "recommended evidence dwell N_k, nats (declarer.h; 0: the frame dwell alone)")
      .def_property_readonly("phi", [](const HypothesisModel& h) { return readonly(h.phi); }, "(nx,nx) Phi")
      .def_property_readonly("bd", [](const HypothesisModel& h) { return readonly(h.bd); }, "(nx,nu) B_d")
      .def_property_readonly("h", [](const HypothesisModel& h) { return readonly(h.h); }, "(nz,nx) H")
      .def_property_readonly("k", [](const HypothesisModel& h) { return readonly(h.k); }, "(nx,nz) gain K")
      .def_property_readonly("a", [](const HypothesisModel& h) { return readonly(h.a); },
                             "(nz,nz) residual covariance A (eq. 5)")
      .def_property_readonly(
          "uninformative_width",
          [](const HypothesisModel& h) {
            return readonly(h.uninformative_width.size() ? h.uninformative_width
                                                          : Eigen::VectorXd(Eigen::VectorXd::Zero(h.h.rows())));
          },
          "(nz,) width of each uninformative channel's uniform density, 0 for an informative one")
      .def_property_readonly(
          "uninformative_level_q",
          [](const HypothesisModel& h) {
            return readonly(h.uninformative_level_q.size() ? h.uninformative_level_q
                                                                : Eigen::VectorXd(Eigen::VectorXd::Zero(h.h.rows())));
          },
          "(nz,) random-walk variance per frame of an uninformative channel's level")
      .def("__repr__", [](const HypothesisModel& h) {
        return "HypothesisModel(name='" + h.name + "', nx=" + std::to_string(h.phi.rows()) +
               ", nu=" + std::to_string(h.bd.cols()) + ", nz=" + std::to_string(h.h.rows()) + ")";
      });

  py::class_<ModelBank> bank_class(m, "ModelBank", R"doc(
The model bank: every hypothesis filter, the trim the estimator subtracts (u_trim, z_trim),
h_output (blended state -> z_hat, default: hypothesis 0's H) and the design's flight
condition. Hypothesis 0 must be "NONE". Immutable once built.

hypotheses: a list of core.HypothesisModel, or of (name, model) pairs, or a dict
name -> model, where a model is a mapping with keys phi, bd, h, k, a or an object with
those attributes (e.g. core.FilterModel). u_trim / z_trim default to zeros; metadata is
JSON text or a dict (stored as canonical JSON) describing how the bank was made; p_min,
threshold, dwell_s are the estimator settings the design recommends (typed fields of the
file since format version 2; default the core's); dwell_nats_per_hypothesis, a mapping name ->
N_k (nats), sets the named hypotheses' recommended evidence dwell (HypothesisModel.dwell_nats,
a field of the file since format version 4) and clears the others' to 0; None keeps the
hypotheses' own. validate=True (default) checks the bank
at once (ValueError naming the field or hypothesis and the value: names, settings, flight
condition, shapes, finiteness, symmetric positive-definite A, stable Phi (I - K H));
save() always validates.

content_hash: hex SHA-256 of the bank's file payload; it names the bank in every record.
Files: bank.save(path) / core.save_bank(bank, path), core.load_bank(path) (refuses a
missing, truncated, corrupted, foreign or invalid file with a message naming the problem).)doc");
  bank_class.attr("FORMAT_VERSION") = ModelBank::kFormatVersion;  // the file format this build reads and writes
  bank_class
      .def(py::init(&make_bank), py::arg("hypotheses"), py::kw_only(), py::arg("state_names"),
           py::arg("input_names"), py::arg("measurement_names"), py::arg("frame_rate_hz"),
           py::arg("u_trim") = py::none(), py::arg("z_trim") = py::none(), py::arg("h_output") = py::none(),
           py::arg("mach") = 0.0, py::arg("alt_ft") = 0.0, py::arg("tuning") = "",
           py::arg("p_min") = kDefaultPMin, py::arg("threshold") = kDefaultThreshold,
           py::arg("dwell_s") = kDefaultDwellS, py::arg("dwell_nats_per_hypothesis") = py::none(),
           py::arg("metadata") = "", py::arg("validate") = true)
      .def_property_readonly("hypothesis_names",
                             [](const ModelBank& b) {
                               py::list out;
                               for (const auto& h : b.hypotheses) out.append(h.name);
                               return py::tuple(out);
                             })
      .def_property_readonly("hypotheses", [](const ModelBank& b) { return b.hypotheses; },
                             "list of core.HypothesisModel (copies)")
      .def_property_readonly("state_names", [](const ModelBank& b) { return py::tuple(py::cast(b.state_names)); })
      .def_property_readonly("input_names", [](const ModelBank& b) { return py::tuple(py::cast(b.input_names)); })
      .def_property_readonly("measurement_names",
                             [](const ModelBank& b) { return py::tuple(py::cast(b.measurement_names)); })
      .def_property_readonly("nx", &ModelBank::nx)
      .def_property_readonly("nu", &ModelBank::nu)
      .def_property_readonly("nz", &ModelBank::nz)
      .def_property_readonly("u_trim", [](const ModelBank& b) { return readonly(b.u_trim); }, "(nu,) trim commands")
      .def_property_readonly("z_trim", [](const ModelBank& b) { return readonly(b.z_trim); },
                             "(nz,) trim measurements")
      .def_property_readonly("h_output", [](const ModelBank& b) { return readonly(b.h_output); },
                             "(nz,nx) blended state -> z_hat")
      .def_property_readonly("frame_rate_hz", [](const ModelBank& b) { return b.frame_rate_hz; })
      .def_property_readonly("mach", [](const ModelBank& b) { return b.mach; })
      .def_property_readonly("alt_ft", [](const ModelBank& b) { return b.alt_ft; })
      .def_property_readonly("tuning", [](const ModelBank& b) { return b.tuning; })
      .def_property_readonly("p_min", [](const ModelBank& b) { return b.estimator.p_min; },
                             "recommended probability floor")
      .def_property_readonly("threshold", [](const ModelBank& b) { return b.estimator.threshold; },
                             "recommended declaration threshold")
      .def_property_readonly("dwell_s", [](const ModelBank& b) { return b.estimator.dwell_s; },
                             "recommended declaration dwell, s")
      .def(
          "with_settings",
          [](const ModelBank& b, std::optional<double> p_min, std::optional<double> threshold,
             std::optional<double> dwell_s, py::handle dwell_nats_per_hypothesis) {
            if (b.schedule)
              throw py::value_error("with_settings: a scheduled bank's settings are its nodes' banks' own; "
                                    "design the nodes with them");
            ModelBank out = b;   // a copy with other recommended settings, checked, hashed anew
            if (p_min) out.estimator.p_min = *p_min;
            if (threshold) out.estimator.threshold = *threshold;
            if (dwell_s) out.estimator.dwell_s = *dwell_s;
            set_dwell_nats(out, dwell_nats_per_hypothesis);
            check_settings(out.estimator, static_cast<int>(out.hypotheses.size()), out.frame_rate_hz,
                           "model bank: estimator");
            out.content_hash = bank_content_hash(out);
            return out;
          },
          py::kw_only(), py::arg("p_min") = py::none(), py::arg("threshold") = py::none(),
          py::arg("dwell_s") = py::none(), py::arg("dwell_nats_per_hypothesis") = py::none(),
          "A copy of this (unscheduled) bank recommending other estimator settings (None: this bank's;\n"
          "dwell_nats_per_hypothesis: name -> N_k, the hypotheses it does not name 0);\n"
          "ValueError for a setting outside its range (cpp/f16mmae/estimator_settings.h).")
      .def_property_readonly("estimator_settings",
                             [](const ModelBank& b) {
                               py::dict d;
                               d["p_min"] = b.estimator.p_min;
                               d["threshold"] = b.estimator.threshold;
                               d["dwell_s"] = b.estimator.dwell_s;
                               // a scheduled-bank file's start-up, where it recommends one
                               if (b.estimator.start_up_s > 0.0) d["start_up_s"] = b.estimator.start_up_s;
                               // the recommended evidence dwell, where the bank recommends one (format 4)
                               py::dict table = dwell_nats_table(b);
                               if (!table.empty()) d["dwell_nats_per_hypothesis"] = table;
                               return d;
                             },
                             "the recommended settings as keyword arguments of core.HierarchicalBank\n"
                             "(start_up_s only where the bank recommends a start-up: a scheduled-bank file of format 3;\n"
                             "dwell_nats_per_hypothesis, name -> N_k, only where a hypothesis has N_k > 0: format 4)")
      .def_property_readonly("metadata", [](const ModelBank& b) { return b.metadata; },
                             "JSON text: how the bank was made (provenance only)")
      .def_property_readonly("content_hash", [](const ModelBank& b) { return b.content_hash; },
                             "hex SHA-256 of the bank-file payload")
      .def_property_readonly("schedule", &schedule_info,
                             "None, or for a scheduled bank (bank_schedule.h) a dict: mach, alt_ft (the grid axes),\n"
                             "nodes (list of {i_mach, i_alt, layer, mach, alt_ft, bank, x_trim, adapt_reference (None: not\n"
                             "carried)}), primary (the node this bank is, in force until air data arrives), metadata\n"
                             "(JSON text), switch_state and switch_thresholds (the configuration law; -1 and ()), start_up_s\n"
                             "(the estimator start-up the schedule recommends, s; 0: none)")
      .def("validate", &ModelBank::validate, "Raise ValueError naming the first problem, else return None.")
      .def(
          "save", [](const ModelBank& b, py::handle path) { return save_bank(b, fspath(path)); }, py::arg("path"),
          "Validate, then write the bank file atomically; returns content_hash.")
      .def("to_bytes",
           [](const ModelBank& b) {
             const std::vector<std::uint8_t> image = bank_file_bytes(b);
             return py::bytes(reinterpret_cast<const char*>(image.data()), image.size());
           },
           "The bank file's bytes (validates first).")
      .def_static("from_bytes", &bank_from_file_bytes, py::arg("data"), py::arg("source") = "<bytes>",
                  "Parse and validate a bank file image (as core.load_bank does).")
      .def("index", &index_of, py::arg("name"), "Position of a hypothesis; KeyError listing the names if absent.")
      .def("__len__", [](const ModelBank& b) { return b.hypotheses.size(); })
      .def("__contains__", [](const ModelBank& b, const std::string& name) { return b.find(name) >= 0; })
      .def("__getitem__", [](const ModelBank& b, const std::string& name) { return b.hypotheses[index_of(b, name)]; })
      .def("__getitem__",
           [](const ModelBank& b, py::ssize_t i) {
             const auto n = static_cast<py::ssize_t>(b.hypotheses.size());
             if (i < 0) i += n;
             if (i < 0 || i >= n) throw py::index_error("hypothesis index out of range (bank of " + std::to_string(n) + ")");
             return b.hypotheses[i];
           })
      .def("__eq__", [](const ModelBank& a, const ModelBank& b) { return a.content_hash == b.content_hash; })
      .def("__hash__", [](const ModelBank& b) { return py::hash(py::str(b.content_hash)); })
      .def("__repr__",
           [](const ModelBank& b) {
             return "ModelBank(" + std::to_string(b.hypotheses.size()) + " hypotheses, nx=" + std::to_string(b.nx()) +
                    ", nu=" + std::to_string(b.nu()) + ", nz=" + std::to_string(b.nz()) +
                    ", mach=" + py::str(py::float_(b.mach)).cast<std::string>() +
                    ", alt_ft=" + py::str(py::float_(b.alt_ft)).cast<std::string>() + ", tuning='" + b.tuning +
                    "', content_hash='" + b.content_hash.substr(0, 12) + "...')";
           })
      .def(py::pickle(
          [](const ModelBank& b) {  // a scheduled bank pickles as its whole schedule file
            const std::vector<std::uint8_t> payload = b.schedule ? schedule_file_bytes(*b.schedule) : encode_bank_payload(b);
            return py::bytes(reinterpret_cast<const char*>(payload.data()), payload.size());
          },
          [](const py::bytes& state) {
            const std::string_view view = state;
            const auto* bytes = reinterpret_cast<const std::uint8_t*>(view.data());
            if (is_schedule_file(bytes, view.size())) return parse_schedule_file(bytes, view.size(), "<pickle>");
            return decode_bank_payload(bytes, view.size());
          }));

  m.def(
      "load_bank",
      [](py::handle path, py::handle public_key) {
        return public_key.is_none() ? load_bank(fspath(path)) : load_signed_bank(fspath(path), fspath(public_key));
      },
      py::arg("path"), py::kw_only(), py::arg("public_key") = py::none(),
      "Read a model-bank file: checks magic, version, size and SHA-256, decodes and validates it.\n"
      "With public_key (a 32-byte Ed25519 key file), first verifies the signature PATH.sig over the\n"
      "file's bytes. FileNotFoundError if absent, OSError if unreadable or not a regular file,\n"
      "ValueError naming what is wrong (a bad signature included).");
  m.def(
      "save_schedule",
      [](const std::vector<double>& mach, const std::vector<double>& alt_ft, const py::list& nodes, int primary,
         const std::string& metadata, py::handle path, int switch_state, const std::vector<double>& switch_thresholds,
         double start_up_s) {
        return save_schedule(
            make_schedule(mach, alt_ft, nodes, primary, metadata, switch_state, switch_thresholds, start_up_s),
            fspath(path));
      },
      py::arg("mach"), py::arg("alt_ft"), py::arg("nodes"), py::kw_only(), py::arg("primary"),
      py::arg("metadata") = "", py::arg("path"), py::arg("switch_state") = -1,
      py::arg("switch_thresholds") = std::vector<double>{}, py::arg("start_up_s") = 0.0,
      "Write a scheduled-bank file (cpp/bankfile/schedule_file.h) atomically; returns its content hash.\n"
      "mach, alt_ft: the ascending grid axes; nodes: [(i_mach, i_alt, ModelBank, x_trim (nx,)[, adapt_reference\n"
      "[, layer[, calm_reference[, reference_scale]]]]), ...], one per covered grid point and layer (adapt_reference: the turbulence\n"
      "adaptation's rho_0 at the node, given for every node or for none, None: not carried; layer: the configuration\n"
      "layer, 0 by default; calm_reference: the measured rho-bar midway between the node's calm and light air,\n"
      "calm_air_complete.h, every node or none; reference_scale: the node's power ratio over its complete-model\n"
      "bank's, which the estimator divides its power ratio by, bank_schedule.h, every node or none); switch_state, switch_thresholds: the configuration law\n"
      "(bank_schedule.h; -1 and none: one layer); primary: the node in force before air data; start_up_s: the\n"
      "estimator start-up the schedule recommends, s (0: none). Written as format 5 with reference scales, else 4 with calm references, else 3 with a start-up, else 2.\n"
      "ValueError naming the field.\n"
      "core.load_bank reads the file back as the primary node's ModelBank with .schedule set.");
  m.attr("MAX_DWELL_S") = kMaxDwellS;  // the longest declaration dwell the core accepts, s
  m.attr("DEFAULT_THRESHOLD") = kDefaultThreshold;  // the declaration threshold the core defaults to
  m.def(
      "generate_bank_signing_keys",
      [](py::handle public_key, py::handle secret_key) { generate_bank_signing_keys(fspath(public_key), fspath(secret_key)); },
      py::arg("public_key"), py::arg("secret_key"),
      "Write a new Ed25519 key pair for bank signatures: public (32 bytes), secret (64 bytes, mode 0600).");
  m.def(
      "sign_bank_file",
      [](py::handle bank, py::handle secret_key) { sign_bank_file(fspath(bank), fspath(secret_key)); },
      py::arg("bank"), py::arg("secret_key"),
      "Sign a bank file's bytes with an Ed25519 secret key; writes the 64-byte signature to BANK.sig.");
  m.def(
      "save_bank", [](const ModelBank& b, py::handle path) { return save_bank(b, fspath(path)); }, py::arg("bank"),
      py::arg("path"), "Validate the bank and write its file atomically; returns content_hash.");
  m.def("_bench_filter_bank_loop", &bench_filter_bank_loop, py::arg("bank"), py::arg("z"), py::arg("u"),
        py::arg("min_time_s") = 0.2, py::arg("adapt_turbulence") = false,
        "Benchmark: seconds per frame of the fixed-size C++ F16FilterBank.step over frames z (N,7), u (N,5),\n"
        "built from the bank's first 13 hypotheses, timed in C++ (f16mmae.bench); adapt_turbulence: with\n"
        "the turbulence adaptation on.");
}

}  // namespace f16mmae::bindings
