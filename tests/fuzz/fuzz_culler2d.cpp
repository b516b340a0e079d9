// libFuzzer target: arbitrary bytes -> a small 2D scene driven through the Culler2D API.
//
// The bytes decode into a grid (origin, voxel size, resolution), then up to 64 operations: addObject,
// updateObject, removeObject and cull, with ids drawn from a small range (so duplicates and unknown ids
// are common) and every number either "tame" (voxel-aligned quarters in and around the grid), or taken
// from a table of troublemakers (NaN, +-inf, -0, denormals, DBL_MAX, 1e+-300), or raw bit patterns.
//
// rgvc::InvalidInput is the one acceptable refusal. Anything else escaping, a crash, a sanitizer report
// or a hang is a bug, and so is any of these:
//   - a PVS that is not sorted ascending without duplicates, holds an id the culler does not hold, or
//     disagrees with stats.pvsSize / stats.objectCount;
//   - a refused call that changed anything (strong guarantee): after it, the last camera culls to the
//     same PVS as before it, and objectCount/hasObject are unchanged;
//   - addObject accepting a duplicate id, update/remove accepting an unknown one, or rejecting a known one
//     for a reason other than the shape.
// With RGVC_FUZZ_REFERENCE=1 in the environment, tame frames are also checked against the exact reference
// (rgvc::reference::exactVisible2D): a visible object missing from the PVS is a bug. With RGVC_FUZZ_TRACE=1
// every operation is printed, every cull with its scene file and PVS, and every refusal with its message
// (refusals re-cull the last camera).
//
// Build: -DRGVC_BUILD_FUZZERS=ON -DCMAKE_CXX_COMPILER=clang++; run: scripts/fuzz.sh culler2d.
#include "ExactVisibility2D.hpp"
#include "RandomScenes2D.hpp"
#include "FuzzTrace.hpp"

#include "rgvc/dynamics/Culler.hpp"

#include <fuzzer/FuzzedDataProvider.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

using namespace rgvc;

namespace {

const bool kReference = [] {
    const char* v = std::getenv("RGVC_FUZZ_REFERENCE");
    return v && *v && std::strcmp(v, "0") != 0;
}();

[[noreturn]] void bug(const std::string& what) {
    std::fprintf(stderr, "fuzz_culler2d: BUG: %s\n", what.c_str());
    std::fflush(stderr);
    std::abort();
}

class Decoder {
public:
    Decoder(const std::uint8_t* data, std::size_t size) : m_in(data, size) {}

    bool done() { return m_in.remaining_bytes() == 0; }
    bool flag() { return m_in.ConsumeBool(); }
    template <class T> T integer(T lo, T hi) { return m_in.ConsumeIntegralInRange<T>(lo, hi); }

    /// A troublemaker, raw bits, or `tame`.
    double number(double tame) {
        switch (m_in.ConsumeIntegralInRange<int>(0, 15)) {
        case 0: {
            static const double table[] = {std::numeric_limits<double>::quiet_NaN(),
                                           std::numeric_limits<double>::infinity(),
                                           -std::numeric_limits<double>::infinity(),
                                           0.0,
                                           -0.0,
                                           std::numeric_limits<double>::denorm_min(),
                                           std::numeric_limits<double>::min(),
                                           std::numeric_limits<double>::max(),
                                           std::numeric_limits<double>::lowest(),
                                           1e-300,
                                           -1e-300,
                                           1e300,
                                           -1e300,
                                           1e6,
                                           -1e6,
                                           std::numeric_limits<double>::epsilon()};
            m_tame = false;
            return table[m_in.ConsumeIntegralInRange<std::size_t>(0, std::size(table) - 1)];
        }
        case 1: {
            const std::uint64_t bits = m_in.ConsumeIntegral<std::uint64_t>();
            double d;
            std::memcpy(&d, &bits, sizeof d);
            m_tame = false;
            return d;
        }
        case 2: // just next to the tame value
            return std::nextafter(tame, m_in.ConsumeBool() ? std::numeric_limits<double>::infinity()
                                                           : -std::numeric_limits<double>::infinity());
        default: return tame;
        }
    }

    /// A world coordinate on axis a: quarter voxels from a little outside the grid to a little beyond.
    double coordinate(const GridGeometry2& g, int a) {
        const int n = g.resolution()[a];
        const double q = m_in.ConsumeIntegralInRange<int>(-16, 4 * std::min(n, 1 << 12) + 16) * 0.25;
        return number(g.origin()[a] + q * g.voxelSize());
    }
    Vec2 point(const GridGeometry2& g) {
        const double x = coordinate(g, 0);
        return {x, coordinate(g, 1)};
    }
    /// A positive length: 1/1024 voxel to 16 voxels, mostly.
    double length(const GridGeometry2& g) {
        const int k = m_in.ConsumeIntegralInRange<int>(-10, 4);
        return number(std::ldexp(1.0, k) * (1 + m_in.ConsumeIntegralInRange<int>(0, 3)) * g.voxelSize());
    }

    Shape<2> shape(const GridGeometry2& g) {
        switch (m_in.ConsumeIntegralInRange<int>(0, 2)) {
        case 0: {
            const Vec2 c = point(g);
            return Ball<2>{c, length(g)};
        }
        case 1: {
            const Vec2 lo = point(g);
            if (m_in.ConsumeBool()) return Box<2>{lo, point(g)}; // possibly inverted
            const double w = length(g);
            return Box<2>{lo, lo + Vec2{w, length(g)}};
        }
        default: {
            ConvexPolygon p;
            if (m_in.ConsumeBool()) { // arbitrary points: mostly invalid
                const int n = m_in.ConsumeIntegralInRange<int>(0, 8);
                for (int i = 0; i < n; ++i) p.points.push_back(point(g));
            } else { // a regular polygon, either winding: valid unless a number is wild
                const Vec2 c = point(g);
                const double r = length(g);
                const int n = m_in.ConsumeIntegralInRange<int>(3, 8);
                const double phase = m_in.ConsumeIntegralInRange<int>(0, 15) * (3.141592653589793 / 8);
                const double sign = m_in.ConsumeBool() ? 1 : -1;
                for (int i = 0; i < n; ++i) {
                    const double a = phase + sign * 2 * 3.141592653589793 * i / n;
                    p.points.push_back({number(c.x + r * std::cos(a)), c.y + r * std::sin(a)});
                }
            }
            return p;
        }
        }
    }

    Camera2 camera(const GridGeometry2& g) {
        static const Vec2 dirs[] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {-1, 1}, {1, -1}, {-1, -1}, {2, 1}, {1, -3}};
        static const double fovs[] = {1e-3, 1, 30, 45, 60, 90, 90.5, 120, 179.999, 180, 180.001, 270, 359.999, 360};
        Camera2 c;
        c.position = point(g);
        const Vec2 d = dirs[m_in.ConsumeIntegralInRange<std::size_t>(0, std::size(dirs) - 1)];
        c.direction = {number(d.x), number(d.y)};
        c.fovDeg = number(fovs[m_in.ConsumeIntegralInRange<std::size_t>(0, std::size(fovs) - 1)]);
        if (m_in.ConsumeIntegralInRange<int>(0, 3) == 0) c.far = number(g.voxelSize() * m_in.ConsumeIntegralInRange<int>(1, 64));
        return c;
    }

    /// Whether every number since the last call was tame (no table value, no raw bits).
    bool takeTame() {
        const bool t = m_tame;
        m_tame = true;
        return t;
    }

private:
    FuzzedDataProvider m_in;
    bool m_tame = true;
};

bool sortedUnique(const std::vector<ObjectId>& v) {
    return std::adjacent_find(v.begin(), v.end(), std::greater_equal<ObjectId>()) == v.end();
}

struct Model {
    std::map<ObjectId, Shape<2>> objects; // validated (normalised) shapes
    bool tame = true;                     // every shape added or updated so far was tame
};

void checkResult(const Culler2D& culler, const Model& model, const CullResult& r) {
    if (!sortedUnique(r.pvs)) bug("PVS not sorted ascending without duplicates");
    for (ObjectId id : r.pvs)
        if (!model.objects.count(id)) bug("PVS holds id " + std::to_string(id) + ", which the culler does not hold");
    if (r.stats.pvsSize != r.pvs.size()) bug("stats.pvsSize != |PVS|");
    if (r.stats.objectCount != model.objects.size() || culler.objectCount() != model.objects.size())
        bug("object count differs from the model");
}

void checkAgainstReference(const Culler2D& culler, const Model& model, const Camera2& cam, const CullResult& r) {
    std::vector<Shape<2>> shapes;
    std::vector<ObjectDesc<2>> descs;
    for (const auto& [id, s] : model.objects) {
        shapes.push_back(s);
        descs.push_back({id, s, true, 0});
    }
    const std::vector<bool> visible = reference::exactVisible2D(shapes, cam);
    std::size_t i = 0;
    for (const auto& [id, s] : model.objects) {
        if (visible[i++] && !std::binary_search(r.pvs.begin(), r.pvs.end(), id)) {
            std::fprintf(stderr, "%s\n", reference::toJson(culler.grid(), descs, cam).c_str());
            bug("visible object " + std::to_string(id) + " missing from the PVS (scene above)");
        }
    }
}

using fuzz::kTrace;

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    Decoder in(data, size);

    // The grid. Resolutions stay small unless they are meant to be refused.
    const double voxel = in.number(std::ldexp(1.0, in.integer(-10, 4)));
    const Vec2 origin{in.number(in.integer(-64, 64) * 0.5), in.number(in.integer(-64, 64) * 0.5)};
    IVec2 res;
    for (int a = 0; a < 2; ++a) {
        static const std::int32_t wild[] = {0, -1, std::numeric_limits<std::int32_t>::min(), std::numeric_limits<std::int32_t>::max(),
                                            (1 << 20) + 1, 1 << 20, 1 << 16};
        res[a] = in.integer(0, 15) == 0 ? wild[in.integer<std::size_t>(0, std::size(wild) - 1)] : in.integer(1, 48);
    }
    std::optional<GridGeometry2> grid;
    try {
        grid.emplace(origin, voxel, res);
    } catch (const InvalidInput&) {
        return 0;
    }
    const bool tameGrid = in.takeTame() && std::abs(origin.x) < 1e4 && std::abs(origin.y) < 1e4 && voxel > 1e-4;
    // Keep allocations small; a resolution over the 2D culler's per-axis limit is refused before allocating.
    const bool overLimit = res.x > (1 << 20) || res.y > (1 << 20);
    if (grid->voxelCount() > (1u << 14) && !overLimit) return 0;

    std::optional<Culler2D> culler;
    try {
        culler.emplace(*grid);
    } catch (const InvalidInput& e) {
        if (!overLimit) bug(std::string("Culler2D refused a small grid: ") + e.what());
        return 0;
    }
    if (overLimit) bug("Culler2D accepted a grid over 2^20 voxels per axis");

    Model model;
    std::optional<Camera2> lastCamera;
    std::vector<ObjectId> lastPvs; // the PVS of lastCamera, valid while nothing changed since
    bool lastValid = false;
    bool lastTbvActivity = false; // the cull that gave lastPvs made, renewed or revealed a TBV

    auto afterRefusal = [&](const char* what) {
        if (kTrace) std::fprintf(stderr, "refused %s (then the last camera culls again: %s)\n", what, lastValid ? "yes" : "no");
        if (culler->objectCount() != model.objects.size()) bug(std::string("refused ") + what + " changed the object count");
        for (const auto& [id, s] : model.objects)
            if (!culler->hasObject(id)) bug(std::string("refused ") + what + " lost object " + std::to_string(id));
        // The same camera gives the same PVS, unless either cull changed the hidden objects' state (a TBV
        // made or revealed): the brick walk classifies a revealed object against its image, so an object
        // hidden only through its TBV can alternate between frames, legitimately (a superset either way).
        if (lastValid) {
            const CullResult& again = culler->cull(*lastCamera);
            const bool tbvsMoved = lastTbvActivity || again.stats.tbvsCreated != 0 || again.stats.tbvsRevealed != 0 ||
                                   again.stats.tbvsRenewed != 0;
            if (!tbvsMoved && again.pvs != lastPvs) bug(std::string("refused ") + what + " changed the PVS");
            lastPvs = again.pvs;
            lastTbvActivity = again.stats.tbvsCreated != 0 || again.stats.tbvsRevealed != 0 || again.stats.tbvsRenewed != 0;
        }
    };

    for (int op = 0; op < 64 && !in.done(); ++op) {
        const int kind = in.integer(0, 9);
        const ObjectId id = in.integer(0, 7) == 0 ? in.integer<ObjectId>(0, ~ObjectId(0)) : in.integer<ObjectId>(0, 11);
        const bool known = model.objects.count(id) != 0;
        if (kind <= 2) { // add
            ObjectDesc<2> o;
            o.id = id;
            o.shape = in.shape(*grid);
            o.isStatic = in.flag();
            o.maxSpeed = in.number(in.integer(0, 8) * 0.25);
            const bool tame = in.takeTame();
            try {
                culler->addObject(o);
            } catch (const InvalidInput& e) {
                if (kTrace) std::fprintf(stderr, "add %llu refused: %s\n", (unsigned long long)id, e.what());
                afterRefusal("addObject");
                continue;
            }
            if (known) bug("addObject accepted duplicate id " + std::to_string(id));
            if (kTrace) std::fprintf(stderr, "add %llu static %d max_speed %g\n", (unsigned long long)id, int(o.isStatic), o.maxSpeed);
            Shape<2> normalised = o.shape;
            validateShape<2>(normalised, "model");
            model.objects[id] = normalised;
            model.tame = model.tame && tame;
            lastValid = false;
        } else if (kind <= 4) { // update
            const Shape<2> s = in.shape(*grid);
            const bool tame = in.takeTame();
            Shape<2> normalised = s;
            bool valid = true;
            try {
                validateShape<2>(normalised, "model");
            } catch (const InvalidInput&) {
                valid = false;
            }
            try {
                culler->updateObject(id, s);
            } catch (const InvalidInput& e) {
                if (kTrace) std::fprintf(stderr, "update %llu refused: %s\n", (unsigned long long)id, e.what());
                if (known && valid) bug("updateObject refused a known id with a valid shape");
                afterRefusal("updateObject");
                continue;
            }
            if (!known) bug("updateObject accepted unknown id " + std::to_string(id));
            if (kTrace) std::fprintf(stderr, "update %llu\n", (unsigned long long)id);
            if (!valid) bug("updateObject accepted a shape validateShape refuses");
            model.objects[id] = normalised;
            model.tame = model.tame && tame;
            lastValid = false;
        } else if (kind == 5) { // remove
            try {
                culler->removeObject(id);
            } catch (const InvalidInput&) {
                if (known) bug("removeObject refused known id " + std::to_string(id));
                afterRefusal("removeObject");
                continue;
            }
            if (!known) bug("removeObject accepted unknown id " + std::to_string(id));
            if (kTrace) std::fprintf(stderr, "remove %llu\n", (unsigned long long)id);
            model.objects.erase(id);
            lastValid = false;
        } else { // cull
            const Camera2 cam = in.camera(*grid);
            const bool tame = in.takeTame();
            try {
                const CullResult& r = culler->cull(cam);
                if (kTrace) fuzz::traceCull<2>(*culler, model.objects, cam, r);
                checkResult(*culler, model, r);
                if (kReference && tameGrid && model.tame && tame) checkAgainstReference(*culler, model, cam, r);
                lastCamera = cam;
                lastPvs = r.pvs;
                lastTbvActivity = r.stats.tbvsCreated != 0 || r.stats.tbvsRevealed != 0 || r.stats.tbvsRenewed != 0;
                lastValid = true;
            } catch (const InvalidInput& e) {
                if (kTrace) std::fprintf(stderr, "cull refused: %s\n%s\n", e.what(), reference::toJson(culler->grid(), {}, cam).c_str());
                afterRefusal("cull");
            }
        }
    }
    if (culler->objectCount() != model.objects.size()) bug("final object count differs from the model");
    return 0;
}
