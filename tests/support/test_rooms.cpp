#include "support/test_rooms.h"

#include <glm/geometric.hpp>

namespace relume::test {

std::vector<glm::dvec3> quad(glm::dvec3 o, glm::dvec3 u, glm::dvec3 v) { return {o, o + u, o + u + v, o + v}; }

void addBox(std::vector<radiosity::Surface>& out, const std::string& name, glm::dvec3 lo, glm::dvec3 hi,
            glm::dvec3 albedo, bool bottom) {
  const glm::dvec3 d = hi - lo;
  auto add = [&](const std::string& n, std::vector<glm::dvec3> v) {
    out.push_back({name + "_" + n, std::move(v), albedo, glm::dvec3(0.0)});
  };
  add("top", quad({lo.x, lo.y, hi.z}, {d.x, 0, 0}, {0, d.y, 0}));
  if (bottom) add("bottom", quad(lo, {0, d.y, 0}, {d.x, 0, 0}));
  add("front", quad(lo, {d.x, 0, 0}, {0, 0, d.z}));
  add("back", quad({hi.x, hi.y, lo.z}, {-d.x, 0, 0}, {0, 0, d.z}));
  add("left", quad({lo.x, hi.y, lo.z}, {0, -d.y, 0}, {0, 0, d.z}));
  add("right", quad({hi.x, lo.y, lo.z}, {0, d.y, 0}, {0, 0, d.z}));
}

std::vector<radiosity::Surface> furnishedRoom(double W, double D, double H, glm::dvec3 lampExitance) {
  std::vector<radiosity::Surface> s;
  auto add = [&](const std::string& n, std::vector<glm::dvec3> v, glm::dvec3 rho) {
    s.push_back({n, std::move(v), rho, glm::dvec3(0.0)});
  };
  add("floor", quad({0, 0, 0}, {W, 0, 0}, {0, D, 0}), {0.45, 0.35, 0.25});
  add("ceiling", quad({0, 0, H}, {0, D, 0}, {W, 0, 0}), {0.8, 0.8, 0.8});
  add("wall_back", quad({0, D, 0}, {W, 0, 0}, {0, 0, H}), {0.7, 0.7, 0.65});
  add("wall_front", quad({W, 0, 0}, {-W, 0, 0}, {0, 0, H}), {0.7, 0.7, 0.65});
  add("wall_left", quad({0, 0, 0}, {0, D, 0}, {0, 0, H}), {0.3, 0.6, 0.35});
  add("wall_right", quad({W, D, 0}, {0, -D, 0}, {0, 0, H}), {0.7, 0.7, 0.65});
  addBox(s, "box", {0.4, 0.5, 0.0}, {1.0, 1.1, 0.5}, {0.2, 0.3, 0.7}, false);
  addBox(s, "table", {1.4, 1.6, 0.66}, {2.4, 2.3, 0.7}, {0.6, 0.45, 0.3}, true);
  const double ls = 0.3, lz = H - 0.01;
  s.push_back({"lamp", quad({W / 2 - ls / 2, D / 2 - ls / 2, lz}, {0, ls, 0}, {ls, 0, 0}), glm::dvec3(0.0),
               lampExitance});
  return s;
}

}  // namespace relume::test
