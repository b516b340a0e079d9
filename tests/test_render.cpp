// rgvc::render: image primitives, PNG output, and the grid picture of a culled scene.
#include "rgvc/dynamics/Culler.hpp"
#include "rgvc/render/GridPicture.hpp"
#include "rgvc/render/Image.hpp"
#include "rgvc/render/PngWriter.hpp"

#include <catch2/catch.hpp>
#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <vector>

using namespace rgvc;

namespace {

constexpr RGB8 kInk{10, 200, 30};

int countColor(const ImageRGB& img, RGB8 c) {
    int n = 0;
    for (int y = 0; y < img.height(); ++y)
        for (int x = 0; x < img.width(); ++x) n += img.at(x, y) == c ? 1 : 0;
    return n;
}

/// Reads a PNG back with libpng's simplified API (independent of the writer's code path).
ImageRGB readPngRgb(const std::string& path) {
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&image, path.c_str())) FAIL("png_image_begin_read_from_file: " << image.message);
    image.format = PNG_FORMAT_RGB;
    ImageRGB out(int(image.width), int(image.height));
    if (!png_image_finish_read(&image, nullptr, out.data(), png_int_32(out.stride()), nullptr))
        FAIL("png_image_finish_read: " << image.message);
    return out;
}

std::string tempPath(const std::string& name) {
    return (std::filesystem::temp_directory_path() / ("rgvc_test_render_" + name)).string();
}

} // namespace

TEST_CASE("ImageRGB: construction, access and clipping of single pixels", "[render]") {
    ImageRGB img(7, 5, RGB8{1, 2, 3});
    CHECK(img.width() == 7);
    CHECK(img.height() == 5);
    CHECK(img.stride() == 21);
    CHECK(countColor(img, RGB8{1, 2, 3}) == 35);
    img.set(6, 4, kInk);
    CHECK(img.at(6, 4) == kInk);
    CHECK(img.data()[(4 * 7 + 6) * 3 + 1] == 200); // row-major, top row first
    img.set(-1, 0, kInk);
    img.set(7, 0, kInk);
    img.set(0, 5, kInk);
    img.set(0, -1, kInk);
    CHECK(countColor(img, kInk) == 1);
    CHECK_THROWS_AS(img.at(7, 0), std::out_of_range);
    CHECK_THROWS_AS(ImageRGB(-1, 3), std::invalid_argument);
    CHECK(ImageRGB(0, 0).empty());

    img.blend(0, 0, RGB8{201, 102, 203}, 0.5);
    CHECK(img.at(0, 0) == RGB8{101, 52, 103});
    CHECK(blendColor(RGB8{0, 0, 0}, RGB8{255, 255, 255}, 0.0) == RGB8{0, 0, 0});
    CHECK(blendColor(RGB8{0, 0, 0}, RGB8{255, 255, 255}, 1.0) == RGB8{255, 255, 255});
}

TEST_CASE("fillRect and drawRectOutline are half-open and clipped", "[render]") {
    ImageRGB img(10, 8);
    fillRect(img, 2, 3, 5, 7, kInk);
    CHECK(countColor(img, kInk) == 3 * 4);
    CHECK(img.at(2, 3) == kInk);
    CHECK(img.at(4, 6) == kInk);
    CHECK(img.at(5, 6) == colors::kWhite);
    CHECK(img.at(4, 7) == colors::kWhite);

    ImageRGB big(10, 8);
    fillRect(big, -1000000000, -5, 3, 2'000'000'000, kInk); // clipped to columns 0..2, every row
    CHECK(countColor(big, kInk) == 3 * 8);
    fillRect(big, std::numeric_limits<std::int32_t>::min(), 0, std::numeric_limits<std::int32_t>::min(), 8, colors::kBlack);
    CHECK(countColor(big, colors::kBlack) == 0);

    ImageRGB o(10, 8);
    drawRectOutline(o, 1, 1, 5, 4, kInk);
    CHECK(countColor(o, kInk) == 4 + 4 + 1 + 1);
    CHECK(o.at(2, 2) == colors::kWhite);
}

TEST_CASE("drawLine: Bresenham pixels, end points included, clipped", "[render]") {
    SECTION("horizontal, vertical and diagonal") {
        ImageRGB img(20, 20);
        drawLine(img, 2, 3, 12, 3, kInk);
        CHECK(countColor(img, kInk) == 11);
        for (int x = 2; x <= 12; ++x) CHECK(img.at(x, 3) == kInk);

        ImageRGB v(20, 20);
        drawLine(v, 5, 15, 5, 1, kInk);
        CHECK(countColor(v, kInk) == 15);

        ImageRGB d(20, 20);
        drawLine(d, 0, 0, 19, 19, kInk);
        CHECK(countColor(d, kInk) == 20);
        for (int i = 0; i < 20; ++i) CHECK(d.at(i, i) == kInk);
    }
    SECTION("a shallow line is 8-connected with one pixel per column") {
        ImageRGB img(30, 10);
        drawLine(img, 1, 2, 28, 7, kInk);
        CHECK(img.at(1, 2) == kInk);
        CHECK(img.at(28, 7) == kInk);
        for (int x = 1; x <= 28; ++x) {
            int n = 0;
            for (int y = 0; y < 10; ++y) n += img.at(x, y) == kInk;
            CHECK(n == 1);
        }
    }
    SECTION("huge and non-finite coordinates: only the visible part, fast") {
        ImageRGB img(16, 12);
        drawLine(img, Vec2(-1e15, 5.5), Vec2(1e15, 5.5), kInk);
        CHECK(countColor(img, kInk) == 16);
        for (int x = 0; x < 16; ++x) CHECK(img.at(x, 5) == kInk);

        ImageRGB none(16, 12);
        drawLine(none, Vec2(-1e9, -1e9), Vec2(-1e9 + 1, 1e9), kInk);           // entirely left of the image
        drawLine(none, Vec2(std::nan(""), 1), Vec2(5, 5), kInk);                 // ignored
        drawLine(none, Vec2(0, 0), Vec2(std::numeric_limits<double>::infinity(), 3), kInk); // ignored
        CHECK(countColor(none, kInk) == 0);
    }
    SECTION("thick lines cover a band") {
        ImageRGB img(20, 20);
        drawLine(img, Vec2(2, 10), Vec2(18, 10), kInk, 4.0);
        for (int x = 2; x < 18; ++x)
            for (int y = 8; y < 12; ++y) CHECK(img.at(x, y) == kInk);
        CHECK(img.at(10, 7) == colors::kWhite);
        CHECK(img.at(10, 12) == colors::kWhite);
    }
}

TEST_CASE("drawDashedLine alternates dashes and gaps anchored at the start", "[render]") {
    ImageRGB img(40, 3);
    drawDashedLine(img, Vec2(0, 1.5), Vec2(40, 1.5), kInk, 4.0, 2.0);
    for (int x = 0; x < 40; ++x) {
        const bool on = (x % 6) < 4;
        INFO("x = " << x);
        CHECK((img.at(x, 1) == kInk) == on);
    }
    // Clipping keeps the phase: the same line started far to the left shows the same pattern shifted.
    ImageRGB far(40, 3);
    drawDashedLine(far, Vec2(-6000000, 1.5), Vec2(40, 1.5), kInk, 4.0, 2.0);
    for (int x = 0; x < 40; ++x) CHECK(far.at(x, 1) == img.at(x, 1));
}

TEST_CASE("circles: filled disc by pixel centres, outline ring, clipping", "[render]") {
    SECTION("filled") {
        ImageRGB img(21, 21);
        const Vec2 c(10.5, 10.5);
        fillCircle(img, c, 4.2, kInk);
        for (int y = 0; y < 21; ++y)
            for (int x = 0; x < 21; ++x) {
                const double d = std::hypot(x + 0.5 - c.x, y + 0.5 - c.y);
                CHECK((img.at(x, y) == kInk) == (d <= 4.2));
            }
    }
    SECTION("outline") {
        ImageRGB img(21, 21);
        const Vec2 c(10.5, 10.5);
        drawCircle(img, c, 6.0, kInk);
        CHECK(img.at(10, 10) == colors::kWhite);
        CHECK(img.at(16, 10) == kInk);
        CHECK(img.at(4, 10) == kInk);
        CHECK(img.at(10, 4) == kInk);
        int n = 0;
        for (int y = 0; y < 21; ++y)
            for (int x = 0; x < 21; ++x)
                if (img.at(x, y) == kInk) {
                    ++n;
                    const double d = std::hypot(x + 0.5 - c.x, y + 0.5 - c.y);
                    CHECK(d >= 5.5 - 1e-9);
                    CHECK(d <= 6.5 + 1e-9);
                }
        CHECK(n > 30);
        // 8-connected ring: every ring pixel has at least two ring neighbours.
        for (int y = 1; y < 20; ++y)
            for (int x = 1; x < 20; ++x) {
                if (!(img.at(x, y) == kInk)) continue;
                int nb = 0;
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) nb += (dx || dy) && img.at(x + dx, y + dy) == kInk;
                CHECK(nb >= 2);
            }
    }
    SECTION("clipped and huge") {
        ImageRGB img(10, 10);
        fillCircle(img, Vec2(0, 0), 3.0, kInk);
        CHECK(img.at(0, 0) == kInk);
        CHECK(img.at(2, 0) == kInk);
        CHECK(img.at(3, 0) == colors::kWhite);
        ImageRGB all(10, 10);
        fillCircle(all, Vec2(5, 5), 1e12, kInk);
        CHECK(countColor(all, kInk) == 100);
        ImageRGB ring(10, 10);
        drawCircle(ring, Vec2(5, 5), 1e12, kInk); // the ring lies far outside
        CHECK(countColor(ring, kInk) == 0);
    }
}

TEST_CASE("fillConvexPolygon fills exactly the pixels whose centres are inside", "[render]") {
    ImageRGB img(30, 30);
    const std::vector<Vec2> tri = {{2.3, 3.1}, {27.7, 9.4}, {11.2, 26.9}};
    fillConvexPolygon(img, tri, kInk);
    auto inside = [&](double x, double y) {
        for (int i = 0; i < 3; ++i) {
            const Vec2 a = tri[i], b = tri[(i + 1) % 3];
            if (cross2(b - a, Vec2(x, y) - a) < 0) return false;
        }
        return true;
    };
    int n = 0;
    for (int y = 0; y < 30; ++y)
        for (int x = 0; x < 30; ++x) {
            const bool in = inside(x + 0.5, y + 0.5);
            n += in;
            CHECK((img.at(x, y) == kInk) == in);
        }
    CHECK(n > 100);

    // The reverse winding fills the same pixels.
    ImageRGB rev(30, 30);
    fillConvexPolygon(rev, {tri[2], tri[1], tri[0]}, kInk);
    CHECK(rev == img);

    // Translucent fill blends.
    ImageRGB half(4, 4, RGB8{0, 0, 0});
    fillConvexPolygon(half, {{-1, -1}, {5, -1}, {5, 5}, {-1, 5}}, RGB8{200, 100, 50}, 0.5);
    CHECK(half.at(2, 2) == RGB8{100, 50, 25});
}

TEST_CASE("primitives never write outside the image, whatever the coordinates", "[render]") {
    std::mt19937 rng(1234);
    std::uniform_real_distribution<double> coord(-200.0, 200.0);
    std::uniform_real_distribution<double> wild(-1e13, 1e13);
    const double nan = std::nan(""), inf = std::numeric_limits<double>::infinity();
    for (int size : {0, 1, 3, 17}) {
        ImageRGB img(size, size + 1);
        for (int i = 0; i < 400; ++i) {
            auto pick = [&](int k) {
                switch (k % 5) {
                case 0: return coord(rng);
                case 1: return wild(rng);
                case 2: return i % 37 == 0 ? nan : coord(rng);
                case 3: return i % 41 == 0 ? inf : coord(rng);
                default: return coord(rng) * 0.05;
                }
            };
            const Vec2 a(pick(i), pick(i + 1)), b(pick(i + 2), pick(i + 3)), c(pick(i + 4), pick(i));
            drawLine(img, a, b, kInk, 1 + (i % 4));
            drawDashedLine(img, a, b, kInk, 3, 2, 1 + (i % 3));
            fillCircle(img, a, std::abs(pick(i + 1)), kInk, 0.5);
            drawCircle(img, b, std::abs(pick(i + 2)), kInk, 1 + (i % 3));
            fillConvexPolygon(img, {a, b, c}, kInk);
            drawPolygonOutline(img, {a, b, c}, kInk, 2);
            fillRect(img, int(std::clamp(a.x, -1e9, 1e9)), int(std::clamp(a.y, -1e9, 1e9)),
                     int(std::clamp(b.x, -1e9, 1e9)), int(std::clamp(b.y, -1e9, 1e9)), kInk);
            drawText(img, int(std::clamp(c.x, -1e9, 1e9)), int(std::clamp(c.y, -1e9, 1e9)), "Hi!", kInk, 1 + i % 3);
        }
        CHECK(img.width() == size); // survived; the sanitizer build catches any stray write
    }
}

TEST_CASE("drawText draws 5x7 glyphs inside their cell", "[render]") {
    ImageRGB img(40, 12);
    drawText(img, 1, 2, "AB", kInk);
    CHECK(textWidth("AB") == 12);
    int n = 0;
    for (int y = 0; y < 12; ++y)
        for (int x = 0; x < 40; ++x)
            if (img.at(x, y) == kInk) {
                ++n;
                CHECK(x >= 1);
                CHECK(x < 1 + 11);
                CHECK(y >= 2);
                CHECK(y < 2 + 7);
            }
    CHECK(n > 20);
    // 'A': its left column starts one row down, its middle column has the top row set; 'B': the left
    // column spans all seven rows.
    CHECK(img.at(1, 2) == colors::kWhite);
    CHECK(img.at(1, 3) == kInk);
    CHECK(img.at(1 + 2, 2) == kInk);
    for (int row = 0; row < 7; ++row) CHECK(img.at(7, 2 + row) == kInk);
}

TEST_CASE("writePng round trip through libpng", "[render]") {
    std::mt19937 rng(99);
    ImageRGB img(37, 23);
    for (int y = 0; y < img.height(); ++y)
        for (int x = 0; x < img.width(); ++x)
            img.set(x, y, RGB8{std::uint8_t(rng()), std::uint8_t(rng()), std::uint8_t(rng())});
    const std::string path = tempPath("roundtrip.png");
    writePng(path, img);
    const ImageRGB back = readPngRgb(path);
    CHECK(back.width() == img.width());
    CHECK(back.height() == img.height());
    CHECK(back == img);

    // Overwrites an existing file.
    ImageRGB small(2, 1, RGB8{9, 8, 7});
    writePng(path, small);
    CHECK(readPngRgb(path) == small);
    std::filesystem::remove(path);
}

TEST_CASE("writePng reports failures with the path", "[render]") {
    const std::string bad = tempPath("no_such_dir/x/out.png");
    try {
        writePng(bad, ImageRGB(3, 3));
        FAIL("no exception");
    } catch (const std::runtime_error& e) {
        CHECK(std::string(e.what()).find(bad) != std::string::npos);
    }
    CHECK_THROWS_AS(writePng(tempPath("empty.png"), ImageRGB()), std::runtime_error);
    CHECK_FALSE(std::filesystem::exists(tempPath("empty.png")));
}

namespace {

// A 64 x 64 grid, voxel size 0.5, origin (-4, 2). In voxel units: camera at (2.5, 32.5) looking along
// +x with a 90 degree wedge, a wall [16, 20] x [20, 45] in front of it, a hidden ball behind the wall,
// a visible ball in front of it.
struct PictureScene {
    GridGeometry2 grid{Vec2(-4.0, 2.0), 0.5, IVec2(64, 64)};
    Culler2D culler{grid};
    Camera2 camera;
    std::vector<ObjectDesc<2>> objects;

    Vec2 world(double lx, double ly) const { return grid.toWorld(Vec2(lx, ly)); }

    PictureScene() {
        objects.push_back({1, Box<2>{world(16, 20), world(20, 45)}, true, 0});
        objects.push_back({2, Ball<2>{world(45, 38), 1.0}, false, 0.1});   // radius 2 voxels
        objects.push_back({3, Ball<2>{world(10.5, 36.5), 0.75}, false, 0.1}); // radius 1.5 voxels
        for (const auto& o : objects) culler.addObject(o);
        camera.position = world(2.5, 32.5);
        camera.direction = {1, 0};
        camera.fovDeg = 90;
        culler.cull(camera);
    }
};

bool contains(const std::vector<ObjectId>& v, ObjectId id) { return std::find(v.begin(), v.end(), id) != v.end(); }

} // namespace

TEST_CASE("layout: about maxPixels on the longer side, y up, voxel <-> pixel consistent", "[render]") {
    GridPictureOptions opt;
    opt.maxPixels = 1024;
    for (IVec2 res : {IVec2(256, 256), IVec2(100, 40), IVec2(300, 700), IVec2(5000, 3), IVec2(1, 1)}) {
        GridGeometry2 grid(Vec2(0.0), 1.0, res);
        const GridPictureLayout L = gridPictureLayout(grid, opt);
        INFO("resolution " << res.x << " x " << res.y);
        const int longer = std::max(L.gridWidth, L.gridHeight);
        CHECK(longer <= 1024);
        CHECK(longer >= 768);
        CHECK(L.width >= L.gridWidth);
        CHECK(L.height > L.gridHeight); // legend below
        for (IVec2 v : {IVec2(0, 0), IVec2(res.x - 1, res.y - 1), IVec2(res.x / 2, res.y / 3)}) {
            const IVec2 p = L.voxelCentrePixel(v);
            if (L.scaleX >= 1 && L.scaleY >= 1) CHECK(L.voxelAtPixel(p.x, p.y) == v);
        }
        // y up: voxel row 0 is at the bottom of the grid area.
        if (L.scaleY >= 1 && res.y > 1)
            CHECK(L.voxelCentrePixel(IVec2(0, 0)).y > L.voxelCentrePixel(IVec2(0, res.y - 1)).y);
    }
    GridGeometry2 g256(Vec2(0.0), 1.0, IVec2(256, 256));
    const GridPictureLayout L = gridPictureLayout(g256, opt);
    CHECK(L.scaleX == 4.0);
    CHECK(L.scaleY == 4.0);
}

TEST_CASE("grid picture of a culled scene shows the voxel states, objects and camera", "[render]") {
    PictureScene s;
    const CullResult& r = s.culler.lastResult();
    REQUIRE(contains(r.pvs, 1));
    REQUIRE(contains(r.pvs, 3));

    GridPictureOptions opt;
    opt.maxPixels = 512; // 8 px per voxel: grid lines and id dots are drawn
    const ImageRGB img = drawGridPicture(s.culler, s.camera, s.objects, opt);
    const GridPictureLayout L = gridPictureLayout(s.grid, opt);
    REQUIRE(img.width() == L.width);
    REQUIRE(img.height() == L.height);
    REQUIRE(L.scaleX == 8.0);

    auto pixelOf = [&](IVec2 v) {
        const IVec2 p = L.voxelCentrePixel(v);
        return img.at(p.x, p.y);
    };

    // Inside the wall: opaque (or part of an extended occluder), dark.
    const IVec2 wallVoxel(18, 26);
    const VoxelState wall = s.culler.voxelState(wallVoxel);
    REQUIRE(wall.inGrid);
    CHECK((wall.opaque || wall.occluder));
    CHECK((voxelCellColor(wall) == picture::kOpaque || voxelCellColor(wall) == picture::kOccluder));
    // The wall is in the PVS: its cells show through the translucent blue fill.
    CHECK(pixelOf(wallVoxel) == blendColor(voxelCellColor(wall), picture::kPvs, picture::kPvsFillAlpha));

    // Deep in the wall's shadow (and before the traversal may stop early): occluded, light gray.
    for (IVec2 v : {IVec2(25, 26), IVec2(30, 40), IVec2(28, 12)}) {
        const VoxelState st = s.culler.voxelState(v);
        INFO("voxel " << v.x << ", " << v.y);
        CHECK(st.occluded);
        CHECK(pixelOf(v) == voxelCellColor(st));
        if (!st.occluder) CHECK(pixelOf(v) == picture::kOccluded);
    }

    // In front of the wall, inside the wedge, no object: visited and not occluded, pale yellow.
    const IVec2 front(8, 28);
    const VoxelState fs = s.culler.voxelState(front);
    CHECK(fs.visited);
    CHECK_FALSE(fs.occluded);
    CHECK(pixelOf(front) == picture::kVisited);

    // Behind the camera, outside the wedge: never reached, white.
    const IVec2 behind(1, 5);
    CHECK_FALSE(s.culler.voxelState(behind).visited);
    CHECK(pixelOf(behind) == picture::kEmpty);

    // The camera is a black dot.
    const Vec2 cam = L.toPicture(s.camera.position);
    CHECK(img.at(int(cam.x), int(cam.y)) == picture::kView);

    // The visible ball is filled translucent blue over its cell colour.
    const IVec2 ballVoxel(10, 36);
    CHECK(pixelOf(ballVoxel) == blendColor(voxelCellColor(s.culler.voxelState(ballVoxel)), picture::kPvs, picture::kPvsFillAlpha));

    // The hidden ball (when culled) is a red outline; its centre keeps the cell colour.
    if (!contains(r.pvs, 2)) {
        const Vec2 c = L.toPicture(s.world(45, 38));
        const double rPx = 2 * L.scaleX;
        CHECK(img.at(int(c.x + rPx - 1), int(c.y)) == picture::kHidden);
        const IVec2 centreVoxel(44, 37); // the cell to the lower left of the centre
        CHECK(pixelOf(centreVoxel) == voxelCellColor(s.culler.voxelState(centreVoxel)));
    }

    // The view edges (black) cross the grid: the +45 degree edge passes voxel (12, 42) at its centre.
    {
        const Vec2 p = L.localToPicture(Vec2(12.5, 42.5));
        int black = 0;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) black += img.at(int(p.x) + dx, int(p.y) + dy) == picture::kView;
        CHECK(black >= 1);
    }

    // The legend strip below the grid has the swatch colours.
    int opaqueInLegend = 0, pvsInLegend = 0;
    for (int y = L.legendY0; y < img.height(); ++y)
        for (int x = 0; x < img.width(); ++x) {
            opaqueInLegend += img.at(x, y) == picture::kOpaque;
            pvsInLegend += img.at(x, y) == picture::kPvs;
        }
    CHECK(opaqueInLegend > 20);
    CHECK(pvsInLegend > 5);

    // And it can be written.
    const std::string path = tempPath("picture.png");
    writePng(path, img);
    CHECK(readPngRgb(path) == img);
    std::filesystem::remove(path);
}

TEST_CASE("grid picture: full circle, camera outside the grid, fractional scale", "[render]") {
    PictureScene s;
    SECTION("fov 360, far limit") {
        s.camera.fovDeg = 360;
        s.camera.far = 10.0; // 20 voxels
        s.culler.cull(s.camera);
        const ImageRGB img = drawGridPicture(s.culler, s.camera, s.objects, {});
        const GridPictureLayout L = gridPictureLayout(s.grid, {});
        // The far circle crosses the point 20 voxels below the camera.
        const Vec2 p = L.localToPicture(Vec2(2.5 + 0.0, 32.5 - 20.0));
        bool black = false;
        for (int dy = -2; dy <= 2; ++dy) black |= img.at(int(p.x), int(p.y) + dy) == picture::kView;
        CHECK(black);
    }
    SECTION("camera outside the grid") {
        s.camera.position = s.world(-30, 32.5);
        s.culler.cull(s.camera);
        const ImageRGB img = drawGridPicture(s.culler, s.camera, s.objects, {});
        const GridPictureLayout L = gridPictureLayout(s.grid, {});
        int black = 0;
        for (int y = L.gridY0; y < L.gridY0 + L.gridHeight; ++y)
            for (int x = L.gridX0; x < L.gridX0 + L.gridWidth; ++x) black += img.at(x, y) == picture::kView;
        CHECK(black > 100); // edges and line of sight enter the grid area
    }
    SECTION("camera very far away") {
        s.camera.position = s.world(-1e9, 1e9);
        s.camera.direction = {1, -1};
        s.culler.cull(s.camera);
        const ImageRGB img = drawGridPicture(s.culler, s.camera, s.objects, {});
        CHECK(img.width() > 0);
    }
    SECTION("fractional pixels per voxel") {
        GridGeometry2 grid(Vec2(0.0), 1.0, IVec2(700, 300));
        Culler2D culler(grid);
        culler.addObject({5, Box<2>{{100, 100}, {120, 200}}, true, 0});
        Camera2 cam;
        cam.position = {50, 150};
        cam.direction = {1, 0.1};
        cam.fovDeg = 60;
        culler.cull(cam);
        GridPictureOptions opt;
        opt.maxPixels = 1000;
        const ImageRGB img = drawGridPicture(culler, cam, {{5, Box<2>{{100, 100}, {120, 200}}, true, 0}}, opt);
        const GridPictureLayout L = gridPictureLayout(grid, opt);
        CHECK(L.gridWidth == 1000);
        CHECK(img.width() == L.width);
        const IVec2 p = L.voxelCentrePixel(IVec2(110, 150));
        CHECK(img.at(p.x, p.y) == blendColor(voxelCellColor(culler.voxelState({110, 150})), picture::kPvs,
                                             picture::kPvsFillAlpha));
    }
    SECTION("an invalid camera is rejected") {
        Camera2 bad = s.camera;
        bad.direction = {0, 0};
        CHECK_THROWS_AS(drawGridPicture(s.culler, bad, s.objects, {}), InvalidInput);
    }
}
