#pragma once
// A luminaire's photometric distribution, as lighting designers download it: IES LM-63 (.ies) and
// EULUMDAT (.ldt) files, read from their bytes (the file reader in relume/project wraps them).
//
// Type C photometry throughout: gamma is the angle from the luminaire's nadir (its emitting
// face's normal), C the angle of the half-plane about that axis, from C0 towards C90.
#include <string>
#include <string_view>
#include <vector>

namespace relume {

struct PhotometricDistribution {
  // How the stored C-planes extend to the full turn.
  enum class Symmetry {
    Full,          // every plane stored, C in [0, 360)
    Rotational,    // one plane: the same in every C
    AboutC0C180,   // I(C) = I(360 - C): planes C0..C180 stored
    AboutC90C270,  // I(C) = I(180 - C): planes C90..C270 stored
    Quadrants,     // both of the above: planes C0..C90 stored
  };
  Symmetry symmetry = Symmetry::Rotational;
  std::vector<double> c;        // degrees, ascending: the stored planes
  std::vector<double> gamma;    // degrees, ascending, within [0, 180]
  std::vector<double> candela;  // c.size() x gamma.size(), plane after plane, candela
  double lampLumens = 0;        // the file's lamp flux (lm); 0 for absolute photometry
  std::string format;           // "IES LM-63-2002", "EULUMDAT", ...
  std::string luminaire;        // the file's name for the luminaire, when it gives one

  // Luminous intensity (cd) towards (C, gamma), in degrees; bilinear between the stored angles,
  // zero beyond the stored gamma range (and for angles that are not finite numbers).
  double intensity(double cDegrees, double gammaDegrees) const;
  // Total luminous flux (lm): the intensity integrated over the sphere.
  double flux() const;
  // The flux into gamma < 90 (the nadir's hemisphere), lm.
  double downwardFlux() const;
  // Integrates both once (about a million intensity lookups) and keeps them for flux() and
  // downwardFlux(); the parsers call it. A distribution built otherwise integrates on each call.
  void integrate();

 private:
  double flux_ = -1, downward_ = -1;  // kept by integrate(); -1: not yet
};

// IES LM-63 (1986, 1991, 1995, 2002) from its bytes; `file` names it in errors. Type C only
// (types A and B, for floodlights and roadway, are refused by name); TILT=NONE or INCLUDE.
PhotometricDistribution parseIes(std::string_view bytes, const std::string& file);
// EULUMDAT from its bytes (decimal points or commas); intensities per 1000 lm are scaled by the
// first lamp set's flux.
PhotometricDistribution parseEulumdat(std::string_view bytes, const std::string& file);

}  // namespace relume
