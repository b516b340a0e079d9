// libFuzzer target: arbitrary bytes -> a small 3D scene driven through the Culler3D API.
//
// The bytes decode into a grid (origin, voxel size, resolution), then up to 64 operations: addObject,
// updateObject, removeObject and cull, with ids drawn from a small range (so duplicates and unknown ids
// are common) and every number either "tame" (voxel-aligned quarters in and around the grid), or taken
// from a table of troublemakers (NaN, +-inf, -0, denormals, DBL_MAX, 1e+-300), or raw bit patterns.
// Shapes are spheres and boxes (possibly inverted); cameras have a direction, an up vector (sometimes
// zero = default, sometimes parallel to the direction), an aspect, a vertical fov and sometimes a far.
//
// rgvc::InvalidInput is the one acceptable refusal. Anything else escaping, a crash, a sanitizer report
// or a hang is a bug, and so is any of these:
//   - a PVS that is not sorted ascending without duplicates, holds an id the culler does not hold, or
//     disagrees with stats.pvsSize / stats.objectCount;
//   - a refused call that changed anything (strong guarantee): after it, the last camera culls to the
//     same PVS as before it, and objectCount/hasObject are unchanged;
//   - addObject accepting a duplicate id, update/remove accepting an unknown one, or rejecting a known one
//     for a reason other than the shape.
// With RGVC_FUZZ_REFERENCE=1 in the environment, tame frames are also checked against the sampled
// reference (rgvc::reference::visible3D, at a low density so that a run stays fast): a visible object
// missing from the PVS is a bug. With RGVC_FUZZ_TRACE=1 every operation is printed, every cull with its
// scene file and PVS, and every refusal with its message (refusals re-cull the last camera).
//
// Build: -DRGVC_BUILD_FUZZERS=ON -DCMAKE_CXX_COMPILER=clang++; run: scripts/fuzz.sh culler3d.
#include "ExactVisibility3D.hpp"
#include "RandomScenes3D.hpp"
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
    std::fprintf(stderr, "fuzz_culler3d: BUG: %s\n", what.c_str());
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
    double coordinate(const GridGeometry3& g, int a) {
        const int n = g.resolution()[a];
        const double q = m_in.ConsumeIntegralInRange<int>(-16, 4 * std::min(n, 1 << 12) + 16) * 0.25;
        return number(g.origin()[a] + q * g.voxelSize());
    }
    Vec3 point(const GridGeometry3& g) {
        const double x = coordinate(g, 0);
        const double y = coordinate(g, 1);
        return {x, y, coordinate(g, 2)};
    }
    /// A positive length: 1/1024 voxel to 16 voxels, mostly.
    double length(const GridGeometry3& g) {
        const int k = m_in.ConsumeIntegralInRange<int>(-10, 4);
        return number(std::ldexp(1.0, k) * (1 + m_in.ConsumeIntegralInRange<int>(0, 3)) * g.voxelSize());
    }

    Shape<3> shape(const GridGeometry3& g) {
        if (m_in.ConsumeBool()) {
            const Vec3 c = point(g);
            return Ball<3>{c, length(g)};
        }
        const Vec3 lo = point(g);
        if (m_in.ConsumeBool()) return Box<3>{lo, point(g)}; // possibly inverted or flat
        const double w = length(g);
        const double h = length(g);
        return Box<3>{lo, lo + Vec3{w, h, length(g)}};
    }

    Camera3 camera(const GridGeometry3& g) {
        static const Vec3 dirs[] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},  {0, -1, 0}, {0, 0, 1},   {0, 0, -1},
                                    {1, 1, 0},  {-1, 1, 1}, {1, -1, 1}, {2, 1, -3}, {1, -3, 0.5}, {0, 1e-3, 1}};
        static const Vec3 ups[] = {{0, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 0}, {0, -1, 0}, {1, 1, 1}};
        static const double fovs[] = {1e-3, 1, 30, 45, 60, 90, 90.5, 120, 179, 179.999, 180, 0, -45};
        static const double aspects[] = {1, 0.5, 4.0 / 3, 16.0 / 9, 3, 1e-3, 0};
        Camera3 c;
        c.position = point(g);
        const Vec3 d = dirs[m_in.ConsumeIntegralInRange<std::size_t>(0, std::size(dirs) - 1)];
        c.direction = {number(d.x), number(d.y), number(d.z)};
        if (m_in.ConsumeBool()) {
            const Vec3 u = ups[m_in.ConsumeIntegralInRange<std::size_t>(0, std::size(ups) - 1)];
            c.up = {number(u.x), u.y, number(u.z)};
        } else if (m_in.ConsumeIntegralInRange<int>(0, 7) == 0) {
            c.up = d; // parallel to the direction
        }
        c.fovDeg = number(fovs[m_in.ConsumeIntegralInRange<std::size_t>(0, std::size(fovs) - 1)]);
        c.aspect = number(aspects[m_in.ConsumeIntegralInRange<std::size_t>(0, std::size(aspects) - 1)]);
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
    std::map<ObjectId, Shape<3>> objects; // validated (normalised) shapes
    bool tame = true;                     // every shape added or updated so far was tame
};

void checkResult(const Culler3D& culler, const Model& model, const CullResult& r) {
    if (!sortedUnique(r.pvs)) bug("PVS not sorted ascending without duplicates");
    for (ObjectId id : r.pvs)
        if (!model.objects.count(id)) bug("PVS holds id " + std::to_string(id) + ", which the culler does not hold");
    if (r.stats.pvsSize != r.pvs.size()) bug("stats.pvsSize != |PVS|");
    if (r.stats.objectCount != model.objects.size() || culler.objectCount() != model.objects.size())
        bug("object count differs from the model");
}

void checkAgainstReference(const Culler3D& culler, const Model& model, const Camera3& cam, const CullResult& r) {
    std::vector<Shape<3>> shapes;
    std::vector<ObjectDesc<3>> descs;
    for (const auto& [id, s] : model.objects) {
        shapes.push_back(s);
        descs.push_back({id, s, true, 0});
    }
    reference::Visibility3DOptions opt;
    opt.gridDivisions = 32;
    opt.targetDivisions = 4;
    const std::vector<bool> visible = reference::visible3D(shapes, cam, opt);
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
    const Vec3 origin{in.number(in.integer(-64, 64) * 0.5), in.number(in.integer(-64, 64) * 0.5),
                      in.number(in.integer(-64, 64) * 0.5)};
    IVec3 res;
    for (int a = 0; a < 3; ++a) {
        static const std::int32_t wild[] = {0, -1, std::numeric_limits<std::int32_t>::min(), std::numeric_limits<std::int32_t>::max(),
                                            (1 << 20) + 1, 1 << 20, 1 << 16};
        res[a] = in.integer(0, 15) == 0 ? wild[in.integer<std::size_t>(0, std::size(wild) - 1)] : in.integer(1, 24);
    }
    std::optional<GridGeometry3> grid;
    try {
        grid.emplace(origin, voxel, res);
    } catch (const InvalidInput&) {
        return 0;
    }
    const bool tameGrid = in.takeTame() && std::abs(origin.x) < 1e4 && std::abs(origin.y) < 1e4 &&
                          std::abs(origin.z) < 1e4 && voxel > 1e-4;
    // Keep allocations and traversals small (the 3D culler has no per-axis limit; every small grid must
    // be accepted).
    if (grid->voxelCount() > (1u << 13)) return 0;

    std::optional<Culler3D> culler;
    try {
        culler.emplace(*grid);
    } catch (const InvalidInput& e) {
        bug(std::string("Culler3D refused a small grid: ") + e.what());
    }

    Model model;
    std::optional<Camera3> lastCamera;
    std::vector<ObjectId> lastPvs; // the PVS of lastCamera, valid while nothing changed since
    bool lastDeferred = false;     // whether the cull that gave lastPvs started without caps
    bool lastSkipped = false;      // whether it walked without the occlusion image
    bool lastValid = false;

    auto afterRefusal = [&](const char* what) {
        if (kTrace) std::fprintf(stderr, "refused %s (then the last camera culls again: %s)\n", what, lastValid ? "yes" : "no");
        if (culler->objectCount() != model.objects.size()) bug(std::string("refused ") + what + " changed the object count");
        for (const auto& [id, s] : model.objects)
            if (!culler->hasObject(id)) bug(std::string("refused ") + what + " lost object " + std::to_string(id));
        // The same camera gives the same PVS, unless adaptive caps (CullerOptions::adaptiveCaps) started one
        // of the two culls without caps, or the adaptive image (CullerOptions::adaptiveImage) walked one
        // of them without the image: each cull advances those schedules, legitimately.
        if (lastValid) {
            const CullResult& again = culler->cull(*lastCamera);
            if (again.stats.capsDeferred == lastDeferred && again.stats.imageSkipped == lastSkipped && again.pvs != lastPvs)
                bug(std::string("refused ") + what + " changed the PVS");
            lastDeferred = again.stats.capsDeferred;
            lastSkipped = again.stats.imageSkipped;
            lastPvs = again.pvs;
        }
    };

    for (int op = 0; op < 64 && !in.done(); ++op) {
        const int kind = in.integer(0, 9);
        const ObjectId id = in.integer(0, 7) == 0 ? in.integer<ObjectId>(0, ~ObjectId(0)) : in.integer<ObjectId>(0, 11);
        const bool known = model.objects.count(id) != 0;
        if (kind <= 2) { // add
            ObjectDesc<3> o;
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
            Shape<3> normalised = o.shape;
            validateShape<3>(normalised, "model");
            model.objects[id] = normalised;
            model.tame = model.tame && tame;
            lastValid = false;
        } else if (kind <= 4) { // update
            const Shape<3> s = in.shape(*grid);
            const bool tame = in.takeTame();
            Shape<3> normalised = s;
            bool valid = true;
            try {
                validateShape<3>(normalised, "model");
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
            const Camera3 cam = in.camera(*grid);
            const bool tame = in.takeTame();
            try {
                const CullResult& r = culler->cull(cam);
                if (kTrace) fuzz::traceCull<3>(*culler, model.objects, cam, r);
                checkResult(*culler, model, r);
                if (kReference && tameGrid && model.tame && tame) checkAgainstReference(*culler, model, cam, r);
                lastCamera = cam;
                lastPvs = r.pvs;
                lastDeferred = r.stats.capsDeferred;
                lastSkipped = r.stats.imageSkipped;
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
