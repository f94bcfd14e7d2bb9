#include "bank_settings.h"

#include <cctype>
#include <cstdlib>
#include <stdexcept>

namespace f16mmae::daemon {

namespace {

// A small JSON reader for what bank_estimator_settings needs: walks one object, skipping the
// values it does not want. Any syntax error throws Malformed.
struct Malformed {};

class Scanner {
 public:
  explicit Scanner(const std::string& s) : s_(s) {}

  void ws() {
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_]))) ++i_;
  }
  char peek() {
    ws();
    if (i_ >= s_.size()) throw Malformed{};
    return s_[i_];
  }
  void expect(char c) {
    if (peek() != c) throw Malformed{};
    ++i_;
  }
  bool at_end() {
    ws();
    return i_ >= s_.size();
  }
  std::string string() {
    expect('"');
    std::string out;
    while (true) {
      if (i_ >= s_.size()) throw Malformed{};
      const char c = s_[i_++];
      if (c == '"') return out;
      if (c == '\\') {
        if (i_ >= s_.size()) throw Malformed{};
        const char e = s_[i_++];
        if (e == 'u') {
          if (i_ + 4 > s_.size()) throw Malformed{};
          i_ += 4;
          out += '?';  // keys we look for are ASCII
        } else {
          out += e;
        }
      } else {
        out += c;
      }
    }
  }
  bool number(double& x) {
    const char c = peek();
    if (!(c == '-' || std::isdigit(static_cast<unsigned char>(c)))) return false;
    const char* begin = s_.c_str() + i_;
    char* end = nullptr;
    x = std::strtod(begin, &end);
    if (end == begin) throw Malformed{};
    i_ += static_cast<std::size_t>(end - begin);
    return true;
  }
  void skip_value() {
    const char c = peek();
    if (c == '"') {
      string();
    } else if (c == '{' || c == '[') {
      const char close = c == '{' ? '}' : ']';
      ++i_;
      if (peek() == close) {
        ++i_;
        return;
      }
      while (true) {
        if (c == '{') {
          string();
          expect(':');
        }
        skip_value();
        if (peek() == ',') {
          ++i_;
          continue;
        }
        expect(close);
        return;
      }
    } else {
      double x;
      if (number(x)) return;
      for (const char* word : {"true", "false", "null"}) {
        const std::string w(word);
        if (s_.compare(i_, w.size(), w) == 0) {
          i_ += w.size();
          return;
        }
      }
      throw Malformed{};
    }
  }
  std::size_t pos() const { return i_; }
  void set_pos(std::size_t p) { i_ = p; }

 private:
  const std::string& s_;
  std::size_t i_ = 0;
};

// Calls on_member(key, scanner) for each member of the object at the scanner's position;
// on_member must consume the value.
template <class F>
void each_member(Scanner& sc, F&& on_member) {
  sc.expect('{');
  if (sc.peek() == '}') {
    sc.expect('}');
    return;
  }
  while (true) {
    const std::string key = sc.string();
    sc.expect(':');
    on_member(key, sc);
    if (sc.peek() == ',') {
      sc.expect(',');
      continue;
    }
    sc.expect('}');
    return;
  }
}

}  // namespace

EstimatorSettings bank_estimator_settings(const std::string& metadata_json) {
  EstimatorSettings out;
  Scanner sc(metadata_json);
  try {
    if (sc.at_end() || sc.peek() != '{') return out;
    EstimatorSettings found;
    each_member(sc, [&](const std::string& key, Scanner& s) {
      if (key != "estimator" || s.peek() != '{') {
        s.skip_value();
        return;
      }
      each_member(s, [&](const std::string& k, Scanner& v) {
        std::optional<double>* slot = k == "p_min" ? &found.p_min
                                      : k == "threshold" ? &found.threshold
                                      : k == "dwell_s" ? &found.dwell_s : nullptr;
        if (!slot) {
          v.skip_value();
          return;
        }
        double x;
        if (!v.number(x))
          throw std::invalid_argument("model bank metadata: estimator." + k + " is not a number");
        *slot = x;
      });
    });
    if (!sc.at_end()) return out;  // trailing text: not a JSON document
    out = found;
  } catch (const Malformed&) {
    return EstimatorSettings{};  // not JSON: no recommendation (as json.loads failing in Python)
  }
  return out;
}

}  // namespace f16mmae::daemon
