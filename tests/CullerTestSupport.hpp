// What the culler test files share (header-only): cameras, a frame checked against the reference with its
// figures tallied and its failures reported in full, the scene of a failing frame written as a replayable
// scene-format file, and the stress tests' scene building.
//
// A checked frame culls one camera and compares the PVS with the reference (the exact 2D one, or the
// sampled 3D one at its defaults): a visible object missing from the PVS is a miss, and the PVS must be
// sorted ascending without duplicates (and, where asked, hold only the culler's ids). The first three
// failing frames of a Tally are reported: the label, the missed ids with the point where the reference saw
// each and the culler's state of the voxel there, the camera, and the scene, written to the temp
// directory (`rgvc cull <file>` replays it). Each test file keeps its own scenes, seeds and cameras.
#pragma once

#include "ExactVisibility2D.hpp"
#include "ExactVisibility3D.hpp"
#include "RandomScenes2D.hpp"
#include "RandomScenes3D.hpp"
#include "SeededRandom.hpp"

#include "rgvc/dynamics/Culler.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

namespace rgvc::culler_test {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kInf = std::numeric_limits<double>::infinity();

// ---------------------------------------------------------------------------------------------------
// Small helpers

inline bool contains(const std::vector<ObjectId>& sorted, ObjectId id) { return std::binary_search(sorted.begin(), sorted.end(), id); }

inline bool sortedUnique(const std::vector<ObjectId>& ids) {
    return std::adjacent_find(ids.begin(), ids.end(), std::greater_equal<ObjectId>()) == ids.end();
}

// ---------------------------------------------------------------------------------------------------
// The sanitized run

/// Whether this test binary runs under AddressSanitizer: the test command's second stage (RGVC_SANITIZE),
/// which looks for memory errors and undefined behaviour. The first scenes of a randomized case reach
/// the same code as the last, ten to twenty times slower there, and the Release stage runs every case in
/// full for misses; so the few heaviest cases (a minute or more each under ASan) run a share of their
/// scenes, cameras or angles there (sanitizedShare), which keeps the whole test command in its budget.
#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kSanitized = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool kSanitized = true;
#else
inline constexpr bool kSanitized = false;
#endif
#else
inline constexpr bool kSanitized = false;
#endif

/// n in the Release run, n / divisor (at least 1) under AddressSanitizer (kSanitized).
inline constexpr int sanitizedShare(int n, int divisor = 2) { return kSanitized ? std::max(1, n / divisor) : n; }

inline double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

/// "<name>, seed <seed>, camera <camera>": the label of one frame of a seeded case.
inline std::string frameLabel(const std::string& name, std::uint64_t seed, int camera) {
    return name + ", seed " + std::to_string(seed) + ", camera " + std::to_string(camera);
}

inline Camera2 makeCamera(const Vec2& position, const Vec2& direction, double fovDeg, double far = kInf) {
    Camera2 c;
    c.position = position;
    c.direction = direction;
    c.fovDeg = fovDeg;
    c.far = far;
    return c;
}

inline Camera3 makeCamera(const Vec3& position, const Vec3& direction, double fovDeg, double far = kInf, double aspect = 1,
                          const Vec3& up = Vec3(0.0)) {
    Camera3 c;
    c.position = position;
    c.direction = direction;
    c.fovDeg = fovDeg;
    c.far = far;
    c.aspect = aspect;
    c.up = up;
    return c;
}

/// A hand-made scene's objects: ids 1, 2, ... in the order of `shapes`, all static.
template <int D> std::vector<ObjectDesc<D>> staticObjects(const std::vector<Shape<D>>& shapes) {
    std::vector<ObjectDesc<D>> objects;
    for (std::size_t i = 0; i < shapes.size(); ++i) {
        ObjectDesc<D> o;
        o.id = i + 1;
        o.shape = shapes[i];
        o.isStatic = true;
        objects.push_back(o);
    }
    return objects;
}

/// A culler holding `objects`.
template <int D> Culler<D> makeCuller(const GridGeometry<D>& grid, const std::vector<ObjectDesc<D>>& objects,
                                      const CullerOptions& options = {}) {
    Culler<D> culler(grid, options);
    for (const ObjectDesc<D>& o : objects) culler.addObject(o);
    return culler;
}

// ---------------------------------------------------------------------------------------------------
// The references, by dimension

template <int D> using ReferenceStats = std::conditional_t<D == 2, reference::ExactStats, reference::Visibility3DStats>;

/// Per object, whether the reference sees it: the exact 2D reference, or the sampled 3D one at its defaults.
/// `stats` (optional) gets the point where each visible object was seen (witness).
template <int D> std::vector<bool> referenceVisible(const std::vector<Shape<D>>& shapes, const Camera<D>& cam,
                                                    ReferenceStats<D>* stats = nullptr) {
    if constexpr (D == 2) return reference::exactVisible2D(shapes, cam, {}, stats);
    else return reference::visible3D(shapes, cam, {}, stats);
}

/// Per object, whether it touches the view region (what view-frustum culling alone reports).
template <int D> std::vector<bool> inViewRegion(const std::vector<Shape<D>>& shapes, const Camera<D>& cam) {
    if constexpr (D == 2) return reference::inViewRegion2D(shapes, cam);
    else return reference::inViewRegion3D(shapes, cam);
}

inline const char* seenName(reference::Seen3D s) {
    switch (s) {
    case reference::Seen3D::No: return "not seen";
    case reference::Seen3D::ContainsCamera: return "contains the camera";
    case reference::Seen3D::GridRay: return "grid ray";
    case reference::Seen3D::TargetRay: return "target ray";
    case reference::Seen3D::CriticalRay: return "critical ray";
    }
    return "?";
}

// ---------------------------------------------------------------------------------------------------
// Failure reports

/// Writes "(x, y[, z])" with os's precision.
template <int D, class T> void writeVec(std::ostream& os, const glm::vec<D, T, glm::defaultp>& v) {
    os << "(";
    for (int a = 0; a < D; ++a) os << (a ? ", " : "") << v[a];
    os << ")";
}

/// The culler's state of the voxel holding `world`.
template <int D> std::string describeVoxel(const Culler<D>& culler, const Vec<D>& world) {
    const IVec<D> v = culler.grid().voxelOf(world);
    const VoxelState s = culler.voxelState(v);
    std::ostringstream os;
    os << "voxel ";
    writeVec(os, v);
    if (!s.inGrid) return os.str() + " outside the grid";
    os << " opaque=" << s.opaque << " occluded=" << s.occluded << " visited=" << s.visited << " occluder=" << s.occluder
       << " hasIds=" << s.hasIds << " hasTbv=" << s.hasTbv;
    return os.str();
}

/// The camera in full (17 digits), with its voxel's state.
template <int D> std::string describeCamera(const Culler<D>& culler, const Camera<D>& cam) {
    std::ostringstream os;
    os.precision(17);
    os << "camera position ";
    writeVec(os, cam.position);
    os << " = voxel units ";
    writeVec(os, culler.grid().toLocal(cam.position));
    os << ", direction ";
    writeVec(os, cam.direction);
    if constexpr (D == 3) {
        os << ", up ";
        writeVec(os, cam.up);
    }
    os << ", fov " << cam.fovDeg;
    if constexpr (D == 3) os << ", aspect " << cam.aspect;
    os << ", far " << cam.far << "; camera " << describeVoxel(culler, cam.position);
    return os.str();
}

/// Writes `json` to <temp>/rgvc-<suite>-<label>.json, each character of the label other than a letter or
/// a digit as '-' (a run of them as one, unless !squeezeDashes). Returns the path, or "" when it cannot.
inline std::string saveScene(std::string_view suite, const std::string& json, const std::string& label, bool squeezeDashes = true) {
    std::string name = "rgvc-" + std::string(suite) + "-";
    for (char ch : label) {
        const char c = std::isalnum(static_cast<unsigned char>(ch)) ? ch : '-';
        if (!squeezeDashes || c != '-' || name.back() != '-') name += c;
    }
    std::error_code ec;
    const std::filesystem::path dir = std::filesystem::temp_directory_path(ec);
    if (ec) return "";
    const std::filesystem::path p = dir / (name + ".json");
    std::ofstream f(p);
    f << json;
    return f ? p.string() : "";
}

/// Saves the scene (saveScene) and says where, with the command that replays it. Catch wraps long
/// messages at 80 columns, which breaks numbers apart; the replayable file is written whole, and the JSON
/// goes into the message only when the file cannot be written.
inline std::string replayNote(std::string_view suite, const std::string& json, const std::string& label) {
    const std::string path = saveScene(suite, json, label);
    if (path.empty()) return "scene:\n" + json;
    return "scene written to " + path + " (replay: rgvc cull " + path + ")";
}

// ---------------------------------------------------------------------------------------------------
// Checked frames and their figures

/// What a test file's checked frames gather and check, and the name its figures and scene files carry.
struct CheckOptions {
    std::string_view suite;     ///< figures print as "[suite] ...", failing scenes go to rgvc-suite-*.json
    bool viewRegion = true;     ///< also count the objects in the view region (the |VFC|/|visible| figures)
    bool checkIdsKnown = false; ///< also check that every id in the PVS is one of the culler's
};

/// Figures of one test case (or part of one), printed at its end; overestimation is measured, not judged.
struct Tally {
    explicit Tally(const CheckOptions& options) : check(options) {}

    CheckOptions check;
    std::size_t frames = 0, framesWithVisible = 0, misses = 0, failedFrames = 0, outsideFallbacks = 0;
    std::size_t sumPvs = 0, sumVisible = 0, sumVfc = 0;
    double sumPvsRatio = 0, sumVfcRatio = 0;
    // The same over frames with the camera in the grid (no fallback): the grid algorithm's own figure,
    // not diluted by the camera-outside fallback, which reports the whole view-region set.
    std::size_t framesInGrid = 0;
    double sumPvsRatioInGrid = 0, sumVfcRatioInGrid = 0;
    std::size_t earlyTerminations = 0, framesWithOcclusion = 0;
    std::size_t unshifted = 0; ///< frames whose reference could not run on the scene shifted next to the origin
    double cullMs = 0, referenceMs = 0;
    std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();

    void add(const CullStats& s, std::size_t nPvs, std::size_t nVisible, std::size_t nVfc) {
        ++frames;
        outsideFallbacks += s.fallback == Fallback::CameraOutsideGrid;
        earlyTerminations += s.earlyTermination;
        framesWithOcclusion += !s.occlusionSkipped;
        if (nVisible == 0) return;
        ++framesWithVisible;
        sumPvsRatio += double(nPvs) / double(nVisible);
        sumVfcRatio += double(nVfc) / double(nVisible);
        sumPvs += nPvs;
        sumVisible += nVisible;
        sumVfc += nVfc;
        if (s.fallback == Fallback::None) {
            ++framesInGrid;
            sumPvsRatioInGrid += double(nPvs) / double(nVisible);
            sumVfcRatioInGrid += double(nVfc) / double(nVisible);
        }
    }

    void print(const std::string& name) const {
        auto mean = [](double sum, std::size_t n) { return n ? sum / double(n) : 0.0; };
        std::ostringstream os;
        os.precision(4);
        os << "[" << check.suite << "] " << name << ": " << frames << " frames (" << framesWithVisible << " with something visible, "
           << outsideFallbacks << " camera-outside fallbacks), " << misses << " misses; |PVS|/|visible| mean "
           << mean(sumPvsRatio, framesWithVisible) << ", pooled " << mean(double(sumPvs), sumVisible);
        if (check.viewRegion)
            os << "; |VFC|/|visible| mean " << mean(sumVfcRatio, framesWithVisible) << ", pooled " << mean(double(sumVfc), sumVisible);
        os << "; cameras in the grid only (" << framesInGrid << " frames): |PVS|/|visible| mean " << mean(sumPvsRatioInGrid, framesInGrid);
        if (check.viewRegion) os << ", |VFC|/|visible| mean " << mean(sumVfcRatioInGrid, framesInGrid);
        os << "; frames with occlusion work " << framesWithOcclusion << ", early terminations " << earlyTerminations;
        if (unshifted) os << "; " << unshifted << " frames checked unshifted";
        os << "; cull " << cullMs << " ms, reference " << referenceMs << " ms, "
           << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() << " s in all\n";
        std::cout << os.str() << std::flush;
    }
};

/// x - shift, when that difference is exact (Sterbenz: same sign, within a factor of two; or shift 0).
inline bool exactDifference(double x, double shift, double& out) {
    out = x - shift;
    if (shift == 0) return true;
    const double a = std::abs(x), b = std::abs(shift);
    return (x > 0) == (shift > 0) && a >= 0.5 * b && a <= 2 * b;
}

/// The scene moved by -shift for the reference, when every coordinate moves exactly (false otherwise).
///
/// The reference's tolerance is 1e-12 of the largest coordinate magnitude: 1e-6 world units for a scene
/// at 1e6, a thousandth of a 1e-3 voxel, so it would call objects that miss the view region by less than
/// that "visible" (the culler, working in voxel units, is far more precise). Moved next to the origin
/// *exactly*, the scene is the same geometric problem, and the reference's tolerance shrinks with it.
template <int D> bool shiftedForReference(const Vec<D>& shift, std::vector<Shape<D>>& shapes, Camera<D>& cam) {
    bool exact = true;
    auto move = [&](Vec<D>& p) {
        Vec<D> q;
        for (int a = 0; a < D; ++a) exact = exactDifference(p[a], shift[a], q[a]) && exact;
        p = q;
    };
    for (Shape<D>& s : shapes)
        std::visit(
            [&](auto& x) {
                using T = std::decay_t<decltype(x)>;
                if constexpr (std::is_same_v<T, Ball<D>>) move(x.center);
                else if constexpr (std::is_same_v<T, Box<D>>) move(x.min), move(x.max);
                else if constexpr (std::is_same_v<T, ConvexPolygon>)
                    for (Vec<D>& q : x.points) move(q);
                else if constexpr (D == 3 && std::is_same_v<T, ConvexPolytope>) {
                    // Vertices and bounds move exactly; plane offsets would round: never exact.
                    exact = false;
                    x = translatedPolytope(x, -shift);
                } else if constexpr (D == 3 && std::is_same_v<T, MeshSolid>) {
                    exact = false; // the same for a mesh's hull
                    x = x.translated(-shift);
                } else
                    static_assert(kUnhandledShape<T>);
            },
            s);
    move(cam.position);
    return exact;
}

/// Culls `cam` on `culler` (which holds exactly `objects`) and compares with the reference, computed on
/// the scene moved by -referenceShift where that is exact (see shiftedForReference). Adds to the tally;
/// reports (INFO + FAIL_CHECK) the first three failing frames of the tally in full.
template <int D> void checkFrame(Culler<D>& culler, const std::vector<ObjectDesc<D>>& objects, const Camera<D>& cam,
                                 const std::string& label, Tally& tally, const Vec<D>& referenceShift = Vec<D>(0.0)) {
    const CheckOptions& opt = tally.check;
    std::vector<Shape<D>> shapes = reference::shapesOf(objects);
    Camera<D> refCam = cam;
    if (referenceShift != Vec<D>(0.0) && !shiftedForReference<D>(referenceShift, shapes, refCam)) {
        shapes = reference::shapesOf(objects);
        refCam = cam;
        ++tally.unshifted;
    }
    auto t0 = std::chrono::steady_clock::now();
    ReferenceStats<D> stats;
    const std::vector<bool> visible = referenceVisible<D>(shapes, refCam, &stats);
    const std::vector<bool> inView = opt.viewRegion ? inViewRegion<D>(shapes, refCam) : std::vector<bool>(objects.size(), false);
    tally.referenceMs += msSince(t0);
    if (refCam.position != cam.position)
        for (Vec<D>& w : stats.witness) w += cam.position - refCam.position; // back to the culler's coordinates

    t0 = std::chrono::steady_clock::now();
    const CullResult& result = culler.cull(cam);
    tally.cullMs += msSince(t0);
    const std::vector<ObjectId>& pvs = result.pvs;

    std::size_t nVisible = 0, nVfc = 0;
    std::vector<std::size_t> missed;
    for (std::size_t i = 0; i < objects.size(); ++i) {
        nVisible += visible[i];
        nVfc += inView[i];
        if (visible[i] && !contains(pvs, objects[i].id)) missed.push_back(i);
    }
    const bool ordered = sortedUnique(pvs);
    bool allKnown = true;
    if (opt.checkIdsKnown) {
        std::vector<ObjectId> known;
        for (const ObjectDesc<D>& o : objects) known.push_back(o.id);
        std::sort(known.begin(), known.end());
        allKnown = ordered && std::includes(known.begin(), known.end(), pvs.begin(), pvs.end());
    }
    tally.add(result.stats, pvs.size(), nVisible, nVfc);
    if (missed.empty() && ordered && allKnown) return;

    tally.misses += missed.size();
    if (++tally.failedFrames > 3) return; // three full reports are plenty; the count says the rest
    std::ostringstream os;
    os.precision(17);
    os << label << ": " << missed.size() << " visible object(s) missing from the PVS (" << pvs.size() << " reported, "
       << nVisible << " visible, ";
    if (opt.viewRegion) os << nVfc << " in the view region, ";
    os << "fallback " << toString(result.stats.fallback) << ", layers " << result.stats.layers << ", early termination "
       << result.stats.earlyTermination << ")\n";
    for (std::size_t i : missed) {
        const Vec<D> w = stats.witness[i];
        os << "  missed id " << objects[i].id << " (object index " << i;
        if constexpr (D == 3) os << ", " << seenName(stats.seen[i]);
        os << "), seen at world ";
        writeVec(os, w);
        os << " = voxel units ";
        writeVec(os, culler.grid().toLocal(w));
        os << ", " << describeVoxel(culler, w) << "\n";
    }
    os << describeCamera(culler, cam) << "\n" << replayNote(opt.suite, reference::toJson(culler.grid(), objects, cam), label);
    INFO(os.str());
    if (!ordered) FAIL_CHECK("the PVS is not sorted ascending without duplicates");
    if (!allKnown) FAIL_CHECK("the PVS holds an id that is not in the culler");
    if (!missed.empty()) FAIL_CHECK("culler missed a visible object");
}

/// The moving-scene loop of the random 3D scene tests: `frames` frames; from the second on, every
/// non-static object moves by min(2 voxels, maxSpeed) in a random direction (updateObject), and each
/// frame is culled from a random camera (the scene's own at frame 0) and checked (checkFrame).
inline void runMovingFrames(Culler3D& culler, std::vector<ObjectDesc<3>>& objects, const reference::Scene3D& s,
                            const reference::SceneOptions3D& opt, std::mt19937_64& rng, int frames, const std::string& label,
                            Tally& tally) {
    for (int frame = 0; frame < frames; ++frame) {
        if (frame > 0)
            for (ObjectDesc<3>& o : objects) {
                if (o.isStatic) continue;
                const double d = std::min(2 * s.grid.voxelSize(), o.maxSpeed);
                Vec3 t{reference::seeded::uniform(rng, -1, 1), reference::seeded::uniform(rng, -1, 1), reference::seeded::uniform(rng, -1, 1)};
                t *= d / std::max(1e-300, std::sqrt(lengthSquared<3>(t)));
                o.shape = translated<3>(o.shape, t);
                culler.updateObject(o.id, o.shape);
            }
        const Camera3 cam = frame == 0 ? s.camera : reference::randomCamera3D(rng, s.grid, objects, s.snapped, opt);
        checkFrame(culler, objects, cam, label + ", frame " + std::to_string(frame), tally);
    }
}

// ---------------------------------------------------------------------------------------------------
// The stress tests' scenes (test_stress2d, test_stress3d)

template <int D> bool isValidShape(const Shape<D>& s) {
    Shape<D> copy = s;
    try {
        validateShape<D>(copy, "stress");
        return true;
    } catch (const InvalidInput&) {
        return false;
    }
}

/// Appends `shape` with a fresh id (some ids beyond 32 bits); drops shapes that rounding made invalid.
template <int D> void pushObject(std::vector<ObjectDesc<D>>& objects, const Shape<D>& shape, std::mt19937_64& rng) {
    if (!isValidShape<D>(shape)) return;
    ObjectDesc<D> o;
    o.id = ObjectId(objects.size()) * 11 + 5 + (objects.size() % 4 == 1 ? (ObjectId(1) << 41) : 0);
    o.shape = shape;
    o.isStatic = reference::seeded::chance(rng, 0.5);
    o.maxSpeed = o.isStatic ? 0.0 : 1.0;
    objects.push_back(o);
}

/// `count` random objects of the RandomScenes2D / RandomScenes3D mixture (snapped: every coordinate on
/// voxel faces).
template <int D> void addRandomObjects(std::mt19937_64& rng, const GridGeometry<D>& grid, bool snapped, int count,
                                       std::vector<ObjectDesc<D>>& objects) {
    using Placer = std::conditional_t<D == 2, reference::scene_detail::Placer, reference::scene3d_detail::Placer3>;
    const Placer pl{grid};
    const Vec<D> r = Vec<D>(grid.resolution());
    double smallest = r[0];
    for (int a = 1; a < D; ++a) smallest = std::min(smallest, r[a]);
    std::vector<Shape<D>> shapes;
    while (int(shapes.size()) < count) {
        Vec<D> c;
        for (int a = 0; a < D; ++a) c[a] = reference::seeded::uniform(rng, -0.1 * r[a], 1.1 * r[a]);
        if constexpr (D == 2) reference::scene_detail::addObjects(rng, pl, snapped, c, smallest / 3, shapes);
        else reference::scene3d_detail::addObjects(rng, pl, snapped, c, smallest / 3, shapes);
    }
    shapes.resize(std::size_t(count));
    for (const Shape<D>& s : shapes) pushObject(objects, s, rng);
}

/// A grid whose voxel faces are exact doubles: a voxel size drawn from `sizes` (dyadic), the origin a
/// multiple of it.
template <int D> GridGeometry<D> exactGrid(std::mt19937_64& rng, int minRes, int maxRes, const std::vector<double>& sizes) {
    namespace sr = reference::seeded;
    const double d = sr::pick(rng, sizes);
    IVec<D> res;
    for (int a = 0; a < D; ++a) res[a] = sr::uniformInt(rng, minRes, maxRes);
    Vec<D> origin;
    for (int a = 0; a < D; ++a) origin[a] = double(sr::uniformInt(rng, -64, 64)) * d;
    return GridGeometry<D>(origin, d, res);
}

/// v, or one ulp above or below it (a third each).
inline double nudgeUlp(std::mt19937_64& rng, double v) {
    const int m = reference::seeded::uniformInt(rng, 0, 2);
    return m == 0 ? v : std::nextafter(v, m == 1 ? kInf : -kInf);
}

// ---------------------------------------------------------------------------------------------------
// The occlusion buffers' tests (test_occlusion_buffer, test_occlusion_buffer2d)

/// The culler's buffer pass (Culler.cpp refineWithBuffer) over all objects: nearest first, hidden ones
/// marked, the others drawn. Buffer: OcclusionBuffer2D or OcclusionBuffer3D.
template <class Buffer, class ShapeT> std::vector<bool> bufferPass(Buffer& buffer, const std::vector<ShapeT>& objects, double slack) {
    std::vector<std::pair<double, std::size_t>> order;
    for (std::size_t i = 0; i < objects.size(); ++i) order.push_back({buffer.nearestDistance(objects[i], slack), i});
    std::sort(order.begin(), order.end());
    std::vector<bool> hidden(objects.size(), false);
    for (const auto& [d, i] : order) {
        if (buffer.hidden(objects[i], slack, d))
            hidden[i] = true;
        else
            buffer.draw(objects[i], slack);
    }
    return hidden;
}

/// A random unit vector (rejection sampling in the unit ball; seeded tests' motions and walks).
template <int D> Vec<D> randomUnit(std::mt19937_64& rng) {
    for (;;) {
        Vec<D> v;
        for (int a = 0; a < D; ++a) v[a] = reference::seeded::uniform(rng, -1, 1);
        const double l2 = lengthSquared<D>(v);
        if (l2 > 1e-4 && l2 <= 1) return v / std::sqrt(l2);
    }
}

} // namespace rgvc::culler_test
