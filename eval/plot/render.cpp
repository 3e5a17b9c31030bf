#include "slamprep/eval/plot/draw.hpp"

namespace slamprep::eval::plot {
namespace {

const Color kWhite{1.0, 1.0, 1.0, 1.0};

}  // namespace

std::vector<PanelLayout> layoutFigure(const Figure& figure) {
  validateFigure(figure);
  TextRenderer text(figure.font_path);
  std::vector<PanelLayout> layouts;
  for (const PanelPlan& panel : planFigure(figure, text).panels) layouts.push_back(panel.layout);
  return layouts;
}

Image render(const Figure& figure) {
  validateFigure(figure);
  TextRenderer text(figure.font_path);
  const FigurePlan plan = planFigure(figure, text);
  const Metrics& m = plan.metrics;
  std::vector<TextItem> texts;
  if (!figure.title.empty()) {
    texts.push_back({figure.title, m.figure_title_font, figure.width_px / 2.0, plan.title_center_y,
                     HAlign::Center, VAlign::Middle});
  }

  GlCanvas canvas(figure.width_px, figure.height_px, figure.supersample);
  canvas.clear(kWhite);
  for (std::size_t i = 0; i < figure.axes.size(); ++i) {
    const Axes& axes = figure.axes[i];
    const PanelPlan& panel = plan.panels[i];
    const PanelLayout& L = panel.layout;
    const auto looks = resolveLooks(axes);
    if (axes.inset) {  // on white, over whatever panel it sits in
      Triangles blank;
      appendRect(blank, panel.cell);
      canvas.fill(blank, kWhite);
    }
    canvas.setClip(plotRect(L));
    if (axes.grid) drawGrid(canvas, panel, axes, m);
    drawSegments(canvas, axes, L);
    for (std::size_t k = 0; k < axes.series.size(); ++k) drawSeries(canvas, axes, k, L, looks[k]);
    canvas.clearClip();
    drawFrameAndTicks(canvas, panel, m, texts);
    drawLegend(canvas, axes, L, looks, m, text, texts);
    queueAxisLabels(axes, panel, m, text, texts);
  }
  Image image = canvas.read();
  for (const TextItem& t : texts) {
    text.draw(image, t.text, t.size, t.x, t.y, t.h, t.v, kInk, t.vertical);
  }
  return image;
}

void renderPng(const Figure& figure, const std::filesystem::path& path) {
  writePng(render(figure), path);
}

}  // namespace slamprep::eval::plot
