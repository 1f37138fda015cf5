#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <fstream>
#include <random>

#include "relume/geometry/error.h"
#include "relume/image/image.h"
#include "relume/project/relight_store.h"
#include "relume/project/fisheye_lens.h"
#include "relume/project/room_io.h"
#include "relume/project/save_hooks.h"
#include "support/error_text.h"
#include "support/replaced.h"

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

std::string text(const fs::path& f) {
  std::ifstream in(f);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

using test::replaced;

using test::errorText;

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

// A crash at any file-system step of a save (the process ends there: no clean-up, no destructors)
// leaves the old or the new project openable at the user's path, with the atomic directory
// exchange and without it (the fallback of two renames, where the next open puts the old project
// back). Every step in turn, until the save completes; then saving again succeeds.
TEST(Project, ACrashAtAnyStepOfASaveLeavesTheOldOrTheNewProject) {
  const Scene s = loadRoom(kSample);
  Scene changed = s;
  changed.polygons[0].albedo = glm::dvec3(0.123, 0.234, 0.345);
  for (bool exchange : {true, false}) {
    int sawNew = 0, sawOld = 0, n = 1;
    for (;; ++n) {
      TempDir tmp;
      const std::string proj = (tmp.path / "room.relume").string();
      saveProject(s, proj);
      const pid_t child = fork();
      ASSERT_GE(child, 0);
      if (child == 0) {
        int step = 0;
        detail::setSaveTestHooks({[&](const char*) {
                                    if (++step == n) std::_Exit(0);
                                  },
                                  exchange});
        try {
          saveProject(changed, proj);
        } catch (...) {
          std::_Exit(2);
        }
        std::_Exit(3);  // the save finished before step n
      }
      int status = 0;
      waitpid(child, &status, 0);
      ASSERT_TRUE(WIFEXITED(status)) << "step " << n;
      if (WEXITSTATUS(status) == 3) break;
      ASSERT_EQ(WEXITSTATUS(status), 0) << "the save failed before step " << n;
      Scene reopened;
      ASSERT_NO_THROW(reopened = loadRoom(proj)) << "crash at step " << n << " (exchange " << exchange << ")";
      const glm::dvec3 a = reopened.polygons[0].albedo;
      const bool isNew = a == changed.polygons[0].albedo, isOld = a == s.polygons[0].albedo;
      EXPECT_TRUE(isNew || isOld) << "crash at step " << n;
      sawNew += isNew;
      sawOld += isOld;
      ASSERT_NO_THROW(saveProject(changed, proj)) << "saving again after a crash at step " << n;
      EXPECT_EQ(loadRoom(proj).polygons[0].albedo, changed.polygons[0].albedo);
      EXPECT_EQ(std::distance(fs::directory_iterator(tmp.path), fs::directory_iterator{}), 1) << "leftovers after step " << n;
    }
    EXPECT_GE(n, 12) << "a save of the sample room has more steps than that";
    EXPECT_GE(sawNew, 2) << "exchange " << exchange;  // after the swap, the new project is there
    EXPECT_GE(sawOld, 10) << "exchange " << exchange;
  }
}

// A project or bundle someone sends may only name files inside its own folder: an absolute
// path, a '..' and a symbolic link leading out are each refused with a message naming the file,
// the element and the path, and nothing outside is read. The same links inside the folder work.
TEST(Confinement, PathsLeadingOutOfAProjectOrBundleAreRefused) {
  TempDir tmp;
  const fs::path outside = tmp.path / "elsewhere";
  fs::create_directories(outside);
  fs::copy_file(kSample + "/photos/main.png", outside / "main.png");
  const std::string proj = (tmp.path / "p.relume").string();
  saveProject(loadRoom(kSample), proj);
  const std::string json = text(fs::path(proj) / "project.json");
  int copies = 0;
  auto variant = [&](const std::string& from, const std::string& to) {
    const fs::path dir = tmp.path / ("copy" + std::to_string(++copies));
    fs::copy(proj, dir, fs::copy_options::recursive);
    std::string j = json;
    j.replace(j.find(from), from.size(), to);
    write(dir / "project.json", j);
    return dir;
  };
  struct Case {
    std::string what;
    fs::path dir;
    std::string expect;
  };
  std::vector<Case> cases = {
      {"absolute", variant("\"photos/main.png\"", "\"" + (outside / "main.png").string() + "\""), "is an absolute path"},
      {"dot-dot", variant("\"photos/main.png\"", "\"photos/../../elsewhere/main.png\""), "leads out of its folder ('..')"},
  };
  {  // a photo file that is a link out
    const fs::path dir = variant("\"main_photo\"", "\"main_photo\"");
    fs::remove(dir / "photos/main.png");
    fs::create_symlink(outside / "main.png", dir / "photos/main.png");
    cases.push_back({"file link", dir, "symbolic link that leads out of"});
  }
  {  // a folder on the way that is a link out
    const fs::path dir = variant("\"main_photo\"", "\"main_photo\"");
    fs::rename(dir / "photos", dir / "real_photos");
    fs::copy_file(dir / "real_photos/main.png", outside / "view0.png");
    fs::create_symlink(outside, dir / "photos");
    cases.push_back({"folder link", dir, "symbolic link that leads out of"});
  }
  for (const auto& c : cases) {
    const std::string msg = errorOf(c.dir.string());
    EXPECT_NE(msg.find(c.expect), std::string::npos) << c.what << ": " << msg;
    EXPECT_NE(msg.find("project.json"), std::string::npos) << c.what << " names the file: " << msg;
    EXPECT_NE(msg.find("photo 'main'"), std::string::npos) << c.what << " names the element: " << msg;
  }
  // A link that stays inside the folder is fine.
  const fs::path inside = variant("\"main_photo\"", "\"main_photo\"");
  fs::rename(inside / "photos/main.png", inside / "photos/main_real.png");
  fs::create_symlink("main_real.png", inside / "photos/main.png");
  EXPECT_NO_THROW(loadRoom(inside.string()));
  // The same in a bundle's scene.json, and a virtual object's OBJ named by a bundle's variant.
  const fs::path bundle = tmp.path / "bundle";
  write(bundle / "scene.json", room("[[0,0,0],[1,0,0],[1,1,0],[0,1,0]]", "[[0,0,1],[0,1,1],[1,1,1],[1,0,1]]",
                                    "[[1,0,0],[0,0,-1],[0,1,0]]", "../elsewhere/main.png"));
  EXPECT_NE(errorOf(bundle.string()).find("leads out of its folder"), std::string::npos) << errorOf(bundle.string());
  std::string withObject = room();
  withObject.insert(withObject.rfind('}'), R"(, "variants": [{"name": "v", "virtual_objects": [{"name": "o", "obj": ")" +
                                               (outside / "box.obj").string() + R"(", "albedo": [0.5, 0.5, 0.5]}]}])");
  write(outside / "box.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\n");
  write(bundle / "scene.json", withObject);
  fs::create_directories(bundle / "photos");
  fs::copy_file(kSample + "/photos/main.png", bundle / "photos/main.png", fs::copy_options::overwrite_existing);
  const std::string objMsg = errorOf(bundle.string());
  EXPECT_NE(objMsg.find("variant 'v': obj"), std::string::npos) << objMsg;
  EXPECT_NE(objMsg.find("is an absolute path"), std::string::npos) << objMsg;
  // A lighting change the user names on the command line is the user's own: its OBJ may be anywhere.
  write(outside / "change.json", R"({"virtual_objects": [{"name": "o", "obj": "box.obj", "albedo": [0.5, 0.5, 0.5]}]})");
  const fs::path userFile = tmp.path / "mine" / "change.json";
  write(userFile, R"({"virtual_objects": [{"name": "o", "obj": ")" + (outside / "box.obj").string() + R"(", "albedo": [0.5, 0.5, 0.5]}]})");
  EXPECT_EQ(readVariantFile(userFile.string()).virtualObjects.size(), 1u);
}

// What an interrupted save leaves beside a project is never taken for one, and the next open says
// what it found: a staging folder opened by mistake is refused, the leftovers are reported, and
// the next save clears them.
TEST(Project, AnInterruptedSavesLeftoversAreReportedAndNeverOpenedAsAProject) {
  TempDir tmp;
  const std::string proj = (tmp.path / "room.relume").string();
  saveProject(loadRoom(kSample), proj);
  const fs::path staging = tmp.path / ".room.relume.saving", backup = tmp.path / ".room.relume.previous";
  fs::copy(proj, staging, fs::copy_options::recursive);
  fs::copy(proj, backup, fs::copy_options::recursive);
  for (const std::string& named : {staging.string(), staging.string() + "/", (staging / "project.json").string()}) {
    const std::string msg = errorOf(named);
    EXPECT_NE(msg.find("not a project"), std::string::npos) << named << ": " << msg;
    EXPECT_NE(msg.find("room.relume"), std::string::npos) << msg;
  }
  const Scene s = loadRoom(proj);
  ASSERT_EQ(s.notes.size(), 2u);
  EXPECT_NE(s.notes[0].find(".room.relume.saving"), std::string::npos) << s.notes[0];
  EXPECT_NE(s.notes[1].find("previous version"), std::string::npos) << s.notes[1];
  saveProject(s, proj + "/");  // the folder, however it is written
  EXPECT_FALSE(fs::exists(staging));
  EXPECT_FALSE(fs::exists(backup));
  EXPECT_EQ(std::distance(fs::directory_iterator(tmp.path), fs::directory_iterator{}), 1);
  EXPECT_TRUE(loadRoom(proj).notes.empty());
  // The project gone and its previous version beside it (a crash between the fallback's two
  // renames): it is moved back, and the note says so.
  fs::rename(proj, backup);
  const Scene back = loadRoom(proj);
  ASSERT_EQ(back.notes.size(), 1u);
  EXPECT_NE(back.notes[0].find("moved back"), std::string::npos) << back.notes[0];
  EXPECT_TRUE(fs::exists(fs::path(proj) / "project.json"));
}

// Each way a project.json can be wrong has its own message naming the element (read from bytes,
// as every reader of projects does).
TEST(Project, EachMalformedProjectFieldIsNamed) {
  const std::string base = text(std::string(RELUME_SOURCE_DIR) + "/tests/fuzz/corpus/project/small.json");
  ASSERT_NO_THROW(parseProject(base, "p.json"));
  auto with = [&](const std::string& from, const std::string& to) { return replaced(base, from, to); };
  const struct {
    std::string what, json, expect;
  } cases[] = {
      {"other format", with("\"relume-project\"", "\"something-else\""), "p.json: format: is not a Relume project"},
      {"newer version", with("\"version\": 1", "\"version\": 99"), "p.json: version: project version 99 is not supported"},
      {"unknown kind", with("\"kind\": \"light\"", "\"kind\": \"lamp\""), "polygon 'light_A': unknown kind 'lamp'"},
      {"polygon named twice", with("\"name\": \"wall_back\"", "\"name\": \"floor\""), "polygon 'floor': the name is used twice"},
      {"polygon without name", with("\"name\": \"wall_back\"", "\"name\": \"\""), "a polygon: has no name"},
      {"albedo of the wrong type", with("\"albedo\": [", "\"albedo\": \"grey\", \"x\": ["), "has no albedo"},
      {"lamp on a missing polygon", with("\"polygon\": \"light_A\"", "\"polygon\": \"light_Z\""), "lamp 'A'"},
      {"main photo not listed", with("\"main_photo\": \"main\"", "\"main_photo\": \"other\""),
       "main_photo: names photo 'other', which is not listed"},
      {"width not a whole number", with("\"width\": 640", "\"width\": 640.5"), "photo 'main': width must be a whole number"},
      {"width of the wrong type", with("\"width\": 640", "\"width\": \"640\""), "photo 'main': width must be a number"},
      {"radiance of two numbers", with("\"radiance_rgb\": [\n    34,", "\"radiance_rgb\": ["),
       "radiance_rgb must be an array of 3 numbers"},
  };
  for (const auto& c : cases) {
    const std::string msg = errorText([&] { parseProject(c.json, "p.json"); });
    EXPECT_NE(msg.find(c.expect), std::string::npos) << c.what << ": " << msg;
  }
}

// The same for relight/relight.json (the fuzzing seed: a preprocessed sample room's project.json
// and relight.json, two 16-bit lengths first).
TEST(Project, EachMalformedRelightFieldIsNamed) {
  const std::string seed = text(std::string(RELUME_SOURCE_DIR) + "/tests/fuzz/corpus/relight/sample_room");
  ASSERT_GT(seed.size(), 4u);
  const size_t la = size_t(uint8_t(seed[0])) | size_t(uint8_t(seed[1])) << 8, lb = size_t(uint8_t(seed[2])) | size_t(uint8_t(seed[3])) << 8;
  const Scene scene = parseProject(seed.substr(4, la), "project.json");
  const std::string base = seed.substr(4 + la, lb);
  ASSERT_NO_THROW(parseRelightJson(base, scene, "relight.json"));
  auto with = [&](const std::string& from, const std::string& to) { return replaced(base, from, to); };
  const struct {
    std::string what, json, expect;
  } cases[] = {
      {"not relighting data", with("\"relume-relight\"", "\"relume-project\""), "relight.json: format: is not 'relume-relight'"},
      {"rays out of range", with("\"visibility_rays\": ", "\"visibility_rays\": 1e9, \"x\": "), "options visibility_rays: must be from 1 to 4096"},
      {"count negative", with("\"joint_fit_elements\": ", "\"joint_fit_elements\": -1, \"x\": "), "estimates joint_fit_elements: must be a whole number"},
      {"texel zero", with("\"texel\": ", "\"texel\": 0, \"x\": "), "has no valid texture grid"},
      {"colour of the wrong type", with("\"exitance_used\": [", "\"exitance_used\": [\"a\", "), "a colour must be 3 finite numbers"},
      {"textures of another room", with("\"textures\": [", "\"textures\": [{}, "), "textures: lists"},
      {"JSON cut short", base.substr(0, base.size() / 2), "relight.json: is not valid JSON"},
  };
  for (const auto& c : cases) {
    const std::string msg = errorText([&] { parseRelightJson(c.json, scene, "relight.json"); });
    EXPECT_NE(msg.find(c.expect), std::string::npos) << c.what << ": " << msg;
  }
}

// A daylight bundle's measured skies (its "daylight" section and each variant's "sun") are read,
// checked, confined to the bundle, and go along into a project.
TEST_F(BadInput, DaylightSkiesAreReadCheckedAndKeptInAProject) {
  auto withDaylight = [](const std::string& fisheye, const std::string& variantSun) {
    std::string j = room();
    j.insert(j.rfind('}'), R"(, "variants": [{"name": "noon", "sun": ")" + variantSun + R"("}],
      "daylight": {"photos_sun": "morning", "sky": [
        {"name": "morning", "fisheye": ")" + fisheye + R"(", "fisheye_model": "equidistant, 180 deg, looking up (+Z), image up = +Y",
         "fisheye_position": [0.5, 0.5, 1.2]},
        {"name": "noon", "fisheye": "sky/noon.exr", "fisheye_model": "equisolid, 180 deg, looking up, image up = -Y"}]})");
    return j;
  };
  const std::string dir = bundle(withDaylight("sky/morning.exr", "noon"));
  writeImage(dir + "/photos/main.png", ImageRGB(64, 48));  // the camera's size
  fs::create_directories(fs::path(dir) / "sky");
  for (const char* f : {"sky/morning.exr", "sky/noon.exr"}) fs::copy_file(kSample + "/photos/main.exr", fs::path(dir) / f);
  const Scene s = loadRoom(dir);
  ASSERT_EQ(s.skies.size(), 2u);
  EXPECT_EQ(s.photoSky, "morning");
  EXPECT_EQ(s.skies[0].fisheye, "sky/morning.exr");
  EXPECT_EQ(s.skies[0].fisheyePosition, glm::dvec3(0.5, 0.5, 1.2));
  EXPECT_EQ(s.variants.at(0).sky, "noon");
  // Into a project: the sky images are copied in and the section written back.
  const std::string proj = (tmp.path / "day.relume").string();
  saveProject(s, proj);
  const Scene p = loadRoom(proj);
  ASSERT_EQ(p.skies.size(), 2u);
  EXPECT_EQ(p.skies[1].fisheyeModel, s.skies[1].fisheyeModel);
  EXPECT_TRUE(fs::exists(fs::path(proj) / p.skies[1].fisheye));
  EXPECT_EQ(p.variants.at(0).sky, "noon");
  // A variant lit by a sky the section does not list, and a fisheye outside the bundle.
  EXPECT_NE(errorOf(bundle(withDaylight("sky/morning.exr", "dusk"))).find("variant 'noon': sun names sky 'dusk'"), std::string::npos);
  EXPECT_NE(errorOf(bundle(withDaylight("../sky.exr", "noon"))).find("daylight sky 'morning': fisheye '../sky.exr' leads out"),
            std::string::npos);
}

// A measured sky's calibrated lens (`relume calibrate --fisheye`), named as a file of the bundle or
// given inline, is read and checked with the room and kept inline in a project.
TEST_F(BadInput, ADaylightSkysCalibratedLensIsReadCheckedAndKeptInAProject) {
  auto withLens = [](const std::string& lensField) {
    std::string j = room();
    j.insert(j.rfind('}'), R"(, "daylight": {"photos_sun": "morning", "sky": [
        {"name": "morning", "fisheye": "sky/morning.exr", "fisheye_model": "180 deg, looking up, image up = +Y",
         "fisheye_lens": )" + lensField + "}]}");
    return j;
  };
  FisheyeLens lens;
  lens.width = 64, lens.height = 48, lens.fx = 20, lens.fy = 20.5, lens.cx = 32.2, lens.cy = 24.1;
  lens.k[0] = 0.02, lens.k[1] = -0.01, lens.k[2] = 0.001;
  lens.circleX = 32, lens.circleY = 24, lens.circleRadius = 23.5;
  const std::string dir = bundle(withLens("\"sky/lens.json\""));
  writeImage(dir + "/photos/main.png", ImageRGB(64, 48));  // the camera's size
  fs::create_directories(fs::path(dir) / "sky");
  fs::copy_file(kSample + "/photos/main.exr", fs::path(dir) / "sky/morning.exr");
  writeFisheyeLens(lens, dir + "/sky/lens.json");
  const Scene s = loadRoom(dir);
  ASSERT_EQ(s.skies.size(), 1u);
  EXPECT_DOUBLE_EQ(s.skies[0].lens.fy, 20.5);
  EXPECT_DOUBLE_EQ(s.skies[0].lens.k[1], -0.01);
  EXPECT_DOUBLE_EQ(s.skies[0].lens.circleRadius, 23.5);
  const std::string proj = (tmp.path / "lens.relume").string();
  saveProject(s, proj);
  EXPECT_NE(text(fs::path(proj) / "project.json").find("OPENCV_FISHEYE"), std::string::npos) << "kept inline";
  const Scene p = loadRoom(proj);
  ASSERT_EQ(p.skies.size(), 1u);
  EXPECT_DOUBLE_EQ(p.skies[0].lens.fx, 20);
  EXPECT_DOUBLE_EQ(p.skies[0].lens.cy, 24.1);
  EXPECT_DOUBLE_EQ(p.skies[0].lens.k[2], 0.001);
  EXPECT_DOUBLE_EQ(p.skies[0].lens.circleX, 32);
  // A lens file of another model, one outside the bundle, and an inline lens with no focal length.
  write(fs::path(dir) / "sky/lens.json", R"({"model": "OPENCV", "width": 64, "height": 48, "fx": 20, "fy": 20, "cx": 32, "cy": 24})");
  const std::string other = errorOf(dir);
  EXPECT_NE(other.find("sky/lens.json"), std::string::npos) << other;
  EXPECT_NE(other.find("OPENCV_FISHEYE"), std::string::npos) << other;
  EXPECT_NE(errorOf(bundle(withLens("\"../lens.json\""))).find("fisheye_lens '../lens.json' leads out"), std::string::npos)
      << errorOf(bundle(withLens("\"../lens.json\"")));
  const std::string inlineBad = errorOf(bundle(withLens(R"({"model": "OPENCV_FISHEYE", "width": 64, "height": 48, "fx": 0, "fy": 20, "cx": 32, "cy": 24})")));
  EXPECT_NE(inlineBad.find("scene.json"), std::string::npos) << inlineBad;
  EXPECT_NE(inlineBad.find("must be positive"), std::string::npos) << inlineBad;
}

// A lamp's photometric file (IES or EULUMDAT) is read with the room, confined to its folder,
// checked, and copied into a project that keeps it.
TEST_F(BadInput, ALampsPhotometricFileIsReadCheckedAndKeptInAProject) {
  auto withPhotometry = [](const std::string& file) {
    return replaced(room(), R"("radiance_rgb": [5,5,5]})", R"("radiance_rgb": [5,5,5], "photometry": ")" + file + R"("})");
  };
  const std::string ies =
      "IESNA:LM-63-2002\n[LUMINAIRE] downlight\nTILT=NONE\n1 1000 1 3 1 1 2 0.2 0.2 0\n1 1 20\n0 45 90\n0\n100 70.7 0\n";
  const std::string dir = bundle(withPhotometry("lamps/downlight.ies"));
  writeImage(dir + "/photos/main.png", ImageRGB(64, 48));  // the camera's size
  write(fs::path(dir) / "lamps/downlight.ies", ies);
  const Scene s = loadRoom(dir);
  ASSERT_EQ(s.lamps.size(), 1u);
  ASSERT_NE(s.lamps[0].photometry, nullptr);
  EXPECT_EQ(s.lamps[0].photometry->lampLumens, 1000.0);
  EXPECT_EQ(s.lamps[0].photometry->luminaire, "downlight");
  const std::string proj = (tmp.path / "lamp.relume").string();
  saveProject(s, proj);
  const Scene p = loadRoom(proj);
  ASSERT_NE(p.lamps.at(0).photometry, nullptr);
  EXPECT_EQ(p.lamps[0].photometryFile, "photometry/downlight.ies");
  EXPECT_EQ(text(fs::path(proj) / "photometry/downlight.ies"), ies);
  EXPECT_NE(text(fs::path(proj) / "project.json").find("\"version\": 2"), std::string::npos);  // older Relumes refuse it
  // A second lamp whose file has the same name but lives in another folder keeps its own.
  {
    Scene two = s;
    Polygon q = two.polygons[two.lamps[0].polygon];
    q.name = "light_M";
    for (auto& v : q.vertices) v.x += 0.2;
    two.polygons.push_back(q);
    Lamp m = two.lamps[0];
    m.name = "M";
    m.polygon = int(two.polygons.size()) - 1;
    m.photometryFile = "other/downlight.ies";
    two.lamps.push_back(m);
    const std::string other = replaced(ies, "[LUMINAIRE] downlight", "[LUMINAIRE] another");
    write(fs::path(dir) / "other/downlight.ies", other);
    const std::string proj2 = (tmp.path / "two.relume").string();
    saveProject(two, proj2);
    const Scene p2 = loadRoom(proj2);
    ASSERT_EQ(p2.lamps.size(), 2u);
    EXPECT_EQ(p2.lamps[0].photometry->luminaire, "downlight");
    EXPECT_EQ(p2.lamps[1].photometry->luminaire, "another");
    EXPECT_NE(p2.lamps[0].photometryFile, p2.lamps[1].photometryFile);
  }
  // Outside the bundle, of another kind, malformed.
  EXPECT_NE(errorOf(bundle(withPhotometry("../downlight.ies"))).find("lamp 'L': photometry '../downlight.ies' leads out"),
            std::string::npos);
  write(fs::path(dir) / "lamps/downlight.txt", ies);
  EXPECT_NE(errorOf(bundle(withPhotometry("lamps/downlight.txt"))).find("must be an IES LM-63 (.ies) or EULUMDAT (.ldt) file"),
            std::string::npos);
  write(fs::path(dir) / "lamps/downlight.ies", replaced(ies, "100 70.7 0", "100 -70.7 0"));
  const std::string negative = errorOf(bundle(withPhotometry("lamps/downlight.ies")));
  EXPECT_NE(negative.find("lamps/downlight.ies"), std::string::npos) << negative;
  EXPECT_NE(negative.find("cannot be negative"), std::string::npos) << negative;
}

// Everything a variant holds goes into a project: its virtual lamps, its virtual objects (a box,
// an OBJ mesh, an image fan) and its images of the room under that lighting — and a kept daylight
// session survives saving the project again without writing a new one (the workbench's Save of a
// lamp-lit room, `relume import`).
TEST_F(BadInput, AVariantsVirtualLampsObjectsAndImagesAndAKeptDaylightSessionAreKeptInAProject) {
  std::string j = room();
  j.insert(j.rfind('}'), R"(, "variants": [{"name": "evening dim", "lights": {"L": 0.5}, "file": "variants/evening.png",
      "virtual_lights": [{"name": "spot", "radiance_rgb": [3, 2, 1], "two_sided": true,
                          "polygon": [[0.2,0.2,0.9],[0.2,0.3,0.9],[0.3,0.3,0.9],[0.3,0.2,0.9]]}],
      "virtual_objects": [{"name": "crate", "box_min": [0.1,0.1,0], "box_max": [0.3,0.3,0.2], "albedo": [0.6,0.5,0.4]},
                          {"name": "wedge", "obj": "objects/wedge.obj", "albedo": [0.3,0.3,0.3]},
                          {"name": "chair", "fan": "objects/chair.fan", "position": [0.5,0.6,0], "scale": 0.8,
                           "rotation_degrees": 30}]}])");
  const std::string dir = bundle(j);
  writeImage(dir + "/photos/main.png", ImageRGB(64, 48));
  fs::create_directories(fs::path(dir) / "variants");
  writeImage(dir + "/variants/evening.png", ImageRGB(64, 48));
  write(fs::path(dir) / "objects/wedge.obj", "v 0.5 0.5 0\nv 0.7 0.5 0\nv 0.5 0.7 0\nv 0.5 0.5 0.3\nf 1 2 3\nf 1 2 4\nf 1 4 3\n");
  write(fs::path(dir) / "objects/chair.fan", "fan bytes");
  const Scene s = loadRoom(dir);
  ASSERT_EQ(s.variants.size(), 1u);
  const std::string proj = (tmp.path / "kept.relume").string();
  saveProject(s, proj);
  fs::remove_all(dir);  // the project must stand on its own
  const Scene p = loadRoom(proj);
  ASSERT_EQ(p.variants.size(), 1u);
  const Variant &a = s.variants[0], &b = p.variants[0];
  EXPECT_EQ(b.name, "evening dim");
  EXPECT_EQ(b.lampScale.at("L"), glm::dvec3(0.5));
  ASSERT_EQ(b.virtualLamps.size(), 1u);
  EXPECT_EQ(b.virtualLamps[0].name, "spot");
  EXPECT_EQ(b.virtualLamps[0].radiance, glm::dvec3(3, 2, 1));
  EXPECT_TRUE(b.virtualLamps[0].twoSided);
  EXPECT_EQ(b.virtualLampPolygons, a.virtualLampPolygons);
  ASSERT_EQ(b.virtualObjects.size(), 3u);
  EXPECT_EQ(b.virtualObjects[0].name, "crate");
  EXPECT_EQ(b.virtualObjects[0].boxMin, glm::dvec3(0.1, 0.1, 0));
  EXPECT_EQ(b.virtualObjects[0].boxMax, glm::dvec3(0.3, 0.3, 0.2));
  EXPECT_EQ(b.virtualObjects[0].albedo, glm::dvec3(0.6, 0.5, 0.4));
  EXPECT_EQ(b.virtualObjects[1].name, "wedge");
  EXPECT_EQ(b.virtualObjects[1].mesh, a.virtualObjects[1].mesh);
  ASSERT_EQ(b.virtualObjects[1].mesh.size(), 3u);
  EXPECT_EQ(b.virtualObjects[1].albedo, glm::dvec3(0.3));
  EXPECT_EQ(b.virtualObjects[2].name, "chair");
  EXPECT_EQ(text(fs::path(proj) / b.virtualObjects[2].fan), "fan bytes");
  EXPECT_EQ(b.virtualObjects[2].position, glm::dvec3(0.5, 0.6, 0));
  EXPECT_EQ(b.virtualObjects[2].scale, 0.8);
  EXPECT_EQ(b.virtualObjects[2].rotationDegrees, 30.0);
  ASSERT_FALSE(b.file.empty());
  EXPECT_EQ(readImageLinear((fs::path(proj) / b.file).string()).width, 64);
  // A kept daylight session stays when the project is saved again without a new one, and one the
  // caller writes replaces it.
  saveProject(p, proj, silentProgress(), [](const std::string& staging) { write(fs::path(staging) / "daylight/solution.bin", "old"); });
  saveProject(loadRoom(proj), proj);
  EXPECT_EQ(text(fs::path(proj) / "daylight/solution.bin"), "old");
  saveProject(loadRoom(proj), proj, silentProgress(), [](const std::string& staging) { write(fs::path(staging) / "daylight/solution.bin", "new"); });
  EXPECT_EQ(text(fs::path(proj) / "daylight/solution.bin"), "new");
  // The preprocess's results (relight/) stay when a save writes only a daylight session (the Sky
  // panel's), and the daylight session when a save writes only relight/ (the workbench's).
  saveProject(loadRoom(proj), proj, silentProgress(), [](const std::string& staging) { write(fs::path(staging) / "relight/relight.json", "lamps"); });
  EXPECT_EQ(text(fs::path(proj) / "daylight/solution.bin"), "new");
  saveProject(loadRoom(proj), proj, silentProgress(), [](const std::string& staging) { write(fs::path(staging) / "daylight/solution.bin", "sky"); });
  EXPECT_EQ(text(fs::path(proj) / "relight/relight.json"), "lamps");
  EXPECT_EQ(text(fs::path(proj) / "daylight/solution.bin"), "sky");
  // And the variants survive a second save too.
  EXPECT_EQ(loadRoom(proj).variants.at(0).virtualObjects.size(), 3u);
  // The workbench's edits and the fans of the objects it placed (objects/) go along together when
  // a save writes neither.
  saveProject(loadRoom(proj), proj, silentProgress(), [](const std::string& staging) {
    write(fs::path(staging) / "workbench.json", "{}");
    write(fs::path(staging) / "objects/image_1.fan", "placed");
  });
  saveProject(loadRoom(proj), proj);
  EXPECT_EQ(text(fs::path(proj) / "objects/image_1.fan"), "placed");
  EXPECT_EQ(text(fs::path(proj) / "workbench.json"), "{}");
}
