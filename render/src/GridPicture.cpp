#include "rgvc/render/GridPicture.hpp"

#include "rgvc/grid/ViewWedge.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <type_traits>
#include <variant>

namespace rgvc {

RGB8 voxelCellColor(const VoxelState& s) {
    if (!s.inGrid) return picture::kEmpty;
    if (s.occluder) return picture::kOccluder;
    if (s.opaque) return picture::kOpaque;
    if (s.hasTbv) return picture::kTbv;
    if (s.occluded) return picture::kOccluded;
    if (s.visited) return picture::kVisited;
    return picture::kEmpty;
}

Vec2 GridPictureLayout::localToPicture(const Vec2& local) const {
    return {gridX0 + local.x * scaleX, gridY0 + gridHeight - local.y * scaleY};
}

Vec2 GridPictureLayout::toPicture(const Vec2& world) const { return localToPicture((world - origin) / voxelSize); }

IVec2 GridPictureLayout::voxelCentrePixel(const IVec2& v) const {
    Vec2 p = localToPicture(Vec2(v) + 0.5);
    auto toInt = [](double d) {
        d = std::floor(d);
        return std::int32_t(std::clamp(d, -1073741824.0, 1073741824.0));
    };
    return {toInt(p.x), toInt(p.y)};
}

IVec2 GridPictureLayout::voxelAtPixel(int x, int y) const {
    Vec2 local((x + 0.5 - gridX0) / scaleX, (gridY0 + gridHeight - (y + 0.5)) / scaleY);
    return GridGeometry2::voxelOfLocal(local);
}

namespace {

// ---------------------------------------------------------------------------------------------------
// Legend

enum class Swatch { Fill, IdDot, PvsObject, HiddenObject, SolidLine, DashedLine, CameraDot };

struct LegendItem {
    Swatch kind;
    RGB8 color;
    const char* label;
};

constexpr LegendItem kLegendItems[] = {
    {Swatch::Fill, picture::kEmpty, "empty"},
    {Swatch::Fill, picture::kVisited, "visited"},
    {Swatch::Fill, picture::kOpaque, "opaque (O)"},
    {Swatch::Fill, picture::kOccluded, "occluded (H)"},
    {Swatch::Fill, picture::kOccluder, "occluder"},
    {Swatch::Fill, picture::kTbv, "TBV (T)"},
    {Swatch::IdDot, picture::kIdDot, "ids (I)"},
    {Swatch::PvsObject, picture::kPvs, "PVS object"},
    {Swatch::HiddenObject, picture::kHidden, "hidden object"},
    {Swatch::SolidLine, picture::kView, "view edges"},
    {Swatch::DashedLine, picture::kView, "line of sight"},
    {Swatch::CameraDot, picture::kView, "camera"},
};

struct LegendMetrics {
    int swatch = 0;  // swatch side
    int rowH = 0;    // height of one row of items
    int textLineH = 0;
    int pad = 0;
};

LegendMetrics legendMetrics(int textScale) {
    LegendMetrics m;
    m.swatch = textHeight(textScale) + 2 * textScale + 2;
    m.rowH = m.swatch + 3 * textScale + 2;
    m.textLineH = textHeight(textScale) + 3 * textScale + 1;
    m.pad = 4 * textScale + 2;
    return m;
}

int itemWidth(const LegendItem& item, const LegendMetrics& m, int textScale, bool withText) {
    int w = m.swatch + m.pad;
    if (withText) w += int(textWidth(item.label, textScale)) + 2 * m.pad;
    return w;
}

/// Number of item rows for a legend of the given width.
int legendItemRows(int width, int textScale, bool withText, const LegendMetrics& m) {
    int rows = 1, x = m.pad;
    for (const LegendItem& item : kLegendItems) {
        int w = itemWidth(item, m, textScale, withText);
        if (x > m.pad && x + w > width) {
            ++rows;
            x = m.pad;
        }
        x += w;
    }
    return rows;
}

int legendTextLines(const GridPictureOptions& opt) {
    if (!opt.legendText) return 0;
    return 2 + (opt.caption.empty() ? 0 : 1);
}

void drawSwatch(ImageRGB& img, const LegendItem& item, int x, int y, int s) {
    const RGB8 frame{150, 150, 150};
    const Vec2 c(x + s / 2.0, y + s / 2.0);
    switch (item.kind) {
    case Swatch::Fill:
        fillRect(img, x, y, x + s, y + s, item.color);
        drawRectOutline(img, x, y, x + s, y + s, frame);
        break;
    case Swatch::IdDot:
        fillRect(img, x, y, x + s, y + s, picture::kVisited);
        drawRectOutline(img, x, y, x + s, y + s, frame);
        fillCircle(img, c, s * 0.2, item.color);
        break;
    case Swatch::PvsObject:
        fillCircle(img, c, s * 0.45, item.color, picture::kPvsFillAlpha);
        drawCircle(img, c, s * 0.45 - 1, item.color, 2);
        break;
    case Swatch::HiddenObject:
        drawCircle(img, c, s * 0.45 - 1, item.color, 2);
        break;
    case Swatch::SolidLine:
        drawLine(img, Vec2(x, y + s / 2.0), Vec2(x + s, y + s / 2.0), item.color, 2);
        break;
    case Swatch::DashedLine:
        drawDashedLine(img, Vec2(x, y + s / 2.0), Vec2(x + s, y + s / 2.0), item.color, s / 3.0, s / 6.0, 2);
        break;
    case Swatch::CameraDot:
        fillCircle(img, c, s * 0.25, item.color);
        break;
    }
}

/// One line of text, shrunk to scale 1 when it would not fit.
void drawTextLine(ImageRGB& img, int x, int y, const std::string& text, int textScale) {
    int scale = textScale;
    if (scale > 1 && x + textWidth(text, scale) > img.width()) scale = 1;
    drawText(img, x, y, text, picture::kText, scale);
}

std::string statsLine1(const CullResult& r) {
    const CullStats& s = r.stats;
    char buf[256];
    std::snprintf(buf, sizeof buf, "PVS: %zu of %u objects   cull: %.3f ms   fallback: %s%s", r.pvs.size(),
                  unsigned(s.objectCount), s.cullMs, toString(s.fallback),
                  s.earlyTermination ? "   early termination" : "");
    return buf;
}

std::string statsLine2(const CullResult& r) {
    const CullStats& s = r.stats;
    char buf[256];
    std::snprintf(buf, sizeof buf, "layers: %u   visited: %llu   occluded: %llu   occluder voxels: %llu   shadows: %llu",
                  unsigned(s.layers), static_cast<unsigned long long>(s.voxelsVisited),
                  static_cast<unsigned long long>(s.voxelsOccluded), static_cast<unsigned long long>(s.occluderVoxels),
                  static_cast<unsigned long long>(s.shadows));
    return buf;
}

void drawLegend(ImageRGB& img, const GridPictureLayout& L, const GridPictureOptions& opt, const CullResult& r) {
    const int ts = L.textScale;
    const LegendMetrics m = legendMetrics(ts);
    fillRect(img, 0, L.legendY0, img.width(), L.legendY0 + 1, RGB8{190, 190, 190});
    int x = m.pad, y = L.legendY0 + m.pad;
    for (const LegendItem& item : kLegendItems) {
        int w = itemWidth(item, m, ts, opt.legendText);
        if (x > m.pad && x + w > img.width()) {
            x = m.pad;
            y += m.rowH;
        }
        drawSwatch(img, item, x, y, m.swatch);
        if (opt.legendText)
            drawText(img, x + m.swatch + m.pad, y + (m.swatch - textHeight(ts)) / 2, item.label, picture::kText, ts);
        x += w;
    }
    y += m.rowH;
    if (!opt.legendText) return;
    if (!opt.caption.empty()) {
        drawTextLine(img, m.pad, y, opt.caption, ts);
        y += m.textLineH;
    }
    drawTextLine(img, m.pad, y, statsLine1(r), ts);
    y += m.textLineH;
    drawTextLine(img, m.pad, y, statsLine2(r), ts);
}

// ---------------------------------------------------------------------------------------------------
// Grid cells

void drawCells(ImageRGB& img, const Culler2D& culler, const GridPictureLayout& L) {
    const IVec2 res = culler.grid().resolution();
    const int x0 = L.gridX0, x1 = L.gridX0 + L.gridWidth;
    std::vector<std::int32_t> columnVoxel(std::size_t(L.gridWidth));
    for (int px = x0; px < x1; ++px)
        columnVoxel[std::size_t(px - x0)] = std::clamp(L.voxelAtPixel(px, 0).x, 0, res.x - 1);
    std::int32_t prevRow = -1;
    for (int py = L.gridY0; py < L.gridY0 + L.gridHeight; ++py) {
        const std::int32_t vy = std::clamp(L.voxelAtPixel(x0, py).y, 0, res.y - 1);
        if (vy == prevRow) { // same voxel row as the pixel row above: copy it
            std::memcpy(img.data() + std::size_t(py) * img.stride() + std::size_t(x0) * 3,
                        img.data() + std::size_t(py - 1) * img.stride() + std::size_t(x0) * 3,
                        std::size_t(L.gridWidth) * 3);
            continue;
        }
        prevRow = vy;
        std::int32_t prevVx = -1;
        RGB8 color{};
        for (int px = x0; px < x1; ++px) {
            const std::int32_t vx = columnVoxel[std::size_t(px - x0)];
            if (vx != prevVx) {
                color = voxelCellColor(culler.voxelState({vx, vy}));
                prevVx = vx;
            }
            img.set(px, py, color);
        }
    }
}

void drawGridLines(ImageRGB& img, const GridPictureLayout& L, const IVec2& res) {
    const RGB8 line{0, 0, 0};
    const double alpha = 0.13;
    for (int vx = 1; vx < res.x; ++vx) {
        int px = L.gridX0 + int(std::lround(vx * L.scaleX));
        for (int py = L.gridY0; py < L.gridY0 + L.gridHeight; ++py) img.blend(px, py, line, alpha);
    }
    for (int vy = 1; vy < res.y; ++vy) {
        int py = L.gridY0 + L.gridHeight - int(std::lround(vy * L.scaleY));
        for (int px = L.gridX0; px < L.gridX0 + L.gridWidth; ++px) img.blend(px, py, line, alpha);
    }
}

void drawIdDots(ImageRGB& img, const Culler2D& culler, const GridPictureLayout& L) {
    const IVec2 res = culler.grid().resolution();
    const double r = std::max(1.0, 0.16 * std::min(L.scaleX, L.scaleY));
    for (std::int32_t vy = 0; vy < res.y; ++vy)
        for (std::int32_t vx = 0; vx < res.x; ++vx) {
            const VoxelState s = culler.voxelState({vx, vy});
            if (!s.hasIds || s.opaque || s.occluder) continue;
            fillCircle(img, L.localToPicture(Vec2(vx + 0.5, vy + 0.5)), r, picture::kIdDot);
        }
}

// ---------------------------------------------------------------------------------------------------
// Objects

std::vector<Vec2> shapeOutline(const Shape<2>& shape, const GridPictureLayout& L) {
    return std::visit(
        [&](const auto& x) -> std::vector<Vec2> {
            using T = std::decay_t<decltype(x)>;
            if constexpr (std::is_same_v<T, Box<2>>) {
                return {L.toPicture(x.min), L.toPicture({x.max.x, x.min.y}), L.toPicture(x.max),
                        L.toPicture({x.min.x, x.max.y})};
            } else if constexpr (std::is_same_v<T, ConvexPolygon>) {
                std::vector<Vec2> pts;
                pts.reserve(x.points.size());
                for (const Vec2& p : x.points) pts.push_back(L.toPicture(p));
                return pts;
            } else {
                return {};
            }
        },
        shape);
}

void drawObject(ImageRGB& img, const Shape<2>& shape, const GridPictureLayout& L, bool inPvs, double thickness) {
    const RGB8 color = inPvs ? picture::kPvs : picture::kHidden;
    if (const auto* ball = std::get_if<Ball<2>>(&shape)) {
        const Vec2 c = L.toPicture(ball->center);
        const double r = ball->radius / L.voxelSize * 0.5 * (L.scaleX + L.scaleY);
        if (inPvs) fillCircle(img, c, r, color, picture::kPvsFillAlpha);
        drawCircle(img, c, std::max(r - thickness / 2, 0.5), color, thickness);
        return;
    }
    const std::vector<Vec2> pts = shapeOutline(shape, L);
    if (inPvs) fillConvexPolygon(img, pts, color, picture::kPvsFillAlpha);
    drawPolygonOutline(img, pts, color, thickness);
}

// ---------------------------------------------------------------------------------------------------
// View wedge

Vec2 directionToPicture(const Vec2& localDir, const GridPictureLayout& L) {
    Vec2 d(localDir.x * L.scaleX, -localDir.y * L.scaleY);
    double len = std::sqrt(lengthSquared<2>(d));
    return len > 0 ? d / len : Vec2(1, 0);
}

void drawView(ImageRGB& img, const Culler2D& culler, const Camera2& camera, const GridPictureLayout& L,
              double thickness) {
    const ViewWedge wedge(camera, culler.grid());
    const Vec2 apex = L.toPicture(camera.position);
    if (!allFinite<2>(apex)) return;
    const double scale = 0.5 * (L.scaleX + L.scaleY);
    // Rays end at the far distance or just past the farthest picture corner.
    double reach = 0;
    for (Vec2 corner : {Vec2(0, 0), Vec2(img.width(), 0), Vec2(0, img.height()), Vec2(img.width(), img.height())})
        reach = std::max(reach, std::sqrt(lengthSquared<2>(corner - apex)));
    reach += 4;
    const double farPx = std::isfinite(wedge.far()) ? wedge.far() * scale : std::numeric_limits<double>::infinity();
    const double len = std::min(reach, farPx);

    if (!wedge.isFullCircle()) {
        drawLine(img, apex, apex + directionToPicture(wedge.edgeCw(), L) * len, picture::kView, thickness);
        drawLine(img, apex, apex + directionToPicture(wedge.edgeCcw(), L) * len, picture::kView, thickness);
    }
    // The far arc, when it is close enough to be drawn as a polyline.
    if (std::isfinite(farPx) && farPx < 1e6) {
        const double a0 = std::atan2(wedge.edgeCw().y, wedge.edgeCw().x);
        const double sweep = wedge.isFullCircle() ? 2 * 3.141592653589793 : wedge.fov();
        const int n = std::clamp(int(std::ceil(farPx * sweep / 3)), 8, 4096);
        Vec2 prev;
        for (int i = 0; i <= n; ++i) {
            const double a = a0 + sweep * i / n;
            const Vec2 p = apex + Vec2(std::cos(a) * L.scaleX, -std::sin(a) * L.scaleY) * wedge.far();
            if (i > 0) drawLine(img, prev, p, picture::kView, std::max(1.0, thickness - 1));
            prev = p;
        }
    }
    const double dash = 6 * thickness + 4, gap = 3 * thickness + 3;
    drawDashedLine(img, apex, apex + directionToPicture(wedge.direction(), L) * len, picture::kView, dash, gap,
                   thickness);
    const double r = std::clamp(0.45 * scale, 3.0, 6.0);
    drawCircle(img, apex, r + 1, colors::kWhite, 1.5);
    fillCircle(img, apex, r, picture::kView);
}

} // namespace

GridPictureLayout gridPictureLayout(const GridGeometry2& grid, const GridPictureOptions& opt) {
    GridPictureLayout L;
    const int maxPx = std::clamp(opt.maxPixels, 16, 8192);
    const int margin = std::clamp(opt.margin, 0, 512);
    const IVec2 res = grid.resolution();
    const int maxRes = std::max(res.x, res.y);
    double cell = double(maxPx) / maxRes;
    if (cell >= 1) {
        // Whole pixels per cell keep the cells even, unless that shrinks the picture by more than 25%.
        const double whole = std::floor(cell);
        if (whole * maxRes >= 0.75 * maxPx) cell = whole;
    }
    L.gridWidth = std::max(1, int(std::lround(res.x * cell)));
    L.gridHeight = std::max(1, int(std::lround(res.y * cell)));
    L.scaleX = double(L.gridWidth) / res.x;
    L.scaleY = double(L.gridHeight) / res.y;
    L.gridX0 = margin;
    L.gridY0 = margin;
    L.width = L.gridWidth + 2 * margin;
    L.legendY0 = L.gridHeight + 2 * margin;
    L.textScale = L.width >= 700 ? 2 : 1;
    int legendH = 0;
    if (opt.legend) {
        const LegendMetrics m = legendMetrics(L.textScale);
        legendH = 2 * m.pad + legendItemRows(L.width, L.textScale, opt.legendText, m) * m.rowH +
                  legendTextLines(opt) * m.textLineH;
    }
    L.height = L.legendY0 + legendH;
    L.origin = grid.origin();
    L.voxelSize = grid.voxelSize();
    return L;
}

ImageRGB drawGridPicture(const Culler2D& culler, const Camera2& camera, const std::vector<ObjectDesc<2>>& objects,
                         const GridPictureOptions& opt) {
    validateCamera(camera);
    const GridGeometry2& grid = culler.grid();
    const GridPictureLayout L = gridPictureLayout(grid, opt);
    ImageRGB img(L.width, L.height, colors::kWhite);
    const double cellPx = std::min(L.scaleX, L.scaleY);

    drawCells(img, culler, L);
    if (opt.gridLines && cellPx >= 6) drawGridLines(img, L, grid.resolution());
    if (opt.markIdVoxels && cellPx >= 6) drawIdDots(img, culler, L);
    drawRectOutline(img, L.gridX0 - 1, L.gridY0 - 1, L.gridX0 + L.gridWidth + 1, L.gridY0 + L.gridHeight + 1,
                    RGB8{120, 120, 120});

    const CullResult& result = culler.lastResult();
    if (opt.drawObjects) {
        std::vector<ObjectId> pvs = result.pvs;
        std::sort(pvs.begin(), pvs.end());
        const double thickness = cellPx >= 4 ? 2 : 1;
        // Hidden objects first, so that the PVS outlines stay on top.
        for (int pass = 0; pass < 2; ++pass)
            for (const ObjectDesc<2>& o : objects) {
                const bool inPvs = std::binary_search(pvs.begin(), pvs.end(), o.id);
                if (inPvs == (pass == 1)) drawObject(img, o.shape, L, inPvs, thickness);
            }
    }
    if (opt.drawView) drawView(img, culler, camera, L, L.width >= 700 ? 2 : 1);
    // Nothing of the grid area may spill over into the legend strip.
    if (opt.legend) {
        fillRect(img, 0, L.legendY0, img.width(), img.height(), colors::kWhite);
        drawLegend(img, L, opt, result);
    }
    return img;
}

} // namespace rgvc
