#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "relume/geometry/error.h"
#include "relume/project/room_io.h"
#include "relume/project/save_hooks.h"

#include <sys/wait.h>
#include <unistd.h>

using namespace relume;
namespace fs = std::filesystem;

namespace {
const std::string kSample = std::string(RELUME_SOURCE_DIR) + "/resources/sample_room";

struct TempDir {
  fs::path path;
  TempDir() {
    std::random_device rd;
    path = fs::temp_directory_path() / ("relume_test_" + std::to_string(rd()));
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
};

void write(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

// A minimal valid bundle: a closed unit room (inward normals) with a lamp and one photo.
std::string room(const std::string& floorVerts = "[[0,0,0],[1,0,0],[1,1,0],[0,1,0]]",
                 const std::string& ceilingVerts = "[[0,0,1],[0,1,1],[1,1,1],[1,0,1]]",
                 const std::string& R = "[[1,0,0],[0,0,-1],[0,1,0]]",
                 const std::string& photo = "photos/main.png") {
  return R"({"polygons": [
    {"name": "floor", "kind": "real", "albedo": [0.5,0.5,0.5], "vertices": )" + floorVerts + R"(},
    {"name": "ceiling", "kind": "real", "albedo": [0.5,0.5,0.5], "vertices": )" + ceilingVerts + R"(},
    {"name": "wall_a", "kind": "real", "albedo": [0.5,0.5,0.5], "vertices": [[0,0,0],[0,1,0],[0,1,1],[0,0,1]]},
    {"name": "wall_b", "kind": "real", "albedo": [0.5,0.5,0.5], "vertices": [[1,1,0],[1,0,0],[1,0,1],[1,1,1]]},
    {"name": "light_L", "kind": "light", "albedo": null, "vertices": [[0.4,0.4,0.99],[0.4,0.6,0.99],[0.6,0.6,0.99],[0.6,0.4,0.99]]}
  ],
  "lights": [{"name": "L", "polygon": [[0.4,0.4,0.99],[0.4,0.6,0.99],[0.6,0.6,0.99],[0.6,0.4,0.99]], "radiance_rgb": [5,5,5]}],
  "photos": [{"name": "main", "file": ")" + photo + R"(", "K": [[100,0,32],[0,100,24],[0,0,1]], "R": )" + R +
         R"(, "t": [-0.5, 0.5, 0.5], "width": 64, "height": 48}],
  "main_photo": "main"})";
}

std::string errorOf(const std::string& folder) {
  try {
    loadRoom(folder);
  } catch (const Error& e) {
    return e.what();
  } catch (const std::exception& e) {
    return std::string("other exception: ") + e.what();
  }
  return "no error";
}

struct BadInput : ::testing::Test {
  TempDir tmp;
  std::string bundle(const std::string& json, bool withPhoto = true) {
    const fs::path dir = tmp.path / "room";
    write(dir / "scene.json", json);
    fs::create_directories(dir / "photos");
    if (withPhoto) fs::copy_file(kSample + "/photos/main.png", dir / "photos/main.png", fs::copy_options::overwrite_existing);
    return dir.string();
  }
};
}  // namespace

TEST(RoomIo, ReadsTheSampleRoom) {
  const Scene s = loadRoom(kSample);
  EXPECT_GE(s.polygons.size(), 30u);
  EXPECT_GE(s.lamps.size(), 2u);
  EXPECT_GE(s.photos.size(), 7u);
  EXPECT_EQ(s.mainPhoto, "main");
  ASSERT_GE(s.findPolygon("floor"), 0);
  EXPECT_GE(s.variants.size(), 2u);
  for (const auto& l : s.lamps) EXPECT_EQ(s.polygons[l.polygon].kind, PolygonKind::Light);
}

TEST_F(BadInput, PhotoSizeMismatchIsReportedWithTheCameraSize) {
  // Our minimal room's camera says 64x48; the sample photo is larger.
  const std::string msg = errorOf(bundle(room()));
  EXPECT_NE(msg.find("photo 'main'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("camera says 64x48"), std::string::npos) << msg;
}

TEST_F(BadInput, EachMalformedInputHasItsOwnMessage) {
  struct Case {
    std::string what, json, expect;
  };
  const std::vector<Case> cases = {
      {"two vertices", room("[[0,0,0],[1,0,0]]"), "polygon 'floor': has 2 distinct vertices"},
      {"zero area", room("[[0,0,0],[1,0,0],[2,0,0]]"), "polygon 'floor': has zero area"},
      {"non-planar", room("[[0,0,0],[1,0,0],[1,1,0.2],[0,1,0]]"), "polygon 'floor': is not planar"},
      {"non-convex", room("[[0,0,0],[1,0,0],[0.5,0.2,0],[1,1,0],[0,1,0]]"), "polygon 'floor': is not convex"},
      {"outward normal", room("[[0,0,0],[1,0,0],[1,1,0],[0,1,0]]", "[[0,0,1],[1,0,1],[1,1,1],[0,1,1]]"),
       "polygon 'ceiling': its normal points out of the room"},
      {"R not a rotation", room(), "photo 'main': camera R is not a rotation"},
      {"missing photo", room(), "photo 'main': the image file does not exist"},
      {"unreadable photo", room(), "photo 'main': cannot read the image"},
      {"bad JSON", "{\"polygons\": [1, 2,", "invalid JSON"},
  };
  for (const auto& c : cases) {
    std::string json = c.json;
    bool photo = true;
    if (c.what == "R not a rotation") json = room("[[0,0,0],[1,0,0],[1,1,0],[0,1,0]]", "[[0,0,1],[0,1,1],[1,1,1],[1,0,1]]", "[[2,0,0],[0,0,-1],[0,1,0]]");
    if (c.what == "missing photo") photo = false;
    const std::string dir = bundle(json, photo);
    if (c.what == "unreadable photo") write(fs::path(dir) / "photos/main.png", "this is not a PNG");
    if (c.what == "missing photo") fs::remove(fs::path(dir) / "photos/main.png");
    const std::string msg = errorOf(dir);
    EXPECT_NE(msg.find(c.expect), std::string::npos) << c.what << ": " << msg;
    EXPECT_NE(msg.find("scene.json"), std::string::npos) << c.what << " names the file: " << msg;
  }
}

TEST_F(BadInput, NaNAndInfinityInAnObjAreNamed) {
  const fs::path obj = tmp.path / "room.obj";
  write(tmp.path / "room.json", R"({"materials": {"m": [0.5, 0.5, 0.5]}})");
  for (const std::string bad : {"nan", "inf"}) {
    write(obj, "o floor\nusemtl m\nv 0 0 0\nv 1 0 0\nv 1 1 " + bad + "\nv 0 1 0\nf 1 2 3 4\n");
    std::string msg;
    try {
      loadRoom(obj.string());
    } catch (const Error& e) {
      msg = e.what();
    }
    EXPECT_NE(msg.find("polygon 'floor': vertex 2 has a NaN or infinite coordinate"), std::string::npos) << msg;
    EXPECT_NE(msg.find("room.obj"), std::string::npos) << msg;
  }
}

TEST(Project, SaveAndReloadKeepTheRoomAndAFailedSaveKeepsTheOldProject) {
  TempDir tmp;
  const Scene s = loadRoom(kSample);
  const std::string proj = (tmp.path / "sample.relume").string();
  saveProject(s, proj);
  const Scene p = loadRoom(proj);
  ASSERT_EQ(p.polygons.size(), s.polygons.size());
  for (size_t i = 0; i < s.polygons.size(); ++i) {
    EXPECT_EQ(p.polygons[i].name, s.polygons[i].name);
    EXPECT_EQ(p.polygons[i].vertices, s.polygons[i].vertices);
    EXPECT_EQ(p.polygons[i].albedo, s.polygons[i].albedo);
  }
  ASSERT_EQ(p.lamps.size(), s.lamps.size());
  EXPECT_EQ(p.lamps[0].radiance, s.lamps[0].radiance);
  ASSERT_EQ(p.photos.size(), s.photos.size());
  EXPECT_EQ(p.photos[0].camera.R, s.photos[0].camera.R);
  EXPECT_TRUE(fs::exists(tmp.path / "sample.relume/photos/main.png"));
  // A save that fails half-way (a photo vanished) leaves the previous project readable as it was.
  Scene broken = s;
  broken.photos.back().file = "photos/does_not_exist.png";
  EXPECT_THROW(saveProject(broken, proj), Error);
  const Scene again = loadRoom(proj);
  EXPECT_EQ(again.photos.back().file, p.photos.back().file);
  EXPECT_FALSE(fs::exists(tmp.path / ".sample.relume.saving"));
}

TEST(Project, SavingAProjectAgainKeepsTheClicksItWasMadeFrom) {
  // A project of `relume triangulate` holds clicks.json and triangulation.json: saving it again
  // (the workbench's Save) must not drop them, and a caller that writes new ones wins.
  TempDir tmp;
  const std::string proj = (tmp.path / "clicked.relume").string();
  saveProject(loadRoom(kSample), proj, silentProgress(), [](const std::string& staging) {
    write(fs::path(staging) / "clicks.json", "{\"points\": {}, \"polygons\": []}");
    write(fs::path(staging) / "triangulation.json", "{\"points\": {}}");
  });
  const Scene p = loadRoom(proj);
  saveProject(p, proj);
  auto text = [](const fs::path& f) {
    std::ifstream in(f);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  EXPECT_EQ(text(fs::path(proj) / "clicks.json"), "{\"points\": {}, \"polygons\": []}");
  EXPECT_EQ(text(fs::path(proj) / "triangulation.json"), "{\"points\": {}}");
  saveProject(loadRoom(proj), proj, silentProgress(),
              [](const std::string& staging) { write(fs::path(staging) / "clicks.json", "{}"); });
  EXPECT_EQ(text(fs::path(proj) / "clicks.json"), "{}");
  EXPECT_TRUE(fs::exists(fs::path(proj) / "triangulation.json"));
  // Saved elsewhere ("Save As"), they go along.
  const std::string other = (tmp.path / "copy.relume").string();
  saveProject(loadRoom(proj), other);
  EXPECT_EQ(text(fs::path(other) / "clicks.json"), "{}");
}

// A crash at any file-system step of a save (the process ends there) leaves the old or the new
// project openable at the user's path: with the atomic directory exchange, and without it (the
// fallback of two renames, where the next open puts the old project back).
TEST(Project, ACrashAtAnyStepOfASaveLeavesTheOldOrTheNewProject) {
  const Scene s = loadRoom(kSample);
  Scene changed = s;
  changed.polygons[0].albedo = glm::dvec3(0.123, 0.234, 0.345);
  for (bool exchange : {true, false}) {
    const std::vector<std::string> steps = exchange ? std::vector<std::string>{"staged", "exchanged", "done"}
                                                    : std::vector<std::string>{"staged", "moved aside", "moved in", "done"};
    int sawNew = 0;
    for (const auto& crashAt : steps) {
      TempDir tmp;
      const std::string proj = (tmp.path / "room.relume").string();
      saveProject(s, proj);
      const pid_t child = fork();
      ASSERT_GE(child, 0);
      if (child == 0) {
        detail::setSaveTestHooks({[&](const char* step) {
                                    if (crashAt == step) std::_Exit(0);  // no clean-up, no destructors
                                  },
                                  exchange});
        try {
          saveProject(changed, proj);
        } catch (...) {
          std::_Exit(2);
        }
        std::_Exit(3);  // the step was never reached
      }
      int status = 0;
      waitpid(child, &status, 0);
      ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "crash at '" << crashAt << "' was not reached";
      Scene reopened;
      ASSERT_NO_THROW(reopened = loadRoom(proj)) << "crash at '" << crashAt << "' (exchange " << exchange << ")";
      const glm::dvec3 a = reopened.polygons[0].albedo;
      const bool isNew = a == changed.polygons[0].albedo, isOld = a == s.polygons[0].albedo;
      EXPECT_TRUE(isNew || isOld) << "crash at '" << crashAt << "'";
      sawNew += isNew;
    }
    EXPECT_GE(sawNew, 2) << "exchange " << exchange;  // after the swap, the new project is there
  }
}
