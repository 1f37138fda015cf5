// Inputs too large for the machine give a clear error naming the file, never an out-of-memory
// kill: an image whose header claims more pixels than memory holds, a step that runs the machine
// out of memory, a room or polygon beyond Relume's limits.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "relume/geometry/error.h"
#include "relume/geometry/memory.h"
#include "relume/geometry/progress.h"
#include "relume/geometry/validate.h"
#include "relume/image/image.h"

using namespace relume;
namespace fs = std::filesystem;

namespace {
std::string messageOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  } catch (const std::exception& e) {
    return std::string("other exception: ") + e.what();
  }
  return "no error";
}
}  // namespace

TEST(Limits, AnImageLargerThanTheMemoryLeftIsRefusedBeforeItIsRead) {
  // A PPM whose header claims 200 000 x 200 000 pixels (4.8e11 bytes as floats) and holds a few.
  const fs::path file = fs::temp_directory_path() / ("relume_huge_" + std::to_string(std::random_device{}()) + ".ppm");
  std::ofstream(file, std::ios::binary) << "P6\n200000 200000\n255\n" << std::string(64, '\x7f');
  const std::string linear = messageOf([&] { readImageLinear(file.string()); });
  const std::string eight = messageOf([&] { readImage8(file.string()); });
  fs::remove(file);
  for (const std::string& msg : {linear, eight}) {
    EXPECT_NE(msg.find(file.string()), std::string::npos) << msg;
    EXPECT_NE(msg.find("200000x200000"), std::string::npos) << msg;
    EXPECT_NE(msg.find("needs"), std::string::npos) << msg;
    EXPECT_NE(msg.find("available"), std::string::npos) << msg;
  }
}

TEST(Limits, AStepThatRunsTheMachineOutOfMemoryStopsWithAClearError) {
  Progress progress;
  EXPECT_NO_THROW(progress.poll());
  // As if less than the reserve were left: the next poll of any long step stops it.
  detail::setMemoryReserveForTest(availableMemoryBytes() + (size_t(1) << 40));
  const std::string msg = messageOf([&] { progress.poll(); });
  Progress child(progress, 0.2, 0.4);
  const std::string inSubStage = messageOf([&] { child.report(0.5, "refining"); });
  detail::setMemoryReserveForTest(0);
  EXPECT_NE(msg.find("nearly out of memory"), std::string::npos) << msg;
  EXPECT_NE(inSubStage.find("nearly out of memory"), std::string::npos) << inSubStage;
  EXPECT_NO_THROW(progress.poll());
}

TEST(Limits, RoomsAndPolygonsBeyondTheLimitsAreRefused) {
  Scene big;
  big.sourceFile = "scan.obj";
  for (size_t i = 0; i <= kMaxRoomPolygons; ++i) {
    Polygon p;
    p.name = "f" + std::to_string(i);
    const double x = double(i % 1000), y = double(i / 1000);
    p.vertices = {{x, y, 0}, {x + 1, y, 0}, {x + 1, y + 1, 0}};
    p.albedo = glm::dvec3(0.5);
    big.polygons.push_back(p);
  }
  const std::string many = messageOf([&] { validateScene(big); });
  EXPECT_NE(many.find("scan.obj"), std::string::npos) << many;
  EXPECT_NE(many.find("polygons; Relume relights rooms of up to"), std::string::npos) << many;
  Scene one;
  one.sourceFile = "room.json";
  Polygon disc;
  disc.name = "disc";
  disc.albedo = glm::dvec3(0.5);
  for (size_t k = 0; k <= kMaxPolygonVertices; ++k) {
    const double a = 2 * 3.14159265358979 * double(k) / double(kMaxPolygonVertices + 1);
    disc.vertices.push_back({std::cos(a), std::sin(a), 0});
  }
  one.polygons.push_back(disc);
  const std::string corners = messageOf([&] { validateScene(one); });
  EXPECT_NE(corners.find("polygon 'disc'"), std::string::npos) << corners;
  EXPECT_NE(corners.find("vertices; a polygon may have up to"), std::string::npos) << corners;
}
