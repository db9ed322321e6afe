#include "scene/obj_check.h"

#include "scene/scene.h"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <string>
#include <vector>

namespace penumbra {
namespace {

bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

// One line's whitespace-separated tokens, comments cut at '#'. The vector is reused from line
// to line, so splitting allocates only when a line is longer than every one before it.
using Line = std::vector<std::string_view>;

void splitLine(std::string_view line, Line& out) {
  out.clear();
  const size_t hash = line.find('#');
  if (hash != std::string_view::npos) line = line.substr(0, hash);
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && isBlank(line[i])) ++i;
    const size_t start = i;
    while (i < line.size() && !isBlank(line[i])) ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
}

// Joins message pieces (GCC 12 warns, wrongly, about `"'" + std::string(...)` chains).
std::string join(std::initializer_list<std::string_view> parts) {
  std::string out;
  for (std::string_view part : parts) out.append(part);
  return out;
}

// A whole token as a number; a leading '+' is accepted, as C's strtod does.
template <class T>
bool parseWhole(std::string_view token, T& value) {
  if (token.size() > 1 && token[0] == '+' && token[1] != '-') token.remove_prefix(1);
  const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), value);
  return error == std::errc() && end == token.data() + token.size();
}

// Walks the text line by line and reports errors with the file and line number.
class Checker {
 public:
  Checker(std::string_view text, const std::string& file) : text_(text), file_(file) {}

  template <class OnLine>
  void forEachLine(OnLine&& onLine) {
    Line line;
    size_t at = 0;
    while (at <= text_.size()) {
      ++lineNumber_;
      size_t end = text_.find('\n', at);
      if (end == std::string_view::npos) end = text_.size();
      splitLine(text_.substr(at, end - at), line);
      if (!line.empty()) onLine(line);
      at = end + 1;
    }
  }

  [[noreturn]] void fail(const std::string& message) const {
    throw SceneError(join({file_, ":", std::to_string(lineNumber_), ": ", message}));
  }

  static std::string quoted(std::string_view token) {
    constexpr size_t kShown = 40;
    std::string shown(token.substr(0, kShown));
    for (char& c : shown)
      if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) c = '?';
    return join({"'", shown, token.size() > kShown ? "...'" : "'"});
  }

  // The tokens after the statement must be finite numbers (in float range), lo to hi of them.
  void numbers(const Line& line, int lo, int hi, const char* const* fieldNames) const {
    const std::string_view statement = line[0];
    const int given = int(line.size()) - 1;
    if (given < lo || given > hi) {
      const std::string want =
          lo == hi ? std::to_string(lo) : join({std::to_string(lo), " to ", std::to_string(hi)});
      fail(join({"'", statement, "' needs ", want, " numbers, got ", std::to_string(given)}));
    }
    for (int k = 1; k <= given; ++k) {
      const std::string_view token = line[size_t(k)];
      // The message is built only on failure: a mesh has millions of these numbers.
      const auto failField = [&](const char* why) {
        const std::string field = fieldNames && fieldNames[k - 1]
                                      ? std::string(fieldNames[k - 1])
                                      : join({"field ", std::to_string(k)});
        fail(join({"'", statement, "' ", field, ": ", quoted(token), why}));
      };
      std::string_view digits = token;
      if (digits.size() > 1 && digits[0] == '+' && digits[1] != '-') digits.remove_prefix(1);
      double value = 0.0;
      const auto [end, error] =
          std::from_chars(digits.data(), digits.data() + digits.size(), value);
      if (end != digits.data() + digits.size() ||
          (error != std::errc() && error != std::errc::result_out_of_range))
        failField(" is not a number");
      if (error == std::errc::result_out_of_range) failField(" is out of range");
      if (!std::isfinite(value) || std::abs(value) > double(std::numeric_limits<float>::max()))
        failField(" is not a finite number");
    }
  }

  // A non-zero integer index; a negative one must reach back no further than `defined`.
  void index(std::string_view statement, int corner, const char* what, std::string_view token,
             int64_t defined) const {
    int64_t value = 0;
    const auto where = [&] {
      return join({"'", statement, "' corner ", std::to_string(corner), ", ", what, " index "});
    };
    if (!parseWhole(token, value)) fail(join({where(), quoted(token), " is not an integer"}));
    if (value == 0) fail(join({where(), "0: OBJ indices start at 1"}));
    if (value < -defined)
      fail(join({where(), std::to_string(value), " reaches before the first ", what, " (",
                 std::to_string(defined), " defined so far)"}));
  }

  int64_t positions = 0, texcoords = 0, normals = 0;

 private:
  std::string_view text_;
  const std::string& file_;
  int lineNumber_ = 0;
};

void checkCorners(const Checker& c, const Line& line, int minimum) {
  const std::string_view statement = line[0];
  const int corners = int(line.size()) - 1;
  if (corners < minimum)
    c.fail(join({"'", statement, "' needs at least ", std::to_string(minimum), " vertices, got ",
                 std::to_string(corners)}));
  for (int k = 1; k <= corners; ++k) {
    const std::string_view corner = line[size_t(k)];
    const auto bad = [&](const char* why) {
      c.fail(join(
          {"'", statement, "' corner ", std::to_string(k), ": ", Checker::quoted(corner), why}));
    };
    const size_t slash1 = corner.find('/');
    c.index(statement, k, "vertex", corner.substr(0, slash1), c.positions);
    if (slash1 == std::string_view::npos) continue;
    const std::string_view rest = corner.substr(slash1 + 1);
    const size_t slash2 = rest.find('/');
    const std::string_view vt = rest.substr(0, slash2);
    if (!vt.empty()) c.index(statement, k, "texcoord", vt, c.texcoords);
    if (slash2 == std::string_view::npos) {
      if (vt.empty()) bad(" has an empty texcoord index");
      continue;
    }
    const std::string_view vn = rest.substr(slash2 + 1);
    if (vn.find('/') != std::string_view::npos) bad(" has more than three indices");
    if (vn.empty()) bad(" has an empty normal index");
    c.index(statement, k, "normal", vn, c.normals);
  }
}

}  // namespace

std::vector<std::string> checkObjText(std::string_view text, const std::string& file) {
  Checker c(text, file);
  std::vector<std::string> libraries;
  static const char* const kV[] = {"x", "y", "z", nullptr, nullptr, nullptr, nullptr};
  static const char* const kVn[] = {"x", "y", "z"};
  static const char* const kVt[] = {"u", "v", "w"};
  c.forEachLine([&](const Line& line) {
    const std::string_view s = line[0];
    if (s == "v") {
      c.numbers(line, 3, 7, kV);
      ++c.positions;
    } else if (s == "vn") {
      c.numbers(line, 3, 3, kVn);
      ++c.normals;
    } else if (s == "vt") {
      c.numbers(line, 1, 3, kVt);
      ++c.texcoords;
    } else if (s == "f") {
      checkCorners(c, line, 3);
    } else if (s == "l") {
      checkCorners(c, line, 2);
    } else if (s == "p") {
      checkCorners(c, line, 1);
    } else if (s == "s") {
      int64_t group = 0;
      if (line.size() != 2 || (line[1] != "off" && !parseWhole(line[1], group)))
        c.fail("'s' needs one group number or 'off'");
    } else if (s == "mtllib") {
      if (line.size() < 2) c.fail("'mtllib' needs a file name");
      libraries.insert(libraries.end(), line.begin() + 1, line.end());
    } else if (s == "usemtl") {
      if (line.size() < 2) c.fail("'usemtl' needs a material name");
    }
  });
  return libraries;
}

void checkMtlText(std::string_view text, const std::string& file) {
  Checker c(text, file);
  bool inMaterial = false;
  static const char* const kRgb[] = {"r", "g", "b"};
  c.forEachLine([&](const Line& line) {
    const std::string_view s = line[0];
    if (s == "newmtl") {
      if (line.size() < 2) c.fail("'newmtl' needs a material name");
      inMaterial = true;
      return;
    }
    const bool colour = s == "Ka" || s == "Kd" || s == "Ks" || s == "Ke" || s == "Tf";
    const bool scalar = s == "Ns" || s == "Ni" || s == "d" || s == "Tr";
    if (!colour && !scalar && s != "illum") return;
    if (!inMaterial) c.fail(join({"'", s, "' before the first 'newmtl'"}));
    if (colour) {
      c.numbers(line, 3, 3, kRgb);
    } else if (scalar) {
      c.numbers(line, 1, 1, nullptr);
    } else {
      int value = -1;
      if (line.size() != 2 || !parseWhole(line[1], value) || value < 0 || value > 10)
        c.fail("'illum' needs one integer in [0, 10]");
    }
  });
}

}  // namespace penumbra
