#include "photos_panel.h"

#include <QChart>
#include <QChartView>
#include <QDateTime>
#include <QDir>
#include <QDoubleSpinBox>
#include <QFileDialog>
#include <QFileInfo>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QImageReader>
#include <QLabel>
#include <QLineSeries>
#include <QLogValueAxis>
#include <QPointer>
#include <QPushButton>
#include <QSpinBox>
#include <QSplitter>
#include <QStandardPaths>
#include <QTabWidget>
#include <QThread>
#include <QThreadPool>
#include <QTreeWidget>
#include <QVBoxLayout>
#include <QValueAxis>
#include <algorithm>
#include <cmath>
#include <filesystem>

#include "job_runner.h"
#include "relume/geometry/error.h"
#include "relume/image/image.h"

namespace relume {

namespace fs = std::filesystem;

namespace {

constexpr int kPreview = 384;  // the thumbnail's longer side, pixels

// A thumbnail of a photo as it shows on screen (EXR: exposed so that its mean is mid-grey).
QImage thumbnailOf(const QString& path) {
  if (isRadianceFile(path.toStdString())) {
    const ImageRGB img = readImageLinear(path.toStdString());
    if (img.width <= 0 || img.height <= 0) return {};
    double mean = 0;
    for (int y = 0; y < img.height; y += 4)
      for (int x = 0; x < img.width; x += 4) {
        const glm::vec3 v = img.at(x, y);
        mean += (v.x + v.y + v.z) / 3.0;
      }
    mean /= std::max(1.0, double((img.height + 3) / 4) * ((img.width + 3) / 4));
    const float gain = float(0.18 / std::max(mean, 1e-12));
    const double s = double(kPreview) / std::max(img.width, img.height);
    const int w = std::max(1, int(img.width * s)), h = std::max(1, int(img.height * s));
    QImage out(w, h, QImage::Format_RGB888);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const glm::vec3 v = img.at(std::min(img.width - 1, int(x / s)), std::min(img.height - 1, int(y / s))) * gain;
        auto q = [](float c) { return int(std::clamp(linearToSrgb(std::clamp(c, 0.f, 1.f)) * 255.f + 0.5f, 0.f, 255.f)); };
        out.setPixel(x, y, qRgb(q(v.x), q(v.y), q(v.z)));
      }
    return out;
  }
  QImageReader reader(path);
  reader.setAutoTransform(true);
  const QSize size = reader.size();
  if (size.isValid() && std::max(size.width(), size.height()) > kPreview)
    reader.setScaledSize(size.scaled(kPreview, kPreview, Qt::KeepAspectRatio));
  QImage img = reader.read();
  if (img.isNull()) {  // a format Qt has no plugin for here (TIFF): OpenImageIO reads it
    const Image8 im = readImage8(path.toStdString());
    const QImage full(im.pixels.data(), im.width, im.height, im.width * 3, QImage::Format_RGB888);
    img = full.copy().scaled(QSize(im.width, im.height).scaled(kPreview, kPreview, Qt::KeepAspectRatio), Qt::IgnoreAspectRatio,
                             Qt::SmoothTransformation);  // copied first: `im` goes away
  }
  return img.convertToFormat(QImage::Format_RGB888);
}

// Where a photo goes in the capture: its own name, unless another photo of that name (other
// bytes) is there already; then NAME_2, NAME_3...
QString captureName(const QString& folder, const QString& src) {
  const QFileInfo in(src);
  auto same = [&](const QString& a) {
    QFile x(a), y(src);
    if (x.size() != y.size() || !x.open(QIODevice::ReadOnly) || !y.open(QIODevice::ReadOnly)) return false;
    while (!x.atEnd())
      if (x.read(1 << 20) != y.read(1 << 20)) return false;
    return true;
  };
  QString dst = folder + "/" + in.fileName();
  for (int k = 2; QFile::exists(dst) && QFileInfo(dst).absoluteFilePath() != in.absoluteFilePath() && !same(dst); ++k)
    dst = folder + "/" + in.completeBaseName() + "_" + QString::number(k) + (in.suffix().isEmpty() ? "" : "." + in.suffix());
  return dst;
}

QChartView* newChartView(QWidget* parent, const QString& title) {
  auto* view = new QChartView(parent);
  view->setRenderHint(QPainter::Antialiasing);
  auto* chart = new QChart;
  chart->setTitle(title);
  chart->legend()->hide();
  chart->setMargins(QMargins(2, 2, 2, 2));
  view->setChart(chart);
  view->setMinimumHeight(200);
  return view;
}

void replaceChart(QWidget* w, QChart* chart) {
  auto* view = static_cast<QChartView*>(w);
  QChart* old = view->chart();
  view->setChart(chart);
  delete old;
}

QString exposureText(double t) {
  if (t <= 0) return QString();
  if (t < 1) return QStringLiteral("1/%1 s").arg(std::round(1.0 / t));
  return QStringLiteral("%1 s").arg(t, 0, 'g', 3);
}

}  // namespace

PhotosPanel::PhotosPanel(JobRunner* jobs, QWidget* parent) : QWidget(parent), jobs_(jobs), pool_(new QThreadPool(this)) {
  pool_->setMaxThreadCount(std::max(1, QThread::idealThreadCount()));
  auto* layout = new QVBoxLayout(this);
  auto* row = new QHBoxLayout;
  importFolder_ = new QPushButton(tr("Import folder..."), this);
  importFiles_ = new QPushButton(tr("Import photos..."), this);
  merge_ = new QPushButton(tr("Merge brackets to HDR"), this);
  merge_->setToolTip(tr("Each bracket of exposures becomes one radiance image (Debevec and Malik), beside its middle "
                        "exposure: one photo per viewpoint, what reconstruction reads"));
  row->addWidget(importFolder_);
  row->addWidget(importFiles_);
  row->addWidget(merge_);
  layout->addLayout(row);
  summary_ = new QLabel(tr("No photos yet: import a folder of photos or brackets."), this);
  summary_->setWordWrap(true);
  layout->addWidget(summary_);
  auto* split = new QSplitter(Qt::Vertical, this);
  list_ = new QTreeWidget(split);
  list_->setColumnCount(8);
  list_->setHeaderLabels({tr("Photo"), tr("Size"), tr("Camera"), tr("Focal"), tr("Exposure"), tr("f/"), tr("ISO"), tr("Bracket")});
  list_->setRootIsDecorated(false);
  list_->setIconSize(QSize(64, 48));
  list_->setSelectionMode(QAbstractItemView::ExtendedSelection);
  list_->header()->setSectionResizeMode(QHeaderView::ResizeToContents);
  split->addWidget(list_);
  auto* tabs = new QTabWidget(split);
  histogram_ = newChartView(tabs, tr("Histogram of the selected photo"));
  response_ = newChartView(tabs, tr("Recovered response (no bracket merged yet)"));
  auto* calib = new QWidget(tabs);
  {
    auto* cl = new QVBoxLayout(calib);
    auto* pr = new QHBoxLayout;
    cols_ = new QSpinBox(calib);
    cols_->setRange(2, 40);
    cols_->setValue(9);
    rows_ = new QSpinBox(calib);
    rows_->setRange(2, 40);
    rows_->setValue(6);
    square_ = new QDoubleSpinBox(calib);
    square_->setRange(0.001, 1.0);
    square_->setDecimals(4);
    square_->setSingleStep(0.005);
    square_->setValue(0.025);
    square_->setSuffix(tr(" m"));
    pr->addWidget(new QLabel(tr("Inner corners"), calib));
    pr->addWidget(cols_);
    pr->addWidget(new QLabel(QStringLiteral("×"), calib));
    pr->addWidget(rows_);
    pr->addWidget(new QLabel(tr("square"), calib));
    pr->addWidget(square_);
    pr->addStretch(1);
    cl->addLayout(pr);
    calibrate_ = new QPushButton(tr("Calibrate from the selected photos"), calib);
    calibrate_->setToolTip(tr("Photos of a flat checkerboard from several angles: focal length, principal point and "
                              "lens distortion (OpenCV), written to the capture's intrinsics.json"));
    cl->addWidget(calibrate_);
    calibration_ = new QLabel(tr("Not calibrated."), calib);
    calibration_->setWordWrap(true);
    calibration_->setTextInteractionFlags(Qt::TextSelectableByMouse);
    cl->addWidget(calibration_);
    cl->addStretch(1);
  }
  tabs->addTab(histogram_, tr("Histogram"));
  tabs->addTab(response_, tr("Response curve"));
  tabs->addTab(calib, tr("Calibration"));
  split->addWidget(tabs);
  split->setStretchFactor(0, 1);
  split->setStretchFactor(1, 1);
  layout->addWidget(split, 1);

  connect(importFolder_, &QPushButton::clicked, this, [this] {
    const QString d = QFileDialog::getExistingDirectory(this, tr("Import a folder of photos"));
    if (!d.isEmpty()) importFolder(d);
  });
  connect(importFiles_, &QPushButton::clicked, this, [this] {
    const QStringList f = QFileDialog::getOpenFileNames(this, tr("Import photos"), QString(),
                                                        tr("Photos (*.jpg *.jpeg *.png *.tif *.tiff *.exr)"));
    if (!f.isEmpty()) importFiles(f);
  });
  connect(merge_, &QPushButton::clicked, this, [this] { mergeBrackets(); });
  connect(calibrate_, &QPushButton::clicked, this, [this] { calibrateSelected(); });
  connect(list_, &QTreeWidget::itemSelectionChanged, this, [this] { showSelected(); });
  merge_->setEnabled(false);
}

PhotosPanel::~PhotosPanel() {
  ++generation_;
  pool_->clear();        // thumbnails not started yet are dropped
  pool_->waitForDone();  // those running end before the panel does
}

void PhotosPanel::setCaptureFolder(const QString& folder) { capture_ = QFileInfo(folder).absoluteFilePath(); }

QString PhotosPanel::ensureCapture() {
  if (capture_.isEmpty())
    capture_ = QStandardPaths::writableLocation(QStandardPaths::AppLocalDataLocation) + "/captures/" +
               QDateTime::currentDateTime().toString("yyyyMMdd-HHmmss");
  QDir().mkpath(capture_ + "/originals");
  return capture_;
}

bool PhotosPanel::importFolder(const QString& folder) {
  QStringList files;
  try {
    for (const auto& f : recon::listPhotos(folder.toStdString())) files << QString::fromStdString(f);
  } catch (const std::exception& e) {
    emit message(tr("Cannot read %1: %2").arg(folder, QString::fromStdString(e.what())));
    return false;
  }
  // Files of other kinds are not photos; but an unreadable photo (a .jpg that is not one) is
  // listed with its reason, as listPhotos keeps every photo extension.
  if (files.isEmpty()) {
    emit message(tr("%1 holds no photos (PNG, JPEG, TIFF or EXR).").arg(folder));
    return false;
  }
  return importFiles(files);
}

bool PhotosPanel::importFiles(const QStringList& files) {
  if (files.isEmpty() || jobs_->busy()) return false;
  const QString originals = ensureCapture() + "/originals";
  std::vector<Entry> existing = entries_;
  return jobs_->start(tr("Importing photos: %1").arg(files.size()),
                      [this, files, originals, existing](Progress& progress) -> JobRunner::Continuation {
    auto all = std::make_shared<std::vector<Entry>>(existing);
    for (int i = 0; i < files.size(); ++i) {
      progress.report(double(i) / files.size(), "reading " + files[i].toStdString());
      Entry e;
      e.path = files[i];
      try {
        e.info = recon::readPhotoInfo(files[i].toStdString());
        const QString dst = captureName(originals, files[i]);
        if (QFileInfo(dst).absoluteFilePath() != QFileInfo(files[i]).absoluteFilePath()) {
          // Copied beside it, then renamed over it: a failed copy leaves what was there.
          const fs::path part = fs::path(dst.toStdString() + ".part");
          fs::copy_file(files[i].toStdString(), part, fs::copy_options::overwrite_existing);
          fs::rename(part, dst.toStdString());
        }
        e.path = dst;
        e.info.path = dst.toStdString();
      } catch (const std::exception& err) {  // relume::Error, and the file system's and the readers' own
        e.problem = QString::fromStdString(err.what());
      }
      bool dup = false;
      for (auto& old : *all)
        if (e.problem.isEmpty() && QFileInfo(old.path).absoluteFilePath() == QFileInfo(e.path).absoluteFilePath()) {
          old = e;  // the same photo imported again
          dup = true;
        }
      if (!dup) all->push_back(e);
    }
    // Brackets: consecutive photos (by name) of one size and camera whose exposures differ.
    std::vector<recon::PhotoInfo> ldr;
    std::vector<size_t> index;
    std::sort(all->begin(), all->end(), [](const Entry& a, const Entry& b) {
      return QFileInfo(a.path).fileName() < QFileInfo(b.path).fileName();
    });
    for (size_t i = 0; i < all->size(); ++i) {
      auto& e = (*all)[i];
      e.bracket = -1;
      e.member = e.members = 0;
      if (e.problem.isEmpty() && !e.info.floatData) {
        ldr.push_back(e.info);
        index.push_back(i);
      }
    }
    const auto groups = recon::groupBrackets(ldr);
    size_t k = 0;
    for (size_t g = 0; g < groups.size(); ++g)
      for (size_t m = 0; m < groups[g].size(); ++m, ++k) {
        auto& e = (*all)[index[k]];
        e.bracket = int(g);
        e.member = int(m);
        e.members = int(groups[g].size());
      }
    return [this, all]() {
      entries_ = std::move(*all);
      rebuildList();
      loadThumbnails();
      int bad = 0;
      for (const auto& e : entries_) bad += !e.problem.isEmpty();
      emit message(bad ? tr("Imported the photos; %1 could not be read (see the list).").arg(bad) : tr("Imported the photos."));
    };
  });
}

void PhotosPanel::rebuildList() {
  list_->clear();
  int ok = 0, bad = 0, brackets = 0, multi = 0;
  for (size_t i = 0; i < entries_.size(); ++i) {
    const Entry& e = entries_[i];
    auto* item = new QTreeWidgetItem(list_);
    item->setText(0, QFileInfo(e.path).fileName());
    item->setData(0, Qt::UserRole, int(i));
    if (!e.problem.isEmpty()) {
      ++bad;
      item->setText(1, tr("cannot be read"));
      item->setText(2, e.problem);
      item->setToolTip(0, e.problem);
      item->setForeground(0, QColor(200, 40, 40));
      item->setForeground(2, QColor(200, 40, 40));
      item->setFlags(item->flags() & ~Qt::ItemIsSelectable);
      continue;
    }
    ++ok;
    const auto& in = e.info;
    item->setText(1, QStringLiteral("%1 × %2%3").arg(in.width).arg(in.height).arg(in.floatData ? tr(", radiance") : QString()));
    item->setText(2, QString::fromStdString((in.make + " " + in.model)).trimmed());
    QString focal;
    if (in.focalMm > 0) focal = tr("%1 mm").arg(in.focalMm, 0, 'g', 3);
    if (in.focal35mm > 0) focal += (focal.isEmpty() ? QString() : QStringLiteral(" ")) + tr("(%1 mm eq.)").arg(in.focal35mm, 0, 'g', 3);
    item->setText(3, focal);
    item->setText(4, in.exposureTime > 0 ? exposureText(in.exposureTime)
                     : in.hasExposureBias ? tr("%1 EV").arg(in.exposureBias, 0, 'f', 1) : QString());
    item->setText(5, in.fNumber > 0 ? QString::number(in.fNumber, 'g', 3) : QString());
    item->setText(6, in.iso > 0 ? QString::number(in.iso) : QString());
    if (e.members > 1) item->setText(7, tr("%1: %2 of %3").arg(e.bracket + 1).arg(e.member + 1).arg(e.members));
    if (!e.thumbnail.isNull()) item->setIcon(0, QIcon(QPixmap::fromImage(e.thumbnail)));
  }
  std::vector<int> seen;
  for (const auto& e : entries_)
    if (e.bracket >= 0 && std::find(seen.begin(), seen.end(), e.bracket) == seen.end()) {
      seen.push_back(e.bracket);
      ++brackets;
      multi += e.members > 1;
    }
  summary_->setText(tr("%1 photos, %2 viewpoints, brackets of several exposures: %3%4. Capture folder: %5")
                        .arg(ok)
                        .arg(brackets)
                        .arg(multi)
                        .arg(bad ? tr("; cannot be read: %1").arg(bad) : QString())
                        .arg(QDir::toNativeSeparators(capture_)));
  merge_->setEnabled(multi > 0 || ok > 0);
}

void PhotosPanel::loadThumbnails() {
  const unsigned gen = ++generation_;
  pending_ = 0;
  QPointer<PhotosPanel> self(this);
  for (size_t i = 0; i < entries_.size(); ++i) {
    if (!entries_[i].problem.isEmpty() || !entries_[i].thumbnail.isNull()) continue;
    ++pending_;
    const QString path = entries_[i].path;
    pool_->start([self, gen, i, path] {
      QImage thumb;
      try {
        thumb = thumbnailOf(path);
      } catch (const std::exception&) {
      }
      std::array<std::vector<int>, 3> hist;
      for (auto& h : hist) h.assign(256, 0);
      for (int y = 0; y < thumb.height(); ++y) {
        const uchar* row = thumb.constScanLine(y);
        for (int x = 0; x < thumb.width(); ++x)
          for (int c = 0; c < 3; ++c) ++hist[size_t(c)][row[3 * x + c]];
      }
      QMetaObject::invokeMethod(
          self.data(),
          [self, gen, i, thumb, hist]() {
            if (!self || self->generation_ != gen || i >= self->entries_.size()) return;
            self->entries_[i].thumbnail = thumb;
            self->entries_[i].histogram = hist;
            for (int r = 0; r < self->list_->topLevelItemCount(); ++r) {
              QTreeWidgetItem* item = self->list_->topLevelItem(r);
              if (item->data(0, Qt::UserRole).toInt() == int(i) && !thumb.isNull())
                item->setIcon(0, QIcon(QPixmap::fromImage(thumb.scaled(64, 48, Qt::KeepAspectRatio, Qt::SmoothTransformation))));
            }
            if (--self->pending_ == 0) emit self->thumbnailsLoaded();
            self->showSelected();
          },
          Qt::QueuedConnection);
    });
  }
  if (pending_ == 0) emit thumbnailsLoaded();
}

void PhotosPanel::showSelected() {
  const auto items = list_->selectedItems();
  if (items.isEmpty()) return;
  const int i = items.front()->data(0, Qt::UserRole).toInt();
  if (i < 0 || size_t(i) >= entries_.size()) return;
  const Entry& e = entries_[size_t(i)];
  auto* chart = new QChart;
  chart->setTitle(tr("Histogram of %1%2")
                      .arg(QFileInfo(e.path).fileName(), e.info.floatData ? tr(" (as shown, exposed)") : QString()));
  chart->legend()->hide();
  chart->setMargins(QMargins(2, 2, 2, 2));
  auto* ax = new QValueAxis;
  ax->setRange(0, 255);
  ax->setLabelFormat("%d");
  auto* ay = new QValueAxis;
  chart->addAxis(ax, Qt::AlignBottom);
  chart->addAxis(ay, Qt::AlignLeft);
  int top = 1;
  const QColor colours[3] = {QColor(220, 50, 50), QColor(40, 170, 60), QColor(50, 90, 220)};
  for (int c = 0; c < 3; ++c) {
    if (e.histogram[size_t(c)].size() != 256) continue;
    auto* s = new QLineSeries;
    s->setColor(colours[c]);
    for (int v = 0; v < 256; ++v) {
      s->append(v, e.histogram[size_t(c)][size_t(v)]);
      if (v > 0 && v < 255) top = std::max(top, e.histogram[size_t(c)][size_t(v)]);
    }
    chart->addSeries(s);
    s->attachAxis(ax);
    s->attachAxis(ay);
  }
  ay->setRange(0, top * 1.05);  // the end bins (clipped pixels) may run off the top
  ay->setLabelFormat("%d");
  replaceChart(histogram_, chart);
  if (e.bracket >= 0) showResponse(e.bracket);
}

void PhotosPanel::showResponse(int bracket) {
  // The merged bracket holding the selected photo's viewpoint, else the first one merged.
  const recon::MergedBracket* m = nullptr;
  for (const auto& mb : merged_) {
    if (mb.response[0].size() != 256) continue;
    if (!m) m = &mb;
    for (const auto& e : entries_)
      if (e.bracket == bracket && e.members > 1 && QFileInfo(QString::fromStdString(mb.photo)).fileName() == QFileInfo(e.path).fileName())
        m = &mb;
  }
  if (!m) return;
  auto* chart = new QChart;
  chart->setTitle(tr("Recovered response, %1 exposures").arg(m->times.size()));
  chart->legend()->hide();
  chart->setMargins(QMargins(2, 2, 2, 2));
  auto* ax = new QValueAxis;
  ax->setRange(0, 255);
  ax->setLabelFormat("%d");
  ax->setTitleText(tr("pixel value"));
  auto* ay = new QLogValueAxis;
  ay->setBase(10);
  ay->setLabelFormat("%g");
  ay->setTitleText(tr("exposure"));
  chart->addAxis(ax, Qt::AlignBottom);
  chart->addAxis(ay, Qt::AlignLeft);
  double lo = 1e300, hi = 0;
  const QColor colours[3] = {QColor(220, 50, 50), QColor(40, 170, 60), QColor(50, 90, 220)};
  for (int c = 0; c < 3; ++c) {
    auto* s = new QLineSeries;
    s->setColor(colours[c]);
    for (int v = 0; v < 256; ++v) {
      const double y = m->response[c][size_t(v)];
      if (!(y > 0)) continue;
      s->append(v, y);
      lo = std::min(lo, y);
      hi = std::max(hi, y);
    }
    chart->addSeries(s);
    s->attachAxis(ax);
    s->attachAxis(ay);
  }
  if (lo < hi) ay->setRange(lo, hi);
  replaceChart(response_, chart);
}

bool PhotosPanel::mergeBrackets() {
  if (jobs_->busy()) return false;
  std::vector<std::vector<recon::PhotoInfo>> groups;
  for (const auto& e : entries_) {
    if (!e.problem.isEmpty() || e.bracket < 0) continue;
    if (size_t(e.bracket) >= groups.size()) groups.resize(size_t(e.bracket) + 1);
    groups[size_t(e.bracket)].push_back(e.info);
  }
  std::erase_if(groups, [](const auto& g) { return g.empty(); });
  if (groups.empty()) {
    emit message(tr("No 8-bit photos to merge."));
    return false;
  }
  const QString out = ensureCapture() + "/photos";
  return jobs_->start(tr("Merging brackets to HDR"), [this, groups, out](Progress& progress) -> JobRunner::Continuation {
    // Into a staging folder first: a failed or cancelled merge leaves the last photos/ as it was.
    const QString staging = out + ".staging";
    QDir(staging).removeRecursively();
    auto merged = std::make_shared<std::vector<recon::MergedBracket>>();
    recon::mergeBracketGroups(groups, staging.toStdString(), progress, merged.get());
    QDir(out + ".previous").removeRecursively();
    const bool had = QDir(out).exists();
    if (had && !QDir().rename(out, out + ".previous")) throw Error(out.toStdString(), "", "cannot replace the merged photos");
    if (!QDir().rename(staging, out)) {
      if (had) QDir().rename(out + ".previous", out);  // the last merge stays
      throw Error(out.toStdString(), "", "cannot move the merged photos in place");
    }
    QDir(out + ".previous").removeRecursively();
    for (auto& m : *merged) {
      m.photo = (out + "/" + QFileInfo(QString::fromStdString(m.photo)).fileName()).toStdString();
      if (!m.hdr.empty()) m.hdr = (out + "/" + QFileInfo(QString::fromStdString(m.hdr)).fileName()).toStdString();
    }
    return [this, merged]() {
      merged_ = std::move(*merged);
      int hdr = 0;
      for (const auto& m : merged_) hdr += !m.hdr.empty();
      emit message(tr("Brackets merged to HDR: %1; viewpoints in %2: %3").arg(hdr).arg(capture_ + "/photos").arg(merged_.size()));
      showResponse(-1);
    };
  });
}

bool PhotosPanel::calibrateSelected() {
  if (jobs_->busy()) return false;
  std::vector<std::string> files;
  for (auto* item : list_->selectedItems()) {
    const int i = item->data(0, Qt::UserRole).toInt();
    if (i >= 0 && size_t(i) < entries_.size() && entries_[size_t(i)].problem.isEmpty())
      files.push_back(entries_[size_t(i)].path.toStdString());
  }
  if (files.size() < 3) {
    calibration_->setText(tr("Select 3 or more photos of the checkerboard first."));
    return false;
  }
  const int cols = cols_->value(), rows = rows_->value();
  const double square = square_->value();
  const QString out = ensureCapture() + "/intrinsics.json";
  return jobs_->start(tr("Calibrating the camera"), [this, files, cols, rows, square, out](Progress& progress) -> JobRunner::Continuation {
    auto in = std::make_shared<recon::Intrinsics>(recon::calibrateCheckerboard(files, cols, rows, square, progress));
    recon::writeIntrinsics(*in, out.toStdString());
    return [this, in, out]() {
      QStringList rejected;
      for (const auto& r : in->rejected) rejected << QFileInfo(QString::fromStdString(r)).fileName();
      calibration_->setText(tr("Reprojection error %1 px over %2 photos.\nfx %3, fy %4, cx %5, cy %6 px; k1 %7, k2 %8, p1 %9, p2 %10.%11\nWritten to %12")
                                .arg(in->rms, 0, 'f', 3)
                                .arg(in->used.size())
                                .arg(in->fx, 0, 'f', 1)
                                .arg(in->fy, 0, 'f', 1)
                                .arg(in->cx, 0, 'f', 1)
                                .arg(in->cy, 0, 'f', 1)
                                .arg(in->k1, 0, 'f', 4)
                                .arg(in->k2, 0, 'f', 4)
                                .arg(in->p1, 0, 'f', 5)
                                .arg(in->p2, 0, 'f', 5)
                                .arg(rejected.isEmpty() ? QString() : tr("\nNo checkerboard found in: %1").arg(rejected.join(", ")))
                                .arg(out));
      intrinsics_ = std::make_unique<recon::Intrinsics>(*in);
    };
  });
}

}  // namespace relume
