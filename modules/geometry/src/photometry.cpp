#include "relume/geometry/photometry.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <numbers>

#include "relume/geometry/error.h"

namespace relume {

namespace {

constexpr size_t kMaxAngles = 3601;  // 0.05 degree steps over a half turn: more than any goniophotometer

// A number read whole from `text` (no trailing characters; whatever the process's locale), or false.
bool toNumber(std::string text, double& out, bool decimalComma = false) {
  if (decimalComma) std::replace(text.begin(), text.end(), ',', '.');
  const char* b = text.data();
  const char* e = b + text.size();
  if (b != e && *b == '+') ++b;  // from_chars takes no leading '+'
  if (b == e) return false;
  const auto r = std::from_chars(b, e, out);
  if (r.ec == std::errc::result_out_of_range && r.ptr == e) {  // below the smallest normal double: zero
    out = 0.0;
    return true;
  }
  return r.ec == std::errc() && r.ptr == e && std::isfinite(out);
}

std::string trim(std::string_view s) {
  size_t a = 0, b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
  return std::string(s.substr(a, b - a));
}

std::vector<std::string_view> splitLines(std::string_view bytes) {
  std::vector<std::string_view> lines;
  size_t start = 0;
  for (size_t i = 0; i <= bytes.size(); ++i)
    if (i == bytes.size() || bytes[i] == '\n') {
      std::string_view line = bytes.substr(start, i - start);
      if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
      if (i < bytes.size() || !line.empty()) lines.push_back(line);
      start = i + 1;
    }
  return lines;
}

std::string fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// Index of the last stored angle <= x in ascending `a` (clamped), and the weight of the next.
void bracket(const std::vector<double>& a, double x, size_t& i, double& t) {
  if (a.size() == 1 || !(x > a.front())) {
    i = 0;
    t = 0;
    return;
  }
  if (x >= a.back()) {
    i = a.size() - 1;
    t = 0;
    return;
  }
  i = size_t(std::upper_bound(a.begin(), a.end(), x) - a.begin()) - 1;
  const double span = a[i + 1] - a[i];
  t = span > 0 ? (x - a[i]) / span : 0.0;
}

// Checks what both formats share: angles ascending within range, intensities non-negative, and
// the C range the symmetry needs.
void checkDistribution(const PhotometricDistribution& d, const std::string& file) {
  using S = PhotometricDistribution::Symmetry;
  auto ascending = [&](const std::vector<double>& a, const char* what, double lo, double hi) {
    for (size_t k = 0; k < a.size(); ++k) {
      if (a[k] < lo || a[k] > hi)
        throw Error(file, std::string(what) + " angle " + std::to_string(k + 1),
                    fmt(a[k]) + " degrees is outside " + fmt(lo) + ".." + fmt(hi));
      if (k > 0 && a[k] <= a[k - 1])
        throw Error(file, std::string(what) + " angle " + std::to_string(k + 1),
                    "the angles must increase (" + fmt(a[k - 1]) + " then " + fmt(a[k]) + ")");
    }
  };
  ascending(d.gamma, "vertical", 0.0, 180.0);
  ascending(d.c, "horizontal", 0.0, 360.0);
  const double first = d.c.front(), last = d.c.back();
  auto range = [&](double a, double b, const char* what) {
    if (std::abs(first - a) > 1e-6 || std::abs(last - b) > 1e-6)
      throw Error(file, "horizontal angles",
                  std::string(what) + " needs planes from " + fmt(a) + " to " + fmt(b) + " degrees, the file has " +
                      fmt(first) + " to " + fmt(last));
  };
  switch (d.symmetry) {
    case S::Rotational: break;
    case S::AboutC0C180: range(0, 180, "symmetry about the C0-C180 plane"); break;
    case S::AboutC90C270: range(90, 270, "symmetry about the C90-C270 plane"); break;
    case S::Quadrants: range(0, 90, "symmetry in the four quadrants"); break;
    case S::Full:
      if (first != 0.0) throw Error(file, "horizontal angles", "a full distribution starts at 0 degrees, not " + fmt(first));
      break;
  }
  bool lit = false;
  for (size_t k = 0; k < d.candela.size(); ++k) {
    const std::string where = "intensity " + std::to_string(k + 1) + " (plane " + fmt(d.c[k / d.gamma.size()]) + ", angle " +
                              fmt(d.gamma[k % d.gamma.size()]) + ")";
    if (d.candela[k] < 0.0) throw Error(file, where, "a luminous intensity cannot be negative: " + fmt(d.candela[k]));
    // 1e9 cd is a thousand times the brightest searchlight: beyond it the file's numbers (or its
    // multipliers) are wrong, and products of them would overflow.
    if (!(d.candela[k] <= 1e9)) throw Error(file, where, "a luminous intensity of " + fmt(d.candela[k]) + " cd is beyond any luminaire");
    lit = lit || d.candela[k] > 0.0;
  }
  if (!lit) throw Error(file, "intensities", "every intensity is zero: the luminaire emits nothing");
}

size_t countOf(double v, const std::string& file, const std::string& what, size_t lo, size_t hi) {
  if (!(v >= double(lo) && v <= double(hi)) || v != std::floor(v))
    throw Error(file, what, "must be a whole number from " + std::to_string(lo) + " to " + std::to_string(hi) + ", not " + fmt(v));
  return size_t(v);
}

}  // namespace

double PhotometricDistribution::intensity(double cDegrees, double gammaDegrees) const {
  if (gamma.empty() || c.empty() || candela.size() != c.size() * gamma.size()) return 0.0;
  if (!std::isfinite(cDegrees) || !std::isfinite(gammaDegrees)) return 0.0;
  if (gammaDegrees < gamma.front() - 1e-9 || gammaDegrees > gamma.back() + 1e-9) return 0.0;
  double C = std::fmod(cDegrees, 360.0);
  if (C < 0) C += 360.0;
  switch (symmetry) {
    case Symmetry::Rotational: C = c.front(); break;
    case Symmetry::AboutC0C180:
      if (C > 180.0) C = 360.0 - C;
      break;
    case Symmetry::AboutC90C270:
      if (C < 90.0) C = 180.0 - C;        // 0..90 -> 180..90
      else if (C > 270.0) C = 540.0 - C;  // 270..360 -> 270..180
      break;
    case Symmetry::Quadrants:
      if (C > 180.0) C = 360.0 - C;
      if (C > 90.0) C = 180.0 - C;
      break;
    case Symmetry::Full: break;
  }
  size_t g = 0;
  double tg = 0;
  bracket(gamma, gammaDegrees, g, tg);
  const size_t ng = gamma.size();
  auto plane = [&](size_t p) {
    const double a = candela[p * ng + g];
    return tg > 0 ? a + tg * (candela[p * ng + g + 1] - a) : a;
  };
  if (symmetry == Symmetry::Full && C > c.back()) {
    // Between the last stored plane and C360 = C0.
    const double span = 360.0 - c.back();
    const double t = span > 0 ? (C - c.back()) / span : 0.0;
    return plane(c.size() - 1) + t * (plane(0) - plane(c.size() - 1));
  }
  size_t p = 0;
  double tc = 0;
  bracket(c, C, p, tc);
  return tc > 0 ? plane(p) + tc * (plane(p + 1) - plane(p)) : plane(p);
}

namespace {
// The intensity integrated over gamma in [g0, g1] and all C (lm), by the midpoint rule on a grid
// fine against the stored angles.
double integrateBand(const PhotometricDistribution& d, double g0, double g1) {
  const int ng = 1440, nc = d.symmetry == PhotometricDistribution::Symmetry::Rotational ? 1 : 720;
  const double dg = (g1 - g0) / ng * std::numbers::pi / 180.0, dc = 2.0 * std::numbers::pi / nc;
  double sum = 0;
  for (int i = 0; i < ng; ++i) {
    const double g = g0 + (i + 0.5) * (g1 - g0) / ng;
    double ring = 0;
    for (int j = 0; j < nc; ++j) ring += d.intensity((j + 0.5) * 360.0 / nc, g);
    sum += ring * dc * std::sin(g * std::numbers::pi / 180.0) * dg;
  }
  return sum;
}
}  // namespace

double PhotometricDistribution::flux() const { return flux_ >= 0 ? flux_ : integrateBand(*this, 0.0, 180.0); }
double PhotometricDistribution::downwardFlux() const { return downward_ >= 0 ? downward_ : integrateBand(*this, 0.0, 90.0); }
void PhotometricDistribution::integrate() {
  flux_ = downward_ = -1;
  flux_ = flux();
  downward_ = downwardFlux();
}

// ----------------------------------------------------------------------------------------------
// IES LM-63

PhotometricDistribution parseIes(std::string_view bytes, const std::string& file) {
  const std::vector<std::string_view> lines = splitLines(bytes);
  if (lines.empty()) throw Error(file, "", "is empty: not an IES LM-63 file");
  PhotometricDistribution d;
  size_t at = 0;
  const std::string header = trim(lines[0]);
  d.format = "IES LM-63-1986";
  if (header.rfind("IESNA", 0) == 0 || header.rfind("IES:LM-63", 0) == 0) {
    d.format = header.find("2019") != std::string::npos   ? "IES LM-63-2019"
               : header.find("2002") != std::string::npos ? "IES LM-63-2002"
               : header.find("1995") != std::string::npos ? "IES LM-63-1995"
                                                          : "IES LM-63-1991";
    ++at;
  }
  // Keyword lines until TILT=.
  for (; at < lines.size(); ++at) {
    const std::string line = trim(lines[at]);
    if (line.rfind("TILT", 0) == 0) break;
    if (line.rfind("[LUMINAIRE]", 0) == 0) d.luminaire = trim(line.substr(11));
  }
  if (at == lines.size()) throw Error(file, "", "has no TILT= line: not an IES LM-63 file, or cut short");
  const std::string tiltLine = trim(lines[at]);
  const size_t eq = tiltLine.find('=');
  const std::string tilt = eq == std::string::npos ? "" : trim(tiltLine.substr(eq + 1));
  if (tilt != "NONE" && tilt != "INCLUDE")
    throw Error(file, "line " + std::to_string(at + 1),
                "TILT=" + tilt + " is not supported: give TILT=NONE, or TILT=INCLUDE with the tilt data in the file");
  // The rest: numbers separated by blanks or commas, across lines.
  struct Token {
    std::string text;
    size_t line;
  };
  std::vector<Token> tokens;
  for (size_t l = at + 1; l < lines.size(); ++l) {
    std::string cur;
    for (char ch : lines[l]) {
      if (std::isspace(static_cast<unsigned char>(ch)) || ch == ',') {
        if (!cur.empty()) tokens.push_back({cur, l + 1});
        cur.clear();
      } else {
        cur += ch;
      }
    }
    if (!cur.empty()) tokens.push_back({cur, l + 1});
  }
  size_t next = 0;
  auto number = [&](const std::string& what) {
    if (next >= tokens.size()) throw Error(file, what, "the file ends before it (cut short, or a count is wrong)");
    double v = 0;
    if (!toNumber(tokens[next].text, v))
      throw Error(file, "line " + std::to_string(tokens[next].line) + ", " + what, "'" + tokens[next].text + "' is not a number");
    ++next;
    return v;
  };
  if (tilt == "INCLUDE") {
    countOf(number("lamp-to-luminaire geometry"), file, "lamp-to-luminaire geometry", 1, 3);
    const size_t n = countOf(number("number of tilt angles"), file, "number of tilt angles", 0, kMaxAngles);
    for (size_t k = 0; k < 2 * n; ++k) number(k < n ? "tilt angle " + std::to_string(k + 1) : "tilt factor " + std::to_string(k - n + 1));
  }
  const double lamps = number("number of lamps");
  const double lumensPerLamp = number("lumens per lamp");
  const double multiplier = number("candela multiplier");
  const size_t nv = countOf(number("number of vertical angles"), file, "number of vertical angles", 1, kMaxAngles);
  const size_t nh = countOf(number("number of horizontal angles"), file, "number of horizontal angles", 1, 2 * kMaxAngles);
  const double type = number("photometric type");
  if (type != 1.0)
    throw Error(file, "photometric type",
                type == 2.0 ? "type B photometry (floodlights) is not supported: Relume reads type C"
                : type == 3.0 ? "type A photometry (automotive) is not supported: Relume reads type C"
                              : "must be 1 (type C), 2 (B) or 3 (A), not " + fmt(type));
  number("units type");
  number("width");
  number("length");
  number("height");
  const double ballast = number("ballast factor");
  const double ballastLamp = number("ballast-lamp photometric factor");
  number("input watts");
  if (!(multiplier > 0)) throw Error(file, "candela multiplier", "must be positive, not " + fmt(multiplier));
  if (!(ballast > 0)) throw Error(file, "ballast factor", "must be positive, not " + fmt(ballast));
  if (tokens.size() - next < nv + nh + nv * nh)
    throw Error(file, "", "the file ends before its " + std::to_string(nv) + " vertical and " + std::to_string(nh) +
                              " horizontal angles and their " + std::to_string(nv * nh) +
                              " candela values (cut short, or a count is wrong)");
  d.gamma.resize(nv);
  for (size_t k = 0; k < nv; ++k) d.gamma[k] = number("vertical angle " + std::to_string(k + 1));
  d.c.resize(nh);
  for (size_t k = 0; k < nh; ++k) d.c[k] = number("horizontal angle " + std::to_string(k + 1));
  // The line's second value is the ballast-lamp photometric factor up to LM-63-1995; 2002 left it
  // for future use (1) and 2019 made it the file generation type: not a factor.
  const bool lampFactor = d.format != "IES LM-63-2002" && d.format != "IES LM-63-2019" && ballastLamp > 0;
  const double scale = multiplier * ballast * (lampFactor ? ballastLamp : 1.0);
  d.candela.resize(nv * nh);
  for (size_t k = 0; k < nv * nh; ++k)
    d.candela[k] = scale * number("candela value " + std::to_string(k + 1) + " of " + std::to_string(nv * nh));
  if (next < tokens.size())
    throw Error(file, "line " + std::to_string(tokens[next].line),
                std::to_string(tokens.size() - next) + " numbers more than the counts say (" + std::to_string(nv) +
                    " vertical x " + std::to_string(nh) + " horizontal angles): a count is wrong");
  // LM-63: the last horizontal angle gives the symmetry.
  using S = PhotometricDistribution::Symmetry;
  const double first = d.c.front(), last = d.c.back();
  d.symmetry = nh == 1 ? S::Rotational
               : last == 90.0 && first == 0.0 ? S::Quadrants
               : last == 180.0 && first == 0.0 ? S::AboutC0C180
               : first == 90.0 && last == 270.0 ? S::AboutC90C270
                                                : S::Full;
  if (d.symmetry == S::Full && last > 360.0) throw Error(file, "horizontal angles", "end at " + fmt(last) + " degrees, beyond 360");
  if (d.symmetry == S::Full && last == 360.0) {  // C360 repeats C0
    d.c.pop_back();
    d.candela.resize(d.c.size() * nv);
  }
  if (d.symmetry == S::Full && first != 0.0)
    throw Error(file, "horizontal angles", "must start at 0 (or at 90 and end at 270), not at " + fmt(first));
  if (d.symmetry == S::Full && d.c.size() == 1) d.symmetry = S::Rotational;
  d.lampLumens = lumensPerLamp > 0 && lamps > 0 ? lumensPerLamp * lamps : 0.0;
  checkDistribution(d, file);
  d.integrate();
  return d;
}

// ----------------------------------------------------------------------------------------------
// EULUMDAT

PhotometricDistribution parseEulumdat(std::string_view bytes, const std::string& file) {
  const std::vector<std::string_view> lines = splitLines(bytes);
  size_t at = 0;
  auto text = [&](const std::string& what) {
    if (at >= lines.size()) throw Error(file, "line " + std::to_string(at + 1) + " (" + what + ")", "the file ends before it (cut short)");
    return trim(lines[at++]);
  };
  auto number = [&](const std::string& what) {
    const std::string t = text(what);
    double v = 0;
    if (!toNumber(t, v, true)) throw Error(file, "line " + std::to_string(at) + " (" + what + ")", "'" + t + "' is not a number");
    return v;
  };
  PhotometricDistribution d;
  d.format = "EULUMDAT";
  text("company identification");
  const size_t ityp = countOf(number("type indicator Ityp"), file, "type indicator Ityp (line 2)", 0, 3);
  (void)ityp;
  const size_t isym = countOf(number("symmetry indicator Isym"), file, "symmetry indicator Isym (line 3)", 0, 4);
  const size_t mc = countOf(number("number of C-planes Mc"), file, "number of C-planes Mc (line 4)", 1, 721);
  number("distance between C-planes Dc");
  const size_t ng = countOf(number("number of intensities per C-plane Ng"), file, "number of intensities per C-plane Ng (line 6)", 1, 361);
  number("distance between intensities Dg");
  text("measurement report number");
  d.luminaire = text("luminaire name");
  text("luminaire number");
  text("file name");
  text("date / user");
  for (const char* w : {"length of luminaire", "width of luminaire", "height of luminaire", "length of luminous area",
                        "width of luminous area", "height of luminous area C0", "height of luminous area C90",
                        "height of luminous area C180", "height of luminous area C270", "downward flux fraction",
                        "light output ratio"})
    number(w);
  const double conversion = number("conversion factor for intensities");
  number("tilt during measurement");
  const size_t sets = countOf(number("number of standard sets of lamps n"), file, "number of standard sets of lamps n (line 26)", 1, 20);
  std::vector<double> setFlux(sets);
  for (size_t s = 0; s < sets; ++s) number("number of lamps, set " + std::to_string(s + 1));
  for (size_t s = 0; s < sets; ++s) text("type of lamps, set " + std::to_string(s + 1));
  for (size_t s = 0; s < sets; ++s) setFlux[s] = number("total luminous flux of lamps, set " + std::to_string(s + 1));
  for (size_t s = 0; s < sets; ++s) text("colour temperature, set " + std::to_string(s + 1));
  for (size_t s = 0; s < sets; ++s) text("colour rendering, set " + std::to_string(s + 1));
  for (size_t s = 0; s < sets; ++s) number("wattage, set " + std::to_string(s + 1));
  for (int k = 0; k < 10; ++k) number("direct ratio " + std::to_string(k + 1));
  std::vector<double> cAngles(mc), gAngles(ng);
  for (size_t k = 0; k < mc; ++k) cAngles[k] = number("C angle " + std::to_string(k + 1));
  for (size_t k = 0; k < ng; ++k) gAngles[k] = number("G angle " + std::to_string(k + 1));
  if (!(setFlux[0] > 0)) throw Error(file, "total luminous flux of lamps, set 1", "must be positive, not " + fmt(setFlux[0]));
  if (!(conversion > 0)) throw Error(file, "conversion factor for intensities (line 24)", "must be positive, not " + fmt(conversion));
  // The stored planes (EULUMDAT's Mc1..Mc2, 1-based, wrapping past Mc).
  using S = PhotometricDistribution::Symmetry;
  size_t mc1 = 1, mc2 = mc;
  switch (isym) {
    case 0: d.symmetry = S::Full; break;
    case 1: d.symmetry = S::Rotational; mc2 = 1; break;
    case 2: d.symmetry = S::AboutC0C180; mc2 = mc / 2 + 1; break;
    case 3: d.symmetry = S::AboutC90C270; mc1 = 3 * mc / 4 + 1; mc2 = mc1 + mc / 2; break;
    case 4: d.symmetry = S::Quadrants; mc2 = mc / 4 + 1; break;
  }
  if ((isym == 2 && mc % 2 != 0) || (isym >= 3 && mc % 4 != 0))
    throw Error(file, "number of C-planes Mc (line 4)",
                "with symmetry indicator " + std::to_string(isym) + " it must be a multiple of " + (isym == 2 ? "2" : "4") +
                    ", not " + std::to_string(mc));
  const size_t planes = mc2 - mc1 + 1;
  const double toCandela = conversion * setFlux[0] / 1000.0;
  std::vector<double> values(planes * ng);
  for (size_t k = 0; k < values.size(); ++k)
    values[k] = toCandela * number("intensity " + std::to_string(k + 1) + " of " + std::to_string(values.size()));
  for (; at < lines.size(); ++at)
    if (!trim(lines[at]).empty())
      throw Error(file, "line " + std::to_string(at + 1),
                  "more lines than the counts say (Mc " + std::to_string(mc) + ", Ng " + std::to_string(ng) + ", symmetry " +
                      std::to_string(isym) + "): a count is wrong");
  d.lampLumens = setFlux[0];
  d.gamma = gAngles;
  d.c.resize(planes);
  for (size_t p = 0; p < planes; ++p) {
    const double a = cAngles[(mc1 - 1 + p) % mc];
    d.c[p] = isym == 3 ? std::fmod(a + 360.0, 360.0) : a;
  }
  if (isym == 3) {
    // Stored C270 .. C360/C0 .. C90: mirrored (I(C) = I(180 - C)) onto C90 .. C270, ascending.
    std::vector<double> mirrored(values.size()), c(planes);
    for (size_t p = 0; p < planes; ++p) {
      c[planes - 1 - p] = std::fmod(540.0 - d.c[p], 360.0);
      std::copy_n(values.begin() + long(p * ng), ng, mirrored.begin() + long((planes - 1 - p) * ng));
    }
    d.c = c;
    values = mirrored;
  }
  d.candela = values;
  checkDistribution(d, file);
  d.integrate();
  return d;
}

}  // namespace relume
