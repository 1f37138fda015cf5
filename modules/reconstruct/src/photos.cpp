#include "relume/reconstruct/photos.h"

#include <OpenImageIO/imageio.h>
#include <QFile>
#include <QJsonDocument>
#include <QJsonObject>
#include <QSaveFile>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/photo.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "relume/geometry/error.h"

namespace fs = std::filesystem;

namespace relume::recon {

namespace {
std::string lower(std::string s) {
  for (auto& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}
bool isPhotoExtension(const std::string& ext) {
  const std::string e = lower(ext);
  return e == ".jpg" || e == ".jpeg" || e == ".png" || e == ".tif" || e == ".tiff" || e == ".exr";
}
double attr(const OIIO::ImageSpec& s, std::initializer_list<const char*> names) {
  for (const char* n : names) {
    const OIIO::ParamValue* p = s.find_attribute(n);
    if (!p) continue;
    // OpenImageIO keeps EXIF values as float, int or rational, and get_float() reads only floats.
    const OIIO::TypeDesc t = p->type();
    if (t.vecsemantics == OIIO::TypeDesc::RATIONAL && t.aggregate == OIIO::TypeDesc::VEC2) {
      const int* v = static_cast<const int*>(p->data());
      return v[1] ? double(v[0]) / v[1] : 0.0;
    }
    if (t.is_floating_point()) return p->get_float();
    return double(p->get_int());
  }
  return 0;
}
bool hasAttr(const OIIO::ImageSpec& s, std::initializer_list<const char*> names) {
  for (const char* n : names)
    if (s.find_attribute(n)) return true;
  return false;
}
std::string formatTime(double t) {
  char b[64];
  if (t < 1) std::snprintf(b, sizeof b, "1/%.4g s", 1 / t);
  else std::snprintf(b, sizeof b, "%.4g s", t);
  return b;
}
}  // namespace

double PhotoInfo::focalPixels() const {
  if (focal35mm <= 0 || width <= 0) return 0;
  return focal35mm / 36.0 * std::max(width, height);
}

PhotoInfo readPhotoInfo(const std::string& path) {
  if (!fs::exists(path)) throw Error(path, "", "the file does not exist");
  auto in = OIIO::ImageInput::open(path);
  if (!in) throw Error(path, "", "cannot read the image: " + OIIO::geterror());
  const OIIO::ImageSpec& s = in->spec();
  PhotoInfo p;
  p.path = path;
  p.width = s.width;
  p.height = s.height;
  p.channels = s.nchannels;
  p.floatData = s.format.is_floating_point();
  p.focalMm = attr(s, {"Exif:FocalLength", "FocalLength"});
  p.focal35mm = attr(s, {"Exif:FocalLengthIn35mmFilm", "FocalLengthIn35mmFilm"});
  p.exposureTime = attr(s, {"ExposureTime", "Exif:ExposureTime"});
  if (!std::isfinite(p.exposureTime) || p.exposureTime < 0) p.exposureTime = 0;  // unreadable rational
  p.fNumber = attr(s, {"FNumber", "Exif:FNumber"});
  p.iso = attr(s, {"Exif:PhotographicSensitivity", "Exif:ISOSpeedRatings", "ISOSpeedRatings"});
  p.hasExposureBias = hasAttr(s, {"Exif:ExposureBiasValue", "ExposureBiasValue"});
  p.exposureBias = attr(s, {"Exif:ExposureBiasValue", "ExposureBiasValue"});
  p.make = s.get_string_attribute("Make");
  p.model = s.get_string_attribute("Model");
  if (p.width <= 0 || p.height <= 0) throw Error(path, "", "the image has no pixels");
  return p;
}

std::vector<std::string> listPhotos(const std::string& folder) {
  if (!fs::is_directory(folder)) throw Error(folder, "", "is not a folder of photos");
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(folder))
    if (e.is_regular_file() && isPhotoExtension(e.path().extension().string())) files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  return files;
}

double exposureFromEv(double ev, double referenceTime) { return referenceTime * std::pow(2.0, ev); }

std::vector<std::vector<PhotoInfo>> groupBrackets(const std::vector<PhotoInfo>& photos) {
  std::vector<std::vector<PhotoInfo>> groups;
  auto exposureKey = [](const PhotoInfo& p) {
    return p.exposureTime > 0 ? p.exposureTime : (p.hasExposureBias ? exposureFromEv(p.exposureBias) : 0.0);
  };
  for (const auto& p : photos) {
    const double key = exposureKey(p);
    bool join = !groups.empty() && key > 0 && !p.floatData;
    if (join) {
      const PhotoInfo& q = groups.back().front();
      join = q.width == p.width && q.height == p.height && q.make == p.make && q.model == p.model && !q.floatData &&
             exposureKey(q) > 0;
      for (const auto& m : groups.back()) join = join && std::abs(exposureKey(m) - key) > 1e-3 * key;
    }
    if (join) groups.back().push_back(p);
    else groups.push_back({p});
  }
  return groups;
}

HdrResult mergeBracket(const std::vector<std::string>& files, std::vector<double> times, Progress& progress) {
  if (files.size() < 2) throw Error(files.empty() ? "" : files[0], "", "an HDR merge needs two or more exposures");
  if (!times.empty() && times.size() != files.size())
    throw Error("", "--times", "gives " + std::to_string(times.size()) + " exposure times for " + std::to_string(files.size()) + " images");
  if (times.empty()) {
    std::vector<PhotoInfo> infos;
    for (const auto& f : files) infos.push_back(readPhotoInfo(f));
    const bool allTimes = std::all_of(infos.begin(), infos.end(), [](const PhotoInfo& p) { return p.exposureTime > 0; });
    const bool allEv = std::all_of(infos.begin(), infos.end(), [](const PhotoInfo& p) { return p.hasExposureBias; });
    for (const auto& p : infos) {
      if (allTimes) times.push_back(p.exposureTime);
      else if (allEv) times.push_back(exposureFromEv(p.exposureBias));
    }
    if (times.empty()) {
      for (const auto& p : infos)
        if (p.exposureTime <= 0 && !p.hasExposureBias)
          throw Error(p.path, "EXIF", "gives neither an exposure time nor an exposure bias; pass --times");
      throw Error(files[0], "EXIF", "the bracket mixes exposure times and exposure biases; pass --times");
    }
  }
  for (size_t i = 0; i < times.size(); ++i)
    if (!(times[i] > 0)) throw Error(files[i], "exposure time", "must be positive");
  std::vector<Image8> images;
  for (size_t i = 0; i < files.size(); ++i) {
    progress.report(0.3 * i / files.size(), "reading " + files[i]);
    images.push_back(readImage8(files[i]));
  }
  Progress sub(progress, 0.3, 1.0);
  return mergeBracket(images, times, files, sub);
}

HdrResult mergeBracket(const std::vector<Image8>& images, const std::vector<double>& times,
                       const std::vector<std::string>& files, Progress& progress) {
  if (images.size() < 2) throw Error("", "bracket", "an HDR merge needs two or more exposures");
  if (times.size() != images.size() || files.size() != images.size())
    throw Error("", "bracket", "needs one exposure time and one name per image");
  for (size_t i = 0; i < times.size(); ++i)
    if (!(times[i] > 0)) throw Error(files[i], "exposure time", "must be positive");
  std::vector<cv::Mat> imgs;
  const int w = images[0].width, h = images[0].height;
  for (size_t i = 0; i < images.size(); ++i) {
    const Image8& im = images[i];
    if (im.width != w || im.height != h)
      throw Error(files[i], "", "is " + std::to_string(im.width) + "x" + std::to_string(im.height) + ", the bracket's first image " +
                                    std::to_string(w) + "x" + std::to_string(h));
    imgs.push_back(cv::Mat(h, w, CV_8UC3, const_cast<unsigned char*>(im.pixels.data())).clone());
  }
  for (size_t i = 0; i < times.size(); ++i)
    for (size_t j = i + 1; j < times.size(); ++j)
      if (std::abs(times[i] - times[j]) < 1e-6 * times[i])
        throw Error(files[j], "exposure time", "equals that of " + files[i] + " (" + formatTime(times[i]) + "): not a bracket");
  std::vector<float> tf(times.begin(), times.end());
  progress.report(0.5, "recovering the camera response (Debevec-Malik)");
  cv::Mat response;
  cv::createCalibrateDebevec()->process(imgs, response, tf);
  progress.report(0.8, "merging " + std::to_string(imgs.size()) + " exposures");
  // Merge with inverse-variance weights: a pixel value z pins ln E to within the quantisation
  // step times g'(z) (g = ln response), so w(z) = hat(z) / g'(z)^2; the hat (Debevec & Malik's
  // triangle) drops clipped values. Pixels clipped in every exposure take the nearest usable one.
  std::vector<double> g[3], wgt[3];
  for (int c = 0; c < 3; ++c) {
    g[c].resize(256);
    wgt[c].resize(256);
    for (int z = 0; z < 256; ++z) g[c][z] = std::log(std::max(double(response.at<cv::Vec3f>(z, 0)[c]), 1e-30));
    std::vector<double> slope(256);
    for (int z = 0; z < 256; ++z)
      slope[z] = std::abs(g[c][std::min(z + 1, 255)] - g[c][std::max(z - 1, 0)]) / (std::min(z + 1, 255) - std::max(z - 1, 0));
    // A locally flat stretch of a noisy curve must not make one exposure dominate.
    std::vector<double> sorted = slope;
    std::nth_element(sorted.begin(), sorted.begin() + 128, sorted.end());
    const double floorSlope = std::max(0.1 * sorted[128], 1e-6);
    for (int z = 0; z < 256; ++z) {
      const double hat = std::min(z, 255 - z);
      const double sl = std::max(slope[z], floorSlope);
      wgt[c][z] = hat / (sl * sl);
    }
  }
  std::vector<double> lnT(times.size());
  size_t shortest = 0, longest = 0;
  for (size_t i = 0; i < times.size(); ++i) {
    lnT[i] = std::log(times[i]);
    if (times[i] < times[shortest]) shortest = i;
    if (times[i] > times[longest]) longest = i;
  }
  HdrResult r;
  r.times = times;
  r.radiance = ImageRGB(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      glm::vec3 out;
      for (int c = 0; c < 3; ++c) {
        double num = 0, den = 0;
        for (size_t i = 0; i < imgs.size(); ++i) {
          const int z = imgs[i].at<cv::Vec3b>(y, x)[c];
          num += wgt[c][z] * (g[c][z] - lnT[i]);
          den += wgt[c][z];
        }
        double lnE;
        if (den > 0) lnE = num / den;
        else if (imgs[shortest].at<cv::Vec3b>(y, x)[c] >= 128) lnE = g[c][254] - lnT[shortest];  // clipped white
        else lnE = g[c][1] - lnT[longest];                                                         // black
        out[c] = float(std::exp(lnE));
      }
      r.radiance.set(x, y, out);
    }
  for (int c = 0; c < 3; ++c) {
    r.response[c].resize(256);
    for (int z = 0; z < 256; ++z) r.response[c][z] = response.at<cv::Vec3f>(z, 0)[c];
  }
  progress.report(1, "merged");
  return r;
}

ImageMetadata exifMetadata(const PhotoInfo& exif) {
  ImageMetadata m;
  if (exif.exposureTime > 0) m.floats.emplace_back("ExposureTime", float(exif.exposureTime));
  if (exif.fNumber > 0) m.floats.emplace_back("FNumber", float(exif.fNumber));
  if (exif.iso > 0) m.ints.emplace_back("Exif:PhotographicSensitivity", int(exif.iso));
  if (exif.focalMm > 0) m.floats.emplace_back("Exif:FocalLength", float(exif.focalMm));
  if (exif.focal35mm > 0) m.ints.emplace_back("Exif:FocalLengthIn35mmFilm", int(exif.focal35mm));
  if (exif.hasExposureBias) m.floats.emplace_back("Exif:ExposureBiasValue", float(exif.exposureBias));
  if (!exif.make.empty()) m.strings.emplace_back("Make", exif.make);
  if (!exif.model.empty()) m.strings.emplace_back("Model", exif.model);
  return m;
}

std::vector<std::vector<PhotoInfo>> mergeBracketFolder(const std::string& folder, const std::string& outFolder,
                                                       Progress& progress, std::vector<MergedBracket>* merged) {
  std::vector<PhotoInfo> infos;
  for (const auto& f : listPhotos(folder))
    if (!isRadianceFile(f)) infos.push_back(readPhotoInfo(f));
  if (infos.empty()) throw Error(folder, "", "holds no 8-bit photos");
  const auto groups = groupBrackets(infos);
  mergeBracketGroups(groups, outFolder, progress, merged);
  return groups;
}

void mergeBracketGroups(const std::vector<std::vector<PhotoInfo>>& groups, const std::string& outFolder, Progress& progress,
                        std::vector<MergedBracket>* merged) {
  std::error_code ec;
  fs::create_directories(outFolder, ec);
  if (ec) throw Error(outFolder, "", "cannot create the folder: " + ec.message());
  for (size_t g = 0; g < groups.size(); ++g) {
    Progress sub(progress, double(g) / groups.size(), double(g + 1) / groups.size());
    auto group = groups[g];
    if (group.empty()) continue;
    std::sort(group.begin(), group.end(), [](const PhotoInfo& a, const PhotoInfo& b) {
      const auto t = [](const PhotoInfo& p) { return p.exposureTime > 0 ? p.exposureTime : exposureFromEv(p.exposureBias); };
      return t(a) < t(b);
    });
    const PhotoInfo& middle = group[group.size() / 2];
    const fs::path dst = fs::path(outFolder) / fs::path(middle.path).filename();
    if (fs::absolute(middle.path) != fs::absolute(dst)) fs::copy_file(middle.path, dst, fs::copy_options::overwrite_existing, ec);
    if (ec) throw Error(dst.string(), "", "cannot copy the photo: " + ec.message());
    MergedBracket m;
    m.photo = dst.string();
    if (group.size() >= 2) {
      std::vector<std::string> files;
      for (const auto& p : group) files.push_back(p.path);
      HdrResult r = mergeBracket(files, {}, sub);
      m.hdr = (fs::path(outFolder) / (fs::path(middle.path).stem().string() + ".exr")).string();
      writeImage(m.hdr, r.radiance);
      for (int c = 0; c < 3; ++c) m.response[c] = std::move(r.response[c]);
      m.times = r.times;
    }
    if (merged) merged->push_back(std::move(m));
  }
}

namespace {
// The checkerboard's inner corners in each photo that shows the whole board (OpenCV's corners put
// the top-left pixel's centre at (0, 0); Relume's at (0.5, 0.5)), and the board's own points.
struct BoardViews {
  int width = 0, height = 0;
  std::vector<std::vector<cv::Point3f>> object;
  std::vector<std::vector<cv::Point2f>> image;
  std::vector<std::string> used, rejected;
};
BoardViews findBoards(const std::vector<std::string>& files, int cols, int rows, double square, Progress& progress) {
  if (cols < 2 || rows < 2) throw Error("", "--pattern", "needs at least 2x2 inner corners");
  if (!(square > 0)) throw Error("", "--square", "the square size must be positive (metres)");
  if (files.empty()) throw Error("", "checkerboard", "no photos given");
  const cv::Size pattern(cols, rows);
  std::vector<cv::Point3f> board;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) board.emplace_back(float(c * square), float(r * square), 0.f);
  BoardViews v;
  for (size_t i = 0; i < files.size(); ++i) {
    progress.report(0.8 * i / files.size(), "finding the checkerboard in " + files[i]);
    const Image8 im = readImage8(files[i]);
    if (v.width == 0) v.width = im.width, v.height = im.height;
    else if (im.width != v.width || im.height != v.height)
      throw Error(files[i], "", "has another size than " + files[0] + "; calibrate one camera setting at a time");
    cv::Mat rgb(im.height, im.width, CV_8UC3, const_cast<unsigned char*>(im.pixels.data())), gray;
    cv::cvtColor(rgb, gray, cv::COLOR_RGB2GRAY);
    std::vector<cv::Point2f> corners;
    const bool found = cv::findChessboardCorners(
        gray, pattern, corners, cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE | cv::CALIB_CB_FAST_CHECK);
    if (!found) {
      v.rejected.push_back(files[i]);
      continue;
    }
    cv::cornerSubPix(gray, corners, cv::Size(5, 5), cv::Size(-1, -1),
                     cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 50, 1e-3));
    for (auto& c : corners) c += cv::Point2f(0.5f, 0.5f);
    v.image.push_back(corners);
    v.object.push_back(board);
    v.used.push_back(files[i]);
  }
  if (v.image.size() < 3) {
    std::string names;
    for (const auto& f : v.rejected) names += (names.empty() ? "" : ", ") + fs::path(f).filename().string();
    throw Error(files.size() == 1 ? files[0] : fs::path(files[0]).parent_path().string(), "checkerboard",
                "a " + std::to_string(cols) + "x" + std::to_string(rows) + " inner-corner checkerboard was found in " +
                    std::to_string(v.image.size()) + " photo(s); calibration needs 3 or more (not found in: " + names + ")");
  }
  progress.report(0.85, "calibrating from " + std::to_string(v.image.size()) + " photos");
  return v;
}
}  // namespace

Intrinsics calibrateCheckerboard(const std::vector<std::string>& files, int cols, int rows, double square,
                                 Progress& progress) {
  BoardViews v = findBoards(files, cols, rows, square, progress);
  Intrinsics in;
  in.width = v.width;
  in.height = v.height;
  in.used = std::move(v.used);
  in.rejected = std::move(v.rejected);
  cv::Mat K, dist;
  std::vector<cv::Mat> rv, tv;
  in.rms = cv::calibrateCamera(v.object, v.image, cv::Size(in.width, in.height), K, dist, rv, tv, cv::CALIB_FIX_K3);
  in.fx = K.at<double>(0, 0);
  in.fy = K.at<double>(1, 1);
  in.cx = K.at<double>(0, 2);
  in.cy = K.at<double>(1, 2);
  in.k1 = dist.at<double>(0);
  in.k2 = dist.at<double>(1);
  in.p1 = dist.at<double>(2);
  in.p2 = dist.at<double>(3);
  progress.report(1, "calibrated");
  return in;
}

FisheyeCalibration calibrateFisheyeCheckerboard(const std::vector<std::string>& files, int cols, int rows, double square,
                                                Progress& progress) {
  BoardViews v = findBoards(files, cols, rows, square, progress);
  FisheyeCalibration out;
  FisheyeLens& in = out.lens;
  in.width = v.width;
  in.height = v.height;
  out.used = std::move(v.used);
  out.rejected = std::move(v.rejected);
  // OpenCV's fisheye fit takes double points, pixel centres at integers.
  std::vector<std::vector<cv::Point3d>> object;
  std::vector<std::vector<cv::Point2d>> image;
  for (size_t i = 0; i < v.image.size(); ++i) {
    object.emplace_back(v.object[i].begin(), v.object[i].end());
    image.emplace_back();
    for (const auto& c : v.image[i]) image.back().emplace_back(c.x - 0.5, c.y - 0.5);
  }
  cv::Matx33d K;
  cv::Vec4d D;
  std::vector<cv::Vec3d> rv, tv;
  try {
    in.rms = cv::fisheye::calibrate(object, image, cv::Size(in.width, in.height), K, D, rv, tv,
                                    cv::fisheye::CALIB_RECOMPUTE_EXTRINSIC | cv::fisheye::CALIB_FIX_SKEW,
                                    cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 200, 1e-12));
  } catch (const cv::Exception& e) {
    throw Error(fs::path(files[0]).parent_path().string(), "fisheye calibration",
                "OpenCV's fit failed (" + std::string(e.err) +
                    "): the photos do not determine the lens; take more, with the board nearer the image's edges too");
  }
  in.fx = K(0, 0);
  in.fy = K(1, 1);
  in.cx = K(0, 2) + 0.5;
  in.cy = K(1, 2) + 0.5;
  for (int i = 0; i < 4; ++i) in.k[i] = D[i];
  bool finite = std::isfinite(in.rms) && std::isfinite(in.cx) && std::isfinite(in.cy);
  for (double k : in.k) finite = finite && std::isfinite(k);
  if (!(in.fx > 0 && in.fy > 0 && std::isfinite(in.fx) && std::isfinite(in.fy)) || !finite)
    throw Error(fs::path(files[0]).parent_path().string(), "fisheye calibration",
                "the fit gave no lens (its focal lengths, principal point or distortion are no finite numbers): take more "
                "photos, with the board nearer the image's edges too");
  progress.report(1, "calibrated");
  return out;
}

void writeIntrinsics(const Intrinsics& in, const std::string& path) {
  QJsonObject o{{"width", in.width}, {"height", in.height}, {"model", "OPENCV"},
                {"fx", in.fx}, {"fy", in.fy}, {"cx", in.cx}, {"cy", in.cy},
                {"k1", in.k1}, {"k2", in.k2}, {"p1", in.p1}, {"p2", in.p2}, {"rms_pixels", in.rms}};
  QSaveFile f(QString::fromStdString(path));
  if (!f.open(QIODevice::WriteOnly) || f.write(QJsonDocument(o).toJson()) < 0 || !f.commit())
    throw Error(path, "", "cannot write the file");
}

Intrinsics parseIntrinsics(const std::string& bytes, const std::string& name) {
  QJsonParseError err;
  const QJsonDocument doc = QJsonDocument::fromJson(QByteArray(bytes.data(), qsizetype(bytes.size())), &err);
  if (doc.isNull() || !doc.isObject()) throw Error(name, "", "is not JSON: " + err.errorString().toStdString());
  const QJsonObject o = doc.object();
  auto number = [&](const char* key, bool required) {
    const QJsonValue v = o[key];
    if (v.isUndefined() && !required) return 0.0;
    if (!v.isDouble() || !std::isfinite(v.toDouble()))
      throw Error(name, key, "must be a number (as `relume calibrate` writes it)");
    return v.toDouble();
  };
  auto size = [&](const char* key) {
    const double x = number(key, true);
    if (!(x >= 1 && x <= (1 << 20)) || x != std::floor(x)) throw Error(name, key, "must be a whole number of pixels from 1 to 1048576");
    return int(x);
  };
  Intrinsics in;
  in.width = size("width");
  in.height = size("height");
  in.fx = number("fx", true);
  in.fy = number("fy", true);
  in.cx = number("cx", true);
  in.cy = number("cy", true);
  in.k1 = number("k1", false);
  in.k2 = number("k2", false);
  in.p1 = number("p1", false);
  in.p2 = number("p2", false);
  if (!(in.fx > 0) || !(in.fy > 0)) throw Error(name, "fx, fy", "must be positive (pixels)");
  return in;
}

Intrinsics readIntrinsics(const std::string& path) {
  QFile f(QString::fromStdString(path));
  if (!f.open(QIODevice::ReadOnly)) throw Error(path, "", "cannot open the file");
  const QByteArray b = f.readAll();
  return parseIntrinsics(std::string(b.constData(), size_t(b.size())), path);
}

}  // namespace relume::recon
