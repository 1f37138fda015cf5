#include "inspector_panel.h"

#include <QBarCategoryAxis>
#include <QBarSet>
#include <QChart>
#include <QChartView>
#include <QComboBox>
#include <QElapsedTimer>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QHorizontalBarSeries>
#include <QLabel>
#include <QLogValueAxis>
#include <QSplitter>
#include <QTabWidget>
#include <QTableWidget>
#include <QTimer>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>

#include "document.h"
#include "job_runner.h"
#include "relume/inspect/inspection.h"
#include "relume/inspect/inspector_view.h"
#include "relume/radiosity/hierarchy.h"

namespace relume {

using inspect::Quantity;

InspectorPanel::InspectorPanel(Document* doc, JobRunner* jobs, QWidget* parent)
    : QWidget(parent), doc_(doc), jobs_(jobs), all_(std::make_unique<inspect::ElementMesh>()),
      shown_(std::make_unique<inspect::ElementMesh>()) {
  auto* layout = new QVBoxLayout(this);
  auto* row = new QHBoxLayout;
  quantity_ = new QComboBox(this);
  quantity_->addItem(tr("Radiosity B"), int(Quantity::Radiosity));
  quantity_->addItem(tr("Irradiance E"), int(Quantity::Irradiance));
  quantity_->addItem(tr("Display factor D"), int(Quantity::DisplayFactor));
  quantity_->addItem(tr("Ratio B / D"), int(Quantity::Ratio));
  quantity_->addItem(tr("Reflectance"), int(Quantity::Reflectance));
  quantity_->addItem(tr("Shadow-free texture T_final"), int(Quantity::FinalTexture));
  quantity_->addItem(tr("Element level"), int(Quantity::Level));
  quantity_->addItem(tr("Visibility from a lamp"), int(Quantity::LampVisibility));
  quantity_->setToolTip(tr("What colours the elements (RGB quantities: the mean of R, G and B)"));
  lamp_ = new QComboBox(this);
  lamp_->setToolTip(tr("The lamp whose links are classed: visible, partly hidden, or hidden"));
  filter_ = new QComboBox(this);
  filter_->setToolTip(tr("Show the elements of one polygon only"));
  mesh_ = new QComboBox(this);
  mesh_->addItem(tr("Viewport's mesh"));
  mesh_->addItem(tr("Other mesh"));
  mesh_->setToolTip(tr("The refined and the interactive mesh: the other one is a second session, built as a job"));
  row->addWidget(new QLabel(tr("Colour by"), this));
  row->addWidget(quantity_, 1);
  row->addWidget(lamp_, 1);
  row->addWidget(new QLabel(tr("Polygon"), this));
  row->addWidget(filter_, 1);
  row->addWidget(mesh_);
  layout->addLayout(row);
  summary_ = new QLabel(this);
  summary_->setWordWrap(true);
  layout->addWidget(summary_);

  auto* split = new QSplitter(Qt::Horizontal, this);
  view_ = new inspect::InspectorView(split);
  split->addWidget(view_);
  auto* right = new QTabWidget(split);
  links_ = new QTableWidget(0, 8, right);
  links_->setHorizontalHeaderLabels({tr("Role"), tr("Source"), tr("Receiver"), tr("F"), tr("V"), tr("F × V"), tr("Type"),
                                     tr("Oracle error")});
  links_->setEditTriggers(QAbstractItemView::NoEditTriggers);
  links_->setSelectionBehavior(QAbstractItemView::SelectRows);
  links_->verticalHeader()->hide();
  links_->horizontalHeader()->setSectionResizeMode(QHeaderView::ResizeToContents);
  links_->setToolTip(tr("The links the picked element holds: those it gathers by, and those it sends by"));
  right->addTab(links_, tr("Links of the picked element"));
  auto* chartView = new QChartView(right);
  chartView->setRenderHint(QPainter::Antialiasing);
  chart_ = chartView;
  right->addTab(chartView, tr("Counts per polygon"));
  split->addWidget(right);
  split->setStretchFactor(0, 3);
  split->setStretchFactor(1, 2);
  layout->addWidget(split, 1);

  refreshTimer_ = new QTimer(this);
  refreshTimer_->setSingleShot(true);
  refreshTimer_->setInterval(250);
  connect(refreshTimer_, &QTimer::timeout, this, [this] {
    if (isVisible()) refresh();
  });
  connect(quantity_, &QComboBox::currentIndexChanged, this, [this] {
    lamp_->setEnabled(Quantity(quantity_->currentData().toInt()) == Quantity::LampVisibility);
    recolour();
  });
  connect(lamp_, &QComboBox::currentIndexChanged, this, [this] { recolour(); });
  connect(filter_, &QComboBox::currentIndexChanged, this, [this] {
    geometryStale_ = true;
    refresh();
  });
  connect(mesh_, &QComboBox::currentIndexChanged, this, [this] { otherMeshChosen(); });
  connect(view_, &inspect::InspectorView::elementPicked, this, [this](int e) {
    pickedNode_ = e >= 0 && size_t(e) < shownIndex_.size() ? shown_->node[size_t(e)] : -1;
    showLinks();
    emit pickedChanged();
  });
  auto reset = [this] {
    // The elements of the old session go at once: nothing may read the new engine through them.
    *all_ = {};
    *shown_ = {};
    shownIndex_.clear();
    view_->setElements(*shown_);
    links_->setRowCount(0);
    other_.reset();
    {
      const QSignalBlocker block(mesh_);
      mesh_->setCurrentIndex(0);
    }
    pickedNode_ = -1;
    fillLamps();
    markStale(true);
    emit pickedChanged();
  };
  connect(doc_, &Document::opened, this, reset);
  connect(doc_, &Document::closed, this, reset);
  connect(doc_, &Document::relightingReplaced, this, reset);
  connect(doc_, &Document::meshChanged, this, [this] { markStale(true); });
  connect(doc_, &Document::virtualsChanged, this, [this] { markStale(true); });
  connect(doc_, &Document::lightingChanged, this, [this] { markStale(false); });
  lamp_->setEnabled(false);
}

InspectorPanel::~InspectorPanel() = default;

const RelightSession* InspectorPanel::session() const {
  if (mesh_->currentIndex() == 1 && other_) return other_.get();
  return doc_->session();
}

const inspect::ElementMesh& InspectorPanel::elements() const { return *shown_; }

int InspectorPanel::pickedNode() const { return pickedNode_; }

void InspectorPanel::markStale(bool geometry) {
  if (mesh_->currentIndex() == 1 && other_ && !geometry) return;  // the other session does not follow edits
  geometryStale_ = geometryStale_ || geometry;
  valuesStale_ = true;
  if (isVisible()) refreshTimer_->start();
}

void InspectorPanel::showEvent(QShowEvent* e) {
  QWidget::showEvent(e);
  if (geometryStale_ || valuesStale_) refreshTimer_->start(0);
}

void InspectorPanel::fillLamps() {
  const QSignalBlocker block(lamp_);
  lamp_->clear();
  const QSignalBlocker blockFilter(filter_);
  filter_->clear();
  filter_->addItem(tr("All polygons"), -1);
  if (!doc_->isOpen()) return;
  const Scene& scene = doc_->scene();
  for (const auto& l : scene.lamps) lamp_->addItem(QString::fromStdString(l.name), l.polygon);
  for (size_t s = 0; s < scene.polygons.size(); ++s) filter_->addItem(QString::fromStdString(scene.polygons[s].name), int(s));
}

void InspectorPanel::refresh() {
  refreshTimer_->stop();
  if (!session()) {
    all_ = std::make_unique<inspect::ElementMesh>();
    shown_ = std::make_unique<inspect::ElementMesh>();
    shownIndex_.clear();
    view_->setElements(*shown_);
    links_->setRowCount(0);
    summary_->setText(tr("No room open."));
    return;
  }
  if (geometryStale_) rebuildMesh();
  if (valuesStale_ || geometryStale_) recolour();
  geometryStale_ = valuesStale_ = false;
}

void InspectorPanel::rebuildMesh() {
  const RelightSession* s = session();
  *all_ = inspect::elementMesh(s->engine());
  const int only = filter_->currentData().isValid() ? filter_->currentData().toInt() : -1;
  *shown_ = {};
  shownIndex_.clear();
  for (size_t i = 0; i < all_->node.size(); ++i) {
    if (only >= 0 && all_->surface[i] != only) continue;
    shown_->node.push_back(all_->node[i]);
    shown_->surface.push_back(all_->surface[i]);
    shown_->outline.push_back(all_->outline[i]);
    shownIndex_.push_back(int(i));
  }
  view_->setElements(*shown_);
  pickNode(pickedNode_);
  rebuildChart();
}

void InspectorPanel::recolour() {
  if (!session() || shown_->node.empty()) return;
  if (session() == doc_->session()) doc_->syncEngine();
  else other_->syncEngine();
  const auto q = Quantity(quantity_->currentData().toInt());
  const int lampSurface = lamp_->currentData().isValid() ? lamp_->currentData().toInt() : -1;
  const auto values = inspect::elementValues(*session(), *shown_, q, lampSurface);
  if (q == Quantity::LampVisibility) {
    view_->setClasses(values, tr("Light from %1").arg(lamp_->currentText()), {tr("VISIBLE"), tr("INVISIBLE"), tr("PARTIAL")},
                      {glm::dvec3(1.0, 0.86, 0.35), glm::dvec3(0.12, 0.16, 0.45), glm::dvec3(0.93, 0.45, 0.15)});
  } else {
    view_->setValues(values, quantity_->currentText());
  }
  const auto totals = session()->engine().totals();
  summary_->setText(tr("%1: %2 elements shown of %3 leaves; %4 links in the engine")
                        .arg(session() == doc_->session() ? (doc_->mesh() == SessionMesh::Interactive ? tr("interactive mesh")
                                                                                                       : tr("refined mesh"))
                                                          : (doc_->mesh() == SessionMesh::Interactive ? tr("refined mesh")
                                                                                                       : tr("interactive mesh")))
                        .arg(shown_->node.size())
                        .arg(totals.leaves)
                        .arg(totals.links));
}

void InspectorPanel::pickNode(int node) {
  int element = -1;
  for (size_t i = 0; i < shown_->node.size() && node >= 0; ++i)
    if (shown_->node[i] == node) element = int(i);
  pickedNode_ = element >= 0 ? node : -1;
  view_->setSelected(element);
  showLinks();
  emit pickedChanged();
}

void InspectorPanel::pickAt(int surface, const glm::dvec3& point) {
  if (!session() || surface < 0 || size_t(surface) >= session()->engine().surfaces().size()) return;
  // The other mesh's session numbers virtual lamps and objects its own way: only the room's
  // polygons are the same surfaces in both.
  if (session() != doc_->session() && size_t(surface) >= session()->realPolygonCount()) return;
  const auto& h = session()->engine();
  if (geometryStale_) refresh();
  pickNode(h.findLeaf(surface, h.toUV(surface, point)));
}

std::vector<glm::dvec3> InspectorPanel::pickedOutline() const {
  for (size_t i = 0; i < shown_->node.size() && pickedNode_ >= 0; ++i)
    if (shown_->node[i] == pickedNode_) return shown_->outline[i];
  return {};
}

namespace {
QString nodeName(const radiosity::HierarchicalRadiosity& h, int node) {
  const auto& N = h.nodes()[size_t(node)];
  if (N.isCluster()) return InspectorPanel::tr("cluster %1").arg(node);
  return InspectorPanel::tr("%1 #%2 (level %3)").arg(QString::fromStdString(h.surfaces()[size_t(N.surface)].name)).arg(node).arg(N.level);
}
}  // namespace

void InspectorPanel::showLinks() {
  links_->setRowCount(0);
  std::vector<std::pair<glm::dvec3, glm::dvec3>> segments;
  std::vector<double> weights;
  if (!session() || pickedNode_ < 0) {
    view_->setLinks(segments, weights);
    return;
  }
  const auto& h = session()->engine();
  const auto rows = inspect::linksOf(h, pickedNode_);
  links_->setUpdatesEnabled(false);
  links_->setRowCount(int(rows.size()));
  static const char* types[] = {QT_TR_NOOP("visible"), QT_TR_NOOP("invisible"), QT_TR_NOOP("partial")};
  for (size_t r = 0; r < rows.size(); ++r) {
    const auto& l = rows[r];
    auto set = [&](int c, const QString& text) { links_->setItem(int(r), c, new QTableWidgetItem(text)); };
    set(0, l.receives ? tr("gathers") : tr("sends"));
    set(1, nodeName(h, l.source));
    set(2, nodeName(h, l.receiver));
    set(3, QString::number(l.formFactor, 'g', 5));
    set(4, QString::number(l.visibility, 'f', 3));
    set(5, QString::number(double(l.formFactor) * l.visibility, 'g', 5));
    set(6, tr(types[std::clamp(l.type, 0, 2)]));
    set(7, QString::number(l.error, 'g', 3));
    const int other = l.receives ? l.source : l.receiver;
    segments.emplace_back(inspect::nodeCentre(h, other), inspect::nodeCentre(h, pickedNode_));
    weights.push_back(double(l.formFactor) * l.visibility);
  }
  links_->setUpdatesEnabled(true);
  view_->setLinks(segments, weights);
}

void InspectorPanel::rebuildChart() {
  auto* chartView = static_cast<QChartView*>(chart_);
  auto* chart = new QChart;
  chart->setTitle(tr("Elements, leaves and links per polygon (the 6 with the most links)"));
  chart->legend()->setAlignment(Qt::AlignRight);
  chart->setMargins(QMargins(4, 4, 4, 4));
  QFont titleFont = chart->titleFont();
  titleFont.setPointSizeF(titleFont.pointSizeF() * 0.9);
  chart->setTitleFont(titleFont);
  if (session()) {
    auto counts = inspect::countsPerPolygon(session()->engine());
    const int only = filter_->currentData().isValid() ? filter_->currentData().toInt() : -1;
    if (only >= 0) std::erase_if(counts, [&](const inspect::PolygonCounts& c) { return c.surface != only; });
    // The polygons with the most links, at most 6 (a chart, not a table).
    std::sort(counts.begin(), counts.end(), [](const auto& a, const auto& b) { return a.links > b.links; });
    if (counts.size() > 6) counts.resize(6);
    std::reverse(counts.begin(), counts.end());
    auto* elements = new QBarSet(tr("elements"));
    auto* leaves = new QBarSet(tr("leaves"));
    auto* links = new QBarSet(tr("links received"));
    QStringList names;
    double hi = 10;
    for (const auto& c : counts) {
      names << QString::fromStdString(c.name);
      *elements << double(std::max<size_t>(c.elements, 1));
      *leaves << double(std::max<size_t>(c.leaves, 1));
      *links << double(std::max<size_t>(c.links, 1));
      hi = std::max(hi, double(c.links));
    }
    auto* series = new QHorizontalBarSeries;
    series->append(elements);
    series->append(leaves);
    series->append(links);
    chart->addSeries(series);
    auto* axisY = new QBarCategoryAxis;
    axisY->append(names);
    axisY->setTruncateLabels(false);
    chart->addAxis(axisY, Qt::AlignLeft);
    series->attachAxis(axisY);
    auto* axisX = new QLogValueAxis;
    axisX->setBase(10);
    axisX->setRange(1, std::pow(10.0, std::ceil(std::log10(hi))));
    axisX->setLabelFormat("%g");
    axisX->setTruncateLabels(false);
    chart->addAxis(axisX, Qt::AlignBottom);
    series->attachAxis(axisX);
  }
  QChart* old = chartView->chart();
  chartView->setChart(chart);
  delete old;
}

void InspectorPanel::otherMeshChosen() {
  if (mesh_->currentIndex() == 0 || other_) {
    pickedNode_ = -1;
    markStale(true);
    refresh();
    emit pickedChanged();
    return;
  }
  if (!doc_->isOpen() || jobs_->busy()) {
    const QSignalBlocker block(mesh_);
    mesh_->setCurrentIndex(0);
    return;
  }
  auto work = doc_->otherMeshSessionWork();
  jobs_->start(tr("Building the other mesh for the inspector"), [this, work](Progress& progress) -> JobRunner::Continuation {
    auto session = std::make_shared<std::unique_ptr<RelightSession>>(work(progress));
    return [this, session] {
      other_ = std::move(*session);
      pickedNode_ = -1;
      geometryStale_ = valuesStale_ = true;
      refresh();
      emit pickedChanged();
    };
  });
  connect(jobs_, &JobRunner::finished, this, [this](bool ok) {
    if (!ok && !other_) {
      const QSignalBlocker block(mesh_);
      mesh_->setCurrentIndex(0);
    }
  }, Qt::SingleShotConnection);
}

}  // namespace relume
