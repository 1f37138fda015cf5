#include "relume/project/room_io.h"
#include "relume/project/fisheye_lens.h"
#include "relume/project/save_hooks.h"

#include <fcntl.h>
#include <stdio.h>

#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QSaveFile>
#include <QTemporaryDir>
#include <QTextStream>
#include <atomic>
#include <cctype>
#include <csignal>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <glm/geometric.hpp>
#include <limits>
#include <map>

#include "relume/geometry/error.h"
#include "relume/geometry/validate.h"
#include "relume/image/image.h"

namespace relume {

namespace {

std::string str(const QString& s) { return s.toStdString(); }

// Why a path named inside a project or bundle may lead outside it ("" when it cannot).
std::string pathEscapes(const std::string& p) {
  if (p.empty()) return "";
  const bool drive = p.size() > 1 && p[1] == ':' && std::isalpha((unsigned char)p[0]);
  if (p.front() == '/' || p.front() == '\\' || drive)
    return "is an absolute path: a project or bundle may only name files inside its own folder";
  if (p.front() == ':') return "is not a file name (a leading ':' names Qt's built-in resources)";
  size_t start = 0;
  while (start <= p.size()) {
    const size_t end = std::min(p.find_first_of("/\\", start), p.size());
    if (p.compare(start, end - start, "..") == 0)
      return "leads out of its folder ('..'): a project or bundle may only name files inside its own folder";
    start = end + 1;
  }
  return "";
}

QJsonObject parseJsonObject(const QByteArray& data, const std::string& name) {
  QJsonParseError err;
  const QJsonDocument doc = QJsonDocument::fromJson(data, &err);
  if (err.error != QJsonParseError::NoError) {
    int line = 1;
    for (int i = 0; i < err.offset && i < data.size(); ++i) line += data[i] == '\n';
    throw Error(name, "line " + std::to_string(line), "invalid JSON: " + str(err.errorString()));
  }
  if (!doc.isObject()) throw Error(name, "", "the JSON document is not an object");
  return doc.object();
}

QByteArray readFileBytes(const QString& path) {
  QFile f(path);
  if (!f.exists()) throw Error(str(path), "", "the file does not exist");
  if (!f.open(QIODevice::ReadOnly)) throw Error(str(path), "", "cannot open: " + str(f.errorString()));
  return f.readAll();
}


struct JsonReader {
  std::string file;
  // Paths it reads are confined to the file's folder (a bundle or project; not a file the user
  // named on the command line).
  bool confined = false;
  // The bytes of a further file the JSON names (a virtual object's OBJ), by its name as given.
  FileBytes files;

  [[noreturn]] void fail(const std::string& element, const std::string& what) const {
    throw Error(file, element, what);
  }
  double number(const QJsonValue& v, const std::string& element, const std::string& field) const {
    if (!v.isDouble()) fail(element, field + " must be a number");
    return v.toDouble();
  }
  // A whole number in [lo, hi].
  int integer(const QJsonValue& v, const std::string& element, const std::string& field, int lo, int hi) const {
    const double x = number(v, element, field);
    if (!(x >= lo && x <= hi) || x != std::floor(x))
      fail(element, field + " must be a whole number from " + std::to_string(lo) + " to " + std::to_string(hi));
    return int(x);
  }
  glm::dvec3 vec3(const QJsonValue& v, const std::string& element, const std::string& field) const {
    const QJsonArray a = v.toArray();
    if (!v.isArray() || a.size() != 3) fail(element, field + " must be an array of 3 numbers");
    return {number(a[0], element, field), number(a[1], element, field), number(a[2], element, field)};
  }
  // A file name as the JSON gives it; when confined, relative and without '..'.
  std::string path(const QJsonValue& v, const std::string& element, const std::string& field) const {
    if (!v.isUndefined() && !v.isString()) fail(element, field + " must be a string (a file name)");
    const std::string p = v.toString().toStdString();
    if (confined && !p.empty()) {
      const std::string why = pathEscapes(p);
      if (!why.empty()) fail(element, field + " '" + p + "' " + why);
    }
    return p;
  }
  glm::dmat3 mat3(const QJsonValue& v, const std::string& element, const std::string& field) const {
    const QJsonArray rows = v.toArray();
    if (!v.isArray() || rows.size() != 3) fail(element, field + " must be a 3x3 array");
    glm::dmat3 m(0.0);
    for (int r = 0; r < 3; ++r) {
      const glm::dvec3 row = vec3(rows[r], element, field);
      for (int c = 0; c < 3; ++c) m[c][r] = row[c];  // glm is column-major
    }
    return m;
  }
  std::vector<glm::dvec3> vertices(const QJsonValue& v, const std::string& element) const {
    if (!v.isArray()) fail(element, "vertices must be an array of [x, y, z]");
    std::vector<glm::dvec3> out;
    for (const auto& p : v.toArray()) out.push_back(vec3(p, element, "each vertex"));
    return out;
  }
};

PolygonKind kindFrom(const QString& k, const JsonReader& jr, const std::string& element) {
  if (k.isEmpty() || k == "real") return PolygonKind::Real;
  if (k == "light") return PolygonKind::Light;
  if (k == "window") return PolygonKind::Window;
  if (k == "virtual") return PolygonKind::Virtual;
  jr.fail(element, "unknown kind '" + str(k) + "' (real, light, window or virtual)");
}

QString kindName(PolygonKind k) {
  switch (k) {
    case PolygonKind::Light: return "light";
    case PolygonKind::Window: return "window";
    case PolygonKind::Virtual: return "virtual";
    default: return "real";
  }
}

bool sameVertices(const std::vector<glm::dvec3>& a, const std::vector<glm::dvec3>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (glm::length(a[i] - b[i]) > 1e-6) return false;
  return true;
}

// "two_sided": true | false (absent: one face).
bool twoSidedOf(const QJsonObject& lo, const JsonReader& jr, const std::string& where) {
  const QJsonValue v = lo["two_sided"];
  if (v.isUndefined() || v.isNull()) return false;
  if (!v.isBool()) jr.fail(where, "two_sided must be true or false");
  return v.toBool();
}

// A lamp's photometric file, named relative to the JSON's folder: parsed by its ending (.ies or .ldt).
std::shared_ptr<const PhotometricDistribution> photometryOf(const JsonReader& jr, const std::string& rel,
                                                            const std::string& where) {
  const std::string bytes = jr.files(rel);
  const std::string ext = str(QFileInfo(QString::fromStdString(rel)).suffix().toLower());
  if (ext == "ies") return std::make_shared<const PhotometricDistribution>(parseIes(bytes, rel));
  if (ext == "ldt") return std::make_shared<const PhotometricDistribution>(parseEulumdat(bytes, rel));
  jr.fail(where, "photometry '" + rel + "' must be an IES LM-63 (.ies) or EULUMDAT (.ldt) file");
}

// Lamps: {name, polygon (a polygon name or its vertex list), radiance_rgb | color * strength,
// two_sided, photometry (an .ies or .ldt file)}.
void readLamps(const QJsonArray& arr, const JsonReader& jr, Scene& scene) {
  for (const auto& lv : arr) {
    const QJsonObject lo = lv.toObject();
    Lamp lamp;
    lamp.name = str(lo["name"].toString());
    const std::string where = "lamp '" + lamp.name + "'";
    if (lamp.name.empty()) jr.fail("a lamp", "has no name");
    if (lo.contains("radiance_rgb")) lamp.radiance = jr.vec3(lo["radiance_rgb"], where, "radiance_rgb");
    else if (lo.contains("color") && lo.contains("strength"))
      lamp.radiance = jr.vec3(lo["color"], where, "color") * jr.number(lo["strength"], where, "strength");
    else jr.fail(where, "needs radiance_rgb (or color and strength)");
    lamp.twoSided = twoSidedOf(lo, jr, where);
    lamp.photometryFile = jr.path(lo["photometry"], where, "photometry");
    if (!lamp.photometryFile.empty()) lamp.photometry = photometryOf(jr, lamp.photometryFile, where);
    const QJsonValue pv = lo["polygon"];
    if (pv.isString()) {
      lamp.polygon = scene.findPolygon(str(pv.toString()));
      if (lamp.polygon < 0) jr.fail(where, "names polygon '" + str(pv.toString()) + "', which does not exist");
    } else if (pv.isArray()) {
      const auto verts = jr.vertices(pv, where);
      lamp.polygon = scene.findPolygon("light_" + lamp.name);
      if (lamp.polygon < 0)
        for (size_t i = 0; i < scene.polygons.size(); ++i)
          if (sameVertices(scene.polygons[i].vertices, verts)) lamp.polygon = int(i);
      if (lamp.polygon < 0) {
        Polygon p;
        p.name = "light_" + lamp.name;
        p.group = p.name;
        p.material = p.name;
        p.kind = PolygonKind::Light;
        p.vertices = verts;
        scene.polygons.push_back(p);
        lamp.polygon = int(scene.polygons.size()) - 1;
      }
    } else {
      jr.fail(where, "needs a polygon (a polygon name or a vertex list)");
    }
    scene.polygons[lamp.polygon].kind = PolygonKind::Light;
    if (scene.findLamp(lamp.name) >= 0) jr.fail(where, "is listed twice");
    scene.lamps.push_back(lamp);
  }
}

void readPhotos(const QJsonArray& arr, const JsonReader& jr, Scene& scene) {
  for (const auto& pv : arr) {
    const QJsonObject po = pv.toObject();
    Photo ph;
    ph.name = str(po["name"].toString());
    const std::string where = "photo '" + ph.name + "'";
    if (ph.name.empty()) jr.fail("a photo", "has no name");
    ph.file = jr.path(po["file"], where, "file");
    ph.hdr = jr.path(po["hdr"], where, "hdr");
    if (ph.file.empty() && ph.hdr.empty()) jr.fail(where, "names no image file");
    ph.camera.K = jr.mat3(po["K"], where, "K");
    ph.camera.R = jr.mat3(po["R"], where, "R");
    ph.camera.t = jr.vec3(po["t"], where, "t");
    ph.camera.width = jr.integer(po["width"], where, "width", 1, 1 << 20);
    ph.camera.height = jr.integer(po["height"], where, "height", 1, 1 << 20);
    scene.photos.push_back(ph);
  }
}

struct ObjPolygon {
  std::string object, group, material;
  std::vector<glm::dvec3> vertices;
};
std::vector<ObjPolygon> parseObj(const QByteArray& bytes, const std::string& name);
// For bytes parsed without a folder: any further file is an error.
FileBytes noFiles(const std::string& name) {
  return [name](const std::string& rel) -> std::string { throw Error(name, "", "names " + rel + ", which is not available here"); };
}

void readVariants(const QJsonArray& arr, const JsonReader& jr, Scene& scene) {
  for (const auto& vv : arr) {
    const QJsonObject vo = vv.toObject();
    Variant v;
    v.name = str(vo["name"].toString());
    const std::string where = "variant '" + v.name + "'";
    const QJsonObject lights = vo["lights"].toObject();
    for (auto it = lights.begin(); it != lights.end(); ++it) {
      if (it.value().isArray()) v.lampScale[str(it.key())] = jr.vec3(it.value(), where, "lights");
      else v.lampScale[str(it.key())] = glm::dvec3(jr.number(it.value(), where, "lights"));
    }
    for (const auto& lv : vo["virtual_lights"].toArray()) {
      const QJsonObject lo = lv.toObject();
      Lamp l;
      l.name = str(lo["name"].toString());
      l.radiance = jr.vec3(lo["radiance_rgb"], where, "virtual_lights radiance_rgb");
      l.twoSided = twoSidedOf(lo, jr, where);
      l.photometryFile = jr.path(lo["photometry"], where, "virtual_lights photometry");
      if (!l.photometryFile.empty()) l.photometry = photometryOf(jr, l.photometryFile, where);
      v.virtualLamps.push_back(l);
      v.virtualLampPolygons.push_back(jr.vertices(lo["polygon"], where));
    }
    for (const auto& ov : vo["virtual_objects"].toArray()) {
      const QJsonObject oo = ov.toObject();
      VirtualBox b;
      b.name = str(oo["name"].toString());
      if (oo.contains("fan")) {  // an image-based object: read by whoever draws it
        b.fan = jr.path(oo["fan"], where, "fan");
        if (b.fan.empty()) jr.fail(where, "fan must name an image fan file (relume ibr-fan writes them)");
        b.position = jr.vec3(oo["position"], where, "position");
        if (oo.contains("scale")) b.scale = jr.number(oo["scale"], where, "scale");
        if (!(b.scale > 0) || b.scale > 1e3) jr.fail(where, "scale must be a number above 0 (and at most 1000)");
        if (oo.contains("rotation_degrees")) b.rotationDegrees = jr.number(oo["rotation_degrees"], where, "rotation_degrees");
        v.virtualObjects.push_back(b);
        continue;
      }
      if (oo.contains("obj")) {
        const std::string rel = jr.path(oo["obj"], where, "obj");
        if (rel.empty()) jr.fail(where, "obj must name a mesh file");
        const std::string bytes = jr.files(rel);
        for (auto& op : parseObj(QByteArray(bytes.data(), qsizetype(bytes.size())), rel)) b.mesh.push_back(std::move(op.vertices));
        if (b.mesh.empty()) jr.fail(where, "the mesh " + rel + " has no faces");
      } else {
        b.boxMin = jr.vec3(oo["box_min"], where, "box_min");
        b.boxMax = jr.vec3(oo["box_max"], where, "box_max");
        if (!glm::all(glm::lessThan(b.boxMin, b.boxMax))) jr.fail(where, "box_min must be below box_max on every axis");
      }
      b.albedo = jr.vec3(oo["albedo"], where, "albedo");
      v.virtualObjects.push_back(b);
    }
    v.file = jr.path(vo["file"], where, "file");
    v.hdr = jr.path(vo["hdr"], where, "hdr");
    if (!vo["sun"].isUndefined() && !vo["sun"].isString()) jr.fail(where, "sun must name one of the daylight skies");
    v.sky = str(vo["sun"].toString());
    scene.variants.push_back(v);
  }
}

// Minimal OBJ reader: o (object name), g (group), usemtl (material), v, f (one polygon per face).

std::vector<ObjPolygon> parseObj(const QByteArray& bytes, const std::string& path) {
  QTextStream in(bytes);
  std::vector<glm::dvec3> verts;
  std::vector<ObjPolygon> out;
  std::string object, group, material;
  int lineNo = 0;
  while (!in.atEnd()) {
    const QString line = in.readLine().trimmed();
    ++lineNo;
    if (line.isEmpty() || line.startsWith('#')) continue;
    const QStringList tok = line.split(' ', Qt::SkipEmptyParts);
    const std::string where = "line " + std::to_string(lineNo);
    if (tok[0] == "o") object = str(tok.mid(1).join(' '));
    else if (tok[0] == "g") group = str(tok.mid(1).join(' '));
    else if (tok[0] == "usemtl") material = str(tok.mid(1).join(' '));
    else if (tok[0] == "v") {
      if (tok.size() < 4) throw Error(path, where, "a vertex needs 3 coordinates");
      glm::dvec3 p;
      for (int i = 0; i < 3; ++i) {
        const std::string t = str(tok[i + 1]);
        char* end = nullptr;
        p[i] = std::strtod(t.c_str(), &end);
        if (end == t.c_str() || *end != '\0') throw Error(path, where, "'" + t + "' is not a number");
      }
      verts.push_back(p);
    } else if (tok[0] == "f") {
      ObjPolygon poly{object, group, material, {}};
      for (int i = 1; i < tok.size(); ++i) {
        bool ok = false;
        int idx = tok[i].section('/', 0, 0).toInt(&ok);
        if (!ok) throw Error(path, where, "face index '" + str(tok[i]) + "' is not a number");
        if (idx < 0) idx = int(verts.size()) + 1 + idx;
        if (idx < 1 || idx > int(verts.size()))
          throw Error(path, where, "face index " + std::to_string(idx) + " refers to no vertex");
        poly.vertices.push_back(verts[idx - 1]);
      }
      out.push_back(poly);
    }
  }
  return out;
}

QString resolve(const QString& base, const std::string& rel) {
  return QFileInfo(rel.c_str()).isAbsolute() ? QString::fromStdString(rel) : QDir(base).filePath(QString::fromStdString(rel));
}

}  // namespace

std::string fileInFolder(const std::string& folder, const std::string& rel, const std::string& file,
                         const std::string& element) {
  const std::string why = rel.empty() || rel == "." || rel == "./" ? "is not a file name" : pathEscapes(rel);
  if (!why.empty()) throw Error(file, element, "'" + rel + "' " + why);
  const QString joined = QDir(QString::fromStdString(folder)).filePath(QString::fromStdString(rel));
  // Through symbolic links, the file's real place must stay inside the folder's real place.
  const QString real = QFileInfo(joined).canonicalFilePath();  // empty when it does not exist
  if (!real.isEmpty()) {
    const QString base = QFileInfo(QString::fromStdString(folder)).canonicalFilePath();
    if (base.isEmpty()) throw Error(file, element, "the folder " + folder + " does not exist");
    if (!real.startsWith(base.endsWith('/') ? base : base + "/"))
      throw Error(file, element,
                  "'" + rel + "' is or passes through a symbolic link that leads out of " + folder + " (to " + str(real) +
                      "): refused, a project or bundle may only name files inside its own folder");
  }
  return str(joined);
}

namespace {
// Every file the scene read from a project or bundle names stays inside its folder.
// `jsonFile` is the file that named them (for messages).
void checkConfined(const Scene& scene, const std::string& jsonFile) {
  for (const auto& ph : scene.photos)
    for (const std::string& rel : {ph.file, ph.hdr})
      if (!rel.empty()) fileInFolder(scene.baseDir, rel, jsonFile, "photo '" + ph.name + "'");
  for (const auto& v : scene.variants)
    for (const std::string& rel : {v.file, v.hdr})
      if (!rel.empty()) fileInFolder(scene.baseDir, rel, jsonFile, "variant '" + v.name + "'");
  for (const auto& c : scene.skies)
    for (const std::string& rel : {c.fisheye, c.panorama})
      if (!rel.empty()) fileInFolder(scene.baseDir, rel, jsonFile, "daylight sky '" + c.name + "'");
}
}  // namespace

void checkPhotos(const Scene& scene) {
  for (const auto& ph : scene.photos) {
    for (const std::string& rel : {ph.file, ph.hdr}) {
      if (rel.empty()) continue;
      const std::string path = str(resolve(QString::fromStdString(scene.baseDir), rel));
      int w = 0, h = 0;
      try {
        imageSize(path, w, h);
      } catch (const Error& e) {
        throw Error(scene.sourceFile, "photo '" + ph.name + "'", e.problem() + " (" + path + ")");
      }
      if (w != ph.camera.width || h != ph.camera.height)
        throw Error(scene.sourceFile, "photo '" + ph.name + "'",
                    path + " is " + std::to_string(w) + "x" + std::to_string(h) + " but the camera says " +
                        std::to_string(ph.camera.width) + "x" + std::to_string(ph.camera.height));
    }
  }
}

// "daylight": {"photos_sun": NAME, "sky": [{name, fisheye, fisheye_model, fisheye_position,
// panorama, panorama_position}]}, as a daylight bundle describes its measured skies.
static void readDaylight(const QJsonValue& v, const JsonReader& jr, Scene& scene) {
  if (v.isUndefined() || v.isNull()) return;
  if (!v.isObject()) jr.fail("daylight", "must be an object");
  const QJsonObject d = v.toObject();
  for (const auto& sv : d["sky"].toArray()) {
    const QJsonObject so = sv.toObject();
    SkyCapture c;
    c.name = str(so["name"].toString());
    if (c.name.empty()) jr.fail("daylight sky", "has no name");
    const std::string where = "daylight sky '" + c.name + "'";
    if (scene.findSky(c.name)) jr.fail(where, "is listed twice");
    c.fisheye = jr.path(so["fisheye"], where, "fisheye");
    if (c.fisheye.empty()) jr.fail(where, "names no fisheye image");
    if (!so["fisheye_model"].isString()) jr.fail(where, "fisheye_model must describe the lens in words");
    c.fisheyeModel = str(so["fisheye_model"].toString());
    if (so.contains("fisheye_position")) c.fisheyePosition = jr.vec3(so["fisheye_position"], where, "fisheye_position");
    // A calibrated lens (`relume calibrate --fisheye`): its JSON inline, or the name of its file.
    if (so["fisheye_lens"].isObject()) {
      c.lens = parseFisheyeLens(QJsonDocument(so["fisheye_lens"].toObject()).toJson().toStdString(),
                                jr.file + " (" + where + ", fisheye_lens)");
    } else if (so.contains("fisheye_lens")) {
      const std::string rel = jr.path(so["fisheye_lens"], where, "fisheye_lens");
      if (rel.empty()) jr.fail(where, "fisheye_lens must name the lens's JSON file or hold it");
      c.lens = parseFisheyeLens(jr.files(rel), rel);
    }
    c.panorama = jr.path(so["panorama"], where, "panorama");
    if (so.contains("panorama_position")) c.panoramaPosition = jr.vec3(so["panorama_position"], where, "panorama_position");
    scene.skies.push_back(c);
  }
  scene.photoSky = str(d["photos_sun"].toString());
  if (!scene.photoSky.empty() && !scene.findSky(scene.photoSky))
    jr.fail("daylight photos_sun", "names sky '" + scene.photoSky + "', which is not listed");
  for (const auto& var : scene.variants)
    if (!var.sky.empty() && !scene.findSky(var.sky))
      jr.fail("variant '" + var.name + "'", "sun names sky '" + var.sky + "', which the daylight section does not list");
}

static void readSceneObject(const QJsonObject& root, const JsonReader& jr, Scene& scene, bool polygonsFromJson) {
  if (polygonsFromJson) {
    if (!root["polygons"].isArray()) jr.fail("", "has no 'polygons' array");
    for (const auto& pv : root["polygons"].toArray()) {
      const QJsonObject po = pv.toObject();
      Polygon p;
      p.name = str(po["name"].toString());
      if (p.name.empty()) jr.fail("a polygon", "has no name");
      const std::string where = "polygon '" + p.name + "'";
      if (scene.findPolygon(p.name) >= 0) jr.fail(where, "the name is used twice");
      p.group = str(po["group"].toString());
      p.material = str(po["material"].toString());
      p.kind = kindFrom(po["kind"].toString(), jr, where);
      p.vertices = jr.vertices(po["vertices"], where);
      if (po["albedo"].isArray()) p.albedo = jr.vec3(po["albedo"], where, "albedo");
      else if (p.kind == PolygonKind::Real) jr.fail(where, "has no albedo");
      scene.polygons.push_back(p);
    }
  }
  readLamps(root[root.contains("lamps") ? "lamps" : "lights"].toArray(), jr, scene);
  readPhotos(root["photos"].toArray(), jr, scene);
  scene.mainPhoto = str(root[root.contains("main_photo") ? "main_photo" : "mainPhoto"].toString());
  if (scene.mainPhoto.empty() && !scene.photos.empty()) scene.mainPhoto = scene.photos.front().name;
  if (!scene.mainPhoto.empty() && !scene.findPhoto(scene.mainPhoto))
    jr.fail("main_photo", "names photo '" + scene.mainPhoto + "', which is not listed");
  readVariants(root["variants"].toArray(), jr, scene);
  readDaylight(root["daylight"], jr, scene);
}

namespace {
// Reads the files a JSON in `folder` names, confined to it (fileInFolder) when `confined`.
FileBytes filesIn(const std::string& folder, const std::string& jsonFile, bool confined) {
  return [folder, jsonFile, confined](const std::string& rel) {
    const std::string path = confined ? fileInFolder(folder, rel, jsonFile, "")
                                      : str(QDir(QString::fromStdString(folder)).filePath(QString::fromStdString(rel)));
    const QByteArray b = readFileBytes(QString::fromStdString(path));
    return std::string(b.constData(), size_t(b.size()));
  };
}
std::string bytesOf(const QString& path) {
  const QByteArray b = readFileBytes(path);
  return std::string(b.constData(), size_t(b.size()));
}
}  // namespace

Scene parseBundle(const std::string& sceneJson, const std::string& name, const FileBytes& files) {
  Scene scene;
  scene.sourceFile = name;
  const QJsonObject root = parseJsonObject(QByteArray(sceneJson.data(), qsizetype(sceneJson.size())), name);
  JsonReader jr{scene.sourceFile, true, files ? files : noFiles(name)};
  const bool jsonHasGeometry = root["polygons"].isArray() && !root["polygons"].toArray().isEmpty() &&
                               root["polygons"].toArray()[0].toObject().contains("vertices");
  if (!jsonHasGeometry) {
    // Geometry from geometry.obj; names, kinds and albedos from scene.json's polygon entries.
    const std::string obj = jr.files("geometry.obj");
    std::map<std::string, QJsonObject> meta;
    for (const auto& pv : root["polygons"].toArray()) meta[str(pv.toObject()["name"].toString())] = pv.toObject();
    int n = 0;
    for (const auto& op : parseObj(QByteArray(obj.data(), qsizetype(obj.size())), "geometry.obj")) {
      Polygon p;
      p.name = op.object.empty() ? "polygon_" + std::to_string(n) : op.object;
      if (scene.findPolygon(p.name) >= 0) p.name += "_" + std::to_string(n);
      p.group = op.group;
      p.material = op.material;
      p.vertices = op.vertices;
      if (auto it = meta.find(p.name); it != meta.end()) {
        const std::string where = "polygon '" + p.name + "'";
        p.kind = kindFrom(it->second["kind"].toString(), jr, where);
        if (it->second["albedo"].isArray()) p.albedo = jr.vec3(it->second["albedo"], where, "albedo");
      }
      scene.polygons.push_back(p);
      ++n;
    }
  }
  readSceneObject(root, jr, scene, jsonHasGeometry);
  validateScene(scene);
  return scene;
}

Scene readBundle(const std::string& folder) {
  const std::string json = fileInFolder(folder, "scene.json", folder, "");
  Scene scene = parseBundle(bytesOf(QString::fromStdString(json)), json, filesIn(folder, json, true));
  scene.baseDir = str(QFileInfo(QString::fromStdString(folder)).absoluteFilePath());
  checkConfined(scene, json);
  checkPhotos(scene);
  return scene;
}

Scene parseObjWithJson(const std::string& objBytes, const std::string& objName, const std::string& jsonBytes,
                       const std::string& jsonName, const FileBytes& files) {
  Scene scene;
  scene.sourceFile = objName;
  const QJsonObject root = parseJsonObject(QByteArray(jsonBytes.data(), qsizetype(jsonBytes.size())), jsonName);
  JsonReader jr{jsonName, true, files ? files : noFiles(jsonName)};
  std::map<std::string, glm::dvec3> materials;
  const QJsonObject mats = root["materials"].toObject();
  for (auto it = mats.begin(); it != mats.end(); ++it)
    materials[str(it.key())] = jr.vec3(it.value().isObject() ? it.value().toObject()["albedo"] : it.value(),
                                       "material '" + str(it.key()) + "'", "albedo");
  int n = 0;
  for (const auto& op : parseObj(QByteArray(objBytes.data(), qsizetype(objBytes.size())), objName)) {
    Polygon p;
    p.name = op.object.empty() ? "polygon_" + std::to_string(n) : op.object;
    if (scene.findPolygon(p.name) >= 0) p.name += "_" + std::to_string(n);
    p.group = op.group.empty() ? op.object : op.group;
    p.material = op.material;
    p.vertices = op.vertices;
    if (auto it = materials.find(p.material); it != materials.end()) p.albedo = it->second;
    else if (root.contains("default_albedo")) p.albedo = jr.vec3(root["default_albedo"], "default_albedo", "albedo");
    scene.polygons.push_back(p);
    ++n;
  }
  readSceneObject(root, jr, scene, false);
  scene.sourceFile = objName;
  validateScene(scene);
  return scene;
}

Scene readObjWithJson(const std::string& objPath, const std::string& jsonPath) {
  const std::string folder = str(QFileInfo(QString::fromStdString(jsonPath)).absolutePath());
  Scene scene = parseObjWithJson(bytesOf(QString::fromStdString(objPath)), objPath, bytesOf(QString::fromStdString(jsonPath)),
                                 jsonPath, filesIn(folder, jsonPath, true));
  scene.baseDir = folder;
  checkConfined(scene, jsonPath);
  checkPhotos(scene);
  return scene;
}

Scene readProject(const std::string& projectPath) {
  QFileInfo fi(QString::fromStdString(projectPath));
  const QString json = fi.isDir() ? QString::fromStdString(fileInFolder(projectPath, "project.json", projectPath, ""))
                                  : fi.filePath();
  const QByteArray bytes = readFileBytes(json);
  const std::string folder = str(QFileInfo(json).absolutePath());
  Scene scene = parseProject(std::string(bytes.constData(), size_t(bytes.size())), str(json), filesIn(folder, str(json), true));
  scene.baseDir = folder;
  checkConfined(scene, str(json));
  checkPhotos(scene);
  return scene;
}

Scene parseProject(const std::string& bytes, const std::string& name, const FileBytes& files) {
  Scene scene;
  scene.sourceFile = name;
  const QJsonObject root = parseJsonObject(QByteArray(bytes.data(), qsizetype(bytes.size())), name);
  JsonReader jr{scene.sourceFile, true, files ? files : noFiles(name)};
  if (root["format"].toString() != "relume-project") jr.fail("format", "is not a Relume project (format must be 'relume-project')");
  const int version = root["version"].toInt(-1);
  if (version < 1 || version > kProjectVersion)
    jr.fail("version", "project version " + std::to_string(version) + " is not supported (this Relume reads up to " +
                           std::to_string(kProjectVersion) + ")");
  readSceneObject(root, jr, scene, true);
  validateScene(scene);
  return scene;
}

std::vector<std::vector<glm::dvec3>> parseObjFaces(const std::string& bytes, const std::string& name) {
  std::vector<std::vector<glm::dvec3>> out;
  for (auto& p : parseObj(QByteArray(bytes.data(), qsizetype(bytes.size())), name)) out.push_back(std::move(p.vertices));
  if (out.empty()) throw Error(name, "", "has no faces");
  return out;
}

std::vector<std::vector<glm::dvec3>> readObjFaces(const std::string& path) {
  const QByteArray bytes = readFileBytes(QString::fromStdString(path));
  return parseObjFaces(std::string(bytes.constData(), size_t(bytes.size())), path);
}

Variant parseVariantFile(const std::string& bytes, const std::string& name, const FileBytes& files) {
  const QJsonObject root = parseJsonObject(QByteArray(bytes.data(), qsizetype(bytes.size())), name);
  Scene scene;
  readVariants(QJsonArray{root}, JsonReader{name, false, files ? files : noFiles(name)}, scene);
  Variant v = scene.variants.front();
  if (v.name.empty()) v.name = str(QFileInfo(QString::fromStdString(name)).completeBaseName());
  return v;
}

Variant readVariantFile(const std::string& path) {
  // The user named this file: what it names is the user's choice too (not confined).
  return parseVariantFile(bytesOf(QString::fromStdString(path)), path,
                          filesIn(str(QFileInfo(QString::fromStdString(path)).absolutePath()), path, false));
}

PhotometricDistribution readPhotometricFile(const std::string& path) {
  const std::string bytes = bytesOf(QString::fromStdString(path));
  const QString suffix = QFileInfo(QString::fromStdString(path)).suffix().toLower();
  if (suffix == "ies") return parseIes(bytes, path);
  if (suffix == "ldt") return parseEulumdat(bytes, path);
  if (bytes.find("TILT=") != std::string::npos) return parseIes(bytes, path);
  throw Error(path, "", "is neither an IES LM-63 file (.ies) nor a EULUMDAT file (.ldt)");
}

namespace {
detail::SaveTestHooks& saveHooks() {
  static detail::SaveTestHooks hooks;
  return hooks;
}

// The project a save on this thread is writing now (empty outside saves), for the snapshots.
std::string& currentSaveTarget() {
  thread_local std::string target;
  return target;
}

// RELUME_SAVE_SNAPSHOTS=DIR: what a crash at this step would leave, copied to DIR/<step>/ — the
// project's path and the folders a save keeps beside it, as they are on disk now.
void snapshotSave(long step) {
  static const char* dir = std::getenv("RELUME_SAVE_SNAPSHOTS");
  if (!dir || currentSaveTarget().empty()) return;
  namespace fs = std::filesystem;
  const fs::path target(currentSaveTarget());
  const fs::path to = fs::path(dir) / std::to_string(step);
  std::error_code ec;
  fs::create_directories(to, ec);
  const std::string name = target.filename().string();
  for (const std::string& n : {name, "." + name + ".saving", "." + name + ".previous", "." + name + ".discard"}) {
    const fs::path from = target.parent_path() / n;
    if (!fs::exists(fs::symlink_status(from))) continue;
    // Hard links: as fast as the save itself (a save never writes into a file it wrote before, it
    // writes new files and renames, so a linked file keeps the content it had at this step).
    fs::copy(from, to / n, fs::copy_options::recursive | fs::copy_options::copy_symlinks | fs::copy_options::create_hard_links, ec);
    if (ec) {
      ec.clear();
      fs::remove_all(to / n, ec);
      fs::copy(from, to / n, fs::copy_options::recursive | fs::copy_options::copy_symlinks, ec);
    }
    if (ec) {
      std::fprintf(stderr, "RELUME_SAVE_SNAPSHOTS: cannot copy %s: %s\n", from.c_str(), ec.message().c_str());
      std::abort();
    }
  }
}

// Names the project being saved for the snapshots while it lives.
struct SaveTargetScope {
  explicit SaveTargetScope(const QString& path) { currentSaveTarget() = path.toStdString(); }
  ~SaveTargetScope() { currentSaveTarget().clear(); }
  SaveTargetScope(const SaveTargetScope&) = delete;
  SaveTargetScope& operator=(const SaveTargetScope&) = delete;
};
}  // namespace

detail::SaveTestHooks detail::setSaveTestHooks(SaveTestHooks hooks) {
  std::swap(hooks, saveHooks());
  return hooks;
}

void detail::saveStep(const char* what) {
  if (const auto& hooks = saveHooks(); hooks.step) hooks.step(what);
  static const long crashAt = [] {
    const char* e = std::getenv("RELUME_CRASH_AT_SAVE_STEP");
    return e ? std::atol(e) : 0L;
  }();
  static std::atomic<long> count{0};
  const long step = ++count;
  snapshotSave(step);
  if (crashAt > 0 && step == crashAt) {
    std::fprintf(stderr, "RELUME_CRASH_AT_SAVE_STEP: killed at save step %ld (%s)\n", crashAt, what);
    std::fflush(stderr);
    std::raise(SIGKILL);
  }
}

namespace {
// The folders a save keeps beside the project `path`: its staging folder (the new project being
// written; after the exchange, the old one on its way out), the old project while the fallback
// moves the new one in, and anything being deleted. Only `.previous` is ever a whole project
// that the user's path lacks.
struct SaveFolders {
  QString staging, backup, discard;
  explicit SaveFolders(const QFileInfo& target)
      : staging(target.absolutePath() + "/." + target.fileName() + ".saving"),
        backup(target.absolutePath() + "/." + target.fileName() + ".previous"),
        discard(target.absolutePath() + "/." + target.fileName() + ".discard") {}
};

// Deletes `folder` without ever leaving a half-deleted project under a name that means one:
// renamed to the discard name first (one step), then removed.
// False when it cannot be renamed (it then stays as it was).
bool discardFolder(const QString& folder, const SaveFolders& names) {
  if (!QFileInfo::exists(folder)) return true;
  if (folder != names.discard) {
    QDir(names.discard).removeRecursively();
    if (!QDir().rename(folder, names.discard)) return false;
    detail::saveStep("moved to discard");
  }
  QDir(names.discard).removeRecursively();
  detail::saveStep("removed");
  return true;
}

bool isSaveFolderName(const QString& name) {
  return name.startsWith('.') && (name.endsWith(".saving") || name.endsWith(".previous") || name.endsWith(".discard"));
}
}  // namespace

namespace {
Scene loadRoomAt(const std::string& path);
}

Scene loadRoom(const std::string& path) {
  const QFileInfo fi(QDir::cleanPath(QFileInfo(QString::fromStdString(path)).absoluteFilePath()));
  // Named by its project.json or scene.json, a room is its folder.
  const QFileInfo folderOf = fi.fileName() == "project.json" || fi.fileName() == "scene.json" ? QFileInfo(fi.absolutePath()) : fi;
  if (isSaveFolderName(folderOf.fileName()))
    throw Error(path, "", "is a folder an interrupted or finishing save left behind, not a project: open " +
                              str(folderOf.absolutePath() + "/" +
                                  folderOf.fileName().mid(1, folderOf.fileName().lastIndexOf('.') - 1)));
  const SaveFolders save(folderOf);
  std::vector<std::string> notes;
  if (!folderOf.exists() && QFileInfo::exists(save.backup + "/project.json")) {
    // A save that stopped between its two renames (no atomic exchange) left the old project
    // beside the path: put it back.
    if (!QDir().rename(save.backup, folderOf.absoluteFilePath()))
      throw Error(path, "", "an interrupted save left the project at " + str(save.backup) + ", and it cannot be moved back");
    notes.push_back("an interrupted save had left this project at " + str(save.backup) + "; it was moved back to " + path);
  }
  Scene scene = loadRoomAt(path);
  if (QFileInfo::exists(save.staging))
    notes.push_back("an interrupted save left " + str(save.staging) +
                    " (a copy on its way in or out, not opened); the project at the path is whole, and the next save removes it");
  if (QFileInfo::exists(save.backup))
    notes.push_back("an interrupted save left the previous version of this project at " + str(save.backup) + "; the next save removes it");
  if (QFileInfo::exists(save.discard))
    notes.push_back("an interrupted save left " + str(save.discard) + " (being deleted); the next save removes it");
  scene.notes.insert(scene.notes.begin(), notes.begin(), notes.end());
  return scene;
}

namespace {
Scene loadRoomAt(const std::string& path) {
  const QFileInfo fi(QString::fromStdString(path));
  if (!fi.exists()) throw Error(path, "", "no such file or folder");
  if (fi.isDir()) {
    const QDir d(fi.filePath());
    if (d.exists("project.json")) return readProject(path);
    if (d.exists("scene.json")) return readBundle(path);
    throw Error(path, "", "the folder holds neither scene.json (a room bundle) nor project.json (a Relume project)");
  }
  if (fi.fileName() == "project.json") return readProject(path);
  if (fi.fileName() == "scene.json") return readBundle(str(fi.absolutePath()));
  if (fi.suffix().toLower() == "obj") {
    const QString json = QDir(fi.absolutePath()).filePath(fi.completeBaseName() + ".json");
    if (!QFileInfo::exists(json)) throw Error(path, "", "an OBJ room needs its JSON beside it: " + str(json));
    return readObjWithJson(path, str(json));
  }
  throw Error(path, "", "not a room: give a bundle folder, a Relume project or an .obj with its .json");
}
}  // namespace

// ----------------------------------------------------------------------------------------------
// Writing

namespace {
QJsonArray toJson(const glm::dvec3& v) { return QJsonArray{v.x, v.y, v.z}; }
QJsonArray toJson(const glm::dmat3& m) {
  QJsonArray rows;
  for (int r = 0; r < 3; ++r) rows.append(QJsonArray{m[0][r], m[1][r], m[2][r]});
  return rows;
}
}  // namespace

void saveProject(const Scene& scene, const std::string& folder, Progress& progress,
                 const std::function<void(const std::string&)>& extra) {
  // "room.relume/" and "room.relume" are one folder (the names beside it come from its name).
  const QFileInfo target(QDir::cleanPath(QFileInfo(QString::fromStdString(folder)).absoluteFilePath()));
  const QString parent = target.absolutePath();
  if (!QDir().mkpath(parent)) throw Error(folder, "", "cannot create the parent folder");
  const SaveFolders names(target);
  const SaveTargetScope scope(target.absoluteFilePath());
  const QString staging = names.staging;
  // An earlier save's leftovers.
  if (!discardFolder(staging, names) || !discardFolder(names.discard, names))
    throw Error(folder, "", "cannot remove what an earlier save left in " + str(parent));
  if (!QDir().mkpath(staging + "/photos")) throw Error(folder, "", "cannot create a staging folder in " + str(parent));
  detail::saveStep("staging folder created");
  // Whatever goes wrong while the new project is assembled (a file that cannot be copied, the
  // caller's extra files, Cancel) leaves no staging folder behind.
  try {
    auto abandon = [&](const std::string& why) { throw Error(folder, "", why); };
    QJsonObject root;
    root["format"] = "relume-project";
    // Version 2 only where it matters: a project whose lamps name photometric files (a Relume
    // that reads version 1 would take them for Lambertian faces without a word).
    bool photometric = std::any_of(scene.lamps.begin(), scene.lamps.end(), [](const Lamp& l) { return !l.photometryFile.empty(); });
    for (const auto& v : scene.variants)
      for (const auto& l : v.virtualLamps) photometric = photometric || !l.photometryFile.empty();
    root["version"] = photometric ? kProjectVersion : 1;
    root["units"] = "metres";
    root["up"] = "+Z";
    QJsonArray polys;
    for (const auto& p : scene.polygons) {
      QJsonObject o;
      o["name"] = QString::fromStdString(p.name);
      o["group"] = QString::fromStdString(p.group);
      o["material"] = QString::fromStdString(p.material);
      o["kind"] = kindName(p.kind);
      QJsonArray vs;
      for (const auto& v : p.vertices) vs.append(toJson(v));
      o["vertices"] = vs;
      if (p.kind != PolygonKind::Light) o["albedo"] = toJson(p.albedo);
      polys.append(o);
    }
    root["polygons"] = polys;
    QJsonArray lamps;
    // A file the room names goes along, copied into `sub`/ once however often it is named; files
    // of the same name from different folders are kept apart (NAME_2.ies, ...). Its name in the
    // project is returned.
    std::map<QString, QString> copies;  // source file -> its name in the project
    auto copyInto = [&](const std::string& rel, const QString& sub, const std::string& what) {
      const QString src = QFileInfo(resolve(QString::fromStdString(scene.baseDir), rel)).absoluteFilePath();
      QString& name = copies[src];
      if (name.isEmpty()) {
        const QFileInfo fi(src);
        name = sub + "/" + fi.fileName();
        for (int k = 2; QFileInfo::exists(staging + "/" + name); ++k)
          name = sub + "/" + fi.completeBaseName() + "_" + QString::number(k) + (fi.suffix().isEmpty() ? "" : "." + fi.suffix());
        if (!QDir().mkpath(staging + "/" + sub)) abandon("cannot create the " + str(sub) + " folder");
        if (!QFile::copy(src, staging + "/" + name)) abandon("cannot copy the " + what + " " + str(src));
        detail::saveStep("file copied");
      }
      return name;
    };
    // A variant's file that is not there (an image of the room under that lighting never taken, a
    // fan not made yet) is left out, as reading left it unchecked; nothing of the user's is lost.
    auto present = [&](const std::string& rel) {
      return QFileInfo(resolve(QString::fromStdString(scene.baseDir), rel)).isFile();
    };
    for (const auto& l : scene.lamps) {
      QJsonObject o{{"name", QString::fromStdString(l.name)},
                    {"polygon", QString::fromStdString(scene.polygons[l.polygon].name)},
                    {"radiance_rgb", toJson(l.radiance)},
                    {"two_sided", l.twoSided}};
      // The luminaire's file goes along, copied into photometry/.
      if (!l.photometryFile.empty()) o["photometry"] = copyInto(l.photometryFile, "photometry", "photometric file");
      lamps.append(o);
    }
    root["lamps"] = lamps;
    QJsonArray photos;
    int done = 0;
    for (const auto& ph : scene.photos) {
      progress.report(double(done++) / std::max<size_t>(1, scene.photos.size()), "copying photo " + ph.name);
      QJsonObject o{{"name", QString::fromStdString(ph.name)}};
      for (const auto& [key, rel] : {std::pair<const char*, std::string>{"file", ph.file}, {"hdr", ph.hdr}}) {
        if (rel.empty()) continue;
        const QString src = resolve(QString::fromStdString(scene.baseDir), rel);
        const QString name = "photos/" + QFileInfo(src).fileName();
        if (!QFile::copy(src, staging + "/" + name)) abandon("cannot copy photo " + str(src));
        detail::saveStep("photo copied");
        o[key] = name;
      }
      o["K"] = toJson(ph.camera.K);
      o["R"] = toJson(ph.camera.R);
      o["t"] = toJson(ph.camera.t);
      o["width"] = ph.camera.width;
      o["height"] = ph.camera.height;
      photos.append(o);
    }
    root["photos"] = photos;
    root["main_photo"] = QString::fromStdString(scene.mainPhoto);
    QJsonArray variants;
    for (const auto& v : scene.variants) {
      QJsonObject o{{"name", QString::fromStdString(v.name)}};
      QJsonObject lights;
      for (const auto& [k, s] : v.lampScale) lights[QString::fromStdString(k)] = toJson(s);
      o["lights"] = lights;
      if (!v.sky.empty()) o["sun"] = QString::fromStdString(v.sky);
      // Everything else a variant holds goes along: its virtual lamps (their photometric files
      // copied), its virtual objects (a mesh written as an OBJ file, an image fan copied, into
      // variants/objects/, apart from the workbench's own objects/) and its images of the room
      // under that lighting (copied into variants/).
      QJsonArray vlamps;
      for (size_t i = 0; i < v.virtualLamps.size(); ++i) {
        const Lamp& l = v.virtualLamps[i];
        QJsonArray poly;
        if (i < v.virtualLampPolygons.size())
          for (const auto& p : v.virtualLampPolygons[i]) poly.append(toJson(p));
        QJsonObject lo{{"name", QString::fromStdString(l.name)},
                       {"radiance_rgb", toJson(l.radiance)},
                       {"two_sided", l.twoSided},
                       {"polygon", poly}};
        if (!l.photometryFile.empty()) lo["photometry"] = copyInto(l.photometryFile, "photometry", "photometric file");
        vlamps.append(lo);
      }
      if (!vlamps.isEmpty()) o["virtual_lights"] = vlamps;
      QJsonArray objects;
      for (size_t k = 0; k < v.virtualObjects.size(); ++k) {
        const VirtualBox& b = v.virtualObjects[k];
        QJsonObject oo{{"name", QString::fromStdString(b.name)}};
        if (!b.fan.empty()) {
          if (present(b.fan)) oo["fan"] = copyInto(b.fan, "variants/objects", "image fan");
          else oo["fan"] = QString::fromStdString(b.fan);  // named as it was: refused when drawn, as before
          oo["position"] = toJson(b.position);
          oo["scale"] = b.scale;
          oo["rotation_degrees"] = b.rotationDegrees;
          objects.append(oo);
          continue;
        }
        if (!b.mesh.empty()) {
          // One "f" line per polygon, its own vertices (what readVariants reads back), named by
          // places only: no name a user typed ends up in a path or in the file.
          const QString name = QString("variants/objects/variant%1_object%2.obj").arg(&v - scene.variants.data() + 1).arg(k + 1);
          if (!QDir().mkpath(staging + "/variants/objects")) abandon("cannot create the variants/objects folder");
          QSaveFile f(staging + "/" + name);
          if (!f.open(QIODevice::WriteOnly)) abandon("cannot write " + str(name));
          QByteArray obj = "# a virtual object's mesh (metres, +Z up)\n";
          size_t next = 1;
          for (const auto& face : b.mesh) {
            QByteArray fl = "f";
            for (const auto& p : face) {
              obj += "v " + QByteArray::number(p.x, 'g', 17) + " " + QByteArray::number(p.y, 'g', 17) + " " +
                     QByteArray::number(p.z, 'g', 17) + "\n";
              fl += " " + QByteArray::number(qulonglong(next++));
            }
            obj += fl + "\n";
          }
          f.write(obj);
          if (!f.commit()) abandon("cannot write " + str(name) + ": " + str(f.errorString()));
          detail::saveStep("mesh written");
          oo["obj"] = name;
        } else {
          oo["box_min"] = toJson(b.boxMin);
          oo["box_max"] = toJson(b.boxMax);
        }
        oo["albedo"] = toJson(b.albedo);
        objects.append(oo);
      }
      if (!objects.isEmpty()) o["virtual_objects"] = objects;
      if (!v.file.empty() && present(v.file)) o["file"] = copyInto(v.file, "variants", "variant image");
      if (!v.hdr.empty() && present(v.hdr)) o["hdr"] = copyInto(v.hdr, "variants", "variant image");
      variants.append(o);
    }
    root["variants"] = variants;
    if (!scene.skies.empty()) {
      // The measured skies go along, copied into sky/.
      if (!QDir().mkpath(staging + "/sky")) abandon("cannot create the sky folder");
      QJsonArray skies;
      for (const auto& c : scene.skies) {
        QJsonObject o{{"name", QString::fromStdString(c.name)},
                      {"fisheye_model", QString::fromStdString(c.fisheyeModel)},
                      {"fisheye_position", toJson(c.fisheyePosition)}};
        for (const auto& [key, rel] : {std::pair<const char*, std::string>{"fisheye", c.fisheye}, {"panorama", c.panorama}}) {
          if (rel.empty()) continue;
          const QString src = resolve(QString::fromStdString(scene.baseDir), rel);
          const QString name = "sky/" + QFileInfo(src).fileName();
          if (!QFileInfo::exists(staging + "/" + name)) {
            if (!QFile::copy(src, staging + "/" + name)) abandon("cannot copy the sky image " + str(src));
            detail::saveStep("sky image copied");
          }
          o[key] = name;
        }
        if (!c.panorama.empty()) o["panorama_position"] = toJson(c.panoramaPosition);
        if (c.lens.fx > 0) o["fisheye_lens"] = QJsonDocument::fromJson(QByteArray::fromStdString(fisheyeLensJson(c.lens))).object();
        skies.append(o);
      }
      root["daylight"] = QJsonObject{{"photos_sun", QString::fromStdString(scene.photoSky)}, {"sky", skies}};
    }
    {
      QSaveFile f(staging + "/project.json");
      if (!f.open(QIODevice::WriteOnly)) abandon("cannot write project.json: " + str(f.errorString()));
      f.write(QJsonDocument(root).toJson(QJsonDocument::Indented));
      if (!f.commit()) abandon("cannot write project.json: " + str(f.errorString()));
      detail::saveStep("project.json written");
    }
    if (extra) extra(str(staging));
    // What the project was made from (the clicks and their triangulation) and the workbench's edits
    // stay with it when a project is saved again, unless the caller wrote new ones.
    const bool fromProject = !scene.baseDir.empty() && QFileInfo::exists(QString::fromStdString(scene.baseDir) + "/project.json");
    // A folder of the old project copied in (its files), unless the caller wrote one.
    auto keepFolder = [&](const char* name) {
      const QString src = QString::fromStdString(fileInFolder(scene.baseDir, name, scene.baseDir, ""));
      if (!QFileInfo(src).isDir() || QFileInfo::exists(staging + "/" + name)) return;
      if (!QDir().mkpath(staging + "/" + name)) abandon("cannot create the " + std::string(name) + " folder");
      for (const QFileInfo& fi : QDir(src).entryInfoList(QDir::Files)) {
        if (!QFile::copy(fi.absoluteFilePath(), staging + "/" + name + "/" + fi.fileName()))
          abandon("cannot copy " + str(fi.absoluteFilePath()) + " into the project");
        detail::saveStep("kept file copied");
      }
    };
    if (fromProject)
      for (const char* name : {"clicks.json", "triangulation.json", "workbench.json"}) {
        const QString src = QString::fromStdString(fileInFolder(scene.baseDir, name, scene.baseDir, "")),
                      dst = staging + "/" + name;
        if (!QFileInfo::exists(src) || QFileInfo::exists(dst)) continue;
        if (!QFile::copy(src, dst)) abandon("cannot copy " + str(src) + " into the project");
        detail::saveStep("kept file copied");
        // The workbench's edits name the image fans of the objects it placed (objects/): they go
        // with it.
        if (std::string(name) == "workbench.json") keepFolder("objects");
      }
    // So do a kept daylight session (daylight/, which checks itself against the room, photo,
    // sky and options when it is opened) and the preprocess's results (relight/: its textures and
    // estimates, written by saveRelightProject), unless the caller wrote them: a save from the Sky
    // panel or `relume daylight-basis` does not lose the lamp session's preprocess, nor a save from
    // the workbench the daylight session.
    if (fromProject)
      for (const char* name : {"daylight", "relight"}) keepFolder(name);
    progress.poll();
  } catch (...) {
    QDir(staging).removeRecursively();
    throw;
  }
  auto abandon = [&](const std::string& why) {
    QDir(staging).removeRecursively();
    throw Error(folder, "", why);
  };
  // Into place, crash-consistent: at every instant the user's path holds the old or the new
  // project, or (fallback only) the old one waits beside it where loadRoom finds it.
  const QString path = target.absoluteFilePath();
  const QString& backup = names.backup;
  if (QFileInfo::exists(backup)) {
    // An earlier save stopped after moving the old project aside: with the project at the
    // path, that copy is stale; without it, it is the project (loadRoom puts it back).
    if (!QFileInfo::exists(path)) {
      if (!QDir().rename(backup, path)) abandon("cannot move back " + str(backup));
      detail::saveStep("moved back");
    }
    discardFolder(backup, names);
  }
  const auto& hooks = saveHooks();
  static const bool noExchange = std::getenv("RELUME_SAVE_NO_EXCHANGE") != nullptr;
  detail::saveStep("staged");
  const bool hadOld = QFileInfo::exists(path);
  if (hadOld && hooks.exchange && !noExchange &&
      renameat2(AT_FDCWD, QFile::encodeName(staging).constData(), AT_FDCWD, QFile::encodeName(path).constData(),
                RENAME_EXCHANGE) == 0) {
    // One atomic step: the new project at the path, the old one in the staging folder.
    detail::saveStep("exchanged");
    discardFolder(staging, names);
    detail::saveStep("done");
    return;
  }
  // No atomic exchange here (another file system, or a new path): old -> backup, staging ->
  // path, drop backup. A crash between the two renames leaves the old project as the backup,
  // which loadRoom moves back.
  if (hadOld && !QDir().rename(path, backup)) abandon("cannot move the existing project aside");
  detail::saveStep("moved aside");
  if (!QDir().rename(staging, path)) {
    if (hadOld) QDir().rename(backup, path);
    abandon("cannot move the new project into place");
  }
  detail::saveStep("moved in");
  if (hadOld) discardFolder(backup, names);
  detail::saveStep("done");
}

}  // namespace relume
