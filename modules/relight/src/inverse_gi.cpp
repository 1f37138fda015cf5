#include "inverse_gi.h"

#include <algorithm>
#include <cmath>

namespace relume::detail {

bool solveDense(std::vector<std::vector<double>> A, std::vector<double> b, std::vector<double>& x) {
  const size_t n = b.size();
  double scale = 0;
  for (size_t i = 0; i < n; ++i) scale = std::max(scale, std::abs(A[i][i]));
  for (size_t c = 0; c < n; ++c) {
    size_t p = c;
    for (size_t r = c + 1; r < n; ++r)
      if (std::abs(A[r][c]) > std::abs(A[p][c])) p = r;
    if (!(std::abs(A[p][c]) > 1e-9 * scale)) return false;
    std::swap(A[p], A[c]);
    std::swap(b[p], b[c]);
    for (size_t r = c + 1; r < n; ++r) {
      const double f = A[r][c] / A[c][c];
      for (size_t k = c; k < n; ++k) A[r][k] -= f * A[c][k];
      b[r] -= f * b[c];
    }
  }
  x.assign(n, 0);
  for (size_t c = n; c-- > 0;) {
    double s = b[c];
    for (size_t k = c + 1; k < n; ++k) s -= A[c][k] * x[k];
    x[c] = s / A[c][c];
  }
  return true;
}

JointFitResult jointFit(const std::vector<JointFitRow>& rows, size_t polygons, const std::vector<glm::dvec3>& guess,
                        const std::vector<std::optional<glm::dvec3>>& fixed) {
  JointFitResult out;
  const size_t nl = guess.size();
  out.reflectance.assign(polygons, glm::dvec3(0.0));
  out.exitance = guess;
  out.uncertainty.assign(nl, 0.0);
  out.polygonWeight.assign(polygons, 0.0);
  // Unknowns: a_s of each polygon with rows, then m_l of each lamp not held.
  std::vector<int> var(polygons, -1);
  int P = 0;
  for (const auto& r : rows)
    if (r.polygon >= 0 && size_t(r.polygon) < polygons && var[r.polygon] < 0) var[r.polygon] = P++;
  std::vector<size_t> freeLamps;
  for (size_t l = 0; l < nl; ++l)
    if (!fixed[l]) freeLamps.push_back(l);
  const size_t n = size_t(P) + freeLamps.size();
  if (P == 0) {
    out.reason = "no photographed element to fit";
    return out;
  }
  if (rows.size() < n + 2) {
    out.reason = "too few photographed elements for the unknowns";
    return out;
  }
  std::vector<double> weightSum(polygons, 0.0);
  for (int c = 0; c < 3; ++c) {
    std::vector<double> m(nl);
    for (size_t l = 0; l < nl; ++l) m[l] = fixed[l] ? (*fixed[l])[c] : guess[l][c];
    std::vector<double> ws(size_t(P), 1.0), x;
    // The lamps' unknowns in units of their guesses (the system's columns of one magnitude).
    std::vector<double> unit(nl, 1.0);
    for (size_t l = 0; l < nl; ++l)
      if (guess[l][c] > 0) unit[l] = guess[l][c];
    std::vector<std::vector<double>> A;
    std::vector<double> coef(n);
    // The row's irradiance per unit exitance of lamp l: direct, and simulated indirect.
    auto coefficient = [&](const JointFitRow& r, size_t l) { return r.G[l] + (r.S.empty() ? 0.0 : r.S[l][c]); };
    auto predicted = [&](const JointFitRow& r) {
      double H = r.I[c];
      for (size_t l = 0; l < nl; ++l) H += m[l] * coefficient(r, l);
      return H;
    };
    auto known = [&](const JointFitRow& r) {
      double k = r.I[c];
      for (size_t l = 0; l < nl; ++l)
        if (fixed[l]) k += (*fixed[l])[c] * coefficient(r, l);
      return k;
    };
    for (int it = 0; it < 6; ++it) {
      // Rows weighted by area over the square of the predicted irradiance: relative residuals,
      // so that elements beside a lamp do not outweigh the rest of the room.
      A.assign(n, std::vector<double>(n, 0.0));
      std::vector<double> b(n, 0.0);
      for (const auto& r : rows) {
        const double H = predicted(r);
        if (!(H > 0)) continue;
        const double w = r.area * ws[size_t(var[r.polygon])] / (H * H);
        std::fill(coef.begin(), coef.end(), 0.0);
        coef[size_t(var[r.polygon])] = r.y[c];
        for (size_t j = 0; j < freeLamps.size(); ++j) coef[size_t(P) + j] = -coefficient(r, freeLamps[j]) * unit[freeLamps[j]];
        const double rhs = known(r);
        const size_t p = size_t(var[r.polygon]);
        // coef has one polygon entry and the lamp entries: accumulate only those.
        auto add = [&](size_t i, double ci) {
          A[i][p] += w * ci * coef[p];
          for (size_t j = 0; j < freeLamps.size(); ++j) A[i][size_t(P) + j] += w * ci * coef[size_t(P) + j];
          b[i] += w * ci * rhs;
        };
        add(p, coef[p]);
        for (size_t j = 0; j < freeLamps.size(); ++j) add(size_t(P) + j, coef[size_t(P) + j]);
      }
      if (!solveDense(A, b, x)) {
        out.reason = "singular: the photographed elements do not tell the lamps apart";
        return out;
      }
      for (size_t j = 0; j < freeLamps.size(); ++j) m[freeLamps[j]] = x[size_t(P) + j] * unit[freeLamps[j]];
      for (size_t l = 0; l < nl; ++l) out.exitance[l][c] = m[l];
      for (size_t j = 0; j < freeLamps.size(); ++j)
        if (!(m[freeLamps[j]] > 0)) {
          out.reason = "lamp " + std::to_string(freeLamps[j] + 1) + " came out non-positive";
          return out;
        }
      // Robust per-polygon weights: a polygon whose texture the one-reflectance model fits badly
      // (a poster, a pattern) counts less, by its relative residual variance.
      std::vector<double> res(size_t(P), 0.0), area(size_t(P), 0.0);
      for (const auto& r : rows) {
        const double H = predicted(r);
        if (!(H > 0)) continue;
        const size_t p = size_t(var[r.polygon]);
        const double e = (x[p] * r.y[c] - H) / H;
        res[p] += r.area * e * e;
        area[p] += r.area;
      }
      for (int p = 0; p < P; ++p) ws[size_t(p)] = area[size_t(p)] > 0 ? 1.0 / (res[size_t(p)] / area[size_t(p)] + 1e-4) : 0.0;
    }
    for (size_t s = 0; s < polygons; ++s)
      if (var[s] >= 0) {
        const double a = x[size_t(var[s])];
        out.reflectance[s][c] = a > 0 ? 1.0 / a : 0.0;
        weightSum[s] += ws[size_t(var[s])];
      }
    for (size_t l = 0; l < nl; ++l) out.exitance[l][c] = m[l];
    // Standard errors: sigma^2 (A^T W A)^-1 with sigma^2 from the weighted residuals. The
    // residuals of neighbouring elements are correlated (texture), so this is a lower bound.
    double rss = 0;
    size_t used = 0;
    for (const auto& r : rows) {
      const double H = predicted(r);
      if (!(H > 0)) continue;
      const size_t p = size_t(var[r.polygon]);
      const double e = x[p] * r.y[c] - H;
      rss += r.area * ws[p] / (H * H) * e * e;
      ++used;
    }
    const double sigma2 = used > n ? rss / double(used - n) : 0.0;
    for (size_t j = 0; j < freeLamps.size(); ++j) {
      std::vector<double> e(n, 0.0), col;
      e[size_t(P) + j] = 1.0;
      if (solveDense(A, e, col)) {
        const size_t l = freeLamps[j];
        out.uncertainty[l] += std::sqrt(std::max(0.0, sigma2 * col[size_t(P) + j])) * unit[l] / m[l] / 3.0;
      }
    }
  }
  for (size_t s = 0; s < polygons; ++s) out.polygonWeight[s] = weightSum[s] / 3.0;
  double sum = 0, area = 0;
  for (const auto& r : rows) {
    const glm::dvec3& rho = out.reflectance[size_t(r.polygon)];
    sum += r.area * (rho.x + rho.y + rho.z) / 3.0;
    area += r.area;
  }
  out.meanReflectance = area > 0 ? sum / area : 0.0;
  out.ok = true;
  return out;
}

}  // namespace relume::detail
