#pragma once
// Rooms built by the tests themselves (independent of the sample room and the benchmarks).
#include <glm/vec3.hpp>
#include <string>
#include <vector>

#include "relume/radiosity/hierarchy.h"

namespace relume::test {

// Counter-clockwise quad seen from the side of u x v.
std::vector<glm::dvec3> quad(glm::dvec3 o, glm::dvec3 u, glm::dvec3 v);

// Appends an axis-aligned box with outward normals (bottom face optional).
void addBox(std::vector<radiosity::Surface>& out, const std::string& name, glm::dvec3 lo, glm::dvec3 hi,
            glm::dvec3 albedo, bool bottom);

// A closed room W x D x H (normals inward) with one ceiling lamp, a box on the floor and a
// table slab; `lampExitance` is the lamp's emitted radiosity.
std::vector<radiosity::Surface> furnishedRoom(double W = 3.0, double D = 3.5, double H = 2.5,
                                              glm::dvec3 lampExitance = glm::dvec3(60.0, 55.0, 45.0));

}  // namespace relume::test
