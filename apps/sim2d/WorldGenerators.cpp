#include "WorldGenerators.hpp"

#include "rgvc/grid/Error.hpp"

#include <cmath>
#include <numbers>
#include <random>

namespace rgvc::sim {

namespace {

constexpr int kSide = 256; // [Voxels] of 1 unit

/// Uniform doubles from the engine's fixed output sequence.
class Random {
public:
    explicit Random(std::uint64_t seed) : m_engine(seed) {}
    double uniform(double lo, double hi) { return lo + (hi - lo) * double(m_engine() >> 11) * 0x1.0p-53; }
    int below(int n) { return int(uniform(0, n)) % n; }

private:
    std::mt19937_64 m_engine;
};

SimObject staticBox(ObjectId id, Vec2 lo, Vec2 hi) { return {id, Box<2>{lo, hi}, Vec2(0.0), Vec2(0.0), 0, true}; }

/// A mover somewhere in [margin, kSide - margin]^2 with a random heading.
SimObject mover(ObjectId id, Random& r) {
    const Vec2 at(r.uniform(4, kSide - 4), r.uniform(4, kSide - 4));
    const double speed = r.uniform(0.15, 0.9), heading = r.uniform(0, 2 * std::numbers::pi);
    SimObject o;
    o.id = id;
    o.isStatic = false;
    o.velocity = speed * Vec2(std::cos(heading), std::sin(heading));
    o.maxSpeed = speed;
    if (r.below(2) == 0) {
        o.shape0 = Ball<2>{at, r.uniform(0.6, 2.0)};
    } else {
        const Vec2 half(r.uniform(0.6, 2.5), r.uniform(0.6, 2.5));
        o.shape0 = Box<2>{at - half, at + half};
    }
    return o;
}

void addCity(std::vector<SimObject>& out, Random& r) {
    // Blocks [32 i + 4, 32 i + 28]; streets are centred on multiples of 32.
    for (int bx = 0; bx < 8; ++bx)
        for (int by = 0; by < 8; ++by) {
            const Vec2 lo(32 * bx + 4, 32 * by + 4);
            const int split = r.below(4); // 0: one building, 1: two side by side, 2: two stacked, 3: four
            const int nx = (split == 1 || split == 3) ? 2 : 1, ny = (split == 2 || split == 3) ? 2 : 1;
            const double w = 24.0 / nx, h = 24.0 / ny;
            for (int i = 0; i < nx; ++i)
                for (int j = 0; j < ny; ++j) {
                    // A courtyard gap of 1-3 units between buildings of one block.
                    const double gx = r.uniform(0.5, 1.5), gy = r.uniform(0.5, 1.5);
                    out.push_back(staticBox(ObjectId(out.size()), lo + Vec2(i * w + gx, j * h + gy),
                                            lo + Vec2((i + 1) * w - gx, (j + 1) * h - gy)));
                }
        }
}

void addMaze(std::vector<SimObject>& out, Random& r) {
    // 16 x 16 rooms of 16 units; walls 2 units thick on the room boundaries. A random spanning tree
    // (randomized depth-first search) opens one 6-unit doorway per tree edge; 1 in 6 other walls opens too.
    constexpr int n = kSide / 16;
    std::vector<bool> openH((n + 1) * n, false), openV((n + 1) * n, false); // wall below / left of a room
    std::vector<bool> seen(n * n, false);
    std::vector<int> stack{0};
    seen[0] = true;
    while (!stack.empty()) {
        const int c = stack.back(), cx = c % n, cy = c / n;
        int options[4], count = 0;
        if (cx > 0 && !seen[c - 1]) options[count++] = 0;
        if (cx + 1 < n && !seen[c + 1]) options[count++] = 1;
        if (cy > 0 && !seen[c - n]) options[count++] = 2;
        if (cy + 1 < n && !seen[c + n]) options[count++] = 3;
        if (count == 0) {
            stack.pop_back();
            continue;
        }
        const int d = options[r.below(count)];
        const int next = d == 0 ? c - 1 : d == 1 ? c + 1 : d == 2 ? c - n : c + n;
        if (d == 0) openV[cy * (n + 1) + cx] = true;
        if (d == 1) openV[cy * (n + 1) + cx + 1] = true;
        if (d == 2) openH[cy * n + cx] = true;
        if (d == 3) openH[(cy + 1) * n + cx] = true;
        seen[next] = true;
        stack.push_back(next);
    }
    auto wall = [&](Vec2 lo, Vec2 hi) { out.push_back(staticBox(ObjectId(out.size()), lo, hi)); };
    for (int y = 0; y <= n; ++y)
        for (int x = 0; x < n; ++x) { // horizontal walls
            const bool border = y == 0 || y == n;
            const bool open = !border && (openH[y * n + x] || r.below(6) == 0);
            const double y0 = std::clamp(16.0 * y - 1, 0.0, kSide - 2.0);
            if (!open) {
                wall({16.0 * x, y0}, {16.0 * x + 16, y0 + 2});
            } else {
                wall({16.0 * x, y0}, {16.0 * x + 5, y0 + 2});
                wall({16.0 * x + 11, y0}, {16.0 * x + 16, y0 + 2});
            }
        }
    for (int y = 0; y < n; ++y)
        for (int x = 0; x <= n; ++x) { // vertical walls, between the horizontal ones
            const bool border = x == 0 || x == n;
            const bool open = !border && (openV[y * (n + 1) + x] || r.below(6) == 0);
            const double x0 = std::clamp(16.0 * x - 1, 0.0, kSide - 2.0);
            if (!open) {
                wall({x0, 16.0 * y + 1}, {x0 + 2, 16.0 * y + 15});
            } else {
                wall({x0, 16.0 * y + 1}, {x0 + 2, 16.0 * y + 5});
                wall({x0, 16.0 * y + 11}, {x0 + 2, 16.0 * y + 15});
            }
        }
}

void addField(std::vector<SimObject>& out, Random& r) {
    for (int k = 0; k < 40; ++k) {
        const Vec2 at(r.uniform(10, kSide - 10), r.uniform(10, kSide - 10));
        const double size = r.uniform(2, 6);
        SimObject o{ObjectId(out.size()), Ball<2>{at, size}, Vec2(0.0), Vec2(0.0), 0, true};
        if (k % 2 == 1) {
            ConvexPolygon p;
            const int corners = 3 + r.below(4);
            const double turn = r.uniform(0, 2 * std::numbers::pi);
            for (int i = 0; i < corners; ++i) {
                const double a = turn + 2 * std::numbers::pi * i / corners;
                p.points.push_back(at + size * Vec2(std::cos(a), std::sin(a)));
            }
            o.shape0 = p;
        }
        out.push_back(std::move(o));
    }
}

} // namespace

const std::vector<std::string>& generatorKinds() {
    static const std::vector<std::string> kinds{"city", "maze", "field"};
    return kinds;
}

GeneratorSpec parseGeneratorSpec(const std::string& text) {
    const std::size_t colon = text.find(':');
    GeneratorSpec s;
    s.kind = text.substr(0, colon);
    bool known = false;
    for (const std::string& k : generatorKinds()) known = known || k == s.kind;
    if (!known) throw InvalidInput("--generate", "unknown world '" + s.kind + "' (expected city:N, maze:N or field:N)");
    const std::string count = colon == std::string::npos ? "" : text.substr(colon + 1);
    std::size_t used = 0;
    long long n = -1;
    try {
        n = std::stoll(count, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (count.empty() || used != count.size() || n < 0 || n > 100000)
        throw InvalidInput("--generate", "expected " + s.kind + ":N with N an integer in [0, 100000], got '" + text + "'");
    s.movers = std::size_t(n);
    return s;
}

SimWorld generateWorld(const GeneratorSpec& spec, std::uint64_t seed) {
    Random r(seed);
    std::vector<SimObject> objects;
    Camera2 camera{.position = {32.5, 128.5}, .direction = {1, 0}, .fovDeg = 70}; // down the middle street
    if (spec.kind == "city") {
        addCity(objects, r);
    } else if (spec.kind == "maze") {
        addMaze(objects, r);
        camera = {.position = {8.5, 8.5}, .direction = {1, 0.6}, .fovDeg = 90};
    } else {
        addField(objects, r);
        camera = {.position = {20.5, 20.5}, .direction = {1, 1}, .fovDeg = 60};
    }
    for (std::size_t k = 0; k < spec.movers; ++k) objects.push_back(mover(ObjectId(objects.size()), r));
    const GridGeometry2 grid({0, 0}, 1.0, {kSide, kSide});
    return SimWorld(spec.kind + ":" + std::to_string(spec.movers), grid, camera, std::move(objects));
}

} // namespace rgvc::sim
