#include "relume/project/fisheye_lens.h"

#include <QFile>
#include <QJsonDocument>
#include <QJsonObject>
#include <QSaveFile>
#include <cmath>
#include <utility>

#include "relume/geometry/error.h"

namespace relume {

FisheyeLens parseFisheyeLens(const std::string& bytes, const std::string& name) {
  QJsonParseError err;
  const QJsonDocument doc = QJsonDocument::fromJson(QByteArray(bytes.data(), qsizetype(bytes.size())), &err);
  if (doc.isNull() || !doc.isObject()) throw Error(name, "", "is not JSON: " + err.errorString().toStdString());
  const QJsonObject o = doc.object();
  if (o["model"].toString() != "OPENCV_FISHEYE")
    throw Error(name, "model", "must be OPENCV_FISHEYE (as `relume calibrate --fisheye` writes it), not '" +
                                   o["model"].toString().toStdString() + "'");
  auto number = [&](const QJsonObject& in, const char* key, bool required) {
    const QJsonValue v = in[key];
    if (v.isUndefined() && !required) return 0.0;
    if (!v.isDouble() || !std::isfinite(v.toDouble()))
      throw Error(name, key, "must be a number (as `relume calibrate --fisheye` writes it)");
    return v.toDouble();
  };
  FisheyeLens lens;
  for (auto [key, out] : {std::pair{"width", &lens.width}, {"height", &lens.height}}) {
    const double x = number(o, key, true);
    if (!(x >= 1 && x <= (1 << 20)) || x != std::floor(x)) throw Error(name, key, "must be a whole number of pixels from 1 to 1048576");
    *out = int(x);
  }
  lens.fx = number(o, "fx", true);
  lens.fy = number(o, "fy", true);
  lens.cx = number(o, "cx", true);
  lens.cy = number(o, "cy", true);
  const char* ks[4] = {"k1", "k2", "k3", "k4"};
  for (int i = 0; i < 4; ++i) lens.k[i] = number(o, ks[i], false);
  lens.rms = number(o, "rms_pixels", false);
  if (!(lens.fx > 0) || !(lens.fy > 0)) throw Error(name, "fx, fy", "must be positive (pixels)");
  if (o.contains("circle")) {
    if (!o["circle"].isObject()) throw Error(name, "circle", "must be an object with cx, cy and radius (pixels)");
    const QJsonObject c = o["circle"].toObject();
    lens.circleX = number(c, "cx", true);
    lens.circleY = number(c, "cy", true);
    lens.circleRadius = number(c, "radius", true);
    if (!(lens.circleRadius > 0)) throw Error(name, "circle", "its radius must be positive (pixels)");
  }
  return lens;
}

FisheyeLens readFisheyeLens(const std::string& path) {
  QFile f(QString::fromStdString(path));
  if (!f.open(QIODevice::ReadOnly)) throw Error(path, "", "cannot open the file");
  const QByteArray b = f.readAll();
  return parseFisheyeLens(std::string(b.constData(), size_t(b.size())), path);
}

std::string fisheyeLensJson(const FisheyeLens& lens) {
  QJsonObject o{{"width", lens.width}, {"height", lens.height}, {"model", "OPENCV_FISHEYE"},
                {"fx", lens.fx}, {"fy", lens.fy}, {"cx", lens.cx}, {"cy", lens.cy},
                {"k1", lens.k[0]}, {"k2", lens.k[1]}, {"k3", lens.k[2]}, {"k4", lens.k[3]}, {"rms_pixels", lens.rms}};
  if (lens.circleRadius > 0) o["circle"] = QJsonObject{{"cx", lens.circleX}, {"cy", lens.circleY}, {"radius", lens.circleRadius}};
  return QJsonDocument(o).toJson().toStdString();
}

void writeFisheyeLens(const FisheyeLens& lens, const std::string& path) {
  QSaveFile f(QString::fromStdString(path));
  const std::string bytes = fisheyeLensJson(lens);
  if (!f.open(QIODevice::WriteOnly) || f.write(bytes.data(), qint64(bytes.size())) < 0 || !f.commit())
    throw Error(path, "", "cannot write the file");
}

}  // namespace relume
