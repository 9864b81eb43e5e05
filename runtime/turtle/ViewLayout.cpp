// Multi-view layout (see ViewLayout.h): lpfg's window grid, restated.
#include "runtime/turtle/ViewLayout.h"

#include <algorithm>
#include <cstdint>

namespace lcjit::runtime {

namespace {

// One axis of lpfg's multi-view layout (mainwindow.cpp): its views are widgets in a QGridLayout of
// 100 × 100 cells, a view spanning cells int(100·left) … for int(100·width) cells, with the
// border width as the layout's spacing. What Qt does with that, measured against Qt 5.15 and
// lpfg's pictures: cells no view covers take no room; spacing follows a cell only where the
// view changes (or no view goes on) in some row; the rest of the length is dealt out equally to
// the covered cells in 1/256 pixel steps, each cell rounding half up and passing the remainder
// on. Returns each view's {position, length} on this axis; nothing when the cells cannot fit.
struct CellSpan {
  int first, count;      // along this axis
  int otherFirst, otherCount;  // across it
};

std::vector<std::array<int, 2>> layoutAxis(const std::vector<CellSpan>& spans, int length, int border) {
  int cells = 0, others = 0;
  for (const CellSpan& s : spans) {
    cells = std::max(cells, s.first + s.count);
    others = std::max(others, s.otherFirst + s.otherCount);
  }
  // The view in each cell (the last one given wins, as in QGridLayout), across × along.
  std::vector<int> owner(size_t(cells) * size_t(others), -1);
  std::vector<char> covered(size_t(cells), 0);
  for (size_t i = 0; i < spans.size(); ++i)
    for (int a = spans[i].first; a < spans[i].first + spans[i].count; ++a) {
      covered[size_t(a)] = 1;
      for (int o = spans[i].otherFirst; o < spans[i].otherFirst + spans[i].otherCount; ++o)
        owner[size_t(o) * size_t(cells) + size_t(a)] = int(i);
    }
  std::vector<int> spacing(size_t(cells), 0);
  for (int o = 0; o < others; ++o) {
    int previous = -1, previousOwner = -1;
    for (int a = 0; a < cells; ++a) {
      if (!covered[size_t(a)]) continue;
      int here = owner[size_t(o) * size_t(cells) + size_t(a)];
      if (previous >= 0 && (here < 0 || here != previousOwner)) spacing[size_t(previous)] = border;
      previous = a;
      previousOwner = here;
    }
  }
  int n = 0, lastCovered = -1, spaced = 0;
  for (int a = 0; a < cells; ++a)
    if (covered[size_t(a)]) {
      if (lastCovered >= 0) spaced += spacing[size_t(lastCovered)];
      lastCovered = a;
      ++n;
    }
  const int64_t room = int64_t(length) - spaced;
  if (n == 0 || room < n) return {};
  auto roundHalfUp = [](int64_t fixed) { return fixed % 256 < 128 ? fixed / 256 : 1 + fixed / 256; };
  std::vector<int> size(size_t(cells), 0), pos(size_t(cells), 0);
  int64_t share = room * 256 / n, carried = 0;
  for (int a = 0; a < cells; ++a) {
    if (!covered[size_t(a)]) continue;
    carried += share;
    int64_t w = roundHalfUp(carried);
    size[size_t(a)] = int(w);
    carried -= w * 256;
  }
  for (int a = 0, p = 0; a < cells; ++a) {
    pos[size_t(a)] = p;
    p += size[size_t(a)] + (covered[size_t(a)] ? spacing[size_t(a)] : 0);
  }
  std::vector<std::array<int, 2>> out;
  for (const CellSpan& s : spans) {
    int last = s.first + s.count - 1;
    out.push_back({pos[size_t(s.first)], pos[size_t(last)] + size[size_t(last)] - pos[size_t(s.first)]});
  }
  return out;
}

}  // namespace

ViewPane::Rect ViewPane::Rect::inside(float left, float top, float width, float height) {
  Rect r;
  r.left = std::clamp(left, 0.f, 1.f);
  r.top = std::clamp(top, 0.f, 1.f);
  // Compared as the sum lpfg's fractions make in float, not against 1 - left, which rounds.
  r.width = std::max(width, 0.f);
  if (r.left + r.width > 1) r.width = 1 - r.left;
  r.height = std::max(height, 0.f);
  if (r.top + r.height > 1) r.height = 1 - r.top;
  return r;
}

std::vector<std::array<int, 4>> paneRects(const std::vector<ViewPane::Rect>& rects, int w, int h, int border) {
  // lpfg truncates 100 × the float fraction: 0.29 is 28 cells.
  auto cells = [](float f) { return std::clamp(int(100.0f * f), 0, 100); };
  std::vector<CellSpan> columns, rows;
  for (const ViewPane::Rect& r : rects) {
    int c = cells(r.left), cw = std::max(1, cells(r.width)), t = cells(r.top), th = std::max(1, cells(r.height));
    columns.push_back({c, cw, t, th});
    rows.push_back({t, th, c, cw});
  }
  auto xs = layoutAxis(columns, w, border), ys = layoutAxis(rows, h, border);
  std::vector<std::array<int, 4>> out;
  for (size_t i = 0; i < rects.size(); ++i) {
    if (xs.empty() || ys.empty()) {
      // Views that cannot all fit (Qt then lets the window overflow): their fractions.
      const ViewPane::Rect& r = rects[i];
      int x0 = int(r.left * w), y0 = int(r.top * h);
      out.push_back({x0, y0, std::max(1, int((r.left + r.width) * w) - x0), std::max(1, int((r.top + r.height) * h) - y0)});
    } else {
      out.push_back({xs[i][0], ys[i][0], std::max(1, xs[i][1]), std::max(1, ys[i][1])});
    }
  }
  return out;
}

CameraMatrices paneCamera(const ViewSettings& view, const ViewPane& pane, const std::array<int, 4>& rect,
                          const ViewAdjustment& adjust) {
  return frameView(view, pane.geometry.framingBounds(), pane.geometry.camera, rect[2], rect[3], pane.viewId, adjust);
}

}  // namespace lcjit::runtime
