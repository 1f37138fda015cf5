#include "relume/reconstruct/colmap_driver.h"

#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QProcess>
#include <QSaveFile>
#include <QSqlDatabase>
#include <QSqlError>
#include <QSqlQuery>
#include <QVariant>
#include <QProcessEnvironment>
#include <QStandardPaths>
#include <QStringList>

#include <chrono>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <regex>
#include <set>

#include "relume/geometry/error.h"
#include "relume/reconstruct/multiview.h"
#include "relume/reconstruct/photos.h"

namespace fs = std::filesystem;

namespace relume::recon {

std::string findColmap(const std::string& preferred) {
  std::string name = preferred;
  if (name.empty()) {
    const char* env = std::getenv("RELUME_COLMAP");
    name = env && *env ? env : "colmap";
  }
  if (name.find('/') != std::string::npos) {
    if (fs::exists(name)) return name;
    throw Error(name, "", "COLMAP is not there (RELUME_COLMAP or --colmap names a missing file)");
  }
  const QString found = QStandardPaths::findExecutable(QString::fromStdString(name));
  if (found.isEmpty())
    throw Error(name, "", "COLMAP is not installed or not on PATH; install it (Debian: apt-get install colmap) "
                          "or name the executable with RELUME_COLMAP");
  return found.toStdString();
}

void runColmapStep(const std::string& colmap, const std::vector<std::string>& args, const std::string& what,
                   Progress& progress, const std::function<void(const std::string&)>& onLine) {
  QProcess proc;
  QProcessEnvironment env = QProcessEnvironment::systemEnvironment();
  env.insert("QT_QPA_PLATFORM", "offscreen");  // COLMAP links Qt; no display is needed
  proc.setProcessEnvironment(env);
  proc.setProcessChannelMode(QProcess::MergedChannels);
  QStringList qargs;
  for (const auto& a : args) qargs << QString::fromStdString(a);
  proc.start(QString::fromStdString(colmap), qargs);
  if (!proc.waitForStarted(10000))
    throw Error(colmap, what, "could not be started: " + proc.errorString().toStdString());
  // However this function is left (a progress report that throws Cancelled from onLine, too),
  // COLMAP does not outlive it.
  struct KillOnExit {
    QProcess& p;
    ~KillOnExit() {
      if (p.state() != QProcess::NotRunning) {
        p.kill();
        p.waitForFinished(5000);
      }
    }
  } killOnExit{proc};
  std::deque<std::string> tail;
  std::string pending;
  auto consume = [&]() {
    pending += proc.readAll().toStdString();
    size_t nl;
    while ((nl = pending.find('\n')) != std::string::npos) {
      std::string line = pending.substr(0, nl);
      pending.erase(0, nl + 1);
      if (!line.empty() && line.back() == '\r') line.pop_back();
      if (line.empty()) continue;
      tail.push_back(line);
      if (tail.size() > 12) tail.pop_front();
      if (onLine) onLine(line);
    }
  };
  while (!proc.waitForFinished(100)) {
    consume();
    if (progress.cancelled()) {
      proc.kill();
      proc.waitForFinished(5000);
      throw Cancelled();
    }
    if (proc.state() == QProcess::NotRunning) break;
  }
  consume();
  if (!pending.empty()) tail.push_back(pending);
  if (proc.exitStatus() != QProcess::NormalExit || proc.exitCode() != 0) {
    std::string last;
    for (const auto& l : tail) last += "\n    " + l;
    throw Error(colmap, what, "failed (exit code " + std::to_string(proc.exitCode()) + "); its last lines:" + last);
  }
}

namespace {
struct DbImage {
  int id = 0, camera = 0;
};
// Image and camera ids COLMAP's database gave each image name (ids follow the order in which
// the extraction threads finished, so they must be read back).
std::map<std::string, DbImage> databaseImages(const std::string& dbPath) {
  std::map<std::string, DbImage> out;
  const QString conn = QString("relume-colmap-%1").arg(reinterpret_cast<quintptr>(&out));
  {
    QSqlDatabase db = QSqlDatabase::addDatabase("QSQLITE", conn);
    db.setDatabaseName(QString::fromStdString(dbPath));
    if (!db.open())
      throw Error(dbPath, "", "cannot open COLMAP's database (Qt's SQLite driver, Debian libqt6sql6-sqlite): " +
                                  db.lastError().text().toStdString());
    QSqlQuery q(db);
    if (!q.exec("SELECT image_id, name, camera_id FROM images"))
      throw Error(dbPath, "images", "cannot be read: " + q.lastError().text().toStdString());
    while (q.next()) out[q.value(1).toString().toStdString()] = {q.value(0).toInt(), q.value(2).toInt()};
    db.close();
  }
  QSqlDatabase::removeDatabase(conn);
  return out;
}

std::string num(double v) {
  char b[64];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}
}  // namespace

ColmapRun runColmap(const std::string& photosDir, const std::string& workspace, const ColmapOptions& opt,
                    Progress& progress) {
  // Options first: nothing expensive runs with a bad one.
  if (opt.matcher != "exhaustive" && opt.matcher != "sequential")
    throw Error("", "--matcher", "must be exhaustive or sequential, not '" + opt.matcher + "'");
  if (!opt.cameraModel.empty()) {
    const int need = ColmapCamera::parameterCount(opt.cameraModel);
    if (need < 0) throw Error("", "--camera", "camera model " + opt.cameraModel + " is not supported (" + ColmapCamera::supportedModels() + ")");
    if (int(opt.cameraParams.size()) != need)
      throw Error("", "--camera", opt.cameraModel + " takes " + std::to_string(need) + " parameters, not " + std::to_string(opt.cameraParams.size()));
  }
  // The photos COLMAP will see: 8-bit images, each checked to be readable first (named if not).
  std::vector<std::string> names;
  for (const auto& f : listPhotos(photosDir)) {
    if (isRadianceFile(f)) continue;
    readImage8(f);  // decodes the whole file: a truncated image is named here, not deep in COLMAP
    names.push_back(fs::path(f).filename().string());
  }
  ColmapModel known;
  ColmapOptions o = opt;
  if (!opt.knownCameras.empty()) {
    known = readColmapModel(opt.knownCameras);
    std::vector<std::string> inModel;
    for (const auto& nm : names)
      if (known.findImage(nm)) inModel.push_back(nm);
    names = inModel;
    // The database's cameras get the known intrinsics.
    if (known.cameras.size() == 1) {
      const ColmapCamera& c = known.cameras.begin()->second;
      o.singleCamera = true;
      o.cameraModel = c.model;
      o.cameraParams = c.params;
    } else {
      o.singleCamera = false;
    }
  }
  if (names.size() < 2) throw Error(photosDir, "", "holds " + std::to_string(names.size()) + " photo(s)" +
                                                  (known.images.empty() ? "" : " that the known cameras name") +
                                                  "; reconstruction needs two or more");
  const std::string colmap = findColmap(opt.executable);
  const fs::path ws(workspace), scratch = ws / "colmap";
  std::error_code ec;
  fs::create_directories(scratch, ec);
  if (ec) throw Error(workspace, "", "cannot create the workspace: " + ec.message());
  const fs::path db = scratch / "database.db";
  fs::remove(db, ec);
  fs::remove(scratch / "features.db", ec);
  fs::remove_all(scratch / "sparse", ec);
  fs::create_directories(scratch / "sparse");
  // Only the 8-bit photos: a list file, so COLMAP leaves the EXRs alone.
  const fs::path list = scratch / "image_list.txt";
  {
    FILE* f = std::fopen(list.c_str(), "w");
    if (!f) throw Error(list.string(), "", "cannot write the file");
    for (const auto& n : names) std::fprintf(f, "%s\n", n.c_str());
    std::fclose(f);
  }
  const std::string threads = std::to_string(opt.threads);
  ColmapRun run;
  const double n = double(names.size());
  using clock = std::chrono::steady_clock;

  // 1. Features (CPU SIFT).
  auto t0 = clock::now();
  {
    Progress sub(progress, 0.0, 0.3);
    std::vector<std::string> a = {"feature_extractor", "--database_path", db.string(), "--image_path", photosDir,
                                  "--image_list_path", list.string(), "--SiftExtraction.use_gpu", "0",
                                  "--SiftExtraction.num_threads", threads, "--SiftExtraction.domain_size_pooling",
                                  opt.dspSift ? "1" : "0", "--SiftExtraction.estimate_affine_shape", opt.dspSift ? "1" : "0",
                                  "--SiftExtraction.peak_threshold",
                                  num(opt.siftPeakThreshold), "--ImageReader.single_camera", o.singleCamera ? "1" : "0"};
    if (!o.cameraModel.empty()) {
      std::string params;
      for (double p : o.cameraParams) params += (params.empty() ? "" : ",") + num(p);
      a.insert(a.end(), {"--ImageReader.camera_model", o.cameraModel, "--ImageReader.camera_params", params});
    }
    const std::regex re(R"(Processed file \[(\d+)/(\d+)\])");
    sub.report(0, "COLMAP: extracting features of " + std::to_string(names.size()) + " photos");
    runColmapStep(colmap, a, "feature_extractor", sub, [&](const std::string& line) {
      std::smatch m;
      if (std::regex_search(line, m, re))
        sub.report(std::stod(m[1]) / std::max(1.0, std::stod(m[2])), "COLMAP: features " + m[1].str() + "/" + m[2].str());
    });
  }
  auto t1 = clock::now();
  double matchSeconds = 0, mapSeconds = 0;
  std::string lastProblem;
  // 2 + 3. Matching, then incremental mapping (or the points of known cameras). The outcome
  // depends on the RANSAC of the pairs' verification: now and then a room's matches lead the
  // mapper to a wrong model. So each attempt matches afresh (own seed) on a copy of the
  // features; when two attempts agree, the one explaining more observations is kept, else a
  // third decides (the model that agrees best with the others).
  const fs::path features = scratch / "features.db";
  fs::rename(db, features, ec);
  if (ec) throw Error(db.string(), "", "cannot keep COLMAP's features: " + ec.message());
  const bool knownPoses = !known.images.empty();
  const int maxAttempts = knownPoses ? 1 : std::max(1, opt.attempts);
  auto attempt = [&](int k, Progress& prog) -> std::vector<ColmapModel> {
    const fs::path dbk = scratch / ("database" + std::to_string(k) + ".db");
    fs::copy_file(features, dbk, fs::copy_options::overwrite_existing);
    const std::string seed = std::to_string(k + 1);
    auto m0 = clock::now();
    {
      Progress sub(prog, 0.0, 0.8);
      const bool seq = opt.matcher == "sequential";
      std::vector<std::string> a = {seq ? "sequential_matcher" : "exhaustive_matcher", "--database_path", dbk.string(),
                                    "--random_seed", seed, "--SiftMatching.use_gpu", "0", "--SiftMatching.num_threads",
                                    threads, "--SiftMatching.guided_matching", opt.guidedMatching ? "1" : "0",
                                    "--SiftMatching.max_error", num(opt.matchMaxError)};
      const std::regex re(R"(Matching (?:block|image) \[(\d+)/(\d+))");
      sub.report(0, "COLMAP: matching (" + opt.matcher + "), attempt " + seed);
      runColmapStep(colmap, a, opt.matcher + "_matcher", sub, [&](const std::string& line) {
        std::smatch m;
        if (std::regex_search(line, m, re))
          sub.report(std::stod(m[1]) / std::max(1.0, std::stod(m[2])), "COLMAP: matching " + m[1].str() + "/" + m[2].str());
      });
    }
    auto m1 = clock::now();
    matchSeconds += std::chrono::duration<double>(m1 - m0).count();
    const fs::path out = scratch / "sparse" / ("attempt" + seed);
    fs::create_directories(out);
    Progress sub(prog, 0.8, 1.0);
    if (knownPoses) {
      const auto dbImages = databaseImages(dbk.string());
      ColmapModel input;
      for (const auto& nm : names) {
        const auto it = dbImages.find(nm);
        if (it == dbImages.end()) throw Error(dbk.string(), "image " + nm, "is missing from COLMAP's database");
        const ColmapImage& ki = *known.findImage(nm);
        ColmapCamera cam = known.cameras.at(ki.camera);
        cam.id = it->second.camera;
        input.cameras[cam.id] = cam;
        ColmapImage im = ki;
        im.id = it->second.id;
        im.camera = cam.id;
        im.name = nm;
        im.points.clear();
        input.images[im.id] = im;
      }
      writeColmapText(input, (scratch / "known").string());
      fs::create_directories(out / "0");
      sub.report(0, "COLMAP: triangulating points with the known cameras");
      runColmapStep(colmap,
                    {"point_triangulator", "--database_path", dbk.string(), "--image_path", photosDir, "--input_path",
                     (scratch / "known").string(), "--output_path", (out / "0").string(), "--Mapper.num_threads", threads,
                     "--Mapper.ba_refine_focal_length", "0", "--Mapper.ba_refine_principal_point", "0",
                     "--Mapper.ba_refine_extra_params", "0"},
                    "point_triangulator", sub, {});
    } else {
      std::vector<std::string> a = {"mapper", "--database_path", dbk.string(), "--image_path", photosDir, "--output_path",
                                    out.string(), "--random_seed", seed, "--Mapper.num_threads", threads,
                                    "--Mapper.min_model_size", "2", "--Mapper.init_min_num_inliers",
                                    std::to_string(opt.initMinInliers), "--Mapper.abs_pose_min_num_inliers",
                                    std::to_string(opt.absPoseMinInliers)};
      if (!opt.cameraModel.empty())
        a.insert(a.end(), {"--Mapper.ba_refine_focal_length", "0", "--Mapper.ba_refine_principal_point", "0",
                           "--Mapper.ba_refine_extra_params", "0"});
      const std::regex re(R"(Registering image #\d+ \((\d+)\))");
      sub.report(0, "COLMAP: mapping, attempt " + seed);
      try {
        runColmapStep(colmap, a, "mapper", sub, [&](const std::string& line) {
          std::smatch m;
          if (std::regex_search(line, m, re))
            sub.report(std::stod(m[1]) / n, "COLMAP: registered " + m[1].str() + " of " + std::to_string(names.size()) + " photos");
        });
      } catch (const Error& e) {
        lastProblem = e.problem();  // COLMAP 3.8 exits with an error when a run makes no model at all
      }
    }
    mapSeconds += std::chrono::duration<double>(clock::now() - m1).count();
    std::vector<ColmapModel> models;
    for (const auto& e : fs::directory_iterator(out))
      if (e.is_directory() && (fs::exists(e.path() / "cameras.bin") || fs::exists(e.path() / "cameras.txt")))
        models.push_back(readColmapModel(e.path().string()));
    return models;
  };
  // The most complete model of an attempt (then the one explaining most observations).
  auto observations = [](const ColmapModel& m) {
    size_t obs = 0;
    for (const auto& [id, pt] : m.points) obs += pt.track.size();
    return obs;
  };
  auto better = [&](const ColmapModel& a, const ColmapModel& b) {
    return a.images.size() != b.images.size() ? a.images.size() > b.images.size() : observations(a) > observations(b);
  };
  auto disagreement = [&](const ColmapModel& a, const ColmapModel& b) {
    std::vector<glm::dvec3> ca, cb;
    for (const auto& [id, im] : a.images)
      if (const ColmapImage* o = b.findImage(im.name)) ca.push_back(im.center()), cb.push_back(o->center());
    if (ca.size() < 3) return 1e9;
    try {
      const CenterAlignment al = alignCenters(ca, cb);
      // Relative to the spread of the reference cameras, so that the models' scales do not matter.
      glm::dvec3 mean(0.0);
      for (const auto& c : cb) mean += c / double(cb.size());
      double spread = 0;
      for (const auto& c : cb) spread += glm::length(c - mean) / double(cb.size());
      return spread > 0 ? al.median / spread : 1e9;
    } catch (const Error&) {
      return 1e9;
    }
  };
  std::vector<ColmapModel> best;  // per attempt
  for (int k = 0; k < maxAttempts; ++k) {
    Progress sub(progress, 0.3 + 0.65 * k / maxAttempts, 0.3 + 0.65 * (k + 1) / maxAttempts);
    const auto models = attempt(k, sub);
    if (models.empty()) continue;
    const ColmapModel* b = &models.front();
    for (const auto& m : models)
      if (better(m, *b)) b = &m;
    best.push_back(*b);
    // Two complete attempts that agree (within 2 % of the cameras' spread) settle it.
    if (best.size() == 2 && best[0].images.size() == best[1].images.size() &&
        disagreement(best[0], best[1]) < 0.02)
      break;
  }
  int bestImages = -1;
  for (const auto& m : best) bestImages = std::max(bestImages, int(m.images.size()));
  double bestScore = 1e300;
  for (const auto& m : best) {
    if (int(m.images.size()) != bestImages) continue;
    double score = 0;
    for (const auto& o : best)
      if (&o != &m && int(o.images.size()) == bestImages) score += disagreement(m, o);
    if (score < bestScore - 1e-12 || (score <= bestScore + 1e-12 && observations(m) > observations(run.model)))
      bestScore = std::min(score, bestScore), run.model = m;
  }
  if (bestImages < 0) {
    std::string all;
    for (const auto& nm : names) all += (all.empty() ? "" : ", ") + nm;
    throw Error(photosDir, "COLMAP mapper",
                "fewer than 2 photos registered (0 of " + std::to_string(names.size()) + "; left out: " + all +
                    "). Too little overlap or texture: try more photos, known intrinsics (--camera/--intrinsics), or "
                    "clicked correspondences (`relume triangulate` without a model)." +
                    (lastProblem.empty() ? "" : " " + lastProblem));
  }
  std::set<std::string> reg;
  for (const auto& [id, im] : run.model.images) reg.insert(im.name);
  for (const auto& nme : names) (reg.count(nme) ? run.registered : run.leftOut).push_back(nme);
  if (run.registered.size() < 2) {
    std::string left;
    for (const auto& l : run.leftOut) left += (left.empty() ? "" : ", ") + l;
    throw Error(photosDir, "COLMAP mapper",
                "fewer than 2 photos registered (" + std::to_string(run.registered.size()) + "); left out: " + left);
  }
  run.modelFolder = (ws / "sparse").string();
  writeColmapText(run.model, run.modelFolder);
  progress.report(1, "COLMAP: " + std::to_string(run.registered.size()) + " of " + std::to_string(names.size()) +
                         " photos registered, " + std::to_string(run.model.points.size()) + " points");
  run.secondsFeatures = std::chrono::duration<double>(t1 - t0).count();
  run.secondsMatching = matchSeconds;
  run.secondsMapping = mapSeconds;

  return run;
}

void writeWorkspaceInfo(const std::string& workspace, const std::string& photosDir, const ColmapRun& run, bool metric) {
  QJsonArray reg, left;
  for (const auto& s : run.registered) reg.append(QString::fromStdString(s));
  for (const auto& s : run.leftOut) left.append(QString::fromStdString(s));
  const QJsonObject info{{"photos", QString::fromStdString(photosDir)},
                         {"registered", reg},
                         {"left_out", left},
                         {"points", qint64(run.model.points.size())},
                         {"metric", metric},
                         {"seconds", QJsonObject{{"features", run.secondsFeatures},
                                                 {"matching", run.secondsMatching},
                                                 {"mapping", run.secondsMapping}}}};
  const std::string path = (fs::path(workspace) / "workspace.json").string();
  QSaveFile f(QString::fromStdString(path));
  if (!f.open(QIODevice::WriteOnly) || f.write(QJsonDocument(info).toJson()) < 0 || !f.commit())
    throw Error(path, "", "cannot write: " + f.errorString().toStdString());
}

}  // namespace relume::recon
