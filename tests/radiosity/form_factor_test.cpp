// Form factors against closed-form values (Howell's catalogue) and reciprocity.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "relume/geometry/polygon.h"
#include "relume/radiosity/form_factor.h"
#include "relume/radiosity/hierarchy.h"
#include "support/test_rooms.h"

using namespace relume;
using namespace relume::radiosity;
using relume::test::quad;

namespace {
// Two directly opposed parallel rectangles a x b at distance c (Howell C-11).
double parallelRectangles(double a, double b, double c) {
  const double X = a / c, Y = b / c;
  const double x1 = 1 + X * X, y1 = 1 + Y * Y;
  return 2.0 / (std::numbers::pi * X * Y) *
         (std::log(std::sqrt(x1 * y1 / (x1 + Y * Y))) + X * std::sqrt(y1) * std::atan(X / std::sqrt(y1)) +
          Y * std::sqrt(x1) * std::atan(Y / std::sqrt(x1)) - X * std::atan(X) - Y * std::atan(Y));
}
// Perpendicular rectangles sharing an edge of length l: from the h x l one to the w x l one (C-14).
double perpendicularRectangles(double l, double h, double w) {
  const double H = h / l, W = w / l;
  const double a = (1 + W * W) * (1 + H * H) / (1 + W * W + H * H);
  const double b = W * W * (1 + W * W + H * H) / ((1 + W * W) * (W * W + H * H));
  const double c = H * H * (1 + H * H + W * W) / ((1 + H * H) * (H * H + W * W));
  return 1.0 / (std::numbers::pi * W) *
         (W * std::atan(1 / W) + H * std::atan(1 / H) - std::sqrt(H * H + W * W) * std::atan(1 / std::sqrt(H * H + W * W)) +
          0.25 * std::log(a * std::pow(b, W * W) * std::pow(c, H * H)));
}
}  // namespace

TEST(FormFactor, AnalyticReferencesAreTheTextbookNumbers) {
  // The two closed forms themselves, against the tabulated values for unit squares.
  EXPECT_NEAR(parallelRectangles(1, 1, 1), 0.19982, 5e-5);
  EXPECT_NEAR(perpendicularRectangles(1, 1, 1), 0.20004, 5e-5);
}

TEST(FormFactor, PointToPolygonMatchesTheDiskFormula) {
  // A disk of radius r at height h straight above: F = r^2 / (h^2 + r^2); a 64-gon approximates it.
  const double r = 0.7, h = 1.3;
  std::vector<glm::dvec3> disk;
  for (int i = 0; i < 64; ++i) {
    const double a = -2 * std::numbers::pi * i / 64;  // clockwise from above: normal points down
    disk.push_back({r * std::cos(a), r * std::sin(a), h});
  }
  const double polygonArea = 0.5 * 64 * r * r * std::sin(2 * std::numbers::pi / 64);
  const double equivalentR2 = polygonArea / std::numbers::pi;
  const double F = pointToPolygonFormFactor({0, 0, 0}, {0, 0, 1}, disk);
  EXPECT_NEAR(F, equivalentR2 / (h * h + equivalentR2), 2e-3);
  // Seen from behind, it sends nothing.
  EXPECT_EQ(pointToPolygonFormFactor({0, 0, 2 * h}, {0, 0, -1}, disk), 0.0);
}

TEST(FormFactor, PointToARectangleAtAnyOffsetIsTheCornerSum) {
  // A point facing up under a parallel rectangle [x0, x1] x [y0, y1] at height c, with the point's
  // foot inside: the sum of the four corner rectangles' closed forms (Howell B-3). Feet near an edge
  // and low heights make edges subtend nearly pi, wide ones nearly 0: every branch of the angle.
  auto corner = [](double a, double b, double c) {
    const double A = a / c, B = b / c, sa = std::sqrt(1 + A * A), sb = std::sqrt(1 + B * B);
    return (A / sa * std::atan(B / sa) + B / sb * std::atan(A / sb)) / (2 * std::numbers::pi);
  };
  const double cases[][5] = {{-1, 1, -1, 1, 1},        {-0.001, 5, -3, 0.002, 0.01}, {-2, 0.3, -0.5, 4, 0.05},
                             {-1e-4, 1e-4, -2, 2, 0.3}, {-7, 2, -1, 9, 3.5},          {-0.4, 0.25, -0.1, 0.6, 1e-3}};
  for (const auto& k : cases) {
    const double x0 = k[0], x1 = k[1], y0 = k[2], y1 = k[3], c = k[4];
    const std::vector<glm::dvec3> rect{{x0, y0, c}, {x0, y1, c}, {x1, y1, c}, {x1, y0, c}};  // facing down
    const double exact = corner(-x0, -y0, c) + corner(x1, -y0, c) + corner(-x0, y1, c) + corner(x1, y1, c);
    EXPECT_NEAR(pointToPolygonFormFactor({0, 0, 0}, {0, 0, 1}, rect), exact, 1e-13)
        << x0 << " " << x1 << " " << y0 << " " << y1 << " at " << c;
  }
}

TEST(FormFactor, ParallelUnitSquaresWithinOnePercent) {
  const auto a = quad({0, 0, 0}, {1, 0, 0}, {0, 1, 0});       // facing up
  const auto b = quad({0, 0, 1}, {0, 1, 0}, {1, 0, 0});       // facing down
  const double exact = parallelRectangles(1, 1, 1);
  EXPECT_NEAR(polygonToPolygonFormFactor(a, b, 4), exact, 0.01 * exact);
  EXPECT_NEAR(polygonToPolygonFormFactor(b, a, 4), exact, 0.01 * exact);
}

TEST(FormFactor, PerpendicularSquaresSharingAnEdgeWithinOnePercent) {
  const auto floor = quad({0, 0, 0}, {1, 0, 0}, {0, 1, 0});  // z = 0, facing up
  const auto wall = quad({0, 0, 0}, {0, 1, 0}, {0, 0, 1});   // x = 0, facing +x
  const double exact = perpendicularRectangles(1, 1, 1);
  EXPECT_NEAR(polygonToPolygonFormFactor(floor, wall, 8), exact, 0.01 * exact);
  EXPECT_NEAR(polygonToPolygonFormFactor(wall, floor, 8), exact, 0.01 * exact);
}

TEST(FormFactor, ReciprocityOfUnequalSkewedPolygons) {
  // A 2 x 0.5 rectangle and a tilted parallelogram: A_i F_ij = A_j F_ji.
  const auto a = quad({0, 0, 0}, {2, 0, 0}, {0, 0.5, 0});
  // A tilted parallelogram above it, facing down and towards it (normal = u x v).
  const auto b = quad({0.3, 1.2, 1.0}, {1.2, 0.3, 0.0}, {0.2, -0.5, 0.4});
  const double Fab = polygonToPolygonFormFactor(a, b, 6), Fba = polygonToPolygonFormFactor(b, a, 6);
  ASSERT_GT(Fab, 0.01);
  EXPECT_NEAR(polygonArea(a) * Fab, polygonArea(b) * Fba, 0.01 * polygonArea(a) * Fab);
}

// The engine's links, refined by its own oracle, carry the same exchange as the closed forms:
// a receiver facing a unit emitter gets irradiance F * B_emitter.
TEST(FormFactor, HierarchicalLinksReproduceAnalyticExchange) {
  for (int config = 0; config < 2; ++config) {
    std::vector<Surface> s;
    if (config == 0) {
      s.push_back({"receiver", quad({0, 0, 0}, {1, 0, 0}, {0, 1, 0}), glm::dvec3(0.5), glm::dvec3(0.0)});
      s.push_back({"emitter", quad({0, 0, 1}, {0, 1, 0}, {1, 0, 0}), glm::dvec3(0.0), glm::dvec3(1.0)});
    } else {
      s.push_back({"receiver", quad({0, 0, 0}, {1, 0, 0}, {0, 1, 0}), glm::dvec3(0.5), glm::dvec3(0.0)});
      s.push_back({"emitter", quad({0, 0, 0}, {0, 1, 0}, {0, 0, 1}), glm::dvec3(0.0), glm::dvec3(1.0)});
    }
    Options o;
    o.epsilon = 0.002;
    o.minArea = 1e-4;
    HierarchicalRadiosity h(s, o);
    h.solve();
    const double exact = config == 0 ? parallelRectangles(1, 1, 1) : perpendicularRectangles(1, 1, 1);
    const double E = h.surfaceIrradiance(0).x;
    EXPECT_NEAR(E, exact, 0.01 * exact) << (config == 0 ? "parallel" : "perpendicular");
    // Reciprocity through the engine: swap the roles.
    std::swap(s[0].exitance, s[1].exitance);
    std::swap(s[0].reflectance, s[1].reflectance);
    HierarchicalRadiosity g(s, o);
    g.solve();
    const double A0 = polygonArea(s[0].vertices), A1 = polygonArea(s[1].vertices);
    EXPECT_NEAR(A1 * g.surfaceIrradiance(1).x, A0 * E, 0.01 * A0 * E);
  }
}

TEST(FormFactor, ElementAverageOfASmallLampCloseBelowALargeElement) {
  // A 12 cm two-sided lamp 2 cm below a 2 x 2 m ceiling element, off its centre: by reciprocity
  // the element's mean factor is A_lamp F_lamp->element / A_element, and F_lamp->element (the
  // lamp's upper face to the big square) is smooth over the lamp. Fixed quadrature points on the
  // element would all miss the 12 cm patch that receives nearly all the light.
  const auto ceiling = quad({0, 0, 1.0}, {0, 2, 0}, {2, 0, 0});  // facing down
  const glm::dvec3 n = polygonNormal(ceiling);
  for (const glm::dvec2 c : {glm::dvec2(0.7, 1.3), glm::dvec2(0.1, 0.1)}) {
    const auto lamp = quad({c.x - 0.06, c.y - 0.06, 0.98}, {0, 0.12, 0}, {0.12, 0, 0});  // faces down
    const std::vector<glm::dvec3> upper(lamp.rbegin(), lamp.rend());
    const double expected = 0.0144 * polygonToPolygonFormFactor(upper, ceiling, 8) / 4.0;
    const auto f = emitterFormFactorOverElement({0, 0, 1.0}, {1, 0, 0}, {0, 1, 0}, n, {}, {0, 0}, {2, 2}, lamp, true);
    EXPECT_NEAR(f.mean, expected, 0.01 * expected) << "lamp at " << c.x << ", " << c.y;
    EXPECT_GT(f.maximum, 0.5);  // straight above the lamp
    EXPECT_LT(f.minimum, 0.01 * f.maximum);
  }
}

TEST(FormFactor, ElementAverageOfOpposedSquaresIsHowells) {
  for (double c : {0.05, 0.3, 1.0}) {
    const auto emitter = quad({0, 0, c}, {0, 0.5, 0}, {0.5, 0, 0});  // facing down, over the element
    const auto f = emitterFormFactorOverElement({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {}, {0, 0}, {0.5, 0.5}, emitter, false);
    EXPECT_NEAR(f.mean, parallelRectangles(0.5, 0.5, c), 0.005 * parallelRectangles(0.5, 0.5, c)) << "distance " << c;
  }
}

TEST(FormFactor, ElementAverageOverAClippedElementMatchesAFineGrid) {
  // A triangle (plane coordinates) inside the element's rectangle, a lamp 10 cm above one corner.
  const std::vector<glm::dvec2> tri{{0, 0}, {1, 0}, {0, 1}};
  const auto lamp = quad({-0.1, -0.1, 0.1}, {0, 0.2, 0}, {0.2, 0, 0});
  double sum = 0;
  int count = 0;
  const int N = 600;
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j) {
      const glm::dvec2 uv((i + 0.5) / N, (j + 0.5) / N);
      if (!insideConvex2D(tri, uv)) continue;
      sum += emitterFormFactor({uv.x, uv.y, 0}, {0, 0, 1}, lamp, false);
      ++count;
    }
  const double expected = sum / count;
  const auto f = emitterFormFactorOverElement({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, tri, {0, 0}, {1, 1}, lamp, false);
  EXPECT_NEAR(f.mean, expected, 0.01 * expected);
}
