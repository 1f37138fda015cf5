#pragma once
// The Photos panel: what a capture starts from. Photos (PNG, JPEG, TIFF, EXR) imported from a
// folder or as files are copied into the capture folder (originals/); each shows its size, camera,
// focal length, exposure time, f-number and ISO from EXIF, a thumbnail and a histogram (read off
// the UI thread), and the bracket it belongs to. Brackets are merged to HDR as a job (one photo
// per viewpoint in photos/, what reconstruction reads), with the recovered response curve shown;
// a chosen set of checkerboard photos calibrates the camera (its reprojection error shown). A
// photo that cannot be read is listed with the reason, and the others import.
#include <QImage>
#include <QString>
#include <QStringList>
#include <QWidget>
#include <array>
#include <memory>
#include <vector>

#include "relume/reconstruct/photos.h"

class QDoubleSpinBox;
class QLabel;
class QPushButton;
class QSpinBox;
class QTreeWidget;
class QThreadPool;
class QTreeWidgetItem;

namespace relume {

class JobRunner;

class PhotosPanel : public QWidget {
  Q_OBJECT
 public:
  struct Entry {
    QString path;         // in the capture's originals/ (or where it was, when it could not be read)
    recon::PhotoInfo info;
    QString problem;      // why it cannot be used (empty: fine)
    int bracket = -1;     // group index (brackets of one viewpoint), -1 none
    int member = 0, members = 0;
    QImage thumbnail;     // null until loaded
    std::array<std::vector<int>, 3> histogram;  // 256 bins per channel, of what the thumbnail shows
  };

  PhotosPanel(JobRunner* jobs, QWidget* parent = nullptr);
  ~PhotosPanel() override;

  // The capture folder (created when needed): originals/ holds the imported photos, photos/ one
  // photo per viewpoint after merging, intrinsics.json a calibration.
  QString captureFolder() const { return capture_; }
  void setCaptureFolder(const QString& folder);
  // Import as a job (false when a job runs or nothing was given).
  bool importFiles(const QStringList& files);
  bool importFolder(const QString& folder);
  bool mergeBrackets();
  // Calibrates from the selected photos (a checkerboard of cols x rows inner corners, squares of
  // `square` metres) as a job.
  bool calibrateSelected();

  const std::vector<Entry>& entries() const { return entries_; }
  const std::vector<recon::MergedBracket>& merged() const { return merged_; }
  const recon::Intrinsics* intrinsics() const { return intrinsics_.get(); }
  int thumbnailsPending() const { return pending_; }
  QTreeWidget* list() const { return list_; }
  QWidget* histogramChart() const { return histogram_; }
  QWidget* responseChart() const { return response_; }
  QLabel* calibrationLabel() const { return calibration_; }
  QSpinBox* patternColumns() const { return cols_; }
  QSpinBox* patternRows() const { return rows_; }
  QDoubleSpinBox* squareSize() const { return square_; }

 signals:
  void message(const QString& text);
  void thumbnailsLoaded();

 private:
  void rebuildList();
  void loadThumbnails();
  void showSelected();
  void showResponse(int bracket);
  QString ensureCapture();

  JobRunner* jobs_;
  QString capture_;
  std::vector<Entry> entries_;
  std::vector<recon::MergedBracket> merged_;
  std::unique_ptr<recon::Intrinsics> intrinsics_;
  QTreeWidget* list_;
  QWidget *histogram_, *response_;
  QLabel *summary_, *calibration_;
  QPushButton *importFolder_, *importFiles_, *merge_, *calibrate_;
  QSpinBox *cols_, *rows_;
  QDoubleSpinBox* square_;
  QThreadPool* pool_;  // thumbnails; waited for when the panel goes
  int pending_ = 0;
  unsigned generation_ = 0;  // thumbnails of an older list are dropped
};

}  // namespace relume
