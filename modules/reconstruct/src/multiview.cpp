#include "relume/reconstruct/multiview.h"

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <numeric>

#include "relume/geometry/error.h"

namespace relume::recon {

namespace {

glm::dmat3 toGlm(const cv::Matx33d& m) {
  glm::dmat3 g;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) g[c][r] = m(r, c);
  return g;
}
cv::Matx33d toCv(const glm::dmat3& g) {
  cv::Matx33d m;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m(r, c) = g[c][r];
  return m;
}
glm::dmat3 rodrigues(const glm::dvec3& w) {
  cv::Matx33d R;
  cv::Rodrigues(cv::Vec3d(w.x, w.y, w.z), R);
  return toGlm(R);
}
glm::dvec3 rodriguesInv(const glm::dmat3& R) {
  cv::Vec3d w;
  cv::Rodrigues(toCv(R), w);
  return {w[0], w[1], w[2]};
}

// Pixel residual of X in camera (K, R, t); false when X is behind it.
bool residual(const Camera& c, const glm::dvec3& X, const glm::dvec2& px, glm::dvec2& r) {
  glm::dvec2 p;
  if (!c.project(X, p)) return false;
  r = p - px;
  return true;
}

// Reprojection error of a point in a pinhole camera: angle-axis rotation w, translation t (x_cam
// = R(w) X + t), then K; in pixels.
struct Reprojection {
  double fx, fy, cx, cy, u, v;
  template <class T>
  bool operator()(const T* pose, const T* X, T* r) const {
    T p[3];
    ceres::AngleAxisRotatePoint(pose, X, p);
    p[0] += pose[3];
    p[1] += pose[4];
    p[2] += pose[5];
    if (p[2] <= T(1e-9)) return false;  // behind the camera: a step that goes there is refused
    r[0] = T(fx) * p[0] / p[2] + T(cx) - T(u);
    r[1] = T(fy) * p[1] / p[2] + T(cy) - T(v);
    return true;
  }
};

// Sampson distance (pixels) of a correspondence under the relative pose (R(w) R0, unit t = t0 +
// a e1 + b e2, normalised): five parameters, w then (a, b).
struct SampsonDistance {
  glm::dmat3 R0, K1i, K2i;
  glm::dvec3 t0, e1, e2, x1, x2;
  template <class T>
  bool operator()(const T* x, T* r) const {
    T Rw[9];  // column-major
    ceres::AngleAxisToRotationMatrix(x, Rw);
    T R[3][3];  // R[row][col] = (R(w) R0)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        R[i][j] = T(0);
        for (int k = 0; k < 3; ++k) R[i][j] += Rw[k * 3 + i] * T(R0[j][k]);
      }
    T t[3];
    for (int i = 0; i < 3; ++i) t[i] = T(t0[i]) + x[3] * T(e1[i]) + x[4] * T(e2[i]);
    const T n = ceres::sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
    for (T& c : t) c /= n;
    // E = [t]x R; F = K2^-T E K1^-1; here F x1 and F^T x2 directly.
    const T tx[3][3] = {{T(0), -t[2], t[1]}, {t[2], T(0), -t[0]}, {-t[1], t[0], T(0)}};
    T E[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) E[i][j] = tx[i][0] * R[0][j] + tx[i][1] * R[1][j] + tx[i][2] * R[2][j];
    T F[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        F[i][j] = T(0);
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b) F[i][j] += T(K2i[i][a]) * E[a][b] * T(K1i[j][b]);  // K2i^T(i,a) = K2i[i][a] (glm col-major)
      }
    T Fx1[3], Ftx2[3];
    for (int i = 0; i < 3; ++i) {
      Fx1[i] = F[i][0] * T(x1.x) + F[i][1] * T(x1.y) + F[i][2] * T(x1.z);
      Ftx2[i] = F[0][i] * T(x2.x) + F[1][i] * T(x2.y) + F[2][i] * T(x2.z);
    }
    const T num = T(x2.x) * Fx1[0] + T(x2.y) * Fx1[1] + T(x2.z) * Fx1[2];
    const T den = Fx1[0] * Fx1[0] + Fx1[1] * Fx1[1] + Ftx2[0] * Ftx2[0] + Ftx2[1] * Ftx2[1];
    r[0] = num / ceres::sqrt(den + T(1e-300));
    return true;
  }
};

ceres::Solver::Options solverOptions(int maxIterations, ceres::LinearSolverType solver) {
  ceres::Solver::Options o;
  o.linear_solver_type = solver;
  o.max_num_iterations = maxIterations;
  o.num_threads = 1;
  o.logging_type = ceres::SILENT;
  o.minimizer_progress_to_stdout = false;
  o.function_tolerance = 1e-12;
  o.parameter_tolerance = 1e-12;
  o.gradient_tolerance = 1e-14;
  return o;
}

}  // namespace

double TriangulatedPoint::maxError() const {
  return reprojectionError.empty() ? 0 : *std::max_element(reprojectionError.begin(), reprojectionError.end());
}

TriangulatedPoint triangulatePoint(const std::vector<Observation>& obs, const std::string& what) {
  if (obs.size() < 2)
    throw Error("", what, "is clicked in " + std::to_string(obs.size()) + " photo(s); triangulation needs two or more");
  // DLT: each view gives two rows of A X = 0 (normalised coordinates for conditioning).
  cv::Mat A(int(obs.size()) * 2, 4, CV_64F);
  for (size_t i = 0; i < obs.size(); ++i) {
    const Camera& c = *obs[i].camera;
    const double x = (obs[i].pixel.x - c.cx()) / c.fx(), y = (obs[i].pixel.y - c.cy()) / c.fy();
    for (int k = 0; k < 4; ++k) {
      const double p0 = k < 3 ? c.R[k][0] : c.t.x, p1 = k < 3 ? c.R[k][1] : c.t.y, p2 = k < 3 ? c.R[k][2] : c.t.z;
      A.at<double>(int(2 * i), k) = x * p2 - p0;
      A.at<double>(int(2 * i + 1), k) = y * p2 - p1;
    }
  }
  // Rays that (nearly) coincide: the largest angle between any two viewing rays.
  double maxAngle = 0;
  for (size_t i = 0; i < obs.size(); ++i)
    for (size_t j = i + 1; j < obs.size(); ++j) {
      const glm::dvec3 di = obs[i].camera->rayDirection(obs[i].pixel.x, obs[i].pixel.y);
      const glm::dvec3 dj = obs[j].camera->rayDirection(obs[j].pixel.x, obs[j].pixel.y);
      maxAngle = std::max(maxAngle, std::acos(std::clamp(glm::dot(di, dj), -1.0, 1.0)));
    }
  cv::Mat w, u, vt;
  cv::SVD::compute(A, w, u, vt, cv::SVD::FULL_UV);
  const double hw = vt.at<double>(3, 3);
  if (maxAngle < 1e-3 || std::abs(hw) < 1e-12)
    throw Error("", what, "is seen along (nearly) the same ray from every photo; click it in photos taken further apart");
  TriangulatedPoint tp;
  tp.rayAngleDeg = maxAngle * 180.0 / M_PI;
  tp.X = {vt.at<double>(3, 0) / hw, vt.at<double>(3, 1) / hw, vt.at<double>(3, 2) / hw};
  for (const auto& o : obs) {
    const glm::dvec3 c = o.camera->R * tp.X + o.camera->t;
    if (c.z <= 0) throw Error("", what, "lies behind the camera of photo " + o.photo + " (a wrong click or a wrong camera)");
  }
  // Gauss-Newton with damping on the reprojection error, analytic Jacobian.
  for (int it = 0; it < 20; ++it) {
    glm::dmat3 JtJ(0.0);
    glm::dvec3 Jtr(0.0);
    double cost = 0;
    for (const auto& o : obs) {
      const Camera& c = *o.camera;
      const glm::dvec3 p = c.R * tp.X + c.t;
      const glm::dvec2 r(c.fx() * p.x / p.z + c.cx() - o.pixel.x, c.fy() * p.y / p.z + c.cy() - o.pixel.y);
      cost += glm::dot(r, r);
      // d(u)/dX = fx (R0 / z - x R2 / z^2), rows of R are R[.][k]
      const glm::dvec3 R0(c.R[0][0], c.R[1][0], c.R[2][0]), R1(c.R[0][1], c.R[1][1], c.R[2][1]),
          R2(c.R[0][2], c.R[1][2], c.R[2][2]);
      const glm::dvec3 ju = c.fx() * (R0 / p.z - p.x * R2 / (p.z * p.z));
      const glm::dvec3 jv = c.fy() * (R1 / p.z - p.y * R2 / (p.z * p.z));
      JtJ += glm::outerProduct(ju, ju) + glm::outerProduct(jv, jv);
      Jtr += ju * r.x + jv * r.y;
    }
    for (int k = 0; k < 3; ++k) JtJ[k][k] *= 1.0 + 1e-9;
    if (std::abs(glm::determinant(JtJ)) < 1e-300) break;
    const glm::dvec3 step = -(glm::inverse(JtJ) * Jtr);
    const glm::dvec3 Xn = tp.X + step;
    double costN = 0;
    bool ok = true;
    for (const auto& o : obs) {
      glm::dvec2 r;
      if (!residual(*o.camera, Xn, o.pixel, r)) ok = false;
      else costN += glm::dot(r, r);
    }
    if (!ok || costN > cost) {
      // Halve the step a few times before giving up (a damped Gauss-Newton step).
      glm::dvec3 s = step;
      bool better = false;
      for (int h = 0; h < 8 && !better; ++h) {
        s *= 0.5;
        double c2 = 0;
        bool ok2 = true;
        for (const auto& o : obs) {
          glm::dvec2 r;
          if (!residual(*o.camera, tp.X + s, o.pixel, r)) ok2 = false;
          else c2 += glm::dot(r, r);
        }
        if (ok2 && c2 < cost) tp.X += s, better = true;
      }
      if (!better) break;
      continue;
    }
    tp.X = Xn;
    if (glm::length(step) < 1e-12 * (1 + glm::length(tp.X))) break;
  }
  double sum = 0;
  for (const auto& o : obs) {
    glm::dvec2 r;
    if (!residual(*o.camera, tp.X, o.pixel, r))
      throw Error("", what, "lies behind the camera of photo " + o.photo + " (a wrong click or a wrong camera)");
    tp.reprojectionError.push_back(glm::length(r));
    sum += glm::dot(r, r);
  }
  tp.rmsError = std::sqrt(sum / obs.size());
  return tp;
}

Similarity fitSimilarity(const std::vector<glm::dvec3>& from, const std::vector<glm::dvec3>& to) {
  if (from.size() != to.size() || from.size() < 3)
    throw Error("", "similarity", "needs three or more pairs of points");
  const double n = double(from.size());
  glm::dvec3 mf(0.0), mt(0.0);
  for (size_t i = 0; i < from.size(); ++i) mf += from[i], mt += to[i];
  mf /= n;
  mt /= n;
  cv::Matx33d C = cv::Matx33d::zeros();
  double varF = 0;
  for (size_t i = 0; i < from.size(); ++i) {
    const glm::dvec3 a = from[i] - mf, b = to[i] - mt;
    varF += glm::dot(a, a);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) C(r, c) += b[r] * a[c];
  }
  varF /= n;
  C *= 1.0 / n;
  cv::Mat w, u, vt;
  cv::SVD::compute(cv::Mat(C), w, u, vt);
  if (varF < 1e-18 || w.at<double>(1) < 1e-9 * w.at<double>(0))
    throw Error("", "similarity", "the points are collinear or coincide; the fit needs a spread in two directions");
  cv::Matx33d D = cv::Matx33d::eye();
  if (cv::determinant(u) * cv::determinant(vt) < 0) D(2, 2) = -1;
  const cv::Matx33d R = cv::Matx33d(cv::Mat(u)) * D * cv::Matx33d(cv::Mat(vt));
  const double s = (w.at<double>(0) * D(0, 0) + w.at<double>(1) * D(1, 1) + w.at<double>(2) * D(2, 2)) / varF;
  Similarity S;
  S.s = s;
  S.R = toGlm(R);
  S.t = mt - s * (S.R * mf);
  return S;
}

Similarity metricFrame(const glm::dvec3& a, const glm::dvec3& b, double metres, const std::vector<glm::dvec3>& floor,
                       const glm::dvec3& above) {
  const double d = glm::length(b - a);
  if (d < 1e-12) throw Error("", "--scale", "the two points coincide");
  if (!(metres > 0)) throw Error("", "--scale", "the distance must be positive");
  Similarity S;
  S.s = metres / d;
  if (floor.size() >= 3) {
    glm::dvec3 n(0.0), c(0.0);
    for (const auto& p : floor) c += p;
    c /= double(floor.size());
    // Newell-free robust normal: largest cross product of pairs around the centroid.
    for (size_t i = 0; i < floor.size(); ++i)
      for (size_t j = i + 1; j < floor.size(); ++j) {
        glm::dvec3 x = glm::cross(floor[i] - c, floor[j] - c);
        if (glm::dot(x, n) < 0) x = -x;
        n += x;
      }
    const double spread = glm::length(floor[1] - floor[0]) + glm::length(floor[2] - floor[0]);
    if (glm::length(n) < 1e-6 * spread * spread)
      throw Error("", "--floor", "the floor points are collinear; pick three points that span the floor");
    n = glm::normalize(n);
    if (glm::dot(above - floor[0], n) < 0) n = -n;
    // Rotation taking n to +Z, keeping the model's x as close to +X as possible.
    glm::dvec3 x = glm::dvec3(1, 0, 0) - n * n.x;
    if (glm::length(x) < 1e-6) x = glm::dvec3(0, 1, 0) - n * n.y;
    x = glm::normalize(x);
    const glm::dvec3 y = glm::cross(n, x);
    glm::dmat3 R;  // rows x, y, n
    for (int k = 0; k < 3; ++k) {
      R[k][0] = x[k];
      R[k][1] = y[k];
      R[k][2] = n[k];
    }
    S.R = R;
    const glm::dvec3 o = floor[0] - n * glm::dot(floor[0] - c, n);  // its foot on the fitted floor
    S.t = -S.s * (R * o);
  }
  return S;
}

CenterAlignment alignCenters(const std::vector<glm::dvec3>& estimated, const std::vector<glm::dvec3>& truth) {
  CenterAlignment a;
  a.S = fitSimilarity(estimated, truth);
  for (size_t i = 0; i < estimated.size(); ++i) a.errors.push_back(glm::length(a.S.apply(estimated[i]) - truth[i]));
  std::vector<double> e = a.errors;
  std::sort(e.begin(), e.end());
  a.median = e.size() % 2 ? e[e.size() / 2] : 0.5 * (e[e.size() / 2 - 1] + e[e.size() / 2]);
  a.max = e.back();
  return a;
}

RelativePose relativePose(const std::vector<glm::dvec2>& p1, const std::vector<glm::dvec2>& p2, const glm::dmat3& K1,
                          const glm::dmat3& K2) {
  if (p1.size() != p2.size() || p1.size() < 8)
    throw Error("", "correspondences", "a relative pose needs 8 or more points clicked in both photos (have " +
                                           std::to_string(std::min(p1.size(), p2.size())) + ")");
  std::vector<cv::Point2d> a, b;
  for (size_t i = 0; i < p1.size(); ++i) {
    a.emplace_back(p1[i].x, p1[i].y);
    b.emplace_back(p2[i].x, p2[i].y);
  }
  // Fundamental matrix by RANSAC (its inliers), then the essential matrix in normalised coordinates.
  std::vector<uchar> fmask;
  const cv::Mat F = cv::findFundamentalMat(a, b, cv::FM_RANSAC, 3.0, 0.999, fmask);
  if (F.empty()) throw Error("", "correspondences", "no fundamental matrix fits the clicks (degenerate configuration?)");
  std::vector<cv::Point2d> na, nb;
  std::vector<int> idx;
  for (size_t i = 0; i < a.size(); ++i) {
    if (!fmask[i]) continue;
    na.emplace_back((a[i].x - K1[2][0]) / K1[0][0], (a[i].y - K1[2][1]) / K1[1][1]);
    nb.emplace_back((b[i].x - K2[2][0]) / K2[0][0], (b[i].y - K2[2][1]) / K2[1][1]);
    idx.push_back(int(i));
  }
  if (na.size() < 6) throw Error("", "correspondences", "too few clicks agree on one epipolar geometry");
  cv::Mat emask;
  const double thr = 3.0 / std::max(K1[0][0], K2[0][0]);
  cv::Mat E = cv::findEssentialMat(na, nb, cv::Mat::eye(3, 3, CV_64F), cv::RANSAC, 0.999, thr, emask);
  if (E.empty() || E.rows < 3 || E.cols != 3)
    throw Error("", "correspondences", "no essential matrix fits the clicks (degenerate configuration?)");
  if (E.rows != 3) E = E.rowRange(0, 3);
  cv::Mat Rm, tm;
  cv::recoverPose(E, na, nb, cv::Mat::eye(3, 3, CV_64F), Rm, tm, emask);
  RelativePose rp;
  rp.inliers.assign(p1.size(), false);
  std::vector<int> in;
  for (size_t k = 0; k < idx.size(); ++k)
    if (emask.at<uchar>(int(k))) {
      rp.inliers[idx[k]] = true;
      in.push_back(idx[k]);
    }
  if (in.size() < 8)
    throw Error("", "correspondences", "only " + std::to_string(in.size()) + " clicks agree on one relative pose; 8 or more are needed");
  glm::dmat3 R = toGlm(cv::Matx33d(Rm));
  glm::dvec3 t(tm.at<double>(0), tm.at<double>(1), tm.at<double>(2));
  t = glm::normalize(t);
  // Non-linear refinement of (R, t) on the Sampson distance in pixels: rotation vector increment
  // (3) and a tangent step of the unit translation (2).
  const glm::dmat3 K1i = glm::inverse(K1), K2i = glm::inverse(K2);
  glm::dvec3 e1 = glm::normalize(glm::cross(t, std::abs(t.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
  glm::dvec3 e2 = glm::cross(t, e1);
  auto pose = [&](const std::vector<double>& x, glm::dmat3& Ro, glm::dvec3& to) {
    Ro = rodrigues({x[0], x[1], x[2]}) * R;
    to = glm::normalize(t + x[3] * e1 + x[4] * e2);
  };
  // Ceres, automatic derivatives; a Huber loss at 1 px keeps a wrong click that RANSAC let in
  // from bending the pose.
  std::vector<double> x(5, 0.0);
  {
    ceres::Problem problem;
    for (int k : in)
      problem.AddResidualBlock(new ceres::AutoDiffCostFunction<SampsonDistance, 1, 5>(new SampsonDistance{
                                   R, K1i, K2i, t, e1, e2, glm::dvec3(p1[k], 1.0), glm::dvec3(p2[k], 1.0)}),
                               new ceres::HuberLoss(1.0), x.data());
    ceres::Solver::Summary summary;
    ceres::Solve(solverOptions(50, ceres::DENSE_QR), &problem, &summary);
  }
  pose(x, rp.R, rp.t);
  double cost = 0;  // squared Sampson distances, without the loss
  {
    glm::dmat3 Ro;
    glm::dvec3 to;
    pose(x, Ro, to);
    const double w[5] = {0, 0, 0, 0, 0};
    for (int k : in) {
      const SampsonDistance d{Ro, K1i, K2i, to, e1, e2, glm::dvec3(p1[k], 1.0), glm::dvec3(p2[k], 1.0)};
      double r = 0;
      d(w, &r);
      cost += r * r;
    }
  }
  rp.fundamentalRms = std::sqrt(std::max(cost, 0.0) / std::max<size_t>(in.size(), 1));
  return rp;
}

CameraSolution solveCameras(const std::vector<Camera>& intr, const std::vector<std::string>& names,
                            const std::vector<Track>& tracks) {
  const int nPhotos = int(intr.size());
  CameraSolution sol;
  sol.cameras = intr;
  sol.posed.assign(nPhotos, false);
  sol.points.resize(tracks.size());
  sol.triangulated.assign(tracks.size(), false);
  // Initial pair: the two photos sharing most tracks.
  int bi = -1, bj = -1;
  size_t best = 0;
  for (int i = 0; i < nPhotos; ++i)
    for (int j = i + 1; j < nPhotos; ++j) {
      size_t n = 0;
      for (const auto& t : tracks) {
        bool hi = false, hj = false;
        for (const auto& c : t.clicks) hi |= c.first == i, hj |= c.first == j;
        n += hi && hj;
      }
      if (n > best) best = n, bi = i, bj = j;
    }
  if (bi < 0 || best < 8)
    throw Error("", "correspondences", "no two photos share 8 or more clicked points (most shared: " + std::to_string(best) + ")");
  std::vector<glm::dvec2> a, b;
  for (const auto& t : tracks) {
    glm::dvec2 pa, pb;
    bool hi = false, hj = false;
    for (const auto& c : t.clicks) {
      if (c.first == bi) pa = c.second, hi = true;
      if (c.first == bj) pb = c.second, hj = true;
    }
    if (hi && hj) a.push_back(pa), b.push_back(pb);
  }
  const RelativePose rp = relativePose(a, b, intr[bi].K, intr[bj].K);
  sol.cameras[bi].R = glm::dmat3(1.0);
  sol.cameras[bi].t = glm::dvec3(0.0);
  sol.cameras[bj].R = rp.R;
  sol.cameras[bj].t = rp.t;
  sol.posed[bi] = sol.posed[bj] = true;
  auto triangulateAll = [&]() {
    for (size_t k = 0; k < tracks.size(); ++k) {
      std::vector<Observation> obs;
      for (const auto& c : tracks[k].clicks)
        if (sol.posed[c.first]) obs.push_back({&sol.cameras[c.first], names[c.first], c.second});
      sol.triangulated[k] = false;
      if (obs.size() < 2) continue;
      try {
        sol.points[k] = triangulatePoint(obs, tracks[k].name);
        sol.triangulated[k] = true;
      } catch (const Error&) {
      }
    }
  };
  triangulateAll();
  // Resection of the remaining photos, most triangulated tracks first.
  std::vector<bool> failed(nPhotos, false);
  for (;;) {
    int next = -1;
    size_t most = 0;
    for (int i = 0; i < nPhotos; ++i) {
      if (sol.posed[i] || failed[i]) continue;
      size_t n = 0;
      for (size_t k = 0; k < tracks.size(); ++k)
        for (const auto& c : tracks[k].clicks) n += c.first == i && sol.triangulated[k];
      if (n > most) most = n, next = i;
    }
    if (next < 0 || most < 6) break;
    std::vector<cv::Point3d> X;
    std::vector<cv::Point2d> x;
    for (size_t k = 0; k < tracks.size(); ++k)
      for (const auto& c : tracks[k].clicks)
        if (c.first == next && sol.triangulated[k]) {
          X.emplace_back(sol.points[k].X.x, sol.points[k].X.y, sol.points[k].X.z);
          x.emplace_back(c.second.x, c.second.y);
        }
    cv::Vec3d rv, tv;
    const cv::Mat K(toCv(intr[next].K));
    std::vector<int> inl;
    if (!cv::solvePnPRansac(X, x, K, cv::noArray(), rv, tv, false, 200, 4.0, 0.999, inl) || inl.size() < 6) {
      failed[next] = true;
      continue;
    }
    std::vector<cv::Point3d> Xi;
    std::vector<cv::Point2d> xi;
    for (int k : inl) Xi.push_back(X[k]), xi.push_back(x[k]);
    cv::solvePnPRefineLM(Xi, xi, K, cv::noArray(), rv, tv);
    sol.cameras[next].R = rodrigues({rv[0], rv[1], rv[2]});
    sol.cameras[next].t = {tv[0], tv[1], tv[2]};
    sol.posed[next] = true;
    triangulateAll();
  }
  // Bundle adjustment: poses of every posed photo but the first, the scale held by the initial
  // pair's second camera, and every triangulated point.
  std::vector<glm::dvec3> X(tracks.size(), glm::dvec3(0.0));
  std::vector<BundleObservation> obs;
  for (size_t k = 0; k < tracks.size(); ++k) {
    if (!sol.triangulated[k]) continue;
    X[k] = sol.points[k].X;
    for (const auto& c : tracks[k].clicks)
      if (sol.posed[c.first]) obs.push_back({c.first, int(k), c.second});
  }
  const BundleReport report = bundleAdjust(sol.cameras, X, obs, {bi}, bj);
  for (size_t k = 0; k < tracks.size(); ++k)
    if (sol.triangulated[k]) sol.points[k].X = X[k];
  triangulateAll();
  sol.rmsError = report.rms;
  sol.bundle = report;
  return sol;
}

BundleReport bundleAdjust(std::vector<Camera>& cameras, std::vector<glm::dvec3>& points,
                          const std::vector<BundleObservation>& observations, const std::vector<int>& fixedCameras,
                          int scaleCamera, const BundleOptions& options) {
  BundleReport rep;
  if (fixedCameras.empty()) throw Error("", "bundle adjustment", "needs at least one camera held fixed (the gauge)");
  for (const auto& o : observations)
    if (o.camera < 0 || size_t(o.camera) >= cameras.size() || o.point < 0 || size_t(o.point) >= points.size())
      throw Error("", "bundle adjustment", "an observation names a camera or point that does not exist");
  std::vector<std::array<double, 6>> pose(cameras.size());
  for (size_t i = 0; i < cameras.size(); ++i) {
    const glm::dvec3 w = rodriguesInv(cameras[i].R);
    pose[i] = {w.x, w.y, w.z, cameras[i].t.x, cameras[i].t.y, cameras[i].t.z};
  }
  std::vector<std::array<double, 3>> X(points.size());
  for (size_t k = 0; k < points.size(); ++k) X[k] = {points[k].x, points[k].y, points[k].z};
  // Observations of points in front of their camera at the start: those solved and reported.
  std::vector<uint8_t> inFront(observations.size(), 0);
  for (size_t i = 0; i < observations.size(); ++i) {
    const auto& o = observations[i];
    const Camera& c = cameras[size_t(o.camera)];
    inFront[i] = (c.R * points[size_t(o.point)] + c.t).z > 0;
  }
  auto rms = [&]() {
    double se = 0;
    size_t n = 0;
    rep.beyondRobust = 0;
    for (size_t i = 0; i < observations.size(); ++i) {
      if (!inFront[i]) continue;
      const auto& o = observations[i];
      const auto& K = cameras[size_t(o.camera)].K;
      const Reprojection f{K[0][0], K[1][1], K[2][0], K[2][1], o.pixel.x, o.pixel.y};
      double r[2];
      if (!f(pose[size_t(o.camera)].data(), X[size_t(o.point)].data(), r)) continue;
      const double e2 = r[0] * r[0] + r[1] * r[1];
      if (!std::isfinite(e2)) continue;
      se += e2;
      ++n;
      rep.beyondRobust += options.robustPixels > 0 && std::sqrt(e2) > 3 * options.robustPixels;
    }
    return n ? std::sqrt(se / double(n)) : 0.0;
  };
  rep.initialRms = rms();
  ceres::Problem problem;
  std::vector<uint8_t> used(cameras.size(), 0);
  for (size_t i = 0; i < observations.size(); ++i) {
    if (!inFront[i]) continue;  // behind it: left out
    const auto& o = observations[i];
    const auto& K = cameras[size_t(o.camera)].K;
    ceres::LossFunction* loss = options.robustPixels > 0 ? new ceres::HuberLoss(options.robustPixels) : nullptr;
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<Reprojection, 2, 6, 3>(
                                 new Reprojection{K[0][0], K[1][1], K[2][0], K[2][1], o.pixel.x, o.pixel.y}),
                             loss, pose[size_t(o.camera)].data(), X[size_t(o.point)].data());
    used[size_t(o.camera)] = 1;
  }
  if (problem.NumResidualBlocks() == 0) throw Error("", "bundle adjustment", "no observation lies in front of its camera");
  bool gauge = false;
  for (int i : fixedCameras)
    if (i >= 0 && size_t(i) < cameras.size() && used[size_t(i)]) {
      problem.SetParameterBlockConstant(pose[size_t(i)].data());
      gauge = true;
    }
  if (!gauge) throw Error("", "bundle adjustment", "the cameras held fixed see none of the points (nothing holds the frame)");
  if (scaleCamera >= 0 && size_t(scaleCamera) < cameras.size() && used[size_t(scaleCamera)] &&
      !problem.IsParameterBlockConstant(pose[size_t(scaleCamera)].data())) {
    int largest = 3;
    for (int k = 4; k < 6; ++k)
      if (std::abs(pose[size_t(scaleCamera)][k]) > std::abs(pose[size_t(scaleCamera)][largest])) largest = k;
    problem.SetManifold(pose[size_t(scaleCamera)].data(), new ceres::SubsetManifold(6, {largest}));
  }
  // Points first in the elimination order: the Schur complement leaves the small camera system.
  auto* order = new ceres::ParameterBlockOrdering;
  for (auto& x : X)
    if (problem.HasParameterBlock(x.data())) order->AddElementToGroup(x.data(), 0);
  for (size_t i = 0; i < pose.size(); ++i)
    if (used[i]) order->AddElementToGroup(pose[i].data(), 1);
  ceres::Solver::Options so = solverOptions(options.maxIterations, ceres::SPARSE_SCHUR);
  so.linear_solver_ordering.reset(order);
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  rep.iterations = int(summary.iterations.size());
  rep.converged = summary.termination_type == ceres::CONVERGENCE;
  for (size_t i = 0; i < cameras.size(); ++i) {
    if (!used[i] || problem.IsParameterBlockConstant(pose[i].data())) continue;  // exactly as given
    cameras[i].R = rodrigues({pose[i][0], pose[i][1], pose[i][2]});
    cameras[i].t = {pose[i][3], pose[i][4], pose[i][5]};
  }
  for (size_t k = 0; k < points.size(); ++k) points[k] = {X[k][0], X[k][1], X[k][2]};
  rep.rms = rms();
  return rep;
}

}  // namespace relume::recon
