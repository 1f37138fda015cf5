// Photometric files (IES LM-63, EULUMDAT): analytic distributions written by the test give their
// flux and their intensities back, in both formats and under every symmetry; each malformed-input
// class gives an error naming the file and the problem.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <random>
#include <sstream>
#include <string>

#include "relume/geometry/error.h"
#include "relume/geometry/photometry.h"
#include "support/error_text.h"
#include "support/replaced.h"

using namespace relume;

namespace {

constexpr double kPi = std::numbers::pi;
double rad(double deg) { return deg * kPi / 180.0; }

using Intensity = std::function<double(double c, double gamma)>;  // degrees -> candela

// An IES LM-63-2002 file of `f` sampled at the given angles.
std::string iesFile(const Intensity& f, const std::vector<double>& vertical, const std::vector<double>& horizontal,
                    const std::string& tilt = "NONE") {
  std::ostringstream s;
  s << "IESNA:LM-63-2002\n[TEST] written by photometry_test\n[LUMINAIRE] analytic\nTILT=" << tilt << "\n";
  s << "1 -1 1 " << vertical.size() << " " << horizontal.size() << " 1 2 0.3 0.3 0\n1 1 40\n";
  for (double v : vertical) s << v << " ";
  s << "\n";
  for (double h : horizontal) s << h << " ";
  s << "\n";
  for (double h : horizontal) {
    for (double v : vertical) s << f(h, v) << " ";
    s << "\n";
  }
  return s.str();
}

// A EULUMDAT file of `f` with Mc planes every 360/Mc degrees and intensities every 5 degrees of
// gamma; the stored planes follow the symmetry indicator. `lampFlux` lumens in the first set.
std::string ldtFile(const Intensity& f, int isym, int mc, double lampFlux = 2000.0) {
  const int ng = 37;
  std::ostringstream s;
  s << "Relume test\n1\n" << isym << "\n" << mc << "\n" << (mc > 1 ? 360.0 / mc : 0.0) << "\n" << ng << "\n5\n";
  s << "report\nanalytic\n1\ntest.ldt\n2026-12-02\n";
  for (int k = 0; k < 9; ++k) s << "100\n";  // sizes (mm)
  s << "50\n100\n1\n0\n";                    // DFF, LORL, conversion factor, tilt
  s << "1\n1\nLED\n" << lampFlux << "\n3000\n90\n20\n";
  for (int k = 0; k < 10; ++k) s << "0,5\n";  // direct ratios, with a decimal comma
  for (int k = 0; k < mc; ++k) s << k * (360.0 / mc) << "\n";
  for (int k = 0; k < ng; ++k) s << 5 * k << "\n";
  int mc1 = 1, mc2 = mc;
  if (isym == 1) mc2 = 1;
  if (isym == 2) mc2 = mc / 2 + 1;
  if (isym == 3) mc1 = 3 * mc / 4 + 1, mc2 = mc1 + mc / 2;
  if (isym == 4) mc2 = mc / 4 + 1;
  for (int p = mc1; p <= mc2; ++p) {
    const double c = ((p - 1) % mc) * (360.0 / mc);
    for (int k = 0; k < ng; ++k) s << f(c, 5.0 * k) * 1000.0 / lampFlux << "\n";  // cd per 1000 lm
  }
  return s.str();
}

std::vector<double> steps(double from, double to, double step) {
  std::vector<double> out;
  for (double a = from; a <= to + 1e-9; a += step) out.push_back(a);
  return out;
}

using test::errorText;
using test::replaced;


// `parse` on `bytes` throws an error naming bad.<ext> that contains `words`.
template <typename Parse>
void expectError(Parse parse, const std::string& ext, const std::string& bytes, const std::string& words) {
  const std::string file = "bad." + ext;
  const std::string e = errorText([&] { parse(bytes, file); });
  EXPECT_NE(e.find(file), std::string::npos) << e;
  EXPECT_NE(e.find(words), std::string::npos) << "wanted '" << words << "' in: " << e;
}

const double I0 = 800.0;
// Lambertian below the luminaire: I0 cos(gamma), flux pi I0.
double lambertian(double, double g) { return g <= 90.0 ? I0 * std::max(0.0, std::cos(rad(g))) : 0.0; }

}  // namespace

TEST(Photometry, ACosineDistributionGivesPiTimesItsPeakInBothFormats) {
  const PhotometricDistribution ies = parseIes(iesFile(lambertian, steps(0, 90, 5), {0.0}), "cos.ies");
  EXPECT_NEAR(ies.flux(), kPi * I0, 0.01 * kPi * I0);
  EXPECT_NEAR(ies.downwardFlux(), ies.flux(), 1e-5 * ies.flux());  // nothing above the horizon
  EXPECT_EQ(ies.symmetry, PhotometricDistribution::Symmetry::Rotational);
  EXPECT_EQ(ies.lampLumens, 0.0);  // -1 lumens: absolute photometry
  EXPECT_EQ(ies.luminaire, "analytic");
  EXPECT_EQ(ies.intensity(123.0, 120.0), 0.0);  // beyond the stored vertical angles
  const PhotometricDistribution ldt = parseEulumdat(ldtFile(lambertian, 1, 1), "cos.ldt");
  EXPECT_NEAR(ldt.flux(), kPi * I0, 0.01 * kPi * I0);
  EXPECT_EQ(ldt.lampLumens, 2000.0);
  // The flux follows the intensities' scale, not the lamp's lumens: 1000 lm of lamps at the same
  // cd/klm give half the candela.
  std::string half = ldtFile(lambertian, 1, 1);
  half.replace(half.find("\n2000\n"), 6, "\n1000\n");
  EXPECT_NEAR(parseEulumdat(half, "half.ldt").flux(), kPi * I0 / 2, 0.01 * kPi * I0 / 2);
}

TEST(Photometry, EverySymmetryGivesTheIntensitiesItWasWrittenFrom) {
  // Each distribution has the symmetry its file declares; the file stores only that part.
  struct Case {
    const char* name;
    int isym;
    Intensity f;
  };
  const std::vector<Case> cases = {
      {"no symmetry", 0, [](double c, double g) { return lambertian(c, g) * (1.0 + 0.5 * std::cos(rad(c - 30.0))); }},
      {"about C0-C180", 2, [](double c, double g) { return lambertian(c, g) * (1.0 + 0.5 * std::cos(rad(c))); }},
      {"about C90-C270", 3, [](double c, double g) { return lambertian(c, g) * (1.0 + 0.5 * std::sin(rad(c))); }},
      {"quadrants", 4, [](double c, double g) { return lambertian(c, g) * (1.0 + 0.5 * std::cos(rad(2 * c))); }},
  };
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> C(0.0, 360.0), G(0.0, 89.0);
  for (const Case& k : cases) {
    SCOPED_TRACE(k.name);
    const PhotometricDistribution ldt = parseEulumdat(ldtFile(k.f, k.isym, 72), "sym.ldt");  // 5-degree planes
    // The IES file stores the half or quadrant LM-63 names by its horizontal angles.
    std::vector<double> horizontal = k.isym == 0 ? steps(0, 360, 5)
                                     : k.isym == 2 ? steps(0, 180, 5)
                                     : k.isym == 3 ? steps(90, 270, 5)
                                                   : steps(0, 90, 5);
    const PhotometricDistribution ies = parseIes(iesFile(k.f, steps(0, 90, 5), horizontal), "sym.ies");
    for (int n = 0; n < 2000; ++n) {
      const double c = C(rng), g = G(rng);
      // Bilinear between 5-degree samples of a smooth function: within 1 % of the peak.
      ASSERT_NEAR(ldt.intensity(c, g), k.f(c, g), 0.01 * 1.5 * I0) << "EULUMDAT at C " << c << ", gamma " << g;
      ASSERT_NEAR(ies.intensity(c, g), k.f(c, g), 0.01 * 1.5 * I0) << "IES at C " << c << ", gamma " << g;
    }
    EXPECT_NEAR(ldt.flux(), kPi * I0, 0.01 * kPi * I0);  // the C-dependent part integrates to zero
    EXPECT_NEAR(ies.flux(), kPi * I0, 0.01 * kPi * I0);
  }
}

TEST(Photometry, TheFormatsVersionDecidesWhatTheLampFactorIs) {
  // Up to LM-63-1995 the second value of the ballast line multiplies the candela; in 2019 it is
  // the file generation type (here 1.10001), in 2002 unused.
  std::string f1995 = iesFile(lambertian, steps(0, 90, 5), {0.0});
  f1995.replace(f1995.find("IESNA:LM-63-2002"), 16, "IESNA:LM-63-1995");
  f1995.replace(f1995.find("\n1 1 40\n"), 8, "\n1 0.5 40\n");
  std::string f2019 = f1995;
  f2019.replace(f2019.find("IESNA:LM-63-1995"), 16, "IES:LM-63-2019");
  f2019.replace(f2019.find("\n1 0.5 40\n"), 10, "\n1 1.10001 40\n");
  const PhotometricDistribution a = parseIes(f1995, "a.ies"), b = parseIes(f2019, "b.ies");
  EXPECT_EQ(b.format, "IES LM-63-2019");
  EXPECT_NEAR(a.flux(), 0.5 * kPi * I0, 0.01 * kPi * I0);
  EXPECT_NEAR(b.flux(), kPi * I0, 0.01 * kPi * I0);
  // Angles that are no numbers give no light (and read nothing out of range).
  EXPECT_EQ(b.intensity(std::nan(""), 10.0), 0.0);
  EXPECT_EQ(b.intensity(10.0, std::numeric_limits<double>::infinity()), 0.0);
}

TEST(Photometry, TiltIncludedIsSkippedAndAnUpwardLuminaireEmitsAbove) {
  std::string withTilt = iesFile(lambertian, steps(0, 90, 5), {0.0}, "INCLUDE");
  withTilt.insert(withTilt.find("TILT=INCLUDE\n") + 13, "1\n3\n0 45 90\n1 0.9 0.8\n");
  EXPECT_NEAR(parseIes(withTilt, "tilt.ies").flux(), kPi * I0, 0.01 * kPi * I0);
  // An uplight: angles 90..180 only.
  auto up = [](double, double g) { return g >= 90.0 ? I0 * std::max(0.0, -std::cos(rad(g))) : 0.0; };
  const PhotometricDistribution d = parseIes(iesFile(up, steps(90, 180, 5), {0.0}), "up.ies");
  EXPECT_NEAR(d.flux(), kPi * I0, 0.01 * kPi * I0);
  EXPECT_LT(d.downwardFlux(), 1e-6 * d.flux());
  EXPECT_EQ(d.intensity(0.0, 30.0), 0.0);
}

TEST(Photometry, EachMalformedIesFileIsNamedWithItsProblem) {
  const std::string good = iesFile(lambertian, steps(0, 90, 5), {0.0, 90.0});
  ASSERT_NO_THROW(parseIes(good, "good.ies"));
  auto expectIesError = [](const std::string& bytes, const std::string& words) { expectError(parseIes, "ies", bytes, words); };
  // Truncated: cut in the candela values, and cut before TILT.
  expectIesError(good.substr(0, good.size() - 40), "ends before");
  expectIesError(good.substr(0, 30), "no TILT= line");
  expectIesError("", "empty");
  // Wrong counts: one vertical angle more than given, one less.
  std::string more = good, fewer = good;
  more.replace(more.find(" 19 2 1 "), 8, " 20 2 1 ");
  expectIesError(more, "ends before");
  fewer.replace(fewer.find(" 19 2 1 "), 8, " 18 2 1 ");
  expectIesError(fewer, "");  // the angles and values no longer line up: some error, named
  EXPECT_NE(errorText([&] { parseIes(fewer, "bad.ies"); }), "");
  std::string extra = good + "5 5 5\n";
  expectIesError(extra, "more than the counts say");
  // A negative candela value.
  std::string negative = good;
  negative.replace(negative.rfind("800 "), 4, "-800 ");
  expectIesError(negative, "cannot be negative");
  // Multipliers that overflow, and a luminaire that emits nothing.
  expectIesError(replaced(good, "1 -1 1 19", "1 -1 1e300 19"), "beyond any luminaire");
  std::string dark = iesFile([](double, double) { return 0.0; }, steps(0, 90, 5), {0.0});
  expectIesError(dark, "emits nothing");
  // Unknown TILT, and a tilt file elsewhere.
  expectIesError(replaced(good, "TILT=NONE", "TILT=SOMETIMES"), "TILT=SOMETIMES is not supported");
  expectIesError(replaced(good, "TILT=NONE", "TILT=lamp.tlt"), "TILT=lamp.tlt is not supported");
  // Type B photometry, a word among the numbers, descending angles.
  expectIesError(replaced(good, " 19 2 1 ", " 19 2 2 "), "type B photometry");
  expectIesError(replaced(good, "1 1 40", "1 x 40"), "'x' is not a number");
  expectIesError(replaced(good, "0 5 10 ", "0 10 5 "), "must increase");
}

TEST(Photometry, EachMalformedEulumdatFileIsNamedWithItsProblem) {
  const std::string good = ldtFile(lambertian, 2, 24);
  ASSERT_NO_THROW(parseEulumdat(good, "good.ldt"));
  auto expectLdtError = [](const std::string& bytes, const std::string& words) { expectError(parseEulumdat, "ldt", bytes, words); };
  expectLdtError(good.substr(0, good.size() / 2), "ends before");
  expectLdtError(good.substr(0, 20), "ends before");
  // Wrong counts: Ng one more (the file ends early) and one less (lines left over).
  std::string more = good, fewer = good;
  more.replace(more.find("\n37\n"), 4, "\n38\n");
  expectLdtError(more, "");
  EXPECT_NE(errorText([&] { parseEulumdat(more, "bad.ldt"); }), "");
  fewer.replace(fewer.find("\n37\n"), 4, "\n36\n");
  EXPECT_NE(errorText([&] { parseEulumdat(fewer, "bad.ldt"); }), "");
  expectLdtError(good + "12\n", "more lines than the counts say");
  // Mc that the symmetry cannot halve or quarter, a symmetry indicator out of range.
  expectLdtError(replaced(good, "\n2\n24\n", "\n2\n23\n"), "multiple of 2");
  expectLdtError(replaced(good, "\n2\n24\n", "\n4\n22\n"), "multiple of 4");
  expectLdtError(replaced(good, "\n2\n24\n", "\n7\n24\n"), "symmetry indicator Isym");
  // A negative intensity.
  std::string negative = good;
  negative.replace(negative.rfind("\n400\n"), 5, "\n-400\n");
  expectLdtError(negative, "cannot be negative");
}
