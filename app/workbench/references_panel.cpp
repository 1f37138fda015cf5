#include "references_panel.h"

#include <QDoubleSpinBox>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QPushButton>
#include <QTreeWidget>
#include <QVBoxLayout>

#include "document.h"
#include "edit_tool.h"
#include "job_runner.h"

namespace relume {

namespace {
QString uvText(const glm::dvec2& uv) { return QString("%1, %2").arg(uv.x, 0, 'f', 2).arg(uv.y, 0, 'f', 2); }
}  // namespace

ReferencesPanel::ReferencesPanel(Document* doc, EditTool* tool, JobRunner* jobs, QWidget* parent)
    : QWidget(parent), doc_(doc), tool_(tool), jobs_(jobs) {
  auto* layout = new QVBoxLayout(this);
  summary_ = new QLabel(this);
  summary_->setWordWrap(true);
  layout->addWidget(summary_);
  show_ = new QPushButton(tr("Show occluded and frontier elements"), this);
  show_->setCheckable(true);
  show_->setToolTip(tr("In the view: occluded elements in blue, the unshadowed frontier they take their colour "
                       "from in yellow"));
  layout->addWidget(show_);
  connect(show_, &QPushButton::toggled, this, &ReferencesPanel::showElements);
  list_ = new QTreeWidget(this);
  list_->setColumnCount(3);
  list_->setHeaderLabels({tr("Polygon"), tr("Automatic"), tr("Yours")});
  list_->setToolTip(tr("Reference patches as plane coordinates u, v of their polygon, in metres"));
  list_->setRootIsDecorated(false);
  layout->addWidget(list_, 1);
  auto* row = new QHBoxLayout;
  pick_ = new QPushButton(tr("Pick in the view"), this);
  pick_->setToolTip(tr("Then click a texel of the selected polygon: its shadowed elements that match no "
                       "unshadowed neighbour take that texel's reflectance."));
  clear_ = new QPushButton(tr("Automatic"), this);
  clear_->setToolTip(tr("Back to the automatic choice for the selected polygon"));
  row->addWidget(pick_);
  row->addWidget(clear_);
  layout->addLayout(row);
  auto* paintRow = new QHBoxLayout;
  paint_ = new QPushButton(tr("Paint a region"), this);
  paint_->setToolTip(tr("Drag over a shadow of the selected polygon, then click the texel whose colour its "
                        "occluded elements should take (for a shadow across two materials, say)"));
  brush_ = new QDoubleSpinBox(this);
  brush_->setRange(0.02, 1.0);
  brush_->setSingleStep(0.02);
  brush_->setDecimals(2);
  brush_->setValue(0.1);
  brush_->setSuffix(tr(" m"));
  brush_->setToolTip(tr("Brush radius"));
  clearRegions_ = new QPushButton(tr("Clear regions"), this);
  clearRegions_->setToolTip(tr("Remove the regions painted on the selected polygon"));
  paintRow->addWidget(paint_);
  paintRow->addWidget(brush_);
  paintRow->addWidget(clearRegions_);
  layout->addLayout(paintRow);
  recompute_ = new QPushButton(tr("Recompute"), this);
  recompute_->setToolTip(tr("Remove the real shadows again with these reference patches: step 2 of the polygons whose choices changed, as a job"));
  layout->addWidget(recompute_);

  connect(pick_, &QPushButton::clicked, this, [this] {
    const std::string p = selectedPolygon();
    if (!p.empty()) tool_->pickReferenceOn(p);
  });
  connect(clear_, &QPushButton::clicked, this, [this] {
    const std::string p = selectedPolygon();
    if (!p.empty()) doc_->setReferenceOverride(p, std::nullopt);
  });
  connect(paint_, &QPushButton::clicked, this, [this] {
    const std::string p = selectedPolygon();
    if (!p.empty()) tool_->paintRegionOn(p, brush_->value());
  });
  connect(clearRegions_, &QPushButton::clicked, this, [this] {
    const std::string p = selectedPolygon();
    if (!p.empty()) doc_->clearReferenceRegions(p);
  });
  connect(recompute_, &QPushButton::clicked, this, [this] { recompute(); });
  connect(list_, &QTreeWidget::itemSelectionChanged, this, &ReferencesPanel::refresh);
  connect(doc_, &Document::opened, this, &ReferencesPanel::rebuild);
  connect(doc_, &Document::closed, this, &ReferencesPanel::rebuild);
  connect(doc_, &Document::referencesChanged, this, &ReferencesPanel::rebuild);
  rebuild();
}

std::string ReferencesPanel::selectedPolygon() const {
  const auto items = list_->selectedItems();
  return items.isEmpty() ? std::string() : items.front()->text(0).toStdString();
}

void ReferencesPanel::rebuild() {
  const std::string keep = selectedPolygon();
  list_->setUpdatesEnabled(false);  // one layout for the whole list, not one per row
  list_->header()->setSectionResizeMode(QHeaderView::Interactive);
  list_->clear();
  if (doc_->isOpen()) {
    const auto& est = doc_->data().estimates;
    const size_t referenced = est.referencedByFrontier + est.referencedByDefault + est.referencedByRegion;
    summary_->setText(tr("%1 occluded elements: %2 keep the light the solution traced as blocked, %3 took a "
                         "similar-coloured unshadowed neighbour as reference, %4 their polygon's reference patch, %5 a "
                         "painted region's. Choose a patch, or paint a region, where a shadow left a wrong colour.")
                          .arg(est.occludedLeaves)
                          .arg(est.occludedLeaves > referenced ? est.occludedLeaves - referenced : 0)
                          .arg(est.referencedByFrontier)
                          .arg(est.referencedByDefault)
                          .arg(est.referencedByRegion));
    for (const auto& p : doc_->scene().polygons) {
      if (p.kind != PolygonKind::Real) continue;
      auto* item = new QTreeWidgetItem(list_);
      item->setText(0, QString::fromStdString(p.name));
      const auto a = doc_->data().referencePatch.find(p.name);
      item->setText(1, a == doc_->data().referencePatch.end() ? tr("not seen") : uvText(a->second));
      const auto o = doc_->referenceOverrides().find(p.name);
      int regions = 0;
      for (const auto& r : doc_->referenceRegions()) regions += r.polygon == p.name;
      QStringList yours;
      if (o != doc_->referenceOverrides().end()) yours << uvText(o->second);
      if (regions == 1) yours << tr("1 region");
      if (regions > 1) yours << tr("%1 regions").arg(regions);
      item->setText(2, yours.isEmpty() ? QString("—") : yours.join(" + "));
      item->setToolTip(2, item->text(2));
      if (p.name == keep) item->setSelected(true);
    }
  } else {
    summary_->setText(tr("No room open."));
  }
  for (int c = 0; c < list_->columnCount(); ++c) list_->resizeColumnToContents(c);
  list_->setUpdatesEnabled(true);
  refresh();
}

void ReferencesPanel::refresh() {
  const bool open = doc_->isOpen();
  const std::string p = selectedPolygon();
  pick_->setEnabled(open && !p.empty());
  clear_->setEnabled(open && !p.empty() && doc_->referenceOverrides().count(p) > 0);
  paint_->setEnabled(open && !p.empty());
  bool hasRegions = false;
  for (const auto& r : doc_->referenceRegions()) hasRegions |= r.polygon == p;
  clearRegions_->setEnabled(open && !p.empty() && hasRegions);
  recompute_->setEnabled(open && doc_->referencesPending());
  recompute_->setText(open && doc_->referencesPending() ? tr("Recompute (changes pending)") : tr("Recompute"));
}

bool ReferencesPanel::recompute() {
  if (!doc_->isOpen() || !doc_->referencesPending()) return false;
  auto work = doc_->recomputeReferencesWork();
  return jobs_->start(tr("Removing the real shadows again"), [work](Progress& progress) { return work(progress); });
}

}  // namespace relume
