// workspace.json, the description `relume reconstruct` leaves beside a COLMAP model (written by
// writeWorkspaceInfo in colmap_driver.cpp; read here without COLMAP's process and database code).
#include <QFile>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <cmath>
#include <filesystem>

#include "relume/geometry/error.h"
#include "relume/reconstruct/colmap_driver.h"

namespace fs = std::filesystem;

namespace relume::recon {

WorkspaceInfo parseWorkspaceInfo(const std::string& bytes, const std::string& name) {
  QJsonParseError err;
  const QJsonDocument doc = QJsonDocument::fromJson(QByteArray(bytes.data(), qsizetype(bytes.size())), &err);
  if (doc.isNull() || !doc.isObject()) throw Error(name, "", "is not JSON: " + err.errorString().toStdString());
  const QJsonObject o = doc.object();
  WorkspaceInfo w;
  auto names = [&](const char* key) {
    std::vector<std::string> out;
    const QJsonValue v = o[key];
    if (v.isUndefined()) return out;
    if (!v.isArray()) throw Error(name, key, "must be a list of photo names");
    for (const auto& e : v.toArray()) {
      if (!e.isString()) throw Error(name, key, "must be a list of photo names");
      out.push_back(e.toString().toStdString());
    }
    return out;
  };
  if (!o["photos"].isUndefined() && !o["photos"].isString()) throw Error(name, "photos", "must be the photos folder (a string)");
  w.photos = o["photos"].toString().toStdString();
  w.registered = names("registered");
  w.leftOut = names("left_out");
  if (!o["points"].isUndefined()) {
    const double n = o["points"].toDouble(-1);
    if (!(n >= 0 && n <= 1e12) || n != std::floor(n)) throw Error(name, "points", "must be a whole number");
    w.points = (long long)n;
  }
  if (!o["metric"].isUndefined() && !o["metric"].isBool()) throw Error(name, "metric", "must be true or false");
  w.metric = o["metric"].toBool();
  return w;
}

std::optional<WorkspaceInfo> readWorkspaceInfo(const std::string& workspace) {
  const std::string path = (fs::path(workspace) / "workspace.json").string();
  QFile f(QString::fromStdString(path));
  if (!f.exists()) return std::nullopt;
  if (!f.open(QIODevice::ReadOnly)) throw Error(path, "", "cannot open: " + f.errorString().toStdString());
  const QByteArray b = f.readAll();
  return parseWorkspaceInfo(std::string(b.constData(), size_t(b.size())), path);
}

}  // namespace relume::recon
