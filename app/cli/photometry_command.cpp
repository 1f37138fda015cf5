// relume photometry: what a luminaire's IES LM-63 or EULUMDAT file says (its flux, its shape).
#include <QCommandLineParser>
#include <QJsonArray>
#include <QJsonObject>
#include <algorithm>
#include <cstdio>

#include "commands.h"
#include "relume/geometry/photometry.h"
#include "relume/project/room_io.h"

namespace relume::cli {

int photometryCommand(const QStringList& args, Progress& progress) {
  QCommandLineParser p;
  p.setApplicationDescription(
      "Read a luminaire's photometric file (IES LM-63 .ies or EULUMDAT .ldt) and print its luminous flux, the share "
      "emitted downwards and its peak intensity.");
  p.addPositionalArgument("FILE", "The .ies or .ldt file.");
  p.addOption({"json", "Also write the figures as JSON.", "OUT.json"});
  parseOrThrow(p, args, 1, "relume photometry FILE.ies|FILE.ldt [--json OUT.json]");
  const std::string file = p.positionalArguments()[0].toStdString();
  progress.report(0, "reading " + file);
  const PhotometricDistribution d = readPhotometricFile(file);
  progress.report(0.5, "integrating the intensities over the sphere");
  const double flux = d.flux(), down = d.downwardFlux();
  const auto peak = std::max_element(d.candela.begin(), d.candela.end());
  const size_t at = size_t(peak - d.candela.begin());
  const double peakC = d.c[at / d.gamma.size()], peakGamma = d.gamma[at % d.gamma.size()];
  static const char* symmetryNames[] = {"none", "rotational", "about the C0-C180 plane", "about the C90-C270 plane",
                                        "in the four quadrants"};
  const char* symmetry = symmetryNames[int(d.symmetry)];
  std::printf("%s%s%s: %zu C-planes (symmetry %s) x %zu angles\n", d.format.c_str(), d.luminaire.empty() ? "" : ", ",
              d.luminaire.c_str(), d.c.size(), symmetry, d.gamma.size());
  std::printf("luminous flux %.1f lm, %.1f %% of it downwards (gamma < 90 deg)\n", flux, flux > 0 ? 100.0 * down / flux : 0.0);
  if (d.lampLumens > 0)
    std::printf("lamp flux %.1f lm: light output ratio %.1f %%\n", d.lampLumens, 100.0 * flux / d.lampLumens);
  else
    std::printf("absolute photometry (no lamp flux given)\n");
  std::printf("peak intensity %.1f cd at C %.1f deg, gamma %.1f deg\n", *peak, peakC, peakGamma);
  if (p.isSet("json"))
    writeJsonAtomically(p.value("json"), QJsonObject{{"file", QString::fromStdString(file)},
                                                     {"format", QString::fromStdString(d.format)},
                                                     {"luminaire", QString::fromStdString(d.luminaire)},
                                                     {"symmetry", symmetry},
                                                     {"c_planes", int(d.c.size())},
                                                     {"gamma_angles", int(d.gamma.size())},
                                                     {"flux_lm", flux},
                                                     {"downward_flux_lm", down},
                                                     {"lamp_flux_lm", d.lampLumens},
                                                     {"peak_cd", *peak},
                                                     {"peak_c_deg", peakC},
                                                     {"peak_gamma_deg", peakGamma}});
  progress.report(1, "done");
  return 0;
}

}  // namespace relume::cli
