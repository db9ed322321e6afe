// A method's parameters, described once: each entry binds a field of the method's typed
// configuration to its name, label, group, help text, range and choice names. The command
// line's flags, the viewer panel's widgets, the stats JSON and compare's labels are all
// generated from these tables (in the manner of pbrt-v4's ParameterDictionary and yocto-gl's
// label tables), so adding a parameter is one entry in the method's table.
#pragma once

#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

namespace penumbra {

enum class ParamKind {
  Int,
  Float,
  Flag,    // a bool; its command-line flag sets the opposite of the default
  Choice,  // an enum; values 0..n-1 named by `choices`
  FloatList
};

template <typename Config>
struct Param {
  ParamKind kind = ParamKind::Int;
  std::string name;   // --name on the command line (Flag: `flag`), the JSON key with '_'
  std::string label;  // the panel's
  std::string group;  // the command line's section and the panel's tree node
  std::string help;
  double min = 0, max = 0;                // Int, Float, FloatList elements: the accepted range
  bool minOpen = false, maxOpen = false;  // the range excludes min, max
  double uiMin = 0, uiMax = 0;            // the panel slider's range (inside min..max)
  bool logarithmic = false;               // the panel slider's scale
  bool field = false;  // the panel shows a text field, not a slider (a seed, seconds)
  // For a table that serves several commands (the run's shape): a mask of those the entry
  // applies to; ~0: all.
  unsigned scope = ~0u;
  std::vector<std::string> choices;
  std::string flag;  // Flag: e.g. "--no-warping"
  // Int, Float, Flag (0 or 1) and Choice (the index) as a double, which holds them exactly.
  std::function<double(const Config&)> get;
  std::function<void(Config&, double)> set;
  std::function<std::vector<float>(const Config&)> getList;
  std::function<void(Config&, const std::vector<float>&)> setList;

  std::string jsonKey() const {
    std::string key = name;
    for (char& c : key)
      if (c == '-') c = '_';
    return key;
  }
};

// The same parameter on another configuration type: `part(config)` gives the `From` that a
// `To` holds (a base, or a variant's alternative), for const and non-const configurations.
template <typename To, typename From, typename Part>
Param<To> rebindParam(const Param<From>& from, Part part) {
  Param<To> to;
  to.kind = from.kind;
  to.name = from.name;
  to.label = from.label;
  to.group = from.group;
  to.help = from.help;
  to.min = from.min;
  to.max = from.max;
  to.minOpen = from.minOpen;
  to.maxOpen = from.maxOpen;
  to.field = from.field;
  to.scope = from.scope;
  to.uiMin = from.uiMin;
  to.uiMax = from.uiMax;
  to.logarithmic = from.logarithmic;
  to.choices = from.choices;
  to.flag = from.flag;
  if (from.get) to.get = [g = from.get, part](const To& c) { return g(part(c)); };
  if (from.set) to.set = [s = from.set, part](To& c, double v) { s(part(c), v); };
  if (from.getList) to.getList = [g = from.getList, part](const To& c) { return g(part(c)); };
  if (from.setList)
    to.setList = [s = from.setList, part](To& c, const std::vector<float>& v) { s(part(c), v); };
  return to;
}

// The panel's range where it differs from the accepted one.
struct UiRange {
  double min = NAN, max = NAN;
};

template <typename Config>
class ParamTable {
 public:
  // Entries after this belong to `name`.
  ParamTable& group(std::string name) {
    group_ = std::move(name);
    return *this;
  }
  // An int field; integer<uint64_t> for a wider one (whole numbers up to 2^53 pass exactly).
  template <typename Int = int>
  ParamTable& integer(std::string name, std::string label, std::string help,
                      std::type_identity_t<Int>& (*ref)(Config&), double min, double max,
                      UiRange ui = {}) {
    Param<Config> p = start(ParamKind::Int, std::move(name), std::move(label), std::move(help));
    range(p, min, max, ui);
    p.get = [ref](const Config& c) { return double(ref(const_cast<Config&>(c))); };
    p.set = [ref](Config& c, double v) { ref(c) = Int(std::llround(v)); };
    return add(std::move(p));
  }
  // A float field; real<double> for a double.
  template <typename Real = float>
  ParamTable& real(std::string name, std::string label, std::string help,
                   std::type_identity_t<Real>& (*ref)(Config&), double min, double max,
                   UiRange ui = {}, bool logarithmic = false) {
    Param<Config> p = start(ParamKind::Float, std::move(name), std::move(label), std::move(help));
    range(p, min, max, ui);
    p.logarithmic = logarithmic;
    p.get = [ref](const Config& c) { return double(ref(const_cast<Config&>(c))); };
    p.set = [ref](Config& c, double v) { ref(c) = Real(v); };
    return add(std::move(p));
  }
  // `flag` sets the field to the opposite of its default (e.g. --no-warping).
  ParamTable& toggle(std::string name, std::string label, std::string help, std::string flag,
                     bool& (*ref)(Config&)) {
    Param<Config> p = start(ParamKind::Flag, std::move(name), std::move(label), std::move(help));
    p.flag = std::move(flag);
    p.max = p.uiMax = 1;
    p.get = [ref](const Config& c) { return ref(const_cast<Config&>(c)) ? 1.0 : 0.0; };
    p.set = [ref](Config& c, double v) { ref(c) = v != 0; };
    return add(std::move(p));
  }
  template <typename Enum>
  ParamTable& choice(std::string name, std::string label, std::string help, Enum& (*ref)(Config&),
                     std::vector<std::string> names) {
    Param<Config> p = start(ParamKind::Choice, std::move(name), std::move(label), std::move(help));
    p.max = p.uiMax = double(names.size()) - 1;
    p.choices = std::move(names);
    p.get = [ref](const Config& c) { return double(int(ref(const_cast<Config&>(c)))); };
    p.set = [ref](Config& c, double v) { ref(c) = Enum(int(v)); };
    return add(std::move(p));
  }
  ParamTable& list(std::string name, std::string label, std::string help,
                   std::vector<float>& (*ref)(Config&), double min, double max, UiRange ui = {},
                   bool logarithmic = false) {
    Param<Config> p =
        start(ParamKind::FloatList, std::move(name), std::move(label), std::move(help));
    range(p, min, max, ui);
    p.logarithmic = logarithmic;
    p.getList = [ref](const Config& c) { return ref(const_cast<Config&>(c)); };
    p.setList = [ref](Config& c, const std::vector<float>& v) { ref(c) = v; };
    return add(std::move(p));
  }
  // Every entry of `other`, whose configuration is a base of this one; the entries after it
  // join its last group.
  template <typename Base>
  ParamTable& include(const ParamTable<Base>& other) {
    if (!other.params().empty()) group_ = other.params().back().group;
    // A Config is a Base: the accessors take it as it is.
    for (const Param<Base>& b : other.params())
      params_.push_back(rebindParam<Config>(
          b, [](auto& c) -> auto& { return c; }));
    return *this;
  }
  // Every entry of `other`, whose configuration is the member `part(config)` of this one
  // (e.g. a method's filter parameters); they keep their own group.
  template <typename Part, typename Member>
  ParamTable& include(const ParamTable<Part>& other, Member member) {
    for (const Param<Part>& b : other.params()) params_.push_back(rebindParam<Config>(b, member));
    return *this;
  }
  // Modifiers of the last entry: its range excludes min (max); the panel shows a text field;
  // it applies only to the commands of `mask`.
  ParamTable& open(bool min, bool max) {
    params_.back().minOpen = min;
    params_.back().maxOpen = max;
    return *this;
  }
  ParamTable& field() {
    params_.back().field = true;
    return *this;
  }
  ParamTable& scope(unsigned mask) {
    params_.back().scope = mask;
    return *this;
  }
  const std::vector<Param<Config>>& params() const { return params_; }

 private:
  Param<Config> start(ParamKind kind, std::string name, std::string label, std::string help) {
    Param<Config> p;
    p.kind = kind;
    p.name = std::move(name);
    p.label = std::move(label);
    p.help = std::move(help);
    p.group = group_;
    return p;
  }
  static void range(Param<Config>& p, double min, double max, UiRange ui) {
    p.min = min;
    p.max = max;
    p.uiMin = std::isnan(ui.min) ? min : ui.min;
    p.uiMax = std::isnan(ui.max) ? max : ui.max;
  }
  ParamTable& add(Param<Config> p) {
    params_.push_back(std::move(p));
    return *this;
  }
  std::string group_;
  std::vector<Param<Config>> params_;
};

inline std::string formatBound(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

// Whether `v` is in the parameter's accepted range.
template <typename Config>
bool inRange(const Param<Config>& p, double v) {
  return (p.minOpen ? v > p.min : v >= p.min) && (p.maxOpen ? v < p.max : v <= p.max);
}
// The accepted range for messages: "0..1", "(0, 0.5263)", "(0, 1e+06]".
template <typename Config>
std::string rangeText(const Param<Config>& p) {
  if (!p.minOpen && !p.maxOpen) return formatBound(p.min) + ".." + formatBound(p.max);
  std::string text = p.minOpen ? "(" : "[";
  text += formatBound(p.min);
  text += ", ";
  text += formatBound(p.max);
  text += p.maxOpen ? ")" : "]";
  return text;
}
// "--name": how messages name the parameter (a toggle by its flag).
template <typename Config>
std::string flagOf(const Param<Config>& p) {
  return p.kind == ParamKind::Flag && !p.flag.empty() ? p.flag : "--" + p.name;
}

// The value as text: "8", "0.05", "true", "hellinger", "0.1,1,3".
template <typename Config>
std::string formatParam(const Param<Config>& p, const Config& c) {
  char text[32];
  switch (p.kind) {
    case ParamKind::Int:
      return std::to_string(int(p.get(c)));
    case ParamKind::Float:
      std::snprintf(text, sizeof text, "%g", p.get(c));
      return text;
    case ParamKind::Flag:
      return p.get(c) != 0 ? "true" : "false";
    case ParamKind::Choice: {
      const size_t i = size_t(p.get(c));
      return i < p.choices.size() ? p.choices[i] : "?";
    }
    case ParamKind::FloatList: {
      std::string s;
      for (float v : p.getList(c)) {
        std::snprintf(text, sizeof text, "%g", double(v));
        if (!s.empty()) s += ',';
        s += text;
      }
      return s;
    }
  }
  return {};
}

// Sets the parameter from text (a Flag takes true/false/1/0; a list is comma-separated).
// Returns an empty string, or what is wrong, naming the parameter.
template <typename Config>
std::string parseParam(const Param<Config>& p, Config& c, std::string_view text) {
  const std::string what = "--" + p.name + " " + std::string(text);
  auto number = [&](std::string_view t, double& v) {
    const std::string s(t);
    char* end = nullptr;
    v = std::strtod(s.c_str(), &end);
    return !s.empty() && end == s.c_str() + s.size() && std::isfinite(v);
  };
  auto within = [&](double v) {
    return inRange(p, v) ? std::string() : what + ": must be in " + rangeText(p);
  };
  double v = 0;
  switch (p.kind) {
    case ParamKind::Int:
      if (!number(text, v) || v != std::floor(v)) return what + ": expected a whole number";
      if (std::string e = within(v); !e.empty()) return e;
      p.set(c, v);
      return {};
    case ParamKind::Float:
      if (!number(text, v)) return what + ": expected a number";
      if (std::string e = within(v); !e.empty()) return e;
      p.set(c, v);
      return {};
    case ParamKind::Flag:
      if (text == "true" || text == "1")
        p.set(c, 1);
      else if (text == "false" || text == "0")
        p.set(c, 0);
      else
        return what + ": expected true or false";
      return {};
    case ParamKind::Choice:
      for (size_t i = 0; i < p.choices.size(); ++i)
        if (text == p.choices[i]) {
          p.set(c, double(i));
          return {};
        }
      {
        std::string names;
        for (const std::string& n : p.choices) names += (names.empty() ? "" : ", ") + n;
        return what + ": expected one of " + names;
      }
    case ParamKind::FloatList: {
      std::vector<float> values;
      size_t start = text.empty() ? 1 : 0;  // an empty text is an empty list
      while (start <= text.size()) {
        const size_t comma = std::min(text.find(',', start), text.size());
        if (!number(text.substr(start, comma - start), v)) return what + ": expected numbers";
        if (std::string e = within(v); !e.empty()) return e;
        values.push_back(float(v));
        start = comma + 1;
      }
      p.setList(c, values);
      return {};
    }
  }
  return what + ": unknown parameter kind";
}

// Empty when every parameter of `config` is in its table's range, else what is wrong with the
// first that is not, naming its flag: "--gamma 0.6: must be in (0, 0.5263)". The one place the
// ranges are checked: the command line, the panel and the factory all come here.
template <typename Config>
std::string checkParams(const std::vector<Param<Config>>& params, const Config& c) {
  for (const Param<Config>& p : params) {
    if (p.kind == ParamKind::FloatList) {
      for (float v : p.getList(c))
        if (!inRange(p, v))
          return flagOf(p) + " " + formatParam(p, c) + ": each value must be in " + rangeText(p);
    } else if (p.kind == ParamKind::Int || p.kind == ParamKind::Float) {
      if (!inRange(p, p.get(c)))
        return flagOf(p) + " " + formatParam(p, c) + ": must be in " + rangeText(p);
    }
  }
  return {};
}

}  // namespace penumbra
